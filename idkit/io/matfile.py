"""Read measurements from MATLAB ``.mat`` files (v4 - v7.2, via scipy.io.loadmat).

A ``.mat`` file has variables, not headers, so the caller (or the manifest
entry's ``mat_columns``) maps each idkit column to a variable and declares its
unit, in the same ``name [unit]`` spirit as a CSV header::

    {"time": "Tout [s]", "deflection": "x_F[:,0] [mm]", "force": "x_F[:,2] [N]"}

``var`` takes a vector variable (shape ``(n,)``, ``(n, 1)`` or ``(1, n)``);
``var[:,k]`` takes column ``k`` (0-based, Python convention) of a 2-D
variable. MATLAB v7.3 (HDF5) files are not supported: DataError says so.
"""

from __future__ import annotations

import hashlib
import io
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.io

from idkit.checks import Instance
from idkit.errors import DataError
from idkit.io.columns import COLUMN_QUANTITIES, KIND, KIND_SCHEMAS, did_you_mean
from idkit.io.csv_measurement import build_measurement
from idkit.io.csv_table import column_to_si, read_file_bytes
from idkit.io.info import MeasurementInfo
from idkit.io.measurements import Measurement
from idkit.io.provenance import Source
from idkit.io.units import lookup_unit

__all__ = ["MatColumn", "check_exact_in_float64", "load_mat_variables", "mat_column_values", "parse_mat_column",
           "read_mat"]

_SPEC_RE = re.compile(
    r"^\s*([A-Za-z][A-Za-z0-9_]*)\s*(?:\[\s*:\s*,\s*(\d+)\s*\])?\s*(?:\[([^\[\]]*)\])?\s*$"
)


@dataclass(frozen=True)
class MatColumn:
    """Where one idkit column is in a ``.mat`` file.

    Parameters
    ----------
    variable : str
        MATLAB variable name, e.g. ``"x_F"``.
    index : int or None
        0-based column of a 2-D variable, or ``None`` for a vector.
    unit : str or None
        Declared unit, e.g. ``"mm"`` (``None``: missing, an error when read).
    """

    variable: str
    index: int | None
    unit: str | None

    def label(self) -> str:
        """The spec as text, e.g. ``"x_F[:,0] [mm]"``."""
        text = self.variable if self.index is None else f"{self.variable}[:,{self.index}]"
        return f"{text} [{self.unit}]" if self.unit else text


def parse_mat_column(spec: str | MatColumn, *, where: str) -> MatColumn:
    """Parse ``"var [unit]"`` or ``"var[:,k] [unit]"`` into a :class:`MatColumn`.

    Parameters
    ----------
    spec : str or MatColumn
        The column spec.
    where : str
        Location for error messages.

    Returns
    -------
    MatColumn
    """
    if isinstance(spec, MatColumn):
        return spec
    match = _SPEC_RE.match(spec) if isinstance(spec, str) else None
    if match is None:
        raise DataError(f"{where}: found column spec {spec!r}, expected 'var [unit]' or "
                        "'var[:,k] [unit]' (k 0-based)")
    variable, index, unit = match.groups()
    unit = unit.strip() if unit is not None else None
    return MatColumn(variable, None if index is None else int(index), unit or None)


def load_mat_variables(path: str | Path) -> tuple[dict[str, np.ndarray], str]:
    """Load the variables of a ``.mat`` file, reading the file once.

    Parameters
    ----------
    path : str or pathlib.Path
        MATLAB v4-v7.2 file.

    Returns
    -------
    variables : dict of str to numpy.ndarray
        Variables (MATLAB ``__header__`` etc. removed).
    sha256 : str
        SHA-256 of the file bytes that were parsed.
    """
    path = Path(path)
    raw = read_file_bytes(path)
    sha256 = hashlib.sha256(raw).hexdigest()
    if not raw:
        raise DataError(f"file '{path}': empty file (0 bytes); expected a MATLAB .mat file")
    if raw[:128].startswith(b"MATLAB 7.3") or raw[:8] == b"\x89HDF\r\n\x1a\n":
        raise DataError(f"file '{path}': MATLAB v7.3 (HDF5) file; expected a v4-v7.2 .mat "
                        "file (re-save with save(..., '-v7'))")
    try:
        variables = scipy.io.loadmat(io.BytesIO(raw))
    # scipy's parser is not hardened against malformed bytes: fuzzing truncated and
    # corrupted files raised OSError, ValueError, zlib.error, IndexError, TypeError,
    # MatReadError and even UnboundLocalError. Whatever it raises while parsing these
    # bytes means one thing, "not a readable .mat file", so every exception is turned
    # into the file's DataError (the exception type is kept in the message).
    except Exception as exc:  # noqa: BLE001 - see above
        raise DataError(f"file '{path}': not a readable MATLAB .mat file, truncated or corrupt "
                        f"({type(exc).__name__}: {exc}); expected a MATLAB v4-v7.2 .mat "
                        "file") from None
    variables = {k: v for k, v in variables.items() if not k.startswith("__")}
    if not variables:
        raise DataError(f"file '{path}': a .mat header without any variable (truncated?); "
                        "expected the variables of a measurement")
    return variables, sha256


