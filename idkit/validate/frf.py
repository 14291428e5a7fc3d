"""White-noise validation: model transmissibility vs measured H1 per held-out mass."""

from __future__ import annotations

import dataclasses

import numpy as np
import pandas as pd

from idkit.errors import DataError, ValidationError
from idkit.io import WhiteNoiseMeasurement
from idkit.signal.frf import half_power_damping, mean_squared_relative_error
from idkit.models.maxwell import preloaded
from idkit.observe.white_noise import FRF_RESOLUTION_HZ, frf_from_white_noise
from idkit.validate.records import RECORD_METRIC, departures
from idkit.validate.result import ValidationResult, check_thresholds
from idkit.validate.systems import system_for

__all__ = ["validate_frf", "FRF_THRESHOLDS", "half_power_damping", "model_through_the_estimator"]

#: Default limits: the error (7.5) of the worst measurement (RMS of |H_model - H_meas| /
#: |H_meas| over the band, a fraction), the largest relative error of the resonance
#: frequency, and the median over the measurements of ``|20 log10(zeta_model / zeta_measured)|``,
#: the damping ratios read from the -3 dB width. The peak of a lightly damped resonance
#: scales as ``1 / zeta``, so 3 dB is the harmonic validation's peak limit
#: (``max_peak_magnitude_error_db``); the median because a single half-power reading on a
#: grid of 0.25-0.5 Hz scatters by 10-20 % (on the bundled elastomer one of eight masses read
#: 0.082 where its neighbours read 0.087-0.095 on the 0.25 Hz grid).
#: ``records_beyond_limit``: runs beyond their own limit (the worst-run limits per run; a run's
#: damping error in dB up to the median limit outside 0 to the median of the runs nearest in top
#: mass, at least two, :func:`idkit.validate.records.departures`).
FRF_THRESHOLDS = {"max_frf_error": 0.15, "max_resonance_frequency_error": 0.05, "median_damping_ratio_error_db": 3.0,
                  RECORD_METRIC: 0}


def model_through_the_estimator(measurement: WhiteNoiseMeasurement, frf, transmissibility, *, band,
                                resolution_hz: float) -> np.ndarray:
    """The model's H1 read by the same estimator as the measured one.

    The measured base signal of ``frf`` (velocity or acceleration) is filtered by the
    model's ``transmissibility(freq_hz)`` over the whole record (FFT, so the record is
    taken as one period: the model's transient from the unknown history before the record
    is missing for about one decay time, ``1 / (zeta omega)``, 0.2 s at 10 Hz and zeta = 0.09),
    and the pair goes through :func:`~idkit.observe.white_noise.frf_from_white_noise` with
    the same band, resolution and segments. Both curves then carry the same Hann-window
    bias: a resonance of half-power width ``B_r`` read with a resolution bandwidth ``B_e``
    loses about ``(B_e / B_r)^2 / 3`` of its peak (on 4 s records, 1 Hz segments, a 2 Hz wide
    resonance reads 0.15 for a true damping ratio of 0.09). Compared with the exact model
    curve, a model right to the last digit would fail the damping check there.
    """
    base_name, top_name = ("v_base", "v_top") if frf.signals == "velocity" else ("a_base", "a_top")
    base = np.asarray(getattr(measurement, base_name), dtype=float)
    fs = float(f"{measurement.sample_rate_hz:.10g}")
    freq = np.fft.rfftfreq(base.size, 1.0 / fs)
    top = np.fft.irfft(np.asarray(transmissibility(freq)) * np.fft.rfft(base), base.size)
    simulated = dataclasses.replace(measurement, **{top_name: top})
    return frf_from_white_noise(simulated, band=band, resolution_hz=resolution_hz, signals=frf.signals).estimate.h1


