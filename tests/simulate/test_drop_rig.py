"""Drop rig: the falling stack with a bottom mass on a unilateral floor (idkit.simulate.drop_rig)."""

import math

import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.gravity import STANDARD_GRAVITY as G
from idkit.models import SDOFSystem, VoigtModel, library
from idkit.signal.drop import drop_phase_peaks
from idkit.simulate import ContactModel, contact_from_velocity_step, drop_rig, simulate


def _peaks(run):
    return drop_phase_peaks(run.deflection, run.top_acceleration, start=run.impact_index)


def test_energy_is_conserved_with_an_elastic_contact_and_an_elastic_isolator():
    # Average-acceleration Newmark conserves the energy of a linear system exactly; the only
    # error comes from the kink of the contact law met inside a step at every touch-down and
    # lift-off, at most the contact energy of one step's penetration, (omega_c h)^2 of the
    # bottom mass's kinetic energy per event. Tolerance: that bound times the events.
    k, m_top, m_bottom = 2.0e4, 2.0, 5.0
    system = SDOFSystem(m_top, VoigtModel(k=k, damping=0.0))
    contact = ContactModel(stiffness=2.0e7, restitution=1.0)
    run = drop_rig(system, bottom_mass=m_bottom, drop_height=[0.05], contact=contact, duration=0.15)
    assert run.ok.all()
    y = run.deflection[0]
    v_top = run.relative_velocity[0] + run.bottom_velocity[0]
    x_bottom = run.bottom_height[0]
    penetration = np.maximum(-x_bottom, 0.0)
    energy = (0.5 * m_top * v_top**2 + 0.5 * m_bottom * run.bottom_velocity[0] ** 2
              + G * (m_top * (x_bottom + y) + m_bottom * x_bottom) + 0.5 * k * y**2
              + 0.5 * contact.stiffness * penetration**2)
    y_static = run.static_deflection[0]
    released = G * (m_top * (0.05 + y_static) + m_bottom * 0.05) + 0.5 * k * y_static**2
    touchdowns = int(np.sum(np.diff((penetration > 0).astype(int)) != 0)) + 1
    omega_h = math.sqrt(contact.stiffness / m_bottom) * run.time_step
    bound = touchdowns * omega_h**2 * 0.5 * m_bottom * 2 * G * 0.05
    assert np.max(np.abs(energy - released)) < bound
    assert run.lifted_off[0]  # an elastic floor throws the bottom mass back up


def test_a_rigid_floor_without_rebound_reproduces_the_conditioned_free_fall():
    # contact 1e10 N/m (the isolator's 2e4 N/m is 2e-6 of it), damping ratio 3 (no rebound):
    # once the bottom mass has stopped, the rest is a free fall onto a fixed base from the same state.
    system = SDOFSystem(1.0, VoigtModel(k=2.0e4, damping=2.0))
    contact = ContactModel(stiffness=1.0e10, damping_ratio_override=3.0)
    run = drop_rig(system, bottom_mass=100.0, drop_height=[0.03], contact=contact, duration=0.12)
    assert run.ok.all()
    penetration = -np.nanmin(run.bottom_height[0])
    assert np.nanmax(run.bottom_height[0, run.impact_index:]) < penetration  # no rebound beyond the floor's give
    stopped = run.impact_index + int(np.flatnonzero(run.bottom_velocity[0, run.impact_index:] >= 0)[0])
    v_top = run.relative_velocity[0, stopped] + run.bottom_velocity[0, stopped]
    t = np.arange(run.time.size - stopped) * run.time_step
    fall = simulate(system, t, initial_velocity=[v_top], initial_deflection=[run.deflection[0, stopped]],
                    gravity=True)
    rig = drop_phase_peaks(run.deflection[0, stopped:], run.top_acceleration[0, stopped:])
    conditioned = drop_phase_peaks(fall.deflection[0, 0], fall.acceleration[0, 0])
    # the overdamped floor gives back its largest penetration slowly after the stop: the top
    # mass's travel, and so its peaks, may differ by that share of the compression, twice for margin
    tolerance = 2.0 * penetration / conditioned.compression
    assert tolerance < 0.01
    for name in ("acceleration_compression", "acceleration_tension", "compression", "tension"):
        assert getattr(rig, name) == pytest.approx(getattr(conditioned, name), rel=tolerance), name


