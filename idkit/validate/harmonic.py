"""Harmonic-sweep validation: simulated vs measured first-order HOSIDF (thesis appendix F)."""

from __future__ import annotations

import numpy as np
import pandas as pd

from idkit.errors import DataError, ValidationError
from idkit.observe.stepped_sine import hosidf_from_stepped_sine
from idkit.signal.harmonics import resonance_peak
from idkit.simulate import harmonic_response
from idkit.simulate._kernel import FLAG_OK
from idkit.validate.records import RECORD_METRIC, phase_floor_deg, sweep_point_envelope
from idkit.checks import accepts
from idkit.validate.result import IDENTIFIED_RANGE, ValidationResult, check_thresholds, checked_identified_range
from idkit.validate.systems import system_for

__all__ = ["validate_harmonic", "HARMONIC_THRESHOLDS", "MAX_UNSETTLED_FRACTION"]

#: Largest share of measured points whose simulation may fail to reach steady state
#: (or go invalid) before the verdict is INCONCLUSIVE: such points are left out of
#: every metric, so none may be missing from a PASS (the unsettled points of a lightly damped
#: isolator lie near its resonance, where the verdict matters most).
MAX_UNSETTLED_FRACTION = 0.0

#: Standard errors of a point's measured H1 (from the residuals of its harmonic fits) added to its
#: own magnitude and phase limits: by noise alone one of 100 points exceeds 4 of them with a
#: chance of 0.6 % (normal errors).
NOISE_STANDARD_ERRORS = 4.0

#: Default limits: RMS of 20 log10(|H1 sim| / |H1 meas|) over the grid (dB), the largest
#: relative error of the resonance frequency per amplitude level, and of the peak magnitude;
#: the fraction of points the simulator flagged (the model left its valid range at a
#: measured point: it cannot be simulated where the data were taken), as for the drops; and
#: ``records_beyond_limit``: settled points beyond their own magnitude or phase limit
#: (:func:`idkit.validate.records.sweep_point_envelope`).
HARMONIC_THRESHOLDS = {
    "rms_log_magnitude_error_db": 2.0,
    "max_resonance_frequency_error": 0.10,
    "max_peak_magnitude_error_db": 3.0,
    "invalid_run_fraction": 0.0,
    RECORD_METRIC: 0,
}


