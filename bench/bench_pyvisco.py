"""idkit against pyvisco on pyvisco's own DMA isotherms: shift factors, master curve, Prony series.

Both sides, one core each (BLAS threads pinned to 1 before numpy loads), the same file
(``../shared/realdata/pyvisco_dma/examples/freq_user_raw.csv``: 21 isotherms, -50 to 100 C),
the same reference temperature (-5 C). pyvisco is not an idkit dependency; run the bench
from a virtual environment that has both::

    python3 -m venv /tmp/pvenv && /tmp/pvenv/bin/pip install -c constraints/ci.txt -e . pyvisco
    /tmp/pvenv/bin/python bench/bench_pyvisco.py [--repeat 3]

What is compared (printed):

* shift factors: idkit (pairwise superposition of cubic-smoothed isotherms) and pyvisco
  (``master.get_aT``: power-law fits of neighbouring isotherms), beside the set shipped with
  the raw file (re-referenced to -5 C);
* Prony series: idkit ``fit_prony`` (order pruned to within 1.1 x the best error) at idkit's
  master curve; pyvisco ``prony.fit`` (one term a decade, fixed times, L-BFGS-B) and
  ``opt.nprony`` (term reduction, criterion 1.5 x) at pyvisco's master curve;
* one error measure for all: RMS over the 210 measured points of ``|E*_model - E*_meas| /
  |E*_meas|``, each model evaluated at the points' reduced frequencies under its own
  tool's shift factors (what the tool claims about the material), and under the other
  tool's (to separate the shift from the series);
* time of each step: min and median over ``--repeat`` runs.
"""

from __future__ import annotations

import os

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_variable] = "1"

import argparse  # noqa: E402
import contextlib  # noqa: E402
import io  # noqa: E402
import statistics  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from idkit.datasets import read_pyvisco_complex_modulus, read_pyvisco_shift_factors, realdata_dir  # noqa: E402
from idkit.fit import fit_prony  # noqa: E402
from idkit.io.complex_stiffness import ShiftFactorTable  # noqa: E402
from idkit.models import GeneralizedMaxwell  # noqa: E402
from idkit.signal.shift_factors import estimate_shift_factors, group_isotherms  # noqa: E402

REFERENCE_C = -5.0


def timed(function, repeat):
    """Result of the last run and the wall times of ``repeat`` runs (s)."""
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        with contextlib.redirect_stdout(io.StringIO()):  # pyvisco prints its progress
            result = function()
        times.append(time.perf_counter() - start)
    return result, times


def pyvisco_model(prony: dict) -> GeneralizedMaxwell:
    """pyvisco's Prony dict (E_0 in MPa, alpha_i, tau_i) as an idkit modulus model in Pa.

    Terms with alpha_i = 0 (pyvisco's bounded fit leaves some at zero) are dropped: they
    contribute nothing, and the order printed counts the terms that do.
    """
    terms = prony["df_terms"]
    alpha, tau = terms["alpha_i"].to_numpy(float), terms["tau_i"].to_numpy(float)
    alpha, tau = alpha[alpha > 0], tau[alpha > 0]
    e0 = 1e6 * float(prony["E_0"])
    return GeneralizedMaxwell(k0=e0 * (1 - alpha.sum()), k=e0 * alpha, rate=1 / tau, quantity="modulus")


