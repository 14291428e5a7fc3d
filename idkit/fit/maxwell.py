"""Generalized Maxwell (elastomer) identification by bounded SQP with a global cross-check.

SPEC section 4 / thesis section 7.2. ``k0`` comes from the quasi-static loops
(:mod:`idkit.observe.k0`); ``[k_1..k_n, rate_1..rate_n, m_eff]`` from the measured
transmissibilities of all top masses at once with objective (7.5)::

    e = sqrt( mean_sets mean_band |H_model - H_meas|^2 / |H_meas|^2 ),
    H_model = k*(s) / (k*(s) - (m + m_eff) omega^2),  k*(s) = k0 + sum k_i s / (s + rate_i)

(every set weighs the same whatever its number of points; one set: the RMS over
the band). The SQP minimises ``e^2``, which is smooth, with analytic gradients:

    dk*/dk_i = s / (s + rate_i),   dk*/drate_i = -k_i s / (s + rate_i)^2,
    dH/dk* = -M omega^2 / D^2,  dH/dm_eff = k* omega^2 / D^2,  D = k* - M omega^2,
    d e^2/dp = 2 sum_j w_j Re( conj(rho_j) dH_j/dp / |H_meas,j| ),  rho_j = (H_j - H_meas,j) / |H_meas,j|.

**Scaling and bounds.** Every stiffness and rate is optimised as
``z = log(p / lower) / log(upper / lower)`` in [0, 1] (defaults: ``k_i`` in
0.1 k0 .. 10 k0, rates 1 .. 1e4 1/s). ``m_eff`` has lower bound 0, where a
logarithm is undefined: it is scaled linearly, ``m_eff = z * m_eff_max``, with
``m_eff_max`` = the isolator mass when given (a part of the isolator cannot move
more mass than it has), else half the smallest top mass.

**Constraints** (inequalities ``c(z) <= 0`` with analytic Jacobians):
``z_rate_i - z_rate_(i+1) <= 0`` (sorted rates remove the n! permutations) and,
when ``monotone_loss``, ``eta(f_g) - eta(f_(g+1)) <= 0`` on a logarithmic grid of
``loss_grid_points`` frequencies over the band (loss factor non-decreasing, SPEC 4).

**Backends.** nlopt ``LD_SLSQP`` or ``scipy.optimize.minimize(method="SLSQP")``.
**Global cross-check**: nlopt ``GN_ISRES`` (evolution strategy with stochastic
ranking of the constraints) or scipy ``differential_evolution`` (with the same
constraints), seeded, each polished by the same SQP; the result reports whether
the SQP optimum was global and the gap. Both searches are :mod:`idkit.fit._optim`'s
(:func:`~idkit.fit._optim.sqp`, :func:`~idkit.fit._optim.constrained_global_search`),
whose status the result's ``success`` reads.

**The problem.** A stiffness law (:class:`_MaxwellLaw`, :class:`_VoigtLaw`: ``k*`` and its
parameter Jacobian) seen through an observation (:class:`_TransmissibilityProblem`:
:func:`idkit.models.laws.sdof_transmissibility` of each top mass; :class:`_StiffnessProblem`:
``k*`` itself). A new law or observation is a new class, not a new string branch. The data
(:class:`~idkit.observe.white_noise.TransmissibilitySet`, the band and its checks) come from
:mod:`idkit.fit.frf_objective`; the order table is :func:`idkit.fit.compare.maxwell_order_table`;
complex stiffness and DMA tables (the same law, observed directly) are fitted by
:mod:`idkit.fit.maxwell_table`.
"""

from __future__ import annotations

import dataclasses
import math
import time

import numpy as np
import scipy.stats

from idkit.checks import Choice, Real, Whole, accepts
from idkit.errors import FitError
from idkit.fit.orders import ORDER_RULE_FACTOR, earns_its_place
from idkit.fit._optim import BACKEND, INFEASIBLE, constrained_global_search, sqp
from idkit.fit._params import Transform, jacobian_statistics, spec_units, to_lmfit, to_physical_statistics
from idkit.fit.frf_objective import (
    as_transmissibility_sets,
    band_points,
    check_band,
    frf_model_form_reasons,
    frf_noise_floor,
)
from idkit.fit.maxwell_result import (
    CONSTRAINT_STEP_LIMIT,
    CrossCheck,
    MaxwellFitResult,
    MaxwellFitSettings,
    constraint_step,
)
from idkit.models import GeneralizedMaxwell, VoigtModel
from idkit.models.laws import sdof_transmissibility

__all__ = ["fit_maxwell", "fit_voigt", "LOSS_RULE_FACTOR"]

#: The declared arguments the Maxwell fits share (:mod:`idkit.checks`).
ORDER = Whole(ge=1, meaning="Maxwell elements")
#: The static stiffness a transmissibility fit starts from.
K0 = Real(unit="N/m", gt=0, meaning="static stiffness, see estimate_k0")
GLOBAL_METHOD = Choice(("isres", "differential_evolution"), optional=True)
LOSS_GRID_POINTS = Whole(ge=2)
_AT_BOUND = 1e-6  # scaled distance to a bound below which a parameter is "at the bound"


