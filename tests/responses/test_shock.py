"""Conditioned free-fall sweeps: analytic linear values, symmetry, phases, relaxation, SRS."""

import numpy as np
import pytest

from idkit.responses.shock import default_shock_grid, shock_sweep, ShockSweep
from idkit.errors import SimulationError
from idkit.limits import MAX_IMPACT_SPEED
from idkit.models import SDOFSystem, VoigtModel, library
from idkit.simulate import STANDARD_GRAVITY

LINEAR_PEAK_TOLERANCE = 1e-5  # relative; sampling at 2000 steps per period costs ~1e-6
MIRROR_TOLERANCE = 1e-9  # relative; v0 -> -v0 of a symmetric system mirrors the response


def _undamped(mass=8.0, freq=5.0):
    omega0 = 2 * np.pi * freq
    return SDOFSystem(mass, VoigtModel(k=mass * omega0**2, damping=0.0)), omega0


def test_undamped_linear_drop_matches_energy_balance():
    system, omega0 = _undamped()
    speed = np.array([0.05, 0.4, 1.5])
    sweep = shock_sweep(system, impact_velocity=-speed)
    assert isinstance(sweep, ShockSweep) and sweep.ok.all()
    assert np.allclose(sweep.rest_shock_level, omega0 * speed, rtol=LINEAR_PEAK_TOLERANCE)  # eq. 3.23
    assert np.allclose(sweep.peak_compression[:, 0], speed / omega0, rtol=LINEAR_PEAK_TOLERANCE)  # eq. 3.21
    # symmetric and lossless: equal peaks in compression and in the following tension
    assert np.allclose(sweep.peak_acceleration_compression, sweep.peak_acceleration_tension,
                       rtol=LINEAR_PEAK_TOLERANCE)
    assert np.allclose(sweep.peak_tension[:, 0], sweep.peak_compression[:, 0], rtol=LINEAR_PEAK_TOLERANCE)


def test_drop_height_gives_the_free_fall_velocity():
    system, omega0 = _undamped()
    heights = np.array([0.01, 0.05])
    sweep = shock_sweep(system, drop_height=heights)
    assert np.allclose(sweep.impact_velocity, -np.sqrt(2 * STANDARD_GRAVITY * heights), rtol=1e-15)
    assert np.allclose(sweep.drop_height, heights, rtol=1e-12)
    assert np.allclose(sweep.rest_shock_level, omega0 * np.sqrt(2 * STANDARD_GRAVITY * heights),
                       rtol=LINEAR_PEAK_TOLERANCE)


def test_symmetric_wire_rope_mirrors_compression_and_tension():
    system = library.get("system_a1_symmetric")
    speed = np.array([0.1, 0.5, 1.2])
    down = shock_sweep(system, impact_velocity=-speed)
    up = shock_sweep(system, impact_velocity=speed)
    assert np.allclose(down.peak_acceleration_compression, up.peak_acceleration_tension, rtol=MIRROR_TOLERANCE)
    assert np.allclose(down.peak_acceleration_tension, up.peak_acceleration_compression, rtol=MIRROR_TOLERANCE)
    assert np.allclose(down.peak_compression, up.peak_tension, rtol=MIRROR_TOLERANCE)
    # friction dissipates during compression: the following tension peak is lower
    assert np.all(down.peak_acceleration_tension < down.peak_acceleration_compression)
    assert list(down.governing_phase) == ["compression"] * 3


def test_asymmetric_wire_rope_tension_governs_at_high_speed():
    # thesis fig. 3.21b: compression critical below about 0.9 m/s, tension above
    sweep = shock_sweep(library.get("system_a1_asymmetric"), impact_velocity=[-0.3, -0.6, -1.5, -2.0])
    assert list(sweep.governing_phase) == ["compression", "compression", "tension", "tension"]
    assert np.allclose(sweep.rest_shock_level,
                       np.maximum(sweep.peak_acceleration_compression, sweep.peak_acceleration_tension))


