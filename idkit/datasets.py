"""Adapters for four public real data sets in ``shared/realdata`` (read in place).

Data-set-specific readers live here, apart from the format readers of :mod:`idkit.io`.

The data live beside the repository (``<repo>/../shared/realdata``) or where
the environment variable ``IDKIT_REALDATA`` points; they are never copied
into the repository. Each adapter reads one file of one set, checks the
layout it expects (names, units, shapes) and returns idkit's typed objects
in SI units with the file's SHA-256. The units come from each folder's
``SOURCE.txt``; where a source does not state a convention, the adapter's
docstring says what is assumed.

=========================  ======================================  =========================
folder                     adapter                                 returns
=========================  ======================================  =========================
pyvisco_dma                :func:`read_pyvisco_complex_modulus`    ComplexStiffnessTable (Pa)
pyvisco_dma                :func:`read_pyvisco_shift_factors`      ShiftFactorTable (K)
pyvisco_dma/verification   :func:`read_prony_reference`            PronyReference
mr_damper_labcontrol       :func:`read_mr_damper`                  QuasiStaticMeasurement
droptower_shock_afrl       :func:`read_afrl_accel`                 AccelerationRecord
boucwen_benchmark          :func:`read_boucwen_benchmark`          BoucWenBenchmark
=========================  ======================================  =========================
"""

from __future__ import annotations

import csv
import hashlib
import io
import os
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pandas as pd

from idkit.checks import Reals
from idkit.errors import DataError
from idkit.inputfiles import decode_utf8
from idkit.io.complex_stiffness import ComplexStiffnessTable, ShiftFactorTable
from idkit.io.csv_table import column_to_si, parse_number_cells, read_file_bytes
from idkit.io.contract import Column, as_signal, check_columns, check_row_widths
from idkit.io.info import MeasurementInfo
from idkit.io.matfile import MatColumn, load_mat_variables, mat_column_values, read_mat
from idkit.io.measurements import AccelerationRecord, QuasiStaticMeasurement
from idkit.io.provenance import Source
from idkit.io.units import lookup_unit

__all__ = [
    "AFRL_CHANNELS",
    "BOUCWEN_SAMPLE_RATE_HZ",
    "BoucWenBenchmark",
    "PronyReference",
    "read_afrl_accel",
    "read_boucwen_benchmark",
    "read_mr_damper",
    "read_prony_reference",
    "read_pyvisco_complex_modulus",
    "read_pyvisco_shift_factors",
    "realdata_dir",
]

#: Channel names of the AFRL drop-tower files accel_1.csv .. accel_6.csv (SOURCE.txt).
AFRL_CHANNELS: dict[int, str] = {1: "pcb_1", 2: "pcb_2", 3: "pcb_3", 4: "pcb_4",
                                 5: "fixture_top", 6: "fixture_bottom"}

#: Sample rate of the Bouc-Wen benchmark in Hz (Noel & Schoukens 2016; not stored in the .mat).
BOUCWEN_SAMPLE_RATE_HZ = 750.0


def realdata_dir(subfolder: str | None = None) -> Path | None:
    """Locate the shared real-data folder.

    Parameters
    ----------
    subfolder : str, optional
        A data set folder, e.g. ``"pyvisco_dma"``.

    Returns
    -------
    pathlib.Path or None
        ``$IDKIT_REALDATA[/subfolder]`` if the variable is set, else
        ``<repo>/../shared/realdata[/subfolder]``; ``None`` if that folder
        does not exist (tests skip then).
    """
    env = os.environ.get("IDKIT_REALDATA")
    base = Path(env) if env else Path(__file__).resolve().parents[1] / ".." / "shared" / "realdata"
    path = (base / subfolder) if subfolder else base
    return path.resolve() if path.is_dir() else None


def _text_rows(path: Path) -> tuple[list[list[str]], str]:
    raw = read_file_bytes(path)
    sha256 = hashlib.sha256(raw).hexdigest()
    text = decode_utf8(raw, f"file '{path}'", DataError)
    rows = [[cell.strip() for cell in row] for row in csv.reader(io.StringIO(text, newline=""))]
    while rows and not any(rows[-1]):
        rows.pop()
    return rows, sha256


