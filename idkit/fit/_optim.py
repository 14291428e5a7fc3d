"""Optimiser plumbing shared by the fitters: one wrapper, one status, one of each search.

* :class:`Tracked` - objective wrapper counting evaluations, keeping the best point and
  replacing a non-finite value by :data:`PENALTY`.
* :func:`nelder_mead` - bounded Nelder-Mead (nlopt ``LN_NELDERMEAD`` or scipy) with
  restarts from the best point (Iwan and Bouc-Wen stages).
* :func:`sqp` - bounded SQP with inequality constraints (nlopt ``LD_SLSQP`` or scipy
  ``SLSQP``) on a :class:`ConstrainedProblem` (Maxwell, Voigt, complex stiffness).
* :func:`constrained_global_search` - nlopt ``GN_ISRES`` or scipy
  ``differential_evolution`` on a :class:`ConstrainedProblem`;
  :func:`global_search` - nlopt ``GN_CRS2_LM`` or scipy ``differential_evolution`` on a
  plain function (Bouc-Wen).

Every local run returns a :class:`LocalRun` whose ``status`` is set here from the
optimiser's own return code (:data:`CONVERGED`, :data:`STALLED`, :data:`MAX_EVALS`,
:data:`FAILED`, :data:`INFEASIBLE`): fit results read success from it, never from the
text of ``message``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import nlopt
import numpy as np
import scipy.optimize

from idkit.checks import Choice

__all__ = [
    "BACKEND", "PENALTY", "CONVERGED", "STALLED", "MAX_EVALS", "FAILED", "INFEASIBLE", "SUCCESSFUL",
    "Tracked", "LocalRun", "ConstrainedProblem", "nlopt_result_name",
    "nelder_mead", "sqp", "constrained_global_search", "global_search",
]

PENALTY = 1e6  # objective value given to a point where the model is not finite

#: The declared ``backend`` of every fitter: nlopt or scipy, the same algorithm in both.
BACKEND = Choice(("nlopt", "scipy"))

#: The optimiser met its own convergence test.
CONVERGED = "converged"
#: It stopped where it could not improve further (nlopt roundoff limit, a scipy SLSQP line
#: search or subproblem failure): the best point is kept and counts as converged, as before.
STALLED = "stalled"
#: It stopped on the evaluation (or iteration) limit.
MAX_EVALS = "max_evals"
#: nlopt's generic failure (e.g. incompatible linearised constraints).
FAILED = "failed"
#: No evaluated point met the constraints: the start was kept.
INFEASIBLE = "infeasible"
#: Statuses of a run whose end point is trusted.
SUCCESSFUL = frozenset({CONVERGED, STALLED})

_NLOPT_NAMES = {nlopt.SUCCESS: "success", nlopt.STOPVAL_REACHED: "stopval reached", nlopt.FTOL_REACHED: "ftol reached",
                nlopt.XTOL_REACHED: "xtol reached", nlopt.MAXEVAL_REACHED: "max_evals reached",
                nlopt.MAXTIME_REACHED: "maxtime reached"}
_CONSTRAINT_TOL = 1e-10



#: nlopt's generic failure: ``RuntimeError`` in most releases, ``nlopt.runtime_error`` (not a
#: ``RuntimeError``) in others, e.g. when SLSQP meets incompatible linearised constraints
#: from an infeasible start.
_NLOPT_FAILURES = (RuntimeError, getattr(nlopt, "runtime_error", RuntimeError))

def nlopt_result_name(code: int) -> str:
    """Readable name of an nlopt result code, e.g. ``"xtol reached"`` (``"code N"`` if unknown)."""
    return _NLOPT_NAMES.get(code, f"code {code}")


def _nlopt_status(code: int) -> str:
    return MAX_EVALS if code in (nlopt.MAXEVAL_REACHED, nlopt.MAXTIME_REACHED) else CONVERGED


class Tracked:
    """Objective wrapper counting evaluations and keeping the best point.

    Parameters
    ----------
    function : callable
        ``function(u) -> float``; a non-finite value is replaced by :data:`PENALTY`.
    """

    def __init__(self, function):
        self.function = function
        self.evaluations = 0
        self.best_u = None
        self.best_value = math.inf

    def __call__(self, u, grad=None):
        value = float(self.function(np.asarray(u, dtype=float)))
        if not math.isfinite(value):
            value = PENALTY
        self.evaluations += 1
        if value < self.best_value:
            self.best_value = value
            self.best_u = np.array(u, dtype=float)
        return value


@dataclass(frozen=True)
class LocalRun:
    """End of a local optimisation.

    Attributes
    ----------
    x : ndarray
        Best point found (internal coordinates).
    value : float
        Objective at ``x``.
    evaluations : int
        Objective evaluations, restarts included.
    restarts : int
        Restarts run after the first search.
    message : str
        The optimiser's stop reason, for people.
    status : str
        :data:`CONVERGED`, :data:`STALLED`, :data:`MAX_EVALS`, :data:`FAILED` or
        :data:`INFEASIBLE`, set from the optimiser's return code.
    """

    x: np.ndarray
    value: float
    evaluations: int
    restarts: int
    message: str
    status: str

    @property
    def success(self) -> bool:
        """The status is :data:`CONVERGED` or :data:`STALLED`."""
        return self.status in SUCCESSFUL


# --------------------------------------------------------------------------- Nelder-Mead


def _nelder_mead_once(tracked: Tracked, u0, step, bounds, *, backend, max_evals, xtol, ftol,
                      step_into_box) -> tuple[str, str]:
    """One simplex search from ``u0``; returns (status, message)."""
    n = u0.size
    lower, upper = bounds
    steps = np.where(u0 + step > upper, -step, step) if step_into_box else np.full(n, float(step))
    if backend == "nlopt":
        opt = nlopt.opt(nlopt.LN_NELDERMEAD, n)
        opt.set_min_objective(tracked)
        opt.set_lower_bounds(lower)
        opt.set_upper_bounds(upper)
        opt.set_initial_step(steps)
        opt.set_xtol_abs(xtol)
        # no ftol for nlopt: its Nelder-Mead stops on one small improvement of the best
        # vertex, which ended the Iwan stage 2 far from the optimum in tests; xtol and restarts decide
        opt.set_maxeval(int(max_evals))
        try:
            opt.optimize(np.array(u0, dtype=float))
        except nlopt.RoundoffLimited:
            return STALLED, "nlopt: roundoff limited"
        code = opt.last_optimize_result()
        return _nlopt_status(code), "nlopt: " + nlopt_result_name(code)
    if step_into_box:
        simplex = np.vstack([u0, u0 + np.diag(steps)])
    else:
        simplex = np.clip(np.vstack([u0, u0 + step * np.eye(n)]), lower, upper)
    result = scipy.optimize.minimize(
        tracked, u0, method="Nelder-Mead", bounds=scipy.optimize.Bounds(lower, upper),
        options={"initial_simplex": simplex, "xatol": xtol, "fatol": ftol, "maxfev": int(max_evals)},
    )
    if result.nfev >= max_evals and not result.success:
        return MAX_EVALS, "scipy: max_evals reached"
    if result.success:
        return CONVERGED, "scipy: converged"
    return STALLED, "scipy: " + str(result.message)  # e.g. the iteration limit 200 n: restarts continue


def nelder_mead(function, u0, *, step: float, bounds, backend: str, max_evals: int, xtol: float, ftol: float,
                restarts: int, step_into_box: bool = False) -> LocalRun:
    """Bounded Nelder-Mead with restarts from the best point (a fresh simplex escapes stalls).

    Parameters
    ----------
    function : callable
        ``function(u) -> float`` in internal coordinates.
    u0 : array_like
        Start (clipped into ``bounds``).
    step : float
        Simplex edge in internal coordinates.
    bounds : (ndarray, ndarray)
        Lower and upper internal bounds.
    backend : {"nlopt", "scipy"}
    max_evals : int
        Evaluation limit over the search and its restarts.
    xtol, ftol : float
        Absolute tolerances on the coordinates and on the objective; a restart that gains
        less than ``ftol`` ends the restarts.
    restarts : int
        Fresh simplices from the best point after the first search.
    step_into_box : bool, default False
        Point every edge of the initial simplex into the box (``-step`` where ``u + step``
        passes the upper bound) instead of clipping the simplex to it.

    Returns
    -------
    LocalRun
    """
    tracked = Tracked(function)
    lower, upper = (np.asarray(b, dtype=float) for b in bounds)
    u0 = np.clip(np.asarray(u0, dtype=float), lower, upper)
    options = dict(backend=backend, xtol=xtol, ftol=ftol, step_into_box=step_into_box)
    status, message = _nelder_mead_once(tracked, u0, step, (lower, upper), max_evals=max_evals, **options)
    done = 0
    for _ in range(restarts):
        before = tracked.best_value
        remaining = max_evals - tracked.evaluations
        if remaining <= 0 or status == MAX_EVALS:
            status = MAX_EVALS if remaining <= 0 else status
            break
        status, message = _nelder_mead_once(tracked, tracked.best_u, step, (lower, upper), max_evals=remaining,
                                             **options)
        done += 1
        if before - tracked.best_value <= ftol:
            break
    return LocalRun(x=tracked.best_u, value=tracked.best_value, evaluations=tracked.evaluations, restarts=done,
                    message=message, status=status)


# --------------------------------------------------------------------------- SQP


class ConstrainedProblem(Protocol):
    """What :func:`sqp` and :func:`constrained_global_search` need of a problem on [0, 1]^P.

    ``names`` are the P free parameters, ``evaluations`` counts objective calls,
    ``objective(z, with_gradient)`` returns the objective and its gradient (or None),
    ``constraints(z)`` returns ``c(z)`` (feasible where ``c <= 0``) and its Jacobian.
    """

    names: list[str]
    evaluations: int

    @property
    def n_constraints(self) -> int: ...

    def objective(self, z, with_gradient: bool = True) -> tuple[float, np.ndarray | None]: ...

    def constraints(self, z) -> tuple[np.ndarray, np.ndarray]: ...


def sqp(problem: ConstrainedProblem, z0, *, backend: str, max_evals: int, ftol: float) -> LocalRun:
    """Bounded SQP on [0, 1]^P from ``z0`` keeping the best feasible point.

    Parameters
    ----------
    problem : ConstrainedProblem
    z0 : array_like
        Start in [0, 1]^P (clipped).
    backend : {"nlopt", "scipy"}
        nlopt ``LD_SLSQP`` or scipy ``SLSQP``.
    max_evals : int
        Evaluation (nlopt) or iteration (scipy) limit.
    ftol : float
        Relative tolerance on the start-normalised objective.

    Returns
    -------
    LocalRun
        ``x`` the best feasible point (the start when none was feasible: status
        :data:`INFEASIBLE`), ``restarts`` 0.
    """
    z0 = np.clip(np.asarray(z0, dtype=float), 0.0, 1.0)
    scale = max(problem.objective(z0, with_gradient=False)[0], 1e-300)  # objective O(1) at the start
    start_evaluations = problem.evaluations
    m = problem.n_constraints
    best = {"z": z0.copy(), "value": math.inf}

    def feasible(z):
        return m == 0 or float(np.max(problem.constraints(z)[0])) <= 1e-8

    def track(z, value):
        if value < best["value"] and feasible(z):
            best["z"], best["value"] = np.array(z, dtype=float), value

    if backend == "nlopt":
        opt = nlopt.opt(nlopt.LD_SLSQP, z0.size)
        opt.set_lower_bounds(np.zeros(z0.size))
        opt.set_upper_bounds(np.ones(z0.size))

        def nlopt_objective(z, grad):
            if not np.all(np.isfinite(z)):  # SLSQP stepped to NaN (a singular quasi-Newton update)
                raise nlopt.ForcedStop
            with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
                value, gradient = problem.objective(z)
            if not (math.isfinite(value) and np.all(np.isfinite(gradient))):
                raise nlopt.ForcedStop
            if grad.size:
                grad[:] = gradient / scale
            track(z, value)
            return value / scale

        def nlopt_constraints(result, z, grad):
            values, jacobian = problem.constraints(z)
            result[:] = values
            if grad.size:
                grad[:] = jacobian

        opt.set_min_objective(nlopt_objective)
        if m:
            opt.add_inequality_mconstraint(nlopt_constraints, np.full(m, _CONSTRAINT_TOL))
        opt.set_ftol_rel(ftol)
        opt.set_xtol_rel(1e-10)
        opt.set_maxeval(int(max_evals))
        try:
            opt.optimize(z0)
            code = opt.last_optimize_result()
            message, status = "nlopt SLSQP: " + nlopt_result_name(code), _nlopt_status(code)
        except nlopt.RoundoffLimited:
            message, status = "nlopt SLSQP: roundoff limited (best point kept)", STALLED
        except nlopt.ForcedStop:
            message, status = "nlopt SLSQP: stepped to a non-finite point (best point kept)", STALLED
        except _NLOPT_FAILURES as error:  # nlopt's generic failure, e.g. incompatible linearised constraints
            message, status = f"nlopt SLSQP: failure '{error}' (best point kept)", FAILED
    else:
        constraints = []
        if m:
            constraints.append({"type": "ineq", "fun": lambda z: -problem.constraints(z)[0],
                                "jac": lambda z: -problem.constraints(z)[1]})

        def scipy_objective(z):
            value, gradient = problem.objective(z)
            track(z, value)
            return value / scale, gradient / scale

        result = scipy.optimize.minimize(
            scipy_objective, z0, jac=True, method="SLSQP", bounds=[(0.0, 1.0)] * z0.size,
            constraints=constraints, options={"ftol": ftol, "maxiter": int(max_evals)},
        )
        message = "scipy SLSQP: " + str(result.message)
        status = CONVERGED if result.success else (MAX_EVALS if result.status == 9 else STALLED)
        track(np.clip(result.x, 0.0, 1.0), problem.objective(np.clip(result.x, 0.0, 1.0), False)[0])
    if not math.isfinite(best["value"]):  # never feasible: keep the start, say so
        best["z"], best["value"] = z0, problem.objective(z0, False)[0]
        message += " (no feasible point found)"
        status = INFEASIBLE
    return LocalRun(x=best["z"], value=best["value"], evaluations=problem.evaluations - start_evaluations,
                    restarts=0, message=message, status=status)


# --------------------------------------------------------------------------- global searches


def constrained_global_search(problem: ConstrainedProblem, *, method: str, max_evals: int, seed: int) -> np.ndarray:
    """Seeded population-based search on [0, 1]^P with the problem's constraints.

    Parameters
    ----------
    problem : ConstrainedProblem
    method : {"isres", "differential_evolution"}
        nlopt ``GN_ISRES`` (stochastic ranking of the constraints, population 20 (P + 1))
        or scipy ``differential_evolution`` (population 15 P, no polish).
    max_evals : int
        Evaluation limit (scipy: ``max_evals // (15 P)`` generations).
    seed : int

    Returns
    -------
    ndarray
        The end point (to be polished by :func:`sqp`).
    """
    p = len(problem.names)
    m = problem.n_constraints
    if method == "isres":
        nlopt.srand(int(seed))
        opt = nlopt.opt(nlopt.GN_ISRES, p)
        opt.set_lower_bounds(np.zeros(p))
        opt.set_upper_bounds(np.ones(p))
        opt.set_min_objective(lambda z, grad: problem.objective(z, with_gradient=False)[0])
        if m:
            def constraint(result, z, grad):
                result[:] = problem.constraints(z)[0]
            opt.add_inequality_mconstraint(constraint, np.full(m, 1e-8))
        opt.set_maxeval(int(max_evals))
        opt.set_population(20 * (p + 1))
        try:
            z = opt.optimize(np.full(p, 0.5))
        except nlopt.RoundoffLimited:
            z = np.full(p, 0.5)
        return np.asarray(z)
    constraints = ()
    if m:
        constraints = scipy.optimize.NonlinearConstraint(lambda z: problem.constraints(z)[0], -np.inf, 0.0)
    popsize = 15
    result = scipy.optimize.differential_evolution(
        lambda z: problem.objective(z, with_gradient=False)[0], [(0.0, 1.0)] * p, seed=int(seed),
        constraints=constraints, polish=False, tol=1e-10, popsize=popsize,
        maxiter=max(1, int(max_evals) // (popsize * p)),
    )
    return np.asarray(result.x)


def global_search(function, u_start, *, method: str, max_evals: int, seed: int):
    """Seeded population search of ``function`` on [0, 1]^p, ``u_start`` in the population.

    Parameters
    ----------
    function : callable
        ``function(u) -> float``.
    u_start : ndarray
        A point the search starts from (nlopt) or holds in its initial population (scipy).
    method : {"crs2", "differential_evolution"}
        nlopt ``GN_CRS2_LM`` (population 10 (p + 1)) or scipy ``differential_evolution``
        (population 10 p, immediate updating, no polish).
    max_evals : int
    seed : int

    Returns
    -------
    (ndarray, float, int, str)
        Best point, its value, evaluations and the method's name.
    """
    p = u_start.size
    tracked = Tracked(function)
    if method == "crs2":
        nlopt.srand(int(seed))
        opt = nlopt.opt(nlopt.GN_CRS2_LM, p)
        opt.set_min_objective(tracked)
        opt.set_lower_bounds(np.zeros(p))
        opt.set_upper_bounds(np.ones(p))
        opt.set_maxeval(int(max_evals))
        opt.set_population(10 * (p + 1))
        try:
            opt.optimize(np.clip(u_start, 0.0, 1.0))
        except nlopt.RoundoffLimited:
            pass
        name = "nlopt GN_CRS2_LM"
    else:
        popsize = 10
        rng = np.random.default_rng(int(seed))
        population = rng.random((popsize * p, p))
        population[0] = np.clip(u_start, 0.0, 1.0)
        scipy.optimize.differential_evolution(
            tracked, [(0.0, 1.0)] * p, init=population, seed=int(seed), polish=False, tol=1e-8,
            maxiter=max(1, int(max_evals) // (popsize * p) - 1), updating="immediate")
        name = "scipy differential_evolution"
    return tracked.best_u, tracked.best_value, tracked.evaluations, name
