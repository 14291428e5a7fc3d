"""Floquet multipliers against what they predict, on systems the shooting code was not built
with: perturbed runs of the period map (idkit's own step) grow or decay by the largest
multiplier per period, the multipliers of a Duffing oscillator obey Liouville's formula, and a
period-doubling range found by continuation is where a long time run shows the 1/2 subharmonic.
"""

import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.models import IwanModel, SDOFSystem, library
from idkit.responses.continuation import continue_in_frequency
from idkit.responses.periodic import PeriodMap, periodic_response
from idkit.simulate import harmonic_response
from tests.responses.test_continuation import _mathieu_tongue

# Hardening Duffing m y'' + c y' + k y + k3 y^3 = m A w^2 sin(w t): 2 kg, 8 Hz, 2 %, base 2 mm;
# the linear peak deflection A / (2 zeta) = 0.05 m carries a cubic force 0.4 of the linear one,
# so three periodic orbits coexist between the folds (8.59 and 9.59 Hz).
MASS = 2.0  # kg
STIFFNESS = (2 * np.pi * 8.0) ** 2 * MASS  # N/m
DAMPING = 2 * 0.02 * np.sqrt(STIFFNESS * MASS)  # N s/m
BASE = 2e-3  # m
CUBIC = 0.4 * STIFFNESS / (BASE / 0.04) ** 2  # N/m^3
STEPS = 256


def _duffing(cubic=CUBIC):
    """A linear spring split between the parallel spring and a Jenkin element that never slips
    (1 MN): its memory F - k y is conserved, a neutral multiplier exactly 1."""
    return SDOFSystem(MASS, IwanModel(g1=0.9 * STIFFNESS, k=[0.1 * STIFFNESS], fc=[1e6], g3=cubic,
                                      c_visc=DAMPING))


@pytest.fixture(scope="module")
def three_orbits():
    """The three periodic orbits at 9 Hz: shot from the branch points around 9 Hz."""
    system = _duffing()
    branch = continue_in_frequency(system, BASE, (6.0, 12.0), steps_per_period=STEPS)
    assert branch.success and len(branch.points("fold")) == 2
    freq = 9.0
    crossings = np.flatnonzero((branch.freq[:-1] - freq) * (branch.freq[1:] - freq) <= 0)
    assert crossings.size == 3
    guesses = []
    for index in crossings:
        weight = (freq - branch.freq[index]) / (branch.freq[index + 1] - branch.freq[index])
        guesses.append(branch.states[index] + weight * (branch.states[index + 1] - branch.states[index]))
    orbits = periodic_response(system, [freq] * 3, BASE, initial_states=guesses, settle_periods=0, steps_per_period=STEPS)
    assert orbits.converged.all()
    return system, orbits


def _distances(period_map, orbit, freq, amplitude, steps, size, n_periods, seed=0):
    """Max scaled distance of the mechanical state from ``orbit`` after each of ``n_periods``
    periods, from a push of ``size`` state scales in a random direction (friction memory kept),
    and the sign of the top displacement's deviation."""
    scale = period_map.scales(freq, amplitude, max(amplitude, float(np.abs(orbit[:period_map.ndof]).max())))[0]
    direction = np.random.default_rng(seed).normal(size=2 * period_map.ndof)
    state = period_map.push(orbit, size * direction * scale[:2 * period_map.ndof])
    distance, sign = [], []
    for _ in range(n_periods):
        state = period_map.run(freq, amplitude, state[None], steps)[0][0]
        deviation = (state - orbit)[:2 * period_map.ndof] / scale[:2 * period_map.ndof]
        distance.append(np.abs(deviation).max())
        sign.append(np.sign(deviation[0]))
        if distance[-1] > 0.1:
            break
    return np.array(distance), np.array(sign)


def test_duffing_multipliers_obey_liouville(three_orbits):
    """The spring is conservative: the monodromy determinant is exp(-c T / m) (Liouville), so the
    product of all multipliers (the friction memory's is 1) is known without any Floquet code.
    Average-acceleration Newmark changes log det by the relative amount <k_t> h^2 / (4 m)
    (k_t the tangent stiffness along the orbit; measured 1.2e-4 on the small orbit, 1.9e-4 on
    the large one against 1.2e-4 and 1.9e-4 predicted): bound 1.5 k_t,max h^2 / (4 m)."""
    system, orbits = three_orbits
    freq = 9.0
    exact = -DAMPING / MASS / freq
    h = 1.0 / (freq * STEPS)
    for index in range(3):
        found = np.sum(np.log(np.abs(orbits.multipliers[index])))
        deflection = orbits.half_range[index, 0] + BASE
        tangent_stiffness = STIFFNESS + 3 * CUBIC * deflection**2
        assert abs(found / exact - 1) < 1.5 * tangent_stiffness * h**2 / (4 * MASS)
    assert list(orbits.stable) == [True, False, True]
    assert orbits.instability[1] == "fold"


