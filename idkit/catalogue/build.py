"""Build a catalogue of identified parts from a folder of part measurement sets.

Input: a folder whose sub-folders are parts, each a measurement set (``manifest.json``,
``docs/data-format.md``) with a ``part.json`` beside it naming the part, its family and its
dimensions (:func:`read_part`). Output folder::

    catalogue.json        every part's record (dimensions, status, reasons, verdicts,
                          covariance, valid range, summary quantities, model file)
    parts.csv             the table of parts (one row each; :func:`idkit.catalogue.table.parts_table`)
    models/<part>.json    the identified model file, provenance extended by the catalogue record

Each part is identified by :func:`idkit.catalogue.identify.identify_measurements` in a task of
its own: serially (``workers=1``), in ``workers`` processes, or on any
``concurrent.futures``-style executor (an object with ``submit(fn, *args)`` returning futures
with ``result()``; a ``dask.distributed.Client`` is one). A part whose data or fit raise an
idkit error is recorded with ``status = "failed"`` and the reason, and the others finish.
``add=`` identifies more parts into an existing catalogue without refitting the rest.
"""

from __future__ import annotations

import json
import multiprocessing
from collections.abc import Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path

from idkit import __version__
from idkit.atomic import atomic_output_folder, write_text_atomic
from idkit.catalogue.identify import identified_record, identify_measurements
from idkit.catalogue.table import parts_table, write_parts_table
from idkit.checks import Choice, Field, Instance, Real, Text, Whole, accepts, check_fields, field_names
from idkit.errors import DataError, IdkitError, OutputError
from idkit.inputfiles import load_json, read_input_bytes
from idkit.io import load_measurement_set
from idkit.models import load_model, save_model

__all__ = ["CATALOGUE_FILE", "FAMILY_DIMENSIONS", "PART_FILE", "Catalogue", "build_catalogue", "find_parts",
           "load_catalogue", "read_part"]

PART_FILE = "part.json"
CATALOGUE_FILE = "catalogue.json"
_OBJECT = Instance((dict,), what="an object")
#: The dimensions each family's part.json must give (SI); other keys are carried along unchecked.
_DIMENSION_FIELDS = {
    "wire_rope": (Field("cable_diameter_m", Real(unit="m", gt=0), required=True),
                  Field("loops", Real(gt=0, meaning="a count"), required=True),
                  Field("height_m", Real(unit="m", gt=0), required=True),
                  Field("width_m", Real(unit="m", gt=0), required=True)),
    "elastomer": (Field("area_m2", Real(unit="m^2", gt=0), required=True),
                  Field("thickness_m", Real(unit="m", gt=0), required=True),
                  Field("shape_factor", Real(gt=0), required=True),
                  Field("compound", Text(nonempty=True, what="a compound name"), required=True)),
}
#: Dimensions each family's part.json must give (SI; ``loops`` a count, ``compound`` a name).
FAMILY_DIMENSIONS = {family: field_names(fields) for family, fields in _DIMENSION_FIELDS.items()}
#: The keys of part.json read here; other keys are carried along unchecked.
_PART_FIELDS = (Field("part", Text(pattern=r"[^/]*[^/\s][^/]*", what="a non-empty name without '/'"), required=True),
                Field("family", Choice(tuple(FAMILY_DIMENSIONS)), required=True),
                Field("dimensions", _OBJECT, required=True))
#: ``fit_options`` of :func:`build_catalogue`: per family, the options passed to its fitter.
_FIT_OPTION_FIELDS = tuple(Field(family, Instance((dict,), what="a dict of fit options"))
                           for family in FAMILY_DIMENSIONS)


def read_part(folder) -> dict:
    """The checked ``part.json`` of a part folder: ``{"part", "family", "dimensions"}``.

    Raises
    ------
    DataError
        Missing file, bad JSON, unknown family, a missing or non-positive dimension (naming
        the file, the key, what was found and what was expected).
    """
    label = f"part description '{Path(folder) / PART_FILE}'"
    raw = read_input_bytes(Path(folder) / PART_FILE, label, DataError)
    document = _OBJECT.check(load_json(raw, label, DataError, expected="an object with part, family, dimensions"),
                             label, DataError)
    part = check_fields(document, _PART_FIELDS, label, known=tuple(document))
    check_fields(part["dimensions"], _DIMENSION_FIELDS[part["family"]], f"{label}: dimensions",
                 known=tuple(part["dimensions"]))
    # the values as written (an integer stays one in the catalogue and the model files' provenance)
    return {"part": part["part"], "family": part["family"], "dimensions": dict(document["dimensions"])}


