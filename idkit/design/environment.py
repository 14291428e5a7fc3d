"""The environment a design must survive, and the limits it must meet (``ENV.json``).

Document (SI units; every key named below, nothing else)::

    {
      "floor_psd": [                       # random floor vibration, one or more profiles
        {"name": "truck", "freq_hz": [1, 10, 100], "level": [1e-3, 1e-3, 1e-4]},
        {"name": "flat 1e-4", "flat": 1e-4, "f_lo": 0.1, "f_hi": 100.0}
      ],
      "drops": {"heights_m": [0.02, 0.05, 0.1]},      # or {"impact_velocity_m_per_s": [...]} (|v0|)
      "limits": {
        "rms_acceleration_m_per_s2": 0.5,   # payload RMS under each floor PSD
        "peak_acceleration_m_per_s2": 60,   # payload peak under the drops (rest shock level)
        "max_deflection_m": 0.02,           # sway space: isolator travel under the drops
        "max_component_deflection_m": 0.015,  # hybrid: each component's own travel
        "max_dissipated_energy_j": 2.0,     # energy one mount's isolator dissipates in a drop
        "max_component_dissipated_energy_j": 1.5,  # hybrid: each component's own
        "resonance_band_hz": [2.5, 4.0],    # the first (small-amplitude) resonance must avoid it
        "probability": 0.9                  # required probability of meeting every limit
      }
    }

``floor_psd`` profiles are breakpoint tables ``(freq_hz, level)`` in (m/s^2)^2/Hz, log-log
interpolated (:class:`idkit.signal.psd.PsdProfile`, the transport study's format), or flat
levels over a band (``PsdProfile.flat``, SPEC 5). Every limit is optional; at least one must
be given. Deflection limits are judged on the drops (their travel far exceeds the
vibration's). The energy limits cap what one mount's isolator (all of a hybrid) and each of a
hybrid's components dissipate in the worst drop, over the simulated time (four small-amplitude
periods; :mod:`idkit.simulate.parameter_sets`): the heat or wear a part must take per shock,
a rating a maker gives (thesis 9.2 names "the energy dissipation of the isolator and its
components" as a design criterion beside their deflections).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from pathlib import Path

from idkit.errors import DataError
from idkit.signal.psd import PsdProfile

__all__ = ["DROP_LIMITS", "LIMIT_KEYS", "Environment", "load_environment"]

#: Limits an environment may set and their units.
LIMIT_KEYS = {
    "rms_acceleration_m_per_s2": "m/s^2", "peak_acceleration_m_per_s2": "m/s^2", "max_deflection_m": "m",
    "max_component_deflection_m": "m", "max_dissipated_energy_j": "J", "max_component_dissipated_energy_j": "J",
    "resonance_band_hz": "Hz", "probability": "-",
}
#: Limits judged on the drops.
DROP_LIMITS = ("peak_acceleration_m_per_s2", "max_deflection_m", "max_component_deflection_m",
               "max_dissipated_energy_j", "max_component_dissipated_energy_j")
_TOP_KEYS = {"floor_psd", "drops", "limits", "name"}


@dataclass(frozen=True)
class Environment:
    """Floor PSDs, drops and limits (module docstring).

    Attributes
    ----------
    profiles : dict of str -> PsdProfile
    drop_heights_m : tuple of float
        Drop heights (``v0 = -sqrt(2 g h)``); impact speeds given are converted.
    limits : dict
        The limits set (keys of :data:`LIMIT_KEYS`); ``probability`` defaults to 0.9.
    name : str
    """

    profiles: dict = field(default_factory=dict)
    drop_heights_m: tuple = ()
    limits: dict = field(default_factory=dict)
    name: str = ""

    @property
    def probability(self) -> float:
        """Required probability of meeting every limit."""
        return float(self.limits.get("probability", 0.9))

    def to_dict(self) -> dict:
        """JSON-ready document (breakpoint form)."""
        return {"name": self.name,
                "floor_psd": [{"name": key, "freq_hz": p.freq.tolist(), "level": p.level.tolist()}
                              for key, p in self.profiles.items()],
                "drops": {"heights_m": list(self.drop_heights_m)}, "limits": dict(self.limits)}

    @classmethod
    def from_dict(cls, document: dict, *, where: str = "environment") -> Environment:
        """Check and build from a document (module docstring); errors name ``where`` and the key."""
        if not isinstance(document, dict):
            raise DataError(f"{where}: found {type(document).__name__}, expected an object")
        unknown = sorted(set(document) - _TOP_KEYS)
        if unknown:
            raise DataError(f"{where}: unknown key(s) {unknown}; expected keys from {sorted(_TOP_KEYS)}")
        profiles = {}
        entries = document.get("floor_psd", [])
        if not isinstance(entries, list):
            raise DataError(f"{where}: floor_psd: found {type(entries).__name__}, expected a list of profiles")
        for index, entry in enumerate(entries):
            label = f"{where}: floor_psd[{index}]"
            if not isinstance(entry, dict):
                raise DataError(f"{label}: found {type(entry).__name__}, expected an object")
            name = str(entry.get("name", f"profile {index + 1}"))
            if "flat" in entry:
                values = [entry.get(key) for key in ("flat", "f_lo", "f_hi")]
                if not all(_positive(v) for v in values) or not values[1] < values[2]:
                    raise DataError(f"{label}: flat, f_lo, f_hi: found {values}, expected a level > 0 "
                                    "((m/s^2)^2/Hz) over 0 < f_lo < f_hi (Hz)")
                profiles[name] = PsdProfile.flat(float(values[0]), f_lo=float(values[1]), f_hi=float(values[2]))
            else:
                try:
                    profiles[name] = PsdProfile(entry["freq_hz"], entry["level"])
                except KeyError as missing:
                    raise DataError(f"{label}: missing {missing.args[0]!r}; expected freq_hz and level "
                                    "(breakpoints, Hz and (m/s^2)^2/Hz) or flat, f_lo, f_hi") from None
                except (DataError, ValueError, TypeError) as problem:
                    raise DataError(f"{label}: {problem}") from None
        drops = document.get("drops", {})
        if not isinstance(drops, dict) or len(drops) > 1 or (drops and not set(drops) <= {
                "heights_m", "impact_velocity_m_per_s"}):
            raise DataError(f"{where}: drops: found {drops!r:.80}, expected {{'heights_m': [...]}} or "
                            "{'impact_velocity_m_per_s': [...]} (|v0|)")
        heights: tuple = ()
        for key, values in drops.items():
            if not isinstance(values, list) or not values or not all(_positive(v) for v in values):
                raise DataError(f"{where}: drops.{key}: found {values!r:.80}, expected a non-empty list of positive "
                                "numbers")
            heights = tuple(float(v) if key == "heights_m" else float(v) ** 2 / (2.0 * 9.80665) for v in values)
        limits = document.get("limits", {})
        if not isinstance(limits, dict) or not limits:
            raise DataError(f"{where}: limits: found {limits!r:.80}, expected an object with at least one of "
                            f"{sorted(LIMIT_KEYS)}")
        unknown = sorted(set(limits) - set(LIMIT_KEYS))
        if unknown:
            raise DataError(f"{where}: limits: unknown key(s) {unknown}; expected keys from {sorted(LIMIT_KEYS)}")
        for key, value in limits.items():
            if key == "resonance_band_hz":
                if not (isinstance(value, list) and len(value) == 2 and all(_positive(v) for v in value)
                        and value[0] < value[1]):
                    raise DataError(f"{where}: limits.resonance_band_hz: found {value!r}, expected [f_low, f_high] "
                                    "with 0 < f_low < f_high (Hz)")
            elif key == "probability":
                if not (_positive(value) and value < 1):
                    raise DataError(f"{where}: limits.probability: found {value!r}, expected a probability in (0, 1)")
            elif not _positive(value):
                raise DataError(f"{where}: limits.{key}: found {value!r}, expected a positive number "
                                f"({LIMIT_KEYS[key]})")
        if "rms_acceleration_m_per_s2" in limits and not profiles:
            raise DataError(f"{where}: limits.rms_acceleration_m_per_s2 needs floor_psd profiles; found none")
        needs_drops = set(DROP_LIMITS) & set(limits)
        if needs_drops and not heights:
            raise DataError(f"{where}: limits {sorted(needs_drops)} need drops; found none")
        return cls(profiles=profiles, drop_heights_m=heights, limits=dict(limits), name=str(document.get("name", "")))


def _positive(value) -> bool:
    return (not isinstance(value, bool) and isinstance(value, (int, float)) and math.isfinite(value) and value > 0)


def load_environment(path) -> Environment:
    """Read and check an environment file (module docstring)."""
    path = Path(path)
    try:
        document = json.loads(path.read_text())
    except FileNotFoundError:
        raise DataError(f"{path}: not found; expected an environment JSON file") from None
    except (json.JSONDecodeError, UnicodeDecodeError) as problem:
        raise DataError(f"{path}: not valid JSON ({problem})") from None
    return Environment.from_dict(document, where=str(path))
