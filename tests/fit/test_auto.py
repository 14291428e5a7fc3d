"""Model choice by prediction (idkit.fit.auto) on truths built to differ (issue 32.2 / 32.5).

Small problems (four sine groups of two cycles, 150 points a set, Iwan orders 1-3, a short
Bouc-Wen global search) keep the test time down; the defaults are exercised by the bench.
"""

import functools
import itertools

import numpy as np
import pytest

from idkit.errors import FitError
from idkit.fit.auto import (Family, fit_auto, fit_boucwen_family, fit_modulated_iwan, fit_plain_iwan,
                            screen_boucwen)
from idkit.models import ModulatedIwanModel
from idkit.observe.histories import ForceHistory, histories_from_records, noise_floor
from idkit.synth.devices import DEVICES, device_records, protocol_records, sine_history
from idkit.validate.history import validate_histories

FAMILIES = [
    Family("iwan", functools.partial(fit_plain_iwan, orders=(1, 2, 3), points_per_set=100), "plain Iwan, orders 1-3"),
    Family("boucwen", functools.partial(fit_boucwen_family, points_per_set=100, global_max_evals=200,
                                        fold_max_evals=400), "Bouc-Wen"),
]
SCREENED_BOUC_WEN = Family("boucwen", FAMILIES[1].fit, "Bouc-Wen, screened", screen_boucwen)
NOISE = 3.0  # N, on forces of 300-900 N: noise floors of 0.5-1.5 %


def training(device, seed):
    return histories_from_records(protocol_records(device, force_noise=NOISE, seed=seed)[0])


def held_out(device, seed):
    return histories_from_records(protocol_records(device, force_noise=NOISE, seed=seed)[1])


@pytest.mark.parametrize("seed", [1])  # seeds 1-6 checked when written (commit message); one keeps the time down
def test_a_jenkin_device_is_identified_as_iwan_and_bouc_wen_is_flagged(seed):
    device = DEVICES["jenkin"]
    fit = fit_auto(training(device, seed), families=FAMILIES)
    assert fit.chosen.family.name == "iwan" and fit.success, fit.report()
    assert fit.model.order == 2
    # parameters within Z = 4.5 reported standard errors (the Iwan fits' calibrated bound, docs/fitting.md)
    for name, true in device.true_params().items():
        assert abs(fit.chosen.fit.params[name] - true) <= 4.5 * fit.chosen.fit.stderr[name], name
    bouc_wen = next(score for score in fit.scores if score.family.name == "boucwen")
    assert not bouc_wen.fit.success and bouc_wen.cv_error > 1.5 * fit.chosen.cv_error
    # its smallest and largest groups, predicted by extrapolation, are beyond 1.5 x its training error
    assert {line.split(" (")[0] for line in bouc_wen.extrapolated} == {"3 mm, 0.5 Hz", "12 mm, 0.5 Hz"}
    # held-out random and earthquake-like histories within 1.5 x the truth's own error (its noise)
    validation = validate_histories(fit.model, held_out(device, seed))
    truth = validate_histories(device_as_model(device), held_out(device, seed))
    assert validation.passed
    ratio = validation.metrics["nrms_error_strong_motion"] / truth.metrics["nrms_error_strong_motion"]
    assert np.all(ratio <= 1.5), validation.metrics


def device_as_model(device):
    from idkit.models import IwanModel

    return IwanModel(g1=device.parallel_stiffness, k=list(device.stiffness), fc=list(device.slip_force))


def test_a_bouc_wen_device_is_identified_as_bouc_wen_and_predicts_within_the_noise_floor():
    device = DEVICES["boucwen"]
    fit = fit_auto(training(device, 3), families=[FAMILIES[0], SCREENED_BOUC_WEN])
    assert fit.chosen.family.name == "boucwen" and fit.success, fit.report()
    # its screen (no global search) ends near the truth's own error: never stopped (fit.auto.EARLY_STOP_FACTOR)
    truth_error = np.mean([np.sqrt(np.mean((device.force(h.deflection, h.time) - h.force) ** 2)
                                   / np.mean(h.force ** 2)) for h in training(device, 3)])
    assert not fit.chosen.stopped_early and fit.chosen.screen_error <= 1.2 * truth_error
    for name in ("k1", "alpha", "beta", "gamma", "n"):
        true = device.true_params()[name]
        assert abs(fit.chosen.fit.params[name] - true) <= 5 * fit.chosen.fit.stderr[name], name
    validation = validate_histories(fit.model, held_out(device, 3))
    assert validation.passed
    floors = [noise_floor(h, None) for h in held_out(device, 3)]
    assert np.all(validation.metrics["nrms_error"].to_numpy() <= 1.5 * np.array(floors)), validation.metrics


def test_a_rate_dependent_damper_trained_at_two_frequencies_does_not_generalise():
    """No rate-independent family predicts a damper whose slip force rises with speed from records at
    another frequency: the result is not a success and names the held-out records."""
    device = DEVICES["rate_dependent_damper"]
    sines = {f"sine_{f:g}Hz": sine_history(8e-3, f, cycles=2, sample_rate_hz=200.0) for f in (0.05, 2.0)}
    histories = histories_from_records(device_records(device, sines, force_noise=NOISE, seed=4))
    fit = fit_auto(histories, families=FAMILIES[:1])
    assert not fit.success
    assert any("does not generalise" in reason and "sine_0.05Hz" in reason for reason in fit.reasons)


def test_fewer_than_two_records_cannot_be_cross_validated():
    with pytest.raises(FitError, match="at least two"):
        fit_auto(training(DEVICES["jenkin"], 1)[:1], families=FAMILIES)


def test_the_modulated_family_adds_elements_by_continuation_to_the_truths_order():
    """The slip-modulated family orders itself as ``fit iwan --family modulated`` does (one chain,
    ``choose_iwan_family``): from the plain order-1 fit, elements added by splitting until a fit is
    a success with every parameter determined. On a modulated truth of order 3 (loops of 0.3-15 mm,
    0.05 N noise, the bundled rope's level) it reaches order 3 through orders 1 and 2 and recovers
    the modulation within 4 standard errors (the calibrated bound of tests/fit/test_iwan_modulated.py)."""
    truth = ModulatedIwanModel(g1=1.84e4, g2=2.45e5, g3=-4.57e5, k=[1.88e5, 3e4, 9.09e3], fc=[15.5, 8.0, 10.3],
                               slip_modulation=0.35, slip_length=6e-3)
    rng = np.random.default_rng(0)
    histories = []
    for amplitude in (0.3e-3, 1e-3, 2e-3, 5e-3, 10e-3, 15e-3):
        corners = [0.0] + [amplitude * (-1) ** i for i in range(5)]  # two cycles from the unloaded state
        x = np.concatenate([[0.0]] + [np.linspace(a, b, 150)[1:] for a, b in itertools.pairwise(corners)])
        force = truth.force(x) + 0.05 * rng.standard_normal(x.size)
        histories.append(ForceHistory(f"{1e3 * amplitude:g} mm", 0.01 * np.arange(x.size), x, force))
    fit = fit_modulated_iwan(histories, orders=(1, 2, 3), points_per_set=100)
    assert fit.success and fit.model.order == 3, fit.result.report()
    names = [stage.name for stage in fit.result.stages]
    assert any("order 2 (order 1 with element" in name for name in names), names
    for name in ("slip_modulation", "slip_length"):
        assert abs(fit.params[name] - truth.params()[name]) <= 4.0 * fit.stderr[name], name
