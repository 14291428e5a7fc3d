"""Staged, scaled, globally searched identification of the modified Bouc-Wen model.

SPEC 1.3 / thesis eqs. (3.3)-(3.6): ``F = b^(c x) (k1 x + k2 sgn(x) x^2 + k3 x^3 + z)``,
``dz/dx = alpha - (gamma + beta sgn(dx z)) |z|^n``, fitted to the same quasi-static
loops and with the same objective (7.1) as the Iwan model (:mod:`idkit.fit.iwan`),
so that the two can be compared set by set (:func:`compare_loop_models`).

**Why it is badly conditioned** (the thesis's remark) and what idkit does about it:

* *Redundancy.* ``b^(c x) = exp(c ln(b) x)``: only ``c ln b`` matters. idkit fixes
  ``b = e`` and fits ``c`` (1/m), so the asymmetry factor is ``exp(c x)``.
* *Scale.* In SI units the parameters span about 15 decades (``beta, gamma`` in
  ``N^(1-n)/m`` depend on ``n``; ``k3`` is ~1e8 N/m^3 for a few mm). The optimiser
  never sees them: it works on the **loop-shape parametrisation**
  ``k1, alpha`` (stiffnesses), ``z_max = (alpha / (beta + gamma))^(1/n)`` (N, the
  saturation force of ``z``: the half height of a large loop), ``shape = beta / (beta + gamma)``
  (dimensionless; 1 means ``gamma = 0``), ``n``, and ``k2 x_ref / K``, ``k3 x_ref^2 / K``,
  ``c x_ref`` (``x_ref`` the largest |deflection|, ``K`` the initial stiffness read
  off the loops), each mapped to ``[0, 1]`` between bounds (logarithmically for the
  positive ones). ``beta + gamma = alpha / z_max^n > 0`` then holds by construction:
  ``z`` saturates, as :class:`~idkit.models.BoucWenModel` requires.
  :attr:`BoucWenFitResult.conditioning` reports the condition number of the
  Gauss-Newton matrix ``J^T J`` in SI parameters and in the scaled ones.
* *Staging.* From the automatic start (:func:`idkit.fit.iwan_start`: initial
  slope ``K = k1 + alpha``, large-amplitude slope ``g1 -> k1``, half loop height
  ``-> z_max``, ``n = 1``, ``shape = 0.75``):

  1. ``elastic``: ``k1, k2, k3, alpha, c`` free, loop shape fixed (bounded Nelder-Mead);
  2. ``loop shape``: ``z_max, shape, n`` free, elastic part fixed;
  3. ``global``: all free, a seeded population search over the whole scaled box
     (nlopt ``GN_CRS2_LM`` controlled random search, or scipy
     ``differential_evolution`` with the stage-2 point in its initial population),
     then a bounded Nelder-Mead **polish** started from the better of the global
     point and the stage-2 point.

Objective: the mean over all sets of the relative RMS error (7.1); small and large
sets weigh equally as groups (``0.5 mean_small + 0.5 mean_large``). Every set starts
at a reversal, in the start state chosen as by :func:`idkit.fit.fit_iwan`
(``initial_state="auto"``: ``z = 0`` at ``x = 0`` loaded to the first point when the
record starts unloaded, otherwise also run once over the set and returned to its
first point, the state of steady cycling).
"""

from __future__ import annotations

import math
import time

import lmfit
import numpy as np
import scipy.optimize

from idkit.checks import Choice, accepts
from idkit.errors import FitError
from idkit.fit._optim import BACKEND, global_search as _global_search
from idkit.fit._optim import nelder_mead
from idkit.fit._params import Transform, central_jacobian, jacobian_statistics, to_lmfit
from idkit.fit.iwan_start import iwan_start
from idkit.fit.loop_objective import BoucWenLoops
from idkit.fit.loop_objective import INITIAL_STATE, boucwen_set_errors, boucwen_set_forces, boucwen_values
from idkit.fit.model_form import loop_model_form_reasons
from idkit.fit.result import BoucWenFitResult, BoucWenFitSettings, StageResult
from idkit.models import BoucWenModel
from idkit.observe.quasi_static import as_loop_sets

