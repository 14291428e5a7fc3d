"""Tests of idkit.signal.drop on synthetic drops of an undamped linear oscillator."""

import numpy as np
import pytest

from idkit.signal.drop import (
    impact_velocity_from_height,
    process_drop,
    STANDARD_GRAVITY,
    zero_phase_moving_average,
)
from idkit.errors import DataError, ParameterError

FS = 10_000.0  # Hz
F0 = 20.0  # Hz, natural frequency of the synthetic isolator
OMEGA0 = 2 * np.pi * F0
W0T = OMEGA0 / FS  # angle per sample, 0.0126 rad
HEIGHT = 0.05  # m


def _drop(*, impact_sample=500, duration=0.2):
    """Free fall (no relative motion) then an undamped oscillator hit at v0 = -sqrt(2 g h).

    After impact: x = (v0/w0) sin(w0 tau), v = v0 cos(w0 tau), a = -w0^2 x, so the peak
    acceleration is w0 |v0| in compression and in tension, and the peak compression and
    tension are |v0| / w0 (analytic).
    """
    v0 = -np.sqrt(2 * STANDARD_GRAVITY * HEIGHT)
    t = np.arange(int(duration * FS)) / FS
    tau = np.clip(t - t[impact_sample], 0.0, None)
    after = t >= t[impact_sample]
    x = np.where(after, v0 / OMEGA0 * np.sin(OMEGA0 * tau), 0.0)
    v = np.where(after, v0 * np.cos(OMEGA0 * tau), 0.0)
    a = -(OMEGA0**2) * x
    return t, x, v, a, v0


def test_synthetic_drop_recovers_the_analytic_peaks():
    t, x, v, a, v0 = _drop()
    rng = np.random.default_rng(1)
    disturbance = rng.normal(0, 5.0, a.size)  # opposite on the two sensors: cancels in the mean
    result = process_drop(t, x + 2e-3, [a + disturbance, a - disturbance],
                          relative_velocity=v, drop_height=HEIGHT)
    # the smoothed step (triangle of 9 samples) crosses one half at the raw step sample
    assert result.impact_index == 500
    assert result.impact_time == pytest.approx(t[500])
    assert result.deflection_reference == pytest.approx(2e-3, abs=1e-15)
    assert result.impact_velocity_from_height == pytest.approx(v0, rel=1e-15)
    peak_acceleration = OMEGA0 * abs(v0)
    # Peaks sit at quarter periods, in the smooth part: the forward-backward 5-sample mean
    # loses 2 (w0 T)^2 of a sine's amplitude and sampling misses <= (w0 T)^2 / 8 of a peak:
    # tolerance 3 (w0 T)^2 = 4.7e-4 relative.
    filter_tolerance = 3 * W0T**2
    assert result.peak_acceleration_compression == pytest.approx(peak_acceleration,
                                                                 rel=filter_tolerance)
    assert result.peak_acceleration_tension == pytest.approx(peak_acceleration,
                                                             rel=filter_tolerance)
    # compression peaks at a quarter period after impact, tension peaks at three quarters;
    # the oscillator is undamped, so any later cycle may hold the (equal) maximum
    period = 1 / F0
    for peak_time, phase in ((result.time_peak_acceleration_compression, 0.25),
                             (result.time_peak_acceleration_tension, 0.75)):
        offset = (peak_time - t[500] - phase * period + period / 2) % period - period / 2
        assert abs(offset) <= 2 / FS
    # deflection is not smoothed: only the sampling error (w0 T)^2 / 8 of the peak
    sampling_tolerance = W0T**2 / 8
    assert result.max_compression == pytest.approx(abs(v0) / OMEGA0, rel=sampling_tolerance)
    assert result.max_tension == pytest.approx(abs(v0) / OMEGA0, rel=sampling_tolerance)
    # the smoothed step reaches its full height 4 samples late, where the cosine has lost
    # (4 w0 T)^2 / 2 = 8 (w0 T)^2, and the filter gain another 2 (w0 T)^2: the stated error
    # of the measured impact velocity is 10 (w0 T)^2 (1.6e-3); allow 12 (w0 T)^2
    assert result.impact_velocity == pytest.approx(v0, rel=12 * W0T**2)
    assert result.peak_acceleration == pytest.approx(peak_acceleration, rel=filter_tolerance)
    assert result.to_dataframe().shape == (1, 7)
    assert result.time_series().shape == (t.size, 4)


def test_a_record_starting_at_impact_and_velocity_from_the_deflection():
    t, x, v, a, v0 = _drop(impact_sample=0, duration=0.1)
    result = process_drop(t, x, a)  # relative velocity from numpy.gradient of x
    assert result.impact_index == 0
    assert result.deflection_reference == 0.0
    # central differences of a sine lose (w0 T)^2 / 6; one-sided at the first sample loses
    # ~(w0 T)^2 / 2 more; smoothing adds < 10 (w0 T)^2 (see above): allow 12 (w0 T)^2
    assert result.impact_velocity == pytest.approx(v0, rel=12 * W0T**2)
    assert result.max_compression == pytest.approx(abs(v0) / OMEGA0, rel=W0T**2 / 8)
    assert np.isnan(result.impact_velocity_from_height)


def test_zero_phase_moving_average_response_of_a_sine():
    t = np.arange(4000) / FS
    sine = np.sin(OMEGA0 * t)
    smoothed = zero_phase_moving_average(sine)
    # net filter = 9-sample triangle: gain (sin(5 w T/2) / (5 sin(w T/2)))^2, no phase
    gain = (np.sin(2.5 * W0T) / (5 * np.sin(0.5 * W0T))) ** 2
    interior = slice(20, -20)
    np.testing.assert_allclose(smoothed[interior], gain * sine[interior], atol=1e-12)
    np.testing.assert_array_equal(zero_phase_moving_average(sine, window=1), sine)


def test_impact_velocity_from_height():
    assert impact_velocity_from_height(0.08) == pytest.approx(-np.sqrt(2 * 9.80665 * 0.08))
    np.testing.assert_allclose(impact_velocity_from_height([0.0, 0.02], g=10.0),
                               [0.0, -0.632455532],
                               rtol=1e-9)
    with pytest.raises(ParameterError, match="height"):
        impact_velocity_from_height(-0.01)


def test_process_drop_checks_its_inputs():
    t, x, v, a, _ = _drop()
    with pytest.raises(DataError, match="acceleration has shape"):
        process_drop(t, x, a[:-1])
    uneven = t.copy()
    uneven[10] += 0.3 / FS
    with pytest.raises(DataError, match="uniformly"):
        process_drop(uneven, x, a)
    with pytest.raises(DataError, match="never becomes negative"):
        process_drop(t, x, a, relative_velocity=np.abs(v))
