"""Force laws of the physical elements (docs/elements.md) against closed forms and an ODE solver."""

import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from idkit.errors import ModelFileError, ParameterError
from idkit.models import (
    BoucWenModel,
    ClearanceIwanModel,
    IwanModel,
    PinchedBoucWenModel,
    RateDependentIwanModel,
    load_model,
    save_model,
)


def _cycles(amplitude, n_cycles=2, per_cycle=4000, freq=1.0):
    """A sinusoid from zero, ``per_cycle`` samples a cycle (a multiple of 4: the peaks are samples)."""
    time = np.arange(n_cycles * per_cycle + 1) / (per_cycle * freq)
    return time, amplitude * np.sin(2.0 * np.pi * freq * time)


def _last_cycle_area(deflection, force, per_cycle=4000):
    """Dissipated energy (J) of the last cycle: the trapezoidal ``integral F dx``."""
    x, f = deflection[-per_cycle - 1:], force[-per_cycle - 1:]
    return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(x)))


# ------------------------------------------------------------------ clearance


DAMPER = dict(gap=3e-3, g1=0.0, k=[5e6], fc=[4e3])


@pytest.mark.parametrize("amplitude", [13e-3, 38e-3])
def test_clearance_loop_area_is_4_fc_times_the_slip_travel(amplitude):
    """Steady sinusoidal cycle: area ``4 fc (A - gap - fc/k)`` (derived in docs/elements.md). The
    law is exact at the samples; the trapezoidal area misses the corners between samples,
    ``O(fc dx)`` with ``dx = 2 pi A / 4000``: below 1e-3 of the area (measured 1e-6)."""
    model = ClearanceIwanModel(**DAMPER)
    _, x = _cycles(amplitude)
    expected = 4.0 * 4e3 * (amplitude - 3e-3 - 4e3 / 5e6)
    assert _last_cycle_area(x, model.force(x)) == pytest.approx(expected, rel=1e-3)
    assert model.loop_area(amplitude) == pytest.approx(expected, rel=1e-15)


def test_clearance_force_is_zero_over_2_gap_after_every_reversal():
    """After the reversal at ``+A`` the force falls to zero at ``A - fc/k`` and stays exactly zero
    for ``2 gap`` of travel (then the other side of the clearance is reached): to within one
    sample spacing (2 pi A / 4000 = 20 um)."""
    model = ClearanceIwanModel(**DAMPER)
    amplitude = 25e-3
    _, x = _cycles(amplitude)
    force = model.force(x)
    descending = slice(4000 + 1000, 4000 + 3000 + 1)  # second cycle, from +A to -A
    zero = x[descending][force[descending] == 0.0]
    spacing = 2.0 * np.pi * amplitude / 4000
    assert zero.max() == pytest.approx(amplitude - 4e3 / 5e6, abs=spacing)
    assert np.ptp(zero) == pytest.approx(2.0 * 3e-3, abs=2.0 * spacing)
    assert np.all(np.abs(force[descending][x[descending] > zero.max()]) > 0.0)


def test_clearance_of_zero_width_is_the_iwan_model_bit_for_bit():
    iwan = dict(g1=2e3, g2=1e5, g3=-1e6, k=[3e3, 9e3], fc=[8.3, 14.6])
    _, x = _cycles(5e-3, per_cycle=400)
    np.testing.assert_array_equal(ClearanceIwanModel(gap=0.0, **iwan).force(x), IwanModel(**iwan).force(x))


# ------------------------------------------------------------------ rate-dependent slip

RATE = dict(g1=0.0, k=[1e9], fc=[1e3], slip_rate_gain=0.6, slip_speed=0.05)


def _rigid_plastic_energy(amplitude, freq):
    """``integral fc(v) |dx|`` over a cycle of ``A sin(w t)`` (rigid slider: ``k -> inf``), by quadrature."""
    speed = 2.0 * np.pi * freq * amplitude

    def integrand(theta):
        return (1.0 + 0.6 * math.tanh(speed * math.cos(theta) / 0.05)) * amplitude * math.cos(theta)

    return 4.0 * 1e3 * quad(integrand, 0.0, 0.5 * math.pi, epsabs=0.0, epsrel=1e-12)[0]


