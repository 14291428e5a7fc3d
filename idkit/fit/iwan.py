"""Three-stage identification of the modified Iwan model from quasi-static loops.

SPEC section 4 / thesis section 7.1. Deflection (m) is the input, force (N) the
output. Each data set is resampled to a fixed number of points and scored by the
relative RMS force error (7.1)::

    e = sqrt(sum (F_model - F_meas)^2 / sum F_meas^2)

and a stage minimises the mean of ``e`` over its sets with Nelder-Mead (nlopt
``LN_NELDERMEAD``, or scipy's ``Nelder-Mead`` as the second backend):

1. small loops: ``g1, k_i, fc_i`` free, ``g2 = g3 = 0``;
2. large loops: all parameters free, started from stage 1;
3. all loops: ``g1, g2, g3`` fixed at stage 2, ``k_i, fc_i`` refined.

Stage 3 departs from SPEC 4 (which refines on the small loops only): an element
whose slip travel ``2 fc_i / k_i`` exceeds the small loops never slips in them, so
their error is flat in its ``fc_i`` and a simplex on them wanders along that direction,
decided by rounding. Scored on all loops every local parameter is seen by some data
(docs/fitting.md).

**Element order.** Jenkin elements are exchangeable (swapping two leaves the force
law unchanged), so after every stage they are sorted by slip travel ``fc_i / k_i``,
shortest first: equal elements cannot come back in an order decided by rounding.

**Search box and honesty.** Every parameter is searched inside a box set by the
data (:data:`STIFFNESS_BOX` x the stuck stiffness, :data:`FRICTION_BOX` x the
largest force, :data:`POLYNOMIAL_BOX` for ``g2``, ``g3``), so nothing overflows. A
final parameter on the box, a stage stopped at the evaluation limit, or an element
that never slips within the data (its slip force undetermined) makes
``success=False`` with the reason in ``result.reasons``.

**Positivity.** ``g1``, ``k_i`` and ``fc_i`` are optimised as their natural
logarithms, so every stiffness and slip force stays strictly positive however
the simplex moves (the thesis could not enforce this). ``g2`` and ``g3`` are
signed and optimised as ``g2 * x_ref / g1_ref`` and ``g3 * x_ref**2 / g1_ref``
(``x_ref`` the largest |deflection| of the large sets, ``g1_ref`` the stage-1
``g1``), i.e. as their share of the linear force at the largest deflection.

**Initial element state.** A resampled set starts at a reversal, where the
element forces depend on the earlier history. Every element is taken unloaded at
zero deflection and loaded to the first point of the set (``"virgin"``): exact
when the record itself starts unloaded, since it reaches its first reversal
without reversing. With ``"cycled"`` the model is then run once over the whole
set and back to its first point, and those element forces start the scored run:
the state of steady cycling, right for repeated loops whose record starts
mid-history (elements that never slip keep the offset ``k_i x`` of the loading,
as they physically do). The default ``"auto"`` chooses per set: "virgin" when
the record starts unloaded (:attr:`LoopSet.starts_unloaded`), else "cycled".
Records whose amplitude grows from an unloaded start (SPEC 3) are wrong in the
cycled state: the largest loop's slip state is imposed on the small ones before it.

**Where the parts live.** Loops come from :mod:`idkit.observe.quasi_static`
(:func:`prepare_loops`, :class:`LoopSet`); the compiled objective of all sets of a stage
(one numba call, no per-point Python work) from :mod:`idkit.fit.loop_objective`; the start
from :mod:`idkit.fit.iwan_start`; the bounded Nelder-Mead with restarts from
:mod:`idkit.fit._optim`; the order table from :mod:`idkit.fit.compare`.
"""

from __future__ import annotations

import dataclasses
import math
import time

import nlopt
import numpy as np

