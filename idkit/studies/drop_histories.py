"""Measured drops beside the model's: top acceleration and deflection over time, from the impact.

The drop validation (:func:`idkit.validate.validate_drops`) compares peaks; a reader also
wants to see the shape: does the model ring at the measured frequency, does it rebound,
does the tension phase come at the right time? :func:`drop_histories` takes a few drops of
one setup (the lowest, a middle and the highest drop height of the top mass with most
drops), reduces each measured record with :func:`idkit.signal.drop.process_drop` (impact
instant, smoothed mean top acceleration, deflection from the unloaded state at impact) and
simulates the same drop on the rig model (:func:`idkit.simulate.drop_rig.drop_rig`:
released from rest under static load at the record's height onto the floor, the contact's
restitution read off the measured records as the validation does). The simulated record,
sampled at the measurement's rate, is read by the same processor, so both time axes start at the impact sample of the same
rule (half the largest closing speed reached) and both deflections are measured from the
same reference (the mean just before the impact).

Compute only; :func:`idkit.plot.validation.plot_drop_histories` draws the result.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from idkit.errors import DataError, SimulationError
from idkit.signal.drop import process_drop
from idkit.simulate.drop_rig import DEFAULT_CONTACT, ContactModel, contact_from_velocity_step, drop_rig
from idkit.validate.systems import system_for

__all__ = ["DropHistories", "DropHistory", "drop_histories"]

#: time shown before the first contact, s
BEFORE_S = 0.005


@dataclass(frozen=True)
class DropHistory:
    """One drop, measured and simulated, on time axes that start at the first contact.

    Attributes
    ----------
    id : str
    drop_height_m : float
    measured_time, measured_acceleration, measured_deflection : ndarray
        s from the impact (:func:`idkit.signal.drop.process_drop`'s rule); smoothed mean
        top acceleration, m/s^2; deflection from the processor's reference just before the
        impact, m (positive = tension).
    simulated_time, simulated_acceleration, simulated_deflection : ndarray
        The same for the model, read by the same processor (deflection of the whole
        isolator stack; unsmoothed).
    status : str
        ``"ok"`` or why the simulation was flagged (the curve then ends where it went invalid).
    """

    id: str
    drop_height_m: float
    measured_time: NDArray[np.float64]
    measured_acceleration: NDArray[np.float64]
    measured_deflection: NDArray[np.float64]
    simulated_time: NDArray[np.float64]
    simulated_acceleration: NDArray[np.float64]
    simulated_deflection: NDArray[np.float64]
    status: str


@dataclass(frozen=True)
class DropHistories:
    """A few drops of one setup (:func:`drop_histories`)."""

    setup: str
    contact: ContactModel
    drops: tuple[DropHistory, ...]


def _spread(items: list, count: int) -> list:
    """``count`` items evenly spread over ``items`` (first and last included)."""
    if len(items) <= count:
        return items
    return [items[i] for i in np.unique(np.round(np.linspace(0, len(items) - 1, count)).astype(int))]


def drop_histories(measurements, *, isolator=None, upper=None, lower=None, max_drops: int = 3,
                   contact: ContactModel | str = "measured", workers: int | None = None) -> DropHistories | None:
    """Measured and simulated time histories of a few drops (module docstring).

    Parameters
    ----------
    measurements : iterable of Measurement
        Records of any kind; the drops that give top mass, bottom mass and drop height are used.
    isolator, upper, lower :
        The model (:func:`idkit.validate.systems.system_for`).
    max_drops : int
        Drops shown: spread over the distinct heights, lowest and highest included.
    contact : ContactModel or "measured"
        The floor contact; "measured": the default stiffness with the median restitution
        read off the setup's records (:func:`~idkit.simulate.drop_rig.contact_from_velocity_step`),
        as :func:`idkit.validate.validate_drops` does.
    workers : int, optional

    Returns
    -------
    DropHistories or None
        None when no drop gives the rig's masses and height.
    """
    drops = [m for m in measurements if getattr(m, "kind", None) == "drop" and m.info.top_mass_kg is not None
             and m.info.bottom_mass_kg is not None and m.info.drop_height_m is not None]
    if not drops:
        return None
    key = Counter((m.info.top_mass_kg, m.info.intermediate_mass_kg) for m in drops).most_common(1)[0][0]
    setup_drops = [m for m in drops if (m.info.top_mass_kg, m.info.intermediate_mass_kg) == key]
    by_height = {}
    for measurement in sorted(setup_drops, key=lambda m: (m.info.drop_height_m, m.info.id or "")):
        by_height.setdefault(measurement.info.drop_height_m, measurement)
    chosen = _spread(list(by_height.values()), max_drops)
    bottom = chosen[0].info.bottom_mass_kg
    if isinstance(contact, str) and contact == "measured":
        restitution = float(np.median([
            contact_from_velocity_step(m.v_rel, m.time, drop_height=m.info.drop_height_m,
                                       bottom_mass=bottom).restitution
            for m in setup_drops if m.v_rel is not None] or [DEFAULT_CONTACT.restitution]))
        contact = ContactModel(stiffness=DEFAULT_CONTACT.stiffness, restitution=restitution)
    elif not isinstance(contact, ContactModel):
        raise SimulationError(f"contact: found {contact!r}, expected 'measured' or a ContactModel")
    system = system_for(chosen[0], isolator=isolator, upper=upper, lower=lower)
    heights = [m.info.drop_height_m for m in chosen]
    run = drop_rig(system, bottom_mass=bottom, drop_height=heights, contact=contact, before=BEFORE_S, workers=workers)
    histories = []
    for index, measurement in enumerate(chosen):
        processed = process_drop(measurement.time, measurement.deflection,
                                 np.vstack([measurement.a_top_1, measurement.a_top_2]),
                                 relative_velocity=measurement.v_rel, drop_height=measurement.info.drop_height_m)
        time = processed.time - processed.impact_time
        keep = (time >= -BEFORE_S) & (time <= run.time[-1])
        finite = np.isfinite(run.top_acceleration[index])
        simulated_time = run.time[finite]
        simulated_acceleration = run.top_acceleration[index][finite]
        simulated_deflection = run.deflection[index][finite]
        try:  # the model's record, sampled as the measurement, read by the same processor: the same
            # impact rule and smoothing, the same deflection reference
            step = float(np.median(np.diff(measurement.time)))
            grid = np.arange(simulated_time[0], simulated_time[-1], step)
            velocity = np.interp(grid, simulated_time, run.relative_velocity[index][finite])
            own = process_drop(grid, np.interp(grid, simulated_time, simulated_deflection),
                               np.interp(grid, simulated_time, simulated_acceleration)[None, :],
                               relative_velocity=velocity, drop_height=heights[index])
            simulated_time = simulated_time - own.impact_time
            simulated_deflection = simulated_deflection - own.deflection_reference
        except DataError:  # no compression in the model's record: leave it on the contact clock
            pass
        histories.append(DropHistory(
            id=measurement.info.id or f"drop {index + 1}", drop_height_m=float(measurement.info.drop_height_m),
            measured_time=time[keep], measured_acceleration=processed.acceleration[keep],
            measured_deflection=processed.deflection[keep], simulated_time=simulated_time,
            simulated_acceleration=simulated_acceleration, simulated_deflection=simulated_deflection,
            status=run.reasons[index]))
    top, middle = key
    setup = f"top mass {top:.3g} kg" + ("" if middle is None else f", intermediate mass {middle:.3g} kg")
    setup += f", bottom mass {bottom:.3g} kg"
    return DropHistories(setup=setup, contact=contact, drops=tuple(histories))
