"""The report as a PDF: the same text, figures and tables, through matplotlib's PDF backend.

Chosen because it needs nothing outside the package registries (matplotlib is already a
dependency; HTML-to-PDF converters need a browser engine or system libraries such as
Pango/Cairo). The PDF is built from the :class:`~idkit.report.html.HtmlReport` after it
has collected its content: each section's text (tags stripped, long lines wrapped) on A4
text pages, every figure on its own page with its caption underneath. Tables are kept as
CSV files beside the report (``tables/``); the PDF lists their names.
"""

from __future__ import annotations

import textwrap
from html.parser import HTMLParser

from matplotlib.backends.backend_pdf import PdfPages
from matplotlib.figure import Figure

__all__ = ["write_pdf"]

A4_INCHES = (8.27, 11.69)
LINES_PER_PAGE = 90
WRAP_COLUMNS = 100


class _Text(HTMLParser):
    """Text lines of an HTML fragment: one line per block element, list items bulleted."""

    _BLOCKS = {"p", "li", "h2", "h3", "pre", "tr", "summary", "figcaption", "div"}

    def __init__(self):
        super().__init__()
        self.lines: list[str] = [""]
        self._skip = 0

    def handle_starttag(self, tag, attrs):
        if tag in ("table", "figure", "img", "style"):
            self._skip += tag != "img"
            return
        if tag in self._BLOCKS:
            self.lines.append("- " if tag == "li" else "")

    def handle_endtag(self, tag):
        if tag in ("table", "figure", "style"):
            self._skip -= 1

    def handle_data(self, data):
        if not self._skip:
            if "\n" in data:  # preformatted text keeps its lines
                first, *rest = data.split("\n")
                self.lines[-1] += first
                self.lines.extend(rest)
            else:
                self.lines[-1] += data


def _text_pages(title: str, lines: list[str]) -> list[Figure]:
    wrapped = []
    for line in lines:
        wrapped.extend(textwrap.wrap(line, WRAP_COLUMNS, subsequent_indent="  ") or [""])
    pages = []
    for start in range(0, max(len(wrapped), 1), LINES_PER_PAGE):
        figure = Figure(figsize=A4_INCHES)
        figure.text(0.06, 0.96, title, fontsize=12, weight="bold", va="top")
        figure.text(0.06, 0.93, "\n".join(wrapped[start:start + LINES_PER_PAGE]), fontsize=7.2,
                    family="monospace", va="top")
        pages.append(figure)
    return pages


def write_pdf(report, path) -> None:
    """Write ``report`` (an :class:`~idkit.report.html.HtmlReport` with ``keep_figures``) to ``path``.

    Text of every section first (the summary reads first, as in the HTML), then every
    figure with its caption. The caller writes into a staging folder (the output folder is
    swapped in only when complete), so a failed export leaves no partial file behind.
    """
    with PdfPages(path, metadata={"Title": report.title, "Creator": "idkit"}) as pdf:
        for section in report._sections:
            parser = _Text()
            parser.feed("\n".join(section.parts))
            lines = [line.rstrip() for line in parser.lines]
            while lines and not lines[0]:
                lines.pop(0)
            for page in _text_pages(f"{report.title}: {section.title}", lines):
                pdf.savefig(page)
        for figure, caption in report.kept_figures:
            note = figure.text(0.5, 0.003, textwrap.fill(caption, 140), ha="center", va="bottom", fontsize=7)
            pdf.savefig(figure)
            note.remove()
