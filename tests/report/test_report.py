"""``idkit report`` end to end on the bundled data (quick mode) and its safety rules."""

import json
import re
from html import unescape
from html.parser import HTMLParser
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from idkit.cli.main import main
from idkit.report.html import MAX_TABLE_COLUMNS
from idkit.report.main_report import REPORT_SECTIONS

DATA = Path(__file__).resolve().parents[2] / "data"


STATUS = {}


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("reports") / "report"
    STATUS["report"] = main(["report", str(DATA), "-o", str(out), "--quick", "--quiet"])
    verdicts = {}
    for line in (out / "report.html").read_text(encoding="utf-8").split("<li>"):  # one sentence per validation
        found = re.match(r'<span class="\w+">(PASS|INCONCLUSIVE|FAIL)</span> ([a-z ]+(?:sweeps|drops|FRF)) \(', line)
        if found:
            verdicts[found.group(2)] = found.group(1)
    STATUS["verdicts"] = verdicts
    return out


@pytest.mark.slow
def test_exit_status_follows_the_verdicts(quick_report):
    """0 only when everything passes; 1 when a validation fails; 3 when none fails but one is
    inconclusive; 4 when every validation passes but the Iwan or Maxwell fit (the models the
    report predicts with) is not a success, as its model file records."""
    html = (quick_report / "report.html").read_text(encoding="utf-8")
    # the validations' verdicts (the conclusions also mark each fit: "the fit succeeded" or
    # "the fit is not a success")
    entries = re.findall(r'<li><span class="(pass|fail|inconclusive)">[^<]*</span>([^<]*)</li>', html)
    verdicts = [css for css, text in entries if "the fit " not in text]
    failed, inconclusive = "fail" in verdicts, "inconclusive" in verdicts
    flagged = [name for name in ("wire_rope_iwan.json", "elastomer_maxwell.json")
               if not json.loads((quick_report / "models" / name).read_text())["provenance"]["success"]]
    assert len(verdicts) >= 1
    assert STATUS["report"] == (1 if failed else 3 if inconclusive else 4 if flagged else 0)
    assert "quick run: at most 8 held-out records" in html  # a quick verdict says so


def test_exit_status_rules():
    from idkit.exit_status import REPORT_EXIT_STATUSES
    from idkit.report.main_report import ReportSummary

    def status(verdicts, reasons):
        return ReportSummary(out_dir=Path("."), html=Path("r.html"), sections=(), validation_passed={}, timings_s={},
                             validation_verdicts=verdicts, fit_reasons=reasons).exit_status

    fine = {"wire rope (Iwan)": (), "elastomer (generalized Maxwell)": ()}
    flagged = {"wire rope (Iwan)": ("small-loop error far above the noise floor",), "elastomer (generalized Maxwell)": ()}
    assert status({"a": "PASS", "b": "PASS"}, fine) == 0
    assert status({"a": "PASS", "b": "PASS"}, flagged) == 4
    assert status({"a": "PASS", "b": "INCONCLUSIVE"}, flagged) == 3
    assert status({"a": "FAIL", "b": "INCONCLUSIVE"}, fine) == 1
    assert set(REPORT_EXIT_STATUSES) == {0, 1, 3, 4}


def test_printed_verdicts_carry_their_reasons_notes_and_the_flagged_fits():
    # the terminal said FAIL or INCONCLUSIVE and no more: the reason was only in the HTML
    from idkit.cli.report import verdict_lines
    from idkit.report.main_report import ReportSummary

    summary = ReportSummary(out_dir=Path("."), html=Path("r.html"), sections=(), validation_passed={}, timings_s={},
                            validation_verdicts={"wire rope sweeps": "FAIL", "wire rope drops": "PASS",
                                                 "hybrid sweeps": "INCONCLUSIVE"},
                            fit_reasons={"wire rope (Iwan)": ("hit a bound",)}, quick=True,
                            validation_notes={"wire rope sweeps": ("level 0.002 lies below the loops",)},
                            validation_reasons={"wire rope sweeps": ("max_peak_magnitude_error_db 4.2 > 3",),
                                                "wire rope drops": (),
                                                "hybrid sweeps": ("2 of 24 points not settled",)})
    assert verdict_lines(summary, "quick").splitlines() == [
        "FAIL          wire rope sweeps",
        "                why: max_peak_magnitude_error_db 4.2 > 3",
        "                note: level 0.002 lies below the loops",
        "PASS          wire rope drops",
        "INCONCLUSIVE  hybrid sweeps",
        "                why: 2 of 24 points not settled",
        "FLAGGED       wire rope (Iwan) fit: hit a bound",
        "(quick)",
    ]


