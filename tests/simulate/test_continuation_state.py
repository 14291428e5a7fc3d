"""Runs continued from a saved state (``TimeResponse.final_state``, ``simulate(initial_state=...)``).

A run cut in two and continued from its state must equal the uninterrupted run: the second
part restarts the base at rest, which only changes the absolute frame (the equations see
deflections and their rates), so the records agree up to the round-off of the different
absolute coordinates. Tolerance: 1e-9 of each record's largest magnitude, far above the
round-off of 2000 steps (about 1e-13 relative per step, Newton tolerance 1e-13) and far below
any physical difference (dropping one Jenkin element's force changes the records by ~1e-2).
"""

from __future__ import annotations

import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.models import BoucWenModel, ModulatedIwanModel, library
from idkit.models.systems import HybridSystem, SDOFSystem
from idkit.simulate import TimeState, simulate

SYSTEMS = {
    "wire rope": lambda: library.get("system_a1_asymmetric"),
    "elastomer": lambda: library.get("system_b1_medium"),
    "hybrid": lambda: library.get("hybrid_asymmetric"),
    "modulated hybrid": lambda: HybridSystem(1.0, library.get("table_7_3_elastomer"), 0.2, ModulatedIwanModel(
        g1=1.84e4, g2=2.45e5, g3=-4.57e5, k=[1.88e5, 9.09e3], fc=[15.5, 10.3], slip_modulation=0.35,
        slip_length=6e-3)),
    "Bouc-Wen": lambda: SDOFSystem(1.0, BoucWenModel(k1=3e3, k2=2e5, k3=-1e6, alpha=2.5e4, beta=1.2e4, gamma=3e3,
                                                     n=1.3, b=np.e, c=20.0)),
}


@pytest.mark.parametrize("name", list(SYSTEMS))
@pytest.mark.parametrize("seed", [1, 2])
def test_a_continued_run_equals_the_uninterrupted_one(name, seed):
    system = SYSTEMS[name]()
    rng = np.random.default_rng(seed)
    h, n_first, n_second = 2e-4, 1200, 800
    accel = rng.normal(0.0, 15.0, size=(3, n_first + n_second + 1))
    whole = simulate(system, np.arange(n_first + n_second + 1) * h, base_acceleration=accel, workers=1)
    first = simulate(system, np.arange(n_first + 1) * h, base_acceleration=accel[:, :n_first + 1], workers=1)
    # the second part's base starts at rest: its acceleration samples continue the first part's
    second = simulate(system, np.arange(n_second + 1) * h, base_acceleration=accel[:, n_first:],
                      initial_state=first.final_state, workers=1)
    assert np.all(whole.ok) and np.all(second.ok)
    for field in ("velocity", "acceleration", "deflection", "isolator_force"):
        expected = getattr(whole, field)[:, :, n_first:]
        got = getattr(second, field)
        np.testing.assert_allclose(got, expected, rtol=0, atol=1e-9 * np.abs(expected).max(), err_msg=field)
    # relative displacement: the whole run's base drifted, the continued one's restarted
    state = second.final_state
    np.testing.assert_allclose(state.displacement, whole.final_state.displacement, rtol=0,
                               atol=1e-9 * np.abs(whole.displacement).max())
    np.testing.assert_allclose(state.jenkin_force, whole.final_state.jenkin_force, rtol=0,
                               atol=1e-9 * max(1.0, np.abs(whole.final_state.jenkin_force).max()))


def test_the_state_matters():
    """Continuing with the Jenkin forces zeroed gives a different run (the check above has power)."""
    system = SYSTEMS["wire rope"]()
    rng = np.random.default_rng(3)
    h = 2e-4
    accel = rng.normal(0.0, 15.0, size=(1, 2001))
    first = simulate(system, np.arange(1001) * h, base_acceleration=accel[:, :1001], workers=1)
    state = first.final_state
    assert np.abs(state.jenkin_force).max() > 0.1
    wiped = TimeState(state.displacement, state.velocity, np.zeros_like(state.jenkin_force),
                      state.maxwell_elongation, state.boucwen_z)
    kept = simulate(system, np.arange(1001) * h, base_acceleration=accel[:, 1000:], initial_state=state, workers=1)
    lost = simulate(system, np.arange(1001) * h, base_acceleration=accel[:, 1000:], initial_state=wiped, workers=1)
    difference = np.abs(kept.isolator_force - lost.isolator_force).max() / np.abs(kept.isolator_force).max()
    assert difference > 1e-3


def test_take_selects_runs():
    system = SYSTEMS["hybrid"]()
    accel = np.random.default_rng(4).normal(0.0, 10.0, size=(4, 301))
    state = simulate(system, np.arange(301) * 2e-4, base_acceleration=accel, workers=1).final_state
    part = state.take(np.array([3, 1]))
    assert len(part) == 2
    np.testing.assert_array_equal(part.jenkin_force, state.jenkin_force[[3, 1]])
    np.testing.assert_array_equal(state.take(np.array([False, True, False, True])).velocity,
                                  state.velocity[[1, 3]])


def test_bad_states_are_refused_with_the_field_named():
    system = SYSTEMS["wire rope"]()
    time = np.arange(101) * 2e-4
    state = simulate(system, time, base_acceleration=np.zeros((2, 101)), workers=1).final_state
    with pytest.raises(SimulationError, match="initial_state alone"):
        simulate(system, time, initial_state=state, initial_deflection=[0.0])
    other = simulate(SYSTEMS["hybrid"](), time, workers=1).final_state
    with pytest.raises(SimulationError, match=r"initial_state\.displacement: found shape \(1, 2\)"):
        simulate(system, time, initial_state=other)
    broken = TimeState(state.displacement, state.velocity, np.full_like(state.jenkin_force, np.nan),
                       state.maxwell_elongation, state.boucwen_z)
    with pytest.raises(SimulationError, match=r"initial_state\.jenkin_force: found a non-finite value in run 0"):
        simulate(system, time, initial_state=broken)
    with pytest.raises(SimulationError, match="expected a TimeState"):
        simulate(system, time, initial_state={"displacement": 0.0})
    with pytest.raises(SimulationError, match="batch sizes differ"):
        simulate(system, time, base_acceleration=np.zeros((3, 101)), initial_state=state)
