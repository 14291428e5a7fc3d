"""Shooting on the exact kernel: Floquet multipliers, agreement with time integration, the 1/2 subharmonic."""

import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.models import SDOFSystem, VoigtModel, library
from idkit.responses.harmonic_map import harmonic_map
from idkit.responses.periodic import STABILITY_MARGIN, periodic_response
from idkit.simulate import harmonic_response

# Multipliers from central differences with a step of 1e-6 of each state's scale: truncation
# O(1e-12), round-off about the step's Newton tolerance over the perturbation, 1e-13 / 1e-6.
MULTIPLIER_TOLERANCE = 1e-6
# Sensitivities propagated through the step: the matrix power of the amplification matrix,
# accumulated over up to 1800 steps in a different order; round-off ~ steps x 1e-16.
EXACT_MULTIPLIER_TOLERANCE = 1e-11
# Time integration run to a window change of 1e-8 (its geometric tail included) against an
# orbit closed to 1e-9 of its scale, same steps: both are the same discrete steady state.
TIME_AGREEMENT = 1e-5


def _voigt_system():
    mass, omega0, zeta = 5.0, 2 * np.pi * 5.0, 0.05
    return SDOFSystem(mass, VoigtModel(k=mass * omega0**2, damping=2 * zeta * mass * omega0))


def _newmark_monodromy(mass, stiffness, damping, step, n_steps):
    """Average-acceleration Newmark amplification matrix of m y'' + c y' + k y = 0, to the power n."""
    left = np.array([[1.0, -step / 2], [step * stiffness / (2 * mass), 1 + step * damping / (2 * mass)]])
    right = np.array([[1.0, step / 2], [-step * stiffness / (2 * mass), 1 - step * damping / (2 * mass)]])
    return np.linalg.matrix_power(np.linalg.solve(left, right), n_steps)


@pytest.mark.parametrize("jacobian, tolerance", [("exact", EXACT_MULTIPLIER_TOLERANCE),
                                                 ("finite differences", MULTIPLIER_TOLERANCE)])
def test_linear_multipliers_are_the_newmark_amplification_eigenvalues(jacobian, tolerance):
    system = _voigt_system()
    freq = np.array([2.0, 5.0, 40.0])
    orbit = periodic_response(system, freq, 1e-3, jacobian=jacobian)
    assert orbit.converged.all() and orbit.stable.all()
    assert np.max(orbit.residual) < 1e-9
    for index, f in enumerate(freq):
        steps = int(orbit.steps_per_period[index])
        exact = np.linalg.eigvals(_newmark_monodromy(system.mass, system.isolator.k, system.isolator.damping,
                                                     1.0 / (f * steps), steps))
        found = orbit.multipliers[index]
        assert np.max(np.abs(np.sort_complex(found) - np.sort_complex(exact))) < tolerance


def test_voigt_orbit_is_the_time_integration_limit():
    system = _voigt_system()
    freq = np.array([3.0, 5.0, 30.0])
    orbit = periodic_response(system, freq, 2e-3)
    settled = harmonic_response(system, freq, 2e-3, tolerance=1e-8, start="linear", max_periods=20000, workers=1)
    assert settled.converged.all()
    error = np.abs(orbit.hosidf(1) - settled.hosidf(1)) / np.abs(settled.hosidf(1))
    assert error.max() < TIME_AGREEMENT


@pytest.mark.parametrize("freq, amplitude", [(5.0, 3e-3), (20.0, 1e-3), (82.86, 1.17e-3)])
def test_wire_rope_orbit_is_the_time_integration_limit(freq, amplitude):
    """Slipping (5 Hz), stuck (20 Hz) and a point the 4000-period map leaves unsettled (83 Hz)."""
    system = library.get("system_a1_asymmetric")
    orbit = periodic_response(system, freq, amplitude)
    assert orbit.converged[0] and orbit.stable[0] and orbit.reasons == ("ok",)
    settled = harmonic_response(system, [freq], [amplitude], tolerance=1e-8, start="linear", max_periods=40000,
                                workers=1)
    assert settled.converged[0]
    for order in (1, 2):
        error = abs(orbit.hosidf(order)[0] - settled.hosidf(order)[0]) / abs(settled.hosidf(1)[0])
        assert error < TIME_AGREEMENT, (order, error)
    assert orbit.half_range[0, 0] == pytest.approx(settled.half_range[0], rel=TIME_AGREEMENT)