def rms_error(model, table, log_a_t_of_row) -> float:
    measured = table.storage + 1j * table.loss
    predicted = model.complex_modulus(table.freq * 10.0 ** log_a_t_of_row)
    return float(np.sqrt(np.mean(np.abs(predicted - measured) ** 2 / np.abs(measured) ** 2)))


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    try:
        import pyvisco.load as pv_load
        import pyvisco.master as pv_master
        import pyvisco.opt as pv_opt
        import pyvisco.prony as pv_prony
    except ImportError:
        print("pyvisco is not installed here; see this script's docstring", file=sys.stderr)
        return 2
    folder = realdata_dir("pyvisco_dma")
    if folder is None:
        print("../shared/realdata/pyvisco_dma is absent", file=sys.stderr)
        return 2
    path = folder / "examples" / "freq_user_raw.csv"
    table = read_pyvisco_complex_modulus(path)
    reference_k = REFERENCE_C + 273.15
    labels, temperatures = group_isotherms(table.temperature)

    # --- shift factors and master curves
    estimate, idkit_shift_times = timed(lambda: estimate_shift_factors(
        table.freq, table.storage, table.loss, table.temperature, reference_temperature_k=reference_k), args.repeat)
    idkit_master = table.master_curve(ShiftFactorTable(temperature=estimate.temperature_k, log_a_t=estimate.log_a_t))

    def pyvisco_master():
        df_raw, *_ = pv_load.user_raw(pv_load.file(path), "freq", "E")
        df_a_t, _ = pv_master.get_aT(df_raw, REFERENCE_C)
        df_master = pv_master.smooth(pv_master.get_curve(df_raw, df_a_t, REFERENCE_C), win=1)
        return df_a_t, df_master

    (pv_a_t, pv_master_curve), pv_shift_times = timed(pyvisco_master, args.repeat)
    pv_log = np.interp(temperatures - 273.15, pv_a_t["T"].to_numpy(float), pv_a_t["log_aT"].to_numpy(float))
    beside = read_pyvisco_shift_factors(folder / "examples" / "time_user_raw__shift_factors.csv")
    order = np.argsort(beside.temperature)
    beside_t, beside_y = beside.temperature[order], beside.log_a_t[order]
    beside_log = np.interp(temperatures, beside_t, beside_y) - np.interp(reference_k, beside_t, beside_y)

    print(f"pyvisco DMA isotherms ({path.name}: {table.freq.size} points, {temperatures.size} isotherms), "
          f"reference {REFERENCE_C:g} C, one core, {args.repeat} repetitions\n")
    print("shift factors log10 aT [decades]")
    print(f"{'T [C]':>8} {'idkit':>9} {'+-':>6} {'pyvisco':>9} {'shipped':>9}")
    for i, t in enumerate(temperatures):
        print(f"{t - 273.15:8.1f} {estimate.log_a_t[i]:9.3f} {estimate.log_a_t_stderr[i]:6.3f} {pv_log[i]:9.3f} "
              f"{beside_log[i]:9.3f}")
    print(f"largest |idkit - pyvisco| {np.max(np.abs(estimate.log_a_t - pv_log)):.3f} decades, "
          f"|idkit - shipped| {np.max(np.abs(estimate.log_a_t - beside_log)):.3f}, "
          f"|pyvisco - shipped| {np.max(np.abs(pv_log - beside_log)):.3f}\n")

    # --- Prony series
    idkit_fit, idkit_fit_times = timed(lambda: fit_prony(idkit_master.freq, idkit_master.storage, idkit_master.loss,
                                                         quantity="modulus"), args.repeat)

    def pyvisco_fixed():
        df_dis = pv_prony.discretize(pv_master_curve)
        return pv_prony.fit(df_dis, pv_master_curve)[0]

    pv_fixed, pv_fixed_times = timed(pyvisco_fixed, args.repeat)

    def pyvisco_reduced():
        prony_series, n_opt, _ = pv_opt.nprony(pv_master_curve, pv_fixed, window="min", opt=1.5)
        return prony_series[n_opt]

    pv_reduced, pv_reduced_times = timed(pyvisco_reduced, args.repeat)

    own = {"idkit": estimate.log_a_t[labels], "pyvisco": pv_log[labels]}
    rows = [("idkit fit_prony (auto)", idkit_fit.model, "idkit", idkit_shift_times, idkit_fit_times),
            ("pyvisco prony.fit", pyvisco_model(pv_fixed), "pyvisco", pv_shift_times, pv_fixed_times),
            ("pyvisco opt.nprony", pyvisco_model(pv_reduced), "pyvisco", pv_shift_times,
             [a + b for a, b in zip(pv_fixed_times, pv_reduced_times)])]
    print("Prony series on the 210 measured points (RMS |dE*| / |E*|)")
    print(f"{'fit':<24} {'terms':>5} {'own shifts':>10} {'other shifts':>12} "
          f"{'shift s min/med':>16} {'series s min/med':>17}")
    for name, model, tool, shift_times, fit_times in rows:
        other = "pyvisco" if tool == "idkit" else "idkit"
        print(f"{name:<24} {model.order:5d} {100 * rms_error(model, table, own[tool]):9.2f}% "
              f"{100 * rms_error(model, table, own[other]):11.2f}% "
              f"{min(shift_times):7.3f}/{statistics.median(shift_times):<8.3f} "
              f"{min(fit_times):8.3f}/{statistics.median(fit_times):<8.3f}")
    print(f"\nidkit kept order {idkit_fit.order} (success {idkit_fit.success}; rule: fewest terms within "
          f"{idkit_fit.factor:g} x the best of orders 1-{int(idkit_fit.table['order'].max())})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
