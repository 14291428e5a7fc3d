"""Force-driven Bouc-Wen oscillator: against solve_ivp, linear theory and the benchmark's own data."""

import bisect
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.interpolate import CubicSpline

from idkit.datasets import read_boucwen_benchmark, realdata_dir
from idkit.models import BoucWenModel, SDOFSystem
from idkit.simulate import (
    BaseMotion,
    benchmark_truth,
    simulate,
    simulate_force_driven,
    solve_ivp_reference,
)

RATE_HZ = 750.0
# solve_ivp (DOP853) settings of the independent reference: rtol 1e-10 with absolute
# tolerances 1e-12 of the state scales (1 mm, 0.3 m/s, 100 N); its own error is then
# < 1e-8 of the peak displacement, far below the tolerance under test.
IVP_RTOL = 1e-10
# RK4 at 20 steps per sample (the benchmark's 15 kHz) against the reference: the sgn(x' z)
# switch of the Bouc-Wen law makes the right-hand side kink at every velocity reversal,
# so RK4 converges at about order 2.3 there (measured 3.5e-5 of the peak at 20 steps,
# 7e-6 at 40); 1e-4 of the peak displacement bounds it with margin on any force record.
TOL_RK4_VS_IVP = 1e-4
# Re-simulating the benchmark's true model: its test multisine was designed on the 15 kHz
# grid (band-limited), so band-limited reconstruction reproduces the data to 2.4e-7 m
# RMS (0.04 % of the 6.7e-4 m RMS); 5e-7 m leaves a factor 2 for platforms.
TOL_FLOOR_MULTISINE_M = 5e-7
# The official sine sweep (40 N, 18 -> 52 Hz) is reproduced to 2.5e-6 m RMS whatever the
# force reconstruction (cubic spline or the exact analytic sweep) or step (10..40 per
# sample): a systematic difference at the resonance crossing in the data themselves. It
# stays below the 3.2e-6 m the benchmark's own description quotes as the floor.
TOL_FLOOR_SWEEP_M = 3.2e-6