def test_hybrid_reports_both_components():
    sweep = shock_sweep(library.get("hybrid_asymmetric"), impact_velocity=[-0.2, -1.0])
    assert sweep.isolator_names == ("upper", "lower")
    assert sweep.peak_compression.shape == (2, 2) and np.all(sweep.peak_compression > 0)
    table = sweep.to_dataframe()
    assert {"max_compression_upper [m]", "max_tension_lower [m]", "governing_phase"} <= set(table)
    duration, step = default_shock_grid(library.get("hybrid_asymmetric"))
    assert sweep.duration == duration and sweep.time_step == step


def test_relaxation_starts_from_the_static_elongation():
    system, omega0 = _undamped()
    sweep = shock_sweep(system, impact_velocity=[-0.3], relaxation=True)
    static = system.mass * STANDARD_GRAVITY / system.isolator.k
    assert sweep.initial_deflection[0] == pytest.approx(static, rel=1e-9)
    # energy: the spring's stored m g^2/(2 k) adds to the kinetic energy -> amplitude sqrt(x_s^2 + (v/w)^2)
    amplitude = np.hypot(static, 0.3 / omega0)
    assert sweep.rest_shock_level[0] == pytest.approx(omega0**2 * amplitude, rel=LINEAR_PEAK_TOLERANCE)


def test_srs_of_the_top_acceleration_tends_to_its_peak_at_high_frequency():
    system, omega0 = _undamped(freq=5.0)
    sweep = shock_sweep(system, impact_velocity=[-0.5])
    srs = sweep.srs(0, [100.0, 200.0], damping_ratio=0.05)
    # far above 5 Hz the oscillator follows its input: SRS -> max |a| (within 2 %, quasi-static)
    assert np.allclose(srs.maximax, sweep.rest_shock_level[0], rtol=2e-2)


def test_input_checks():
    system, _ = _undamped()
    with pytest.raises(SimulationError, match="exactly one"):
        shock_sweep(system)
    with pytest.raises(SimulationError, match="impact_velocity"):
        shock_sweep(system, impact_velocity=[np.nan])


@pytest.mark.parametrize("gravity", ["yes", float("nan"), -9.81, np.array([9.81])])
@pytest.mark.parametrize("entry", ["shock_sweep", "solve_ivp_reference"])
def test_gravity_that_is_not_an_acceleration_is_refused_by_every_entry(entry, gravity):
    # shock_sweep and the reference path read gravity as float(gravity or 0): 'yes' raised
    # Python's ValueError, NaN and an upward value ran; free_fall and simulate refused them
    from idkit.simulate import solve_ivp_reference

    system = SDOFSystem(1.0, VoigtModel(k=1e4, damping=10.0))
    calls = {
        "shock_sweep": lambda: shock_sweep(system, impact_velocity=[-1.0], duration=0.05, time_step=1e-4,
                                           gravity=gravity),
        "solve_ivp_reference": lambda: solve_ivp_reference(system, np.linspace(0.0, 0.01, 5), gravity=gravity),
    }
    with pytest.raises(SimulationError, match="gravity: found"):
        calls[entry]()


@pytest.mark.parametrize("mass", [1e6, 1e-7])
def test_the_default_drop_grid_refuses_a_resonance_it_has_not_located(mass):
    # 1e6 kg on 1e3 N/m resonates at 5 mHz, 1e-7 kg at 16 kHz: outside the 0.1 Hz - 5 kHz band
    # searched, the grid was built on the band's end (40 s for a 200 s period) and ran "ok"
    system = SDOFSystem(mass, VoigtModel(k=1e3, damping=0.1 * np.sqrt(1e3 * mass)))
    with pytest.raises(SimulationError, match="an end of the band 0.1-5000 Hz"):
        default_shock_grid(system)
    with pytest.raises(SimulationError, match="an end of the band"):
        shock_sweep(system, drop_height=[0.05])
    # given a grid, it runs
    assert shock_sweep(system, drop_height=[0.05], duration=1e-3, time_step=1e-5).drop_height.size == 1


