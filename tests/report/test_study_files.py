"""A study's files: figures, CSV tables and summary.json in a folder that appears whole or not at all."""

import json

import pandas as pd
import pytest

from idkit.cli.main import main
from idkit.report.study_files import run_study, run_transport_study


@pytest.mark.slow
def test_wire_rope_study_files(tmp_path):
    target = tmp_path / "wire-rope"
    study = run_study("wire-rope", target, quick=True)
    written = json.loads((target / "summary.json").read_text())
    expected = study.summary()
    assert written["cases"] == expected["cases"] and written["grid"] == expected["grid"]
    assert "writing" in written["timings_s"]
    assert written["files"] == sorted(p.name for p in target.iterdir() if p.name != "summary.json") + ["summary.json"]
    case = "wire-rope_asymmetric"
    for stem in (f"map_{case}.csv", f"map_{case}_ratio_surface.png", f"map_{case}_h1_surface.png",
                 f"map_{case}_top_views.png", f"cross_sections_{case}.png", f"resonance_{case}.png",
                 f"resonance_{case}.csv", f"shock_{case}_velocity.csv", f"shock_{case}_height.csv",
                 "shock_rest_level.png", "shock_phases.png", "shock_deflection.png"):
        assert (target / stem).stat().st_size > 0, stem
    assert len(pd.read_csv(target / f"map_{case}.csv")) == 8 * 4 * 4  # 8 freq x 4 amplitudes x orders 1/2, 1, 2, 3
    assert [p.name for p in tmp_path.iterdir()] == ["wire-rope"]  # no partial folder left


def test_elastomer_study_through_the_cli(tmp_path, capsys):
    target = tmp_path / "elastomer"
    assert main(["study", "elastomer", "-o", str(target), "--quick", "--quiet", "--workers", "1"]) == 0
    summary = json.loads((target / "summary.json").read_text())
    assert summary["cases"]["elastomer_medium"]["linear"]["resonance_Hz"] == pytest.approx(4.99, abs=0.01)
    for name in ("elastomer_complex_stiffness.png", "elastomer_transmissibility.png", "shock_rest_level.png",
                 "linear_elastomer_low.csv", "harmonic_check_elastomer_high.csv", "shock_elastomer_medium_height.csv"):
        assert (target / name).stat().st_size > 0, name
    check = pd.read_csv(target / "harmonic_check_elastomer_medium.csv")
    assert (check["relative deviation [-]"] < 1e-2).all()
    capsys.readouterr()
    assert main(["study", "elastomer", "-o", str(target), "--quick", "--quiet"]) == 2  # refuses to overwrite
    assert "exists" in capsys.readouterr().err


def test_transport_study_files(tmp_path):
    out = tmp_path / "transport"
    study = run_transport_study(out, quick=True, seed=5)
    names = {p.name for p in out.iterdir()}
    assert {"transport_output_psd.png", "transport_rest_shock.png", "transport_rms.csv", "transport_tuning.csv",
            "transport_shock_vs_height.csv", "transport_summary.csv", "transport_psd.csv.gz", "summary.json"} <= names
    summary = json.loads((out / "summary.json").read_text())
    assert summary["seed"] == 5 and summary["n_realizations"] == study.n_realizations == 4
    tuning = pd.read_csv(out / "transport_tuning.csv")
    assert {"moving mass [kg]", "top mass without m_eff [kg]"} <= set(tuning.columns) and len(tuning) == 5
    with pytest.raises(FileExistsError):
        run_transport_study(out, quick=True)
