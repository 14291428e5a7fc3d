"""Benchmark: the fast batched integrator against the solve_ivp reference, in one run.

    python bench/bench_simulator.py [--sample N] [--workers W]

Prints (issue 2) the wall time of the hybrid asymmetric grid, 20 frequencies
(1-100 Hz, log) x 10 amplitudes (1e-5..1e-2 m) run to steady state (tolerance
1e-3); the solve_ivp reference (BDF, tanh-smoothed, rtol 1e-6) timed on a sample
of those points for the same number of periods the fast run needed; the
per-point ratio and the largest first-harmonic deviation between them. Then
(issue 6) the standard 50 x 30 map and a 100-drop shock sweep. Ratios are
measured in this process on this machine; nothing here is asserted.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from idkit.models import library
from idkit.simulate import free_fall, harmonic_response
from idkit.simulate.reference import harmonic_reference


def timed(function, *args, **kwargs):
    start = time.perf_counter()
    value = function(*args, **kwargs)
    return value, time.perf_counter() - start


def reference_sample(system, fast, freq, amplitude, rng, size):
    """Time solve_ivp on a random sample of the grid for the periods the fast run needed.

    Returns the mean seconds per point, the seconds per simulated period and the
    largest |H1 fast / H1 reference - 1|.
    """
    sample = np.sort(rng.choice(freq.size, size=min(size, freq.size), replace=False))
    seconds, deviations, simulated_periods = [], [], 0
    print(f"  solve_ivp (BDF, rtol 1e-6, tanh smoothing 1e-4) on {sample.size} sampled points:")
    for index in sample:
        periods = int(max(8, fast.periods[index] + fast.periods[index] % 2))
        reference, elapsed = timed(harmonic_reference, system, float(freq[index]), float(amplitude[index]),
                                   n_periods=periods, rtol=1e-6, smoothing=1e-4)
        deviation = abs(fast.hosidf(1)[index] / reference.hosidf(1) - 1)
        seconds.append(elapsed)
        deviations.append(deviation)
        simulated_periods += periods
        print(f"    f = {freq[index]:7.3f} Hz, A = {amplitude[index]:.1e} m, {periods:4d} periods: "
              f"{elapsed:7.3f} s, |H1 fast/ref - 1| = {deviation:.2e}")
    return float(np.mean(seconds)), float(np.sum(seconds)) / simulated_periods, float(max(deviations))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sample", type=int, default=10, help="grid points timed with solve_ivp")
    parser.add_argument("--workers", type=int, default=None, help="threads for the fast integrator")
    args = parser.parse_args()

    system = library.get("hybrid_asymmetric")
    print(f"system: {library.describe('hybrid_asymmetric')}")
    harmonic_response(system, [5.0], [1e-3])  # compile (cached on disk after the first run)
    free_fall(system, impact_velocity=[-0.1], duration=0.01, time_step=1e-4)

    freq_axis = np.logspace(0, 2, 20)
    amplitude_axis = np.logspace(-5, -2, 10)
    freq, amplitude = (grid.ravel() for grid in np.meshgrid(freq_axis, amplitude_axis, indexing="ij"))
    fast, fast_time = timed(harmonic_response, system, freq, amplitude, tolerance=1e-3, workers=args.workers)
    per_point_fast = fast_time / freq.size
    print(f"\n[issue 2] grid 20 x 10 = {freq.size} points to steady state (tol 1e-3): "
          f"{fast_time:.3f} s wall, {per_point_fast * 1e3:.3f} ms per point; "
          f"converged {int(fast.converged.sum())}/{freq.size}, flagged {int((fast.flags != 0).sum())}, "
          f"periods {int(fast.periods.min())}-{int(fast.periods.max())}")

    rng = np.random.default_rng(2026)
    per_point_reference, per_period_reference, worst = reference_sample(system, fast, freq, amplitude, rng,
                                                                        args.sample)
    per_period_fast = fast_time / fast.periods.sum()
    print(f"  per point: fast {per_point_fast * 1e3:.3f} ms, solve_ivp {per_point_reference * 1e3:.1f} ms, "
          f"ratio {per_point_reference / per_point_fast:.0f}x (target >= 1000x)")
    print(f"  per simulated period (removes the bias of which points were sampled): fast "
          f"{per_period_fast * 1e6:.1f} us, solve_ivp {per_period_reference * 1e3:.2f} ms, "
          f"ratio {per_period_reference / per_period_fast:.0f}x")
    print(f"  largest first-harmonic deviation: {worst * 100:.3f} % (target <= 1 %)")

    freq_axis = np.logspace(0, 2, 50)
    amplitude_axis = np.logspace(-5, -2, 30)
    freq, amplitude = (grid.ravel() for grid in np.meshgrid(freq_axis, amplitude_axis, indexing="ij"))
    standard, standard_time = timed(harmonic_response, system, freq, amplitude, n_harmonics=3, tolerance=1e-3,
                                    workers=args.workers)
    print(f"\n[issue 6] standard map 50 x 30 = {freq.size} points, harmonics 1-3 and 1/2, steady state 1e-3: "
          f"{standard_time:.3f} s wall (target <= 2 s), converged {int(standard.converged.sum())}/{freq.size}")
    per_point_map = standard_time / freq.size
    map_reference, map_per_period, map_worst = reference_sample(system, standard, freq, amplitude, rng,
                                                                args.sample)
    print(f"  per point: fast {per_point_map * 1e3:.3f} ms, solve_ivp {map_reference * 1e3:.1f} ms, "
          f"ratio {map_reference / per_point_map:.0f}x (target >= 1000x); per simulated period "
          f"{map_per_period / (standard_time / standard.periods.sum()):.0f}x; "
          f"largest first-harmonic deviation {map_worst * 100:.3f} % (target <= 1 %)")
    speeds = np.linspace(0.01, 1.0, 100)
    drops, drop_time = timed(free_fall, system, impact_velocity=-speeds, duration=0.5, time_step=5e-5,
                             record_every=4, workers=args.workers)
    print(f"  100-drop shock sweep (0.5 s each, step 50 us): {drop_time:.3f} s (target <= 0.5 s), "
          f"flagged {int((drops.flags != 0).sum())}")


if __name__ == "__main__":
    main()
