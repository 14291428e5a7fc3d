"""``idkit report`` end to end on the bundled data (quick mode) and its safety rules."""

import json
from pathlib import Path

import pytest

from idkit.cli.main import main
from idkit.report.main_report import REPORT_SECTIONS

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.fixture(scope="module")
def quick_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("reports") / "report"
    assert main(["report", str(DATA), "-o", str(out), "--quick", "--quiet"]) == 0
    return out


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
    assert main(["report", str(tmp_path), "-o", str(tmp_path / "out"), "--quiet"]) == 2
    assert "no manifest.json" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


@pytest.mark.slow
def test_report_states_the_valid_range_of_the_identified_wire_rope(quick_report):
    html = (quick_report / "report.html").read_text(encoding="utf-8")
    assert "Valid range of the identified Iwan model" in html