_EXACT_INTEGER_LIMIT = 2**53  # every integer up to this magnitude is exact in float64


def mat_column_values(variables: dict, column: MatColumn, where: str) -> np.ndarray:
    """The values of one column of loaded ``.mat`` variables (a vector, or column ``k`` of a 2-D
    variable), refused unless present, real and exactly representable in float64."""
    if column.variable not in variables:
        raise DataError(f"{where}: variable '{column.variable}' not in the file; found "
                        f"{', '.join(sorted(variables)) or 'no variables'}")
    value = np.asarray(variables[column.variable])
    if value.dtype.kind not in "iuf":
        raise DataError(f"{where}: variable '{column.variable}' has dtype {value.dtype}, "
                        "expected real numbers")
    if column.index is None:
        if value.ndim > 2 or (value.ndim == 2 and min(value.shape) != 1):
            raise DataError(f"{where}: variable '{column.variable}' has shape {value.shape}, "
                            "expected a vector; select a column with 'var[:,k]'")
        selected = value.reshape(-1)
    else:
        if value.ndim != 2 or column.index >= value.shape[1]:
            raise DataError(f"{where}: variable '{column.variable}' has shape {value.shape}, "
                            f"expected a 2-D array with a column {column.index} (0-based)")
        selected = value[:, column.index]
    check_exact_in_float64(selected, column.variable, where)
    return selected


def check_exact_in_float64(values: np.ndarray, variable: str, where: str) -> None:
    """Refuse integers (int64/uint64) that float64 would round: beyond 2^53 only some are exact."""
    if values.dtype.kind not in "iu" or values.dtype.itemsize < 8:
        return  # float, or integers of up to 32 bits: all exact in float64
    beyond = np.flatnonzero((values > _EXACT_INTEGER_LIMIT) | (values < -_EXACT_INTEGER_LIMIT))
    for i in beyond:
        number = int(values[i])
        if int(float(number)) != number:
            raise DataError(f"{where}: variable '{variable}' ({values.dtype}) sample {i + 1} (1-based): "
                            f"found {number}, which float64 cannot hold exactly (it would read as "
                            f"{float(number)!r}); expected integers within +-2^53 or exactly "
                            "representable as float64")


_COLUMN_MAPPING = Instance((Mapping,), what="a mapping idkit column -> 'var [unit]' (a .mat file has no header "
                                          "to read the units from)")


def read_mat(path: str | Path, kind: str, *, columns: Mapping[str, str | MatColumn],
             info: MeasurementInfo | None = None) -> Measurement:
    """Read one measurement from a MATLAB ``.mat`` file.

    Parameters
    ----------
    path : str or pathlib.Path
        ``.mat`` file (v4 - v7.2).
    kind : str
        ``"quasi_static"``, ``"white_noise"``, ``"stepped_sine"`` or ``"drop"``.
    columns : mapping of str to str or MatColumn
        idkit column name -> ``"var [unit]"`` or ``"var[:,k] [unit]"``
        (k 0-based). Units are required and looked up as for CSV headers.
    info : MeasurementInfo, optional
        Metadata (sample rate checked within 1 %).

    Returns
    -------
    Measurement
        Values in SI; ``source.columns`` records the specs; rows in error
        messages are 1-based sample numbers.

    Raises
    ------
    DataError
        Missing variable, wrong shape, unknown or missing unit, non-finite
        values, time not strictly increasing, sample-rate mismatch, ...

    Examples
    --------
    >>> read_mat("ensaio1.mat", "quasi_static", columns={  # doctest: +SKIP
    ...     "time": "Tout [s]", "deflection": "x_F[:,0] [mm]", "force": "x_F[:,2] [N]"})
    """
    path = Path(path)
    schema = KIND_SCHEMAS[KIND.check(kind, f"file '{path}': kind", DataError)]
    _COLUMN_MAPPING.check(columns, f"file '{path}': columns", DataError)
    specs = {name: parse_mat_column(spec, where=f"file '{path}', column '{name}'")
             for name, spec in columns.items()}
    unknown = [name for name in specs if name not in schema.allowed]
    missing = [name for name in schema.required if name not in specs]
    if unknown or missing:
        hints = "".join(f"; '{name}'{did_you_mean(name, schema.allowed)}" for name in unknown
                        if did_you_mean(name, schema.allowed))
        raise DataError(f"file '{path}': column mapping has unknown {unknown} / lacks "
                        f"{missing}{hints}; expected for {kind}: {schema.describe()}")
    variables, sha256 = load_mat_variables(path)
    source = Source(path=path, sha256=sha256,
                    columns=tuple((name, spec.label()) for name, spec in specs.items()))
    values = {}
    for name, spec in specs.items():
        where = source.where(name)
        scale = lookup_unit(spec.unit, COLUMN_QUANTITIES[name], where=where)
        values[name] = column_to_si(mat_column_values(variables, spec, where), scale, name, source)
    if info is None:
        info = MeasurementInfo(id=path.name.removesuffix(".mat"))
    return build_measurement(kind, values, info=info, source=source)
