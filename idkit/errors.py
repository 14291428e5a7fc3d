"""Exceptions raised by idkit.

Every error idkit raises on bad input subclasses :class:`IdkitError` and one of
the built-in ``ValueError``/``TypeError`` (``OSError`` for outputs), so callers can catch either idkit's
own family or the standard one. Messages name the parameter, file, column or
row, what was found and what was expected.

A message that suggests another argument value is a :class:`Message` holding a
:class:`Suggestion`: Python callers read ``k0_method='secant'``, and the ``idkit`` command
renders the same suggestion as its option, ``--k0-method secant`` (``idkit.cli.hints``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

__all__ = ["Suggestion", "Message", "IdkitError", "ParameterError", "ModelFileError", "DataError", "OutputError",
           "SimulationError", "FitError", "ValidationError"]


@dataclass(frozen=True)
class Suggestion:
    """An argument value an error message suggests.

    Parameters
    ----------
    keyword : str
        The keyword argument of idkit's Python API, e.g. ``"k0_method"``.
    value : object
        The suggested value, e.g. ``"secant"`` (None where the API takes None).
    placeholder : bool
        ``value`` is a text standing for values the caller chooses (``"(x_min, x_max)"``),
        written as it is rather than as a Python literal.

    Examples
    --------
    >>> str(Suggestion("k0_method", "secant"))
    "k0_method='secant'"
    >>> str(Suggestion("valid_range", "(x_min, x_max)", placeholder=True))
    'valid_range=(x_min, x_max)'
    """

    keyword: str
    value: object = None
    placeholder: bool = False

    def __str__(self) -> str:
        return f"{self.keyword}={self.value if self.placeholder else repr(self.value)}"


class Message(str):
    """An error message with :class:`Suggestion` pieces: as a ``str``, the Python spelling.

    Raise it as the only argument of an idkit error: ``FitError(Message("... (use ",
    Suggestion("k0_method", "secant"), ")"))``. :meth:`render` spells the suggestions another
    way; the command line renders them as options, so no message is written twice.

    Examples
    --------
    >>> text = Message("use ", Suggestion("split", None), " to fit every record")
    >>> text
    'use split=None to fit every record'
    >>> text.render(lambda s: "--split all")
    'use --split all to fit every record'
    """

    pieces: tuple

    def __new__(cls, *pieces):
        for piece in pieces:
            if not isinstance(piece, (str, Suggestion)):
                raise TypeError(f"Message: found a {type(piece).__name__} piece, expected str or Suggestion")
        self = super().__new__(cls, "".join(str(piece) for piece in pieces))
        self.pieces = pieces
        return self

    def __getnewargs__(self):  # pickling (errors cross process boundaries): rebuilt from the pieces
        return self.pieces

    @property
    def suggestions(self) -> tuple[Suggestion, ...]:
        """The suggestions, in order."""
        return tuple(piece for piece in self.pieces if isinstance(piece, Suggestion))

    def render(self, spell: Callable[[Suggestion], str]) -> str:
        """The message with every suggestion spelled by ``spell``."""
        return "".join(spell(piece) if isinstance(piece, Suggestion) else piece for piece in self.pieces)


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
