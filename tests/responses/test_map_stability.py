"""Harmonic maps show the orbit a long run reaches: every settled point classified by its Floquet
multipliers, unstable orbits carried to the stable one; maps chained along the amplitude axis
independently of the workers."""

import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.models import library
from idkit.responses.harmonic_map import HarmonicMap, harmonic_map
from idkit.responses.periodic import PeriodMap, monodromy, periodic_response
from idkit.simulate import harmonic_response

#: The map's steady-state tolerance (default): a settled point's coefficients are within about one
#: tolerance of the first harmonic from their limit (window change and its geometric
#: extrapolation), so a ratio of two of them is good to about two tolerances.
MAP_TOLERANCE = 1e-3


def test_table_a1_map_shows_the_subharmonic_that_long_runs_reach():
    """Table A.1 asymmetric rope, 8 kg: the period-1 orbit loses stability by period doubling
    between 10.649 and 10.701 Hz at 1.2 mm (tests/responses/test_floquet.py), a tongue that widens
    with the amplitude (at 1 mm only 10.68 Hz lies inside, multiplier -1.0016). On a 13 x 5 map
    (10.40-11.00 Hz x 0.5-2 mm, log) the points at 10.65 and 10.70 Hz and 1.41 and 2 mm settle on
    the unstable period-1 orbit first (the perturbation grows by 0.3-1 % a period); the map now
    shows the 1/2 subharmonic there, as independent long runs from rest (to 1e-7, up to 60000
    periods) do: |H1/2| / |H1| within three map tolerances (two for the map's settling, one
    margin; measured 2e-5). Below, at 1 mm, the long runs keep the period-1 orbit, and so does
    the map (|H1/2| / |H1| below ten tolerances, the threshold that names a period-2 orbit)."""
    system = library.get("system_a1_asymmetric")
    freq, amplitude = np.linspace(10.40, 11.00, 13), np.geomspace(5e-4, 2e-3, 5)
    result = harmonic_map(system, freq, amplitude, workers=1)
    assert result.valid.all(), result.reasons[~result.valid]
    assert set(np.unique(result.stability)) <= {"stable", "period-2", "jumped"}
    rows = [int(np.argmin(np.abs(freq - value))) for value in (10.65, 10.70)]
    inside = [(row, column) for row in rows for column in (3, 4)]   # 1.41 and 2 mm
    below = [(row, 2) for row in rows]                              # 1 mm
    doubled = {(int(r), int(c)) for r, c in np.argwhere(result.stability == "period-2")}
    assert doubled == set(inside), doubled
    points = inside + below
    runs = harmonic_response(system, [freq[r] for r, _ in points], [amplitude[c] for _, c in points],
                             tolerance=1e-7, max_periods=60000, start="rest", workers=1)
    assert runs.converged.all()
    long_ratio = np.abs(runs.hosidf(0.5)) / np.abs(runs.hosidf(1))
    map_ratio = np.array([result.magnitude(0.5)[point] / result.magnitude(1)[point] for point in points])
    assert np.all(long_ratio[:4] > 0.1) and np.all(long_ratio[4:] < 1e-6), long_ratio
    assert np.all(np.abs(map_ratio[:4] - long_ratio[:4]) < 3 * MAP_TOLERANCE), (map_ratio, long_ratio)
    assert np.all(map_ratio[4:] < 10 * MAP_TOLERANCE), map_ratio
    first = np.array([result.magnitude(1)[point] for point in points])
    assert np.all(np.abs(first / np.abs(runs.hosidf(1)) - 1) < 3 * MAP_TOLERANCE)
    # a period-2 point reports its orbit's multiplier over two periods, inside the unit circle
    assert np.all(np.abs(result.multiplier[result.stability == "period-2"]) < 1)
    table = result.to_dataframe()
    assert {"stability", "|mu| [-]"} <= set(table.columns)


def test_map_does_not_depend_on_the_workers():
    """Chains (one frequency's amplitudes) are never split between workers: one worker and two give
    the same map to the last bit."""
    system = library.get("hybrid_asymmetric")
    freq, amplitude = np.geomspace(2.0, 60.0, 7), np.geomspace(1e-4, 3e-3, 5)
    one = harmonic_map(system, freq, amplitude, workers=1)
    two = harmonic_map(system, freq, amplitude, workers=2)
    for name in ("hosidf_values", "half_range", "bias", "periods", "change", "converged", "multiplier"):
        assert np.array_equal(getattr(one, name), getattr(two, name), equal_nan=True), name
    assert np.array_equal(one.stability, two.stability) and np.array_equal(one.reasons, two.reasons)


