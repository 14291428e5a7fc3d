"""The transport-tool systems of SPEC 6 (thesis chapter 8), tuned to one resonance.

Every system is tuned to a small-amplitude resonance at ``target_freq`` (5 Hz):

* reference: viscous mass-spring-damper, m = 15.0 kg, zeta = 0.07;
* elastomer: the identified elastomer; moving mass (top mass plus the isolator's
  ``m_eff``) from ``|k*(5 Hz)| = m (2 pi 5)^2``;
* wire rope: the identified wire rope; mass from the stuck stiffness ``g1 + sum k_i``;
* hybrids: wire rope unchanged; elastomer stiffnesses scaled so that
  ``r_k = g1 / |k*_el(5 Hz)|`` takes each requested value; moving top mass from the
  magnitude of the series stiffness at 5 Hz; intermediate mass 1 % of the top mass.

Choice (the study is silent): the rule fixes the *moving* mass, so the elastomer's
``m_eff`` is subtracted to get the top mass; the resonance is then exactly at 5 Hz.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.errors import ParameterError
from idkit.models import GeneralizedMaxwell, HybridSystem, IwanModel, SDOFSystem, VoigtModel, library

__all__ = ["TransportSystem", "transport_systems", "RK_VALUES", "tuning_table"]

RK_VALUES = (0.1, 0.2, 0.4, 0.6, 0.8, 1.0, 1.25)


@dataclass(frozen=True)
class TransportSystem:
    """One tuned system of the study: a name, its kind, the system and the tuning numbers."""

    name: str
    kind: str  # "reference", "elastomer", "wire_rope", "hybrid"
    system: SDOFSystem | HybridSystem
    stiffness_at_target: float  # N/m, magnitude used by the tuning rule
    r_k: float | None = None


def _omega(target_freq: float) -> float:
    if not (np.isfinite(target_freq) and target_freq > 0):
        raise ParameterError(f"target_freq: found {target_freq!r}, expected a positive frequency in Hz")
    return 2.0 * np.pi * float(target_freq)


def transport_systems(*, wire_rope: IwanModel | None = None, elastomer: GeneralizedMaxwell | None = None,
                      target_freq: float = 5.0, reference_mass: float = 15.0, reference_damping_ratio: float = 0.07,
                      r_k_values=RK_VALUES, intermediate_fraction: float = 0.01) -> list[TransportSystem]:
    """Build the reference, elastomer, wire-rope and hybrid systems tuned to ``target_freq`` (Hz).

    Defaults: the identified parts of the study (Table 7.1 wire rope, Table 7.3 elastomer).
    """
    wire_rope = wire_rope if wire_rope is not None else library.get("table_7_1_wire_rope")
    elastomer = elastomer if elastomer is not None else library.get("table_7_3_elastomer")
    omega = _omega(target_freq)
    systems = []

    stiffness = reference_mass * omega**2
    damping = 2.0 * reference_damping_ratio * np.sqrt(stiffness * reference_mass)
    systems.append(TransportSystem("reference", "reference",
                                   SDOFSystem(reference_mass, VoigtModel(k=stiffness, damping=damping)), stiffness))

    k_elastomer = float(abs(elastomer.complex_stiffness(target_freq)))
    moving = k_elastomer / omega**2
    systems.append(TransportSystem("elastomer", "elastomer", SDOFSystem(_top_mass(moving, elastomer), elastomer),
                                   k_elastomer))

    k_stuck = wire_rope.stuck_stiffness
    systems.append(TransportSystem("wire rope", "wire_rope", SDOFSystem(k_stuck / omega**2, wire_rope), k_stuck))

    for r_k in r_k_values:
        if not (np.isfinite(r_k) and r_k > 0):
            raise ParameterError(f"r_k: found {r_k!r}, expected positive ratios g1 / |k*_el|")
        scaled = elastomer.scaled(wire_rope.g1 / (r_k * k_elastomer))
        series = float(abs(1.0 / (1.0 / scaled.complex_stiffness(target_freq)
                                   + 1.0 / wire_rope.small_amplitude_stiffness(target_freq))))
        moving = series / omega**2
        top = _top_mass(moving, scaled)
        systems.append(TransportSystem(f"hybrid r_k={r_k:g}", "hybrid",
                                       HybridSystem(top, scaled, intermediate_fraction * top, wire_rope), series,
                                       float(r_k)))
    return systems


def _top_mass(moving_mass: float, isolator) -> float:
    top = moving_mass - isolator.m_eff
    if top <= 0:
        raise ParameterError(
            f"tuning: the moving mass {moving_mass:.4g} kg is below the isolator's m_eff {isolator.m_eff:.4g} kg"
        )
    return top


def tuning_table(systems: list[TransportSystem], target_freq: float = 5.0) -> pd.DataFrame:
    """Masses and tuning checks of the study systems (one row each).

    Columns: ``moving mass [kg]``, the mass the thesis prints for each system (top mass plus
    the elastomer's ``m_eff``, the mass the tuning rule fixes: 101, 65.4, 38.4, 27.2, 21.1,
    17.2, 14.0 kg for the hybrids, 218 kg wire rope, 15.4 kg elastomer);
    ``top mass without m_eff [kg]``, the rigid top mass alone (what the simulator's
    ``SDOFSystem.mass`` / ``HybridSystem.mass`` holds); ``intermediate mass [kg]``;
    ``stiffness at target [N/m]``; ``r_k [-]`` requested and, for the hybrids, achieved.
    """
    rows = []
    for item in systems:
        system = item.system
        masses = system.masses
        row = {"system": item.name, "moving mass [kg]": masses[0], "top mass without m_eff [kg]": system.mass,
               "intermediate mass [kg]": getattr(system, "intermediate_mass", np.nan),
               "stiffness at target [N/m]": item.stiffness_at_target, "r_k [-]": item.r_k}
        if item.kind == "hybrid":
            elastomer_k = abs(system.upper.complex_stiffness(target_freq))
            row["r_k achieved [-]"] = system.lower.g1 / elastomer_k
        rows.append(row)
    return pd.DataFrame(rows)
