"""Typed results of the loop fitters (Iwan, Bouc-Wen) and what every fit result shares.

Every fit returns a frozen dataclass with named fields, an lmfit
:class:`~lmfit.Parameters` view (``result.parameters``: values, physical bounds,
``vary``, ``stderr`` where estimated, unit in ``user_data``), ``report()`` text for
people and ``to_dataframe()`` for tables. The Maxwell and Voigt results are
:mod:`idkit.fit.maxwell_result`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import lmfit
import numpy as np
import pandas as pd

from idkit.models import BoucWenModel, IwanModel

__all__ = [
    "IwanFitSettings",
    "IwanStart",
    "StageResult",
    "IwanFitResult",
    "BoucWenFitSettings",
    "BoucWenFitResult",
    "UNDETERMINED_CORRELATION",
    "undetermined_groups",
    "determinacy_reasons",
]


#: |correlation| at or above which two fitted parameters are reported as determined only in
#: combination (:attr:`_LmfitStatistics.undetermined`): their standard errors then describe
#: the combination's flat direction, and each value alone is not a property of the data.
UNDETERMINED_CORRELATION = 0.999


#: Standard errors to either side of a positive parameter's value spanned by its 95 % interval
#: (two-sided normal quantile): an interval reaching zero leaves the parameter undetermined.
INTERVAL_Z = 1.96


def undetermined_groups(parameters: lmfit.Parameters, threshold: float = UNDETERMINED_CORRELATION
                        ) -> tuple[tuple[str, ...], ...]:
    """Groups of varied parameters linked by ``|correl| >= threshold`` (in parameter order)."""
    names = [name for name, par in parameters.items() if par.vary]
    group = {name: name for name in names}

    def root(name):
        while group[name] != name:
            group[name] = group[group[name]]
            name = group[name]
        return name

    for name in names:
        for other, value in (parameters[name].correl or {}).items():
            if other in group and value is not None and abs(value) >= threshold:
                group[root(other)] = root(name)
    members: dict[str, list[str]] = {}
    for name in names:
        members.setdefault(root(name), []).append(name)
    return tuple(tuple(found) for found in members.values() if len(found) > 1)


def determinacy_reasons(parameters: lmfit.Parameters, statistics, *, excused: tuple[str, ...] = ()) -> tuple[str, ...]:
    """Why the data do not determine the fitted parameters: the shared verdict of every fitter.

    The policy (docs/fitting.md, "Verdicts"): a fit whose varied parameters the data do not
    each determine is **not a success** (``success=False``), whatever its error, and the
    reason names the parameters. One reason per kind:

    * the statistics could not be formed (no residuals, fewer residuals than varied
      parameters) or a residual is not finite (NaN or inf) at the optimum;
    * a varied parameter has no standard error or a non-finite one: ``J^T J`` is singular or
      near-singular (smallest singular value below 1e-10 of the largest,
      :func:`idkit.fit._params.gauss_newton_covariance`), its Jacobian column is zero, or the
      Jacobian is not finite (``stderr_notes`` give the fitter's own words);
    * a positive parameter (search domain ``min >= 0``) whose 95 % interval ``value +- 1.96
      stderr`` reaches zero (:data:`INTERVAL_Z`): the data fix not even its order of magnitude;
    * parameters determined only in combination (``|correlation| >=``
      :data:`UNDETERMINED_CORRELATION`, :func:`undetermined_groups`).

    ``excused`` names parameters already given a reason of their own (a parameter on its search
    bound has no standard error by construction); they are not named again.
    """
    varied = [name for name, par in parameters.items() if par.vary and name not in excused]
    if not varied:
        return ()
    reasons = []
    if statistics is None:
        return (f"no least-squares statistics at the optimum: the data do not determine {', '.join(varied)}",)
    residual = np.asarray(getattr(statistics, "residual", ()), dtype=float)
    if residual.size and not np.all(np.isfinite(residual)):
        reasons.append(f"{int(np.sum(~np.isfinite(residual)))} of {residual.size} residuals are not finite at the "
                       "optimum (NaN or inf): the fit's error and standard errors mean nothing")
    nvarys = int(getattr(statistics, "nvarys", len(varied)) or 0)
    if 0 < int(getattr(statistics, "ndata", 0) or 0) <= nvarys:
        reasons.append(f"{int(statistics.ndata)} residuals for {nvarys} varied parameters: fewer data than "
                       "parameters, the data cannot determine them")
    missing = [name for name in varied
               if parameters[name].stderr is None or not np.isfinite(float(parameters[name].stderr))]
    if missing:
        notes = tuple(getattr(statistics, "stderr_notes", ()) or ())
        why = "; ".join(notes) if notes else "no finite standard error"
        reasons.append(f"not determined by the data: {', '.join(missing)} ({why})")
    wide = [name for name in varied if name not in missing and _interval_reaches_zero(parameters[name])]
    if wide:
        listed = ", ".join(f"{name} = {parameters[name].value:.4g} +- {parameters[name].stderr:.2g}" for name in wide)
        reasons.append(f"not determined by the data: {listed} (a positive parameter whose 95 % interval, "
                       f"+-{INTERVAL_Z:g} standard errors, reaches zero: not even its order of magnitude is fixed)")
    for group in undetermined_groups(parameters):
        group = [name for name in group if name not in excused]
        if len(group) > 1:
            reasons.append(f"determined only in combination: {', '.join(group)} (|correlation| >= "
                           f"{UNDETERMINED_CORRELATION:g}; each value alone is not fixed by the data)")
    return tuple(reasons)


def _interval_reaches_zero(par) -> bool:
    """A varied parameter whose search domain is non-negative (``min >= 0``: a stiffness, a slip
    force, a rate, an exponent) and whose 95 % interval ``value +- INTERVAL_Z stderr`` reaches
    zero (``stderr >= value / 1.96``, 51 % of the value). Signed parameters (``g2``, ``g3``, ``c``)
    are not judged: an interval across zero leaves their sign open, not their existence."""
    if par.min is None or not par.min >= 0.0 or par.stderr is None:
        return False
    value, stderr = float(par.value), float(par.stderr)
    return np.isfinite(stderr) and value > 0.0 and value - INTERVAL_Z * stderr <= 0.0


def _undetermined_lines(groups) -> list[str]:
    return [f"    determined only in combination: {', '.join(found)} (|correlation| >= {UNDETERMINED_CORRELATION:g}; "
            "each value alone is not fixed by the data)" for found in groups]


def _parameter_lines(parameters: lmfit.Parameters, notes: dict[str, str] | None = None) -> list[str]:
    """One line per parameter; ``notes`` (name -> text) are appended to their parameter's line."""
    notes = notes or {}
    lines = [f"    {'name':<8} {'value':>12} {'stderr':>10} {'unit':<7} {'bounds'}"]
    for name, par in parameters.items():
        unit = (par.user_data or {}).get("unit", "")
        stderr = f"{par.stderr:10.3g}" if par.stderr is not None else f"{'n/a':>10}"
        state = "" if par.vary else "  (fixed)"
        note = f"  ({notes[name]})" if name in notes else ""
        lines.append(f"    {name:<8} {par.value:12.5g} {stderr} {unit:<7} [{par.min:.3g}, {par.max:.3g}]{state}{note}")
    return lines


# --------------------------------------------------------------------------- Iwan


@dataclass(frozen=True)
class IwanFitSettings:
    """Algorithm settings of a three-stage Iwan fit (recorded for provenance)."""

    order: int
    backend: str
    points_per_set: int | None
    max_evals: int | None
    xtol: float
    ftol: float
    restarts: int
    initial_step: float
    initial_state: str
    seed: int
    valid_range: tuple[float, float] | None = None
    stage2_starts: int = 1
    #: ``"plain"`` (three stages) or ``"modulated"`` (the slip-modulation stage of
    #: :func:`idkit.fit.fit_iwan_modulated` on top of them)
    family: str = "plain"


@dataclass(frozen=True)
class IwanStart:
    """Automatic starting point read off the loops (see :func:`idkit.fit.iwan_start`).

    Attributes
    ----------
    stuck_stiffness : float
        Initial slope after reversals of the smallest branches, ``g1 + sum k_i``, N/m.
    half_height : float
        Half the vertical loop height of the largest loop at its centre, ``~ sum fc_i``, N.
    g1 : float
        Tip-to-tip secant slope of the largest loop minus ``half_height / amplitude``, N/m.
    slip_onset, slip_full : float
        Smallest and largest slip travel ``2 fc_i / k_i`` (m) of the starting
        elements: the travel after a reversal where the first and the last one slips.
    model : IwanModel
        The starting model built from these numbers.
    """

    stuck_stiffness: float
    half_height: float
    g1: float
    slip_onset: float
    slip_full: float
    model: IwanModel


@dataclass(frozen=True)
class StageResult:
    """One stage of a fit: what was free, on which sets, the errors and the cost.

    ``set_errors`` are the per-set relative RMS errors (7.1) as fractions (0.01 = 1 %)
    at the end of the stage; ``mean_error`` is their mean (the stage objective).
    ``status`` is the optimiser's end state as :mod:`idkit.fit._optim` set it
    (``"converged"``, ``"stalled"``, ``"max_evals"``, ...); ``message`` the same for people.
    """

    name: str
    data: str
    free: tuple[str, ...]
    start: dict
    params: dict
    set_names: tuple[str, ...]
    set_errors: np.ndarray
    mean_error: float
    start_error: float
    evaluations: int
    restarts: int
    message: str
    elapsed_s: float
    status: str = "converged"


class _LmfitStatistics:
    """lmfit's :class:`~lmfit.minimizer.MinimizerResult` names on a fit result.

    The result holds ``parameters`` (:class:`lmfit.Parameters`) and ``statistics``
    (the :class:`~lmfit.minimizer.MinimizerResult` of
    :func:`idkit.fit._params.jacobian_statistics` at the optimum, or None); ``nfev``
    and ``message`` are each result's own.
    """

    @property
    def params(self) -> lmfit.Parameters:
        """The fitted :class:`lmfit.Parameters` (``stderr``, ``correl``); same object as ``parameters``."""
        return self.parameters

    @property
    def chisqr(self) -> float:
        """``sum r^2`` of the (weighted) per-point residuals of the statistics."""
        return _statistic(self, "chisqr")

    @property
    def redchi(self) -> float:
        """``chisqr / (N - p)``: the variance of one weighted residual."""
        return _statistic(self, "redchi")

    @property
    def aic(self) -> float:
        """Akaike information criterion ``N ln(chisqr / N) + 2 p`` (lmfit's definition)."""
        return _statistic(self, "aic")

    @property
    def bic(self) -> float:
        """Bayesian information criterion ``N ln(chisqr / N) + ln(N) p`` (lmfit's definition)."""
        return _statistic(self, "bic")

    @property
    def ndata(self) -> int:
        """Residuals in the statistics (0 when none were computed)."""
        return 0 if self.statistics is None else int(self.statistics.ndata)

    @property
    def stderr_notes(self) -> tuple[str, ...]:
        """Why a fitted parameter has no standard error (empty when every one has)."""
        return tuple(getattr(self.statistics, "stderr_notes", ()) or ())

    @property
    def undetermined(self) -> tuple[tuple[str, ...], ...]:
        """Groups of fitted parameters the data determine only in combination.

        Two parameters belong to one group when the correlation of their estimates is at least
        :data:`UNDETERMINED_CORRELATION` in magnitude (connected groups are merged): the
        residuals change along a combination of them and hardly along the others, so each value
        alone can move far under a tiny change of the data while the fit quality does not. Empty when every correlation is below the threshold or none was
        estimated.
        """
        return undetermined_groups(self.parameters)

    def fit_report(self, **options) -> str:
        """:func:`lmfit.fit_report` of the statistics (fit statistics, variables, correlations),
        followed by the reasons for any missing standard error; ``options`` go to lmfit."""
        source = self.statistics if self.statistics is not None else self.parameters
        text = lmfit.fit_report(source, **options)
        return "\n".join([text, *(f"    no stderr: {note}" for note in self.stderr_notes)])


class LoopErrors:
    """What every loop fit's result reads off its per-set errors (7.1) and its reasons: the plain
    and Bouc-Wen results (:class:`_LoopFitResult`) and the modulation stage's
    (:class:`~idkit.fit.iwan_modulated.ModulatedIwanFitResult`)."""

    @property
    def error_small(self) -> float:
        """Mean relative RMS error (7.1, fraction) of the final model on the small sets."""
        return float(np.mean(self.small_errors))

    @property
    def error_large(self) -> float:
        """Mean relative RMS error (7.1, fraction) of the final model on the large sets."""
        return float(np.mean(self.large_errors))

    @property
    def success(self) -> bool:
        """True unless :attr:`reasons` names a problem."""
        return not self.reasons


class _LoopFitResult(LoopErrors, _LmfitStatistics):
    """What the two loop fits (Iwan, Bouc-Wen) share: per-set errors, stages, success, tables.

    A subclass is a frozen dataclass with ``model``, ``stages`` (:class:`StageResult`),
    ``small_errors``, ``large_errors``, ``small_names``, ``large_names``, ``settings``,
    ``parameters``, ``elapsed_s`` and ``statistics``, and defines :attr:`reasons`.
    """

    @property
    def evaluations(self) -> int:
        """Objective evaluations over all stages."""
        return int(sum(stage.evaluations for stage in self.stages))

    @property
    def nfev(self) -> int:
        """Objective evaluations of the stages plus the residual evaluations of the Jacobian."""
        return self.evaluations + (0 if self.statistics is None else int(self.statistics.nfev))

    @property
    def message(self) -> str:
        """Stop message of the last stage and, if any, why the fit is not a success."""
        last = self.stages[-1].message if self.stages else ""
        return "; ".join([last, *self.reasons]) if self.reasons else last

    @property
    def backend(self) -> str:
        """Optimiser backend, ``"nlopt"`` or ``"scipy"``."""
        return self.settings.backend

    def _stopped_stages(self) -> list[str]:
        """One reason per stage whose optimiser stopped on its evaluation limit (its status)."""
        return [f"{stage.name} stopped at the evaluation limit ({stage.message})" for stage in self.stages
                if stage.status == "max_evals"]

    def to_dataframe(self) -> pd.DataFrame:
        """One row per (stage, set) plus ``final`` rows: ``stage``, ``data``, ``set``,
        ``error_percent`` and ``evaluations`` (of the stage; 0 on the final rows)."""
        rows = []
        for stage in self.stages:
            for name, error in zip(stage.set_names, stage.set_errors):
                rows.append({"stage": stage.name, "data": stage.data, "set": name,
                             "error_percent": 100.0 * error, "evaluations": stage.evaluations})
        for data, names, errors in (("small", self.small_names, self.small_errors),
                                    ("large", self.large_names, self.large_errors)):
            for name, error in zip(names, errors):
                rows.append({"stage": "final", "data": data, "set": name,
                             "error_percent": 100.0 * error, "evaluations": 0})
        return pd.DataFrame(rows)

    def _summary_lines(self) -> list[str]:
        """The lines both reports open with: cost, success and reasons, mean errors."""
        return [
            f"    evaluations {self.evaluations}, wall time {self.elapsed_s:.3f} s, success {self.success}, "
            f"seed {self.settings.seed}",
            *(f"    not a success: {reason}" for reason in self.reasons),
            f"    mean error (7.1): small sets {100 * self.error_small:.3f} %, "
            f"large sets {100 * self.error_large:.3f} %",
        ]

    def _variables_lines(self, title: str, notes: dict[str, str] | None = None) -> list[str]:
        """``[[Variables]]`` with units and stderr (``notes``: as :func:`_parameter_lines`), the
        missing-stderr notes and the statistics."""
        return [f"[[Variables]] {title}", *_parameter_lines(self.parameters, notes),
                *(f"    no stderr: {note}" for note in self.stderr_notes), *_undetermined_lines(self.undetermined),
                *_statistics_lines(self.statistics)]


@dataclass(frozen=True)
class IwanFitResult(_LoopFitResult):
    """Result of :func:`idkit.fit.fit_iwan` (three stages, SPEC 4).

    Attributes
    ----------
    model : IwanModel
        Identified model: global parameters (g1, g2, g3) of stage 2, local ones
        (k_i, fc_i) of stage 3; ``c_visc = 0`` (quasi-static data carry no rate).
    stages : tuple of StageResult
        The three stages in order (the stage history).
    small_errors, large_errors : ndarray
        Per-set errors (fractions) of the final model on the small and large sets.
    small_names, large_names : tuple of str
    start : IwanStart or None
        The start estimate from the loops (None for a slip-modulated refit started from a model).
    settings : IwanFitSettings
        ``settings.family`` is ``"modulated"`` when ``model`` is a
        :class:`~idkit.models.ModulatedIwanModel` (:meth:`ModulatedIwanFitResult.to_iwan_result`).
    parameters : lmfit.Parameters
        Values, bounds and standard errors (see :func:`idkit.fit.fit_iwan`).
    elapsed_s : float
        Wall time of the three stages (s), excluding the standard-error estimate.
    reasons : tuple of str
        Why the fit is not a success (empty when it is): a stage
        stopped at the evaluation limit (its optimiser status), a parameter of stage 2 or 3
        sits on its search bound, an element never slips within the data (its slip force is
        undetermined), or the spring turns negative-stiff inside the loops.
    start_states : dict
        Set name -> ``"virgin"`` or ``"cycled"``: the start state each set was scored
        from (``settings.initial_state="auto"`` chooses per set).
    statistics : lmfit.minimizer.MinimizerResult or None
        Least-squares statistics at the final parameters (not moved): ``params``,
        ``covar``, ``chisqr``, ``redchi``, ``aic``, ``bic``, ``stderr_notes``,
        ``gauss_newton_step`` (:func:`idkit.fit._params.jacobian_statistics`). The
        properties below expose them as lmfit users expect.
    """

    model: IwanModel
    stages: tuple[StageResult, ...]
    small_errors: np.ndarray
    large_errors: np.ndarray
    small_names: tuple[str, ...]
    large_names: tuple[str, ...]
    start: IwanStart | None
    settings: IwanFitSettings
    parameters: lmfit.Parameters = field(repr=False)
    elapsed_s: float
    reasons: tuple[str, ...] = ()
    start_states: dict = field(default_factory=dict)
    statistics: lmfit.minimizer.MinimizerResult | None = field(default=None, repr=False)

    def report(self, parameter_notes: dict[str, str] | None = None) -> str:
        """Readable summary: parameters with units and stderr, errors per stage and set;
        ``parameter_notes`` (name -> text) are printed beside their parameters."""
        s = self.settings
        title = ("Iwan fit, order {}, three stages" if s.family == "plain" else
                 "Slip-modulated Iwan fit, order {}, the plain fit's stages and the modulation stage(s)").format(s.order)
        lines = [
            f"[[{title}, Nelder-Mead ({s.backend}), initial state "
            f"'{s.initial_state}']]",
            *self._summary_lines(),
            *(["    start state per set: " + ", ".join(f"{n}: {v}" for n, v in self.start_states.items())]
              if self.start_states else []),
            *(["[[Start (from the loops)]]",
               f"    stuck stiffness {self.start.stuck_stiffness:.4g} N/m, half loop height "
               f"{self.start.half_height:.4g} N, g1 {self.start.g1:.4g} N/m, slip travel "
               f"{1e3 * self.start.slip_onset:.3g}-{1e3 * self.start.slip_full:.3g} mm"] if self.start is not None
              else ["[[Start]] a given model (no start estimate from the loops)"]),
            "[[Stages]]",
        ]
        for stage in self.stages:
            per_set = ", ".join(f"{n}: {100 * e:.2f}" for n, e in zip(stage.set_names, stage.set_errors))
            lines.append(
                f"    {stage.name} ({stage.data} loops, free {', '.join(stage.free)}): "
                f"{100 * stage.start_error:.3f} % -> {100 * stage.mean_error:.3f} %, "
                f"{stage.evaluations} evaluations, {stage.restarts} restarts, {stage.message}"
            )
            lines.append(f"        per set [%]: {per_set}")
        lines.extend(self._variables_lines("(stderr from the residual Jacobian at the optimum)", parameter_notes))
        return "\n".join(lines)


def _statistic(result, name: str) -> float:
    """An lmfit statistic of ``result.statistics``, NaN when it was not computed."""
    return float(getattr(result.statistics, name, np.nan)) if result.statistics is not None else float("nan")


def _statistics_lines(statistics) -> list[str]:
    if statistics is None:
        return []
    lines = [f"    statistics: {statistics.ndata} residuals, {statistics.nvarys} varied, chi-square "
             f"{statistics.chisqr:.5g}, reduced {statistics.redchi:.4g}, AIC {statistics.aic:.6g}, "
             f"BIC {statistics.bic:.6g}"]
    steps = getattr(statistics, "gauss_newton_step", {}) or {}
    if steps:
        name = max(steps, key=lambda key: abs(steps[key]))
        freed = ", one force offset free per loop set" if getattr(statistics, "step_nuisance_count", 0) else ""
        lines.append(f"    least-squares optimum of the same residuals{freed} (one Gauss-Newton step): at most "
                     f"{abs(steps[name]):.2g} stderr away ({name})")
    return lines


# --------------------------------------------------------------------------- Bouc-Wen


@dataclass(frozen=True)
class BoucWenFitSettings:
    """Algorithm settings of a Bouc-Wen loop fit (recorded for provenance).

    ``bounds`` are the physical bounds of the scaled box (name -> (lower, upper)).
    """

    backend: str
    points_per_set: int | None
    global_search: bool
    global_method: str | None
    global_max_evals: int
    max_evals: int
    xtol: float
    restarts: int
    initial_step: float
    initial_state: str
    seed: int
    bounds: dict


@dataclass(frozen=True)
class BoucWenFitResult(_LoopFitResult):
    """Result of :func:`idkit.fit.fit_boucwen` (three stages: elastic, loop shape, global + polish).

    Attributes
    ----------
    model : BoucWenModel
        Identified model (``b = e``, so the asymmetry factor is ``exp(c x)``; ``c_visc = 0``).
    stages : tuple of StageResult
        ``elastic``, ``loop shape``, ``global``; ``set_errors`` over small then large sets.
    small_errors, large_errors : ndarray
        Per-set errors (7.1, fractions) of the final model.
    small_names, large_names : tuple of str
    settings : BoucWenFitSettings
    parameters : lmfit.Parameters
        ``k1 .. c`` (varied) with stderr and correlations by the delta method from the
        statistics in the scaled coordinates; ``z_max``, ``shape`` (derived loop-shape
        parameters, listed as fixed, with stderr) and ``b``, ``c_visc`` (fixed).
    conditioning : dict
        Condition number of ``J^T J`` in the scaled coordinates (``"scaled"``)
        and in SI parameters ``k1, k2, k3, alpha, beta, gamma, n, c`` (``"si"``).
    at_bound : tuple of str
        Scaled parameters at a bound of the box.
    global_search : dict or None
        ``method``, ``error`` (best of the population search), ``evaluations``,
        ``stage2_error``.
    elapsed_s : float
    statistics : lmfit.minimizer.MinimizerResult or None
        Least-squares statistics at the final parameters (not moved), mapped to
        ``k1 .. c`` (:func:`idkit.fit.fit_boucwen`); ``params`` (alias of ``parameters``),
        ``chisqr``, ``redchi``, ``aic``, ``bic``, ``nfev``, ``message``, ``stderr_notes``
        and ``fit_report()`` expose them as lmfit does.
    model_form : tuple of str
        Why the model form misses the loops (a group's mean error more than the margin above
        its noise floor, :func:`idkit.fit.model_form.loop_model_form_reasons`); empty when not.
    """

    model: BoucWenModel
    stages: tuple[StageResult, ...]
    small_errors: np.ndarray
    large_errors: np.ndarray
    small_names: tuple[str, ...]
    large_names: tuple[str, ...]
    settings: BoucWenFitSettings
    parameters: lmfit.Parameters = field(repr=False)
    conditioning: dict
    at_bound: tuple[str, ...]
    global_search: dict | None
    elapsed_s: float
    statistics: lmfit.minimizer.MinimizerResult | None = field(default=None, repr=False)
    model_form: tuple[str, ...] = ()

    n_params = 8  # k1, k2, k3, alpha, beta, gamma, n, c (b fixed)

    @property
    def reasons(self) -> tuple[str, ...]:
        """Why the fit is not a success: a stage stopped on its evaluation limit (its optimiser status),
        a scaled coordinate sits on a bound of the box (the data do not place it inside), or the
        data do not determine the parameters (:func:`determinacy_reasons`), or the error is more than
        the margin above the noise floor (``model_form``, :mod:`idkit.fit.model_form`)."""
        bound = ([f"at a bound of the search box (not determined inside it): {', '.join(self.at_bound)}"]
                 if self.at_bound else [])
        return tuple([*self._stopped_stages(), *bound, *determinacy_reasons(self.parameters, self.statistics),
                      *self.model_form])

    def report(self) -> str:
        """Readable summary: stages, conditioning, parameters with stderr."""
        s = self.settings
        lines = [
            f"[[Bouc-Wen fit, three stages (elastic, loop shape, global + polish), local {s.backend} Nelder-Mead]]",
            *self._summary_lines(),
            f"    conditioning of J^T J: {self.conditioning['si']:.3g} in SI parameters, "
            f"{self.conditioning['scaled']:.3g} in the scaled ones",
            f"    at a bound of the box: {', '.join(self.at_bound) if self.at_bound else 'none'}",
            "[[Stages]]",
        ]
        for stage in self.stages:
            lines.append(f"    {stage.name} (free {', '.join(stage.free)}): {100 * stage.start_error:.3f} % -> "
                         f"{100 * stage.mean_error:.3f} %, {stage.evaluations} evaluations, {stage.message}")
        for data, names, errors in (("small", self.small_names, self.small_errors),
                                    ("large", self.large_names, self.large_errors)):
            lines.append(f"    final {data} per set [%]: " + ", ".join(f"{n}: {100 * e:.2f}" for n, e in zip(names, errors)))
        lines.extend(self._variables_lines("(z_max, shape: derived loop-shape parameters; b fixed: only c ln b "
                                           "matters; stderr from the residual Jacobian at the optimum)"))
        return "\n".join(lines)
