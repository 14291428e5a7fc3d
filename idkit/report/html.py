"""A small, dependency-free builder of self-contained HTML reports.

Figures are embedded as base64 PNG and, when the report is given a ``figures_dir``, also
saved there as PNG and SVG; tables are rendered by pandas and, with a ``tables_dir``, also
written there as CSV. Nothing is fetched from the network when the file is opened.

A page answers first and details second: a section can be collapsed (``<details>``, its
title and a one-line :meth:`HtmlReport.summarize` visible), text dumps (:meth:`~HtmlReport.preformatted`)
always are, and so are tables longer than :data:`MAX_INLINE_ROWS` rows; :meth:`HtmlReport.folded`
collapses anything else. :meth:`HtmlReport.thumbnail` shows a small copy of a figure drawn
anywhere on the page, linked to it (opening the sections around it).

Rendering a figure (layout, rasterising, SVG) costs far more than building it. With
``render_processes > 1`` and a ``figures_dir``, where the caller can fork
(:func:`idkit.forked.can_fork`), each figure is rendered by a forked child process (at
most ``render_processes`` at a time, :func:`idkit.forked.fork_call`) while the caller
goes on building the next one; the caller saves the PNG and SVG bytes the child sends
back and embeds the PNG; :meth:`HtmlReport.render` waits for the last ones and raises
:class:`~idkit.errors.OutputError` naming any figure whose child failed. The files are
byte for byte those of the in-process path (same calls, same settings). Otherwise figures
are rendered in the calling process, one after the other.
"""

from __future__ import annotations

import base64
import html
import io
import re
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import pandas as pd

from idkit.atomic import write_bytes_atomic, write_text_atomic
from idkit.errors import OutputError
from idkit.forked import can_fork, fork_call

__all__ = ["MAX_INLINE_ROWS", "MAX_TABLE_COLUMNS", "HtmlReport", "file_stem"]

#: widest table the page shows (columns, index included); wider ones are transposed or split by the caller
MAX_TABLE_COLUMNS = 12

#: longest table shown open; a longer one is collapsed (its caption and row count stay visible)
MAX_INLINE_ROWS = 12

_STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1100px; padding: 0 1em; color: #222; }
h1 { border-bottom: 2px solid #345; padding-bottom: .2em; font-size: 1.6em; overflow-wrap: anywhere; }
h2 { border-bottom: 1px solid #aab; margin-top: 2em; }
h3 { margin-top: 1.4em; }
table { border-collapse: collapse; font-size: 0.85em; margin: .6em 0; display: block; max-width: 100%;
        overflow-x: auto; }
th, td { border: 1px solid #ccd; padding: .2em .5em; text-align: right; white-space: nowrap; }
td.text, th.text { white-space: normal; }
th { background: #eef; }
pre { background: #f6f6f8; padding: .6em; font-size: 0.85em; white-space: pre-wrap; overflow-wrap: anywhere; }
.pass { color: #176b2c; font-weight: bold; } .fail { color: #a11; font-weight: bold; }
.inconclusive { color: #8a5a00; font-weight: bold; }
ul.conclusions li { margin: .3em 0; }
nav a { margin-right: 1em; } figure { margin: 1em 0; } figcaption { font-size: .9em; color: #444; }
img { max-width: 100%; height: auto; }
details > summary { cursor: pointer; color: #345; }
section > details > summary h2 { display: inline; border: none; font-size: 1.25em; margin: 0; color: #223; }
section > details > summary .gist { color: #555; margin-left: .6em; }
section > details { border-top: 1px solid #aab; padding: .5em 0; }
section.front h2 { display: none; }
details.fold { margin: .4em 0; } details.fold > summary { font-size: .9em; }
.thumbs { display: flex; gap: .6em; margin: .5em 0; }
.thumbs a { flex: 1 1 0; min-width: 0; text-decoration: none; color: #444; font-size: .8em; }
.thumbs img { width: 100%; height: 150px; object-fit: contain; border: 1px solid #ccd; background: #fff; }
table.front td, table.front th { text-align: left; white-space: normal; } table.front .num { text-align: right; white-space: nowrap; }
table.front { display: table; width: 100%; font-size: .82em; margin: .3em 0; }
p.lead { margin: .3em 0; }
"""

#: opens the collapsed sections around the target of a link (a thumbnail's figure)
_OPEN_TARGET = """
function idkitOpenTarget() {
  var target = document.getElementById(decodeURIComponent(location.hash.slice(1)));
  for (var node = target; node; node = node.parentElement) { if (node.tagName === "DETAILS") node.open = true; }
  if (target) target.scrollIntoView();
}
window.addEventListener("hashchange", idkitOpenTarget);
window.addEventListener("load", function () { if (location.hash) idkitOpenTarget(); });
"""


#: resolution of the report's PNG figures (dots per inch); the layout is solved at it
PNG_DPI = 90


@contextmanager
def _on_agg_canvas(figure):
    """``figure`` on a new Agg canvas inside the block; its own canvas is given back after.

    One canvas keeps one renderer for a size and resolution, and matplotlib caches text
    extents and parsed mathtext per renderer: drawn on it, the layout and the PNG measure
    each label once. A canvas of its own (no window manager) also lets the figure's
    resolution change for the layout without resizing any window the figure is shown in.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    canvas = figure.canvas
    try:
        yield FigureCanvasAgg(figure)  # attaches itself to the figure
    finally:
        figure.set_canvas(canvas)


def _solve_layout_once(figure, dpi: float) -> None:
    """Place the axes of ``figure`` with its layout engine at ``dpi``, then drop the engine.

    ``savefig`` with a layout engine draws the whole figure once without output, only to
    run the engine, before drawing it for real, and the SVG would do the same again. Run
    on the figure's Agg canvas (:func:`_on_agg_canvas`) at the PNG's resolution, the engine
    measures the text as the PNG's own pass would, so the files keep the same placement;
    without an engine each ``savefig`` draws once.
    """
    from matplotlib import rc_context

    engine = figure.get_layout_engine()
    if engine is None:
        return
    if figure.axes:
        original_dpi = figure.dpi
        figure.dpi = dpi
        try:
            engine.execute(figure)
        except ValueError:  # skipped as matplotlib's own draw skips it: the axes stay where they are
            pass
        finally:
            figure.dpi = original_dpi
    # ``None`` removes the engine only when the rc parameters name no default one
    with rc_context({"figure.autolayout": False, "figure.constrained_layout.use": False}):
        figure.set_layout_engine(None)


def _render_figure(figure, *, with_svg: bool) -> tuple[bytes, bytes | None]:
    """PNG (:data:`PNG_DPI`) and, when asked, SVG bytes of a figure; its layout is solved once for both."""
    from matplotlib import rc_context

    buffer = io.BytesIO()
    with _on_agg_canvas(figure):
        _solve_layout_once(figure, PNG_DPI)
        figure.savefig(buffer, format="png", dpi=PNG_DPI)
        if not with_svg:
            return buffer.getvalue(), None
        svg = io.BytesIO()
        # no clock and no random ids in the file: the same figure gives the same bytes
        with rc_context({"svg.hashsalt": "idkit"}):
            figure.savefig(svg, format="svg", metadata={"Date": None})
    return buffer.getvalue(), svg.getvalue()


def _warm_up() -> None:
    """Render a small figure with the usual text (log ticks, mathtext, labels, legend) once.

    A forked child starts with the caller's matplotlib state: fonts loaded, glyphs and text
    layouts cached. Without this each child would load them anew for its one figure.
    """
    from matplotlib.figure import Figure

    figure = Figure(figsize=(4, 3), layout="constrained")
    ax = figure.subplots()
    ax.loglog([1.0, 10.0, 100.0], [1e-3, 1.0, 1e3], label="curve")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("|H| [-] (m/s$^2$)")
    ax.set_title("title", fontsize="small")
    ax.legend(fontsize="x-small", title="legend")
    _render_figure(figure, with_svg=True)


def _figure_html(stem: str, alt: str, caption: str, png: bytes) -> str:
    encoded = base64.b64encode(png).decode("ascii")
    return (f'<figure id="figure-{html.escape(stem)}"><img alt="{html.escape(alt)}" '
            f'src="data:image/png;base64,{encoded}"><figcaption>{html.escape(caption)}</figcaption></figure>')


def file_stem(text: str) -> str:
    """A file-name stem made of ``text``: letters, digits, ``_``, ``-`` and ``.`` only.

    Examples
    --------
    >>> file_stem("wire rope: drops, validation")
    'wire_rope_drops_validation'
    """
    return re.sub(r"[^A-Za-z0-9.-]+", "_", text).strip("_") or "item"


@dataclass
class _Section:
    title: str
    anchor: str
    parts: list = field(default_factory=list)
    collapsed: bool = False
    gist: str = ""
    front: bool = False


@dataclass
class HtmlReport:
    """Collects sections of HTML and renders one self-contained page.

    Attributes
    ----------
    title : str
    figures_dir, tables_dir : Path, optional
        Where every figure is also saved (``<name>.png`` and ``<name>.svg``) and every
        table written (``<name>.csv``); nothing is saved when None.
    figure_seconds : float
        Time the caller spent on figures (s): rendering them, or handing them to child
        processes and waiting for those; for the report's timings.
    render_processes : int
        Figures rendered at a time by forked children (module docstring); 0 or 1 renders
        in the calling process.
    """

    title: str
    figures_dir: Path | None = None
    tables_dir: Path | None = None
    figure_seconds: float = 0.0
    figure_files: list = field(default_factory=list)
    keep_figures: bool = False
    kept_figures: list = field(default_factory=list)
    table_files: list = field(default_factory=list)
    render_processes: int = 0
    _sections: list[_Section] = field(default_factory=list)
    _pending: dict = field(default_factory=dict)
    _pngs: dict = field(default_factory=dict)
    _thumbnails: dict = field(default_factory=dict)
    _fold_depth: int = 0

    def section(self, title: str, anchor: str, *, collapsed: bool = False, front: bool = False) -> None:
        """Start a new section; later content goes into it.

        ``collapsed``: inside a closed ``<details>`` whose summary line is the title and the
        section's :meth:`summarize` text. ``front``: the page's first screen (its title is
        not drawn: the page title heads it).
        """
        self._sections.append(_Section(title, anchor, [], collapsed, front=front))

    def summarize(self, text: str) -> None:
        """The current section's one-line gist, shown beside its title when it is collapsed."""
        self._sections[-1].gist = text

    def _add(self, fragment: str) -> None:
        if not self._sections:
            self.section("Overview", "overview")
        self._sections[-1].parts.append(fragment)

    def placeholder(self) -> str:
        """Reserve the current place for content added later with :meth:`filling`; returns its token."""
        token = f"\x00placeholder {sum(len(section.parts) for section in self._sections)}\x00"
        self._add(token)
        return token

    @contextmanager
    def filling(self, token: str):
        """Content added inside the ``with`` block goes where :meth:`placeholder` returned ``token``.

        The report can so be written in the order its inputs become ready (the summary's
        transport paragraph is written once the study is done, at the end) while it reads
        in its own order.
        """
        saved = self._sections
        self._sections = [_Section("", "")]
        try:
            yield
        finally:
            filled = self._sections[0].parts
            self._sections = saved
        for section in self._sections:
            if token in section.parts:
                at = section.parts.index(token)
                section.parts[at:at + 1] = filled
                return
        raise ValueError("filling: no placeholder with this token (already filled?)")

    @contextmanager
    def folded(self, label: str):
        """Content added inside the ``with`` block is collapsed under ``label`` (a closed ``<details>``)."""
        self._add(f'<details class="fold"><summary>{html.escape(label)}</summary>')
        self._fold_depth += 1
        try:
            yield
        finally:
            self._fold_depth -= 1
            self._add("</details>")

    def heading(self, text: str) -> None:
        self._add(f"<h3>{html.escape(text)}</h3>")

    def paragraph(self, text: str) -> None:
        self._add(f"<p>{html.escape(text)}</p>")

    def items(self, entries) -> None:
        """A bulleted list; each entry is a text or a ``(verdict, text)`` pair (verdict coloured)."""
        rendered = []
        for entry in entries:
            if isinstance(entry, tuple):
                verdict, text = entry
                rendered.append(f"<li>{self._verdict_span(verdict)} {html.escape(text)}</li>")
            else:
                rendered.append(f"<li>{html.escape(entry)}</li>")
        self._add('<ul class="conclusions">' + "".join(rendered) + "</ul>")

    @staticmethod
    def _verdict_span(verdict: str) -> str:
        css = {"PASS": "pass", "FAIL": "fail"}.get(verdict, "inconclusive")
        return f'<span class="{css}">{html.escape(verdict)}</span>'

    def verdict(self, label: str, verdict: str) -> None:
        """One validation verdict: ``"PASS"``, ``"INCONCLUSIVE"`` or ``"FAIL"``."""
        self._add(f"<p>{html.escape(label)}: {self._verdict_span(verdict)}</p>")

    def preformatted(self, text: str, *, label: str = "show the log") -> None:
        """A text dump (a fit log, an inspection), collapsed under ``label`` unless already inside a fold."""
        block = f"<pre>{html.escape(text)}</pre>"
        if self._fold_depth:
            self._add(block)
        else:
            self._add(f'<details class="fold"><summary>{html.escape(label)}</summary>{block}</details>')

    def front_table(self, rows: list[dict], *, verdict_column: str | None = None, numeric=(), caption=None) -> None:
        """A short first-screen table of texts: one dict per row (keys are the columns, in order).

        Cells are escaped; ``verdict_column`` is coloured as :meth:`items` colours verdicts;
        ``numeric`` columns are right-aligned. A cell given as ``(text, hover)`` shows
        ``text`` and carries ``hover`` as its tooltip (the full sentence of a shortened one).
        """
        columns = list(rows[0]) if rows else []
        head = "".join(f"<th>{html.escape(column)}</th>" for column in columns)
        body = []
        for row in rows:
            cells = []
            for column in columns:
                value = row[column]
                text, hover = value if isinstance(value, tuple) else (value, None)
                content = self._verdict_span(text) if column == verdict_column else html.escape(str(text))
                attributes = (' class="num"' if column in numeric else "") + (
                    f' title="{html.escape(hover)}"' if hover else "")
                cells.append(f"<td{attributes}>{content}</td>")
            body.append("<tr>" + "".join(cells) + "</tr>")
        caption_html = f"<caption>{html.escape(caption)}</caption>" if caption else ""
        self._add(f'<table class="front">{caption_html}<thead><tr>{head}</tr></thead>'
                  f'<tbody>{"".join(body)}</tbody></table>')

    def table(self, frame: pd.DataFrame, *, caption: str | None = None, index: bool = False,
              float_format: str = "{:.4g}", name: str | None = None) -> None:
        """A table (and ``tables_dir/<name>.csv`` when ``name`` is given and the report has a tables folder).

        A table of more than :data:`MAX_INLINE_ROWS` rows is collapsed under its caption.
        """
        rendered = frame.to_html(index=index, float_format=float_format.format, border=0, na_rep="-")
        caption_html = f"<p><em>{html.escape(caption)}</em></p>" if caption else ""
        if name and self.tables_dir is not None:
            path = Path(self.tables_dir) / f"{file_stem(name)}.csv"
            text = frame.to_csv(index=index)
            # a study may have written the same table already (same name, same content): keep it;
            # a different table under the same name is a bug, never a silent overwrite
            if not (path.exists() and path.read_text(encoding="utf-8") == text):
                write_text_atomic(path, text)
            self.table_files.append(path)
            caption_html += f'<p class="file">CSV: tables/{html.escape(path.name)}</p>'
        if len(frame) > MAX_INLINE_ROWS and not self._fold_depth:
            label = f"show the table ({len(frame)} rows): {caption or name or 'table'}"
            self._add(f'<details class="fold"><summary>{html.escape(label)}</summary>{caption_html}{rendered}'
                      "</details>")
        else:
            self._add(caption_html + rendered)

    def figure(self, figure, *, caption: str, name: str, alt: str | None = None) -> None:
        """Embed a matplotlib Figure as a base64 PNG; also ``figures_dir/<name>.png`` and ``.svg``.

        ``caption`` is the one line under the figure (what to look at); ``alt`` (default the
        caption) describes the picture for readers who cannot see it.
        """
        started = time.perf_counter()
        stem = file_stem(name)
        if self._can_fork():
            self._fork_render(figure, name, alt or caption, caption)
        else:
            png, svg = _render_figure(figure, with_svg=self.figures_dir is not None)
            if self.figures_dir is not None:
                self.figure_files.append(write_bytes_atomic(Path(self.figures_dir) / f"{stem}.png", png))
                self.figure_files.append(write_bytes_atomic(Path(self.figures_dir) / f"{stem}.svg", svg))
            self._pngs[stem] = png
            self._add(_figure_html(stem, alt or caption, caption, png))
        if self.keep_figures:  # for the PDF export (idkit.report.pdf)
            self.kept_figures.append((figure, caption))
        self.figure_seconds += time.perf_counter() - started

    def thumbnail(self, name: str, label: str) -> None:
        """A small copy of the figure ``name`` (drawn before or after this call), linked to it.

        Consecutive thumbnails share one row. :meth:`render` refuses a thumbnail whose figure
        was never drawn.
        """
        token = f"\x00thumbnail {len(self._thumbnails)}\x00"
        self._thumbnails[token] = (file_stem(name), label)
        parts = self._sections[-1].parts if self._sections else None
        if parts and parts[-1] == "</div>" and len(parts) > 1 and parts[-2].startswith("\x00thumbnail"):
            parts.insert(len(parts) - 1, token)
        else:
            self._add('<div class="thumbs">')
            self._add(token)
            self._add("</div>")

    def _thumbnail_html(self, token: str) -> str:
        stem, label = self._thumbnails[token]
        if stem not in self._pngs:
            raise ValueError(f"thumbnail: no figure named {stem!r} on the page")
        encoded = base64.b64encode(self._pngs[stem]).decode("ascii")
        return (f'<a href="#figure-{html.escape(stem)}" title="open the figure"><img alt="{html.escape(label)}" '
                f'src="data:image/png;base64,{encoded}">{html.escape(label)}</a>')

    def _can_fork(self) -> bool:
        return self.render_processes > 1 and self.figures_dir is not None and can_fork()

    def _fork_render(self, figure, name: str, alt: str, caption: str) -> None:
        if not self._pending:
            _warm_up()  # every child inherits the loaded fonts and text caches
        while sum(1 for entry in self._pending.values() if entry[0] is not None) >= self.render_processes:
            self._collect(next(token for token, entry in self._pending.items() if entry[0] is not None))
        token = f"\x00figure {len(self._pending)}\x00"
        self._pending[token] = (fork_call(_render_figure, figure, with_svg=True), name, alt, caption)
        self._add(token)

    def _collect(self, token: str) -> None:
        """Wait for one child's figure, save its files and keep its HTML for the token."""
        call, name, alt, caption = self._pending[token]
        try:
            png, svg = call.result()
        except Exception as problem:
            self.abandon_figures()
            raise OutputError(f"figure {name!r}: rendering it failed in its child process ({problem})") from problem
        stem = file_stem(name)
        self.figure_files.append(write_bytes_atomic(Path(self.figures_dir) / f"{stem}.png", png))
        self.figure_files.append(write_bytes_atomic(Path(self.figures_dir) / f"{stem}.svg", svg))
        self._pngs[stem] = png
        self._pending[token] = (None, _figure_html(stem, alt, caption, png), None, None)

    def abandon_figures(self) -> None:
        """Stop every child still rendering, without embedding (on an error, before the folder goes)."""
        for token, entry in list(self._pending.items()):
            if entry[0] is not None:
                entry[0].abandon()
                self._pending[token] = (None, "", None, None)

    def finish_figures(self) -> None:
        """Wait for the figures rendered by child processes and embed them (see the module docstring)."""
        started = time.perf_counter()
        for token in list(self._pending):
            if self._pending[token][0] is not None:
                self._collect(token)
        if self._pending:
            embedded = {token: entry[1] for token, entry in self._pending.items()}
            for section in self._sections:
                section.parts[:] = [embedded.get(part, part) for part in section.parts]
            self._pending.clear()
        self.figure_seconds += time.perf_counter() - started

    @property
    def section_titles(self) -> list[str]:
        return [section.title for section in self._sections]

    def render(self) -> str:
        self.finish_figures()
        for section in self._sections:
            section.parts[:] = [self._thumbnail_html(part) if part in self._thumbnails else part
                                for part in section.parts]
        blocks = []
        for section in self._sections:
            content = "\n".join(section.parts)
            title = html.escape(section.title)
            if section.front:
                blocks.append(f'<section id="{section.anchor}" class="front"><h2>{title}</h2>\n{content}</section>')
            elif section.collapsed:
                gist = f'<span class="gist">{html.escape(section.gist)}</span>' if section.gist else ""
                blocks.append(f'<section id="{section.anchor}"><details><summary><h2>{title}</h2>{gist}</summary>\n'
                              f"{content}\n</details></section>")
            else:
                blocks.append(f'<section id="{section.anchor}"><h2>{title}</h2>\n{content}</section>')
        body = "\n".join(blocks)
        return (f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
                f"<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
                f"<title>{html.escape(self.title)}</title><style>{_STYLE}</style>"
                f"<script>{_OPEN_TARGET}</script></head>\n"
                f"<body><h1>{html.escape(self.title)}</h1>\n{body}\n</body></html>\n")
