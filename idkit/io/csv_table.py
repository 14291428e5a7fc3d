"""Strict reader of idkit CSV tables: a ``name [unit]`` header, then numbers.

The file is read once as bytes (SHA-256 of exactly those bytes), decoded as
UTF-8 (a leading byte-order mark is accepted), and parsed with :mod:`csv`.
Every cell must be a plain decimal number (``-1.5``, ``3e-4``); ``nan``,
``inf``, empty cells, thousands separators and any other text raise
:class:`~idkit.errors.DataError` naming the file, the column, the 1-based data
row (first row after the header = 1; the file line is also given), what was
found and what was expected. Trailing empty lines at the end of the file are
ignored; an empty line between data rows is an error. Values are converted
to SI; nothing is dropped, clipped or altered.
"""

from __future__ import annotations

import csv
import difflib
import gzip
import hashlib
import io
import re
import zlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from idkit.errors import DataError
from idkit.inputfiles import decode_utf8, read_input_bytes
from idkit.io.columns import COLUMN_QUANTITIES, KindSchema, parse_header_cell
from idkit.io.provenance import Source
from idkit.io.units import UnitScale, convert_to_si, lookup_unit

__all__ = ["CsvTable", "decode_text", "parse_number_cells", "read_csv_table", "read_file_bytes"]

# ASCII digits only: Python's float() would also accept Unicode digits and underscores
_NUMBER_RE = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_NONFINITE_RE = re.compile(r"[+-]?(?:nan|inf|infinity)", re.IGNORECASE)


@dataclass(frozen=True)
class CsvTable:
    """Columns of a CSV table converted to SI.

    Parameters
    ----------
    values : dict of str to numpy.ndarray
        Column name -> values in SI units.
    scales : dict of str to UnitScale
        Column name -> the declared unit (its ``quantity`` tells e.g.
        stiffness from modulus).
    source : Source
        Path, SHA-256 and declared headers.
    """

    values: dict[str, np.ndarray]
    scales: dict[str, UnitScale]
    source: Source


def read_file_bytes(path: str | Path) -> bytes:
    """Read a file's bytes, raising DataError if it is missing, a folder or unreadable.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.

    Returns
    -------
    bytes
        Its content (never modified).
    """
    return read_input_bytes(path, f"file '{path}'", DataError)


def decode_text(path: str | Path, raw: bytes) -> str:
    """Text of a data file's bytes: gunzipped for ``.gz`` names, decoded as UTF-8.

    Raises
    ------
    DataError
        A corrupt, truncated or non-gzip ``.gz`` file; text that is not UTF-8.
    """
    path = Path(path)
    if path.name.endswith(".gz"):
        try:
            raw = gzip.decompress(raw)
        # BadGzipFile (an OSError): bad header or CRC; EOFError: truncated stream;
        # zlib.error: a corrupted deflate stream
        except (OSError, EOFError, zlib.error) as exc:
            raise DataError(f"file '{path}': not a valid gzip file ({exc}); expected "
                            "gzip-compressed CSV") from None
    return decode_utf8(raw, f"file '{path}'", DataError)


def parse_number_cells(cells: list[str], column: str, source: Source) -> np.ndarray:
    """Parse one column's cells into float64, strictly.

    Parameters
    ----------
    cells : list of str
        The cells, whitespace already stripped.
    column : str
        Column name (for messages).
    source : Source
        For messages (file, declared header, row convention).

    Returns
    -------
    numpy.ndarray
        The values, correctly rounded by Python's ``float``.

    Raises
    ------
    DataError
        On an empty cell, ``nan``/``inf`` or any non-numeric text.
    """
    match = _NUMBER_RE.fullmatch
    for i, cell in enumerate(cells):
        if match(cell) is None:
            if cell == "":
                found, expected = "an empty cell", "a number"
            elif _NONFINITE_RE.fullmatch(cell):
                found, expected = repr(cell), "a finite number"
            else:
                found, expected = repr(cell), "a decimal number such as -1.5 or 3e-4"
            raise DataError(f"{source.where(column)}: {source.row_label(i)}: found {found}, "
                            f"expected {expected}")
    return np.fromiter(map(float, cells), dtype=np.float64, count=len(cells))


def _check_names(names: list[str], schema: KindSchema, source: Source) -> None:
    allowed = schema.allowed
    seen: set[str] = set()
    for k, name in enumerate(names, start=1):
        if name in seen:
            raise DataError(f"{source.where()}: header column {k}: duplicate column '{name}'")
        seen.add(name)
        if name not in allowed:
            close = difflib.get_close_matches(name, allowed, n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            raise DataError(
                f"{source.where()}: header column {k}: unknown column '{name}'{hint}; "
                f"expected for {schema.kind}: {schema.describe()}"
            )
    missing = [name for name in schema.required if name not in seen]
    if missing:
        raise DataError(f"{source.where()}: missing column(s) {', '.join(missing)}; "
                        f"found {', '.join(names)}; expected for {schema.kind}: "
                        f"{schema.describe()}")


def read_csv_table(path: str | Path, schema: KindSchema) -> CsvTable:
    """Read and check an idkit CSV table against a column schema.

    Parameters
    ----------
    path : str or pathlib.Path
        ``.csv`` or ``.csv.gz`` file with a ``name [unit]`` header.
    schema : KindSchema
        Allowed and required columns.

    Returns
    -------
    CsvTable
        Values in SI with provenance. Cross-column checks (e.g. time order)
        are left to the caller's constructor.

    Raises
    ------
    DataError
        On any deviation from the format (see module docstring).
    """
    path = Path(path)
    raw = read_file_bytes(path)
    sha256 = hashlib.sha256(raw).hexdigest()
    text = decode_text(path, raw)
    bare = Source(path=path, sha256=sha256, header_lines=1)
    if not text.strip():
        raise DataError(f"{bare.where()}: empty file; expected a header line "
                        f"'name [unit], ...' and data rows ({schema.describe()})")
    try:
        rows = list(csv.reader(io.StringIO(text, newline="")))
    except csv.Error as exc:
        raise DataError(f"{bare.where()}: not parseable as CSV ({exc})") from None
    while rows and not rows[-1]:
        rows.pop()  # trailing empty lines carry no data
    header = [cell.strip() for cell in rows[0]]
    parsed = [parse_header_cell(cell, where=f"{bare.where()}, header column {k}")
              for k, cell in enumerate(header, start=1)]
    names = [name for name, _ in parsed]
    declared = tuple((name, cell) for (name, _), cell in zip(parsed, header))
    source = Source(path=path, sha256=sha256, columns=declared, header_lines=1)
    _check_names(names, schema, source)
    scales = {name: lookup_unit(unit, COLUMN_QUANTITIES[name], where=source.where(name))
              for name, unit in parsed}
    body = rows[1:]
    if not body:
        raise DataError(f"{source.where()}: header only, no data rows; expected at least "
                        "2 data rows")
    n_columns = len(names)
    for i, row in enumerate(body):
        if len(row) != n_columns:
            what = "an empty line" if not row else f"{len(row)} field(s)"
            raise DataError(f"{source.where()}: {source.row_label(i)}: found {what}, "
                            f"expected {n_columns} fields as in the header "
                            f"(truncated or malformed row)")
    values = {}
    for k, name in enumerate(names):
        cells = [row[k].strip() for row in body]
        values[name] = convert_to_si(parse_number_cells(cells, name, source), scales[name])
    return CsvTable(values=values, scales=scales, source=source)