def find_parts(folder) -> list[Path]:
    """Part folders under ``folder`` (sub-folders holding ``part.json``; ``folder`` itself if it holds one)."""
    folder = Path(folder)
    if not folder.is_dir():
        raise DataError(f"{folder}: not a folder; expected a folder of parts (each with {PART_FILE})")
    if (folder / PART_FILE).is_file():
        return [folder]
    found = sorted(path for path in folder.iterdir() if path.is_dir() and (path / PART_FILE).is_file())
    if not found:
        raise DataError(f"{folder}: found no part folder; expected sub-folders with a {PART_FILE} and a manifest.json")
    return found


def _part_name(folder: Path) -> str:
    """The part's name for the repeated-name check; a part.json that does not read is recorded
    as a failure by its task, under its folder's name."""
    try:
        return read_part(folder)["part"]
    except DataError:
        return folder.name


def _identify_task(folder: str, output: str, fit_options: dict) -> dict:
    """Identify one part and write its model file; never raises an idkit error (it is recorded)."""
    record = {"folder": str(folder), "part": Path(folder).name, "family": "", "dimensions": {}}
    try:
        record.update(read_part(folder))
        measurements = load_measurement_set(folder)
        identified = identify_measurements(measurements, record["family"],
                                           fit_options=fit_options.get(record["family"], {}))
    except IdkitError as problem:
        return {**record, "status": "failed", "reasons": [f"{type(problem).__name__}: {problem}"]}
    summary = identified_record(identified)
    status = "identified" if summary["success"] else "not a success"
    record.update(summary, status=status)
    model_file = Path(output) / "models" / f"{record['part']}.json"
    provenance = identified.fit.provenance_dict()
    provenance["catalogue"] = {key: record[key] for key in ("part", "family", "dimensions", "status", "held_out",
                                                          "covariance", "valid_range_m", "quantities")}
    save_model(identified.fit.model, model_file, provenance=provenance, overwrite=True)
    record["model_file"] = str(Path("models") / f"{record['part']}.json")
    return record


@dataclass(frozen=True)
class Catalogue:
    """A built catalogue: its folder and the part records (``catalogue.json``)."""

    folder: Path
    records: tuple

    def table(self):
        """The table of parts (:func:`idkit.catalogue.table.parts_table`)."""
        return parts_table(self.records)

    def record(self, part: str) -> dict:
        """The record of one part (DataError naming the known parts when absent)."""
        for record in self.records:
            if record["part"] == part:
                return record
        raise DataError(f"catalogue {self.folder}: part {part!r} not found; parts: "
                        f"{', '.join(r['part'] for r in self.records)}")

    def model(self, part: str):
        """The identified model of ``part`` (loaded from its model file)."""
        record = self.record(part)
        if "model_file" not in record:
            raise DataError(f"catalogue {self.folder}: part {part!r} has no model ({record['status']}: "
                            f"{'; '.join(record.get('reasons', []))})")
        return load_model(self.folder / record["model_file"])

    def usable(self) -> tuple:
        """Records of parts identified successfully and passing (or not running) held-out validation."""
        return tuple(r for r in self.records if r["status"] == "identified"
                     and r.get("held_out", {}).get("verdict") in ("PASS", "NOT RUN"))


_CATALOGUE_OBJECT = Instance((dict,), what="a JSON object (a catalogue built by 'idkit catalogue build')")


def load_catalogue(folder) -> Catalogue:
    """Read a catalogue folder written by :func:`build_catalogue`."""
    folder = Path(folder)
    path = folder / CATALOGUE_FILE
    label = f"catalogue '{path}'"  # read as strictly as every input file (idkit.inputfiles)
    document = load_json(read_input_bytes(path, label, DataError), label, DataError,
                         expected="a catalogue built by 'idkit catalogue build'")
    _CATALOGUE_OBJECT.check(document, label, DataError)
    Choice(("idkit-catalogue",)).check(document.get("format"), f"{path}: format", DataError)
    return Catalogue(folder, tuple(document["parts"]))


def _run(tasks: list, output: Path, fit_options: dict, workers: int, executor) -> list[dict]:
    if executor is not None:
        futures = [executor.submit(_identify_task, str(folder), str(output), fit_options) for folder in tasks]
        return [future.result() for future in futures]
    if workers == 1 or len(tasks) == 1:
        return [_identify_task(str(folder), str(output), fit_options) for folder in tasks]
    # forkserver: workers start clean (no inherited threads or numba state), import idkit once
    context = multiprocessing.get_context("forkserver")
    with ProcessPoolExecutor(max_workers=min(workers, len(tasks)), mp_context=context) as pool:
        futures = [pool.submit(_identify_task, str(folder), str(output), fit_options) for folder in tasks]
        return [future.result() for future in futures]


