"""Benchmark: rig drops (bottom mass, floor contact) against conditioned free falls, one core.

    python bench/bench_drop_rig.py [--repeat R]

Times 14 drops (1-14 cm) of the Table 7.1 wire rope on 4.33 kg (bottom mass 7.88 kg) and of
the chapter-5 hybrid on 4.25 kg, each way: :func:`idkit.responses.shock.shock_sweep` with
``drop_model="conditioned"`` and ``"rig"`` on their automatic grids, ``workers=1``, after one
warm-up run (compilation), ``R`` repetitions; prints min and median. Nothing is asserted.
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from idkit.models import HybridSystem, SDOFSystem, library
from idkit.responses.shock import shock_sweep


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5, help="timed repetitions per case")
    args = parser.parse_args()
    heights = np.arange(1, 15) / 100.0
    systems = {
        "wire rope 4.33 kg": SDOFSystem(4.33, library.get("table_7_1_wire_rope")),
        "hybrid 4.25 kg": HybridSystem(4.25, library.get("table_7_3_elastomer"), 0.14,
                                       library.get("table_7_1_wire_rope")),
    }
    for name, system in systems.items():
        for model in ("conditioned", "rig"):
            options = {"drop_model": model, "workers": 1}
            if model == "rig":
                options["bottom_mass"] = 7.88
            shock_sweep(system, drop_height=heights[:1], **options)  # compile
            times = []
            for _ in range(args.repeat):
                start = time.perf_counter()
                sweep = shock_sweep(system, drop_height=heights, **options)
                times.append(time.perf_counter() - start)
            print(f"{name:18s} {model:11s} 14 drops: min {min(times):.3f} s, median {statistics.median(times):.3f} s, "
                  f"step {sweep.time_step:.3g} s, {int(sweep.ok.sum())}/14 valid")


if __name__ == "__main__":
    main()
