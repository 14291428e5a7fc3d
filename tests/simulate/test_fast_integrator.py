"""The compiled batched integrator against analytic results."""

import re

import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.models import IwanModel, SDOFSystem, VoigtModel, library
from idkit.simulate import BaseMotion, free_fall, harmonic_response, simulate


@pytest.mark.parametrize("system_name", ["voigt", "system_b1_medium"])
def test_linear_steady_state_matches_transmissibility(system_name):
    """Amplitude and phase of the first harmonic within 1e-3 of k*/(k* - m w^2).

    Error budget: the trapezoidal rule's frequency warping, (w h)^2 / 12 times
    the log-slope of H, is below 4e-4 at 512 steps per period over 1-100 Hz;
    the steady-state tolerance 1e-7 adds nothing visible.
    """
    if system_name == "voigt":
        system = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5) ** 2, damping=2 * 0.05 * 2 * np.pi * 5))
    else:
        system = library.get(system_name)
    freq = np.logspace(0, 2, 11)
    response = harmonic_response(system, freq, 1e-3, steps_per_period=512, tolerance=1e-7, max_periods=20000)
    assert response.converged.all()
    ratio = response.hosidf(1) / system.transmissibility(freq)
    assert np.max(np.abs(np.abs(ratio) - 1)) < 1e-3
    assert np.max(np.abs(np.angle(ratio))) < 1e-3
    # a linear system has no higher harmonics, no subharmonic and no bias
    for order in (0.5, 2, 3):
        assert np.max(np.abs(response.hosidf(order))) < 1e-5 * np.max(np.abs(response.hosidf(1)))


def test_stick_does_not_drift_over_1000_periods():
    """Table A.1 at 1e-5 m, 1 Hz: Jenkin forces ~0.03 N << Fc, all elements stay stuck."""
    system = library.get("system_a1_symmetric")
    n_periods, per_period = 1000, 64
    time = np.arange(n_periods * per_period + 1) / per_period
    response = simulate(system, time, base=BaseMotion.harmonic(1.0, 1e-5), record_every=per_period)
    deflection = response.deflection[0, 0]
    # sampled once per period at the same phase: a drift would show as a trend
    late, early = deflection[-100:], deflection[100:200]
    assert abs(late.mean() - early.mean()) < 1e-6 * 1e-5
    assert np.ptp(late) < 1e-6 * 1e-5
    assert np.max(np.abs(response.isolator_force[0, 0])) < 0.1


@pytest.mark.parametrize("velocity", [-0.1, -0.5, -2.0])
def test_undamped_linear_free_fall(velocity):
    """max |a| = w0 |v0| and max deflection = |v0| / w0; step 1e-5 s, w0 h = 1e-3."""
    mass, stiffness = 2.0, 2e4
    omega0 = np.sqrt(stiffness / mass)
    response = free_fall(SDOFSystem(mass, VoigtModel(k=stiffness, damping=0.0)),
                         impact_velocity=[velocity], duration=0.1, time_step=1e-5)
    # sampled extremes: cos(w0 h / 2) - 1 ~ 1.3e-7 relative
    assert np.max(np.abs(response.acceleration[0, 0])) == pytest.approx(omega0 * abs(velocity), rel=1e-6)
    assert np.max(-response.deflection[0, 0]) == pytest.approx(abs(velocity) / omega0, rel=1e-6)
    # symmetric system: equal compression and tension acceleration peaks
    acceleration = response.acceleration[0, 0]
    assert acceleration.max() == pytest.approx(-acceleration.min(), rel=1e-6)


def test_hybrid_small_amplitude_first_harmonic_equals_stuck_transmissibility():
    system = library.get("hybrid_asymmetric")
    freq = np.array([2.0, 5.0, 10.0, 30.0])
    response = harmonic_response(system, freq, 1e-6, steps_per_period=512, tolerance=1e-7, max_periods=20000)
    ratio = response.hosidf(1) / system.transmissibility(freq)
    # stuck Jenkin elements are exactly linear; g2 x^2 at 1e-6 m adds ~1e-5 relative
    assert np.max(np.abs(ratio - 1)) < 2e-3