def _two_line_header_table(path: Path, expected: dict[str, tuple[str, ...]]
                           ) -> tuple[dict[str, np.ndarray], dict[str, str], Source]:
    """Read a pyvisco CSV: line 1 names, line 2 units, then numbers.

    ``expected`` maps each accepted source name to the idkit quantities of
    its column. Returns SI values, the declared unit per name, and the source.
    """
    rows, sha256 = _text_rows(path)
    if len(rows) < 3:
        raise DataError(f"file '{path}': found {len(rows)} line(s), expected a name line, a "
                        "unit line and data rows")
    names, units = rows[0], rows[1]
    source = Source(path=path, sha256=sha256, header_lines=2,
                    columns=tuple((n, f"{n} [{u}]") for n, u in zip(names, units)))
    if len(units) != len(names) or any(n not in expected for n in names):
        raise DataError(f"{source.where()}: header {names} / units {units}; expected names "
                        f"from {list(expected)} and one unit per name")
    body = rows[2:]
    check_row_widths(body, len(names), source)
    values, declared = {}, {}
    for k, name in enumerate(names):
        scale = lookup_unit(units[k], expected[name], where=source.where(name))
        cells = [row[k] for row in body]
        values[name] = column_to_si(parse_number_cells(cells, name, source), scale, name, source)
        declared[name] = scale.quantity
    return values, declared, source


#: Columns of a pyvisco DMA table (its names; the units are on line 2).
_MODULUS_COLUMNS = (Column("f", required=True), Column("E_stor", required=True), Column("E_loss", required=True),
                    Column("T"), Column("Set"))
_SHIFT_COLUMNS = (Column("T", required=True), Column("log_aT", required=True))


def read_pyvisco_complex_modulus(path: str | Path) -> ComplexStiffnessTable:
    """Read a pyvisco DMA table (``freq_user_master.csv`` or ``freq_user_raw.csv``).

    Layout: line 1 ``f, E_stor, E_loss[, T, Set]``, line 2 the units
    (``Hz, MPa, MPa[, C, -]``), then data. The units are read from line 2
    (MPa -> Pa). The ``Set`` column of the raw file (isotherm number) is
    not kept: ``temperature`` identifies the isotherm.

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV file in ``pyvisco_dma/examples`` or ``verification``.

    Returns
    -------
    ComplexStiffnessTable
        ``quantity="modulus"``, storage/loss in Pa, temperature in K for
        raw isotherm files.
    """
    path = Path(path)
    values, quantities, source = _two_line_header_table(path, {
        "f": ("frequency",), "E_stor": ("modulus",), "E_loss": ("modulus",),
        "T": ("temperature",), "Set": ("dimensionless",),
    })
    check_columns(values, _MODULUS_COLUMNS, source.where())
    if "Set" in values and np.any(values["Set"] != np.round(values["Set"])):
        raise DataError(f"{source.where('Set')}: found non-integer isotherm numbers")
    return ComplexStiffnessTable(freq=values["f"], storage=values["E_stor"],
                                 loss=values["E_loss"], quantity="modulus",
                                 temperature=values.get("T"), source=source)


def read_pyvisco_shift_factors(path: str | Path) -> ShiftFactorTable:
    """Read a pyvisco shift-factor table (``*__shift_factors.csv``: ``T, log_aT`` / ``C, -``).

    Parameters
    ----------
    path : str or pathlib.Path
        The CSV file.

    Returns
    -------
    ShiftFactorTable
        Temperatures in K, decimal-log shift factors.
    """
    values, _, source = _two_line_header_table(Path(path), {
        "T": ("temperature",), "log_aT": ("dimensionless",)})
    check_columns(values, _SHIFT_COLUMNS, source.where())
    return ShiftFactorTable(temperature=values["T"], log_a_t=values["log_aT"], source=source)


