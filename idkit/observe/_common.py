"""Helpers shared by the observers."""

from __future__ import annotations

import numpy as np

from idkit.errors import DataError


def _require(measurement, cls, function: str):
    if not isinstance(measurement, cls):
        raise DataError(f"{function}: found {type(measurement).__name__}, expected {cls.__name__}")


def _sample_rate(time: np.ndarray) -> float:
    return 1.0 / float(np.median(np.diff(time)))

