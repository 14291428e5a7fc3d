"""Modified Bouc-Wen model of a wire-rope isolator (SPEC 1.3, thesis eqs. 3.3-3.6).

``F = b^(c x) (k1 x + k2 sgn(x) x^2 + k3 x^3 + z) + c_visc xdot`` with the
hysteretic force ``z`` (N) obeying
``dz/dx = alpha - (gamma + beta sgn(xdot z)) |z|^n`` (rate independent).
"""

from __future__ import annotations

import math

import numpy as np

from idkit.checks import accepts
from idkit.errors import ParameterError, SimulationError
from idkit.models.laws import boucwen_z_history, kernel_array
from idkit.models.base import C_VISC_SPEC, IsolatorArrays, IsolatorModel
from idkit.models.base import DEFLECTION, FREQUENCY, TIME, _as_time, _velocity
from idkit.params import ParamSpec

__all__ = ["BoucWenModel", "check_boucwen_shape"]

#: Runge-Kutta sub-steps per deflection sample when integrating z; 4 keeps the
#: error of z below ~1e-6 relative for steps up to 1/10 of the yield deflection.
BOUCWEN_SUBSTEPS = 4


def check_boucwen_shape(beta: float, gamma: float, n: float, *, model: str = "BoucWenModel") -> None:
    """Raise unless ``(beta, gamma, n)`` is in the admissible Bouc-Wen space.

    The conditions and their reasons are in the Notes of :class:`BoucWenModel`:
    ``beta + gamma > 0``; or ``beta + gamma <= 0`` and ``beta > 0`` (for
    ``n > 1`` and ``beta + gamma < 0`` within :attr:`BoucWenModel.escape_deflection`).

    Parameters
    ----------
    beta, gamma : float
        Loop shape coefficients in N^(1-n)/m.
    n : float
        Smoothness exponent (dimensionless).
    model : str
        Name used in the error message.

    Raises
    ------
    ParameterError
        Naming the violated condition and the values found.

    Examples
    --------
    >>> check_boucwen_shape(800.0, -1100.0, 1.0)          # the benchmark's hardening law
    >>> check_boucwen_shape(-100.0, -200.0, 1.0)
    Traceback (most recent call last):
    ...
    idkit.errors.ParameterError: BoucWenModel: found beta + gamma = -300 <= 0 with beta = -100; expected beta + gamma > 0 (saturating z), or beta > 0 (unloading steeper than loading) when beta + gamma <= 0, otherwise the loops ratchet without bound
    """
    total = beta + gamma
    if total > 0.0:
        return
    if beta <= 0.0:
        raise ParameterError(
            f"{model}: found beta + gamma = {total:g} <= 0 with beta = {beta:g}; expected beta + gamma > 0 "
            "(saturating z), or beta > 0 (unloading steeper than loading) when beta + gamma <= 0, "
            "otherwise the loops ratchet without bound"
        )