def test_a_halved_step_changes_the_peaks_by_less_than_half_a_percent():
    system = SDOFSystem(4.33, library.get("table_7_1_wire_rope"))
    heights = [0.02, 0.08, 0.14]
    coarse = drop_rig(system, bottom_mass=7.88, drop_height=heights, duration=0.25)
    fine = drop_rig(system, bottom_mass=7.88, drop_height=heights, duration=0.25, time_step=coarse.time_step / 2)
    assert coarse.ok.all() and fine.ok.all()
    assert coarse.lifted_off.any()  # bounce and lift-off are part of the comparison
    a, b = _peaks(coarse), _peaks(fine)
    for name in ("acceleration_compression", "acceleration_tension", "compression", "tension"):
        np.testing.assert_array_less(np.abs(getattr(a, name) / getattr(b, name) - 1), 0.005, err_msg=name)


def test_the_fall_starts_from_the_statically_loaded_rest_state():
    rope = library.get("table_7_1_wire_rope")
    run = drop_rig(SDOFSystem(4.33, rope), bottom_mass=7.88, drop_height=[0.05], duration=0.02)
    y = run.static_deflection[0]
    assert float(rope.force(np.linspace(0.0, y, 200))[-1]) == pytest.approx(-4.33 * G, rel=1e-9)
    # impact speed: free fall of the centre of mass, plus the relaxation oscillation of the stack
    assert abs(run.impact_velocity[0]) == pytest.approx(math.sqrt(2 * G * 0.05), rel=0.05)


def test_validity_flags_stop_a_run_outside_the_valid_range():
    from idkit.models import IwanModel

    soft = IwanModel(g1=1e4, g3=-3e7, k=[1e4], fc=[5.0])  # local stiffness < 0 beyond 10.5 mm
    run = drop_rig(SDOFSystem(5.0, soft), bottom_mass=8.0, drop_height=[0.001, 0.10], duration=0.1)
    assert run.flags[0] == 0 and run.flags[1] == 1
    assert "negative local stiffness" in run.reasons[1]


def test_contact_read_off_the_velocity_step_of_a_simulated_drop():
    run = drop_rig(SDOFSystem(4.33, library.get("table_7_1_wire_rope")), bottom_mass=7.88, drop_height=[0.08],
                   contact=ContactModel(stiffness=5e7, restitution=0.3), before=0.02, duration=0.05)
    found = contact_from_velocity_step(run.relative_velocity[0], run.time, drop_height=0.08, bottom_mass=7.88,
                                       window=1)
    # the step also holds the relative velocity of the fall's oscillation, at most omega y_static
    # (released from the static deflection): that over sqrt(2 g h) is the reading's tolerance
    rope = library.get("table_7_1_wire_rope")
    omega = math.sqrt(rope.stuck_stiffness * (1 / 4.33 + 1 / 7.88))
    tolerance = omega * abs(run.static_deflection[0]) / math.sqrt(2 * G * 0.08)
    assert found.restitution == pytest.approx(0.3, abs=tolerance)


def test_a_start_after_the_shortest_fall_and_a_bad_restitution_are_named():
    with pytest.raises(SimulationError, match="before"):
        drop_rig(SDOFSystem(1.0, VoigtModel(k=1e4, damping=1.0)), bottom_mass=5.0, drop_height=[0.1], before=1.0)
    with pytest.raises(SimulationError, match="restitution"):
        ContactModel(restitution=0.0)
