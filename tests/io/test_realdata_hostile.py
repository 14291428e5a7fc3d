"""Hostile variants of the shared real data, written to tmp_path (never into the repository).

Each variant is read correctly or refused with a named error; nothing is dropped or altered
silently. Skipped when ``../shared/realdata`` is absent.
"""

from __future__ import annotations

import numpy as np
import pytest

from idkit.datasets import read_afrl_accel
from idkit.errors import DataError


def _afrl_lines(realdata, k=1):
    lines = (realdata("droptower_shock_afrl") / f"accel_{k}.csv").read_text().splitlines(keepends=True)
    return lines[:2], lines[2:]


@pytest.mark.parametrize("row", [1, 2000, 4998])
def test_afrl_record_with_a_missing_sample_is_refused(realdata, tmp_path, row):
    """A removed row (a step of 2 us in a 1 MS/s record) was read, and the SRS, filter and velocity
    change ran at 1 / median step as if the samples were evenly spaced."""
    head, body = _afrl_lines(realdata)
    path = tmp_path / "accel_1.csv"
    path.write_text("".join(head + body[:row] + body[row + 1:]))
    with pytest.raises(DataError, match=rf"data row {row + 1} .*time step 2e-06 s.*2 x the median step 1e-06 s.*"
                                        r"expected uniform sampling"):
        read_afrl_accel(path)
