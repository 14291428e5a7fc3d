"""White-noise validation: model transmissibility vs measured H1 per held-out mass."""

from __future__ import annotations

import numpy as np
import pandas as pd

from idkit.signal.frf import estimate_frf
from idkit.errors import ValidationError
from idkit.validate.result import ValidationResult, check_thresholds
from idkit.validate.systems import system_for

__all__ = ["validate_frf", "FRF_THRESHOLDS", "half_power_damping"]

#: Default limits: the largest per-mass error (7.5) (RMS of |H_model - H_meas| / |H_meas| over
#: the band, as a fraction) and the largest relative error of the resonance frequency.
#: Default limits: the error (7.5) of the worst measurement, the largest relative error of
#: the resonance frequency, and the median over the measurements of
#: ``|20 log10(zeta_model / zeta_measured)|``, the damping ratios read from the -3 dB
#: width. The peak of a lightly damped resonance scales as ``1 / zeta``, so 3 dB is the
#: harmonic validation's peak limit (``max_peak_magnitude_error_db``); the median because a
#: single half-power reading on a 0.25 Hz grid scatters by 10-20 % (on the bundled elastomer
#: one of eight masses read 0.082 where its neighbours read 0.087-0.095).
FRF_THRESHOLDS = {"max_frf_error": 0.15, "max_resonance_frequency_error": 0.05, "median_damping_ratio_error_db": 3.0}


def half_power_damping(freq: np.ndarray, magnitude: np.ndarray) -> tuple[float, float]:
    """Resonance frequency (Hz) and damping ratio from the -3 dB width ``(f2 - f1) / (2 f_r)``.

    The half-power points are interpolated linearly; NaN when the band does not contain them.
    """
    index = int(np.argmax(magnitude))
    level = magnitude[index] / np.sqrt(2.0)
    below = np.flatnonzero(magnitude[:index] < level)
    above = np.flatnonzero(magnitude[index:] < level)
    if below.size == 0 or above.size == 0:
        return float(freq[index]), np.nan
    i1 = below[-1]
    f1 = np.interp(level, [magnitude[i1], magnitude[i1 + 1]], [freq[i1], freq[i1 + 1]])
    i2 = index + above[0]
    f2 = np.interp(level, [magnitude[i2], magnitude[i2 - 1]], [freq[i2], freq[i2 - 1]])
    return float(freq[index]), float((f2 - f1) / (2.0 * freq[index]))


def validate_frf(measurements, *, system=None, isolator=None, band=(1.0, 100.0), resolution: float = 0.25,
                 thresholds: dict | None = None, name: str = "white-noise FRF") -> ValidationResult:
    """Error (7.5) and resonance/damping per held-out white-noise measurement.

    H1 = S_xy / S_xx of top over base velocity (Welch, Hann, 50 % overlap,
    segments of ``1 / resolution`` s, see :func:`idkit.signal.frf.estimate_frf`),
    compared over ``band`` (Hz) with the model's small-amplitude transmissibility.
    """
    limits = check_thresholds(FRF_THRESHOLDS, thresholds)
    measurements = list(measurements)
    if not measurements:
        raise ValidationError(f"{name}: no white-noise measurements given")
    rows, curves = [], {}
    for measurement in measurements:
        info = measurement.info
        where = info.id or str(measurement.source.path)
        if measurement.v_base is None or measurement.v_top is None:
            raise ValidationError(f"{where}: v_base and v_top are needed for the transmissibility")
        fs = 1.0 / float(np.median(np.diff(measurement.time)))
        nperseg = int(min(2 ** np.ceil(np.log2(fs / resolution)), measurement.time.size // 4))
        estimate = estimate_frf(measurement.v_base, measurement.v_top, fs=fs, nperseg=nperseg,
                                f_lo=band[0], f_hi=band[1])
        model = system_for(measurement, system=system, isolator=isolator)
        predicted = model.transmissibility(estimate.freq)
        if np.any(np.abs(estimate.h1) == 0) or not np.all(np.isfinite(estimate.h1)):
            raise ValidationError(f"{where}: measured H1 has zero or non-finite values in the band")
        error = float(np.sqrt(np.mean(np.abs(predicted - estimate.h1) ** 2 / np.abs(estimate.h1) ** 2)))
        f_meas, zeta_meas = half_power_damping(estimate.freq, np.abs(estimate.h1))
        f_model, zeta_model = half_power_damping(estimate.freq, np.abs(predicted))
        rows.append({"id": info.id, "top mass [kg]": info.top_mass_kg, "repetition": info.repetition,
                     "frf error [-]": error, "resonance measured [Hz]": f_meas, "resonance model [Hz]": f_model,
                     "resonance error [-]": f_model / f_meas - 1, "damping ratio measured [-]": zeta_meas,
                     "damping ratio model [-]": zeta_model, "damping ratio error [-]": zeta_model / zeta_meas - 1,
                     "mean coherence [-]": float(estimate.coherence.mean())})
        curves[info.id] = pd.DataFrame({"freq [Hz]": estimate.freq, "H1 measured": estimate.h1,
                                        "H model": predicted, "coherence": estimate.coherence})
    table = pd.DataFrame(rows)
    summary = {
        "max_frf_error": float(table["frf error [-]"].max()),
        "mean_frf_error": float(table["frf error [-]"].mean()),
        "max_resonance_frequency_error": float(table["resonance error [-]"].abs().max()),
        # NaN (not measurable: INCONCLUSIVE) only when no measurement shows both half-power points
        "median_damping_ratio_error_db": float(np.nanmedian(np.abs(20 * np.log10(
            table["damping ratio model [-]"] / table["damping ratio measured [-]"]))))
        if table[["damping ratio model [-]", "damping ratio measured [-]"]].notna().all(axis=1).any() else np.nan,
    }
    return ValidationResult(name=name, metrics=table, summary=summary, thresholds=limits, details={"curves": curves})
