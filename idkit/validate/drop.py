"""Drop-test validation: measured vs simulated shock peaks versus impact velocity."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.errors import ValidationError
from idkit.responses.shock import shock_sweep
from idkit.signal.drop import process_drop
from idkit.simulate import DEFAULT_CONTACT, ContactModel, contact_from_velocity_step
from idkit.validate.records import MIN_SIBLINGS, RECORD_METRIC, departures
from idkit.checks import Choice, Flag, accepts
from idkit.validate.result import IDENTIFIED_RANGE, ValidationResult, check_thresholds, checked_identified_range
from idkit.validate.systems import system_for

__all__ = ["DROP_MODELS", "DROP_THRESHOLDS", "validate_drops"]

#: Drop models: the thesis's conditioned free fall, the rig (:func:`idkit.simulate.drop_rig`), or
#: "auto": the rig when every measurement gives its bottom mass and drop height, else conditioned.
DROP_MODELS = ("auto", "conditioned", "rig")

#: Default limits on the median relative errors over the drops the model could simulate,
#: on the fraction of drops that left the model's valid range (flagged runs), and on the
#: number of drops beyond their own limit: a drop's error may lie up to the median limit
#: outside the interval between 0 and the median error of its nearest siblings (drops of the same
#: top mass nearest in drop height, :func:`idkit.validate.records.departures`).
DROP_THRESHOLDS = {
    "median_peak_acceleration_error": 0.25,
    "median_peak_compression_error": 0.25,
    "invalid_run_fraction": 0.0,
    RECORD_METRIC: 0,
}

#: The per-drop errors judged one drop at a time, with the median limit that bounds each.
_PER_DROP = (("peak acceleration", "median_peak_acceleration_error"),
             ("peak compression", "median_peak_compression_error"))


@dataclass(frozen=True)
class _Simulated:
    impact_velocity: float
    compression_acceleration: float
    tension_acceleration: float
    compression: float
    status: str


@accepts(relaxation=Flag(), impact_velocity=Choice(("height", "velocity_step", "measured")),
         drop_model=Choice(DROP_MODELS), identified_range=IDENTIFIED_RANGE, error=ValidationError)
def validate_drops(measurements, *, system=None, isolator=None, upper=None, lower=None, relaxation: bool = False,
                   impact_velocity: str = "height", duration: float | None = None, thresholds: dict | None = None,
                   name: str = "drop tests", workers=None, drop_model: str = "auto",
                   contact: ContactModel | str = "measured", identified_range=None) -> ValidationResult:
    """Compare peak accelerations (compression, tension) and peak compression per drop.

    ``drop_model="rig"`` drops the model as the rig does (:func:`idkit.simulate.drop_rig`):
    top (and intermediate) mass, isolator(s) and the bottom mass of each measurement
    (``info.bottom_mass_kg``) released from the statically loaded rest state at the drop height,
    the bottom mass on a unilateral floor ``contact``: ``"measured"`` (default) reads the
    restitution off each group's measured relative-velocity steps
    (:func:`idkit.simulate.contact_from_velocity_step`, median over the drops) with the default
    stiffness, or give a :class:`~idkit.simulate.ContactModel`. The simulated record is reduced by
    the same phase rule from its first floor contact (``impact_velocity`` and ``relaxation`` are
    then not used: the fall itself sets both). ``"conditioned"`` is the thesis's free fall from
    impact. The default ``"auto"`` takes the rig when every measurement gives
    ``bottom_mass_kg`` and ``drop_height_m`` (the rig's own masses and fall, docs/validation.md),
    else the conditioned fall;
    ``relaxation=True`` or ``impact_velocity="measured"`` ask for the conditioned reading and
    keep it. The summary says which model was used (``drop_model``) and, for the rig, the contact.

    Column names say what each quantity is: ``relative velocity step [m/s]`` is the most
    negative smoothed relative velocity of the first stroke (what
    :attr:`idkit.signal.drop.DropResult.impact_velocity` holds; it includes the bottom mass's
    rebound, so it reads up to ``(1 + e)`` times the impact speed), ``impact velocity from
    height [m/s]`` is ``-sqrt(2 g h)``; ``impact_velocity="measured"`` (alias
    ``"velocity_step"``) starts the conditioned fall at the former.

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

    ``identified_range`` (smallest and largest loop amplitude the isolator model was identified
    on, m; only with ``isolator=``): the drops whose measured peak compression lies outside it
    are counted in :attr:`ValidationResult.notes` with their median peak acceleration error
    against the drops inside: the model is extrapolated there, which the verdict alone does
    not say.

    Each drop is also judged on its own (:mod:`idkit.validate.records`): its peak acceleration
    and peak compression errors may lie up to the median limit outside the interval between 0 and
    the median error of its siblings, the drops of the same top mass nearest in drop height (at
    least two: the model's error at that condition, which they share); a drop beyond is counted
    in ``records_beyond_limit`` (limit 0) and named in :attr:`ValidationResult.record_failures`.
    A drop with fewer than two siblings is not judged alone (counted in the notes). The table
    gives each drop's ``... departure [-]``, its limit and ``record verdict``.
    """
    if impact_velocity == "velocity_step":
        impact_velocity = "measured"
    measurements = list(measurements)
    if drop_model == "auto":
        rig_ready = all(getattr(m.info, "bottom_mass_kg", None) is not None and m.info.drop_height_m is not None
                        for m in measurements)
        conditioned_asked = relaxation or impact_velocity == "measured"
        drop_model = "rig" if rig_ready and measurements and not conditioned_asked else "conditioned"
    if not (contact == "measured" or isinstance(contact, ContactModel)):
        raise ValidationError(f"contact: found {contact!r}, expected 'measured' or a ContactModel")
    limits = check_thresholds(DROP_THRESHOLDS, thresholds)
    identified_range = checked_identified_range(identified_range, isolator)
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
        key = (info.top_mass_kg, info.intermediate_mass_kg, info.bottom_mass_kg) if system is None else None
        if drop_model == "rig" and (info.bottom_mass_kg is None or info.drop_height_m is None):
            raise ValidationError(f"{info.id}: drop_model 'rig' needs bottom_mass_kg and drop_height_m in the "
                                  "measurement info; found none")
        if key not in groups:
            model = system_for(measurement, system=system, isolator=isolator, upper=upper, lower=lower)
            groups[key] = (model, [], [])
        groups[key][1].append(index)
        groups[key][2].append(velocity)
    simulated = [None] * len(measurements)
    contacts = {}
    for key, (model, indices, velocities) in groups.items():
        if drop_model == "conditioned":
            sweep = shock_sweep(model, impact_velocity=velocities, duration=duration, relaxation=relaxation,
                                workers=workers)
            for position, index in enumerate(indices):
                simulated[index] = _Simulated(
                    float(sweep.impact_velocity[position]), float(sweep.peak_acceleration_compression[position]),
                    float(sweep.peak_acceleration_tension[position]), float(sweep.travel_compression[position]),
                    sweep.reasons[position])
            continue
        bottom = measurements[indices[0]].info.bottom_mass_kg
        heights = [measurements[i].info.drop_height_m for i in indices]
        if contact == "measured":
            readings = [contact_from_velocity_step(measurements[i].v_rel, measurements[i].time,
                                                   drop_height=measurements[i].info.drop_height_m,
                                                   bottom_mass=bottom).restitution for i in indices]
            group_contact = ContactModel(stiffness=DEFAULT_CONTACT.stiffness, restitution=float(np.median(readings)))
        else:
            group_contact = contact
        contacts[str(key[0] if key else "all")] = group_contact
        # repetitions share their nominal height: one simulation per distinct height
        distinct, which = np.unique(np.asarray(heights, dtype=float), return_inverse=True)
        sweep = shock_sweep(model, drop_height=distinct, duration=duration, workers=workers, drop_model="rig",
                            bottom_mass=bottom, contact=group_contact)
        for position, index in enumerate(indices):
            run = int(which[position])
            simulated[index] = _Simulated(
                float(sweep.impact_velocity[run]), float(sweep.peak_acceleration_compression[run]),
                float(sweep.peak_acceleration_tension[run]), float(sweep.travel_compression[run]),
                sweep.reasons[run])
    rows = []
    for measurement, result, sim in zip(measurements, processed, simulated):
        info = measurement.info
        rows.append({
            "id": info.id, "top mass [kg]": info.top_mass_kg, "drop height [m]": info.drop_height_m,
            "relative velocity step [m/s]": result.impact_velocity,
            "impact velocity from height [m/s]": result.impact_velocity_from_height,
            "impact velocity simulated [m/s]": sim.impact_velocity,
            "peak accel compression measured [m/s^2]": result.peak_acceleration_compression,
            "peak accel compression simulated [m/s^2]": sim.compression_acceleration,
            "peak accel tension measured [m/s^2]": result.peak_acceleration_tension,
            "peak accel tension simulated [m/s^2]": sim.tension_acceleration,
            "peak compression measured [m]": result.max_compression,
            "peak compression simulated [m]": sim.compression,
            "status": sim.status,
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

    # siblings: drops of the same top mass nearest in drop height (else in measured velocity step)
    heights = table["drop height [m]"].to_numpy(float)
    condition = heights if np.all(np.isfinite(heights)) else np.abs(table["relative velocity step [m/s]"]
                                                                    .to_numpy(float))
    judged = np.zeros(len(table), dtype=bool)
    lines = [[] for _ in range(len(table))]
    for quantity, limit_name in _PER_DROP:
        departure, sibling_median = departures(table[f"{quantity} error [-]"].to_numpy(float),
                                               groups=table["top mass [kg]"].to_numpy(), coordinate=condition)
        limit = limits[limit_name]
        table[f"{quantity} departure [-]"] = departure
        table[f"{quantity} departure limit [-]"] = limit
        judged |= np.isfinite(departure)
        for index in np.flatnonzero(departure > limit):
            lines[index].append(f"{quantity} error {table[f'{quantity} error [-]'].iloc[index]:+.3f} lies "
                                f"{departure[index]:.3f} outside 0 to its nearest siblings' median "
                                f"{sibling_median[index]:+.3f} (limit {limit:g})")
    beyond = np.array([bool(words) for words in lines], dtype=bool)
    failures = [f"{table['id'].iloc[index]}: " + "; ".join(lines[index]) for index in np.flatnonzero(beyond)]
    table["record verdict"] = np.where(beyond, "FAIL", np.where(judged, "ok", ""))
    alone = int((valid.to_numpy(bool) & ~judged).sum())

    def median_abs(column):
        values = np.abs(table.loc[valid, column].to_numpy(float))
        return float(np.median(values)) if values.size else np.nan

    summary = {
        "median_peak_acceleration_error": median_abs("peak acceleration error [-]"),
        "median_peak_compression_error": median_abs("peak compression error [-]"),
        "max_peak_acceleration_error": float(np.nanmax(np.abs(table["peak acceleration error [-]"])))
        if valid.any() else np.nan,
        "invalid_run_fraction": float(1.0 - valid.mean()),
        RECORD_METRIC: int(beyond.sum()),
        "relaxation": bool(relaxation) if drop_model == "conditioned" else False,
        "impact_velocity": impact_velocity if drop_model == "conditioned" else "rig fall from the drop height",
        "drop_model": drop_model,
    }
    if drop_model == "rig":
        summary["contact"] = "; ".join(f"top {mass} kg: k_c {c.stiffness:.3g} N/m, e {c.restitution:.3g}"
                                       for mass, c in contacts.items())
    for column, label in (("peak accel compression", "compression"), ("peak accel tension", "tension")):
        error = np.abs(table[f"{column} simulated [m/s^2]"] / table[f"{column} measured [m/s^2]"] - 1)
        error[~valid] = np.nan
        finite = error[np.isfinite(error)].to_numpy(float)  # a phase that never occurred is NaN
        summary[f"median_peak_acceleration_{label}_error"] = float(np.median(finite)) if finite.size else np.nan
        summary[f"max_peak_acceleration_{label}_error"] = float(np.max(finite)) if finite.size else np.nan
    by_height = table.groupby(["top mass [kg]", "drop height [m]"])[
        ["peak acceleration error [-]", "peak compression error [-]"]].mean().reset_index()
    notes = () if identified_range is None else _outside_notes(table, identified_range)
    if alone:
        notes += (f"{alone} of {len(table)} drops have fewer than {MIN_SIBLINGS} other drops of their top mass to "
                  "compare with: they are judged only together (medians), not one at a time",)
    return ValidationResult(name=name, metrics=table, summary=summary, thresholds=limits,
                            details={"by_height": by_height}, notes=notes, record_failures=tuple(failures))


def _outside_notes(table: pd.DataFrame, identified_range) -> tuple[str, ...]:
    """The drops whose measured peak compression lies outside the identified loop amplitudes, with
    their median peak acceleration error against the drops inside."""
    smallest, largest = identified_range
    compression = table["peak compression measured [m]"].to_numpy(float)
    error = np.abs(table["peak acceleration error [-]"].to_numpy(float))
    inside = (compression >= smallest) & (compression <= largest)

    def median_words(mask):
        values = error[mask & np.isfinite(error)]
        return f"{np.median(values):.3f}" if values.size else "not computed"

    notes = []
    for mask, where, bound, extreme in (
            (compression > largest, "beyond the largest", largest, "up to"),
            (compression < smallest, "less than the smallest", smallest, "down to")):
        if not mask.any():
            continue
        reached = compression[mask].max() if extreme == "up to" else compression[mask].min()
        notes.append(f"{int(mask.sum())} of {len(table)} drops compress the isolator {where} loop amplitude the "
                     f"model was identified on ({1e3 * bound:.3g} mm; measured peak compression {extreme} "
                     f"{1e3 * reached:.3g} mm): there the model is extrapolated; their median peak acceleration "
                     f"error is {median_words(mask)}, that of the drops inside the range {median_words(inside)}")
    return tuple(notes)
