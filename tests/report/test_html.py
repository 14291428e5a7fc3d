"""The HTML writer: figures embedded and saved as PNG and SVG, tables as CSV, collapsed sections."""

import pandas as pd

from idkit.plot._figure import new_axes
from idkit.report.html import HtmlReport


def test_figures_and_tables_are_embedded_and_saved(tmp_path):
    report = HtmlReport("t", figures_dir=tmp_path, tables_dir=tmp_path)
    report.section("Results", "results")
    ax = new_axes()
    ax.plot([0, 1], [0, 1])
    report.figure(ax.figure, caption="a line: look at its slope", name="a line", alt="straight line")
    report.table(pd.DataFrame({"a [m]": [1.0]}), caption="one row", name="one row")
    report.section("Provenance", "provenance", collapsed=True)
    report.paragraph("hashes")
    page = report.render()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a_line.png", "a_line.svg", "one_row.csv"]
    assert (tmp_path / "a_line.svg").read_text().lstrip().startswith("<?xml")
    assert 'alt="straight line"' in page and "<figcaption>a line: look at its slope</figcaption>" in page
    assert "<details><summary>show provenance</summary>" in page
    assert page.index("<details>") > page.index('id="provenance"')
    assert [p.name for p in report.figure_files] == ["a_line.png", "a_line.svg"]
    assert pd.read_csv(tmp_path / "one_row.csv")["a [m]"].tolist() == [1.0]
