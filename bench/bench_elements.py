"""Benchmark: the generic step with the physical elements of docs/elements.md.

    IDKIT_WORKERS=1 OMP_NUM_THREADS=1 python bench/bench_elements.py [--steps N] [--repeats R]

The generic time driver called directly, one core, on the Table A.1 asymmetric wire rope
(10 Hz, 1 mm harmonic base motion, step 1e-4 s, as bench_kernel.py) as it is, behind a clearance
of 0.2 mm, with rate-dependent slip forces (r = 0.5, v_ref = 0.02 m/s), and a Bouc-Wen law
fitted to nothing in particular (k1 = 2e4 N/m, alpha = 1e5 N/m, z_u = 20 N, n = 1.5) plain and
pinched (pinch 0.7, width 0.25 z_u). Prints ns per step (min, median). Nothing is asserted.
"""

from __future__ import annotations

import argparse
import os
import sys
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)  # this checkout's idkit, also when run as a script from elsewhere


def systems():
    from idkit.models import (BoucWenModel, ClearanceIwanModel, PinchedBoucWenModel, RateDependentIwanModel,
                              SDOFSystem, library)

    base = library.get("system_a1_asymmetric")
    rope = base.isolator
    shared = dict(g1=rope.g1, g2=rope.g2, g3=rope.g3, k=rope.k, fc=rope.fc, c_visc=rope.c_visc)
    total = 1e5 / 20.0**1.5
    bouc_wen = dict(k1=2e4, k2=0.0, k3=0.0, alpha=1e5, beta=0.6 * total, gamma=0.4 * total, n=1.5, c_visc=rope.c_visc)
    return {
        "Iwan": base,
        "Iwan + clearance": SDOFSystem(base.mass, ClearanceIwanModel(gap=2e-4, **shared)),
        "rate-dependent Iwan": SDOFSystem(base.mass, RateDependentIwanModel(slip_rate_gain=0.5, slip_speed=0.02,
                                                                            **shared)),
        "Bouc-Wen": SDOFSystem(base.mass, BoucWenModel(**bouc_wen)),
        "pinched Bouc-Wen": SDOFSystem(base.mass, PinchedBoucWenModel(pinch=0.7, pinch_width=0.25, **bouc_wen)),
    }


def arguments(system, n_steps):
    from idkit.simulate import BaseMotion
    from idkit.simulate._arrays import force_scale, system_arrays

    arrays = system_arrays(system)
    h = 1e-4
    disp, vel = BaseMotion.harmonic(10.0, 1e-3).on_grid(np.arange(n_steps + 1) * h)
    return (*arrays.as_tuple(), h, disp[None, :].copy(), vel[None, :].copy(), 0.0, np.zeros((1, 1)), np.zeros((1, 1)),
            np.zeros((1, 1, arrays.jk.shape[1])), np.zeros((1, 1, arrays.mk.shape[1])), np.zeros((1, 1)), 1000,
            force_scale(arrays, np.array([4e2])))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--steps", type=int, default=200_000)
    parser.add_argument("--repeats", type=int, default=5)
    options = parser.parse_args()
    from idkit.simulate import _kernel

    print(f"generic step, ns per step, {options.steps} steps, {options.repeats} repetitions, one core")
    for label, system in systems().items():
        args = arguments(system, options.steps)
        result = _kernel.run_time_batch(*args)  # compile / load from cache
        assert result[4][0] == 0, label
        times = []
        for _ in range(options.repeats):
            start = time.perf_counter()
            _kernel.run_time_batch(*args)
            times.append((time.perf_counter() - start) / options.steps * 1e9)
        print(f"{label:22s} {min(times):7.1f} ({np.median(times):7.1f})")


if __name__ == "__main__":
    main()
