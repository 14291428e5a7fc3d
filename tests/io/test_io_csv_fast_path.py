"""The pandas fast path of the CSV reader gives exactly what the strict parser gives.

Bit-identical float64 values on every bundled data file, and the same outcome
(the same DataError message, or the same values) on every hostile corpus file
and on random texts built from the characters the fast path admits.
"""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from idkit.errors import DataError
from idkit.io.columns import COMPLEX_STIFFNESS_SCHEMA, KIND_SCHEMAS
from idkit.io.csv_table import decode_text, parse_table_text, read_file_bytes

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT / "data"
CORPUS_DIR = ROOT / "tests" / "data_corpus"
EXPECTED = json.loads((CORPUS_DIR / "expected.json").read_text(encoding="utf-8"))
SCHEMAS = {**KIND_SCHEMAS, "complex_stiffness": COMPLEX_STIFFNESS_SCHEMA}
QS = KIND_SCHEMAS["quasi_static"]


def _bundled_files() -> list[tuple[Path, str]]:
    out = []
    for manifest in sorted(DATA.glob("*/manifest.json")):
        for entry in json.loads(manifest.read_text(encoding="utf-8"))["measurements"]:
            out.append((manifest.parent / entry["file"], entry["kind"]))
    return out


def _outcome(path, text, schema, *, strict):
    """('ok', columns, units, source) or ('error', message) of one parse."""
    try:
        table = parse_table_text(path, "0" * 64, text, schema, strict=strict)
    except DataError as exc:
        return ("error", str(exc))
    return ("ok", table.values, table.scales, table.source)


def _assert_same(fast, strict):
    assert fast[0] == strict[0], (fast, strict)
    if fast[0] == "error":
        assert fast[1] == strict[1]
        return
    _, fast_values, fast_scales, fast_source = fast
    _, strict_values, strict_scales, strict_source = strict
    assert list(fast_values) == list(strict_values)
    for name in strict_values:
        a, b = fast_values[name], strict_values[name]
        assert a.dtype == b.dtype == np.float64 and a.shape == b.shape
        # bit-identical: compare the integer images, so -0.0 != 0.0 would be caught
        assert np.array_equal(a.view(np.int64), b.view(np.int64)), name
    assert fast_scales == strict_scales and fast_source == strict_source


def test_every_bundled_file_is_bit_identical_through_pandas():
    files = _bundled_files()
    assert len(files) == 537
    for path, kind in files:
        raw = read_file_bytes(path)
        text = decode_text(path, raw)
        sha = hashlib.sha256(raw).hexdigest()
        fast = parse_table_text(path, sha, text, KIND_SCHEMAS[kind])
        strict = parse_table_text(path, sha, text, KIND_SCHEMAS[kind], strict=True)
        _assert_same(("ok", fast.values, fast.scales, fast.source),
                     ("ok", strict.values, strict.scales, strict.source))


CSV_CASES = sorted(case for case, spec in EXPECTED.items()
                   if case.startswith("csv/") and spec["reader"] in SCHEMAS)


@pytest.mark.parametrize("case", CSV_CASES)
def test_hostile_corpus_file_gives_the_same_outcome_both_ways(case):
    path = CORPUS_DIR / case
    try:
        text = decode_text(path, read_file_bytes(path))
    except DataError:
        return  # refused before any parsing (not UTF-8, not gzip): one code path
    schema = SCHEMAS[EXPECTED[case]["reader"]]
    fast = _outcome(path, text, schema, strict=False)
    strict = _outcome(path, text, schema, strict=True)
    _assert_same(fast, strict)
    if fast[0] == "error":
        assert path.name in fast[1]


@pytest.mark.parametrize("text", [
    "time [s],deflection [m],force [N]\n0,1,2\n1,2,3,\n",          # trailing comma
    "time [s],deflection [m],force [N]\n0,1,2,\n1,2,3,\n",         # trailing comma everywhere
    "time [s],deflection [m],force [N]\n0,1,2\n\n1,2,3\n",         # empty line between rows
    "time [s],deflection [m],force [N]\n0,1,2\n1,2\n2,3,4,5\n",    # short and long rows
    "time [s],deflection [m],force [N]\n0,1,2\n1,,3\n",            # empty cell
    "time [s],deflection [m],force [N]\n0,1,2\n1,2,1e400\n",       # overflow to inf
    "time [s],deflection [m],force [N]\n0,1,2\n1,2,1e-400\n",      # underflow to 0
    "time [s],deflection [m],force [N]\n0,1,2\n1,2,0e-400\n",      # a true 0
    "time [s],deflection [m],force [N]\n0,1,2\n1,2,5e-324\n",      # the smallest, kept
    "time [s],deflection [m],force [N]\n0,1,2\n1,2,0." + "0" * 330 + "1\n",  # underflow, no exponent
    "time [s],deflection [mm],force [kN]\n0,1,2\n1,5e-324,3\n",    # 0 after the unit conversion
    "time [s],deflection [mm],force [kN]\n0,1,2\n1,2,1e306\n",     # inf after the unit conversion
    "time [s],deflection [m],force [N]\n0,1,2\r1,2,3\r",           # bare carriage returns
    "time [s],deflection [m],force [N]\n0,1,2\n1,2,3\n \n",        # a blank-looking last line
    '"time [s]",deflection [m],force [N]\n0,1,2\n1,2,3\n',         # quoted header cell
    "time [s],deflection [m],force [N]\n0,1,2\n1,2,3e\n",          # exponent without digits
    "time [s],deflection [m],force [N]\n0,1,2\n1,2,1 5\n",         # blank inside a number
    "time [s],deflection [m],force [N]\n0,1,2\n1,2,-\n",           # sign alone
    "time [s],deflection [m],force [N]\n0, 1\t,2\r\n1,2,+.5e-3\r\n\r\n",  # valid, blanks
    "\ntime [s],deflection [m],force [N]\n0,1,2\n",                  # empty first line
    "time [s],deflection [m],force [N]\n",                          # header only
])
def test_edge_texts_give_the_same_outcome_both_ways(text):
    _assert_same(_outcome("edge.csv", text, QS, strict=False),
                 _outcome("edge.csv", text, QS, strict=True))


# cells drawn from the characters the fast path admits, plus a few it refuses
_CELL = st.text(alphabet="0123456789+-.eE \t", min_size=0, max_size=8)
_NUMBER = st.floats(allow_nan=False, allow_infinity=False).map(repr)


@settings(max_examples=300, deadline=None)
@given(rows=st.lists(st.lists(st.one_of(_NUMBER, _NUMBER, _CELL), min_size=2, max_size=4),
                     min_size=1, max_size=5),
       line_end=st.sampled_from(["\n", "\r\n"]), trailing=st.sampled_from(["", "\n", "\n\n"]))
def test_random_texts_give_the_same_outcome_both_ways(rows, line_end, trailing):
    text = line_end.join(["time [s],deflection [m],force [N]"] + [",".join(r) for r in rows])
    text += trailing
    _assert_same(_outcome("random.csv", text, QS, strict=False),
                 _outcome("random.csv", text, QS, strict=True))
