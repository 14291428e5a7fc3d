"""Accessors of computed responses given what is not an order, a kind or an amplitude: an idkit
error naming it (TypeError/ValueError before; ``True`` read as order 1; an unknown special-point
kind returned no points as if none had been found)."""

import numpy as np
import pytest

from idkit.errors import SimulationError
from idkit.models import SDOFSystem, VoigtModel
from idkit import responses as R

SYSTEM = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5.0) ** 2, damping=0.5))


@pytest.fixture(scope="module")
def results():
    return {"map": R.harmonic_map(SYSTEM, [3.0, 5.0, 8.0], [1e-3]),
            "branch": R.continue_in_frequency(SYSTEM, 1e-3, (4.0, 6.0)),
            "orbit": R.periodic_response(SYSTEM, 5.0, 1e-3)}


@pytest.mark.parametrize("order", ["a", None, True, np.nan])
@pytest.mark.parametrize("which, method", [("map", "magnitude"), ("map", "phase"), ("map", "resonance_frequency"),
                                           ("branch", "harmonic"), ("branch", "hosidf"), ("orbit", "harmonic"),
                                           ("orbit", "hosidf")])
def test_a_bad_order_is_refused_naming_it(results, which, method, order):
    with pytest.raises(SimulationError, match=r"order: found .*expected"):
        getattr(results[which], method)(order)
    assert np.all(np.isfinite(np.abs(getattr(results[which], method)(1))))  # order 1 still works


def test_unknown_special_point_kind_and_amplitude_are_refused(results):
    with pytest.raises(SimulationError, match=r"kind: found 'folds', expected 'fold' or 'period doubling'"):
        results["branch"].points("folds")
    assert results["branch"].points("fold") == ()
    with pytest.raises(SimulationError, match=r"amplitude: found 'a'"):
        results["map"].amplitude_index("a")


def test_chapter_study_quick_must_be_a_bool():
    from idkit.studies import StudyError, compute_chapter_study

    with pytest.raises(StudyError, match=r"quick: found 'no', expected True or False"):
        compute_chapter_study("wire-rope", quick="no")