from idkit.checks import Whole, accepts
from idkit.errors import FitError
from idkit.fit._optim import BACKEND, MAX_EVALS, nelder_mead
from idkit.fit._params import Transform, jacobian_statistics, spec_units, to_lmfit, to_physical_statistics
from idkit.fit.iwan_start import iwan_start
from idkit.fit.loop_objective import INITIAL_STATE, IwanLoops, iwan_set_errors, iwan_set_forces
from idkit.fit.model_form import loop_model_form_reasons
from idkit.fit.result import IwanFitResult, IwanFitSettings, StageResult, determinacy_reasons
from idkit.models import IwanModel
from idkit.models.laws import lowest_spring_stiffness
from idkit.observe.quasi_static import LoopSet, as_loop_sets, prepare_loops

__all__ = ["fit_iwan", "iwan_start", "iwan_set_errors", "iwan_set_forces", "LoopSet", "prepare_loops"]

#: Default evaluation limit of a stage per free parameter (at least 10000): enough for the
#: high orders of a rope whose slip spreads over the whole loop to converge in every stage
#: (docs/fitting.md).
EVALUATIONS_PER_PARAMETER = 4000


# --------------------------------------------------------------------------- the three stages


_STAGE_FREE = {
    "stage 1": ("g1", "k", "fc"),
    "stage 2": ("g1", "g2", "g3", "k", "fc"),
    "stage 3": ("k", "fc"),
}


#: An Iwan fit's order.
IWAN_ORDER = Whole(ge=1, meaning="Jenkin elements")


@accepts(order=IWAN_ORDER, backend=BACKEND, initial_state=INITIAL_STATE,
         stage2_starts=Whole(ge=1), error=FitError)