@accepts(identified_range=IDENTIFIED_RANGE, error=ValidationError)
def validate_harmonic(measurements, *, system=None, isolator=None, upper=None, lower=None, n_harmonics: int = 3,
                      thresholds: dict | None = None, tolerance: float = 1e-3, max_periods: int = 4000, workers=None,
                      name: str = "harmonic sweep", identified_range=None) -> ValidationResult:
    """Compare the simulated and measured first-order HOSIDF over the measured grid.

    Each measured point is reduced to the first harmonic of the base velocity
    and of the top velocity (least squares over whole periods); the simulation is
    driven by a pure sine with the measured first-harmonic base amplitude (the
    measured distortion is reported, not reproduced). Points are grouped into
    amplitude levels by their nominal excitation amplitude.

    A simulated point that does not reach a valid steady state (its status is not
    ``"ok"``) is left out of every metric and counted in ``points_not_converged``;
    with any point left out (:data:`MAX_UNSETTLED_FRACTION` = 0) the verdict is
    INCONCLUSIVE, never PASS (FAIL when a metric of the settled points fails). A point the simulator flagged (the model left its valid
    range there) also counts in ``invalid_run_fraction``, limit 0: a model that cannot be
    simulated at a measured point FAILs, as in :func:`~idkit.validate.validate_drops`.

    Each settled point is also judged on its own (:mod:`idkit.validate.records`): its magnitude
    error may reach the RMS limit plus, and its phase error ``asin(10^(RMS limit / 20) - 1)``
    (15 degrees) plus, what a model the aggregate limits accept may differ there (resonance moved
    by up to ``max_resonance_frequency_error``, damping by up to ``max_peak_magnitude_error_db``:
    :func:`~idkit.validate.records.sweep_point_envelope`; near a lightly damped resonance that
    allows almost any phase), plus :data:`NOISE_STANDARD_ERRORS` standard errors of its measured
    H1 (column ``H1 measured relative standard error [-]``). A point beyond is counted in
    ``records_beyond_limit`` (limit 0) and named in :attr:`ValidationResult.record_failures`; the
    table gives each point's limits and ``record verdict``.

    Parameters
    ----------
    measurements : sequence of SteppedSineMeasurement
        Held-out stepped-sine points (each needs ``info.excitation.freq`` and the masses).
    system, isolator, upper, lower :
        The model: a whole system, one isolator (SDOF with the measured top mass) or
        the two hybrid components (see :func:`idkit.validate.systems.system_for`).
    thresholds : dict, optional
        Overrides of :data:`HARMONIC_THRESHOLDS`.
    tolerance, max_periods :
        Steady-state criterion and period limit of :func:`idkit.simulate.harmonic_response`.
    identified_range : (float, float), optional
        Smallest and largest deflection amplitude (m) of the loops the isolator model was
        identified on (:meth:`idkit.observe.quasi_static.LoopData.amplitude_range`); only with
        ``isolator=`` (the deflection is then the isolator's). An amplitude level whose
        largest measured deflection amplitude ``|H1 - 1| x base amplitude`` (at its resonance,
        which the level's metrics judge) lies outside it is named in
        :attr:`ValidationResult.notes` with its resonance error: the model is extrapolated
        there, which the verdict alone does not say.
    """
    limits = check_thresholds(HARMONIC_THRESHOLDS, thresholds)
    identified_range = checked_identified_range(identified_range, isolator)
    measurements = list(measurements)
    if not measurements:
        raise ValidationError(f"{name}: no stepped-sine measurements given")
    rows = []
    for measurement in measurements:
        info = measurement.info
        if info.excitation is None or info.excitation.freq is None:
            raise ValidationError(f"{info.id or measurement.source.path}: excitation frequency missing")
        freq = info.excitation.freq
        try:  # the one stepped-sine point -> HOSIDF of idkit.observe (harmonics kept below Nyquist)
            point = hosidf_from_stepped_sine(measurement, n_harmonics=n_harmonics, subharmonic=False).result
        except DataError as problem:
            raise ValidationError(f"{info.id or measurement.source.path}: {problem}") from None
        base_velocity = point.input_amplitude
        rows.append({
            "id": info.id, "freq [Hz]": freq,
            "level": info.excitation.amplitude if info.excitation.amplitude is not None else np.nan,
            "base velocity amplitude [m/s]": base_velocity,
            "base amplitude [m]": base_velocity / (2 * np.pi * freq),
            "input distortion h2 [-]": point.input_distortion[0],
            "input distortion h3 [-]": point.input_distortion[1],
            "H1 measured": complex(point.hosidf[0]),
            # standard error of H1 over |H1| from the two harmonic fits' residuals (white residual)
            "H1 measured relative standard error [-]": float(np.hypot(
                point.input.standard_error / np.abs(point.input.coefficients[0]),
                point.output.standard_error / np.abs(point.output.coefficients[0]))),
            "_system": system_for(measurement, system=system, isolator=isolator, upper=upper, lower=lower),
        })
    table = pd.DataFrame(rows)
    simulated = np.empty(len(table), dtype=complex)
    converged = np.zeros(len(table), dtype=bool)
    flagged = np.zeros(len(table), dtype=bool)
    status = [""] * len(table)
    # one batch per distinct system (masses may differ between points)
    keys = [repr(item) for item in table["_system"]]
    for key in dict.fromkeys(keys):
        members = [index for index, other in enumerate(keys) if other == key]
        response = harmonic_response(table["_system"].iloc[members[0]], table["freq [Hz]"].to_numpy()[members],
                                     table["base amplitude [m]"].to_numpy()[members], n_harmonics=n_harmonics,
                                     tolerance=tolerance, max_periods=max_periods, workers=workers)
        simulated[members] = response.hosidf(1)
        converged[members] = response.converged
        flagged[members] = response.flags != FLAG_OK
        for member, reason in zip(members, response.reasons):
            status[member] = reason
    table = table.drop(columns="_system")
    table["H1 simulated"] = simulated
    table["|H1| measured [-]"] = np.abs(table["H1 measured"].to_numpy(complex))
    table["|H1| simulated [-]"] = np.abs(simulated)
    table["magnitude error [dB]"] = 20 * np.log10(table["|H1| simulated [-]"] / table["|H1| measured [-]"])
    table["phase error [deg]"] = np.degrees(np.angle(simulated / table["H1 measured"].to_numpy(complex)))
    # the isolator's deflection as measured (first harmonic of top minus base): what the level probes
    table["deflection amplitude measured [m]"] = (np.abs(table["H1 measured"].to_numpy(complex) - 1.0)
                                                  * table["base amplitude [m]"].to_numpy(float))
    table["converged"] = converged
    table["status"] = status
    if table["level"].isna().all():
        # no nominal levels: group by the measured base velocity rounded to 2 significant digits
        table["level"] = [float(f"{value:.1e}") for value in table["base velocity amplitude [m/s]"]]
    settled = table[table["converged"]]  # an unsettled point has no steady state to compare

    resonance_rows = []
    for level, group in settled.groupby("level"):
        if len(group) < 3:
            continue
        f_meas, peak_meas = resonance_peak(group["freq [Hz]"].to_numpy(), group["|H1| measured [-]"].to_numpy())
        f_sim, peak_sim = resonance_peak(group["freq [Hz]"].to_numpy(), group["|H1| simulated [-]"].to_numpy())
        resonance_rows.append({
            "level": level, "resonance measured [Hz]": f_meas, "resonance simulated [Hz]": f_sim,
            "resonance error [-]": f_sim / f_meas - 1, "peak measured [-]": peak_meas,
            "peak simulated [-]": peak_sim, "peak error [dB]": 20 * np.log10(peak_sim / peak_meas),
        })
    resonance = pd.DataFrame(resonance_rows)
    failures = _record_checks(table, limits)
    errors = settled["magnitude error [dB]"].to_numpy()
    unsettled = int((~converged).sum())
    summary = {
        "rms_log_magnitude_error_db": (np.nan if errors.size == 0 else float(np.sqrt(np.mean(errors**2)))
                                       if np.all(np.isfinite(errors)) else np.inf),
        "max_resonance_frequency_error": float(np.max(np.abs(resonance["resonance error [-]"])))
        if len(resonance) else np.nan,
        "max_peak_magnitude_error_db": float(np.max(np.abs(resonance["peak error [dB]"]))) if len(resonance) else np.nan,
        "rms_phase_error_deg": float(np.sqrt(np.mean(settled["phase error [deg]"] ** 2))) if len(settled) else np.nan,
        "max_input_distortion": float(table[["input distortion h2 [-]", "input distortion h3 [-]"]].to_numpy().max()),
        "points_not_converged": unsettled,
        "invalid_run_fraction": float(flagged.mean()),
        RECORD_METRIC: len(failures),
    }
    inconclusive = ()
    if unsettled > MAX_UNSETTLED_FRACTION * len(table):
        causes = sorted({status[i].split(" (")[0] for i in np.flatnonzero(~converged)})
        inconclusive = (f"{unsettled} of {len(table)} simulated points did not reach a valid steady state "
                        f"(limit {MAX_UNSETTLED_FRACTION:.0%}; {'; '.join(causes)}); they are left out of "
                        "every metric",)
    notes = () if identified_range is None else _outside_notes(table, resonance, identified_range)
    return ValidationResult(name=name, metrics=table, summary=summary, thresholds=limits,
                            details={"resonance": resonance}, inconclusive=inconclusive, notes=notes,
                            record_failures=failures)


