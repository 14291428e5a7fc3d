"""Benchmark: shooting against long time integration on the same points, one core, same step.

    python bench/bench_periodic.py [--repeat R] [--map]

Points: the Table A.1 asymmetric wire rope (8 kg, 0.24 % damping) at the high-frequency
points the 50 x 30 map leaves unsettled after 4000 periods (62-100 Hz, 0.3-2.4 mm), a point
in slip (5 Hz, 3 mm), a stuck one (20 Hz, 1 mm) and the 1/2 subharmonic (10.68 Hz, 1.2 mm);
and the hybrid (Maxwell + Iwan) at 4 and 20 Hz. Both sides use the same integrator and steps
per period: the time integration runs from the linear start until the window change is
below 1e-6 (at most 40000 periods), shooting (``periodic_response``) integrates 20 periods
from the same start and closes the orbit by Newton to 1e-9 (the subharmonic: the period-2
orbit found first is the unstable doubled period-1 orbit, left along its unstable
eigenvector). Each side is timed ``--repeat`` times on one thread after a warm-up call
(compilation excluded); min and median are printed with the largest first-harmonic
deviation between the two sides.

``--map`` also runs the Table A.1 asymmetric 50 x 30 map (1-100 Hz, 1e-5 - 1e-2 m): 4000 periods
without and with the shooting fallback (one worker, once), and the default (200 periods, then
shooting) on one and two workers (``--repeat`` times, min and median), with settled points and
the first-harmonic agreement with the plain 4000-period grid.
Nothing here is asserted; the figures depend on the machine and its load.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from idkit.models import library
from idkit.responses.harmonic_map import harmonic_map
from idkit.responses.periodic import periodic_response
from idkit.simulate import harmonic_response

CASES = {
    "system_a1_asymmetric": (
        [62.51, 68.66, 75.43, 82.86, 91.03, 100.0, 100.0, 5.0, 20.0],
        [2.4e-3, 1.49e-3, 9.24e-4, 1.17e-3, 5.74e-4, 2.81e-4, 2.4e-3, 3e-3, 1e-3],
    ),
    "hybrid_asymmetric": ([4.0, 20.0], [1e-3, 1e-3]),
}


def repeat(function, times):
    seconds = []
    value = None
    for _ in range(times):
        start = time.perf_counter()
        value = function()
        seconds.append(time.perf_counter() - start)
    return value, min(seconds), statistics.median(seconds)


def compare(name, freq, amplitude, periods, times):
    system = library.get(name)
    freq, amplitude = np.asarray(freq), np.asarray(amplitude)

    def integrate():
        return harmonic_response(system, freq, amplitude, tolerance=1e-6, start="linear", max_periods=40000,
                                 workers=1)

    def shoot():
        return periodic_response(system, freq, amplitude, periods=periods)

    integrate(), shoot()  # compile / warm up
    timed, t_min, t_median = repeat(integrate, times)
    orbit, s_min, s_median = repeat(shoot, times)
    deviation = np.abs(orbit.hosidf(1) / timed.hosidf(1) - 1)
    sub = np.abs(np.abs(orbit.hosidf(0.5)) - np.abs(timed.hosidf(0.5))) / np.abs(timed.hosidf(1))
    print(f"{name}, {freq.size} points, orbits of {periods} period(s):")
    print(f"  time integration: {int(timed.periods.sum())} periods in all ({int(timed.converged.sum())}/{freq.size} "
          f"settled to 1e-6); min {t_min * 1e3:.1f} ms, median {t_median * 1e3:.1f} ms")
    print(f"  shooting: {int(orbit.iterations.sum())} Newton iterations, {int(orbit.converged.sum())}/{freq.size} "
          f"closed, largest closing error {np.nanmax(orbit.residual):.1e}; min {s_min * 1e3:.1f} ms, "
          f"median {s_median * 1e3:.1f} ms")
    print(f"  ratio of medians (time / shooting): {t_median / s_median:.1f}x; largest |H1 shoot / H1 time - 1| = "
          f"{np.nanmax(deviation):.1e}, |H0.5| difference / |H1| = {np.nanmax(sub):.1e}")


def map_run(times):
    system = library.get("system_a1_asymmetric")
    freq = np.geomspace(1.0, 100.0, 50)
    amplitude = np.geomspace(1e-5, 1e-2, 30)
    settings = [("4000 periods, no shooting", dict(max_periods=4000, shooting=False), 1),
                ("4000 periods, then shooting", dict(max_periods=4000), 1),
                ("default: 200 periods, then shooting", {}, 1),
                ("default: 200 periods, then shooting", {}, 2)]
    reference = None
    for label, options, workers in settings:
        hmap, t_min, t_median = repeat(lambda: harmonic_map(system, freq, amplitude, workers=workers, **options),
                                       times if "default" in label else 1)
        if reference is None:
            reference = hmap
        both = reference.converged & hmap.converged
        deviation = np.max(np.abs(hmap.hosidf(1)[both] / reference.hosidf(1)[both] - 1))
        print(f"Table A.1 asymmetric 50 x 30 map, {label}, {workers} worker(s): {int(hmap.converged.sum())}/"
              f"{hmap.converged.size} settled ({int(hmap.shooting.sum())} by shooting); min {t_min:.2f} s, "
              f"median {t_median:.2f} s wall; |H1 / H1(4000, no shooting) - 1| <= {deviation:.1e} where both settled")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="timed repetitions per side")
    parser.add_argument("--map", action="store_true", help="also run the 50 x 30 map with and without shooting")
    args = parser.parse_args()
    for name, (freq, amplitude) in CASES.items():
        compare(name, freq, amplitude, 1, args.repeat)
    compare("system_a1_asymmetric", [10.68], [1.2e-3], 2, args.repeat)
    if args.map:
        map_run(args.repeat)


if __name__ == "__main__":
    main()
