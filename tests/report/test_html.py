"""The HTML writer: figures embedded and saved as PNG and SVG, tables as CSV, collapsed sections."""

import inspect

import pandas as pd
import pytest

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
    assert '<section id="provenance"><details><summary><h2>Provenance</h2>' in page
    assert page.index("<details>") > page.index('id="provenance"')
    assert [p.name for p in report.figure_files] == ["a_line.png", "a_line.svg"]
    assert pd.read_csv(tmp_path / "one_row.csv")["a [m]"].tolist() == [1.0]


def _make_report(root, processes, broken):
    """Five log-log figures between paragraphs (the fourth broken on request), written to root/."""
    import numpy as np

    from idkit.plot._figure import new_axes
    from idkit.report.html import HtmlReport

    (root / "figures").mkdir(parents=True)
    report = HtmlReport("t", figures_dir=root / "figures", render_processes=processes)
    report.section("S", "s")
    for index in range(5):
        ax = new_axes()
        ax.loglog(np.arange(1, 50), np.arange(1, 50) ** (index + 1), label=f"curve {index}")
        ax.set_title(f"figure {index}")
        ax.legend()
        if broken and index == 3:
            ax.text(0.5, 0.5, "$\\notacommand$")  # mathtext fails only when the figure is drawn
        report.figure(ax.figure, caption=f"caption {index}", name=f"figure {index}")
        report.paragraph(f"after {index}")
    (root / "report.html").write_text(report.render())


# the same function run as a script in a fresh interpreter: a good report, then one whose
# fourth figure fails, each into its own folder; a failure's traceback goes to stderr and the
# last line names the reports that failed
_FORKED_SCRIPT = inspect.getsource(_make_report) + '''
import sys
import traceback
from pathlib import Path

failed = []
for name, broken in (("forked", False), ("broken", True)):
    try:
        _make_report(Path(sys.argv[1]) / name, 2, broken)
    except Exception:
        traceback.print_exc()
        failed.append(name)
print("failed:", " ".join(failed))
'''