@pytest.mark.parametrize("freq", [0.05, 0.5, 5.0])
def test_rate_dependent_loop_area_matches_the_slip_force_integral(freq):
    """A nearly rigid element (``fc / k = 1 um`` against ``A = 10 mm``) dissipates ``integral fc(v)
    |dx|`` a cycle; within 2e-3 (the stick travel ``2 fc / k`` over ``4 A`` and the sampled rate,
    the secant over a step, against ``v`` at the samples: ``(2 pi / 4000)^2``); measured 1e-4."""
    model = RateDependentIwanModel(**RATE)
    time, x = _cycles(10e-3, freq=freq)
    area = _last_cycle_area(x, model.force(x, time=time))
    assert area == pytest.approx(_rigid_plastic_energy(10e-3, freq), rel=2e-3)


def test_rate_dependent_loop_area_rises_with_frequency():
    model = RateDependentIwanModel(**RATE)
    areas = []
    for freq in (0.05, 0.5, 5.0):
        time, x = _cycles(10e-3, freq=freq, per_cycle=400)
        areas.append(_last_cycle_area(x, model.force(x, time=time), per_cycle=400))
    assert areas[0] < areas[1] < areas[2]
    assert areas[2] / areas[0] > 1.5  # towards 1 + r = 1.6 at speeds far above v_ref


def test_rate_dependent_without_gain_is_the_iwan_model_bit_for_bit():
    iwan = dict(g1=2e3, k=[3e3, 9e3], fc=[8.3, 14.6])
    time, x = _cycles(5e-3, per_cycle=400, freq=3.0)
    model = RateDependentIwanModel(slip_rate_gain=0.0, slip_speed=0.01, **iwan)
    np.testing.assert_array_equal(model.force(x, time=time), IwanModel(**iwan).force(x))
    # without sample times: the quasi-static limit, slip forces at rest
    np.testing.assert_array_equal(RateDependentIwanModel(slip_rate_gain=2.0, slip_speed=0.01, **iwan).force(x),
                                  IwanModel(**iwan).force(x))


# ------------------------------------------------------------------ pinched Bouc-Wen

Z_U, N = 40.0, 1.5
TOTAL = 2e4 / Z_U**N
PINCHED = dict(k1=1e3, k2=0.0, k3=0.0, alpha=2e4, beta=0.6 * TOTAL, gamma=0.4 * TOTAL, n=N, pinch=0.7,
               pinch_width=0.25, pinch_shift=0.1)


def test_pinched_boucwen_without_pinching_is_the_boucwen_model_bit_for_bit():
    plain = {key: value for key, value in PINCHED.items() if not key.startswith("pinch")}
    _, x = _cycles(6e-3, per_cycle=400)
    np.testing.assert_array_equal(PinchedBoucWenModel(**{**PINCHED, "pinch": 0.0}).force(x),
                                  BoucWenModel(**plain).force(x))


def test_pinched_z_matches_an_ode_solver():
    """``z`` along rising and falling branches against solve_ivp (DOP853, rtol 1e-11) on the
    pinched ``dz/dx``; within 1e-6 of ``z_u`` (RK4 sub-steps: ``(dx / length)^4``-small at 400
    samples a branch)."""
    model = PinchedBoucWenModel(**PINCHED)
    pinch, width, shift = model.pinching()
    path = np.concatenate([np.linspace(0.0, 6e-3, 401), np.linspace(6e-3, -4e-3, 401)[1:]])
    z = model.hysteretic_force(path)

    def slope(direction):
        def rate(_x, state):
            value = state[0]
            sign = np.sign(direction * value)
            factor = 1.0 - pinch * math.exp(-((value * direction - shift) / width) ** 2)
            return [factor * (2e4 - (0.4 * TOTAL + 0.6 * TOTAL * sign) * abs(value) ** N)]
        return rate

    up = solve_ivp(slope(1.0), (0.0, 6e-3), [0.0], method="DOP853", rtol=1e-11, atol=1e-12, dense_output=True)
    down = solve_ivp(slope(-1.0), (6e-3, -4e-3), [up.y[0, -1]], method="DOP853", rtol=1e-11, atol=1e-12,
                     dense_output=True)
    reference = np.concatenate([up.sol(path[:401])[0], down.sol(path[401:])[0]])
    assert np.max(np.abs(z - reference)) < 1e-6 * Z_U


