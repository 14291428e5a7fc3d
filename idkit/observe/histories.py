"""Force histories: force records driven by any deflection history, and how a prediction is scored.

A :class:`ForceHistory` is one record of an isolator's force under a deflection history of any
shape (sinusoids, random, earthquake-like, multi-level): the unit that :mod:`idkit.fit.auto`
trains and cross-validates on and that :mod:`idkit.validate.history` scores held-out
predictions on. :func:`force_histories` reads them from a measurement set's quasi-static
(force-deflection) records and gives each its **group**: the records of one test condition
(amplitude and cycle rate within :data:`GROUP_TOLERANCE` of each other, e.g. repetitions),
which a cross-validation holds out together.

The scores (one definition for the fit's cross-validation and the validator):

* :func:`normalised_rms_error` - ``rms(F_pred - F_meas) / rms(F_meas)`` over a span: predicting
  zero scores 1; a right model scores the force noise over the force's RMS (the noise floor,
  :func:`noise_floor`).
* :func:`strong_motion_window` - where the record moves: from 5 % to 95 % of the cumulative
  integral of the deflection rate squared (the velocity analogue of an earthquake's
  significant duration, which reads the Arias intensity, the integral of acceleration
  squared; a force record's deflection is measured directly, its second derivative would
  amplify the sensor noise).
* :func:`dissipated_energy` - ``integral F dx`` over the record (the work done on the
  isolator; for closed loops the area enclosed).

Sign convention (docs/data-format.md): positive deflection is tension, and positive force is
the tension the isolator carries, so a stiffness ``dF/dx`` and the work ``F dx`` done on the
isolator are positive.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from idkit.checks import Instance, Items, Reals, Samples, accepts
from idkit.errors import DataError
from idkit.io import QuasiStaticMeasurement
from idkit.io.selection import DataProvenance, select_measurements
from idkit.signal.cycles import find_reversals, noise_level, reversal_threshold

__all__ = [
    "ForceHistory", "force_histories", "histories_from_records", "GROUP_TOLERANCE", "MIN_HISTORY_SAMPLES",
    "normalised_rms_error", "strong_motion_window", "STRONG_MOTION_FRACTIONS", "dissipated_energy", "noise_floor",
]

#: Fewest samples of a force history (a second difference for the noise floor, a few reversals).
MIN_HISTORY_SAMPLES = 20
#: Two records belong to one group (one test condition) when their amplitudes and their cycle
#: rates are both within this relative tolerance: repetitions of a test differ by less, test
#: levels of a protocol by more (the thesis's loops: 0.05 to 15 mm; lab sinusoids a factor of 1.5-2).
GROUP_TOLERANCE = 0.10
#: The strong-motion window: the span between these fractions of the cumulative integral of
#: the deflection rate squared (Trifunac-Brady's 5-95 % significant duration).
STRONG_MOTION_FRACTIONS = (0.05, 0.95)


#: A history's deflection or force: 1-D and finite; its time: a strictly increasing axis in s
#: (lengths checked together).
_SIGNAL = Samples(min_size=0)
_TIME = Reals(unit="s", min_size=0, increasing=True)


@dataclass(frozen=True, eq=False)
class ForceHistory:
    """One force record under a deflection history of any shape.

    Attributes
    ----------
    name : str
        The record's id.
    time : ndarray, shape (n,)
        Sample times in s, strictly increasing.
    deflection : ndarray, shape (n,)
        Deflection in m (positive = tension).
    force : ndarray, shape (n,)
        Measured force in N (positive = tension).
    group : str
        Test condition shared with its repetitions (:func:`force_histories`); a
        cross-validation holds out a whole group.
    """

    name: str
    time: np.ndarray
    deflection: np.ndarray
    force: np.ndarray
    group: str = ""

    def __post_init__(self):
        where = f"force history {self.name!r}"
        arrays = {label: spec.check(getattr(self, label), f"{where} {label}", DataError)
                  for label, spec in (("time", _TIME), ("deflection", _SIGNAL), ("force", _SIGNAL))}
        sizes = {label: value.size for label, value in arrays.items()}
        if len(set(sizes.values())) != 1:
            raise DataError(f"{where}: found sample counts {sizes}, expected equal counts")
        if arrays["time"].size < MIN_HISTORY_SAMPLES:
            raise DataError(f"{where}: found {arrays['time'].size} samples, expected at least {MIN_HISTORY_SAMPLES}")
        if np.ptp(arrays["deflection"]) <= 0:
            raise DataError(f"{where} deflection: found a constant record, expected a deflection history")
        for label, value in arrays.items():
            object.__setattr__(self, label, value)
        object.__setattr__(self, "group", str(self.group or self.name))

    @property
    def amplitude(self) -> float:
        """Half the peak-to-peak deflection, m."""
        return 0.5 * float(np.ptp(self.deflection))

    @property
    def duration(self) -> float:
        """Record length, s."""
        return float(self.time[-1] - self.time[0])

    @property
    def cycle_rate(self) -> float:
        """Half the reversals per second between the first and the last reversal (Hz): a sinusoid's
        frequency, a random record's mean cycle rate; 0 with fewer than two reversals."""
        x = self.deflection
        reversals = find_reversals(x, min_excursion=reversal_threshold(x))
        if len(reversals) < 2:
            return 0.0
        return 0.5 * (len(reversals) - 1) / float(self.time[reversals[-1]] - self.time[reversals[0]])

    @property
    def velocity(self) -> np.ndarray:
        """Deflection rate in m/s (second-order central differences)."""
        return np.gradient(self.deflection, self.time)

    def __repr__(self) -> str:
        return (f"ForceHistory({self.name!r}, {self.time.size} samples, {self.duration:.4g} s, "
                f"amplitude {1e3 * self.amplitude:.4g} mm, group {self.group!r})")


