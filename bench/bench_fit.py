"""Wall times of the fitters (issue 4 targets). Run: python bench/bench_fit.py

* Iwan three-stage fit on the bundled wire-rope loops (fit split)    target <= 1 s
* Maxwell SQP order 2 on all bundled white-noise FRFs (fit split)    target <= 0.5 s
* global cross-check of that fit                                     target <= 20 s
* DMA master-curve Prony fit (../shared/realdata/pyvisco_dma), idkit against pyvisco
  in the same run, if pyvisco is installed (optional dependency of this script only).

Loading and FRF estimation are timed separately; each fit once after a warm-up
(numba compilation) run.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from idkit.datasets import read_pyvisco_complex_modulus, realdata_dir
from idkit.fit import (
    fit_boucwen,
    fit_complex_stiffness,
    fit_iwan,
    fit_maxwell,
    k0_from_measurements,
    loop_sets,
    transmissibility_sets,
)
from idkit.io import load_measurement_set

DATA = Path(__file__).resolve().parents[1] / "data"


def timed(function, *args, **kwargs):
    start = time.perf_counter()
    result = function(*args, **kwargs)
    return result, time.perf_counter() - start


def line(name, seconds, target=None, extra=""):
    verdict = "" if target is None else (f"(target <= {target:g} s: {'met' if seconds <= target else 'MISSED'})")
    print(f"{name:<52s} {seconds:8.3f} s  {verdict} {extra}")


def main():
    wire_rope, t = timed(load_measurement_set, DATA / "wire_rope")
    line("load data/wire_rope", t)
    loops, t = timed(loop_sets, wire_rope)
    line("prepare loops (4 records, 600 points each)", t)
    fit_iwan(list(loops.small), list(loops.large))  # warm-up: numba compilation
    iwan, t = timed(fit_iwan, list(loops.small), list(loops.large))
    line("Iwan three-stage fit, order 2 (nlopt)", t, 1.0,
         f"errors {100 * iwan.error_small:.2f} % / {100 * iwan.error_large:.2f} %, {iwan.evaluations} evaluations")
    bouc_wen, t = timed(fit_boucwen, list(loops.small), list(loops.large))
    line("Bouc-Wen staged fit + CRS2 global + polish", t, None,
         f"errors {100 * bouc_wen.error_small:.2f} % / {100 * bouc_wen.error_large:.2f} %")

    elastomer, t = timed(load_measurement_set, DATA / "elastomer")
    line("load data/elastomer", t)
    frfs, t = timed(transmissibility_sets, elastomer)
    line(f"H1 estimates ({len(frfs[0])} records)", t)
    k0 = k0_from_measurements(elastomer).k0
    fit_maxwell(list(frfs[0]), k0=k0)  # warm-up
    maxwell, t = timed(fit_maxwell, list(frfs[0]), k0=k0, order=2)
    line("Maxwell SQP order 2, all FRFs (nlopt SLSQP)", t, 0.5, f"error {100 * maxwell.error:.2f} %")
    checked, t = timed(fit_maxwell, list(frfs[0]), k0=k0, order=2, cross_check=True)
    line("Maxwell SQP + global cross-check (GN_ISRES)", t, 20.0,
         f"reached global: {checked.cross_check.reached_global}, gap {100 * checked.cross_check.gap:.4f} %")

    folder = realdata_dir("pyvisco_dma")
    if folder is None:
        print("DMA benchmark skipped: ../shared/realdata/pyvisco_dma is absent")
        return
    table = read_pyvisco_complex_modulus(folder / "verification" / "freq_master" / "freq_user_master.csv")
    for order in (20, 27):
        dma, t = timed(fit_complex_stiffness, table.freq, table.storage, table.loss, order=order)
        line(f"idkit DMA Prony fit, {order} terms (SLSQP)", t, None, f"error {100 * dma.error:.2f} %")
    try:
        import pandas as pd
        from pyvisco import load, master, prony
    except ImportError as problem:
        print(f"pyvisco comparison skipped: pyvisco does not import ({problem}); pip install pyvisco")
        return
    csv = (folder / "verification" / "freq_master" / "freq_user_master.csv").read_bytes()
    try:
        start = time.perf_counter()
        loaded = load.user_master(csv, "freq", -5.0, "E")  # Tref -5 C per SOURCE.txt
        df_master = loaded[0] if isinstance(loaded, tuple) else loaded
        df_master = master.smooth(df_master, win=1)  # pyvisco's discretize reads the *_filt columns
        df_dis = prony.discretize(df_master)
        fitted = prony.fit(df_dis, df_master, opt=False)
        t = time.perf_counter() - start
    except (AttributeError, KeyError, TypeError, ValueError) as problem:  # a third-party API we do not control
        print(f"pyvisco comparison failed: {type(problem).__name__}: {problem}")
        return
    prony_series, df_fit = fitted[0], fitted[1]
    extra = f"{len(prony_series['df_terms'])} terms" if isinstance(prony_series, dict) and "df_terms" in prony_series \
        else ""
    terms = prony_series.get("df_terms") if isinstance(prony_series, dict) else None
    if terms is not None and {"tau_i", "alpha_i"} <= set(terms.columns):
        omega = 2 * np.pi * table.freq
        tau, alpha = terms["tau_i"].to_numpy(), terms["alpha_i"].to_numpy()
        unit = 1e6 if float(prony_series["E_0"]) < 1e6 else 1.0  # pyvisco works in MPa
        e0 = float(prony_series["E_0"]) * unit
        model = e0 * (1 - alpha.sum() + (alpha * 1j * omega[:, None] * tau / (1 + 1j * omega[:, None] * tau)).sum(1))
        measured = table.storage + 1j * table.loss
        error = np.sqrt(np.mean(np.abs(model - measured) ** 2 / np.abs(measured) ** 2))
        extra += f", error {100 * error:.2f} % on the same points as idkit"
    del df_fit
    line("pyvisco discretize + fit (opt=False)", t, None, extra)

if __name__ == "__main__":
    main()