@pytest.mark.parametrize("amplitude", [1e-3, 1.2e-3, 1.5e-3])
def test_table_a1_half_subharmonic_near_11_hz(amplitude):
    """Thesis 3.4.2, fig. 3.17-3.19: a 1/2 subharmonic near 11 Hz at about 1e-3 m base amplitude.

    The period-1 orbit at 10.68 Hz (twice the stuck resonance, 5.34 Hz) loses stability by
    period doubling (a real multiplier below -1); the period-2 orbit found instead is stable,
    carries a large 1/2 subharmonic and is what a long time integration reaches.
    """
    system = library.get("system_a1_asymmetric")
    freq = 10.68
    single = periodic_response(system, freq, amplitude)
    assert single.converged[0] and not single.stable[0]
    assert single.instability[0] == "period doubling"
    assert np.min(single.multipliers[0].real) < -1 - STABILITY_MARGIN
    double = periodic_response(system, freq, amplitude, periods=2)
    assert double.converged[0] and double.stable[0]
    subharmonic = abs(double.hosidf(0.5)[0])
    assert subharmonic > 0.3  # comparable to the first harmonic (about 0.33), not a numerical trace
    settled = harmonic_response(system, [freq], [amplitude], tolerance=1e-7, start="linear", max_periods=40000,
                                workers=1)
    assert settled.converged[0]
    assert subharmonic == pytest.approx(abs(settled.hosidf(0.5)[0]), rel=1e-4)
    # away from twice the resonance the period-1 orbit is stable: no subharmonic
    outside = periodic_response(system, [10.4, 11.2], amplitude)
    assert outside.stable.all()


def test_map_points_that_did_not_settle_are_shot():
    """Lightly damped wire rope far above resonance: the 5 Hz free oscillation outlives a short cap."""
    system = library.get("system_a1_asymmetric")
    freq, amplitude = [82.86, 100.0], [1.17e-3, 2.4e-3]
    plain = harmonic_map(system, freq, amplitude, max_periods=200, shooting=False, workers=1)
    assert not plain.converged.any()
    assert all(reason.startswith("not settled") for reason in plain.reasons.ravel())
    shot = harmonic_map(system, freq, amplitude, max_periods=200, workers=1)
    assert shot.converged.all() and shot.shooting.all()
    assert set(shot.reasons.ravel()) == {"ok"}
    assert "4 settled by shooting" in shot.report()
    assert shot.to_dataframe()["shooting"].all()
    reference = harmonic_response(system, [freq[0]], [amplitude[0]], tolerance=1e-8, start="linear",
                                  max_periods=40000, workers=1)
    assert abs(shot.hosidf(1)[0, 0] - reference.hosidf(1)[0]) < TIME_AGREEMENT * abs(reference.hosidf(1)[0])


def test_default_map_shoots_after_48_periods_and_agrees_with_long_time_integration():
    # the default cap (NEWTON_AFTER_PERIODS = 48, then batched Newton, at most 3 tangent periods and
    # 2 windows of two; per-point shooting for what it leaves) against a plain grid of time
    # integrations run up to 4000 periods: every point settled, and wherever the long run settled
    # the two agree within the steady-state tolerance (1e-3 of |H1|, the long run's own)
    from idkit.responses.map_settling import NEWTON_AFTER_PERIODS, NEWTON_TANGENT_PERIODS, NEWTON_WINDOWS

    system = library.get("system_a1_asymmetric")
    freq, amplitude = np.geomspace(1.0, 100.0, 8), np.geomspace(1e-5, 1e-2, 4)
    fast = harmonic_map(system, freq, amplitude, workers=1)
    most = NEWTON_AFTER_PERIODS + NEWTON_TANGENT_PERIODS + 2 * NEWTON_WINDOWS
    assert fast.converged.all() and fast.periods.max() <= most
    assert fast.shooting.any()  # some lightly damped points need it
    long = harmonic_map(system, freq, amplitude, shooting=False, workers=1)
    assert long.periods.max() > most
    both = long.converged
    ratio = np.abs(fast.hosidf(1)[both] / long.hosidf(1)[both] - 1)
    assert ratio.max() < long.tolerance


def test_a_point_shooting_cannot_settle_keeps_a_reason(monkeypatch):
    from idkit.responses import map_settling

    original = map_settling.periodic_response  # the shooting of the points the time runs leave
    monkeypatch.setattr(map_settling, "periodic_response",
                        lambda *args, **kwargs: original(*args, **{**kwargs, "max_iterations": 0}))
    result = harmonic_map(library.get("system_a1_asymmetric"), [100.0], [2.4e-3], max_periods=200, workers=1)
    assert not result.converged[0, 0] and not result.shooting[0, 0]
    reason = str(result.reasons[0, 0])
    assert reason != "ok" and "not settled" in reason and "shooting: shooting did not converge" in reason


