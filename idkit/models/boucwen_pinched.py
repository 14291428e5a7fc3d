"""Bouc-Wen model with Baber-Noori pinching (docs/elements.md).

The modified Bouc-Wen force law of :mod:`idkit.models.boucwen`,
``F = b^(c x) (k1 x + k2 sgn(x) x^2 + k3 x^3 + z) + c_visc xdot``, with the hysteretic force
``z`` (N) obeying the pinched law (Baber & Noori 1986; Foliente 1995, without degradation)

``dz/dx = h(z) (alpha - (gamma + beta sgn(xdot z)) |z|^n)``,
``h(z) = 1 - pinch exp(-((z sgn(xdot) - shift z_u) / (width z_u))^2)``,

``z_u = (alpha / (beta + gamma))^(1/n)`` the saturated hysteretic force. ``pinch`` (0 to < 1)
is the depth of the dip of the slope (the loop's waist: the slope falls to ``(1 - pinch)
alpha``), ``pinch_width`` its width and ``pinch_shift`` its centre as fractions of ``z_u`` (``0``:
centred where ``z`` crosses zero after a reversal, the slack of a rope or a joint taking up).
Dimensionless width and centre keep the parameters of one rope comparable across sizes.
``pinch = 0`` is the plain Bouc-Wen model exactly (the factor is 1.0). Degradation (the
energy-dependent growth of ``pinch`` in the full BWBN model) is not modelled: loops cycled at
one amplitude stay the same.
"""

from __future__ import annotations

import math

import numpy as np

from idkit.checks import accepts
from idkit.errors import ParameterError, SimulationError
from idkit.models.base import DEFLECTION, FREQUENCY, IsolatorArrays
from idkit.models.boucwen import BOUCWEN_SUBSTEPS, BoucWenModel
from idkit.models.laws import kernel_array, pinched_boucwen_z_history, pinching_factor
from idkit.params import ParamSpec

__all__ = ["PinchedBoucWenModel"]

PINCH_SPECS = (
    ParamSpec("pinch", "-", 0.0, 1.0, "depth of the pinching dip of dz/dx (0: none, < 1)"),
    ParamSpec("pinch_width", "-", 0.0, math.inf, "width of the pinching dip as a fraction of z_u", True),
    ParamSpec("pinch_shift", "-", -1.0, 1.0, "centre of the pinching dip (z sgn(xdot)) as a fraction of z_u"),
)


class PinchedBoucWenModel(BoucWenModel):
    """Bouc-Wen model whose ``z`` law is pinched (Baber-Noori factor, module docstring).

    Parameters
    ----------
    k1, k2, k3, alpha, beta, gamma, n, b, c, c_visc
        As :class:`idkit.models.BoucWenModel`; ``beta + gamma > 0`` (a saturating ``z``:
        the pinching is scaled by ``z_u``).
    pinch : float
        Depth of the dip, dimensionless, 0 <= pinch < 1.
    pinch_width : float
        Width of the dip as a fraction of ``z_u``, > 0.
    pinch_shift : float
        Centre of the dip as a fraction of ``z_u``, -1 to 1. Default 0.

    Examples
    --------
    >>> rope = PinchedBoucWenModel(k1=1e3, k2=0.0, k3=0.0, alpha=5e3, beta=2e3, gamma=1e3, n=1.0,
    ...                            pinch=0.8, pinch_width=0.2)
    >>> round(rope.saturated_force, 4), round(float(rope.small_amplitude_stiffness(0.0).real), 6)
    (1.6667, 2000.0)
    """

    kind = "bouc_wen_pinched"
    _SPECS = (*BoucWenModel._SPECS, *PINCH_SPECS)
    _DEFAULTS = {**BoucWenModel._DEFAULTS, "pinch_shift": 0.0}

    def __init__(self, *, k1, k2, k3, alpha, beta, gamma, n, pinch, pinch_width, pinch_shift=0.0, b=1.0, c=0.0,
                 c_visc=0.0):
        super().__init__(k1=k1, k2=k2, k3=k3, alpha=alpha, beta=beta, gamma=gamma, n=n, b=b, c=c, c_visc=c_visc)
        name = type(self).__name__
        pinching = tuple(spec.check(value, model=name) for spec, value in zip(PINCH_SPECS,
                                                                                (pinch, pinch_width, pinch_shift)))
        if not pinching[0] < 1.0:
            raise ParameterError(f"{name} parameter 'pinch': found {pinching[0]!r}, expected 0 <= pinch < 1 (at 1 "
                                 "the slope of z vanishes and the loop locks)")
        if not self.beta + self.gamma > 0.0:
            raise ParameterError(f"{name}: found beta + gamma = {self.beta + self.gamma:g}, expected > 0 (the pinching "
                                 "is scaled by the saturated force z_u = (alpha / (beta + gamma))^(1/n))")
        self._values = self._values + pinching

    def plain(self) -> BoucWenModel:
        """The Bouc-Wen model with the same parameters and no pinching."""
        return BoucWenModel(**{spec.name: value for spec, value in zip(BoucWenModel._SPECS, self._values)})

    @property
    def saturated_force(self) -> float:
        """``z_u = (alpha / (beta + gamma))^(1/n)`` in N."""
        return (self.alpha / (self.beta + self.gamma)) ** (1.0 / self.n)

    def pinching(self) -> tuple[float, float, float]:
        """``(pinch, width, shift)`` of the factor, width and shift in N."""
        z_u = self.saturated_force
        return self.pinch, self.pinch_width * z_u, self.pinch_shift * z_u

    @accepts(deflection=DEFLECTION)
    def hysteretic_force(self, deflection, initial_z: float = 0.0) -> np.ndarray:
        """The pinched ``z`` in N along a deflection history in m (see :meth:`BoucWenModel.hysteretic_force`)."""
        x = deflection
        pinch, width, shift = self.pinching()
        z = pinched_boucwen_z_history(kernel_array(x), self.alpha, self.beta, self.gamma, self.n, pinch, width, shift,
                                      float(initial_z), BOUCWEN_SUBSTEPS)
        if not np.isfinite(z).all() and math.isfinite(initial_z):
            first = int(np.argmin(np.isfinite(z)))
            raise SimulationError(f"{type(self).__name__}: the hysteretic force z diverged at deflection sample "
                                  f"{first}: sample the deflection history finer")
        return z

    @accepts(freq=FREQUENCY)
    def small_amplitude_stiffness(self, freq) -> np.ndarray:
        """``k1 + h(0) alpha + i omega c_visc`` (N/m): the slope of ``z`` at ``z = 0`` is pinched."""
        omega = 2.0 * np.pi * freq
        pinch, width, shift = self.pinching()
        return (self.k1 + pinching_factor(0.0, 1.0, pinch, width, shift) * self.alpha) + 1j * omega * self.c_visc

    def kernel_arrays(self) -> IsolatorArrays:
        plain = super().kernel_arrays()
        return IsolatorArrays(
            poly=plain.poly, c_visc=plain.c_visc, jenkin_stiffness=plain.jenkin_stiffness,
            jenkin_friction=plain.jenkin_friction, maxwell_stiffness=plain.maxwell_stiffness,
            maxwell_rate=plain.maxwell_rate, boucwen=plain.boucwen, pinching=np.array(self.pinching()),
        )
