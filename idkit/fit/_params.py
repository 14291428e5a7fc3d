"""Parameter transforms shared by the fitters and the lmfit reporting layer.

Optimisers work on an *internal* vector ``u``; models take *physical* values in SI
units. One :class:`Transform` per free parameter maps between the two:

``"log"``
    ``value = exp(u)``. Unbounded in ``u``, strictly positive in value: this is how
    the Iwan fit keeps every stiffness and slip force positive under the
    (unconstrained) Nelder-Mead simplex, which the thesis could not (SPEC 4).
    A step of ``du`` is a relative change of about ``du`` in the value.
``"scaled"``
    ``value = scale * u``. For signed coefficients (Iwan ``g2``, ``g3``) so that a
    unit step in ``u`` is a physically comparable change.
``"log01"``
    ``value = lower * (upper / lower) ** u`` with ``u`` in [0, 1]: the logarithmic
    scaling between bounds of the Maxwell fit (SPEC 4). Needs ``0 < lower < upper``.
``"linear01"``
    ``value = lower + (upper - lower) * u`` with ``u`` in [0, 1], for parameters
    whose lower bound is 0 (Maxwell ``m_eff``), where a logarithm is undefined.

The same declarations produce :class:`lmfit.Parameters` (values, physical bounds,
``vary``, standard errors) through :func:`to_lmfit`.

Standard errors come from the residual Jacobian at the optimum, without moving it
(:func:`jacobian_statistics`): the fitters' optimum is that of a Nelder-Mead objective
(or SQP with constraints), and a least-squares polish would report the uncertainty of a
different point. The result is an :class:`lmfit.minimizer.MinimizerResult` with what an
lmfit user expects (``params`` with ``stderr`` and ``correl``, ``covar``, ``chisqr``,
``redchi``, ``aic``, ``bic``, ``nfev``; :func:`lmfit.fit_report` prints it), computed
with lmfit's definitions (``scale_covar=True``: ``covar = redchi (J^T J)^-1``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import lmfit
import numpy as np

__all__ = ["Transform", "spec_units", "to_lmfit", "gauss_newton_covariance", "central_jacobian",
           "jacobian_statistics", "to_physical_statistics"]

_KINDS = ("log", "scaled", "log01", "linear01")


@dataclass(frozen=True)
class Transform:
    """Mapping of one free parameter between internal and physical coordinates.

    Parameters
    ----------
    name : str
        Parameter name as in the model's :meth:`param_specs` (e.g. ``"k_1"``).
    unit : str
        SI unit of the physical value.
    kind : {"log", "scaled", "log01", "linear01"}
        See the module docstring.
    lower, upper : float
        Physical bounds (used by ``*01`` kinds and reported to lmfit).
    scale : float
        Scale of the ``"scaled"`` kind (physical value of ``u = 1``).
    """

    name: str
    unit: str
    kind: str
    lower: float = -math.inf
    upper: float = math.inf
    scale: float = 1.0

    def __post_init__(self) -> None:
        if self.kind not in _KINDS:
            raise ValueError(f"Transform {self.name!r}: kind={self.kind!r}, expected one of {_KINDS}")
        if self.kind == "log01" and not (0.0 < self.lower < self.upper < math.inf):
            raise ValueError(
                f"Transform {self.name!r}: log scaling needs 0 < lower < upper < inf, "
                f"found lower={self.lower!r}, upper={self.upper!r}"
            )
        if self.kind == "linear01" and not (self.lower < self.upper < math.inf):
            raise ValueError(
                f"Transform {self.name!r}: found lower={self.lower!r}, upper={self.upper!r}, "
                "expected finite lower < upper"
            )

    def to_physical(self, u):
        """Physical value(s) of internal coordinate(s) ``u``."""
        u = np.asarray(u, dtype=float)
        if self.kind == "log":
            return np.exp(u)
        if self.kind == "scaled":
            return self.scale * u
        if self.kind == "log01":
            return self.lower * (self.upper / self.lower) ** u
        return self.lower + (self.upper - self.lower) * u

    def to_internal(self, value):
        """Internal coordinate(s) of physical value(s)."""
        value = np.asarray(value, dtype=float)
        if self.kind == "log":
            return np.log(value)
        if self.kind == "scaled":
            return value / self.scale
        if self.kind == "log01":
            return np.log(value / self.lower) / math.log(self.upper / self.lower)
        return (value - self.lower) / (self.upper - self.lower)

    def derivative(self, u):
        """``d value / d u`` at internal coordinate(s) ``u`` (chain rule of gradients)."""
        u = np.asarray(u, dtype=float)
        if self.kind == "log":
            return np.exp(u)
        if self.kind == "scaled":
            return np.full_like(u, self.scale)
        if self.kind == "log01":
            return self.to_physical(u) * math.log(self.upper / self.lower)
        return np.full_like(u, self.upper - self.lower)


def central_jacobian(residuals: Callable[[np.ndarray], np.ndarray], u: np.ndarray, step: float = 1e-4) -> np.ndarray:
    """Jacobian ``d residuals / d u`` by central differences with a fixed step in ``u``.

    With log-transformed coordinates a fixed step is a relative step of the
    physical value (``1e-4`` = 0.01 %).
    """
    u = np.asarray(u, dtype=float)
    columns = []
    for index in range(u.size):
        delta = np.zeros_like(u)
        delta[index] = step
        columns.append((residuals(u + delta) - residuals(u - delta)) / (2.0 * step))
    return np.column_stack(columns)


def gauss_newton_covariance(jacobian: np.ndarray, residual: np.ndarray, *, rcond: float = 1e-10):
    """Covariance ``s^2 (J^T J)^-1`` with ``s^2 = |r|^2 / (N - p)``, or ``None`` if singular.

    The classical least-squares estimate (what lmfit reports as ``stderr``),
    valid near a minimum of ``|r|^2`` for independent residuals of equal variance.
    Returns ``None`` when ``J^T J`` is numerically singular (a parameter the data
    do not determine) or when there are not more residuals than parameters.
    """
    jacobian = np.atleast_2d(np.asarray(jacobian, dtype=float))
    n_res, n_par = jacobian.shape
    if n_par == 0 or n_res <= n_par or not np.all(np.isfinite(jacobian)):
        return None
    normal = jacobian.T @ jacobian
    singular = np.linalg.svd(normal, compute_uv=False)
    if singular[-1] <= rcond * singular[0]:
        return None
    variance = float(np.sum(np.asarray(residual, dtype=float) ** 2)) / (n_res - n_par)
    return variance * np.linalg.inv(normal)


def spec_units(model) -> dict[str, str]:
    """Parameter name -> SI unit, as the model declares them (:meth:`param_specs`).

    The fitters read units (and physical bounds) from here, never from a table of their own.

    Parameters
    ----------
    model : IsolatorModel
        An instance (the parameter names of Iwan and Maxwell models depend on the order).

    Returns
    -------
    dict of str to str

    Examples
    --------
    >>> from idkit.models import IwanModel
    >>> spec_units(IwanModel(g1=1e3, k=[1e3], fc=[1.0]))["fc_1"]
    'N'
    """
    return {spec.name: spec.unit for spec in model.param_specs()}


def to_lmfit(
    names: Sequence[str],
    values: Sequence[float],
    *,
    units: Sequence[str],
    lower: Sequence[float],
    upper: Sequence[float],
    vary: Sequence[bool],
    stderr: Sequence[float | None] | None = None,
) -> lmfit.Parameters:
    """Build :class:`lmfit.Parameters` from parallel sequences.

    The unit of each parameter is stored in ``Parameter.user_data`` (lmfit has no
    unit field). ``stderr`` entries that are ``None`` stay unset (lmfit's "not
    estimated"). Fixed parameters get ``vary=False``.
    """
    parameters = lmfit.Parameters()
    errors = [None] * len(names) if stderr is None else list(stderr)
    for name, value, unit, low, high, free, error in zip(names, values, units, lower, upper, vary, errors):
        # lmfit clips a value outside [min, max]; widen rather than let it move the value.
        low = min(float(low), float(value))
        high = max(float(high), float(value))
        parameters.add(name, value=float(value), min=low, max=high, vary=bool(free))
        parameters[name].user_data = {"unit": unit}
        if error is not None and math.isfinite(error):
            parameters[name].stderr = float(error)
    return parameters


#: A Jacobian column whose norm is below this share of the largest column's is a
#: parameter the residuals do not change with (e.g. the slip force of an element that
#: never slips): it gets no standard error, and the others are estimated without it.
_NULL_COLUMN = 1e-8


def _interpolated_meat(block: np.ndarray, residual: np.ndarray, sources: np.ndarray) -> np.ndarray:
    """``sigma^2 (W^T J)^T (W^T J)`` of one group whose residuals interpolate measured samples.

    ``sources[i] = j + a`` (``0 <= a < 1``): residual ``i`` is ``(1 - a)`` sample ``j`` plus
    ``a`` sample ``j + 1`` (:func:`jacobian_statistics`, ``point_sources``).
    """
    lower = np.floor(sources).astype(np.int64)
    fraction = sources - lower
    base = int(lower.min())
    mixed = np.zeros((int(lower.max()) - base + 2, block.shape[1]))
    np.add.at(mixed, lower - base, (1.0 - fraction)[:, None] * block)
    np.add.at(mixed, lower - base + 1, fraction[:, None] * block)
    weight = float(np.sum((1.0 - fraction) ** 2 + fraction**2))
    return float(np.sum(residual**2)) / weight * (mixed.T @ mixed)


def jacobian_statistics(
    residuals: Callable[[np.ndarray], np.ndarray],
    u: np.ndarray,
    names: Sequence[str],
    *,
    step: float = 1e-4,
    rcond: float = 1e-10,
    method: str = "Jacobian at the optimum",
    jacobian: Callable[[np.ndarray], np.ndarray] | None = None,
    group_sizes: Sequence[int] | None = None,
    step_nuisance: np.ndarray | None = None,
    point_sources: np.ndarray | None = None,
) -> lmfit.minimizer.MinimizerResult:
    """Least-squares statistics of ``residuals`` at ``u`` without moving ``u``.

    Parameters
    ----------
    residuals : callable
        ``residuals(u) -> ndarray`` of the per-point residuals (dimensionless).
    u : ndarray, shape (p,)
        The optimum, in the coordinates the covariance is wanted in.
    names : sequence of str
        One name per coordinate.
    step : float
        Central-difference step of the Jacobian in ``u`` (:func:`central_jacobian`).
    rcond : float
        Smallest singular value of ``J^T J`` relative to its largest below which the
        covariance is singular (:func:`gauss_newton_covariance`).
    method : str
        Recorded as ``result.method`` (first line of :func:`lmfit.fit_report`).
    jacobian : callable, optional
        ``jacobian(u) -> ndarray`` of shape ``(N, p)``: the analytic ``d residuals / d u``
        (lmfit's ``Dfun``), used instead of central differences (``step`` is then unused).
    group_sizes : sequence of int, optional
        The residuals come in consecutive groups of these sizes (one per loop set) whose noise
        variances may differ: the covariance is then the sandwich
        ``(J^T J)^-1 (sum_g s_g^2 J_g^T J_g) (J^T J)^-1 N / (N - p)`` with ``s_g^2`` the mean
        squared residual of group ``g`` (it is ``redchi (J^T J)^-1`` when every group has the
        same variance). Loops measured with one load cell carry the same force noise in N, so
        their relative residuals differ by the ratio of the loops' forces: with one pooled
        variance the standard errors of the parameters the small loops fix came out 1.6-1.9
        times too small (docs/fitting.md, "Iwan uncertainty").
    point_sources : ndarray, shape (N,), optional
        With ``group_sizes``: the (fractional) index of the measured sample each residual was
        interpolated at, within its group (a loop set resampled from its record: the point at
        ``i + a`` is ``(1 - a)`` sample ``i`` plus ``a`` sample ``i + 1``; NaN for a residual
        that is its own measurement). Neighbouring points that share a sample share its noise,
        and an interpolated point carries ``(1 - a)^2 + a^2`` of a sample's noise variance: the
        meat is then ``sigma_g^2 (W_g^T J_g)^T (W_g^T J_g)``, ``W_g`` the interpolation weights
        and ``sigma_g^2 = sum r_g^2 / sum W_g^2`` the noise variance per measured sample (white
        noise on the samples). Integral indices, each once, give the plain sandwich. A 0.05 mm
        branch of 20 samples resampled to 41 points counted 41 independent residuals.
    step_nuisance : ndarray, shape (N, q), optional
        Residual derivatives of ``q`` nuisance quantities the fit holds at zero (e.g. one
        force offset per loop set): ``gauss_newton_step`` is then the step to the least-squares
        optimum with these free too (reported for ``names`` only); the covariance is unchanged.

    Returns
    -------
    lmfit.minimizer.MinimizerResult
        ``params`` (unbounded, values ``u``, ``stderr`` and ``correl`` where estimated),
        ``covar`` (``redchi (J^T J)^-1`` over ``var_names``, or None), ``residual``,
        ``chisqr``, ``redchi``, ``aic``, ``bic``, ``ndata``, ``nvarys``, ``nfree``,
        ``nfev`` (the ``1 + 2p`` residual evaluations, or 1 with an analytic ``jacobian``),
        ``errorbars``, plus

        ``stderr_notes`` : list of str
            Why a standard error is missing: the parameter the residuals do not change
            with, or the combination that makes ``J^T J`` singular.
        ``gauss_newton_step`` : dict
            Name -> one Gauss-Newton step ``-(J^T J)^-1 J^T r`` in units of that
            parameter's standard error (with ``step_nuisance``: ``step_nuisance_count``
            nuisance quantities free too): how far the least-squares optimum of the same
            residuals lies from ``u`` (a polish that moves a parameter by more than one
            stderr shows that the fitted point is not that optimum).

    Notes
    -----
    ``chisqr = sum r^2``, ``redchi = chisqr / (N - p)``, ``aic = N ln(chisqr / N) + 2 p``,
    ``bic = N ln(chisqr / N) + ln(N) p``: lmfit's definitions (``MinimizerResult``).

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(0.0, 1.0, 50)
    >>> y = 2.0 + 3.0 * x + 0.01 * np.sin(40 * x)
    >>> best = np.polyfit(x, y, 1)[::-1]
    >>> stats = jacobian_statistics(lambda u: u[0] + u[1] * x - y, best, ["a", "b"])
    >>> bool(stats.params["b"].stderr < 0.01), stats.nvarys
    (True, 2)
    """
    u = np.asarray(u, dtype=float)
    names = list(names)
    if u.shape != (len(names),):
        raise ValueError(f"u: found shape {u.shape}, expected ({len(names)},), one value per name in {names}")
    parameters = lmfit.Parameters()
    for name, value in zip(names, u):
        parameters.add(name, value=float(value))
    residual = np.asarray(residuals(u), dtype=float)
    analytic = jacobian is not None
    if not analytic:
        matrix = central_jacobian(residuals, u, step=step)
        unchanged = f"a step of {step:g} in its internal coordinate changes no residual"
    else:
        matrix = np.atleast_2d(np.asarray(jacobian(u), dtype=float))
        if matrix.shape != (residual.size, len(names)):
            raise ValueError(f"jacobian: found shape {matrix.shape}, expected ({residual.size}, {len(names)}), "
                             "one row per residual and one column per name")
        unchanged = "its column of the analytic Jacobian is zero"
    jacobian = matrix
    n_data, n_vary = residual.size, len(names)
    chisqr = max(float(np.sum(residual**2)), 1e-250 * n_data)
    nfree = n_data - n_vary
    neg2_log_likelihood = n_data * math.log(chisqr / n_data)
    notes = []
    column_norm = np.linalg.norm(jacobian, axis=0) if np.all(np.isfinite(jacobian)) else np.zeros(n_vary)
    seen = column_norm > _NULL_COLUMN * max(float(column_norm.max(initial=0.0)), 1e-300)
    for name in np.asarray(names)[~seen]:
        notes.append(f"{name}: the residuals do not change with it ({unchanged}): the data do not determine it")
    covar_seen = gauss_newton_covariance(jacobian[:, seen], residual, rcond=rcond) if seen.any() else None
    step_in_stderr = {}
    if covar_seen is None and seen.any():
        if nfree <= 0:
            notes.append(f"every parameter: {n_data} residuals for {n_vary} parameters, expected more residuals")
        elif not np.all(np.isfinite(jacobian)):
            notes.append("every parameter: the residual Jacobian is not finite at the optimum")
        else:
            _, singular, right = np.linalg.svd(jacobian[:, seen], full_matrices=False)
            null = right[-1]
            involved = [f"{name} ({weight:+.2f})" for name, weight in
                        zip(np.asarray(names)[seen], null) if abs(weight) > 0.1]
            condition = (singular[0] / singular[-1]) ** 2 if singular[-1] > 0 else math.inf
            notes.append(f"every parameter: J^T J is singular (condition {condition:.3g}); "
                         f"the data do not determine the combination of {', '.join(involved)} "
                         "(weights of the direction the residuals do not change along)")
    if covar_seen is not None and group_sizes is not None:
        sizes = np.asarray(group_sizes, dtype=int)
        if sizes.sum() != n_data or np.any(sizes < 1):
            raise ValueError(f"group_sizes: found sizes summing to {int(sizes.sum())}, expected positive sizes "
                             f"summing to the {n_data} residuals")
        columns = jacobian[:, seen]
        bread = np.linalg.inv(columns.T @ columns)
        meat = np.zeros_like(bread)
        sources = None
        if point_sources is not None:
            sources = np.asarray(point_sources, dtype=float)
            if sources.shape != (n_data,):
                raise ValueError(f"point_sources: found shape {sources.shape}, expected ({n_data},), one per residual")
        for rows in np.split(np.arange(n_data), np.cumsum(sizes)[:-1]):
            block = columns[rows]
            if sources is None or not np.all(np.isfinite(sources[rows])):
                meat += float(np.mean(residual[rows] ** 2)) * (block.T @ block)
                continue
            meat += _interpolated_meat(block, residual[rows], sources[rows])
        covar_seen = bread @ meat @ bread * (n_data / max(1, nfree))
    covar = None
    if covar_seen is not None:
        index = np.flatnonzero(seen)
        covar = np.full((n_vary, n_vary), np.nan)
        covar[np.ix_(index, index)] = covar_seen
        sigma = np.sqrt(np.clip(np.diag(covar_seen), 0.0, None))
        correlation = covar_seen / np.outer(sigma, sigma)
        design = jacobian[:, seen]
        if step_nuisance is not None:
            extra = np.asarray(step_nuisance, dtype=float).reshape(n_data, -1)
            design = np.hstack([design, extra])
        gn_step = -np.linalg.lstsq(design, residual, rcond=None)[0][: index.size]
        for position, i in enumerate(index):
            parameters[names[i]].stderr = float(sigma[position])
            parameters[names[i]].correl = {names[j]: float(correlation[position, other])
                                           for other, j in enumerate(index) if j != i}
            step_in_stderr[names[i]] = float(gn_step[position] / sigma[position])
    result = lmfit.minimizer.MinimizerResult(
        method=method, params=parameters, var_names=names, init_vals=[float(v) for v in u],
        init_values={n: float(v) for n, v in zip(names, u)}, residual=residual, covar=covar,
        nfev=1 if analytic else 1 + 2 * n_vary, ndata=n_data, nvarys=n_vary, nfree=nfree, chisqr=chisqr,
        redchi=chisqr / max(1, nfree), aic=neg2_log_likelihood + 2 * n_vary,
        bic=neg2_log_likelihood + math.log(n_data) * n_vary, errorbars=covar_seen is not None and not notes,
        success=True, aborted=False, message="statistics at the given optimum (not moved)",
        stderr_notes=notes, gauss_newton_step=step_in_stderr,
        step_nuisance_count=0 if step_nuisance is None else int(np.asarray(step_nuisance).reshape(n_data, -1).shape[1]))
    return result


def to_physical_statistics(
    internal: lmfit.minimizer.MinimizerResult,
    transforms: Sequence[Transform],
    parameters: lmfit.Parameters,
) -> lmfit.minimizer.MinimizerResult:
    """The statistics of :func:`jacobian_statistics` in physical parameters.

    ``stderr(p) = |dp/du| stderr(u)`` (first order; for ``"log"`` the relative error of
    ``p`` is the stderr of ``log p``), ``covar = D covar_u D`` with ``D = diag(dp/du)``;
    correlations are unchanged (every transform is increasing). ``parameters`` (physical
    values, bounds, units, fixed parameters) receive the standard errors and
    correlations and become ``result.params``; the other statistics are copied.
    """
    names = list(internal.var_names)
    if [t.name for t in transforms] != names:
        raise ValueError(f"transforms: found {[t.name for t in transforms]}, expected the statistics' {names}")
    u = np.array([internal.params[name].value for name in names])
    derivative = np.array([float(abs(t.derivative(value))) for t, value in zip(transforms, u)])
    for name, scale in zip(names, derivative):
        source, target = internal.params[name], parameters[name]
        target.stderr = None if source.stderr is None else float(scale * source.stderr)
        target.correl = None if source.correl is None else dict(source.correl)
    values = {key: getattr(internal, key) for key in vars(internal)}
    values.update(params=parameters, var_names=names,
                  init_vals=[float(parameters[name].value) for name in names],
                  init_values={name: float(parameters[name].value) for name in names},
                  covar=None if internal.covar is None else internal.covar * np.outer(derivative, derivative))
    return lmfit.minimizer.MinimizerResult(**values)
