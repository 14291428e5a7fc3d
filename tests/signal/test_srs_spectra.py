"""The three shock response spectra (ISO 18431-4) against analytic results and each other."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal as sps

from idkit.errors import DataError
from idkit.signal.srs import shock_response_spectrum, shock_spectra, smallwood_coefficients


def half_sine(amplitude=1.0, duration=0.01, fs=100_000.0):
    time = np.arange(0.0, duration, 1.0 / fs)
    return amplitude * np.sin(np.pi * time / duration), fs


@pytest.mark.parametrize("damping_ratio", [0.0, 0.05, 0.3])
@pytest.mark.parametrize("freq", [10.0, 400.0, 2400.0])
def test_smallwood_is_the_first_order_hold_discretisation(freq, damping_ratio):
    """Smallwood's closed form equals scipy's FOH (ramp-invariant) discretisation of
    (2 z w s + w^2) / (s^2 + 2 z w s + w^2): two derivations, round-off agreement."""
    fs, omega = 10_000.0, 2 * np.pi * freq
    numerator = [2 * damping_ratio * omega, omega**2] if damping_ratio else [omega**2]
    num, den, _ = sps.cont2discrete((numerator, [1, 2 * damping_ratio * omega, omega**2]), 1 / fs, method="foh")
    b, a = smallwood_coefficients([freq], fs=fs, damping_ratio=damping_ratio)
    np.testing.assert_allclose(b[0], np.ravel(num)[-3:], rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(a[0], den, rtol=1e-12)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_undamped_spectra_are_one_curve(seed):
    """Without damping the absolute acceleration is -w^2 z exactly, so the spectra agree.

    Both are read from the same complex mode (Im(w_n^2 w) / w_d against -Im(w) / w_d), so
    they agree to the round-off of one product: rtol 1e-13."""
    rng = np.random.default_rng(seed)
    record = np.convolve(rng.standard_normal(400), np.hanning(40), mode="same")
    freq = np.logspace(1, 3, 15)
    spectra = shock_spectra(record, fs=20_000.0, freq=freq, damping_ratio=0.0)
    omega = 2 * np.pi * freq
    np.testing.assert_allclose(spectra.absolute_acceleration, omega**2 * spectra.relative_displacement, rtol=1e-13)
    np.testing.assert_allclose(spectra.pseudo_velocity, omega * spectra.relative_displacement, rtol=1e-15)
    np.testing.assert_allclose(spectra.absolute_acceleration,
                               shock_response_spectrum(record, fs=20_000.0, freq=freq, damping_ratio=0.0).maximax,
                               rtol=1e-12)


@pytest.mark.parametrize("f_tau", [0.02, 0.05, 0.1, 0.2])
def test_half_sine_residual_pseudo_velocity_is_the_pulse_spectrum(f_tau):
    """Undamped, below f tau ~ 0.5 the largest response is the residual one, whose
    pseudo-velocity is |A(w)|, the Fourier magnitude of the pulse:
    A (2 pi / tau) |cos(w tau / 2)| / |(pi / tau)^2 - w^2|; -> dv = 2 A tau / pi as f -> 0.
    Tolerance: the peak between samples, (w T)^2 / 8 < 1e-6 here, and the residual window
    holds a full period."""
    pulse, fs = half_sine()
    tau = 0.01
    freq = f_tau / tau
    omega = 2 * np.pi * freq
    expected = (2 * np.pi / tau) * abs(np.cos(omega * tau / 2)) / abs((np.pi / tau) ** 2 - omega**2)
    spectra = shock_spectra(pulse, fs=fs, freq=[freq], damping_ratio=0.0)
    assert spectra.pseudo_velocity[0] == pytest.approx(expected, rel=1e-4)


def test_stiff_oscillators_follow_the_pulse():
    """Far above the pulse the relative displacement is quasi-static, peak |a| / w^2
    (tracking error ~ (f_pulse / f_n)^2 plus the onset transient, within 2 % at 100x)."""
    pulse, fs = half_sine()
    freq = 5000.0  # the pulse's own frequency is 50 Hz; 20 samples per period
    spectra = shock_spectra(pulse, fs=fs, freq=[freq], damping_ratio=0.05)
    assert spectra.relative_displacement[0] * (2 * np.pi * freq) ** 2 == pytest.approx(1.0, rel=0.02)


def test_table_has_units_and_bad_band_is_named():
    pulse, fs = half_sine()
    spectra = shock_spectra(pulse, fs=fs, freq=[10.0, 100.0])
    frame = spectra.to_dataframe()
    assert list(frame.columns) == ["freq [Hz]", "absolute_acceleration [m/s^2]", "pseudo_velocity [m/s]",
                                   "relative_displacement [m]"]
    for column, values in zip(frame.columns, (spectra.freq, spectra.absolute_acceleration, spectra.pseudo_velocity,
                                              spectra.relative_displacement)):
        np.testing.assert_array_equal(frame[column].to_numpy(), values)
    with pytest.raises(DataError, match="freq"):
        shock_spectra(pulse, fs=fs, freq=[fs])