# --------------------------------------------------------------------------- the problem


class _MaxwellLaw:
    """``k*(s) = k0 + sum k_i s / (s + rate_i)`` over ``[k0], k_1..k_n, rate_1..rate_n, [m_eff]``.

    ``k0`` is a parameter when ``k0_fixed`` is None; ``m_eff`` the last one when ``with_m_eff``.
    """

    name = "maxwell"

    def __init__(self, order: int, k0_fixed: float | None, with_m_eff: bool):
        self.order, self.k0_fixed, self.with_m_eff = order, k0_fixed, with_m_eff

    def values(self, p) -> dict:
        index = 0
        if self.k0_fixed is None:
            k0, index = p[0], 1
        else:
            k0 = self.k0_fixed
        n = self.order
        k, rate = p[index : index + n], p[index + n : index + 2 * n]
        m_eff = p[index + 2 * n] if self.with_m_eff else 0.0
        return {"k0": k0, "k": k, "rate": rate, "m_eff": m_eff}

    def model(self, values) -> GeneralizedMaxwell:
        return GeneralizedMaxwell(k0=values["k0"], k=values["k"], rate=values["rate"], m_eff=values["m_eff"])

    def stiffness(self, values, s, with_jacobian: bool = True):
        """k*(s) and dk*/dp (columns in parameter order, the m_eff column zero)."""
        shift = s[:, None] + values["rate"][None, :]
        element = s[:, None] / shift
        stiffness = values["k0"] + element.dot(values["k"].astype(complex))
        if not with_jacobian:
            return stiffness, None
        columns = []
        if self.k0_fixed is None:
            columns.append(np.ones((s.size, 1), dtype=complex))
        columns.append(element)
        columns.append(-values["k"][None, :] * element / shift)
        if self.with_m_eff:
            columns.append(np.zeros((s.size, 1), dtype=complex))
        return stiffness, np.hstack(columns)


class _VoigtLaw:
    """``k*(s) = k + d s`` over ``k, damping, [m_eff]``."""

    name = "voigt"
    order = 1
    k0_fixed = None

    def __init__(self, with_m_eff: bool):
        self.with_m_eff = with_m_eff

    def values(self, p) -> dict:
        return {"k": p[0], "damping": p[1], "m_eff": p[2] if self.with_m_eff else 0.0}

    def model(self, values) -> VoigtModel:
        return VoigtModel(k=values["k"], damping=values["damping"], m_eff=values["m_eff"])

    def stiffness(self, values, s, with_jacobian: bool = True):
        """k*(s) and dk*/dp (columns in parameter order, the m_eff column zero)."""
        stiffness = values["k"] + values["damping"] * s
        if not with_jacobian:
            return stiffness, None
        columns = [np.ones_like(s), s]
        if self.with_m_eff:
            columns.append(np.zeros_like(s))
        return stiffness, np.column_stack(columns)


