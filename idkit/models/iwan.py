"""Modified Iwan model of a wire-rope isolator (SPEC 1.1-1.2, thesis 3.2.2).

``F = g1 x + g2 x^2 + g3 x^3 + sum_i F_J,i + c_visc xdot`` with Jenkin elements
(spring ``k_i`` in series with a Coulomb slider of strength ``fc_i``) evaluated by
the exact stop operator. The symmetric model has ``g2 = g3 = 0`` (``g1`` is then the
thesis's ``k_wr0``).
"""

from __future__ import annotations

import math

import numpy as np

from idkit.checks import accepts
from idkit.models.laws import (CONSTANT_SLIP, kernel_array, polynomial_spring_force, polynomial_spring_stiffness,
                               stop_operator)
from idkit.models.base import C_VISC_SPEC, IsolatorArrays, IsolatorModel, taking_params
from idkit.models.base import DEFLECTION, FREQUENCY, TIME, _as_time, _velocity
from idkit.params import ParamSpec, check_array

__all__ = ["IwanModel", "jenkin_force"]

G1_SPEC = ParamSpec("g1", "N/m", 0.0, math.inf, "parallel spring stiffness at the origin")
G2_SPEC = ParamSpec("g2", "N/m^2", -math.inf, math.inf, "quadratic (asymmetry) spring coefficient")
G3_SPEC = ParamSpec("g3", "N/m^3", -math.inf, math.inf, "cubic (soft/hardening) spring coefficient")


@accepts(deflection=DEFLECTION)
def jenkin_force(deflection, stiffness: float, friction_force: float, initial_force: float = 0.0):
    """Force in N of one Jenkin element along a deflection history in m (stop operator).

    Examples
    --------
    >>> jenkin_force([0.0, 1e-3, 3e-3, 2e-3], stiffness=3e3, friction_force=8.3)
    array([0. , 3. , 8.3, 5.3])
    """
    x = deflection
    forces = stop_operator(
        kernel_array(x), np.array([float(stiffness)]), np.array([float(friction_force)]),
        np.array([float(initial_force)]), *CONSTANT_SLIP,
    )
    return forces[:, 0]


