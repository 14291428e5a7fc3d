"""Tests of idkit.signal.harmonics: least-squares harmonics and HOSIDFs."""

import numpy as np
import pytest

from idkit.signal.harmonics import fit_harmonics, hosidf, input_flatness
from idkit.errors import DataError

FS = 1000.0  # Hz
FREQ = 7.3  # Hz: fs/freq = 136.99... samples per period, deliberately not an integer


def _signal(n_samples, *, bias, coefficients, sub, freq=FREQ, fs=FS):
    t = np.arange(n_samples) / fs
    omega = 2 * np.pi * freq
    values = bias + np.real(sub * np.exp(0.5j * omega * t))
    for order, c in enumerate(coefficients, start=1):
        values = values + np.real(c * np.exp(1j * order * omega * t))
    return values


COEFFICIENTS = np.array([1.5 * np.exp(-0.4j), 0.2 * np.exp(1.1j), 0.05 * np.exp(-2.5j)])


def test_exact_recovery_of_a_multi_harmonic_signal():
    values = _signal(2000, bias=0.3, coefficients=COEFFICIENTS, sub=0.1 * np.exp(0.7j))
    fit = fit_harmonics(values, fs=FS, freq=FREQ, n_harmonics=3)
    # noiseless: only rounding of a well-conditioned ~1600 x 9 least-squares problem
    # (basis nearly orthogonal over whole periods), far below 1e-12 of a unit amplitude
    np.testing.assert_allclose(fit.coefficients, COEFFICIENTS, rtol=0, atol=1e-12)
    assert abs(fit.subharmonic - 0.1 * np.exp(0.7j)) < 1e-12
    assert abs(fit.bias - 0.3) < 1e-12
    assert fit.residual_rms < 1e-12


def test_window_is_the_largest_whole_number_of_periods_from_the_end():
    values = _signal(1000, bias=0.0, coefficients=COEFFICIENTS, sub=0.0)
    # 1000 samples hold 7.3 periods: 6 (even) with the subharmonic, 7 without
    with_sub = fit_harmonics(values, fs=FS, freq=FREQ, n_harmonics=3)
    assert (with_sub.n_periods, with_sub.n_samples, with_sub.first_sample) == (6, 821, 179)
    without = fit_harmonics(values, fs=FS, freq=FREQ, n_harmonics=3, subharmonic=False)
    assert (without.n_periods, without.n_samples, without.first_sample) == (7, 958, 42)
    assert np.isnan(without.subharmonic)
    start = fit_harmonics(values, fs=FS, freq=FREQ, n_harmonics=3, n_periods=4, align="start")
    assert (start.n_samples, start.first_sample) == (547, 0)
    # phases refer to the record's first sample, so every window gives the same coefficients
    for fit in (with_sub, without, start):
        np.testing.assert_allclose(fit.coefficients, COEFFICIENTS, rtol=0, atol=1e-12)


def test_noisy_recovery_is_within_the_least_squares_standard_error():
    rng = np.random.default_rng(2024)
    sigma = 0.05
    clean = _signal(20000, bias=0.3, coefficients=COEFFICIENTS, sub=0.1 * np.exp(0.7j))
    fit = fit_harmonics(clean + rng.normal(0, sigma, clean.size), fs=FS, freq=FREQ, n_harmonics=3)
    standard_error = sigma * np.sqrt(2.0 / fit.n_samples)
    # the reported standard error estimates sigma * sqrt(2/N) (N ~ 2e4: within 3 %)
    assert fit.standard_error == pytest.approx(standard_error, rel=0.03)
    errors = np.concatenate([fit.coefficients - COEFFICIENTS,
                             [fit.subharmonic - 0.1 * np.exp(0.7j)]])
    # 8 real Gaussian errors of std standard_error: 4 sigma is exceeded with p ~ 5e-4
    assert np.max(np.abs(errors.real)) < 4 * standard_error
    assert np.max(np.abs(errors.imag)) < 4 * standard_error
    # bias: std sigma / sqrt(N) (half the variance of a cos/sin coefficient's)
    assert abs(fit.bias - 0.3) < 4 * sigma / np.sqrt(fit.n_samples)


def test_fit_harmonics_rejects_bad_requests():
    values = _signal(1000, bias=0.0, coefficients=COEFFICIENTS, sub=0.0)
    with pytest.raises(DataError, match="n_periods=5 is odd"):
        fit_harmonics(values, fs=FS, freq=FREQ, n_periods=5)
    with pytest.raises(DataError, match="n_periods=8 does not fit"):
        fit_harmonics(values, fs=FS, freq=FREQ, n_periods=8)
    with pytest.raises(DataError, match="Nyquist"):
        fit_harmonics(values, fs=FS, freq=FREQ, n_harmonics=70)
    with pytest.raises(DataError, match="at least 2 are needed"):
        fit_harmonics(values[:200], fs=FS, freq=FREQ)