class _Problem:
    """Objective, gradient and constraints in scaled coordinates ``z`` in [0, 1]^P.

    A stiffness law (:class:`_MaxwellLaw`, :class:`_VoigtLaw`) seen through an observation:
    :class:`_TransmissibilityProblem` (H of a top mass on the isolator) or
    :class:`_StiffnessProblem` (k* itself, DMA data); the subclass defines :meth:`prediction`.
    Satisfies :class:`idkit.fit._optim.ConstrainedProblem`.
    """

    data = ""
    #: Per set: the noise floor of the error (7.5) (:func:`~idkit.fit.frf_objective.frf_noise_floor`),
    #: NaN when unknown; None when the observation has no model-form check (stiffness tables).
    set_floors = None

    def __init__(self, law, *, omega, measured, mass, weights, set_index, set_names, transforms: list[Transform],
                 loss_omega, monotone_loss: bool, static_offset=None):
        self.law = law
        self.omega, self.measured = omega, measured
        # per point: the static tangent stiffness at the set's preload minus k0 (N/m), added to k*
        self.static_offset = np.zeros_like(omega) if static_offset is None else np.asarray(static_offset, float)
        self.s = 1j * omega
        self.mass = mass
        self.abs_measured = np.abs(measured)
        self.weights = weights
        self.set_index, self.set_names = set_index, set_names
        self.transforms = transforms
        self.names = [t.name for t in transforms]
        self.loss_s = 1j * loss_omega if loss_omega is not None else None
        self.monotone_loss = monotone_loss and loss_omega is not None
        self.rate_columns = [i for i, name in enumerate(self.names) if name.startswith("rate_")]
        self.evaluations = 0
        self._condense()

    model = property(lambda self: self.law.name, doc="``\"maxwell\"`` or ``\"voigt\"``.")
    order = property(lambda self: self.law.order, doc="Number of Maxwell elements (1 for Voigt).")
    k0_fixed = property(lambda self: self.law.k0_fixed, doc="The fixed k0 in N/m, None when fitted.")

    # physical parameters -----------------------------------------------------------------
    def physical(self, z) -> np.ndarray:
        return np.array([float(t.to_physical(u)) for t, u in zip(self.transforms, z)])

    def internal(self, values) -> np.ndarray:
        return np.array([float(t.to_internal(v)) for t, v in zip(self.transforms, values)])

    def chain(self, z) -> np.ndarray:
        return np.array([float(t.derivative(u)) for t, u in zip(self.transforms, z)])

    def make_model(self, z):
        return self.law.model(self.law.values(self.physical(z)))

    def prediction(self, p, points=None, with_jacobian: bool = True):
        """Model prediction and its Jacobian wrt the physical parameters at ``points``
        (``(omega, mass, static offset)``; default the measured points)."""
        raise NotImplementedError

    def _condense(self):
        """Merge points with equal (omega, mass): repetitions cost one model evaluation.

        ``sum_j w_j |H - Hm_j|^2 / |Hm_j|^2 = a |H|^2 - 2 Re(conj(H) b) + c`` per unique
        point, ``a = sum w / |Hm|^2``, ``b = sum w Hm / |Hm|^2``, ``c = sum w``.
        """
        mass = np.zeros_like(self.omega) if self.mass is None else self.mass
        keys, inverse = np.unique(np.column_stack([self.omega, mass, self.static_offset]), axis=0,
                                  return_inverse=True)
        inverse = inverse.ravel()
        ratio = self.weights / self.abs_measured**2
        self.c_omega, self.c_mass = keys[:, 0], (None if self.mass is None else keys[:, 1])
        self.c_offset = keys[:, 2]
        self.c_a = np.bincount(inverse, ratio, minlength=keys.shape[0])
        self.c_b = (np.bincount(inverse, ratio * self.measured.real, minlength=keys.shape[0])
                    + 1j * np.bincount(inverse, ratio * self.measured.imag, minlength=keys.shape[0]))
        self.c_c = float(self.weights.sum())

    def residuals(self, z):
        """Relative complex residuals at every measured point and their Jacobian wrt ``z``."""
        prediction, jacobian = self.prediction(self.physical(z))
        rho = (prediction - self.measured) / self.abs_measured
        return rho, jacobian / self.abs_measured[:, None] * self.chain(z)[None, :]

    def objective(self, z, with_gradient: bool = True):
        """``e^2`` (7.5 squared) and its gradient wrt ``z`` (on the condensed points)."""
        self.evaluations += 1
        prediction, jacobian = self.prediction(self.physical(z), (self.c_omega, self.c_mass, self.c_offset),
                                               with_gradient)
        value = float(np.sum(self.c_a * (prediction.real**2 + prediction.imag**2))
                      - 2.0 * np.real(np.vdot(prediction, self.c_b)) + self.c_c)
        value = max(value, 0.0)
        if not with_gradient:
            return value, None
        gradient = 2.0 * np.real(np.conj(self.c_a * prediction - self.c_b) @ jacobian) * self.chain(z)
        return value, gradient

    def set_errors(self, z) -> np.ndarray:
        rho, _ = self.residuals(z)
        squared = np.abs(rho) ** 2
        return np.array([math.sqrt(float(np.mean(squared[self.set_index == i])))
                         for i in range(len(self.set_names))])

    # constraints -------------------------------------------------------------------------
    @property
    def n_constraints(self) -> int:
        count = max(len(self.rate_columns) - 1, 0)
        if self.monotone_loss:
            count += self.loss_s.size - 1
        return count

    def constraints(self, z):
        """``c(z) <= 0`` and its Jacobian, shape (m,) and (m, P)."""
        rows, jac_rows = [], []
        for a, b in zip(self.rate_columns[:-1], self.rate_columns[1:]):
            rows.append(z[a] - z[b])
            row = np.zeros(z.size)
            row[a], row[b] = 1.0, -1.0
            jac_rows.append(row)
        if self.monotone_loss:
            values = self.law.values(self.physical(z))
            stiffness, d_stiffness = self.law.stiffness(values, self.loss_s)
            real, imag = stiffness.real, stiffness.imag
            eta = imag / real
            d_eta = (d_stiffness.imag * real[:, None] - imag[:, None] * d_stiffness.real) / real[:, None] ** 2
            d_eta = d_eta * self.chain(z)[None, :]
            rows.extend(eta[:-1] - eta[1:])
            jac_rows.extend(d_eta[:-1] - d_eta[1:])
        if not rows:
            return np.zeros(0), np.zeros((0, z.size))
        return np.asarray(rows, dtype=float), np.vstack(jac_rows)


class _TransmissibilityProblem(_Problem):
    """The law seen as the transmissibility of top masses: :func:`~idkit.models.laws.sdof_transmissibility`
    of ``k*`` with ``mass + m_eff``; ``m_eff`` is the last parameter."""

    data = "transmissibility"

    def prediction(self, p, points=None, with_jacobian: bool = True):
        omega, mass, offset = (self.omega, self.mass, self.static_offset) if points is None else points
        values = self.law.values(p)
        stiffness, d_stiffness = self.law.stiffness(values, 1j * omega, with_jacobian)
        stiffness = stiffness + offset
        moving_mass = mass + values["m_eff"]
        prediction = sdof_transmissibility(stiffness, moving_mass, omega)
        if not with_jacobian:
            return prediction, None
        inertia = moving_mass * omega**2
        denominator = stiffness - inertia
        jacobian = (-inertia / denominator**2)[:, None] * d_stiffness
        jacobian[:, -1] = stiffness * omega**2 / denominator**2
        return prediction, jacobian


