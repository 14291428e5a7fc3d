"""Iwan (Jenkin) elements whose slip force rises with the sliding speed (docs/elements.md).

The modified Iwan force law (:mod:`idkit.models.iwan`)
``F = g1 y + g2 y^2 + g3 y^3 + sum_i F_J,i + c_visc ydot`` with every slip force following the
deflection rate ``v = ydot`` (the sliding speed of a slipping element):

``fc_i(v) = fc_i (1 + r tanh(|v| / v_ref))``,

i.e. ``fc0 + fc1 tanh(|v| / v_ref)`` with ``fc0 = fc_i`` (at rest) and ``fc1 = r fc_i``. The
``tanh`` law is chosen over a Stribeck curve because it is bounded (the slip force lies between
``fc`` and ``fc (1 + r)``), smooth in ``v``, and has two parameters a loop test at a few
frequencies determines; ``r < 0`` (down to ``-1``) gives a slip force falling with speed, the
Stribeck drop without its low-speed peak. Viscous damping is the limit ``v_ref >> |v|``
(``r fc / v_ref`` N s/m), which is why a fit does not free ``c_visc`` beside ``r`` and ``v_ref``.

Update over a step (:func:`idkit.models.laws.rate_dependent_stop_operator`):
``F <- clip(F + k dy, -fc(v), fc(v))`` with ``v`` the step's deflection rate; the dynamic
simulator uses the rate at the end of its step (trapezoidal rule), the same to first order.
``r = 0`` is the Iwan model exactly.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from idkit.checks import accepts
from idkit.errors import ParameterError
from idkit.models.base import DEFLECTION, TIME, IsolatorArrays, _as_time, _velocity, taking_params
from idkit.models.iwan import IwanModel
from idkit.models.laws import kernel_array, rate_dependent_slip_force, rate_dependent_stop_operator
from idkit.params import ParamSpec

__all__ = ["RateDependentIwanModel"]

RATE_GAIN_SPEC = ParamSpec("slip_rate_gain", "-", -1.0, math.inf,
                           "rise r of the slip forces with speed, fc (1 + r tanh(|v| / v_ref)) (fc1 / fc0)")
SLIP_SPEED_SPEC = ParamSpec("slip_speed", "m/s", 0.0, math.inf,
                            "sliding speed v_ref over which the slip forces change", True)


class RateDependentIwanModel(IwanModel):
    """Iwan model with slip forces ``fc_i (1 + r tanh(|v| / v_ref))`` at the deflection rate ``v``.

    Parameters
    ----------
    slip_rate_gain : float
        ``r = fc1 / fc0``, dimensionless, > -1 (0: the plain Iwan model).
    slip_speed : float
        ``v_ref`` in m/s, > 0.
    g1, k, fc, g2, g3, c_visc
        As :class:`idkit.models.IwanModel` (N/m, N/m, N, N/m^2, N/m^3, N s/m); ``fc_i`` are the
        slip forces at rest.

    Examples
    --------
    >>> damper = RateDependentIwanModel(g1=0.0, k=[1e6], fc=[1e3], slip_rate_gain=0.5, slip_speed=0.05)
    >>> [round(float(f), 1) for f in damper.slip_forces(np.array([0.0, 0.05, 1.0]))[:, 0]]
    [1000.0, 1380.8, 1500.0]
    """

    kind = "iwan_rate"

    def __init__(self, *, g1, k, fc, slip_rate_gain, slip_speed, g2=0.0, g3=0.0, c_visc=0.0):
        super().__init__(g1=g1, k=k, fc=fc, g2=g2, g3=g3, c_visc=c_visc)
        name = type(self).__name__
        gain = RATE_GAIN_SPEC.check(slip_rate_gain, model=name)
        if not gain > -1.0:
            raise ParameterError(f"{name} parameter 'slip_rate_gain': found {gain!r}, expected > -1 (the slip force "
                                 "fc (1 + r tanh(|v| / v_ref)) must stay positive)")
        self._gain = gain
        self._speed = SLIP_SPEED_SPEC.check(slip_speed, model=name)

    slip_rate_gain = property(lambda self: self._gain, doc="Rise r of the slip forces with speed, dimensionless.")
    slip_speed = property(lambda self: self._speed, doc="Reference sliding speed v_ref, m/s.")

    def plain(self) -> IwanModel:
        """The Iwan model with the slip forces at rest."""
        return IwanModel(g1=self.g1, g2=self.g2, g3=self.g3, k=self.k, fc=self.fc, c_visc=self.c_visc)

    def slip_forces(self, speed) -> np.ndarray:
        """Slip forces in N at deflection rates ``speed`` (m/s), shape ``(n, order)``."""
        v = np.atleast_1d(np.asarray(speed, dtype=float))
        return rate_dependent_slip_force(v[:, None], self.fc[None, :], self._gain, self._speed)

    def param_specs(self) -> tuple[ParamSpec, ...]:
        return (*super().param_specs(), RATE_GAIN_SPEC, SLIP_SPEED_SPEC)

    def params(self) -> dict[str, float]:
        values = super().params()
        values["slip_rate_gain"] = self._gain
        values["slip_speed"] = self._speed
        return values

    @classmethod
    def from_params(cls, params: dict[str, float]) -> RateDependentIwanModel:
        with taking_params("RateDependentIwanModel", params) as left:  # the rest: IwanModel's
            gain, speed = left.pop("slip_rate_gain"), left.pop("slip_speed")
        plain = IwanModel.from_params(left)
        return cls(g1=plain.g1, g2=plain.g2, g3=plain.g3, k=plain.k, fc=plain.fc, c_visc=plain.c_visc,
                   slip_rate_gain=gain, slip_speed=speed)

    @accepts(deflection=DEFLECTION)
    def jenkin_forces(self, deflection, initial_forces=None, *, time=None) -> np.ndarray:
        """Forces in N of every Jenkin element, shape ``(n_samples, order)``, at sample times ``time``
        (s); ``time=None``: the quasi-static limit (vanishing rate, slip forces ``fc_i``)."""
        x = deflection
        start = np.zeros(self.order) if initial_forces is None else np.asarray(initial_forces, float)
        if time is None:
            return self.plain().jenkin_forces(x, start)
        t = _as_time(time, x.size)
        return rate_dependent_stop_operator(kernel_array(x), kernel_array(t), kernel_array(self.k),
                                            kernel_array(self.fc), float(self._gain), float(self._speed),
                                            kernel_array(start))

    @accepts(deflection=DEFLECTION, time=TIME)
    def force(self, deflection, time=None, initial_forces=None) -> np.ndarray:
        """Isolator force in N along a deflection history in m at sample times ``time`` in s (the
        slip forces follow the deflection rate); without ``time`` the quasi-static limit (vanishing
        rate: slip forces ``fc_i``, no viscous force), as :meth:`IwanModel.force`."""
        x = deflection
        total = self.spring_force(x) + self.jenkin_forces(x, initial_forces, time=time).sum(axis=1)
        if time is not None and self.c_visc:
            total = total + self.c_visc * _velocity(x, _as_time(time, x.size))
        return total

    def kernel_arrays(self) -> IsolatorArrays:
        return dataclasses.replace(super().kernel_arrays(), slip_rate=np.array([self._gain, self._speed]))
