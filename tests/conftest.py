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