class _StiffnessProblem(_Problem):
    """The law seen as the complex stiffness itself (DMA data, no mass)."""

    data = "stiffness"

    def prediction(self, p, points=None, with_jacobian: bool = True):
        omega = self.omega if points is None else points[0]  # no preload: the offsets are zero
        return self.law.stiffness(self.law.values(p), 1j * omega, with_jacobian)


# --------------------------------------------------------------------------- input handling


#: ``monotone_loss="auto"``: the loss-factor constraint is dropped when the free fit's error is
#: below the constrained fit's by more than this factor: the order rule's
#: (:data:`idkit.fit.orders.ORDER_RULE_FACTOR`, :func:`idkit.fit.orders.earns_its_place`), the
#: standard an extra element must meet.
LOSS_RULE_FACTOR = ORDER_RULE_FACTOR


def _check_bounds(name: str, bounds, unit: str) -> tuple[float, float]:
    low, high = (float(v) for v in bounds)
    if not (0 < low < high < math.inf):
        raise FitError(f"{name}: found ({low:g}, {high:g}) {unit}, expected 0 < lower < upper")
    return low, high


def _loss_grid(band, points: int):
    return 2 * np.pi * np.geomspace(band[0], band[1], int(points))


def _stack(parts):
    """Concatenate per-set arrays; weights make every set count equally."""
    omega = np.concatenate([2 * np.pi * f for f, _, _ in parts])
    measured = np.concatenate([v for _, v, _ in parts])
    mass = np.concatenate([np.full(f.size, m) for f, _, m in parts])
    set_index = np.concatenate([np.full(f.size, i) for i, (f, _, _) in enumerate(parts)])
    weights = np.concatenate([np.full(f.size, 1.0 / (len(parts) * f.size)) for f, _, _ in parts])
    return omega, measured, mass, set_index, weights


# --------------------------------------------------------------------------- public fitters


def _declared(model: str, order: int) -> dict:
    """Name -> ParamSpec of the model fitted (units and physical bounds come from here)."""
    if model == "voigt":
        reference = VoigtModel(k=1.0, damping=1.0)  # any valid model: its declarations
    else:
        reference = GeneralizedMaxwell(k0=1.0, k=np.ones(order), rate=np.arange(1.0, order + 1.0))
    return {spec.name: spec for spec in reference.param_specs()}


def _maxwell_transforms(order, stiffness_bounds, rate_bounds, *, k0_bounds=None, m_eff_max=None):
    units = spec_units(GeneralizedMaxwell(k0=1.0, k=np.ones(order), rate=np.arange(1.0, order + 1.0)))
    transforms = []
    if k0_bounds is not None:
        transforms.append(Transform("k0", units["k0"], "log01", *k0_bounds))
    transforms += [Transform(f"k_{i}", units[f"k_{i}"], "log01", *stiffness_bounds) for i in range(1, order + 1)]
    transforms += [Transform(f"rate_{i}", units[f"rate_{i}"], "log01", *rate_bounds) for i in range(1, order + 1)]
    if m_eff_max is not None:
        transforms.append(Transform("m_eff", units["m_eff"], "linear01", 0.0, m_eff_max))
    return transforms


def _default_start(problem: _Problem, band, seed: int, samples: int = 64) -> np.ndarray:
    """Best feasible point of a seeded scrambled Sobol sample of [0, 1]^P (plus the band guess).

    The band guess: ``k_i`` at the geometric middle of their bounds, rates
    log-spaced inside the band (as 2 pi f), ``m_eff`` at 20 % of its bound. The
    objective has deep valleys along the resonances of each top mass, so a
    single fixed start can sit on the wrong side of one; 64 cheap evaluations
    pick a start in the right basin far more often.
    """
    guess = np.full(len(problem.names), 0.5)
    rate_names = [name for name in problem.names if name.startswith("rate_")]
    if rate_names:
        rates = 2 * np.pi * np.geomspace(band[0], band[1], len(rate_names) + 2)[1:-1]
        for name, rate in zip(rate_names, rates):
            t = problem.transforms[problem.names.index(name)]
            guess[problem.names.index(name)] = float(np.clip(t.to_internal(np.clip(rate, t.lower, t.upper)), 0, 1))
    if "m_eff" in problem.names:
        guess[problem.names.index("m_eff")] = 0.2
    sampler = scipy.stats.qmc.Sobol(d=len(problem.names), scramble=True, seed=int(seed))
    candidates = np.vstack([guess, sampler.random(samples)])
    if len(problem.rate_columns) > 1:  # sort the rates of every candidate: the constraint holds
        columns = problem.rate_columns
        candidates[:, columns] = np.sort(candidates[:, columns], axis=1)
    best, best_value = guess, math.inf
    for z in candidates:
        if problem.n_constraints and np.max(problem.constraints(z)[0]) > 0:
            continue
        value = problem.objective(z, with_gradient=False)[0]
        if value < best_value:
            best, best_value = z, value
    return best


