"""Shared fixtures: locations resolved from this file, never the working directory.

The suite runs in parallel processes (pytest-xdist, ``addopts`` in pyproject.toml) on
few cores, so each process computes on one thread: one BLAS/OpenMP thread, and under
xdist one simulator thread (``IDKIT_WORKERS``). Set here, at the top of the first
conftest, before any test module imports numpy; xdist workers and the subprocesses of
the CLI and notebook tests inherit the environment. Values set by the caller win.

The test processes (the pytest process and each xdist worker) collect garbage less often
than CPython's default (:data:`YOUNG_COLLECTION_THRESHOLD`): numba's compiler, pandas and
matplotlib allocate millions of short-lived objects, and at the default a young-generation
collection runs every 700 net allocations, each walking every object that survived the
last one. What a test computes does not depend on when cycles are collected.
"""

import gc
import os
import sys
from importlib import metadata
from pathlib import Path

import pytest

# headless backend for the tests, set before anything imports matplotlib (idkit never chooses one)
os.environ.setdefault("MPLBACKEND", "Agg")
for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")
if int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")) > 1:
    os.environ.setdefault("IDKIT_WORKERS", "1")

#: Net allocations between young-generation collections in the test processes (CPython's default
#: 700; the measured effect is in docs/development.md, "Test data and speed").
YOUNG_COLLECTION_THRESHOLD = 50_000
gc.set_threshold(YOUNG_COLLECTION_THRESHOLD, *gc.get_threshold()[1:])

# the allocator the `idkit` command runs with (idkit.cli.allocator; the command sets it in
# run(), which the tests bypass by calling main() in process): freed arrays reused, not mapped
# afresh. The user's MALLOC_* settings win, as for the command.
from idkit.cli.allocator import keep_freed_memory  # noqa: E402 - after the thread settings above

keep_freed_memory()

REPO_ROOT = Path(__file__).resolve().parents[1]

# distributions whose versions explain a red run (printed in the pytest header)
REPORTED_PACKAGES = ("numpy", "scipy", "pandas", "numba", "llvmlite", "nlopt", "lmfit", "matplotlib",
                     "hypothesis")
HYPOTHESIS_PROFILE = os.environ.get("HYPOTHESIS_PROFILE", "ci")


def _register_hypothesis_profiles() -> None:
    """Profiles: "ci" (default) derandomized, no deadline; "dev" random (HYPOTHESIS_PROFILE=dev).

    A test's own ``@settings(...)`` overrides only the fields it names; the rest come from
    the loaded profile, so every property test is reproducible under "ci".
    """
    try:
        from hypothesis import settings
    except ImportError:  # hypothesis is a test dependency; its tests skip or fail on their own
        return
    settings.register_profile("ci", derandomize=True, deadline=None, print_blob=True)
    settings.register_profile("dev", derandomize=False, deadline=None, print_blob=True)
    settings.load_profile(HYPOTHESIS_PROFILE)


_register_hypothesis_profiles()


def _distribution_version(name: str) -> str:
    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "absent"


def _numpy_cpu_features() -> str:
    """numpy's compiled-in baseline and the dispatched features this CPU runs (found, not disabled)."""
    try:
        from numpy._core import _multiarray_umath as umath
    except ImportError:
        try:  # numpy < 2
            from numpy.core import _multiarray_umath as umath
        except ImportError:
            return "unknown"
    found = getattr(umath, "__cpu_features__", {})
    baseline = [name for name in getattr(umath, "__cpu_baseline__", []) if found.get(name)]
    dispatch = [name for name in getattr(umath, "__cpu_dispatch__", []) if found.get(name)]
    return f"baseline {' '.join(baseline) or 'none'}; dispatch {' '.join(dispatch) or 'none'}"


