"""Held-out force histories (idkit.validate.history): a right model scores its noise floor, wrong ones fail."""

import numpy as np
import pytest

from idkit.models import IwanModel
from idkit.observe.histories import histories_from_records
from idkit.synth.devices import DEVICES, device_records, earthquake_history, random_history
from idkit.validate.history import validate_histories

DEVICE = DEVICES["jenkin"]
TRUE_MODEL = IwanModel(g1=DEVICE.parallel_stiffness, k=list(DEVICE.stiffness), fc=list(DEVICE.slip_force))


def held_out(noise=3.0, seed=7):
    histories = {"random": random_history(9e-3, (0.1, 1.5), duration=12.0, seed=seed),
                 "quake": earthquake_history(9e-3, duration=12.0, dominant_hz=0.5, seed=seed)}
    return histories_from_records(device_records(DEVICE, histories, force_noise=noise, seed=seed, split="validation"))


def test_the_true_model_scores_its_noise_floor_and_passes():
    """The device's own law on its noisy records: the error is the noise; the floor estimate (second
    differences) reads it within 10 % on 2400 samples, so error / floor within 0.9-1.1."""
    result = validate_histories(TRUE_MODEL, held_out())
    assert result.verdict == "PASS", result.why
    assert result.metrics["error_over_floor"].to_numpy() == pytest.approx(1.0, abs=0.1)
    assert np.all(np.abs(result.metrics["energy_error"]) < 0.02)


@pytest.mark.parametrize("wrong", [dict(k=[3e5, 8e4]), dict(fc=[180.0, 600.0]), dict(fc=[18.0, 60.0])])
def test_wrong_components_fail(wrong):
    """Stiffness x2, slip forces x3 and x0.3 (the power probes of docs/validation.md)."""
    parts = dict(g1=DEVICE.parallel_stiffness, k=list(DEVICE.stiffness), fc=list(DEVICE.slip_force)) | wrong
    result = validate_histories(IwanModel(**parts), held_out())
    assert result.verdict == "FAIL"


def test_records_too_noisy_to_judge_are_inconclusive():
    """Noise of 100 N on a force of ~400 N RMS: the floor (0.25) is above half the median limit."""
    result = validate_histories(TRUE_MODEL, held_out(noise=100.0))
    assert result.verdict == "INCONCLUSIVE"
    assert any("noise floor" in reason for reason in result.inconclusive)


def test_the_energy_error_of_thin_loops_is_reported_not_judged():
    """A linear spring with a little viscous damping (dissipation about 0.3 % of the work through it) and a
    model with twice the damping: the energy error is +100 % but the loops are thin, so it is a note; the
    force error (about 1 %) passes."""
    from idkit.io import MeasurementInfo, QuasiStaticMeasurement
    from idkit.models import VoigtModel

    t = np.arange(0.0, 20.0, 0.01)
    x = 5e-3 * np.sin(2 * np.pi * 0.5 * t)
    truth, model = VoigtModel(k=1e4, damping=10.0), VoigtModel(k=1e4, damping=20.0)
    records = [QuasiStaticMeasurement(time=t, deflection=x, force=truth.force(x, t),
                                      info=MeasurementInfo(id="thin", split="validation"))]
    result = validate_histories(model, records, split=None)
    assert result.metrics["energy_error"].iloc[0] == pytest.approx(1.0, rel=0.01)  # the open end adds k x^2 / 2
    assert result.metrics["dissipated_share"].iloc[0] < 0.05
    assert result.verdict == "PASS" and "not judged" in result.notes[0]
    assert "median_abs_energy_error" not in result.thresholds


def test_baselines_are_scored_beside_the_model_and_judged():
    """The true model beside two simple baselines (fitted to the same held-out records: the best
    they can do there): it predicts better than every one and passes; the linear spring and dashpot
    fitted to the records, validated as "the model", is exactly its own baseline (ratio 1, within
    the limit) and a Jenkin element is better still, so the dashpot FAILS against it."""
    from idkit.fit.baselines import fit_baselines

    records = held_out()
    baselines = fit_baselines(records)
    result = validate_histories(TRUE_MODEL, records, baselines=baselines)
    assert result.verdict == "PASS", result.why
    assert result.summary["median_error_over_best_baseline"] < 0.5
    assert {"baseline linear spring and dashpot", "baseline Jenkin element"} <= set(result.metrics.columns)
    assert any("better than every baseline" in note for note in result.notes)
    dashpot = validate_histories(baselines["linear spring and dashpot"], records, baselines=baselines)
    assert dashpot.verdict == "FAIL"
    assert any(line.startswith("median_error_over_best_baseline") for line in dashpot.why)
