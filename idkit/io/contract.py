"""Declared contracts of data-file contents: the keys of a JSON object and the columns of a record.

A manifest entry, its excitation and a measurement's metadata are tables of
:class:`idkit.checks.Field` (key, spec with its unit and meaning, required or not), walked by
:func:`idkit.checks.check_fields` (defined beside the specs so that every floor, model files
included, declares its JSON contents the same way, and imported from there); a manifest value is
checked as an argument is, so its refusal reads ``<file and entry>: <key>: found X, expected Y``
like every other in idkit. A record's columns are
a table of :class:`Column` (name, required or part of a pair, and for a time column its
:class:`Axis` rule: strictly increasing, sample rate, uniform steps), walked by :func:`check_columns`;
each column is read by :func:`as_signal`, a record's columns together by :func:`read_record` and
the rows of a text table by :func:`check_row_widths`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from idkit.errors import DataError
from idkit.io.provenance import Source

__all__ = ["SAMPLE_RATE_TOLERANCE", "Axis", "Column", "TIME_AXIS", "UNIFORM_TIME_AXIS", "as_signal", "check_columns",
           "check_row_widths", "read_columns", "read_record"]

#: Relative tolerance between a declared sample rate and ``1 / median(diff(time))``, and, on a
#: uniform axis, between each step and the median step.
SAMPLE_RATE_TOLERANCE = 0.01


@dataclass(frozen=True)
class Axis:
    """The rule of a sample axis (a record's time column, in s): at least ``min_size`` samples,
    strictly increasing, a declared sample rate within :data:`SAMPLE_RATE_TOLERANCE` of
    ``1 / median step``, and, when ``uniform``, every step within the same tolerance of the median
    step (records whose spectra and integrals run at one sample rate)."""

    min_size: int = 2
    uniform: bool = False

    @staticmethod
    def rate_hz(time: np.ndarray) -> float:
        """Sample rate in Hz of an axis: ``1 / median step`` (robust to one odd step)."""
        return 1.0 / float(np.median(np.diff(time)))

    def check(self, time: np.ndarray, name: str, source: Source, declared_rate_hz: float | None = None) -> None:
        """Refuse an axis breaking the rule, naming the file, the column, the 1-based row, what was
        found and what was expected (``time`` finite, as :func:`as_signal` returns it)."""
        where = source.where(name)
        if time.size < self.min_size:
            raise DataError(f"{where}: found {time.size} data row(s), expected at least {self.min_size}")
        step = np.diff(time)
        bad = np.flatnonzero(step <= 0)
        if bad.size:
            i = int(bad[0]) + 1
            what = "duplicate time stamp" if step[i - 1] == 0 else "time decreases (unsorted)"
            raise DataError(f"{where}: {source.row_label(i)}: {what}: found {float(time[i])!r} after "
                            f"{float(time[i - 1])!r}, expected strictly increasing time")
        median = float(np.median(step))
        if declared_rate_hz is not None and \
                abs(1.0 / median - declared_rate_hz) > SAMPLE_RATE_TOLERANCE * declared_rate_hz:
            raise DataError(f"{where}: sample rate from the time column {1.0 / median:.6g} Hz (1 / median step) "
                            f"contradicts the declared sample_rate_hz {declared_rate_hz:.6g} Hz (tolerance "
                            f"{SAMPLE_RATE_TOLERANCE:.0%} relative)")
        odd = np.flatnonzero(np.abs(step - median) > SAMPLE_RATE_TOLERANCE * median) if self.uniform else ()
        if len(odd):
            i = int(odd[0]) + 1
            raise DataError(
                f"{where}: {source.row_label(i)}: time step {float(step[i - 1]):.6g} s from {float(time[i - 1])!r} "
                f"to {float(time[i])!r}, {float(step[i - 1]) / median:.4g} x the median step {median:.6g} s "
                f"({len(odd)} such step(s)); expected uniform sampling within {SAMPLE_RATE_TOLERANCE:.0%} (a "
                "missing or inserted sample?), since the spectra and integrals run at one sample rate")


#: A record's time column: strictly increasing, irregular steps allowed (the quasi-static lathe
#: data are hand-driven; the median step makes the rate robust to them).
TIME_AXIS = Axis()

#: A shock record's time column: every step within :data:`SAMPLE_RATE_TOLERANCE` of the median
#: (a missing sample, a splice or a pause would be processed as if the samples were evenly spaced;
#: stamps rounded to four significant digits of the step stay within it).
UNIFORM_TIME_AXIS = Axis(uniform=True)


@dataclass(frozen=True)
class Column:
    """One signal column of a record kind: its name, whether it is required, optional, or one
    of a pair that must be given together (``pair`` names the group; a kind needs at least one
    complete pair when it declares any), and the :class:`Axis` rule of a time column."""

    name: str
    required: bool = False
    pair: str = ""
    axis: Axis | None = None


def check_columns(present: Mapping[str, object], columns: Sequence[Column], where: str) -> None:
    """Refuse a record missing a required column, half a pair, or every pair (messages name
    ``where``, the column missing and the columns expected)."""
    pairs: dict[str, list[str]] = {}
    for column in columns:
        if column.required and present.get(column.name) is None:
            raise DataError(f"{where}: column '{column.name}' missing; expected "
                            f"{', '.join(c.name for c in columns if c.required)}")
        if column.pair:
            pairs.setdefault(column.pair, []).append(column.name)
    complete = False
    for names in pairs.values():
        given = [present.get(name) is not None for name in names]
        if any(given) and not all(given):
            raise DataError(f"{where}: column '{names[given.index(False)]}' missing: expected both of "
                            f"{', '.join(names)}")
        complete = complete or all(given)
    if pairs and not complete:
        raise DataError(f"{where}: no response columns; expected "
                        f"{', or '.join(' and '.join(names) for names in pairs.values())}")


def as_signal(value: object, name: str, source: Source) -> np.ndarray:
    """``value`` as a read-only 1-D float64 copy, or DataError naming the column and the first
    non-finite sample (its 1-based row or sample) of ``source``."""
    try:
        array = np.array(value, dtype=np.float64, copy=True)
    except (TypeError, ValueError) as exc:
        raise DataError(f"{source.where(name)}: found values that are not numbers ({exc}), "
                        "expected a 1-D array of floats") from exc
    if array.ndim != 1:
        raise DataError(f"{source.where(name)}: found an array of shape {array.shape}, "
                        "expected 1-D")
    bad = np.flatnonzero(~np.isfinite(array))
    if bad.size:
        i = int(bad[0])
        raise DataError(f"{source.where(name)}: {source.row_label(i)}: found {float(array[i])!r}, "
                        f"expected a finite number ({bad.size} non-finite value(s) in total)")
    array.setflags(write=False)
    return array


def check_row_widths(rows: Sequence[Sequence[str]], width: int, source: Source, why: str = "") -> None:
    """Every data row of a text table holds ``width`` fields; the first that does not is refused,
    named by its 1-based data row and file line (``why`` ends the expectation)."""
    odd = next((index for index, row in enumerate(rows) if len(row) != width), None)
    if odd is not None:
        found = f"{len(rows[odd])} field(s)" if rows[odd] else "an empty line"
        raise DataError(f"{source.where()}: {source.row_label(odd)}: found {found}, expected {width} fields{why}")


def read_columns(values: Mapping[str, object], source: Source, labels: Mapping[str, str] | None = None
                 ) -> dict[str, np.ndarray]:
    """The columns given (``None`` skipped), each read by :func:`as_signal` under its label, all as
    long as the first (the message names the column, its length and the first's)."""
    labels = labels or {}
    arrays = {name: as_signal(value, labels.get(name, name), source) for name, value in values.items()
              if value is not None}
    first = next(iter(arrays), None)
    odd = next((name for name, array in arrays.items() if array.size != arrays[first].size), None)
    if odd is not None:
        raise DataError(f"{source.where(labels.get(odd, odd))}: found {arrays[odd].size} values, expected "
                        f"{arrays[first].size} (as many as {labels.get(first, first)})")
    return arrays


def read_record(values: Mapping[str, object], columns: Sequence[Column], source: Source,
                declared_rate_hz: float | None = None) -> dict[str, np.ndarray]:
    """The columns of a record (``values``: every declared column, ``None`` when absent), checked
    against their declarations: :func:`check_columns`, then :func:`read_columns`, then each axis
    column's :class:`Axis` rule (``declared_rate_hz``: the sample rate the metadata state)."""
    check_columns(values, columns, source.where())
    arrays = read_columns(values, source)
    for column in columns:
        if column.axis is not None and column.name in arrays:
            column.axis.check(arrays[column.name], column.name, source, declared_rate_hz)
    return arrays