def _groups(records: Sequence[tuple[str, float, float]]) -> dict[str, str]:
    """Name -> group label: records whose amplitude and cycle rate are both within
    :data:`GROUP_TOLERANCE` of a group's first record join it (records sorted by amplitude)."""
    groups: list[tuple[float, float, str]] = []
    labels = {}
    for name, amplitude, rate in sorted(records, key=lambda item: (item[1], item[2], item[0])):
        for first_amplitude, first_rate, label in groups:
            close_rate = abs(rate - first_rate) <= GROUP_TOLERANCE * max(first_rate, 1e-300)
            if abs(amplitude - first_amplitude) <= GROUP_TOLERANCE * first_amplitude and close_rate:
                labels[name] = label
                break
        else:
            label = f"{1e3 * amplitude:.3g} mm, {rate:.3g} Hz"
            while label in {g[2] for g in groups}:  # two groups rounding to one label
                label += "'"
            groups.append((amplitude, rate, label))
            labels[name] = label
    return labels


@accepts(records=Items(Instance((QuasiStaticMeasurement,), what="a quasi-static (force-deflection) record")),
         error=DataError)
def histories_from_records(records) -> list[ForceHistory]:
    """:class:`ForceHistory` items of quasi-static records already selected, grouped by test
    condition (module docstring); ids must be unique."""
    built, seen = [], set()
    for index, record in enumerate(records, start=1):
        name = record.id or f"record{index}"
        if name in seen:
            raise DataError(f"records: found the id {name!r} twice, expected unique record ids")
        seen.add(name)
        try:
            built.append(ForceHistory(name, record.time, record.deflection, record.force))
        except DataError as problem:
            raise DataError(f"{record.source.where()}: {problem}") from None
    labels = _groups([(h.name, h.amplitude, h.cycle_rate) for h in built])
    return [ForceHistory(h.name, h.time, h.deflection, h.force, labels[h.name]) for h in built]


