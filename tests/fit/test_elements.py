"""Element fitters (idkit.fit.elements) on noisy synthetic records with known parameters.

Every record is a truth's force along a sinusoid plus white noise of 2 % of its RMS force
(seeded). A fit must succeed and put every varied parameter within 4 of its reported standard
errors of the truth (a two-sided normal tail of 6e-5 per parameter: the reported errors are
honest when it holds for every seed; the z-scores over seeds 0-7 were spread like a standard
normal, largest 2.7).
"""

import math

import numpy as np
import pytest

from idkit.errors import FitError
from idkit.fit.model_form import MODEL_FORM_PREFIX
from idkit.fit.elements import ElementHistory, fit_clearance_jenkin, fit_pinched_boucwen, fit_rate_dependent_jenkin
from idkit.models import ClearanceIwanModel, PinchedBoucWenModel, RateDependentIwanModel, load_model, save_model

NOISE = 0.02  # of each record's RMS force
Z_LIMIT = 4.0


def _records(truth, amplitudes, freqs, seed, *, cycles=2, per_cycle=100):
    rng = np.random.default_rng(seed)
    records = []
    for amplitude in amplitudes:
        for freq in freqs:
            time = np.arange(cycles * per_cycle + 1) / (per_cycle * freq)
            deflection = amplitude * np.sin(2.0 * np.pi * freq * time)
            force = truth.force(deflection, time=time)
            force = force + NOISE * math.sqrt(float(np.mean(force**2))) * rng.standard_normal(force.size)
            records.append(ElementHistory(f"{1e3 * amplitude:g} mm {freq:g} Hz", time, deflection, force))
    return records


Z_U, N = 40.0, 1.5
TOTAL = 2e4 / Z_U**N
CASES = {
    "clearance": (fit_clearance_jenkin, ClearanceIwanModel(gap=2e-3, g1=0.0, k=[5e6], fc=[4e3]),
                  [13e-3, 25e-3, 38e-3], [0.5]),
    "rate": (fit_rate_dependent_jenkin,
             RateDependentIwanModel(g1=1e4, k=[2e6], fc=[2e3], slip_rate_gain=0.6, slip_speed=0.05),
             [10e-3, 25e-3], [0.25, 1.0, 2.0]),
    "pinched": (fit_pinched_boucwen,
                PinchedBoucWenModel(k1=1e3, k2=0.0, k3=0.0, alpha=2e4, beta=0.6 * TOTAL, gamma=0.4 * TOTAL, n=N,
                                    pinch=0.7, pinch_width=0.25, pinch_shift=0.1),
                [2e-3, 5e-3, 10e-3], [1.0]),
}
#: samples a cycle: 100, the pinched Bouc-Wen 60 (its z law is integrated by sub-steps: the cost)
PER_CYCLE = {"clearance": 100, "rate": 100, "pinched": 60}


def _derived(model) -> dict:
    """The pinched Bouc-Wen fit's own parameters beside the model's (``fit_pinched_boucwen``)."""
    if not isinstance(model, PinchedBoucWenModel):
        return {}
    return {"saturated_force": model.saturated_force, "beta_share": model.beta / (model.beta + model.gamma)}


@pytest.mark.parametrize("family, seed", [("clearance", 0), ("clearance", 1), ("rate", 0), ("rate", 1),
                                          ("pinched", 0), ("pinched", 1)])
def test_fit_recovers_the_truth_within_its_standard_errors(family, seed):
    fit, truth, amplitudes, freqs = CASES[family]
    result = fit(_records(truth, amplitudes, freqs, seed, per_cycle=PER_CYCLE[family]))
    assert result.success, result.reasons
    assert result.undetermined == []
    expected = {**truth.params(), **_derived(truth)}
    for name in result.varied:
        assert abs(result.params[name] - expected[name]) < Z_LIMIT * result.stderr[name], (name, result.report())
    # the residual is the noise: each record's error within 30 % of the 2 % noise (the RMS of n
    # white samples scatters by 1 / sqrt(2 n), 6.4 % for the shortest record, n = 121: 4.7 sd)
    assert all(0.7 * NOISE < error < 1.3 * NOISE for error in result.errors.values())
    assert result.n_params == len(result.varied)


