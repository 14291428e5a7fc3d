"""Tests of idkit.signal.frf against an exactly discretized linear SDOF transmissibility."""

import numpy as np
import pytest
from scipy import signal as sps

from idkit.signal.frf import estimate_frf
from idkit.errors import DataError

FS = 1000.0  # Hz
MASS, F_N, ZETA = 1.0, 10.0, 0.1  # kg, Hz, -
STIFFNESS = MASS * (2 * np.pi * F_N) ** 2  # N/m
DAMPING = 2 * ZETA * np.sqrt(STIFFNESS * MASS)  # Ns/m


def _transmissibility(freq):
    s = 2j * np.pi * freq
    return (DAMPING * s + STIFFNESS) / (MASS * s**2 + DAMPING * s + STIFFNESS)


def _simulate(n_samples, *, output_noise, seed):
    """Top acceleration of the base-excited SDOF driven by white base acceleration.

    The bilinear (Tustin) map H_d(z) = H(2/T (z-1)/(z+1)) is exact in the sense that
    H_d(exp(i w T)) = H(i (2/T) tan(w T / 2)): the sampled system's true FRF is the analytic
    transmissibility at the warped frequency, an independent exact reference.
    """
    num, den, _ = sps.cont2discrete(([DAMPING, STIFFNESS], [MASS, DAMPING, STIFFNESS]),
                                    1 / FS, method="bilinear")
    rng = np.random.default_rng(seed)
    base = rng.standard_normal(n_samples)
    top = sps.lfilter(np.ravel(num), den, base)
    return base, top + output_noise * rng.standard_normal(n_samples)


def _warped(freq):
    return np.tan(np.pi * freq / FS) * FS / np.pi


# Bendat & Piersol random error of H1: eps = sqrt(1-g^2)/(|g| sqrt(2 n_d)) for |H|, and a
# phase std of ~eps rad, so |H1 - H| / |H| is Rayleigh-distributed with scale eps:
# P(> 3 eps) = exp(-4.5) = 1.1 % of the lines. Over 100 noise seeds the measured share was
# 1.15 % on average and at most 2.6 % (neighbouring lines of overlapping Hann segments are
# correlated, which widens the spread of the share, not its mean); the maximum over the
# 811 lines reached 6.3 eps, so a bound on the maximum must sit well above 5 eps.
SHARE_BEYOND_3_EPS = 0.04  # ~3.5x the Rayleigh share
MAX_IN_EPS = 8.0  # Rayleigh: P(> 8 eps) = 1e-14 per line
BIAS = 0.005  # Hann resolution bias at the peak: (1/3)(1.5 x 0.122 Hz / 2 Hz)^2 = 0.28 %
# Coherence estimate std (Bendat & Piersol 9.73): sqrt(2) |g| (1 - g^2) / sqrt(n_d), plus
# 0.01 for its small positive bias: Gaussian share beyond 3 std 0.27 %; measured at most
# 0.6 % over 100 seeds, maximum 5.7 std.
COHERENCE_SHARE_BEYOND_3_STD = 0.02
COHERENCE_MAX_IN_STD = 8.0


@pytest.mark.parametrize("seed", [7, 9, 27])
def test_h1_matches_the_analytic_transmissibility_within_the_random_error(seed):
    base, top = _simulate(2**18, output_noise=0.02, seed=seed)
    est = estimate_frf(base, top, fs=FS, nperseg=8192, f_lo=1.0, f_hi=100.0)
    exact = _transmissibility(_warped(est.freq))
    assert est.n_segments == 63
    in_eps = (np.abs(est.h1 - exact) / np.abs(exact) - BIAS) / est.random_error
    assert np.mean(in_eps > 3.0) < SHARE_BEYOND_3_EPS
    assert np.max(in_eps) < MAX_IN_EPS
    # ...and the bound is not vacuous: the typical error is the Rayleigh median 1.18 eps
    assert 0.8 < np.median(np.abs(est.h1 - exact) / np.abs(exact) / est.random_error) < 1.6
    # coherence falls where |H| drops below the output noise: g^2 = |H|^2/(|H|^2 + 0.02^2)
    expected_coherence = np.abs(exact) ** 2 / (np.abs(exact) ** 2 + 0.02**2)
    coherence_std = (np.sqrt(2 * expected_coherence) * (1 - expected_coherence)
                     / np.sqrt(est.n_segments))
    coherence_in_std = (np.abs(est.coherence - expected_coherence) - 0.01) / coherence_std
    assert np.mean(coherence_in_std > 3.0) < COHERENCE_SHARE_BEYOND_3_STD
    assert np.max(coherence_in_std) < COHERENCE_MAX_IN_STD


def test_h1_is_coherence_times_h2_and_h2_is_biased_up_by_output_noise():
    base, top = _simulate(2**16, output_noise=0.05, seed=3)
    est = estimate_frf(base, top, fs=FS, nperseg=2048, overlap=2 / 3, f_lo=1.0, f_hi=200.0)
    # algebraic identity of the estimators: rounding only
    np.testing.assert_allclose(est.h1, est.coherence * est.h2, rtol=1e-10)
    assert np.all(np.abs(est.h2) >= np.abs(est.h1))
    assert est.noverlap == 1365
    assert est.freq[0] >= 1.0 and est.freq[-1] <= 200.0
    assert list(est.to_dataframe().columns) == ["freq [Hz]", "h1", "h2", "coherence", "random_error"]


def test_estimate_frf_checks_its_inputs():
    x = np.random.default_rng(0).standard_normal(1000)
    with pytest.raises(DataError, match="equal length"):
        estimate_frf(x, x[:-1], fs=FS, nperseg=256)
    with pytest.raises(DataError, match="nperseg"):
        estimate_frf(x, x, fs=FS, nperseg=2000)
    with pytest.raises(DataError, match="f_lo"):
        estimate_frf(x, x, fs=FS, nperseg=256, f_lo=100.0, f_hi=10.0)


def test_relative_error_refuses_unpaired_points_and_zero_references():
    from idkit.signal.frf import mean_squared_relative_error

    with pytest.raises(DataError, match=r"found shapes \(2,\) and \(3,\)"):  # was numpy's broadcast error
        mean_squared_relative_error([1.0, 2.0], [1.0, 2.0, 3.0])
    with pytest.raises(DataError, match="measured: found a zero value"):  # was inf with a RuntimeWarning
        mean_squared_relative_error([1.0, 2.0], [0.0, 2.0])
