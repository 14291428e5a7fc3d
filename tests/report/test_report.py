"""``idkit report`` end to end on the bundled data (quick mode) and its safety rules."""

import json
from pathlib import Path

import pytest

from idkit.cli.main import main
from idkit.report.main_report import REPORT_SECTIONS

DATA = Path(__file__).resolve().parents[2] / "data"


STATUS = {}


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("reports") / "report"
    STATUS["report"] = main(["report", str(DATA), "-o", str(out), "--quick", "--quiet"])
    return out


@pytest.mark.slow
def test_exit_status_follows_the_verdicts(quick_report):
    """0 only when every validation passes; 1 when one fails; 3 when none fails but one is inconclusive."""
    html = (quick_report / "report.html").read_text(encoding="utf-8")
    failed = '<span class="fail">FAIL</span>' in html
    inconclusive = '<span class="inconclusive">INCONCLUSIVE</span>' in html
    assert html.count('<span class="pass">PASS</span>') + failed + inconclusive >= 1
    assert STATUS["report"] == (1 if failed else 3 if inconclusive else 0)
    assert "quick run: at most 8 held-out records" in html  # a quick verdict says so


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
    html = (quick_report / "report.html").read_text(encoding="utf-8")
    assert "Valid range of the identified Iwan model" in html


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
    import pandas as pd

    table = pd.read_csv(quick_report / "tables" / "wire_rope_drop_models.csv")
    assert set(table["drop model"]) == {"conditioned", "rig"}
    assert "plain Iwan" in set(table["isolator model"])
    from html import unescape

    html = unescape((quick_report / "report.html").read_text(encoding="utf-8"))
    assert "The held-out drops support the" in html and "drop_model='auto'" in html
    # the named pair is the one with the smallest worst-phase median error among the PASSes
    passing = table[table["verdict"] == "PASS"].groupby(["isolator model", "drop model"])[
        ["median_compression_error [-]", "median_tension_error [-]"]].median().max(axis=1)
    model, drop = passing.idxmin()
    assert f"support the {model} model with the {drop} drop model" in html
