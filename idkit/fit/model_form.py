"""Model-form check of a loop fit: is its error more than the margin above the data's own noise floor?

The one rule (docs/fitting.md, "Verdicts"): a loop fit (plain or slip-modulated Iwan, Bouc-Wen)
whose mean error (7.1) over a group of sets (small or large loops) exceeds the group's noise
floor by more than :data:`FLOOR_MARGIN` is not a success: the model form misses the loops.
Two readings of the floor, one rule (:func:`misses_the_floor`): the array-level fitters see only
the resampled sets and read the floor off the residual of the fit itself
(:func:`loop_model_form_reasons`, :func:`residual_floor`: the difference between repeated
branches, else its second differences along each branch); the measurement-level fits read it
off each raw record as well (:func:`record_floor_reasons`, :func:`loop_noise_floor`). Each reason
is a :class:`ModelFormReason` naming its loop group, so a group is named once without reading
the text.

Why the difference ``error - floor`` (and not a test of whether the residual is white): every
real loop carries some model error, and a statistical test finds it once the noise is small
enough, in fits that still predict every held-out test. The margin says how much systematic
error a success may carry, in the units of the objective. Since the floor is never negative, a
fit can only fail when its own error exceeds the margin: an exactly right model on data whose
noise is below 2 % of each set's RMS force cannot fail, whatever the floor estimate.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from idkit.observe.histories import noise_floor

__all__ = ["FLOOR_MARGIN", "MODEL_FORM_PREFIX", "ModelFormReason", "is_model_form_reason", "misses_the_floor",
           "loop_model_form_reasons", "residual_floor", "loop_noise_floor", "record_floor_reasons"]

#: A loop fit is not a success when its mean error in a group (small or large loops) is more
#: than this above the group's noise floor: the reach of a model that is right (2 percentage
#: points above what the generating law scores on the same loops).
FLOOR_MARGIN = 0.02

#: Start of the text of the array-level reason.
MODEL_FORM_PREFIX = "the model form misses the"


class ModelFormReason(str):
    """A reason of the model-form check: its text, and the loop ``group`` it names ("small",
    "large"). A ``str`` everywhere a reason is read (reports, model files); the check itself
    tells its reasons apart by type (:func:`is_model_form_reason`), not by their words."""

    group: str

    def __new__(cls, text: str, group: str) -> "ModelFormReason":
        reason = super().__new__(cls, text)
        reason.group = group
        return reason

    def __reduce__(self):
        return (ModelFormReason, (str(self), self.group))


def is_model_form_reason(reason: str, group: str | None = None) -> bool:
    """``reason`` is the model-form check's (of loop group ``group``, when given)."""
    return isinstance(reason, ModelFormReason) and (group is None or reason.group == group)


def misses_the_floor(error: float, floor: float) -> bool:
    """The model-form rule: a group's mean ``error`` lies more than :data:`FLOOR_MARGIN` above its
    noise ``floor`` (both fractions of the RMS force, objective 7.1)."""
    return error - floor > FLOOR_MARGIN


#: Two branches repeat when both ends lie within this fraction of the branch's travel of each other.
REPEAT_TOLERANCE = 0.02


def residual_floor(measured, model, reversals, deflection) -> float:
    """Noise floor of one resampled loop set read off a fit's residual, as a fraction of its RMS force.

    **Repeated branches** (every pair of branches ``i``, ``i + 2`` of a set, same direction,
    both ends within :data:`REPEAT_TOLERANCE` of the travel): the model error is the same on
    both (the same deflections, the same hysteresis state in steady cycling) and cancels in the
    difference of their residuals, the noise does not: ``floor^2 = mean((r_i - r_{i+2})^2) / 2``.
    The noise is that of the resampled points, whatever the resampling did to it (a grid
    denser than the record interpolates the noise and lowers it in the error too), and what
    does not repeat (drift between cycles, the truth's own transient) counts as noise: the
    floor can read high, never low.

    **Otherwise** (a set whose cycles differ in amplitude, a single cycle): the noise estimate
    of :func:`idkit.signal.cycles.noise_level` applied to the residual, ``1.4826 median(|d2 -
    median(d2)|) / sqrt(6)``, ``d2`` its second differences along each branch (none across a
    reversal): a model error is smooth along a branch (points equally spaced in deflection) and
    contributes little. On a grid denser than the record two neighbouring points interpolate the
    same raw samples and this reads low (the points share their noise), so the check is
    stricter there.

    Returns NaN when neither applies (no branch of three points).
    """
    measured = np.asarray(measured, dtype=float)
    residual = np.asarray(model, dtype=float) - measured
    x = np.asarray(deflection, dtype=float)
    rms = math.sqrt(float(np.mean(measured**2)))
    if not rms > 0:
        return math.nan
    bounds = np.asarray(reversals, dtype=int)
    spans = list(zip(bounds[:-1], bounds[1:]))
    differences = []
    for (a, b), (c, d) in zip(spans[:-2], spans[2:]):
        travel = abs(x[b] - x[a])
        if (b - a == d - c and travel > 0 and abs(x[a] - x[c]) <= REPEAT_TOLERANCE * travel
                and abs(x[b] - x[d]) <= REPEAT_TOLERANCE * travel):
            differences.append(residual[a:b + 1] - residual[c:d + 1])
    if differences:
        return math.sqrt(float(np.mean(np.concatenate(differences) ** 2)) / 2.0) / rms
    second = [np.diff(residual[a:b + 1], 2) for a, b in spans if b - a >= 2]
    if not second:
        return math.nan
    d2 = np.concatenate(second)
    return float(1.4826 * np.median(np.abs(d2 - np.median(d2))) / math.sqrt(6.0)) / rms