@pytest.mark.parametrize("arguments, gravity, moves", [
    (dict(drop_height=[0.0, 0.02]), False, [False, True]),
    (dict(impact_velocity=[0.0, -0.3]), False, [False, True]),
    (dict(drop_height=[0.0]), True, [True]),       # set down under gravity: it compresses
])
def test_a_drop_that_cannot_move_says_so_instead_of_ok(arguments, gravity, moves):
    # drop_height=[0.0] without gravity reported NaN peaks with status "ok"; nothing can move
    # (no speed, no weight, no initial deflection), so the status says why the peaks are NaN
    from idkit.responses.shock import NO_MOTION

    system = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5.0) ** 2, damping=1.0))
    sweep = shock_sweep(system, duration=0.2, time_step=1e-3, gravity=gravity, **arguments)
    assert sweep.ok.all()  # the runs are valid
    for index, moving in enumerate(moves):
        if moving:
            assert sweep.reasons[index] == "ok" and sweep.rest_shock_level[index] > 0
        else:
            assert sweep.reasons[index] == NO_MOTION
            assert np.isnan(sweep.rest_shock_level[index]) and sweep.travel_compression[index] == 0.0
    assert list(sweep.to_dataframe()["status"]) == list(sweep.reasons)


def test_relaxation_moves_a_drop_without_speed_or_gravity():
    system = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5.0) ** 2, damping=1.0))
    sweep = shock_sweep(system, impact_velocity=[0.0], duration=0.2, time_step=1e-3, relaxation=True)
    assert sweep.reasons == ("ok",) and sweep.rest_shock_level[0] > 0


def test_an_impact_whose_arrest_overflows_the_force_scale_is_refused_from_a_height_or_a_speed():
    # drop_height=[1e300] (4.4e150 m/s) ran "ok" with 1e148 m of travel; the impact now passes the
    # force-scale rule of every simulation: mass x |v0| / time_step (stopped within one step) below
    # sqrt(largest float64) = 1.34e154 N, here |v0| < 1.34e154 x 1e-4 s / 1 kg = 1.34e150 m/s
    import warnings

    system = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5.0) ** 2, damping=1.0))
    grid = dict(duration=0.2, time_step=1e-4)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(SimulationError, match=r"drop_height: found 1e\+300 m \(impact at 4.429e\+150 m/s\).*"
                                                  r"expected \|v0\| below 1.341e\+150 m/s"):
            shock_sweep(system, drop_height=[0.1, 1e300], **grid)
        with pytest.raises(SimulationError, match=r"impact_velocity: found -1e\+152 m/s.*forces below 1.341e\+154 N"):
            shock_sweep(system, impact_velocity=[-1e152], **grid)
        # below the bound the linear system's answer scales exactly with the speed
        sweep = shock_sweep(system, impact_velocity=[-1.0, -1e149], **grid)
    assert sweep.reasons == ("ok", "ok")
    assert sweep.rest_shock_level[1] / 1e149 == pytest.approx(sweep.rest_shock_level[0], rel=1e-9)
    # the speed whose square overflows is the limit the message states (idkit.limits.MAX_IMPACT_SPEED)
    with np.errstate(over="ignore"):
        squares = np.array([MAX_IMPACT_SPEED, np.nextafter(MAX_IMPACT_SPEED, np.inf)]) ** 2
    assert np.isfinite(squares).tolist() == [True, False]
    with pytest.raises(SimulationError, match=r"found -1e\+160 m/s, whose drop height .* below 1.34e\+154 m/s"):
        shock_sweep(system, impact_velocity=[-1e160], **grid)


def test_a_rig_drop_whose_fall_exceeds_the_simulator_steps_is_refused():
    # drop_rig(drop_height=[1e300]): a 4.5e149 s fall cast to int64 steps (numpy RuntimeWarning)
    import warnings

    from idkit.simulate import drop_rig

    system = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5.0) ** 2, damping=1.0))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(SimulationError, match=r"drop_height: found 1e\+300 m, whose fall of 4.516e\+149 s.*"
                                                  r"expected fewer than 1e\+08"):
            drop_rig(system, bottom_mass=5.0, drop_height=[1e300], duration=0.1, time_step=1e-3)
