"""Quick-mode held-out subset: from the lowest to the highest test level, whatever the manifest
order, and sweeps with enough frequencies around their measured peak to be judged."""

from types import SimpleNamespace

import numpy as np
import pytest

from idkit.io.info import Excitation, MeasurementInfo
from idkit.studies.pipeline import QUICK_HELD_OUT, SWEEP_POINTS_PER_LEVEL, quick_subset

FREQS = np.geomspace(3.0, 100.0, 20).round(2)
AMPLITUDES = (0.002, 0.008, 0.03, 0.12, 0.2)
#: measured resonance of each level: softening with the amplitude, as a wire rope
PEAKS = dict(zip(AMPLITUDES, (25.0, 20.0, 15.0, 11.0, 8.0)))


def _sweep(amplitude, freq, mass=0.99):
    """A stepped-sine record whose top/base velocity ratio peaks at the level's resonance."""
    info = MeasurementInfo(id=f"ss_{amplitude}_{freq:06.2f}", top_mass_kg=mass, split="validation",
                           excitation=Excitation(freq=freq, amplitude=amplitude, amplitude_quantity="velocity"))
    time = np.arange(400) / 2000.0
    ratio = 1.0 / abs(1.0 - (freq / PEAKS[amplitude]) ** 2 + 0.1j * freq / PEAKS[amplitude])
    v_base = amplitude * np.sin(2 * np.pi * freq * time)
    return SimpleNamespace(info=info, kind="stepped_sine", v_base=v_base, v_top=ratio * v_base)


def _drop(mass, height, repetition):
    return SimpleNamespace(kind="drop", info=MeasurementInfo(id=f"drop_{mass}_{height}_{repetition}", top_mass_kg=mass,
                                                             drop_height_m=height, repetition=repetition,
                                                             split="validation"))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_level_sorted_sweep_manifest_is_validated_at_its_extreme_levels_around_their_peaks(seed):
    """Before: the first 8 records of a manifest sorted by amplitude were the lowest level's
    3-11 Hz points, below its resonance."""
    records = [_sweep(a, f) for a in AMPLITUDES for f in FREQS]
    chosen, skipped = quick_subset(records, QUICK_HELD_OUT)
    assert len(chosen) == QUICK_HELD_OUT and len(skipped) == len(records) - QUICK_HELD_OUT
    assert [m.info.id for m in skipped] == [m.info.id for m in records if m not in chosen]  # manifest order
    per_level = {}
    for m in chosen:
        per_level.setdefault(m.info.excitation.amplitude, []).append(m.info.excitation.freq)
    # as many levels as can each be judged by a resonance (3 points), the lowest and the highest
    assert sorted(per_level) == [AMPLITUDES[0], AMPLITUDES[-1]]
    for amplitude, freqs in per_level.items():
        assert len(freqs) >= SWEEP_POINTS_PER_LEVEL
        index = [int(np.flatnonzero(FREQS == f)[0]) for f in sorted(freqs)]
        assert index == list(range(index[0], index[0] + len(index)))  # contiguous
        assert min(freqs) < PEAKS[amplitude] < max(freqs)  # the measured resonance is bracketed
    shuffled = list(np.random.default_rng(seed).permutation(np.array(records, dtype=object)))
    assert [m.info.id for m in quick_subset(shuffled, QUICK_HELD_OUT)[0]] == [m.info.id for m in chosen]


def test_more_drop_levels_than_records_spreads_from_the_lowest_to_the_highest():
    heights = np.round(np.arange(1, 15) * 0.01, 2)
    records = [_drop(mass, h, r) for mass in (4.25, 7.31) for h in heights for r in (1, 2, 3)]
    chosen, skipped = quick_subset(records, QUICK_HELD_OUT)
    assert len(chosen) == QUICK_HELD_OUT and len(skipped) == len(records) - QUICK_HELD_OUT
    levels = sorted((m.info.top_mass_kg, m.info.drop_height_m) for m in chosen)
    assert levels[0] == (4.25, heights[0]) and levels[-1] == (7.31, heights[-1])  # both extremes
    for mass in (4.25, 7.31):
        assert sum(1 for m in chosen if m.info.top_mass_kg == mass) == QUICK_HELD_OUT // 2


def test_no_limit_or_few_records_keeps_all():
    records = [_sweep(0.03, f) for f in FREQS[:5]]
    assert quick_subset(records, None) == (records, [])
    assert quick_subset(records, QUICK_HELD_OUT) == (records, [])
