"""Benchmark: harmonic maps against their kernel floor and against solve_ivp, one core each.

    python bench/bench_simulator.py [--blocks F A] [--repeat R] [--skip-compile]

Run from the repository (``PYTHONPATH=.`` to time the working tree). One BLAS/OpenMP
thread and ``IDKIT_WORKERS=1`` are set before numpy is imported. Every time is printed as min
and median over ``--repeat`` repetitions (wall clock, ``time.perf_counter``, and CPU time of the
process; the machine may be shared, so the min is the figure to compare, the median shows the
spread).

1. Maps (``harmonic_map``: points chained up the amplitude axis, batched Newton on the period map
   where 48 periods do not settle, every settled orbit classified by its Floquet multipliers over
   one period, the unstable ones carried to a stable orbit): the standard map (SPEC hybrid asymmetric,
   ``library.get("hybrid_asymmetric")``, 50 frequencies 1-100 Hz log x 30 amplitudes
   1e-5 - 1e-2 m, harmonics 1-3 and 1/2, steady state 1e-3) and the Table A.1 asymmetric wire
   rope map on the same grid, on 1 and 2 workers. Beside the wall time: periods per point, the
   steps taken (counted during one map: plain ones of the time runs and windows, tangent ones with
   the propagated Jacobian, of the classification and Newton, and the periods run with it, one
   eigenvalue problem each) and the kernel floor, steps x ns per step + eigenvalue problems x us
   each, measured on the same points (the plain step: the slope of fixed 8- and 24-period runs; the
   tangent step: one period with the Jacobian from the linear start, the step included, the grid's
   points in frequency-major order as the map batches them, so that members of one frequency run
   two by two as in the map; the eigenvalues: ``numpy.linalg.eigvals`` of that batch's monodromy
   matrices).
2. solve_ivp over the whole map, one core: ``harmonic_reference`` (BDF, rtol 1e-6, tanh
   smoothing 1e-4) from rest (its only start) for the periods the map spent at the point. The
   grid is cut into ``--blocks`` (default 5 x 3: frequency decades' fifths, amplitude thirds);
   the middle point of each block is run, and the block's periods are charged at its sample's
   seconds per period (solve_ivp's cost per period grows with frequency and slip). The sum
   stands for solve_ivp over the whole map (same points, same periods), against the 1-worker
   map's CPU time (on a shared machine CPU time is the one-core figure; wall time counts the
   other processes' turns).
3. Kernel compile time: the first call of each simulation entry point in a fresh
   process whose numba cache (``NUMBA_CACHE_DIR`` and ``IDKIT_CACHE_DIR``) is an empty temporary folder, minus
   the same call repeated (warm).

Nothing here is asserted; the numbers go in docs/periodic.md (maps) and docs/simulator.md.
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
from idkit.responses.harmonic_map import harmonic_map
maps_module = sys.modules["idkit.responses.harmonic_map"]
from idkit.responses.periodic import PeriodMap
from idkit.simulate import default_steps_per_period, harmonic_response
from idkit.simulate.reference import harmonic_reference

_IMPORT_SECONDS = time.perf_counter() - _START

SYSTEM = "hybrid_asymmetric"
ROPE = "system_a1_asymmetric"
REFERENCE_OPTIONS = {"rtol": 1e-6, "smoothing": 1e-4}
FREQ_AXIS = np.logspace(0, 2, 50)
AMPLITUDE_AXIS = np.logspace(-5, -2, 30)


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


def grid():
    return tuple(values.ravel() for values in np.meshgrid(FREQ_AXIS, AMPLITUDE_AXIS, indexing="ij"))


def the_map(system, workers):
    return harmonic_map(system, FREQ_AXIS, AMPLITUDE_AXIS, n_harmonics=3, tolerance=1e-3, workers=workers)


def counted_steps(system):
    """One map on one worker, counting the steps it integrates: ``(plain, tangent, tangent periods)``,
    the plain ones of the time runs (``harmonic_response``) and of the period map without the
    Jacobian, the tangent ones with it (classification and Newton), and the member periods run with
    it (one monodromy matrix, one eigenvalue problem each)."""
    counts = {"plain": 0, "tangent": 0, "periods": 0}
    run, response = PeriodMap.run, maps_module.harmonic_response

    def counting_run(self, freq, amplitude, states, steps_per_period, *, n_periods=None, n_record=0,
                     with_tangent=False):
        batch = np.atleast_2d(states).shape[0]
        periods = self.periods if n_periods is None else int(n_periods)
        steps = int(np.sum(np.broadcast_to(steps_per_period, (batch,))))
        counts["tangent" if with_tangent else "plain"] += steps * periods
        counts["periods"] += batch if with_tangent else 0
        return run(self, freq, amplitude, states, steps_per_period, n_periods=n_periods, n_record=n_record,
                   with_tangent=with_tangent)

    def counting_response(*args, **kwargs):
        result = response(*args, **kwargs)
        counts["plain"] += int(np.sum(result.periods * result.steps_per_period))
        return result

    PeriodMap.run, maps_module.harmonic_response = counting_run, counting_response
    try:
        the_map(system, 1)
    finally:
        PeriodMap.run, maps_module.harmonic_response = run, response
    return counts["plain"], counts["tangent"], counts["periods"]


def floor(system, result, repeat):
    """Steps of the map's plain and tangent periods and its eigenvalue problems (counted), ns per
    step of each kind and us per eigenvalue problem."""
    freq, amplitude = grid()
    steps = default_steps_per_period(system, freq)
    run_steps, tangent_steps, tangent_periods = (float(count) for count in counted_steps(system))
    fixed = {}
    for periods in (8, 24):
        _, _, cpus = repeated(lambda periods=periods: harmonic_response(
            system, freq, amplitude, min_periods=periods, max_periods=periods, start="linear", workers=1), repeat)
        fixed[periods] = min(cpus)
    ns_step = (fixed[24] - fixed[8]) / (16 * float(steps.sum())) * 1e9
    one = PeriodMap(system, 1)
    states = one.linear_guess(freq, amplitude)
    (_, _, tangents), _, cpus = repeated(lambda: one.run(freq, amplitude, states, steps, with_tangent=True), repeat)
    ns_tangent = min(cpus) / float(steps.sum()) * 1e9
    matrices = tangents[:, one._tangent_rows]
    _, _, cpus = repeated(lambda: np.linalg.eigvals(matrices), repeat)
    us_eigen = min(cpus) / freq.size * 1e6
    return run_steps, ns_step, tangent_steps, ns_tangent, tangent_periods, us_eigen


def map_rows(name, repeat):
    system = library.get(name)
    print(f"\n{name}: {library.describe(name)}")
    the_map(system, 1)  # warm-up: compilation (or the on-disk numba cache)
    print(f"{'workers':>8s} {'wall min':>9s} {'median':>9s} {'CPU min':>9s} {'median':>9s}  settled  stability")
    results = {}
    for workers in (1, 2):
        result, walls, cpus = repeated(lambda workers=workers: the_map(system, workers), repeat)
        results[workers] = (result, walls, cpus)
        kinds = ", ".join(f"{kind} {int((result.stability == kind).sum())}" for kind in np.unique(result.stability))
        print(f"{workers:8d} {min_median(walls)} {min_median(cpus)}  {int(result.valid.sum())}/1500  {kinds}")
    result = results[1][0]
    run_steps, ns_step, tangent_steps, ns_tangent, tangent_periods, us_eigen = floor(system, result, repeat)
    plain_seconds, tangent_seconds = run_steps * ns_step * 1e-9, tangent_steps * ns_tangent * 1e-9
    eigen_seconds = tangent_periods * us_eigen * 1e-6
    kernel_floor = plain_seconds + tangent_seconds + eigen_seconds
    steps = default_steps_per_period(system, grid()[0])
    print(f"  periods per point: mean {result.periods.mean():.1f}, median {np.median(result.periods):.0f}, "
          f"max {result.periods.max():.0f}; of them with the propagated Jacobian (classification, Newton): "
          f"{tangent_steps / steps.sum():.2f} a point; {int(result.shooting.sum())} points shot (Newton or "
          "per-point shooting)")
    print(f"  kernel floor: plain {run_steps:.3g} steps x {ns_step:.1f} ns = {plain_seconds:.4f} s "
          f"+ tangent {tangent_steps:.3g} steps x {ns_tangent:.1f} ns (the step and its tangent) = "
          f"{tangent_seconds:.4f} s + eigenvalues {tangent_periods:.0f} x {us_eigen:.1f} us = {eigen_seconds:.4f} s; "
          f"{kernel_floor:.4f} s of one core")
    for workers in (1, 2):
        walls, cpus = results[workers][1], results[workers][2]
        print(f"  {workers} worker(s): wall min {min(walls):.4f} s = {min(walls) / (kernel_floor / workers):.2f} x "
              f"the floor over {workers} core(s); CPU min {min(cpus):.4f} s = {min(cpus) / kernel_floor:.2f} x "
              "the floor")
    return system, result, min(results[1][2])


def reference_ratio(system, result, map_seconds, blocks):
    """solve_ivp over the whole map, one core: the grid cut into ``blocks`` (frequency x amplitude)
    blocks, the middle point of each run by solve_ivp for the periods the map spent there, and each
    block's periods charged at its sample's seconds per period."""
    periods = result.periods
    freq_blocks = np.array_split(np.arange(FREQ_AXIS.size), blocks[0])
    amplitude_blocks = np.array_split(np.arange(AMPLITUDE_AXIS.size), blocks[1])
    estimate, sampled_seconds, sampled_periods = 0.0, 0.0, 0
    # warm-up, not timed: the first call pays for imports and first-use set-up (2.9 s against
    # 0.2 s for the same 6 periods at the next amplitude)
    harmonic_reference(system, float(FREQ_AXIS[0]), float(AMPLITUDE_AXIS[0]), n_periods=4, **REFERENCE_OPTIONS)
    print(f"{'f [Hz]':>8s} {'A [m]':>8s} {'periods':>7s} {'ivp [s]':>8s} {'block periods':>13s}")
    for rows in freq_blocks:
        for columns in amplitude_blocks:
            row, column = rows[rows.size // 2], columns[columns.size // 2]
            n_periods = int(max(4, periods[row, column] + periods[row, column] % 2))
            start = time.process_time()
            harmonic_reference(system, float(FREQ_AXIS[row]), float(AMPLITUDE_AXIS[column]), n_periods=n_periods,
                               **REFERENCE_OPTIONS)
            elapsed = time.process_time() - start
            block_periods = float(periods[np.ix_(rows, columns)].sum())
            estimate += elapsed / n_periods * block_periods
            sampled_seconds += elapsed
            sampled_periods += n_periods
            print(f"{FREQ_AXIS[row]:8.3f} {AMPLITUDE_AXIS[column]:8.1e} {n_periods:7d} {elapsed:8.3f} {block_periods:13.0f}")
    print(f"  solve_ivp: {sampled_seconds / sampled_periods * 1e3:.2f} ms per period over the {blocks[0] * blocks[1]} "
          f"samples; the map's {periods.sum():.0f} periods, each block at its sample's rate -> {estimate:.1f} s of "
          "one core")
    print(f"  ratio to the 1-worker map ({map_seconds:.4f} s of CPU, min): {estimate / map_seconds:.0f}x")


def compile_times():
    """Run this script's ``--compile-child`` in a fresh process with an empty numba cache."""
    with tempfile.TemporaryDirectory(prefix="idkit-numba-cache-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, IDKIT_CACHE_DIR=cache)
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
    parser.add_argument("--blocks", type=int, nargs=2, default=(5, 3), metavar=("FREQ", "AMPLITUDE"),
                        help="solve_ivp sample: the middle point of each of FREQ x AMPLITUDE blocks of the grid")
    parser.add_argument("--repeat", type=int, default=5, help="repetitions of every timing")
    parser.add_argument("--skip-compile", action="store_true", help="skip the fresh-process compile timing")
    parser.add_argument("--compile-child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.compile_child:
        compile_child()
        return

    print(f"[1] maps 50 x 30 = 1500 points, harmonics 1-3 and 1/2, steady state 1e-3, {args.repeat} repetitions "
          "(seconds)")
    system, standard, seconds = map_rows(SYSTEM, args.repeat)
    map_rows(ROPE, args.repeat)

    print(f"\n[2] solve_ivp over the standard map, one core, {args.blocks[0]} x {args.blocks[1]} blocks")
    reference_ratio(system, standard, seconds, args.blocks)

    if not args.skip_compile:
        print("\n[3] compile time, fresh process, empty numba cache (first call minus second call; s)")
        for name, seconds in compile_times().items():
            print(f"  {name:<42s} {seconds:7.2f}")


if __name__ == "__main__":
    main()
