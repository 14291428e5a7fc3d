"""The PDF export: every section's text and every figure with its caption, through matplotlib."""

import re

import pandas as pd
from matplotlib.figure import Figure

from idkit.report.html import HtmlReport
from idkit.report.pdf import LINES_PER_PAGE, write_pdf


def _pages(path):
    return len(re.findall(rb"/Type\s*/Page[^s]", path.read_bytes()))


def test_pdf_holds_the_text_pages_and_one_page_per_figure(tmp_path):
    report = HtmlReport("idkit report: test", keep_figures=True)
    report.section("Summary", "summary")
    report.items([("PASS", "wire rope sweeps: predicts well"), "a sentence with <angle> brackets"])
    report.section("Long", "long")
    report.preformatted("\n".join(f"line {i}" for i in range(LINES_PER_PAGE + 5)))  # two text pages
    report.table(pd.DataFrame({"a": [1.0]}), caption="a table (kept as CSV, not in the PDF)")
    figure = Figure()
    figure.subplots().plot([0, 1], [0, 1])
    report.figure(figure, caption="a line: look at its slope", name="line")
    path = tmp_path / "report.pdf"
    write_pdf(report, path)
    assert path.read_bytes().startswith(b"%PDF")
    assert _pages(path) == 1 + 2 + 1
    assert len(figure.texts) == 0  # the caption added for the PDF page is removed again