class BoucWenModel(IsolatorModel):
    """Modified (asymmetric, soft-hardening) Bouc-Wen model.

    Parameters
    ----------
    k1 : float
        Linear stiffness in N/m (>= 0).
    k2 : float
        ``sgn(x) x^2`` coefficient in N/m^2.
    k3 : float
        Cubic coefficient in N/m^3.
    alpha : float
        Initial slope of ``z`` versus deflection in N/m (> 0).
    beta, gamma : float
        Loop shape coefficients in N^(1-n)/m; admissible pairs below.
    n : float
        Smoothness exponent (dimensionless, 0.2-10).
    b : float
        Base of the asymmetry factor ``b^(c x)`` (dimensionless, > 0). Default 1.
    c : float
        Exponent coefficient of the asymmetry factor in 1/m. Default 0.
    c_visc : float
        Parallel viscous damping in N s/m. Default 0.

    Notes
    -----
    **Admissible parameter space.** With ``s = sgn(xdot z)`` the loading
    (``s = +1``) slope is ``dz/dx = alpha - (beta + gamma) |z|^n`` and the
    unloading (``s = -1``) slope ``alpha - (gamma - beta) |z|^n``. With
    ``alpha > 0`` and ``0.2 <= n <= 10`` the constructor accepts:

    * ``beta + gamma > 0`` (softening, saturating; Ikhouane, Manosa & Rodellar
      2007, classes I and II): on loading ``|z|`` tends to
      ``z_max = (alpha / (beta + gamma))^(1/n)``, so ``z`` stays bounded for any
      deflection history starting from ``|z0| <= z_max`` (class I:
      ``beta - gamma >= 0``; class II: ``beta - gamma < 0``, whose unloading
      slope is steeper than ``alpha`` until ``|z| = (alpha / (gamma - beta))^(1/n)``).
    * ``beta + gamma = 0`` with ``beta > 0``: linear loading (``dz/dx = alpha``),
      steeper unloading.
    * ``beta + gamma < 0`` (hardening: the loading slope grows with ``|z|``, as
      in the Noel & Schoukens benchmark, ``beta + gamma = -300`` 1/m) with
      **beta > 0**: unloading steeper than loading. The loop amplitude ``Z``
      of repeated cycles between fixed deflection limits maps to ``Z'`` with
      ``dZ'/dZ = -(alpha + |beta + gamma| Z^n) / (alpha + (beta - gamma) Z^n)``
      at a closed loop, so the cycles converge to a closed loop iff
      ``beta - gamma > -(beta + gamma)``, i.e. ``beta > 0``; otherwise they
      ratchet without bound (Ikhouane, Manosa & Rodellar 2007 call such
      classes not BIBO stable). For ``n <= 1`` the hardening ``z`` is bounded
      on every bounded deflection history. For ``n > 1`` the loading law
      ``dz/dx = alpha + |beta + gamma| |z|^n`` reaches infinity after a finite
      monotone excursion, :attr:`escape_deflection`
      ``= (alpha / |beta + gamma|)^(1/n) / alpha * (pi / n) / sin(pi / n)`` from
      ``z = 0``: the model holds only for histories whose monotone excursions
      stay well below it, and a simulation that reaches it fails with a reason.
      (Near ``n = 1`` it is very large: 0.3 m for the benchmark with ``n = 1.01``;
      accepting ``n > 1`` lets a fit cross ``n = 1``.)

    Anything else raises :class:`~idkit.errors.ParameterError` naming the
    condition.

    Examples
    --------
    >>> hardening = BoucWenModel(k1=5e4, k2=0.0, k3=0.0, alpha=5e4, beta=800.0, gamma=-1100.0, n=1.0)
    >>> model = BoucWenModel(k1=1e3, k2=0.0, k3=0.0, alpha=5e3, beta=2e3, gamma=1e3, n=1.0)
    >>> x = 1e-3 * np.sin(np.linspace(0, 4 * np.pi, 401))
    >>> force = model.force(x)
    """

    kind = "bouc_wen"
    #: values :meth:`from_params` takes for the parameters a mapping leaves out
    _DEFAULTS = {"b": 1.0, "c": 0.0, "c_visc": 0.0}
    _SPECS = (
        ParamSpec("k1", "N/m", 0.0, math.inf, "linear stiffness"),
        ParamSpec("k2", "N/m^2", -math.inf, math.inf, "sgn(x) x^2 coefficient"),
        ParamSpec("k3", "N/m^3", -math.inf, math.inf, "cubic coefficient"),
        ParamSpec("alpha", "N/m", 0.0, math.inf, "initial slope of the hysteretic force", True),
        ParamSpec("beta", "N^(1-n)/m", -math.inf, math.inf, "loop shape coefficient"),
        ParamSpec("gamma", "N^(1-n)/m", -math.inf, math.inf, "loop shape coefficient"),
        ParamSpec("n", "-", 0.2, 10.0, "smoothness exponent"),
        ParamSpec("b", "-", 0.0, math.inf, "base of the asymmetry factor b^(c x)", True),
        ParamSpec("c", "1/m", -math.inf, math.inf, "exponent coefficient of the asymmetry factor"),
        C_VISC_SPEC,
    )

    def __init__(self, *, k1, k2, k3, alpha, beta, gamma, n, b=1.0, c=0.0, c_visc=0.0):
        name = type(self).__name__
        values = (k1, k2, k3, alpha, beta, gamma, n, b, c, c_visc)
        self._values = tuple(spec.check(value, model=name) for spec, value in zip(self._SPECS, values))
        check_boucwen_shape(self._values[4], self._values[5], self._values[6], model=name)

    def __getattr__(self, item):
        names = [spec.name for spec in type(self)._SPECS]
        if item in names:
            return self._values[names.index(item)]
        raise AttributeError(item)

    @property
    def escape_deflection(self) -> float:
        """Monotone deflection in m after which a hardening ``z`` (from 0) is infinite.

        ``inf`` unless ``beta + gamma < 0`` and ``n > 1`` (class Notes).

        Examples
        --------
        >>> model = BoucWenModel(k1=5e4, k2=0.0, k3=0.0, alpha=5e4, beta=800.0, gamma=-1100.0, n=1.01)
        >>> round(model.escape_deflection, 2)
        0.32
        """
        hardening = -(self.beta + self.gamma)
        if hardening <= 0.0 or self.n <= 1.0:
            return math.inf
        n = self.n
        return (self.alpha / hardening) ** (1.0 / n) / self.alpha * (math.pi / n) / math.sin(math.pi / n)

    def param_specs(self) -> tuple[ParamSpec, ...]:
        return self._SPECS

    def params(self) -> dict[str, float]:
        return {spec.name: value for spec, value in zip(self._SPECS, self._values)}

    @classmethod
    def from_params(cls, params: dict[str, float]) -> BoucWenModel:
        required = [spec.name for spec in cls._SPECS]
        missing = [name for name in required if name not in params and name not in cls._DEFAULTS]
        if missing:
            raise ParameterError(f"{cls.__name__}: parameter {missing[0]!r} missing")
        unknown = sorted(set(params) - set(required))
        if unknown:
            raise ParameterError(f"{cls.__name__}: unknown parameters {unknown}, expected {required}")
        return cls(**{**cls._DEFAULTS, **params})

    @accepts(deflection=DEFLECTION)
    def hysteretic_force(self, deflection, initial_z: float = 0.0) -> np.ndarray:
        """The internal variable ``z`` in N along a deflection history in m.

        ``z`` is integrated over each deflection step with at least :data:`BOUCWEN_SUBSTEPS`
        Runge-Kutta sub-steps, more where the step is long against ``z``'s relaxation length
        (:func:`idkit.models.laws.boucwen_substeps`). A step too long even for the most
        sub-steps (about a million relaxation lengths) can still make the update diverge: a
        :class:`~idkit.errors.SimulationError` names the sample (resample finer) instead of
        returning NaN.
        """
        x = deflection
        z = boucwen_z_history(kernel_array(x), self.alpha, self.beta, self.gamma, self.n, float(initial_z),
                              BOUCWEN_SUBSTEPS)
        if not np.isfinite(z).all() and np.isfinite(x).all() and math.isfinite(initial_z):
            first = int(np.argmin(np.isfinite(z)))
            step = abs(float(x[first] - x[first - 1])) if first else 0.0
            raise SimulationError(
                f"{type(self).__name__}: the hysteretic force z diverged at deflection sample {first} (a step of "
                f"{step:.3g} m): the step is too long for the model's yield travel z_max / alpha = "
                f"{self.yield_travel:.3g} m; sample the deflection history finer")
        return z

    @property
    def yield_travel(self) -> float:
        """``z_max / alpha`` in m: the deflection over which ``z`` saturates from zero
        (``z_max = (alpha / (beta + gamma))^(1/n)``; infinite when ``beta + gamma <= 0``)."""
        if self.beta + self.gamma <= 0.0 or self.alpha <= 0.0:
            return math.inf
        return (self.alpha / (self.beta + self.gamma)) ** (1.0 / self.n) / self.alpha

    @accepts(deflection=DEFLECTION, time=TIME)
    def force(self, deflection, time=None, initial_z: float = 0.0) -> np.ndarray:
        """Isolator force in N along a deflection history (m); viscous part if ``time`` is given."""
        x = deflection
        z = self.hysteretic_force(x, initial_z)
        elastic = x * (self.k1 + self.k2 * np.abs(x) + self.k3 * x * x)
        total = self.b ** (self.c * x) * (elastic + z)
        if time is not None and self.c_visc:
            total = total + self.c_visc * _velocity(x, _as_time(time, x.size))
        return total

    @accepts(freq=FREQUENCY)
    def small_amplitude_stiffness(self, freq) -> np.ndarray:
        omega = 2.0 * np.pi * freq
        return (self.k1 + self.alpha) + 1j * omega * self.c_visc

    def kernel_arrays(self) -> IsolatorArrays:
        return IsolatorArrays(
            poly=np.zeros(3),
            c_visc=self.c_visc,
            jenkin_stiffness=np.zeros(0),
            jenkin_friction=np.zeros(0),
            maxwell_stiffness=np.zeros(0),
            maxwell_rate=np.zeros(0),
            boucwen=np.array([1.0, self.k1, self.k2, self.k3, self.alpha, self.beta,
                              self.gamma, self.n, self.b, self.c]),
        )
