"""Run compiled batch kernels over chunks of a batch on several threads.

The kernels release the GIL (``nogil``), so plain threads run them in parallel
without process start-up or pickling. ``executor`` may be any
``concurrent.futures``-style executor (``submit`` returning futures), e.g. a
Dask ``Client`` for a cluster.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from idkit.checks import Whole, accepts
from idkit.errors import SimulationError


def default_workers() -> int:
    """Number of usable CPU cores, or the environment variable ``IDKIT_WORKERS`` if set.

    ``IDKIT_WORKERS`` caps the threads when several processes share the cores (the
    test suite sets it to 1 in each of its parallel worker processes).
    """
    setting = os.environ.get("IDKIT_WORKERS", "").strip()
    if setting:
        # ASCII digits only: int() would also read "1_0" as 10 and other scripts' digits
        if not (setting.isascii() and setting.isdigit() and int(setting) >= 1):
            raise SimulationError(f"environment variable IDKIT_WORKERS: found {setting!r}, expected a "
                                  "whole number >= 1 written in digits (threads per batch)")
        return int(setting)
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


def chunk_slices(size: int, chunk_size: int) -> list[slice]:
    return [slice(start, min(start + chunk_size, size)) for start in range(0, size, chunk_size)]


#: ``workers`` (threads) and ``chunk_size`` (points per chunk) of the chunked runs.
WORKERS = Whole(ge=1, optional=True, meaning="threads")
CHUNK_SIZE = Whole(ge=1, optional=True)


@accepts(workers=WORKERS, chunk_size=CHUNK_SIZE, error=SimulationError)
def run_chunked(task, size: int, *, workers=None, chunk_size=None, progress=None, executor=None):
    """Call ``task(slice)`` for chunks covering ``range(size)``; concatenate each output field.

    ``task`` returns a tuple of arrays whose first axis runs over the chunk. ``workers`` and
    ``chunk_size`` are whole numbers >= 1 (2.5 or 0 are refused, never truncated or raised).
    """
    workers = default_workers() if workers is None else workers
    if chunk_size is None:
        chunk_size = max(1, -(-size // (4 * workers))) if size > workers else 1
    slices = chunk_slices(size, chunk_size)
    results = [None] * len(slices)
    done = 0
    if executor is None and workers == 1:
        for index, part in enumerate(slices):
            results[index] = task(part)
            done += part.stop - part.start
            if progress is not None:
                progress(done, size)
    else:
        own_pool = executor is None
        pool = ThreadPoolExecutor(max_workers=workers) if own_pool else executor
        try:
            futures = {index: pool.submit(task, part) for index, part in enumerate(slices)}
            for index, part in enumerate(slices):
                results[index] = futures[index].result()
                done += part.stop - part.start
                if progress is not None:
                    progress(done, size)
        finally:
            if own_pool:
                pool.shutdown()
    return tuple(np.concatenate(field) for field in zip(*results))
