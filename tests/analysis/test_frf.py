"""Tests of idkit.analysis.frf against an exactly discretized linear SDOF transmissibility."""

import numpy as np
import pytest
from scipy import signal as sps

from idkit.analysis.frf import estimate_frf
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


def test_h1_matches_the_analytic_transmissibility_within_the_random_error():
    base, top = _simulate(2**18, output_noise=0.02, seed=7)
    est = estimate_frf(base, top, fs=FS, nperseg=8192, f_lo=1.0, f_hi=100.0)
    exact = _transmissibility(_warped(est.freq))
    relative_error = np.abs(est.h1 - exact) / np.abs(exact)
    # Bendat & Piersol random error eps = sqrt(1-g^2)/(|g| sqrt(2 n_d)) for |H| (and phase
    # std ~ eps rad), so the complex error is ~ Rayleigh with scale eps; 5 eps is exceeded
    # with p ~ 4e-6 per line. Bias allowance 0.5 %: Hann resolution bias at the peak is
    # (1/3)(B_e/B_r)^2 = (1/3)(1.5 * 0.122 Hz / 2 Hz)^2 = 0.28 %; overlapping segments make
    # n_d slightly optimistic, which the factor 5 absorbs.
    assert est.n_segments == 63
    assert np.all(relative_error < 5 * est.random_error + 0.005)
    # ...and the bound is not vacuous: typical errors are about eps
    assert 0.3 < np.median(relative_error / est.random_error) < 2.0
    # coherence falls where |H| drops below the output noise: g^2 = |H|^2/(|H|^2 + 0.02^2)
    expected_coherence = np.abs(exact) ** 2 / (np.abs(exact) ** 2 + 0.02**2)
    # coherence estimate std (Bendat & Piersol eq. 9.73): sqrt(2) |g| (1 - g^2) / sqrt(n_d);
    # 5 of those plus 0.01 for its small positive bias and overlap
    coherence_std = (np.sqrt(2 * expected_coherence) * (1 - expected_coherence)
                     / np.sqrt(est.n_segments))
    assert np.all(np.abs(est.coherence - expected_coherence) < 5 * coherence_std + 0.01)


def test_h1_is_coherence_times_h2_and_h2_is_biased_up_by_output_noise():
    base, top = _simulate(2**16, output_noise=0.05, seed=3)
    est = estimate_frf(base, top, fs=FS, nperseg=2048, overlap=2 / 3, f_lo=1.0, f_hi=200.0)
    # algebraic identity of the estimators: rounding only
    np.testing.assert_allclose(est.h1, est.coherence * est.h2, rtol=1e-10)
    assert np.all(np.abs(est.h2) >= np.abs(est.h1))
    assert est.noverlap == 1365
    assert est.freq[0] >= 1.0 and est.freq[-1] <= 200.0
    assert list(est.to_dataframe().columns) == ["freq_Hz", "h1", "h2", "coherence", "random_error"]


def test_estimate_frf_checks_its_inputs():
    x = np.random.default_rng(0).standard_normal(1000)
    with pytest.raises(DataError, match="equal length"):
        estimate_frf(x, x[:-1], fs=FS, nperseg=256)
    with pytest.raises(DataError, match="nperseg"):
        estimate_frf(x, x, fs=FS, nperseg=2000)
    with pytest.raises(DataError, match="f_lo"):
        estimate_frf(x, x, fs=FS, nperseg=256, f_lo=100.0, f_hi=10.0)
    with pytest.raises(DataError, match="overlap"):
        estimate_frf(x, x, fs=FS, nperseg=256, overlap=1.0)