def _record_checks(table: pd.DataFrame, limits: dict) -> tuple[str, ...]:
    """Each settled point against its own magnitude and phase limits (columns added to ``table``,
    with ``record verdict``); the lines naming the points beyond."""
    settled = table["converged"].to_numpy(bool)
    model = np.where(settled, table["H1 simulated"].to_numpy(complex), np.nan)
    tolerance, peak_db = limits["max_resonance_frequency_error"], limits["max_peak_magnitude_error_db"]
    phase_envelope, magnitude_envelope = sweep_point_envelope(
        table["freq [Hz]"].to_numpy(float), table["level"].to_numpy(), model, frequency_tolerance=tolerance,
        peak_tolerance_db=peak_db)
    rms_limit = limits["rms_log_magnitude_error_db"]
    floor = phase_floor_deg(rms_limit)
    # the record's own noise: NOISE_STANDARD_ERRORS standard errors of its H1 (relative: radians of
    # phase, 20 / ln 10 dB per unit of magnitude)
    relative_error = NOISE_STANDARD_ERRORS * table["H1 measured relative standard error [-]"].to_numpy(float)
    noise_phase, noise_magnitude = np.degrees(relative_error), 20 / np.log(10) * relative_error
    table["magnitude error limit [dB]"] = rms_limit + magnitude_envelope + noise_magnitude
    table["phase error limit [deg]"] = floor + phase_envelope + noise_phase
    magnitude = table["magnitude error [dB]"].to_numpy(float)
    phase = table["phase error [deg]"].to_numpy(float)
    judged = settled & np.isfinite(phase_envelope)
    allowance = (f"a resonance moved by {tolerance:.0%} and a peak {peak_db:g} dB off allow there, plus")
    failures, verdicts = [], []
    for index in range(len(table)):
        if not judged[index]:
            verdicts.append("")
            continue
        lines = []
        magnitude_limit = table["magnitude error limit [dB]"].iloc[index]
        if not abs(magnitude[index]) <= magnitude_limit:  # an infinite error too
            lines.append(f"magnitude error {magnitude[index]:+.2f} dB beyond {magnitude_limit:.2f} dB "
                         f"({magnitude_envelope[index]:.2f} dB {allowance} the RMS limit {rms_limit:g} dB "
                         f"and {noise_magnitude[index]:.2f} dB of noise)")
        phase_limit = table["phase error limit [deg]"].iloc[index]
        if abs(phase[index]) > phase_limit:
            lines.append(f"phase error {phase[index]:+.0f} deg beyond {phase_limit:.0f} deg "
                         f"({phase_envelope[index]:.0f} deg {allowance} {floor:.0f} deg and "
                         f"{noise_phase[index]:.0f} deg of noise)")
        verdicts.append("FAIL" if lines else "ok")
        if lines:
            failures.append(f"{table['id'].iloc[index]} ({table['freq [Hz]'].iloc[index]:g} Hz, level "
                            f"{table['level'].iloc[index]:g}): " + "; ".join(lines))
    table["record verdict"] = verdicts
    return tuple(failures)


