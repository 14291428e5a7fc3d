"""The compiled step with the physical elements of docs/elements.md against independent methods.

* clearance-Jenkin and rate-dependent Jenkin SDOF under harmonic base motion against an
  explicit central-difference loop written here (plain Python, the element's law from its
  definition, a 10x finer step);
* pinched Bouc-Wen SDOF against the force-driven RK4 integrator in time
  (:func:`idkit.simulate.simulate_force_driven`, which integrates ``z`` in time instead of in
  deflection);
* a drop onto a clearance damper against its energy closed form; a harmonic map point of a
  clearance damper moving within its clearance against the linear transmissibility; shooting
  (the period map) on a rate-dependent damper against the settled harmonic run.
"""

import math

import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.models import ClearanceIwanModel, PinchedBoucWenModel, RateDependentIwanModel, SDOFSystem
from idkit.models.laws import sdof_transmissibility
from idkit.responses.periodic import periodic_response
from idkit.simulate import BaseMotion, free_fall, harmonic_response, simulate, simulate_force_driven

MASS = 10.0  # kg
FREQ = 3.0  # Hz, base displacement
AMPLITUDE = 8e-3  # m
DURATION = 1.0  # s
STEP = 2e-4  # s, the compiled kernel's
FINE = 10  # the explicit loop's steps per kernel step


def _explicit_relative_motion(element_force, c_visc):
    """Relative displacement ``y`` (m) of ``m y'' + F + c y' = m A w^2 sin(w t)`` at the kernel's
    step times, by central differences (velocity at half steps) with ``STEP / FINE``;
    ``element_force(y, v, h)`` returns the hysteretic force (N) after a step to ``y`` at rate ``v``."""
    h = STEP / FINE
    omega = 2.0 * math.pi * FREQ
    n = int(round(DURATION / h))
    y, v_half = 0.0, -AMPLITUDE * omega  # top at rest, base moving: relative velocity -A w
    force = element_force(y, 0.0, h)
    out = [y]
    for step in range(1, n + 1):
        t = (step - 1) * h
        accel = AMPLITUDE * omega**2 * math.sin(omega * t) - (force + c_visc * v_half) / MASS
        v_half += accel * h if step > 1 else 0.5 * accel * h
        y += v_half * h
        force = element_force(y, v_half, h)
        if step % FINE == 0:
            out.append(y)
    return np.array(out)


def _kernel_relative_motion(isolator):
    time = np.arange(int(round(DURATION / STEP)) + 1) * STEP
    run = simulate(SDOFSystem(MASS, isolator), time, base=BaseMotion.harmonic(FREQ, AMPLITUDE))
    assert run.reasons == ("ok",)
    return run.deflection[0, 0]


def _play(stiffness, limit):
    """A stop operator on the virtual force ``V = k e`` (its state kept in a closure)."""
    state = {"y": 0.0, "virtual": 0.0}

    def update(y, limit_now):
        virtual = state["virtual"] + stiffness * (y - state["y"])
        state["y"], state["virtual"] = y, min(max(virtual, -limit_now), limit_now)
        return state["virtual"]

    return update


def test_clearance_jenkin_sdof_matches_an_explicit_loop():
    """Relative motion of a mass on a clearance damper (g1, k, fc, gap, c): the Newmark kernel and
    an explicit loop agree within 0.5 % of the peak deflection (3.6 mm). The error of both is first
    order at every contact and slip event (a kink resolved to within a step): at most ``v h`` = 0.15
    m/s x 2e-4 s = 0.8 % of the peak, less where the kinks' errors do not add up; measured 0.012 %."""
    g1, k, fc, gap, c = 2e4, 2e5, 50.0, 2e-3, 5.0
    play = _play(k, fc + k * gap)

    def element(y, _v, _h):
        virtual = play(y, fc + k * gap)
        dead = k * gap
        return g1 * y + (virtual - dead if virtual > dead else virtual + dead if virtual < -dead else 0.0)

    reference = _explicit_relative_motion(element, c)
    kernel = _kernel_relative_motion(ClearanceIwanModel(gap=gap, g1=g1, k=[k], fc=[fc], c_visc=c))
    peak = np.max(np.abs(reference))
    assert peak > gap + fc / k  # the run does slip through the clearance
    assert np.max(np.abs(kernel - reference)) < 5e-3 * peak


def test_rate_dependent_jenkin_sdof_matches_an_explicit_loop():
    """Same for a Jenkin element whose slip force rises with speed (r = 0.8, v_ref = 0.05 m/s):
    the kernel takes the end-of-step rate of the trapezoidal rule, the loop its half-step rate;
    both are first order in the step at slip events (bound as above, ``v h`` = 2.3 % of the 1.3 mm
    peak); within 1 %, measured 0.35 % (0.21 % with half the kernel's step). Without the rate
    dependence (r = 0) the same run differs by 46 %: the check sees the law."""
    g1, k, fc, gain, speed, c = 2e4, 2e5, 50.0, 0.8, 0.05, 5.0
    play = _play(k, fc)

    def element(y, v, _h):
        return g1 * y + play(y, fc * (1.0 + gain * math.tanh(abs(v) / speed)))

    reference = _explicit_relative_motion(element, c)
    kernel = _kernel_relative_motion(RateDependentIwanModel(g1=g1, k=[k], fc=[fc], slip_rate_gain=gain,
                                                            slip_speed=speed, c_visc=c))
    plain = _kernel_relative_motion(RateDependentIwanModel(g1=g1, k=[k], fc=[fc], slip_rate_gain=0.0,
                                                           slip_speed=speed, c_visc=c))
    peak = np.max(np.abs(reference))
    assert np.max(np.abs(kernel - reference)) < 1e-2 * peak
    assert np.max(np.abs(plain - reference)) > 0.2 * peak  # the rate dependence matters in this run