class IwanModel(IsolatorModel):
    """Parallel-series (modified) Iwan model of order ``n``.

    Parameters
    ----------
    g1 : float
        Parallel spring stiffness at the origin in N/m (``k_wr0`` of the symmetric model), >= 0.
    k : array_like, shape (n,)
        Jenkin spring stiffnesses in N/m, > 0.
    fc : array_like, shape (n,)
        Jenkin Coulomb slip forces in N, > 0.
    g2 : float, optional
        Quadratic spring coefficient in N/m^2 (asymmetry). Default 0.
    g3 : float, optional
        Cubic spring coefficient in N/m^3 (softening < 0, hardening > 0). Default 0.
    c_visc : float, optional
        Small parallel viscous damping in N s/m (SPEC 1.2). Default 0.

    Examples
    --------
    >>> wire_rope = IwanModel(g1=3e3, k=[3e3, 3e3], fc=[8.3, 14.6])
    >>> wire_rope.stuck_stiffness
    9000.0
    """

    kind = "iwan"

    def __init__(self, *, g1, k, fc, g2=0.0, g3=0.0, c_visc=0.0):
        name = type(self).__name__
        self._g1 = G1_SPEC.check(g1, model=name)
        self._g2 = G2_SPEC.check(g2, model=name)
        self._g3 = G3_SPEC.check(g3, model=name)
        self._k = check_array(k, name="k", unit="N/m", lower=0.0, meaning="Jenkin stiffness",
                              positive=True, model=name, min_length=1)
        self._fc = check_array(fc, name="fc", unit="N", lower=0.0, meaning="Jenkin slip force",
                               positive=True, model=name, length=self._k.size)
        self._c_visc = C_VISC_SPEC.check(c_visc, model=name)

    @classmethod
    def symmetric(cls, *, k_wr0, k, fc, c_visc=0.0) -> IwanModel:
        """Symmetric Iwan model: linear parallel spring ``k_wr0`` in N/m (eq. 3.7)."""
        return cls(g1=k_wr0, k=k, fc=fc, c_visc=c_visc)

    g1 = property(lambda self: self._g1, doc="Parallel spring stiffness at the origin, N/m.")
    g2 = property(lambda self: self._g2, doc="Quadratic spring coefficient, N/m^2.")
    g3 = property(lambda self: self._g3, doc="Cubic spring coefficient, N/m^3.")
    k = property(lambda self: self._k, doc="Jenkin stiffnesses, N/m.")
    fc = property(lambda self: self._fc, doc="Jenkin slip forces, N.")
    c_visc = property(lambda self: self._c_visc, doc="Parallel viscous damping, N s/m.")

    @property
    def order(self) -> int:
        """Number of Jenkin elements."""
        return int(self._k.size)

    @property
    def is_symmetric(self) -> bool:
        """True if the parallel spring is linear (identical tension and compression)."""
        return self._g2 == 0.0 and self._g3 == 0.0

    @property
    def stuck_stiffness(self) -> float:
        """Small-amplitude stiffness ``g1 + sum k_i`` in N/m (all elements stuck)."""
        return self._g1 + float(self._k.sum())

    def param_specs(self) -> tuple[ParamSpec, ...]:
        n = self.order
        return (
            G1_SPEC, G2_SPEC, G3_SPEC,
            *(ParamSpec(f"k_{i}", "N/m", 0.0, math.inf, "Jenkin stiffness", True) for i in range(1, n + 1)),
            *(ParamSpec(f"fc_{i}", "N", 0.0, math.inf, "Jenkin slip force", True) for i in range(1, n + 1)),
            C_VISC_SPEC,
        )

    def params(self) -> dict[str, float]:
        values = {"g1": self._g1, "g2": self._g2, "g3": self._g3}
        values.update({f"k_{i}": float(v) for i, v in enumerate(self._k, start=1)})
        values.update({f"fc_{i}": float(v) for i, v in enumerate(self._fc, start=1)})
        values["c_visc"] = self._c_visc
        return values

    @classmethod
    def from_params(cls, params: dict[str, float]) -> IwanModel:
        with taking_params("IwanModel", params, "g1..g3, k_i, fc_i, c_visc") as left:
            order = sum(1 for name in left if name.startswith("k_"))
            model = cls(
                g1=left.pop("g1"), g2=left.pop("g2", 0.0), g3=left.pop("g3", 0.0),
                k=[left.pop(f"k_{i}") for i in range(1, order + 1)],
                fc=[left.pop(f"fc_{i}") for i in range(1, order + 1)],
                c_visc=left.pop("c_visc", 0.0),
            )
        return model

    def spring_force(self, deflection) -> np.ndarray:
        """Parallel (polynomial) spring force ``g1 x + g2 x^2 + g3 x^3`` in N."""
        x = np.asarray(deflection, dtype=float)
        return polynomial_spring_force(x, self._g1, self._g2, self._g3)

    def spring_stiffness(self, deflection) -> np.ndarray:
        """Local stiffness of the parallel spring ``g1 + 2 g2 x + 3 g3 x^2`` in N/m."""
        x = np.asarray(deflection, dtype=float)
        return polynomial_spring_stiffness(x, self._g1, self._g2, self._g3)

    def valid_deflection_range(self) -> tuple[float, float]:
        """Deflections (m) between which the parallel spring's local stiffness is >= 0.

        Outside this interval the model is invalid (SPEC 1.2): the simulator flags
        such runs. Returns ``(-inf, inf)`` when the stiffness never turns negative.
        """
        roots = np.roots([3.0 * self._g3, 2.0 * self._g2, self._g1]) if self._g3 or self._g2 else []
        real = sorted(float(r.real) for r in np.atleast_1d(roots) if abs(r.imag) < 1e-12 * max(1.0, abs(r)))
        lower = max((r for r in real if r < 0), default=-math.inf)
        upper = min((r for r in real if r > 0), default=math.inf)
        return lower, upper

    @accepts(deflection=DEFLECTION)
    def jenkin_forces(self, deflection, initial_forces=None) -> np.ndarray:
        """Forces in N of every Jenkin element, shape ``(n_samples, order)``."""
        x = deflection
        start = np.zeros(self.order) if initial_forces is None else np.asarray(initial_forces, float)
        return stop_operator(kernel_array(x), kernel_array(self._k), kernel_array(self._fc), kernel_array(start),
                             *CONSTANT_SLIP)

    @accepts(deflection=DEFLECTION, time=TIME)
    def force(self, deflection, time=None, initial_forces=None) -> np.ndarray:
        """Isolator force in N along a deflection history in m.

        Exact (stop operator) for the hysteretic part; the viscous part
        ``c_visc * xdot`` is included when ``time`` (s) is given.
        The Jenkin elements start from ``initial_forces`` (default: unloaded)
        at the first sample.
        """
        x = deflection
        total = self.spring_force(x) + self.jenkin_forces(x, initial_forces).sum(axis=1)
        if time is not None and self._c_visc:
            total = total + self._c_visc * _velocity(x, _as_time(time, x.size))
        return total

    @accepts(freq=FREQUENCY)
    def small_amplitude_stiffness(self, freq) -> np.ndarray:
        omega = 2.0 * np.pi * freq
        return self.stuck_stiffness + 1j * omega * self._c_visc

    def kernel_arrays(self) -> IsolatorArrays:
        return IsolatorArrays(
            poly=np.array([self._g1, self._g2, self._g3]),
            c_visc=self._c_visc,
            jenkin_stiffness=np.array(self._k),
            jenkin_friction=np.array(self._fc),
            maxwell_stiffness=np.zeros(0),
            maxwell_rate=np.zeros(0),
            boucwen=np.zeros(10),
        )
