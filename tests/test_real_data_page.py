"""docs/real-data.md: every worked example runs as written (skipped when ../shared/realdata is absent)."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

from idkit.datasets import realdata_dir

ROOT = Path(__file__).resolve().parents[1]
BLOCKS = re.findall(r"```python\n(.*?)```", (ROOT / "docs" / "real-data.md").read_text(), flags=re.S)


def test_the_page_has_the_four_examples():
    assert len(BLOCKS) == 4


@pytest.mark.skipif(realdata_dir() is None, reason="../shared/realdata is not present")
@pytest.mark.parametrize("index", range(4), ids=["mr_damper", "shock", "boucwen", "dma"])
def test_example_runs_and_prints_what_the_page_says(index, monkeypatch):
    monkeypatch.chdir(ROOT)
    out = io.StringIO()
    namespace: dict = {}
    with contextlib.redirect_stdout(out):
        exec(compile(BLOCKS[index], f"docs/real-data.md block {index + 1}", "exec"), namespace)
    text = out.getvalue()
    if index == 0:
        assert "9.38 to 5.91 mm" in text and "+101.3 N" in text
        assert namespace["fit"].success is False and namespace["fit"].data.single_amplitude
    elif index == 1:
        peaks = namespace["table"]["peak [g]"] / 1000
        assert peaks.min() > 10.5 and peaks.max() < 13.0
        assert abs(float(namespace["analysis"].ratios[0].ratio.mean()) - 1) < 0.1
    elif index == 2:
        assert float(text.split()[0]) < 1e-6  # well under the published floor 3.2e-6 m
    else:
        assert namespace["table"].quantity == "modulus" and namespace["fit"].model.unit == "Pa"
        assert "DISAGREE" in text.splitlines()[0] and " agree" in text.splitlines()[1]
        assert namespace["fit"].result.error < 0.02 and namespace["part"].unit == "N/m"
