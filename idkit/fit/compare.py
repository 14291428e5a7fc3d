"""Model comparisons on the same data: loop models side by side, order tables (SPEC 4).

* :func:`compare_loop_models` - Iwan against Bouc-Wen set by set;
* :func:`iwan_order_table` - Iwan orders 1-6 on the same loops, with the order rule
  (:mod:`idkit.fit.orders`);
* :func:`maxwell_order_table` - Maxwell orders and the Voigt model on the same FRFs.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.errors import FitError
from idkit.fit.iwan import fit_iwan
from idkit.fit.iwan_start import smallest_branch_secant
from idkit.fit.maxwell import fit_maxwell, fit_voigt
from idkit.fit.model_form import is_model_form_reason
from idkit.fit.orders import ORDER_RULE_FACTOR, order_rule
from idkit.models import GeneralizedMaxwell
from idkit.observe.quasi_static import as_loop_sets

__all__ = ["LoopModelComparison", "compare_loop_models", "ORDER_RULE_FACTOR", "iwan_order_table",
           "maxwell_order_table"]


@dataclass(frozen=True)
class LoopModelComparison:
    """Errors of several loop models on the same sets.

    Attributes
    ----------
    per_set : pandas.DataFrame
        One row per set: ``group`` (small/large), ``set``, then one
        ``<model> error [%]`` column per model (objective 7.1 of the final model).
    summary : pandas.DataFrame
        One row per model: ``model``, ``n_params`` (free parameters),
        ``mean small [%]``, ``mean large [%]``, ``mean all [%]``, ``time [s]``,
        ``evaluations``.
    """

    per_set: pd.DataFrame
    summary: pd.DataFrame

    def report(self) -> str:
        """Both tables as text."""
        return ("[[Per set]]\n" + self.per_set.to_string(index=False, float_format=lambda v: f"{v:.3f}")
                + "\n[[Summary]]\n" + self.summary.to_string(index=False, float_format=lambda v: f"{v:.3f}"))


def _n_params(result) -> int:
    if hasattr(result, "n_params"):
        return int(result.n_params)
    return int(sum(1 for par in result.parameters.values() if par.vary))


def compare_loop_models(results: dict) -> LoopModelComparison:
    """Tabulate loop fits (e.g. ``{"iwan": IwanFitResult, "bouc_wen": BoucWenFitResult}``) set by set.

    Every result must have been fitted to the same sets (same names, same order);
    otherwise a :class:`~idkit.errors.FitError` names the first difference.
    """
    items = list(results.items())
    if not items:
        raise FitError("results: found none, expected at least one fit result")
    first_name, first = items[0]
    for name, result in items[1:]:
        if result.small_names != first.small_names or result.large_names != first.large_names:
            raise FitError(f"results: {name!r} was fitted to sets {result.small_names + result.large_names}, "
                           f"{first_name!r} to {first.small_names + first.large_names}; expected the same sets")
    rows = [{"group": "small", "set": n} for n in first.small_names]
    rows += [{"group": "large", "set": n} for n in first.large_names]
    per_set = pd.DataFrame(rows)
    summary = []
    for name, result in items:
        errors = 100 * np.concatenate([result.small_errors, result.large_errors])
        per_set[f"{name} error [%]"] = errors
        summary.append({"model": name, "n_params": _n_params(result),
                        "mean small [%]": 100 * float(np.mean(result.small_errors)),
                        "mean large [%]": 100 * float(np.mean(result.large_errors)),
                        "mean all [%]": float(np.mean(errors)), "time [s]": float(result.elapsed_s),
                        "evaluations": int(result.evaluations)})
    return LoopModelComparison(per_set=per_set, summary=pd.DataFrame(summary))


# --------------------------------------------------------------------------- order tables


def iwan_order_table(small, large, *, orders: Sequence[int] = (1, 2, 3, 4, 5, 6), **options) -> pd.DataFrame:
    """Fit orders ``orders`` on the same loops and tabulate what each identifies (SPEC 4).

    One row per order: ``order``, ``n_params`` (``3 + 2 n``), ``error_small_percent``,
    ``error_large_percent``, ``stuck_stiffness [N/m]`` (``g1 + sum k_i``),
    ``smallest_loop_secant [N/m]`` (tip-to-tip secant of the smallest measured loop, the
    data's own stuck-stiffness reading), ``spring_negative_below [m]`` and
    ``spring_negative_above [m]`` (where ``g1 + 2 g2 x + 3 g3 x^2`` turns negative,
    +-inf if never), ``success``, ``reasons``, ``model_form_only`` (not a success only because
    the model form misses the loops, :mod:`idkit.fit.model_form`) and ``recommended``: the
    lowest order whose mean of small and large error is within :data:`ORDER_RULE_FACTOR` of the
    best, among the fits that succeeded (an order that stopped at a limit or a bound is not
    recommended while another succeeds; when none did, among the ``model_form_only`` ones),
    ``family`` and ``fit`` (``"loops"``: fitted without a valid-range
    barrier; ``"valid range"``: with one). ``options`` go to :func:`fit_iwan`.
    """
    return iwan_order_fits(small, large, orders=orders, **options)[0]


def iwan_order_fits(small, large, *, orders: Sequence[int] = (1, 2, 3, 4, 5, 6), **options):
    """:func:`iwan_order_table` and the fit of every order: ``(table, {order: IwanFitResult})``
    (the measurement-level fit keeps the recommended order's fit instead of repeating it)."""
    small_sets = as_loop_sets(small, "small", options.get("points_per_set", 200))
    large_sets = as_loop_sets(large, "large", options.get("points_per_set", 200))
    secant = smallest_branch_secant(small_sets + large_sets)
    rows, results = [], {}
    for order in orders:
        result = fit_iwan(small_sets, large_sets, order=int(order), **options)
        results[int(order)] = result
        rows.append(iwan_order_row(result, secant))
    table = pd.DataFrame(rows)
    table["recommended"] = table["order"] == order_rule(table, 0.5 * (table["error_small_percent"]
                                                                  + table["error_large_percent"]))
    return table, results


def iwan_order_row(result, secant: float) -> dict:
    """One row of the Iwan order table for a fit (plain or slip-modulated: ``family`` from its
    settings, ``n_params`` its varied parameters); ``secant`` the smallest loop's secant, N/m."""
    below, above = result.model.valid_deflection_range()
    return {"order": int(result.model.order), "n_params": int(sum(1 for p in result.parameters.values() if p.vary)),
            "error_small_percent": 100 * result.error_small, "error_large_percent": 100 * result.error_large,
            "stuck_stiffness [N/m]": float(result.model.stuck_stiffness), "smallest_loop_secant [N/m]": secant,
            "spring_negative_below [m]": below, "spring_negative_above [m]": above,
            "success": result.success, "reasons": "; ".join(result.reasons),
            "model_form_only": bool(result.reasons) and all(map(is_model_form_reason, result.reasons)),
            "family": getattr(result.settings, "family", "plain"),
            "fit": "loops" if getattr(result.settings, "valid_range", None) is None else "valid range"}


def maxwell_order_table(frfs, *, k0: float, orders: Sequence[int] = (1, 2, 3, 4), voigt: bool = True,
                        **options) -> pd.DataFrame:
    """Errors of Maxwell orders ``orders`` and of the Voigt model on the same data (SPEC 4).

    Each order is fitted from its default start and, when the previous order of the
    table is lower, also from that optimum extended by weak elements (stiffness at the
    lower bound, rates in the widest gaps of log rate); the better fit is kept, so an
    order never reports a worse error than the model it contains (a start of its own can end
    in a local minimum above the lower order's error).

    Returns a DataFrame with one row per model: ``model``, ``order``, ``n_params``,
    ``error_percent`` (objective 7.5), ``at_bound`` (free parameters stuck at a
    bound, comma-separated, ``""`` if none), ``success`` and ``recommended``: the lowest
    Maxwell order whose error is within :data:`ORDER_RULE_FACTOR` of the best Maxwell
    error, among the successful fits (an order with a parameter at a bound is not
    recommended while another succeeds; the Voigt row never is). ``options`` go to
    :func:`fit_maxwell` (and the common ones to :func:`fit_voigt`).
    """
    rows, previous = [], None
    for order in orders:
        result = fit_maxwell(frfs, k0=k0, order=order, **options)
        if previous is not None and previous.model.order < order and "start" not in options:
            nested = fit_maxwell(frfs, k0=k0, order=order, start=_nested_start(previous.model, order, k0, options),
                                 **options)
            if nested.error < result.error:
                result = nested
        previous = result
        rows.append({"model": "maxwell", "order": int(order), "n_params": 2 * int(order) + 1,
                     "error_percent": 100 * result.error, "at_bound": ", ".join(result.at_bound),
                     "success": result.success})
    if voigt:
        voigt_options = {key: value for key, value in options.items()
                         if key in ("band", "backend", "stiffness_bounds", "rate_bounds", "m_eff_max",
                                    "isolator_mass", "max_evals", "ftol", "seed")}
        result = fit_voigt(frfs, k0=k0, **voigt_options)
        rows.append({"model": "voigt", "order": 0, "n_params": 3, "error_percent": 100 * result.error,
                     "at_bound": ", ".join(result.at_bound), "success": result.success})
    table = pd.DataFrame(rows)
    maxwell = table[table["model"] == "maxwell"]
    table["recommended"] = (table["model"] == "maxwell") & (table["order"] == order_rule(maxwell, maxwell["error_percent"]))
    return table


def _nested_start(model: GeneralizedMaxwell, order: int, k0: float, options: dict) -> GeneralizedMaxwell:
    """``model`` with weak elements added up to ``order``: at the stiffness lower bound,
    each at the geometric middle of the widest gap of log rate (bounds included)."""
    low_k = (options.get("stiffness_bounds") or (0.1 * k0, 10 * k0))[0]
    rate_low, rate_high = options.get("rate_bounds", (1.0, 1e4))
    k, rate = list(np.asarray(model.k, float)), list(np.asarray(model.rate, float))
    while len(k) < order:
        edges = np.log(np.sort(np.concatenate([[rate_low, rate_high], rate])))
        widest = int(np.argmax(np.diff(edges)))
        k.append(float(low_k))
        rate.append(float(np.exp(0.5 * (edges[widest] + edges[widest + 1]))))
    order_of_rates = np.argsort(rate)
    return GeneralizedMaxwell(k0=k0, k=np.asarray(k)[order_of_rates], rate=np.asarray(rate)[order_of_rates],
                              m_eff=model.m_eff)
