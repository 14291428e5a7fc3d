"""Model choice by prediction: every candidate family fitted and cross-validated across records.

:func:`fit_auto` fits each family of a candidate set (:data:`FAMILIES`) to a device's force
histories (:mod:`idkit.observe.histories`), then refits it with each group of records held out
(leave one test condition out: records of one amplitude and cycle rate, e.g. repetitions, go
together; with a single group, leave one record out), **warm-started from the full fit**, and
predicts the held-out records from the virgin state with the fold's model. The scores are the
normalised RMS force error over each whole record (:func:`~idkit.observe.histories.normalised_rms_error`:
predicting zero scores 1).

**The choice** (docs/fitting.md, "Model choice by prediction"): among the families whose full fit
is a success (all of them when none is), the family with the fewest parameters whose mean
cross-validated error is within :data:`~idkit.fit.compare.ORDER_RULE_FACTOR` (1.1) of the lowest:
the order rule's standard, applied to prediction instead of training error. **Success** requires
the chosen family's full fit to be a success and its predictions to generalise: for every held-out
group, the mean cross-validated error at most :data:`GENERALISATION_FACTOR` times the larger of the
group's training error (the full fit's error on the same records) and its noise floor
(:func:`~idkit.observe.histories.noise_floor`); otherwise the result says "does not generalise" and
names the records. A held-out group whose amplitudes lie outside the other records' amplitude range
(beyond :data:`~idkit.observe.histories.GROUP_TOLERANCE`) asks the fold's model to extrapolate in
amplitude, which the model finally fitted on every record does not do there: its error counts in the
choice, and a group beyond the factor is reported (``extrapolated``), not judged.

**Families are fitted in order**, the cheap ones first; a family with a screen (a cheap first
stage, :class:`Family`) is stopped after it when its training error is above
:data:`EARLY_STOP_FACTOR` times the lowest of the families fitted before it (no full fit, no
folds; ``stopped_early`` in the table): a wrong expensive family costs its screen only.

**A family** is a :class:`Family` ``(name, fit, description, screen=None)`` with ``fit(histories, *, start=None,
seed=0) -> CandidateFit``; ``start`` is the same family's full fit, to warm-start the folds. Adding
one to the candidate set is one line: append it to :data:`FAMILIES` (or pass ``families=`` to
:func:`fit_auto`). The families of this module fit the rate-independent loop models on loops cut
from the histories (:func:`history_loops`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
import time as _time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from idkit.checks import Real, accepts
from idkit.errors import FitError, IdkitError
from idkit.fit.compare import iwan_order_fits
from idkit.fit.elements import fit_clearance_jenkin, fit_pinched_boucwen, fit_rate_dependent_jenkin
from idkit.fit.orders import ORDER_RULE_FACTOR, within_order_rule
from idkit.fit.result import undetermined_groups
from idkit.forked import fork_call
from idkit.observe.histories import ForceHistory, force_histories, noise_floor, normalised_rms_error
from idkit.observe.quasi_static import LOOP_POINTS_PER_SET, prepare_loops, split_threshold

__all__ = [
    "CandidateFit", "Family", "FAMILIES", "element_family", "GENERALISATION_FACTOR", "AutoFit", "fit_auto", "history_loops",
    "cross_validation_folds", "fit_plain_iwan", "fit_modulated_iwan", "fit_boucwen_family", "IWAN_ORDERS",
    "EARLY_STOP_FACTOR", "screen_boucwen",
]

#: A family generalises when each held-out group's mean cross-validated error is at most this
#: times the larger of its training error and its noise floor. 1.5: a right model's held-out error
#: is its noise floor plus the error of parameters estimated without the group, and issue 32 asks
#: a chosen model to predict held-out histories within 1.5 x the noise floor.
GENERALISATION_FACTOR = 1.5
#: Evaluation limit per local stage of a warm-started Bouc-Wen fold (the full fit's is 3000, after a
#: global search): a fold starts at the full fit's optimum, near its own, and the Bouc-Wen family's
#: folds are the costliest of ``fit auto``.
FOLD_BOUCWEN_EVALS = 500
#: Orders the plain and slip-modulated Iwan families try (the order rule picks among them).
IWAN_ORDERS = (1, 2, 3, 4, 5, 6)
#: A family with a screen (:class:`Family`) is stopped when its mean training error after the
#: screen is above this factor times the lowest mean training error of the families fully fitted
#: before it. 2: a right family's screen ends within 1.2 x the noise floor on the truths of
#: :mod:`idkit.synth.devices` (docs/fitting.md, "Stopping wrong families early"), and no family's
#: training error is far below the floor, so the true family keeps a margin of 1.7.
EARLY_STOP_FACTOR = 2.0
#: Least-squares iterations of a pinched Bouc-Wen screen (its first start only, thinned records; each
#: iteration also evaluates a finite-difference Jacobian, eight evaluations): enough for the true
#: family's screen to end at its noise floor (docs/fitting.md, "Stopping wrong families early").
PINCHED_SCREEN_EVALS = 10
#: Evaluations per local stage of a Bouc-Wen screen (no global search, no restarts, 100-point loops).
BOUCWEN_SCREEN_EVALS = 200


@dataclass(frozen=True)
class CandidateFit:
    """One family fitted to some force histories.

    Attributes
    ----------
    family : str
    model : IsolatorModel
        ``model.force(deflection, time=time)`` gives the force in N; writable as a model file.
    success : bool
    reasons : tuple of str
        Why it is not a success (empty when it is).
    params, stderr : dict
        Parameter name -> value and standard error (SI units; NaN where there is none).
    undetermined : list of str
        Parameters the data determine only in combination (|correlation| >= 0.999).
    n_params : int
        Parameters varied by the fit.
    result : object
        The fitter's own result (e.g. an :class:`~idkit.fit.IwanFitResult`), for its report.
    """

    family: str
    model: object
    success: bool
    reasons: tuple[str, ...]
    params: dict
    stderr: dict
    undetermined: list
    n_params: int
    result: object = field(default=None, repr=False)


@dataclass(frozen=True)
class Family:
    """A candidate family: ``fit(histories, *, start=None, seed=0) -> CandidateFit``.

    ``screen``, optional: ``screen(histories, *, seed=0) -> model``, a cheap first stage of the fit
    (a fraction of its cost). :func:`fit_auto` runs it first and stops the family there when the
    model's mean training error is above :data:`EARLY_STOP_FACTOR` times the lowest of the
    families fully fitted before it; else the full fit runs as without a screen. Worth giving to
    a family whose fit is expensive where it does not belong (the pinched Bouc-Wen and Bouc-Wen
    families: a wrong family's optimiser wanders to costly parameters)."""

    name: str
    fit: Callable[..., CandidateFit]
    description: str
    screen: Callable | None = None


def history_loops(histories: Sequence[ForceHistory], points_per_set: int | None = LOOP_POINTS_PER_SET):
    """Small and large loop sets of force histories (one set per history, cut at its first and
    last reversal, :func:`~idkit.observe.quasi_static.prepare_loops`), split at the histories' own
    :func:`~idkit.observe.quasi_static.split_threshold`; with one amplitude, both groups hold every set."""
    sets, amplitudes = [], []
    for history in histories:
        try:
            sets.append(prepare_loops(history.deflection, history.force, points_per_set=points_per_set,
                                      name=history.name))
        except FitError as problem:
            raise FitError(f"force history {history.name!r}: {problem}") from None
        amplitudes.append(history.amplitude)
    threshold = split_threshold(amplitudes)
    small = [s for s, a in zip(sets, amplitudes) if a <= threshold]
    large = [s for s, a in zip(sets, amplitudes) if a > threshold]
    if not small or not large:
        return list(sets), list(sets)
    return small, large


def _candidate(family: str, result, model, parameters) -> CandidateFit:
    """A :class:`CandidateFit` from a fitter's result and its lmfit parameters."""
    params = {name: float(p.value) for name, p in parameters.items()}
    stderr = {name: float(p.stderr) if p.stderr is not None else math.nan for name, p in parameters.items()}
    varied = sum(1 for p in parameters.values() if p.vary)
    undetermined = sorted({name for group in undetermined_groups(parameters) for name in group})
    return CandidateFit(family=family, model=model, success=bool(result.success), reasons=tuple(result.reasons),
                        params=params, stderr=stderr, undetermined=undetermined, n_params=int(varied), result=result)


@functools.lru_cache(maxsize=4)
def _plain_order_rule(histories: tuple, seed: int, orders: tuple, points_per_set):
    """The plain Iwan fits of every order on the histories' loops and the order the order rule
    recommends, shared by the plain and the slip-modulated family within one :func:`fit_auto`
    (the histories are keyed by identity): ``(small, large, fits by order, recommended order)``."""
    small, large = history_loops(histories, points_per_set)
    table, fits = iwan_order_fits(small, large, orders=orders, points_per_set=None, seed=seed)
    return small, large, fits, int(table.loc[table["recommended"], "order"].iloc[0])


def fit_plain_iwan(histories: Sequence[ForceHistory], *, start: CandidateFit | None = None, seed: int = 0,
                   orders: Sequence[int] = IWAN_ORDERS, points_per_set: int | None = LOOP_POINTS_PER_SET
                   ) -> CandidateFit:
    """The plain Iwan family: orders ``orders`` and the order rule (docs/fitting.md); with ``start``
    (a fit of this family), that model's order refitted from it."""
    from idkit.fit.iwan import fit_iwan

    if start is not None:
        small, large = history_loops(histories, points_per_set)
        result = fit_iwan(small, large, start=start.model, points_per_set=None, seed=seed)
    else:
        _, _, fits, order = _plain_order_rule(tuple(histories), seed, tuple(orders), points_per_set)
        result = fits[order]
    return _candidate("iwan", result, result.model, result.params)


def fit_modulated_iwan(histories: Sequence[ForceHistory], *, start: CandidateFit | None = None, seed: int = 0,
                       orders: Sequence[int] = IWAN_ORDERS, points_per_set: int | None = LOOP_POINTS_PER_SET
                       ) -> CandidateFit:
    """The slip-modulated Iwan family, ordered as ``fit iwan --family modulated`` orders it (one
    order rule, :func:`~idkit.fit.family.choose_iwan_family`): the modulation stage
    (:func:`~idkit.fit.fit_iwan_modulated`) from the lowest plain fit (the plain family's, computed
    once), elements added by continuation in the order up to ``max(orders)`` until a fit succeeds
    with every parameter determined, else the order rule over the chain; with ``start``, the stage
    refitted from that model at its order."""
    from idkit.fit.family import choose_iwan_family
    from idkit.fit.iwan_modulated import fit_iwan_modulated

    if start is not None:
        small, large = history_loops(histories, points_per_set)
        result = fit_iwan_modulated(small, large, plain=start.model, points_per_set=None)
        return _candidate("iwan_modulated", result, result.model, result.lmfit_parameters)
    small, large, fits, order = _plain_order_rule(tuple(histories), seed, tuple(orders), points_per_set)
    # the loops' own model-form check is in every fit's reasons: no record-level floor check here
    result, _, _ = choose_iwan_family(small, large, fits, plain_order=order, family="modulated")
    return _candidate("iwan_modulated", result, result.model, result.params)


def screen_boucwen(histories: Sequence[ForceHistory], *, seed: int = 0, points_per_set: int | None = 100):
    """The Bouc-Wen family's screen: its staged fit without the global search and restarts, at most
    :data:`BOUCWEN_SCREEN_EVALS` evaluations a stage, on loops of ``points_per_set`` points."""
    from idkit.fit.boucwen import fit_boucwen

    small, large = history_loops(histories, points_per_set)
    return fit_boucwen(small, large, points_per_set=None, global_search=False, max_evals=BOUCWEN_SCREEN_EVALS,
                       restarts=0, seed=seed).model


def fit_boucwen_family(histories: Sequence[ForceHistory], *, start: CandidateFit | None = None, seed: int = 0,
                       points_per_set: int | None = LOOP_POINTS_PER_SET, global_max_evals: int = 1000,
                       fold_max_evals: int = FOLD_BOUCWEN_EVALS) -> CandidateFit:
    """The modified Bouc-Wen family (:func:`~idkit.fit.fit_boucwen`, staged with a global search);
    with ``start``, a local refit from that model (no global search)."""
    from idkit.fit.boucwen import fit_boucwen

    small, large = history_loops(histories, points_per_set)
    if start is not None:
        result = fit_boucwen(small, large, start=start.model, points_per_set=None, global_search=False, seed=seed,
                             max_evals=fold_max_evals)
    else:
        result = fit_boucwen(small, large, points_per_set=None, global_max_evals=global_max_evals, seed=seed)
    return _candidate("boucwen", result, result.model, result.params)


def element_family(name: str, fitter: Callable, description: str, screen_evals: int | None = None) -> Family:
    """A :class:`Family` of one of the physical elements of :mod:`idkit.fit.elements` (a fitter
    ``fitter(histories, *, start=None, seed=0, statistics=True)`` returning an
    :class:`~idkit.fit.elements.ElementFitResult`); a fold is warm-started from the full fit.

    Folds are fitted like the full fit, polished on the full records: a fold fitted on thinned
    records only would score a rate-dependent element at other step rates than the held-out
    records it predicts. With ``screen_evals``, the family's screen is the fitter's first start
    alone, at most ``screen_evals`` evaluations on the thinned records, without statistics."""

    def fit(histories: Sequence[ForceHistory], *, start: CandidateFit | None = None, seed: int = 0) -> CandidateFit:
        result = fitter(histories, start=None if start is None else start.result, seed=seed)
        return CandidateFit(family=name, model=result.model, success=result.success, reasons=tuple(result.reasons),
                            params=dict(result.params), stderr=dict(result.stderr),
                            undetermined=list(result.undetermined), n_params=result.n_params, result=result)

    def screen(histories: Sequence[ForceHistory], *, seed: int = 0):
        return fitter(histories, seed=seed, statistics=False, max_nfev=screen_evals, max_starts=1).model

    return Family(name, fit, description, screen if screen_evals is not None else None)


#: The candidate set of :func:`fit_auto`, in the order they are fitted and listed: the cheap families
#: first, so that the screened expensive ones meet a low best training error. To add a family,
#: append ``Family(name, fit, description)`` here (docs/fitting.md, "How to add a family"); an
#: element of :mod:`idkit.fit.elements` through :func:`element_family`.
FAMILIES: list[Family] = [
    Family("iwan", fit_plain_iwan, "plain Iwan model, orders 1-6 and the order rule"),
    Family("iwan_modulated", fit_modulated_iwan, "slip-modulated Iwan model, orders by continuation (fit iwan's chain)"),
    element_family("clearance_jenkin", fit_clearance_jenkin,
                   "Jenkin element through a clearance (dead zone), with a parallel spring"),
    element_family("rate_dependent_jenkin", fit_rate_dependent_jenkin,
                   "Jenkin element whose slip force rises with sliding speed, with a parallel spring"),
    Family("boucwen", fit_boucwen_family, "modified Bouc-Wen model", screen_boucwen),
    element_family("pinched_boucwen", fit_pinched_boucwen, "Bouc-Wen model with Baber-Noori pinching",
                   screen_evals=PINCHED_SCREEN_EVALS),
]


def cross_validation_folds(histories: Sequence[ForceHistory]) -> list[tuple[str, tuple[str, ...]]]:
    """``(label, held-out record names)`` per fold: one fold per group when there are two groups or
    more, else one per record (leave one record out)."""
    groups: dict[str, list[str]] = {}
    for history in histories:
        groups.setdefault(history.group, []).append(history.name)
    if len(groups) >= 2:
        return [(label, tuple(names)) for label, names in groups.items()]
    return [(history.name, (history.name,)) for history in histories]


def _predict(model, history: ForceHistory) -> tuple[float, str]:
    """nRMS error of ``model`` on ``history`` (simulated from the virgin state), and why it is
    infinite when the model cannot simulate the record."""
    try:
        predicted = model.force(history.deflection, time=history.time)
    except IdkitError as problem:
        return math.inf, f"{history.name}: {problem}"
    error = normalised_rms_error(predicted, history.force)
    return (error, "") if math.isfinite(error) else (math.inf, f"{history.name}: the prediction is not finite")


@dataclass(frozen=True)
class FamilyScore:
    """One family of :func:`fit_auto`: its full fit and its errors per record."""

    family: Family
    fit: CandidateFit | None
    training: dict
    cross_validated: dict
    fit_time_s: float
    cv_time_s: float
    problem: str = ""
    not_generalising: tuple = ()
    extrapolated: tuple = ()
    #: mean training error after the family's screen (NaN without one)
    screen_error: float = math.nan
    #: stopped after its screen (:data:`EARLY_STOP_FACTOR`): no full fit, no folds
    stopped_early: bool = False

    @property
    def training_error(self) -> float:
        """Mean training error of the full fit (of the screen when the family was stopped there)."""
        if self.stopped_early:
            return self.screen_error
        return float(np.mean(list(self.training.values()))) if self.training else math.nan

    @property
    def cv_error(self) -> float:
        return float(np.mean(list(self.cross_validated.values()))) if self.cross_validated else math.nan

    @property
    def generalises(self) -> bool:
        """Every held-out group within the generalisation factor (:func:`fit_auto`)."""
        return self.fit is not None and not self.not_generalising


@dataclass(frozen=True)
class AutoFit:
    """Result of :func:`fit_auto`.

    Attributes
    ----------
    scores : tuple of FamilyScore
        Every family: full fit, training and cross-validated error per record, times.
    chosen : FamilyScore
        The family chosen by prediction (module docstring).
    folds : list of (label, names)
        The held-out groups.
    floors : dict
        Record -> noise floor (:func:`~idkit.observe.histories.noise_floor`).
    not_generalising : tuple of str
        One line per held-out group of the chosen family beyond :data:`GENERALISATION_FACTOR`,
        naming its records; empty when the family generalises.
    why : str
        Why the family was chosen.
    provenance : DataProvenance or None
    """

    scores: tuple
    chosen: FamilyScore
    folds: list
    floors: dict
    not_generalising: tuple
    why: str
    provenance: object = None
    generalisation_factor: float = GENERALISATION_FACTOR
    judged_folds: int = 0

    @property
    def model(self):
        return self.chosen.fit.model

    @property
    def success(self) -> bool:
        """The chosen family's full fit is a success and its predictions generalise."""
        return bool(self.chosen.fit.success) and not self.not_generalising

    @property
    def reasons(self) -> tuple[str, ...]:
        reasons = tuple(self.chosen.fit.reasons)
        if self.not_generalising:
            reasons += ("does not generalise: " + "; ".join(self.not_generalising),)
        return reasons

    def table(self) -> pd.DataFrame:
        """One row per family: errors (%), parameters determined, success, times."""
        rows = []
        for score in self.scores:
            fit = score.fit
            rows.append({
                "family": score.family.name,
                "n_params": fit.n_params if fit else 0,
                "training_error_percent": 100 * score.training_error,
                "cv_error_percent": 100 * score.cv_error,
                "determined": (f"{fit.n_params - len(fit.undetermined)}/{fit.n_params}" if fit else "-"),
                "success": bool(fit.success) if fit else False,
                "generalises": score.generalises,
                "stopped_early": score.stopped_early,
                "fit_time_s": score.fit_time_s,
                "cv_time_s": score.cv_time_s,
                "chosen": score is self.chosen,
            })
        return pd.DataFrame(rows)

    def report(self) -> str:
        lines = [f"[[Model choice by prediction: {len(self.scores)} families, {len(self.folds)} folds "
                 f"(held out: {', '.join(label for label, _ in self.folds)})]]",
                 self.table().to_string(index=False, float_format=lambda v: f"{v:.3g}"),
                 f"chosen: {self.chosen.family.name}: {self.why}"]
        for score in self.scores:
            if score.problem:
                lines.append(f"  {score.family.name}: {score.problem}")
            elif score.fit is not None and not score.fit.success:
                lines.append(f"  {score.family.name} not a success: " + "; ".join(score.fit.reasons))
            if score is not self.chosen and score.not_generalising:
                lines.append(f"  {score.family.name} does not generalise: " + "; ".join(score.not_generalising))
        if self.chosen.extrapolated:
            lines.append("beyond the factor where a fold extrapolates in amplitude (reported, not judged): "
                         + "; ".join(self.chosen.extrapolated))
        if self.not_generalising:
            lines.append(f"does not generalise (held-out error above {self.generalisation_factor:g} x the larger of "
                         "training error and noise floor): " + "; ".join(self.not_generalising))
        elif self.judged_folds == 0:
            lines.append("generalisation not judged: every fold extrapolates in amplitude (hold-out groups at the "
                         "ends of the amplitude range only); record an amplitude between the others to judge it")
        else:
            lines.append(f"generalises: every judged held-out group ({self.judged_folds} of {len(self.folds)}) within "
                         f"{self.generalisation_factor:g} x the larger of its training error and noise floor")
        lines.append("per record (training / cross-validated / noise floor, %): " + ", ".join(
            f"{name} {100 * self.chosen.training[name]:.3g} / {100 * self.chosen.cross_validated.get(name, math.nan):.3g}"
            f" / {100 * self.floors[name]:.3g}" for name in self.chosen.training))
        if self.chosen.fit.result is not None and hasattr(self.chosen.fit.result, "report"):
            lines.append(self.chosen.fit.result.report())
        return "\n".join(lines)

    def provenance_dict(self) -> dict:
        from idkit import __version__
        from idkit.fit.measurement_fit import _jsonable

        table = self.table()
        return _jsonable({
            "fitter": "idkit.fit.auto.fit_auto",
            "idkit_version": __version__,
            "data": self.provenance.to_dict() if self.provenance is not None else None,
            "family": self.chosen.family.name,
            "why": self.why,
            "success": self.success,
            "reasons": list(self.reasons),
            "generalisation_factor": self.generalisation_factor,
            "folds_judged_for_generalisation": self.judged_folds,
            "folds": [{"held_out": label, "records": list(names)} for label, names in self.folds],
            "family_table": table.to_dict(orient="records"),
            "errors_per_record": {s.family.name: {"training": s.training, "cross_validated": s.cross_validated}
                                  for s in self.scores},
            "noise_floor_per_record": self.floors,
            "parameters": {"values": self.chosen.fit.params, "stderr": self.chosen.fit.stderr},
            "determined_only_in_combination": list(self.chosen.fit.undetermined),
            "extrapolated_folds_beyond_the_factor": list(self.chosen.extrapolated),
        })

    def save(self, path, *, overwrite: bool = False):
        """Write the chosen model as a model file with :meth:`provenance_dict`."""
        from idkit.models import save_model

        return save_model(self.model, path, provenance=self.provenance_dict(), overwrite=overwrite)


def _checked_histories(data, isolator, split):
    if isinstance(data, (list, tuple)) and data and all(isinstance(item, ForceHistory) for item in data):
        names = [h.name for h in data]
        if len(set(names)) != len(names):
            raise FitError(f"histories: found repeated names {sorted(n for n in set(names) if names.count(n) > 1)}, "
                           "expected one name per record")
        return list(data), None
    return force_histories(data, isolator=isolator, split=split)


@accepts(generalisation_factor=Real(ge=1.0, meaning="held-out error over training error"),
         early_stop_factor=Real(ge=1.0, optional=True, meaning="screen error over the best so far"),
         error=FitError)
def fit_auto(data, *, families: Sequence[Family] | None = None, isolator: str | None = None,
             split: str | None = "fit", seed: int = 0, generalisation_factor: float = GENERALISATION_FACTOR,
             early_stop_factor: float | None = EARLY_STOP_FACTOR,
             progress: Callable[[str], None] | None = None) -> AutoFit:
    """Fit every candidate family and choose by cross-validated prediction error (module docstring).

    Parameters
    ----------
    data : MeasurementSet, sequence of measurements, or sequence of ForceHistory
        The training records (a set's quasi-static records of ``isolator`` and ``split``).
    families : sequence of Family, optional
        Default :data:`FAMILIES`.
    isolator, split : as :func:`~idkit.observe.histories.force_histories`
    seed : int
        Passed to every family's fit.
    generalisation_factor : float, default :data:`GENERALISATION_FACTOR`
    early_stop_factor : float or None, default :data:`EARLY_STOP_FACTOR`
        A family with a screen stops there when its training error is above this factor times the
        lowest of the families fully fitted before it; None: every family is fitted in full.
    progress : callable, optional
        Called with a line per family as it finishes.

    Returns
    -------
    AutoFit

    Raises
    ------
    FitError
        Fewer than two records (nothing to hold out), no family that could be fitted, bad options.
    """
    families = list(FAMILIES if families is None else families)
    if not families or not all(isinstance(f, Family) for f in families):
        raise FitError(f"families: found {families!r}, expected a non-empty sequence of Family")
    names = [f.name for f in families]
    if len(set(names)) != len(names):
        raise FitError(f"families: found repeated names {names}, expected one family per name")
    histories, provenance = _checked_histories(data, isolator, split)
    if len(histories) < 2:
        raise FitError(f"records: found {len(histories)} force history, expected at least two: cross-validation "
                       "predicts a record from a fit to the others")
    folds = cross_validation_folds(histories)
    floors = {h.name: noise_floor(h) for h in histories}
    scores = []
    for family in families:
        fitted_so_far = [s.training_error for s in scores if s.fit is not None and math.isfinite(s.training_error)]
        best = min(fitted_so_far) if fitted_so_far else None
        score, screen_time, screen_error = _screened(family, histories, seed, best, early_stop_factor)
        if score is None:
            score = _score(family, histories, folds, seed)
            judged, extrapolated = _beyond(score, folds, floors, generalisation_factor, histories)
            score = dataclasses.replace(score, not_generalising=judged, extrapolated=extrapolated,
                                        fit_time_s=score.fit_time_s + screen_time, screen_error=screen_error)
        scores.append(score)
        if progress is not None:
            s = scores[-1]
            progress(f"{family.name}: training {100 * s.training_error:.3g} %, cross-validated "
                     f"{100 * s.cv_error:.3g} % ({s.fit_time_s:.3g} s fit, {s.cv_time_s:.3g} s folds)"
                     + (f"; {s.problem}" if s.problem else ""))
    fitted = [s for s in scores if s.fit is not None and math.isfinite(s.cv_error)]
    if not fitted:
        raise FitError("no candidate family could be fitted and cross-validated: " +
                       "; ".join(f"{s.family.name}: {s.problem}" for s in scores))
    candidates = [s for s in fitted if s.fit.success] or fitted
    best = min(s.cv_error for s in candidates)
    within = sorted((s for s in candidates if within_order_rule(s.cv_error, best)),
                    key=lambda s: (s.fit.n_params, s.cv_error))
    chosen = within[0]
    pool = "successful families" if any(s.fit.success for s in fitted) else "families (none is a success)"
    why = (f"fewest parameters ({chosen.fit.n_params}) among the {pool} whose cross-validated error is within "
           f"{ORDER_RULE_FACTOR:g} x the lowest ({100 * best:.3g} %): {100 * chosen.cv_error:.3g} %")
    by_name = {h.name: h for h in histories}
    judged_folds = sum(1 for _, held in folds if not _extrapolated(held, list(by_name.values())))
    return AutoFit(scores=tuple(scores), chosen=chosen, folds=folds, floors=floors, judged_folds=judged_folds,
                   not_generalising=chosen.not_generalising,
                   why=why, provenance=provenance, generalisation_factor=float(generalisation_factor))


def _extrapolated(held, histories) -> bool:
    """The held-out records' amplitudes lie outside the others' amplitude range (beyond the grouping
    tolerance): the fold's model is extrapolated there."""
    from idkit.observe.histories import GROUP_TOLERANCE

    inside = [h.amplitude for h in histories if h.name not in held]
    out = [h.amplitude for h in histories if h.name in held]
    return (max(out) > (1.0 + GROUP_TOLERANCE) * max(inside)) or (min(out) < (1.0 - GROUP_TOLERANCE) * min(inside))


def _beyond(score: FamilyScore, folds, floors: dict, factor: float, histories) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Lines per held-out group whose mean cross-validated error exceeds ``factor`` times the larger of
    its mean training error and its mean noise floor, naming the records: ``(judged, extrapolated)``,
    the second for groups whose amplitudes lie outside the other records' range (reported, not judged)."""
    if score.fit is None:
        return (), ()
    judged, extrapolated = [], []
    for label, held in folds:
        cv = float(np.mean([score.cross_validated[name] for name in held]))
        train = float(np.mean([score.training[name] for name in held]))
        floor = float(np.nanmean([floors[name] for name in held]))
        limit = factor * max(train, floor if math.isfinite(floor) else 0.0)
        if not cv <= limit:
            line = (f"{label} ({', '.join(held)}): held-out {100 * cv:.3g} % against training {100 * train:.3g} %, "
                    f"floor {100 * floor:.3g} % (limit {100 * limit:.3g} %)")
            (extrapolated if _extrapolated(held, histories) else judged).append(line)
    return tuple(judged), tuple(extrapolated)


def _cross_validate(family: Family, histories, folds, full: CandidateFit, seed: int) -> tuple[dict, list]:
    """Held-out error of each record of ``folds`` (a fold's fit warm-started from ``full``), and the
    problems met; plain values, so a forked child can return them."""
    cross_validated, problems = {}, []
    for label, held in folds:
        train = [h for h in histories if h.name not in held]
        try:
            fold = family.fit(train, start=full, seed=seed)
        except FitError as problem:
            problems.append(f"fold {label}: not fitted: {problem}")
            cross_validated.update({name: math.inf for name in held})
            continue
        for history in histories:
            if history.name in held:
                cross_validated[history.name], problem = _predict(fold.model, history)
                problems += [problem] if problem else []
    return cross_validated, problems


def _screened(family: Family, histories, seed: int, best: float | None,
              factor: float | None) -> tuple[FamilyScore | None, float, float]:
    """``(score, seconds, error)``: the family stopped after its screen (a :class:`FamilyScore`
    without a fit), or None when it has no screen, nothing was fitted before it, or its screen's
    mean training error is within ``factor`` times ``best``; the screen's wall time and error (NaN
    without a screen)."""
    if family.screen is None or best is None or factor is None:
        return None, 0.0, math.nan
    started = _time.perf_counter()
    try:
        model = family.screen(histories, seed=seed)
    except FitError:
        return None, _time.perf_counter() - started, math.nan  # the full fit says why
    error = float(np.mean([_predict(model, history)[0] for history in histories]))
    elapsed = _time.perf_counter() - started
    if error <= factor * best:
        return None, elapsed, error
    problem = (f"stopped after its first stage: training error {100 * error:.3g} % above {factor:g} x the lowest "
               f"of the families fitted before it ({100 * best:.3g} %)")
    return (FamilyScore(family, None, {}, {}, elapsed, 0.0, problem, screen_error=error, stopped_early=True),
            elapsed, error)


def _score(family: Family, histories, folds, seed) -> FamilyScore:
    started = _time.perf_counter()
    try:
        full = family.fit(histories, seed=seed)
    except FitError as problem:
        return FamilyScore(family, None, {}, {}, _time.perf_counter() - started, 0.0, f"not fitted: {problem}")
    fit_time = _time.perf_counter() - started
    problems = []
    training = {}
    for history in histories:
        training[history.name], problem = _predict(full.model, history)
        problems += [problem] if problem else []
    started = _time.perf_counter()
    # the folds are independent: half of them run in a forked child (a second core) while this
    # process runs the other half; where forking is not possible both halves run here
    half = len(folds) // 2
    child = fork_call(_cross_validate, family, histories, folds[:half], full, seed) if half else None
    cross_validated, fold_problems = _cross_validate(family, histories, folds[half:], full, seed)
    if child is not None:
        first, first_problems = child.result()
        cross_validated, fold_problems = {**first, **cross_validated}, first_problems + fold_problems
    problems += fold_problems
    return FamilyScore(family, full, training, cross_validated, fit_time, _time.perf_counter() - started,
                       "; ".join(problems))