@pytest.mark.slow
def test_report_names_every_section_and_writes_models(quick_report):
    html = (quick_report / "report.html").read_text(encoding="utf-8")
    for section in REPORT_SECTIONS:
        assert f"<h2>{section}</h2>" in html
    assert html.count("data:image/png;base64,") >= 8  # figures embedded: self-contained page
    assert "http://" not in html and "https://" not in html
    models = {p.name for p in (quick_report / "models").iterdir()}
    assert models == {"wire_rope_iwan.json", "wire_rope_bouc_wen.json", "elastomer_maxwell.json", "hybrid.json"}
    iwan = json.loads((quick_report / "models" / "wire_rope_iwan.json").read_text())
    assert iwan["provenance"]["data"]["files"] and iwan["provenance"]["seed"] == 2026
    provenance = json.loads((quick_report / "provenance.json").read_text())
    assert provenance["seed"] == 2026 and "wire_rope" in provenance["data_files_sha256"]
    # quick mode: the hybrid sweeps validated are the lowest and the highest amplitude level of the
    # bundled manifest, enough points each to judge a resonance (sorted by level, the first 8 records
    # were the lowest level's 3-11 Hz points), and the skipped ones are named
    skipped = set(provenance["quick_skipped_records"]["hybrid sweeps"])
    sweeps = [e for e in json.loads((DATA / "hybrid" / "manifest.json").read_text())["measurements"]
              if e["kind"] == "stepped_sine"]
    validated = [e["excitation"]["amplitude"] for e in sweeps if e["id"] not in skipped]
    levels = sorted({e["excitation"]["amplitude"] for e in sweeps})
    assert sorted(set(validated)) == [levels[0], levels[-1]] and min(map(validated.count, set(validated))) >= 3
    assert len(validated) == 8 and all(i in html for i in sorted(skipped)[:3])


@pytest.mark.slow
def test_report_refuses_to_overwrite_and_leaves_no_partial_folder(quick_report, capsys):
    before = sorted(p.name for p in quick_report.parent.iterdir())
    assert main(["report", str(DATA), "-o", str(quick_report), "--quick", "--quiet"]) == 2
    assert "exists" in capsys.readouterr().err
    assert sorted(p.name for p in quick_report.parent.iterdir()) == before


def test_report_on_a_folder_without_data_fails_clearly(tmp_path, capsys):
    (tmp_path / "empty").mkdir()
    assert main(["report", str(tmp_path / "empty"), "-o", str(tmp_path / "out"), "--quiet"]) == 2
    assert "no manifest.json" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_report_states_the_valid_range_of_the_identified_wire_rope(quick_report):
    """Named by the identified family (the bundled rope is slip-modulated, issue 10), with the
    margin the required range is built with and the drop model 'auto' resolved to."""
    html = unescape((quick_report / "report.html").read_text(encoding="utf-8"))
    iwan = json.loads((quick_report / "models" / "wire_rope_iwan.json").read_text())
    family = "slip-modulated Iwan" if "slip_modulation" in json.dumps(iwan) else "plain Iwan"
    assert f"Valid range of the identified {family} model: valid for deflections" in html
    assert "1.25 times the data set's deflections" in html
    # the first screen's model table names the family and the range
    summary = html[html.index('id="summary"'):html.index('id="data"')]
    assert f"<td>{family}, order " in summary
    from idkit.models import load_model

    lower, upper = load_model(quick_report / "models" / "wire_rope_iwan.json").valid_deflection_range()
    for edge in (lower, upper):  # the valid range column holds the model's own edges
        assert not np.isfinite(edge) or f"{1e3 * edge:.1f}" in summary
    assert "drop validations above use drop_model='auto', here the rig)" in html


@pytest.mark.slow
def test_timings_are_durations(quick_report):
    """Every stage time is a duration, never a raw clock reading (the HTML table once showed one)."""
    provenance = json.loads((quick_report / "provenance.json").read_text())
    durations = provenance["timings_s"]
    assert set(durations) >= {"loading and inspecting the data", "writing the report"}
    assert all(value >= 0 for value in durations.values()), durations
    html = (quick_report / "report.html").read_text(encoding="utf-8")
    assert "writing the report (until this table)" in html  # the running stage is labelled as such


@pytest.mark.slow
def test_iwan_table_shows_stderr_and_spread_across_repetitions(quick_report):
    html = (quick_report / "report.html").read_text(encoding="utf-8")
    assert "Iwan parameters: stderr from the residual Jacobian at the optimum" in html
    for column in ("stderr", "stderr_note", "repetition_std", "repetition_values"):
        assert f"<th>{column}</th>" in html, column
    assert "spread across repetitions: repetition, 2 refits" in html