def fit_iwan(
    small,
    large,
    *,
    order: int = 2,
    start: IwanModel | None = None,
    backend: str = "nlopt",
    points_per_set: int | None = 200,
    max_evals: int | None = None,
    xtol: float = 1e-7,
    ftol: float = 1e-12,
    restarts: int = 2,
    initial_step: float = 0.3,
    initial_state: str = "auto",
    seed: int = 0,
    valid_range: tuple[float, float] | None = None,
    stage2_starts: int = 1,
) -> IwanFitResult:
    """Identify an order-``n`` modified Iwan model in three Nelder-Mead stages (SPEC 4).

    Parameters
    ----------
    small, large : sequence
        Small-amplitude and large-amplitude loop sets. Each item is a
        :class:`LoopSet` (used as is), a ``(deflection, force)`` pair of arrays
        in m and N, or any object with ``.deflection`` and ``.force`` (e.g.
        :class:`idkit.signal.cycles.ResampledLoops`); raw items are prepared with
        :func:`prepare_loops` (cut at the reversals, resampled to
        ``points_per_set`` points; :func:`~idkit.observe.quasi_static.as_loop_sets`).
    order : int, default 2
        Number of Jenkin elements, >= 1.
    start : IwanModel, optional
        Starting model (its order wins over ``order``); default: :func:`iwan_start`.
    backend : {"nlopt", "scipy"}
        ``nlopt.LN_NELDERMEAD`` or ``scipy.optimize.minimize(method="Nelder-Mead")``,
        both from the same initial simplex ``u0 + initial_step * e_i``.
    points_per_set : int or None, default 200
    max_evals : int, optional
        Evaluation limit per stage (restarts included); default
        ``max(10000, EVALUATIONS_PER_PARAMETER x free parameters)`` (a simplex needs more
        steps in more dimensions, and crawls along the valid-range barrier).
    xtol, ftol : float
        Absolute tolerances on the internal coordinates (log: relative change of
        the value) and on the mean error (fraction).
    restarts : int, default 2
        Fresh simplices started from the best point after convergence; stops
        early when a restart gains less than ``ftol``.
    initial_step : float, default 0.3
        Simplex edge in internal coordinates (0.3 ~ 35 % change of a log parameter).
    initial_state : {"auto", "cycled", "virgin"}
        Element forces at the first point of a set (module docstring); ``"auto"``
        takes "virgin" for a set whose record starts unloaded, else "cycled".
    seed : int
        Seeds nlopt's generator (Nelder-Mead itself is deterministic); recorded.
    valid_range : (float, float), optional
        Deflections (m, ``x_min < 0 < x_max``) over which the fitted parallel spring must
        keep a non-negative local stiffness ``g1 + 2 g2 x + 3 g3 x^2`` (SPEC 1.2): the
        large-loop stage adds a barrier ``1 + violation / g1`` to the objective wherever it
        turns negative there. Default: no constraint (the thesis's fit).

    stage2_starts : int, default 1
        Starts of stage 2 (all parameters, large loops): the stage-1 result and
        ``stage2_starts - 1`` seeded perturbations of it (:func:`_extra_starts`); the
        end point with the lowest large-loop error is kept (its evaluations count them
        all). Default 1: judged on the large loops alone, an extra start can win by
        over-fitting them (docs/fitting.md).

    Returns
    -------
    IwanFitResult
        ``result.params`` (alias ``result.parameters``) carries standard errors and
        correlations from the covariance ``redchi (J^T J)^-1`` of the per-point residuals
        of all small and large sets at the final parameters, which it does not move
        (:func:`idkit.fit._params.jacobian_statistics`): ``r = (F_model - F_meas) /
        (|F_meas|_set sqrt(e_set))``, each set normalised as the objective (7.1) does and
        weighted by its error at the optimum so that ``chisqr = sum e_set`` and the
        least-squares optimum of ``r`` is the objective's. ``J`` by central differences
        (step 1e-4) in the internal coordinates, mapped by ``stderr(p) = p stderr(log p)``
        (``g2``, ``g3``: linear). ``result.chisqr``, ``redchi``, ``aic``, ``bic``,
        ``fit_report()`` as in lmfit; a parameter without stderr is named with the reason
        in ``result.stderr_notes``. Each stderr is ``sqrt(s^2 + d^2)``, ``d`` the Gauss-Newton
        step to the least-squares optimum of ``r`` with one force offset per set free. Points
        resampled between measured samples count the samples behind them
        (:attr:`LoopSet.source_index`, ``jacobian_statistics(..., point_sources=...)``): a
        branch of 20 samples resampled to 41 points holds 20 measurements.
        Calibrated on synthetic loops in docs/fitting.md.

    Raises
    ------
    FitError
        Bad sets (too few points, no reversals, NaN), ``order < 1``, unknown backend.

    Examples
    --------
    >>> import numpy as np
    >>> from idkit.models import IwanModel
    >>> truth = IwanModel(g1=3e3, k=[6e3], fc=[10.0])
    >>> x = np.concatenate([a * np.sin(np.linspace(0, 4 * np.pi, 400)) for a in (2e-3, 8e-3)])
    >>> pair = lambda a: (a * x[:400] / 2e-3, truth.force(a * x[:400] / 2e-3))
    >>> result = fit_iwan([pair(1e-3), pair(2e-3)], [pair(8e-3)], order=1)
    >>> bool(result.error_small < 1e-3)
    True
    """
    t0 = time.perf_counter()
    small_sets = as_loop_sets(small, "small", points_per_set)
    large_sets = as_loop_sets(large, "large", points_per_set)
    start_info = iwan_start(small_sets, large_sets, order if start is None else start.order)
    model0 = start_info.model if start is None else start
    n = model0.order
    nlopt.srand(int(seed))
    small_packed, large_packed = IwanLoops(small_sets, initial_state), IwanLoops(large_sets, initial_state)
    all_packed = IwanLoops(small_sets + large_sets, initial_state)
    x_ref = max(float(np.max(np.abs(s.deflection))) for s in large_sets)
    if valid_range is not None:
        x_min, x_max = (float(v) for v in valid_range)
        if not (np.isfinite(x_min) and np.isfinite(x_max) and x_min < 0.0 < x_max):
            raise FitError(f"valid_range: found {valid_range!r}, expected (x_min, x_max) in m with x_min < 0 < x_max")

    units = spec_units(model0)
    stiffness_ref = start_info.stuck_stiffness
    force_ref = max(float(np.max(np.abs(s.force))) for s in small_sets + large_sets)
    refs = {"g1": f"{STIFFNESS_BOX} x the stuck stiffness {stiffness_ref:.4g} N/m",
            "k": f"{STIFFNESS_BOX} x the stuck stiffness {stiffness_ref:.4g} N/m",
            "fc": f"{FRICTION_BOX} x the largest |force| {force_ref:.4g} N",
            "g2": f"+-{POLYNOMIAL_BOX:g} x g1 / x_ref", "g3": f"+-{POLYNOMIAL_BOX:g} x g1 / x_ref^2"}

    current = {"g1": model0.g1, "g2": model0.g2, "g3": model0.g3,
               "k": np.array(model0.k, float), "fc": np.array(model0.fc, float)}
    stages, reasons = [], []
    for stage_name, data in (("stage 1", "small"), ("stage 2", "large"), ("stage 3", "all")):
        t_stage = time.perf_counter()
        packed = {"small": small_packed, "large": large_packed, "all": all_packed}[data]
        if stage_name == "stage 1":
            current["g2"] = current["g3"] = 0.0
        g1_ref = current["g1"]
        transforms = _stage_transforms(_STAGE_FREE[stage_name], n, x_ref, g1_ref, stiffness_ref, force_ref, units)
        bounds = _internal_bounds(transforms)
        stage_evals = max(10000, EVALUATIONS_PER_PARAMETER * len(transforms)) if max_evals is None else int(max_evals)
        u0 = _to_internal(current, transforms)
        unpack = _make_unpack(current, transforms, n)

        def objective(u, packed=packed, unpack=unpack):
            g1, g2, g3, k, fc = unpack(u)
            packed.evaluate(g1, g2, g3, k, fc)
            errors = packed.errors
            error = np.add.reduce(errors) / errors.size  # errors.mean() to the bit, without its ~4 us wrapper
            if valid_range is not None:
                lowest = lowest_spring_stiffness(g1, g2, g3, x_min, x_max)
                if lowest < 0.0:
                    error += 1.0 - lowest / g1
            return error

        start_params = _flat_params(current)
        start_error = objective(np.clip(u0, *bounds))
        search = dict(step=initial_step, bounds=bounds, backend=backend, max_evals=stage_evals, xtol=xtol,
                      ftol=ftol, restarts=restarts)
        best = nelder_mead(objective, u0, **search)
        evaluations = best.evaluations
        if stage_name == "stage 2":  # the global stage: several starts against local minima
            for extra in _extra_starts(u0, bounds, stage2_starts - 1, seed):
                run = nelder_mead(objective, extra, **search)
                evaluations += run.evaluations
                if run.value < best.value:
                    best = run
        if best.status == MAX_EVALS:
            # one continuation from the best point with a fresh simplex and budget: a stage of
            # 13-15 parameters can stop at its limit while still descending, and whether it does
            # must not hang on an ulp of the data; still at the limit -> not a success
            more = nelder_mead(objective, best.x, **search)
            evaluations += more.evaluations
            if more.value <= best.value:
                best = dataclasses.replace(more, restarts=best.restarts + more.restarts + 1)
        g1, g2, g3, k, fc = unpack(best.x)
        by_travel = np.argsort(fc / k, kind="stable")  # one order of the exchangeable elements
        current = {"g1": float(g1), "g2": float(g2), "g3": float(g3), "k": k[by_travel], "fc": fc[by_travel]}
        errors = packed.set_errors(g1, g2, g3, k, fc)
        if best.status == MAX_EVALS:
            reasons.append(f"{stage_name} stopped at the evaluation limit max_evals={stage_evals}")
        if stage_name != "stage 1":  # stage 1 only starts stage 2; its bounds are the final stages' too
            reasons.extend(f"{stage_name}: {r}" for r in _bound_reasons(transforms, _to_internal(current, transforms),
                                                                       refs))
        stages.append(StageResult(
            name=stage_name, data=data, free=tuple(t.name for t in transforms), start=start_params,
            params=_flat_params(current), set_names=packed.names, set_errors=errors,
            mean_error=float(errors.mean()), start_error=float(start_error), evaluations=evaluations,
            restarts=best.restarts, message=best.message, elapsed_s=time.perf_counter() - t_stage,
            status=best.status))
    elapsed = time.perf_counter() - t0
    travel = max(float(np.ptp(s.deflection)) for s in small_sets + large_sets)
    for i, (k_i, fc_i) in enumerate(zip(current["k"], current["fc"]), start=1):
        if 2.0 * fc_i / k_i > travel:
            reasons.append(f"fc_{i} is not determined: element {i} never slips within the data (slip travel "
                           f"2 fc/k = {1e3 * 2.0 * fc_i / k_i:.4g} mm > largest loop travel {1e3 * travel:.4g} mm)")

    model = IwanModel(g1=current["g1"], g2=current["g2"], g3=current["g3"], k=current["k"], fc=current["fc"])
    low = min(float(np.min(s.deflection)) for s in small_sets + large_sets)
    high = max(float(np.max(s.deflection)) for s in small_sets + large_sets)
    lower, upper = model.valid_deflection_range()
    if not (lower <= low and high <= upper):
        reasons.append(f"the fitted spring turns negative-stiff at {1e3 * lower:.4g} / {1e3 * upper:.4g} mm, inside "
                       f"the loops' own deflections ({1e3 * low:.4g} to {1e3 * high:.4g} mm): the model cannot be "
                       "simulated over its data")
    parameters, statistics = _iwan_lmfit(model, small_packed, large_packed, x_ref, stiffness_ref, force_ref, units)
    reasons.extend(determinacy_reasons(parameters, statistics))  # the shared verdict (docs/fitting.md, "Verdicts")
    final = (model.g1, model.g2, model.g3, np.array(model.k, dtype=np.float64), np.array(model.fc, dtype=np.float64))
    reasons.extend(loop_model_form_reasons(
        [("small", small_sets, small_packed.split(small_packed.forces(*final))),
         ("large", large_sets, large_packed.split(large_packed.forces(*final)))],
        remedy="a higher order (order table), the slip-modulated Iwan or another model form, docs/fitting.md"))
    settings = IwanFitSettings(order=n, backend=backend, points_per_set=points_per_set, max_evals=max_evals,
                               xtol=xtol, ftol=ftol, restarts=restarts, initial_step=initial_step,
                               initial_state=initial_state, seed=int(seed),
                               valid_range=None if valid_range is None else (x_min, x_max),
                               stage2_starts=int(stage2_starts))
    args = (model.g1, model.g2, model.g3, np.array(model.k, dtype=np.float64), np.array(model.fc, dtype=np.float64))
    return IwanFitResult(
        model=model, stages=tuple(stages),
        small_errors=small_packed.set_errors(*args), large_errors=large_packed.set_errors(*args),
        small_names=small_packed.names, large_names=large_packed.names, start=start_info,
        settings=settings, parameters=parameters, elapsed_s=elapsed, reasons=tuple(dict.fromkeys(reasons)),
        start_states=dict(zip(all_packed.names, all_packed.start_states)), statistics=statistics)


