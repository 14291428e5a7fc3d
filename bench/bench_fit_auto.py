"""Benchmark: ``idkit fit auto`` (every candidate family, cross-validation included) on ten records
of 20,000 samples, two processes (half of each family's folds forked).

    OMP_NUM_THREADS=1 python bench/bench_fit_auto.py [--repeat R] [--device clearance_friction_damper]

The records: a synthetic device of :mod:`idkit.synth.devices` (default the friction damper with
clearance, the issue-32 case) under sines of five amplitudes (13-38 mm) at two frequencies (0.25 and
1 Hz), ten cycles each, sampled so that every record holds 20,000 samples, with 2 N force noise.
:func:`idkit.fit.auto.fit_auto` with the default candidate set is timed ``--repeat`` times after a
warm-up on two short records (compilation excluded); the total wall and CPU time (this process and
the forked children that run half of each family's folds; min and median)
and, from the last run, each family's full-fit and folds time are printed. Target (issue 32): at
most 120 s on 2 cores. Nothing is asserted.
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

from idkit.fit.auto import fit_auto  # noqa: E402
from idkit.observe.histories import ForceHistory, histories_from_records  # noqa: E402
from idkit.synth.devices import DEVICES, device_records, sine_history  # noqa: E402

SAMPLES = 20_000
CYCLES = 10


def records(device):
    sines = {}
    for amplitude in (13e-3, 19e-3, 25e-3, 31e-3, 38e-3):
        for frequency in (0.25, 1.0):
            rate = (SAMPLES - 1) * frequency / CYCLES
            sines[f"sine_{1e3 * amplitude:g}mm_{frequency:g}Hz"] = sine_history(amplitude, frequency, cycles=CYCLES,
                                                                                 sample_rate_hz=rate)
    return histories_from_records(device_records(device, sines, force_noise=2.0, seed=1))


def _cpu() -> float:
    """CPU seconds of this process and of its finished children (the folds forked to a second core)."""
    times = os.times()
    return times.user + times.system + times.children_user + times.children_system


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--device", choices=sorted(DEVICES), default="clearance_friction_damper")
    options = parser.parse_args()
    histories = records(DEVICES[options.device])
    # warm-up on two short records (one cycle each): compiles every kernel the families use
    short = [ForceHistory(h.name, h.time[:n], h.deflection[:n], h.force[:n], h.group)
             for h, n in ((h, SAMPLES // CYCLES + 1) for h in histories[:2])]
    fit_auto(short, seed=0, early_stop_factor=None)
    walls, cpus = [], []
    for _ in range(options.repeat):
        started, started_cpu = time.perf_counter(), _cpu()
        result = fit_auto(histories, seed=0)
        walls.append(time.perf_counter() - started)
        cpus.append(_cpu() - started_cpu)
    print(f"fit auto, {options.device}: {len(histories)} records x {histories[0].time.size} samples, "
          f"{len(result.folds)} folds, one thread per process (folds split over two processes), "
          f"{options.repeat} repetition(s)")
    print(f"total wall {min(walls):.1f} s min ({statistics.median(walls):.1f} median), "
          f"CPU {min(cpus):.1f} s min ({statistics.median(cpus):.1f} median)")
    print(result.table().to_string(index=False, float_format=lambda v: f"{v:.3g}"))
    for score in result.scores:
        if score.problem:
            print(f"  {score.family.name}: {score.problem}")
    print(f"chosen: {result.chosen.family.name}; success {result.success}")


if __name__ == "__main__":
    main()
