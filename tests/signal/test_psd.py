"""Tests of idkit.signal.psd: profiles, random-phase synthesis, Welch, RMS."""

import numpy as np
import pytest
from scipy import integrate
from scipy import signal as sps

from idkit.signal.psd import (
    cumulative_rms,
    output_psd,
    PsdProfile,
    rms_from_psd,
    synthesize_random,
    welch_psd,
    welch_rms,
)
from idkit.errors import DataError

FS, FREQ_STEP = 800.0, 0.05  # SPEC section 5 defaults: 16000 samples, 20 s
FLAT = PsdProfile.flat(1e-3, f_lo=0.1, f_hi=100.0)


def test_log_log_interpolation_matches_hand_values():
    profile = PsdProfile([10.0, 100.0], [1e-3, 1e-2])
    # a decade at constant log-log slope 1: the geometric mid-frequency has the geometric
    # mean level, 31.62 Hz -> 3.162e-3 (the rounded frequency gives 3.1620e-3)
    assert float(profile(31.62)) == pytest.approx(3.162e-3, rel=1e-12)
    assert float(profile(np.sqrt(1000.0))) == pytest.approx(np.sqrt(1e-5), rel=1e-12)
    np.testing.assert_allclose(profile([10.0, 100.0]), [1e-3, 1e-2], rtol=1e-12)
    np.testing.assert_array_equal(profile([5.0, 150.0]), [0.0, 0.0])  # zero outside the band
    np.testing.assert_allclose(profile.slopes_db_per_octave, [10 * np.log10(2)], rtol=1e-12)


def test_profile_from_slopes_in_db_per_octave():
    # +3 dB/oct from 20 to 80 Hz (two octaves: x4), flat to 350 Hz, -6 dB/oct to 2000 Hz
    profile = PsdProfile.from_slopes([20.0, 80.0, 350.0, 2000.0], start_level=0.01,
                                     slopes_db_per_octave=[10 * np.log10(2), 0.0,
                                                           -20 * np.log10(2)])
    np.testing.assert_allclose(profile.level, [0.01, 0.04, 0.04, 0.04 * (350 / 2000) ** 2],
                               rtol=1e-12)
    assert float(profile(40.0)) == pytest.approx(0.02, rel=1e-12)
    assert list(profile.to_dataframe().columns) == ["freq [Hz]", "level", "slope [dB/octave]"]


@pytest.mark.parametrize("levels", [[1e-3, 1e-2, 1e-2, 1e-4], [1e-2, 1e-3, 1e-3, 1e-6]])
def test_exact_mean_square_of_a_profile(levels):
    # the second table has an f^-1 segment (10 -> 100 Hz, 1e-2 -> 1e-3), the log special case
    profile = PsdProfile([1.0, 10.0, 100.0, 500.0], levels)
    f = np.geomspace(1.0, 500.0, 200_001)
    numeric = integrate.trapezoid(profile(f), f)
    # trapezoid on 2e5 log-spaced points: relative error ~ (d ln f)^2 / 12 ~ 1e-10
    assert profile.mean_square() == pytest.approx(numeric, rel=1e-8)
    assert profile.rms() == pytest.approx(np.sqrt(numeric), rel=1e-8)


def test_synthesis_is_real_reproducible_and_seed_dependent():
    signals = synthesize_random(FLAT, seed=42)
    assert signals.shape == (30, 16000)
    assert signals.dtype == np.float64
    np.testing.assert_array_equal(signals, synthesize_random(FLAT, seed=42))  # bit for bit
    other = synthesize_random(FLAT, seed=43)
    assert not np.allclose(signals, other)
    assert not np.allclose(signals[0], signals[1])  # realizations differ


