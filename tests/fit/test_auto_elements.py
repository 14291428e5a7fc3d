"""Model choice by prediction on the three devices idkit was not designed around (issue 32.5):
a friction damper with clearance, a pinched rope and a rate-dependent damper, each trained on
sines and validated on random and earthquake-like histories (idkit.synth.devices: independent
numpy laws). Small candidate sets keep the time down; each holds the true family and wrong ones."""

import functools

import numpy as np
import pytest

from idkit.fit.auto import (EARLY_STOP_FACTOR, FAMILIES, Family, fit_auto, fit_boucwen_family, fit_plain_iwan,
                            screen_boucwen)
from idkit.fit.elements import fit_pinched_boucwen
from idkit.observe.histories import histories_from_records
from idkit.synth.devices import DEVICES, protocol_records
from idkit.validate.history import validate_histories

BY_NAME = {family.name: family for family in FAMILIES}
IWAN = Family("iwan", functools.partial(fit_plain_iwan, orders=(1, 2, 3), points_per_set=100), "plain Iwan 1-3")
BOUC_WEN = Family("boucwen", functools.partial(fit_boucwen_family, points_per_set=100, global_max_evals=200,
                                               fold_max_evals=400), "Bouc-Wen", screen_boucwen)
NOISE = 3.0  # N of force noise: noise floors of 1-4 % on these devices
#: Held-out error allowed against the truth's own on the same noisy records (issue 32.5).
FLOOR_FACTOR = 1.5


def _protocol(name, seed, **options):
    training, held_out = protocol_records(DEVICES[name], force_noise=NOISE, seed=seed, **options)
    return histories_from_records(training), histories_from_records(held_out)


def _within_the_floor(model, device, held_out):
    """Per held-out record, the model's strong-motion error within FLOOR_FACTOR x the truth's own."""
    validation = validate_histories(model, held_out)
    truth = np.array([np.sqrt(np.mean((device.force(h.deflection, h.time) - h.force) ** 2))
                      / np.sqrt(np.mean(h.force ** 2)) for h in held_out])
    errors = validation.metrics["nrms_error"].to_numpy()
    assert validation.passed, validation.report()
    assert np.all(errors <= FLOOR_FACTOR * truth), (errors, truth)


def _recovered(fit, truth: dict, z=4.0):
    """Each true parameter within z reported standard errors (the element fits' calibration:
    over seeds 0-7 the errors behaved like a standard normal, largest 2.7)."""
    for name, true in truth.items():
        value, error = fit.params[name], fit.stderr[name]
        assert abs(value - true) <= z * error, (name, value, true, error)


@pytest.mark.parametrize("seed", [1])
def test_a_friction_damper_with_clearance_is_identified_with_its_clearance(seed):
    device = DEVICES["clearance_friction_damper"]
    training, held_out = _protocol("clearance_friction_damper", seed)
    fit = fit_auto(training, families=[IWAN, BY_NAME["clearance_jenkin"], BY_NAME["rate_dependent_jenkin"], BOUC_WEN])
    assert fit.chosen.family.name == "clearance_jenkin" and fit.success, fit.report()
    series = 1.0 / (1.0 / device.contact_stiffness + 1.0 / device.stiffness)  # contact and element in series
    _recovered(fit.chosen.fit, {"gap": device.clearance, "g1": device.parallel_stiffness, "k_1": series,
                                "fc_1": device.slip_force})
    _within_the_floor(fit.model, device, held_out)
    scores = {score.family.name: score for score in fit.scores}
    # the rate-independent Iwan misses the zero-force plateau; the Bouc-Wen family, fitted after the
    # clearance element, is stopped after its screen (tens of times the clearance element's error)
    assert not scores["iwan"].fit.success and scores["iwan"].cv_error > 10 * fit.chosen.cv_error
    assert scores["boucwen"].stopped_early and scores["boucwen"].fit is None
    assert scores["boucwen"].training_error > 10 * fit.chosen.training_error


@pytest.mark.parametrize("seed", [1])
def test_a_rate_dependent_damper_trained_at_two_rates_is_identified_and_generalises(seed):
    device = DEVICES["rate_dependent_damper"]
    training, held_out = _protocol("rate_dependent_damper", seed, training_frequencies_hz=(0.05, 2.0))
    fit = fit_auto(training, families=[IWAN, BY_NAME["clearance_jenkin"], BY_NAME["rate_dependent_jenkin"]])
    assert fit.chosen.family.name == "rate_dependent_jenkin" and fit.success, fit.report()
    _recovered(fit.chosen.fit, {"g1": device.parallel_stiffness, "k_1": device.stiffness, "fc_1": device.fc0,
                                "slip_rate_gain": device.fc1 / device.fc0, "slip_speed": device.v_ref})
    _within_the_floor(fit.model, device, held_out)


@functools.lru_cache(maxsize=1)
def _pinched_rope_choice(seed=1):
    training, held_out = _protocol("pinched_rope", seed)
    return fit_auto(training, families=[BOUC_WEN, BY_NAME["pinched_boucwen"]]), training, held_out


def _pinched_truth(device) -> dict:
    """The pinched rope's parameters in the pinched fit's coordinates (fit_pinched_boucwen)."""
    saturated = device.ultimate_z
    return {"k1": device.k1, "alpha": device.alpha, "saturated_force": saturated,
            "beta_share": device.beta / (device.beta + device.gamma), "n": device.n, "pinch": device.pinching,
            "pinch_width": device.width / saturated, "pinch_shift": device.position}


def test_a_pinched_rope_is_identified_as_pinched_and_predicts_within_the_noise_floor():
    """The pinched family wins by prediction, and succeeds: fitted in the loop's own coordinates
    (saturated force, beta share, n) every parameter is determined and recovered."""
    device = DEVICES["pinched_rope"]
    fit, training, held_out = _pinched_rope_choice()
    assert fit.chosen.family.name == "pinched_boucwen" and fit.success, fit.report()
    _recovered(fit.chosen.fit, _pinched_truth(device))
    plain = next(score for score in fit.scores if score.family.name == "boucwen")
    assert plain.cv_error > 3 * fit.chosen.cv_error
    _within_the_floor(fit.model, device, held_out)
    _screen_keeps_the_truth(fit.chosen.screen_error, device, training)


def _screen_keeps_the_truth(screen_error, device, training):
    """The true family's screen error within EARLY_STOP_FACTOR x 0.95 x the truth's own error on its
    records: no family fitted before it can score below 0.95 x the truth's error (a least-squares
    fit of p parameters to n noisy samples removes a share p / n of the noise variance: 8 / 1600 here,
    a factor 0.997 on the error), so the screen never stops the true family."""
    truth = np.mean([np.sqrt(np.mean((device.force(h.deflection, h.time) - h.force) ** 2) / np.mean(h.force ** 2))
                     for h in training])
    assert screen_error <= EARLY_STOP_FACTOR * 0.95 * truth, (screen_error, truth)


@pytest.mark.parametrize("seed", [2, 3])
def test_the_pinched_fit_is_determined_for_other_seeds(seed):
    """Seeds 2 and 3 of the pinched rope: the pinched fit, warm-started from seed 1's optimum (a
    different noise draw, not the truth), is a success with every parameter within its standard
    errors of the truth (cold starts reach the same optima: commit message)."""
    device = DEVICES["pinched_rope"]
    training, _ = _protocol("pinched_rope", seed)
    first = _pinched_rope_choice()[0].chosen.fit.result
    fit = fit_pinched_boucwen(training, start=first, seed=seed)
    assert fit.success and fit.undetermined == [], fit.report()
    _recovered(fit, _pinched_truth(device))