def test_table_report_and_bad_input():
    orbit = periodic_response(library.get("system_a1_asymmetric"), [20.0, 30.0], 1e-3)
    table = orbit.to_dataframe()
    assert {"freq [Hz]", "amplitude [m]", "x1 [m]", "|H1| [-]", "stable", "residual [-]"} <= set(table)
    assert orbit.state_names == ("x1 [m]", "v1 [m/s]", "F_J1.1 [N]", "F_J1.2 [N]")
    assert "2/2 converged" in orbit.report()
    with pytest.raises(SimulationError, match="periods"):
        periodic_response(_voigt_system(), 5.0, 1e-3, periods=3)
    with pytest.raises(SimulationError, match="freq"):
        periodic_response(_voigt_system(), -5.0, 1e-3)
    with pytest.raises(SimulationError, match="initial_states"):
        periodic_response(_voigt_system(), 5.0, 1e-3, initial_states=np.zeros((1, 5)))


def test_hybrid_with_maxwell_elements_is_shot():
    """Series hybrid: Maxwell elongations and Jenkin forces in the state; agrees with time integration."""
    system = library.get("hybrid_asymmetric")
    orbit = periodic_response(system, [4.0, 20.0], 1e-3)
    assert orbit.converged.all() and orbit.stable.all()
    assert len(orbit.state_names) == 4 + 2 + 10
    settled = harmonic_response(system, [4.0, 20.0], 1e-3, tolerance=1e-8, start="linear", max_periods=20000,
                                workers=1)
    error = np.abs(orbit.hosidf(1) - settled.hosidf(1)) / np.abs(settled.hosidf(1))
    assert error.max() < TIME_AGREEMENT


def test_bouc_wen_orbit_is_the_time_integration_limit():
    """Bouc-Wen z (advanced by Runge-Kutta sub-steps in the step) as a state of the period map."""
    from idkit.models import BoucWenModel

    isolator = BoucWenModel(k1=2e3, k2=1e4, k3=5e4, alpha=4e3, beta=3e3, gamma=1e3, n=1.0, b=1.5, c=5.0, c_visc=1.0)
    system = SDOFSystem(2.0, isolator)
    freq = np.array([3.0, 6.0, 20.0])
    orbit = periodic_response(system, freq, 2e-3)
    assert orbit.state_names == ("x1 [m]", "v1 [m/s]", "z1 [N]")
    assert orbit.converged.all() and orbit.stable.all()
    settled = harmonic_response(system, freq, 2e-3, tolerance=1e-8, start="linear", max_periods=40000, workers=1)
    assert settled.converged.all()
    assert np.max(np.abs(orbit.hosidf(1) / settled.hosidf(1) - 1)) < TIME_AGREEMENT


@pytest.mark.parametrize("name, freq, amplitude", [("system_a1_asymmetric", 5.0, 3e-3),
                                                   ("system_a1_asymmetric", 20.0, 1e-3),
                                                   ("hybrid_asymmetric", 4.0, 1e-3)])
def test_step_sensitivities_agree_with_finite_differences(name, freq, amplitude):
    """The Jacobian propagated through the step (slipping and sticking Jenkin elements, Maxwell
    elements) against central differences, whose own error is about 1e-7 (module docstring)."""
    from idkit.responses.periodic import PeriodMap

    system = library.get(name)
    orbit = periodic_response(system, freq, amplitude)
    exact, differences = PeriodMap(system), PeriodMap(system, jacobian="finite differences")
    assert exact.jacobian_method == "exact"
    scale = exact.scales(freq, amplitude, orbit.half_range[0].max())[0]
    steps = int(orbit.steps_per_period[0])
    phi, jacobian, derivative, flag = exact.jacobian(freq, amplitude, orbit.states[0], scale, steps, parameter="freq")
    phi_fd, jacobian_fd, derivative_fd, flag_fd = differences.jacobian(freq, amplitude, orbit.states[0], scale, steps,
                                                                       parameter="freq")
    assert flag == flag_fd == 0
    assert np.array_equal(phi, phi_fd)
    assert np.max(np.abs(jacobian - jacobian_fd)) < 10 * MULTIPLIER_TOLERANCE * max(1.0, np.abs(jacobian).max())
    assert np.allclose(derivative, derivative_fd, rtol=0, atol=1e-12)