def _extra_starts(u0: np.ndarray, bounds, count: int, seed: int) -> list[np.ndarray]:
    """``count`` seeded starts around ``u0``: each coordinate moved by N(0, 0.5) in the
    internal coordinates (a log parameter by a factor e^0.5 = 1.6 typically; g2, g3 by half
    their share of the linear force), clipped into the search box."""
    rng = np.random.default_rng([int(seed), 2])
    return [np.clip(u0 + rng.normal(0.0, 0.5, u0.size), *bounds) for _ in range(max(0, int(count)))]


# Search box of every parameter, relative to scales read off the data (see fit_iwan):
STIFFNESS_BOX = (1e-6, 1e2)  # g1, k_i: x the stuck stiffness of the loops (N/m)
FRICTION_BOX = (1e-6, 1e1)  # fc_i: x the largest |force| of the loops (N)
POLYNOMIAL_BOX = 1e3  # |g2 x_ref| and |g3 x_ref^2|: x the stage-1 linear force g1 x_ref
_AT_BOUND = 1e-3  # internal distance below which a parameter counts as sitting on its bound


def _stage_transforms(free: tuple[str, ...], n: int, x_ref: float, g1_ref: float,
                      stiffness_ref: float, force_ref: float, units: dict) -> list[Transform]:
    """The free parameters of a stage, units from the model's ``param_specs`` (``units``)."""
    k_low, k_high = (b * stiffness_ref for b in STIFFNESS_BOX)
    f_low, f_high = (b * force_ref for b in FRICTION_BOX)
    g2_scale, g3_scale = g1_ref / x_ref, g1_ref / x_ref**2
    transforms = []
    for group in free:
        if group == "g1":
            transforms.append(Transform("g1", units["g1"], "log", k_low, k_high))
        elif group == "g2":
            bound = POLYNOMIAL_BOX * g2_scale
            transforms.append(Transform("g2", units["g2"], "scaled", -bound, bound, scale=g2_scale))
        elif group == "g3":
            bound = POLYNOMIAL_BOX * g3_scale
            transforms.append(Transform("g3", units["g3"], "scaled", -bound, bound, scale=g3_scale))
        elif group == "k":
            transforms.extend(Transform(f"k_{i}", units[f"k_{i}"], "log", k_low, k_high) for i in range(1, n + 1))
        else:
            transforms.extend(Transform(f"fc_{i}", units[f"fc_{i}"], "log", f_low, f_high) for i in range(1, n + 1))
    return transforms


