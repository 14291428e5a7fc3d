"""Mechanical systems built from isolator models (SPEC 1.5).

Coordinates: ``q`` are mass displacements relative to the base (m, positive up).
An isolator's deflection is the displacement of its upper end minus its lower
end, positive in tension. Each system lists its masses top first.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from idkit.checks import accepts
from idkit.errors import ParameterError
from idkit.models.base import FREQUENCY, IsolatorModel
from idkit.models.iwan import IwanModel
from idkit.models.laws import hybrid_transmissibility, sdof_transmissibility
from idkit.params import ParamSpec

__all__ = ["SDOFSystem", "HybridSystem", "CoulombSpringSystem", "System"]

MASS_SPEC = ParamSpec("mass", "kg", 0.0, math.inf, "mass", positive=True)


def _check_isolator(isolator, role: str) -> IsolatorModel:
    if not isinstance(isolator, IsolatorModel):
        raise ParameterError(f"{role}: found {type(isolator).__name__}, expected an idkit isolator model")
    if getattr(isolator, "quantity", "stiffness") != "stiffness":
        raise ParameterError(f"{role}: found a {isolator.quantity} model ({isolator.unit}, a material), expected "
                             "a stiffness model (N/m, a part); convert it with to_stiffness(area_m2=..., "
                             "thickness_m=...)")
    return isolator


@dataclass(frozen=True, repr=False)
class SDOFSystem:
    """Top mass on one isolator on a moving base.

    Parameters
    ----------
    mass : float
        Top mass in kg. The isolator's ``m_eff`` is added to it (:attr:`moving_mass`).
    isolator : IsolatorModel
        The isolator between base and mass.
    """

    mass: float
    isolator: IsolatorModel

    kind = "sdof"

    def __post_init__(self):
        object.__setattr__(self, "mass", MASS_SPEC.check(self.mass, model="SDOFSystem"))
        _check_isolator(self.isolator, "SDOFSystem isolator")

    @property
    def masses(self) -> np.ndarray:
        """Moving masses in kg, top first (including the isolator's ``m_eff``)."""
        return np.array([self.mass + self.isolator.m_eff])

    @property
    def moving_mass(self) -> float:
        return float(self.masses[0])

    @property
    def isolators(self) -> tuple[IsolatorModel, ...]:
        """Isolators top first: the one below mass 0."""
        return (self.isolator,)

    @accepts(freq=FREQUENCY)
    def transmissibility(self, freq) -> np.ndarray:
        """Small-amplitude (linearized) transmissibility ``k* / (k* - m omega^2)`` at ``freq`` Hz.

        Exact for linear isolators; for hysteretic ones it is the all-stuck limit.
        """
        freq = freq
        omega = 2.0 * np.pi * freq
        return sdof_transmissibility(self.isolator.small_amplitude_stiffness(freq), self.moving_mass, omega)

    def to_dict(self) -> dict:
        return {"kind": self.kind, "mass": self.mass, "isolator": self.isolator.to_dict()}

    def __repr__(self) -> str:
        return f"SDOFSystem(mass={self.mass:g} kg, isolator={self.isolator!r})"


@dataclass(frozen=True, repr=False)
class HybridSystem:
    """Series ("hybrid") system (SPEC 1.5, eq. 5.1).

    top mass -- ``upper`` isolator (elastomer) -- intermediate mass -- ``lower``
    isolator (wire rope) -- base.

    Parameters
    ----------
    mass : float
        Top mass in kg (the upper isolator's ``m_eff`` is added to it).
    upper : IsolatorModel
        Isolator between intermediate and top mass (the elastomer in the thesis).
    intermediate_mass : float
        Intermediate mass in kg (1 % of the top mass in the studies).
    lower : IsolatorModel
        Isolator between base and intermediate mass (the wire rope).
    """

    mass: float
    upper: IsolatorModel
    intermediate_mass: float
    lower: IsolatorModel

    kind = "hybrid"

    def __post_init__(self):
        object.__setattr__(self, "mass", MASS_SPEC.check(self.mass, model="HybridSystem"))
        intermediate = ParamSpec("intermediate_mass", "kg", 0.0, math.inf, "intermediate mass", True)
        object.__setattr__(self, "intermediate_mass", intermediate.check(self.intermediate_mass, model="HybridSystem"))
        _check_isolator(self.upper, "HybridSystem upper")
        _check_isolator(self.lower, "HybridSystem lower")

    @property
    def masses(self) -> np.ndarray:
        """``[top, intermediate]`` in kg; ``m_eff`` of each isolator joins the mass above it."""
        return np.array([self.mass + self.upper.m_eff, self.intermediate_mass + self.lower.m_eff])

    @property
    def isolators(self) -> tuple[IsolatorModel, ...]:
        return (self.upper, self.lower)

    @accepts(freq=FREQUENCY)
    def transmissibility(self, freq) -> np.ndarray:
        """Small-amplitude transmissibility top/base (stuck wire rope, linear elastomer)."""
        freq = freq
        omega = 2.0 * np.pi * freq
        m_top, m_in = self.masses
        return hybrid_transmissibility(self.upper.small_amplitude_stiffness(freq),
                                       self.lower.small_amplitude_stiffness(freq), m_top, m_in, omega)

    @accepts(freq=FREQUENCY)
    def series_stiffness(self, freq) -> np.ndarray:
        """Small-amplitude series stiffness ``1 / (1/k_upper + 1/k_lower)`` in N/m."""
        freq = freq
        return 1.0 / (1.0 / self.upper.small_amplitude_stiffness(freq)
                      + 1.0 / self.lower.small_amplitude_stiffness(freq))

    def to_dict(self) -> dict:
        return {
            "kind": self.kind, "mass": self.mass, "intermediate_mass": self.intermediate_mass,
            "upper": self.upper.to_dict(), "lower": self.lower.to_dict(),
        }

    def __repr__(self) -> str:
        return (f"HybridSystem(mass={self.mass:g} kg, upper={self.upper!r}, "
                f"intermediate_mass={self.intermediate_mass:g} kg, lower={self.lower!r})")


@dataclass(frozen=True, repr=False)
class CoulombSpringSystem:
    """Mass on a spring in parallel with a Coulomb slider (eqs. 3.14-3.15).

    ``m xdd + k (x - x_b) + Fc sgn(xd - xd_b) + c (xd - xd_b) = 0`` with the set-valued sgn.

    The exact reference is :func:`idkit.simulate.moreau_coulomb_spring`. The fast
    integrator represents the slider as a Jenkin element of stiffness
    ``contact_stiffness_ratio * stiffness`` (an elastic-plastic contact): in stick
    it deflects by at most ``Fc / (ratio k)``, which bounds its difference from
    the rigid slider (:meth:`as_sdof`).
    """

    mass: float
    stiffness: float
    friction_force: float
    damping: float = 0.0
    contact_stiffness_ratio: float = 1e4

    kind = "coulomb_spring"

    def __post_init__(self):
        checks = (
            MASS_SPEC,
            ParamSpec("stiffness", "N/m", 0.0, math.inf, "spring stiffness"),
            ParamSpec("friction_force", "N", 0.0, math.inf, "Coulomb friction force", True),
            ParamSpec("damping", "N s/m", 0.0, math.inf, "viscous damping"),
            ParamSpec("contact_stiffness_ratio", "-", 1.0, math.inf, "slider stiffness / spring stiffness"),
        )
        for spec in checks:
            object.__setattr__(self, spec.name, spec.check(getattr(self, spec.name), model="CoulombSpringSystem"))

    @property
    def contact_compliance_bound(self) -> float:
        """Largest elastic slider deflection ``Fc / (ratio k)`` in m."""
        return self.friction_force / (self.contact_stiffness_ratio * max(self.stiffness, 1.0))

    def as_sdof(self) -> SDOFSystem:
        """The equivalent SDOF system with a one-element Iwan isolator."""
        slider = IwanModel(
            g1=self.stiffness,
            k=[self.contact_stiffness_ratio * max(self.stiffness, 1.0)],
            fc=[self.friction_force],
            c_visc=self.damping,
        )
        return SDOFSystem(self.mass, slider)

    def to_dict(self) -> dict:
        return {"kind": self.kind, "mass": self.mass, "stiffness": self.stiffness,
                "friction_force": self.friction_force, "damping": self.damping,
                "contact_stiffness_ratio": self.contact_stiffness_ratio}

    def __repr__(self) -> str:
        return (f"CoulombSpringSystem(mass={self.mass:g} kg, stiffness={self.stiffness:g} N/m, "
                f"friction_force={self.friction_force:g} N, damping={self.damping:g} N s/m)")


System = SDOFSystem | HybridSystem
