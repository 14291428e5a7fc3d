"""Read and write one measurement as an idkit CSV file (``.csv`` or ``.csv.gz``)."""

from __future__ import annotations

import gzip
from collections.abc import Mapping
from pathlib import Path

from idkit.errors import DataError
from idkit.atomic import write_bytes_atomic
from idkit.io.columns import KIND, KIND_SCHEMAS
from idkit.io.csv_table import read_csv_table
from idkit.io.info import MeasurementInfo
from idkit.io.measurements import (
    SIGNAL_QUANTITIES,
    Measurement,
    measurement_class,
)
from idkit.io.provenance import Source
from idkit.io.units import SI_UNITS, convert_from_si, lookup_unit

__all__ = ["build_measurement", "read_csv_measurement", "write_csv_measurement"]


def build_measurement(kind: str, values: Mapping, *, info: MeasurementInfo | None = None,
                      source: Source | None = None) -> Measurement:
    """Construct the measurement dataclass of ``kind`` from SI columns.

    Parameters
    ----------
    kind : str
        ``"quasi_static"``, ``"white_noise"``, ``"stepped_sine"`` or ``"drop"``.
    values : mapping of str to array_like
        Column name -> values in SI units (names as in the file format).
    info : MeasurementInfo, optional
        Metadata.
    source : Source, optional
        Provenance.

    Returns
    -------
    Measurement
        The dataclass instance (all checks done).
    """
    cls = measurement_class(kind)
    return cls(**dict(values), info=info or MeasurementInfo(), source=source or Source())


def read_csv_measurement(path: str | Path, kind: str, *,
                         info: MeasurementInfo | None = None) -> Measurement:
    """Read one measurement from an idkit CSV file.

    Parameters
    ----------
    path : str or pathlib.Path
        ``.csv`` or ``.csv.gz`` file; header ``name [unit]`` (see
        ``docs/data-format.md``).
    kind : str
        ``"quasi_static"`` (time, deflection, force; optional v_rel),
        ``"white_noise"`` (time and v_base, v_top or a_base, a_top),
        ``"stepped_sine"`` (time, v_base, v_top; optional x_base, u_in) or
        ``"drop"`` (time, deflection, a_top_1, a_top_2; optional v_rel).
    info : MeasurementInfo, optional
        Metadata. Its ``sample_rate_hz`` (if set) is checked against the
        time column within 1 %; stepped-sine points need
        ``info.excitation.freq`` in Hz. Default: id = file name stem.

    Returns
    -------
    QuasiStaticMeasurement, WhiteNoiseMeasurement, SteppedSineMeasurement or DropMeasurement
        Values in SI, with ``source.path`` and ``source.sha256``.

    Raises
    ------
    DataError
        On any format or content problem; the message names the file, the
        column, the 1-based data row, what was found and what was expected.

    Examples
    --------
    >>> m = read_csv_measurement("qs_small_1.csv", "quasi_static")  # doctest: +SKIP
    >>> m.force  # N  # doctest: +SKIP
    """
    KIND.check(kind, f"file '{path}': kind", DataError)
    table = read_csv_table(path, KIND_SCHEMAS[kind])
    if info is None:
        name = Path(path).name
        info = MeasurementInfo(id=name.split(".")[0])
    return build_measurement(kind, table.values, info=info, source=table.source)


def format_csv(columns: Mapping[str, object]) -> str:
    """Format named float columns as CSV text with shortest round-trip floats.

    Parameters
    ----------
    columns : mapping of str to array_like
        Header cell -> values; all of the same length.

    Returns
    -------
    str
        CSV text, ``\\n`` line ends, each value as Python ``repr(float)`` (the
        shortest string that reads back to the same double).
    """
    header = ",".join(columns)
    lists = [list(map(repr, [float(v) for v in values])) for values in columns.values()]
    lines = [header] + [",".join(row) for row in zip(*lists)]
    return "\n".join(lines) + "\n"


def write_csv_measurement(measurement: Measurement, path: str | Path, *,
                          units: Mapping[str, str] | None = None,
                          overwrite: bool = False) -> Path:
    """Write a measurement as an idkit CSV file, atomically.

    Parameters
    ----------
    measurement : Measurement
        Any of the four measurement dataclasses.
    path : str or pathlib.Path
        Target ``.csv`` or ``.csv.gz`` file (gzip written with mtime 0, so the
        bytes are reproducible).
    units : mapping of str to str, optional
        Column name -> unit to write instead of SI, e.g. ``{"force": "daN"}``.
        SI columns round-trip bit for bit; converted columns may differ in
        the last bit.
    overwrite : bool
        Replace an existing file. Default ``False``: raise FileExistsError.

    Returns
    -------
    pathlib.Path
        The written file.

    Raises
    ------
    DataError
        For a unit not accepted for a column or a column the measurement
        does not have.
    FileExistsError
        If the target exists and ``overwrite`` is false.
    """
    path = Path(path)
    units = dict(units or {})
    signals = measurement.signals()
    unknown = sorted(set(units) - set(signals))
    if unknown:
        raise DataError(f"units given for column(s) {', '.join(unknown)} that "
                        f"{type(measurement).__name__} does not have; it has {', '.join(signals)}")
    columns = {}
    for name, values in signals.items():
        quantity = SIGNAL_QUANTITIES[name]
        if name in units:
            scale = lookup_unit(units[name], quantity, where=f"writing '{path}', column '{name}'")
            columns[f"{name} [{scale.symbol}]"] = convert_from_si(values, scale)
        else:
            columns[f"{name} [{SI_UNITS[quantity]}]"] = values
    data = format_csv(columns).encode("utf-8")
    if path.name.endswith(".gz"):
        data = gzip.compress(data, mtime=0)
    return write_bytes_atomic(path, data, overwrite=overwrite)
