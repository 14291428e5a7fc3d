"""Drop-test validation: measured vs simulated shock peaks versus impact velocity."""

from __future__ import annotations

import numpy as np
import pandas as pd

from idkit.signal.drop import process_drop
from idkit.errors import ValidationError
from idkit.responses.shock import shock_sweep
from idkit.validate.result import ValidationResult, check_thresholds
from idkit.validate.systems import system_for

__all__ = ["validate_drops", "DROP_THRESHOLDS"]

#: Default limits on the median relative errors over the drops the model could simulate,
#: and on the fraction of drops that left the model's valid range (flagged runs).
DROP_THRESHOLDS = {
    "median_peak_acceleration_error": 0.25,
    "median_peak_compression_error": 0.25,
    "invalid_run_fraction": 0.0,
}


def validate_drops(measurements, *, system=None, isolator=None, upper=None, lower=None, relaxation: bool = False,
                   impact_velocity: str = "height", duration: float | None = None, thresholds: dict | None = None,
                   name: str = "drop tests", workers=None) -> ValidationResult:
    """Compare peak accelerations (compression, tension) and peak compression per drop.

    Each drop is processed (mean of the accelerometers, zero-phase 5-sample average,
    impact from the relative-velocity step, see :func:`idkit.signal.drop.process_drop`);
    the model is dropped by :func:`idkit.responses.shock.shock_sweep` (conditioned free
    fall, base fixed, its automatic time grid unless ``duration`` is given) at the impact
    velocity ``-sqrt(2 g h)`` from the drop height (``impact_velocity="height"``, the
    thesis's reading, eq. 3.18) or at the one measured from the relative-velocity step
    (``"measured"``; it includes the bounce and the oscillation of the fall), with
    ``relaxation`` adding the initial elongation of :func:`idkit.simulate.relaxation_deflection`.
    Measured and simulated records are reduced by the same rule
    (:func:`idkit.signal.drop.drop_phase_peaks`): compression while the top mass is below its
    position at impact relative to the base (for a hybrid, the deflection summed over both
    isolators, which is what the rig measures).

    Drops of the same system (same masses) are simulated in one batch.
    """
    if impact_velocity not in ("height", "measured"):
        raise ValidationError(f"impact_velocity: found {impact_velocity!r}, expected 'height' or 'measured'")
    limits = check_thresholds(DROP_THRESHOLDS, thresholds)
    measurements = list(measurements)
    if not measurements:
        raise ValidationError(f"{name}: no drop measurements given")
    processed, groups = [], {}
    for index, measurement in enumerate(measurements):
        info = measurement.info
        result = process_drop(measurement.time, measurement.deflection,
                              np.vstack([measurement.a_top_1, measurement.a_top_2]),
                              relative_velocity=measurement.v_rel, drop_height=info.drop_height_m)
        processed.append(result)
        if impact_velocity == "height" and info.drop_height_m is not None:
            velocity = result.impact_velocity_from_height
        else:
            velocity = result.impact_velocity
        key = (info.top_mass_kg, info.intermediate_mass_kg) if system is None else None
        if key not in groups:
            model = system_for(measurement, system=system, isolator=isolator, upper=upper, lower=lower)
            groups[key] = (model, [], [])
        groups[key][1].append(index)
        groups[key][2].append(velocity)
    simulated = [None] * len(measurements)
    for model, indices, velocities in groups.values():
        sweep = shock_sweep(model, impact_velocity=velocities, duration=duration, relaxation=relaxation,
                            workers=workers)
        for position, index in enumerate(indices):
            simulated[index] = (sweep, position)
    rows = []
    for measurement, result, (sweep, k) in zip(measurements, processed, simulated):
        info = measurement.info
        rows.append({
            "id": info.id, "top mass [kg]": info.top_mass_kg, "drop height [m]": info.drop_height_m,
            "impact velocity measured [m/s]": result.impact_velocity,
            "impact velocity from height [m/s]": result.impact_velocity_from_height,
            "impact velocity simulated [m/s]": float(sweep.impact_velocity[k]),
            "peak accel compression measured [m/s^2]": result.peak_acceleration_compression,
            "peak accel compression simulated [m/s^2]": float(sweep.peak_acceleration_compression[k]),
            "peak accel tension measured [m/s^2]": result.peak_acceleration_tension,
            "peak accel tension simulated [m/s^2]": float(sweep.peak_acceleration_tension[k]),
            "peak compression measured [m]": result.max_compression,
            "peak compression simulated [m]": float(sweep.travel_compression[k]),
            "status": sweep.reasons[k],
        })
    table = pd.DataFrame(rows)
    # rest shock level: the larger phase peak (a phase that never occurred is NaN and ignored)
    measured_peak = np.fmax(table["peak accel compression measured [m/s^2]"],
                            table["peak accel tension measured [m/s^2]"])
    simulated_peak = np.fmax(table["peak accel compression simulated [m/s^2]"],
                             table["peak accel tension simulated [m/s^2]"])
    table["peak acceleration error [-]"] = simulated_peak / measured_peak - 1
    table["peak compression error [-]"] = (table["peak compression simulated [m]"]
                                           / table["peak compression measured [m]"] - 1)
    valid = table["status"] == "ok"
    table.loc[~valid, ["peak acceleration error [-]", "peak compression error [-]"]] = np.nan

    def median_abs(column):
        values = np.abs(table.loc[valid, column].to_numpy(float))
        return float(np.median(values)) if values.size else np.nan

    summary = {
        "median_peak_acceleration_error": median_abs("peak acceleration error [-]"),
        "median_peak_compression_error": median_abs("peak compression error [-]"),
        "max_peak_acceleration_error": float(np.nanmax(np.abs(table["peak acceleration error [-]"])))
        if valid.any() else np.nan,
        "invalid_run_fraction": float(1.0 - valid.mean()),
        "relaxation": bool(relaxation),
        "impact_velocity": impact_velocity,
    }
    by_height = table.groupby(["top mass [kg]", "drop height [m]"])[
        ["peak acceleration error [-]", "peak compression error [-]"]].mean().reset_index()
    return ValidationResult(name=name, metrics=table, summary=summary, thresholds=limits,
                            details={"by_height": by_height})
