"""The identified model against the whole data set: can it be simulated wherever the data reach?

Every record of the isolator counts here, of either split (loops, sweeps and drops): an
identified model that cannot simulate a test its own data set holds is not a successful
identification, whatever its fit error.

* :func:`data_valid_range` - the deflections the spring must stay stiff over (the Iwan fit's
  default ``valid_range``); :func:`valid_over_the_data` - the check of a fitted model against them;
* :func:`survives_the_largest_drops`, :func:`survives_the_largest_sweep_level` - the data set's
  most severe drop and largest stepped-sine level, simulated (responses and simulator);
* :func:`damping_settled` - a viscous damping matched on sweeps that never settled.

Each check returns the reasons (tuple of str) a measurement-level fit is not a success.
"""

from __future__ import annotations

import numpy as np

from idkit.errors import DataError, Message, Suggestion
from idkit.fit.damping import ViscousDamping
from idkit.models import SDOFSystem
from idkit.observe.stepped_sine import hosidf_from_stepped_sine
from idkit.responses.shock import shock_sweep
from idkit.simulate import harmonic_response

__all__ = ["VALID_RANGE_MARGIN", "SWEEP_CHECK_PERIODS", "data_valid_range", "deflection_extent",
           "valid_over_the_data", "survives_the_largest_drops", "survives_the_largest_sweep_level",
           "damping_settled"]


def _records(measurements) -> list:
    """The measurements of a :class:`~idkit.io.MeasurementSet` or of a plain sequence of them."""
    return list(getattr(measurements, "measurements", measurements))


def damping_settled(damping: ViscousDamping | None) -> tuple[str, ...]:
    """A viscous damping matched to a simulated peak that never reached steady state is not an
    identification: its runs were cut at the period limit, so the peak compared was a transient's."""
    if damping is None or not damping.unsettled_points:
        return ()
    return (f"c_visc = {damping.c_visc:.4g} N s/m: {damping.unsettled_points} of {damping.points} simulated "
            f"stepped-sine points of level {damping.level:g} did not reach steady state with it, so the resonance "
            "peak it was matched on is a transient's; the viscous damping is not identified by these sweeps",)


#: The default valid range of an Iwan fit reaches this far beyond the data set's deflections.
VALID_RANGE_MARGIN = 1.25


def deflection_extent(measurements, isolator: str | None) -> tuple[float, float] | None:
    """Lowest and highest finite deflection (m) of every record of ``isolator`` (None: every
    record), or None when no record has one."""
    seen = [np.asarray(m.deflection, dtype=float) for m in _records(measurements)
            if getattr(m, "deflection", None) is not None
            and (isolator is None or getattr(getattr(m, "info", None), "isolator", None) == isolator)]
    seen = [d[np.isfinite(d)] for d in seen]
    seen = [d for d in seen if d.size]
    if not seen:
        return None
    return min(float(d.min()) for d in seen), max(float(d.max()) for d in seen)


def data_valid_range(measurements, *, isolator: str | None = None,
                     margin: float = VALID_RANGE_MARGIN) -> tuple[float, float]:
    """``margin`` times the lowest and highest deflection (m) of every record of the isolator.

    Loops, sweeps and drops of every split count: drops compress far beyond the quasi-static
    loops, and an identified spring must stay valid wherever the data set will be simulated.
    The range always straddles zero (a side the data do not reach is ``-1e-3`` times the
    other side's reach). NaN deflections are ignored.

    Raises
    ------
    DataError
        No record of the isolator has a finite deflection.
    """
    extent = deflection_extent(measurements, isolator)
    if extent is None:
        raise DataError(Message(f"valid range: found no record of isolator {isolator!r} with a finite deflection, "
                                "expected at least one (pass ", Suggestion("valid_range", None), " or ",
                                Suggestion("valid_range", "(x_min, x_max)", placeholder=True), ")"))
    low = margin * min(0.0, extent[0])
    high = margin * max(0.0, extent[1])
    if low == 0.0:
        low = -1e-3 * high
    if high == 0.0:
        high = -1e-3 * low
    return low, high