def test_pinched_boucwen_sdof_matches_the_force_driven_integrator():
    """A mass on a pinched Bouc-Wen element: base-excited Newmark kernel (``z`` by RK4 in
    deflection) against the force-driven RK4 in time with the base's inertial force ``m A w^2
    sin(w t)``; within 0.5 % of the peak deflection (the Newmark kernel's second-order error at
    5000 steps for 3 periods, (w h)^2 / 12 ~ 1e-6, plus the sign switches of ``z``'s law, first
    order in the step); measured 0.002 %, where the same run without pinching differs by 52 %."""
    z_u, n = 40.0, 1.5
    total = 2e4 / z_u**n
    model = PinchedBoucWenModel(k1=1e3, k2=0.0, k3=0.0, alpha=2e4, beta=0.6 * total, gamma=0.4 * total, n=n,
                                pinch=0.7, pinch_width=0.25, pinch_shift=0.1)
    kernel = _kernel_relative_motion(model)
    rate = 5000.0  # Hz, force samples
    omega = 2.0 * math.pi * FREQ
    times = np.arange(int(round(DURATION * rate)) + 1) / rate
    forced = simulate_force_driven(model, MASS, MASS * AMPLITUDE * omega**2 * np.sin(omega * times), rate,
                                   initial_velocity=-AMPLITUDE * omega)
    assert forced.success
    reference = forced.displacement[:: int(round(rate * STEP))]
    peak = np.max(np.abs(reference))
    assert peak > 2.0 * z_u / 2e4  # beyond the yield travel: the pinched hysteresis acts
    assert np.max(np.abs(kernel - reference)) < 5e-3 * peak
    assert np.max(np.abs(_kernel_relative_motion(model.plain()) - reference)) > 0.2 * peak


def test_drop_onto_a_clearance_damper_follows_its_energy_balance():
    """Free fall at -0.5 m/s onto a clearance damper with no parallel spring: no force while the
    travel is within the clearance, then the element loads to fc and slips until the kinetic energy
    is spent, ``y_max = gap + fc/k + (m v0^2 / 2 - fc^2 / (2 k)) / fc``; within 1 % (the step's
    share of the stopping time: |v0| h / travel = 0.5 x 5e-5 / 11 mm = 0.2 %); measured 1.5e-6."""
    k, fc, gap, v0 = 1e6, 150.0, 3e-3, -0.5
    run = free_fall(SDOFSystem(MASS, ClearanceIwanModel(gap=gap, g1=0.0, k=[k], fc=[fc])), impact_velocity=v0,
                    duration=0.15, time_step=5e-5)
    assert run.reasons == ("ok",)
    y, force = run.deflection[0, 0], run.isolator_force[0, 0]
    first_contact = np.argmax(y < -gap)
    assert np.all(force[:first_contact] == 0.0)  # free flight through the clearance
    expected = gap + fc / k + (0.5 * MASS * v0**2 - fc**2 / (2.0 * k)) / fc
    assert abs(-np.min(y) - expected) < 1e-2 * expected
    assert np.min(force) == pytest.approx(-fc, rel=1e-12)  # slips at exactly fc


def test_harmonic_point_within_the_clearance_is_linear():
    """Base motion small enough that the damper never closes its clearance: the steady state is
    that of the parallel spring and dashpot, ``T = k* / (k* - m w^2)`` with ``k* = g1 + i w c``,
    within 1e-2 (the map's default 128+ steps a period: Newmark's phase error (w h)^2 / 12 and the
    steady-state tolerance 1e-3; measured 1.0e-3 at 4 Hz); the clearance stays open (deflection
    amplitude below the gap)."""
    g1, c, gap = 4e3, 8.0, 5e-3
    system = SDOFSystem(MASS, ClearanceIwanModel(gap=gap, g1=g1, k=[2e5], fc=[50.0], c_visc=c))
    freq = np.array([1.5, 4.0])
    result = harmonic_response(system, freq, 5e-4, start="linear")
    assert result.converged.all()
    omega = 2.0 * np.pi * freq
    expected = sdof_transmissibility(g1 + 1j * omega * c, MASS, omega)
    measured = result.coefficients[:, 2] / (-1j * 5e-4)
    assert np.max(np.abs(measured - expected) / np.abs(expected)) < 1e-2
    deflection_peak = np.abs(result.deflection_coefficients[:, 2])
    assert np.all(deflection_peak < gap)


def test_shooting_finds_the_steady_state_of_a_rate_dependent_damper():
    """The period map's shooting (finite-difference Jacobian: the exact one assumes constant slip
    limits) closes on the orbit the harmonic run settles to: the same step and scheme, so the first
    harmonics agree to the run's steady-state tolerance, 1e-6 (measured 9e-7)."""
    system = SDOFSystem(MASS, RateDependentIwanModel(g1=2e4, k=[2e5], fc=[50.0], slip_rate_gain=0.8,
                                                     slip_speed=0.05, c_visc=5.0))
    freq, amplitude = np.array([FREQ]), np.array([AMPLITUDE])
    orbit = periodic_response(system, freq, amplitude)
    settled = harmonic_response(system, freq, amplitude, tolerance=1e-6, max_periods=2000)
    assert orbit.converged.all() and settled.converged.all()
    first = settled.coefficients[0, 2]
    assert abs(orbit.coefficients[0, 2] - first) < 1e-5 * abs(first)
    with pytest.raises(SimulationError, match="finite differences"):
        periodic_response(system, freq, amplitude, jacobian="exact")