def _internal_bounds(transforms: list[Transform]) -> tuple[np.ndarray, np.ndarray]:
    lower = np.array([float(t.to_internal(t.lower)) for t in transforms])
    upper = np.array([float(t.to_internal(t.upper)) for t in transforms])
    return lower, upper


def _bound_reasons(transforms: list[Transform], u: np.ndarray, refs: dict) -> list[str]:
    """One sentence per parameter sitting on its search bound at internal point ``u``."""
    reasons = []
    lower, upper = _internal_bounds(transforms)
    for t, value, low, high in zip(transforms, u, lower, upper):
        for side, bound in (("lower", low), ("upper", high)):
            if abs(value - bound) <= _AT_BOUND * max(1.0, abs(bound)):
                reasons.append(
                    f"{t.name} = {float(t.to_physical(value)):.4g} {t.unit} sits at its {side} search bound "
                    f"({refs[t.name.split('_')[0]]}): the loops do not determine it")
    return reasons


def _to_internal(current: dict, transforms: list[Transform]) -> np.ndarray:
    values = []
    for t in transforms:
        if "_" in t.name:
            group, index = t.name.split("_")
            values.append(current[group][int(index) - 1])
        else:
            values.append(current[t.name])
    return np.array([float(t.to_internal(v)) for t, v in zip(transforms, values)])


