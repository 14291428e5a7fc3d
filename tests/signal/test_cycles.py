"""Tests of idkit.signal.cycles: reversals, cycle split, resampling."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from idkit.signal.cycles import classify_amplitudes, find_reversals, resample_loops, split_cycles
from idkit.errors import DataError, FitError


def _loops(amplitudes_m, samples_per_cycle=400):
    """Deflection of consecutive sine cycles with the given amplitudes (starting at 0)."""
    phase = np.linspace(0, 2 * np.pi, samples_per_cycle, endpoint=False)
    return np.concatenate([a * np.sin(phase) for a in amplitudes_m] + [np.zeros(1)])


def test_reversals_of_a_clean_sine_are_its_extrema():
    x = 1e-3 * np.sin(np.linspace(0, 6 * np.pi, 601))
    assert find_reversals(x, min_excursion=1e-5).tolist() == [50, 150, 250, 350, 450, 550]


def test_threshold_semantics_move_back_by_more_than_min_excursion():
    x = np.array([0.0, 1.0, 2.0, 1.5, 3.0, 0.0])
    # 2 -> 1.5 moves back by 0.5: no reversal for a 0.6 threshold, a reversal for 0.4
    assert find_reversals(x, min_excursion=0.6).tolist() == [4]
    assert find_reversals(x, min_excursion=0.4).tolist() == [2, 3, 4]
    # exactly equal to the threshold is not "more than"
    assert find_reversals(x, min_excursion=0.5).tolist() == [4]


def test_reversals_are_robust_to_noise_and_spikes():
    rng = np.random.default_rng(11)
    amplitudes = [1e-3, 2e-3, 0.5e-3, 3e-3]
    clean = _loops(amplitudes)
    noisy = clean + rng.normal(0.0, 2e-6, clean.size)
    spikes = rng.choice(clean.size, 30, replace=False)
    noisy[spikes] += rng.choice([-1, 1], 30) * 2e-5  # 20 um spikes, 10x the noise sigma
    reversals = find_reversals(noisy, min_excursion=5e-5)
    # 2 turning points per cycle; the spike height (20 um) + noise stays below 50 um
    assert reversals.size == 2 * len(amplitudes)
    expected = np.ravel([[100 + 400 * i, 300 + 400 * i] for i in range(len(amplitudes))])
    # Near a sine peak the curve is flat: |x - peak| < noise + spike within
    # sqrt(2 * 2.6e-5 / a) rad, i.e. at most ~0.23 rad = 15 samples for a = 1e-3 m
    # (0.5e-3 m loop: 21 samples). A spike at the peak may win, so allow 25 samples.
    assert np.max(np.abs(reversals - expected)) <= 25
    signs = np.sign(np.diff(noisy[reversals]))
    assert np.all(signs[1:] == -signs[:-1])  # maxima and minima alternate


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.floats(0.2, 5.0), min_size=2, max_size=8),
    st.integers(3, 30),
)
def test_reversals_of_a_zigzag_are_its_corners(excursions, samples_per_leg):
    # Legs alternate in direction with lengths > 2 * threshold; every corner is a reversal.
    corners = np.concatenate([[0.0], np.cumsum(excursions * np.resize([1, -1], len(excursions)))])
    legs = [np.linspace(a, b, samples_per_leg, endpoint=False)
            for a, b in zip(corners, corners[1:])]
    x = np.concatenate(legs + [corners[-1:]])
    expected = samples_per_leg * np.arange(1, len(excursions))
    assert find_reversals(x, min_excursion=0.1).tolist() == expected.tolist()


@pytest.mark.parametrize("record", [[0.0, 1.0], np.linspace(0, 1, 50), np.zeros(50)])
def test_no_reversal_or_too_few_points_raise_fit_error(record):
    with pytest.raises(FitError, match="deflection"):
        find_reversals(record, min_excursion=1e-3)


def test_split_cycles_amplitudes_and_classification():
    amplitudes = [0.5e-3, 2e-3, 8e-3, 1e-3]
    x = _loops(amplitudes) + 1e-4  # an offset goes into center, not amplitude
    split = split_cycles(x, min_excursion=1e-5, large_threshold=1.5e-3)
    # reversals at 100 (max), 300 (min), 500 (max), ...; a cycle is max-min-max over three
    # reversals (100-300-500, 500-700-900, 900-1100-1300): high = the larger of the two
    # maxima, low = the minimum of the first sine.
    assert split.reversals.size == 8
    assert split.n_cycles == 3
    pairs = np.array([[amplitudes[i], amplitudes[i + 1]] for i in range(3)])
    high, low = pairs.max(axis=1), -pairs[:, 0]
    expected = 0.5 * (high - low)
    # sampled sine peaks are exact (index 100 is phase pi/2): tolerance = rounding only
    np.testing.assert_allclose(split.amplitude, expected, rtol=1e-12)
    np.testing.assert_allclose(split.center, 1e-4 + 0.5 * (high + low), atol=1e-15)
    assert split.is_large.tolist() == (expected > 1.5e-3).tolist()
    assert split.branch_direction.tolist() == [-1, 1, -1, 1, -1, 1, -1]
    table = split.to_dataframe()
    assert list(table.columns) == [
        "cycle_start", "cycle_stop", "amplitude [m]", "center [m]", "is_large"
    ]
    assert len(table) == 3


def test_classify_amplitudes_strictly_above_threshold():
    assert classify_amplitudes([1.0, 2.0, 3.0], threshold=2.0).tolist() == [False, False, True]


def test_resampled_branches_keep_reversals_and_are_equally_spaced_in_deflection():
    # Irregular, hand-driven rate: phase advances non-uniformly in time.
    t = np.linspace(0, 1, 6001)
    phase = 2 * np.pi * 3 * (t + 0.05 * np.sin(2 * np.pi * 7 * t))
    x = 2e-3 * np.sin(phase)
    force = 3e3 * x + 5e4 * x**2
    split = split_cycles(x, min_excursion=1e-5)
    loops = resample_loops(x, force, split=split, points_per_branch=21)
    n_branches = split.branch_start.size
    assert loops.deflection.size == n_branches * 20 + 1
    # every reversal is a point of the path, exactly
    ends = np.flatnonzero(np.diff(np.append(loops.branch, -1)) != 0)
    np.testing.assert_array_equal(loops.deflection[np.r_[0, ends]], x[split.reversals])
    for number in range(n_branches):
        on_branch = np.flatnonzero(loops.branch == number)
        if number > 0:
            on_branch = np.r_[on_branch[0] - 1, on_branch]  # starting reversal
        steps = np.diff(loops.deflection[on_branch])
        # monotone branch: linear interpolation hits the targets exactly (rounding only)
        np.testing.assert_allclose(steps, steps.mean(), rtol=1e-9)
    # force interpolated linearly in sample index: the quadratic term's error is at most
    # 5e4 * (largest sample step of x)^2 / 4 (chord error of a parabola)
    bound = 5e4 * np.max(np.abs(np.diff(x))) ** 2 / 4
    np.testing.assert_allclose(loops.force, 3e3 * loops.deflection + 5e4 * loops.deflection**2,
                               rtol=0, atol=bound)
    by_index = resample_loops(x, force, split=split, points_per_branch=21, spacing="index")
    # the irregular rate makes index spacing unequal in deflection
    first = np.diff(by_index.deflection[:21])
    assert first.std() / abs(first.mean()) > 0.1


def test_resampling_a_noisy_branch_stays_near_the_targets():
    rng = np.random.default_rng(5)
    clean = _loops([2e-3, 2e-3])
    noisy = clean + rng.normal(0.0, 1e-6, clean.size)
    loops = resample_loops(noisy, 1e3 * noisy, min_excursion=2e-5, points_per_branch=50)
    first = loops.deflection[:50]
    targets = np.linspace(first[0], first[-1], 50)
    # located on the running envelope: off the target by at most the local noise (5 sigma)
    np.testing.assert_allclose(first, targets, atol=5e-6)
    assert loops.to_dataframe().shape == (loops.deflection.size, 4)


def test_resample_loops_checks_its_inputs():
    x = 1e-3 * np.sin(np.linspace(0, 4 * np.pi, 401))
    with pytest.raises(DataError, match="force has 3 samples"):
        resample_loops(x, [1.0, 2.0, 3.0], min_excursion=1e-5)
    with pytest.raises(DataError, match="min_excursion"):
        resample_loops(x, x)
    one_reversal = 1e-3 * np.sin(np.linspace(0, np.pi, 101))
    with pytest.raises(FitError, match="complete branch"):
        resample_loops(one_reversal, one_reversal, min_excursion=1e-5)
