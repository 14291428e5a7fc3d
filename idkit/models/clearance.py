"""Jenkin (Iwan) elements acting through a clearance: friction dampers with play (docs/elements.md).

Every Jenkin element (spring ``k_i`` in series with a Coulomb slider ``fc_i``) acts through a
clearance (dead zone) of half-width ``gap`` in m: while the travel since the last contact lies
within the clearance the element carries nothing. With the parallel spring and dashpot of the
Iwan model (:mod:`idkit.models.iwan`)

``F = g1 y + g2 y^2 + g3 y^3 + sum_i D_i + c_visc ydot``,  ``D_i = dead_zone(V_i, k_i gap)``,

where ``V_i`` is the element's *virtual* force: a Jenkin element of stiffness ``k_i`` and slip
force ``fc_i + k_i gap`` (``V_i = k_i e_i``, ``e_i`` the travel from the middle of the clearance;
:func:`idkit.models.laws.clearance_jenkin_forces`). This is exact: with the contact spring and
the element spring in series only their series stiffness acts, so ``k_i`` is that series
stiffness (the two cannot be told apart from a force record). Under a sinusoid of amplitude
``A > gap + fc/k`` one element gives a loop with a zero-force plateau of width ``2 gap`` after
every reversal and the area ``4 fc (A - gap - fc/k)``. ``gap = 0`` is the Iwan model exactly.

Each element has its own clearance of the common half-width ``gap`` (a clearance in series with
the whole parallel Iwan model would need an implicit solve for the contact travel); with one
element (``order = 1``) the two are the same: the clearance-Jenkin friction damper.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from idkit.checks import accepts
from idkit.models.base import DEFLECTION, FREQUENCY, IsolatorArrays, taking_params
from idkit.models.iwan import IwanModel
from idkit.models.laws import clearance_jenkin_forces
from idkit.params import ParamSpec

__all__ = ["ClearanceIwanModel"]

GAP_SPEC = ParamSpec("gap", "m", 0.0, math.inf, "half-width of the clearance before every Jenkin element")


class ClearanceIwanModel(IwanModel):
    """Iwan model whose Jenkin elements act through a clearance of half-width ``gap``.

    Parameters
    ----------
    gap : float
        Half-width of the clearance in m (>= 0; 0: the plain Iwan model).
    g1, k, fc, g2, g3, c_visc
        As :class:`idkit.models.IwanModel` (N/m, N/m, N, N/m^2, N/m^3, N s/m); ``k_i`` is the
        series stiffness of the contact and the element's spring.

    Examples
    --------
    >>> damper = ClearanceIwanModel(gap=2e-3, g1=0.0, k=[5e6], fc=[4e3])
    >>> x = np.array([0.0, 10e-3, 9e-3, 7e-3, 5e-3])
    >>> damper.force(x).round(3)
    array([    0.,  4000.,     0.,     0., -1000.])
    >>> round(damper.loop_area(10e-3), 3)
    115.2
    """

    kind = "iwan_clearance"

    def __init__(self, *, gap, g1, k, fc, g2=0.0, g3=0.0, c_visc=0.0):
        super().__init__(g1=g1, k=k, fc=fc, g2=g2, g3=g3, c_visc=c_visc)
        self._gap = GAP_SPEC.check(gap, model=type(self).__name__)

    gap = property(lambda self: self._gap, doc="Half-width of the clearance, m.")

    def plain(self) -> IwanModel:
        """The Iwan model with the same parameters and no clearance."""
        return IwanModel(g1=self.g1, g2=self.g2, g3=self.g3, k=self.k, fc=self.fc, c_visc=self.c_visc)

    def param_specs(self) -> tuple[ParamSpec, ...]:
        return (*super().param_specs(), GAP_SPEC)

    def params(self) -> dict[str, float]:
        values = super().params()
        values["gap"] = self._gap
        return values

    @classmethod
    def from_params(cls, params: dict[str, float]) -> ClearanceIwanModel:
        with taking_params("ClearanceIwanModel", params) as left:  # the rest: IwanModel's
            gap = left.pop("gap")
        plain = IwanModel.from_params(left)
        return cls(gap=gap, g1=plain.g1, g2=plain.g2, g3=plain.g3, k=plain.k, fc=plain.fc, c_visc=plain.c_visc)

    def loop_area(self, amplitude: float) -> float:
        """Dissipated energy (J) of a steady cycle ``+-amplitude`` (m): ``sum_i 4 fc_i (A - gap -
        fc_i / k_i)`` over the elements that slip (``A > gap + fc_i / k_i``)."""
        travel = float(amplitude) - self._gap - self.fc / self.k
        return float(np.sum(4.0 * self.fc * np.maximum(travel, 0.0)))

    @accepts(deflection=DEFLECTION)
    def jenkin_forces(self, deflection, initial_forces=None) -> np.ndarray:
        """Forces in N each element passes on, shape ``(n_samples, order)``; ``initial_forces`` are
        the elements' virtual forces at the first sample (default 0: centred in the clearance)."""
        x = deflection
        start = np.zeros(self.order) if initial_forces is None else np.asarray(initial_forces, float)
        return clearance_jenkin_forces(x, self.k, self.fc, self._gap, start)

    @accepts(freq=FREQUENCY)
    def small_amplitude_stiffness(self, freq) -> np.ndarray:
        """Complex stiffness (N/m) about the middle of the clearance: ``g1 + i omega c_visc`` (the
        elements do not touch), or the Iwan model's ``g1 + sum k_i`` without a clearance."""
        if self._gap == 0.0:
            return super().small_amplitude_stiffness(freq)
        omega = 2.0 * np.pi * freq
        return self.g1 + 1j * omega * self.c_visc

    def kernel_arrays(self) -> IsolatorArrays:
        plain = super().kernel_arrays()
        return dataclasses.replace(plain, clearance=self._gap,  # the virtual elements' slip limits
                                   jenkin_friction=plain.jenkin_friction + plain.jenkin_stiffness * self._gap)
