"""Every broken file of tests/data_corpus raises DataError with a precise message,
and reading leaves the files byte-identical (hash and mtime)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from idkit.errors import DataError, IdkitError
from idkit.io import load_measurement_set, read_complex_stiffness, read_csv_measurement
from idkit.io.provenance import file_sha256

CORPUS_DIR = Path(__file__).resolve().parents[1] / "data_corpus"
EXPECTED = json.loads((CORPUS_DIR / "expected.json").read_text(encoding="utf-8"))


def _load(case: str, reader: str) -> object:
    path = CORPUS_DIR / case
    if reader == "measurement_set":
        return load_measurement_set(path)
    if reader == "complex_stiffness":
        return read_complex_stiffness(path)
    return read_csv_measurement(path, reader)


def _snapshot(root: Path) -> dict[str, tuple[str, int]]:
    return {str(p.relative_to(root)): (file_sha256(p), p.stat().st_mtime_ns)
            for p in sorted(root.rglob("*")) if p.is_file()}


@pytest.mark.parametrize("case", sorted(EXPECTED))
def test_broken_file_raises_data_error_naming_the_problem(case):
    spec = EXPECTED[case]
    with pytest.raises(DataError) as info:
        _load(case, spec["reader"])
    message = str(info.value)
    assert isinstance(info.value, ValueError) and isinstance(info.value, IdkitError)
    assert Path(case).name in message, f"message does not name the file: {message}"
    for fragment in spec["match"]:
        assert fragment in message, f"{fragment!r} not in {message!r}"


def test_every_corpus_case_is_listed():
    listed = set(EXPECTED)
    on_disk = {f"csv/{p.name}" for p in (CORPUS_DIR / "csv").iterdir()}
    on_disk |= {f"manifests/{p.name}" for p in (CORPUS_DIR / "manifests").iterdir()}
    assert on_disk == listed


def test_reading_the_corpus_leaves_files_byte_identical():
    before = _snapshot(CORPUS_DIR)
    for case, spec in EXPECTED.items():
        with pytest.raises(DataError):
            _load(case, spec["reader"])
    assert _snapshot(CORPUS_DIR) == before
