"""Benchmark: a 200-point continuation branch of the SPEC hybrid against the harmonic map, one core.

    IDKIT_WORKERS=1 OMP_NUM_THREADS=1 python bench/bench_continuation.py [--repeat R] [--amplitude A]

The branch (:func:`idkit.responses.continuation.continue_in_frequency`) of the SPEC hybrid
asymmetric system (``library.get("hybrid_asymmetric")``) at a fixed base amplitude (default
1e-3 m) from 1 to 100 Hz with the arclength step capped at ``--max-step`` (0.0375: about 200
points over the range); timed ``--repeat`` times after a warm-up call (compilation excluded), min and
median printed with the number of points and the branch's end reason. Then the standard
map's time integration (``harmonic_response``, steady state 1e-6) at the branch's own
frequencies and amplitude, one worker, timed the same way, and the largest relative
difference of the first harmonic between the two. Nothing is asserted.
"""

from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_name, "1")
os.environ.setdefault("IDKIT_WORKERS", "1")

import argparse
import statistics
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)  # this checkout's idkit

from idkit.models import library  # noqa: E402
from idkit.responses.continuation import continue_in_frequency  # noqa: E402
from idkit.simulate import harmonic_response  # noqa: E402


def timed(function, repeat):
    seconds, value = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        value = function()
        seconds.append(time.perf_counter() - start)
    return value, min(seconds), statistics.median(seconds)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--amplitude", type=float, default=1e-3, help="base displacement amplitude, m")
    parser.add_argument("--max-step", type=float, default=0.0375,
                        help="arclength step cap (0.0375: about 200 points over 1-100 Hz at 1e-3 m)")
    args = parser.parse_args()
    system = library.get("hybrid_asymmetric")

    def branch():
        return continue_in_frequency(system, args.amplitude, (1.0, 100.0), max_step=args.max_step, max_points=1000)

    branch()  # compile / warm up
    result, b_min, b_median = timed(branch, args.repeat)
    print(f"hybrid asymmetric, base amplitude {args.amplitude:g} m, 1-100 Hz, one core, {args.repeat} repetitions")
    print(f"  continuation: {result.freq.size} points over {result.freq.min():.3g}-{result.freq.max():.4g} Hz "
          f"({result.reason}, {int(result.stable.sum())} stable); "
          f"min {b_min:.3f} s, median {b_median:.3f} s, {1e3 * b_min / result.freq.size:.2f} ms a point")

    freq = result.freq
    amplitude = np.full(freq.size, args.amplitude)

    def grid():
        return harmonic_response(system, freq, amplitude, tolerance=1e-6, max_periods=4000, workers=1,
                                 steps_per_period=result.steps_per_period)

    grid()
    response, g_min, g_median = timed(grid, max(1, args.repeat // 2))
    settled = response.converged
    h_branch = result.coefficients[:, 2]  # orders 0, 1/2, 1, ...: the first harmonic
    h_grid = response.coefficients[:, 2]
    deviation = np.abs(np.abs(h_branch[settled]) / np.abs(h_grid[settled]) - 1)
    print(f"  time integration at the same {freq.size} points (steady state 1e-6, same steps per period): "
          f"{int(settled.sum())} settled; min {g_min:.3f} s, median {g_median:.3f} s")
    print(f"  largest |H1 branch| / |H1 time integration| - 1 over the settled points: {np.max(deviation):.2e}")


if __name__ == "__main__":
    main()