def _solve(problem: _Problem, *, start, band, backend, max_evals, ftol, cross_check, global_method,
           global_max_evals, seed, settings_extra, k0_stderr=None):
    if global_method is None:
        global_method = "isres" if backend == "nlopt" else "differential_evolution"
    if start is None:
        z0 = _default_start(problem, band, seed)
    else:
        values = _start_values(problem, start)
        z0 = problem.internal(values)
        if np.any(~np.isfinite(z0)) or np.any(z0 < 0) or np.any(z0 > 1):
            raise FitError(f"start: found parameters {dict(zip(problem.names, values))} outside the bounds "
                           f"{[(t.name, t.lower, t.upper) for t in problem.transforms]}")
    t0 = time.perf_counter()
    run = sqp(problem, z0, backend=backend, max_evals=max_evals, ftol=ftol)
    z_sqp, value_sqp = run.x, run.value
    elapsed = time.perf_counter() - t0
    sqp_error = math.sqrt(value_sqp)
    z_best, source, check = z_sqp, "sqp", None
    if cross_check:
        t1 = time.perf_counter()
        before = problem.evaluations
        z_global = constrained_global_search(problem, method=global_method, max_evals=global_max_evals, seed=seed)
        polished = sqp(problem, z_global, backend=backend, max_evals=max_evals, ftol=ftol)
        z_polished, value_global = polished.x, polished.value
        global_error = math.sqrt(value_global)
        tolerance = max(1e-4, 1e-3 * global_error)
        gap = sqp_error - global_error
        check = CrossCheck(
            method=("nlopt GN_ISRES" if global_method == "isres" else "scipy differential_evolution")
            + f" + {backend} SLSQP polish",
            sqp_error=sqp_error, global_error=global_error, gap=gap, tolerance=tolerance,
            reached_global=bool(gap <= tolerance),
            global_params=dict(zip(problem.names, problem.physical(z_polished).tolist())),
            evaluations=problem.evaluations - before, seed=int(seed), elapsed_s=time.perf_counter() - t1)
        if not check.reached_global:  # keep the SQP model unless the global one is really better
            z_best, source = z_polished, "global"
    model = problem.make_model(z_best)
    at_bound = tuple(name for name, z in zip(problem.names, z_best) if z < _AT_BOUND or z > 1 - _AT_BOUND)
    set_errors = problem.set_errors(z_best)
    error = math.sqrt(problem.objective(z_best, with_gradient=False)[0])
    parameters, statistics = _lmfit_view(problem, z_best, at_bound, k0_stderr)
    settings = MaxwellFitSettings(
        model=problem.model, order=problem.order, data=problem.data, backend=backend, band=tuple(band),
        bounds={t.name: (t.lower, t.upper) for t in problem.transforms}, monotone_loss=problem.monotone_loss,
        loss_grid_points=0 if problem.loss_s is None else int(problem.loss_s.size), max_evals=int(max_evals),
        ftol=float(ftol), seed=int(seed), global_method=global_method if cross_check else None,
        global_max_evals=int(global_max_evals) if cross_check else None, **settings_extra)
    floors = problem.set_floors
    model_form = () if floors is None else frf_model_form_reasons(problem.set_names, set_errors, floors)
    return MaxwellFitResult(
        model=model, error=error, set_errors=set_errors, set_names=tuple(problem.set_names),
        set_floors=floors, model_form_reasons=model_form,
        sqp_error=sqp_error, at_bound=at_bound, evaluations=run.evaluations, message=run.message, source=source,
        status=run.status,
        cross_check=check, settings=settings, parameters=parameters, elapsed_s=elapsed, statistics=statistics)


def _start_values(problem: _Problem, start) -> np.ndarray:
    params = start.params()
    names = problem.names
    if isinstance(start, GeneralizedMaxwell) and start.order != problem.order:
        raise FitError(f"start: found order {start.order}, expected order {problem.order}")
    try:
        return np.array([params[name] for name in names], dtype=float)
    except KeyError as missing:
        raise FitError(f"start: parameter {missing.args[0]!r} missing, expected {names}") from None


