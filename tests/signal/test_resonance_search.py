"""The one resonance search (idkit.signal.harmonics.search_resonance) against the closed-form peak of a
viscously damped oscillator, and the two searches built on it (linear_resonance refines,
small_amplitude_resonance keeps the grid maximum) against each other."""

import numpy as np

from idkit.models import SDOFSystem, VoigtModel
from idkit.responses import linear_resonance
from idkit.signal.harmonics import search_resonance
from idkit.simulate import small_amplitude_resonance
from idkit.simulate.harmonic import RESONANCE_BAND_HZ

F_N, ZETA = 5.0, 0.05


def _base_transmissibility(freq):
    r = np.asarray(freq) / F_N
    return np.abs((1 + 2j * ZETA * r) / (1 - r**2 + 2j * ZETA * r))


#: Peak of |(1 + 2 i zeta r) / (1 - r^2 + 2 i zeta r)|: r^2 = (sqrt(1 + 8 zeta^2) - 1) / (4 zeta^2).
F_PEAK = F_N * np.sqrt(np.sqrt(1 + 8 * ZETA**2) - 1) / (2 * ZETA)


def test_refined_search_finds_the_closed_form_peak_and_the_grid_maximum_lies_within_a_step():
    found = search_resonance(_base_transmissibility, f_min=0.1, f_max=100.0, n_grid=200)
    # a maximum is located to about sqrt(machine epsilon) of its width (|H| is flat there to second
    # order): 1e-7 relative leaves that margin tenfold
    assert found.inside and abs(found.freq / F_PEAK - 1) < 1e-7
    assert found.peak == _base_transmissibility(found.freq)
    coarse = search_resonance(_base_transmissibility, f_min=0.1, f_max=100.0, n_grid=200, refine=False)
    step = (100.0 / 0.1) ** (1 / 199)  # ratio of neighbouring grid frequencies
    assert coarse.freq in coarse.grid and 1 / step < coarse.freq / F_PEAK < step


def test_a_maximum_at_an_end_of_the_grid_is_returned_unrefined_and_not_inside():
    found = search_resonance(_base_transmissibility, f_min=0.1, f_max=2.0, n_grid=50)
    assert not found.inside and found.freq == 2.0 and found.index == 49


def test_the_simulator_resonance_is_the_unrefined_search_within_a_grid_step_of_linear_resonance():
    system = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * F_N) ** 2, damping=2 * ZETA * 2 * np.pi * F_N))
    grid_peak = small_amplitude_resonance(system)
    assert grid_peak == search_resonance(lambda f: np.abs(system.transmissibility(f)), f_min=RESONANCE_BAND_HZ[0],
                                         f_max=RESONANCE_BAND_HZ[1], n_grid=2000, refine=False).freq
    refined = linear_resonance(system).freq
    step = (RESONANCE_BAND_HZ[1] / RESONANCE_BAND_HZ[0]) ** (1 / 1999)
    assert abs(refined / F_PEAK - 1) < 1e-7 and 1 / step < grid_peak / refined < step