def validate_frf(measurements, *, system=None, isolator=None, band=(1.0, 100.0),
                 resolution_hz: float = FRF_RESOLUTION_HZ, thresholds: dict | None = None,
                 name: str = "white-noise FRF", static_stiffness=None) -> ValidationResult:
    """Error (7.5) and resonance/damping per held-out white-noise measurement.

    Parameters
    ----------
    measurements : iterable of WhiteNoiseMeasurement
        The held-out runs.
    system, isolator :
        The model to validate (:func:`idkit.validate.systems.system_for`).
    band : (float, float), default (1, 100)
        Band compared, Hz.
    resolution_hz : float, default :data:`~idkit.observe.white_noise.FRF_RESOLUTION_HZ`
        Frequency step of the measured H1: the one estimate of a white-noise run,
        :func:`idkit.observe.white_noise.frf_from_white_noise` (top over base velocity,
        acceleration when there are no velocities); by default the very H1 the Maxwell fit
        uses.
    thresholds : dict, optional
        Overrides of :data:`FRF_THRESHOLDS`.
    name : str
    static_stiffness : callable, optional
        ``static_stiffness(top_mass_kg)`` -> the isolator's tangent static stiffness (N/m)
        under that top mass's weight, or None (e.g.
        :meth:`idkit.fit.ElastomerData.static_stiffness`, read off the loops). A Maxwell
        ``isolator`` is then compared about that preload
        (:meth:`~idkit.models.GeneralizedMaxwell.preloaded`), as its fit was.

    Each run is also judged on its own (:mod:`idkit.validate.records`): its FRF error and
    resonance error against the worst-run limits, and its damping error ``20 log10(zeta_model /
    zeta_measured)`` up to the median limit outside the interval between 0 and the median of the
    (at least two) runs nearest in top mass (with fewer runs the damping is judged only by the
    median); a run beyond is counted in ``records_beyond_limit`` (limit 0) and named in
    :attr:`ValidationResult.record_failures`.

    Returns
    -------
    ValidationResult
        ``metrics`` one row per measurement, ``details["curves"]`` the measured and model
        curves.

    Raises
    ------
    ValidationError
        No measurement, a measurement that is not a white-noise run or gives no usable H1.
    """
    limits = check_thresholds(FRF_THRESHOLDS, thresholds)
    measurements = list(measurements)
    if not measurements:
        raise ValidationError(f"{name}: no white-noise measurements given")
    rows, curves = [], {}
    for measurement in measurements:
        if not isinstance(measurement, WhiteNoiseMeasurement):
            raise ValidationError(f"{name}: found {type(measurement).__name__}, expected WhiteNoiseMeasurement")
        info = measurement.info
        where = info.id or str(measurement.source.path)
        try:
            frf = frf_from_white_noise(measurement, band=band, resolution_hz=resolution_hz)
            if static_stiffness is not None and isolator is not None:
                local = preloaded(isolator, static_stiffness(info.top_mass_kg))
            else:
                local = isolator
            model = system_for(measurement, system=system, isolator=local)
            predicted = model_through_the_estimator(measurement, frf, model.transmissibility, band=band,
                                                    resolution_hz=resolution_hz)
        except DataError as problem:
            raise ValidationError(f"{where}: {problem}") from None
        estimate = frf.estimate
        if np.any(np.abs(estimate.h1) == 0) or not np.all(np.isfinite(estimate.h1)):
            raise ValidationError(f"{where}: measured H1 has zero or non-finite values in the band")
        error = float(np.sqrt(mean_squared_relative_error(predicted, estimate.h1)))
        f_meas, zeta_meas = half_power_damping(estimate.freq, np.abs(estimate.h1))
        f_model, zeta_model = half_power_damping(estimate.freq, np.abs(predicted))
        rows.append({"id": info.id, "top mass [kg]": info.top_mass_kg, "repetition": info.repetition,
                     "frf error [-]": error, "resonance measured [Hz]": f_meas, "resonance model [Hz]": f_model,
                     "resonance error [-]": f_model / f_meas - 1, "damping ratio measured [-]": zeta_meas,
                     "damping ratio model [-]": zeta_model, "damping ratio error [-]": zeta_model / zeta_meas - 1,
                     "mean coherence [-]": float(estimate.coherence.mean())})
        curves[info.id] = pd.DataFrame({"freq [Hz]": estimate.freq, "H1 measured": estimate.h1,
                                        "H model": predicted, "H model exact": model.transmissibility(estimate.freq),
                                        "coherence": estimate.coherence})
    table = pd.DataFrame(rows)
    table["damping error [dB]"] = 20 * np.log10(table["damping ratio model [-]"].to_numpy(float)
                                                / table["damping ratio measured [-]"].to_numpy(float))
    failures, beyond = _record_checks(table, limits)
    summary = {
        "max_frf_error": float(table["frf error [-]"].max()),
        "mean_frf_error": float(table["frf error [-]"].mean()),
        "max_resonance_frequency_error": float(table["resonance error [-]"].abs().max()),
        # NaN (not measurable: INCONCLUSIVE) only when no measurement shows both half-power points
        "median_damping_ratio_error_db": float(np.nanmedian(np.abs(20 * np.log10(
            table["damping ratio model [-]"] / table["damping ratio measured [-]"]))))
        if table[["damping ratio model [-]", "damping ratio measured [-]"]].notna().all(axis=1).any() else np.nan,
        RECORD_METRIC: int(beyond.sum()),
    }
    return ValidationResult(name=name, metrics=table, summary=summary, thresholds=limits, details={"curves": curves},
                            record_failures=failures)


