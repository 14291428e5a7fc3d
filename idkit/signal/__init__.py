"""Pure array maths of isolator signals (the role :mod:`scipy.signal` plays for idkit).

Every function takes arrays and returns arrays or a frozen result; nothing here knows a
measurement file, a model or a simulator. One concept per module:

- :mod:`~idkit.signal.cycles` - quasi-static loops: reversals against the noise level, cycles,
  resampling (SPEC 4);
- :mod:`~idkit.signal.harmonics` - stepped sine: harmonics, subharmonic, bias, HOSIDF (SPEC 5); the
  peak of a response, sampled (:func:`resonance_peak`) or searched (:func:`search_resonance`);
- :mod:`~idkit.signal.frf` - white-noise FRF estimators: H1, H2, coherence (SPEC 3);
- :mod:`~idkit.signal.drop` - drop records: impact, shock peaks, peak deflection (SPEC 3, 5);
- :mod:`~idkit.signal.srs` - shock response spectrum (Smallwood filter);
- :mod:`~idkit.signal.psd` - random vibration: PSD profiles, synthesis, Welch, RMS (SPEC 5);
- :mod:`~idkit.signal.shift_factors` - time-temperature superposition: shift factors from
  isotherms, WLF and polynomial laws, checks of given shift factors.
"""

from idkit.signal.cycles import (
    classify_amplitudes,
    CycleSplit,
    find_reversals,
    noise_level,
    resample_loops,
    ResampledLoops,
    reversal_threshold,
    split_cycles,
)
from idkit.signal.harmonics import (
    fit_harmonics,
    HarmonicFit,
    hosidf,
    HosidfResult,
    input_flatness,
    InputFlatness,
    resonance_peak,
    ResonanceSearch,
    search_resonance,
)
from idkit.signal.frf import (
    estimate_frf,
    FrfEstimate,
    mean_squared_relative_error,
)
from idkit.signal.drop import (
    drop_phase_peaks,
    DropResult,
    impact_velocity_from_height,
    PhasePeaks,
    process_drop,
    STANDARD_GRAVITY,
    zero_phase_moving_average,
)
from idkit.signal.srs import (
    MIN_SAMPLES_PER_PERIOD,
    relative_displacement_coefficients,
    shock_response_spectrum,
    shock_spectra,
    ShockResponseSpectrum,
    ShockSpectra,
    smallwood_coefficients,
)
from idkit.signal.psd import (
    cumulative_rms,
    output_psd,
    PsdEstimate,
    PsdProfile,
    rms_from_psd,
    synthesize_random,
    welch_psd,
)
from idkit.signal.shift_factors import (
    compare_shift_factors,
    estimate_shift_factors,
    fit_shift_polynomial,
    fit_wlf,
    ShiftFactorCheck,
    ShiftFactorEstimate,
    ShiftLawFit,
)

__all__ = [
    "classify_amplitudes",
    "compare_shift_factors",
    "cumulative_rms",
    "CycleSplit",
    "drop_phase_peaks",
    "DropResult",
    "estimate_frf",
    "estimate_shift_factors",
    "find_reversals",
    "fit_harmonics",
    "fit_shift_polynomial",
    "fit_wlf",
    "FrfEstimate",
    "HarmonicFit",
    "hosidf",
    "HosidfResult",
    "impact_velocity_from_height",
    "input_flatness",
    "InputFlatness",
    "mean_squared_relative_error",
    "MIN_SAMPLES_PER_PERIOD",
    "noise_level",
    "output_psd",
    "PhasePeaks",
    "process_drop",
    "PsdEstimate",
    "PsdProfile",
    "relative_displacement_coefficients",
    "resample_loops",
    "ResampledLoops",
    "resonance_peak",
    "ResonanceSearch",
    "reversal_threshold",
    "rms_from_psd",
    "ShiftFactorCheck",
    "ShiftFactorEstimate",
    "ShiftLawFit",
    "shock_response_spectrum",
    "shock_spectra",
    "ShockResponseSpectrum",
    "ShockSpectra",
    "search_resonance",
    "smallwood_coefficients",
    "split_cycles",
    "STANDARD_GRAVITY",
    "synthesize_random",
    "welch_psd",
    "zero_phase_moving_average",
]
