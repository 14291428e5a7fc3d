"""The simple baselines an identified model must out-predict (issue 32: "it must predict better
than every simple baseline").

:func:`fit_baselines` fits, to force records of any deflection history (the training records),
the two simple models a user would try first, each by least squares over all records with every
record weighted alike (its force errors divided by its RMS force and the square root of its
length, as the element fits weigh them):

* ``"linear spring and dashpot"`` - ``F = k x + c dx/dt`` (:class:`~idkit.models.VoigtModel`),
  ``k, c >= 0``, the rate ``dx/dt`` by central differences of each record
  (:func:`numpy.gradient` on its sample times): a linear least-squares problem, solved exactly
  (:func:`scipy.optimize.nnls`);
* ``"Jenkin element"`` - a spring in series with a slider beside a parallel spring
  (:func:`idkit.fit.elements.fit_jenkin`, the Iwan model of order 1), from its four starts.

The third baseline, predicting zero force, needs no fit: its normalised RMS error is 1 on every
record. :func:`idkit.validate.history.validate_histories` scores the baselines beside the model
(``baselines=``); docs/validation.md, "Baselines".
"""

from __future__ import annotations

import math

import numpy as np
import scipy.optimize

from idkit.errors import DataError, FitError
from idkit.fit.elements import _checked_histories, fit_jenkin
from idkit.models import VoigtModel

__all__ = ["fit_baselines", "fit_linear_spring_dashpot", "baselines_for_records", "BASELINE_NAMES"]

#: Names of the fitted baselines, in the order :func:`fit_baselines` returns them.
BASELINE_NAMES = ("linear spring and dashpot", "Jenkin element")


def fit_linear_spring_dashpot(histories) -> VoigtModel:
    """``F = k x + c dx/dt`` by weighted linear least squares with ``k, c >= 0`` (module docstring).

    ``histories``: records with ``name``, ``time`` (s), ``deflection`` (m), ``force`` (N)."""
    records = _checked_histories(histories)
    rows, targets = [], []
    for record in records:
        weight = 1.0 / (math.sqrt(float(np.mean(record.force**2))) * math.sqrt(record.force.size))
        rate = np.gradient(record.deflection, record.time)
        rows.append(weight * np.column_stack([record.deflection, rate]))
        targets.append(weight * record.force)
    matrix, target = np.vstack(rows), np.concatenate(targets)
    scale = np.max(np.abs(matrix), axis=0)  # columns of order 1 for nnls
    scale[scale == 0.0] = 1.0
    solution, _ = scipy.optimize.nnls(matrix / scale, target)
    stiffness, damping = solution / scale
    return VoigtModel(k=float(stiffness), damping=float(damping))


def fit_baselines(histories, *, seed: int = 0) -> dict:
    """Baseline name (:data:`BASELINE_NAMES`) -> fitted model, each with ``force(deflection, time=time)``.

    Raises
    ------
    FitError
        Bad records (named), or a baseline that cannot be fitted.
    """
    linear = fit_linear_spring_dashpot(histories)
    try:
        jenkin = fit_jenkin(histories, seed=seed, statistics=False).model
    except FitError as problem:
        raise FitError(f"Jenkin baseline: {problem}") from None
    return dict(zip(BASELINE_NAMES, (linear, jenkin)))


def baselines_for_records(data, *, isolator: str | None = None, split: str | None = "validation",
                          seed: int = 0) -> tuple[dict, str]:
    """The baselines for validating the ``split`` records of ``data`` (a measurement set or
    measurements): fitted on the set's ``fit`` split when ``split`` is another and the set holds fit
    records (of ``isolator``), else on the validated records themselves (the best each baseline
    can do there: a stricter test). Returns ``(baselines, where)``, ``where`` saying which records."""
    from idkit.observe.histories import force_histories

    training = None
    if split != "fit":
        try:
            training, _ = force_histories(data, isolator=isolator, split="fit")
        except DataError:
            training = None
    where = "the fit split's records"
    if not training:
        training, _ = force_histories(data, isolator=isolator, split=split)
        where = "the validated records themselves"
    return fit_baselines(training, seed=seed), f"{where} ({len(training)} records)"
