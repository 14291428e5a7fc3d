"""Types and checks of the ``idkit`` command-line numbers: every number is validated at the boundary.

One option, one check, one message. A single value is checked by its argparse ``type=``
callable (:func:`real`, :func:`integer`: the ``parse`` of an :mod:`idkit.checks` spec, the
contract the library functions declare, with the same message); argparse then stops with exit status 2 and
``idkit <command>: error: argument --height: found '-0.05', expected a finite number >= 0 m``.
Checks that need two options at once (a grid's START STOP COUNT and its size, a time
step against a duration, a band's two ends) run at the start of the command, before any
file is read or any work starts, and raise :class:`OptionError`, which ``idkit`` prints
as ``idkit: error: --freq: ...`` with the same exit status 2.

Limits and why (also in docs/cli-reference.md):

* ``--order`` of Iwan and Maxwell fits: 1 to :data:`MAX_ORDER` (12). Each order adds two
  parameters; the bundled loops and the 1-100 Hz FRFs identify no more than a few, and
  the fit time grows with the order (order 100000 never finishes).
* ``--global-evals``: 1 to :data:`MAX_EVALS` (10^7), a budget of hours at most.
* ``--harmonics``: 1 to :data:`MAX_HARMONICS` (32). The harmonic simulator takes at
  least 128 steps per period, which resolve orders up to 64 (Nyquist); 32 keeps a
  factor 2 against aliasing.
* ``--time-step``, ``--tolerance``, ``--max-points``, ``--max-samples``, ``--workers``, ``--seed``
  and every real number's subnormal floor: the size, memory and precision limits of
  :mod:`idkit.limits` (the library's own), each stated there with its reason.
* Grid sizes: ``simulate harmonic`` refuses more than :data:`DEFAULT_MAX_POINTS` (10^6)
  points (``--max-points`` raises it, up to ``limits.MAX_GRID_POINTS``); ``simulate drop``
  refuses more than :data:`DEFAULT_MAX_SAMPLES` (10^7) stored samples, drops x (steps + 1),
  about 80 MB per recorded signal and degree of freedom (``--max-samples`` raises it, up to
  ``limits.MAX_DROP_SAMPLES``). Both are counted from the options before anything is allocated.
* ``fit maxwell --k0``: :data:`MIN_K0` (1e-12 N/m) to :data:`MAX_K0` (1.3e153 N/m): the element
  stiffnesses are searched in 0.1-10 k0; a narrower span is "min == max" to lmfit, a larger one
  overflows when squared.
"""

from __future__ import annotations

import argparse
import math
import re
from dataclasses import dataclass

import numpy as np

from idkit.checks import Real, Whole
from idkit.errors import IdkitError
from idkit.limits import (MAX_DROP_SAMPLES, MAX_GRID_POINTS, MAX_SEED, MAX_STEPS, MAX_WORKERS, MIN_TIME_STEP,
                          MIN_TOLERANCE, SMALLEST_NORMAL)

__all__ = [
    "IdkitArgumentParser", "OptionError", "real", "integer", "Axis", "parse_axis", "check_grid_size",
    "check_band", "check_valid_range", "check_drop", "seed", "workers",
    "MAX_ORDER", "MAX_DMA_ORDER", "MAX_EVALS", "MAX_HARMONICS", "MIN_TOLERANCE", "MIN_TIME_STEP", "MAX_STEPS",
    "DEFAULT_MAX_POINTS", "DEFAULT_MAX_SAMPLES", "MAX_GRID_POINTS", "MAX_DROP_SAMPLES", "MAX_WORKERS", "MAX_SEED", "SMALLEST_NORMAL", "MIN_K0", "MAX_K0",
]

