"""Measurement sets: a folder with ``manifest.json`` listing every measurement file.

See ``docs/data-format.md`` for the format. The manifest is JSON because the
standard library both reads and writes it (``tomllib`` only reads TOML), so
the synthetic-data generator can write manifests without a dependency.
Entries are checked completely (unknown keys, kinds, masses, files) before
any data file is read; every problem raises
:class:`~idkit.errors.DataError` naming the manifest, the entry (1-based
position in ``measurements`` and its id), what was found and what was
expected.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, replace
from pathlib import Path

import pandas as pd

from idkit.checks import Choice, Field, Instance, Real, Reals, Text, accepts, check_fields, field_names, refuse
from idkit.errors import DataError
from idkit.inputfiles import load_json, path_problem, read_input_bytes
from idkit.atomic import write_bytes_atomic
from idkit.io.columns import KIND, KINDS
from idkit.io.csv_measurement import read_csv_measurement, write_csv_measurement
from idkit.io.info import AMPLITUDE_QUANTITIES, INFO_FIELDS, Excitation, MeasurementInfo
from idkit.io.matfile import MatColumn, parse_mat_column, read_mat
from idkit.io.measurements import Measurement, check_excitation_resolved
from idkit.io.units import SI_UNITS, lookup_unit

__all__ = [
    "MANIFEST_FORMAT",
    "MANIFEST_NAME",
    "MANIFEST_VERSION",
    "Manifest",
    "ManifestEntry",
    "MeasurementSet",
    "load_measurement_set",
    "read_manifest",
    "write_measurement_set",
]

MANIFEST_NAME = "manifest.json"
MANIFEST_FORMAT = "idkit-measurement-set"
MANIFEST_VERSION = 1

_INFO_KEYS = tuple(name for name in field_names(INFO_FIELDS) if name not in ("id", "excitation"))

#: A measurement id: also the stem of the file the writer names after it.
_ID = Text(pattern=r"[A-Za-z0-9][A-Za-z0-9_.\-]*",
           what="a string of letters, digits, '_', '-', '.' (starting with a letter or digit; usable as a file name)")

#: The top-level keys of ``manifest.json``.
MANIFEST_FIELDS: tuple[Field, ...] = (
    Field("format", Choice((MANIFEST_FORMAT,))),
    Field("version", Choice((MANIFEST_VERSION,))),
    Field("name", Text()),
    Field("notes", Text()),
    Field("defaults", Instance((dict,), what="an object of entry keys other than id and file")),
    Field("measurements", Instance((list,), what="a non-empty list of entries"), required=True),
)

#: The keys of a manifest entry besides the metadata of :data:`idkit.io.info.INFO_FIELDS`
#: (checked by :class:`~idkit.io.info.MeasurementInfo`).
ENTRY_FIELDS: tuple[Field, ...] = (
    Field("id", _ID, required=True),
    Field("kind", KIND, required=True),
    Field("file", Text(pattern=r"(?!/)(?!(?:.*/)?\.\.(?:/|$))[^\\\x00-\x1f]+\.(?:csv|csv\.gz|mat)",
                       what="a relative POSIX path inside the set's folder (no '..', no absolute path, no "
                            "backslash, no control characters) ending in .csv, .csv.gz or .mat"), required=True),
    Field("excitation", Instance((dict, type(None)), what="an object of freq_hz, amplitude, amplitude_unit, band_hz")),
    Field("mat_columns", Instance((dict,), what="an object mapping column names to 'var [unit]' or "
                                                "'var[:,k] [unit]'")),
)

#: The keys of a manifest entry's ``excitation`` (units in the names; :class:`Excitation` checks the values).
EXCITATION_FIELDS: tuple[Field, ...] = (
    Field("freq_hz", Real(unit="Hz", gt=0, meaning="stepped-sine excitation frequency")),
    Field("amplitude", Real(gt=0, meaning="nominal amplitude in amplitude_unit")),
    Field("amplitude_unit", Text()),
    Field("band_hz", Reals(unit="Hz", ge=0, min_size=2, max_size=2, increasing=True,
                           meaning="white-noise band [low, high]")),
)

#: Metadata a kind of measurement cannot do without: (test on the info, what is expected).
_NEEDED_BY_KIND = {
    "drop": (lambda info: info.drop_height_m is not None, "'drop_height_m': the drop height in m"),
    "stepped_sine": (lambda info: info.excitation is not None and info.excitation.freq is not None,
                     "'excitation': {'freq_hz': ...}: the excitation frequency in Hz"),
}


@dataclass(frozen=True)
class ManifestEntry:
    """One checked entry of a manifest.

    Parameters
    ----------
    kind : str
        Kind of measurement.
    file : str
        Path relative to the set's folder (POSIX separators).
    info : MeasurementInfo
        Metadata (id, isolator, masses, ...).
    mat_columns : tuple of (str, MatColumn)
        Column mapping for ``.mat`` files (empty for CSV).
    """

    kind: str
    file: str
    info: MeasurementInfo
    mat_columns: tuple[tuple[str, MatColumn], ...] = ()

    @property
    def id(self) -> str:
        """The entry's id."""
        return self.info.id


