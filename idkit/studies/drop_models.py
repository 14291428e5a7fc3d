"""Which drop model do the held-out drops support? Conditioned fall vs drop rig, per isolator model.

:func:`compare_drop_models` validates the same held-out drops once per (isolator model,
drop model) pair with :func:`idkit.validate.validate_drops` and tabulates, per top mass,
the median and worst relative errors of the peak acceleration in compression and in
tension, with each run's verdict. :meth:`DropModelComparison.supported` names the pair the
data support: the one with the smallest worst-phase median error among those that PASS (or,
if none passes, the smallest overall), so the report's default choice is read from data,
not assumed.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from idkit.errors import ValidationError
from idkit.validate import validate_drops

__all__ = ["DROP_MODELS", "DropModelComparison", "compare_drop_models", "wire_rope_drop_models"]

#: The two drop models of :func:`idkit.validate.validate_drops`.
DROP_MODELS = ("conditioned", "rig")


@dataclass(frozen=True)
class DropModelComparison:
    """Drop validations of several isolator models under both drop models.

    Attributes
    ----------
    table : pandas.DataFrame
        One row per isolator model, drop model and top mass: ``median_compression_error [-]``,
        ``worst_compression_error [-]``, ``median_tension_error [-]``,
        ``worst_tension_error [-]`` (absolute relative errors of the peak acceleration),
        ``drops``, ``verdict``.
    results : dict
        ``(model name, drop model) -> ValidationResult``.
    notes : tuple of str
        Models left out and why.
    loop_errors : dict
        Model name -> ``(small, large)`` mean loop error (7.1, fractions) of each model on the
        same fit loops (the model-form evidence beside the drops).
    """

    table: pd.DataFrame
    results: dict
    notes: tuple = ()
    loop_errors: dict = field(default_factory=dict)

    def supported(self) -> tuple[str, str]:
        """``(model name, drop model)`` the held-out drops support (module docstring)."""
        scores = {}
        for key, result in self.results.items():
            summary = result.summary
            worst_phase = np.nanmax([summary.get("median_peak_acceleration_compression_error", np.nan),
                                     summary.get("median_peak_acceleration_tension_error", np.nan)])
            scores[key] = (result.verdict != "PASS", worst_phase)
        return min(scores, key=lambda key: scores[key])

    def report(self) -> str:
        """The table and the supported choice in words."""
        model, drop = self.supported()
        best = self.results[(model, drop)].summary
        text = self.table.to_string(index=False, float_format=lambda v: f"{v:.3f}")
        notes = "".join(f"\n{note}" for note in self.notes)
        return (f"{text}{notes}\nsupported by the held-out drops: {model} with the {drop} drop model (median peak "
                f"error {best.get('median_peak_acceleration_compression_error', np.nan):.3f} in compression, "
                f"{best.get('median_peak_acceleration_tension_error', np.nan):.3f} in tension)")


def _per_mass(result, model: str, drop_model: str) -> list[dict]:
    table = result.metrics
    valid = table["status"] == "ok"
    rows = []
    for mass, group in table[valid].groupby("top mass [kg]"):
        row = {"isolator model": model, "drop model": drop_model, "top mass [kg]": mass, "drops": len(group)}
        for column, label in (("peak accel compression", "compression"), ("peak accel tension", "tension")):
            error = np.abs(group[f"{column} simulated [m/s^2]"] / group[f"{column} measured [m/s^2]"] - 1)
            error = error[np.isfinite(error)]
            row[f"median_{label}_error [-]"] = float(np.median(error)) if error.size else np.nan
            row[f"worst_{label}_error [-]"] = float(np.max(error)) if error.size else np.nan
        row["verdict"] = result.verdict
        rows.append(row)
    return rows


def compare_drop_models(measurements, models: dict, *, drop_models=DROP_MODELS, name: str = "drops",
                        workers=None) -> DropModelComparison:
    """Validate the same drops under every isolator model and drop model.

    Parameters
    ----------
    measurements : sequence of DropMeasurement
        Held-out drops (with top mass, bottom mass and drop height for the rig).
    models : dict
        Name -> keyword arguments of :func:`~idkit.validate.validate_drops` naming the model,
        e.g. ``{"plain Iwan": {"isolator": rope}, "modulated Iwan": {"isolator": modulated}}``
        or ``{"hybrid": {"upper": elastomer, "lower": rope}}``.
    drop_models : sequence of str, default ("conditioned", "rig")
    name : str
        Name of the validations.
    workers : int, optional

    Returns
    -------
    DropModelComparison
    """
    measurements = list(measurements)
    if not models:
        raise ValidationError("compare_drop_models: no isolator model given")
    unknown = sorted(set(drop_models) - set(DROP_MODELS))
    if unknown:
        raise ValidationError(f"drop_models: found {unknown}, expected some of {list(DROP_MODELS)}")
    results, rows = {}, []
    for model_name, arguments in models.items():
        for drop_model in drop_models:
            result = validate_drops(measurements, drop_model=drop_model, workers=workers,
                                    name=f"{name}: {model_name}, {drop_model} drop model", **arguments)
            results[(model_name, drop_model)] = result
            rows.extend(_per_mass(result, model_name, drop_model))
    return DropModelComparison(table=pd.DataFrame(rows), results=results)


def wire_rope_drop_models(drops, fit, *, valid_range=None, workers=None) -> DropModelComparison:
    """Plain vs slip-modulated Iwan, conditioned fall vs drop rig, on a wire rope's held-out drops.

    Both families come from ``fit.family_fits`` (the family rule of
    :func:`idkit.fit.fit_iwan_measurements` fits both when the plain model misses the loops);
    when the modulation stage did not run there, it is fitted here on the fit's own loop sets
    on top of the plain fit (:func:`idkit.fit.iwan_modulated.fit_iwan_modulated`). Both models
    carry the fit's identified viscous damping. A modulated fit that is not a success is left
    out of the table, with its reasons in :attr:`DropModelComparison.notes`.

    Parameters
    ----------
    drops : sequence of DropMeasurement
        Held-out wire-rope drops.
    fit : MeasurementFit
        The Iwan fit (:func:`idkit.fit.fit_iwan_measurements`), its ``data`` the loop sets.
    valid_range : (float, float), optional
        Deflections over which a modulated fit made here keeps the spring stiff (m).
    workers : int, optional

    Returns
    -------
    DropModelComparison
    """
    from idkit.fit.iwan_modulated import fit_iwan_modulated

    plain_result = fit.family_fits.get("plain", fit.result)
    modulated = fit.family_fits.get("modulated")
    if modulated is None:
        modulated = fit_iwan_modulated(list(fit.data.small), list(fit.data.large), plain=plain_result,
                                       valid_range=valid_range).to_iwan_result()
    models = {"plain Iwan": {"isolator": fit.with_damping(plain_result.model)}}
    loop_errors = {"plain Iwan": (float(plain_result.error_small), float(plain_result.error_large))}
    notes = []
    if modulated.success:
        models["slip-modulated Iwan"] = {"isolator": fit.with_damping(modulated.model)}
        loop_errors["slip-modulated Iwan"] = (float(modulated.error_small), float(modulated.error_large))
    else:
        notes.append("slip-modulated Iwan left out: " + "; ".join(modulated.reasons))
    comparison = compare_drop_models(drops, models, name="wire rope drops", workers=workers)
    return DropModelComparison(table=comparison.table, results=comparison.results, notes=tuple(notes),
                               loop_errors=loop_errors)
