"""Declared data-file contracts: every key of the manifest tables and every metadata field refuses
the bad values its spec lists, with the file, the key, what was found and what was expected named."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from idkit.errors import DataError
from idkit.io import (AccelerationRecord, Excitation, MeasurementInfo, QuasiStaticMeasurement, Source,
                      WhiteNoiseMeasurement, read_manifest)
from idkit.io.contract import TIME_AXIS, UNIFORM_TIME_AXIS, Column, check_columns
from idkit.io.info import EXCITATION_FIELDS as INFO_EXCITATION_FIELDS
from idkit.io.info import INFO_FIELDS
from idkit.io.manifest import ENTRY_FIELDS, EXCITATION_FIELDS, MANIFEST_FIELDS
from idkit.checks import Field, Real, check_fields


def _json_value(value):
    """``value`` as JSON can hold it, or None when it cannot (a NaN, an array, a subnormal float that
    JSON text would round-trip differently): such bad values are covered by the Python-level test."""
    if isinstance(value, np.ndarray):
        return None
    if isinstance(value, float) and (not math.isfinite(value) or value != 0 and abs(value) < 1e-300):
        return None
    if isinstance(value, list) and any(_json_value(item) is None and item is not None for item in value):
        return None
    return value


def _manifest_cases():
    """(table, key, bad value) for every declared manifest key whose bad value JSON can state."""
    tables = (("top", MANIFEST_FIELDS), ("entry", ENTRY_FIELDS), ("entry", INFO_FIELDS[1:]),
              ("excitation", EXCITATION_FIELDS))
    for where, fields in tables:
        for field in fields:
            for bad in field.spec.bad_values():
                if (bad is None and not field.required) or _json_value(bad) is None and bad is not None:
                    continue
                if bad is None and field.required:
                    continue  # a present null: covered by the missing-key case below
                yield pytest.param(where, field.name, bad, id=f"{where}.{field.name}={bad!r}"[:60])


def _document(where: str, key: str, bad) -> dict:
    entry = {"id": "qs1", "kind": "quasi_static", "file": "data.csv"}
    document = {"format": "idkit-measurement-set", "version": 1, "measurements": [entry]}
    if where == "top":
        document[key] = bad
    elif where == "entry":
        entry[key] = bad
    else:
        entry["excitation"] = {key: bad}
    return document


@pytest.mark.parametrize(("where", "key", "bad"), list(_manifest_cases()))
def test_every_declared_manifest_key_refuses_its_bad_values(tmp_path, where, key, bad):
    (tmp_path / "data.csv").write_text("time [s],deflection [m],force [N]\n0,0,0\n0.1,0,0\n")
    (tmp_path / "manifest.json").write_text(json.dumps(_document(where, key, bad)))
    with pytest.raises(DataError) as raised:
        read_manifest(tmp_path)
    message = str(raised.value)
    assert "manifest.json" in message, message
    assert key in message, message
    assert "found" in message and "expected" in message, message


@pytest.mark.parametrize("fields", [MANIFEST_FIELDS, ENTRY_FIELDS], ids=["top", "entry"])
def test_every_required_key_is_refused_when_missing(fields):
    valid = {"format": "idkit-measurement-set", "measurements": [{}], "id": "a", "kind": "drop", "file": "a.csv"}
    for field in (f for f in fields if f.required):
        values = {f.name: valid[f.name] for f in fields if f.required and f.name != field.name}
        with pytest.raises(DataError, match=f"here: required key '{field.name}' missing"):
            check_fields(values, fields, "here")


@pytest.mark.parametrize(("cls", "fields"), [(MeasurementInfo, INFO_FIELDS), (Excitation, INFO_EXCITATION_FIELDS)])
def test_every_metadata_field_refuses_its_bad_values_by_name(cls, fields):
    for field in fields:
        for bad in field.spec.bad_values():
            if bad is None and field.spec.optional:
                continue
            with pytest.raises(DataError) as raised:
                cls(**{field.name: bad})
            assert field.name in str(raised.value) and "expected" in str(raised.value)


def test_checked_metadata_is_stored_as_declared():
    info = MeasurementInfo(id="a", top_mass_kg=3, repetition=np.int64(2), excitation=Excitation(band=[0, 10]))
    assert type(info.top_mass_kg) is float and info.top_mass_kg == 3.0
    assert type(info.repetition) is int and info.repetition == 2
    assert info.excitation.band == (0.0, 10.0) and all(type(b) is float for b in info.excitation.band)


def test_unknown_key_names_the_keys_expected():
    with pytest.raises(DataError, match=r"here: unknown key\(s\) top_mas_kg; expected keys from .*top_mass_kg"):
        check_fields({"top_mas_kg": 1.0}, (Field("top_mass_kg", Real(unit="kg", gt=0)),), "here")


def test_column_contract_walks_required_and_paired_columns():
    columns = (Column("time", required=True), Column("v_base", pair="v"), Column("v_top", pair="v"),
               Column("a_base", pair="a"), Column("a_top", pair="a"))
    check_columns({"time": 1, "a_base": 1, "a_top": 1}, columns, "f")
    for present, fragment in (({"v_base": 1}, "column 'time' missing"),
                              ({"time": 1, "v_base": 1}, "column 'v_top' missing: expected both of v_base, v_top"),
                              ({"time": 1}, "no response columns; expected v_base and v_top, or a_base and a_top")):
        with pytest.raises(DataError, match=fragment):
            check_columns(present, columns, "f")
    t = np.arange(3.0)
    with pytest.raises(DataError, match="column 'a_top' missing"):
        WhiteNoiseMeasurement(time=t, a_base=t)
    with pytest.raises(DataError, match="column 'force' missing"):
        QuasiStaticMeasurement(time=t, deflection=t, force=None)


@pytest.mark.parametrize(("time", "axis", "rate", "fragments"), [
    ([0.0], TIME_AXIS, None, ["found 1 data row(s), expected at least 2"]),
    ([0.0, 0.1, 0.1], TIME_AXIS, None, ["sample 3 (1-based)", "duplicate time stamp", "found 0.1 after 0.1"]),
    ([0.0, 0.2, 0.1], TIME_AXIS, None, ["sample 3", "time decreases (unsorted)", "expected strictly increasing"]),
    ([0.0, 0.1, 0.2], TIME_AXIS, 20.0, ["10 Hz (1 / median step)", "declared sample_rate_hz 20 Hz", "tolerance 1%"]),
    ([0.0, 0.1, 0.2, 0.4], UNIFORM_TIME_AXIS, None, ["sample 4", "time step 0.2 s", "2 x the median step 0.1 s",
                                                     "expected uniform sampling within 1%"]),
])
def test_the_time_axis_rule_names_the_column_the_row_and_what_was_expected(time, axis, rate, fragments):
    """One declared rule (io.contract.Axis) for every reader's time column; a record whose steps vary
    is refused only where the axis is declared uniform."""
    source = Source(path="rec.csv")
    with pytest.raises(DataError) as raised:
        axis.check(np.array(time), "time", source, rate)
    message = str(raised.value)
    assert message.startswith("file 'rec.csv', column 'time': ")
    assert all(fragment in message for fragment in fragments), message
    TIME_AXIS.check(np.array([0.0, 0.1, 0.2, 0.4]), "time", source)  # irregular steps: fine when not uniform
    with pytest.raises(DataError, match="expected uniform sampling"):
        AccelerationRecord(time=[0.0, 0.1, 0.2, 0.4], accel=np.zeros(4))
