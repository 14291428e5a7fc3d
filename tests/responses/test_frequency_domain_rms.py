"""The batched frequency paths of random_response (frequency_domain_rms): the expected Welch RMS in
closed form, and the stays-stuck verdicts decided by bounds before sampling."""

import numpy as np
import pytest
from scipy import integrate

from idkit.models import HybridSystem, library
from idkit.responses.frequency_domain import _expected_output_rms, frequency_domain_rms, small_amplitude_transfer
from idkit.responses.random_vibration import _folded_lines, _hann_line_smoothing
from idkit.responses.small_amplitude import small_amplitude_lines, stays_stuck
from idkit.signal.psd import PsdProfile, synthesize_random

FS, FREQ_STEP = 800.0, 0.05


@pytest.mark.parametrize("record, n_lines", [(16000, 8001), (16000, 32001), (15, 40), (16, 35), (4, 3), (5, 13)])
def test_the_expected_rms_in_closed_form_is_the_smoothed_spectrums_trapezoid(record, n_lines):
    # the spectrum formed (folded above record / 2, Hann-smoothed, integrated by the trapezoidal rule)
    # against one weight per line: the same sums in another order, round-off (2e-15 measured)
    rng = np.random.default_rng(1)
    level = rng.random(n_lines) * (rng.random(n_lines) > 0.3)
    band = level > 0
    gains = rng.random((3, int(band.sum()))) * 10.0
    gains[2, 0] = np.inf  # an undamped resonance on a line: refused
    power = np.zeros((2, n_lines))
    power[:, band] = gains[:2] * level[band]
    spectrum = _hann_line_smoothing(_folded_lines(power, record), record)
    reference = np.sqrt(integrate.trapezoid(spectrum, np.arange(record // 2 + 1) * (FS / record), axis=-1))
    rms = _expected_output_rms(gains, level, band, record, FS)
    np.testing.assert_allclose(rms[:2], reference, rtol=1e-13)
    assert rms[2] == np.inf


def test_stuck_verdicts_decided_by_bounds_are_the_sampled_ones():
    # hybrids (elastomer on the Table 7.1 rope) under one record; the rope's slip forces scaled so
    # that its stuck limit lies below the record's RMS deflection (slips at the lower bound), between
    # the RMS and the sampled peak (sampled: slips), between the peak and the sum of the line
    # amplitudes (sampled: stuck) and above that sum (stuck at the upper bound); the elastomer
    # never slips and is never sampled. Limits at geometric means: far from round-off. The floor keeps
    # the rope's spring linear (deflections below the 75 um at which g2, g3 reach 1e-3 of g1).
    rope, body = library.get("table_7_1_wire_rope"), library.get("table_7_3_elastomer")
    profile = PsdProfile.flat(1e-6, f_lo=1.0, f_hi=100.0)
    signals = synthesize_random(profile, seed=5, fs=FS, freq_step=FREQ_STEP, n_realizations=1)
    _, _, _, deflections = small_amplitude_lines(HybridSystem(15.0, body, 0.15, rope), signals, FS)
    lines = deflections[1][0]
    rms = np.sqrt(0.5 * np.sum(np.abs(lines) ** 2))
    peak = np.abs(np.fft.irfft(np.concatenate([[0.0], lines]) * (signals.shape[1] / 2.0), n=signals.shape[1])).max()
    bound = np.abs(lines).sum()
    assert rms < peak < bound
    params = rope.params()
    limit = min(params["fc_1"] / params["k_1"], params["fc_2"] / params["k_2"])  # deflection at first slip
    targets = [0.5 * rms, np.sqrt(rms * peak), np.sqrt(peak * bound), 2.0 * bound]
    systems = [HybridSystem(15.0, body, 0.15, type(rope).from_params(
        {**params, "fc_1": params["fc_1"] * target / limit, "fc_2": params["fc_2"] * target / limit}))
        for target in targets]
    rms_values = frequency_domain_rms(systems, profile, np.repeat(signals, len(systems), axis=0), fs=FS,
                                      freq_step=FREQ_STEP)
    verdicts = [stays_stuck(system, signals, FS)[0] for system in systems]
    assert verdicts == [False, False, True, True]
    assert list(np.isfinite(rms_values)) == verdicts  # NaN: the time domain
    # a transfer given by the caller on more lines than the band's (taken), or on fewer (computed): the
    # same numbers
    freq = np.fft.rfftfreq(signals.shape[1], d=1.0 / FS)[1:]
    for given in (freq[freq <= 200.0], freq[(freq >= 1.0) & (freq <= 60.0)]):
        transfer = (given, *small_amplitude_transfer(systems, np.array([s.masses for s in systems]), given))
        again = frequency_domain_rms(systems, profile, np.repeat(signals, len(systems), axis=0), fs=FS,
                                     freq_step=FREQ_STEP, transfer=transfer)
        np.testing.assert_array_equal(again, rms_values)
