"""Sentences of the main report read off small stand-ins of the computed data (fast, no fit)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import pytest

from idkit.report.main_report import _valid_range_words


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
