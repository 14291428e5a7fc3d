"""Benchmark: the generic step against the steps specialised per structure (issue 14, item 4).

    IDKIT_WORKERS=1 OMP_NUM_THREADS=1 python bench/bench_kernel.py [--steps N] [--repeats R]

For each structure (SDOF Iwan: Table A.1 asymmetric wire rope; SDOF Maxwell: Table B.1 medium
elastomer; hybrid asymmetric) the compiled time driver is called directly, one core, on the same
prepared arrays (harmonic base motion, 10 Hz, 1 mm, step 1e-4 s), generic and specialised in
turn, ``R`` repetitions each; it prints the nanoseconds per step (min and median) and the
largest difference between the two records. Then the first-call (compile) time of each kernel,
each in a fresh process with an empty numba cache (``NUMBA_CACHE_DIR`` and ``IDKIT_CACHE_DIR`` a new temporary
directory; a kernel's time includes compiling the shared helpers it calls). Nothing is asserted.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)  # this checkout's idkit, also when run as a script from elsewhere

CASES = {"SDOF Iwan": "system_a1_asymmetric", "SDOF Maxwell": "system_b1_medium", "hybrid": "hybrid_asymmetric",
         "SDOF mod. Iwan": "modulated:system_a1_asymmetric"}


def library_system(name):
    """A library system; ``modulated:<name>``: its wire rope with the slip modulation a = 0.3,
    y_ref = 2 mm (the specialised Iwan step carries it since issue 14)."""
    from idkit.models import ModulatedIwanModel, library
    from idkit.models.systems import SDOFSystem

    if not name.startswith("modulated:"):
        return library.get(name)
    system = library.get(name.split(":", 1)[1])
    rope = system.isolator
    modulated = ModulatedIwanModel(g1=rope.g1, g2=rope.g2, g3=rope.g3, k=rope.k, fc=rope.fc, c_visc=rope.c_visc,
                                   slip_modulation=0.3, slip_length=2e-3)
    return SDOFSystem(system.mass, modulated)


def prepared(name, n_steps):
    """Arguments of the time driver for a library system, as :func:`idkit.simulate.simulate` builds them."""
    from idkit.simulate import BaseMotion
    from idkit.simulate._arrays import force_scale, system_arrays

    system = library_system(name)
    arrays = system_arrays(system)
    h = 1e-4
    time_grid = np.arange(n_steps + 1) * h
    disp, vel = BaseMotion.harmonic(10.0, 1e-3).on_grid(time_grid)
    ndof = arrays.ndof
    return arrays, (*arrays.as_tuple(), h, disp[None, :].copy(), vel[None, :].copy(), 0.0, np.zeros((1, ndof)),
                    np.zeros((1, ndof)), np.zeros((1, ndof, arrays.jk.shape[1])),
                    np.zeros((1, ndof, arrays.mk.shape[1])), np.zeros((1, ndof)), 1000,
                    force_scale(arrays, np.array([4e2])),  # one scale per member of the batch
                    np.full((1, ndof), np.nan))  # a0: NaN, a run from equilibrium


def compile_time(label, name):
    """Seconds of the first call of one kernel in a fresh process with an empty numba cache."""
    code = (
        "import time, sys\n"
        f"sys.path.insert(0, {ROOT!r})\n"
        "from bench.bench_kernel import prepared\n"
        "from idkit.simulate import _kernel\n"
        "from idkit.simulate._structured import structure_of\n"
        f"arrays, args = prepared({name!r}, 10)\n"
        f"kernel = _kernel.time_kernel(structure_of(arrays)) if {label!r} == 'specialised' else _kernel.run_time_batch\n"
        "start = time.perf_counter(); kernel(*args); print(time.perf_counter() - start)\n"
    )
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, IDKIT_CACHE_DIR=cache, IDKIT_WORKERS="1", OMP_NUM_THREADS="1")
        result = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    return float(result.stdout.strip().splitlines()[-1])


def harmonic_map(repeats):
    """A 6 x 5 harmonic map (1-30 Hz x 1e-4..3e-3 m, from rest, at most 200 periods) per structure,
    generic and specialised: seconds (min, median) and ns per simulated step."""
    from idkit.simulate import _kernel, harmonic_response

    freq, amplitude = np.meshgrid(np.geomspace(1.0, 30.0, 6), np.geomspace(1e-4, 3e-3, 5))
    print("harmonic map 6 x 5 (maps drive the same step), one worker: s min (median), ns per step")
    for label, name in CASES.items():
        system = library_system(name)
        line = f"{label:14s}"
        for which in ("generic", "specialised"):
            saved = _kernel.SPECIALISED
            if which == "generic":
                _kernel.SPECIALISED = frozenset()
            try:
                response = harmonic_response(system, freq, amplitude, max_periods=200, workers=1)
                times = []
                for _ in range(repeats):
                    start = time.perf_counter()
                    response = harmonic_response(system, freq, amplitude, max_periods=200, workers=1)
                    times.append(time.perf_counter() - start)
            finally:
                _kernel.SPECIALISED = saved
            steps = float(np.sum(response.periods * response.steps_per_period))
            line += f"  {which} {min(times):6.3f} ({np.median(times):6.3f}) s {min(times) / steps * 1e9:6.1f} ns"
        print(line)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--steps", type=int, default=200_000)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--no-compile", action="store_true", help="skip the fresh-process compile times")
    options = parser.parse_args()
    from idkit.simulate import _kernel
    from idkit.simulate._structured import structure_of

    print(f"ns per step, {options.steps} steps, {options.repeats} repetitions, one core")
    print(f"{'structure':14s} {'generic min':>12s} {'median':>8s} {'special min':>12s} {'median':>8s} "
          f"{'speed-up':>8s} {'max |diff|/max':>15s}")
    for label, name in CASES.items():
        arrays, args = prepared(name, options.steps)
        kernels = {"generic": _kernel.run_time_batch, "specialised": _kernel.time_kernel(structure_of(arrays))}
        seconds = {}
        records = {}
        for which, kernel in kernels.items():
            kernel(*args)  # compile / load from cache
            times = []
            for _ in range(options.repeats):
                start = time.perf_counter()
                records[which] = kernel(*args)
                times.append(time.perf_counter() - start)
            seconds[which] = np.array(times) / options.steps * 1e9
        q_generic = records["generic"][0]
        diff = np.nanmax(np.abs(records["specialised"][0] - q_generic)) / np.nanmax(np.abs(q_generic))
        g, s = seconds["generic"], seconds["specialised"]
        print(f"{label:14s} {g.min():12.1f} {np.median(g):8.1f} {s.min():12.1f} {np.median(s):8.1f} "
              f"{g.min() / s.min():8.2f} {diff:15.1e}")
    harmonic_map(options.repeats)
    if options.no_compile:
        return
    print("first call (compile) in a fresh process, empty numba cache, s")
    for label, name in CASES.items():
        specialised = compile_time("specialised", name)
        print(f"{label:14s} specialised {specialised:6.1f}")
    print(f"{'any':14s} generic     {compile_time('generic', 'system_a1_asymmetric'):6.1f}")


if __name__ == "__main__":
    main()