@accepts(workers=Whole(ge=1, meaning="processes"), error=OutputError)
def build_catalogue(parts, output, *, add: Sequence | None = None, workers: int = 1, executor=None,
                    fit_options: dict | None = None, progress=None) -> Catalogue:
    """Identify every part under ``parts`` into the catalogue folder ``output``.

    Parameters
    ----------
    parts : str or pathlib.Path or None
        Folder of part folders (:func:`find_parts`). None with ``add``: only add.
    output : str or pathlib.Path
        Catalogue folder. Without ``add`` it must not exist yet (never replaced); with
        ``add`` it must hold a catalogue, whose parts are kept as they are.
    add : sequence of paths, optional
        Part folders to add to the existing catalogue ``output`` (a part already in it is
        refused: remove it first).
    workers : int, default 1
        Processes identifying parts at once (ignored with ``executor``).
    executor : concurrent.futures-style executor, optional
        ``submit(fn, *args)`` returning futures (``ThreadPoolExecutor``, ``ProcessPoolExecutor``,
        ``dask.distributed.Client``).
    fit_options : dict, optional
        Per family, options passed to its fitter, e.g. ``{"wire_rope": {"order": 3}}``.
    progress : callable(str), optional
        Called with one line per finished part.

    Returns
    -------
    Catalogue
    """
    output = Path(output)
    if executor is not None and not callable(getattr(executor, "submit", None)):
        raise OutputError(f"executor: found {type(executor).__name__}, expected an object with submit(fn, *args)")
    fit_options = dict(fit_options or {})
    check_fields(fit_options, _FIT_OPTION_FIELDS, "fit_options", error=OutputError)
    existing: list[dict] = []
    if add:
        catalogue = load_catalogue(output)
        existing = list(catalogue.records)
        tasks = [Path(folder) for folder in add]
        for folder in tasks:
            part = read_part(folder)["part"]
            if any(record["part"] == part for record in existing):
                raise DataError(f"{folder}: part {part!r} is already in the catalogue {output}; expected a new part")
        if parts is not None:
            raise OutputError("parts and add: found both, expected a parts folder (new catalogue) or add= "
                              "(an existing one)")
    else:
        if parts is None:
            raise OutputError("parts: found None, expected a folder of parts (or add= with an existing catalogue)")
        if output.exists():
            raise OutputError(f"{output}: exists; expected a new catalogue folder (add= adds parts to one)")
        tasks = find_parts(parts)
        names = [_part_name(folder) for folder in tasks]
        repeated = sorted({name for name in names if names.count(name) > 1})
        if repeated:
            raise DataError(f"{parts}: parts named more than once: {', '.join(repeated)}")
    resolved_parts = [Path(folder).resolve() for folder in tasks]
    if any(output.resolve() == folder or folder in output.resolve().parents for folder in resolved_parts):
        raise OutputError(f"{output}: inside a part folder; expected the catalogue outside the input data")
    if add:  # each model file and then catalogue.json are replaced atomically; the old parts stay
        records = _write(output, existing, tasks, fit_options, workers, executor)
    else:  # a new catalogue appears whole or not at all
        with atomic_output_folder(output) as staging:
            records = _write(staging, existing, tasks, fit_options, workers, executor)
    if progress is not None:
        for record in records:
            progress(f"{record['part']}: {record['status']}"
                     + (f" ({record['reasons'][0]})" if record.get("reasons") and record["status"] != "identified"
                        else ""))
    all_records = existing + records
    return Catalogue(output, tuple(json.loads(json.dumps(all_records, default=_json_default))))


def _write(folder: Path, existing: list, tasks: list, fit_options: dict, workers: int, executor) -> list[dict]:
    """Identify ``tasks`` into ``folder`` and write its catalogue.json and table; the new records."""
    (folder / "models").mkdir(parents=True, exist_ok=True)
    records = _run(tasks, folder, fit_options, workers, executor)
    all_records = existing + records
    document = {"format": "idkit-catalogue", "version": 1, "idkit_version": __version__,
                "fit_options": fit_options, "parts": all_records}
    write_text_atomic(folder / CATALOGUE_FILE, json.dumps(document, indent=1, default=_json_default) + "\n",
                      overwrite=True)
    write_parts_table(parts_table(all_records), folder)
    return records


def _json_default(value):
    if hasattr(value, "item"):
        return value.item()
    if isinstance(value, Path):
        return str(value)
    raise TypeError(f"not JSON serialisable: {type(value).__name__}")