__all__ = ["fit_boucwen", "boucwen_set_errors", "boucwen_set_forces"]

B_FIXED = math.e  # base of the asymmetry factor; only c ln b is identifiable
_NAMES = ("k1", "alpha", "z_max", "shape", "n", "k2", "k3", "c")
_STAGE_FREE = {
    "elastic": ("k1", "alpha", "k2", "k3", "c"),
    "loop shape": ("z_max", "shape", "n"),
    "global": _NAMES,
}


# --------------------------------------------------------------------------- parametrisation


class _Space:
    """Scaled box [0, 1]^8 <-> Bouc-Wen parameters (module docstring)."""

    def __init__(self, stiffness: float, half_height: float, x_ref: float):
        self.stiffness, self.half_height, self.x_ref = stiffness, half_height, x_ref
        k, h, x = stiffness, half_height, x_ref
        box = {"k1": ("log01", 1e-3 * k, 2.0 * k), "alpha": ("log01", 1e-3 * k, 20.0 * k),
               "z_max": ("log01", 1e-2 * h, 1e2 * h), "shape": ("linear01", 0.0, 2.5), "n": ("log01", 0.3, 6.0),
               "k2": ("linear01", -10.0 * k / x, 10.0 * k / x), "k3": ("linear01", -10.0 * k / x**2, 10.0 * k / x**2),
               "c": ("linear01", -2.0 / x, 2.0 / x)}
        units = {name: unit for name, (unit, _, _) in _declared().items()}
        self.transforms = {name: Transform(name, units[name], kind, low, high)
                           for name, (kind, low, high) in box.items()}

    def physical(self, u) -> dict:
        q = {name: float(self.transforms[name].to_physical(value)) for name, value in zip(_NAMES, u)}
        total = q["alpha"] / q["z_max"] ** q["n"]  # beta + gamma > 0
        q["beta"] = q["shape"] * total
        q["gamma"] = (1.0 - q["shape"]) * total
        return q

    def internal(self, q: dict) -> np.ndarray:
        return np.array([float(self.transforms[name].to_internal(q[name])) for name in _NAMES])

    def clip_values(self, q: dict) -> dict:
        out = dict(q)
        for name in _NAMES:
            t = self.transforms[name]
            out[name] = float(min(max(q[name], t.lower), t.upper))
        return out


def _shape_values(values: dict) -> dict:
    """Loop-shape parameters (z_max, shape) of Bouc-Wen parameters (beta + gamma > 0)."""
    total = values["beta"] + values["gamma"]
    if not total > 0:
        raise FitError(f"start: found beta + gamma = {total:g}, expected > 0 (a saturating z)")
    out = dict(values)
    out["z_max"] = (values["alpha"] / total) ** (1.0 / values["n"])
    out["shape"] = values["beta"] / total
    return out


# --------------------------------------------------------------------------- the fit


@accepts(backend=BACKEND, global_method=Choice(("crs2", "differential_evolution"), optional=True),
         initial_state=INITIAL_STATE, error=FitError)