@dataclass(frozen=True)
class Manifest:
    """A checked ``manifest.json`` (no data file read yet).

    Parameters
    ----------
    path : pathlib.Path
        The manifest file.
    name, notes : str
        Set name and notes.
    entries : tuple of ManifestEntry
        The checked entries, in file order (defaults applied).
    sha256 : str
        SHA-256 of the manifest bytes.
    """

    path: Path
    name: str
    notes: str
    entries: tuple[ManifestEntry, ...]
    sha256: str


def _nan_if_none(value: float | None) -> float:
    return float("nan") if value is None else float(value)


def _load_json(path: Path, raw: bytes) -> object:
    return load_json(raw, f"manifest '{path}'", DataError,
                     expected="a JSON object with a 'measurements' list")


def _parse_excitation(value: dict, where: str) -> Excitation:
    checked = check_fields(value, EXCITATION_FIELDS, f"{where}: excitation")
    amplitude, unit = checked.get("amplitude"), checked.get("amplitude_unit")
    quantity = None
    if (amplitude is None) != (unit is None):
        raise DataError(f"{where}: excitation: 'amplitude' and 'amplitude_unit' must be given together")
    if amplitude is not None:
        scale = lookup_unit(unit, AMPLITUDE_QUANTITIES, where=f"{where}: excitation amplitude_unit")
        quantity = scale.quantity
        amplitude = amplitude * scale.numerator / scale.denominator
    band = checked.get("band_hz")
    return Excitation(freq=checked.get("freq_hz"), amplitude=amplitude, amplitude_quantity=quantity,
                      band=None if band is None else tuple(band))


def _parse_entry(number: int, raw_entry: object, defaults: dict, path: Path) -> ManifestEntry:
    where = f"manifest '{path}': measurements entry {number} (1-based)"
    if not isinstance(raw_entry, dict):
        raise DataError(f"{where}: found {type(raw_entry).__name__}, expected an object")
    if "id" in raw_entry:
        where += f", id {raw_entry['id']!r}"
    entry = {**defaults, **raw_entry}
    checked = check_fields(entry, ENTRY_FIELDS, where, known=_INFO_KEYS)
    kind, file = checked["kind"], checked["file"]
    mat_columns: tuple = ()
    if file.endswith(".mat") != ("mat_columns" in checked) or checked.get("mat_columns") == {}:
        raise DataError(f"{where}: 'mat_columns' goes with a .mat file and only with one (file {file!r}); "
                        "expected an object mapping column names to 'var [unit]' or 'var[:,k] [unit]' for a .mat file")
    if file.endswith(".mat"):
        mat_columns = tuple((name, parse_mat_column(text, where=f"{where}: mat_columns.{name}"))
                            for name, text in checked["mat_columns"].items())
    try:
        excitation = (_parse_excitation(checked["excitation"], where)
                      if checked.get("excitation") is not None else None)
        info = MeasurementInfo(id=checked["id"], excitation=excitation,
                               **{key: entry[key] for key in _INFO_KEYS if key in entry})
    except DataError as exc:
        text = str(exc)
        raise DataError(text if text.startswith(where) else f"{where}: {text}") from None
    needed, expected = _NEEDED_BY_KIND.get(kind, (lambda info: True, ""))
    if not needed(info):
        raise DataError(f"{where}: {kind} without {expected}")
    return ManifestEntry(kind=kind, file=file, info=info, mat_columns=mat_columns)


