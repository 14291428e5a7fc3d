"""Declared argument contracts: each public argument's kind, unit, range and meaning, stated once.

A public function declares its arguments with :func:`accepts`; the declaration is checked when
the function is called, before its body runs, and the body receives the coerced values (a
``float``, an ``int``, a read-only float64 array). Inner layers trust what a public function
hands them, so a value is checked once, at the boundary it enters through.

Every refusal reads ``name: found X, expected Y`` and is raised as the error class the function
declares (``DataError`` for signals and records, ``ParameterError`` for model and option values,
``SimulationError`` for simulator inputs), so callers catch idkit's family or ``ValueError``.

>>> from idkit.errors import DataError
>>> @accepts(fs=Real(unit="Hz", gt=0), error=DataError)
... def nyquist(*, fs):
...     return fs / 2
>>> nyquist(fs=100)
50.0
>>> nyquist(fs=True)
Traceback (most recent call last):
...
idkit.errors.DataError: fs: found True (bool), expected a finite real number > 0 Hz

Each spec also lists values it must refuse (:meth:`Spec.bad_values`); the test suite feeds them
to every declared argument of every declared function (:data:`DECLARED`), so a new argument is
covered by declaring it.
"""

from __future__ import annotations

import argparse
import functools
import inspect
import math
import os
import re
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from idkit.errors import DataError, ParameterError
from idkit.inputfiles import path_problem
from idkit.limits import SMALLEST_NORMAL

__all__ = ["Spec", "Real", "Reals", "Whole", "Choice", "Flag", "Text", "Samples", "Seed", "Instance", "InputPath",
           "Items", "Either", "accepts", "unchecked", "refuse", "DECLARED", "Contract", "OptionValueError", "Field",
           "field_names", "check_fields"]

#: Values that ``float()`` converts but that are not numbers.
_NOT_NUMBERS = (bool, np.bool_, str, bytes)


class _Refused(Exception):
    """Raised by a spec's ``coerce``: what was found and what was expected; ``at``, the position
    of a refused item inside the value (``[3]``), follows the argument's name in the message."""

    def __init__(self, found: str, expected: str, at: str = ""):
        super().__init__(found, expected)
        self.found, self.expected, self.at = found, expected, at


def refuse(name: str, value: Any, expected: str, error: type[Exception] = ParameterError) -> Exception:
    """The one refusal message, ``name: found X, expected Y``, as an exception to raise."""
    found = value if isinstance(value, str) and value.startswith("<") else _found(value)
    return error(f"{name}: found {found}, expected {expected}")


def _found(value: Any) -> str:
    if isinstance(value, (bool, np.bool_)):
        return f"{value!r} (bool)"
    if isinstance(value, np.ndarray):
        return f"an array of shape {value.shape}"
    if isinstance(value, int) and abs(value) >= 10**20:  # a digit string would drown the message
        return f"an integer of {len(str(abs(value)))} digits"
    return repr(value)


class OptionValueError(argparse.ArgumentTypeError, ValueError):
    """A command-line value refused by :meth:`Spec.parse` (argparse prints its message after
    ``argument --option:`` and exits with status 2)."""


class Spec:
    """One argument's contract. Subclasses define :meth:`coerce`, :meth:`expected` and
    :meth:`bad_values`."""

    optional: bool = False

    def coerce(self, value: Any) -> Any:  # pragma: no cover - abstract
        raise NotImplementedError

    def expected(self) -> str:  # pragma: no cover - abstract
        raise NotImplementedError

    def bad_values(self) -> list:
        """Values this spec must refuse (used by the table-driven refusal test)."""
        return [] if self.optional else [None]

    def check(self, value: Any, name: str, error: type[Exception] = ParameterError) -> Any:
        """``value`` coerced, or ``error`` naming ``name``, the value and the expectation."""
        if value is None and self.optional:
            return None
        try:
            return self.coerce(value)
        except _Refused as refusal:
            raise error(f"{name}{refusal.at}: found {refusal.found}, expected {refusal.expected}") from None

    def parse(self, text: str) -> Any:
        """An argparse ``type=``: ``text`` read as a number and checked (:class:`OptionValueError`,
        a ``ValueError``, on refusal). A whole number's digits are read exactly (``int`` first)."""
        try:
            number = int(text, 10) if isinstance(self, Whole) and text.strip().lstrip("+-").isdigit() \
                else float(text)
        except ValueError:
            raise OptionValueError(f"found {text!r}, expected {self.expected()}") from None
        try:
            return self.coerce(int(number) if isinstance(self, Whole) and isinstance(number, float)
                               and number.is_integer() else number)
        except _Refused as refusal:
            raise OptionValueError(f"found {text!r}, expected {refusal.expected}") from None


