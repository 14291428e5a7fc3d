"""Design search cost: candidates x parameter draws (random vibration + drops), screening and full.

Run: python bench/bench_design.py [--candidates N] [--draws D] [--repeat R] [--dask N_DASK]

Parts: the study's Table 7.1 wire rope and Table 7.3 elastomer at four stiffness scales each
(covariance: 5 % on every stiffness and slip force, uncorrelated), giving single and hybrid
candidates at 1-6 mounts under a 40 kg payload. Environment: the flat 1e-4 (m/s^2)^2/Hz floor
over 0.1-100 Hz at the study's resolution (800 Hz, 0.05 Hz lines, one realization per draw)
and five drop heights 1-5 cm. One core (``workers=1``), after a warm-up call (numba
compilation). Prints per-candidate wall time (min and median over the repetitions) on the
screening path and in full, and the projection to 1,000 candidates x 30 draws on 2 cores.
``--dask N`` evaluates N candidates on a local Dask cluster (2 processes) and on one process
and checks the rows are identical.
"""

from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_name, "1")
os.environ.setdefault("IDKIT_WORKERS", "1")

import argparse
import json
import statistics
import time

import numpy as np

from idkit.design import DesignPart, Environment, evaluate_candidates, make_candidates
from idkit.models import library

ENVIRONMENT = {"floor_psd": [{"name": "flat 1e-4", "flat": 1e-4, "f_lo": 0.1, "f_hi": 100.0}],
               "drops": {"heights_m": [0.01, 0.02, 0.03, 0.04, 0.05]},
               "limits": {"rms_acceleration_m_per_s2": 0.5, "peak_acceleration_m_per_s2": 80.0,
                          "max_deflection_m": 0.03, "resonance_band_hz": [1.0, 3.0]}}


def parts() -> list[DesignPart]:
    out = []
    for name, family, base in (("rope", "wire_rope", library.get("table_7_1_wire_rope")),
                               ("body", "elastomer", library.get("table_7_3_elastomer"))):
        for scale in (0.5, 1.0, 2.0, 4.0):
            params = {k: (v * scale if k.startswith(("g", "k", "fc")) else v) for k, v in base.params().items()}
            model = type(base).from_params(params)
            names = tuple(k for k, v in model.params().items() if v > 0 and k.startswith(("g1", "k", "fc")))
            covariance = np.diag([(0.05 * model.params()[k]) ** 2 for k in names])
            out.append(DesignPart(f"{name} x{scale:g}", family, model, names, covariance))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--candidates", type=int, default=6)
    parser.add_argument("--draws", type=int, default=30)
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--dask", type=int, default=0)
    args = parser.parse_args()
    environment = Environment.from_dict(ENVIRONMENT)
    everything = make_candidates(parts(), 40.0, counts=(1, 2, 3, 4, 5, 6))
    rng = np.random.default_rng(0)
    chosen = [everything[i] for i in sorted(rng.choice(len(everything), args.candidates, replace=False))]
    evaluate_candidates(chosen[:2], environment, n_draws=1)  # warm-up: compilation
    evaluate_candidates(chosen[:2], environment, n_draws=1, screening=False)
    for screening in (True, False):
        times, cpu = [], []
        for _ in range(args.repeat):
            start, start_cpu = time.perf_counter(), time.process_time()
            evaluate_candidates(chosen, environment, n_draws=args.draws, screening=screening)
            times.append((time.perf_counter() - start) / len(chosen))
            cpu.append((time.process_time() - start_cpu) / len(chosen))
        label = "screening" if screening else "full"
        projected = min(cpu) * 1000 * 30 / args.draws / 2
        print(f"{label}: {len(chosen)} candidates x {args.draws} draws, per candidate wall min {min(times):.3f} s, "
              f"median {statistics.median(times):.3f} s; CPU min {min(cpu):.3f} s, median {statistics.median(cpu):.3f} s; "
              f"1,000 x 30 on 2 idle cores ~ {projected:.0f} s (from CPU time)")
    if args.dask:
        from dask.distributed import Client, LocalCluster

        sample = everything[:args.dask]
        local = evaluate_candidates(sample, environment, n_draws=2)
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True) as cluster, Client(cluster) as client:
            start = time.perf_counter()
            remote = evaluate_candidates(sample, environment, n_draws=2, executor=client)
            seconds = time.perf_counter() - start
        # NaN (a limit a single mount has no component for) never equals itself: compare the JSON text
        same = json.dumps(remote, default=float) == json.dumps(local, default=float)
        print(f"dask local cluster (2 processes): {len(sample)} candidates x 2 draws in {seconds:.1f} s; rows "
              f"identical to the local run: {same}")


if __name__ == "__main__":
    main()
