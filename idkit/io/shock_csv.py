"""Shock records in idkit's CSV layout: ``time [s]`` then one acceleration column per test.

Layout (``docs/data-format.md``): one header row of ``name [unit]`` cells, the first column
``time`` in a time unit, every other column an acceleration of the same channel in one test
(``m/s^2``, ``mm/s^2``, ``g``, ``1000g``; the unit is read from the header, never guessed),
then one row of numbers per sample (empty lines at the very end are ignored; an empty line or
empty cell between samples is an error, never skipped). A ``.gz`` name is gunzipped first. The result is the
typed :class:`~idkit.io.measurements.AccelerationRecord` every shock function of
:mod:`idkit.observe.shock` takes.

idkit's own drop records (``time, deflection, a_top_1, a_top_2[, v_rel]``, the ``drop`` kind of a
measurement set) are shock records too: :func:`read_shock_file` reads either layout, telling
them apart by the header, and :func:`drop_shock_record` turns a drop record into one.
"""

from __future__ import annotations

import csv
import dataclasses
import hashlib
import io
from pathlib import Path

import numpy as np

from idkit.errors import DataError
from idkit.io.columns import parse_header_cell
from idkit.io.contract import check_row_widths
from idkit.io.csv_table import column_to_si, decode_text, parse_number_cells, read_file_bytes
from idkit.io.measurements import AccelerationRecord, DropMeasurement
from idkit.io.provenance import Source
from idkit.io.units import lookup_unit

__all__ = ["read_shock_csv", "read_shock_file", "drop_shock_record", "is_drop_record_file"]


def drop_shock_record(measurement: DropMeasurement) -> AccelerationRecord:
    """The top-mass accelerometers of a drop record as a shock record.

    Parameters
    ----------
    measurement : DropMeasurement
        A drop record (both accelerometers sit on the top mass).

    Returns
    -------
    AccelerationRecord
        Channel: the record's id (else its file name); one column per accelerometer,
        ``a_top_1`` then ``a_top_2``, in m/s^2, on the record's time base. The record's
        source is kept, its tests labelled by the accelerometers' columns, so messages name the
        file and the column (``file 'drop.csv', column 'a_top_1 [m/s^2]'``).
    """
    if not isinstance(measurement, DropMeasurement):
        raise DataError(f"{measurement.source.where()}: found a {measurement.kind} record, expected a drop record "
                        "(time, deflection, a_top_1, a_top_2)")
    source = measurement.source
    name = measurement.id or (source.path.name.split(".")[0] if source.path else "drop")
    # the shock functions name a record's columns "test 1", "test 2": here they are the accelerometers
    columns = (("time", source.column_label("time")), ("test 1", source.column_label("a_top_1")),
               ("test 2", source.column_label("a_top_2")))
    return AccelerationRecord(time=measurement.time, accel=np.column_stack([measurement.a_top_1, measurement.a_top_2]),
                              channel=name, source=dataclasses.replace(source, columns=columns))


def read_shock_file(path: str | Path) -> AccelerationRecord:
    """A shock record in idkit's shock layout (:func:`read_shock_csv`) or an idkit drop record.

    A file whose header names the drop columns ``deflection`` and ``a_top_1`` is read as a
    drop record (with the metadata of an enclosing measurement set's manifest when it lists
    the file) and turned into a shock record by :func:`drop_shock_record`; any other file is
    read by :func:`read_shock_csv`, whose errors it keeps.

    Parameters
    ----------
    path : str or pathlib.Path
        CSV file (optionally ``.gz``).

    Returns
    -------
    AccelerationRecord
    """
    from idkit.io.discover import load_measurements

    path = Path(path)
    if is_drop_record_file(path):
        _, measurements = load_measurements(path, kind="drop")
        return drop_shock_record(measurements[0])
    return read_shock_csv(path)


def is_drop_record_file(path: str | Path) -> bool:
    """True when the header of ``path`` names idkit's drop columns ``deflection`` and ``a_top_1``.

    Raises
    ------
    DataError
        The reader's own checks (not a file, corrupt gzip, not UTF-8).
    """
    path = Path(path)
    header = decode_text(path, read_file_bytes(path)).lstrip("\ufeff").splitlines()[:1]
    names = {cell.split("[")[0].strip() for cell in (header[0].split(",") if header else ())}
    return {"deflection", "a_top_1"} <= names


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
    check_row_widths(body, len(header), source, " as in the header")
    time_scale = lookup_unit(units[0], "time", where=source.where("time"))
    time = column_to_si(parse_number_cells([row[0] for row in body], "time", source), time_scale, "time", source)
    columns = []
    for k in range(1, len(header)):
        scale = lookup_unit(units[k], "acceleration", where=source.where(names[k]))
        columns.append(column_to_si(parse_number_cells([row[k] for row in body], names[k], source), scale, names[k],
                                    source))
    return AccelerationRecord(time=time, accel=np.column_stack(columns), channel=channel or path.name.split(".")[0],
                              source=source)
