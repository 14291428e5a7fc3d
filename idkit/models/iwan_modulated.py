"""Modified Iwan model whose slip forces follow the deflection (thesis 9.2).

The thesis (9.2) recommends "relating the width of the hysteretic loop to the soft-hardening
(global) behaviour": real wire ropes have wider loops in compression than in tension. This
model keeps the modified Iwan force law (:mod:`idkit.models.iwan`)

``F = g1 y + g2 y^2 + g3 y^3 + sum_i F_J,i + c_visc ydot``

but every Jenkin element slips at ``s(y) fc_i`` instead of ``fc_i``, with the **slip scale**

``s(y) = 1 - a t + b t^2``,  ``t = tanh(y / y_ref)``,  ``|a| < 1``, ``y_ref > 0``

(``y`` the deflection in m, positive = tension) and ``s > 0`` for every ``t`` in ``[-1, 1]``
(:func:`lowest_slip_scale`). ``s`` is smooth and equals 1 at zero deflection (so the stuck
stiffness and the small loops about zero are those of the plain model). The **asymmetric
term** ``a`` (``slip_modulation``): with ``a > 0`` the slip forces, and so the loop width,
grow in compression (up to ``1 + a``) and shrink in tension (down to ``1 - a``). The
**symmetric term** ``b`` (``slip_growth``): with ``b > 0`` the loops widen in tension and
compression alike as the deflection grows (up to ``1 + b``), the amplitude-dependent
widening of wire ropes whose strands slip over more of their contacts in large loops; ``b <
0`` narrows them. ``a = b = 0`` is the plain Iwan model exactly (the limits are multiplied by
1.0).

**Stop operator with deflection-dependent limits.** Over a step in which the deflection
moves linearly from ``y0`` to ``y1`` every element is updated by

``F_i <- clip(F_i + k_i (y1 - y0), -s(y1) fc_i, s(y1) fc_i)``.

When the limit shrinks below the current element force (the deflection moves towards the
narrow side while the element is slipping there, or sticks near its limit), the element force
is **clipped to the new limit**: the slider slips just enough to carry ``s(y1) fc_i``. This
update is the exact solution of the continuous operator (element force follows ``k_i dy``
while inside the limits and tracks the limit while on it) whenever the limit changes more
slowly with the deflection than the element's spring can load,
``|d(s fc_i)/dy| = |2 b t - a| fc_i / y_ref sech^2(y / y_ref) < k_i``, which holds for every
``y`` when every slip travel obeys ``fc_i / k_i < y_ref / (|a| + 2 |b|)``
(:attr:`ModulatedIwanModel.stop_operator_exact`, a sufficient condition): the spring force
minus the limit is then monotone along the step, so the element sticks first and slips after,
never the other way round. Outside that condition the rule above still defines the model
(documented clipping), but it is no longer the limit of a continuous path.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from idkit.checks import accepts
from idkit.errors import ParameterError
from idkit.models.base import DEFLECTION, IsolatorArrays, taking_params
from idkit.models.iwan import IwanModel
from idkit.models import laws
from idkit.models.laws import kernel_array
from idkit.params import ParamSpec

__all__ = ["ModulatedIwanModel", "lowest_slip_scale", "modulated_stop_operator", "slip_scale"]

SLIP_MODULATION_SPEC = ParamSpec("slip_modulation", "-", -1.0, 1.0,
                                 "asymmetric slip-force modulation a of s(y) = 1 - a t + b t^2, t = tanh(y / y_ref)")
SLIP_GROWTH_SPEC = ParamSpec("slip_growth", "-", -1.0, math.inf,
                             "symmetric slip-force modulation b of s(y) = 1 - a t + b t^2, t = tanh(y / y_ref)")
SLIP_LENGTH_SPEC = ParamSpec("slip_length", "m", 0.0, math.inf,
                             "deflection scale y_ref of the slip-force modulation", True)


def slip_scale(deflection, modulation: float, length: float, growth: float = 0.0) -> np.ndarray:
    """Slip scale ``s(y) = 1 - a t + b t^2``, ``t = tanh(y / y_ref)`` (dimensionless) at
    deflections ``y`` in m (``modulation`` a, ``length`` y_ref in m, ``growth`` b).

    Examples
    --------
    >>> [round(float(v), 4) for v in slip_scale([-0.01, 0.0, 0.01], 0.3, 0.005)]
    [1.2892, 1.0, 0.7108]
    >>> [round(float(v), 4) for v in slip_scale([-0.01, 0.0, 0.01], 0.0, 0.005, growth=0.4)]
    [1.3717, 1.0, 1.3717]
    """
    y = np.asarray(deflection, dtype=float)
    if modulation == 0.0 and growth == 0.0:
        return np.ones_like(y)
    t = np.tanh(y / length)
    return 1.0 - modulation * t + growth * t * t


def lowest_slip_scale(modulation: float, growth: float, extent: float = 1.0) -> float:
    """Smallest slip scale ``1 - a t + b t^2`` over ``t`` in ``[-extent, extent]``
    (``extent = tanh(y_max / y_ref)`` for deflections up to ``y_max``; 1: every deflection).

    Examples
    --------
    >>> [round(lowest_slip_scale(a, b), 6) for a, b in [(0.3, 0.0), (0.0, 0.5), (0.4, 0.5)]]
    [0.7, 1.0, 0.92]
    """
    a, b, extent = float(modulation), float(growth), abs(float(extent))
    candidates = [1.0 - a * extent + b * extent**2, 1.0 + a * extent + b * extent**2]
    if b > 0.0 and abs(a / (2.0 * b)) <= extent:  # the parabola's vertex lies inside
        candidates.append(1.0 - a * a / (4.0 * b))
    return min(candidates)


def modulated_stop_operator(deflection, stiffness, friction_force, modulation, length, initial_force, growth=0.0):
    """Jenkin forces (N) with slip forces ``s(y) fc_i`` along a deflection history (m): the stop
    operator :func:`idkit.models.laws.stop_operator` with the slip modulation, limits taken at
    the new sample; the first sample holds ``initial_force``. Shape ``(n_samples, n_elements)``."""
    return laws.stop_operator(deflection, stiffness, friction_force, initial_force, modulation, growth, length)


class ModulatedIwanModel(IwanModel):
    """Modified Iwan model with slip forces scaled by ``s(y) = 1 - a t + b t^2``, ``t = tanh(y / y_ref)``.

    Parameters
    ----------
    g1, k, fc, g2, g3, c_visc
        As :class:`idkit.models.IwanModel` (N/m, N/m, N, N/m^2, N/m^3, N s/m); ``fc`` are the
        slip forces at zero deflection.
    slip_modulation : float
        ``a`` in (-1, 1), dimensionless: > 0 widens the loops in compression and narrows them
        in tension.
    slip_length : float
        ``y_ref`` in m, > 0: the deflection over which the modulation sets in.
    slip_growth : float
        ``b``, dimensionless, default 0: > 0 widens the loops in tension and compression alike.
        ``s`` must stay positive (:func:`lowest_slip_scale` > 0); ``a = b = 0`` is the plain
        Iwan model.

    Examples
    --------
    >>> rope = ModulatedIwanModel(g1=3e3, k=[3e3, 3e3], fc=[8.3, 14.6], slip_modulation=0.3,
    ...                           slip_length=5e-3)
    >>> rope.stuck_stiffness, rope.stop_operator_exact
    (9000.0, True)
    >>> [round(float(v), 3) for v in rope.slip_forces(-0.01)]
    [10.7, 18.822]
    >>> widening = ModulatedIwanModel(g1=3e3, k=[3e3], fc=[10.0], slip_growth=0.5, slip_length=5e-3)
    >>> [round(float(v), 3) for v in widening.slip_forces(-0.01)], [round(float(v), 3) for v in widening.slip_forces(0.01)]
    ([14.647], [14.647])
    """

    kind = "iwan_modulated"

    def __init__(self, *, g1, k, fc, g2=0.0, g3=0.0, c_visc=0.0, slip_modulation=0.0, slip_length=1e-2,
                 slip_growth=0.0):
        super().__init__(g1=g1, k=k, fc=fc, g2=g2, g3=g3, c_visc=c_visc)
        name = type(self).__name__
        modulation = SLIP_MODULATION_SPEC.check(slip_modulation, model=name)
        if not -1.0 < modulation < 1.0:
            raise ParameterError(f"{name}: slip_modulation found {modulation!r}, expected -1 < a < 1 "
                                 "(the slip scale 1 - a t + b t^2 must stay positive)")
        growth = SLIP_GROWTH_SPEC.check(slip_growth, model=name)
        lowest = lowest_slip_scale(modulation, growth)
        if not lowest > 0.0:
            raise ParameterError(f"{name}: slip_modulation {modulation!r} with slip_growth {growth!r} give a slip "
                                 f"scale 1 - a t + b t^2 down to {lowest:.4g}, expected it positive for every "
                                 "t = tanh(y / y_ref) in [-1, 1]")
        self._modulation = modulation
        self._growth = growth
        self._length = SLIP_LENGTH_SPEC.check(slip_length, model=name)

    slip_modulation = property(lambda self: self._modulation, doc="Asymmetric modulation a, dimensionless.")
    slip_growth = property(lambda self: self._growth, doc="Symmetric modulation b, dimensionless.")
    slip_length = property(lambda self: self._length, doc="Modulation length y_ref, m.")

    @classmethod
    def from_iwan(cls, model: IwanModel, *, slip_modulation: float = 0.0, slip_length: float = 1e-2,
                  slip_growth: float = 0.0):
        """The plain ``model`` with a slip modulation added (``a = b = 0``: the same force law)."""
        return cls(g1=model.g1, g2=model.g2, g3=model.g3, k=model.k, fc=model.fc, c_visc=model.c_visc,
                   slip_modulation=slip_modulation, slip_length=slip_length, slip_growth=slip_growth)

    def plain(self) -> IwanModel:
        """The plain Iwan model with the same parameters (slip forces ``fc_i``, no modulation)."""
        return IwanModel(g1=self.g1, g2=self.g2, g3=self.g3, k=self.k, fc=self.fc, c_visc=self.c_visc)

    @property
    def stop_operator_exact(self) -> bool:
        """True when every slip travel obeys ``fc_i / k_i < y_ref / (|a| + 2 |b|)`` (module docstring)."""
        return bool(np.all((abs(self._modulation) + 2.0 * abs(self._growth)) * self.fc / self.k < self._length))

    def slip_scale(self, deflection) -> np.ndarray:
        """``s(y)`` at deflections in m (dimensionless)."""
        return slip_scale(deflection, self._modulation, self._length, self._growth)

    def slip_forces(self, deflection) -> np.ndarray:
        """Slip forces ``s(y) fc_i`` in N at one deflection in m, shape ``(order,)``."""
        return float(self.slip_scale(float(deflection))) * self.fc

    def param_specs(self) -> tuple[ParamSpec, ...]:
        return (*super().param_specs(), SLIP_MODULATION_SPEC, SLIP_GROWTH_SPEC, SLIP_LENGTH_SPEC)

    def params(self) -> dict[str, float]:
        values = super().params()
        values["slip_modulation"] = self._modulation
        values["slip_growth"] = self._growth
        values["slip_length"] = self._length
        return values

    @classmethod
    def from_params(cls, params: dict[str, float]) -> ModulatedIwanModel:
        with taking_params("ModulatedIwanModel", params) as left:  # the rest: IwanModel's
            modulation, length = left.pop("slip_modulation"), left.pop("slip_length")
        growth = left.pop("slip_growth", 0.0)  # model files written before the symmetric term: b = 0
        return cls.from_iwan(IwanModel.from_params(left), slip_modulation=modulation, slip_length=length,
                             slip_growth=growth)

    @accepts(deflection=DEFLECTION)
    def jenkin_forces(self, deflection, initial_forces=None) -> np.ndarray:
        """Forces in N of every Jenkin element, shape ``(n_samples, order)`` (modulated stop operator)."""
        x = deflection
        start = np.zeros(self.order) if initial_forces is None else np.asarray(initial_forces, float)
        return modulated_stop_operator(kernel_array(x), kernel_array(self.k), kernel_array(self.fc),
                                       float(self._modulation), float(self._length), kernel_array(start),
                                       float(self._growth))

    def kernel_arrays(self) -> IsolatorArrays:
        return dataclasses.replace(super().kernel_arrays(),
                                   slip_modulation=np.array([self._modulation, self._length, self._growth]))