def force_histories(measurements, *, isolator: str | None = None,
                    split: str | None = "fit") -> tuple[list[ForceHistory], DataProvenance]:
    """The force histories of a measurement set (its quasi-static records of one isolator and split).

    Parameters
    ----------
    measurements : MeasurementSet or sequence of measurements
    isolator : str or None
        Only this isolator's records (None: any).
    split : {"fit", "validation", "all", None}

    Returns
    -------
    (list of ForceHistory, DataProvenance)

    Raises
    ------
    DataError
        No matching record (the message lists what the set holds), records of more than one isolator
        with ``isolator=None`` (one device's histories are fitted or validated at a time), a record
        that is not a force history (constant deflection, fewer than :data:`MIN_HISTORY_SAMPLES` samples).
    """
    records, provenance = select_measurements(measurements, kind="quasi_static", isolator=isolator, split=split)
    isolators = sorted({str(record.info.isolator) for record in records})
    if isolator is None and len(isolators) > 1:
        raise DataError(f"quasi-static records: found records of the isolators {', '.join(isolators)}, expected one "
                        "device's records (give the isolator: --isolator NAME / isolator=)")
    return histories_from_records(records), provenance


def normalised_rms_error(predicted, measured, span: slice | None = None) -> float:
    """``rms(predicted - measured) / rms(measured)`` over ``span`` (default the whole record); NaN
    when the measured force is zero throughout or the prediction is not finite."""
    p = np.asarray(predicted, dtype=float)
    m = np.asarray(measured, dtype=float)
    if span is not None:
        p, m = p[span], m[span]
    scale = float(np.sqrt(np.mean(m**2))) if m.size else 0.0
    if not scale > 0 or not np.all(np.isfinite(p)):
        return math.nan
    return float(np.sqrt(np.mean((p - m) ** 2))) / scale


def strong_motion_window(time, deflection, fractions: tuple[float, float] = STRONG_MOTION_FRACTIONS) -> slice:
    """Samples from ``fractions[0]`` to ``fractions[1]`` of the cumulative integral of the
    deflection rate squared (trapezoids on the record's own times), both ends included.

    Examples
    --------
    >>> t = np.linspace(0.0, 10.0, 1001)
    >>> x = np.clip(t, 2.0, 8.0)            # moves at constant speed from 2 to 8 s only
    >>> window = strong_motion_window(t, x)
    >>> round(float(t[window.start]), 1), round(float(t[window.stop - 1]), 1)
    (2.3, 7.7)
    """
    t = np.asarray(time, dtype=float)
    x = np.asarray(deflection, dtype=float)
    velocity = np.gradient(x, t)
    energy = np.concatenate([[0.0], np.cumsum(0.5 * (velocity[1:] ** 2 + velocity[:-1] ** 2) * np.diff(t))])
    total = energy[-1]
    if not total > 0:
        return slice(0, t.size)
    start = int(np.searchsorted(energy, fractions[0] * total, side="left"))
    stop = int(np.searchsorted(energy, fractions[1] * total, side="left")) + 1
    return slice(min(start, t.size - 1), min(max(stop, start + 1), t.size))


def dissipated_energy(deflection, force) -> float:
    """``integral F dx`` along the record (trapezoids), J: the work done on the isolator."""
    x = np.asarray(deflection, dtype=float)
    f = np.asarray(force, dtype=float)
    return float(np.sum(0.5 * (f[1:] + f[:-1]) * np.diff(x)))


def noise_floor(history: ForceHistory | QuasiStaticMeasurement, span: slice | None = None) -> float:
    """The error an exactly right model scores on ``history`` (any record with a ``force`` array
    in N): the force noise (:func:`idkit.signal.cycles.noise_level`, second differences) over the
    RMS force of ``span`` (NaN where that is zero). A lower bound: offsets and drift are not in
    it."""
    force = np.asarray(history.force, dtype=float)
    part = force if span is None else force[span]
    rms = float(np.sqrt(np.mean(part**2)))
    return noise_level(force) / rms if rms > 0 else math.nan