@dataclass(frozen=True, eq=False)
class PronyReference:
    """A reference Prony series ``E(t) = E_0 (1 - sum alpha_i (1 - exp(-t / tau_i)))``.

    Parameters
    ----------
    alpha : numpy.ndarray
        Relative moduli ``E_i / E_0`` (dimensionless).
    tau : numpy.ndarray
        Relaxation times in s.
    instantaneous_modulus : float or None
        ``E_0`` in Pa, if the file (or the caller) gives it.
    source : Source
        Provenance.
    """

    alpha: np.ndarray
    tau: np.ndarray
    instantaneous_modulus: float | None = None
    source: Source = field(default_factory=Source)

    def _need_e0(self) -> float:
        if self.instantaneous_modulus is None:
            raise DataError(f"{self.source.where()}: the file gives relative moduli only; pass "
                            "instantaneous_modulus (E_0 in Pa) to read_prony_reference")
        return self.instantaneous_modulus

    @property
    def moduli(self) -> np.ndarray:
        """``E_i = alpha_i E_0`` in Pa."""
        return self.alpha * self._need_e0()

    @property
    def equilibrium_modulus(self) -> float:
        """``E_inf = E_0 (1 - sum alpha_i)`` in Pa."""
        return self._need_e0() * (1.0 - float(np.sum(self.alpha)))

    @property
    def rate(self) -> np.ndarray:
        """Relaxation rates ``1 / tau_i`` in 1/s."""
        return 1.0 / self.tau

    def to_dataframe(self) -> pd.DataFrame:
        """Columns ``alpha [-]``, ``tau [s]`` and, if E_0 is known, ``modulus [Pa]``."""
        data = {"alpha [-]": np.array(self.alpha), "tau [s]": np.array(self.tau)}
        if self.instantaneous_modulus is not None:
            data["modulus [Pa]"] = self.moduli
        return pd.DataFrame(data)


_TBDATA_RE = re.compile(r"^TBDATA\s*,\s*(\d+)\s*,(.*)$", re.IGNORECASE)
_TBPRON_RE = re.compile(r"^TB\s*,\s*PRON\s*,[^,]*,\s*(\d+)\s*,\s*(\d+)\s*,\s*(\w+)", re.IGNORECASE)


def _read_ansys_prony(path: Path, text: str, sha256: str) -> tuple[np.ndarray, np.ndarray, Source]:
    source = Source(path=path, sha256=sha256)
    n_terms = None
    data: dict[int, float] = {}
    for line_number, line in enumerate(text.splitlines(), 1):
        line = line.strip()
        header = _TBPRON_RE.match(line)
        if header:
            n_terms = int(header.group(2))
            continue
        match = _TBDATA_RE.match(line)
        if not match:
            continue
        start = int(match.group(1))
        for offset, cell in enumerate(c.strip() for c in match.group(2).split(",")):
            if cell:  # ANSYS: a blank field leaves its location as it is (the next values keep theirs)
                data[start + offset] = float(parse_number_cells([cell], f"TBDATA on line {line_number}", source)[0])
    if n_terms is None or not data:
        raise DataError(f"{source.where()}: no 'TB,PRON' table with TBDATA lines found; "
                        "expected an ANSYS Prony material file")
    expected = set(range(1, 2 * n_terms + 1))
    if set(data) != expected:
        raise DataError(f"{source.where()}: TB,PRON declares {n_terms} terms; found TBDATA "
                        f"indices {min(data)}..{max(data)} ({len(data)} values), expected "
                        f"1..{2 * n_terms}")
    pairs = np.array([data[i] for i in sorted(data)]).reshape(n_terms, 2)
    return pairs[:, 0], pairs[:, 1], source


_RELATIVE_MODULI = Reals(ge=0, meaning="relative moduli alpha_i = E_i / E_0")
_RELAXATION_TIMES = Reals(unit="s", gt=0, meaning="relaxation times tau_i")
#: The sample period ``Ts`` of an MR-damper file.
_SAMPLE_PERIOD = Reals(unit="s", gt=0, min_size=1, max_size=1, meaning="the sample period")