def test_synthesis_rms_equals_the_psd_integral():
    signals = synthesize_random(FLAT, seed=1, n_realizations=4)
    grid = np.arange(16000 // 2 + 1) * FREQ_STEP
    lines = FLAT(grid)
    lines[[0, -1]] = 0.0
    # Parseval: every realization's mean square is the grid sum of S df, to rounding
    np.testing.assert_allclose(np.mean(signals**2, axis=1), np.sum(lines) * FREQ_STEP,
                               rtol=1e-12)
    # the grid sum differs from the exact integral by the band-edge lines only:
    # at most FREQ_STEP * (S(f_lo) + S(f_hi)) / 2 = 5e-5 absolute, 5e-4 relative here
    edge = FREQ_STEP * (FLAT(0.1) + FLAT(100.0)) / 2
    np.testing.assert_allclose(np.mean(signals**2, axis=1), FLAT.mean_square(),
                               rtol=0, atol=1.01 * edge)


@pytest.mark.parametrize(
    "profile",
    [FLAT, PsdProfile([2.0, 10.0, 60.0, 150.0], [1e-4, 1e-3, 1e-3, 1e-5])],
    ids=["flat", "breakpoints"],
)
def test_welch_psd_of_the_realizations_matches_the_target(profile):
    estimate = welch_psd(synthesize_random(profile, seed=9), fs=FS)
    assert (estimate.nperseg, estimate.noverlap, estimate.n_segments) == (1998, 1332, 22)
    resolution = FS / estimate.nperseg
    # Hann leakage smears the band edges over ~2 lines: compare 3 lines inside the band
    inside = ((estimate.freq > profile.freq[0] + 3 * resolution)
              & (estimate.freq < profile.freq[-1] - 3 * resolution))
    ratio = estimate.psd[inside] / profile(estimate.freq[inside])
    # Chi-square scatter: with K averages of independent segments the relative std is
    # 1/sqrt(K). Overlapped segments are not independent, so bound it with the count of
    # non-overlapping segments, K = 30 * 16000 / 1998 = 240 -> 6.5 % (random phases with
    # deterministic amplitudes scatter less than that).
    independent = 30 * 16000 / estimate.nperseg
    assert np.std(ratio) < 1 / np.sqrt(independent)
    # no bias: the mean over ~250-450 lines averages the scatter down to < 1 %; slope
    # curvature within one Hann main lobe adds < 0.2 % for these profiles
    assert np.mean(ratio) == pytest.approx(1.0, abs=0.01)


def test_rms_and_cumulative_rms():
    freq = np.linspace(0.0, 100.0, 1001)
    psd = np.full(freq.size, 1e-2)
    assert rms_from_psd(freq, psd) == pytest.approx(1.0, rel=1e-12)
    cumulative = cumulative_rms(freq, psd)
    # flat PSD: mean square grows linearly, RMS as sqrt(f)
    np.testing.assert_allclose(cumulative, np.sqrt(1e-2 * freq), rtol=1e-12, atol=1e-15)
    assert cumulative[-1] == pytest.approx(rms_from_psd(freq, psd), rel=1e-12)


def test_output_psd_of_a_linear_system_matches_filtered_realizations():
    # Base-excited SDOF transmissibility, 5 Hz, zeta = 0.07 (SPEC 6 reference system),
    # discretized with Tustin: the sampled system's FRF is H_d(exp(i w T)) (exact).
    wn, zeta = 2 * np.pi * 5.0, 0.07
    num, den, _ = sps.cont2discrete(([2 * zeta * wn, wn**2], [1, 2 * zeta * wn, wn**2]),
                                    1 / FS, method="bilinear")
    inputs = synthesize_random(FLAT, seed=5)
    # the synthesized records are periodic: filter two periods, keep the second (transient
    # decays as exp(-zeta wn t), < 1e-9 after 20 s)
    outputs = sps.lfilter(np.ravel(num), den, np.tile(inputs, 2), axis=-1)[:, 16000:]
    estimate = welch_psd(outputs, fs=FS)
    _, h = sps.freqz(np.ravel(num), den, worN=estimate.freq, fs=FS)
    predicted = output_psd(h, FLAT(estimate.freq))
    resolution = FS / estimate.nperseg
    # away from the band edges and from the resonance peak (where the 0.4 Hz resolution
    # against the 0.7 Hz half-power bandwidth biases Welch by a few %)
    inside = ((estimate.freq > 1.0) & (estimate.freq < 100.0 - 3 * resolution)
              & (np.abs(estimate.freq - 5.0) > 2.0))
    ratio = estimate.psd[inside] / predicted[inside]
    assert np.std(ratio) < 1 / np.sqrt(30 * 16000 / estimate.nperseg)  # as above, 6.5 %
    assert np.mean(ratio) == pytest.approx(1.0, abs=0.01)
    with pytest.raises(DataError, match="shape"):
        output_psd(h[:-1], predicted)


def test_synthesis_and_welch_check_their_inputs():
    with pytest.raises(DataError, match="integer number of samples"):
        synthesize_random(FLAT, seed=0, fs=800.0, freq_step=0.07)
    with pytest.raises(DataError, match="psd"):
        synthesize_random(lambda f: -np.ones_like(f), seed=0)
    with pytest.raises(DataError, match="nperseg"):
        welch_psd(np.zeros(100), fs=FS, nperseg=200)
    with pytest.raises(DataError, match="increasing"):
        PsdProfile([10.0, 5.0], [1.0, 1.0])
    with pytest.raises(DataError, match="positive"):
        PsdProfile([1.0, 5.0], [1.0, 0.0])


def test_synthesis_refuses_a_profile_it_would_cut_and_seeds_numpy_would_reject():
    profile = PsdProfile.flat(1e-3, f_lo=0.1, f_hi=100.0)
    with pytest.raises(DataError, match="reaching 100 Hz, expected none above the Nyquist frequency fs / 2 = 50 Hz"):
        synthesize_random(profile, seed=1, fs=100.0, freq_step=0.5)
    kept = synthesize_random(profile, seed=1, fs=200.0, freq_step=0.5, n_realizations=1)  # 100 Hz = fs / 2
    assert kept.shape == (1, 400)


@pytest.mark.parametrize("n_samples, nperseg, overlap", [
    (26667, 16000, 2 / 3),  # the study's analysed span: one record and its 2/3 overlap, three segments
    (1000, 99, 0.5),  # odd segments (the last bin counts twice), a remainder left out
    (37, 9, 2 / 3),
    (500, 500, 0.0),
])
def test_welch_rms_is_the_rms_of_the_welch_psd(n_samples, nperseg, overlap):
    # Parseval's theorem against the spectrum itself: the same quantity summed in another order, so
    # round-off of sums of up to 16000 terms (a few 1e-16 measured); the offset checks the segments'
    # means are removed as welch_psd removes them
    signals = np.random.default_rng(3).standard_normal((3, n_samples)) * 2.0 + 1.5
    estimate = welch_psd(signals, fs=FS, nperseg=nperseg, overlap=overlap, average=False)
    reference = [rms_from_psd(estimate.freq, psd) for psd in estimate.psd]
    np.testing.assert_allclose(welch_rms(signals, fs=FS, nperseg=nperseg, overlap=overlap), reference, rtol=1e-12)
    assert welch_rms(signals[0], fs=FS, nperseg=nperseg, overlap=overlap) == pytest.approx(reference[0], rel=1e-12)
    with pytest.raises(DataError, match="nperseg"):
        welch_rms(signals, fs=FS, nperseg=n_samples + 1)