def _lmfit_view(problem: _Problem, z, at_bound, k0_stderr=None):
    """lmfit Parameters and statistics from the analytic Jacobian (parameters at a bound excluded).

    Returns ``(parameters, statistics)``: :class:`lmfit.Parameters` in physical units with
    ``stderr`` and ``correl``, and the :class:`lmfit.minimizer.MinimizerResult` of
    :func:`idkit.fit._params.jacobian_statistics` mapped to them (None when every free
    parameter is at a bound).
    """
    # The residuals are those of the objective (7.5): sqrt(w) rho with real and imaginary
    # parts stacked, so chisqr = error^2 and the optimum is a least-squares one (SQP).
    # The covariance is formed in the scaled coordinates z (columns of comparable size;
    # in SI units k ~ 1e4 N/m and m_eff ~ 0.1 kg make J^T J look singular) and mapped
    # to physical units by the chain rule: stderr(p) = |dp/dz| stderr(z). A parameter at
    # a bound is held there: the statistics of a minimum do not hold at a bound.
    root_w = np.sqrt(problem.weights)
    free = [i for i, name in enumerate(problem.names) if name not in at_bound]

    def full(v):
        point = np.array(z, dtype=float)
        point[free] = v
        return point

    def residuals(v):
        rho, _ = problem.residuals(full(v))
        return np.concatenate([(root_w * rho).real, (root_w * rho).imag])

    def jacobian(v):
        _, jacobian_z = problem.residuals(full(v))
        weighted = root_w[:, None] * jacobian_z[:, free]
        return np.vstack([weighted.real, weighted.imag])

    values = problem.physical(z)
    names, units = list(problem.names), [t.unit for t in problem.transforms]
    lower, upper = [t.lower for t in problem.transforms], [t.upper for t in problem.transforms]
    vary = [True] * len(names)
    stderr = [None] * len(names)
    if problem.model == "maxwell" and problem.k0_fixed is not None:
        k0 = _declared("maxwell", problem.order)["k0"]
        names, values = ["k0", *names], np.concatenate([[problem.k0_fixed], values])
        units, lower, upper = [k0.unit, *units], [k0.lower, *lower], [k0.upper, *upper]
        vary, stderr = [False, *vary], [k0_stderr, *stderr]  # fixed in the fit, uncertain from its source
    parameters = to_lmfit(names, values, units=units, lower=lower, upper=upper, vary=vary, stderr=stderr)
    if not free:
        return parameters, None
    internal = jacobian_statistics(residuals, np.asarray(z, dtype=float)[free], [problem.names[i] for i in free],
                                   jacobian=jacobian,
                                   method="analytic Jacobian of the weighted residuals at the SQP optimum")
    return parameters, to_physical_statistics(internal, [problem.transforms[i] for i in free], parameters)


def _frf_problem(frfs, *, model, order, k0, band, stiffness_bounds, rate_bounds, damping_bounds, m_eff_max,
                 isolator_mass, monotone_loss, loss_grid_points):
    band = check_band(band)
    sets = as_transmissibility_sets(frfs)
    n_params = (2 * order + 1) if model == "maxwell" else 3
    parts, offsets = [], []
    for item in sets:
        if not (math.isfinite(item.mass) and item.mass > 0):
            raise FitError(f"frfs {item.name!r}: found mass {item.mass!r}, expected a positive mass in kg")
        f_in, h_in = band_points(item.freq, item.transmissibility, band, f"frfs {item.name!r}", min_points=3)
        parts.append((f_in, h_in, item.mass))
        static = item.static_stiffness
        if static is not None and not (math.isfinite(static) and static > 0):
            raise FitError(f"frfs {item.name!r}: found static_stiffness {static!r}, expected a positive N/m or None")
        # a Maxwell model about the set's preload: k0 -> the static tangent stiffness there (the
        # Voigt model's static stiffness is a parameter: it ignores the preload)
        shift = 0.0 if static is None or model != "maxwell" else float(static) - float(k0 or 0.0)
        offsets.append(np.full(f_in.size, shift))
    if sum(f.size for f, _, _ in parts) <= n_params:
        raise FitError(f"frfs: found {sum(f.size for f, _, _ in parts)} points in the band, "
                       f"expected more than the {n_params} parameters")
    if m_eff_max is None:
        m_eff_max = isolator_mass if isolator_mass is not None else 0.5 * min(item.mass for item in sets)
    if not (math.isfinite(m_eff_max) and m_eff_max > 0):
        raise FitError(f"m_eff_max: found {m_eff_max!r}, expected a positive mass in kg")
    stiffness_bounds = _check_bounds("stiffness_bounds", stiffness_bounds or (0.1 * k0, 10.0 * k0), "N/m")
    rate_bounds = _check_bounds("rate_bounds", rate_bounds, "1/s")
    if model == "maxwell":
        transforms = _maxwell_transforms(order, stiffness_bounds, rate_bounds, m_eff_max=m_eff_max)
        loss_omega = _loss_grid(band, loss_grid_points) if monotone_loss else None
    else:
        damping_bounds = _check_bounds("damping_bounds", damping_bounds or (k0 / rate_bounds[1], k0 / rate_bounds[0]),
                                       "N s/m")
        specs = _declared("voigt", 1)
        transforms = [Transform("k", specs["k"].unit, "log01", *stiffness_bounds),
                      Transform("damping", specs["damping"].unit, "log01", *damping_bounds),
                      Transform("m_eff", specs["m_eff"].unit, "linear01", 0.0, m_eff_max)]
        loss_omega, monotone_loss = None, False  # a Voigt loss factor omega d / k always increases
    omega, measured, mass, set_index, weights = _stack(parts)
    law = _MaxwellLaw(order, float(k0), with_m_eff=True) if model == "maxwell" else _VoigtLaw(with_m_eff=True)
    problem = _TransmissibilityProblem(law, omega=omega, measured=measured, mass=mass, weights=weights,
                                       set_index=set_index, set_names=[item.name for item in sets],
                                       transforms=transforms, loss_omega=loss_omega, monotone_loss=monotone_loss,
                                       static_offset=np.concatenate(offsets))
    problem.set_floors = np.array([frf_noise_floor(item, band) for item in sets])
    return problem, band


