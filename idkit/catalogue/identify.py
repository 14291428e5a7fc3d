"""Identify one catalogue part: the family's fitter, held-out validation, covariance, summary.

:func:`identify_part` is the one place a part meets the fitters: a wire rope goes through
:func:`idkit.fit.fit_iwan_measurements` (order rule, family rule ``family="auto"``), an elastomer
through :func:`idkit.fit.fit_maxwell_measurements` (order rule). Replacing these two calls
(:data:`FITTERS`) by a model choice by prediction is a one-line change.

Held-out validation (the ``validation`` split of the part's set, never seen by the fit):

* wire rope: the relative RMS loop error (7.1) of the identified model on each held-out
  quasi-static record, grouped small / large as in the fit; PASS when each group's mean is
  within :data:`HELD_OUT_MARGIN` percentage points of the fit split's mean (the same
  2-point margin the model-form check allows above the noise floor: held-out repetitions of
  the same programme differ by their noise and the hand-driven path only);
* elastomer: :func:`idkit.validate.validate_frf` on the held-out white-noise runs, about the
  static preload read off the loops, with its documented thresholds.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from idkit.errors import DataError, FitError
from idkit.fit import fit_iwan_measurements, fit_maxwell_measurements, iwan_set_errors, loop_sets
from idkit.models import GeneralizedMaxwell, IwanModel
from idkit.validate import validate_frf

__all__ = ["FITTERS", "HELD_OUT_MARGIN", "TABLE_FREQ_HZ", "Identified", "covariance_of", "identified_record",
           "identify_measurements", "part_quantities"]

#: Percentage points the held-out loop error may exceed the fit split's (module docstring).
HELD_OUT_MARGIN = 2.0

#: The fitter of each family: ``fitter(measurement_set, **options) -> MeasurementFit``.
FITTERS = {
    "wire_rope": lambda measurements, **options: fit_iwan_measurements(measurements, **{"family": "auto", **options}),
    "elastomer": lambda measurements, **options: fit_maxwell_measurements(measurements, **options),
}

#: Frequency (Hz) at which the catalogue table reports a part's dynamic stiffness and loss.
TABLE_FREQ_HZ = 5.0


@dataclass(frozen=True)
class Identified:
    """What :func:`identify_measurements` found for one part.

    Attributes
    ----------
    fit : MeasurementFit
        The fit (model, provenance, reasons).
    covariance_names : tuple of str
        Model parameters the covariance covers (those with a standard error).
    covariance : ndarray, shape (p, p)
        Covariance of those parameters (SI units squared), from the fit's Jacobian
        (``redchi (J^T J)^-1``: lmfit's standard errors and correlations).
    held_out : dict
        ``verdict`` (PASS / FAIL / NOT RUN), ``metric`` and ``why``.
    quantities : dict
        Summary numbers for the table and the scaling laws (:func:`part_quantities`).
    valid_range_m : tuple or None
        Deflections (m) inside which the model was constrained to stay valid.
    seconds : float
    """

    fit: object
    covariance_names: tuple
    covariance: np.ndarray
    held_out: dict
    quantities: dict
    valid_range_m: tuple | None
    seconds: float = 0.0
    notes: tuple = field(default=())


def covariance_of(fit) -> tuple[tuple[str, ...], np.ndarray]:
    """Parameter names and covariance (SI) of a measurement fit's model parameters.

    From the lmfit parameters' standard errors and correlations; a parameter whose value
    is carried by the model under the same name and has a standard error enters. A fixed
    parameter with a standard error of its own (a Maxwell ``k0`` read off the loops) enters
    uncorrelated.
    """
    model_names = set(fit.model.params())
    parameters = fit.result.parameters
    names = [name for name, par in parameters.items() if name in model_names and par.stderr is not None
             and math.isfinite(par.stderr) and par.stderr > 0]
    if fit.damping is not None and "c_visc" in names:  # identified apart from the loops
        names.remove("c_visc")
    size = len(names)
    covariance = np.zeros((size, size))
    for i, a in enumerate(names):
        covariance[i, i] = parameters[a].stderr ** 2
        for j, b in enumerate(names):
            if i != j:
                correl = (parameters[a].correl or {}).get(b)
                if correl is not None and math.isfinite(correl):
                    covariance[i, j] = correl * parameters[a].stderr * parameters[b].stderr
    return tuple(names), covariance


def part_quantities(model, freq_hz: float = TABLE_FREQ_HZ) -> dict:
    """Summary numbers of an identified part (SI): what the table shows and the laws scale.

    Wire rope: ``stuck_stiffness`` (``g1 + sum k_i``, N/m), ``g1`` (N/m), ``total_slip_force``
    (``sum fc_i``, N). Elastomer: ``k0`` (N/m), ``dynamic_stiffness`` ``|k*(freq_hz)|`` (N/m),
    ``loss_factor`` at ``freq_hz``. Every part: ``stiffness_at_table_freq`` ``|k*(freq_hz)|`` of
    the small-amplitude model.
    """
    stiffness = float(abs(np.asarray(model.small_amplitude_stiffness(freq_hz))))
    out = {"stiffness_at_table_freq": stiffness}
    if isinstance(model, IwanModel):
        params = model.params()
        out.update(stuck_stiffness=model.stuck_stiffness, g1=params["g1"],
                   total_slip_force=float(sum(v for k, v in params.items() if k.startswith("fc_"))))
    elif isinstance(model, GeneralizedMaxwell):
        out.update(k0=model.k0, dynamic_stiffness=stiffness, loss_factor=float(model.loss_factor(freq_hz)))
    return out


def _held_out_loops(fit, measurements) -> dict:
    try:
        data = loop_sets(measurements, isolator=None, split="validation",
                         small_threshold=fit.options.get("small_threshold", 8e-3))
    except (DataError, FitError) as problem:
        return {"verdict": "NOT RUN", "metric": {}, "why": [f"no held-out loops: {problem}"]}
    metric, why = {}, []
    for group, sets, fitted in (("small", data.small, fit.result.small_errors),
                                ("large", data.large, fit.result.large_errors)):
        if not sets:
            continue
        held = 100.0 * float(np.mean(iwan_set_errors(fit.model, list(sets))))
        reference = 100.0 * float(np.mean(fitted)) if len(fitted) else float("nan")
        metric[f"{group}_loop_error_percent"] = held
        metric[f"{group}_fit_error_percent"] = reference
        if not held <= reference + HELD_OUT_MARGIN:
            why.append(f"{group} loops: held-out error {held:.2f} % is more than {HELD_OUT_MARGIN:g} points above "
                       f"the fit split's {reference:.2f} %")
    return {"verdict": "FAIL" if why else "PASS", "metric": metric, "why": why}


def _held_out_frf(fit, measurements) -> dict:
    held = [m for m in measurements.select(kind="white_noise", split="validation")]
    if not held:
        return {"verdict": "NOT RUN", "metric": {}, "why": ["no held-out white-noise run"]}
    result = validate_frf(held, isolator=fit.model, static_stiffness=fit.data.static_stiffness,
                          name="held-out white-noise FRFs")
    metric = {key: float(value) for key, value in result.summary.items()
              if isinstance(value, (int, float, np.floating)) and math.isfinite(float(value))}
    return {"verdict": result.verdict, "metric": metric, "why": list(result.why)}


def identify_measurements(measurements, family: str, *, fit_options: dict | None = None) -> Identified:
    """Fit a part's measurement set with its family's fitter and validate on the held-out split.

    Parameters
    ----------
    measurements : MeasurementSet
    family : {"wire_rope", "elastomer"}
    fit_options : dict, optional
        Passed to the family's fitter (:data:`FITTERS`), e.g. ``{"order": 3}``.

    Returns
    -------
    Identified
    """
    if family not in FITTERS:
        raise FitError(f"family: found {family!r}, expected one of {sorted(FITTERS)}")
    start = time.perf_counter()
    options = {"isolator": None, **(fit_options or {})}
    fit = FITTERS[family](measurements, **options)
    names, covariance = covariance_of(fit)
    held_out = _held_out_loops(fit, measurements) if family == "wire_rope" else _held_out_frf(fit, measurements)
    valid = getattr(fit.result.settings, "valid_range", None)
    return Identified(fit=fit, covariance_names=names, covariance=covariance, held_out=held_out,
                      quantities=part_quantities(fit.model),
                      valid_range_m=None if valid is None else tuple(float(v) for v in valid),
                      seconds=time.perf_counter() - start)


def identified_record(identified: Identified) -> dict:
    """JSON-ready summary of :class:`Identified` (no model, no data)."""
    fit = identified.fit
    return {
        "model_kind": fit.model.kind,
        "order": int(getattr(fit.model, "order", 0)),
        "success": bool(fit.success),
        "reasons": list(fit.reasons),
        "held_out": identified.held_out,
        "quantities": identified.quantities,
        "covariance": {"names": list(identified.covariance_names), "matrix": identified.covariance.tolist()},
        "valid_range_m": None if identified.valid_range_m is None else list(identified.valid_range_m),
        "loop_amplitude_range_m": None if fit.loop_amplitude_range is None else list(fit.loop_amplitude_range),
        "fit_seconds": identified.seconds,
    }

