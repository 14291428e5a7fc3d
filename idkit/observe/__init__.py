"""The one place a measurement becomes an observable.

Each module takes the typed measurements of :mod:`idkit.io` and returns what the fitters,
validators, ``idkit inspect`` and the report all read, with the same defaults for everyone:

- :mod:`~idkit.observe.quasi_static` - cycles, amplitudes, small/large classification,
  resampled loops, cycle statistics and offset removal;
- :mod:`~idkit.observe.k0` - the static stiffness read off the loops and the operating point
  under a preload;
- :mod:`~idkit.observe.white_noise` - transmissibility H1/H2 and coherence;
- :mod:`~idkit.observe.stepped_sine` - HOSIDFs of points and sweeps, input report;
- :mod:`~idkit.observe.drop` - impact, impact velocity, shock peaks;
- :mod:`~idkit.observe.shock` - shock records: offset, filtering, pulses, the three SRS, response/input;
- :mod:`~idkit.observe.quality` - overview and data-quality warnings of a set.
"""

from idkit.observe.drop import DropMeasurementResult, process_drop_measurement
from idkit.observe.quality import InspectionWarning, MeasurementSummary, find_clipping, summarize_measurements
from idkit.observe.quasi_static import QuasiStaticResult, process_quasi_static
from idkit.observe.shock import MIN_PRE_TRIGGER_SAMPLES, ConditionedShock, RecordSpectra, ResponseRatio, ShockPulses
from idkit.observe.shock import condition_shock, default_srs_band, record_spectra, response_ratio, shock_pulses
from idkit.observe.stepped_sine import SteppedSinePoint, SteppedSineSweep, hosidf_from_stepped_sine, stepped_sine_sweep
from idkit.observe.white_noise import WhiteNoiseFrf, frf_from_white_noise

__all__ = [
    "DropMeasurementResult", "process_drop_measurement",
    "InspectionWarning", "MeasurementSummary", "find_clipping", "summarize_measurements",
    "QuasiStaticResult", "process_quasi_static",
    "MIN_PRE_TRIGGER_SAMPLES", "ConditionedShock", "RecordSpectra", "ResponseRatio", "ShockPulses", "condition_shock",
    "default_srs_band", "record_spectra", "response_ratio", "shock_pulses",
    "SteppedSinePoint", "SteppedSineSweep", "hosidf_from_stepped_sine", "stepped_sine_sweep",
    "WhiteNoiseFrf", "frf_from_white_noise",
]