def read_prony_reference(path: str | Path, *,
                         instantaneous_modulus: float | None = None) -> PronyReference:
    """Read a reference Prony series of the pyvisco verification folder.

    Two layouts are understood:

    * ANSYS material file ``prony_terms.MPL``: ``TB,PRON,...,NPTS,...`` then
      ``TBDATA,start,v1,v2,v3`` lines holding the pairs (alpha_i, tau_i),
      normalized (``TBIN,NORM,1``); E_0 is not in the file.
    * ``prony_terms_KPf_MD.csv``: comment ``# E0 = <value> MPa``, comment
      ``# rel_mod, rel_time``, then rows ``alpha_i, tau_i``.

    Parameters
    ----------
    path : str or pathlib.Path
        The file.
    instantaneous_modulus : float, optional
        E_0 in Pa, for files that do not state it (or to override nothing:
        if the file states E_0 and this differs by more than 1e-9 relative,
        DataError).

    Returns
    -------
    PronyReference
        alpha (dimensionless), tau (s) and E_0 (Pa) if known; ``moduli``
        and ``equilibrium_modulus`` give E_i and E_inf in Pa.
    """
    path = Path(path)
    raw = read_file_bytes(path)
    sha256 = hashlib.sha256(raw).hexdigest()
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise DataError(f"file '{path}': not UTF-8 text (byte {exc.start})") from None
    e0 = None
    if path.suffix.upper() == ".MPL":
        alpha, tau, source = _read_ansys_prony(path, text, sha256)
    else:
        lines = text.splitlines()
        source = Source(path=path, sha256=sha256)
        header_lines = next((n for n, line in enumerate(lines) if not line.startswith("#")),
                            len(lines))
        comments = lines[:header_lines]
        match = next((re.match(r"#\s*E0\s*=\s*(\S+)\s*(\S+)", c) for c in comments
                      if re.match(r"#\s*E0\s*=", c)), None)
        if match is None:
            raise DataError(f"{source.where()}: no '# E0 = <value> <unit>' line; expected the "
                            "pyvisco prony_terms layout")
        scale = lookup_unit(match.group(2), "modulus", where=f"{source.where()}, E0 line")
        e0 = float(column_to_si(parse_number_cells([match.group(1)], "E0", source), scale, "E0", source)[0])
        source = Source(path=path, sha256=sha256, header_lines=header_lines)
        body = lines[header_lines:]
        while body and not body[-1].strip():
            body.pop()
        rows = [[c.strip() for c in line.split(",")] for line in body]
        check_row_widths(rows, 2, source, " (rel_mod, rel_time)")
        alpha = parse_number_cells([r[0] for r in rows], "rel_mod", source)
        tau = parse_number_cells([r[1] for r in rows], "rel_time", source)
    if e0 is not None and instantaneous_modulus is not None and not np.isclose(
            e0, instantaneous_modulus, rtol=1e-9, atol=0.0):
        raise DataError(f"{source.where()}: file states E0 = {e0} Pa, caller passed "
                        f"instantaneous_modulus = {instantaneous_modulus} Pa")
    e0 = e0 if e0 is not None else instantaneous_modulus
    alpha = _RELATIVE_MODULI.check(alpha, f"{source.where()}: alpha", DataError)
    tau = _RELAXATION_TIMES.check(tau, f"{source.where()}: tau", DataError)
    return PronyReference(alpha=alpha, tau=tau, instantaneous_modulus=e0, source=source)


def read_mr_damper(path: str | Path) -> QuasiStaticMeasurement:
    """Read an MR-damper loop file of ``mr_damper_labcontrol`` (``ensaio*.mat``, ``exp*.mat``).

    Columns: ``Tout`` time [s]; ``x_F[:,0]`` position [mm] -> deflection;
    ``x_F[:,1]`` velocity [mm/s] -> v_rel; ``x_F[:,2]`` force [N]. The
    units are not stated by the source; SOURCE.txt reads them as mm, mm/s, N
    (the velocity column is the time derivative of the position column in
    the same length unit, correlation 0.9995). The sign convention of the
    position is the source's (not stated); idkit takes it as deflection as
    is. ``Ts`` (s) is checked against ``Tout`` as ``sample_rate_hz`` (1 %).

    Parameters
    ----------
    path : str or pathlib.Path
        The ``.mat`` file.

    Returns
    -------
    QuasiStaticMeasurement
        SI units (m, m/s, N); ``info.isolator = "mr_damper"``.
    """
    path = Path(path)
    variables, _ = load_mat_variables(path)
    ts = _SAMPLE_PERIOD.check(np.asarray(variables.get("Ts", np.array([]))).ravel(), f"file '{path}': variable 'Ts'",
                              DataError)
    info = MeasurementInfo(id=path.name.removesuffix(".mat"), isolator="mr_damper",
                           sample_rate_hz=1.0 / float(ts[0]),
                           notes="mr_damper_labcontrol; units mm, mm/s, N per SOURCE.txt")
    return read_mat(path, "quasi_static", info=info, columns={
        "time": "Tout [s]", "deflection": "x_F[:,0] [mm]",
        "v_rel": "x_F[:,1] [mm/s]", "force": "x_F[:,2] [N]"})