@pytest.mark.parametrize("steps", [1, 2, 5])
def test_step_sensitivities_of_a_few_steps_agree_with_finite_differences(steps):
    """Runs of one, two and five steps: the step updates a Maxwell row in the next step's pass
    over it and the run's last update is completed after the loop, so the first and last steps
    are where a misplaced update would show (hybrid: ten Maxwell elements; a Jenkin force 0.16 N
    from its slip limit). Tolerance as in the test above (central differences' own error)."""
    from idkit.responses.periodic import PeriodMap

    system = library.get("hybrid_asymmetric")
    exact, differences = PeriodMap(system), PeriodMap(system, jacobian="finite differences")
    freq, amplitude = 4.0, 1e-3
    state = exact.linear_guess(freq, amplitude)[0]
    state[exact.state_names.index("F_J2.1 [N]")] = 8.3 - 0.16
    scale = exact.scales(freq, amplitude, amplitude)[0]
    phi, jacobian, _, flag = exact.jacobian(freq, amplitude, state, scale, steps)
    phi_fd, jacobian_fd, _, flag_fd = differences.jacobian(freq, amplitude, state, scale, steps)
    assert flag == flag_fd == 0
    assert np.array_equal(phi, phi_fd)
    assert np.max(np.abs(jacobian - jacobian_fd)) < 10 * MULTIPLIER_TOLERANCE * max(1.0, np.abs(jacobian).max())


@pytest.mark.parametrize("arguments, name", [
    (dict(steps_per_period=100.5), "steps_per_period"),  # was truncated to 100
    (dict(steps_per_period=np.nan), "steps_per_period"),  # ValueError
    (dict(freq=[5.0, 6.0, 7.0], amplitude=[1e-3, 2e-3]), "broadcast"),  # ValueError from numpy
    (dict(freq=1e-6), "steps per period"),  # 2.6e8 steps per period: hours and a 57 GB Fourier table
    (dict(freq=1e300), "overflows"),
])
def test_hostile_arguments_are_refused_naming_them(arguments, name):
    call = dict(freq=5.0, amplitude=1e-3) | arguments
    with pytest.raises(SimulationError, match=name):
        periodic_response(_voigt_system(), call.pop("freq"), call.pop("amplitude"), **call)


@pytest.mark.parametrize("name", ["hybrid_asymmetric", "system_a1_asymmetric"])
def test_period_map_runs_the_specialised_step_with_the_generic_steps_numbers(monkeypatch, name):
    # The period map is compiled per structure and calls the structure's specialised step, as the
    # map's kernel does; emptying SPECIALISED runs the generic step on the same inputs. Same
    # operations on the parts the structure has: end states and propagated tangents agree bit for
    # bit (stuck, slipping and isolated points, two periods).
    from idkit.responses.periodic import PeriodMap
    from idkit.simulate import _kernel

    freq, amplitude = np.array([2.0, 10.0, 60.0]), np.array([1e-4, 2e-3, 5e-3])

    def run():
        one = PeriodMap(library.get(name), 1)
        return one, one.run(freq, amplitude, one.linear_guess(freq, amplitude), 128, n_periods=2, with_tangent=True)

    specialised_map, specialised = run()
    with monkeypatch.context() as patch:
        patch.setattr(_kernel, "SPECIALISED", frozenset())
        generic_map, generic = run()
    assert specialised_map._kernel is not generic_map._kernel
    for got, expected in zip(specialised, generic):
        np.testing.assert_array_equal(got, expected)


@pytest.mark.parametrize("name", ["hybrid_asymmetric", "system_a1_asymmetric"])
def test_members_run_in_pairs_carry_their_own_tangents_bit_for_bit(name):
    # Members of one frequency and steps per period run two by two, their tangent columns side by
    # side in one pass (idkit.responses._sensitivity.tangent_step): every column must get its own
    # member's arithmetic, so each member's end state and tangent equal those of the member run
    # alone (the path the finite-difference tests above check), bit for bit. Three members at 4 Hz
    # (a pair and one alone, sticking and slipping amplitudes), then a pair at 9 Hz whose first
    # member starts from a non-finite state and flags in its first step: its partner runs on alone.
    from idkit.responses.periodic import PeriodMap

    system = library.get(name)
    one = PeriodMap(system, 1)
    freq = np.array([4.0, 4.0, 4.0, 9.0, 9.0])
    amplitude = np.array([1e-4, 3e-3, 1e-3, 1e-3, 2e-3])
    states = one.linear_guess(freq, amplitude)
    states[:, 0] *= 1.1  # off the linear orbit, so that the Jenkin elements slip and stick in turn
    states[3, 1] = np.nan
    steps = 64
    end, flags, tangents = one.run(freq, amplitude, states, steps, with_tangent=True)
    assert list(flags[:3]) == [0, 0, 0] and flags[3] != 0 and flags[4] == 0
    for member in (0, 1, 2, 4):
        alone_end, alone_flags, alone_tangent = one.run(freq[member], amplitude[member], states[member], steps,
                                                        with_tangent=True)
        assert alone_flags[0] == 0
        assert np.array_equal(end[member], alone_end[0])
        assert np.array_equal(tangents[member], alone_tangent[0])
        assert np.isfinite(tangents[member]).all()
