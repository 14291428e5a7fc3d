"""Synthetic devices (issue 32.5): each plain-numpy law against a closed form or idkit's own kernel."""

import numpy as np
import pytest

from idkit.errors import ParameterError
from idkit.models import BoucWenModel, IwanModel
from idkit.synth.devices import (
    DEVICES,
    BoucWenDevice,
    ClearanceFrictionDamper,
    JenkinDevice,
    PinchedRope,
    RateDependentDamper,
    device_records,
    earthquake_history,
    multilevel_history,
    random_history,
    sine_history,
)


def triangle(corners, step=2e-5):
    """Piecewise-linear deflection through ``corners`` in steps of at most ``step`` m."""
    pieces = [np.array([corners[0]])]
    for a, b in zip(corners[:-1], corners[1:]):
        pieces.append(np.linspace(a, b, int(abs(b - a) / step) + 2)[1:])
    x = np.concatenate(pieces)
    return np.arange(x.size) * 0.01, x


def test_jenkin_device_is_the_iwan_models_stop_operator():
    """Both are exact stop operators at the samples: agreement to round-off (1e-9 of the force range)."""
    device = DEVICES["jenkin"]
    model = IwanModel(g1=device.parallel_stiffness, k=list(device.stiffness), fc=list(device.slip_force))
    time, x = random_history(9e-3, (0.1, 2.0), duration=8.0, seed=4)
    force = device.force(x, time)
    assert np.max(np.abs(force - model.force(x, time=time))) <= 1e-9 * np.ptp(force)


def test_boucwen_device_closed_form_matches_idkits_integration():
    """The n = 1 closed form against idkit's RK4 sub-steps (relative error about 1e-6, BOUCWEN_SUBSTEPS):
    1e-5 of the force range."""
    device = DEVICES["boucwen"]
    model = BoucWenModel(k1=device.k1, k2=0.0, k3=0.0, alpha=device.alpha, beta=device.beta, gamma=device.gamma, n=1.0)
    time, x = earthquake_history(8e-3, duration=15.0, dominant_hz=0.5, seed=3)
    force = device.force(x, time)
    assert np.max(np.abs(force - model.force(x, time=time))) <= 1e-5 * np.ptp(force)
    # first loading from rest: z = z_u (1 - exp(-(beta + gamma) x)), z_u = alpha / (beta + gamma)
    z_u = device.alpha / (device.beta + device.gamma)
    ramp = np.linspace(0.0, 5e-3, 51)
    expected = device.k1 * ramp + z_u * (1.0 - np.exp(-(device.beta + device.gamma) * ramp))
    assert device.force(ramp, np.arange(51.0)) == pytest.approx(expected, rel=1e-12, abs=1e-9)


def test_pinched_rope_without_pinching_is_the_boucwen_closed_form():
    """RK4 with sub-steps of yield_travel / 200: within 1e-6 of the force range of the exact solution."""
    exact = BoucWenDevice(k1=1.5e4, alpha=1.2e5, beta=600.0, gamma=300.0)
    rope = PinchedRope(k1=1.5e4, alpha=1.2e5, beta=600.0, gamma=300.0, n=1.0, pinching=0.0, width=30.0)
    time, x = triangle([0.0, 6e-3, -4e-3, 3e-3, -6e-3, 0.0], step=1e-4)
    force = exact.force(x, time)
    assert np.max(np.abs(rope.force(x, time) - force)) <= 1e-6 * np.ptp(force)
    pinched = DEVICES["pinched_rope"]
    def hysteresis(device):
        f = device.force(x, time)
        return abs(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(x)))

    assert hysteresis(pinched) < 0.9 * hysteresis(PinchedRope(**{**pinched.true_params(), "pinching": 0.0}))


def test_clearance_damper_reversal_plateau_is_twice_the_clearance():
    """After slipping, a reversal unloads the series branch along its series stiffness, then carries zero
    force over 2 x clearance of travel, then reloads (the analytic path of a dead zone and a Jenkin)."""
    device = ClearanceFrictionDamper(parallel_stiffness=0.0, contact_stiffness=5e5, clearance=2e-3, stiffness=2e5,
                                     slip_force=400.0)
    series = 1.0 / (1.0 / 5e5 + 1.0 / 2e5)
    time, x = triangle([0.0, 10e-3, -10e-3], step=1e-5)
    force = device.force(x, time)
    top = int(np.argmax(x))
    assert force[top] == pytest.approx(400.0)
    after = x[top] - x[top:]  # travel since the reversal
    unload = (after > 0) & (after < 400.0 / series)
    assert force[top:][unload] == pytest.approx(400.0 - series * after[unload], abs=1e-9)
    plateau = (after > 400.0 / series + 1e-9) & (after < 400.0 / series + 2 * 2e-3 - 1e-9)
    assert plateau.sum() > 300 and np.all(force[top:][plateau] == 0.0)
    assert force[-1] == pytest.approx(-400.0)


def test_rate_dependent_damper_slips_at_the_rate_law():
    """At constant deflection rate v the sliding force is fc0 + fc1 tanh(v / v_ref) on top of the spring."""
    device = RateDependentDamper(parallel_stiffness=1e4, stiffness=2e5, fc0=150.0, fc1=150.0, v_ref=0.02)
    for speed in (0.002, 0.02, 0.2):
        x = np.linspace(0.0, 10e-3, 2001)
        time = x / speed
        force = device.force(x, time)
        expected = 1e4 * x[-1] + 150.0 + 150.0 * np.tanh(speed / 0.02)
        assert force[-1] == pytest.approx(expected, rel=1e-12)


def test_histories_start_and_end_at_rest_with_the_asked_peak():
    for time, x in (random_history(5e-3, (0.2, 2.0), duration=10.0, seed=1),
                    earthquake_history(5e-3, duration=10.0, seed=1), sine_history(5e-3, 1.0, cycles=2),
                    multilevel_history([1e-3, 5e-3], 1.0)):
        assert x[0] == pytest.approx(0.0, abs=1e-12) and abs(x[-1]) <= 1e-12 + 1e-3 * np.max(np.abs(x))
        assert np.max(np.abs(x)) == pytest.approx(5e-3, rel=1e-3)
        assert np.all(np.diff(time) > 0)


def test_device_records_add_seeded_noise_and_bad_parameters_are_refused():
    device = DEVICES["jenkin"]
    histories = {"s": sine_history(4e-3, 0.5)}
    first = device_records(device, histories, force_noise=2.0, seed=5)[0]
    again = device_records(device, histories, force_noise=2.0, seed=5)[0]
    clean = device.force(first.deflection, first.time)
    assert np.array_equal(first.force, again.force)
    assert np.std(first.force - clean) == pytest.approx(2.0, rel=0.1)  # 601 samples: sampling spread ~3 %
    with pytest.raises(ParameterError, match="slip_force"):
        JenkinDevice(parallel_stiffness=1e4, stiffness=(1e5,), slip_force=(-1.0,))
    with pytest.raises(ParameterError, match="pinching"):
        PinchedRope(k1=1.0, alpha=1.0, beta=1.0, gamma=1.0, n=1.0, pinching=1.0, width=1.0)