def fit_boucwen(
    small,
    large,
    *,
    start: BoucWenModel | None = None,
    backend: str = "nlopt",
    points_per_set: int | None = 200,
    global_search: bool = True,
    global_method: str | None = None,
    global_max_evals: int = 1000,
    max_evals: int = 3000,
    xtol: float = 1e-7,
    restarts: int = 2,
    initial_step: float = 0.05,
    initial_state: str = "auto",
    seed: int = 0,
) -> BoucWenFitResult:
    """Identify a modified Bouc-Wen model on quasi-static loops (staged, scaled, global + polish).

    Parameters
    ----------
    small, large : sequence
        Loop sets as for :func:`idkit.fit.fit_iwan` (:class:`~idkit.fit.LoopSet`,
        ``(deflection m, force N)`` pairs or objects with ``.deflection``/``.force``).
    start : BoucWenModel, optional
        Starting model (``beta + gamma > 0``); default read off the loops (module docstring).
    backend : {"nlopt", "scipy"}
        Local solver: bounded Nelder-Mead of nlopt (``LN_NELDERMEAD``) or scipy.
    points_per_set : int or None, default 200
    global_search : bool, default True
        Run stage 3's population search (off: stage 3 is a local polish only).
    global_method : {"crs2", "differential_evolution"}, optional
        Default follows ``backend`` (``crs2`` = nlopt ``GN_CRS2_LM``).
    global_max_evals : int, default 1000
    max_evals : int, default 3000
        Evaluation limit per local stage (restarts included).
    xtol : float, default 1e-7
        Absolute tolerance in the scaled [0, 1] coordinates.
    restarts : int, default 2
    initial_step : float, default 0.05
        Simplex edge in scaled coordinates (5 % of each parameter's range).
    initial_state : {"auto", "cycled", "virgin"}
    seed : int, default 0
        Seeds the global search (nlopt's generator or numpy's); every result is
        reproducible bit for bit for a given seed.

    Returns
    -------
    BoucWenFitResult
        ``parameters`` (alias ``params``) carry standard errors and correlations from
        the covariance ``redchi (J^T J)^-1`` of the per-point residuals of all sets at the
        final parameters, which it does not move
        (:func:`idkit.fit._params.jacobian_statistics`): ``r = (F_model - F_meas) /
        |F_meas|_set x sqrt(S w_set / e_set)``, ``w_set`` the set's weight in the objective
        and ``S`` the number of sets, so that ``chisqr = S x objective`` and the
        least-squares optimum of ``r`` is the objective's, as for :func:`fit_iwan`. ``J``
        by central differences (step 1e-3 in the scaled coordinates, wider than the
        integrator's sub-step jumps), propagated to
        ``k1 .. c`` (and ``z_max``, ``shape``) by the Jacobian of the parameter map; a
        coordinate at a bound of the box is held there. ``chisqr``, ``redchi``, ``aic``,
        ``bic``, ``fit_report()`` as in lmfit; a missing stderr is named with the reason in
        ``stderr_notes``. ``conditioning`` the condition numbers.

    Raises
    ------
    FitError
        Bad sets (too few points, no reversals, NaN), unknown backend or method.

    Examples
    --------
    >>> import numpy as np
    >>> from idkit.models import BoucWenModel
    >>> truth = BoucWenModel(k1=2e3, k2=0, k3=0, alpha=2e4, beta=6e3, gamma=2e3, n=1.0)
    >>> x = np.sin(np.linspace(0, 4 * np.pi, 401))
    >>> pair = lambda a: (a * x, truth.force(a * x))
    >>> result = fit_boucwen([pair(1e-3)], [pair(4e-3)], global_max_evals=500)
    >>> bool(result.error_large < 0.02)
    True
    """
    t0 = time.perf_counter()
    if global_method is None:
        global_method = "crs2" if backend == "nlopt" else "differential_evolution"
    small_sets = as_loop_sets(small, "small", points_per_set)
    large_sets = as_loop_sets(large, "large", points_per_set)
    info = iwan_start(small_sets, large_sets, 1)
    x_ref = max(float(np.max(np.abs(s.deflection))) for s in small_sets + large_sets)
    space = _Space(info.stuck_stiffness, info.half_height, x_ref)
    if start is None:
        k1 = info.g1
        values = {"k1": k1, "alpha": max(info.stuck_stiffness - k1, 0.05 * info.stuck_stiffness),
                  "z_max": info.half_height, "shape": 0.75, "n": 1.0, "k2": 0.0, "k3": 0.0, "c": 0.0}
    else:
        values = _shape_values(boucwen_values(start))
    values = space.clip_values(values)
    small_packed, large_packed = BoucWenLoops(small_sets, initial_state), BoucWenLoops(large_sets, initial_state)

    def mean_error(u):
        q = space.physical(u)
        small, large = small_packed.set_errors(q), large_packed.set_errors(q)
        # np.mean to the bit, without its ~4 us wrapper (this runs at every evaluation)
        return 0.5 * float(np.add.reduce(small) / small.size) + 0.5 * float(np.add.reduce(large) / large.size)

    u_current = space.internal(values)
    stages, global_info = [], None
    for stage_name in ("elastic", "loop shape", "global"):
        t_stage = time.perf_counter()
        free = [_NAMES.index(name) for name in _STAGE_FREE[stage_name]]
        base = u_current.copy()

        def objective(v, base=base, free=free):
            u = base.copy()
            u[free] = v
            return mean_error(u)

        start_error = objective(base[free])
        start_params = _report_values(space.physical(base))
        evaluations = 0
        v0 = base[free]
        message_prefix = ""
        if stage_name == "global" and global_search:
            v_global, value_global, used, method_name = _global_search(
                objective, v0, method=global_method, max_evals=global_max_evals, seed=seed)
            evaluations += used
            global_info = {"method": method_name, "error": value_global, "evaluations": used,
                           "stage2_error": start_error}
            if value_global < start_error:
                v0 = v_global
            message_prefix = f"{method_name} ({used} evaluations, {100 * value_global:.3f} %) + polish: "
        if stage_name == "global":
            # Gauss-Newton steps on the stacked normalised residuals converge where a
            # simplex in 8 dimensions crawls; Nelder-Mead then finishes on (7.1) itself.
            def residuals(v, base=base, free=free):
                u = base.copy()
                u[free] = v
                return _stacked_residuals(space, u, small_packed, large_packed)

            polished = scipy.optimize.least_squares(residuals, np.clip(v0, 0.0, 1.0), bounds=(0.0, 1.0),
                                                    method="trf", x_scale=1.0, max_nfev=50 * (len(free) + 1))
            evaluations += int(polished.nfev * (len(free) + 1))
            if objective(polished.x) < objective(v0):
                v0 = polished.x
            message_prefix += f"least squares ({polished.nfev} steps), "
        run = nelder_mead(objective, v0, step=initial_step, bounds=(np.zeros(len(free)), np.ones(len(free))),
                          backend=backend, max_evals=max_evals, xtol=xtol, ftol=1e-12, restarts=restarts,
                          step_into_box=True)
        evaluations += run.evaluations
        u_current = base.copy()
        u_current[free] = run.x
        q = space.physical(u_current)
        errors = np.concatenate([small_packed.set_errors(q), large_packed.set_errors(q)])
        stages.append(StageResult(
            name=stage_name, data="small + large", free=_STAGE_FREE[stage_name], start=start_params,
            params=_report_values(q), set_names=small_packed.names + large_packed.names, set_errors=errors,
            mean_error=float(run.value), start_error=float(start_error), evaluations=evaluations,
            restarts=run.restarts, message=message_prefix + run.message, elapsed_s=time.perf_counter() - t_stage,
            status=run.status))
    elapsed = time.perf_counter() - t0

    q = space.physical(u_current)
    model = BoucWenModel(k1=q["k1"], k2=q["k2"], k3=q["k3"], alpha=q["alpha"], beta=q["beta"], gamma=q["gamma"],
                         n=q["n"], b=B_FIXED, c=q["c"])
    parameters, statistics, conditioning, at_bound = _lmfit_view(space, u_current, small_packed, large_packed)
    settings = BoucWenFitSettings(
        backend=backend, points_per_set=points_per_set, global_search=bool(global_search),
        global_method=global_method if global_search else None, global_max_evals=int(global_max_evals),
        max_evals=int(max_evals), xtol=float(xtol), restarts=int(restarts), initial_step=float(initial_step),
        initial_state=initial_state, seed=int(seed),
        bounds={name: (t.lower, t.upper) for name, t in space.transforms.items()})
    return BoucWenFitResult(
        model=model, stages=tuple(stages), small_errors=small_packed.set_errors(q),
        large_errors=large_packed.set_errors(q), small_names=small_packed.names, large_names=large_packed.names,
        settings=settings, parameters=parameters, conditioning=conditioning, at_bound=at_bound,
        global_search=global_info, elapsed_s=elapsed, statistics=statistics,
        model_form=loop_model_form_reasons(  # the shared model-form check (docs/fitting.md, "Verdicts")
            [("small", small_sets, small_packed.split(small_packed.forces(q))),
             ("large", large_sets, large_packed.split(large_packed.forces(q)))],
            remedy="another model form, docs/fitting.md"))