def test_invalid_runs_are_flagged_while_the_batch_finishes():
    """Table 7.1 wire rope turns negative-stiff near -34 mm: hard drops are flagged."""
    system = SDOFSystem(20.0, library.get("table_7_1_wire_rope"))
    response = free_fall(system, impact_velocity=[-0.05, -3.0, -0.1], duration=0.3, time_step=2e-5)
    assert response.flags.tolist() == [0, 1, 0]
    assert "negative local stiffness" in response.reasons[1]
    assert np.isfinite(response.flag_time[1]) and np.isnan(response.flag_time[0])
    assert np.all(np.isfinite(response.acceleration[[0, 2]]))
    assert np.min(response.deflection[1, 0][np.isfinite(response.deflection[1, 0])]) < -0.03


def test_batch_members_equal_single_runs():
    system = library.get("hybrid_symmetric")
    time = np.arange(0, 0.5, 1e-4)
    rng = np.random.default_rng(7)
    accel = rng.normal(0, 1.0, (3, time.size))
    batch = simulate(system, time, base_acceleration=accel)
    single = simulate(system, time, base_acceleration=accel[1])
    np.testing.assert_array_equal(batch.acceleration[1], single.acceleration[0])


def test_base_quantities_are_consistent():
    """The same motion given as displacement, velocity or acceleration gives the same run."""
    system = SDOFSystem(8.0, IwanModel(g1=3e3, k=[3e3], fc=[8.3], c_visc=1.3))
    time = np.arange(0, 2.0, 1e-4)
    freq, amp = 3.0, 2e-3
    omega = 2 * np.pi * freq
    runs = [
        simulate(system, time, base=BaseMotion.harmonic(freq, amp)),
        simulate(system, time, base=BaseMotion.from_function(
            lambda t: amp * omega * np.cos(omega * t), quantity="velocity")),
        simulate(system, time, base=BaseMotion.from_function(
            lambda t: -amp * omega**2 * np.sin(omega * t), quantity="acceleration", initial_velocity=amp * omega)),
    ]
    reference = runs[0].deflection[0, 0]
    shifted = simulate(system, time, base=BaseMotion.harmonic(freq, amp * omega, quantity="velocity", phase=np.pi / 2))
    runs.append(shifted)
    for run in runs[1:]:
        # velocity/acceleration integrated by the trapezoidal rule: O((w h)^2) ~ 4e-6 relative
        assert np.max(np.abs(run.deflection[0, 0] - reference)) < 1e-4 * np.max(np.abs(reference))


def test_relaxation_deflection_carries_the_weight_above():
    """Linear parts: y = (masses carried) g / k; the lower hybrid isolator carries both masses."""
    from idkit.models import HybridSystem
    from idkit.simulate import STANDARD_GRAVITY, relaxation_deflection

    sdof = SDOFSystem(4.0, VoigtModel(k=2e4, damping=5.0))
    assert relaxation_deflection(sdof) == pytest.approx([4.0 * STANDARD_GRAVITY / 2e4], rel=1e-9)
    hybrid = HybridSystem(2.0, VoigtModel(k=1e4, damping=1.0), 0.5, VoigtModel(k=3e4, damping=1.0))
    expected = [2.0 * STANDARD_GRAVITY / 1e4, 2.5 * STANDARD_GRAVITY / 3e4]
    assert relaxation_deflection(hybrid) == pytest.approx(expected, rel=1e-9)


