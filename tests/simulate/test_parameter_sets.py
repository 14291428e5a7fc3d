"""Parameter sets in one call: the runs simulate / shock_sweep make, bit for bit; dissipated energy against closed forms."""

import math

import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.models import BoucWenModel, HybridSystem, IwanModel, SDOFSystem, VoigtModel, library
from idkit.responses import shock_sweep
from idkit.simulate import simulate
from idkit.simulate.base_motion import integrate_acceleration
from idkit.simulate.parameter_sets import simulate_parameter_sets, stack_parameter_sets

ROPE = library.get("table_7_1_wire_rope")
BODY = library.get("table_7_3_elastomer")


BOUC_WEN = BoucWenModel(k1=1.5e4, k2=0.0, k3=0.0, alpha=4e4, beta=2e3, gamma=1e3, n=1.0, c_visc=5.0)


@pytest.mark.parametrize("systems", [
    [SDOFSystem(10.0, ROPE), SDOFSystem(13.0, ROPE)],
    [HybridSystem(10.0, BODY, 0.1, ROPE), HybridSystem(12.0, BODY, 0.15, ROPE)],
    [SDOFSystem(10.0, BOUC_WEN), SDOFSystem(13.0, BOUC_WEN)],  # the generic step
], ids=["sdof", "hybrid", "generic"])
def test_drops_of_several_parameter_sets_in_one_call_are_shock_sweeps_runs_bit_for_bit(systems):
    heights = np.array([0.005, 0.04])  # stuck, and slipping
    v0 = -np.sqrt(2.0 * 9.80665 * heights)
    sets = stack_parameter_sets(systems)
    duration, step = 0.3, 2e-4
    n_steps = round(duration / step)
    h = float(np.diff(np.arange(n_steps + 1) * step).mean())  # free_fall's grid, simulate's step on it
    runs = simulate_parameter_sets(sets, np.repeat([0, 1], 2), time_step=h, n_steps=n_steps,
                                   initial_velocity=np.repeat(np.tile(v0, 2)[:, None], sets.ndof, axis=1))
    for index, system in enumerate(systems):
        sweep = shock_sweep(system, drop_height=heights, duration=duration, time_step=step, workers=1)
        mine = slice(2 * index, 2 * index + 2)
        assert np.array_equal(runs.rest_shock_level[mine], sweep.rest_shock_level)
        assert np.array_equal(runs.travel_compression[mine], sweep.travel_compression)
        assert np.array_equal(runs.travel_tension[mine], sweep.travel_tension)
        assert np.array_equal(runs.isolator_compression[mine], sweep.peak_compression)
        assert np.array_equal(runs.isolator_extension[mine], sweep.peak_tension)


def test_floor_records_of_several_parameter_sets_are_simulates_records_bit_for_bit():
    systems = [SDOFSystem(10.0, ROPE), SDOFSystem(7.0, ROPE)]
    rate, n_steps = 800.0, 1200
    floor = np.random.default_rng(4).standard_normal((2, n_steps + 1)) * 4.0  # m/s^2: the rope slips
    time = np.arange(n_steps + 1) / rate
    h = float(np.diff(time).mean())
    disp, vel = integrate_acceleration(floor, h)
    runs = simulate_parameter_sets(stack_parameter_sets(systems), [0, 1], time_step=h, n_steps=n_steps,
                                   base_displacement=disp, base_velocity=vel, base_row=[0, 1],
                                   acceleration_scale=np.abs(np.diff(vel, axis=1)).max(axis=1) / h,
                                   record_from=200, record_every=2, n_records=500)
    for index, system in enumerate(systems):
        reference = simulate(system, time, base_acceleration=floor[index:index + 1], workers=1)
        assert np.array_equal(runs.records[index], reference.acceleration[0, 0, 200:1200:2])
    # records only: the same records, no reductions
    bare = simulate_parameter_sets(stack_parameter_sets(systems), [0, 1], time_step=h, n_steps=n_steps,
                                   base_displacement=disp, base_velocity=vel, base_row=[0, 1],
                                   acceleration_scale=np.abs(np.diff(vel, axis=1)).max(axis=1) / h,
                                   record_from=200, record_every=2, n_records=500, reduce=False)
    assert np.array_equal(bare.records, runs.records) and np.array_equal(bare.flags, runs.flags)
    assert np.isfinite(runs.travel_compression).all() and np.isnan(bare.travel_compression).all()
    assert np.isnan(bare.dissipated_energy).all()


