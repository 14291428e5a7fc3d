"""The one resonance search (idkit.signal.harmonics.search_resonance, its grid part
resonance_grid_maxima) against the closed-form peak of a viscously damped oscillator, and the
searches built on it (linear_resonance refines, small_amplitude_resonance keeps the grid maximum,
the design evaluation searches many systems at once) against each other."""

import numpy as np

from idkit.design.evaluation import _resonances
from idkit.models import HybridSystem, SDOFSystem, VoigtModel, library
from idkit.responses import linear_resonance
from idkit.signal.harmonics import resonance_grid_maxima, search_resonance
from idkit.simulate import small_amplitude_resonance
from idkit.simulate.harmonic import RESONANCE_BAND_HZ, RESONANCE_GRID_POINTS

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
                                         f_max=RESONANCE_BAND_HZ[1], n_grid=RESONANCE_GRID_POINTS,
                                         refine=False).freq
    refined = linear_resonance(system).freq
    step = (RESONANCE_BAND_HZ[1] / RESONANCE_BAND_HZ[0]) ** (1 / (RESONANCE_GRID_POINTS - 1))
    assert abs(refined / F_PEAK - 1) < 1e-7 and 1 / step < grid_peak / refined < step


def test_many_magnitudes_at_once_give_each_ones_grid_maximum():
    """resonance_grid_maxima with one row per oscillator: each row's maximum is the one-magnitude
    search's, bit for bit (the same grid and the same values: nothing to round differently)."""
    ratios = np.array([0.5, 1.0, 2.0])[:, None]  # natural frequencies F_N / 2, F_N, 2 F_N
    grid, values, index = resonance_grid_maxima(lambda f: _base_transmissibility(f / ratios), f_min=0.1,
                                                f_max=100.0, n_grid=200)
    assert values.shape == (3, 200) and index.shape == (3,)
    for row, ratio in enumerate(ratios[:, 0]):
        one = search_resonance(lambda f: _base_transmissibility(f / ratio), f_min=0.1, f_max=100.0, n_grid=200,
                               refine=False)
        assert one.index == index[row] and one.freq == grid[index[row]]


def test_the_design_search_of_many_systems_is_each_systems_small_amplitude_resonance():
    """The design evaluation searches every draw's resonance in one array; it must be the simulator's
    small_amplitude_resonance of each system exactly (the same grid, the same transmissibility formula
    over arrays: bit for bit), for one-mass and two-mass systems."""
    rope, body = library.get("table_7_1_wire_rope"), library.get("table_7_3_elastomer")
    for systems in ([SDOFSystem(mass, rope) for mass in (3.0, 30.0)], [SDOFSystem(mass, body) for mass in (3.0, 30.0)],
                    [HybridSystem(mass, body, 0.01 * mass, rope) for mass in (3.0, 30.0)]):
        np.testing.assert_array_equal(_resonances(systems), [small_amplitude_resonance(s) for s in systems])
