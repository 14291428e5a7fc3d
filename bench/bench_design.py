"""Design search cost: 1,000 candidates x 30 parameter draws (random vibration + drops), and 10^4 on Dask.

Run: python bench/bench_design.py [--candidates 1000] [--draws 30] [--repeat 2] [--workers 2]
                                  [--per-draw 4] [--dask 10000] [--dask-draws 3]

Parts: the study's Table 7.1 wire rope and Table 7.3 elastomer at seven stiffness scales each
(0.5-4, covariance 5 % on every stiffness and slip force, uncorrelated), giving single and
hybrid candidates at 1-21 mounts under 40 kg (and, for 10^4, more payloads). Environment: the
flat 1e-4 (m/s^2)^2/Hz floor over 0.1-100 Hz and a road-like 1-100 Hz profile at 3e-3, both at
the study's resolution (800 Hz, 0.05 Hz lines, one realization per draw), five drop heights
1-5 cm, every limit. Prints:

* the search: ``--candidates`` candidates x ``--draws`` draws on ``--workers`` processes forked
  after the warm-up (the screening path, every candidate, guided chunks shrinking to one
  candidate), wall time min and median over ``--repeat`` runs, and the CPU time of the runs
  (this process and its worker processes): on a machine shared with other jobs the wall time is
  the CPU time spread over the share of the cores the run got; ``uptime`` before and after;
* one core: CPU per candidate batched and one draw at a time (``--per-draw`` candidates), and
  whether their rows agree;
* ``--dask N``: N candidates on a ``distributed.LocalCluster`` of 2 worker processes and the same
  on a local process pool, and whether the ranked tables are identical.
"""

from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_name, "1")
os.environ.setdefault("IDKIT_WORKERS", "1")

import argparse
import dataclasses
import json
import multiprocessing
import resource
import statistics
import subprocess
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

from idkit.design import DesignPart, Environment, evaluate_candidates, judge, make_candidates
from idkit.design.evaluation import METRICS, evaluate_candidate
from idkit.models import library

ENVIRONMENT = {"floor_psd": [{"name": "flat 1e-4", "flat": 1e-4, "f_lo": 0.1, "f_hi": 100.0},
                             {"name": "road", "freq_hz": [1.0, 10.0, 100.0], "level": [3e-3, 3e-3, 3e-4]}],
               "drops": {"heights_m": [0.01, 0.02, 0.03, 0.04, 0.05]},
               "limits": {"rms_acceleration_m_per_s2": 1.0, "peak_acceleration_m_per_s2": 150.0,
                          "max_deflection_m": 0.05, "max_component_deflection_m": 0.04,
                          "max_dissipated_energy_j": 5.0, "max_component_dissipated_energy_j": 4.0,
                          "resonance_band_hz": [1.0, 3.0]}}
SCALES = (0.5, 0.7, 1.0, 1.4, 2.0, 2.8, 4.0)


def parts() -> list[DesignPart]:
    out = []
    for name, family, base in (("rope", "wire_rope", library.get("table_7_1_wire_rope")),
                               ("body", "elastomer", library.get("table_7_3_elastomer"))):
        for scale in SCALES:
            params = {k: (v * scale if k.startswith(("g", "k", "fc")) else v) for k, v in base.params().items()}
            model = type(base).from_params(params)
            names = tuple(k for k, v in model.params().items() if v > 0 and k.startswith(("g1", "k", "fc")))
            covariance = np.diag([(0.05 * model.params()[k]) ** 2 for k in names])
            out.append(DesignPart(f"{name} x{scale:g}", family, model, names, covariance))
    return out


def candidates(number: int, seed: int = 0) -> list:
    """``number`` distinct candidates: 1-21 mounts under 40 kg, then more payloads as needed."""
    everything = []
    for payload in (40.0, 25.0, 60.0, 15.0, 90.0, 10.0, 130.0, 180.0, 250.0, 6.0):
        batch = make_candidates(parts(), payload, counts=range(1, 22))
        everything += [dataclasses.replace(c, name=f"{c.name} under {payload:g} kg") for c in batch]
        if len(everything) >= number:
            break
    rng = np.random.default_rng(seed)
    return [everything[i] for i in sorted(rng.choice(len(everything), number, replace=False))]


