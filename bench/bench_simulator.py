"""Benchmark: idkit's compiled integrator against solve_ivp, both sides on one core.

    python bench/bench_simulator.py [--sample N] [--repeat R] [--skip-compile]

Run from the repository (``PYTHONPATH=.`` to time the working tree). One BLAS/OpenMP
thread and ``IDKIT_WORKERS=1`` are set before numpy is imported; idkit runs with
``workers=1``, solve_ivp in the same process. Every time is printed as min and median
over ``--repeat`` repetitions (wall clock, ``time.perf_counter``; the machine may be
shared, so the min is the figure to compare, the median shows the spread).

1. Per point, SPEC hybrid asymmetric (``library.get("hybrid_asymmetric")``): the
   standard map's steady-state run gives the periods each point needs; on a seeded
   sample of its points, idkit (``harmonic_response`` with ``min_periods = max_periods``
   = those periods, one point per call) and ``harmonic_reference`` (solve_ivp BDF,
   rtol 1e-6, tanh smoothing 1e-4) simulate exactly the same periods from rest, and
   their first harmonics are compared (same transient, same analysis window).
2. The standard map (50 frequencies 1-100 Hz log x 30 amplitudes 1e-5-1e-2 m, harmonics
   1-3 and 1/2, steady state 1e-3) on 1 and 2 workers: wall and CPU time.
3. Kernel compile time: the first call of each simulation entry point in a fresh
   process whose numba cache (``NUMBA_CACHE_DIR``) is an empty temporary folder, minus
   the same call repeated (warm).

Nothing here is asserted; the numbers go in docs/simulator.md.
"""

from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_name] = "1"
os.environ["IDKIT_WORKERS"] = "1"

import time

_START = time.perf_counter()  # the child of the compile timing reports the import time

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from idkit.models import library
from idkit.simulate import harmonic_response
from idkit.simulate.reference import harmonic_reference

_IMPORT_SECONDS = time.perf_counter() - _START

SYSTEM = "hybrid_asymmetric"
REFERENCE_OPTIONS = {"rtol": 1e-6, "smoothing": 1e-4}


def repeated(function, repeat):
    """(last value, wall seconds list, CPU seconds list) of ``repeat`` calls."""
    walls, cpus, value = [], [], None
    for _ in range(repeat):
        wall, cpu = time.perf_counter(), time.process_time()
        value = function()
        walls.append(time.perf_counter() - wall)
        cpus.append(time.process_time() - cpu)
    return value, walls, cpus


def min_median(values):
    return f"{min(values):9.4f} {statistics.median(values):9.4f}"


def standard_grid():
    freq_axis = np.logspace(0, 2, 50)
    amplitude_axis = np.logspace(-5, -2, 30)
    return tuple(grid.ravel() for grid in np.meshgrid(freq_axis, amplitude_axis, indexing="ij"))


def standard_map(system, workers):
    freq, amplitude = standard_grid()
    return harmonic_response(system, freq, amplitude, n_harmonics=3, tolerance=1e-3, workers=workers)