@accepts(k0=K0, order=ORDER, backend=BACKEND, global_method=GLOBAL_METHOD, loss_grid_points=LOSS_GRID_POINTS,
         monotone_loss=Choice((True, False, "auto")), k0_stderr=Real(unit="N/m", ge=0, optional=True), error=FitError)
def fit_maxwell(
    frfs,
    *,
    k0: float,
    k0_stderr: float | None = None,
    order: int = 2,
    band=(1.0, 100.0),
    backend: str = "nlopt",
    stiffness_bounds=None,
    rate_bounds=(1.0, 1e4),
    m_eff_max: float | None = None,
    isolator_mass: float | None = None,
    monotone_loss: bool | str = "auto",
    loss_grid_points: int = 25,
    start: GeneralizedMaxwell | None = None,
    max_evals: int = 500,
    ftol: float = 1e-12,
    cross_check: bool = False,
    global_method: str | None = None,
    global_max_evals: int = 10000,
    seed: int = 0,
) -> MaxwellFitResult:
    """Fit ``[k_1..k_n, rate_1..rate_n, m_eff]`` of a generalized Maxwell model to transmissibilities.

    Parameters
    ----------
    frfs : sequence
        :class:`TransmissibilitySet` items or ``(mass kg, freq Hz, complex H)``
        triples: every top mass and repetition, fitted at once.
    k0 : float
        Static stiffness in N/m, fixed (from :func:`estimate_k0`).
    k0_stderr : float, optional
        Standard uncertainty of ``k0`` in N/m from its own estimate (e.g.
        :attr:`~idkit.observe.k0.K0FromLoops.stderr`); reported as the stderr of
        the fixed ``k0`` parameter, which the fit does not move.
    order : int, default 2
        Number of Maxwell elements, >= 1.
    band : (float, float), default (1, 100)
        Frequency band in Hz (the elastomer's internal mode near 200 Hz is excluded).
    backend : {"nlopt", "scipy"}
        nlopt ``LD_SLSQP`` or scipy ``SLSQP``.
    stiffness_bounds : (float, float), optional
        Bounds of ``k_i`` in N/m; default ``(0.1 k0, 10 k0)``.
    rate_bounds : (float, float), default (1, 1e4)
        Bounds of the relaxation rates in 1/s.
    m_eff_max : float, optional
        Upper bound of ``m_eff`` in kg; default ``isolator_mass`` if given, else
        half the smallest top mass.
    isolator_mass : float, optional
        Mass of the isolator in kg.
    monotone_loss : bool or "auto", default "auto"
        Constrain the loss factor to be non-decreasing over the band (SPEC 4). ``"auto"``
        fits with and without the constraint and keeps it unless the free fit's error is
        below the constrained one by more than :data:`LOSS_RULE_FACTOR` (the data then
        contradict it: a loss factor that falls with frequency, as a relaxation spectrum
        spread over decades gives); ``settings.loss_rule`` says which and why.
    loss_grid_points : int, default 25
        Frequencies (log-spaced over the band) of that constraint.
    start : GeneralizedMaxwell, optional
        Starting model; default: the best feasible point of a seeded Sobol sample
        (see :func:`_default_start`).
    max_evals : int, default 500
    ftol : float, default 1e-12
        Relative tolerance on the (start-normalised) objective.
    cross_check : bool, default False
        Run the seeded global search (module docstring) and report the gap.
    global_method : {"isres", "differential_evolution"}, optional
        Default follows ``backend``.
    global_max_evals : int, default 10000
        Evaluation limit of the global search.
    seed : int, default 0
        Seeds the Sobol start sample and the global search.

    Returns
    -------
    MaxwellFitResult
        ``parameters`` (alias ``params``) carry stderr and correlations from the
        covariance ``redchi (J^T J)^-1`` of the weighted relative residuals (real and
        imaginary parts stacked, ``chisqr = error**2``) with the analytic Jacobian at the
        optimum (:func:`idkit.fit._params.jacobian_statistics`); parameters at a bound
        get none, named in ``stderr_notes``. ``chisqr``, ``redchi``, ``aic``, ``bic``,
        ``fit_report()`` as in lmfit.

    Raises
    ------
    FitError
        Order < 1, NaN or zero transmissibility in the band, too few points, bad bounds.
    """

    def problem_for(constrained: bool):
        return _frf_problem(frfs, model="maxwell", order=order, k0=k0, band=band, stiffness_bounds=stiffness_bounds,
                            rate_bounds=rate_bounds, damping_bounds=None, m_eff_max=m_eff_max,
                            isolator_mass=isolator_mass, monotone_loss=constrained, loss_grid_points=loss_grid_points)

    common = dict(backend=backend, max_evals=max_evals, ftol=ftol, global_method=global_method,
                  global_max_evals=global_max_evals, seed=seed, k0_stderr=k0_stderr)
    if monotone_loss != "auto":
        problem, band = problem_for(bool(monotone_loss))
        return _solve(problem, start=start, band=band, cross_check=cross_check,
                      settings_extra={"loss_rule": f"monotone_loss={bool(monotone_loss)} (given)"}, **common)
    problem, band = problem_for(True)
    constrained = _solve(problem, start=start, band=band, cross_check=False, settings_extra={}, **common)
    free_problem, _ = problem_for(False)
    free = _solve(free_problem, start=start, band=band, cross_check=False, settings_extra={}, **common)
    # each optimum starts the other problem too: the constrained one is feasible in the free
    # problem, and the free one starts the constrained SQP (which restores feasibility), so the
    # rule compares the best of both starts and a constrained SQP stuck at a bad start cannot
    # drop the constraint
    if constrained.error < free.error:
        free = _better(free, _polish(free_problem, constrained.model, band, common))
    if earns_its_place(free.error, constrained.error):
        constrained = _better(constrained, _polish(problem, free.model, band, common))
    better = earns_its_place(free.error, constrained.error)
    # near the noise floor the errors differ by less than the factor while the constraint still
    # moves the parameters by many standard errors (the data reject it): dropped then too, when
    # the free fit is a success
    step = constraint_step(constrained.statistics)
    rejected = step is not None and step[1] > CONSTRAINT_STEP_LIMIT and free.success
    drop = better or rejected
    rule = (f"auto: error {100 * constrained.error:.3g} % with a non-decreasing loss factor, "
            f"{100 * free.error:.3g} % without; " +
            (f"dropped (the free fit is better by more than a factor {LOSS_RULE_FACTOR:g}: the data do not "
             "support a loss factor that never falls with frequency)" if better else
             f"dropped (the data reject it: with it the least-squares optimum lies {step[1]:.3g} standard errors "
             f"away, {step[0]}, limit {CONSTRAINT_STEP_LIMIT:g})" if rejected else
             f"kept (the free fit is not better by more than a factor {LOSS_RULE_FACTOR:g})"))
    chosen_problem, chosen = (free_problem, free) if drop else (problem, constrained)
    if not cross_check:
        return dataclasses.replace(chosen, settings=dataclasses.replace(chosen.settings, loss_rule=rule))
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):  # SLSQP restarted on its optimum
        return _solve(chosen_problem, start=chosen.model, band=band, cross_check=True,
                      settings_extra={"loss_rule": rule}, **common)