def valid_over_the_data(model, measurements, isolator) -> tuple[str, ...]:
    """A reason if the model's spring turns negative-stiff inside the deflections of the whole set.

    Every record of the isolator counts (loops, sweeps and drops, either split): a model
    that cannot be simulated over its own data's range is not a successful identification.
    """
    extent = deflection_extent(measurements, isolator)
    if extent is None:
        return ()
    low, high = extent
    lower, upper = model.valid_deflection_range()
    if lower <= low and high <= upper:
        return ()
    return (f"the fitted spring turns negative-stiff at {1e3 * lower:.4g} / {1e3 * upper:.4g} mm, inside the "
            f"deflections of the data set ({1e3 * low:.4g} to {1e3 * high:.4g} mm, every record of the isolator): "
            "the model cannot be simulated over its own data (fit with valid_range, idkit fit iwan --valid-range)",)


def survives_the_largest_drops(model, measurements, isolator) -> tuple[str, ...]:
    """A reason if the model cannot simulate the data set's most severe drop.

    For every top mass among the isolator's drop records, the highest drop is simulated
    (:func:`idkit.responses.shock_sweep`: conditioned free fall at ``sqrt(2 g h)``, 0.3 s at
    20 us, enough for the first compression and rebound of the slowest data-set system); a run
    the simulator flags (negative spring stiffness, Newton failure, non-finite state) means the
    model cannot predict a test the data set holds.
    """
    records = _records(measurements)
    highest: dict[float, float] = {}
    for m in records:
        info = getattr(m, "info", None)
        if (getattr(m, "kind", None) != "drop" or info is None or info.drop_height_m is None
                or info.top_mass_kg is None or (isolator is not None and info.isolator != isolator)):
            continue
        highest[info.top_mass_kg] = max(highest.get(info.top_mass_kg, 0.0), float(info.drop_height_m))
    reasons = []
    for mass, height in sorted(highest.items()):
        run = shock_sweep(SDOFSystem(mass, model), drop_height=[height], duration=0.3, time_step=2e-5)
        if run.reasons[0] != "ok":
            reasons.append(f"the model cannot simulate the data set's highest drop ({height:g} m on {mass:g} kg): "
                           f"{run.reasons[0]}")
    return tuple(reasons)

#: Periods of the short simulation at the data set's largest sweep level (enough for the
#: transient's largest excursion; steady state is the validation's business).
SWEEP_CHECK_PERIODS = 16


def survives_the_largest_sweep_level(model, measurements, isolator) -> tuple[str, ...]:
    """A reason if the model cannot simulate the data set's largest stepped-sine level.

    Every stepped-sine record of the isolator at the largest nominal level (either split) is
    simulated from rest for :data:`SWEEP_CHECK_PERIODS` periods of a pure sine with the
    record's measured first-harmonic base amplitude, as the sweep validation drives it; a run
    the simulator flags (negative spring stiffness, Newton failure, non-finite state) means
    the model cannot predict a test the data set holds. Not settling is not a reason here.
    """
    records = [m for m in _records(measurements)
               if getattr(m, "kind", None) == "stepped_sine" and m.info.top_mass_kg is not None
               and m.info.excitation is not None and m.info.excitation.amplitude is not None
               and (isolator is None or m.info.isolator == isolator)]
    if not records:
        return ()
    level = max(m.info.excitation.amplitude for m in records)
    reasons = []
    for mass in sorted({m.info.top_mass_kg for m in records}):
        points = [hosidf_from_stepped_sine(m) for m in records
                  if m.info.excitation.amplitude == level and m.info.top_mass_kg == mass]
        freq = np.array([p.freq for p in points])
        amplitude = np.array([p.result.input_amplitude for p in points]) / (2 * np.pi * freq)
        run = harmonic_response(SDOFSystem(mass, model), freq, amplitude, min_periods=SWEEP_CHECK_PERIODS,
                                max_periods=SWEEP_CHECK_PERIODS, workers=1)
        flagged = [(f, a, reason) for f, a, flag, reason in zip(freq, amplitude, run.flags, run.reasons) if flag]
        if flagged:
            f, a, reason = flagged[0]
            reasons.append(f"the model cannot simulate the data set's largest sweep level ({level:g} on {mass:g} kg): "
                           f"{len(flagged)} of {freq.size} points flagged, first at {f:g} Hz, base amplitude "
                           f"{1e3 * a:.3g} mm: {reason}")
    return tuple(reasons)
