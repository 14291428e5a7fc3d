"""Map points the time run leaves are settled by batched Newton on the period map: the same orbits
and multipliers as per-point shooting, and the batched Newton step is the per-point one."""

import numpy as np

from idkit.models import library
from idkit.responses.harmonic_map import harmonic_map
from idkit.responses.map_settling import NEWTON_AFTER_PERIODS, NEWTON_REACH, _newton_batch, _NewtonPoints
from idkit.responses.periodic import STABILITY_MARGIN, PeriodMap, newton_step, newton_steps, periodic_response
from idkit.simulate import default_steps_per_period


def test_newton_settles_the_points_left_as_per_point_shooting_does():
    """Table A.1 rope far above resonance (lightly damped: 48 periods do not settle it): the batched
    Newton path and the per-point shooting after 200 periods land on the same orbits. Both close
    them well within the map's tolerance (1e-3 of |H1|, the contract; measured 9e-9), and both
    classify by the propagated Jacobian at states within that tolerance of the orbit, so their
    leading multipliers agree within the stability margin (1e-4; measured 4e-6)."""
    system = library.get("system_a1_asymmetric")
    freq, amplitude = [60.0, 100.0], [1.2e-3, 2.4e-3]
    newton = harmonic_map(system, freq, amplitude, workers=1)
    shot = harmonic_map(system, freq, amplitude, newton=False, workers=1)
    assert newton.valid.all() and shot.valid.all()
    assert newton.shooting.all() and (newton.stability == "stable").all()
    assert (newton.periods > NEWTON_AFTER_PERIODS).all() and (newton.periods < shot.periods).all()
    difference = np.abs(newton.hosidf_values - shot.hosidf_values) / newton.magnitude(1)[None]
    assert difference.max() < newton.tolerance
    assert np.abs(newton.multiplier - shot.multiplier).max() < STABILITY_MARGIN


def test_batched_newton_steps_are_the_per_point_steps_with_friction_memory():
    """newton_steps (LU, conserved Jenkin quantities replacing their void rows) against newton_step
    (the singular values of J - I, for every point) on the rope's Jacobians: stuck at 1e-5 m
    (memory multipliers at +1, kept at the guess's) and slipping at 10 mm (none): the same step to
    round-off (1e-9 of the largest)."""
    system = library.get("system_a1_asymmetric")
    one = PeriodMap(system)
    freq, amplitude = np.array([20.0, 20.0]), np.array([1e-5, 1e-2])
    steps = default_steps_per_period(system, freq)
    states = one.linear_guess(freq, amplitude) * 1.01  # off the orbit: a non-zero residual
    end, flags, tangents = one.run(freq, amplitude, states, steps, with_tangent=True)
    assert (flags == 0).all()
    scale = one.scales(freq, amplitude, np.maximum(amplitude, np.abs(states[:, :1]).max(axis=1)))
    jacobians = tangents[:, one._tangent_rows] * scale[:, None, :] / scale[:, :, None]
    residuals = (end - states) / scale
    offsets = np.array([[0.0] * one.size, [1e-3] * one.size])
    memory = (np.abs(np.linalg.eigvals(jacobians) - 1) <= STABILITY_MARGIN).sum(axis=1)
    assert memory[0] > 0 and memory[1] == 0
    batched, conserved = newton_steps(jacobians, residuals, offsets, memory, one.conserved_gradients(scale))
    assert conserved[0] == memory[0]
    for row in range(2):
        single, nulls = newton_step(jacobians[row], residuals[row], offsets[row])
        assert nulls == conserved[row]
        assert np.abs(batched[row] - single).max() <= 1e-9 * np.abs(single).max()


def test_a_newton_orbit_far_from_its_start_is_left_to_the_time_run():
    """Hybrid, 9.54 Hz, 3.86 mm: from the linear start Newton lands, 0.25 state scales away, on a
    slipping stable orbit, while the time run from the same start reaches another (an element stuck
    all period, |H1| 0.5 % apart): beyond NEWTON_REACH the point is not taken."""
    system = library.get("hybrid_asymmetric")
    one = PeriodMap(system)
    freq, amplitude = np.array([9.540954763499938]), np.array([3.8566204211634724e-3])
    steps = default_steps_per_period(system, freq)
    start = one.linear_guess(freq, amplitude)
    found = _NewtonPoints.start(start, 3)
    _newton_batch(system, one, freq, amplitude, steps, np.arange(1), found, 3, 1e-3, 1, None)
    assert not found.accepted[0]
    orbit = periodic_response(system, freq, amplitude, steps_per_period=steps, settle_periods=0, initial_states=start)
    assert orbit.converged[0] and orbit.stable[0]
    distance = np.abs(orbit.states[0] - start[0]) / one.scales(freq, amplitude, amplitude)[0]
    assert distance.max() > NEWTON_REACH
