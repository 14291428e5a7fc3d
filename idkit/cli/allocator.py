"""The ``idkit`` command's memory allocator: freed memory kept for the next allocation (glibc).

A command allocates and frees arrays of megabytes over and over: the simulator's records and
base motions, spectra, figures, in the main process, its threads and its forked children.
glibc's ``malloc`` serves a block above its mmap threshold with fresh pages mapped for it and
unmaps them when it is freed, and returns free memory at the top of its heap to the system
above its trim threshold; both thresholds start at 128 KiB and grow only after such a block
is freed (to its size, and twice that). The next array of about the same size then gets fresh pages,
and the first write to each is a page fault the kernel serves by zeroing the page: system
CPU spent on memory the process had a moment before. :func:`keep_freed_memory` sets the two
thresholds once, at the start of the command (forked children inherit them): blocks below
:data:`MMAP_THRESHOLD_BYTES` come from the heap, whose freed memory is reused, and up to
:data:`TRIM_THRESHOLD_BYTES` of free memory stays at its top. The numbers computed are the
same; what changes is where the memory comes from (docs/cli-reference.md).

Only the command does this (the console script and ``python -m idkit``,
:func:`idkit.cli.main.run`): a program that imports idkit, or calls
:func:`idkit.cli.main.main`, keeps its allocator as it is. Settings the user gave the allocator
(``MALLOC_*_`` variables or ``GLIBC_TUNABLES``) are left alone, and so is every other C library.
"""

from __future__ import annotations

import ctypes
import os
import sys

__all__ = ["MMAP_THRESHOLD_BYTES", "TRIM_THRESHOLD_BYTES", "keep_freed_memory"]

#: Blocks below this size come from the heap (glibc's largest mmap threshold on 64-bit systems).
MMAP_THRESHOLD_BYTES = 32 * 2**20
#: Free memory at the top of the heap kept up to this size.
TRIM_THRESHOLD_BYTES = 256 * 2**20

# mallopt's parameter numbers (glibc's malloc.h)
_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3
# the user's own allocator settings, which win
_USER_SETTINGS = ("MALLOC_MMAP_THRESHOLD_", "MALLOC_TRIM_THRESHOLD_", "MALLOC_TOP_PAD_", "MALLOC_MMAP_MAX_")


def keep_freed_memory(environ=None) -> bool:
    """Set glibc's mmap and trim thresholds of this process (module docstring).

    Parameters
    ----------
    environ : mapping, optional
        The environment whose allocator settings are respected (default ``os.environ``).

    Returns
    -------
    bool
        Whether both thresholds were set: False off Linux, with another C library, when
        ``mallopt`` refuses, or when the user set the allocator's thresholds.
    """
    environ = os.environ if environ is None else environ
    if not sys.platform.startswith("linux") or any(name in environ for name in _USER_SETTINGS) \
            or "glibc.malloc" in environ.get("GLIBC_TUNABLES", ""):
        return False
    try:
        libc = ctypes.CDLL(None)
        libc.gnu_get_libc_version  # noqa: B018 - glibc's own symbol: another C library's mallopt differs
        mallopt = libc.mallopt
    except (OSError, AttributeError):
        return False
    mallopt.argtypes = (ctypes.c_int, ctypes.c_int)
    mallopt.restype = ctypes.c_int
    # mallopt returns 1 on success
    return (mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES) == 1
            and mallopt(_M_TRIM_THRESHOLD, TRIM_THRESHOLD_BYTES) == 1)
