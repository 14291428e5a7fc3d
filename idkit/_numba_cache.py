"""Process-safe writes to numba's on-disk cache (imported by every module that caches).

numba keeps the compiled functions of one Python function in an index file, which maps each
compiled signature (for a closure kernel also the values it closes over: one driver per system
structure) to a numbered data file holding its machine code. Adding an entry reads the index,
takes the first free number, writes the index and then the data. Two processes that add
different entries to the same index at the same moment (pytest-xdist workers or the report's
forked children on a cold cache, a user's process pool) can both take the same number: one
entry then names the other's machine code, which every later process loads and runs for it,
giving wrong numbers or a crash ("In 'NRT_adapt_ndarray_to_python', 'descr' is NULL", seen in
a fresh clone's test run on 2026-11-26). numba's own issue #4807 tracks such races.

Installed on import, :func:`install` makes the save of every cached function take an exclusive
``flock`` on a file beside its index, read the index inside the lock, and write the data before
the index, so that an index entry always names data written for that entry. A save that
fails (a full disk, a file-size limit) warns and leaves the cache as it was: the compiled code
is kept in memory, and the command goes on to fail, if at all, on its own outputs, whose
errors name them. Loading is
unchanged (numba replaces both files atomically). Where ``fcntl`` is missing (Windows) or a
numba version lacks the methods used, numba's own save is left in place and :data:`INSTALLED`
says so.
"""

from __future__ import annotations

import itertools
import warnings
from pathlib import Path

from numba.core import caching

try:
    import fcntl
except ImportError:  # not POSIX
    fcntl = None

__all__ = ["INSTALLED", "install", "locked_save"]

_NEEDED = ("_load_index", "_save_index", "_save_data", "_data_name")
_NUMBA_SAVE = caching.IndexDataCacheFile.save


def locked_save(self, key, data) -> None:
    """:meth:`numba.core.caching.IndexDataCacheFile.save` under an exclusive lock (module docstring)."""
    try:
        lock = open(self._index_path + ".lock", "ab")  # noqa: SIM115 - held for the block below
    except OSError:  # the lock cannot be made where numba could still write: its own save
        _NUMBA_SAVE(self, key, data)
        return
    with lock:
        fcntl.flock(lock.fileno(), fcntl.LOCK_EX)  # released when the file closes
        overloads = self._load_index()
        name = overloads.get(key)
        if name is None:
            taken = set(overloads.values())
            name = next(candidate for candidate in map(self._data_name, itertools.count(1))
                        if candidate not in taken)
            overloads[key] = name
        try:
            self._save_data(name, data)  # first: an index entry never names data not yet written
            self._save_index(overloads)
        except OSError as problem:  # a full disk or a file-size limit: the cache is not an output
            warnings.warn(f"numba cache not written ({problem.strerror or problem}, in "
                          f"{Path(self._index_path).parent}); the compiled code is used from memory and "
                          "compiled again by the next run", RuntimeWarning, stacklevel=2)


def install() -> bool:
    """Replace numba's cache save by :func:`locked_save` (idempotent); whether it is in place."""
    if fcntl is None or not all(hasattr(caching.IndexDataCacheFile, name) for name in _NEEDED):
        return False
    caching.IndexDataCacheFile.save = locked_save
    return True


INSTALLED = install()