def test_duffing_perturbations_grow_by_the_largest_multiplier(three_orbits):
    """From 1e-6 of the state scale: the middle orbit's deviation grows by its multiplier 1.207
    per period until it leaves (a tenth of the response), measured between 10 periods (the
    second multiplier 0.66 has then decayed by (0.66 / 1.21)^10 = 2.5e-3) and a deviation of
    1e-3 (nonlinear terms O(1e-3)) over about 30 periods: error below 1e-4 each, tolerance 2e-3.
    The two stable orbits take a push of 1e-4 back below 1e-9 within 200 periods
    (|mu| = 0.894: 0.894^200 = 2e-10)."""
    system, orbits = three_orbits
    period_map = PeriodMap(system, 1)
    for index in range(3):
        distance, _ = _distances(period_map, orbits.states[index], 9.0, BASE, STEPS,
                                 1e-6 if index == 1 else 1e-4, 400 if index != 1 else 200)
        largest = abs(orbits.multipliers[index, 0])
        if orbits.stable[index]:
            assert distance[-1] < 1e-9 and distance.size == 400
            assert largest <= 1 + 1e-9
        else:
            assert distance[-1] > 0.1  # it left
            window = np.flatnonzero((np.arange(distance.size) >= 10) & (distance < 1e-3))
            first, last = window[0], window[-1]
            rate = (distance[last] / distance[first]) ** (1 / (last - first))
            assert last - first > 20
            assert abs(rate / largest - 1) < 2e-3, (rate, largest)


def test_table_a1_period_doubling_orbit_diverges_alternating_by_its_multiplier():
    """Thesis 3.4.2 (Table A.1 asymmetric rope, 8 kg, 10.68 Hz, 1.2 mm): the period-1 orbit is
    unstable by period doubling, multiplier -1.0035. A push of 1e-7 of the state scale grows by
    |mu| per period (both Jenkin elements stick: the map is smooth there) with the deviation
    changing sign every period; over 2000 periods of growth from 1e-6 to 1e-3 the rate is good
    to the nonlinear drift d / n ~ 1e-3 / 2000 and the decay of the second multiplier -0.98:
    tolerance 1e-5. Below the tongue (10.5 Hz) the same push returns."""
    system = library.get("system_a1_asymmetric")
    inside = periodic_response(system, 10.68, 1.2e-3, seek_stable=False)
    assert inside.converged[0] and inside.instability[0] == "period doubling"
    mu = inside.multipliers[0, 0]
    assert mu.real < -1 and abs(mu.imag) < 1e-9
    period_map = PeriodMap(system, 1)
    steps = int(inside.steps_per_period[0])
    distance, sign = _distances(period_map, inside.states[0], 10.68, 1.2e-3, steps, 1e-7, 3000)
    window = np.flatnonzero((np.arange(distance.size) >= 500) & (distance < 1e-3))
    first, last = window[0], window[-1]
    assert last - first > 1000
    rate = (distance[last] / distance[first]) ** (1 / (last - first))
    assert abs(rate / abs(mu) - 1) < 1e-5, (rate, abs(mu))
    assert np.all(sign[first + 1:last + 1] == -sign[first:last])  # the 1/2 subharmonic grows
    below = periodic_response(system, 10.5, 1.2e-3, seek_stable=False)
    assert below.stable[0]
    distance, _ = _distances(period_map, below.states[0], 10.5, 1.2e-3, int(below.steps_per_period[0]), 1e-5, 3000)
    assert distance[-1] < 1e-3 * distance[0]


def _quadratic_rope():
    """5 kg on an asymmetric rope of our own: quadratic spring 1.5e5 N/m^2, one Jenkin element
    (4 kN/m, 30 N), 0.19 % damping; stuck resonance 6.75 Hz, so a 1/2 subharmonic near 13.5 Hz."""
    return SDOFSystem(5.0, IwanModel(g1=5e3, g2=1.5e5, k=[4e3], fc=[30.0], c_visc=0.8))


