"""Writing outputs: files and folders appear whole or not at all, and never destroy a good one.

Every file and folder the ``idkit`` command writes goes through this module:

* :func:`write_bytes_atomic` / :func:`write_text_atomic`: a file is written to a hidden
  temporary file next to it (``.NAME.XXXX.tmp``), synced, then moved onto its name with
  :func:`os.replace`, so a reader sees the old file or the complete new one.
* :func:`atomic_output_folder`: a folder of outputs is built in a hidden staging folder next
  to it (``.NAME.partial.PID.XXXX``); when complete, :func:`replace_folder` puts it in place.
  An existing folder is renamed aside (``.NAME.old.PID.XXXX``), the staging folder renamed
  onto ``NAME``, and only then is the aside copy deleted; if the second rename fails the old
  folder is renamed back. ``NAME`` names nothing only between those two renames.
  Files written inside the staging folder need no atomic write of their own: nobody sees
  them before the whole folder is in place.

After a ``SIGKILL`` (nothing can clean up) hidden ``.NAME.partial.PID.*`` or
``.NAME.old.PID.*`` folders may remain next to ``NAME``. The next
:func:`atomic_output_folder` on the same ``NAME`` removes those of dead processes and, if the
kill fell between the two renames (``NAME`` missing, an aside copy present), first renames
the old folder back to ``NAME`` (:func:`recover_leftovers`).
"""

from __future__ import annotations

import os
import re
import secrets
import shutil
import tempfile
import time
from contextlib import contextmanager
from pathlib import Path

from idkit.errors import OutputError

__all__ = ["write_bytes_atomic", "write_text_atomic", "atomic_output_folder", "replace_folder",
           "recover_leftovers", "SWAP_PAUSE_VARIABLE"]

#: Test hook (not for users): ``POINT:FILE`` with POINT one of ``before`` (the old folder still
#: at NAME), ``between`` (old renamed aside, new not yet in place) or ``after`` (new in place,
#: aside copy not yet deleted). At that point the swap creates FILE and waits while it exists
#: (up to 120 s), so a test can deliver a signal at a known instant of the swap.
SWAP_PAUSE_VARIABLE = "IDKIT_TEST_SWAP_PAUSE"


def _current_umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def _reason(problem: OSError) -> str:
    return problem.strerror or str(problem)


def write_bytes_atomic(path: str | Path, data: bytes, *, overwrite: bool = False) -> Path:
    """Write bytes to ``path`` atomically.

    The data go to a temporary file in the same folder, which is flushed,
    synced and then moved onto ``path`` with :func:`os.replace`, so a reader
    sees either the old file or the complete new one, never a partial file.

    Parameters
    ----------
    path : str or pathlib.Path
        Target file; its folder must exist.
    data : bytes
        Content.
    overwrite : bool
        Replace an existing file. Default ``False``: refuse.

    Returns
    -------
    pathlib.Path
        The target path.

    Raises
    ------
    FileExistsError
        If ``path`` exists and ``overwrite`` is false.
    idkit.errors.OutputError
        If the file cannot be written (missing or read-only folder, full disk); names ``path``.
    """
    path = Path(path)
    if path.exists() and not overwrite:
        raise FileExistsError(f"file '{path}' exists; refusing to overwrite it "
                              "(pass overwrite=True to replace it)")
    if path.is_dir():
        raise OutputError(f"cannot write '{path}': it is a folder, expected a file name")
    try:
        handle = tempfile.NamedTemporaryFile(
            mode="wb", dir=path.parent, prefix=f".{path.name}.", suffix=".tmp", delete=False
        )
    except OSError as problem:
        raise OutputError(f"cannot write '{path}': {_reason(problem)} (in folder '{path.parent}')") from None
    try:
        with handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.chmod(handle.name, 0o666 & ~_current_umask())  # as open() would create it
        if not overwrite and path.exists():  # appeared while we were writing
            raise FileExistsError(f"file '{path}' appeared while writing; not replaced")
        os.replace(handle.name, path)
    except FileExistsError:
        Path(handle.name).unlink(missing_ok=True)
        raise
    except OSError as problem:
        Path(handle.name).unlink(missing_ok=True)
        raise OutputError(f"cannot write '{path}': {_reason(problem)}; nothing written") from None
    except BaseException:
        Path(handle.name).unlink(missing_ok=True)
        raise
    return path


def write_text_atomic(path: str | Path, text: str, *, overwrite: bool = False, encoding: str = "utf-8") -> Path:
    """Write text to ``path`` atomically (:func:`write_bytes_atomic`; UTF-8 by default)."""
    return write_bytes_atomic(path, text.encode(encoding), overwrite=overwrite)