def _random_force(seed, n_samples, rms_n=50.0):
    """Band-limited (5-150 Hz) random-phase multisine, as in the benchmark."""
    rng = np.random.default_rng(seed)
    spectrum = np.zeros(n_samples // 2 + 1, dtype=complex)
    freq = np.fft.rfftfreq(n_samples, 1.0 / RATE_HZ)
    band = (freq >= 5.0) & (freq <= 150.0)
    spectrum[band] = np.exp(2j * np.pi * rng.random(np.count_nonzero(band)))
    force = np.fft.irfft(spectrum, n_samples)
    return rms_n * force / np.std(force)


def _ivp_reference(model, mass, force):
    """DOP853 on the same cubic spline of the force. The right-hand side runs in Python
    floats (the spline's own piecewise coefficients, the Bouc-Wen law written out): the
    same equations as CubicSpline and numpy scalars would evaluate, at a fraction of the
    per-call cost over the ~7e4 calls the tolerance asks for."""
    spline = CubicSpline(np.arange(force.size) / RATE_HZ, force)
    knots, coefficients, last = spline.x.tolist(), spline.c.T.tolist(), force.size - 2
    k1, k2, k3, alpha, beta, gamma, n, c_visc = (float(getattr(model, name)) for name in
                                                 ("k1", "k2", "k3", "alpha", "beta", "gamma", "n", "c_visc"))
    c_log_b = float(model.c) * math.log(model.b)

    def rates(t, state):
        x, v, z = state.tolist()
        piece = min(bisect.bisect_right(knots, t) - 1, last)
        a3, a2, a1, a0 = coefficients[piece]
        step = t - knots[piece]
        driving = ((a3 * step + a2) * step + a1) * step + a0
        sign = 0.0 if v * z == 0.0 else math.copysign(1.0, v * z)
        z_rate = v * (alpha - (gamma + beta * sign) * abs(z) ** n)
        elastic = x * (k1 + k2 * abs(x) + k3 * x * x)
        restoring = math.exp(c_log_b * x) * (elastic + z) + c_visc * v
        return [v, (driving - restoring) / mass, z_rate]

    time = np.arange(force.size) / RATE_HZ
    solution = solve_ivp(rates, (0.0, time[-1]), [0.0, 0.0, 0.0], method="DOP853", t_eval=time, rtol=IVP_RTOL,
                         atol=[1e-15, 3e-13, 1e-10])
    assert solution.success
    return solution.y[0]


@pytest.mark.parametrize("seed", [0, 1])
@pytest.mark.parametrize("case", ["benchmark", "full"])
def test_rk4_matches_solve_ivp_on_the_same_force(seed, case):
    model, mass = benchmark_truth()
    if case == "full":            # softening law, n != 1, polynomial and asymmetric terms
        model = BoucWenModel(k1=3e4, k2=2e6, k3=-1e8, alpha=4e4, beta=900.0, gamma=300.0, n=1.5, b=math.e,
                             c=30.0, c_visc=8.0)
    force = _random_force(seed, 600)
    fast = simulate_force_driven(model, mass, force, RATE_HZ, interpolation="cubic")
    reference = _ivp_reference(model, mass, force)
    assert fast.success
    peak = np.max(np.abs(reference))
    assert np.max(np.abs(fast.displacement - reference)) < TOL_RK4_VS_IVP * peak


def test_base_motion_is_the_force_driven_system_in_relative_coordinates():
    """Base displacement X sin(w t): the deflection r = x - x_b obeys m r'' + F(r, r', z) = m w^2 X sin(w t),
    starting with r' = -w X. Checks the hardening law through idkit's other integrator, the
    average-acceleration Newmark kernel of simulate() (second order: 2.6e-5 of the peak at
    30 kHz, 2.9e-6 at 120 kHz, so it converges to the RK4 answer); 1e-4 bounds the 30 kHz run."""
    model, mass = benchmark_truth()
    amplitude, freq = 1e-3, 30.0
    omega = 2 * np.pi * freq
    fine = np.arange(15000) / 30000.0
    base_run = simulate(SDOFSystem(mass=mass, isolator=model), fine, base=BaseMotion.harmonic(freq, amplitude))
    deflection = np.asarray(base_run.deflection).ravel()[::10]
    samples = fine[::10]
    relative = simulate_force_driven(model, mass, mass * omega ** 2 * amplitude * np.sin(omega * samples), 3000.0,
                                     substeps=10, initial_velocity=-omega * amplitude)
    assert np.max(np.abs(deflection - relative.displacement)) < 1e-4 * np.max(np.abs(relative.displacement))


def test_smoothed_reference_handles_the_hardening_law():
    """solve_ivp_reference (tanh-smoothed signs, BDF) on the benchmark's hardening law with base
    motion, against the force-driven run in relative coordinates: measured 3.7e-6 of the peak
    (smoothing 1e-4, rtol 1e-8); 2e-5 allows the smoothing error to double."""
    model, mass = benchmark_truth()
    amplitude, freq = 1e-3, 30.0
    omega = 2 * np.pi * freq
    samples = np.arange(1500) / 3000.0
    reference = solve_ivp_reference(SDOFSystem(mass=mass, isolator=model), samples,
                                    base=BaseMotion.harmonic(freq, amplitude), smoothing=1e-4, rtol=1e-8)
    relative = simulate_force_driven(model, mass, mass * omega ** 2 * amplitude * np.sin(omega * samples), 3000.0,
                                     substeps=10, initial_velocity=-omega * amplitude)
    deflection = np.asarray(reference.deflection).ravel()
    assert np.max(np.abs(deflection - relative.displacement)) < 2e-5 * np.max(np.abs(relative.displacement))


def test_linear_limit_matches_the_frequency_response():
    """beta = gamma = 0: z = alpha x, so the steady state of a periodic force is X = U / (k - m w^2 + i c w)."""
    model = BoucWenModel(k1=3e4, k2=0.0, k3=0.0, alpha=2e4, beta=0.0, gamma=1e-9, n=1.0, c_visc=10.0)
    mass = 2.0
    n_period = 750
    force = np.tile(_random_force(3, n_period), 8)             # 8 s; damping time 1/(zeta w) = 0.2 s
    response = simulate_force_driven(model, mass, force, RATE_HZ, interpolation="fourier")
    omega = 2 * np.pi * np.fft.rfftfreq(n_period, 1.0 / RATE_HZ)
    expected = np.fft.irfft(np.fft.rfft(force[:n_period]) / (5e4 - mass * omega ** 2 + 1j * 10.0 * omega),
                            n_period)
    # gamma = 1e-9 1/m leaves z = alpha x to 1e-9 * 1e-3 m relative; the tolerance is the
    # RK4 error (< 1e-6 of the peak for this smooth linear system) with margin.
    assert np.max(np.abs(response.displacement[-n_period:] - expected)) < 1e-5 * np.max(np.abs(expected))


def test_runaway_is_reported_not_returned_as_numbers():
    model = BoucWenModel(k1=1e3, k2=0.0, k3=0.0, alpha=5e4, beta=800.0, gamma=-3000.0, n=2.0)
    assert model.escape_deflection < 1e-3
    response = simulate_force_driven(model, 2.0, np.full(2000, 500.0), RATE_HZ)
    assert not response.success and "sample" in response.reasons[0]
    assert np.isnan(response.displacement[-1])


def _benchmark():
    folder = realdata_dir("boucwen_benchmark")
    if folder is None:
        pytest.skip("real data folder ../shared/realdata/boucwen_benchmark is absent (set IDKIT_REALDATA)")
    return read_boucwen_benchmark(folder / "bouc-wen.mat")


def test_true_model_reproduces_the_official_test_multisine():
    data = _benchmark()
    model, mass = benchmark_truth()
    periods = np.tile(data.test_multisine_force, 3)          # the record is one steady-state period
    response = simulate_force_driven(model, mass, periods, data.sample_rate_hz, interpolation="fourier")
    error = response.displacement[-data.test_multisine_force.size:] - data.test_multisine_displacement
    assert np.sqrt(np.mean(error ** 2)) < TOL_FLOOR_MULTISINE_M


def test_true_model_reproduces_the_official_test_sweep():
    data = _benchmark()
    model, mass = benchmark_truth()
    response = simulate_force_driven(model, mass, data.test_sinesweep_force, data.sample_rate_hz)
    error = response.displacement - data.test_sinesweep_displacement
    assert np.sqrt(np.mean(error ** 2)) < TOL_FLOOR_SWEEP_M


def test_held_force_lags_half_a_sample():
    """Why a zero-order-hold re-simulation misses the benchmark data by 1e-4 m RMS."""
    data = _benchmark()
    model, mass = benchmark_truth()
    periods = np.tile(data.test_multisine_force, 3)
    held = simulate_force_driven(model, mass, periods, data.sample_rate_hz, interpolation="hold")
    error = held.displacement[-data.test_multisine_force.size:] - data.test_multisine_displacement
    assert np.sqrt(np.mean(error ** 2)) > 100 * TOL_FLOOR_MULTISINE_M