def _check_unique_ids(ids: list[str], what: str) -> None:
    """Refuse the first id given twice, naming both positions (1-based) after ``what``."""
    first: dict[str, int] = {}
    for number, entry_id in enumerate(ids, 1):
        if first.setdefault(entry_id, number) != number:
            raise DataError(f"{what} {number} (1-based): duplicate id {entry_id!r} (first in entry {first[entry_id]})")


def _check_data_files(folder: Path, path: Path, entries: tuple[ManifestEntry, ...]) -> None:
    """Every listed file exists, is a regular file, lies inside the set's folder once
    symlinks are resolved, and no two entries name the same file (checked before any
    data file is read; all missing files are listed in one message)."""
    problems = [f"entry {n} (id {e.id!r}): '{e.file}' {why}" for n, e in enumerate(entries, 1)
                if (why := path_problem(folder / e.file, "file")) is not None]
    if problems:
        raise DataError(f"manifest '{path}': data file(s) not found or unusable (relative to "
                        f"'{folder}'): {'; '.join(problems)}")
    root = folder.resolve()
    seen: dict[tuple[int, int], int] = {}
    for number, entry in enumerate(entries, 1):
        where = f"manifest '{path}': measurements entry {number} (1-based), id {entry.id!r}"
        target = (folder / entry.file).resolve()
        if not target.is_relative_to(root):
            raise DataError(f"{where}: file '{entry.file}' resolves to '{target}', outside the "
                            f"set's folder '{root}' (through a symlink); expected a file inside "
                            "the set's folder")
        # the same file through another spelling, a symlink or a hard link
        status = target.stat()
        key = (status.st_dev, status.st_ino)
        if key in seen:
            first = entries[seen[key] - 1]
            raise DataError(f"{where}: file '{entry.file}' is the same data file as entry "
                            f"{seen[key]} (id {first.id!r}, file '{first.file}'); expected "
                            "one entry per data file")
        seen[key] = number


def read_manifest(folder: str | Path) -> Manifest:
    """Read and check ``folder/manifest.json`` (no data file is read).

    Parameters
    ----------
    folder : str or pathlib.Path
        The measurement set's folder.

    Returns
    -------
    Manifest
        Name, notes, checked entries and the manifest's SHA-256.

    Raises
    ------
    DataError
        Invalid JSON, schema violations, duplicate ids, missing data files.
    """
    folder = Path(folder)
    path = folder / MANIFEST_NAME
    raw = read_input_bytes(path, f"manifest '{path}'", DataError)
    sha256 = hashlib.sha256(raw).hexdigest()
    document = _load_json(path, raw)
    if not isinstance(document, dict):
        raise DataError(f"manifest '{path}': found a JSON {type(document).__name__}, "
                        "expected an object with a 'measurements' list")
    checked = check_fields(document, MANIFEST_FIELDS, f"manifest '{path}'")
    defaults, measurements = checked.get("defaults", {}), checked["measurements"]
    if not measurements:
        raise refuse(f"manifest '{path}': measurements", measurements, "a non-empty list of entries", DataError)
    if {"id", "file"} & set(defaults):
        raise DataError(f"manifest '{path}': defaults: found key(s) "
                        f"{', '.join(sorted({'id', 'file'} & set(defaults)))}, "
                        "expected an object of entry keys other than id and file")
    entries = tuple(_parse_entry(n, e, defaults, path) for n, e in enumerate(measurements, 1))
    _check_unique_ids([entry.id for entry in entries], f"manifest '{path}': measurements entry")
    _check_data_files(folder, path, entries)
    return Manifest(path=path, name=checked.get("name", ""),
                    notes=checked.get("notes", ""), entries=entries, sha256=sha256)


def _read_entry(folder: Path, entry: ManifestEntry) -> Measurement:
    path = folder / entry.file
    if entry.file.endswith(".mat"):
        measurement = read_mat(path, entry.kind, columns=dict(entry.mat_columns), info=entry.info)
    else:
        measurement = read_csv_measurement(path, entry.kind, info=entry.info)
    check_excitation_resolved(measurement)
    return measurement