def pytest_report_header(config):
    """Package versions and numpy's CPU features, so a red CI log explains itself."""
    python = f"python {sys.version.split()[0]} ({sys.platform})"
    versions = ", ".join(f"{name} {_distribution_version(name)}" for name in REPORTED_PACKAGES)
    lines = [f"idkit test environment: {python}", f"packages: {versions}",
             f"numpy cpu features in use: {_numpy_cpu_features()}"]
    disabled = os.environ.get("NPY_DISABLE_CPU_FEATURES")
    if disabled:
        lines.append(f"NPY_DISABLE_CPU_FEATURES={disabled}")
    lines.append(f"hypothesis profile: {HYPOTHESIS_PROFILE} (HYPOTHESIS_PROFILE=dev explores at random)")
    return lines


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return REPO_ROOT


# Compiled kernels, warmed in parallel before the xdist workers start: otherwise, from a
# fresh clone (empty per-user numba cache, idkit._numba_cache), every worker compiles the same big
# kernels itself. Each snippet compiles one kernel through the public API (the argument
# types the tests use) and writes numba's on-disk cache; the workers then load it. The
# snippets are dealt out in turn over one process per worker, which collect garbage as the tests do.


def _harmonic_and_time(system: str) -> str:
    """The harmonic and time drivers of ``system``'s structure (each structure has its own
    specialised step, idkit.simulate._structured)."""
    return ("import numpy as np\n"
            "from idkit.models import BoucWenModel, SDOFSystem, library\n"
            "from idkit.simulate import harmonic_response, simulate\n"
            f"system = {system}\n"
            "harmonic_response(system, [5.0], 1e-3, workers=1)\n"
            "simulate(system, np.arange(11) * 1e-4, workers=1)\n")


# In this order, dealt out to two processes, the snippets of the SDOF wire rope (its drivers,
# its periodic orbit, the drops) go to one and the Maxwell, hybrid and generic drivers to the
# other: the steps a process compiled inside one driver are in its memory for the next, and the
# two shares take about the same time.
_WARM_UP = (
    _harmonic_and_time("library.get('system_a1_asymmetric')"),
    _harmonic_and_time("library.get('system_b1_medium')"),
    "from idkit.models import library\n"
    "from idkit.responses.periodic import periodic_response\n"
    "periodic_response(library.get('system_a1_asymmetric'), [20.0], [1e-3], settle_periods=2)\n",
    _harmonic_and_time("library.get('hybrid_asymmetric')"),
    "from idkit.models import library\n"
    "from idkit.simulate import drop_rig\n"
    "drop_rig(library.get('system_a1_asymmetric'), bottom_mass=8.0, drop_height=[0.01], duration=0.01, workers=1)\n"
    "drop_rig(library.get('hybrid_asymmetric'), bottom_mass=8.0, drop_height=[0.01], duration=0.01, workers=1)\n",
    _harmonic_and_time("SDOFSystem(2.0, BoucWenModel(k1=5e4, k2=0.0, k3=0.0, alpha=5e4, beta=800.0, "
                       "gamma=-1100.0, n=1.0))"),
)


def pytest_configure(config):
    workers = getattr(config.option, "numprocesses", None)
    if hasattr(config, "workerinput") or not isinstance(workers, int) or workers < 2:
        return  # an xdist worker, or a run in one process: it compiles each kernel once anyway
    import subprocess
    import sys

    # one process per worker, each running its share of the snippets in turn: a process more
    # costs an interpreter and idkit's imports, and only as many compile at once as there are cores
    shares = ["\n".join(_WARM_UP[first::workers]) for first in range(min(workers, len(_WARM_UP)))]
    garbage = f"import gc\ngc.set_threshold({YOUNG_COLLECTION_THRESHOLD}, *gc.get_threshold()[1:])\n"
    runs = [subprocess.Popen([sys.executable, "-c", garbage + code], cwd=REPO_ROOT, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL) for code in shares]
    for run in runs:
        run.wait()  # a failure shows up again, with its message, in the tests themselves
