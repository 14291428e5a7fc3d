"""Write a measurement set's manifest from its files and what the user states (``idkit data init``).

Nothing is guessed: the kind, the isolator, the masses, drop heights, excitation and, for
``.mat`` files, the variable-to-column mapping with units are what the caller states, the
same for every file it names; CSV files carry their units in their headers. Before the
manifest is written, every entry is checked with the manifest's own rules and every file
is read with them (so a manifest that ``init`` writes loads); the file is written
atomically and never replaces an existing manifest unless asked (``force``), or extends
it (``append``, refusing ids that exist). The user then reads the manifest and corrects
what differs between files (e.g. one drop height per file).
"""

from __future__ import annotations

import json
import re
from collections.abc import Mapping

from idkit.atomic import write_text_atomic
from idkit.checks import Flag, InputPath, Instance, Text, accepts
from idkit.errors import DataError
from idkit.io.columns import KIND
from idkit.io.manifest import (
    MANIFEST_NAME,
    Manifest,
    _check_data_files,
    _parse_entry,
    _read_entry,
    read_manifest,
)

__all__ = ["DATA_SUFFIXES", "init_manifest"]

#: Files a measurement set may list.
DATA_SUFFIXES = (".csv", ".csv.gz", ".mat")


def _entry_id(relative: str, taken: set[str]) -> str:
    stem = relative
    for suffix in DATA_SUFFIXES:
        if stem.endswith(suffix):
            stem = stem[: -len(suffix)]
            break
    base = re.sub(r"[^A-Za-z0-9_.-]+", "_", stem.replace("/", "_")).strip("._-") or "measurement"
    if not base[0].isalnum():
        base = "m" + base
    name, count = base, 2
    while name in taken:
        name, count = f"{base}_{count}", count + 1
    taken.add(name)
    return name


#: ``files``: a glob pattern relative to the folder that stays inside it (pathlib's glob refuses
#: an empty or absolute pattern, ``.`` names no file, a ``..`` component leaves the folder).
_FILES = Text(pattern=r"(?![./]*$)(?!/)(?!(?:.*/)?\.\.(?:/|$)).+", optional=True,
              what="a glob pattern relative to the folder and inside it (e.g. 'drops/*.csv')")


@accepts(folder=InputPath(kind="folder", what="the folder holding the data files"), kind=KIND, files=_FILES,
         metadata=Instance((Mapping,), what="a mapping of manifest entry keys to values", optional=True),
         mat_columns=Instance((Mapping,), what="a mapping of column names to 'var [unit]'", optional=True),
         name=Text(), append=Flag(), force=Flag(), error=DataError)
def init_manifest(folder, *, kind: str, files: str | None = None, metadata: dict | None = None,
                  mat_columns: dict | None = None, name: str = "", append: bool = False,
                  force: bool = False) -> Manifest:
    """Write ``folder/manifest.json`` listing the data files of ``folder`` with stated metadata.

    Parameters
    ----------
    folder : str or pathlib.Path
        The measurement set's folder.
    kind : str
        Kind of every listed file (``quasi_static``, ``white_noise``, ``stepped_sine``, ``drop``).
    files : str, optional
        Glob pattern relative to ``folder`` (e.g. ``"drops/*.csv"``); default every
        ``.csv``, ``.csv.gz`` and ``.mat`` file below ``folder``.
    metadata : dict, optional
        Entry keys applied to every file: ``isolator``, ``top_mass_kg``,
        ``intermediate_mass_kg``, ``bottom_mass_kg``, ``drop_height_m``, ``excitation``,
        ``repetition``, ``sample_rate_hz``, ``split``, ``notes`` (docs/data-format.md).
    mat_columns : dict, optional
        For ``.mat`` files: column name -> ``"var [unit]"`` or ``"var[:,k] [unit]"``.
    name : str
        The set's name.
    append : bool
        Add the files to an existing manifest (ids and files must be new).
    force : bool
        Replace an existing manifest.

    Returns
    -------
    Manifest
        The manifest as written and read back.

    Raises
    ------
    DataError
        No matching file, a file already listed, a stated value the manifest refuses, a
        file that does not read as ``kind`` with the stated metadata (the message names the
        file, the column and what was expected), an existing manifest without ``force`` or
        ``append``.
    """
    path = folder / MANIFEST_NAME
    if append and force:
        raise DataError("give at most one of append and force")
    if append and name:
        raise DataError(f"name: found {name!r} with append; the existing manifest keeps its own name "
                        "(edit it there), expected no name")
    existing: dict = {}
    if path.exists():
        if append:
            read_manifest(folder)  # the existing manifest must be valid before it is extended
            existing = json.loads(path.read_text(encoding="utf-8"))
        elif not force:
            raise DataError(f"manifest '{path}': exists; pass --append to add files or --force to replace it")
    elif append:
        raise DataError(f"manifest '{path}': not found, nothing to append to")
    listed = {entry["file"] for entry in existing.get("measurements", [])}
    pattern = "**/*" if files is None else files
    found = sorted(p for p in folder.glob(pattern) if p.is_file() and p.name.endswith(DATA_SUFFIXES))
    relative = [p.relative_to(folder).as_posix() for p in found]
    relative = [r for r in relative if r not in listed] if append else relative
    if not relative:
        raise DataError(f"folder '{folder}': no {' / '.join(DATA_SUFFIXES)} file matches {pattern!r}"
                        + (" that the manifest does not list already" if append else ""))
    if mat_columns and not any(file.endswith(".mat") for file in relative):
        raise DataError(f"mat_columns: found {', '.join(mat_columns)} but no .mat file among the {len(relative)} "
                        "listed file(s), expected them only for .mat files (CSV files carry their own header)")
    taken = {entry["id"] for entry in existing.get("measurements", [])}
    raw_entries = []
    for file in relative:
        entry = {"id": _entry_id(file, taken), "kind": kind, "file": file, **(metadata or {})}
        if file.endswith(".mat"):
            if not mat_columns:
                raise DataError(f"file '{folder / file}': a .mat file needs its columns stated "
                                "(--mat-column time='Tout [s]' ...), expected name=var [unit] pairs")
            entry["mat_columns"] = dict(mat_columns)
        raw_entries.append(entry)
    # the manifest's own rules, then every file read with them, before anything is written
    entries = [_parse_entry(n, e, {}, path) for n, e in enumerate(raw_entries, len(listed) + 1)]
    _check_data_files(folder, path, tuple(entries))
    for entry in entries:
        _read_entry(folder, entry)
    document = existing or {"format": "idkit-measurement-set", "version": 1, "name": name,
                            "notes": "written by 'idkit data init'; check every value", "measurements": []}
    document["measurements"] = list(document.get("measurements", [])) + raw_entries
    write_text_atomic(path, json.dumps(document, indent=1) + "\n", overwrite=force or append)
    return read_manifest(folder)