def test_linear_start_reaches_the_same_steady_state_sooner():
    """Start from the small-amplitude steady state: linear systems start settled; the
    stuck wire rope converges in far fewer periods to the rest-start answer."""
    voigt = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5) ** 2, damping=0.3))
    freq = np.array([2.0, 5.0, 30.0])
    settled = harmonic_response(voigt, freq, 1e-3, steps_per_period=512, start="linear")
    from_rest = harmonic_response(voigt, freq, 1e-3, steps_per_period=512)
    # the only transient left is the trapezoidal rule's ~(w h)^2 / 12 departure from the
    # continuous steady state (times Q = 100 at resonance): off resonance settled after the
    # minimum 8 periods, and far fewer periods overall than from rest
    assert settled.periods[0] == 8
    assert settled.periods.sum() < 0.5 * from_rest.periods.sum()
    ratio = settled.hosidf(1) / voigt.transmissibility(freq)
    # warping (2 pi / 512)^2 / 12 = 1.3e-5, times Q = 100 at the 5 Hz resonance: 1.3e-3
    assert np.max(np.abs(ratio - 1)) < 3e-3
    wire_rope = library.get("system_a1_symmetric")
    freq = np.array([3.0, 20.0, 60.0])
    rest = harmonic_response(wire_rope, freq, 1e-5, tolerance=1e-4, max_periods=20000)
    linear = harmonic_response(wire_rope, freq, 1e-5, tolerance=1e-4, max_periods=20000, start="linear")
    assert rest.converged.all() and linear.converged.all()
    # both within the steady-state tolerance of each other (a few 1e-4 relative)
    assert np.max(np.abs(linear.hosidf(1) / rest.hosidf(1) - 1)) < 1e-3
    assert linear.periods.sum() < 0.35 * rest.periods.sum()  # measured 0.24 (2744 vs 11340 periods)
    with pytest.raises(ValueError, match="start"):
        harmonic_response(wire_rope, freq, 1e-5, start="warm")


@pytest.mark.parametrize("freq, n_harmonics, words", [
    (1e-300, 3, "resonance"),   # 48 f_res / f steps a period overflowed int64 (a negative array size)
    (1e-6, 3, "at most"),       # ~1e9 steps a period: Fourier tables of terabytes
    (5e-4, 32, "n_harmonics=32"),  # the table grows with the harmonics too (3 harmonics run)
])
def test_frequency_far_below_resonance_is_refused_before_allocation(freq, n_harmonics, words):
    """A period's steps grow as 1/f: a frequency whose tables cannot fit is named, not allocated."""
    with pytest.raises(SimulationError, match=rf"freq: found {freq:g} Hz.*steps per period") as refused:
        harmonic_response(library.get("system_a1_symmetric"), freq, 1e-3, n_harmonics=n_harmonics)
    assert words in str(refused.value)


