"""Tests of idkit.signal.srs against independent SDOF solutions."""

import numpy as np
import pytest
from scipy import integrate
from scipy import signal as sps

from idkit.signal.srs import shock_response_spectrum, smallwood_coefficients
from idkit.errors import DataError

AMPLITUDE = 100.0  # m/s^2
DURATION = 0.011  # s, half-sine pulse
ZETA = 0.05


def _half_sine(t):
    return np.where((t >= 0) & (t <= DURATION), AMPLITUDE * np.sin(np.pi * t / DURATION), 0.0)


def _absolute_acceleration_ivp(fn, base_acceleration, t_end, t_eval):
    """Direct integration of z'' + 2 zeta wn z' + wn^2 z = -a_b(t) (z relative displacement);
    the absolute acceleration is -2 zeta wn z' - wn^2 z."""
    wn = 2 * np.pi * fn

    def rhs(_, state):
        z, dz = state
        return [dz, -base_acceleration(_) - 2 * ZETA * wn * dz - wn**2 * z]

    # max_step below the pulse duration/20 so the pulse is never stepped over
    solution = integrate.solve_ivp(rhs, (0.0, t_end), [0.0, 0.0], method="DOP853", rtol=1e-10,
                                   atol=1e-12, t_eval=t_eval, max_step=DURATION / 20)
    z, dz = solution.y
    return -2 * ZETA * wn * dz - wn**2 * z


def test_smallwood_filter_is_exact_for_piecewise_linear_input():
    # Ramp invariance: for input linear between samples the filter output equals the exact
    # continuous response at the samples. Reference: scipy.signal.lsim with first-order hold
    # (matrix-exponential solution of the same piecewise-linear input), independent code.
    fs = 2000.0
    t = np.arange(0, 0.1, 1 / fs)
    accel = _half_sine(t)
    for fn in (10.0, 80.0, 300.0):
        wn = 2 * np.pi * fn
        system = sps.lti([2 * ZETA * wn, wn**2], [1, 2 * ZETA * wn, wn**2])
        _, exact, _ = sps.lsim(system, accel, t, interp=True)
        b, a = smallwood_coefficients([fn], fs=fs, damping_ratio=ZETA)
        filtered = sps.lfilter(b[0], a[0], accel)
        # both exact for this input: agreement to rounding of ~200-step recursions
        np.testing.assert_allclose(filtered, exact, rtol=0, atol=1e-9 * AMPLITUDE)


def test_half_sine_srs_matches_direct_time_integration():
    fs = 50_000.0
    freq = np.array([5.0, 30.0, 90.0, 200.0, 600.0])
    t_record = np.arange(0, DURATION + 1 / fs, 1 / fs)
    srs = shock_response_spectrum(_half_sine(t_record), fs=fs, freq=freq, damping_ratio=ZETA)
    for index, fn in enumerate(freq):
        t_end = t_record[-1] + 1 / fn  # record + the default residual window
        t_fine = np.linspace(0, t_end, 40_001)
        response = _absolute_acceleration_ivp(fn, _half_sine, t_end, t_fine)
        true_max, true_min = response.max(), response.min()
        # The filter sees the response only at its samples: it can miss a peak by up to
        # (wn T)^2 / 8 relative (1.8e-3 at 600 Hz), never overshoot it; the piecewise-linear
        # input and the integrator add < 1e-4.
        tolerance = (2 * np.pi * fn / fs) ** 2 / 8 + 1e-4
        assert srs.positive[index] == pytest.approx(true_max, rel=tolerance)
        assert srs.negative[index] == pytest.approx(-true_min, rel=tolerance)
    np.testing.assert_array_equal(srs.maximax, np.maximum(srs.positive, srs.negative))


def test_srs_limits_impulse_and_static():
    fs = 50_000.0
    t = np.arange(0, DURATION + 1 / fs, 1 / fs)
    srs = shock_response_spectrum(_half_sine(t), fs=fs, freq=[0.5, 5000.0], damping_ratio=0.0)
    # Far below 1/DURATION the pulse is an impulse of area 2 A tau / pi; the undamped
    # residual amplitude is wn * area. Correction is O((wn tau)^2) = 1.2e-3 at 0.5 Hz.
    impulse = 2 * AMPLITUDE * DURATION / np.pi
    assert srs.maximax[0] == pytest.approx(2 * np.pi * 0.5 * impulse, rel=3e-3)
    # Far above, the oscillator follows the pulse: SRS -> A (undamped overshoot of a
    # half-sine at fn tau = 55 is ~ 1 / (2 fn tau) ~ 1 %)
    assert srs.maximax[1] == pytest.approx(AMPLITUDE, rel=0.02)
    assert list(srs.to_dataframe().columns) == ["freq [Hz]", "positive", "negative", "maximax"]


def test_srs_refuses_natural_frequencies_at_or_above_half_the_sample_rate():
    pulse = _half_sine(np.arange(0, 0.02, 1e-4))
    with pytest.raises(DataError, match="below fs / 2"):
        shock_response_spectrum(pulse, fs=1e4, freq=[6000.0])
