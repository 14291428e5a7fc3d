"""Simple baselines (idkit.fit.baselines) against closed forms."""

import numpy as np
import pytest

from idkit.errors import FitError
from idkit.fit.baselines import fit_baselines, fit_linear_spring_dashpot
from idkit.models import IwanModel, VoigtModel
from idkit.observe.histories import ForceHistory


def _history(name, model, amplitude, frequency_hz):
    time = np.arange(401) / (100.0 * frequency_hz)  # two cycles, 200 samples a cycle
    deflection = amplitude * np.sin(2.0 * np.pi * frequency_hz * time)
    return ForceHistory(name, time, deflection, model.force(deflection, time=time))


def test_the_linear_baseline_recovers_a_spring_and_dashpot_exactly():
    """Noise-free records of F = k x + c dx/dt with the model's own rate: the least squares is exact
    (relative 1e-9: the normal equations' rounding on forces of order 1e2 N)."""
    truth = VoigtModel(k=2.0e4, damping=150.0)
    records = [_history("a", truth, 5e-3, 0.5), _history("b", truth, 10e-3, 2.0)]
    fitted = fit_linear_spring_dashpot(records)
    assert fitted.k == pytest.approx(2.0e4, rel=1e-9) and fitted.damping == pytest.approx(150.0, rel=1e-9)


def test_the_jenkin_baseline_recovers_a_jenkin_element():
    """Noise-free loops of a Jenkin element beside a spring: the fit reaches the truth (relative 1e-4,
    the least squares' tolerance on a piecewise-linear objective)."""
    truth = IwanModel(g1=1e4, k=[2e5], fc=[300.0])
    records = [_history("a", truth, 3e-3, 0.5), _history("b", truth, 9e-3, 0.5)]
    jenkin = fit_baselines(records)["Jenkin element"]
    assert jenkin.g1 == pytest.approx(1e4, rel=1e-4)
    assert jenkin.k[0] == pytest.approx(2e5, rel=1e-4) and jenkin.fc[0] == pytest.approx(300.0, rel=1e-4)


def test_bad_records_are_refused():
    with pytest.raises(FitError, match="histories"):
        fit_baselines([])
