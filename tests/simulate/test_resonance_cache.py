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


def test_a_one_point_call_equals_that_point_of_a_batch():
    # one point takes its own path (no dealing, no copies): the same record as in a batch
    system = library.get("hybrid_asymmetric")
    freq, amplitude = np.array([3.0, 12.0, 40.0]), np.array([2e-4, 1e-3, 5e-5])
    batch = harmonic.harmonic_response(system, freq, amplitude, workers=1)
    for index in range(freq.size):
        one = harmonic.harmonic_response(system, freq[index], amplitude[index], workers=1)
        np.testing.assert_array_equal(one.coefficients[0], batch.coefficients[index])
        assert one.reasons[0] == batch.reasons[index] and one.periods[0] == batch.periods[index]


@pytest.mark.parametrize("freq, amplitude, word", [
    (np.nan, 1e-3, "freq"), (-2.0, 1e-3, "freq"), ([5.0, np.inf], 1e-3, "freq"),
    (5.0, 0.0, "amplitude"), (5.0, np.nan, "amplitude"), ([5.0, 6.0], [1e-3, -1e-3], "amplitude"),
])
def test_bad_points_are_named(freq, amplitude, word):
    from idkit.errors import SimulationError

    with pytest.raises(SimulationError, match=f"{word}: found"):
        harmonic.harmonic_response(library.get("system_a1_asymmetric"), freq, amplitude, workers=1)
