"""Finding measurements on disk: data folders, measurement sets, lone data files.

- :func:`default_data_dir` - the bundled data folder;
- :func:`find_measurement_sets` - every measurement set below a folder, keyed by isolator;
- :func:`guess_kind` - the kind of a lone CSV file from its header;
- :func:`load_measurements` - the measurements of a set folder or of one data file (its
  metadata from the manifest of an enclosing set when one lists it).
"""

from __future__ import annotations

import re
from pathlib import Path

from idkit.checks import InputPath, accepts
from idkit.errors import DataError
from idkit.io.columns import KINDS
from idkit.io.csv_measurement import read_csv_measurement
from idkit.io.csv_table import decode_text, read_file_bytes
from idkit.io.manifest import MeasurementSet, load_measurement_set, read_manifest

__all__ = ["KINDS", "default_data_dir", "find_measurement_sets", "guess_kind", "load_measurements"]

# a column found only in one kind's files, first match wins
_KIND_BY_COLUMN = (("force", "quasi_static"), ("a_top_1", "drop"), ("x_base", "stepped_sine"),
                   ("u_in", "stepped_sine"))


def default_data_dir() -> Path:
    """``./data`` if it holds data (the README runs from the repository root), else the source tree's ``data``."""
    local = Path("data")
    if (local / "README.md").exists() or any(local.glob("*/manifest.json")):
        return local
    return Path(__file__).resolve().parents[2] / "data"


@accepts(data_dir=InputPath(kind="folder", what="a data folder holding measurement sets"), error=DataError)
def find_measurement_sets(data_dir, *, required=("wire_rope", "elastomer")) -> dict[str, MeasurementSet]:
    """Load every measurement set in ``data_dir`` and its sub-folders, keyed by the isolator its records name.

    Parameters
    ----------
    data_dir : path
        A folder holding ``manifest.json`` or sub-folders that do.
    required : sequence of str
        Isolators that must be present.

    Returns
    -------
    dict of str to MeasurementSet

    Raises
    ------
    DataError
        Not a folder, no manifest, an isolator in two sets, or a required isolator missing.
    """
    folders = sorted({path.parent for path in data_dir.glob("*/manifest.json")})
    if (data_dir / "manifest.json").exists():
        folders.insert(0, data_dir)
    if not folders:
        raise DataError(f"{data_dir}: no manifest.json in it or its sub-folders, expected measurement sets "
                        "(see docs/data-format.md)")
    sets: dict[str, MeasurementSet] = {}
    for folder in folders:
        measurement_set = load_measurement_set(folder)
        for isolator in sorted({m.info.isolator for m in measurement_set.measurements if m.info.isolator}):
            if isolator in sets:
                raise DataError(f"{folder}: isolator {isolator!r} also found in {sets[isolator].folder}; "
                                "expected one set per isolator")
            sets[isolator] = measurement_set
    for isolator in required:
        if isolator not in sets:
            raise DataError(f"{data_dir}: no measurements of isolator {isolator!r} found, expected "
                            f"{' and '.join(required)} sets (hybrid optional)")
    return sets


def is_complex_table(path) -> bool:
    """True when ``path`` is a text table whose header names a complex stiffness / DMA table
    (``.mat`` and other binary files are not tables: False without reading them as text)."""
    path = Path(path)
    if path.suffix.lower() == ".mat":
        return False
    try:
        return complex_table_format(path) is not None
    except DataError:
        return False


def _first_line(text: str) -> str:
    """The header line: up to the first line end, ``\\n``, ``\\r\\n`` or a lone ``\\r``, as the
    CSV readers split lines."""
    return re.split(r"\r\n?|\n", text, maxsplit=1)[0]


def complex_table_format(path) -> str | None:
    """``"complex_stiffness"`` (idkit CSV: frequency, storage, loss), ``"pyvisco"`` (two-line
    header ``f, E_stor, E_loss`` / units) or None, from the first line of a file.

    Raises
    ------
    DataError
        The reader's own checks (not a file, corrupt gzip, not UTF-8).
    """
    path = Path(path)
    header = _first_line(decode_text(path, read_file_bytes(path)).lstrip("\ufeff"))
    names = {cell.split("[")[0].strip() for cell in header.split(",")}
    if {"frequency", "storage", "loss"} <= names:
        return "complex_stiffness"
    if {"f", "E_stor", "E_loss"} <= names:
        return "pyvisco"
    return None


def shift_factor_format(path) -> str:
    """``"pyvisco"`` (two-line header ``T, log_aT`` / units) or ``"idkit"`` (``temperature [C|K]``,
    ``log_aT [-]``) from the first line of a shift-factor file."""
    path = Path(path)
    header = _first_line(decode_text(path, read_file_bytes(path)).lstrip("\ufeff"))
    names = {cell.split("[")[0].strip() for cell in header.split(",")}
    return "pyvisco" if {"T", "log_aT"} <= names else "idkit"


def guess_kind(path) -> str:
    """Kind of a lone CSV file from its header.

    A white-noise and a stepped-sine file differ only by the manifest's frequency, so
    ``v_base``/``v_top`` alone reads as white noise.

    Raises
    ------
    DataError
        The header names no kind's columns (or the reader's own checks: not a file,
        corrupt gzip, not UTF-8).
    """
    path = Path(path)
    header = _first_line(decode_text(path, read_file_bytes(path)))
    names = {cell.split("[")[0].strip() for cell in header.split(",")}
    for column, kind in _KIND_BY_COLUMN:
        if column in names:
            return kind
    if {"v_base", "v_top"} <= names or {"a_base", "a_top"} <= names:
        return "white_noise"
    raise DataError(f"file '{path}': cannot tell the kind from the header {header.strip()!r}; "
                    "expected columns of a quasi_static, white_noise, stepped_sine or drop file "
                    "(or pass --kind)")


@accepts(path=InputPath(what="a measurement-set folder (with manifest.json) or a data file"), error=DataError)
def load_measurements(path, kind: str | None = None) -> tuple[str, list]:
    """Measurements of a measurement-set folder or of a single data file.

    A single file takes its metadata from the manifest of an enclosing set when one lists
    it, otherwise its kind from ``kind`` or from its header (:func:`guess_kind`).

    Returns
    -------
    (str, list)
        A title (the set's name or the file name) and the measurements.
    """
    if path.is_dir():
        if not (path / "manifest.json").exists():
            raise DataError(f"folder '{path}': no manifest.json; expected a measurement-set "
                            "folder (see docs/data-format.md)")
        measurement_set = load_measurement_set(path)
        return measurement_set.name or path.name, list(measurement_set.measurements)
    for parent in path.resolve().parents:
        if (parent / "manifest.json").exists():
            manifest = read_manifest(parent)
            relative = path.resolve().relative_to(parent).as_posix()
            for entry in manifest.entries:
                if entry.file == relative:
                    return path.name, [read_csv_measurement(path, entry.kind, info=entry.info)]
            break
    if path.suffix.lower() == ".mat":
        raise DataError(f"file '{path}': a lone .mat file holds no measurement metadata (kind, units, masses); "
                        "expected a measurement CSV, or a measurement-set folder whose manifest lists the .mat "
                        "file with its variables and units (docs/data-format.md, section 4)")
    return path.name, [read_csv_measurement(path, kind or guess_kind(path))]