def per_point(system, standard, sample, repeat):
    """Both sides on the sampled points for the same periods; returns the table rows."""
    freq, amplitude = standard_grid()
    rows = []
    for index in sample:
        f, a = float(freq[index]), float(amplitude[index])
        periods = int(max(8, standard.periods[index] + standard.periods[index] % 2))
        fast, fast_walls, _ = repeated(
            lambda f=f, a=a, periods=periods: harmonic_response(
                system, [f], [a], n_harmonics=3, tolerance=1e-3, min_periods=periods, max_periods=periods,
                workers=1), repeat)
        assert int(fast.periods[0]) == periods  # the same periods as the reference
        reference, reference_walls, _ = repeated(
            lambda f=f, a=a, periods=periods: harmonic_reference(system, f, a, n_periods=periods,
                                                                 **REFERENCE_OPTIONS), max(1, repeat // 2))
        deviation = abs(fast.hosidf(1)[0] / reference.hosidf(1) - 1)
        rows.append((f, a, periods, fast_walls, reference_walls, deviation))
    return rows


def compile_times():
    """Run this script's ``--compile-child`` in a fresh process with an empty numba cache."""
    with tempfile.TemporaryDirectory(prefix="idkit-numba-cache-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        out = subprocess.run([sys.executable, str(Path(__file__).resolve()), "--compile-child"], env=env,
                             capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def compile_child():
    """First and second call of each entry point (printed as JSON); run in a fresh process."""
    from idkit.simulate import free_fall, simulate
    timings = {"import numpy, idkit.models, idkit.simulate": _IMPORT_SECONDS}
    hybrid = library.get(SYSTEM)
    sdof = library.get("system_a1_asymmetric")
    time_grid = np.arange(801) / 800.0
    drive = np.sin(2 * np.pi * 5 * time_grid)[None, :]
    calls = {
        "harmonic_response (hybrid)": lambda: harmonic_response(hybrid, [5.0], [1e-3], workers=1),
        "free_fall (hybrid)": lambda: free_fall(hybrid, impact_velocity=[-0.1], duration=0.01, time_step=1e-4,
                                                workers=1),
        "simulate, base acceleration (hybrid)": lambda: simulate(hybrid, time_grid, base_acceleration=drive,
                                                                 workers=1),
    }
    calls["harmonic_response (SDOF wire rope A.1)"] = lambda: harmonic_response(sdof, [5.0], [1e-3], workers=1)
    for name, call in calls.items():
        first = time.perf_counter()
        call()
        first = time.perf_counter() - first
        second = time.perf_counter()
        call()
        second = time.perf_counter() - second
        timings[name] = first - second
    print(json.dumps(timings))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sample", type=int, default=8, help="map points timed on both sides")
    parser.add_argument("--repeat", type=int, default=5, help="repetitions of every timing")
    parser.add_argument("--seed", type=int, default=2026, help="seed of the point sample")
    parser.add_argument("--skip-compile", action="store_true", help="skip the fresh-process compile timing")
    parser.add_argument("--compile-child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.compile_child:
        compile_child()
        return

    system = library.get(SYSTEM)
    print(f"system: {library.describe(SYSTEM)}")
    standard_map(system, 1)  # warm-up: compilation (or the on-disk numba cache)

    print(f"\n[2] standard map 50 x 30 = 1500 points, harmonics 1-3 and 1/2, steady state 1e-3, "
          f"{args.repeat} repetitions")
    print(f"{'workers':>8s} {'wall min':>9s} {'median':>9s} {'CPU min':>9s} {'median':>9s}  converged")
    maps = {}
    for workers in (1, 2):
        result, walls, cpus = repeated(lambda workers=workers: standard_map(system, workers), args.repeat)
        maps[workers] = result
        print(f"{workers:8d} {min_median(walls)} {min_median(cpus)}  {int(result.converged.sum())}/1500")
    standard = maps[1]

    rng = np.random.default_rng(args.seed)
    sample = np.sort(rng.choice(1500, size=min(args.sample, 1500), replace=False))
    rows = per_point(system, standard, sample, args.repeat)
    print(f"\n[1] per point, one core each, same points and periods from rest (idkit {args.repeat}, "
          f"solve_ivp {max(1, args.repeat // 2)} repetitions; seconds)")
    print(f"{'f [Hz]':>8s} {'A [m]':>8s} {'periods':>7s} {'idkit min':>10s} {'median':>9s} "
          f"{'ivp min':>9s} {'median':>9s} {'ratio':>7s} {'|dH1|':>9s}")
    for f, a, periods, fast_walls, reference_walls, deviation in rows:
        print(f"{f:8.3f} {a:8.1e} {periods:7d} {min(fast_walls):10.5f} {statistics.median(fast_walls):9.5f} "
              f"{min(reference_walls):9.3f} {statistics.median(reference_walls):9.3f} "
              f"{min(reference_walls) / min(fast_walls):7.0f} {deviation:9.2e}")
    fast_total = sum(min(r[3]) for r in rows)
    reference_total = sum(min(r[4]) for r in rows)
    ratios = [min(r[4]) / min(r[3]) for r in rows]
    print(f"  sum over the sample (mins): idkit {fast_total:.4f} s, solve_ivp {reference_total:.2f} s, "
          f"ratio {reference_total / fast_total:.0f}x; per-point ratio min {min(ratios):.0f}x, "
          f"median {statistics.median(ratios):.0f}x, max {max(ratios):.0f}x")
    print(f"  largest first-harmonic deviation idkit vs solve_ivp: {max(r[5] for r in rows) * 100:.3f} %")
    batch_per_point = min(repeated(lambda: standard_map(system, 1), 1)[1]) / 1500
    print(f"  (in the 1-worker map, a point costs {batch_per_point * 1e3:.3f} ms on average: batching spares "
          f"the per-call overhead of the one-point calls above)")

    if not args.skip_compile:
        print("\n[3] compile time, fresh process, empty numba cache (first call minus second call; s)")
        for name, seconds in compile_times().items():
            print(f"  {name:<42s} {seconds:7.2f}")


if __name__ == "__main__":
    main()