def read_afrl_accel(path: str | Path) -> AccelerationRecord:
    """Read one AFRL drop-tower accelerometer file (``accel_<k>.csv``).

    Layout (SOURCE.txt, checked): two header lines (they list channel names
    and do not describe the columns; they are checked to start with
    ``time`` and otherwise ignored), then rows ``time [s], test 1 .. test 5``
    with accelerations in units of 1000 g (``kg_n`` in the source; idkit
    unit ``1000g`` = 9806.65 m/s^2).

    Parameters
    ----------
    path : str or pathlib.Path
        ``accel_1.csv`` .. ``accel_6.csv``.

    Returns
    -------
    AccelerationRecord
        Time in s, accel in m/s^2 with shape ``(5000, 5)``; channel from
        :data:`AFRL_CHANNELS` (``accel_6`` = fixture bottom = the input).
    """
    path = Path(path)
    rows, sha256 = _text_rows(path)
    source = Source(path=path, sha256=sha256, header_lines=2)
    if len(rows) < 4 or not rows[0] or rows[0][0].lower() != "time":
        raise DataError(f"{source.where()}: expected two header lines starting with 'time' "
                        "and data rows")
    body = rows[2:]
    width = len(body[0])
    if width < 2:
        raise DataError(f"{source.where()}: found {width} column(s), expected time + tests")
    check_row_widths(body, width, source)
    time = parse_number_cells([r[0] for r in body], "time", source)
    scale = lookup_unit("1000g", "acceleration", where=source.where())
    accel = np.column_stack([
        column_to_si(parse_number_cells([r[k] for r in body], f"test {k}", source), scale, f"test {k}", source)
        for k in range(1, width)])
    match = re.search(r"accel_(\d+)", path.name)
    channel = AFRL_CHANNELS.get(int(match.group(1)), path.stem) if match else path.stem
    return AccelerationRecord(time=time, accel=accel, channel=channel, source=source)


@dataclass(frozen=True, eq=False)
class BoucWenBenchmark:
    """The Noel & Schoukens Bouc-Wen benchmark data (simulated; force in, displacement out).

    Parameters
    ----------
    sample_rate_hz : float
        750 Hz.
    train_force, train_displacement : numpy.ndarray
        Training multisine (5 periods of 8192 samples): force in N,
        displacement in m.
    test_multisine_force, test_multisine_displacement : numpy.ndarray
        Official multisine test data (N, m).
    test_sinesweep_force, test_sinesweep_displacement : numpy.ndarray
        Official sine-sweep test data (N, m).
    source : Source
        Provenance.
    """

    sample_rate_hz: float
    train_force: np.ndarray
    train_displacement: np.ndarray
    test_multisine_force: np.ndarray
    test_multisine_displacement: np.ndarray
    test_sinesweep_force: np.ndarray
    test_sinesweep_displacement: np.ndarray
    source: Source = field(default_factory=Source)

    def time(self, n_samples: int) -> np.ndarray:
        """Time in s of ``n_samples`` samples from 0 at :attr:`sample_rate_hz`."""
        return np.arange(n_samples) / self.sample_rate_hz


def read_boucwen_benchmark(path: str | Path) -> BoucWenBenchmark:
    """Read ``boucwen_benchmark/bouc-wen.mat`` (variables u, y, uval_*, yval_*).

    Parameters
    ----------
    path : str or pathlib.Path
        The ``.mat`` file.

    Returns
    -------
    BoucWenBenchmark
        Force in N and displacement in m (SOURCE.txt; already SI), at
        :data:`BOUCWEN_SAMPLE_RATE_HZ`.
    """
    path = Path(path)
    variables, sha256 = load_mat_variables(path)
    source = Source(path=path, sha256=sha256)
    names = {"train_force": "u", "train_displacement": "y",
             "test_multisine_force": "uval_multisine",
             "test_multisine_displacement": "yval_multisine",
             "test_sinesweep_force": "uval_sinesweep",
             "test_sinesweep_displacement": "yval_sinesweep"}
    arrays = {}
    for field_name, var in names.items():
        values = mat_column_values(variables, MatColumn(var, None, None), source.where(var))
        arrays[field_name] = as_signal(values, var, source)
    for prefix in ("train", "test_multisine", "test_sinesweep"):
        if arrays[f"{prefix}_force"].size != arrays[f"{prefix}_displacement"].size:
            force_var, displacement_var = names[f"{prefix}_force"], names[f"{prefix}_displacement"]
            raise DataError(f"{source.where()}: {prefix}: found {arrays[f'{prefix}_force'].size} samples of "
                            f"'{force_var}' (force) and {arrays[f'{prefix}_displacement'].size} of "
                            f"'{displacement_var}' (displacement), expected equal lengths")
    return BoucWenBenchmark(sample_rate_hz=BOUCWEN_SAMPLE_RATE_HZ, source=source, **arrays)
