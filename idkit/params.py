"""Parameter declarations shared by models, simulators and every fitter backend.

A model declares each parameter once as a :class:`ParamSpec` (name, unit, bounds,
meaning). Constructors validate against these declarations; fitters read the
bounds from them (nlopt, scipy and lmfit alike); model files store values by
these names.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from idkit.checks import Real, Reals
from idkit.errors import ParameterError

__all__ = ["ParamSpec", "check_value", "check_array"]


@dataclass(frozen=True)
class ParamSpec:
    """Declaration of one scalar model parameter.

    Parameters
    ----------
    name : str
        Name used in the API, in model files and in fit reports (e.g. ``"k_1"``).
    unit : str
        SI unit, e.g. ``"N/m"``, ``"1/s"``, ``"-"`` for dimensionless.
    lower, upper : float
        Physical bounds (inclusive). ``-inf``/``inf`` when unbounded.
    meaning : str
        One-line description for reports.
    positive : bool
        If true the value must be strictly greater than ``lower`` (a stiffness
        or friction force of exactly zero is degenerate).
    """

    name: str
    unit: str
    lower: float
    upper: float
    meaning: str
    positive: bool = False

    def check(self, value: float, *, model: str = "") -> float:
        """Return ``value`` as float if it satisfies the declaration, else raise.

        Raises
        ------
        ParameterError
            Naming the model, the parameter, the value found and what was expected.
        """
        where = f"{model} parameter {self.name!r}" if model else f"parameter {self.name!r}"
        return self.spec.check(value, where, ParameterError)

    @cached_property
    def spec(self) -> Real:
        """The declaration as an :class:`idkit.checks.Real` (finite bounds only; ``positive``
        makes ``lower`` an open bound)."""
        lower = self.lower if math.isfinite(self.lower) else None
        return Real(unit=self.unit, gt=lower if self.positive else None, ge=None if self.positive else lower,
                    le=self.upper if math.isfinite(self.upper) else None, meaning=self.meaning)


def check_value(spec: ParamSpec, value: float, *, model: str = "") -> float:
    """Validate one scalar against its declaration (see :meth:`ParamSpec.check`)."""
    return spec.check(value, model=model)


def check_array(
    values,
    *,
    name: str,
    unit: str,
    lower: float,
    meaning: str,
    positive: bool,
    model: str,
    length: int | None = None,
    min_length: int = 0,
) -> np.ndarray:
    """Validate a 1-D array of same-kind parameters named ``name_1 .. name_n``.

    Returns a read-only float64 copy. Raises :class:`ParameterError` naming the
    first offending element (1-based, as in the model's parameter names).
    """
    where = f"{model} parameter {name!r}"
    array = np.array(Reals(unit=unit, min_size=0).check(values, where, ParameterError), ndmin=1)
    if array.ndim != 1:
        raise ParameterError(f"{where}: found an array of shape {array.shape}, expected 1-D")
    if length is not None and array.size != length:
        raise ParameterError(f"{where}: found {array.size} values, expected {length}")
    if array.size < min_length:
        raise ParameterError(f"{where}: found {array.size} values, expected at least {min_length}")
    for index, number in enumerate(array, start=1):
        ParamSpec(f"{name}_{index}", unit, lower, math.inf, meaning, positive).check(number, model=model)
    array.setflags(write=False)
    return array