def _make_unpack(current: dict, transforms: list[Transform], n: int):
    """Fast internal -> (g1, g2, g3, k, fc) for one stage (fixed values from ``current``)."""
    names = [t.name for t in transforms]
    log_mask = np.array([t.kind == "log" for t in transforms])
    scales = np.array([t.scale for t in transforms])
    index = {name: i for i, name in enumerate(names)}
    g1_fixed, g2_fixed, g3_fixed = current["g1"], current["g2"], current["g3"]
    k_fixed, fc_fixed = np.array(current["k"], float), np.array(current["fc"], float)
    k_slice = slice(index["k_1"], index["k_1"] + n) if "k_1" in index else None
    fc_slice = slice(index["fc_1"], index["fc_1"] + n) if "fc_1" in index else None

    def unpack(u):
        u = np.asarray(u, dtype=float)
        values = np.where(log_mask, np.exp(np.minimum(u, 700.0)), scales * u)
        g1 = values[index["g1"]] if "g1" in index else g1_fixed
        g2 = values[index["g2"]] if "g2" in index else g2_fixed
        g3 = values[index["g3"]] if "g3" in index else g3_fixed
        k = np.ascontiguousarray(values[k_slice]) if k_slice else k_fixed
        fc = np.ascontiguousarray(values[fc_slice]) if fc_slice else fc_fixed
        return float(g1), float(g2), float(g3), k, fc

    return unpack


def _flat_params(current: dict) -> dict:
    values = {"g1": float(current["g1"]), "g2": float(current["g2"]), "g3": float(current["g3"])}
    values.update({f"k_{i}": float(v) for i, v in enumerate(current["k"], start=1)})
    values.update({f"fc_{i}": float(v) for i, v in enumerate(current["fc"], start=1)})
    return values