def _bounds(gt, ge, lt, le, unit: str) -> str:
    parts = [f"{symbol} {bound:g}" for symbol, bound in ((">", gt), (">=", ge), ("<", lt), ("<=", le))
             if bound is not None]
    text = " and ".join(parts)
    return f"{text} {unit}" if text and unit not in ("", "-") else text


def _number(value: Any, spec: Spec) -> float:
    """``value`` as a finite float; the expectation is spelled out only on refusal."""
    if isinstance(value, _NOT_NUMBERS):  # float() would take True as 1 and "8" as 8
        raise _Refused(_found(value), spec.expected())
    try:
        number = float(value)
    except (TypeError, ValueError):
        raise _Refused(_found(value), spec.expected()) from None
    if not math.isfinite(number):
        raise _Refused(repr(number), spec.expected())
    return number


@dataclass(frozen=True)
class Real(Spec):
    """A finite real number in ``unit``, with optional open (``gt``, ``lt``) or closed (``ge``,
    ``le``) bounds; ``None`` accepted when ``optional``."""

    unit: str = "-"
    gt: float | None = None
    ge: float | None = None
    lt: float | None = None
    le: float | None = None
    meaning: str = ""
    optional: bool = False

    def expected(self) -> str:
        bounds = _bounds(self.gt, self.ge, self.lt, self.le, self.unit)
        unit = "" if bounds or self.unit in ("", "-") else f" in {self.unit}"
        text = f"a finite real number {bounds}".rstrip() + unit
        return f"{text} ({self.meaning})" if self.meaning else text

    def coerce(self, value: Any) -> float:
        number = _number(value, self)
        if number != 0 and abs(number) < SMALLEST_NORMAL:  # fewer significant bits; ratios overflow
            raise _Refused(f"{number!r}", f"{self.expected()}, of magnitude 0 or >= {SMALLEST_NORMAL:.4g} (a "
                           "subnormal float64 has fewer than 53 significant bits)")
        if ((self.gt is not None and not number > self.gt) or (self.ge is not None and not number >= self.ge)
                or (self.lt is not None and not number < self.lt) or (self.le is not None and not number <= self.le)):
            raise _Refused(f"{number:g}", self.expected())
        return number

    def bad_values(self) -> list:
        bad = super().bad_values() + [math.nan, math.inf, True, "abc", 5e-310]
        low = self.gt if self.gt is not None else self.ge
        high = self.lt if self.lt is not None else self.le
        if low is not None:
            bad.append(low if self.gt is not None else low - max(1.0, abs(low)))
        if high is not None:
            bad.append(high if self.lt is not None else high + max(1.0, abs(high)))
        return bad


