"""CPU time of loading the bundled data set (data/, 537 gzip CSV files), one core.

Run: python bench/bench_loader.py [--repeat N]

Times, each as min and median over ``--repeat`` repetitions in this process
(CPU time of this process, ``time.process_time``, so other users of the
machine do not inflate it):

* the full load (``load_measurement_set`` of the three bundled sets: manifest,
  read, gunzip, SHA-256, parse, SI conversion, measurement checks);
* its parsing step alone, both ways: the pandas fast path of
  ``read_csv_table`` and the strict :mod:`csv` + regex parser it falls back
  to (the full load is also timed with the strict parser only).

Run with one BLAS/OpenMP thread (set below before numpy is imported).
"""

from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

import argparse
import functools
import statistics
import time
from pathlib import Path

from idkit.io import csv_table, load_measurement_set
from idkit.io.columns import KIND_SCHEMAS

DATA = Path(__file__).resolve().parents[1] / "data"
SETS = ("wire_rope", "elastomer", "hybrid")


def cpu_times(function, repeat):
    """CPU seconds of ``repeat`` calls of ``function()``."""
    out = []
    for _ in range(repeat):
        start = time.process_time()
        function()
        out.append(time.process_time() - start)
    return out


def load_all():
    return [load_measurement_set(DATA / name) for name in SETS]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()

    sets = load_all()  # warm-up: imports, page cache
    n_files = sum(len(s) for s in sets)
    files = [(m.source.path, KIND_SCHEMAS[e.kind]) for s in sets for e, m in zip(s.entries, s)]
    texts = [(path, schema, csv_table.decode_text(path, csv_table.read_file_bytes(path)))
             for path, schema in files]

    def parse(strict):
        for path, schema, text in texts:
            csv_table.parse_table_text(path, "0" * 64, text, schema, strict=strict)

    rows = [
        ("full load, pandas fast path", cpu_times(load_all, args.repeat)),
    ]
    fast = csv_table.parse_table_text
    csv_table.parse_table_text = functools.partial(fast, strict=True)  # the loader before
    try:
        rows.append(("full load, strict parser only", cpu_times(load_all, args.repeat)))
    finally:
        csv_table.parse_table_text = fast
    rows.append(("parse only (decoded text), pandas fast path",
                 cpu_times(lambda: parse(False), args.repeat)))
    rows.append(("parse only (decoded text), strict parser",
                 cpu_times(lambda: parse(True), args.repeat)))
    print(f"bundled data: {n_files} files, {args.repeat} repetitions, CPU seconds of one core")
    print(f"{'step':<48s} {'min [s]':>9s} {'median [s]':>11s}")
    for name, times in rows:
        print(f"{name:<48s} {min(times):9.3f} {statistics.median(times):11.3f}")


if __name__ == "__main__":
    main()