def _add_the_step(internal, names) -> None:
    """Add the distance to the least-squares optimum to each standard error, in quadrature (in place).

    The stages stop where Nelder-Mead's tolerance lets them (and hold ``g1, g2, g3`` from the
    large loops), not at the least-squares optimum of the residuals the statistics describe;
    one Gauss-Newton step ``d`` measures how far that optimum is. The reported standard error
    is ``sqrt(s^2 + d^2)``, the spread of the returned point about the truth when the step is
    as random as the noise (correlations kept, covariance rescaled; the step is then reported
    in the new standard errors). With the same force noise (N) on every loop the steps of
    ``g1, g2, g3`` reached 2-3 standard errors (docs/fitting.md, "Iwan uncertainty"). The
    optimum is that of the residuals with one force offset per loop set free (a load-cell zero
    error the fit holds at 0 is absorbed by ``g2`` and the others; the step measures it).
    """
    steps = getattr(internal, "gauss_newton_step", None) or {}
    if internal.covar is None or not steps:
        return
    for index, name in enumerate(names):
        if name not in steps or internal.params[name].stderr is None:
            continue
        factor = math.sqrt(1.0 + steps[name] ** 2)
        internal.covar[index, :] *= factor
        internal.covar[:, index] *= factor
        internal.params[name].stderr *= factor
        steps[name] /= factor


def _iwan_lmfit(model: IwanModel, small: IwanLoops, large: IwanLoops, x_ref: float, stiffness_ref: float,
                force_ref: float, units: dict):
    """lmfit view of the final model and its statistics at the optimum (see :func:`fit_iwan`).

    Returns ``(parameters, statistics)``: :class:`lmfit.Parameters` in physical units
    with ``stderr`` and ``correl``, and the :class:`lmfit.minimizer.MinimizerResult` of
    :func:`idkit.fit._params.jacobian_statistics` mapped to them.
    """
    n = model.order
    transforms = _stage_transforms(_STAGE_FREE["stage 2"], n, x_ref, model.g1, stiffness_ref, force_ref, units)
    current = {"g1": model.g1, "g2": model.g2, "g3": model.g3,
               "k": np.array(model.k, float), "fc": np.array(model.fc, float)}
    u_opt = _to_internal(current, transforms)
    unpack = _make_unpack(current, transforms, n)
    # weights 1 / sqrt(e_s) frozen at the optimum: sum r^2 = sum_s e_s (the stage objective
    # times the number of sets) and its gradient is the objective's, so the least-squares
    # optimum of these residuals is the Nelder-Mead one when the stages reached it
    errors = np.concatenate([small.set_errors(*unpack(u_opt)), large.set_errors(*unpack(u_opt))])
    sizes = np.concatenate([np.diff(small.offsets), np.diff(large.offsets)])
    weights = np.repeat(1.0 / np.sqrt(np.maximum(errors, 1e-300)), sizes)

    def residuals(u):
        args = unpack(u)
        return weights * np.concatenate([small.residuals(*args), large.residuals(*args)])

    names = [t.name for t in transforms]
    # one force offset per loop set (a load-cell zero the fit holds at 0): d r / d offset
    norms = np.concatenate([small.norm, large.norm])
    nuisance = np.zeros((int(sizes.sum()), sizes.size))
    for s, (a, b) in enumerate(zip(np.cumsum(sizes) - sizes, np.cumsum(sizes))):
        nuisance[a:b, s] = weights[a:b] / norms[s]
    internal = jacobian_statistics(residuals, u_opt, names, group_sizes=sizes,
                                   step_nuisance=nuisance,
                                   point_sources=np.concatenate([small.sources, large.sources]),
                                   method="Jacobian of the per-point residuals at the Nelder-Mead optimum")
    _add_the_step(internal, names)
    specs = {spec.name: spec for spec in model.param_specs()}
    parameters = to_lmfit(
        names + ["c_visc"], [float(t.to_physical(u)) for t, u in zip(transforms, u_opt)] + [0.0],
        units=[t.unit for t in transforms] + [specs["c_visc"].unit],
        lower=[t.lower for t in transforms] + [specs["c_visc"].lower],
        upper=[t.upper for t in transforms] + [specs["c_visc"].upper],
        vary=[True] * len(names) + [False],
    )
    return parameters, to_physical_statistics(internal, transforms, parameters)