def loop_model_form_reasons(groups: Sequence[tuple[str, Sequence, Sequence[np.ndarray]]], *,
                            remedy: str = "another model form or a higher order, docs/fitting.md") -> tuple[str, ...]:
    """One reason per group whose mean error is more than :data:`FLOOR_MARGIN` above its floor.

    Parameters
    ----------
    groups : sequence of (name, sets, model_forces)
        ``name`` ("small", "large"), the group's :class:`~idkit.observe.quasi_static.LoopSet`
        items and the fitted model's force along each (the start state the fit used).
    remedy : str
        What to try, quoted in the reason.

    Returns
    -------
    tuple of str
        The error of each set is (7.1), ``|F_model - F_meas| / |F_meas|``; the group's floor is
        the mean of its sets' :func:`residual_floor` (what an exactly right model scores under
        the objective: the mean of its sets' noise); sets without a floor are left out.
    """
    reasons = []
    for name, sets, forces in groups:
        errors, floors = [], []
        for loop, force in zip(sets, forces):
            measured = np.asarray(loop.force, dtype=float)
            floor = residual_floor(measured, force, loop.reversals, loop.deflection)
            if not math.isfinite(floor):
                continue
            errors.append(math.sqrt(float(np.sum((np.asarray(force) - measured) ** 2) / np.sum(measured**2))))
            floors.append(floor)
        if not errors:
            continue
        error, floor = float(np.mean(errors)), float(np.mean(floors))
        if misses_the_floor(error, floor):
            reasons.append(ModelFormReason(f"{MODEL_FORM_PREFIX} {name} loops: their error {100 * error:.3g} % is "
                           f"{100 * (error - floor):.3g} points above the noise floor {100 * floor:.2g} % read off "
                           "the residual (repeated branches, else second differences along each branch, limit "
                           f"{100 * FLOOR_MARGIN:g} points): the residual is systematic, not noise ({remedy})", name))
    return tuple(reasons)


def loop_noise_floor(records) -> dict:
    """Relative force noise of each quasi-static record by id: :func:`idkit.observe.histories.noise_floor`
    (``noise_level(force) / rms(force)``, the white sensor noise on the force), what a model that
    were exactly right would score under the objective (7.1). Offsets and drift between
    repetitions are not in it, so it is a lower bound of the floor, and :data:`FLOOR_MARGIN` is
    measured from it.
    """
    return {record.id or f"record{index}": noise_floor(record) for index, record in enumerate(records, start=1)}


def record_floor_reasons(result, records) -> tuple[str, ...]:
    """A reason per loop group of a loop fit whose mean error exceeds its records' noise floor
    (:func:`loop_noise_floor`) by more than :data:`FLOOR_MARGIN`.

    The group's floor is the largest over its records (repetitions); records are matched to the
    fit's sets by id. A group the fit's own check (:func:`loop_model_form_reasons`, the floor read
    off its residual) named already is not named again.
    """
    floors = loop_noise_floor(records)
    family = getattr(getattr(result, "settings", None), "family", None)
    remedy = {"plain": "a higher order, --order-table, or the slip-modulated Iwan: --family, docs/fitting.md",
              "modulated": "a higher order: --order auto, --order-table, docs/fitting.md"}.get(
        family, "another model form, docs/fitting.md")
    reasons = []
    named = tuple(getattr(result, "reasons", ()) or ())
    for group, names, errors in (("small", result.small_names, result.small_errors),
                                 ("large", result.large_names, result.large_errors)):
        known = [floors[name] for name in names if name in floors and math.isfinite(floors[name])]
        if not known or any(is_model_form_reason(reason, group) for reason in named):
            continue
        floor, error = max(known), float(np.mean(errors))
        if misses_the_floor(error, floor):
            reasons.append(f"{group}-loop error {100 * error:.3g} % is {100 * (error - floor):.3g} points above the "
                           f"noise floor {100 * floor:.2g} % of its {len(known)} record(s) (limit "
                           f"{100 * FLOOR_MARGIN:g} points): the model form misses the loops ({remedy}), or the "
                           "records carry a force offset the floor does not count (--remove-offsets)")
    return tuple(reasons)