MAX_ORDER = 12
#: Highest Prony order of a DMA table fit (one term a decade of a 40-decade master curve).
MAX_DMA_ORDER = 40
MAX_EVALS = 10**7
MAX_HARMONICS = 32
DEFAULT_MAX_POINTS = 10**6
DEFAULT_MAX_SAMPLES = 10**7
#: ``fit maxwell --k0`` (N/m): the element stiffnesses are searched in 0.1 k0 .. 10 k0 and the order
#: table's Voigt damping in k0 / 1e4 .. k0 / 1 s (idkit.fit.maxwell). The narrower, the damping box,
#: spans 0.9999 k0; at or below lmfit's absolute 1e-13 its Parameter refuses "min == max", so
#: MIN_K0 = 1e-12 keeps every box nine times wider than that; above MAX_K0, 10 k0 squared in
#: lmfit's bound transform overflows float64.
MIN_K0 = 1e-12
MAX_K0 = math.sqrt(np.finfo(np.float64).max) / 10.0


class OptionError(IdkitError, ValueError):
    """Command-line options that are inconsistent together (names the options, values, expectation)."""


class IdkitArgumentParser(argparse.ArgumentParser):
    """``argparse.ArgumentParser`` that takes ``-1e-12``, ``-inf`` and ``-nan`` as values.

    argparse reads an argument starting with ``-`` as a value only when it looks like
    ``-5`` or ``-0.5``; ``--time-step -1e-12`` would stop with "expected one argument",
    which hides the value. No idkit option looks like a number, so every number-like
    argument is a value and reaches its type check (sub-parsers inherit this class).
    """

    _NUMBER = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|infinity|nan)$", re.IGNORECASE)

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = self._NUMBER


def real(*, above=None, at_least=None, below=None, at_most=None, unit: str = "", why: str = ""):
    """argparse ``type=``: a finite float within the given bounds, checked by
    :class:`idkit.checks.Real` (the contract the library declares, with its one message).

    Parameters
    ----------
    above, at_least, below, at_most : float, optional
        Exclusive and inclusive bounds.
    unit : str
        Unit named in the message (``"m"``, ``"Hz"``).
    why : str
        Reason of a bound that is not obvious, appended to the message.

    Examples
    --------
    >>> real(above=0, unit="kg")("2.5")
    2.5
    """
    return Real(unit=unit or "-", gt=above, ge=at_least, lt=below, le=at_most, meaning=why).parse


def integer(*, at_least: int = 1, at_most: int | None = None, why: str = ""):
    """argparse ``type=``: a whole number from ``at_least`` to ``at_most``, checked by
    :class:`idkit.checks.Whole` (a fractional value is refused, never truncated; ``1e6`` is
    taken as 1000000).

    Examples
    --------
    >>> integer(at_most=12)("3")
    3
    """
    return Whole(ge=at_least, le=at_most, meaning=why).parse


seed = integer(at_least=0, at_most=MAX_SEED, why="the range of the numpy and nlopt generators")
workers = integer(at_least=1, at_most=MAX_WORKERS, why="simulation threads")


@dataclass(frozen=True)
class Axis:
    """One axis of a grid, checked but not yet built (its size is known before allocation)."""

    option: str
    values: tuple[float, ...]
    spacing: str | None = None

    @property
    def size(self) -> int:
        return len(self.values) if self.spacing is None else int(self.values[2])

    def build(self) -> np.ndarray:
        if self.spacing is None:
            return np.asarray(self.values, dtype=float)
        start, stop, count = self.values
        if self.spacing == "log":
            return np.logspace(np.log10(start), np.log10(stop), int(count))
        return np.linspace(start, stop, int(count))


def parse_axis(option: str, values, spacing: str | None, *, what: str, unit: str) -> Axis:
    """Check explicit values (``spacing`` None) or ``START STOP COUNT`` of a grid option.

    Values must be finite and > 0 (``what`` in ``unit``, e.g. frequencies in Hz). Explicit
    values are taken as given: their order is kept and a repeated value is computed again.
    START > STOP gives a descending grid; COUNT is a whole number >= 1 (2.5 is refused,
    never truncated). Raises :class:`OptionError` naming ``option``.
    """
    values = tuple(float(v) for v in values)
    if spacing is not None:
        if len(values) != 3:
            raise OptionError(f"{option}: found {len(values)} value(s) ({' '.join(f'{v:g}' for v in values)}) "
                              f"with {option}-spacing {spacing}, expected 3 values: START STOP COUNT")
        start, stop, count = values
        if not (count >= 1 and count == int(count)):
            raise OptionError(f"{option}: COUNT found {count:g}, expected a whole number >= 1 "
                              f"(START STOP COUNT with {option}-spacing {spacing})")
        bounds = (("START", start), ("STOP", stop))
    else:
        bounds = tuple((f"value {i + 1}", v) for i, v in enumerate(values))
    for name, value in bounds:
        if not (math.isfinite(value) and value > 0):
            raise OptionError(f"{option}: {name} found {value:g}, expected finite {what} > 0 {unit}")
    return Axis(option, values, spacing)