def _record_checks(table: pd.DataFrame, limits: dict) -> tuple[tuple[str, ...], np.ndarray]:
    """Each run against its own limits: FRF and resonance errors against the worst-run limits, the
    damping error's departure from 0 to the other runs' median against the median limit. Adds the
    limits, the departure and ``record verdict`` to ``table``; returns the lines naming the runs
    beyond and the mask of those runs."""
    failures = []
    beyond = np.zeros(len(table), dtype=bool)
    judged = np.zeros(len(table), dtype=bool)
    frf_limit, resonance_limit = limits["max_frf_error"], limits["max_resonance_frequency_error"]
    damping_limit = limits["median_damping_ratio_error_db"]
    # siblings: the runs nearest in top mass (at least two; with fewer the damping is judged only by the median)
    departure, sibling_median = departures(table["damping error [dB]"].to_numpy(float),
                                           coordinate=table["top mass [kg]"].to_numpy(float))
    table["frf error limit [-]"] = frf_limit
    table["resonance error limit [-]"] = resonance_limit
    table["damping departure [dB]"] = departure
    table["damping departure limit [dB]"] = damping_limit
    for index in range(len(table)):
        frf_error, resonance_error = table["frf error [-]"].iloc[index], table["resonance error [-]"].iloc[index]
        judged[index] = np.isfinite(frf_error) or np.isfinite(resonance_error) or np.isfinite(departure[index])
        lines = []
        if frf_error > frf_limit:
            lines.append(f"FRF error {frf_error:.3f} > {frf_limit:g}")
        if abs(resonance_error) > resonance_limit:
            lines.append(f"resonance error {resonance_error:+.3f} beyond {resonance_limit:g}")
        if departure[index] > damping_limit:
            lines.append(f"damping error {table['damping error [dB]'].iloc[index]:+.1f} dB lies "
                         f"{departure[index]:.1f} dB outside 0 to the nearest runs' median "
                         f"{sibling_median[index]:+.1f} dB (limit {damping_limit:g} dB)")
        if lines:
            beyond[index] = True
            failures.append(f"{table['id'].iloc[index]}: " + "; ".join(lines))
    table["record verdict"] = np.where(beyond, "FAIL", np.where(judged, "ok", ""))
    return tuple(failures), beyond
