"""The chapter 3-5 studies run in quick mode and write their files; the CLI wires them."""

import argparse
import json

import numpy as np
import pandas as pd
import pytest

from idkit.cli.main import main
from idkit.cli.study import add_common_study_options, study_subparsers
from idkit.report.studies import StudyError, run_study


@pytest.mark.slow
@pytest.mark.parametrize("name, case", [("wire-rope", "wire-rope_asymmetric"), ("hybrid", "hybrid_symmetric")])
def test_nonlinear_study_quick(tmp_path, name, case):
    calls = []
    target = tmp_path / name
    summary = run_study(name, target, quick=True, progress=lambda done, total: calls.append((done, total)))
    assert calls and calls[-1][0] == calls[-1][1]  # the progress reaches its total
    assert json.loads((target / "summary.json").read_text()) == summary
    for stem in (f"map_{case}.csv", f"map_{case}_ratio_surface.png", f"map_{case}_top_views.png",
                 f"cross_sections_{case}.png", f"shock_{case}_velocity.csv", "shock_rest_level.png",
                 "shock_phases.png", "shock_deflection.png"):
        assert (target / stem).stat().st_size > 0, stem
    table = pd.read_csv(target / f"map_{case}.csv")
    assert len(table) == 8 * 4 * 4  # 8 frequencies x 4 amplitudes x orders 1/2, 1, 2, 3
    result = summary["cases"][case]
    assert result["shock"]["valid"] == result["shock"]["runs"]
    assert result["map"]["flagged"] == 0
    if case == "wire-rope_asymmetric":
        # thesis fig. 3.21b: tension governs above about 0.9 m/s (quick grid: 0.25 m/s steps)
        assert result["shock"]["tension_governs_from_m_s"] == pytest.approx(1.0)
    if name == "hybrid":
        assert (target / "linear_hybrid_transmissibility.png").exists()
        assert result["linear"]["resonance_Hz"] == pytest.approx(7.30, abs=0.01)
    assert [p.name for p in tmp_path.iterdir()] == [name]  # no partial folder left


def test_elastomer_study_through_the_cli(tmp_path, capsys):
    target = tmp_path / "elastomer"
    assert main(["study", "elastomer", "-o", str(target), "--quick", "--quiet", "--workers", "1"]) == 0
    summary = json.loads((target / "summary.json").read_text())
    resonance = {variant: summary["cases"][f"elastomer_{variant}"]["linear"]["resonance_Hz"]
                 for variant in ("low", "medium", "high")}
    # thesis 4.3.1: shifting the glass transition down stiffens the mount (higher resonance)
    assert resonance["low"] > resonance["medium"] > resonance["high"]
    assert resonance["medium"] == pytest.approx(4.99, abs=0.01)
    for variant in ("low", "medium", "high"):
        # time-domain first HOSIDF = transmissibility of the linear elastomer (<= 1 %)
        assert summary["cases"][f"elastomer_{variant}"]["harmonic_check_max_relative_deviation"] < 1e-2
    assert (target / "elastomer_complex_stiffness.png").exists()
    assert np.isfinite(pd.read_csv(target / "shock_elastomer_medium_velocity.csv")["rest_shock_level_m_s2"]).all()
    capsys.readouterr()
    assert main(["study", "elastomer", "-o", str(target), "--quick", "--quiet"]) == 2  # refuses to overwrite
    assert "exists" in capsys.readouterr().err


def test_unknown_study_and_plug_in_point():
    with pytest.raises(StudyError, match="expected one of"):
        run_study("transport-tool", "unused", quick=True)
    parser = argparse.ArgumentParser(prog="idkit")
    commands = parser.add_subparsers(dest="command")
    kinds = study_subparsers(commands)
    assert study_subparsers(commands) is kinds  # a later module gets the same sub-parsers
    extra = kinds.add_parser("transport")
    add_common_study_options(extra, "transport")
    args = parser.parse_args(["study", "transport", "--quick"])
    assert args.study == "transport" and args.quick and args.output == "idkit-study-transport"