@dataclass(frozen=True, eq=False)
class MeasurementSet:
    """A loaded measurement set: manifest entries and their measurements (eager).

    Parameters
    ----------
    folder : pathlib.Path or None
        The set's folder.
    entries : tuple of ManifestEntry
        Checked manifest entries.
    measurements : tuple of Measurement
        One measurement per entry, same order.
    name, notes : str
        From the manifest.
    manifest_sha256 : str or None
        SHA-256 of ``manifest.json``.
    """

    folder: Path | None
    entries: tuple[ManifestEntry, ...]
    measurements: tuple[Measurement, ...]
    name: str = ""
    notes: str = ""
    manifest_sha256: str | None = None

    def __len__(self) -> int:
        return len(self.measurements)

    def __iter__(self) -> Iterator[Measurement]:
        return iter(self.measurements)

    @property
    def ids(self) -> tuple[str, ...]:
        """Ids of the measurements, in manifest order."""
        return tuple(entry.id for entry in self.entries)

    def get(self, measurement_id: str) -> Measurement:
        """The measurement with this id (KeyError if absent)."""
        for entry, measurement in zip(self.entries, self.measurements):
            if entry.id == measurement_id:
                return measurement
        raise KeyError(f"no measurement with id {measurement_id!r}; ids: {', '.join(self.ids)}")

    @accepts(kind=Choice(KINDS, optional=True), top_mass_kg=Real(unit="kg", gt=0, optional=True),
             mass_tol_kg=Real(unit="kg", ge=0), error=DataError)
    def select(self, *, kind: str | None = None, isolator: str | None = None,
               split: str | None = None, top_mass_kg: float | None = None,
               mass_tol_kg: float = 1e-9) -> MeasurementSet:
        """A new set with the measurements matching every given criterion.

        Parameters
        ----------
        kind, isolator, split : str, optional
            Exact matches.
        top_mass_kg : float, optional
            Top mass in kg, matched within ``mass_tol_kg``.
        mass_tol_kg : float
            Absolute tolerance of the mass match in kg.

        Returns
        -------
        MeasurementSet
            Possibly empty; same folder and manifest hash.
        """

        def keep(entry: ManifestEntry) -> bool:
            info = entry.info
            return ((kind is None or entry.kind == kind)
                    and (isolator is None or info.isolator == isolator)
                    and (split is None or info.split == split)
                    and (top_mass_kg is None or (info.top_mass_kg is not None
                         and abs(info.top_mass_kg - top_mass_kg) <= mass_tol_kg)))

        pairs = [(e, m) for e, m in zip(self.entries, self.measurements) if keep(e)]
        return replace(self, entries=tuple(e for e, _ in pairs),
                       measurements=tuple(m for _, m in pairs))

    def hashes(self) -> dict[str, str]:
        """SHA-256 of every file of the set, for provenance records.

        Returns
        -------
        dict of str to str
            Relative path -> hex digest, ``manifest.json`` first.
        """
        out = {}
        if self.manifest_sha256 is not None:
            out[MANIFEST_NAME] = self.manifest_sha256
        for entry, measurement in zip(self.entries, self.measurements):
            out[entry.file] = measurement.source.sha256
        return out

    def to_dataframe(self) -> pd.DataFrame:
        """One row per measurement: id, kind, file, metadata, sample count, SHA-256."""
        rows = []
        for entry, measurement in zip(self.entries, self.measurements):
            info = entry.info
            exc = info.excitation or Excitation()
            rows.append({
                "id": entry.id, "kind": entry.kind, "file": entry.file,
                "isolator": info.isolator, "top_mass [kg]": _nan_if_none(info.top_mass_kg),
                "intermediate_mass [kg]": _nan_if_none(info.intermediate_mass_kg),
                "bottom_mass [kg]": _nan_if_none(info.bottom_mass_kg),
                "drop_height [m]": _nan_if_none(info.drop_height_m),
                "freq [Hz]": _nan_if_none(exc.freq), "repetition": info.repetition,
                "sample_rate [Hz]": _nan_if_none(info.sample_rate_hz), "split": info.split,
                "n_samples": measurement.n_samples, "sha256": measurement.source.sha256,
            })
        return pd.DataFrame(rows)


