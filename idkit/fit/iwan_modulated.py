"""Identification of the Iwan model with deflection-dependent slip forces from quasi-static loops.

The model (:class:`idkit.models.ModulatedIwanModel`) is the modified Iwan model whose slip
forces are ``s(y) fc_i`` with ``s(y) = 1 - a t + b t^2``, ``t = tanh(y / y_ref)``. It is
identified by **its own stage on top of a plain Iwan fit**:

1. the plain three-stage fit (:func:`idkit.fit.fit_iwan`), unless a plain result or model is
   given;
2. the modulation stage: every parameter free (``g1, g2, g3, k_i, fc_i, a, b, y_ref``),
   started from the plain model with ``(a, b)`` at each pair of :data:`MODULATION_STARTS` x
   :data:`GROWTH_STARTS` (``y_ref`` at half the largest deflection), solved by bounded least
   squares (``scipy.optimize.least_squares``, trust-region reflective) on the per-point
   residuals ``(F_model - F_meas) / ||F_meas||`` of every small and large set: the sum of
   squares is the sum over sets of the squared error (7.1) the plain fit scores. The start
   with the lowest sum wins.

Internal coordinates as in the plain fit: ``log g1``, ``log k_i``, ``log fc_i`` (positive
whatever the solver does), ``g2 x_ref / g1_ref`` and ``g3 x_ref^2 / g1_ref`` (share of the
linear force at the largest deflection ``x_ref``), ``a`` itself in ``[-0.95, 0.95]``, ``b``
itself in ``[-0.95, 10]`` and ``log y_ref`` in ``[x_ref / 50, 20 x_ref]``. The slip scale must
stay positive: a barrier row ``10 max(0, 0.05 - (1 - |a| + min(b, 0)))`` keeps its lowest value
(at ``t = +-1`` when ``b <= 0``; ``b > 0`` with ``|a| < 1`` keeps it positive everywhere) above
0.05.

**Uncertainty.** Standard errors from the covariance ``redchi (J^T J)^-1`` of the residuals
at the solution (internal coordinates, mapped to physical ones by the chain rule), as the
plain fit reports them: they describe the data's noise, not the model error.

**Honesty.** ``success=False`` with the reasons when a parameter ends on its search bound,
the solver stops without converging, the modulation is not resolved (``|a|`` below two
standard errors: the plain model explains the loops as well, and ``y_ref`` is then
undetermined), or an element never slips in the data. Sets start "virgin" when their record
started unloaded (:attr:`idkit.fit.LoopSet.starts_unloaded`), else "cycled" (run once over the
set and back to its first point), as in the plain fit.

:func:`loop_model_table` fits the plain Iwan, the modulated Iwan and the Bouc-Wen model to the
same sets and tabulates them with :func:`idkit.fit.compare.compare_loop_models`.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numba
import numpy as np
import pandas as pd
import scipy.optimize

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.checks import Choice, Real, Whole, accepts
from idkit.errors import FitError
from idkit.fit.compare import LoopModelComparison, compare_loop_models
from idkit.fit._params import Transform, jacobian_statistics, to_lmfit, to_physical_statistics
from idkit.fit.iwan import LoopSet, _add_the_step, fit_iwan, prepare_loops
from idkit.fit.loop_objective import (INITIAL_STATE, cycled_flags, modulated_errors, modulated_forces, modulated_set_errors,
                                     modulated_set_forces)
from idkit.fit.model_form import loop_model_form_reasons
from idkit.fit.orders import earns_its_place
from idkit.fit.result import IwanFitResult, IwanFitSettings, LoopErrors, StageResult, determinacy_reasons
from idkit.models import IwanModel, ModulatedIwanModel
from idkit.models.laws import polynomial_spring_force

__all__ = [
    "GROWTH_STARTS",
    "MODULATION_STARTS",
    "SPLIT_RATIO",
    "ModulatedIwanFitResult",
    "fit_iwan_modulated",
    "fit_modulated_orders",
    "split_element",
    "loop_model_table",
    "modulated_set_errors",
    "modulated_set_forces",
]

#: Starting values of the asymmetric modulation ``a`` of the modulation stage.
MODULATION_STARTS = (-0.3, 0.0, 0.3)
#: Starting values of the symmetric modulation ``b`` (each paired with every ``a`` start).
GROWTH_STARTS = (0.0, 0.3)
_A_BOUND = 0.95
_B_BOUNDS = (-0.95, 10.0)
_SCALE_MARGIN = 0.05  # the lowest slip scale the stage's barrier keeps
#: The modulation is resolved when ``(a, b)`` differs from ``(0, 0)`` by at least this
#: ``chi2 = [a b] C^-1 [a b]`` (``C`` their covariance): 2 degrees of freedom, p = 6.3e-5, the
#: probability of a normal variable beyond 4 standard errors. Loops without modulation pass
#: for a modulation with that probability only; a real one (the truths' a = 0.35, b = 0.4)
#: scores chi2 in the thousands.
RESOLVED_CHI2 = -2.0 * math.log(math.erfc(4.0 / math.sqrt(2.0)))


def _modulation_chi2(parameters) -> float:
    """``[a b] C^-1 [a b]`` from the lmfit parameters' standard errors and correlation (nan
    without standard errors)."""
    a, b = parameters["slip_modulation"], parameters["slip_growth"]
    if not (a.stderr and b.stderr and math.isfinite(a.stderr) and math.isfinite(b.stderr)):
        return math.nan
    rho = (a.correl or {}).get("slip_growth", 0.0)
    if not abs(rho) < 1.0:
        return math.nan
    za, zb = a.value / a.stderr, b.value / b.stderr
    return (za * za - 2.0 * rho * za * zb + zb * zb) / (1.0 - rho * rho)
_LOG_BOX = math.log(1e3)  # k_i, fc_i, g1 searched within x/1000 .. x*1000 of the plain fit
_STIFFNESS_MARGIN = 0.01  # share of g1 the valid-range barrier keeps the local stiffness above
_BOUND_MARGIN = 1e-3  # of the internal range: a value closer than this to a bound is "on" it


@numba.njit(cache=True, inline="always")
def _scale_with_derivatives(y, a, b, length):
    """Slip scale ``s = 1 - a t + b t^2`` (``t = tanh(y / y_ref)``) at deflection ``y`` and its
    derivatives in ``a``, ``b`` and ``log y_ref``."""
    t = math.tanh(y / length)
    return 1.0 - a * t + b * t * t, -t, t * t, (a - 2.0 * b * t) * (1.0 - t * t) * y / length


@numba.njit(cache=True, inline="always")
def _sensitive_stop(i, step, scale, scale_a, scale_b, scale_length, k, fc, state, d_k, d_fc, d_a, d_b, d_length):
    """One stop-operator update of element ``i`` over a deflection ``step`` (m) with the limit
    ``scale fc_i``, carrying the force's derivatives in ``log k_i``, ``log fc_i``, ``a``, ``b``
    and ``log y_ref`` (``scale_a``, ``scale_b``, ``scale_length``: the limit scale's)."""
    trial = state[i] + k[i] * step
    limit = scale * fc[i]
    if trial > limit or trial < -limit:
        sign = 1.0 if trial > limit else -1.0
        state[i] = sign * limit
        d_k[i] = 0.0
        d_fc[i] = sign * limit
        d_a[i] = sign * scale_a * fc[i]
        d_b[i] = sign * scale_b * fc[i]
        d_length[i] = sign * scale_length * fc[i]
    else:
        state[i] = trial
        d_k[i] += k[i] * step


@numba.njit(cache=True)
def _stage_residuals(u, n, g1_ref, x_ref, x_all, f_all, offsets, inv_norms, cycled, grid, want_jacobian,
                     residual, jacobian):
    """Residuals of the modulation stage at internal coordinates ``u`` and, on request, their
    exact Jacobian (forward sensitivities of the stop operator), for all sets in one call.

    ``u = [log g1, g2 x_ref / g1_ref, g3 x_ref^2 / g1_ref, log k_i, log fc_i, a, b, log y_ref]``.
    The sets are concatenated in ``x_all``, ``f_all`` (``offsets[s]:offsets[s + 1]``); row ``j``
    of a set is ``(F_model - F_meas) / ||F_meas||``, followed by one valid-range barrier row
    per ``grid`` point, ``10 max(0, 0.01 - (g1 + 2 g2 y + 3 g3 y^2) / g1_ref)``, and the slip
    scale's barrier ``10 max(0, 0.05 - (1 - |a| + min(b, 0)))`` as the last row. An element
    force on its limit depends on ``fc_i``, ``a`` and ``y_ref`` through the limit only; a
    sticking one on ``k_i`` through every step since it last left the limit.
    """
    g1 = math.exp(u[0])
    g2 = u[1] * g1_ref / x_ref
    g3 = u[2] * g1_ref / (x_ref * x_ref)
    k = np.exp(u[3:3 + n])
    fc = np.exp(u[3 + n:3 + 2 * n])
    a = u[3 + 2 * n]
    b = u[4 + 2 * n]
    length = math.exp(u[5 + 2 * n])
    state = np.empty(n)
    d_k = np.empty(n)
    d_fc = np.empty(n)
    d_a = np.empty(n)
    d_b = np.empty(n)
    d_length = np.empty(n)
    for s in range(offsets.shape[0] - 1):
        start, stop = offsets[s], offsets[s + 1]
        weight = inv_norms[s]
        x0 = x_all[start]
        scale0, scale0_a, scale0_b, scale0_length = _scale_with_derivatives(x0, a, b, length)
        for i in range(n):  # monotone loading from the unloaded state to the first point
            state[i] = 0.0
            d_k[i] = 0.0
            d_fc[i] = 0.0
            d_a[i] = 0.0
            d_b[i] = 0.0
            d_length[i] = 0.0
            _sensitive_stop(i, x0, scale0, scale0_a, scale0_b, scale0_length, k, fc, state, d_k, d_fc, d_a, d_b,
                            d_length)
        passes = 2 if cycled[s] else 1
        for p in range(passes):
            scoring = p == passes - 1
            if p == 1:  # back from the last point to the first (one linear step)
                step = x0 - x_all[stop - 1]
                for i in range(n):
                    _sensitive_stop(i, step, scale0, scale0_a, scale0_b, scale0_length, k, fc, state, d_k, d_fc, d_a,
                                    d_b, d_length)
            for j in range(start, stop):
                y = x_all[j]
                scale, scale_a, scale_b, scale_length = _scale_with_derivatives(y, a, b, length)
                total = polynomial_spring_force(y, g1, g2, g3)
                sum_a = 0.0
                sum_b = 0.0
                sum_length = 0.0
                for i in range(n):
                    if j > start:
                        _sensitive_stop(i, y - x_all[j - 1], scale, scale_a, scale_b, scale_length, k, fc, state,
                                        d_k, d_fc, d_a, d_b, d_length)
                    total += state[i]
                    if scoring and want_jacobian:
                        jacobian[j, 3 + i] = weight * d_k[i]
                        jacobian[j, 3 + n + i] = weight * d_fc[i]
                        sum_a += d_a[i]
                        sum_b += d_b[i]
                        sum_length += d_length[i]
                if scoring:
                    residual[j] = weight * (total - f_all[j])
                    if want_jacobian:
                        jacobian[j, 0] = weight * g1 * y
                        jacobian[j, 1] = weight * y * y * g1_ref / x_ref
                        jacobian[j, 2] = weight * y * y * y * g1_ref / (x_ref * x_ref)
                        jacobian[j, 3 + 2 * n] = weight * sum_a
                        jacobian[j, 4 + 2 * n] = weight * sum_b
                        jacobian[j, 5 + 2 * n] = weight * sum_length
    rows = x_all.shape[0]
    for q in range(grid.shape[0]):
        y = grid[q]
        # the expanded form of the spring's stiffness, as the stage has always summed it (the Horner
        # form of models.laws rounds differently and moves the fitted parameters in their last digit)
        shortfall = _STIFFNESS_MARGIN - (g1 + 2.0 * g2 * y + 3.0 * g3 * y * y) / g1_ref
        active = shortfall > 0.0
        residual[rows + q] = 10.0 * shortfall if active else 0.0
        if want_jacobian:
            for c in range(jacobian.shape[1]):
                jacobian[rows + q, c] = 0.0
            if active:
                jacobian[rows + q, 0] = -10.0 * g1 / g1_ref
                jacobian[rows + q, 1] = -20.0 * y / x_ref
                jacobian[rows + q, 2] = -30.0 * y * y / (x_ref * x_ref)
    last = rows + grid.shape[0]  # the slip scale's lowest value 1 - |a| + min(b, 0) above the margin
    shortfall = _SCALE_MARGIN - (1.0 - abs(a) + min(b, 0.0))
    residual[last] = 10.0 * shortfall if shortfall > 0.0 else 0.0
    if want_jacobian:
        for c in range(jacobian.shape[1]):
            jacobian[last, c] = 0.0
        if shortfall > 0.0:
            jacobian[last, 3 + 2 * n] = 10.0 if a > 0.0 else -10.0
            jacobian[last, 4 + 2 * n] = -10.0 if b < 0.0 else 0.0


@dataclass(frozen=True)
class ModulatedIwanFitResult(LoopErrors):
    """Result of :func:`fit_iwan_modulated`.

    Attributes
    ----------
    model : ModulatedIwanModel
        Identified model (``c_visc = 0``: quasi-static data carry no rate).
    plain_model : IwanModel
        The plain Iwan model the stage started from.
    plain : IwanFitResult or None
        The plain fit, when this function ran it.
    small_errors, large_errors : ndarray
        Per-set errors (7.1, fractions) of the modulated model.
    plain_small_errors, plain_large_errors : ndarray
        The same for the plain model, on the same sets and start states.
    small_names, large_names : tuple of str
    parameters : pandas.DataFrame
        One row per parameter: ``name``, ``value``, ``stderr``, ``unit``, ``at_bound``.
    elapsed_s : float
        Wall time of the modulation stage, s (the plain fit's time is in ``plain``).
    evaluations : int
        Residual evaluations of the modulation stage (all starts).
    reasons : tuple of str
        Why the fit is not a success (empty when it is).
    """

    model: ModulatedIwanModel
    plain_model: IwanModel
    plain: IwanFitResult | None
    small_errors: np.ndarray
    large_errors: np.ndarray
    plain_small_errors: np.ndarray
    plain_large_errors: np.ndarray
    small_names: tuple[str, ...]
    large_names: tuple[str, ...]
    parameters: pd.DataFrame = field(repr=False)
    elapsed_s: float = 0.0
    evaluations: int = 0
    reasons: tuple[str, ...] = ()
    lmfit_parameters: object = field(default=None, repr=False)
    statistics: object = field(default=None, repr=False)
    start_states: dict = field(default_factory=dict)
    starts: tuple[tuple[float, float], ...] = ()
    message: str = ""
    status: str = "converged"
    initial_state: str = "auto"
    valid_range: tuple[float, float] | None = None
    start_errors: np.ndarray | None = field(default=None, repr=False)
    stage_name: str = "modulation"
    history: tuple = field(default=(), repr=False)
    history_start: object = field(default=None, repr=False)

    def stage_result(self) -> StageResult:
        """The modulation stage as a :class:`~idkit.fit.StageResult` (its start error is the
        model it started from: the plain fit, or a modulated model)."""
        names = self.small_names + self.large_names
        errors = np.concatenate([self.small_errors, self.large_errors])
        start_errors = (self.start_errors if self.start_errors is not None else
                        np.concatenate([self.plain_small_errors, self.plain_large_errors]))
        return StageResult(
            name=self.stage_name, data="small+large", free=tuple(self.parameters["name"]),
            start={**self.plain_model.params(), "slip_modulation": [a for a, _ in self.starts],
                   "slip_growth": [b for _, b in self.starts]},
            params=self.model.params(), set_names=names, set_errors=errors, mean_error=float(np.mean(errors)),
            start_error=float(np.mean(start_errors)), evaluations=self.evaluations,
            restarts=max(len(self.starts) - 1, 0), message=self.message, elapsed_s=self.elapsed_s, status=self.status)

    def to_iwan_result(self, settings: IwanFitSettings | None = None) -> IwanFitResult:
        """This fit as an :class:`~idkit.fit.IwanFitResult` (``settings.family = "modulated"``).

        The stages are the plain fit's three followed by ``"modulation"`` (all parameters free,
        least squares), or, for an order reached by continuation
        (:func:`fit_modulated_orders`), the stages of the whole chain: the plain fit of its
        lowest order and one modulation stage per order; ``parameters`` and ``statistics`` are
        the last modulation stage's (lmfit, with standard errors from the residual Jacobian at
        its optimum). ``settings`` default to the plain fit's; they are required when the stage
        started from a model instead of a fit.
        """
        if settings is None:
            if self.plain is None:
                raise FitError("settings: found None, expected the IwanFitSettings to record (the modulation "
                               "stage started from a model, not from a plain fit)")
            settings = self.plain.settings
        settings = dataclasses.replace(settings, family="modulated", order=self.model.order,
                                       initial_state=self.initial_state, valid_range=self.valid_range)
        earlier = tuple(self.plain.stages) if self.plain is not None else tuple(self.history)
        stages = earlier + (self.stage_result(),)
        start = self.plain.start if self.plain is not None else self.history_start
        elapsed = sum(stage.elapsed_s for stage in stages)
        return IwanFitResult(model=self.model, stages=stages, small_errors=self.small_errors,
                             large_errors=self.large_errors, small_names=self.small_names,
                             large_names=self.large_names, start=start, settings=settings,
                             parameters=self.lmfit_parameters, elapsed_s=elapsed, reasons=self.reasons,
                             start_states=dict(self.start_states), statistics=self.statistics)

    @property
    def n_params(self) -> int:
        """Free parameters of the modulation stage."""
        return len(self.parameters)

    def stderr(self, name: str) -> float:
        """Standard error of parameter ``name`` in its unit."""
        rows = self.parameters.loc[self.parameters["name"] == name, "stderr"]
        if rows.empty:
            raise FitError(f"name: found {name!r}, expected one of {list(self.parameters['name'])}")
        return float(rows.iloc[0])

    def report(self) -> str:
        """Parameters with standard errors, errors of both models, verdict."""
        lines = [(f"Modulated Iwan fit (order {self.model.order}): "
                 f"{'success' if self.success else 'NOT a success'}")]
        for row in self.parameters.itertuples():
            flag = "  (on its search bound)" if row.at_bound else ""
            lines.append(f"  {row.name:16s} {row.value: .6g} +/- {row.stderr:.3g} {row.unit}{flag}")
        lines.append(f"  mean error small {100 * self.error_small:.3f} % (plain {100 * np.mean(self.plain_small_errors):.3f} %), "
                     f"large {100 * self.error_large:.3f} % (plain {100 * np.mean(self.plain_large_errors):.3f} %)")
        lines += [f"  reason: {reason}" for reason in self.reasons]
        return "\n".join(lines)


def _sources(loop_set: LoopSet) -> np.ndarray:
    """Raw-sample index of every point of a set (NaN: each point a measured sample of its own)."""
    index = getattr(loop_set, "source_index", None)
    return np.full(loop_set.deflection.size, np.nan) if index is None else np.asarray(index, dtype=float)


def _prepare(sets, group, points_per_set):
    prepared = []
    for index, item in enumerate(sets):
        if isinstance(item, LoopSet):
            prepared.append(item)
            continue
        if hasattr(item, "deflection") and hasattr(item, "force"):
            x, f, name = item.deflection, item.force, getattr(item, "name", "") or f"{group}{index}"
        else:
            try:
                x, f = item
            except (TypeError, ValueError):
                raise FitError(f"{group} set {index}: found {type(item).__name__}, expected a (deflection, force) "
                               "pair of arrays, an object with .deflection and .force, or a LoopSet") from None
            name = f"{group}{index}"
        prepared.append(prepare_loops(x, f, points_per_set=points_per_set, name=name))
    return prepared


@accepts(jacobian=Choice(("exact", "2-point")), initial_state=INITIAL_STATE, error=FitError)
def fit_iwan_modulated(small, large, *, plain: IwanFitResult | IwanModel | None = None, order: int = 2,
                       points_per_set: int | None = 200, initial_state: str = "auto",
                       modulation_starts: Sequence[float] = MODULATION_STARTS,
                       growth_starts: Sequence[float] = GROWTH_STARTS, max_nfev: int = 2000,
                       valid_range: tuple[float, float] | None = None, jacobian: str = "exact",
                       **plain_options) -> ModulatedIwanFitResult:
    """Identify a :class:`~idkit.models.ModulatedIwanModel` on quasi-static loops (module docstring).

    Parameters
    ----------
    small, large : sequence
        Loop sets as for :func:`idkit.fit.fit_iwan` (both non-empty).
    plain : IwanFitResult or IwanModel, optional
        The plain Iwan fit (or model) to start from; default: :func:`idkit.fit.fit_iwan` of
        order ``order`` on the same sets with ``plain_options``.
    order : int, default 2
        Jenkin elements of the plain fit run here (ignored when ``plain`` is given).
    points_per_set : int or None, default 200
        Resampling of raw sets (:func:`idkit.fit.prepare_loops`).
    initial_state : {"auto", "cycled", "virgin"}
        Element forces at the first point of each set (module docstring).
    modulation_starts : sequence of float
        Starting values of ``a`` in (-0.95, 0.95).
    growth_starts : sequence of float
        Starting values of ``b`` in (-0.95, 10); the stage starts from every pair ``(a, b)``
        with ``1 - |a| + min(b, 0) > 0.05``.
    max_nfev : int, default 2000
        Residual evaluations per start.
    valid_range : (float, float), optional
        Deflections (m, ``x_min < 0 < x_max``) over which the parallel spring must keep a
        non-negative local stiffness ``g1 + 2 g2 y + 3 g3 y^2`` (SPEC 1.2), e.g. the range of every
        record the model will simulate (drops compress further than the loops): 61 barrier
        residuals ``10 max(0, 0.01 - stiffness / g1_ref)`` on a grid over the range join the data's
        (the 1 % margin keeps the hinge's solution off zero stiffness). A
        final model that still turns negative-stiff there is not a success. Default: none.
    jacobian : {"exact", "2-point"}, default "exact"
        The stage's Jacobian: the forward sensitivities of the stop operator, or scipy's
        forward differences (the former method, kept for ``bench/bench_modulated_fit.py`` and
        cross-checks). The standard errors use the exact one in both cases.
    **plain_options
        Passed to :func:`idkit.fit.fit_iwan` when it runs.

    Returns
    -------
    ModulatedIwanFitResult
    """
    small_sets = _prepare(small, "small", points_per_set)
    large_sets = _prepare(large, "large", points_per_set)
    if not small_sets or not large_sets:
        raise FitError(f"found {len(small_sets)} small and {len(large_sets)} large sets, expected at least one of each")
    a_starts = [float(a) for a in modulation_starts]
    if not a_starts or any(not -_A_BOUND < a < _A_BOUND for a in a_starts):
        raise FitError(f"modulation_starts: found {a_starts}, expected values in (-{_A_BOUND}, {_A_BOUND})")
    b_starts = [float(b) for b in growth_starts]
    if not b_starts or any(not _B_BOUNDS[0] < b < _B_BOUNDS[1] for b in b_starts):
        raise FitError(f"growth_starts: found {b_starts}, expected values in ({_B_BOUNDS[0]}, {_B_BOUNDS[1]})")
    starts = [(a, b) for a in a_starts for b in b_starts if 1.0 - abs(a) + min(b, 0.0) > _SCALE_MARGIN]
    if not starts:
        raise FitError(f"modulation_starts {a_starts} with growth_starts {b_starts}: found no pair with a slip "
                       f"scale above {_SCALE_MARGIN} (1 - |a| + min(b, 0)), expected at least one")
    plain_result, modulated_start = None, None
    if plain is None:
        plain_result = fit_iwan(small_sets, large_sets, order=order, points_per_set=None,
                                initial_state=initial_state, **plain_options)
        plain_model = plain_result.model
    elif isinstance(plain, IwanFitResult):
        plain_result, plain_model = plain, plain.model
    elif isinstance(plain, ModulatedIwanModel):  # a modulated start (e.g. a refit per repetition)
        plain_model, modulated_start = plain.plain(), plain
        starts = [(float(np.clip(plain.slip_modulation, -_A_BOUND + 1e-6, _A_BOUND - 1e-6)),
                   float(np.clip(plain.slip_growth, _B_BOUNDS[0] + 1e-6, _B_BOUNDS[1] - 1e-6)))]
    elif isinstance(plain, IwanModel):
        plain_model = plain
    else:
        raise FitError(f"plain: found {type(plain).__name__}, expected an IwanFitResult or an IwanModel")
    sets = small_sets + large_sets
    cycled = cycled_flags(sets, initial_state)
    norms = [math.sqrt(float(np.sum(s.force**2))) for s in sets]
    n = plain_model.order
    x_ref = max(float(np.max(np.abs(s.deflection))) for s in large_sets)
    g1_ref = max(plain_model.g1, 1e-3 * plain_model.stuck_stiffness)

    def unpack(u) -> ModulatedIwanModel:
        return ModulatedIwanModel(g1=math.exp(u[0]), g2=u[1] * g1_ref / x_ref, g3=u[2] * g1_ref / x_ref**2,
                                  k=np.exp(u[3:3 + n]), fc=np.exp(u[3 + n:3 + 2 * n]), slip_modulation=u[-3],
                                  slip_growth=u[-2], slip_length=math.exp(u[-1]))

    if valid_range is not None:
        low, high = (float(v) for v in valid_range)
        if not (math.isfinite(low) and math.isfinite(high) and low < 0.0 < high):
            raise FitError(f"valid_range: found {valid_range!r}, expected (x_min < 0 < x_max) in m")
        grid = np.linspace(low, high, 61)
    else:
        grid = np.zeros(0)

    x_all = np.ascontiguousarray(np.concatenate([s.deflection for s in sets]), dtype=float)
    f_all = np.ascontiguousarray(np.concatenate([s.force for s in sets]), dtype=float)
    offsets = np.concatenate([[0], np.cumsum([s.deflection.size for s in sets])]).astype(np.int64)
    inv_norms = 1.0 / np.asarray(norms, dtype=float)
    cycled_array = np.asarray(cycled, dtype=np.bool_)
    width = 6 + 2 * n
    rows = x_all.size + grid.size + 1  # data, spring barrier, slip-scale barrier
    cache: dict = {}

    def evaluate(u, want_jacobian: bool):
        key = np.asarray(u, dtype=float).tobytes()
        if cache.get("key") != key or (want_jacobian and "jacobian" not in cache):
            residual = np.empty(rows)
            jacobian = np.empty((rows, width)) if want_jacobian else np.empty((0, width))
            _stage_residuals(np.ascontiguousarray(u, dtype=float), n, g1_ref, x_ref, x_all, f_all, offsets,
                             inv_norms, cycled_array, grid, want_jacobian, residual, jacobian)
            cache.clear()
            cache.update(key=key, residual=residual)
            if want_jacobian:
                cache["jacobian"] = jacobian
        return cache

    def residuals(u) -> np.ndarray:  # with the Jacobian when it will be asked for at the same point
        return evaluate(u, jacobian == "exact")["residual"]

    def stage_jacobian(u) -> np.ndarray:
        return evaluate(u, True)["jacobian"]

    length0 = modulated_start.slip_length if modulated_start is not None else 0.5 * x_ref
    base = np.concatenate([[math.log(g1_ref), plain_model.g2 * x_ref / g1_ref, plain_model.g3 * x_ref**2 / g1_ref],
                           np.log(plain_model.k), np.log(plain_model.fc), [0.0, 0.0, math.log(length0)]])
    lower = np.concatenate([[base[0] - _LOG_BOX, -20.0, -20.0], base[3:3 + 2 * n] - _LOG_BOX,
                            [-_A_BOUND, _B_BOUNDS[0], math.log(x_ref / 50.0)]])
    upper = np.concatenate([[base[0] + _LOG_BOX, 20.0, 20.0], base[3:3 + 2 * n] + _LOG_BOX,
                            [_A_BOUND, _B_BOUNDS[1], math.log(20.0 * x_ref)]])
    begin = time.perf_counter()
    best, evaluations = None, 0
    for a, b in starts:
        u0 = base.copy()
        u0[-3], u0[-2] = a, b
        u0 = np.clip(u0, lower + 1e-9, upper - 1e-9)
        solution = scipy.optimize.least_squares(residuals, u0, jac=stage_jacobian if jacobian == "exact" else "2-point",
                                                bounds=(lower, upper), method="trf",
                                                x_scale="jac", max_nfev=max_nfev, xtol=1e-12, ftol=1e-12)
        evaluations += int(solution.nfev)
        if best is None or solution.cost < best.cost:
            best = solution
    elapsed = time.perf_counter() - begin
    model = unpack(best.x)
    units = {spec.name: spec.unit for spec in model.param_specs()}
    physical = model.params()
    order_names = ["g1", "g2", "g3", *(f"k_{i}" for i in range(1, n + 1)), *(f"fc_{i}" for i in range(1, n + 1)),
                   "slip_modulation", "slip_growth", "slip_length"]
    kinds = ["log", "scaled", "scaled", *["log"] * (2 * n), "scaled", "scaled", "log"]
    scales = [1.0, g1_ref / x_ref, g1_ref / x_ref**2, *[1.0] * (2 * n), 1.0, 1.0, 1.0]
    transforms = [Transform(name, units[name], kind, float(np.exp(low) if kind == "log" else low * scale),
                            float(np.exp(high) if kind == "log" else high * scale), scale)
                  for name, kind, scale, low, high in zip(order_names, kinds, scales, lower, upper)]
    # least-squares statistics at the solution (internal coordinates, then the chain rule):
    # the residuals are the stage's own, so these describe the data's noise, not the model error
    # one force offset per loop set (a load-cell zero the fit holds at 0): d r / d offset, none
    # in the barrier rows
    nuisance = np.zeros((rows, len(sets)))
    for s in range(len(sets)):
        nuisance[offsets[s]:offsets[s + 1], s] = inv_norms[s]
    internal = jacobian_statistics(lambda u: evaluate(u, True)["residual"].copy(), best.x, order_names,
                                   jacobian=lambda u: evaluate(u, True)["jacobian"].copy(),
                                   # a noise variance per loop set (same force noise in N: the small
                                   # loops' relative residuals are larger), the barrier rows as one
                                   group_sizes=[*np.diff(offsets), grid.size + 1], step_nuisance=nuisance,
                                   # the raw samples behind resampled points (NaN: the barrier rows)
                                   point_sources=np.concatenate([_sources(s) for s in sets]
                                                                + [np.full(grid.size + 1, np.nan)]),
                                   method="Jacobian of the per-point residuals at the least-squares optimum")
    # the distance to the optimum with the offsets free, in quadrature (as for the plain fit)
    _add_the_step(internal, order_names)
    specs = {spec.name: spec for spec in model.param_specs()}
    lmfit_parameters = to_lmfit(
        order_names + ["c_visc"], [physical[name] for name in order_names] + [0.0],
        units=[units[name] for name in order_names] + [specs["c_visc"].unit],
        lower=[t.lower for t in transforms] + [specs["c_visc"].lower],
        upper=[t.upper for t in transforms] + [specs["c_visc"].upper],
        vary=[True] * len(order_names) + [False])
    statistics = to_physical_statistics(internal, transforms, lmfit_parameters)
    stderr = [lmfit_parameters[name].stderr for name in order_names]
    span = upper - lower
    at_bound = (best.x - lower < _BOUND_MARGIN * span) | (upper - best.x < _BOUND_MARGIN * span)
    table = pd.DataFrame({"name": order_names, "value": [physical[name] for name in order_names],
                          "stderr": [math.nan if e is None else float(e) for e in stderr],
                          "unit": [units[name] for name in order_names], "at_bound": at_bound})
    reasons = []
    for row in table.itertuples():
        if row.at_bound:
            reasons.append(f"parameter {row.name} = {row.value:.6g} {row.unit} is on its search bound")
    if best.status <= 0:
        reasons.append(f"least squares stopped without converging: {best.message}")
    reasons.extend(determinacy_reasons(lmfit_parameters, statistics,  # the shared verdict (docs/fitting.md)
                                       excused=tuple(row.name for row in table.itertuples() if row.at_bound)))
    chi2 = _modulation_chi2(lmfit_parameters)
    if not chi2 >= RESOLVED_CHI2:
        a_err = lmfit_parameters["slip_modulation"].stderr
        b_err = lmfit_parameters["slip_growth"].stderr
        reasons.append(f"modulation not resolved: slip_modulation = {model.slip_modulation:.3g} +/- {a_err or math.nan:.2g} "
                       f"and slip_growth = {model.slip_growth:.3g} +/- {b_err or math.nan:.2g} differ from (0, 0) by "
                       f"chi2 = {chi2:.3g} < {RESOLVED_CHI2:.3g} (4 standard errors; no standard errors: nan): the "
                       "plain Iwan model explains the loops as well, slip_length is undetermined")
    largest_travel = max(float(np.ptp(s.deflection)) for s in sets)
    widest = 1.0 + abs(model.slip_modulation) + max(model.slip_growth, 0.0)  # the largest slip scale, bound
    for i, (k, fc) in enumerate(zip(model.k, model.fc), start=1):
        if 2.0 * fc * widest / k > largest_travel:
            reasons.append(f"element {i} never slips within the data (slip travel {2e3 * fc / k:.3g} mm): "
                           f"fc_{i} undetermined")
    if grid.size and np.any(model.spring_stiffness(grid) < 0.0):
        negative_low, negative_high = model.valid_deflection_range()
        reasons.append(f"the fitted spring turns negative-stiff at {1e3 * negative_low:.4g} / "
                       f"{1e3 * negative_high:.4g} mm, inside valid_range {1e3 * grid[0]:.4g} to {1e3 * grid[-1]:.4g} mm")
    low = min(float(np.min(s.deflection)) for s in sets)
    high = max(float(np.max(s.deflection)) for s in sets)
    negative_low, negative_high = model.valid_deflection_range()
    if not (negative_low <= low and high <= negative_high):
        reasons.append(f"the fitted spring turns negative-stiff at {1e3 * negative_low:.4g} / "
                       f"{1e3 * negative_high:.4g} mm, inside the loops' own deflections ({1e3 * low:.4g} to "
                       f"{1e3 * high:.4g} mm)")
    ns = len(small_sets)
    final_forces = modulated_forces(model, sets, cycled)
    reasons.extend(loop_model_form_reasons(  # the shared model-form check (docs/fitting.md, "Verdicts")
        [("small", sets[:ns], final_forces[:ns]), ("large", sets[ns:], final_forces[ns:])],
        remedy="a higher order (--order auto, --order-table) or another model form, docs/fitting.md"))
    reasons = list(dict.fromkeys(reasons))
    errors = modulated_errors(model, sets, cycled)
    plain_errors = modulated_errors(ModulatedIwanModel.from_iwan(plain_model), sets, cycled)
    start_errors = modulated_errors(modulated_start, sets, cycled) if modulated_start is not None else plain_errors
    return ModulatedIwanFitResult(
        model=model, plain_model=plain_model, plain=plain_result, small_errors=errors[:ns], large_errors=errors[ns:],
        plain_small_errors=plain_errors[:ns], plain_large_errors=plain_errors[ns:],
        small_names=tuple(s.name for s in small_sets), large_names=tuple(s.name for s in large_sets),
        parameters=table, elapsed_s=elapsed, evaluations=evaluations, reasons=tuple(dict.fromkeys(reasons)),
        lmfit_parameters=lmfit_parameters, statistics=statistics,
        start_states={s.name: "cycled" if c else "virgin" for s, c in zip(sets, cycled)},
        starts=tuple(starts), message=str(best.message), status="converged" if best.status > 0 else "max_evals",
        initial_state=initial_state, valid_range=None if valid_range is None else (float(grid[0]), float(grid[-1])),
        start_errors=start_errors,
    )


#: Slip-displacement ratio of the continuation's element split: element ``(k, fc)`` becomes two
#: of stiffness ``k / 2`` slipping at ``fc / k`` divided and multiplied by this.
SPLIT_RATIO = 1.5


@accepts(index=Whole(ge=0), ratio=Real(gt=1, meaning="the two halves slip at different displacements"),
         error=FitError)
def split_element(model: ModulatedIwanModel, index: int, ratio: float = SPLIT_RATIO) -> ModulatedIwanModel:
    """``model`` with Jenkin element ``index`` (0-based) split into two: stiffness ``k / 2``
    each, slip displacements ``fc / k / ratio`` and ``fc / k * ratio``; one order more.

    Examples
    --------
    >>> rope = ModulatedIwanModel(g1=1e4, k=[2e4], fc=[10.0], slip_growth=0.4, slip_length=5e-3)
    >>> two = split_element(rope, 0, ratio=2.0)
    >>> two.k.tolist(), two.fc.tolist(), two.slip_growth
    ([10000.0, 10000.0], [2.5, 10.0], 0.4)
    """
    if not 0 <= index < model.order:
        raise FitError(f"index: found {index!r}, expected 0 <= index < {model.order} (the model's elements)")
    k, fc = list(model.k), list(model.fc)
    half, travel = 0.5 * k[index], fc[index] / k[index]
    k[index:index + 1] = [half, half]
    fc[index:index + 1] = [half * travel / ratio, half * travel * ratio]
    return ModulatedIwanModel(g1=model.g1, g2=model.g2, g3=model.g3, k=k, fc=fc, c_visc=model.c_visc,
                              slip_modulation=model.slip_modulation, slip_growth=model.slip_growth,
                              slip_length=model.slip_length)


@accepts(max_order=Whole(ge=1), patience=Whole(ge=1, optional=True), error=FitError)
def fit_modulated_orders(small, large, first: IwanFitResult | IwanModel, *, max_order: int,
                         points_per_set: int | None = 200, initial_state: str = "auto",
                         valid_range: tuple[float, float] | None = None,
                         accept=lambda fit: False, patience: int | None = 2) -> dict[int, ModulatedIwanFitResult]:
    """Modulated fits of increasing order by **continuation in the order**.

    The lowest order is :func:`fit_iwan_modulated` from ``first`` (a plain fit or model);
    order ``n + 1`` starts from the modulated fit of order ``n`` with each of its elements in
    turn split in two (:func:`split_element`), and keeps the start whose optimum has the
    lowest sum of squared set errors (within a relative 1e-9 of it, the lowest element index:
    equal minima reached from two splits are one model with its elements renumbered). The
    chain stops after ``max_order``, at the first fit ``accept(fit)`` is true for, or when
    ``patience`` orders in a row have not lowered the best mean of small and large error by
    the order rule's factor (:data:`~idkit.fit.orders.ORDER_RULE_FACTOR`): the order rule
    would not pick them, and elements that do not help leave the loops as they are.
    ``patience=None`` never stops early.

    Why a chain and not a start from the plain fit of each order: the plain fits of the
    higher orders carry elements that slip only at the tips of the largest loops, traded
    against ``g1`` (:attr:`~idkit.fit.IwanFitResult.undetermined`); one ulp on the forces can
    move them to another local minimum, and a modulation stage started there would follow.
    Each link of the chain starts from a fit that is itself a smooth function of the data, so
    the whole chain is too, and it reaches errors as low or lower (docs/fitting.md).
    """
    small_sets = _prepare(small, "small", points_per_set)
    large_sets = _prepare(large, "large", points_per_set)
    options = dict(points_per_set=None, initial_state=initial_state, valid_range=valid_range)
    current = fit_iwan_modulated(small_sets, large_sets, plain=first, **options)
    fits = {current.model.order: current}
    history = tuple(current.plain.stages) if current.plain is not None else ()
    history_start = current.plain.start if current.plain is not None else None
    best_mean, stalled = 0.5 * (current.error_small + current.error_large), 0
    while current.model.order < max_order and not accept(current) and (patience is None or stalled < patience):
        candidates = [fit_iwan_modulated(small_sets, large_sets, plain=split_element(current.model, index), **options)
                      for index in range(current.model.order)]
        costs = np.array([np.sum(c.small_errors**2) + np.sum(c.large_errors**2) for c in candidates])
        index = int(np.flatnonzero(costs <= costs.min() * (1.0 + 1e-9))[0])
        history = history + (current.stage_result(),)  # the chain so far, for the result's stages
        current = dataclasses.replace(
            candidates[index], history=history, history_start=history_start,
            stage_name=f"modulation, order {current.model.order + 1} (order {current.model.order} with element "
                       f"{index + 1} split)")
        fits[current.model.order] = current
        mean = 0.5 * (current.error_small + current.error_large)
        stalled = 0 if earns_its_place(mean, best_mean) else stalled + 1
        best_mean = min(best_mean, mean)
    return fits


def loop_model_table(small, large, *, order: int = 2, points_per_set: int | None = 200, boucwen: bool = True,
                     **plain_options) -> LoopModelComparison:
    """Plain Iwan, modulated Iwan and (optionally) Bouc-Wen fitted to the same sets, side by side.

    The modulated stage starts from the plain fit made here; the Bouc-Wen fit is
    :func:`idkit.fit.fit_boucwen` with its defaults. Returns
    :func:`idkit.fit.compare.compare_loop_models` of ``{"iwan", "iwan_modulated", "bouc_wen"}``;
    each fit's ``success`` is in its own result (the table shows errors, parameters and cost).
    """
    small_sets = _prepare(small, "small", points_per_set)
    large_sets = _prepare(large, "large", points_per_set)
    modulated = fit_iwan_modulated(small_sets, large_sets, order=order, points_per_set=None, **plain_options)
    results = {"iwan": modulated.plain, "iwan_modulated": modulated}
    if boucwen:
        from idkit.fit.boucwen import fit_boucwen

        results["bouc_wen"] = fit_boucwen(small_sets, large_sets, points_per_set=None)
    return compare_loop_models(results)