def _report_values(q: dict) -> dict:
    return {name: float(q[name]) for name in _REPORTED}


_REPORTED = ("k1", "k2", "k3", "alpha", "beta", "gamma", "n", "c", "z_max", "shape")
#: Units and bounds of the two derived loop-shape parameters (not model parameters); the
#: model's own come from :meth:`BoucWenModel.param_specs`.
_DERIVED = {"z_max": ("N", 0.0, math.inf), "shape": ("-", -math.inf, math.inf)}


def _declared() -> dict:
    """Name -> (unit, lower, upper) of every reported parameter, as the model declares them."""
    reference = BoucWenModel(k1=1.0, k2=0.0, k3=0.0, alpha=1.0, beta=1.0, gamma=0.0, n=1.0)  # any valid model
    return {**{spec.name: (spec.unit, spec.lower, spec.upper) for spec in reference.param_specs()}, **_DERIVED}


def _stacked_residuals(space: _Space, u, small: BoucWenLoops, large: BoucWenLoops) -> np.ndarray:
    """Per-set normalised residuals; each group weighs as in the objective (1 / sqrt(2 n_sets))."""
    q = space.physical(u)
    return np.concatenate([small.residuals(q) / math.sqrt(2 * len(small.names)),
                           large.residuals(q) / math.sqrt(2 * len(large.names))])