def load_measurement_set(folder: str | Path) -> MeasurementSet:
    """Load a measurement set: check ``manifest.json``, then read every file.

    Parameters
    ----------
    folder : str or pathlib.Path
        Folder holding ``manifest.json`` and the data files it names.

    Returns
    -------
    MeasurementSet
        All measurements loaded (SI units) with provenance.

    Raises
    ------
    DataError
        On any problem in the manifest or a data file (the message names
        the file, entry or column and row).

    Examples
    --------
    >>> mset = load_measurement_set("lab/elastomer")  # doctest: +SKIP
    >>> fit = mset.select(kind="white_noise", split="fit")  # doctest: +SKIP
    """
    folder = Path(folder)
    manifest = read_manifest(folder)
    measurements = tuple(_read_entry(folder, entry) for entry in manifest.entries)
    return MeasurementSet(folder=folder, entries=manifest.entries, measurements=measurements,
                          name=manifest.name, notes=manifest.notes,
                          manifest_sha256=manifest.sha256)


def _entry_json(kind: str, file: str, info: MeasurementInfo) -> dict:
    out: dict = {"id": info.id, "kind": kind, "file": file}
    for key in _INFO_KEYS:
        value = getattr(info, key)
        if value is not None and value != "":
            out[key] = value
    exc = info.excitation
    if exc is not None:
        spec: dict = {}
        if exc.freq is not None:
            spec["freq_hz"] = exc.freq
        if exc.amplitude is not None:
            spec["amplitude"] = exc.amplitude
            spec["amplitude_unit"] = SI_UNITS[exc.amplitude_quantity]
        if exc.band is not None:
            spec["band_hz"] = list(exc.band)
        out["excitation"] = spec
    return out


def write_measurement_set(folder: str | Path, measurements: Iterable[Measurement], *,
                          name: str = "", notes: str = "", gzip: bool = False,
                          units: Mapping[str, str] | None = None,
                          overwrite: bool = False) -> Path:
    """Write measurements as a measurement set (CSV files + ``manifest.json``).

    Each measurement goes to ``<kind>/<id>.csv`` (or ``.csv.gz``); the
    manifest is written last, so a set with a manifest is complete. Every
    file is written atomically; existing files are never replaced unless
    ``overwrite`` is true.

    Parameters
    ----------
    folder : str or pathlib.Path
        Target folder (created if missing).
    measurements : iterable of Measurement
        Each with a unique, non-empty ``info.id``.
    name, notes : str
        Set name and notes for the manifest.
    gzip : bool
        Write ``.csv.gz`` files.
    units : mapping of str to str, optional
        Column units to write instead of SI (see :func:`write_csv_measurement`).
    overwrite : bool
        Replace existing files.

    Returns
    -------
    pathlib.Path
        Path of the written ``manifest.json``.

    Raises
    ------
    DataError
        Missing or duplicate ids.
    FileExistsError
        A target file exists and ``overwrite`` is false (checked for all
        files before anything is written).
    """
    folder = Path(folder)
    measurements = list(measurements)
    suffix = ".csv.gz" if gzip else ".csv"
    ids = [_ID.check(m.info.id, f"measurement {number} (1-based): id", DataError)
           for number, m in enumerate(measurements, 1)]
    _check_unique_ids(ids, "measurement")
    plan = [(m, f"{m.kind}/{entry_id}{suffix}") for m, entry_id in zip(measurements, ids)]
    if not plan:
        raise DataError("write_measurement_set: no measurements given")
    manifest_path = folder / MANIFEST_NAME
    if not overwrite:
        existing = [p for p in [manifest_path] + [folder / f for _, f in plan] if p.exists()]
        if existing:
            raise FileExistsError(f"refusing to overwrite existing file(s): "
                                  f"{', '.join(map(str, existing))} (pass overwrite=True)")
    for measurement, file in plan:
        (folder / file).parent.mkdir(parents=True, exist_ok=True)
        kind_units = {k: v for k, v in (units or {}).items() if k in measurement.signals()}
        write_csv_measurement(measurement, folder / file, units=kind_units, overwrite=overwrite)
    document = {
        "format": MANIFEST_FORMAT, "version": MANIFEST_VERSION, "name": name, "notes": notes,
        "measurements": [_entry_json(m.kind, f, m.info) for m, f in plan],
    }
    text = json.dumps(document, indent=2, ensure_ascii=False, allow_nan=False) + "\n"
    return write_bytes_atomic(manifest_path, text.encode("utf-8"), overwrite=overwrite)