def check_grid_size(axes, max_points: int, *, limit_option: str = "--max-points") -> int:
    """Refuse a grid of more than ``max_points`` points, before it is allocated."""
    total = math.prod(axis.size for axis in axes)
    if total > max_points:
        # sizes beyond 10^9 in exponent notation (a huge count has hundreds of digits)
        sizes = " x ".join(f"{axis.size if axis.size < 10**9 else f'{axis.size:.4g}'} ({axis.option})" for axis in axes)
        raise OptionError(f"{' and '.join(a.option for a in axes)}: the grid has {sizes} = {total:.4g} points, "
                          f"expected at most {limit_option} {max_points} " + (
                              f"(raise {limit_option} to run it)" if total <= MAX_GRID_POINTS else
                              f"(beyond the largest {limit_option}, {MAX_GRID_POINTS:.0e}, whose grid "
                              "would not fit in memory)"))
    return total


def check_band(option: str, band, unit: str = "Hz") -> None:
    """A band ``LOW HIGH`` with LOW < HIGH (each end already checked by its type)."""
    low, high = band
    if not low < high:
        raise OptionError(f"{option}: found {low:g} {high:g}, expected LOW < HIGH in {unit}")


def check_valid_range(option: str, bounds) -> None:
    """Deflections ``X_MIN X_MAX`` with X_MIN < 0 < X_MAX."""
    low, high = bounds
    if not low < 0 < high:
        raise OptionError(f"{option}: found {low:g} {high:g}, expected X_MIN < 0 < X_MAX in m")


def check_drop(n_drops: int, duration: float, time_step: float, max_samples: int) -> int:
    """Step count and stored samples of ``simulate drop``, before anything is allocated.

    Returns the number of stored samples ``n_drops * (steps + 1)``.
    """
    if time_step > duration:
        raise OptionError(f"--time-step: found {time_step:g} s with --duration {duration:g} s, "
                          f"expected a step <= the duration")
    steps = duration / time_step
    if steps >= MAX_STEPS:
        raise OptionError(f"--duration {duration:g} s / --time-step {time_step:g} s: found {steps:.4g} steps, "
                          f"expected fewer than {MAX_STEPS:.0e} (the simulator's limit)")
    samples = n_drops * (int(round(steps)) + 1)
    if samples > max_samples:
        raise OptionError(f"--duration {duration:g} s / --time-step {time_step:g} s for {n_drops} drop(s): "
                          f"{samples:.4g} samples to store, expected at most --max-samples {max_samples} "
                          f"(about {8 * samples / 2**20:.0f} MiB per signal and degree of freedom; " + (
                              "raise --max-samples to run it)" if samples <= MAX_DROP_SAMPLES else
                              f"beyond the largest --max-samples, {MAX_DROP_SAMPLES:.0e}, whose records would "
                              "not fit in memory)"))
    return samples


def add_study_options(parser, name: str) -> None:
    """``-o/--output``, ``--force``, ``--quick``, ``--workers``, ``--quiet`` for a study parser."""
    parser.add_argument("-o", "--output", default=f"idkit-study-{name}",
                        help=f"output folder (default: idkit-study-{name})")
    parser.add_argument("--force", action="store_true", help="replace an existing output folder")
    parser.add_argument("--quick", action="store_true", help="small grids (seconds instead of minutes)")
    parser.add_argument("--workers", type=workers, default=None, help="simulation threads (default: all cores)")
    parser.add_argument("--quiet", action="store_true", help="no progress bar")