@pytest.mark.slow
def test_drop_models_are_compared_and_the_supported_one_named(quick_report):
    """Conditioned vs rig, plain vs slip-modulated Iwan, on the same held-out drops (issue 15)."""
    table = pd.read_csv(quick_report / "tables" / "wire_rope_drop_models.csv")
    assert set(table["drop model"]) == {"conditioned", "rig"}
    assert "plain Iwan" in set(table["isolator model"])
    html = unescape((quick_report / "report.html").read_text(encoding="utf-8"))
    assert "The held-out drops support the" in html and "drop_model='auto'" in html
    # the named pair is the one with the smallest worst-phase median error among the PASSes
    passing = table[table["verdict"] == "PASS"].groupby(["isolator model", "drop model"])[
        ["median_compression_error [-]", "median_tension_error [-]"]].median().max(axis=1)
    model, drop = passing.idxmin()
    assert f"support the {model} model with the {drop} drop model" in html
    # the model-form evidence: both rope models' loop errors on the same loops, numbers as fitted
    if "slip-modulated Iwan" in set(table["isolator model"]):
        line = re.search(r"Loop error \(7\.1, small / large\) on the same fit loops: plain Iwan ([0-9.]+) / "
                         r"([0-9.]+) %, slip-modulated Iwan ([0-9.]+) / ([0-9.]+) %", html)
        assert line is not None
        saved = json.loads((quick_report / "models" / "wire_rope_iwan.json").read_text())
        assert float(line.group(1)) > 0 and float(line.group(3)) > 0
        # the model file holds the family the family rule chose, and says which
        family = saved["provenance"]["options"]["family"]
        assert saved["model"]["kind"] == {"plain": "iwan", "modulated": "iwan_modulated"}[family]


class _Page(HTMLParser):
    """The parts of the report a reader sees: sections, figures (alt, caption), tables (columns), details."""

    def __init__(self):
        super().__init__()
        self.sections, self.figures, self.tables, self.details_sections = [], [], [], []
        self.table_classes = []
        self._stack, self._text = [], None

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        self._stack.append(tag)
        if tag == "section":
            self.sections.append(attrs.get("id"))
        elif tag == "figure":
            self.figures.append({"alt": None, "caption": ""})
        elif tag == "img" and self.figures and "figure" in self._stack:
            self.figures[-1]["alt"] = attrs.get("alt")
        elif tag == "figcaption":
            self._text = "caption"
        elif tag == "table":
            self.tables.append(0)
            self.table_classes.append(attrs.get("class"))
        elif tag == "tr" and self.tables:
            self._row = 0
        elif tag in ("td", "th") and self.tables:
            self._row += int(attrs.get("colspan", 1))
            self.tables[-1] = max(self.tables[-1], self._row)
        elif tag == "details" and self._stack.count("details") == 1:
            self.details_sections.append(self.sections[-1])

    def handle_endtag(self, tag):
        while self._stack and self._stack.pop() != tag:
            pass
        if tag == "figcaption":
            self._text = None

    def handle_data(self, data):
        if self._text == "caption":
            self.figures[-1]["caption"] += data


def _page(folder):
    parser = _Page()
    parser.feed((folder / "report.html").read_text(encoding="utf-8"))
    return parser


@pytest.mark.slow
def test_page_answers_first_and_collapses_every_other_section(quick_report):
    page = _page(quick_report)
    assert page.sections[0] == "summary" and page.sections[-1] == "provenance"
    assert page.details_sections == page.sections[1:]  # every section below the first screen is collapsed
    html = unescape((quick_report / "report.html").read_text(encoding="utf-8"))
    summary = html[html.index('id="summary"'):html.index('id="data"')]
    # the verdict table: every validation and predicting fit, read off the results
    verdicts = dict(re.findall(r"<tr><td>([^<]+)</td>(?:<td[^>]*>[^<]*</td>){3}<td[^>]*><span class=\"\w+\">(\w+)</span>",
                               summary))
    for key, verdict in STATUS["verdicts"].items():
        assert verdicts[key] == verdict, key
    assert any(name.startswith("wire rope fit (") for name in verdicts)
    assert any(name.startswith("elastomer fit (") for name in verdicts)
    # the model table: the family rule's choice, values with standard errors
    assert re.search(r"(slip-modulated|plain) Iwan, order \d", summary) and " ± " in summary
    assert summary.count('<div class="thumbs">') == 1 and summary.count('href="#figure-') == 4
    assert "<pre>" not in summary and "<details" not in summary
    assert summary.count("protects the payload best") == 0  # the ranking sentences live in the study's section