def cpu_seconds() -> float:
    """CPU time of this process and its finished children (worker processes), s."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime


def uptime() -> str:
    """``uptime``'s line (the machine's load), or the load averages where it is missing."""
    try:
        return subprocess.run(["uptime"], capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return "load average " + ", ".join(f"{load:.2f}" for load in os.getloadavg())


def same_rows(a: list, b: list) -> bool:
    # NaN (a limit a single mount has no component for) never equals itself: compare the JSON text
    return json.dumps(a, default=float) == json.dumps(b, default=float)


def largest_difference(a: dict, b: dict) -> float:
    worst = 0.0
    for name in METRICS:
        x = np.array([a[name]] + a[f"{name} draws"], dtype=float)
        y = np.array([b[name]] + b[f"{name} draws"], dtype=float)
        same = (x == y) | (np.isnan(x) & np.isnan(y))
        with np.errstate(invalid="ignore", divide="ignore"):
            worst = max(worst, float(np.max(np.where(same, 0.0, np.abs(x - y) / np.abs(y)))))
    return worst


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--candidates", type=int, default=1000)
    parser.add_argument("--draws", type=int, default=30)
    parser.add_argument("--repeat", type=int, default=2)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--per-draw", type=int, default=4,
                        help="candidates re-run one draw at a time to compare (0: skip the comparison)")
    parser.add_argument("--dask", type=int, default=0)
    parser.add_argument("--dask-draws", type=int, default=3)
    args = parser.parse_args()
    print(f"uptime before: {uptime()}")
    environment = Environment.from_dict(ENVIRONMENT)
    chosen = candidates(args.candidates)
    kinds = {kind: sum(c.kind == kind for c in chosen) for kind in ("single", "hybrid")}
    print(f"{len(chosen)} candidates ({kinds['single']} single, {kinds['hybrid']} hybrid) x {args.draws} draws, "
          f"{len(environment.profiles)} floor profiles, {len(environment.drop_heights_m)} drop heights")
    evaluate_candidates(chosen[:4], environment, n_draws=1)  # warm-up: compilation, cached kernels
    walls, cpus = [], []
    rows = None
    for _ in range(args.repeat):
        start, start_cpu = time.perf_counter(), cpu_seconds()
        # worker processes forked from this one (their CPU time counts once they are joined)
        with ProcessPoolExecutor(args.workers, mp_context=multiprocessing.get_context("fork")) as pool:
            rows = evaluate_candidates(chosen, environment, n_draws=args.draws, executor=pool, workers=args.workers)
        walls.append(time.perf_counter() - start)
        cpus.append(cpu_seconds() - start_cpu)
    load = os.getloadavg()[0]
    print(f"search on {args.workers} processes: wall min {min(walls):.1f} s, median {statistics.median(walls):.1f} s; "
          f"CPU min {min(cpus):.1f} s, median {statistics.median(cpus):.1f} s "
          f"(CPU / {args.workers} cores: {min(cpus) / args.workers:.1f} s); load average {load:.1f} on "
          f"{os.cpu_count()} cores")
    print(f"uptime after: {uptime()}")
    table = judge(rows, environment)
    print(f"verdicts: {table['verdict'].value_counts().to_dict()}; flagged runs {int(table['flagged'].sum())}")

    if args.per_draw >= 1:
        sample = chosen[:: max(1, len(chosen) // args.per_draw)][:args.per_draw]
        batched_cpu, single_cpu, worst = [], [], 0.0
        for candidate in sample:
            start = time.process_time()
            fast = evaluate_candidate(candidate, environment, n_draws=args.draws)
            batched_cpu.append(time.process_time() - start)
            start = time.process_time()
            slow = evaluate_candidate(candidate, environment, n_draws=args.draws, batched=False)
            single_cpu.append(time.process_time() - start)
            worst = max(worst, largest_difference(fast, slow))
        print(f"one core, {len(sample)} candidates x {args.draws} draws: CPU per candidate batched min "
              f"{min(batched_cpu):.3f} s, median {statistics.median(batched_cpu):.3f} s; one draw at a time min "
              f"{min(single_cpu):.3f} s, median {statistics.median(single_cpu):.3f} s; largest relative difference "
              f"{worst:.1e}")

    if args.dask:
        from dask.distributed import Client, LocalCluster

        many = candidates(args.dask, seed=1)
        start = time.perf_counter()
        local = evaluate_candidates(many, environment, n_draws=args.dask_draws, workers=2)
        local_seconds = time.perf_counter() - start
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True) as cluster, Client(cluster) as client:
            start = time.perf_counter()
            remote = evaluate_candidates(many, environment, n_draws=args.dask_draws, executor=client)
            seconds = time.perf_counter() - start
        same_table = judge(remote, environment).equals(judge(local, environment))
        print(f"dask LocalCluster (2 worker processes): {len(many)} candidates x {args.dask_draws} draws in "
              f"{seconds:.0f} s (local pool of 2 processes: {local_seconds:.0f} s); rows identical: "
              f"{same_rows(remote, local)}; ranked tables identical: {same_table}")


if __name__ == "__main__":
    main()