def test_pinched_loop_slope_dips_to_its_depth_where_z_crosses_the_dip():
    """On a falling branch, away from saturation (``|z| < z_u / 2``), the slope ``dz/dx`` is smallest
    near ``z sgn(dx) = shift z_u``, i.e. ``z = -0.1 z_u`` (within 0.05 ``z_u``: the Bouc-Wen factor
    also falls with ``|z|``), and there equals ``(1 - pinch)(alpha - (gamma + beta)|z|^n)`` (the
    law's closed form; loading: ``sgn(dx z) = +1``); the sampled slope (800 points a branch, the
    secant between samples) is within 2 % of it (measured 0.04 %)."""
    model = PinchedBoucWenModel(**PINCHED)
    path = np.concatenate([np.linspace(0.0, 6e-3, 401), np.linspace(6e-3, -6e-3, 801)[1:]])
    z = model.hysteretic_force(path)
    falling_z, falling_x = z[401:], path[401:]
    slopes = np.diff(falling_z) / np.diff(falling_x)
    middle = 0.5 * (falling_z[1:] + falling_z[:-1])
    inside = np.abs(middle) < 0.5 * Z_U
    at = int(np.argmin(np.where(inside, slopes, np.inf)))
    centre = -0.1 * Z_U
    assert middle[at] == pytest.approx(centre, abs=0.05 * Z_U)
    nearest = int(np.argmin(np.abs(middle - centre)))
    expected = (1.0 - 0.7) * (2e4 - TOTAL * abs(centre) ** N)
    assert slopes[nearest] == pytest.approx(expected, rel=2e-2)
    assert model.small_amplitude_stiffness(0.0).real == pytest.approx(1e3 + (1.0 - 0.7 * math.exp(-0.16)) * 2e4)


# ------------------------------------------------------------------ files and refusals


@pytest.mark.parametrize("model", [
    ClearanceIwanModel(gap=2e-3, g1=10.0, k=[5e6], fc=[4e3], c_visc=1.0),
    RateDependentIwanModel(g1=1e4, k=[2e6], fc=[2e3], slip_rate_gain=0.6, slip_speed=0.05),
    PinchedBoucWenModel(**PINCHED),
], ids=lambda model: model.kind)
def test_model_file_round_trip(model, tmp_path):
    path = tmp_path / f"{model.kind}.json"
    save_model(model, path)
    loaded = load_model(path)
    assert type(loaded) is type(model) and loaded == model


def test_model_file_refuses_a_wrong_unit(tmp_path):
    path = tmp_path / "damper.json"
    save_model(ClearanceIwanModel(gap=2e-3, g1=0.0, k=[5e6], fc=[4e3]), path)
    path.write_text(path.read_text().replace('"gap": "m"', '"gap": "mm"'))
    with pytest.raises(ModelFileError, match="gap"):
        load_model(path)


@pytest.mark.parametrize("build, name", [
    (lambda: ClearanceIwanModel(gap=-1e-3, g1=0.0, k=[5e6], fc=[4e3]), "gap"),
    (lambda: RateDependentIwanModel(g1=0.0, k=[1.0], fc=[1.0], slip_rate_gain=-1.0, slip_speed=0.1),
     "slip_rate_gain"),
    (lambda: RateDependentIwanModel(g1=0.0, k=[1.0], fc=[1.0], slip_rate_gain=0.5, slip_speed=0.0), "slip_speed"),
    (lambda: PinchedBoucWenModel(**{**PINCHED, "pinch": 1.0}), "pinch"),
    (lambda: PinchedBoucWenModel(**{**PINCHED, "pinch_width": 0.0}), "pinch_width"),
    (lambda: PinchedBoucWenModel(**{**PINCHED, "gamma": -TOTAL}), "beta \\+ gamma"),
])
def test_parameters_outside_their_domain_are_refused_by_name(build, name):
    with pytest.raises(ParameterError, match=name):
        build()
