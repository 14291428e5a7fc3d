"""The one place a measurement becomes an observable.

Each module takes the typed measurements of :mod:`idkit.io` and returns what the fitters,
validators, ``idkit inspect`` and the report all read, with the same defaults for everyone:

- :mod:`~idkit.observe.quasi_static` - cycles, amplitudes, small/large classification and
  resampled loops;
- :mod:`~idkit.observe.white_noise` - transmissibility H1/H2 and coherence;
- :mod:`~idkit.observe.stepped_sine` - HOSIDFs of points and sweeps, input report;
- :mod:`~idkit.observe.drop` - impact, impact velocity, shock peaks;
- :mod:`~idkit.observe.shock` - shock records: offset, filtering, pulses, the three SRS, response/input;
- :mod:`~idkit.observe.quality` - overview and data-quality warnings of a set.
"""

from idkit.observe.quasi_static import (
    process_quasi_static,
    QuasiStaticResult,
)
from idkit.observe.white_noise import (
    frf_from_white_noise,
    WhiteNoiseFrf,
)
from idkit.observe.stepped_sine import (
    hosidf_from_stepped_sine,
    stepped_sine_sweep,
    SteppedSinePoint,
    SteppedSineSweep,
)
from idkit.observe.drop import (
    DropMeasurementResult,
    process_drop_measurement,
)
from idkit.observe.quality import (
    find_clipping,
    InspectionWarning,
    MeasurementSummary,
    summarize_measurements,
)

from idkit.observe.shock import (
    ConditionedShock,
    RecordSpectra,
    ResponseRatio,
    ShockPulses,
    condition_shock,
    default_srs_band,
    record_spectra,
    response_ratio,
    shock_pulses,
    MIN_PRE_TRIGGER_SAMPLES,
)

__all__ = [
    "ConditionedShock",
    "RecordSpectra",
    "ResponseRatio",
    "ShockPulses",
    "condition_shock",
    "default_srs_band",
    "record_spectra",
    "response_ratio",
    "shock_pulses",
    "MIN_PRE_TRIGGER_SAMPLES",
    "DropMeasurementResult",
    "find_clipping",
    "frf_from_white_noise",
    "hosidf_from_stepped_sine",
    "InspectionWarning",
    "MeasurementSummary",
    "process_drop_measurement",
    "process_quasi_static",
    "QuasiStaticResult",
    "stepped_sine_sweep",
    "SteppedSinePoint",
    "SteppedSineSweep",
    "summarize_measurements",
    "WhiteNoiseFrf",
]
