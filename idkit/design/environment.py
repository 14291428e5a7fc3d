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

from dataclasses import dataclass, field
from pathlib import Path

from idkit.checks import Field, Instance, Real, Reals, Text, check_fields, field_names, refuse
from idkit.errors import DataError
from idkit.gravity import STANDARD_GRAVITY
from idkit.inputfiles import load_json, read_input_bytes
from idkit.signal.psd import _BREAKPOINTS, _LEVELS, PsdProfile

__all__ = ["DROP_LIMITS", "LIMIT_KEYS", "Environment", "load_environment"]

_OBJECT = Instance((dict,), what="an object")
#: The keys of the document.
_TOP = (Field("floor_psd", Instance((list,), what="a list of profiles")),
        Field("drops", Instance((dict,), what="an object with heights_m or impact_velocity_m_per_s")),
        Field("limits", Instance((dict,), what="an object of limits")), Field("name", Text()))
#: A breakpoint profile, and a flat level over a band (``f_lo < f_hi`` is checked by hand).
_BREAKPOINT_PROFILE = (Field("name", Text()), Field("freq_hz", _BREAKPOINTS, required=True),
                       Field("level", _LEVELS, required=True))
_FLAT_PROFILE = (Field("name", Text()), Field("flat", Real(unit="(m/s^2)^2/Hz", gt=0), required=True),
                 Field("f_lo", Real(unit="Hz", gt=0), required=True),
                 Field("f_hi", Real(unit="Hz", gt=0), required=True))
#: The drops, as heights or as impact speeds |v0| (one of the two).
_DROPS = (Field("heights_m", Reals(unit="m", gt=0)), Field("impact_velocity_m_per_s", Reals(unit="m/s", gt=0)))
#: The limits an environment may set (every one optional).
_LIMITS = (
    Field("rms_acceleration_m_per_s2", Real(unit="m/s^2", gt=0, meaning="payload RMS under each floor PSD")),
    Field("peak_acceleration_m_per_s2", Real(unit="m/s^2", gt=0, meaning="payload peak under the drops")),
    Field("max_deflection_m", Real(unit="m", gt=0, meaning="isolator travel under the drops")),
    Field("max_component_deflection_m", Real(unit="m", gt=0, meaning="each hybrid component's travel")),
    Field("max_dissipated_energy_j", Real(unit="J", gt=0, meaning="energy one mount dissipates in a drop")),
    Field("max_component_dissipated_energy_j", Real(unit="J", gt=0, meaning="each hybrid component's own")),
    Field("resonance_band_hz", Reals(unit="Hz", gt=0, min_size=2, max_size=2, increasing=True,
                                     meaning="[f_low, f_high] the first resonance must avoid")),
    Field("probability", Real(gt=0, lt=1, meaning="required probability of meeting every limit")),
)

#: Limits an environment may set and their units.
LIMIT_KEYS = {item.name: item.spec.unit for item in _LIMITS}

#: Limits judged on the drops.
DROP_LIMITS = ("peak_acceleration_m_per_s2", "max_deflection_m", "max_component_deflection_m",
               "max_dissipated_energy_j", "max_component_dissipated_energy_j")


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
        top = check_fields(_OBJECT.check(document, where, DataError), _TOP, where)
        profiles = {}
        for index, entry in enumerate(top.get("floor_psd", [])):
            label = f"{where}: floor_psd[{index}]"
            entry = _OBJECT.check(entry, label, DataError)
            if "flat" in entry:
                flat = check_fields(entry, _FLAT_PROFILE, label)
                if not flat["f_lo"] < flat["f_hi"]:
                    raise DataError(f"{label}: f_lo, f_hi: found {flat['f_lo']:g}, {flat['f_hi']:g}, expected "
                                    "f_lo < f_hi (Hz)")
                profile = PsdProfile.flat(flat["flat"], f_lo=flat["f_lo"], f_hi=flat["f_hi"])
            else:
                points = check_fields(entry, _BREAKPOINT_PROFILE, label, known=field_names(_FLAT_PROFILE))
                if points["freq_hz"].size != points["level"].size:
                    raise DataError(f"{label}: level: found {points['level'].size} values, expected "
                                    f"{points['freq_hz'].size} (one per freq_hz breakpoint)")
                profile = PsdProfile(points["freq_hz"], points["level"])
            profiles[entry.get("name", f"profile {index + 1}")] = profile
        drops = check_fields(top.get("drops", {}), _DROPS, f"{where}: drops")
        if len(drops) > 1:
            raise DataError(f"{where}: drops: found {sorted(drops)}, expected one of heights_m or "
                            "impact_velocity_m_per_s")
        heights: tuple = ()
        for key, values in drops.items():
            if values.ndim != 1:
                raise refuse(f"{where}: drops: {key}", values, "a list of numbers > 0", DataError)
            heights = tuple(float(v) if key == "heights_m" else float(v) ** 2 / (2.0 * STANDARD_GRAVITY)
                            for v in values)
        limits = check_fields(top.get("limits", {}), _LIMITS, f"{where}: limits")
        if not limits:
            raise DataError(f"{where}: limits: found none, expected at least one of {', '.join(LIMIT_KEYS)}")
        if "resonance_band_hz" in limits:
            limits["resonance_band_hz"] = [float(v) for v in limits["resonance_band_hz"]]
        if "rms_acceleration_m_per_s2" in limits and not profiles:
            raise DataError(f"{where}: limits.rms_acceleration_m_per_s2 needs floor_psd profiles; found none")
        needs_drops = set(DROP_LIMITS) & set(limits)
        if needs_drops and not heights:
            raise DataError(f"{where}: limits {sorted(needs_drops)} need drops; found none")
        return cls(profiles=profiles, drop_heights_m=heights, limits=limits, name=top.get("name", ""))


def load_environment(path) -> Environment:
    """Read and check an environment file (module docstring)."""
    path = Path(path)
    label = f"environment file '{path}'"  # read as strictly as every input file (idkit.inputfiles)
    document = load_json(read_input_bytes(path, label, DataError), label, DataError,
                         expected="an environment JSON object (floor_psd, drops, limits)")
    return Environment.from_dict(document, where=str(path))
