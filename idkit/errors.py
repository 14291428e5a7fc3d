"""Exceptions raised by idkit.

Every error idkit raises on bad input subclasses :class:`IdkitError` and one of
the built-in ``ValueError``/``TypeError`` (``OSError`` for outputs), so callers can catch either idkit's
own family or the standard one. Messages name the parameter, file, column or
row, what was found and what was expected.
"""


class IdkitError(Exception):
    """Base class of every idkit error."""


class ParameterError(IdkitError, ValueError):
    """A model parameter is missing, non-finite, out of its bounds or of the wrong count."""


class ModelFileError(IdkitError, ValueError):
    """A model file (JSON) cannot be read: unknown kind, wrong schema, bad values."""


class DataError(IdkitError, ValueError):
    """A measurement file or manifest is malformed (names file, column/row, found, expected)."""


class OutputError(IdkitError, OSError):
    """An output cannot be written: it would overlap an input, its folder is missing or
    read-only, the disk is full (names the path and the reason)."""


class SimulationError(IdkitError, ValueError):
    """Simulation inputs are inconsistent (time grid, base motion, initial conditions)."""


class FitError(IdkitError, ValueError):
    """Fit inputs are unusable (too few points, no reversals, NaN in a response)."""


class ValidationError(IdkitError, ValueError):
    """Validation inputs are unusable (no measurements, missing masses, unknown thresholds)."""
