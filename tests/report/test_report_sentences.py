"""Sentences of the main report read off small stand-ins of the computed data (fast, no fit)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from idkit.report.fit_sections import _valid_range_words


def _data(lower, upper):
    model = SimpleNamespace(valid_deflection_range=lambda: (lower, upper))
    return SimpleNamespace(iwan=SimpleNamespace(model=model), valid_range=(-0.0848, 0.015))


@pytest.mark.parametrize(("lower", "upper", "words"), [
    (-math.inf, math.inf, "valid for every deflection ("),
    (-0.02, 0.03, "valid for deflections -20.0 mm <= x <= 30.0 mm ("),
    (-0.02, math.inf, "valid for deflections x >= -20.0 mm (no upper limit) ("),
    (-math.inf, 0.03, "valid for deflections x <= 30.0 mm (no lower limit) ("),
])
def test_the_valid_range_sentence_reads_for_every_kind_of_range(lower, upper, words):
    """A spring stiff everywhere (a Table A.1 rope: g2^2 < 3 g1 g3) was 'valid for deflections
    every deflection'."""
    sentence = _valid_range_words(_data(lower, upper))
    assert sentence.startswith(words)
    assert "required: -84.8 to 15.0 mm" in sentence


def test_the_outcome_names_as_failed_only_the_validations_that_failed():
    """With status 1 every non-PASS verdict was listed as failed: 'a validation failed (wire rope
    sweeps, elastomer FRF)' where the sweeps were INCONCLUSIVE (Table A.1 / Table B.1 high set)."""
    from idkit.report.front_page import outcome_sentence

    verdicts = {"wire rope sweeps": "INCONCLUSIVE", "wire rope drops": "PASS", "elastomer FRF": "FAIL"}
    assert outcome_sentence(verdicts, ()).endswith(
        "exits with status 1: a validation failed (elastomer FRF; inconclusive: wire rope sweeps).")
    verdicts["wire rope sweeps"] = "PASS"
    assert outcome_sentence(verdicts, ()).endswith("exits with status 1: a validation failed (elastomer FRF).")
    verdicts.update({"elastomer FRF": "INCONCLUSIVE", "wire rope drops": "INCONCLUSIVE"})
    assert outcome_sentence(verdicts, ("wire rope (Iwan)",)).endswith(
        "exits with status 3: no validation failed, but one is inconclusive (wire rope drops, elastomer FRF).")


def test_the_transport_gist_groups_the_floor_levels_by_their_best_system():
    import numpy as np
    import pandas as pd

    from idkit.report.transport_section import transport_gist
    from idkit.studies.transport import TransportStudy

    unit = "[(m/s^2)^2/Hz]"
    rms = pd.DataFrame({f"1e-08 {unit}": [1.0, 2.0], f"1e-06 {unit}": [1.0, 2.0], f"0.001 {unit}": [3.0, 2.0]},
                       index=["reference", "wire rope"])
    study = TransportStudy(tuning=pd.DataFrame(), rms=rms, psd=(), seed=0, n_realizations=1, flagged_runs=0,
                           shock_velocity=pd.DataFrame(),
                           shock_height=pd.DataFrame({"reference": [1.0], "wire rope": [np.nan]}, index=[0.05]))
    assert transport_gist(study) == (
        "Transport study (2 systems tuned to 5 Hz): lowest RMS top acceleration: reference at 1e-08, 1e-06, "
        f"wire rope at 0.001 {unit}; lowest rest shock after a 5 cm drop: reference.")


def test_data_warnings_are_listed_once_per_distinct_message_with_their_records():
    from idkit.report.main_report import warning_rows

    def warning(record, message):
        return SimpleNamespace(kind="non_flat_input", measurement_id=record, message=message)

    same = "first-harmonic base amplitude varies 1.58:1 over frequency"
    data = SimpleNamespace(inspections={
        "wire_rope": SimpleNamespace(warnings=(warning("a", same), warning("b", same))),
        "hybrid": SimpleNamespace(warnings=(warning("c", same), warning("c", "varies 1.55:1")))})
    assert warning_rows(data) == [
        {"kind": "non_flat_input", "message": same, "records": "3: a; b; c"},
        {"kind": "non_flat_input", "message": "varies 1.55:1", "records": "1: c"}]


def test_the_key_metric_is_the_one_nearest_or_furthest_beyond_its_limit():
    from idkit.report.conclusions import key_metric

    def result(summary, thresholds, verdict):
        return SimpleNamespace(summary=summary, thresholds=thresholds, verdict=verdict)

    # a count with limit 0 above 0 outranks any ratio; at 0 it ranks as a metric at 0 % of its limit
    assert key_metric(result({"a": 2.9, "records_beyond_limit": 1.0}, {"a": 3.0, "records_beyond_limit": 0.0},
                             "FAIL"))[0] == "records_beyond_limit"
    assert key_metric(result({"a": 2.9, "records_beyond_limit": 0.0}, {"a": 3.0, "records_beyond_limit": 0.0},
                             "PASS"))[0] == "a"
    # a metric that could not be computed is what an INCONCLUSIVE verdict hangs on
    name, value, limit = key_metric(result({"a": 2.9, "b": math.nan}, {"a": 3.0, "b": 1.0}, "INCONCLUSIVE"))
    assert name == "b" and math.isnan(value) and limit == 1.0
    assert key_metric(result({}, {}, "PASS"))[0] == ""
