"""Shared fixtures: locations resolved from this file, never the working directory.

The suite runs in parallel processes (pytest-xdist, ``addopts`` in pyproject.toml) on
few cores, so each process computes on one thread: one BLAS/OpenMP thread, and under
xdist one simulator thread (``IDKIT_WORKERS``). Set here, at the top of the first
conftest, before any test module imports numpy; xdist workers and the subprocesses of
the CLI and notebook tests inherit the environment. Values set by the caller win.
"""

import os
from pathlib import Path

import pytest

for _variable in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")
if int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")) > 1:
    os.environ.setdefault("IDKIT_WORKERS", "1")

REPO_ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return REPO_ROOT


# Compiled kernels, warmed in parallel before the xdist workers start: otherwise, from a
# fresh clone (empty numba cache in __pycache__), every worker compiles the same big
# kernels itself. Each snippet compiles one kernel through the public API (the argument
# types the tests use) and writes numba's on-disk cache; the workers then load it.
_WARM_UP = (
    "from idkit.models import library\n"
    "from idkit.simulate import harmonic_response\n"
    "harmonic_response(library.get('system_b1_medium'), [5.0], 1e-3, workers=1)\n",
    "import numpy as np\n"
    "from idkit.models import library\n"
    "from idkit.simulate import simulate\n"
    "simulate(library.get('system_b1_medium'), np.arange(11) * 1e-4, workers=1)\n",
)


def pytest_configure(config):
    workers = getattr(config.option, "numprocesses", None)
    if hasattr(config, "workerinput") or not isinstance(workers, int) or workers < 2:
        return  # an xdist worker, or a run in one process: it compiles each kernel once anyway
    import subprocess
    import sys

    runs = [subprocess.Popen([sys.executable, "-c", code], cwd=REPO_ROOT, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL) for code in _WARM_UP]
    for run in runs:
        run.wait()  # a failure shows up again, with its message, in the tests themselves
