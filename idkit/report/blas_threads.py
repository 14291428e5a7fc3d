"""One BLAS thread per process while the report computes (:func:`one_blas_thread`).

The report already keeps the cores busy with its own processes (the forked Bouc-Wen fit,
transport study and figure renderers beside the main process, :mod:`idkit.forked`), and the
fits' linear algebra is small: matrix-vector products of a few thousand frequencies by a few
Prony terms, singular value decompositions of Jacobians of a few columns. OpenBLAS, which
NumPy's and SciPy's wheels each bundle, splits such calls over all cores; with every core
already taken its threads wait for one another at each call, so a product of microseconds
takes milliseconds (a 2000 x 4 complex product: 5.5 us on one thread, 28 ms on two of a busy
two-core machine, measured). One thread per process leaves the parallelism to the report's
processes. Results change only by round-off: a product's rows are summed in the same order;
a decomposition's blocking may differ in the last digits.

The thread count of every OpenBLAS library loaded in the process is set through its own
function (found by the library paths in ``/proc/self/maps``) and restored afterwards;
forked children inherit it. Where no OpenBLAS is found (another BLAS, a system without
``/proc``) nothing is changed.
"""

from __future__ import annotations

import contextlib
import ctypes
import os
from pathlib import Path

__all__ = ["loaded_openblas", "one_blas_thread"]

#: (getter, setter) names of OpenBLAS builds: plain, 64-bit integer, and the scipy-openblas
#: wheels NumPy (64-bit, ``64_`` suffix) and SciPy (32-bit) bundle, whose names carry a prefix
_FUNCTIONS = (("openblas_get_num_threads", "openblas_set_num_threads"),
              ("openblas_get_num_threads64_", "openblas_set_num_threads64_"),
              ("scipy_openblas_get_num_threads", "scipy_openblas_set_num_threads"),
              ("scipy_openblas_get_num_threads64_", "scipy_openblas_set_num_threads64_"))


def _mapped_libraries(maps: Path = Path("/proc/self/maps")) -> list[str]:
    """Paths of the shared libraries mapped into this process whose name mentions OpenBLAS."""
    try:
        lines = maps.read_text().splitlines()
    except OSError:  # not Linux
        return []
    paths = []
    for line in lines:
        path = line.split(maxsplit=5)[5] if len(line.split(maxsplit=5)) == 6 else ""
        name = os.path.basename(path).lower()
        if "openblas" in name and ".so" in name and path not in paths:
            paths.append(path)
    return paths


def loaded_openblas() -> list[tuple]:
    """``(path, get_num_threads, set_num_threads)`` of every OpenBLAS loaded in this process."""
    found = []
    for path in _mapped_libraries():
        try:
            library = ctypes.CDLL(path, mode=getattr(os, "RTLD_NOLOAD", 0) | ctypes.RTLD_LOCAL)
        except OSError:
            continue
        for getter, setter in _FUNCTIONS:
            if hasattr(library, getter) and hasattr(library, setter):
                get, put = getattr(library, getter), getattr(library, setter)
                get.restype, get.argtypes = ctypes.c_int, []
                put.restype, put.argtypes = None, [ctypes.c_int]
                found.append((path, get, put))
                break
    return found


@contextlib.contextmanager
def one_blas_thread():
    """Run the block with one thread in every loaded OpenBLAS (NumPy's and SciPy's); restore the
    previous counts afterwards (module docstring)."""
    import numpy  # noqa: F401 - load both libraries before looking for them
    import scipy.linalg  # noqa: F401

    libraries = loaded_openblas()
    previous = [get() for _, get, _ in libraries]
    for _, _, put in libraries:
        put(1)
    try:
        yield
    finally:
        for (_, _, put), count in zip(libraries, previous):
            put(count)
