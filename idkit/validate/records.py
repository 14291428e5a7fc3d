"""Per-record judgement: one held-out record that disagrees with the model far beyond its siblings.

The aggregate metrics of a validation (an RMS over the sweep points, medians over the drops,
per-level resonances) judge the held-out records together, so one record of another isolator
among many of the right one can hide in them (a rope drop of another rope, errors 0.40 / 0.47
among drops at most 0.16 / 0.11, median 0.15 / 0.07: PASS). Each validator therefore also
judges every record on its own, against a limit derived from the aggregate limit it already
has (docs/validation.md, "One record at a time"):

* a per-record quantity whose aggregate is a **maximum** (FRF error, resonance error per
  white-noise run) has that limit per record: the verdict is the same, but the record is named;
* a quantity whose aggregate is a **median** (drop peak errors, FRF damping) may lie anywhere
  between zero (the model right) and the median error of its siblings (the nearest records of
  the same top mass: the model's error at that condition, which they share), and up to the
  aggregate limit beyond that interval: :func:`departures`. A record within the aggregate limit
  of zero is never blamed, a shared error is not held against one record, and a record with
  fewer than two siblings is not judged alone (its error cannot be told from a model error that
  changes with the condition);
* a sweep point's first harmonic (:func:`sweep_point_envelope`) may be off the model's by as
  much as the aggregate limits allow a model to differ there: the resonance shifted by up to
  ``max_resonance_frequency_error`` and the damping scaled by up to the peak limit
  (``max_peak_magnitude_error_db``), plus a complex error as large as the RMS limit. Near a
  lightly damped resonance that allows almost any phase (the phase is not determined by the
  validated tolerances there), away from it a few degrees.

A record beyond its limit is counted in the summary metric ``records_beyond_limit`` (limit 0,
overridable like every threshold) and named, with its error and limit, in
:attr:`idkit.validate.ValidationResult.record_failures` and in ``why``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["RECORD_METRIC", "MIN_SIBLINGS", "departures", "phase_floor_deg", "sweep_point_envelope"]

#: Summary metric counting the held-out records beyond their own limit (threshold 0).
RECORD_METRIC = "records_beyond_limit"


#: Fewest siblings (records of the same group with a finite error) a record is compared with; with
#: fewer, a record's error cannot be told from a model error that changes with the condition
#: (drop height, top mass), and the record is not judged on its own.
MIN_SIBLINGS = 2


def departures(errors, *, groups=None, coordinate=None,
               min_siblings: int = MIN_SIBLINGS) -> tuple[np.ndarray, np.ndarray]:
    """How far each record's signed error lies outside ``[min(0, m), max(0, m)]``, ``m`` the median
    error of its siblings.

    The siblings of a record are the *other* records of its group (``groups``, e.g. the top mass;
    all records when None) with a finite error; with ``coordinate`` (e.g. the drop height) only the
    nearest of them: those no farther than the ``min_siblings``-th nearest (ties included), where
    the model's error is what it is at the record's own condition. A record with fewer than
    ``min_siblings`` siblings is not judged (NaN), nor is one whose own error is NaN.

    Returns ``(departure, sibling_median)``.

    >>> dep, med = departures([0.05, 0.07, 0.06, 0.47])
    >>> [round(float(v), 2) for v in dep], [round(float(v), 2) for v in med]
    ([0.0, 0.01, 0.0, 0.41], [0.07, 0.06, 0.07, 0.06])
    >>> departures([-0.3, 0.1])[0].tolist()  # one sibling each: which one is off cannot be told
    [nan, nan]
    """
    errors = np.asarray(errors, dtype=float)
    count = errors.size
    groups = np.zeros(count) if groups is None else np.asarray(groups)
    coordinate = np.zeros(count) if coordinate is None else np.asarray(coordinate, dtype=float)
    departure = np.full(count, np.nan)
    sibling_median = np.full(count, np.nan)
    for index, error in enumerate(errors):
        others = np.flatnonzero((groups == groups[index]) & np.isfinite(errors) & (np.arange(count) != index))
        if others.size < max(1, min_siblings) or not np.isfinite(error):
            continue
        distance = np.abs(coordinate[others] - coordinate[index])
        distance = np.where(np.isfinite(distance), distance, np.inf)
        reach = np.sort(distance)[max(1, min_siblings) - 1]
        median = float(np.median(errors[others[distance <= reach]]))
        sibling_median[index] = median
        departure[index] = max(0.0, error - max(0.0, median), min(0.0, median) - error)
    return departure, sibling_median


def phase_floor_deg(rms_limit_db: float) -> float:
    """Phase a complex error as large as the RMS magnitude limit can cause: ``asin(10^(L/20) - 1)``
    (15.0 degrees for the default 2 dB; 90 when that relative error reaches 1).

    >>> round(phase_floor_deg(2.0), 1)
    15.0
    """
    relative = 10 ** (float(rms_limit_db) / 20) - 1
    return float(np.degrees(np.arcsin(min(1.0, relative))))


def sweep_point_envelope(freq, level, h1_model, *, frequency_tolerance: float, peak_tolerance_db: float,
                         samples: int = 21) -> tuple[np.ndarray, np.ndarray]:
    """Phase (degrees) and magnitude (dB) by which a model the aggregate limits accept may differ
    from ``h1_model`` at each point: the larger of two readings.

    * The point's equivalent linear system: ``u = H / (H - 1)`` is the complex stiffness the top
      mass sees over ``m omega^2`` (exact for one isolator, ``H = u / (u - 1)``); its resonance
      moved by ``rho`` (``u`` scaled by ``rho^2``) for every ``rho = f_measured / f_model`` that a
      resonance error within ``frequency_tolerance`` leaves, ``1 / (1 + tol) <= rho <= 1 / (1 - tol)``,
      and its imaginary part scaled by ``g``, ``|20 log10 g| <= peak_tolerance_db`` (a resonance
      peak scales as the inverse loss factor).
    * The model's own curve over the level (linear in log frequency between its points) read at
      ``f / rho`` for the same ``rho``: what the equivalent system cannot see (a second mode of a
      hybrid). Beyond the level's first and last points the curve goes on with the slope of
      its end segment.

    Points of one ``level`` form a curve; NaN entries of ``h1_model`` are skipped (their envelope
    is NaN).
    """
    freq = np.asarray(freq, dtype=float)
    level = np.asarray(level)
    h1 = np.asarray(h1_model, dtype=complex)
    phase = np.full(freq.shape, np.nan)
    magnitude = np.full(freq.shape, np.nan)
    good = np.isfinite(h1) & (h1 != 0) & (h1 != 1) & np.isfinite(freq) & (freq > 0)
    # the resonance ratio rho = f_measured / f_model that a resonance error f_model / f_measured - 1
    # within +/- frequency_tolerance leaves (a tolerance of 1 or more: down to a hundredth)
    tolerance = min(float(frequency_tolerance), 0.99)
    ratio_of_resonances = np.geomspace(1 / (1 + tolerance), 1 / (1 - tolerance), samples)
    # the equivalent linear system at each point
    shift = ratio_of_resonances ** 2
    gain = 10 ** (np.linspace(-peak_tolerance_db, peak_tolerance_db, samples) / 20)
    u = h1[good] / (h1[good] - 1)
    moved = (u.real[:, None, None] + 1j * u.imag[:, None, None] * gain[None, None, :]) * shift[None, :, None]
    ratio = moved / (moved - 1) / h1[good][:, None, None]
    phase[good] = np.degrees(np.max(np.abs(np.angle(ratio)), axis=(1, 2)))
    magnitude[good] = np.max(np.abs(20 * np.log10(np.abs(ratio))), axis=(1, 2))
    # the model's own curve, level by level
    offsets = -np.log(ratio_of_resonances)  # a resonance moved by rho reads the curve at f / rho
    for value in dict.fromkeys(level[good].tolist()):
        members = np.flatnonzero(good & (level == value))
        members = members[np.argsort(freq[members])]
        if members.size < 2:
            continue
        x = np.log(freq[members])
        steps = np.angle(h1[members][1:] / h1[members][:-1])
        unwrapped = np.concatenate([[0.0], np.cumsum(steps)])
        decibels = 20 * np.log10(np.abs(h1[members]))
        for position, member in enumerate(members):
            where = x[position] + offsets
            phase_change = np.degrees(np.max(np.abs(_along(where, x, unwrapped) - unwrapped[position])))
            magnitude_change = np.max(np.abs(_along(where, x, decibels) - decibels[position]))
            phase[member] = max(phase[member], phase_change)
            magnitude[member] = max(magnitude[member], magnitude_change)
    return phase, magnitude


def _along(where, x, y):
    """``y(x)`` piecewise linear at ``where``, continued beyond both ends with the end segments' slopes."""
    value = np.interp(where, x, y)
    below, above = where < x[0], where > x[-1]
    value[below] = y[0] + (where[below] - x[0]) * (y[1] - y[0]) / (x[1] - x[0])
    value[above] = y[-1] + (where[above] - x[-1]) * (y[-1] - y[-2]) / (x[-1] - x[-2])
    return value
