"""Output folders that appear whole or not at all."""

from __future__ import annotations

import shutil
import tempfile
from contextlib import contextmanager
from pathlib import Path


@contextmanager
def atomic_output_folder(path, *, force: bool = False):
    """Yield a temporary sibling folder; on success it replaces ``path``.

    Refuses an existing ``path`` unless ``force``. A crash leaves nothing under
    the final name (the temporary folder is removed).
    """
    path = Path(path)
    if path.exists() and not force:
        raise FileExistsError(f"{path}: exists; pass --force (force=True) to replace it")
    path.parent.mkdir(parents=True, exist_ok=True)
    staging = Path(tempfile.mkdtemp(dir=path.parent, prefix=f".{path.name}.partial."))
    try:
        yield staging
    except BaseException:
        shutil.rmtree(staging, ignore_errors=True)
        raise
    if path.exists():
        shutil.rmtree(path)
    staging.rename(path)
