"""Quasi-static hysteresis loops: reversals, cycles, amplitudes, resampling.

The quasi-static tests of SPEC section 3 were driven by hand (a lathe spindle), so the
deflection rate is irregular and the record carries noise and small spikes. This module
turns such a deflection/force record into the pieces the Iwan fitter needs (SPEC section 4,
thesis section 7.1 and eq. (7.1)):

1. :func:`find_reversals` - turning points of the deflection, found with a hysteresis
   (dead-band) threshold so that noise and spikes smaller than ``min_excursion`` never count;
2. :func:`split_cycles` - half-cycles (branches between consecutive reversals) and cycles
   (pairs of consecutive branches) with their amplitude and a small/large classification;
3. :func:`resample_loops` - every branch resampled to the same number of equally spaced
   points, so that each data set enters the objective with a fixed number of points.

Sign convention: deflection ``x = x_top - x_base`` in m, positive = tension.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from idkit.checks import Choice, Real, Reals, Samples, Whole, accepts, unchecked
from idkit.errors import DataError, FitError

__all__ = [
    "CycleSplit",
    "ResampledLoops",
    "classify_amplitudes",
    "find_reversals",
    "noise_level",
    "resample_loops",
    "reversal_threshold",
    "split_cycles",
]

_MIN_POINTS = 3  # a reversal needs at least one sample on either side of it


#: A deflection or force record: 1-D, finite (a record too short for a reversal is a
#: :class:`FitError`, :func:`_reversible`, not a malformed argument).
_DEFLECTION = Samples(unit="m", min_size=0)
_FORCE = Samples(unit="N", min_size=0)


def _reversible(array: NDArray[np.float64], name: str) -> NDArray[np.float64]:
    """``array`` (a checked record) if it is long enough to hold a reversal, else :class:`FitError`."""
    if array.size < _MIN_POINTS:
        raise FitError(
            f"{name} has {array.size} samples; at least {_MIN_POINTS} are needed to find a reversal"
        )
    return array


@accepts(deflection=_DEFLECTION, min_excursion=Real(unit="m", gt=0), error=DataError)
def find_reversals(deflection: ArrayLike, *, min_excursion: float) -> NDArray[np.intp]:
    """Indices of the turning points (reversals) of a deflection record.

    A hysteresis (dead-band, "zig-zag") detector: the running extreme in the current
    direction of travel is tracked, and it is confirmed as a reversal only once the
    deflection has moved back from it by **more than** ``min_excursion``. Noise, spikes and
    hesitations of the hand-driven spindle smaller than ``min_excursion`` therefore never
    create a reversal, and a spike cannot become a turning point unless it is followed by a
    genuine return of more than ``min_excursion``. The initial direction is the one in which
    the record first leaves its starting value by more than ``min_excursion``. The first and
    last samples are not reversals.

    Parameters
    ----------
    deflection : array_like, shape (n,)
        Deflection record in m (positive = tension).
    min_excursion : float
        Hysteresis threshold in m, > 0. Choose it above the peak-to-peak noise (a few times
        the noise standard deviation) and below the smallest loop amplitude of interest.

    Returns
    -------
    ndarray of int, shape (n_reversals,)
        Sample indices of the reversals, increasing; maxima and minima alternate.

    Raises
    ------
    FitError
        If the record has fewer than 3 samples or no reversal is found.
    DataError
        If ``min_excursion`` is not positive or the record is not finite.

    Examples
    --------
    >>> import numpy as np
    >>> x = 1e-3 * np.sin(np.linspace(0, 4 * np.pi, 401))
    >>> find_reversals(x, min_excursion=1e-5).tolist()
    [50, 150, 250, 350]
    """
    x = _reversible(deflection, "deflection")
    reversals: list[int] = []
    # Direction: first departure from the start by more than the threshold.
    departed = np.flatnonzero(np.abs(x - x[0]) > min_excursion)
    if departed.size == 0:
        raise FitError(
            f"deflection never moves more than min_excursion={min_excursion:g} m from its start; "
            "no reversal found"
        )
    first = int(departed[0])
    # The extreme before the first departure may itself be the first turning point (the
    # record can start moving the "wrong" way by less than the threshold); start tracking
    # from the start of the record so that case is handled by the same rule.
    direction = 1 if x[first] > x[0] else -1
    extreme_index = int(np.argmax(x[: first + 1]) if direction > 0 else np.argmin(x[: first + 1]))
    extreme = x[extreme_index]
    # A Python loop over samples: O(n) with a tiny body; quasi-static records are 1e4-1e5
    # samples, for which this takes milliseconds. A vectorised form needs the same state.
    for index in range(first + 1, x.size):
        value = x[index]
        if direction > 0:
            if value > extreme:
                extreme, extreme_index = value, index
            elif extreme - value > min_excursion:
                reversals.append(extreme_index)
                direction, extreme, extreme_index = -1, value, index
        else:
            if value < extreme:
                extreme, extreme_index = value, index
            elif value - extreme > min_excursion:
                reversals.append(extreme_index)
                direction, extreme, extreme_index = 1, value, index
    if not reversals:
        raise FitError(
            "no reversal found in deflection: the record never moves back by more than "
            f"min_excursion={min_excursion:g} m after a turning point"
        )
    return np.asarray(reversals, dtype=np.intp)


@accepts(amplitude=Reals(unit="m", min_size=0), threshold=Real(unit="m", ge=0), error=DataError)
def classify_amplitudes(amplitude: ArrayLike, *, threshold: float) -> NDArray[np.bool_]:
    """Classify cycle amplitudes as large (``True``) or small (``False``).

    Parameters
    ----------
    amplitude : array_like
        Cycle amplitudes in m (half the peak-to-peak deflection of each cycle).
    threshold : float
        Threshold amplitude in m; an amplitude strictly above it is "large". The wire-rope
        tests of SPEC section 3 overlap (small loops 0.05-4.5 mm, large 1-15 mm), so the
        threshold is the user's choice, e.g. 4.5e-3 m.

    Returns
    -------
    ndarray of bool
        ``True`` where the amplitude exceeds ``threshold``.
    """
    return amplitude > threshold


@dataclass(frozen=True)
class CycleSplit:
    """Reversals, half-cycles and cycles of one deflection record.

    Branches (half-cycles) run between consecutive reversals, both ends included, so only
    complete branches are kept: the partial segment before the first reversal and after the
    last one are dropped (their index ranges are ``[0, reversals[0]]`` and
    ``[reversals[-1], n - 1]``). A cycle is a pair of consecutive branches ``(2 j, 2 j + 1)``;
    an odd final branch belongs to no cycle.

    Attributes
    ----------
    reversals : ndarray of int, shape (n_reversals,)
        Sample indices of the reversals.
    branch_start, branch_stop : ndarray of int, shape (n_branches,)
        First and last sample index (inclusive) of each branch; ``n_branches = n_reversals - 1``.
    branch_direction : ndarray of int, shape (n_branches,)
        +1 where the deflection increases along the branch (towards tension), -1 otherwise.
    cycle_start, cycle_stop : ndarray of int, shape (n_cycles,)
        First and last sample index (inclusive) of each cycle.
    amplitude : ndarray, shape (n_cycles,)
        Half the peak-to-peak deflection of each cycle, m.
    center : ndarray, shape (n_cycles,)
        Mid-range deflection ``(max + min) / 2`` of each cycle, m.
    is_large : ndarray of bool, shape (n_cycles,)
        Classification by ``large_threshold`` (all ``False`` when no threshold was given).
    large_threshold : float or None
        Threshold amplitude used for ``is_large``, m.
    min_excursion : float
        Hysteresis threshold used to find the reversals, m.
    """

    reversals: NDArray[np.intp]
    branch_start: NDArray[np.intp]
    branch_stop: NDArray[np.intp]
    branch_direction: NDArray[np.int8]
    cycle_start: NDArray[np.intp]
    cycle_stop: NDArray[np.intp]
    amplitude: NDArray[np.float64]
    center: NDArray[np.float64]
    is_large: NDArray[np.bool_]
    large_threshold: float | None
    min_excursion: float

    @property
    def n_cycles(self) -> int:
        """Number of complete cycles."""
        return int(self.amplitude.size)

    def to_dataframe(self) -> pd.DataFrame:
        """One row per cycle: start/stop index, amplitude (m), center (m), is_large."""
        return pd.DataFrame(
            {
                "cycle_start": self.cycle_start,
                "cycle_stop": self.cycle_stop,
                "amplitude [m]": self.amplitude,
                "center [m]": self.center,
                "is_large": self.is_large,
            }
        )


@accepts(signal=Samples(min_size=3), error=DataError)
def noise_level(signal) -> float:
    """Robust estimate of the white-noise standard deviation of a smooth record.

    ``1.4826 * median(|d2 - median(d2)|) / sqrt(6)`` with ``d2`` the second differences:
    for white noise of standard deviation ``s`` the second difference has variance
    ``6 s^2``, while a signal that is smooth on the sample scale contributes little, and the
    median ignores the few samples at reversals, jerks or impacts.

    Parameters
    ----------
    signal : array_like
        Uniformly sampled record (any unit).

    Returns
    -------
    float
        Noise standard deviation, unit of the signal.

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> round(noise_level(np.linspace(0, 1, 20000) + 0.01 * rng.standard_normal(20000)), 3)
    0.01
    """
    second = np.diff(signal, 2)
    return float(1.4826 * np.median(np.abs(second - np.median(second))) / np.sqrt(6.0))


REVERSAL_NOISE_FACTOR = 10.0  # a reversal must exceed 10 noise standard deviations ...
REVERSAL_RANGE_FRACTION = 1e-3  # ... and a thousandth of the record's deflection range


def reversal_threshold(deflection) -> float:
    """Hysteresis threshold (m) of reversal detection in a loop record: noise, not amplitude.

    ``max(10 noise_level(x), 1e-3 ptp(x))``: a turn of the deflection counts as a
    reversal when it exceeds ten times the record's own noise (so noise never makes
    one; the chance of a 10-sigma excursion is nil), and a thousandth of the range (a
    floor for noise-free synthetic records). Every loop the rig really made, down to
    the smallest amplitude, is kept: a threshold tied to the amplitude (2 % of the
    range) dropped the 0.05-0.1 mm loops of records reaching 4.5 mm.
    """
    x = np.asarray(deflection, dtype=float)
    return max(REVERSAL_NOISE_FACTOR * noise_level(x), REVERSAL_RANGE_FRACTION * float(np.ptp(x)))


@accepts(deflection=_DEFLECTION, min_excursion=Real(unit="m", gt=0),
         large_threshold=Real(unit="m", ge=0, optional=True), error=DataError)
def split_cycles(
    deflection: ArrayLike,
    *,
    min_excursion: float,
    large_threshold: float | None = None,
) -> CycleSplit:
    """Split a deflection record into half-cycles and cycles and measure their amplitude.

    Parameters
    ----------
    deflection : array_like, shape (n,)
        Deflection record in m (positive = tension).
    min_excursion : float
        Hysteresis threshold of :func:`find_reversals`, m.
    large_threshold : float, optional
        Amplitude in m above which a cycle is "large" (:func:`classify_amplitudes`).

    Returns
    -------
    CycleSplit
        Reversals, branches and cycles; see the class for the conventions.

    Raises
    ------
    FitError
        If fewer than 3 samples are given or no reversal is found.

    Examples
    --------
    >>> import numpy as np
    >>> x = 2e-3 * np.sin(np.linspace(0, 6 * np.pi, 601))
    >>> split = split_cycles(x, min_excursion=1e-4)
    >>> split.n_cycles, round(float(split.amplitude[0]), 6)
    (2, 0.002)
    """
    x = _reversible(deflection, "deflection")
    reversals = unchecked(find_reversals)(x, min_excursion=min_excursion)
    branch_start = reversals[:-1]
    branch_stop = reversals[1:]
    branch_direction = np.sign(x[branch_stop] - x[branch_start]).astype(np.int8)
    n_cycles = branch_start.size // 2
    cycle_start = branch_start[0 : 2 * n_cycles : 2]
    cycle_stop = branch_stop[1 : 2 * n_cycles : 2]
    # Cycle extremes are its reversals by construction (running extremes of the detector).
    first_turn = x[branch_start[0 : 2 * n_cycles : 2]]
    middle_turn = x[branch_stop[0 : 2 * n_cycles : 2]]
    last_turn = x[cycle_stop]
    high = np.maximum(np.maximum(first_turn, middle_turn), last_turn)
    low = np.minimum(np.minimum(first_turn, middle_turn), last_turn)
    amplitude = 0.5 * (high - low)
    center = 0.5 * (high + low)
    if large_threshold is None:
        is_large = np.zeros(n_cycles, dtype=bool)
    else:
        is_large = unchecked(classify_amplitudes)(amplitude, threshold=large_threshold)
    return CycleSplit(
        reversals=reversals,
        branch_start=branch_start,
        branch_stop=branch_stop,
        branch_direction=branch_direction,
        cycle_start=cycle_start,
        cycle_stop=cycle_stop,
        amplitude=amplitude,
        center=center,
        is_large=is_large,
        large_threshold=large_threshold,
        min_excursion=float(min_excursion),
    )


@dataclass(frozen=True)
class ResampledLoops:
    """A set of loops resampled to a fixed number of points per branch.

    The branches are concatenated into one deflection path (the input of a hysteresis
    model, SPEC section 4) with the shared reversal point stored once, so the path has
    ``n_branches * (points_per_branch - 1) + 1`` points.

    Attributes
    ----------
    deflection : ndarray, shape (n_points,)
        Resampled deflection path, m.
    force : ndarray, shape (n_points,)
        Measured force at the resampled points, N.
    branch : ndarray of int, shape (n_points,)
        Branch number of each point (a reversal point carries the number of the branch it ends).
    source_index : ndarray, shape (n_points,)
        Fractional sample index in the original record of each point.
    points_per_branch : int
        Points per branch, both reversals included.
    spacing : {"deflection", "index"}
        How the points were spaced along each branch.
    """

    deflection: NDArray[np.float64]
    force: NDArray[np.float64]
    branch: NDArray[np.intp]
    source_index: NDArray[np.float64]
    points_per_branch: int
    spacing: str

    def to_dataframe(self) -> pd.DataFrame:
        """One row per point: branch, source_index, deflection_m, force_N."""
        return pd.DataFrame(
            {
                "branch": self.branch,
                "source_index": self.source_index,
                "deflection [m]": self.deflection,
                "force [N]": self.force,
            }
        )


def _branch_positions(
    x_branch: NDArray[np.float64], points: int, spacing: str
) -> NDArray[np.float64]:
    """Fractional positions (sample index within the branch) of the resampled points."""
    last = x_branch.size - 1
    if spacing == "index":
        return np.linspace(0.0, last, points)
    # Equal deflection steps located through the monotone envelope of the branch (running
    # max on a rising branch, running min on a falling one). The envelope is non-decreasing
    # (after a sign flip), so np.interp is valid even when noise makes the raw branch wiggle;
    # where the envelope is flat (a hesitation) the first sample of the plateau is used.
    rising = x_branch[-1] >= x_branch[0]
    envelope = np.maximum.accumulate(x_branch) if rising else -np.minimum.accumulate(x_branch)
    targets = np.linspace(envelope[0], envelope[-1], points)
    upper = np.searchsorted(envelope, targets, side="left")
    upper = np.clip(upper, 1, last)
    lower = upper - 1
    rise = envelope[upper] - envelope[lower]
    with np.errstate(invalid="ignore", divide="ignore"):
        fraction = np.where(rise > 0, (targets - envelope[lower]) / rise, 1.0)
    positions = lower + np.clip(fraction, 0.0, 1.0)
    positions[0], positions[-1] = 0.0, float(last)  # the reversals themselves, exactly
    return positions


@accepts(deflection=_DEFLECTION, force=_FORCE, min_excursion=Real(unit="m", gt=0, optional=True),
         points_per_branch=Whole(ge=2), spacing=Choice(("deflection", "index")), error=DataError)
def resample_loops(
    deflection: ArrayLike,
    force: ArrayLike,
    *,
    min_excursion: float | None = None,
    split: CycleSplit | None = None,
    points_per_branch: int = 100,
    spacing: Literal["deflection", "index"] = "deflection",
) -> ResampledLoops:
    """Resample every complete branch of a loop record to the same number of points.

    The Iwan fitter (SPEC section 4, thesis section 7.1) interpolates each data set to "a
    constant number of equally spaced data points" and evaluates the relative RMS force error
    (7.1) on them, deflection being the input. This function does that per branch (between
    consecutive reversals), which keeps every reversal as a point of the path, so a
    hysteresis model driven by the resampled deflection turns exactly where the measurement
    did.

    Spacing along a branch:

    - ``"deflection"`` (default): the points are equally spaced in deflection between the two
      reversals. The hand-driven rate is irregular, so equal spacing in sample index would
      weight the slow parts of a loop more; equal deflection steps weight the loop uniformly
      along its deflection range. Noise wiggles are handled by locating the target deflections
      on the branch's monotone envelope (running maximum/minimum). Force and deflection are
      interpolated linearly in sample index at the located positions, so the deflection of a
      point equals its target up to the noise within one sample step.
    - ``"index"``: equally spaced in sample index (time for a constant sample rate).

    Parameters
    ----------
    deflection : array_like, shape (n,)
        Deflection record, m (positive = tension).
    force : array_like, shape (n,)
        Force record, N.
    min_excursion : float, optional
        Hysteresis threshold for :func:`split_cycles`, m. Required unless ``split`` is given.
    split : CycleSplit, optional
        A split of this same record (from :func:`split_cycles`), reused instead of recomputed.
    points_per_branch : int, default 100
        Points per branch including both reversals, >= 2.
    spacing : {"deflection", "index"}, default "deflection"
        Where the points sit along each branch (see above).

    Returns
    -------
    ResampledLoops
        The concatenated resampled path.

    Raises
    ------
    FitError
        Too few samples, no reversal, or fewer than one complete branch.
    DataError
        Mismatched lengths, bad options.

    Examples
    --------
    >>> import numpy as np
    >>> x = 1e-3 * np.sin(np.linspace(0, 4 * np.pi, 4001))
    >>> loops = resample_loops(x, 3e3 * x, min_excursion=1e-5, points_per_branch=11)
    >>> loops.deflection.shape
    (31,)
    """
    x = _reversible(deflection, "deflection")
    f = _reversible(force, "force")
    if f.size != x.size:
        raise DataError(f"force has {f.size} samples; expected {x.size} like deflection")
    points = points_per_branch
    if split is None:
        if min_excursion is None:
            raise DataError("give min_excursion (m) or a precomputed split")
        split = unchecked(split_cycles)(x, min_excursion=min_excursion)
    if split.branch_start.size == 0:
        raise FitError(
            f"only {split.reversals.size} reversal found; at least 2 are needed for one "
            "complete branch"
        )
    if split.reversals[-1] >= x.size:
        raise DataError(
            f"split refers to sample {split.reversals[-1]} but the record has {x.size} samples"
        )
    all_positions = []
    all_branches = []
    for number, (start, stop) in enumerate(zip(split.branch_start, split.branch_stop)):
        positions = start + _branch_positions(x[start : stop + 1], points, spacing)
        if number > 0:
            positions = positions[1:]  # shared reversal, already stored
        all_positions.append(positions)
        all_branches.append(np.full(positions.size, number, dtype=np.intp))
    source_index = np.concatenate(all_positions)
    samples = np.arange(x.size)
    return ResampledLoops(
        deflection=np.interp(source_index, samples, x),
        force=np.interp(source_index, samples, f),
        branch=np.concatenate(all_branches),
        source_index=source_index,
        points_per_branch=points,
        spacing=spacing,
    )
