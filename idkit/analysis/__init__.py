"""Array-level signal processing of isolator measurements and simulations.

Pure numpy/scipy functions (no plotting), one concept per module:

- :mod:`~idkit.analysis.cycles` - quasi-static loops: reversals, cycles, resampling (SPEC 4);
- :mod:`~idkit.analysis.harmonics` - stepped sine: harmonics, subharmonic, bias, HOSIDF (SPEC 5);
- :mod:`~idkit.analysis.frf` - white-noise FRF: H1, H2, coherence (SPEC 3);
- :mod:`~idkit.analysis.drop` - drop tests: impact, shock peaks, peak deflection (SPEC 3, 5);
- :mod:`~idkit.analysis.srs` - shock response spectrum (Smallwood filter);
- :mod:`~idkit.analysis.psd` - random vibration: PSD profiles, synthesis, Welch, RMS (SPEC 5).

Model responses (these import :mod:`idkit.models` and :mod:`idkit.simulate`):

- :mod:`~idkit.analysis.harmonic_map` - frequency-amplitude maps of steady states, HOSIDF (SPEC 5);
- :mod:`~idkit.analysis.linear` - complex stiffness, loss factor, transmissibility, damping ratios;
- :mod:`~idkit.analysis.shock` - conditioned free-fall sweeps, rest shock level, SRS;
- :mod:`~idkit.analysis.random_vibration` - random floor vibration, output PSDs.
"""

from idkit.analysis.cycles import (
    CycleSplit,
    ResampledLoops,
    classify_amplitudes,
    find_reversals,
    resample_loops,
    split_cycles,
)
from idkit.analysis.drop import (
    STANDARD_GRAVITY,
    DropResult,
    impact_velocity_from_height,
    process_drop,
    zero_phase_moving_average,
)
from idkit.analysis.frf import FrfEstimate, estimate_frf
from idkit.analysis.harmonic_map import HarmonicMap, harmonic_map, parabolic_peak
from idkit.analysis.harmonics import (
    HarmonicFit,
    HosidfResult,
    InputFlatness,
    fit_harmonics,
    hosidf,
    input_flatness,
)
from idkit.analysis.linear import (
    LinearFrf,
    LinearResonance,
    StiffnessResponse,
    complex_stiffness,
    effective_stiffness,
    linear_frf,
    linear_resonance,
    loss_factor,
    stiffness_response,
)
from idkit.analysis.psd import (
    PsdEstimate,
    PsdProfile,
    cumulative_rms,
    output_psd,
    rms_from_psd,
    synthesize_random,
    welch_psd,
)
from idkit.analysis.random_vibration import (
    FLAT_LEVELS,
    RandomResponse,
    flat_input_psds,
    is_linear_system,
    linear_output_psd,
    random_response,
)
from idkit.analysis.shock import ShockSweep, default_shock_grid, shock_sweep
from idkit.analysis.srs import (
    ShockResponseSpectrum,
    shock_response_spectrum,
    smallwood_coefficients,
)

from idkit.analysis.measurements import (
    DropMeasurementResult,
    InspectionWarning,
    MeasurementSummary,
    QuasiStaticResult,
    SteppedSinePoint,
    SteppedSineSweep,
    WhiteNoiseFrf,
    find_clipping,
    frf_from_white_noise,
    hosidf_from_stepped_sine,
    noise_level,
    process_drop_measurement,
    process_quasi_static,
    stepped_sine_sweep,
    summarize_measurements,
)
from idkit.analysis.transport import RK_VALUES, TransportSystem, transport_systems, tuning_table

__all__ = [
    "FLAT_LEVELS",
    "HarmonicMap",
    "LinearFrf",
    "LinearResonance",
    "RandomResponse",
    "ShockSweep",
    "StiffnessResponse",
    "complex_stiffness",
    "default_shock_grid",
    "effective_stiffness",
    "flat_input_psds",
    "harmonic_map",
    "is_linear_system",
    "linear_frf",
    "linear_output_psd",
    "linear_resonance",
    "loss_factor",
    "parabolic_peak",
    "random_response",
    "shock_sweep",
    "stiffness_response",
    "STANDARD_GRAVITY",
    "CycleSplit",
    "DropResult",
    "FrfEstimate",
    "HarmonicFit",
    "HosidfResult",
    "InputFlatness",
    "PsdEstimate",
    "PsdProfile",
    "ResampledLoops",
    "ShockResponseSpectrum",
    "classify_amplitudes",
    "cumulative_rms",
    "estimate_frf",
    "find_reversals",
    "fit_harmonics",
    "hosidf",
    "impact_velocity_from_height",
    "input_flatness",
    "output_psd",
    "process_drop",
    "resample_loops",
    "rms_from_psd",
    "shock_response_spectrum",
    "smallwood_coefficients",
    "split_cycles",
    "synthesize_random",
    "welch_psd",
    "zero_phase_moving_average",
    "DropMeasurementResult",
    "InspectionWarning",
    "MeasurementSummary",
    "QuasiStaticResult",
    "SteppedSinePoint",
    "SteppedSineSweep",
    "WhiteNoiseFrf",
    "find_clipping",
    "frf_from_white_noise",
    "hosidf_from_stepped_sine",
    "noise_level",
    "process_drop_measurement",
    "process_quasi_static",
    "stepped_sine_sweep",
    "summarize_measurements",
    "RK_VALUES",
    "TransportSystem",
    "transport_systems",
    "tuning_table",
]
