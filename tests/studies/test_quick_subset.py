"""Quick-mode held-out subset: spread over the test levels, whatever the manifest order."""

from types import SimpleNamespace

import numpy as np
import pytest

from idkit.io.info import Excitation, MeasurementInfo
from idkit.studies.pipeline import QUICK_HELD_OUT, quick_subset


def _sweep(amplitude, freq, mass=0.99):
    info = MeasurementInfo(id=f"ss_{amplitude}_{freq:06.2f}", top_mass_kg=mass, split="validation",
                           excitation=Excitation(freq=freq, amplitude=amplitude, amplitude_quantity="velocity"))
    return SimpleNamespace(info=info)


def _drop(mass, height, repetition):
    return SimpleNamespace(info=MeasurementInfo(id=f"drop_{mass}_{height}_{repetition}", top_mass_kg=mass,
                                                drop_height_m=height, repetition=repetition, split="validation"))


FREQS = np.geomspace(3.0, 100.0, 20).round(2)
AMPLITUDES = (0.002, 0.008, 0.03, 0.12, 0.2)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_level_sorted_manifest_is_validated_at_every_level(seed):
    """Before: the first 8 records of a manifest sorted by amplitude were all at the lowest one."""
    records = [_sweep(a, f) for a in AMPLITUDES for f in FREQS]
    chosen, skipped = quick_subset(records, QUICK_HELD_OUT)
    assert len(chosen) == QUICK_HELD_OUT and len(skipped) == len(records) - QUICK_HELD_OUT
    assert {m.info.id for m in chosen}.isdisjoint(m.info.id for m in skipped)
    assert [m.info.id for m in skipped] == [m.info.id for m in records if m not in chosen]  # manifest order
    # every level, as evenly as 8 over 5 allows, and the levels that get two span their frequencies
    per_level = {a: sorted(m.info.excitation.freq for m in chosen if m.info.excitation.amplitude == a)
                 for a in AMPLITUDES}
    assert sorted(len(v) for v in per_level.values()) == [1, 1, 2, 2, 2]
    for freqs in per_level.values():
        if len(freqs) == 2:
            assert freqs[0] < np.median(FREQS) < freqs[1]
    # the same subset whatever the manifest order
    shuffled = list(np.random.default_rng(seed).permutation(np.array(records, dtype=object)))
    assert [m.info.id for m in quick_subset(shuffled, QUICK_HELD_OUT)[0]] == [m.info.id for m in chosen]


def test_more_levels_than_records_spreads_over_masses_and_heights():
    heights = np.round(np.arange(1, 15) * 0.01, 2)
    records = [_drop(mass, h, r) for mass in (4.25, 7.31) for h in heights for r in (1, 2, 3)]
    chosen, skipped = quick_subset(records, QUICK_HELD_OUT)
    assert len(chosen) == QUICK_HELD_OUT and len(skipped) == len(records) - QUICK_HELD_OUT
    for mass in (4.25, 7.31):
        picked = sorted(m.info.drop_height_m for m in chosen if m.info.top_mass_kg == mass)
        assert len(picked) == QUICK_HELD_OUT // 2
        assert picked[0] <= heights[2] and picked[-1] >= heights[-3]  # low and high drops both


def test_no_limit_or_few_records_keeps_all():
    records = [_sweep(0.03, f) for f in FREQS[:5]]
    assert quick_subset(records, None) == (records, [])
    assert quick_subset(records, QUICK_HELD_OUT) == (records, [])