def test_hosidf_of_a_linear_system_is_its_frequency_response_with_a_distorted_input():
    h = 2.5 * np.exp(-1.2j)  # transmissibility at FREQ
    base_coefficients = np.array([0.01, 1e-4 * np.exp(0.3j), 3e-5 * np.exp(-1j)])
    # a linear system maps harmonic k of the input through H(k w); take H(2w), H(3w) too
    h_k = np.array([h, 0.4 * np.exp(-2.8j), 0.1 * np.exp(-3.0j)])
    base = _signal(4000, bias=0.0, coefficients=base_coefficients, sub=0.0)
    top = _signal(4000, bias=2e-4, coefficients=h_k * base_coefficients, sub=0.0)
    result = hosidf(base, top, fs=FS, freq=FREQ, n_harmonics=3)
    # HOSIDF_k = C_k(top) / C_1(base) = H(k w) C_k(base) / C_1(base); rounding-level tolerance
    expected = h_k * base_coefficients / base_coefficients[0]
    np.testing.assert_allclose(result.hosidf, expected, rtol=0, atol=1e-10)
    np.testing.assert_allclose(result.input_distortion, [1e-2, 3e-3], rtol=1e-8)
    assert result.bias == pytest.approx(2e-2, rel=1e-8)
    assert abs(result.subharmonic) < 1e-10
    assert result.input_amplitude == pytest.approx(0.01, rel=1e-10)
    table = result.to_dataframe()
    assert table["order"].tolist() == [0.0, 0.5, 1.0, 2.0, 3.0]


def test_hosidf_finds_a_subharmonic_response():
    base = _signal(4000, bias=0.0, coefficients=[1.0], sub=0.0)
    top = _signal(4000, bias=0.0, coefficients=[0.5j], sub=0.2 * np.exp(0.5j))
    result = hosidf(base, top, fs=FS, freq=FREQ, n_harmonics=2)
    assert abs(result.subharmonic - 0.2 * np.exp(0.5j)) < 1e-12
    assert abs(result.hosidf[0] - 0.5j) < 1e-12
    # peak-to-peak/2 of top: bounded by the sum of the component amplitudes
    assert result.output_half_range <= 0.7 + 1e-12


def test_input_flatness_from_amplitudes_and_from_results():
    flat = input_flatness([5.0, 10.0, 20.0, 40.0], [0.02, 0.025, 0.01, 0.016])
    assert flat.ratio == pytest.approx(2.5)
    assert flat.ratio_db == pytest.approx(20 * np.log10(2.5))
    assert (flat.freq_of_max, flat.freq_of_min) == (10.0, 20.0)
    results = []
    for freq, amplitude in [(5.0, 0.02), (10.0, 0.03)]:
        base = _signal(2000, bias=0.0, coefficients=[amplitude], sub=0.0, freq=freq)
        results.append(hosidf(base, base, fs=FS, freq=freq, n_harmonics=1))
    from_results = input_flatness([5.0, 10.0], results)
    assert from_results.ratio == pytest.approx(1.5, rel=1e-10)
    with pytest.raises(DataError, match="positive"):
        input_flatness([1.0, 2.0], [0.0, 1.0])


def test_resonance_peak_is_exact_for_a_log_log_parabola_on_an_uneven_axis():
    """The vertex of the parabola through three samples of a parabola is its vertex: equal to
    round-off (1e-12 relative on numbers of order 1); a maximum at the edge is not extrapolated."""
    from idkit.signal.harmonics import resonance_peak

    freq = np.array([1.0, 2.0, 3.1, 7.5, 9.0])
    magnitude = np.exp(2.0 - 3.0 * (np.log(freq) - np.log(3.456)) ** 2)
    f_peak, peak = resonance_peak(freq, magnitude)
    assert f_peak == pytest.approx(3.456, rel=1e-12) and peak == pytest.approx(np.exp(2.0), rel=1e-12)
    assert resonance_peak(freq, freq) == (9.0, 9.0)


def test_resonance_peak_skips_nan_points_and_refuses_unpaired_samples():
    from idkit.signal.harmonics import resonance_peak

    freq = np.array([4.0, 5.0, 6.0, 7.0, 8.0])
    magnitude = np.array([2.0, 5.0, 3.0, np.nan, 1.5])
    # argmax took the NaN at 7 Hz for the peak: (7.0, nan)
    f_peak, peak = resonance_peak(freq, magnitude)
    assert 4.0 < f_peak < 6.0 and peak >= 5.0
    # a NaN neighbour: no parabola, the grid maximum itself
    assert resonance_peak(freq, [2.0, np.nan, 3.0, 5.0, np.nan]) == (7.0, 5.0)
    assert all(np.isnan(resonance_peak(freq, np.full(5, np.nan))))
    with pytest.raises(DataError, match=r"found shapes \(5,\) and \(4,\)"):
        resonance_peak(freq, magnitude[:4])  # was an IndexError