@pytest.mark.slow
def test_transport_conclusion_names_the_lowest_rms_system(quick_report):
    """The words follow the numbers of the CSV the page was written with, level by level."""
    rms = pd.read_csv(quick_report / "tables" / "transport_rms.csv", index_col=0)
    html = unescape((quick_report / "report.html").read_text(encoding="utf-8"))
    for column in rms.columns:
        assert f"floor PSD {column}, RMS top acceleration: {rms[column].idxmin()} protects the payload best" in html


@pytest.mark.slow
def test_every_figure_has_caption_alt_text_and_files(quick_report):
    page = _page(quick_report)
    assert len(page.figures) >= 10
    for figure in page.figures:
        assert figure["alt"] and figure["caption"].strip(), figure
    figures = {p.name for p in (quick_report / "figures").iterdir()}
    pngs = {name[:-4] for name in figures if name.endswith(".png")}
    assert len(pngs) == len(page.figures)
    assert pngs == {name[:-4] for name in figures if name.endswith(".svg")}
    html = (quick_report / "report.html").read_text(encoding="utf-8")
    thumbnails = html.count('<div class="thumbs">') and re.findall(r'<a href="#figure-([^"]+)"', html)
    assert set(thumbnails) <= {figure[len("figure-"):] for figure in re.findall(r'<figure id="(figure-[^"]+)"', html)}
    assert html.count("data:image/png;base64,") == len(page.figures) + len(thumbnails)  # self-contained


@pytest.mark.slow
def test_no_table_is_wider_than_the_page_limit_and_every_table_has_a_csv(quick_report):
    page = _page(quick_report)
    assert max(page.tables) <= MAX_TABLE_COLUMNS, page.tables
    html = (quick_report / "report.html").read_text(encoding="utf-8")
    listed = re.findall(r"CSV: tables/([^<]+)</p>", html)
    assert len(listed) == sum(css != "front" for css in page.table_classes)  # the first-screen tables are texts
    assert all((quick_report / "tables" / name).stat().st_size > 0 for name in listed)
    assert "white-space: pre-wrap" in html  # warnings wrap instead of running off the page


@pytest.mark.slow
def test_the_rest_shock_figure_says_where_a_curve_ends(quick_report):
    shock = pd.read_csv(quick_report / "tables" / "transport_shock_vs_velocity.csv", index_col=0)
    ends = [name for name in shock.columns if np.isnan(shock[name].iloc[-1]) and np.isfinite(shock[name]).any()]
    html = unescape((quick_report / "report.html").read_text(encoding="utf-8"))
    for name in ends:
        assert f"the {name} curve stops at" in html
    provenance = json.loads((quick_report / "provenance.json").read_text())
    assert provenance["timings_s"]["drawing and saving the figures (part of the writing)"] >= 0


def test_the_figures_a_reader_of_the_study_expects_are_there(quick_report):
    """Issue 16's list: HOSIDF maps and Bode sections, equivalent stiffness and damping, the
    measured complex stiffness, drop time histories, shock response spectra, residuals and
    the parameters' spread, each drawn for every isolator it applies to."""
    stems = {p.stem for p in (quick_report / "figures").iterdir()}
    expected = {
        "wire_rope_hosidf_maps", "hybrid_hosidf_maps", "wire_rope_bode_sections", "hybrid_bode_sections",
        "wire_rope_equivalent_stiffness_and_loss_factor", "elastomer_measured_complex_stiffness",
        "wire_rope_drop_time_histories", "elastomer_drop_time_histories", "hybrid_drop_time_histories",
        "wire_rope_drop_srs", "wire_rope_iwan_residuals", "elastomer_frf_residuals",
        "wire_rope_iwan_parameter_spread", "elastomer_maxwell_parameter_spread",
    }
    assert expected <= stems, sorted(expected - stems)
    html = (quick_report / "report.html").read_text(encoding="utf-8")
    assert html.count('id="figure-hybrid_hosidf_maps"') == 1


