"""The "true" isolators behind the synthetic data (richer than the fitted models).

The truth is deliberately **not** a member of the model families idkit fits, so that a fit
on the synthetic data is an identification with a model error, not an echo of the generator.
Two named truths exist (:func:`truth_models`); ``"a"`` made the bundled ``data/``:

* :class:`WireRopeTruth` - Iwan model of order 30 with a log-normal mixture of slip
  displacements (two families near 0.1 mm and 1.1 mm, as the two elements of Table 7.1),
  the Table 7.1 polynomial spring plus a bottoming stiffener below -18 mm, and slip forces
  scaled by ``s(y) = 1 + beta tanh(-y / y_ref)`` (wider loops in compression, narrower in
  tension);
* :class:`ElastomerTruth` - generalized Maxwell of order 8 (rates 3 - 7000 1/s) about 15 %
  stiffer than the catalogue 12e3 N/m quasi-statically, within 5 % of Table 7.3 over
  1-100 Hz, split into two halves (each twice as stiff) with an internal elastomer mass
  between them that gives an internal mode near 200 Hz, plus a softening
  ``1 - alpha tanh^2(y / y_soft)`` of the static spring in compression only.

Truth ``"b"`` differs from ``"a"`` where identification is sensitive:

* :class:`ModulatedWireRopeTruth` - Iwan model of order 24 whose slip displacements
  ``fc_i / k_i`` are log-spaced from 20 um to 7.5 mm (half the largest 15 mm loop), so
  elements still slip across the large loops; a nearly linear spring (``g2 y^2`` and
  ``g3 y^3`` below 2 % of ``g1 y`` at 15 mm); the **whole** hysteretic force scaled by
  ``m(y) = 1 + beta tanh^2(y / y_ref)`` (loops widen in tension and compression alike);
  12 N s/m viscous damping;
* :class:`SingleBodyElastomerTruth` - generalized Maxwell of order 7 with rates spread
  over three decades (2 - 2000 1/s), no internal mass (no internal mode), 0.30 kg of
  elastomer moving with the top mass and a mild softening in compression.

All values SI. ``to_dict()`` gives the JSON written to the truth files.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import ClassVar

import numpy as np

from idkit.synth.chain import LINK_ELASTOMER, LINK_WIRE_ROPE, LINK_WIRE_ROPE_MODULATED, link_force_path, pack_links
from idkit.synth.names import TRUTH_NAMES

__all__ = ["ElastomerTruth", "ModulatedWireRopeTruth", "SingleBodyElastomerTruth",
           "WireRopeTruth", "default_elastomer", "default_wire_rope", "truth_models"]

def _quasi_static_force(link, deflection) -> np.ndarray:
    """Force (N) of ``link`` along ``deflection`` (m) from the unloaded (virgin) state, so
    slowly that viscous and Maxwell rate terms vanish."""
    deflection = np.asarray(deflection, dtype=float)
    kinds, scalars, ks, bs, ns = pack_links([link])
    slow = np.linspace(0.0, 1e12, deflection.size)
    force, _ = link_force_path(kinds[0], scalars[0], ks[0], bs[0], ns[0], np.zeros(ks.shape[1]),
                               deflection, slow)
    return force


def _wire_rope_elements(order: int) -> tuple[list[float], list[float]]:
    """Slip forces (N) and stiffnesses (N/m) of the wire-rope Jenkin elements.

    Slip displacements ``delta_i = fc_i / k_i`` are log-spaced from 10 um to 5 mm; the slip
    force per element follows a two-hump log-normal density (15.5 N around 0.1 mm and
    10.3 N around 1.1 mm in total, the two elements of Table 7.1) plus 0.01 N each.
    """
    delta = np.geomspace(1e-5, 5e-3, order)
    log_d = np.log(delta)
    hump_small = np.exp(-0.5 * ((log_d - np.log(0.1e-3)) / 0.7) ** 2)
    hump_large = np.exp(-0.5 * ((log_d - np.log(1.1e-3)) / 0.6) ** 2)
    fc = 15.5 * hump_small / hump_small.sum() + 10.3 * hump_large / hump_large.sum() + 0.01
    k = fc / delta
    return [float(v) for v in np.round(fc, 4)], [float(v) for v in np.round(k, 1)]


class _RopeTruth:
    """What every wire-rope truth derives from its ``link()``, ``g1``, ``k`` and ``fc``."""

    MODEL: ClassVar[str]
    DESCRIPTION: ClassVar[str]

    @property
    def stuck_stiffness(self) -> float:
        """``g1 + sum k_i`` in N/m (every element stuck, at zero deflection)."""
        return self.g1 + float(np.sum(self.k))

    def quasi_static_force(self, deflection) -> np.ndarray:
        """Force (N) along a deflection path (m) starting unloaded at its first point."""
        return _quasi_static_force(self.link(), deflection)

    def to_dict(self) -> dict:
        out = {"model": self.MODEL, **asdict(self)}
        out["order"] = len(self.k)
        out["stuck_stiffness_N_per_m"] = self.stuck_stiffness
        out["description"] = self.DESCRIPTION
        return out


@dataclass(frozen=True)
class WireRopeTruth(_RopeTruth):
    """True wire-rope isolator (see the module docstring); forces in N, deflection in m."""

    g1: float = 1.84e4
    g2: float = 2.45e5
    g3: float = -4.57e5
    k_bottom: float = 2.0e7  # N/m^3, stiffener below -y_bottom
    y_bottom: float = 0.018
    c_visc: float = 5.0  # N s/m
    beta: float = 0.35  # slip-force scale amplitude
    y_ref: float = 0.006  # m
    fc: list[float] = field(default_factory=lambda: _wire_rope_elements(30)[0])
    k: list[float] = field(default_factory=lambda: _wire_rope_elements(30)[1])
    mass_kg: float = 0.21

    def link(self):
        """Kernel link tuple ``(kind, scalars, k, fc)``."""
        scalars = [self.g1, self.g2, self.g3, self.c_visc, self.k_bottom, self.y_bottom,
                   self.beta, self.y_ref]
        return (LINK_WIRE_ROPE, scalars, list(self.k), list(self.fc))

    MODEL: ClassVar[str] = "iwan_deflection_scaled_slip"
    DESCRIPTION: ClassVar[str] = (
        "F = g1 y + g2 y^2 + g3 y^3 - k_bottom max(0, -y - y_bottom)^3 + sum_i F_i + c_visc ydot; "
        "F_i by the stop operator with slip force s(y) fc_i, s(y) = 1 + beta tanh(-y / y_ref); "
        "y = deflection (m, positive = tension)"
    )


class _ElastomerTruth:
    """What every elastomer truth derives from its ``k0``, ``k`` and ``rate``."""

    MODEL: ClassVar[str]
    DESCRIPTION: ClassVar[str]

    def complex_stiffness(self, freq) -> np.ndarray:
        """Small-amplitude complex stiffness of the isolator's Maxwell body, without an internal
        mass (N/m): ``k0 + sum k_i s / (s + rate_i)``, ``s = 2 pi i freq``."""
        s = 2j * np.pi * np.asarray(freq, dtype=float)
        return self.k0 + np.sum(np.asarray(self.k) * s[..., None]
                                / (s[..., None] + np.asarray(self.rate)), axis=-1)

    def to_dict(self) -> dict:
        out = {"model": self.MODEL, **asdict(self)}
        out["order"] = len(self.k)
        out["description"] = self.DESCRIPTION
        return out


@dataclass(frozen=True)
class ElastomerTruth(_ElastomerTruth):
    """True elastomer isolator: two generalized-Maxwell halves and an internal mass."""

    k0: float = 13.8e3  # N/m, whole isolator (quasi-static stiffness ~ 1.15 x 12e3)
    k: list[float] = field(default_factory=lambda: [350.0, 600.0, 1300.0, 1700.0, 2600.0,
                                                    5200.0, 4200.0, 3000.0])
    rate: list[float] = field(default_factory=lambda: [3.0, 10.0, 30.0, 90.0, 270.0, 800.0,
                                                       2400.0, 7000.0])
    alpha: float = 0.15  # softening depth in compression
    y_soft: float = 0.010  # m, softening length of the whole isolator
    internal_mass_kg: float = 0.065  # between the halves: internal mode near 200 Hz
    moving_mass_kg: float = 0.10  # elastomer mass moving with the top mass
    mass_kg: float = 0.53

    def half_link(self):
        """Kernel link of one half: every stiffness doubled, softening length halved."""
        scalars = [2.0 * self.k0, self.alpha, 0.5 * self.y_soft]
        return (LINK_ELASTOMER, scalars, [2.0 * v for v in self.k], list(self.rate))

    def chain_links(self):
        """Masses the isolator adds between its links (kg) and its links, top first."""
        return [self.internal_mass_kg], [self.half_link(), self.half_link()]

    def quasi_static_link(self):
        """Link and the share of the isolator's deflection it takes in a slow test: the
        two identical halves in series, inertia negligible, each take half."""
        return self.half_link(), 0.5

    MODEL: ClassVar[str] = "two_maxwell_halves_with_internal_mass"
    DESCRIPTION: ClassVar[str] = (
        "whole-isolator generalized Maxwell k0, k_i, rate_i (1/s) split into two halves in "
        "series (each 2 k0, 2 k_i, same rates) with internal_mass_kg between them; static "
        "spring of a half 2 k0 y (1 - alpha tanh^2(min(y, 0) / (y_soft / 2))); "
        "moving_mass_kg is added to the top mass"
    )


def _spread_slip_elements(order: int) -> tuple[list[float], list[float]]:
    """Slip forces (N) and stiffnesses (N/m) of truth "b"'s Jenkin elements.

    Slip displacements ``delta_i = fc_i / k_i`` are log-spaced from 20 um to 7.5 mm (half the
    largest loop amplitude of SPEC 3, so elements keep slipping across the large loops); the
    slip forces grow as ``delta^0.25`` and total 36 N.
    """
    delta = np.geomspace(20e-6, 7.5e-3, order)
    weight = delta ** 0.25
    fc = np.round(36.0 * weight / weight.sum(), 4)
    k = np.round(fc / delta, 1)
    return [float(v) for v in fc], [float(v) for v in k]


@dataclass(frozen=True)
class ModulatedWireRopeTruth(_RopeTruth):
    """Truth "b" wire rope (module docstring); forces in N, deflection in m.

    ``F = g1 y + g2 y^2 + g3 y^3 + (1 + beta tanh^2(y / y_ref)) sum_i F_i + c_visc ydot``
    with Jenkin forces ``F_i`` of constant slip forces ``fc_i``.
    """

    g1: float = 2.6e4
    g2: float = 2.0e4  # N/m^2: 4.5 N at 15 mm, 1.2 % of g1 y
    g3: float = -4.0e4  # N/m^3: 0.14 N at 15 mm
    c_visc: float = 12.0  # N s/m
    beta: float = 0.4  # hysteretic-force modulation depth
    y_ref: float = 0.006  # m
    fc: list[float] = field(default_factory=lambda: _spread_slip_elements(24)[0])
    k: list[float] = field(default_factory=lambda: _spread_slip_elements(24)[1])
    mass_kg: float = 0.21

    def link(self):
        """Kernel link tuple ``(kind, scalars, k, fc)`` (no bottoming stiffener)."""
        scalars = [self.g1, self.g2, self.g3, self.c_visc, 0.0, 1.0, self.beta, self.y_ref]
        return (LINK_WIRE_ROPE_MODULATED, scalars, list(self.k), list(self.fc))

    MODEL: ClassVar[str] = "iwan_modulated_hysteresis"
    DESCRIPTION: ClassVar[str] = (  # the modulation is 1 at zero deflection: the stuck stiffness is g1 + sum k_i
        "F = g1 y + g2 y^2 + g3 y^3 + (1 + beta tanh^2(y / y_ref)) sum_i F_i + c_visc ydot; "
        "F_i by the stop operator with constant slip force fc_i; "
        "y = deflection (m, positive = tension)"
    )


@dataclass(frozen=True)
class SingleBodyElastomerTruth(_ElastomerTruth):
    """Truth "b" elastomer: one generalized-Maxwell body, no internal mass (no internal mode)."""

    k0: float = 9.0e3  # N/m
    k: list[float] = field(default_factory=lambda: [900.0, 1100.0, 1300.0, 1500.0, 1500.0,
                                                    1300.0, 1100.0])
    rate: list[float] = field(default_factory=lambda: [2.0, 6.3, 20.0, 63.0, 200.0, 630.0,
                                                       2000.0])
    alpha: float = 0.05  # softening depth in compression
    y_soft: float = 0.012  # m
    moving_mass_kg: float = 0.30  # elastomer mass moving with the top mass
    mass_kg: float = 0.75

    def link(self):
        """Kernel link of the whole isolator."""
        return (LINK_ELASTOMER, [self.k0, self.alpha, self.y_soft], list(self.k), list(self.rate))

    def chain_links(self):
        """Masses the isolator adds between its links (none) and its one link."""
        return [], [self.link()]

    def quasi_static_link(self):
        """The one link takes the whole deflection."""
        return self.link(), 1.0

    MODEL: ClassVar[str] = "generalized_maxwell_single_body"
    DESCRIPTION: ClassVar[str] = (
        "generalized Maxwell k0, k_i, rate_i (1/s) of the whole isolator; static spring "
        "k0 y (1 - alpha tanh^2(min(y, 0) / y_soft)); moving_mass_kg is added to the top mass"
    )


def truth_models(name: str = "a"):
    """``(wire_rope, elastomer)`` truths of the named truth (:data:`idkit.synth.names.TRUTH_NAMES`)."""
    if name == "a":
        return default_wire_rope(), default_elastomer()
    if name == "b":
        return ModulatedWireRopeTruth(), SingleBodyElastomerTruth()
    raise ValueError(f"truth: found {name!r}, expected one of {TRUTH_NAMES}")


def default_wire_rope() -> WireRopeTruth:
    """The wire-rope truth of the bundled data."""
    return WireRopeTruth()


def default_elastomer() -> ElastomerTruth:
    """The elastomer truth of the bundled data."""
    return ElastomerTruth()
