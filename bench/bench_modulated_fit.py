"""Benchmark: the slip-modulation stage with its exact Jacobian against forward differences, one core.

    OMP_NUM_THREADS=1 python bench/bench_modulated_fit.py [--repeat R] [--orders 3 4]

Same work on both sides: the bundled wire rope's fit-split loop sets
(:func:`idkit.fit.fit_iwan_measurements`' own sets), the plain Iwan fit of each order (made
once, outside the timing), then :func:`idkit.fit.iwan_modulated.fit_iwan_modulated` from it
with ``jacobian="exact"`` (forward sensitivities of the stop operator) and
``jacobian="2-point"`` (scipy's forward differences, the stage's former method), the same
three starts of the modulation depth, the same tolerances, and the valid-range barrier of the
measurement-level fit (``data_valid_range``; ``--no-valid-range`` leaves it out). Timed ``--repeat`` times after a
warm-up call (compilation excluded); min and median printed with the solver's iterations
(``nfev``: scipy does not count the difference quotients' evaluations)
and the mean loop errors each side reaches. Nothing is asserted.
"""

from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

import argparse
import statistics
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)  # this checkout's idkit

from idkit.fit import fit_iwan, fit_iwan_measurements  # noqa: E402
from idkit.fit.data_set_checks import data_valid_range  # noqa: E402
from idkit.fit.iwan_modulated import fit_iwan_modulated  # noqa: E402
from idkit.io.discover import default_data_dir, find_measurement_sets  # noqa: E402


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--orders", type=int, nargs="+", default=[3, 4])
    parser.add_argument("--no-valid-range", action="store_true")
    options = parser.parse_args()
    rope = find_measurement_sets(default_data_dir())["wire_rope"]
    valid_range = None if options.no_valid_range else data_valid_range(rope, isolator="wire_rope")
    data = fit_iwan_measurements(rope, order=1, family="plain", damping_level=None).data
    small, large = list(data.small), list(data.large)
    print(f"slip-modulation stage, bundled rope ({len(small)} small + {len(large)} large sets), valid range "
          f"{valid_range}, one core, "
          f"{options.repeat} repetitions: s min (median), residual evaluations, mean loop error small / large %")
    for order in options.orders:
        plain = fit_iwan(small, large, order=order, seed=0)
        line = f"order {order}:"
        for jacobian in ("exact", "2-point"):
            fit_iwan_modulated(small, large, plain=plain, jacobian=jacobian, valid_range=valid_range)  # warm-up
            seconds = []
            for _ in range(options.repeat):
                started = time.perf_counter()
                result = fit_iwan_modulated(small, large, plain=plain, jacobian=jacobian, valid_range=valid_range)
                seconds.append(time.perf_counter() - started)
            line += (f"  {jacobian} {min(seconds):.3f} ({statistics.median(seconds):.3f}) s, {result.evaluations} "
                     f"iterations, {100 * result.error_small:.3f} / {100 * result.error_large:.3f} %")
        print(line)


if __name__ == "__main__":
    main()