def _outside_notes(table: pd.DataFrame, resonance: pd.DataFrame, identified_range) -> tuple[str, ...]:
    """One note for the levels below and one for those above the identified deflection range."""
    smallest, largest = identified_range
    errors = dict(zip(resonance["level"], resonance["resonance error [-]"])) if len(resonance) else {}
    below, above, inside = [], [], []
    for level, group in table.groupby("level"):
        amplitudes = group["deflection amplitude measured [m]"].to_numpy(float)
        amplitudes = amplitudes[np.isfinite(amplitudes)]
        if amplitudes.size == 0:
            continue
        # the largest deflection of a level is at its resonance, which the level's metrics judge
        entry = (level, amplitudes.max(), errors.get(level, np.nan))
        (below if entry[1] < smallest else above if entry[1] > largest else inside).append(entry)

    def listed(entries):
        words = [f"{level:g} (largest deflection amplitude {1e3 * largest_here:.3g} mm"
                 + (f", resonance error {100 * error:+.1f} %)" if np.isfinite(error) else ")")
                 for level, largest_here, error in entries]
        return ("levels " if len(entries) > 1 else "level ") + ", ".join(words) + (" lie" if len(entries) > 1
                                                                                   else " lies")

    finite = [abs(error) for *_, error in inside if np.isfinite(error)]
    inside_words = (f"; at the levels inside the identified range the largest resonance error is "
                    f"{100 * max(finite):.1f} %" if finite else "")
    notes = []
    if below:
        notes.append(f"{listed(below)} below the smallest loop amplitude the model was identified on "
                     f"({1e3 * smallest:.3g} mm): there the model is extrapolated, and loops at these amplitudes "
                     f"would identify it{inside_words}")
    if above:
        notes.append(f"{listed(above)} above the largest loop amplitude the model was identified on "
                     f"({1e3 * largest:.3g} mm): there the model is extrapolated{inside_words}")
    return tuple(notes)