@dataclass(frozen=True)
class Whole(Spec):
    """A whole number (``2.5`` refused, never truncated; ``1e3`` read as 1000) within ``[ge, le]``,
    even if ``even``."""

    ge: int | None = None
    le: int | None = None
    even: bool = False
    meaning: str = ""
    optional: bool = False

    def expected(self) -> str:
        bounds = (f"from {self.ge} to {self.le}" if self.ge is not None and self.le is not None
                  else _bounds(None, self.ge, None, self.le, ""))
        text = f"{'an even' if self.even else 'a'} whole number {bounds}".rstrip()
        return f"{text} ({self.meaning})" if self.meaning else text

    def coerce(self, value: Any) -> int:
        if isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)):
            number = int(value)
        else:
            real = _number(value, self)
            if not real.is_integer():
                raise _Refused(_found(value), self.expected())
            number = int(real)
        if (self.ge is not None and number < self.ge) or (self.le is not None and number > self.le) \
                or (self.even and number % 2):
            raise _Refused(_found(number), self.expected())
        return number

    def bad_values(self) -> list:
        bad = super().bad_values() + [2.5, math.nan, True, "3"]
        if self.ge is not None:
            bad.append(self.ge - 1)
        if self.le is not None:
            bad.append(self.le + 1)
        if self.even:
            bad.append((self.ge if self.ge is not None else 0) // 2 * 2 + 3)
        return bad


@dataclass(frozen=True)
class Choice(Spec):
    """One of a fixed set of values (compared with ``==``; text is not case-folded)."""

    options: tuple = ()
    optional: bool = False

    def expected(self) -> str:
        return "one of " + ", ".join(repr(option) for option in self.options)

    def coerce(self, value: Any) -> Any:
        if isinstance(value, (str, bool, int, float, type(None))) and value in self.options \
                and (not isinstance(value, bool) or any(option is value for option in self.options)):
            return value  # True == 1, but True is not the option 1
        raise _Refused(_found(value), self.expected())

    def bad_values(self) -> list:
        bad = super().bad_values() + ["no-such-option", 3.5]
        return bad + [True] if not any(isinstance(option, bool) for option in self.options) else bad


@dataclass(frozen=True)
class Flag(Spec):
    """``True`` or ``False`` (numpy booleans accepted; ``1`` and ``"yes"`` refused); ``None``
    too when ``optional`` (a default decided by the function)."""

    optional: bool = False

    def expected(self) -> str:
        return "True, False or None" if self.optional else "True or False"

    def coerce(self, value: Any) -> bool:
        if isinstance(value, (bool, np.bool_)):
            return bool(value)
        raise _Refused(_found(value), self.expected())

    def bad_values(self) -> list:
        return super().bad_values() + [1, "yes"]


@dataclass(frozen=True)
class Text(Spec):
    """A string; with ``pattern``, one the regular expression matches in full; with ``nonempty``,
    one with a character other than white space. ``what`` describes it in the message."""

    pattern: str = ""
    nonempty: bool = False
    what: str = ""
    optional: bool = False

    def expected(self) -> str:
        return self.what or ("a non-empty string" if self.nonempty else "a string")

    def coerce(self, value: Any) -> str:
        if not isinstance(value, str) or (self.nonempty and not value.strip()) \
                or (self.pattern and re.fullmatch(self.pattern, value) is None):
            raise _Refused(_found(value), self.expected())
        return value

    def bad_values(self) -> list:
        bad = super().bad_values() + [3.0, True, ["a"]]
        return bad + [" "] if self.nonempty else bad


@dataclass(frozen=True)
class Reals(Spec):
    """Real numbers in ``unit``, each within the bounds of :class:`Real`: a number or an array
    of any shape (amplitudes that broadcast with frequencies) with at least ``min_size`` values;
    with ``increasing``, an axis: one number or a 1-D array, strictly increasing. Returned as a
    read-only float64 array (``numpy.asarray`` of the value: the caller's array is never altered)."""

    unit: str = "-"
    gt: float | None = None
    ge: float | None = None
    lt: float | None = None
    le: float | None = None
    min_size: int = 1
    max_size: int | None = None
    increasing: bool = False
    meaning: str = ""
    optional: bool = False

    def expected(self) -> str:
        bounds = _bounds(self.gt, self.ge, self.lt, self.le, self.unit)
        unit = "" if bounds or self.unit in ("", "-") else f" in {self.unit}"
        kind = "a strictly increasing 1-D axis of finite real numbers" if self.increasing else "finite real numbers"
        if self.max_size is not None:
            count = f"{self.min_size}" if self.min_size == self.max_size else f"{self.min_size} to {self.max_size}"
            kind = f"{kind} ({count} values)"
        text = f"{kind} {bounds}".rstrip() + unit
        return f"{text} ({self.meaning})" if self.meaning else text

    def coerce(self, value: Any) -> np.ndarray:
        if isinstance(value, (str, bytes, bool, np.bool_)):
            raise _Refused(_found(value), self.expected())
        try:
            array = np.asarray(value)
        except (TypeError, ValueError):
            raise _Refused(f"<{type(value).__name__}>", self.expected()) from None
        # numpy reads [False, 10] as integers: a boolean among numbers is refused, not read as 0 or 1
        if array.dtype.kind not in "iuf" or (isinstance(value, (list, tuple))
                                             and any(isinstance(item, (bool, np.bool_)) for item in value)):
            raise _Refused(_shown(value), self.expected())
        array = array.astype(np.float64, copy=False)
        if array.size < self.min_size or (self.max_size is not None and array.size > self.max_size):
            raise _Refused(f"{array.size} values", self.expected())
        if not self._inside(array):
            outside = ~np.isfinite(array)
            for bound, refused in ((self.gt, np.less_equal), (self.ge, np.less), (self.lt, np.greater_equal),
                                   (self.le, np.greater)):
                if bound is not None:
                    with np.errstate(invalid="ignore"):
                        outside |= refused(array, bound)
            index = tuple(int(i) for i in np.unravel_index(int(np.argmax(outside)), array.shape))
            where = f" at index {index[0] if len(index) == 1 else index}" if index else ""
            raise _Refused(f"{float(array[index])!r}{where}", self.expected())
        if self.increasing:
            if array.ndim > 1:
                raise _Refused(f"an array of shape {array.shape}", self.expected())
            steps = np.flatnonzero(np.diff(array) <= 0) if array.ndim and not (array[1:] > array[:-1]).all() \
                else np.zeros(0, dtype=int)
            if steps.size:
                raise _Refused(f"{float(array[steps[0] + 1])!r} at index {steps[0] + 1} not above its predecessor",
                               self.expected())
        view = array.view()
        view.setflags(write=False)
        return view

    def _inside(self, array: np.ndarray) -> bool:
        """Every value finite and within the bounds (the common case, without a per-value mask: a
        finite sum has no NaN or inf terms; the extremes decide the bounds)."""
        if array.size == 0:
            return True
        if not math.isfinite(float(array.sum())):  # NaN, inf, or finite values whose sum overflows
            return bool(np.isfinite(array).all()) and self._inside_bounds(array)
        return self._inside_bounds(array)

    def _inside_bounds(self, array: np.ndarray) -> bool:
        low = float(array.min()) if self.gt is not None or self.ge is not None else None
        high = float(array.max()) if self.lt is not None or self.le is not None else None
        return ((self.gt is None or low > self.gt) and (self.ge is None or low >= self.ge)
                and (self.lt is None or high < self.lt) and (self.le is None or high <= self.le))

    def bad_values(self) -> list:
        bad = super().bad_values() + ["abc", [1.0, math.nan], True, [[1.0, math.inf]]]
        if self.increasing:
            inside = (self.gt if self.gt is not None else self.ge if self.ge is not None else 0.0) + 1.0
            bad += [[inside, inside], [[inside], [inside + 1.0]]]
        if self.min_size > 0:
            bad.append(np.zeros(0))
        if self.max_size is not None:
            start = (self.gt if self.gt is not None else self.ge if self.ge is not None else 0.0) + 1.0
            bad.append(start + np.arange(self.max_size + 1.0))
        low = self.gt if self.gt is not None else self.ge
        if low is not None:
            bad.append([low if self.gt is not None else low - max(1.0, abs(low))])
        high = self.lt if self.lt is not None else self.le
        if high is not None:
            bad.append([high if self.lt is not None else high + max(1.0, abs(high))])
        return bad


def _shown(value: Any) -> str:
    text = repr(value)
    return text[:80] + ("..." if len(text) > 80 else "")


@dataclass(frozen=True)
class Samples(Spec):
    """A record of real samples: a float64 array of ``ndim`` dimensions with at least
    ``min_size`` samples along its last axis, finite unless ``finite`` is false. Returned as
    a read-only float64 array (a view of the caller's when it already is one: never altered)."""

    unit: str = "-"
    ndim: tuple[int, ...] = (1,)
    min_size: int = 1
    finite: bool = True
    optional: bool = False

    def expected(self) -> str:
        shape = " or ".join(f"{n}-D" for n in self.ndim)
        finite = "finite " if self.finite else ""
        unit = f" in {self.unit}" if self.unit not in ("", "-") else ""
        count = f"at least {self.min_size} " if self.min_size else ""
        return f"a {shape} array of {count}{finite}real samples{unit}"

    def coerce(self, value: Any) -> np.ndarray:
        if isinstance(value, (str, bytes, bool, np.bool_)) or value is None:
            raise _Refused(_found(value), self.expected())
        try:
            array = np.asarray(value)
        except (TypeError, ValueError):
            raise _Refused(f"<{type(value).__name__}>", self.expected()) from None
        if array.dtype.kind not in "iuf" or array.ndim not in self.ndim:
            raise _Refused(f"an array of shape {array.shape} and dtype {array.dtype}", self.expected())
        array = array.astype(np.float64, copy=False)
        if array.shape[-1] < self.min_size:
            raise _Refused(f"{array.shape[-1]} samples", self.expected())
        # a finite sum has no NaN or inf terms (an overflowing one is looked at value by value)
        if self.finite and not (math.isfinite(float(array.sum())) or np.isfinite(array).all()):
            index = tuple(int(i) for i in np.unravel_index(int(np.argmin(np.isfinite(array))), array.shape))
            raise _Refused(f"{float(array[index])!r} at index {index[0] if len(index) == 1 else index}",
                           self.expected())
        view = array.view()
        view.setflags(write=False)
        return view

    def bad_values(self) -> list:
        bad = super().bad_values() + ["abc", np.zeros((self.min_size, 2, 2))]
        if self.min_size > 0:
            bad.append(np.zeros(self.min_size - 1))
        if self.finite:
            bad.append(np.full(max(self.min_size, 1), np.nan))
        return bad


@dataclass(frozen=True)
class Seed(Spec):
    """A random seed: a whole number in [0, 2^32 - 1] (the range numpy and nlopt accept), a
    ``numpy.random.SeedSequence`` or a ``numpy.random.Generator``."""

    optional: bool = False

    def expected(self) -> str:
        return "an integer in [0, 4294967295], a SeedSequence or a Generator"

    def coerce(self, value: Any) -> Any:
        if isinstance(value, (np.random.SeedSequence, np.random.Generator)):
            return value
        if isinstance(value, (int, np.integer)) and not isinstance(value, (bool, np.bool_)) \
                and 0 <= value <= 2**32 - 1:
            return int(value)
        raise _Refused(_found(value), self.expected())

    def bad_values(self) -> list:
        return super().bad_values() + [-1, 2**32, 1.5, True, "1"]


@dataclass(frozen=True)
class Instance(Spec):
    """An object of one of ``types`` (a system, a model, a result); ``what`` names them in the
    message (default: the class names). Found values are named by their type."""

    types: tuple = ()
    what: str = ""
    optional: bool = False

    def expected(self) -> str:
        return self.what or " or ".join(kind.__name__ for kind in self.types)

    def coerce(self, value: Any) -> Any:
        if isinstance(value, self.types):
            return value
        raise _Refused(type(value).__name__, self.expected())

    def bad_values(self) -> list:
        return super().bad_values() + ["abc", 3.0]


@dataclass(frozen=True)
class InputPath(Spec):
    """A path to read from: a string or path-like naming an existing ``kind`` of entry (``"file"``,
    a regular file; ``"folder"``; ``"any"``, either: :func:`idkit.inputfiles.path_problem`),
    returned as a :class:`pathlib.Path`. ``what`` says what it should be, in the message."""

    kind: str = "any"
    what: str = ""
    optional: bool = False

    def expected(self) -> str:
        return self.what or {"file": "a regular file", "folder": "a folder", "any": "a file or folder"}[self.kind]

    def coerce(self, value: Any) -> Path:
        if not isinstance(value, (str, os.PathLike)) or not str(value):
            raise _Refused(_found(value), self.expected())
        path = Path(value)
        problem = path_problem(path, self.kind)
        if problem is not None:
            raise _Refused(f"'{path}' ({problem})", self.expected())
        return path

    def bad_values(self) -> list:
        return super().bad_values() + [3.0, True, "", "/nonexistent/idkit-input-path"]


@dataclass(frozen=True)
class Items(Spec):
    """A sequence (a list, tuple or other iterable; not text) of at least ``min_size`` items, each
    one ``item`` accepts; returned as a tuple of the coerced items. A refused item is named by its
    position: ``records[2]: found float, expected QuasiStaticMeasurement``."""

    item: Spec = field(default_factory=lambda: Instance((object,)))
    min_size: int = 0
    optional: bool = False

    def expected(self) -> str:
        count = f"at least {self.min_size} item{'s' if self.min_size > 1 else ''}" if self.min_size else "items"
        return f"a sequence of {count}, each {self.item.expected()}"

    def coerce(self, value: Any) -> tuple:
        if isinstance(value, (str, bytes, Mapping)) or not isinstance(value, Iterable):
            raise _Refused(type(value).__name__, self.expected())
        items = tuple(value)
        if len(items) < self.min_size:
            raise _Refused(f"{len(items)} items", self.expected())
        checked = []
        for index, item in enumerate(items):
            try:
                checked.append(self.item.coerce(item))
            except _Refused as refusal:
                raise _Refused(refusal.found, refusal.expected, f"[{index}]{refusal.at}") from None
        return tuple(checked)

    def bad_values(self) -> list:
        return super().bad_values() + ["abc", 3.0] + [[bad] for bad in self.item.bad_values() if bad is not None]


@dataclass(frozen=True)
class Either(Spec):
    """A value one of ``specs`` accepts, coerced by the first that does (an order or ``"auto"``:
    ``Either((Whole(ge=1), Choice(("auto",))))``). A sequence one :class:`Items` spec refuses for
    one of its items is refused naming that item."""

    specs: tuple = ()
    optional: bool = False

    def expected(self) -> str:
        return " or ".join(spec.expected() for spec in self.specs)

    def coerce(self, value: Any) -> Any:
        inner = None  # a value shaped as one spec wants, one of whose items that spec refused
        for spec in self.specs:
            try:
                return spec.coerce(value)
            except _Refused as refusal:
                inner = inner or (refusal if refusal.at else None)
        if inner is not None:
            raise inner
        raise _Refused(_found(value), self.expected())

    def parse(self, text: str) -> Any:
        """An argparse ``type=``: ``text`` as the first spec reads it (a :class:`Choice` takes the text
        itself, the others their :meth:`Spec.parse`), else :class:`OptionValueError`."""
        for spec in self.specs:
            try:
                return spec.coerce(text) if isinstance(spec, Choice) else spec.parse(text)
            except (_Refused, OptionValueError):
                continue
        raise OptionValueError(f"found {text!r}, expected {self.expected()}")

    def bad_values(self) -> list:
        def refused(value) -> bool:
            try:
                self.coerce(value)
            except _Refused:
                return True
            return False

        candidates = super().bad_values() + [bad for spec in self.specs for bad in spec.bad_values()]
        return [bad for bad in candidates if (not self.optional if bad is None else refused(bad))]


@dataclass(frozen=True)
class Contract:
    """What :func:`accepts` recorded of one function (the checked function, as callers see it):
    its declared arguments and error class."""

    function: Callable
    specs: dict = field(default_factory=dict)
    error: type[Exception] = ParameterError

    @property
    def name(self) -> str:
        return f"{self.function.__module__}.{self.function.__qualname__}"


#: Every function declared with :func:`accepts`, in import order (read by the refusal tests).
DECLARED: list[Contract] = []


def accepts(*, error: type[Exception] = ParameterError, **specs: Spec) -> Callable:
    """Declare the contracts of a function's arguments (module docstring).

    The arguments given are checked in declaration order against their specs and replaced by
    the coerced values; an argument left at its default is not checked (defaults are trusted).
    Checking happens before the call binds all arguments, so a bad value is named even when
    other arguments are missing.
    """

    def decorate(function: Callable) -> Callable:
        signature = inspect.signature(function)
        unknown = set(specs) - set(signature.parameters)
        if unknown:
            raise TypeError(f"accepts: {function.__qualname__} has no argument {sorted(unknown)}")

        positional = [parameter.name for parameter in signature.parameters.values()
                      if parameter.kind in (parameter.POSITIONAL_ONLY, parameter.POSITIONAL_OR_KEYWORD)]
        checks = [(name, spec, positional.index(name) if name in positional else None) for name, spec in specs.items()]
        first = min((index for _, _, index in checks if index is not None), default=len(positional))

        @functools.wraps(function)
        def checked(*args, **kwargs):
            if len(args) > first:  # a declared argument given by position
                args = list(args)
            for name, spec, index in checks:
                if index is not None and index < len(args):
                    args[index] = spec.check(args[index], name, error)
                elif name in kwargs:
                    kwargs[name] = spec.check(kwargs[name], name, error)
            return function(*args, **kwargs)

        contract = Contract(checked, dict(specs), error)
        checked.contract = contract
        DECLARED.append(contract)
        return checked

    return decorate


def unchecked(function: Callable) -> Callable:
    """The body of a function declared with :func:`accepts`, without its checks: for a public
    function that has checked the same arguments itself and calls another (inner layers trust
    the boundary)."""
    return function.__wrapped__


# ---------------------------------------------------------------- contents of JSON objects

@dataclass(frozen=True)
class Field:
    """One key of a data-file object: its name, its contract (a :class:`idkit.checks.Spec`
    stating kind, unit, range and meaning) and whether the object must hold it."""

    name: str
    spec: Spec
    required: bool = False


def field_names(fields: Sequence[Field]) -> tuple[str, ...]:
    """The keys a table declares, in declaration order."""
    return tuple(item.name for item in fields)


def check_fields(values: Mapping, fields: Sequence[Field], where: str, *, known: Sequence[str] = (),
                 error: type[Exception] = DataError) -> dict:
    """The values of ``fields`` found in ``values``, each checked and coerced by its spec.

    A key neither declared nor in ``known`` (keys another table checks) is refused, naming the
    keys expected; a required key that is absent is refused; a value is refused as
    ``<where>: <key>: found X, expected Y`` (``<key>: ...`` when ``where`` is empty). Keys absent
    and not required are left out of the result (the reader's default applies).
    """
    names = field_names(fields)
    unknown = sorted(set(values) - set(names) - set(known))
    if unknown:
        raise error(f"{where}: unknown key(s) {', '.join(map(str, unknown))}; expected keys from "
                    f"{', '.join(sorted({*names, *known}))}")
    missing = [item.name for item in fields if item.required and item.name not in values]
    if missing:
        raise error(f"{where}: required key '{missing[0]}' missing")
    prefix = f"{where}: " if where else ""
    return {item.name: item.spec.check(values[item.name], prefix + item.name, error)
            for item in fields if item.name in values}
