"""Identification of the Iwan model with deflection-dependent slip forces from quasi-static loops.

The model (:class:`idkit.models.ModulatedIwanModel`) is the modified Iwan model whose slip
forces are ``s(y) fc_i`` with ``s(y) = 1 - a tanh(y / y_ref)``. It is identified by **its own
stage on top of a plain Iwan fit**:

1. the plain three-stage fit (:func:`idkit.fit.fit_iwan`), unless a plain result or model is
   given;
2. the modulation stage: every parameter free (``g1, g2, g3, k_i, fc_i, a, y_ref``), started
   from the plain model with ``a`` at each of :data:`MODULATION_STARTS` (``y_ref`` at half the
   largest deflection), solved by bounded least squares (``scipy.optimize.least_squares``,
   trust-region reflective) on the per-point residuals ``(F_model - F_meas) / ||F_meas||`` of
   every small and large set: the sum of squares is the sum over sets of the squared error
   (7.1) the plain fit scores. The start with the lowest sum wins.

Internal coordinates as in the plain fit: ``log g1``, ``log k_i``, ``log fc_i`` (positive
whatever the solver does), ``g2 x_ref / g1_ref`` and ``g3 x_ref^2 / g1_ref`` (share of the
linear force at the largest deflection ``x_ref``), ``a`` itself in ``[-0.95, 0.95]`` and
``log y_ref`` in ``[x_ref / 50, 20 x_ref]``.

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

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numba
import numpy as np
import pandas as pd
import scipy.optimize

from idkit.errors import FitError
from idkit.fit.compare import LoopModelComparison, compare_loop_models
from idkit.fit.iwan import LoopSet, fit_iwan, prepare_loops
from idkit.fit.result import IwanFitResult
from idkit.models import IwanModel, ModulatedIwanModel

__all__ = [
    "MODULATION_STARTS",
    "ModulatedIwanFitResult",
    "fit_iwan_modulated",
    "loop_model_table",
    "modulated_set_errors",
]

#: Starting values of the modulation depth ``a`` of the modulation stage.
MODULATION_STARTS = (-0.3, 0.0, 0.3)
_A_BOUND = 0.95
_LOG_BOX = math.log(1e3)  # k_i, fc_i, g1 searched within x/1000 .. x*1000 of the plain fit
_STIFFNESS_MARGIN = 0.01  # share of g1 the valid-range barrier keeps the local stiffness above
_BOUND_MARGIN = 1e-3  # of the internal range: a value closer than this to a bound is "on" it


@numba.njit(cache=True)
def _set_forces(x, g1, g2, g3, k, fc, a, length, cycled, out):
    """Force (N) along one set ``x`` (m) from the virgin or the cycled start state."""
    n = k.shape[0]
    state = np.empty(n)
    scale0 = 1.0 - a * math.tanh(x[0] / length) if a != 0.0 else 1.0
    for i in range(n):  # monotone loading from the unloaded state to the first point
        state[i] = min(max(k[i] * x[0], -scale0 * fc[i]), scale0 * fc[i])
    passes = 2 if cycled else 1
    for p in range(passes):
        if p == 1:  # back from the last point to the first (one linear step), then score
            step = x[0] - x[x.shape[0] - 1]
            for i in range(n):
                state[i] = min(max(state[i] + k[i] * step, -scale0 * fc[i]), scale0 * fc[i])
        for s in range(x.shape[0]):
            y = x[s]
            scale = 1.0 - a * math.tanh(y / length) if a != 0.0 else 1.0
            total = y * (g1 + y * (g2 + y * g3))
            for i in range(n):
                if s > 0:
                    trial = state[i] + k[i] * (y - x[s - 1])
                    limit = scale * fc[i]
                    if trial > limit:
                        trial = limit
                    elif trial < -limit:
                        trial = -limit
                    state[i] = trial
                total += state[i]
            out[s] = total


def _model_forces(model: ModulatedIwanModel, sets: Sequence[LoopSet], cycled: Sequence[bool]) -> list[np.ndarray]:
    forces = []
    for loop_set, is_cycled in zip(sets, cycled):
        out = np.empty(loop_set.deflection.size)
        _set_forces(loop_set.deflection, model.g1, model.g2, model.g3, np.ascontiguousarray(model.k, float),
                    np.ascontiguousarray(model.fc, float), model.slip_modulation, model.slip_length,
                    bool(is_cycled), out)
        forces.append(out)
    return forces


def _errors(model, sets, cycled) -> np.ndarray:
    return np.array([np.sqrt(np.sum((f - s.force) ** 2) / np.sum(s.force**2))
                     for f, s in zip(_model_forces(model, sets, cycled), sets)])


def modulated_set_errors(model: IwanModel, sets: Sequence[LoopSet], *, initial_state: str = "auto") -> np.ndarray:
    """Error (7.1) as a fraction of ``model`` (plain or modulated Iwan) on each prepared set."""
    if not isinstance(model, ModulatedIwanModel):
        model = ModulatedIwanModel.from_iwan(model)
    return _errors(model, sets, _cycled_flags(sets, initial_state))


def _cycled_flags(sets, initial_state: str) -> list[bool]:
    if initial_state not in ("auto", "cycled", "virgin"):
        raise FitError(f"initial_state: found {initial_state!r}, expected 'auto', 'cycled' or 'virgin'")
    if initial_state == "auto":
        return [not s.starts_unloaded for s in sets]
    return [initial_state == "cycled"] * len(sets)


@dataclass(frozen=True)
class ModulatedIwanFitResult:
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

    @property
    def success(self) -> bool:
        """True unless :attr:`reasons` names a problem."""
        return not self.reasons

    @property
    def n_params(self) -> int:
        """Free parameters of the modulation stage."""
        return len(self.parameters)

    @property
    def error_small(self) -> float:
        """Mean error (fraction) on the small sets."""
        return float(np.mean(self.small_errors))

    @property
    def error_large(self) -> float:
        """Mean error (fraction) on the large sets."""
        return float(np.mean(self.large_errors))

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


def fit_iwan_modulated(small, large, *, plain: IwanFitResult | IwanModel | None = None, order: int = 2,
                       points_per_set: int | None = 200, initial_state: str = "auto",
                       modulation_starts: Sequence[float] = MODULATION_STARTS, max_nfev: int = 2000,
                       valid_range: tuple[float, float] | None = None, **plain_options) -> ModulatedIwanFitResult:
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
    max_nfev : int, default 2000
        Residual evaluations per start.
    valid_range : (float, float), optional
        Deflections (m, ``x_min < 0 < x_max``) over which the parallel spring must keep a
        non-negative local stiffness ``g1 + 2 g2 y + 3 g3 y^2`` (SPEC 1.2), e.g. the range of every
        record the model will simulate (drops compress further than the loops): 61 barrier
        residuals ``10 max(0, 0.01 - stiffness / g1_ref)`` on a grid over the range join the data's
        (the 1 % margin keeps the hinge's solution off zero stiffness). A
        final model that still turns negative-stiff there is not a success. Default: none.
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
    starts = [float(a) for a in modulation_starts]
    if not starts or any(not -_A_BOUND < a < _A_BOUND for a in starts):
        raise FitError(f"modulation_starts: found {starts}, expected values in (-{_A_BOUND}, {_A_BOUND})")
    plain_result = None
    if plain is None:
        plain_result = fit_iwan(small_sets, large_sets, order=order, points_per_set=None,
                                initial_state=initial_state, **plain_options)
        plain_model = plain_result.model
    elif isinstance(plain, IwanFitResult):
        plain_result, plain_model = plain, plain.model
    elif isinstance(plain, IwanModel):
        plain_model = plain.plain() if isinstance(plain, ModulatedIwanModel) else plain
    else:
        raise FitError(f"plain: found {type(plain).__name__}, expected an IwanFitResult or an IwanModel")
    sets = small_sets + large_sets
    cycled = _cycled_flags(sets, initial_state)
    norms = [math.sqrt(float(np.sum(s.force**2))) for s in sets]
    n = plain_model.order
    x_ref = max(float(np.max(np.abs(s.deflection))) for s in large_sets)
    g1_ref = max(plain_model.g1, 1e-3 * plain_model.stuck_stiffness)

    def unpack(u) -> ModulatedIwanModel:
        return ModulatedIwanModel(g1=math.exp(u[0]), g2=u[1] * g1_ref / x_ref, g3=u[2] * g1_ref / x_ref**2,
                                  k=np.exp(u[3:3 + n]), fc=np.exp(u[3 + n:3 + 2 * n]), slip_modulation=u[-2],
                                  slip_length=math.exp(u[-1]))

    if valid_range is not None:
        low, high = (float(v) for v in valid_range)
        if not (math.isfinite(low) and math.isfinite(high) and low < 0.0 < high):
            raise FitError(f"valid_range: found {valid_range!r}, expected (x_min < 0 < x_max) in m")
        grid = np.linspace(low, high, 61)
    else:
        grid = np.zeros(0)

    def residuals(u) -> np.ndarray:
        model = unpack(u)
        forces = _model_forces(model, sets, cycled)
        barrier = 10.0 * np.maximum(_STIFFNESS_MARGIN - model.spring_stiffness(grid) / g1_ref, 0.0)
        return np.concatenate([*((f - s.force) / norm for f, s, norm in zip(forces, sets, norms)), barrier])

    base = np.concatenate([[math.log(g1_ref), plain_model.g2 * x_ref / g1_ref, plain_model.g3 * x_ref**2 / g1_ref],
                           np.log(plain_model.k), np.log(plain_model.fc), [0.0, math.log(0.5 * x_ref)]])
    lower = np.concatenate([[base[0] - _LOG_BOX, -20.0, -20.0], base[3:3 + 2 * n] - _LOG_BOX,
                            [-_A_BOUND, math.log(x_ref / 50.0)]])
    upper = np.concatenate([[base[0] + _LOG_BOX, 20.0, 20.0], base[3:3 + 2 * n] + _LOG_BOX,
                            [_A_BOUND, math.log(20.0 * x_ref)]])
    begin = time.perf_counter()
    best, evaluations = None, 0
    for a in starts:
        u0 = base.copy()
        u0[-2] = a
        u0 = np.clip(u0, lower + 1e-9, upper - 1e-9)
        solution = scipy.optimize.least_squares(residuals, u0, bounds=(lower, upper), method="trf",
                                                x_scale="jac", max_nfev=max_nfev, xtol=1e-12, ftol=1e-12)
        evaluations += int(solution.nfev) + int(getattr(solution, "njev", 0) or 0) * u0.size
        if best is None or solution.cost < best.cost:
            best = solution
    elapsed = time.perf_counter() - begin
    model = unpack(best.x)
    units = {spec.name: spec.unit for spec in model.param_specs()}
    physical = model.params()
    # covariance in internal coordinates, chain rule to physical ones
    jac = best.jac
    dof = max(jac.shape[0] - jac.shape[1], 1)
    redchi = 2.0 * best.cost / dof
    try:
        covariance = redchi * np.linalg.inv(jac.T @ jac)
        internal_err = np.sqrt(np.clip(np.diag(covariance), 0.0, np.inf))
    except np.linalg.LinAlgError:
        internal_err = np.full(best.x.size, np.inf)
    derivative = np.concatenate([[physical["g1"], g1_ref / x_ref, g1_ref / x_ref**2], model.k, model.fc,
                                 [1.0, model.slip_length]])
    order_names = ["g1", "g2", "g3", *(f"k_{i}" for i in range(1, n + 1)), *(f"fc_{i}" for i in range(1, n + 1)),
                   "slip_modulation", "slip_length"]
    span = upper - lower
    at_bound = (best.x - lower < _BOUND_MARGIN * span) | (upper - best.x < _BOUND_MARGIN * span)
    table = pd.DataFrame({"name": order_names, "value": [physical[name] for name in order_names],
                          "stderr": internal_err * np.abs(derivative), "unit": [units[name] for name in order_names],
                          "at_bound": at_bound})
    reasons = []
    for row in table.itertuples():
        if row.at_bound:
            reasons.append(f"parameter {row.name} = {row.value:.6g} {row.unit} is on its search bound")
    if best.status <= 0:
        reasons.append(f"least squares stopped without converging: {best.message}")
    a_err = float(table.loc[table["name"] == "slip_modulation", "stderr"].iloc[0])
    if not abs(model.slip_modulation) > 2.0 * a_err:
        reasons.append(f"modulation not resolved: slip_modulation = {model.slip_modulation:.3g} +/- {a_err:.2g} "
                       "(within two standard errors of 0: the plain Iwan model explains the loops as well, "
                       "slip_length is undetermined)")
    largest_travel = max(float(np.ptp(s.deflection)) for s in sets)
    for i, (k, fc) in enumerate(zip(model.k, model.fc), start=1):
        if 2.0 * fc * (1.0 + abs(model.slip_modulation)) / k > largest_travel:
            reasons.append(f"element {i} never slips within the data (slip travel {2e3 * fc / k:.3g} mm): "
                           f"fc_{i} undetermined")
    if grid.size and np.any(model.spring_stiffness(grid) < 0.0):
        lower, upper = model.valid_deflection_range()
        reasons.append(f"the fitted spring turns negative-stiff at {1e3 * lower:.4g} / {1e3 * upper:.4g} mm, inside "
                       f"valid_range {1e3 * grid[0]:.4g} to {1e3 * grid[-1]:.4g} mm")
    ns = len(small_sets)
    errors = _errors(model, sets, cycled)
    plain_errors = _errors(ModulatedIwanModel.from_iwan(plain_model), sets, cycled)
    return ModulatedIwanFitResult(
        model=model, plain_model=plain_model, plain=plain_result, small_errors=errors[:ns], large_errors=errors[ns:],
        plain_small_errors=plain_errors[:ns], plain_large_errors=plain_errors[ns:],
        small_names=tuple(s.name for s in small_sets), large_names=tuple(s.name for s in large_sets),
        parameters=table, elapsed_s=elapsed, evaluations=evaluations, reasons=tuple(reasons),
    )


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