def _lmfit_view(space: _Space, u: np.ndarray, small: BoucWenLoops, large: BoucWenLoops):
    """lmfit Parameters and statistics at the optimum; condition numbers; parameters at a bound.

    Returns ``(parameters, statistics, conditioning, at_bound)`` (see :func:`fit_boucwen`).
    """
    q = space.physical(u)
    errors = np.concatenate([small.set_errors(q), large.set_errors(q)])
    # the objective is sum_s w_s e_s (w_s = 0.5 / sets of the group); weights sqrt(S w_s / e_s)
    # frozen at the optimum give sum r^2 = S x objective (S sets: = sum_s e_s when both groups
    # have as many sets, as for Iwan) and its gradient, so the least-squares optimum of r is
    # the Nelder-Mead one
    share = np.concatenate([np.full(len(small.names), 0.5 / len(small.names)),
                            np.full(len(large.names), 0.5 / len(large.names))])
    sizes = np.concatenate([np.diff(small.offsets), np.diff(large.offsets)])
    weights = np.repeat(np.sqrt(errors.size * share / np.maximum(errors, 1e-300)), sizes)
    at_bound = tuple(name for name, value in zip(_NAMES, u) if value < 1e-6 or value > 1 - 1e-6)
    free = [i for i, name in enumerate(_NAMES) if name not in at_bound]

    def residuals_all(v):
        p = space.physical(v)
        return weights * np.concatenate([small.residuals(p), large.residuals(p)])

    def residuals(v):
        point = np.array(u, dtype=float)
        point[free] = v
        return residuals_all(point)

    def mapped(v):
        p = space.physical(v)
        return np.array([p[name] for name in _REPORTED])

    step = 1e-3
    jacobian = central_jacobian(residuals_all, u, step=step)
    map_jacobian = central_jacobian(mapped, u, step=step)  # d(physical)/d(scaled), rows _REPORTED
    # condition numbers of J^T J: scaled coordinates vs the SI parameters k1, k2, k3, alpha, beta, gamma, n, c
    normal_scaled = jacobian.T @ jacobian
    try:
        jacobian_si = jacobian @ np.linalg.inv(map_jacobian[:8])
        cond_si = float(np.linalg.cond(jacobian_si.T @ jacobian_si))
    except np.linalg.LinAlgError:
        cond_si = math.inf
    conditioning = {"scaled": float(np.linalg.cond(normal_scaled)), "si": cond_si}
    declared = _declared()
    names = list(_REPORTED) + ["b", "c_visc"]
    varied = _REPORTED[:8]
    parameters = to_lmfit(
        names, list(mapped(u)) + [B_FIXED, 0.0],
        units=[declared[name][0] for name in names],
        lower=[declared[name][1] for name in names],
        upper=[declared[name][2] for name in names],
        vary=[name in varied for name in names])
    if not free:
        return parameters, None, conditioning, at_bound
    internal = jacobian_statistics(residuals, u[free], [_NAMES[i] for i in free], step=step, group_sizes=sizes,
                                   point_sources=np.concatenate([small.sources, large.sources]),
                                   method="Jacobian of the per-point residuals at the Nelder-Mead optimum")
    return parameters, _physical_statistics(internal, map_jacobian, free, parameters, at_bound), conditioning, at_bound


