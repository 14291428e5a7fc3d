"""A small, dependency-free builder of self-contained HTML reports.

Figures are embedded as base64 PNG, tables are rendered by pandas; nothing is
fetched from the network when the file is opened.
"""

from __future__ import annotations

import base64
import html
import io
from dataclasses import dataclass, field

import pandas as pd

__all__ = ["HtmlReport"]

_STYLE = """
body { font-family: system-ui, sans-serif; margin: 2em auto; max-width: 1100px; color: #222; }
h1 { border-bottom: 2px solid #345; padding-bottom: .2em; }
h2 { border-bottom: 1px solid #aab; margin-top: 2em; }
table { border-collapse: collapse; font-size: 0.85em; margin: .6em 0; }
th, td { border: 1px solid #ccd; padding: .2em .5em; text-align: right; }
th { background: #eef; }
pre { background: #f6f6f8; padding: .6em; overflow-x: auto; font-size: 0.85em; }
.pass { color: #176b2c; font-weight: bold; } .fail { color: #a11; font-weight: bold; } .inconclusive { color: #8a5a00; font-weight: bold; }
nav a { margin-right: 1em; } figure { margin: 1em 0; } figcaption { font-size: .85em; color: #555; }
img { max-width: 100%; }
"""


@dataclass
class HtmlReport:
    """Collects sections of HTML and renders one self-contained page."""

    title: str
    _sections: list[tuple[str, str, list[str]]] = field(default_factory=list)

    def section(self, title: str, anchor: str) -> None:
        """Start a new section; later content goes into it."""
        self._sections.append((title, anchor, []))

    def _add(self, fragment: str) -> None:
        if not self._sections:
            self.section("Overview", "overview")
        self._sections[-1][2].append(fragment)

    def paragraph(self, text: str) -> None:
        self._add(f"<p>{html.escape(text)}</p>")

    def verdict(self, label: str, verdict: str) -> None:
        """One validation verdict: ``"PASS"``, ``"INCONCLUSIVE"`` or ``"FAIL"``."""
        css = {"PASS": "pass", "FAIL": "fail"}.get(verdict, "inconclusive")
        self._add(f'<p>{html.escape(label)}: <span class="{css}">{html.escape(verdict)}</span></p>')

    def preformatted(self, text: str) -> None:
        self._add(f"<pre>{html.escape(text)}</pre>")

    def table(self, frame: pd.DataFrame, *, caption: str | None = None, index: bool = False,
              float_format: str = "{:.4g}") -> None:
        rendered = frame.to_html(index=index, float_format=float_format.format, border=0, na_rep="-")
        caption_html = f"<p><em>{html.escape(caption)}</em></p>" if caption else ""
        self._add(caption_html + rendered)

    def figure(self, figure, *, caption: str = "") -> None:
        """Embed a matplotlib Figure as a base64 PNG."""
        buffer = io.BytesIO()
        figure.savefig(buffer, format="png", dpi=90)
        encoded = base64.b64encode(buffer.getvalue()).decode("ascii")
        self._add(f'<figure><img alt="{html.escape(caption)}" src="data:image/png;base64,{encoded}">'
                  f"<figcaption>{html.escape(caption)}</figcaption></figure>")

    def image_file(self, path, *, caption: str = "") -> None:
        """Embed a PNG file written elsewhere (e.g. by a study)."""
        encoded = base64.b64encode(path.read_bytes()).decode("ascii")
        self._add(f'<figure><img alt="{html.escape(caption)}" src="data:image/png;base64,{encoded}">'
                  f"<figcaption>{html.escape(caption)}</figcaption></figure>")

    @property
    def section_titles(self) -> list[str]:
        return [title for title, _, _ in self._sections]

    def render(self) -> str:
        navigation = " ".join(f'<a href="#{anchor}">{html.escape(title)}</a>' for title, anchor, _ in self._sections)
        body = "\n".join(f'<section id="{anchor}"><h2>{html.escape(title)}</h2>\n' + "\n".join(parts) + "</section>"
                         for title, anchor, parts in self._sections)
        return (f"<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
                f"<title>{html.escape(self.title)}</title><style>{_STYLE}</style></head>\n"
                f"<body><h1>{html.escape(self.title)}</h1><nav>{navigation}</nav>\n{body}\n</body></html>\n")
