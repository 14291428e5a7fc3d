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

Two parsers give the same result. The fast one hands the data rows to
:func:`pandas.read_csv` (C tokenizer, correctly rounded float conversion:
every value is bit-identical to Python's ``float`` of the cell) after cheap
whole-text checks that keep it from accepting anything the strict one refuses:
only the characters of plain decimal numbers, commas, spaces, tabs and line
ends; ``\r`` only in ``\r\n``; no quotes; as many lines as rows and exactly
``columns - 1`` commas per row; no exponent of -100 or below and no run of 200 zeros
(a cell can only underflow to 0 that way); every value finite. When any check fails, the
strict parser (:mod:`csv` and a regular expression per cell, about 6 times
slower) reads the text again: it words the error (file, column, row, found,
expected), or returns the values when the text was valid after all (a quoted
header, ``1e-300``). A nonzero cell below float64's smallest magnitude (``1e-400``,
which would read as 0), a cell beyond its largest (``1e400``) and a value the unit
conversion would take there (``5e-324 mm``) are refused with their row and column.
"""

from __future__ import annotations

import csv
import gzip
import hashlib
import io
import re
import warnings
import zlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from idkit.errors import DataError
from idkit.inputfiles import decode_utf8, read_input_bytes
from idkit.io.columns import COLUMN_QUANTITIES, KindSchema, did_you_mean, parse_header_cell
from idkit.io.contract import check_row_widths
from idkit.io.provenance import Source
from idkit.io.units import SI_UNITS, UnitScale, convert_to_si, lookup_unit

__all__ = [
    "CsvTable",
    "column_to_si",
    "decode_text",
    "parse_number_cells",
    "parse_table_text",
    "read_csv_table",
    "read_file_bytes",
]

# ASCII digits only: Python's float() would also accept Unicode digits and underscores
_NUMBER_RE = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_NONFINITE_RE = re.compile(r"[+-]?(?:nan|inf|infinity)", re.IGNORECASE)
_NONZERO_DIGIT = re.compile(r"[1-9]")
# A cell can only underflow to 0 with an exponent of -100 or below or a run of 200 zeros
# (0.000...1); the fast path leaves such texts, rare in measurements, to the strict parser
# (overflow gives inf, which the fast path refuses anyway). Literal first bytes: "e-" and
# "E-" are searched for several times faster than a character class.
_TINY_EXPONENT = re.compile(rb"e-0*[1-9][0-9]{2}")
_TINY_EXPONENT_UPPER = re.compile(rb"E-0*[1-9][0-9]{2}")
_LONG_ZERO_RUN = b"0" * 200
_LARGEST = float(np.finfo(np.float64).max)
_SMALLEST = float(np.finfo(np.float64).smallest_subnormal)
# bytes a data row may hold on the fast path: digits, sign, point, exponent, comma, blanks
_FAST_ROW_BYTES = b"0123456789+-.eE, \t\r\n"
# pandas < 3 converts with xstrtod by default, which may miss the last bit; "round_trip"
# calls CPython's correctly rounded conversion. pandas 3 converts correctly by default
# and deprecates the option.
_PANDAS_PRECISION = ({} if int(pd.__version__.split(".")[0]) >= 3
                     else {"float_precision": "round_trip"})


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
    values = np.fromiter(map(float, cells), dtype=np.float64, count=len(cells))
    if not np.isfinite(values).all():
        i = int(np.flatnonzero(~np.isfinite(values))[0])
        raise DataError(f"{source.where(column)}: {source.row_label(i)}: found {cells[i]!r}, which is "
                        f"beyond float64's largest magnitude ({_LARGEST:.4g}); expected a finite number")
    # a nonzero number below float64's smallest magnitude reads as 0.0: only exact zeros are
    # looked at again, by their text (a nonzero digit before the exponent)
    for i in np.flatnonzero(values == 0.0):
        if _NONZERO_DIGIT.search(cells[i].partition("e")[0].partition("E")[0]):
            raise DataError(f"{source.where(column)}: {source.row_label(i)}: found {cells[i]!r}, which is "
                            f"nonzero but below float64's smallest magnitude ({_SMALLEST:.3g}) and would "
                            "read as 0; expected 0 or a number of magnitude >= that")
    return values


def column_to_si(values: np.ndarray, scale: UnitScale, column: str, source: Source) -> np.ndarray:
    """``values`` (in the column's declared unit) in SI, refusing a value the conversion would
    turn into infinity or (from nonzero) into 0."""
    with np.errstate(over="ignore", under="ignore"):
        si = convert_to_si(values, scale)
    if scale.numerator == 1.0 and scale.denominator == 1.0 and scale.offset == 0.0:
        return si
    changed = ~np.isfinite(si) | ((si == 0.0) & (values != 0.0) & (scale.offset == 0.0))
    if changed.any():
        i = int(np.flatnonzero(changed)[0])
        raise DataError(f"{source.where(column)}: {source.row_label(i)}: found {float(values[i])!r} "
                        f"{scale.symbol}, which is {float(si[i])!r} {SI_UNITS[scale.quantity]} in SI "
                        f"(beyond float64's range); expected a value whose SI magnitude is 0 or lies in "
                        f"{_SMALLEST:.3g} to {_LARGEST:.4g}")
    return si


def _check_names(names: list[str], schema: KindSchema, source: Source) -> None:
    allowed = schema.allowed
    seen: set[str] = set()
    for k, name in enumerate(names, start=1):
        if name in seen:
            raise DataError(f"{source.where()}: header column {k}: duplicate column '{name}'")
        seen.add(name)
        if name not in allowed:
            raise DataError(
                f"{source.where()}: header column {k}: unknown column '{name}'{did_you_mean(name, allowed)}; "
                f"expected for {schema.kind}: {schema.describe()}"
            )
    missing = [name for name in schema.required if name not in seen]
    if missing:
        raise DataError(f"{source.where()}: missing column(s) {', '.join(missing)}; "
                        f"found {', '.join(names)}; expected for {schema.kind}: "
                        f"{schema.describe()}")


def _read_header(cells: list[str], path: Path, sha256: str, schema: KindSchema,
                 bare: Source) -> tuple[list[str], Source, dict[str, UnitScale]]:
    """Names, provenance and units of the header cells (checked against the schema)."""
    header = [cell.strip() for cell in cells]
    parsed = [parse_header_cell(cell, where=f"{bare.where()}, header column {k}")
              for k, cell in enumerate(header, start=1)]
    names = [name for name, _ in parsed]
    declared = tuple((name, cell) for (name, _), cell in zip(parsed, header))
    source = Source(path=path, sha256=sha256, columns=declared, header_lines=1)
    _check_names(names, schema, source)
    scales = {name: lookup_unit(unit, COLUMN_QUANTITIES[name], where=source.where(name))
              for name, unit in parsed}
    return names, source, scales


def _parse_fast(path: Path, sha256: str, text: str, schema: KindSchema) -> CsvTable | None:
    """The table read through pandas, or None when the text needs the strict parser.

    None means only "not provably valid by the cheap checks" (see the module
    docstring); header problems raise the same errors as the strict parser,
    since the header cells are split exactly as :mod:`csv` splits them.
    """
    end = text.find("\n")
    if end <= 0 or '"' in text or not text.strip():
        return None
    header_line = text[:end].removesuffix("\r")
    if "\r" in header_line or not header_line.strip():
        return None
    bare = Source(path=path, sha256=sha256, header_lines=1)
    names, source, scales = _read_header(header_line.split(","), path, sha256, schema, bare)
    body = text[end + 1:].rstrip("\r\n")  # trailing empty lines carry no data
    if not body or not body.isascii():
        return None
    data = body.encode("ascii")
    if data.translate(None, _FAST_ROW_BYTES):
        return None
    if b"\r" in data and data.count(b"\r") != data.count(b"\r\n"):
        return None
    if (_TINY_EXPONENT.search(data) or (b"E" in data and _TINY_EXPONENT_UPPER.search(data))
            or _LONG_ZERO_RUN in data):
        return None  # may underflow to 0: the strict parser decides, by the text
    n_columns = len(names)
    n_rows = data.count(b"\n") + 1
    if data.count(b",") != n_rows * (n_columns - 1):
        return None
    try:
        with warnings.catch_warnings():
            # rows of unequal length: pandas would warn and drop the extra fields
            warnings.simplefilter("error", pd.errors.ParserWarning)
            frame = pd.read_csv(io.BytesIO(data), header=None, names=list(range(n_columns)),
                                index_col=False, dtype=np.float64, engine="c",
                                skip_blank_lines=False, **_PANDAS_PRECISION)
    # ValueError includes pandas.errors.ParserError: a cell or a row it cannot read
    except (ValueError, pd.errors.ParserWarning):
        return None
    if len(frame) != n_rows:
        return None
    columns = np.array(frame.to_numpy(dtype=np.float64).T, order="C")  # own, one row a column
    if not np.isfinite(columns).all():
        return None  # empty cells (NaN) and overflow: the strict parser decides
    values = {name: column_to_si(columns[k], scales[name], name, source) for k, name in enumerate(names)}
    return CsvTable(values=values, scales=scales, source=source)


def _parse_strict(path: Path, sha256: str, text: str, schema: KindSchema) -> CsvTable:
    """The table read cell by cell with :mod:`csv` and a regular expression."""
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
    names, source, scales = _read_header(rows[0], path, sha256, schema, bare)
    body = rows[1:]
    if not body:
        raise DataError(f"{source.where()}: header only, no data rows; expected at least "
                        "2 data rows")
    n_columns = len(names)
    check_row_widths(body, n_columns, source, " as in the header (truncated or malformed row)")
    values = {}
    for k, name in enumerate(names):
        cells = [row[k].strip() for row in body]
        values[name] = column_to_si(parse_number_cells(cells, name, source), scales[name], name, source)
    return CsvTable(values=values, scales=scales, source=source)


def parse_table_text(path: str | Path, sha256: str, text: str, schema: KindSchema, *,
                     strict: bool = False) -> CsvTable:
    """Parse the decoded text of an idkit CSV table (see the module docstring).

    Parameters
    ----------
    path : str or pathlib.Path
        The file the text came from (for provenance and messages).
    sha256 : str
        SHA-256 of the file's bytes as stored.
    text : str
        The decoded text.
    schema : KindSchema
        Allowed and required columns.
    strict : bool
        Skip the pandas fast path and parse every cell with the strict parser
        (same values and errors, about 6 times slower; for tests and
        benchmarks). Default ``False``.

    Returns
    -------
    CsvTable
        Values in SI with provenance.

    Raises
    ------
    DataError
        On any deviation from the format, worded by the strict parser.
    """
    path = Path(path)
    if not strict:
        table = _parse_fast(path, sha256, text, schema)
        if table is not None:
            return table
    return _parse_strict(path, sha256, text, schema)


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
    return parse_table_text(path, hashlib.sha256(raw).hexdigest(), decode_text(path, raw), schema)
