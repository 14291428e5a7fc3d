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
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import lmfit
import numpy as np

__all__ = ["Transform", "to_lmfit", "gauss_newton_covariance", "central_jacobian"]

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
