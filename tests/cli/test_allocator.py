"""The command's allocator keeps freed memory for the next allocation (idkit.cli.allocator)."""

import platform
import subprocess
import sys
import textwrap

import pytest

from idkit.cli.allocator import keep_freed_memory

GLIBC = sys.platform.startswith("linux") and platform.libc_ver()[0] == "glibc"

# Arrays of 8 MB, each a little larger than the one freed before it (as a simulation's records
# grow with its duration), written whole: the pages written and the page faults they cost.
_REALLOCATE = textwrap.dedent("""
    import resource, sys
    import numpy as np
    from idkit.cli.allocator import keep_freed_memory
    applied = keep_freed_memory() if sys.argv[1] == "keep" else False
    pages = 0
    before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
    for i in range(40):
        records = np.ones(1_000_000 + 1_000 * i)
        pages += records.nbytes // 4096
        del records
    print(applied, pages, resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before)
""")


def _reallocate(mode: str) -> tuple[bool, int, int]:
    completed = subprocess.run([sys.executable, "-c", _REALLOCATE, mode], capture_output=True, text=True, check=True)
    applied, pages, faults = completed.stdout.split()
    return applied == "True", int(pages), int(faults)


@pytest.mark.skipif(not GLIBC, reason="the thresholds are glibc's")
def test_freed_arrays_are_reused_without_page_faults():
    """After keep_freed_memory a freed array's pages serve the next one: only the first array's
    pages and each one's growth (2 pages) are new, about 2,100 of the 78,000 pages written; 10 %
    leaves room for the interpreter's own allocations. glibc's defaults map most of them afresh
    (about half the pages written fault; not asserted: it depends on glibc's version)."""
    applied, pages, faults = _reallocate("keep")
    assert applied
    assert faults < 0.1 * pages, (faults, pages)


def test_the_users_allocator_settings_are_left_alone():
    """An environment that sets glibc's thresholds itself is respected (nothing set, False)."""
    assert keep_freed_memory({"MALLOC_TRIM_THRESHOLD_": "0"}) is False
    assert keep_freed_memory({"MALLOC_MMAP_THRESHOLD_": "131072"}) is False
    assert keep_freed_memory({"GLIBC_TUNABLES": "glibc.malloc.trim_threshold=0"}) is False
