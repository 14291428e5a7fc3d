"""Fixtures of the io tests: corpus location and the shared real data (skip if absent)."""

from __future__ import annotations

from pathlib import Path

import pytest

from idkit.datasets import realdata_dir

CORPUS_DIR = Path(__file__).resolve().parents[1] / "data_corpus"


@pytest.fixture
def corpus_dir() -> Path:
    """The broken-file corpus ``tests/data_corpus``."""
    return CORPUS_DIR


@pytest.fixture
def realdata():
    """Return a function ``realdata(subfolder) -> Path`` that skips if the folder is absent."""

    def locate(subfolder: str) -> Path:
        path = realdata_dir(subfolder)
        if path is None:
            pytest.skip(f"real data folder '{subfolder}' not found (set IDKIT_REALDATA or "
                        "place shared/realdata beside the repository)")
        return path

    return locate