@pytest.fixture(scope="module")
def forked_reports(tmp_path_factory):
    """The good and the broken report, built by child processes of one fresh interpreter."""
    import subprocess
    import sys

    root = tmp_path_factory.mktemp("forked")
    script = root / "make_report.py"
    script.write_text(_FORKED_SCRIPT)
    # a fresh interpreter: one Python thread, so the report may fork (pytest-xdist workers run two)
    done = subprocess.run([sys.executable, str(script), str(root)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    return root, done


def test_figures_rendered_by_child_processes_equal_those_rendered_in_process(tmp_path, forked_reports):
    root, done = forked_reports
    assert "forked" not in done.stdout.splitlines()[-1].split()[1:], done.stderr
    # the reference renders in this process: with no child processes there is nothing to fork,
    # so the fresh interpreter is needed only for the forked report
    _make_report(tmp_path / "inline", 0, False)
    forked, inline = root / "forked", tmp_path / "inline"
    names = sorted(p.name for p in (inline / "figures").iterdir())
    assert names == sorted(p.name for p in (forked / "figures").iterdir())
    assert len(names) == 10  # five PNG + five SVG
    for name in names:
        assert (forked / "figures" / name).read_bytes() == (inline / "figures" / name).read_bytes(), name
    html_forked, html_inline = (forked / "report.html").read_text(), (inline / "report.html").read_text()
    assert html_forked == html_inline
    # the figures stay in the order they were added, between the paragraphs
    order = [html_forked.index(f"caption {i}") for i in range(5)] + [html_forked.index("after 4")]
    assert order == sorted(order)


def test_a_figure_that_fails_in_its_child_process_is_named(forked_reports):
    root, done = forked_reports
    assert done.stdout.splitlines()[-1].split()[1:] == ["broken"]
    assert "figure 3" in done.stderr and "OutputError" in done.stderr
    assert not (root / "broken" / "report.html").exists()


def test_a_placeholder_is_filled_where_it_was_reserved(tmp_path):
    report = HtmlReport("t", figures_dir=tmp_path)
    report.section("Summary", "summary")
    report.paragraph("first")
    slot = report.placeholder()
    report.paragraph("after the slot")
    report.section("Later", "later")
    report.paragraph("written before the slot's content")
    with report.filling(slot):
        report.heading("filled")
        ax = new_axes()
        ax.plot([0, 1], [1, 0])
        report.figure(ax.figure, caption="a figure inside the slot", name="slot figure")
    page = report.render()
    order = [page.index(text) for text in ("first", "filled", "a figure inside the slot", "after the slot",
                                           "written before the slot")]
    assert order == sorted(order)
    assert "\x00" not in page
    assert report.section_titles == ["Summary", "Later"]
    assert (tmp_path / "slot_figure.png").exists()


def test_filling_an_unknown_placeholder_is_an_error():
    report = HtmlReport("t")
    report.section("S", "s")
    slot = report.placeholder()
    with report.filling(slot):
        report.paragraph("once")
    with pytest.raises(ValueError, match="no placeholder"):
        with report.filling(slot):
            report.paragraph("twice")
    assert "twice" not in report.render() and "once" in report.render()


def test_text_dumps_and_long_tables_are_collapsed_and_a_gist_stands_beside_a_collapsed_title():
    from idkit.report.html import MAX_INLINE_ROWS

    report = HtmlReport("t")
    report.section("Fit", "fit", collapsed=True)
    report.summarize("order 2, error 1.2 %")
    report.preformatted("[[Variables]]\n    k: 1", label="show the fit log")
    report.table(pd.DataFrame({"a": range(MAX_INLINE_ROWS)}), caption="short")
    report.table(pd.DataFrame({"b": range(MAX_INLINE_ROWS + 1)}), caption="per point")
    with report.folded("show more"):
        report.preformatted("inside a fold already")
    page = report.render()
    assert '<summary><h2>Fit</h2><span class="gist">order 2, error 1.2 %</span></summary>' in page
    assert '<details class="fold"><summary>show the fit log</summary><pre>[[Variables]]' in page
    assert f"<summary>show the table ({MAX_INLINE_ROWS + 1} rows): per point</summary>" in page
    assert page.count('<details class="fold">') == 3  # the log, the long table, the fold (its log not again)
    assert "<p><em>short</em></p><table" in page  # a short table stays open


def test_a_thumbnail_shows_a_figure_drawn_later_and_links_to_it(tmp_path):
    report = HtmlReport("t", figures_dir=tmp_path)
    report.section("Summary", "summary", front=True)
    report.thumbnail("a line", "the line")
    report.thumbnail("a dot", "the dot")
    report.section("Details", "details", collapsed=True)
    for name in ("a line", "a dot"):
        ax = new_axes()
        ax.plot([0, 1], [0, 1])
        report.figure(ax.figure, caption=name, name=name)
    page = report.render()
    assert page.count('<div class="thumbs">') == 1  # consecutive thumbnails share a row
    assert '<a href="#figure-a_line" title="open the figure"><img alt="the line"' in page
    assert page.count("data:image/png;base64,") == 4
    assert '<section id="summary" class="front">' in page
    broken = HtmlReport("t")
    broken.section("S", "s")
    broken.thumbnail("never drawn", "x")
    with pytest.raises(ValueError, match="never_drawn"):
        broken.render()


def _figure_with_the_report_s_text():
    """A small figure with what makes the report's figures costly to lay out: a log-log panel
    (minor ticks and grid, mathtext tick labels and label, a title, a legend placed by
    matplotlib) beside a colour mesh with a log colour bar."""
    import numpy as np
    from matplotlib.colors import LogNorm

    curve_ax, mesh_ax = new_axes(1, 2)
    frequency = np.geomspace(1.0, 200.0, 40)
    curve_ax.loglog(frequency, 1.0 / np.abs(1.0 - (frequency / 20.0) ** 2 + 0.1j * frequency / 20.0), label="model")
    curve_ax.loglog(frequency[::4], frequency[::4] ** -0.5, ".", label="measured")
    curve_ax.set_title("panel", fontsize="small")
    curve_ax.set_ylabel("|H| [-] (m/s$^2$)")
    curve_ax.grid(True, which="both", alpha=0.3)
    curve_ax.legend(fontsize="x-small", title="legend")
    mesh = mesh_ax.pcolormesh(frequency[::8], frequency[::10], np.outer(frequency[:3], frequency[:4]) * 1e-6,
                              norm=LogNorm(), shading="flat")
    mesh_ax.set_xscale("log")
    mesh_ax.figure.colorbar(mesh, ax=mesh_ax, label="|H2| [-]")
    return curve_ax.figure


def _render_as_matplotlib_lays_out(figure):
    """PNG and SVG the plain way: ``savefig`` runs the layout engine in a draw of its own before each file."""
    import io

    from matplotlib import rc_context

    from idkit.report.html import PNG_DPI

    png = io.BytesIO()
    figure.savefig(png, format="png", dpi=PNG_DPI)
    figure.set_layout_engine("none")  # the SVG keeps the PNG's placement
    svg = io.BytesIO()
    with rc_context({"svg.hashsalt": "idkit"}):
        figure.savefig(svg, format="svg", metadata={"Date": None})
    return png.getvalue(), svg.getvalue()


def test_a_figure_laid_out_once_gives_the_files_matplotlib_s_own_layout_pass_gives():
    from idkit.report.html import _render_figure

    figure = _figure_with_the_report_s_text()
    canvas = figure.canvas
    draws = []
    figure.canvas.mpl_connect("draw_event", lambda event: draws.append(type(event.canvas).__name__))
    png, svg = _render_figure(figure, with_svg=True)
    # one draw per file: the layout is solved without drawing, on the canvas the PNG is drawn on
    assert draws == ["FigureCanvasAgg", "FigureCanvasSVG"]
    assert figure.canvas is canvas  # the caller's canvas is given back
    assert figure.get_layout_engine() is None
    # byte for byte what matplotlib writes when it solves the layout in a draw of its own
    reference_png, reference_svg = _render_as_matplotlib_lays_out(_figure_with_the_report_s_text())
    assert png == reference_png
    assert svg == reference_svg


def test_a_figure_rendered_without_its_svg_gives_the_png_alone():
    from idkit.report.html import _render_figure

    def line():
        ax = new_axes()
        ax.plot([0.0, 1.0], [0.0, 2.0])
        ax.set_xlabel("time [s]")
        return ax.figure

    assert _render_figure(line(), with_svg=False) == (_render_as_matplotlib_lays_out(line())[0], None)