def _hidden_name(path: Path, role: str) -> Path:
    return path.parent / f".{path.name}.{role}.{os.getpid()}.{secrets.token_hex(4)}"


def _remove(path: Path) -> None:
    if path.is_symlink() or not path.is_dir():
        path.unlink(missing_ok=True)
    else:
        shutil.rmtree(path, ignore_errors=True)


def _pause_for_tests(point: str) -> None:
    hook = os.environ.get(SWAP_PAUSE_VARIABLE, "")
    wanted, _, flag = hook.partition(":")
    if wanted != point or not flag:
        return
    flag_path = Path(flag)
    flag_path.touch()
    deadline = time.monotonic() + 120.0
    while flag_path.exists() and time.monotonic() < deadline:
        time.sleep(0.01)


def _process_alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # someone else's process
        return True
    return True


def recover_leftovers(path: str | Path) -> list[Path]:
    """Clean up after a killed run that wrote ``path``; return what was removed or restored.

    Hidden ``.NAME.partial.PID.*`` and ``.NAME.old.PID.*`` folders next to ``path`` whose
    process ``PID`` no longer runs are removed; if ``path`` itself is missing and such an
    aside copy exists (the run was killed between the two renames of the swap), the newest
    aside copy is renamed back to ``path`` first.
    """
    path = Path(path)
    if not path.parent.is_dir():
        return []
    pattern = re.compile(rf"^\.{re.escape(path.name)}\.(partial|old)\.(\d+)\.[0-9a-f]+$")
    stale = []
    for entry in path.parent.iterdir():
        match = pattern.match(entry.name)
        if match and not _process_alive(int(match.group(2))):
            stale.append((match.group(1), entry))
    asides = sorted((entry for role, entry in stale if role == "old"), key=lambda p: p.lstat().st_mtime)
    touched = []
    if asides and not os.path.lexists(path):
        os.rename(asides[-1], path)
        touched.append(path)
    for _, entry in stale:
        if os.path.lexists(entry):
            _remove(entry)
            touched.append(entry)
    return touched


def replace_folder(staging: str | Path, path: str | Path) -> Path:
    """Move the complete folder ``staging`` to ``path``, replacing an existing folder there.

    The old folder is renamed aside (hidden ``.NAME.old.PID.XXXX`` next to it), ``staging``
    is renamed onto ``path``, then the aside copy is deleted. If anything fails before the
    new folder is in place (including ``KeyboardInterrupt``), the old folder is renamed back.
    ``staging`` must be in the same folder as ``path`` (renames do not cross file systems).

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    staging, path = Path(staging), Path(path)
    _pause_for_tests("before")
    if not os.path.lexists(path):
        os.rename(staging, path)
        return path
    if not path.is_dir():
        raise OutputError(f"cannot replace '{path}': it is not a folder")
    aside = _hidden_name(path, "old")
    os.rename(path, aside)
    try:
        _pause_for_tests("between")
        os.rename(staging, path)
    except BaseException:
        if not os.path.lexists(path):
            os.rename(aside, path)
        raise
    _pause_for_tests("after")
    _remove(aside)
    return path


@contextmanager
def atomic_output_folder(path: str | Path, *, force: bool = False):
    """Yield a hidden staging folder next to ``path``; on success it replaces ``path``.

    Refuses an existing ``path`` unless ``force``; missing parent folders are created.
    On any exception (also ``KeyboardInterrupt`` and the ``SIGTERM`` the CLI turns into
    one) the staging folder is removed and an existing ``path`` is left untouched; on
    success the swap is :func:`replace_folder`. Leftovers of killed runs are cleaned first
    (:func:`recover_leftovers`).

    Examples
    --------
    >>> with atomic_output_folder("out", force=True) as folder:  # doctest: +SKIP
    ...     (folder / "summary.json").write_text("{}")
    """
    path = Path(path)
    recover_leftovers(path)
    if os.path.lexists(path) and not force:
        raise FileExistsError(f"{path}: exists; pass --force (force=True) to replace it")
    if os.path.lexists(path) and not path.is_dir():
        raise OutputError(f"output folder '{path}': exists and is not a folder; not replaced")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        staging = _hidden_name(path, "partial")
        staging.mkdir()
    except OSError as problem:
        raise OutputError(f"cannot create output folder '{path}': {_reason(problem)}") from None
    try:
        yield staging
        replace_folder(staging, path)
    except OSError as problem:
        if isinstance(problem, OutputError) or problem.filename is None:
            raise
        raise OutputError(f"writing output folder '{path}': {_reason(problem)} ('{problem.filename}'); "
                          "the previous output (if any) is unchanged") from problem
    finally:
        if os.path.lexists(staging):
            _remove(staging)
