"""Property tests of the CSV reader: exact round trips, and every corruption -> DataError."""

from __future__ import annotations

import re
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from idkit.errors import DataError
from idkit.io import Excitation, MeasurementInfo, read_csv_measurement, write_csv_measurement
from idkit.io.columns import KIND_SCHEMAS
from idkit.io.csv_measurement import build_measurement

SETTINGS = settings(max_examples=50, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow])
FINITE = st.floats(allow_nan=False, allow_infinity=False, width=64)
NUMBER_RE = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
INFO = {"stepped_sine": MeasurementInfo(id="p", excitation=Excitation(freq=12.5))}


@st.composite
def measurements(draw):
    """A random valid measurement of a random kind (finite floats, increasing time)."""
    kind = draw(st.sampled_from(sorted(KIND_SCHEMAS)))
    schema = KIND_SCHEMAS[kind]
    names = list(schema.required)
    if schema.alternatives:
        for group in draw(st.sampled_from([(0,), (1,), (0, 1)])):
            names += list(schema.alternatives[group])
    names += [n for n in schema.optional if draw(st.booleans())]
    time = draw(st.lists(FINITE, min_size=2, max_size=25, unique=True).map(sorted))
    values = {"time": np.array(time)}
    for name in names:
        if name != "time":
            values[name] = np.array(draw(st.lists(FINITE, min_size=len(time), max_size=len(time))))
    return build_measurement(kind, values, info=INFO.get(kind, MeasurementInfo(id="m")))


def _bits(array: np.ndarray) -> np.ndarray:
    return np.asarray(array, dtype=np.float64).view(np.int64)


@SETTINGS
@given(measurement=measurements(), gz=st.booleans())
def test_write_then_read_is_bit_exact(measurement, gz):
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / ("m.csv.gz" if gz else "m.csv")
        write_csv_measurement(measurement, path)
        back = read_csv_measurement(path, measurement.kind, info=measurement.info)
    assert type(back) is type(measurement)
    assert back.signals().keys() == measurement.signals().keys()
    for name, values in measurement.signals().items():
        assert np.array_equal(_bits(getattr(back, name)), _bits(values)), name


GARBAGE = st.text(alphabet=st.characters(blacklist_characters=',\n\r"', codec="utf-8"),
                  min_size=1, max_size=8).filter(lambda s: NUMBER_RE.fullmatch(s.strip()) is None)
NONFINITE = st.sampled_from(["nan", "NaN", "-nan", "inf", "-inf", "+Infinity", "INF"])


@st.composite
def corruptions(draw):
    """(kind, info, corrupted CSV text, description) from a valid written measurement."""
    measurement = draw(measurements())
    with tempfile.TemporaryDirectory() as folder:
        path = write_csv_measurement(measurement, Path(folder) / "m.csv")
        lines = path.read_text(encoding="utf-8").splitlines()
    header, rows = lines[0], [line.split(",") for line in lines[1:]]
    i = draw(st.integers(0, len(rows) - 1))
    k = draw(st.integers(0, len(rows[0]) - 1))
    how = draw(st.sampled_from(["nonfinite", "delete", "empty", "duplicate_time", "garbage",
                                "drop_header_cell", "truncate"]))
    if how == "nonfinite":
        rows[i][k] = draw(NONFINITE)
    elif how == "delete":
        del rows[i][k]
    elif how == "empty":
        rows[i][k] = ""
    elif how == "duplicate_time":
        i = max(i, 1)
        rows[i][0] = rows[i - 1][0]
    elif how == "garbage":
        rows[i][k] = draw(GARBAGE)
    elif how == "drop_header_cell":
        header = ",".join(header.split(",")[:-1])
    elif how == "truncate":  # the file ends inside row i
        rows = rows[:i + 1]
        rows[-1] = rows[-1][:draw(st.integers(1, len(rows[-1]) - 1))]
    text = "\n".join([header] + [",".join(r) for r in rows]) + "\n"
    return measurement.kind, measurement.info, text, how


@SETTINGS
@given(case=corruptions())
def test_corruptions_raise_data_error_only(case):
    kind, info, text, how = case
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "bad.csv"
        path.write_text(text, encoding="utf-8")
        with pytest.raises(DataError) as error:
            read_csv_measurement(path, kind, info=info)
    assert "bad.csv" in str(error.value), how
