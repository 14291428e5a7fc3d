"""Run time of ``random_response`` with its defaults, one core.

Run: python bench/bench_random_vibration.py [--repeat N] [--transport]

The SPEC 6 reference system (viscous, m = 15 kg, zeta = 0.07, 5 Hz) under the flat
1e-4 (m/s^2)^2/Hz input: 30 realizations of 20 s at 800 Hz, integrated at 3200 Hz,
``workers=1`` and one BLAS thread, after a warm-up call (numba compilation). Prints the
wall time (min and median over the repetitions), the analysed resolution and the
half-power damping ratio read from the output PSD.

``--transport`` also times the random-vibration part of the transport study on the parts
identified from the bundled data (every system and level, continuation to the study's
settling limit included; one impact speed and one drop height) and prints the runs it
leaves unsettled and the largest settling error.
"""

from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_name, "1")
os.environ.setdefault("IDKIT_WORKERS", "1")

import argparse
import statistics
import time

import numpy as np

from idkit.models import SDOFSystem, VoigtModel
from idkit.responses.random_vibration import random_response
from idkit.signal.psd import PsdProfile


def half_power_damping(freq, psd):
    """Damping ratio from the half-power band of the highest peak (linear interpolation)."""
    k = int(np.argmax(psd))
    half = 0.5 * psd[k]
    lo = k - int(np.argmax(psd[k::-1] <= half))
    hi = k + int(np.argmax(psd[k:] <= half))
    f_lo = np.interp(half, [psd[lo], psd[lo + 1]], [freq[lo], freq[lo + 1]])
    f_hi = np.interp(half, [psd[hi], psd[hi - 1]], [freq[hi], freq[hi - 1]])
    return (f_hi - f_lo) / (2.0 * freq[k])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--transport", action="store_true", help="also time the transport study's random runs")
    args = parser.parse_args()
    mass, f0, zeta = 15.0, 5.0, 0.07
    omega0 = 2 * np.pi * f0
    system = SDOFSystem(mass, VoigtModel(k=mass * omega0**2, damping=2 * zeta * mass * omega0))
    profile = PsdProfile.flat(1e-4, f_lo=0.1, f_hi=100.0)
    result = random_response(system, profile, seed=1, workers=1)  # warm-up: compilation
    times = []
    for _ in range(args.repeat):
        start = time.perf_counter()
        result = random_response(system, profile, seed=1, workers=1)
        times.append(time.perf_counter() - start)
    resolution = result.freq[1] - result.freq[0]
    print(f"random_response, defaults, workers=1, {args.repeat} repetitions: "
          f"min {min(times):.3f} s, median {statistics.median(times):.3f} s")
    print(f"Welch segment {result.nperseg} samples ({resolution:.3f} Hz), "
          f"half-power zeta {half_power_damping(result.freq, result.output_psd):.4f} (true {zeta})")
    if args.transport:
        transport(args.repeat)


def transport(repeat: int) -> None:
    """The transport study's random runs on the bundled parts: time, unsettled runs."""
    from idkit.studies.pipeline import identify_parts
    from idkit.studies.transport import SETTLING_LIMIT, compute_transport_study

    wire_rope, elastomer = identify_parts(seed=2026)
    options = dict(wire_rope=wire_rope, elastomer=elastomer, seed=2026, workers=1, speeds=[0.5], heights=[0.05])
    compute_transport_study(levels=[1e-6], r_k_values=(0.4,), **options)  # warm-up: compilation
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        study = compute_transport_study(**options)
        times.append(time.perf_counter() - start)
    worst = float(np.nanmax(study.settling.to_numpy(float)))
    print(f"transport study, random runs (10 systems x 6 levels x 30 realizations), workers=1, {repeat} "
          f"repetitions: min {min(times):.1f} s, median {statistics.median(times):.1f} s")
    print(f"unsettled (settling error > {SETTLING_LIMIT}): {study.unsettled() or 'none'}; largest settling "
          f"error {worst:.3g}")


if __name__ == "__main__":
    main()
