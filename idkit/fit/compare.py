"""Side-by-side comparison of hysteresis models fitted to the same loop sets."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

__all__ = ["LoopModelComparison", "compare_loop_models"]


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
    otherwise :class:`ValueError` names the first difference.
    """
    from idkit.errors import FitError

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
