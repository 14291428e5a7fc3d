"""The small-amplitude resonance is searched once per system (kernel arrays) and reused."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from idkit.models import library
from idkit.simulate import harmonic, small_amplitude_resonance


def _searched(system) -> float:
    freq = np.logspace(-1, np.log10(5e3), 2000)
    return float(freq[np.argmax(np.abs(system.transmissibility(freq)))])


@pytest.mark.parametrize("name", ["hybrid_asymmetric", "system_a1_asymmetric", "system_b1_medium"])
def test_the_kept_resonance_is_the_searched_one(name, monkeypatch):
    monkeypatch.setattr(harmonic, "_RESONANCES", {})
    system = library.get(name)
    first = small_amplitude_resonance(system)
    assert first == _searched(system)
    assert len(harmonic._RESONANCES) == 1
    assert small_amplitude_resonance(system) == first  # read back
    # another mass is another system: its own search (the resonance moves as 1/sqrt(mass))
    heavier = dataclasses.replace(system, mass=4.0 * system.mass)
    assert small_amplitude_resonance(heavier) == _searched(heavier) < first
    assert len(harmonic._RESONANCES) == 2