def test_a_chained_point_starts_from_its_neighbours_end_state_scaled_to_its_amplitude():
    """The kernel's chain equals a separate run started from the neighbour's end state, positions,
    velocities and internal states times the amplitude ratio (Jenkin forces within their slip
    limits): bit for bit."""
    system = library.get("system_a1_asymmetric")
    chained = harmonic_response(system, [8.0, 8.0], [1e-3, 2e-3], chain_length=2, start="linear", workers=1)
    first = harmonic_response(system, 8.0, 1e-3, start="linear", workers=1)
    q, v, jforce, mstate, bwz = (np.array(values) for values in first.end_states)
    limit = PeriodMap(system).arrays.jfc
    start = (2 * q, 2 * v, np.clip(2 * jforce, -limit, limit), 2 * mstate, 2 * bwz)
    alone = harmonic_response(system, 8.0, 2e-3, start=start, workers=1)
    assert np.array_equal(chained.coefficients[1], alone.coefficients[0])
    assert chained.periods[1] == alone.periods[0]
    with pytest.raises(SimulationError, match="chain_length: found 2 for 3 points"):
        harmonic_response(system, [8.0, 9.0, 10.0], 1e-3, chain_length=2)


def test_monodromy_of_many_orbits_is_the_shooting_jacobian():
    """monodromy (one batch) at orbits closed by shooting gives their Floquet multipliers: the
    same propagated tangent, so to round-off of the eigenvalues (1e-9)."""
    system = library.get("system_a1_asymmetric")
    orbits = periodic_response(system, [5.0, 10.68], [3e-3, 1.2e-3], seek_stable=False)
    closing, multipliers, _, flags = monodromy(PeriodMap(system, 1), orbits.freq, orbits.amplitude, orbits.states,
                                               orbits.steps_per_period)
    assert np.all(flags == 0) and np.all(closing < 1e-8)
    assert np.allclose(multipliers, orbits.multipliers, atol=1e-9)


def test_a_map_refuses_a_settled_point_on_an_unstable_orbit():
    """The invariant: a converged, valid point of a HarmonicMap carries a classified stable orbit."""
    shape = (1, 1)
    fields = dict(freq=np.array([10.0]), amplitude=np.array([1e-3]), orders=(0.5, 1.0),
                  hosidf_values=np.ones((2,) + shape, dtype=complex), half_range=np.ones(shape),
                  bias=np.zeros(shape), peak_acceleration=np.ones(shape), periods=np.full(shape, 8.0),
                  change=np.zeros(shape), converged=np.ones(shape, dtype=bool), flags=np.zeros(shape, dtype=np.int64),
                  reasons=np.full(shape, "ok"), tolerance=1e-3, shooting=np.zeros(shape, dtype=bool))
    HarmonicMap(**fields, stability=np.full(shape, "stable"), multiplier=np.full(shape, -0.9 + 0j))
    with pytest.raises(SimulationError, match="unstable"):
        HarmonicMap(**fields, stability=np.full(shape, "unstable"), multiplier=np.full(shape, -1.01 + 0j))
    with pytest.raises(SimulationError, match="multiplier"):
        HarmonicMap(**fields, stability=np.full(shape, "stable"), multiplier=np.full(shape, -1.01 + 0j))


def test_a_slowly_growing_doubling_at_the_tongue_edge_is_carried_to_the_subharmonic():
    """Table A.1 rope, 10.66 Hz, 1 mm, the edge of the period-doubling tongue: the period-1 orbit's
    multiplier is about -1.0008, so a 1e-2 push would need 5800 periods to grow to the orbit's scale;
    it is pushed |mu|^-4000 of the scale instead and reaches the 1/2 subharmonic that a long run
    from rest reaches (|H1/2| / |H1| 2.8155), within three map tolerances as above."""
    system = library.get("system_a1_asymmetric")
    result = harmonic_map(system, [10.66], [1e-3], workers=1)
    run = harmonic_response(system, 10.66, 1e-3, tolerance=1e-7, max_periods=60000, start="rest", workers=1)
    assert run.converged[0] and result.stability[0, 0] == "period-2", result.reasons
    long_ratio = abs(run.hosidf(0.5)[0]) / abs(run.hosidf(1)[0])
    assert long_ratio > 1
    assert abs(result.magnitude(0.5)[0, 0] / result.magnitude(1)[0, 0] - long_ratio) < 3 * MAP_TOLERANCE


def test_the_cli_table_is_the_library_map_on_axes_in_any_order():
    """``simulate harmonic`` (harmonic_grid_table) and harmonic_map settle the same points the same
    way: the table of unsorted, repeated axes holds the map's values of each (freq, amplitude),
    bit for bit, frequency-major in the order given."""
    from idkit.studies.harmonic_grid import harmonic_grid_table

    system = library.get("system_b1_medium")
    freq, amplitude = [20.0, 5.0, 20.0], [1e-3, 1e-4]
    table = harmonic_grid_table(system, freq, amplitude, n_harmonics=2, workers=1)
    result = harmonic_map(system, [5.0, 20.0], [1e-4, 1e-3], n_harmonics=2, workers=1)
    assert list(table["freq [Hz]"]) == [20.0, 20.0, 5.0, 5.0, 20.0, 20.0]
    rows = {5.0: 0, 20.0: 1}
    columns = {1e-4: 0, 1e-3: 1}
    for _, line in table.iterrows():
        point = rows[line["freq [Hz]"]], columns[line["amplitude [m]"]]
        assert line["|H1| [-]"] == result.magnitude(1)[point]
        assert line["stability"] == result.stability[point] and line["status"] == result.reasons[point]
