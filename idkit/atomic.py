"""Atomic file writing that never silently replaces an existing file."""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

__all__ = ["write_bytes_atomic"]


def _current_umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


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
    """
    path = Path(path)
    if path.exists() and not overwrite:
        raise FileExistsError(f"file '{path}' exists; refusing to overwrite it "
                              "(pass overwrite=True to replace it)")
    handle = tempfile.NamedTemporaryFile(
        mode="wb", dir=path.parent, prefix=f".{path.name}.", suffix=".tmp", delete=False
    )
    try:
        with handle:
            handle.write(data)
            handle.flush()
            os.fsync(handle.fileno())
        os.chmod(handle.name, 0o666 & ~_current_umask())  # as open() would create it
        if not overwrite and path.exists():  # appeared while we were writing
            raise FileExistsError(f"file '{path}' appeared while writing; not replaced")
        os.replace(handle.name, path)
    except BaseException:
        Path(handle.name).unlink(missing_ok=True)
        raise
    return path