def test_period_doubling_range_of_a_quadratic_rope_is_where_time_runs_find_the_subharmonic():
    """Base 0.5 mm: the quadratic spring modulates the stuck stiffness at the excitation frequency
    with depth 2 g2 Y / k = 0.022 (Y the first-harmonic deflection), a damped Mathieu tongue
    whose first-order bounds are good to O(depth^2) = 5e-4, plus the interpolation between
    branch points 0.2 % apart: tolerance 1e-3 (measured 1.2e-4, 1.3e-4). Time runs (to 1e-8)
    0.3 % outside either period-doubling point settle on the period-1 orbit (|H0.5| at the
    noise floor 1e-6), 0.3 % inside on a 1/2 subharmonic, which shooting with periods=2 finds
    too (to 1e-6, the same discrete orbit)."""
    system = _quadratic_rope()
    amplitude = 5e-4
    branch = continue_in_frequency(system, amplitude, (13.0, 14.0), max_step=0.002)
    assert branch.success
    doubling = sorted(point.freq for point in branch.points("period doubling"))
    assert len(doubling) == 2
    near = [int(np.argmin(np.abs(branch.freq - freq))) for freq in doubling]
    deflection = np.abs(branch.deflection_coefficients[near, 2]).mean()
    mean = branch.deflection_coefficients[near, 0].real.mean()
    rope = system.isolator
    stiffness = rope.stuck_stiffness + 2 * rope.g2 * mean
    expected = _mathieu_tongue(system.mass, stiffness, rope.c_visc, 2 * rope.g2 * deflection / stiffness)
    assert np.all(np.abs(np.array(doubling) / expected - 1) < 1e-3), (doubling, expected)
    outside = [doubling[0] * 0.997, doubling[1] * 1.003]
    inside = [doubling[0] * 1.003, doubling[1] * 0.997]
    runs = harmonic_response(system, outside + inside, amplitude, tolerance=1e-8, max_periods=40000,
                             start="linear", workers=1)
    assert runs.converged.all()
    subharmonic = np.abs(runs.hosidf(0.5))
    assert np.all(subharmonic[:2] < 1e-6) and np.all(subharmonic[2:] > 1.0), subharmonic
    shot = periodic_response(system, inside, amplitude, periods=2)
    assert shot.converged.all() and shot.stable.all()
    assert np.allclose(np.abs(shot.hosidf(0.5)), subharmonic[2:], rtol=1e-6, atol=0)


def test_a_subharmonic_far_larger_than_the_unstable_orbit_is_found():
    """Inside the quadratic rope's tongue (13.45 Hz, 0.5 mm) the stable 1/2 subharmonic
    (7.5 mm, slipping) is 45 times the period-1 orbit (0.17 mm): pushes of 1 and 3 state scales
    and 20 periods fell back onto the doubled period-1 orbit, and periods=2 returned it
    (unstable, |H0.5| = 0) while a time run settles on |H0.5| = 7.48."""
    system = _quadratic_rope()
    shot = periodic_response(system, 13.45, 5e-4, periods=2)
    assert shot.converged[0] and shot.stable[0]
    run = harmonic_response(system, 13.45, 5e-4, tolerance=1e-8, max_periods=40000, start="linear", workers=1)
    assert run.converged[0]
    assert abs(abs(shot.hosidf(0.5)[0]) / abs(run.hosidf(0.5)[0]) - 1) < 1e-6


def test_a_scalar_frequency_broadcasts_over_the_starting_states(three_orbits):
    """One (freq, amplitude) and three starts find the three coexisting orbits (before: refused,
    'expected shape (1, 3)', and the caller repeated the frequency); other shapes name the rule."""
    system, orbits = three_orbits
    again = periodic_response(system, 9.0, BASE, initial_states=orbits.states, settle_periods=0,
                              steps_per_period=STEPS)
    assert again.freq.tolist() == [9.0] * 3 and again.converged.all()
    np.testing.assert_array_equal(again.states, orbits.states)  # the same Newton runs
    assert len({round(float(x), 9) for x in again.half_range[:, 0]}) == 3
    with pytest.raises(SimulationError, match=r"initial_states: found shape \(3, 3\) for 2 .*point\(s\), "
                                              r"expected \(n, 3\) with n = 2"):
        periodic_response(system, [9.0, 9.1], BASE, initial_states=orbits.states, steps_per_period=STEPS)
