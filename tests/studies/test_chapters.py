"""The chapter 3-5 studies compute typed results (quick grids)."""

import numpy as np
import pytest

from idkit.studies.chapters import ChapterStudy, MapCase, StudyError, compute_chapter_study


@pytest.mark.slow
@pytest.mark.parametrize("name, case", [("wire-rope", "wire-rope_asymmetric"), ("hybrid", "hybrid_symmetric")])
def test_nonlinear_study_quick(name, case):
    calls = []
    study = compute_chapter_study(name, quick=True, progress=lambda done, total: calls.append((done, total)))
    assert isinstance(study, ChapterStudy) and calls and calls[-1][0] == calls[-1][1]  # progress reaches its total
    result = study.case(case)
    assert isinstance(result, MapCase)
    assert result.hmap.shape == (8, 4)  # 8 frequencies x 4 amplitudes
    assert result.top_view_orders == ((2, 3, 0.5) if "asymmetric" in case else (2, 3))
    summary = study.summary()["cases"][case]
    assert summary["shock"]["valid"] == summary["shock"]["runs"]
    assert summary["map"]["flagged"] == 0
    assert list(result.resonance_table().columns) == ["amplitude [m]", "resonance [Hz]"]
    if case == "wire-rope_asymmetric":
        # thesis fig. 3.21b: tension governs above about 0.9 m/s (quick grid: 0.25 m/s steps)
        assert result.shock.tension_governs_from == pytest.approx(1.0)
    if name == "hybrid":
        assert study.hybrid_linear is not None
        assert summary["linear"]["resonance_Hz"] == pytest.approx(7.30, abs=0.01)
    else:
        assert study.hybrid_linear is None


def test_elastomer_study_quick():
    study = compute_chapter_study("elastomer", quick=True, workers=1)
    resonance = {case.variant: case.frf.resonance.freq for case in study.cases}
    # thesis 4.3.1: shifting the glass transition down stiffens the mount (higher resonance)
    assert resonance["low"] > resonance["medium"] > resonance["high"]
    assert resonance["medium"] == pytest.approx(4.99, abs=0.01)
    for case in study.cases:
        # time-domain first HOSIDF = transmissibility of the linear elastomer (<= 1 %: steady-state tolerance 1e-3
        # plus the time grid's phase error)
        assert case.check_deviation.max() < 1e-2
        assert np.isfinite(case.shock.by_speed.rest_shock_level).all()
        table = case.harmonic_check_table()
        assert list(table.columns) == ["freq [Hz]", "|H1| time domain [-]", "|H| linear [-]", "relative deviation [-]"]
    assert set(study.summary()["timings_s"]) >= {"total", "shock_elastomer_low"}


def test_unknown_study():
    with pytest.raises(StudyError, match="expected one of"):
        compute_chapter_study("transport-tool", quick=True)