def test_a_viscous_dampers_dissipated_energy_is_the_initial_energy_less_what_remains():
    # m x'' + c x' + k x = 0 from x = 0, x' = v0: x = v0 / wd exp(-zeta w t) sin(wd t); what it
    # dissipated by T is m v0^2 / 2 - (m x'(T)^2 + k x(T)^2) / 2
    mass, stiffness, zeta, v0 = 2.0, 8.0e4, 0.05, -0.4
    omega = math.sqrt(stiffness / mass)
    damping = 2.0 * zeta * mass * omega
    wd = omega * math.sqrt(1.0 - zeta**2)
    period = 2.0 * math.pi / omega
    n_steps, h = 2000, 1.3 * period / 2000  # 2000 steps a period, ends 1.3 periods in
    end = n_steps * h
    decay = math.exp(-zeta * omega * end)
    x = v0 / wd * decay * math.sin(wd * end)
    v = v0 * decay * (math.cos(wd * end) - zeta * omega / wd * math.sin(wd * end))
    dissipated = 0.5 * mass * v0**2 - 0.5 * (mass * v**2 + stiffness * x**2)
    system = SDOFSystem(mass, VoigtModel(k=stiffness, damping=damping))
    runs = simulate_parameter_sets(stack_parameter_sets([system]), [0], time_step=h, n_steps=n_steps,
                                   initial_velocity=[[v0]])
    # Newmark's period error (omega h)^2 / 12 = 8e-7 shifts the phase by 1e-5 rad over 1.3 periods:
    # the energies move by that times the energy, 1e-5 of m v0^2 / 2
    assert runs.dissipated_energy[0, 0] == pytest.approx(dissipated, abs=2e-5 * 0.5 * mass * v0**2)
    assert 0.5 < dissipated / (0.5 * mass * v0**2) < 0.6  # a real share of the drop's energy


def test_a_friction_elements_dissipated_energy_is_its_slip_force_times_its_slip():
    # one Jenkin element (k, Fc) beside a spring g1, dropped: stuck to y1 = Fc / k, then slipping; while
    # the first compression goes on, the energy dissipated is Fc (|y| - y1) and nothing else loses any
    g1, k, fc, mass, v0 = 1.0e4, 3.0e4, 30.0, 1.0, -0.5
    system = SDOFSystem(mass, IwanModel(g1=g1, k=[k], fc=[fc]))
    n_steps, h = 4000, 1e-6  # 4 ms: past the slip onset (about 2 ms), before the largest compression (8 ms)
    runs = simulate_parameter_sets(stack_parameter_sets([system]), [0], time_step=h, n_steps=n_steps,
                                   initial_velocity=[[v0]])
    travel = runs.isolator_compression[0, 0]
    assert travel > 1.5 * fc / k
    # the trapezoidal work misses at most the corner of the one step that crosses the slip onset,
    # k (v0 h)^2 / 2 = 4e-9 J
    assert runs.dissipated_energy[0, 0] == pytest.approx(fc * (travel - fc / k), abs=1e-8)


def test_a_stuck_rope_dissipates_nothing_but_its_dashpot_and_its_elements_store_the_rest():
    # small drop of the rope without its dashpot: amplitude v0 / omega = 0.034 mm, below the first
    # element's slip deflection Fc_1 / k_1 = 0.082 mm, so every element stays stuck and the work done on
    # the rope is all stored (its cubic spring and its elements' springs): nothing is dissipated but
    # what each step's Newton tolerance (1e-13 of the force scale m g + sum Fc = 124 N) and the element
    # forces' running sums leave, 1e-10 of the drop's energy here
    stuck = IwanModel(g1=ROPE.params()["g1"], g2=ROPE.params()["g2"], g3=ROPE.params()["g3"], k=list(ROPE.k),
                      fc=list(ROPE.fc))
    system = SDOFSystem(10.0, stuck)
    v0 = -0.005
    runs = simulate_parameter_sets(stack_parameter_sets([system]), [0], time_step=1e-4, n_steps=3000,
                                   initial_velocity=[[v0]])
    assert runs.isolator_compression[0, 0] < ROPE.fc[0] / ROPE.k[0]
    assert abs(runs.dissipated_energy[0, 0]) < 1e-9 * 0.5 * 10.0 * v0**2


def test_parameter_sets_of_different_structures_are_refused():
    with pytest.raises(SimulationError, match="differs in structure"):
        stack_parameter_sets([SDOFSystem(1.0, ROPE), HybridSystem(1.0, BODY, 0.1, ROPE)])
