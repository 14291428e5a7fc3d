"""Catalogue build time: a synthetic family identified part by part, serial and on 2 processes.

Run: python bench/bench_catalogue.py [--ropes N] [--elastomers M] [--workers W] [--repeat R] [--rope-order auto|K]

Generates ``N`` wire ropes and ``M`` elastomers (:mod:`idkit.synth.catalogue`, short records)
into a temporary folder (timed apart), then builds the catalogue with ``workers=1`` and with
``--workers`` processes (forkserver), each build from scratch; prints min and median wall
time over the repetitions, the parts identified, and the leave-one-part-out coverage of the
rope stuck-stiffness law. The wire ropes use the order rule (``--rope-order auto``, the
default of ``idkit catalogue build``) unless an order is given.
"""

from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_name, "1")
os.environ.setdefault("IDKIT_WORKERS", "1")

import argparse
import statistics
import tempfile
import time
from pathlib import Path

from idkit.catalogue import build_catalogue
from idkit.catalogue.scaling import leave_one_part_out
from idkit.synth.catalogue import elastomer_family, generate_catalogue, wire_rope_family


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ropes", type=int, default=10)
    parser.add_argument("--elastomers", type=int, default=10)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--rope-order", default="auto")
    args = parser.parse_args()
    options = {} if args.rope_order == "auto" else {"wire_rope": {"order": int(args.rope_order)}}
    with tempfile.TemporaryDirectory() as folder:
        folder = Path(folder)
        start = time.perf_counter()
        parts = wire_rope_family(count=args.ropes) + elastomer_family(count=args.elastomers)
        generate_catalogue(folder / "parts", parts)
        print(f"generated {len(parts)} parts in {time.perf_counter() - start:.1f} s")
        quantities = {}
        for workers in sorted({1, args.workers}):
            times = []
            for index in range(args.repeat):
                start = time.perf_counter()
                catalogue = build_catalogue(folder / "parts", folder / f"cat-{workers}-{index}", workers=workers,
                                            fit_options=options)
                times.append(time.perf_counter() - start)
            statuses = [r["status"] for r in catalogue.records]
            quantities[workers] = [(r["part"], r.get("quantities")) for r in catalogue.records]
            print(f"build, workers={workers}: min {min(times):.1f} s, median {statistics.median(times):.1f} s over "
                  f"{args.repeat}; {statuses.count('identified')} of {len(statuses)} identified "
                  f"({', '.join(sorted(set(statuses)))})")
        if len(quantities) == 2:
            print(f"records of workers=1 and workers={args.workers} identical: "
                  f"{quantities[1] == quantities[args.workers]}")
        for record in catalogue.records:
            if record["status"] != "identified":
                print(f"    {record['part']}: {record['status']}: {'; '.join(record['reasons'])[:160]}")
        ropes = [r for r in catalogue.usable() if r["family"] == "wire_rope"]
        if len(ropes) >= 6:
            coverage = leave_one_part_out(ropes, "stuck_stiffness")
            print(f"rope stuck-stiffness law, leave one part out: {int(coverage['inside'].sum())} of "
                  f"{len(coverage)} inside their 95 % band")


if __name__ == "__main__":
    main()
