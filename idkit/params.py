"""Parameter declarations shared by models, simulators and every fitter backend.

A model declares each parameter once as a :class:`ParamSpec` (name, unit, bounds,
meaning). Constructors validate against these declarations; fitters read the
bounds from them (nlopt, scipy and lmfit alike); model files store values by
these names.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from idkit.errors import ParameterError

__all__ = ["ParamSpec", "check_value", "check_array"]


#: Values that convert to a float but are not numbers: a boolean, text.
_NOT_NUMBERS = (bool, np.bool_, str, bytes)


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
        if isinstance(value, _NOT_NUMBERS):  # float() would take True as 1 and "8" as 8
            raise ParameterError(f"{where}: found {value!r} ({type(value).__name__}), expected a real number "
                                 f"in {self.unit}")
        try:
            number = float(value)
        except (TypeError, ValueError):
            raise ParameterError(
                f"{where}: found {value!r}, expected a real number in {self.unit}"
            ) from None
        if not math.isfinite(number):
            raise ParameterError(f"{where}: found {number}, expected a finite number in {self.unit}")
        if self.positive and number <= self.lower:
            raise ParameterError(
                f"{where}: found {number:g} {self.unit}, expected > {self.lower:g} ({self.meaning})"
            )
        if number < self.lower or number > self.upper:
            raise ParameterError(
                f"{where}: found {number:g} {self.unit}, expected within "
                f"[{self.lower:g}, {self.upper:g}] ({self.meaning})"
            )
        return number


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
    try:
        if any(isinstance(value, _NOT_NUMBERS) for value in np.ravel(np.asarray(values, dtype=object))):
            raise TypeError  # np.array(..., dtype=float) would take True as 1 and "8" as 8
        array = np.array(values, dtype=float, ndmin=1)
    except (TypeError, ValueError):
        raise ParameterError(
            f"{model} parameter {name!r}: found {values!r}, expected a sequence of numbers in {unit}"
        ) from None
    if array.ndim != 1:
        raise ParameterError(
            f"{model} parameter {name!r}: found an array of shape {array.shape}, expected 1-D"
        )
    if length is not None and array.size != length:
        raise ParameterError(
            f"{model} parameter {name!r}: found {array.size} values, expected {length}"
        )
    if array.size < min_length:
        raise ParameterError(
            f"{model} parameter {name!r}: found {array.size} values, expected at least {min_length}"
        )
    for index, number in enumerate(array, start=1):
        ParamSpec(f"{name}_{index}", unit, lower, math.inf, meaning, positive).check(number, model=model)
    array.setflags(write=False)
    return array
