"""Run time of ``random_response`` with its defaults, one core.

Run: python bench/bench_random_vibration.py [--repeat N]

The SPEC 6 reference system (viscous, m = 15 kg, zeta = 0.07, 5 Hz) under the flat
1e-4 (m/s^2)^2/Hz input: 30 realizations of 20 s at 800 Hz, integrated at 3200 Hz,
``workers=1`` and one BLAS thread, after a warm-up call (numba compilation). Prints the
wall time (min and median over the repetitions), the analysed resolution and the
half-power damping ratio read from the output PSD.
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


if __name__ == "__main__":
    main()
