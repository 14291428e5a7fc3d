"""Unknown column names: answered with the closest known names, never renamed."""

from __future__ import annotations

import pytest

from idkit.errors import DataError
from idkit.io import read_csv_measurement
from idkit.io.columns import KIND_SCHEMAS, closest_column_names


@pytest.mark.parametrize(("found", "kind", "expected"), [
    ("displacement", "quasi_static", ("deflection",)),
    ("disp", "quasi_static", ("deflection",)),
    ("stroke", "quasi_static", ("deflection",)),
    ("load", "quasi_static", ("force",)),
    ("Force", "quasi_static", ("force",)),   # case differs: the name in idkit's spelling
    ("forse", "quasi_static", ("force",)),   # a misspelling, by difflib
    ("displacement", "stepped_sine", ("x_base",)),  # no deflection in a stepped-sine file
    ("E_stor", "complex", ("storage",)),
    ("colour", "quasi_static", ()),          # nothing close: no hint
])
def test_closest_names_come_from_synonyms_then_spelling(found, kind, expected):
    from idkit.io.columns import COMPLEX_STIFFNESS_SCHEMA

    schema = COMPLEX_STIFFNESS_SCHEMA if kind == "complex" else KIND_SCHEMAS[kind]
    assert closest_column_names(found, schema.allowed) == expected


def test_a_lab_column_name_is_refused_with_the_idkit_name_and_the_file(tmp_path):
    path = tmp_path / "loops.csv"
    text = "time [s],displacement [mm],force [kip]\n0,0,0\n0.1,1,0.5\n"
    path.write_text(text)
    with pytest.raises(DataError) as info:
        read_csv_measurement(path, "quasi_static")
    message = str(info.value)
    assert "loops.csv" in message and "header column 2" in message
    assert "unknown column 'displacement' (did you mean 'deflection'?)" in message
    assert path.read_text() == text  # never renamed in place


def test_kip_column_reads_in_newtons(tmp_path):
    path = tmp_path / "loops.csv"
    path.write_text("time [s],deflection [in],force [kip]\n0,0,0\n0.1,1,0.5\n")
    measurement = read_csv_measurement(path, "quasi_static")
    # 1 in = 0.0254 m and 1 kip = 4448.2216152605 N exactly; one rounding of the product each
    assert measurement.deflection[1] == 0.0254
    assert measurement.force[1] == pytest.approx(2224.11080763025, rel=2**-52)
