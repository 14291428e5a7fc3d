"""Shock records in idkit's CSV layout: ``time [s]`` then one acceleration column per test.

Layout (``docs/data-format.md``): one header row of ``name [unit]`` cells, the first column
``time`` in a time unit, every other column an acceleration of the same channel in one test
(``m/s^2``, ``mm/s^2``, ``g``, ``1000g``; the unit is read from the header, never guessed),
then one row of numbers per sample (empty lines at the very end are ignored; an empty line or
empty cell between samples is an error, never skipped). A ``.gz`` name is gunzipped first. The result is the
typed :class:`~idkit.io.measurements.AccelerationRecord` every shock function of
:mod:`idkit.observe.shock` takes.
"""

from __future__ import annotations

import csv
import hashlib
import io
from pathlib import Path

import numpy as np

from idkit.errors import DataError
from idkit.io.columns import parse_header_cell
from idkit.io.csv_table import column_to_si, decode_text, parse_number_cells, read_file_bytes
from idkit.io.measurements import AccelerationRecord
from idkit.io.provenance import Source
from idkit.io.units import lookup_unit

__all__ = ["read_shock_csv"]


def read_shock_csv(path: str | Path, *, channel: str | None = None) -> AccelerationRecord:
    """Read a shock record written as ``time [unit], <test> [unit], ...``.

    Parameters
    ----------
    path : str or pathlib.Path
        CSV file (optionally ``.gz``).
    channel : str, optional
        Name of the accelerometer channel; default the file name without extension.

    Returns
    -------
    AccelerationRecord
        Time in s, acceleration in m/s^2, one column per test.

    Raises
    ------
    DataError
        Naming the file, the column and the row: a first column that is not time, a
        missing or unknown unit, a row of the wrong width, a cell that is not a number,
        fewer than two samples, time that does not increase.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> folder = pathlib.Path(tempfile.mkdtemp())
    >>> _ = (folder / "fixture.csv").write_text("time [ms],shot_1 [g]\\n0,0\\n0.01,1.5\\n0.02,0.5\\n")
    >>> record = read_shock_csv(folder / "fixture.csv")
    >>> record.channel, float(record.time[1]), round(float(record.accel[1, 0]), 5)
    ('fixture', 1e-05, 14.70998)
    """
    path = Path(path)
    raw = read_file_bytes(path)
    text = decode_text(path, raw)
    where = f"file '{path}'"
    try:
        rows = list(csv.reader(io.StringIO(text, newline="")))
    except csv.Error as exc:
        raise DataError(f"{where}: not parseable as CSV ({exc})") from None
    while rows and not any(cell.strip() for cell in rows[-1]):
        rows.pop()  # trailing empty lines carry no data; any other row is a sample (an empty one is refused)
    if len(rows) < 3:
        raise DataError(f"{where}: found {max(len(rows) - 1, 0)} data row(s), expected a header "
                        "'time [s], <test> [unit], ...' and at least 2 rows of samples")
    header = [cell.strip() for cell in rows[0]]
    if len(header) < 2:
        raise DataError(f"{where}: found {len(header)} column(s), expected time and at least one acceleration")
    names, units = [], []
    for number, cell in enumerate(header, start=1):
        name, unit = parse_header_cell(cell, where=f"{where}, column {number}")
        if name in names:
            raise DataError(f"{where}, column {number}: found the name {name!r} twice, expected one column per test")
        names.append(name)
        units.append(unit)
    if names[0].lower() != "time":
        raise DataError(f"{where}, column 1: found {header[0]!r}, expected the time column 'time [s]'")
    source = Source(path=path, sha256=hashlib.sha256(raw).hexdigest(), columns=tuple(zip(names, header)),
                    header_lines=1)
    body = [[cell.strip() for cell in row] for row in rows[1:]]
    for index, row in enumerate(body):
        if len(row) != len(header):
            what = "an empty line" if not row else f"{len(row)} field(s)"
            raise DataError(f"{where}: {source.row_label(index)}: found {what}, "
                            f"expected {len(header)} as in the header")
    time_scale = lookup_unit(units[0], "time", where=source.where("time"))
    time = column_to_si(parse_number_cells([row[0] for row in body], "time", source), time_scale, "time", source)
    columns = []
    for k in range(1, len(header)):
        scale = lookup_unit(units[k], "acceleration", where=source.where(names[k]))
        columns.append(column_to_si(parse_number_cells([row[k] for row in body], names[k], source), scale, names[k],
                                    source))
    return AccelerationRecord(time=time, accel=np.column_stack(columns), channel=channel or path.name.split(".")[0],
                              source=source)
