"""Runs continued from a saved state (``TimeResponse.final_state``, ``simulate(initial_state=...)``).

A ``final_state`` carries the integrator's own numbers (absolute positions, velocities and
accelerations, the base's displacement and velocity, the step and the force scale): a run
cut in two and continued from it, driven by the following base-acceleration samples, is the
same computation as the uninterrupted run, so its records are equal bit for bit. That holds
when the run's force scale (the Newton tolerances' force magnitude, from its largest base
acceleration) is the same for both: the largest sample is put in the first part here (a
periodic drive, as random_response continues, always has it in its first record).

A state without those numbers (built by hand, or changed after its run) restarts the base at
rest and the accelerations from equilibrium, which changes the absolute frame and the
solver's last digits: velocities and deflections agree to 1e-9 of their largest magnitude
(the Newton tolerance is 1e-13 of the force scale), accelerations to 1e-6: the restarted
acceleration differs from the trapezoidal rule's own by that tolerance, the rule carries
the difference undamped (its alternating acceleration mode) and the accelerations amplify a
position difference by 4 / h^2 (measured 7e-8 with the Bouc-Wen part, 1e-10 with the hybrid).
Both are far below any physical difference (dropping one Jenkin element's force changes the
records by ~1e-2).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.models import BoucWenModel, ModulatedIwanModel, library
from idkit.models.systems import HybridSystem, SDOFSystem
from idkit.simulate import IntegratorState, TimeState, simulate

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
FIELDS = ("velocity", "acceleration", "displacement", "deflection", "isolator_force")
STEP = 2.0**-12  # s: a binary step, so every grid below has exactly the same spacing


def _drive(seed, n_samples):
    """Three runs of clipped Gaussian base acceleration (m/s^2), the largest sample early."""
    rng = np.random.default_rng(seed)
    accel = np.clip(rng.normal(0.0, 15.0, size=(3, n_samples)), -45.0, 45.0)
    accel[:, 7] = 60.0
    return accel


@pytest.mark.parametrize("name", list(SYSTEMS))
@pytest.mark.parametrize("seed", [1, 2])
def test_a_continued_run_is_the_uninterrupted_one_bit_for_bit(name, seed):
    system = SYSTEMS[name]()
    n_first, n_second = 1200, 800
    accel = _drive(seed, n_first + n_second + 1)
    whole = simulate(system, np.arange(n_first + n_second + 1) * STEP, base_acceleration=accel, workers=1)
    first = simulate(system, np.arange(n_first + 1) * STEP, base_acceleration=accel[:, :n_first + 1], workers=1)
    # the second part's acceleration samples continue the first part's (the cut sample is shared)
    second = simulate(system, np.arange(n_second + 1) * STEP, base_acceleration=accel[:, n_first:],
                      initial_state=first.final_state, workers=1)
    assert np.all(whole.ok) and np.all(second.ok)
    for field in FIELDS:
        np.testing.assert_array_equal(getattr(second, field), getattr(whole, field)[:, :, n_first:], err_msg=field)
    for field in ("displacement", "velocity", "jenkin_force", "maxwell_elongation", "boucwen_z"):
        np.testing.assert_array_equal(getattr(second.final_state, field), getattr(whole.final_state, field))


@pytest.mark.parametrize("name", ["hybrid", "Bouc-Wen"])
def test_a_state_without_the_integrators_numbers_continues_to_the_solver_tolerance(name):
    system = SYSTEMS[name]()
    n_first, n_second = 1200, 800
    accel = _drive(3, n_first + n_second + 1)
    whole = simulate(system, np.arange(n_first + n_second + 1) * STEP, base_acceleration=accel, workers=1)
    state = simulate(system, np.arange(n_first + 1) * STEP, base_acceleration=accel[:, :n_first + 1],
                     workers=1).final_state
    by_hand = TimeState(state.displacement, state.velocity, state.jenkin_force, state.maxwell_elongation,
                        state.boucwen_z)
    second = simulate(system, np.arange(n_second + 1) * STEP, base_acceleration=accel[:, n_first:],
                      initial_state=by_hand, workers=1)
    for field in FIELDS:
        expected = getattr(whole, field)[:, :, n_first:]
        tolerance = 1e-6 if field == "acceleration" else 1e-9  # module docstring
        np.testing.assert_allclose(getattr(second, field), expected, rtol=0,
                                   atol=tolerance * np.abs(expected).max(), err_msg=field)


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
    # a state changed after its run keeps its integrator part, which then no longer applies: the
    # run continues from the changed fields alone, as from the same state built by hand
    changed = dataclasses.replace(state, jenkin_force=np.zeros_like(state.jenkin_force))
    assert changed.integrator is not None
    again = simulate(system, np.arange(1001) * h, base_acceleration=accel[:, 1000:], initial_state=changed, workers=1)
    np.testing.assert_array_equal(again.isolator_force, lost.isolator_force)


def test_take_selects_runs():
    system = SYSTEMS["hybrid"]()
    accel = np.random.default_rng(4).normal(0.0, 10.0, size=(4, 301))
    state = simulate(system, np.arange(301) * 2e-4, base_acceleration=accel, workers=1).final_state
    part = state.take(np.array([3, 1]))
    assert len(part) == 2
    np.testing.assert_array_equal(part.jenkin_force, state.jenkin_force[[3, 1]])
    np.testing.assert_array_equal(part.integrator.acceleration, state.integrator.acceleration[[3, 1]])
    np.testing.assert_array_equal(state.take(np.array([False, True, False, True])).velocity,
                                  state.velocity[[1, 3]])
    # runs 3 and 1 put back from the part give the state again, integrator numbers included
    merged = state.replace_runs(np.array([0, 2]), state.take(np.array([0, 2])))
    for name in ("displacement", "velocity", "jenkin_force", "maxwell_elongation", "boucwen_z"):
        np.testing.assert_array_equal(getattr(merged, name), getattr(state, name))
    np.testing.assert_array_equal(merged.integrator.position, state.integrator.position)


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
    short = dataclasses.replace(state.integrator, acceleration=state.integrator.acceleration[:1])
    with pytest.raises(SimulationError, match=r"initial_state\.integrator\.acceleration: found shape \(1, 1\)"):
        simulate(system, time, initial_state=dataclasses.replace(state, integrator=short))
    with pytest.raises(SimulationError, match="expected an IntegratorState"):
        simulate(system, time, initial_state=dataclasses.replace(state, integrator={"position": 0.0}))
    assert isinstance(state.integrator, IntegratorState)