def test_the_summary_states_the_outcome_and_the_exit_status(quick_report):
    """The page said every verdict but not what they add up to: a quick run whose validations
    all pass exits 4 when a predicting fit is flagged, which the page did not say."""
    from idkit.report.front_page import outcome_sentence

    assert outcome_sentence({"a": "PASS", "b": "PASS"}, ()) == (
        "Outcome: 2 PASS of 2 validation(s). idkit report exits with status 0: every validation passed and "
        "every fit the report predicts with is a success.")
    assert outcome_sentence({"a": "PASS", "b": "PASS"}, ("elastomer (generalized Maxwell)",)).endswith(
        "; not a success: elastomer (generalized Maxwell). idkit report exits with status 4: every validation "
        "passed, but a fit the report predicts with is not a success (see its reasons).")
    assert outcome_sentence({"a": "PASS", "b": "INCONCLUSIVE", "c": "FAIL"}, ()) == (
        "Outcome: 1 PASS, 1 INCONCLUSIVE, 1 FAIL of 3 validation(s). idkit report exits with status 1: "
        "a validation failed (c; inconclusive: b).")
    html = unescape((quick_report / "report.html").read_text(encoding="utf-8"))
    assert f"idkit report exits with status {STATUS['report']}:" in html


#: the first screen and the page limit of issue 30, CSS px (a 1280 x 1000 window)
SCREEN_WIDTH, SCREEN_HEIGHT, MAX_SCREENS = 1280, 1000, 10


@pytest.fixture(scope="module")
def browser_page(quick_report):
    """The quick report opened in headless Chromium at 1280 x 1000 (skipped where there is no browser)."""
    import shutil

    sync_api = pytest.importorskip("playwright.sync_api", reason="playwright is not installed (pip install "
                                                                 "'idkit-isolators[test]')")
    executable = next((found for name in ("chromium", "chromium-browser", "google-chrome")
                       if (found := shutil.which(name))), None)
    if executable is None:
        pytest.skip("no Chromium on PATH (e.g. apt-get install chromium): the page cannot be rendered")
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=executable)
        try:
            page = browser.new_page(viewport={"width": SCREEN_WIDTH, "height": SCREEN_HEIGHT})
            page.goto((quick_report / "report.html").as_uri())
            yield page
        finally:
            browser.close()


def _bottom(page, selector: str) -> float:
    return page.evaluate(f"Math.max(...Array.from(document.querySelectorAll('{selector}'))"
                         ".map(e => e.getBoundingClientRect().bottom + window.scrollY))")


@pytest.mark.slow
def test_the_page_answers_on_its_first_screen_and_fits_ten_screens(browser_page):
    """Rendered by a real browser: the verdict and model tables and the thumbnails lie within the
    first 1000 px, before any prose; the whole page is at most ten screens tall."""
    page = browser_page
    height = page.evaluate("document.documentElement.scrollHeight")
    assert height <= MAX_SCREENS * SCREEN_HEIGHT, height
    assert _bottom(page, "#summary table.front") <= SCREEN_HEIGHT
    assert _bottom(page, "#summary .thumbs img") <= SCREEN_HEIGHT
    assert page.locator("#summary table.front").count() == 2
    # a thumbnail leads to its figure: the collapsed section around it opens
    link = page.locator("#summary .thumbs a").first
    target = link.get_attribute("href")
    assert not page.locator(target).is_visible()
    link.click()
    page.wait_for_function(f"document.querySelector('{target}').closest('details').open")
    assert page.locator(target).is_visible()


@pytest.mark.slow
def test_no_text_dump_stands_outside_a_collapsed_block(quick_report, browser_page):
    """Fit logs, inspections and long tables are in <details>: on the page as it opens, none is
    visible, and the visible prose is a few sentences."""
    from idkit.report.html import MAX_INLINE_ROWS

    page = browser_page
    page.goto((quick_report / "report.html").as_uri())  # as opened, whatever the test before clicked
    assert page.locator("pre").count() >= 3
    assert page.locator("pre:visible").count() == 0
    visible = page.evaluate("document.body.innerText")
    for dump in ("[[Variables]]", "[[Fit Statistics]]", "sha256", "warning(s):"):
        assert dump not in visible, dump
    rows = page.evaluate("Array.from(document.querySelectorAll('table')).filter(t => t.checkVisibility())"
                         ".map(t => t.querySelectorAll('tbody tr').length)")
    assert rows and max(rows) <= MAX_INLINE_ROWS, rows
    prose = page.evaluate("Array.from(document.querySelectorAll('p')).filter(p => p.checkVisibility())"
                          ".map(p => p.innerText).join(' ')")
    assert len(re.findall(r"[.!?](?:\s|$)", prose)) <= 6, prose  # a few sentences
    # the same in the file, for a reader without a browser: every <pre> sits inside a <details>
    html = (quick_report / "report.html").read_text(encoding="utf-8")
    outside = re.sub(r"<section[^>]*><details>.*?</details></section>", "", html, flags=re.S)
    assert "[[Variables]]" in html and "<pre>" in html
    assert "<pre>" not in outside and "[[Variables]]" not in outside
