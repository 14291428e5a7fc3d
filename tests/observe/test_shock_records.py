"""Shock records as a first-class input: conditioning, pulses, spectra, response over input."""

from __future__ import annotations

import numpy as np
import pytest

from idkit.datasets import read_afrl_accel, realdata_dir
from idkit.errors import DataError
from idkit.io import AccelerationRecord, Source
from idkit.observe import condition_shock, record_spectra, response_ratio, shock_pulses
from idkit.signal.srs import shock_spectra

FS = 200_000.0


def pulse_record(offset=0.0, amplitude=500.0, duration=0.004, tests=3, seed=0, sign=1.0):
    """Half-sine pulses after a 2 ms pre-trigger, with white sensor noise of 0.1 % of the peak."""
    rng = np.random.default_rng(seed)
    time = np.arange(int(0.02 * FS)) / FS
    shape = np.where((time >= 0.002) & (time <= 0.002 + duration), np.sin(np.pi * (time - 0.002) / duration), 0.0)
    accel = np.column_stack([sign * amplitude * (1 + 0.1 * k) * shape for k in range(tests)])
    accel += offset + rng.normal(0.0, 1e-3 * amplitude, accel.shape)
    return AccelerationRecord(time=time, accel=accel, channel="fixture",
                              source=Source(path="pulse.csv")), duration


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_offset_is_removed_and_the_input_kept(seed):
    record, duration = pulse_record(offset=37.0, seed=seed)
    before = record.accel.copy()
    shock = condition_shock(record)
    # median of ~200 samples of noise sigma 0.5 m/s^2: standard error ~0.04 m/s^2; 0.25 is > 5 sigma
    np.testing.assert_allclose(shock.offset, 37.0, atol=0.25)
    np.testing.assert_array_equal(record.accel, before)
    pulses = shock_pulses(shock.record)
    expected_dv = 2 * 500.0 * np.array([1.0, 1.1, 1.2]) * duration / np.pi
    # the removed offset's error times the record length bounds the velocity error
    np.testing.assert_allclose(pulses.velocity_change, expected_dv, atol=0.25 * 0.02)


def test_negative_pulses_keep_their_sign():
    record, _ = pulse_record(sign=-1.0)
    pulses = shock_pulses(condition_shock(record).record)
    assert np.all(pulses.peak < 0) and np.all(pulses.velocity_change < 0)


def test_low_pass_leaves_a_slow_pulse_and_refuses_nyquist():
    record, _ = pulse_record()
    plain = shock_pulses(condition_shock(record).record)
    filtered = shock_pulses(condition_shock(record, lowpass_hz=20_000.0).record)
    # a 4 ms half sine has no content near 20 kHz; the filter only removes noise (0.1 % of peak)
    np.testing.assert_allclose(filtered.peak, plain.peak, rtol=2e-3)
    with pytest.raises(DataError, match="lowpass_hz.*Nyquist"):
        condition_shock(record, lowpass_hz=FS / 2)


def test_record_without_pre_trigger_is_named():
    record, _ = pulse_record()
    late = AccelerationRecord(time=record.time[415:], accel=record.accel[415:], channel="fixture",
                              source=Source(path="late.csv"))
    with pytest.raises(DataError, match=r"late.csv.*test 1.*offset"):
        condition_shock(late)
    assert condition_shock(late, offset="none").offset.tolist() == [0.0, 0.0, 0.0]


def test_band_beyond_the_sample_rate_is_refused_naming_the_file():
    record, _ = pulse_record()
    with pytest.raises(DataError, match=r"pulse.csv.*too slowly.*fs >= 500000"):
        record_spectra(record, freq=[100.0, 50_000.0])


def test_spectra_per_test_match_the_array_function_and_ratio_is_scale():
    record, _ = pulse_record(tests=2)
    freq = np.logspace(1, 3.5, 12)
    spectra = record_spectra(record, freq=freq)
    direct = shock_spectra(record.accel[:, 1], fs=record.sample_rate_hz, freq=freq)
    np.testing.assert_array_equal(spectra.spectra[1].pseudo_velocity, direct.pseudo_velocity)
    doubled = AccelerationRecord(time=record.time, accel=2 * record.accel, channel="response")
    ratio = response_ratio(doubled, record, freq=freq)
    np.testing.assert_allclose(ratio.ratio, 2.0, rtol=1e-12)
    assert ratio.to_dataframe().columns[0] == "freq [Hz]"


def test_functions_refuse_other_types_with_a_clear_error():
    with pytest.raises(DataError, match="AccelerationRecord"):
        shock_pulses(np.zeros(10))


AFRL = realdata_dir("droptower_shock_afrl")


@pytest.mark.skipif(AFRL is None, reason="../shared/realdata/droptower_shock_afrl is not present")
def test_afrl_drop_tower_records_read_as_the_source_describes():
    """SOURCE.txt: peaks ~11-82 kg_n (1000 g), fixture bottom = input; every shock function
    takes the loaded record type."""
    peaks = {}
    for k in range(1, 7):
        record = read_afrl_accel(AFRL / f"accel_{k}.csv")
        shock = condition_shock(record)
        peaks[record.channel] = np.abs(shock_pulses(shock.record).peak) / 9806.65
        assert np.all(np.abs(shock.offset) < 0.002 * np.abs(record.accel).max(axis=0))
    everything = np.concatenate(list(peaks.values()))
    assert 10.0 < everything.min() < 12.0 and 80.0 < everything.max() < 84.0
    fixture_in = condition_shock(read_afrl_accel(AFRL / "accel_6.csv")).record
    fixture_top = condition_shock(read_afrl_accel(AFRL / "accel_5.csv")).record
    ratio = response_ratio(fixture_top, fixture_in)
    # one rigid fixture: top and bottom see the same shock at low frequency (within 20 %)
    low = ratio.freq < 1000.0
    assert np.all(np.abs(ratio.ratio[:, low] - 1.0) < 0.2)
