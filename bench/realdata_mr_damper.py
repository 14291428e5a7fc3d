"""Real device check: ``fit auto`` and ``validate`` on a measured MR damper against the simple baselines.

    OMP_NUM_THREADS=1 python bench/realdata_mr_damper.py [--folder FOLDER]

The data (read in place from ``idkit.datasets.realdata_dir("mr_damper_labcontrol") / "data"``, never
copied; SOURCE.txt there: labcontrol-data/mr-damper, MIT): a small
MR damper on a shaking table, position (mm), velocity and force (N) at 100 Hz. The series
``ensaioN.1`` (N = 1..10) are sines of 24.8 to 11.2 mm stroke at 0.84 to 1.22 Hz, each starting
at rest at position 0. Read here as force histories: deflection = position / 1000 (m, from the rest
position), force = measured force minus its mean over the first second at rest (the load cell's
tare, 85 N on ``ensaio1.1``), so that both are zero in the virgin state the models start from.
Training: the odd-numbered records (five strokes); held out: the even-numbered ones (the
strokes between them, at their own frequencies). These are the only real hysteretic records
available here, and they are sinusoidal: no earthquake or random history was recorded.

:func:`idkit.fit.auto.fit_auto` (default candidate set) chooses a family on the training records;
:func:`idkit.validate.history.validate_histories` scores it on the held-out ones beside the
baselines of :func:`idkit.fit.baselines.fit_baselines` fitted on the training records (and zero
force). Printed: the family table, the validation table and the baseline comparison. Nothing is
asserted; the outcome is recorded in docs/validation.md.
"""

from __future__ import annotations

import os

for _name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ.setdefault(_name, "1")

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)  # this checkout's idkit

from idkit.datasets import realdata_dir  # noqa: E402
from idkit.fit.auto import fit_auto  # noqa: E402
from idkit.fit.baselines import fit_baselines  # noqa: E402
from idkit.observe.histories import ForceHistory  # noqa: E402
from idkit.validate.history import validate_histories  # noqa: E402

#: seconds at rest at the start of every record used for the load cell's tare
REST_S = 1.0


def read_record(path: Path, group: str) -> ForceHistory:
    """One ``ensaioN.1`` file as a force history (module docstring): SI units, tared force."""
    import scipy.io

    content = scipy.io.loadmat(path)
    time_s = np.ravel(content["Tout"]).astype(float)
    position_mm, force_n = content["x_F"][:, 0].astype(float), content["x_F"][:, 2].astype(float)
    rest = time_s < REST_S
    if np.ptp(position_mm[rest]) > 0.05:
        raise SystemExit(f"{path}: the position moves in the first {REST_S} s, expected the device at rest")
    return ForceHistory(path.stem, time_s, 1e-3 * position_mm, force_n - float(np.mean(force_n[rest])), group=group)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--folder", type=Path, default=None, help="default: the shared real-data folder's copy")
    options = parser.parse_args()
    if options.folder is None:
        found = realdata_dir("mr_damper_labcontrol")
        options.folder = Path(found) / "data" if found is not None else Path("mr_damper_labcontrol/data")
    if not options.folder.is_dir():
        raise SystemExit(f"{options.folder}: not found (the real data are read in place, never copied)")
    records = {n: read_record(options.folder / f"ensaio{n}.1.mat", f"stroke {n}") for n in range(1, 11)}
    training = [records[n] for n in (1, 3, 5, 7, 9)]
    held_out = [records[n] for n in (2, 4, 6, 8, 10)]
    started = time.perf_counter()
    result = fit_auto(training, progress=lambda line: print(line, flush=True))
    print(f"fit auto: {time.perf_counter() - started:.1f} s")
    print(result.report().split("\n[[")[0])
    baselines = fit_baselines(training)
    validation = validate_histories(result.model, held_out, baselines=baselines, name="MR damper, held-out strokes")
    print(validation.report())
    columns = ["record", "nrms_error", "nrms_error_strong_motion",
               *[c for c in validation.metrics.columns if c.startswith("baseline ")], "noise_floor"]
    print(validation.metrics[columns].to_string(index=False, float_format=lambda v: f"{v:.4g}"))


if __name__ == "__main__":
    main()
