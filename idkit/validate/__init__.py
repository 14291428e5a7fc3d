"""Validation of identified models against held-out measurements (issue 5).

Each validator returns a :class:`ValidationResult` with a metrics table, scalar
metrics and pass/fail against documented default thresholds that users can override.
"""

from idkit.validate.blind_spots import PROBES, blind_spots
from idkit.validate.drop import DROP_THRESHOLDS, validate_drops
from idkit.validate.frf import FRF_THRESHOLDS, half_power_damping, model_through_the_estimator, validate_frf
from idkit.validate.harmonic import HARMONIC_THRESHOLDS, validate_harmonic
from idkit.validate.result import ValidationResult, Verdict
from idkit.validate.systems import system_for

__all__ = [
    "ValidationResult", "Verdict", "validate_harmonic", "validate_frf", "validate_drops", "system_for",
    "half_power_damping", "model_through_the_estimator", "HARMONIC_THRESHOLDS", "FRF_THRESHOLDS", "DROP_THRESHOLDS", "blind_spots", "PROBES",
]
