"""A loop record whose deflection or force never changes is named with its file and column."""

from __future__ import annotations

import math

import pytest

from tests.cli.hostile import check, run_main


def _record(path, column):
    rows = ["time [s],deflection [mm],force [kN]"]
    for i in range(60):
        deflection, force = math.sin(i / 5), 0.5 + 0.1 * math.sin(i / 5)
        rows.append(f"{0.1 * i!r},{0.0 if column == 'deflection' else deflection!r},"
                    f"{0.5 if column == 'force' else force!r}")
    path.write_text("\n".join(rows) + "\n")
    return path


@pytest.mark.parametrize("column, declared, value", [("deflection", "deflection [mm]", "0 m"),
                                                     ("force", "force [kN]", "500 N")])
@pytest.mark.parametrize("command", ["fit", "report"])
def test_a_constant_column_is_named_by_file_and_column(tmp_path, column, declared, value, command):
    path = _record(tmp_path / "loops.csv", column)
    out = tmp_path / ("model.json" if command == "fit" else "report")
    argv = ["fit", "iwan", path, "-o", out] if command == "fit" else ["report", path, "-o", out, "--quiet"]
    outcome = run_main(argv, inputs=[path], must_not_exist=[out])
    check(outcome, "error", [f"file '{path}', column '{declared}' (record loops): found a constant {column}, "
                             f"{value} in all 60 samples"])
