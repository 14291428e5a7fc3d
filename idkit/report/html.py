"""A small, dependency-free builder of self-contained HTML reports.

Figures are embedded as base64 PNG and, when the report is given a ``figures_dir``, also
saved there as PNG and SVG; tables are rendered by pandas and, with a ``tables_dir``, also
written there as CSV. Nothing is fetched from the network when the file is opened. A
section can be collapsed (``<details>``) so that bulky provenance stays out of the way.

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

__all__ = ["MAX_TABLE_COLUMNS", "HtmlReport", "file_stem"]

#: widest table the page shows (columns, index included); wider ones are transposed or split by the caller
MAX_TABLE_COLUMNS = 12

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
"""


def _render_figure(figure, *, with_svg: bool) -> tuple[bytes, bytes | None]:
    """PNG (90 dpi) and, when asked, SVG bytes of a figure."""
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", dpi=90)
    if not with_svg:
        return buffer.getvalue(), None
    # the layout was solved for the PNG: keep it rather than solve it again for the SVG
    figure.set_layout_engine("none")
    from matplotlib import rc_context

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
    _sections: list[tuple[str, str, list[str], bool]] = field(default_factory=list)
    _pending: dict = field(default_factory=dict)

    def section(self, title: str, anchor: str, *, collapsed: bool = False) -> None:
        """Start a new section; later content goes into it (inside a closed ``<details>`` when ``collapsed``)."""
        self._sections.append((title, anchor, [], collapsed))

    def _add(self, fragment: str) -> None:
        if not self._sections:
            self.section("Overview", "overview")
        self._sections[-1][2].append(fragment)

    def placeholder(self) -> str:
        """Reserve the current place for content added later with :meth:`filling`; returns its token."""
        token = f"\x00placeholder {sum(len(parts) for _, _, parts, _ in self._sections)}\x00"
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
        self._sections = [("", "", [], False)]
        try:
            yield
        finally:
            filled = self._sections[0][2]
            self._sections = saved
        for _, _, parts, _ in self._sections:
            if token in parts:
                at = parts.index(token)
                parts[at:at + 1] = filled
                return
        raise ValueError("filling: no placeholder with this token (already filled?)")

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

    def preformatted(self, text: str) -> None:
        self._add(f"<pre>{html.escape(text)}</pre>")

    def table(self, frame: pd.DataFrame, *, caption: str | None = None, index: bool = False,
              float_format: str = "{:.4g}", name: str | None = None) -> None:
        """A table (and ``tables_dir/<name>.csv`` when ``name`` is given and the report has a tables folder)."""
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
            self._add(_figure_html(stem, alt or caption, caption, png))
        if self.keep_figures:  # for the PDF export (idkit.report.pdf)
            self.kept_figures.append((figure, caption))
        self.figure_seconds += time.perf_counter() - started

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
            for _, _, parts, _ in self._sections:
                parts[:] = [embedded.get(part, part) for part in parts]
            self._pending.clear()
        self.figure_seconds += time.perf_counter() - started

    @property
    def section_titles(self) -> list[str]:
        return [title for title, _, _, _ in self._sections]

    def render(self) -> str:
        self.finish_figures()
        navigation = " ".join(f'<a href="#{anchor}">{html.escape(title)}</a>' for title, anchor, _, _ in self._sections)
        blocks = []
        for title, anchor, parts, collapsed in self._sections:
            content = "\n".join(parts)
            if collapsed:
                content = f"<details><summary>show {html.escape(title.lower())}</summary>\n{content}\n</details>"
            blocks.append(f'<section id="{anchor}"><h2>{html.escape(title)}</h2>\n{content}</section>')
        body = "\n".join(blocks)
        return (f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
                f"<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
                f"<title>{html.escape(self.title)}</title><style>{_STYLE}</style></head>\n"
                f"<body><h1>{html.escape(self.title)}</h1><nav>{navigation}</nav>\n{body}\n</body></html>\n")