def _polish(problem, start, band, common):
    """The SQP of ``problem`` from another problem's optimum, or None when it breaks down
    (an SQP started on an exact zero of the objective can step to NaN)."""
    try:
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            result = _solve(problem, start=start, band=band, cross_check=False, settings_extra={}, **common)
    except (FitError, RuntimeError, ValueError):
        return None
    return result if math.isfinite(result.error) else None


def _better(result, other):
    """``other`` when it found a feasible point with a lower error, else ``result``."""
    if other is None or other.status == INFEASIBLE or other.error >= result.error:
        return result
    return other


@accepts(k0=K0, backend=BACKEND, global_method=GLOBAL_METHOD, error=FitError)
def fit_voigt(
    frfs,
    *,
    k0: float,
    band=(1.0, 100.0),
    backend: str = "nlopt",
    stiffness_bounds=None,
    damping_bounds=None,
    rate_bounds=(1.0, 1e4),
    m_eff_max: float | None = None,
    isolator_mass: float | None = None,
    max_evals: int = 500,
    ftol: float = 1e-12,
    cross_check: bool = False,
    global_method: str | None = None,
    global_max_evals: int = 10000,
    seed: int = 0,
) -> MaxwellFitResult:
    """Fit the viscous (Voigt) model ``k + d s`` and ``m_eff`` to transmissibilities.

    ``k`` is free within ``stiffness_bounds`` (default 0.1 k0 .. 10 k0; a spring
    pinned at k0 would make the comparison unfair), ``damping`` within
    ``damping_bounds`` (default ``k0 / rate_bounds[1] .. k0 / rate_bounds[0]`` N s/m),
    both log-scaled; other arguments as :func:`fit_maxwell`.
    """
    problem, band = _frf_problem(frfs, model="voigt", order=1, k0=k0, band=band,
                                 stiffness_bounds=stiffness_bounds, rate_bounds=rate_bounds,
                                 damping_bounds=damping_bounds, m_eff_max=m_eff_max, isolator_mass=isolator_mass,
                                 monotone_loss=False, loss_grid_points=2)
    return _solve(problem, start=None, band=band, backend=backend, max_evals=max_evals, ftol=ftol,
                  cross_check=cross_check, global_method=global_method, global_max_evals=global_max_evals,
                  seed=seed, settings_extra={})