def test_given_steps_per_period_are_bounded_by_the_table_size():
    from idkit.simulate.harmonic import MAX_PERIOD_TABLE

    too_many = 2 * (MAX_PERIOD_TABLE // (2 * 3) // 2 + 1)  # n_harmonics=1: 3 coefficients
    with pytest.raises(SimulationError, match="with n_harmonics=1 a period may take at most"):
        harmonic_response(library.get("system_a1_symmetric"), 5.0, 1e-3, n_harmonics=1, steps_per_period=too_many)


def test_overflowing_base_acceleration_is_refused():
    """A (2 pi f)^2 sets every point's force scale: an infinite one would void the batch's convergence tests."""
    with pytest.raises(SimulationError, match=r"found 1e\+300 Hz and 0.001 m, whose base acceleration"):
        harmonic_response(library.get("system_a1_symmetric"), [10.0, 1e300], 1e-3)


@pytest.mark.parametrize("arguments, words", [
    # each was run as something else without a word: 2.5 harmonics as 2, 128.7 steps as 128,
    # max_periods 0 as 2 periods, a negative or NaN tolerance as never met (every point to max_periods)
    (dict(n_harmonics=2.5), "n_harmonics: found 2.5, expected a whole number >= 1"),
    (dict(n_harmonics=True), "n_harmonics: found True"),
    (dict(steps_per_period=128.7), "steps_per_period: found 128.7, expected even integers >= 8"),
    (dict(max_periods=0), "max_periods: found 0, expected a whole number >= 1"),
    (dict(min_periods=100, max_periods=10), "max_periods: found 10, expected a whole number >= min_periods (100)"),
    (dict(tolerance=-1.0), "tolerance: found -1, expected a finite real number > 0 and < 1 (a relative change)"),
    (dict(tolerance=float("nan")), "tolerance: found nan"),
    # numpy's own errors before: a shape mismatch, a reduction over no points
    (dict(freq=[5.0, 10.0, 20.0], amplitude=[1e-3, 2e-3]), "found shapes (3,) and (2,)"),
    (dict(freq=[]), "found no points"),
])
def test_harmonic_response_refuses_arguments_it_would_change(arguments, words):
    call = dict(freq=5.0, amplitude=1e-3) | arguments
    with pytest.raises(SimulationError) as refused:
        harmonic_response(library.get("system_a1_symmetric"), **call)
    assert words in str(refused.value)


@pytest.mark.parametrize("arguments, words", [
    # run as something else without a word: NaN gravity, gravity upward, 2.5 as every 2nd step
    (dict(gravity=float("nan")), "gravity: found nan"),
    (dict(gravity=-9.81), "gravity: found -9.81, expected True, False or a finite acceleration >= 0"),
    # numpy's or Python's own errors before
    (dict(gravity="yes"), "gravity: found 'yes'"),
    (dict(impact_velocity=-np.ones((2, 2))), "impact_velocity: found shape (2, 2)"),
    (dict(time_step=0.3), "found time_step=0.3 > duration=0.1"),
    (dict(duration=1e6, time_step=1e-6), "1e+12 steps, expected fewer than 1e+08"),
])
def test_free_fall_refuses_arguments_it_would_change_or_trip_over(arguments, words):
    call = dict(impact_velocity=-1.0, duration=0.1, time_step=1e-3) | arguments
    with pytest.raises(SimulationError) as refused:
        free_fall(library.get("system_a1_symmetric"), **call)
    assert words in str(refused.value)


@pytest.mark.parametrize("duration, time_step, steps", [
    (0.1, 0.07, 2),      # 1.43 steps: was rounded down to 0.07 s, short of the duration
    (0.1, 0.06, 2),      # 1.67 steps: 0.12 s
    (0.3, 2e-5, 15000),  # 14999.999999999998 by division: a whole number, not 15001
    (0.1, 0.1, 1),
])
def test_free_fall_covers_the_whole_duration_without_changing_the_step(duration, time_step, steps):
    run = free_fall(library.get("system_a1_symmetric"), impact_velocity=-1.0, duration=duration,
                    time_step=time_step)
    assert run.time.size == steps + 1
    assert run.time[-1] >= duration * (1 - 1e-9)
    assert np.allclose(np.diff(run.time), time_step, rtol=1e-9, atol=0)


def test_free_fall_throws_upward_for_a_positive_impact_velocity():
    """Documented: ``v0 > 0`` starts in tension, the mirror image of the drop (symmetric rope)."""
    system = library.get("system_a1_symmetric")
    down = free_fall(system, impact_velocity=-0.5, duration=0.05, time_step=1e-5)
    up = free_fall(system, impact_velocity=0.5, duration=0.05, time_step=1e-5)
    assert up.deflection[0, 0, 1] > 0 > down.deflection[0, 0, 1]
    assert np.allclose(up.deflection, -down.deflection, rtol=0, atol=1e-9 * np.abs(down.deflection).max())


def test_simulate_refuses_a_3d_batch_of_initial_velocities():
    time = np.linspace(0.0, 0.01, 11)
    for velocity, shape in ((np.zeros((2, 1, 1)), "(2, 1, 1)"),):
        with pytest.raises(SimulationError, match=re.escape(f"initial_velocity: found shape {shape}")):
            simulate(library.get("system_a1_symmetric"), time, initial_velocity=velocity)


@pytest.mark.parametrize("name", ["system_a1_asymmetric", "hybrid_asymmetric"])
def test_a_point_gives_the_same_bits_alone_and_in_any_batch(name):
    """Each point's convergence tests scale with its own base acceleration. They scaled with
    the batch's largest, so a 100 Hz, 1 cm point beside an 8 Hz, 2 mm one loosened the latter's
    Newton tolerance and moved its harmonics (by 1.3e-16 m on the wire rope, measured): a
    map's point differed from the same point run alone. Now the bits are the same alone, in a
    batch, first or last, and on any number of workers; the same for time runs sharing a batch
    with a run 1000x louder."""
    system = library.get(name)
    alone = harmonic_response(system, 8.0, 2e-3, workers=1)
    for freq, amplitude, index in (([8.0, 100.0], [2e-3, 1e-2], 0), ([100.0, 1.0, 8.0], [1e-2, 1e-5, 2e-3], 2)):
        for workers in (1, 2):
            batch = harmonic_response(system, freq, amplitude, workers=workers, chunk_size=1)
            assert np.array_equal(batch.coefficients[index], alone.coefficients[0])
            assert np.array_equal(batch.deflection_coefficients[index], alone.deflection_coefficients[0])
            assert batch.periods[index] == alone.periods[0]
    time = np.arange(4001) * 2.5e-4
    quiet = 5.0 * np.sin(2.0 * np.pi * 7.0 * time) * np.exp(-time)
    single = simulate(system, time, base_acceleration=quiet[None], workers=1)
    paired = simulate(system, time, base_acceleration=np.vstack([1e3 * quiet[::-1], quiet]), workers=1)
    assert np.array_equal(paired.acceleration[1], single.acceleration[0])


def test_a_stiff_bouc_wen_law_settles_at_the_default_step():
    """z relaxing over 1 / (beta + gamma) = 1e-5 m of deflection: four fixed Runge-Kutta
    sub-steps of a 128-step period at 12 Hz, 3 mm covered about 5.6 relaxation lengths each,
    past the explicit scheme's stability (2.8), and the point never settled ("not settled after
    4000 periods"; from the linear start a failed Newton iteration), while 256 steps settled.
    The sub-steps now follow the relaxation length (idkit.models.laws.boucwen_substeps): the
    default settles, and its first harmonic is within the integrator's own O(h^2) error of a
    1024-step run (6e-4 measured at 128 steps by Richardson from 128/256; bound 2e-3)."""
    from idkit.models import BoucWenModel

    system = SDOFSystem(1.0, BoucWenModel(k1=2000, k2=0, k3=1e6, alpha=3000, beta=5e4, gamma=5e4, n=1,
                                          c_visc=2.0))
    default = harmonic_response(system, 12.0, 3e-3, tolerance=1e-6)
    fine = harmonic_response(system, 12.0, 3e-3, tolerance=1e-6, steps_per_period=1024)
    assert default.reasons == ("ok",) and fine.reasons == ("ok",)
    assert abs(default.hosidf(1)[0] / fine.hosidf(1)[0] - 1) < 2e-3


@pytest.mark.parametrize("freq", [-1.0, 0.0, float("inf"), float("nan")])
def test_default_steps_per_period_refuses_a_frequency_that_is_not_one(freq):
    # -1 Hz and inf Hz were given 128 steps a period
    from idkit.simulate import default_steps_per_period

    with pytest.raises(SimulationError, match="freq: found"):
        default_steps_per_period(library.get("system_b1_medium"), [5.0, freq])




def test_a_subnormal_amplitude_is_refused_not_answered_with_inf():
    # 1e-310 m returned |H1| = inf with the reason "ok"; 1e-306 m (normal) is a linear answer
    system = library.get("system_b1_medium")
    normal = harmonic_response(system, 5.0, 1e-306)
    # a linear system: the same |H1| as at 1 mm, to round-off of the scaled run
    reference = harmonic_response(system, 5.0, 1e-3)
    assert normal.reasons == ("ok",) and np.isclose(normal.hosidf(1)[0], reference.hosidf(1)[0], rtol=1e-9)
    with pytest.raises(SimulationError,
                       match=r"amplitude: found \[1.e-310\], expected finite amplitudes >= 2.23e-308 m \(positive and"):
        harmonic_response(system, 5.0, 1e-310)