def _physical_statistics(internal, map_jacobian: np.ndarray, free: list[int], parameters, at_bound):
    """The statistics in the reported parameters by the delta method ``M C M^T``.

    ``M = d(reported)/d(scaled)``; the loop-shape map is not one-to-one per parameter
    (``beta``, ``gamma`` depend on ``alpha, z_max, shape, n``), so a reported parameter
    gets no stderr when it depends on a coordinate at a bound of the box or one without
    a stderr, and the note says which.
    """
    known = np.array([internal.params[_NAMES[i]].stderr is not None for i in free])
    covar = np.zeros((len(free), len(free))) if internal.covar is None else np.nan_to_num(internal.covar)
    matrix = map_jacobian[:, free]
    physical = matrix @ covar @ matrix.T
    notes = list(internal.stderr_notes)
    notes.extend(f"{name}: at a bound of the search box, where the least-squares statistics do not hold"
                 for name in at_bound)
    depends = np.abs(map_jacobian) > 0.0
    available = []
    for row, name in enumerate(_REPORTED):
        missing = [_NAMES[j] for j in np.flatnonzero(depends[row])
                   if j not in free or not known[free.index(j)]]
        if internal.covar is None or missing:
            parameters[name].stderr = None
            if missing and missing != [name]:
                notes.append(f"{name}: depends on {', '.join(missing)}, which has no stderr")
            continue
        parameters[name].stderr = float(math.sqrt(max(physical[row, row], 0.0)))
        available.append(row)
    for row in available:
        name = _REPORTED[row]
        if not parameters[name].vary:
            continue
        parameters[name].correl = {
            _REPORTED[other]: float(physical[row, other] / math.sqrt(physical[row, row] * physical[other, other]))
            for other in available if other != row and parameters[_REPORTED[other]].vary
            and physical[row, row] > 0 and physical[other, other] > 0}
    varied = [row for row, name in enumerate(_REPORTED) if parameters[name].vary]
    values = {key: getattr(internal, key) for key in vars(internal)}
    values.update(params=parameters, var_names=[_REPORTED[row] for row in varied],
                  init_vals=[float(parameters[_REPORTED[row]].value) for row in varied],
                  init_values={_REPORTED[row]: float(parameters[_REPORTED[row]].value) for row in varied},
                  covar=None if internal.covar is None else physical[np.ix_(varied, varied)],
                  stderr_notes=notes)
    return lmfit.minimizer.MinimizerResult(**values)
