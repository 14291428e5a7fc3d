"""Declared contracts of data-file contents: the keys of a JSON object and the columns of a record.

A manifest entry, its excitation and a measurement's metadata are tables of
:class:`idkit.checks.Field` (key, spec with its unit and meaning, required or not), walked by
:func:`idkit.checks.check_fields` (defined beside the specs so that every floor, model files
included, declares its JSON contents the same way, and imported from there); a manifest value is
checked as an argument is, so its refusal reads ``<file and entry>: <key>: found X, expected Y``
like every other in idkit. A record's columns are
a table of :class:`Column` (name, required or part of a pair), walked by :func:`check_columns`;
each column is read by :func:`as_signal` and the rows of a text table by :func:`check_row_widths`.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from idkit.errors import DataError
from idkit.io.provenance import Source

__all__ = ["Column", "as_signal", "check_columns", "check_row_widths", "read_columns"]


@dataclass(frozen=True)
class Column:
    """One signal column of a record kind: its name, and whether it is required, optional, or one
    of a pair that must be given together (``pair`` names the group; a kind needs at least one
    complete pair when it declares any)."""

    name: str
    required: bool = False
    pair: str = ""


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
