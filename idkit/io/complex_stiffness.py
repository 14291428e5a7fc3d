"""Complex stiffness / DMA tables: frequency, storage and loss part.

File format (idkit CSV, ``name [unit]`` header)::

    frequency [Hz],storage [MPa],loss [MPa]
    0.1,8097.175545,93.07449045

``storage`` and ``loss`` are either stiffness (N/m, N/mm, kN/m, kN/mm) or
modulus (Pa, kPa, MPa, GPa); both columns must be the same quantity, which
the table records as ``quantity``. Optional columns: ``temperature [C|K]``
(isotherm sweeps) and ``log_aT [-]`` (decimal log of the time-temperature
shift factor of each row). A separate shift-factor table
(``temperature``, ``log_aT``) is read by :func:`read_shift_factors`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from idkit.checks import Choice
from idkit.errors import DataError
from idkit.atomic import write_bytes_atomic
from idkit.io.columns import COMPLEX_STIFFNESS_SCHEMA, KindSchema
from idkit.io.contract import as_signal, read_columns
from idkit.io.csv_measurement import format_csv
from idkit.io.csv_table import read_csv_table
from idkit.io.provenance import Source
from idkit.io.units import SI_UNITS

__all__ = [
    "ComplexStiffnessTable",
    "ShiftFactorTable",
    "read_complex_stiffness",
    "read_shift_factors",
    "write_complex_stiffness",
]

SHIFT_FACTOR_SCHEMA = KindSchema("shift_factors", ("temperature", "log_aT"))


_QUANTITY = Choice(("stiffness", "modulus"))


@dataclass(frozen=True, eq=False)
class ComplexStiffnessTable:
    """Complex stiffness ``k* = storage + i loss`` (or modulus ``E*``) versus frequency.

    Parameters
    ----------
    freq : numpy.ndarray
        Frequency in Hz (> 0). Not required to be sorted (isotherm sweeps
        repeat the frequency grid per temperature).
    storage : numpy.ndarray
        Storage part in N/m (``quantity="stiffness"``) or Pa (``"modulus"``).
    loss : numpy.ndarray
        Loss part, same unit as ``storage``.
    quantity : str
        ``"stiffness"`` or ``"modulus"``.
    temperature : numpy.ndarray or None
        Test temperature of each row in K.
    log_a_t : numpy.ndarray or None
        Decimal log of the shift factor of each row (dimensionless).
    source : Source
        Provenance.
    """

    freq: np.ndarray
    storage: np.ndarray
    loss: np.ndarray
    quantity: str = "stiffness"
    temperature: np.ndarray | None = None
    log_a_t: np.ndarray | None = None
    source: Source = field(default_factory=Source)

    def __post_init__(self) -> None:
        _QUANTITY.check(self.quantity, "quantity", DataError)
        names = ("freq", "storage", "loss", "temperature", "log_a_t")
        arrays = read_columns({name: getattr(self, name) for name in names}, self.source,
                              {"freq": "frequency", "log_a_t": "log_aT"})
        for name, array in arrays.items():
            object.__setattr__(self, name, array)
        if self.freq.size == 0:
            raise DataError(f"{self.source.where()}: no rows, expected at least one")
        bad = np.flatnonzero(self.freq <= 0)
        if bad.size:
            i = int(bad[0])
            raise DataError(f"{self.source.where('frequency')}: {self.source.row_label(i)}: "
                            f"found {float(self.freq[i])!r}, expected a frequency > 0 Hz")

    @property
    def unit(self) -> str:
        """SI unit of storage and loss: ``"N/m"`` or ``"Pa"``."""
        return SI_UNITS[self.quantity]

    @property
    def omega(self) -> np.ndarray:
        """Angular frequency in rad/s."""
        return 2.0 * np.pi * self.freq

    @property
    def complex_value(self) -> np.ndarray:
        """``storage + 1j * loss`` in N/m or Pa."""
        return self.storage + 1j * self.loss

    @property
    def loss_factor(self) -> np.ndarray:
        """Loss factor ``eta = loss / storage`` (SPEC eq. 4.4), dimensionless."""
        return self.loss / self.storage

    def to_dataframe(self) -> pd.DataFrame:
        """Columns ``frequency [Hz]``, ``storage [N/m|Pa]``, ``loss [...]`` (+ optional)."""
        data = {"frequency [Hz]": np.array(self.freq),
                f"storage [{self.unit}]": np.array(self.storage),
                f"loss [{self.unit}]": np.array(self.loss)}
        if self.temperature is not None:
            data["temperature [K]"] = np.array(self.temperature)
        if self.log_a_t is not None:
            data["log_aT [-]"] = np.array(self.log_a_t)
        return pd.DataFrame(data)

    def master_curve(self, shift_factors: ShiftFactorTable, *,
                     temperature_tol_k: float = 1.0) -> ComplexStiffnessTable:
        """Shift isotherm rows to the reference temperature (time-temperature superposition).

        Each row's reduced frequency is ``freq * 10**log_aT`` with the shift
        factor of the isotherm whose temperature is nearest to the row's
        temperature; rows are then sorted by reduced frequency (a new table;
        this one is unchanged).

        Parameters
        ----------
        shift_factors : ShiftFactorTable
            Temperatures in K and log10 shift factors.
        temperature_tol_k : float
            Largest accepted distance in K between a row's measured
            temperature and the nearest shift-factor temperature.

        Returns
        -------
        ComplexStiffnessTable
            Reduced frequency in Hz, same storage/loss, with ``log_a_t`` set.

        Raises
        ------
        DataError
            If the table has no temperature column or a row has no shift
            factor within ``temperature_tol_k``.
        """
        if self.temperature is None:
            raise DataError(f"{self.source.where()}: no temperature column; expected "
                            "isotherm data with 'temperature [C|K]' to build a master curve")
        distance = np.abs(self.temperature[:, None] - shift_factors.temperature[None, :])
        nearest = np.argmin(distance, axis=1)
        worst = int(np.argmax(distance[np.arange(nearest.size), nearest]))
        if distance[worst, nearest[worst]] > temperature_tol_k:
            raise DataError(
                f"{self.source.where('temperature')}: {self.source.row_label(worst)}: "
                f"found {self.temperature[worst]:.4g} K, expected a shift factor within "
                f"{temperature_tol_k} K (nearest {shift_factors.temperature[nearest[worst]]:.4g} K)"
            )
        log_a_t = shift_factors.log_a_t[nearest]
        reduced = self.freq * 10.0 ** log_a_t
        order = np.argsort(reduced, kind="stable")
        return ComplexStiffnessTable(
            freq=reduced[order], storage=self.storage[order], loss=self.loss[order],
            quantity=self.quantity, temperature=self.temperature[order],
            log_a_t=log_a_t[order], source=self.source,
        )


@dataclass(frozen=True, eq=False)
class ShiftFactorTable:
    """Time-temperature shift factors of a master curve.

    Parameters
    ----------
    temperature : numpy.ndarray
        Temperatures in K.
    log_a_t : numpy.ndarray
        Decimal log of the shift factor at each temperature (0 at the
        reference temperature).
    source : Source
        Provenance.
    """

    temperature: np.ndarray
    log_a_t: np.ndarray
    source: Source = field(default_factory=Source)

    def __post_init__(self) -> None:
        temperature = as_signal(self.temperature, "temperature", self.source)
        log_a_t = as_signal(self.log_a_t, "log_aT", self.source)
        if temperature.size != log_a_t.size or temperature.size == 0:
            raise DataError(f"{self.source.where()}: found {temperature.size} temperatures and "
                            f"{log_a_t.size} shift factors, expected equal non-zero counts")
        # master_curve takes the nearest temperature's shift factor: a repeated temperature would
        # silently keep one of its rows
        order = np.argsort(temperature, kind="stable")
        repeated = np.flatnonzero(np.diff(temperature[order]) == 0)
        if repeated.size:
            first, second = sorted((int(order[repeated[0]]), int(order[repeated[0] + 1])))
            raise DataError(f"{self.source.where('temperature')}: {self.source.row_label(second)}: temperature "
                            f"{float(temperature[second])!r} K repeats {self.source.row_label(first)} (log_aT "
                            f"{float(log_a_t[first])!r} there, {float(log_a_t[second])!r} here); expected one shift "
                            "factor per temperature")
        object.__setattr__(self, "temperature", temperature)
        object.__setattr__(self, "log_a_t", log_a_t)

    @property
    def reference_temperature(self) -> float | None:
        """Temperature in K where ``log_aT == 0``, if present."""
        hits = np.flatnonzero(self.log_a_t == 0.0)
        return float(self.temperature[hits[0]]) if hits.size else None

    def to_dataframe(self) -> pd.DataFrame:
        """Columns ``temperature [K]``, ``log_aT [-]``."""
        return pd.DataFrame({"temperature [K]": np.array(self.temperature),
                             "log_aT [-]": np.array(self.log_a_t)})


def read_complex_stiffness(path: str | Path) -> ComplexStiffnessTable:
    """Read a complex stiffness or DMA modulus table (idkit CSV format).

    Parameters
    ----------
    path : str or pathlib.Path
        ``.csv`` / ``.csv.gz`` with columns ``frequency [Hz]``,
        ``storage [unit]``, ``loss [unit]`` and optionally
        ``temperature [C|K]``, ``log_aT [-]``.

    Returns
    -------
    ComplexStiffnessTable
        SI values: N/m for stiffness units, Pa for modulus units.

    Raises
    ------
    DataError
        Format problems, or storage and loss of different quantities.

    Examples
    --------
    >>> table = read_complex_stiffness("dma.csv")  # doctest: +SKIP
    >>> table.quantity, table.unit  # doctest: +SKIP
    ('modulus', 'Pa')
    """
    table = read_csv_table(path, COMPLEX_STIFFNESS_SCHEMA)
    storage_q = table.scales["storage"].quantity
    loss_q = table.scales["loss"].quantity
    if storage_q != loss_q:
        raise DataError(f"{table.source.where('loss')}: found a {loss_q} unit, expected a "
                        f"{storage_q} unit like the storage column")
    v = table.values
    return ComplexStiffnessTable(freq=v["frequency"], storage=v["storage"], loss=v["loss"],
                                 quantity=storage_q, temperature=v.get("temperature"),
                                 log_a_t=v.get("log_aT"), source=table.source)


def read_shift_factors(path: str | Path) -> ShiftFactorTable:
    """Read a shift-factor table with columns ``temperature [C|K]``, ``log_aT [-]``.

    Parameters
    ----------
    path : str or pathlib.Path
        idkit CSV file.

    Returns
    -------
    ShiftFactorTable
        Temperatures in K.
    """
    table = read_csv_table(path, SHIFT_FACTOR_SCHEMA)
    return ShiftFactorTable(temperature=table.values["temperature"],
                            log_a_t=table.values["log_aT"], source=table.source)


def write_complex_stiffness(table: ComplexStiffnessTable, path: str | Path, *,
                            overwrite: bool = False) -> Path:
    """Write a complex stiffness table in SI units (round-trips bit for bit), atomically.

    Parameters
    ----------
    table : ComplexStiffnessTable
        The table.
    path : str or pathlib.Path
        Target ``.csv`` file.
    overwrite : bool
        Replace an existing file (default: raise FileExistsError).

    Returns
    -------
    pathlib.Path
        The written file.
    """
    columns = dict(table.to_dataframe().items())
    return write_bytes_atomic(path, format_csv(columns).encode("utf-8"), overwrite=overwrite)