def test_clearance_fit_holds_an_unneeded_parallel_spring_at_zero_and_warm_starts(tmp_path):
    """The truth has no parallel spring; where the fit finds ``g1`` at its bound it holds it at 0
    (a note, not a failure). A warm start from the result returns the same optimum in fewer
    evaluations, and the model is a model file."""
    fit, truth, amplitudes, freqs = CASES["clearance"]
    records = _records(truth, amplitudes, freqs, seed=1)
    cold = fit(records)
    assert "g1" not in cold.varied and cold.params["g1"] == 0.0 and cold.notes
    warm = fit(records, start=cold)
    assert warm.evaluations < cold.evaluations
    for name in cold.varied:
        assert warm.params[name] == pytest.approx(cold.params[name], abs=0.01 * cold.stderr[name])
    save_model(warm.model, tmp_path / "damper.json")
    assert load_model(tmp_path / "damper.json") == warm.model


def test_a_wrong_family_is_not_reported_as_determined():
    """A clearance damper fitted as a rate-dependent Jenkin element (no clearance): its error stays
    far above the noise floor, so the fit is not a success and says the model form misses."""
    _, truth, amplitudes, freqs = CASES["clearance"]
    result = fit_rate_dependent_jenkin(_records(truth, amplitudes, freqs, seed=0))
    assert not result.success
    assert result.error > 3.0 * NOISE
    assert any(reason.startswith(MODEL_FORM_PREFIX) for reason in result.reasons)


def test_bad_records_are_refused_by_name():
    time = np.linspace(0.0, 1.0, 50)
    good = ElementHistory("a", time, 1e-3 * np.sin(6.0 * time), np.sin(6.0 * time))
    with pytest.raises(FitError, match="'b'.*time: not increasing"):
        fit_clearance_jenkin([good, ElementHistory("b", time[::-1], good.deflection, good.force)])
    with pytest.raises(FitError, match="'a'.*force: found nan at sample 3"):
        fit_clearance_jenkin([ElementHistory("a", time, good.deflection, np.where(time == time[3], np.nan, 1.0))])
    with pytest.raises(FitError, match="given twice"):
        fit_clearance_jenkin([good, good])
    with pytest.raises(FitError, match="expected a 'clearance_jenkin' ElementFitResult"):
        fit_clearance_jenkin([good], start=fit_pinched_boucwen.__name__)


def test_a_record_cut_mid_cycle_is_fitted_from_its_cycled_state():
    """Two steady cycles of the clearance damper starting at the peak (loaded, closed): ``"auto"``
    evaluates them from the cycled state, as the truth made them, and recovers the truth; from the
    unloaded state the first quarter cycle is a transient the element cannot follow."""
    _, truth, _, _ = CASES["clearance"]
    time = np.arange(401) / 200.0
    warm_up = 25e-3 * np.cos(np.pi * np.arange(401) / 100.0)  # one cycle from the peak
    deflection = warm_up
    force = truth.force(np.concatenate([warm_up, deflection[1:]]))[400:]  # the second, steady pass
    rng = np.random.default_rng(0)
    record = ElementHistory("peak start", time, deflection,
                            force + NOISE * math.sqrt(float(np.mean(force**2))) * rng.standard_normal(force.size))
    cycled = fit_clearance_jenkin([record])
    assert cycled.start_states == {"peak start": "cycled"}
    assert cycled.success, cycled.reasons
    for name in cycled.varied:
        assert abs(cycled.params[name] - truth.params()[name]) < Z_LIMIT * cycled.stderr[name]
    unloaded = fit_clearance_jenkin([record], initial_state="unloaded")
    assert unloaded.error > cycled.error


def test_thinned_search_and_folds(monkeypatch):
    """Records longer than SEARCH_SAMPLES are searched thinned and polished at full length: the
    same optimum as the full search (within 0.05 standard errors: the polish stops at the
    statistics' precision, ftol 1e-8). A fold (``statistics=False``, warm started) gives a model
    and errors but no standard errors."""
    import idkit.fit.elements as elements

    fit, truth, amplitudes, freqs = CASES["clearance"]
    records = _records(truth, amplitudes, freqs, seed=2)
    full = fit(records)
    monkeypatch.setattr(elements, "SEARCH_SAMPLES", 60)  # 201-sample records: every 4th sample
    thinned = fit(records)
    assert thinned.success, thinned.reasons
    for name in full.varied:
        assert thinned.params[name] == pytest.approx(full.params[name], abs=0.05 * full.stderr[name])
    fold = fit(records[1:], start=full, statistics=False)
    assert all(math.isnan(value) for value in fold.stderr.values()) and fold.undetermined == []
    assert fold.params["gap"] == pytest.approx(truth.gap, rel=0.05)
