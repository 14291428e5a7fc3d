"""Shared fixtures: locations resolved from this file, never the working directory."""

import os

# headless backend for the tests, set before anything imports matplotlib (idkit never chooses one)
os.environ.setdefault("MPLBACKEND", "Agg")

from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session")
def repo_root() -> Path:
    return REPO_ROOT
