"""Checks of an output location before any long work: it must not harm an input and must be writable.

A command that reads inputs and writes outputs calls :func:`check_output` for each output
before it loads, fits or simulates anything, so a bad ``-o`` fails in a second with an
error naming the path instead of after minutes of work (or, worse, by deleting the input
it would have replaced). The rules (docs/cli-reference.md, "Outputs never destroy inputs or good outputs"):

* an output is never an input, never inside an input folder and never contains an input
  (paths compared after resolving symlinks), and a folder that will be replaced never
  contains the working folder;
* a file's folder must exist; a folder's missing parents are created, but nothing may lie
  below a regular file;
* the folder that will receive the output must accept a new file (a probe file is created
  and removed: this also catches read-only mounts, which permission bits do not show);
* leftovers of a killed earlier run on a folder that will be replaced are cleaned up
  first (:func:`idkit.atomic.recover_leftovers`);
* the disk must have at least :data:`MIN_FREE_BYTES` free (a cheap floor, not a promise:
  a full disk during the write still fails cleanly, leaving the previous output in place).
"""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

from idkit.atomic import recover_leftovers
from idkit.errors import OutputError

__all__ = ["MIN_FREE_BYTES", "check_output", "check_plot_folder"]

#: Free space required on the output's disk before long work starts (bytes). The largest
#: output, ``idkit report``, takes a few MB; a model file or a table far less.
MIN_FREE_BYTES = 16 * 2**20

_KINDS = ("file", "folder", "replaced")


def _nearest_existing(path: Path) -> Path:
    for candidate in (path, *path.parents):
        if os.path.lexists(candidate):
            return candidate
    return Path(path.anchor or ".")


def _overlap(output: Path, source: Path) -> str | None:
    if output == source:
        return "is"
    if source in output.parents:
        return "lies inside"
    if output in source.parents:
        return "contains"
    return None


def check_output(path: str | Path, *, kind: str = "file", inputs=(), option: str = "-o", force: bool = False,
                 min_free_bytes: int = MIN_FREE_BYTES) -> Path:
    """Refuse, before long work, an output that would overlap an input or cannot be written.

    Parameters
    ----------
    path : str or pathlib.Path
        The output as the user gave it.
    kind : {"file", "folder", "replaced"}
        ``"file"``: one file (its folder must exist). ``"folder"``: a folder that files are
        written into (created if missing). ``"replaced"``: a folder built elsewhere and
        swapped in as a whole (:func:`idkit.atomic.atomic_output_folder`).
    inputs : iterable of path
        Files and folders the command reads (``None`` entries are skipped).
    option : str
        The option named in messages (``"-o"``, ``"--plots"``).
    force : bool
        Accept an existing ``"replaced"`` folder (``--force``). An existing ``"file"`` is
        always refused (idkit never overwrites a file it was asked to create).
    min_free_bytes : int
        Free space (bytes) required on the output's disk.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    FileExistsError
        If a ``"file"`` exists, or a ``"replaced"`` folder exists and ``force`` is false.
    idkit.errors.OutputError
        Naming the output path, and the input path for an overlap.
    """
    if kind not in _KINDS:
        raise ValueError(f"kind: found {kind!r}, expected one of {_KINDS}")
    path = Path(path)
    where = f"{option} '{path}'"
    resolved = path.resolve()
    for source in inputs:
        if source is None:
            continue
        relation = _overlap(resolved, Path(source).resolve())
        if relation:
            raise OutputError(f"{where}: {relation} the input '{source}'; an output must not overlap "
                              f"an input (it could destroy it): choose another {option}")
    if kind == "replaced" and (resolved == Path.cwd().resolve() or resolved in Path.cwd().resolve().parents):
        raise OutputError(f"{where}: contains the working folder '{Path.cwd()}'; refusing to replace it")
    if kind == "replaced":
        recover_leftovers(path)  # a killed earlier run may have left NAME renamed aside
    if kind == "file" and os.path.lexists(path) and not path.is_dir():
        raise FileExistsError(f"{path}: exists; refusing to overwrite it (choose another name)")
    if kind == "replaced" and path.is_dir() and not force:
        raise FileExistsError(f"{path}: exists; refusing to overwrite it (pass --force to replace it)")
    if kind == "file" and path.is_dir():
        raise OutputError(f"{where}: is a folder; expected a file name")
    if kind != "file" and os.path.lexists(path) and not path.is_dir():
        raise OutputError(f"{where}: exists and is not a folder")
    receiving = path if kind == "folder" else path.parent
    existing = _nearest_existing(receiving)
    if not existing.is_dir():
        raise OutputError(f"{where}: lies below '{existing}', which is a file, not a folder")
    if kind == "file" and existing != receiving:
        raise OutputError(f"{where}: folder '{receiving}' does not exist (create it first)")
    _probe(existing, where)
    free = shutil.disk_usage(existing).free
    if free < min_free_bytes:
        raise OutputError(f"{where}: only {free / 2**20:.1f} MiB free on the disk of '{existing}', "
                          f"need at least {min_free_bytes / 2**20:.0f} MiB")
    return path


def _probe(folder: Path, where: str) -> None:
    """Create and remove a hidden file in ``folder``: the only honest test of writability."""
    try:
        descriptor, name = tempfile.mkstemp(dir=folder, prefix=".idkit-probe.", suffix=".tmp")
    except OSError as problem:
        raise OutputError(f"{where}: cannot write into folder '{folder}' "
                          f"({problem.strerror or problem})") from None
    os.close(descriptor)
    os.unlink(name)


def check_plot_folder(plots: str | Path, figures, *, inputs=(),
                      beside: tuple[str, str | Path | None] = ("the output -o", None)) -> Path:
    """Refuse, before long work, a ``--plots`` folder whose figures could not all be written.

    The folder is checked as a ``"folder"`` output (:func:`check_output`); it must not be the
    command's other output ``beside`` (what it is and its path: ``("the model file -o",
    path)``); and none of ``figures`` (the paths the command would write there) may exist,
    since figures are never overwritten.

    Raises
    ------
    FileExistsError
        A figure exists (every existing one is named).
    idkit.errors.OutputError
        As :func:`check_output`, or the folder is the other output.
    """
    what, other = beside
    if other is not None and Path(plots).resolve() == Path(other).resolve():
        raise OutputError(f"--plots '{plots}': is {what} '{other}'; expected a folder apart from it")
    check_output(plots, kind="folder", inputs=inputs, option="--plots")
    existing = [str(path) for path in figures if Path(path).exists()]
    if existing:
        raise FileExistsError(f"refusing to overwrite existing plot(s): {', '.join(existing)}")
    return Path(plots)
