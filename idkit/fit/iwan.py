"""Three-stage identification of the modified Iwan model from quasi-static loops.

SPEC section 4 / thesis section 7.1. Deflection (m) is the input, force (N) the
output. Each data set is resampled to a fixed number of points and scored by the
relative RMS force error (7.1)::

    e = sqrt(sum (F_model - F_meas)^2 / sum F_meas^2)

and a stage minimises the mean of ``e`` over its sets with Nelder-Mead (nlopt
``LN_NELDERMEAD``, or scipy's ``Nelder-Mead`` as the second backend):

1. small loops: ``g1, k_i, fc_i`` free, ``g2 = g3 = 0``;
2. large loops: all parameters free, started from stage 1;
3. all loops: ``g1, g2, g3`` fixed at stage 2, ``k_i, fc_i`` refined.

Stage 3 departs from SPEC 4 (which refines on the small loops only): an element
whose slip travel ``2 fc_i / k_i`` exceeds the small loops never slips in them, so
their error is flat in its ``fc_i`` (to 9 digits from 12.5 to 100 N in one case) and
the simplex wandered along that direction, decided by rounding: the final model was
up to 80x worse on the large loops than stage 2's and differed between CPUs. Scored
on all loops every local parameter is seen by some data; on loops of a known model
the slip force comes back to 0.1 % instead of 5-20 % (docs/fitting.md).

**Element order.** Jenkin elements are exchangeable (swapping two leaves the force
law unchanged), so after every stage they are sorted by slip travel ``fc_i / k_i``,
shortest first: equal elements cannot come back in an order decided by rounding.

**Search box and honesty.** Every parameter is searched inside a box set by the
data (:data:`STIFFNESS_BOX` x the stuck stiffness, :data:`FRICTION_BOX` x the
largest force, :data:`POLYNOMIAL_BOX` for ``g2``, ``g3``), so nothing overflows. A
final parameter on the box, a stage stopped at the evaluation limit, or an element
that never slips within the data (its slip force undetermined) makes
``success=False`` with the reason in ``result.reasons``.

**Positivity.** ``g1``, ``k_i`` and ``fc_i`` are optimised as their natural
logarithms, so every stiffness and slip force stays strictly positive however
the simplex moves (the thesis could not enforce this). ``g2`` and ``g3`` are
signed and optimised as ``g2 * x_ref / g1_ref`` and ``g3 * x_ref**2 / g1_ref``
(``x_ref`` the largest |deflection| of the large sets, ``g1_ref`` the stage-1
``g1``), i.e. as their share of the linear force at the largest deflection.

**Initial element state.** A resampled set starts at a reversal, where the
element forces depend on the earlier history. Every element is taken unloaded at
zero deflection and loaded to the first point of the set (``"virgin"``): exact
when the record itself starts unloaded, since it reaches its first reversal
without reversing. With ``"cycled"`` the model is then run once over the whole
set and back to its first point, and those element forces start the scored run:
the state of steady cycling, right for repeated loops whose record starts
mid-history (elements that never slip keep the offset ``k_i x`` of the loading,
as they physically do). The default ``"auto"`` chooses per set: "virgin" when
the record starts unloaded (:attr:`LoopSet.starts_unloaded`), else "cycled".
Records whose amplitude grows from an unloaded start (SPEC 3) are wrong in the
cycled state: the largest loop's slip state is imposed on the small ones before it.

**Speed.** The objective of all sets of a stage is one compiled (numba) call
running the stop operator without per-point Python work or allocations.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass

import nlopt
import numba
import numpy as np
import pandas as pd
import scipy.optimize

from idkit.signal.cycles import resample_loops, reversal_threshold, split_cycles
from idkit.errors import FitError
from idkit.fit._params import Transform, jacobian_statistics, to_lmfit, to_physical_statistics
from idkit.fit.result import IwanFitResult, IwanFitSettings, IwanStart, StageResult
from idkit.models import IwanModel

__all__ = ["LoopSet", "prepare_loops", "iwan_start", "iwan_set_errors", "iwan_set_forces", "fit_iwan", "iwan_order_table"]

MIN_POINTS = 20  # per set, after resampling: fewer cannot resolve slip onset and loop height
#: A record "starts unloaded" when its first deflection and force are within this share
#: of their largest magnitudes in the record (an isolator at rest, sensors zeroed).
UNLOADED_FRACTION = 0.02
START_STATES = ("auto", "cycled", "virgin")
_BACKENDS = ("nlopt", "scipy")
_PENALTY = 1e6  # objective returned for non-finite model forces


@dataclass(frozen=True)
class LoopSet:
    """One quasi-static data set ready for fitting (a path starting at a reversal).

    Attributes
    ----------
    deflection : ndarray, shape (n,)
        Deflection path in m (positive = tension).
    force : ndarray, shape (n,)
        Measured force in N.
    reversals : ndarray of int
        Indices of the first point, every reversal and the last point.
    name : str
    starts_unloaded : bool
        The raw record began unloaded (deflection and force within
        :data:`UNLOADED_FRACTION` of their peaks) and reached the first point of the
        set without a reversal: the "virgin" start state is then exact.
    """

    deflection: np.ndarray
    force: np.ndarray
    reversals: np.ndarray
    name: str = ""
    starts_unloaded: bool = False

    @property
    def amplitude(self) -> float:
        """Half the peak-to-peak deflection, m."""
        return 0.5 * float(np.ptp(self.deflection))


def _as_pair(item, index: int, group: str):
    if isinstance(item, LoopSet):
        return item.deflection, item.force, item.name or f"{group}{index}"
    if hasattr(item, "deflection") and hasattr(item, "force"):
        return item.deflection, item.force, getattr(item, "name", "") or f"{group}{index}"
    try:
        deflection, force = item
    except (TypeError, ValueError):
        raise FitError(
            f"{group} set {index}: found {type(item).__name__}, expected a (deflection, force) pair "
            "of arrays or an object with .deflection and .force"
        ) from None
    return deflection, force, f"{group}{index}"


def _check_record(values, what: str) -> np.ndarray:
    array = np.asarray(values, dtype=float)
    if array.ndim != 1:
        raise FitError(f"{what}: found shape {array.shape}, expected a 1-D array")
    if array.size < MIN_POINTS:
        raise FitError(f"{what}: found {array.size} points, expected at least {MIN_POINTS}")
    bad = np.flatnonzero(~np.isfinite(array))
    if bad.size:
        raise FitError(f"{what}: found {array[bad[0]]} at index {bad[0]}, expected finite values")
    return array


def prepare_loops(
    deflection,
    force,
    *,
    points_per_set: int | None = 200,
    min_excursion: float | None = None,
    name: str = "",
) -> LoopSet:
    """Cut a loop record to its complete branches and resample it to a fixed size.

    Parameters
    ----------
    deflection, force : array_like, shape (n,)
        Record in m and N, at least 20 finite points, with at least two reversals.
    points_per_set : int or None, default 200
        Total points of the resampled set (every branch gets the same count, the
        reversals are kept exactly, :func:`idkit.analysis.resample_loops` with
        equal deflection spacing). ``None`` keeps the record as given after
        cutting it at the first and last reversal.
    min_excursion : float, optional
        Reversal threshold in m; default :func:`idkit.signal.cycles.reversal_threshold`
        (ten times the record's deflection noise, at least 0.1 % of its range), so every
        loop the record holds enters the fit.
    name : str

    Returns
    -------
    LoopSet

    Raises
    ------
    FitError
        Too few or non-finite points, mismatched lengths, fewer than two reversals.
    """
    what = f"set {name!r}" if name else "set"
    x = _check_record(deflection, f"{what} deflection")
    f = _check_record(force, f"{what} force")
    if f.size != x.size:
        raise FitError(f"{what}: found {f.size} force and {x.size} deflection samples, expected equal counts")
    span = float(np.ptp(x))
    if span <= 0:
        raise FitError(f"{what} deflection: found a constant record, expected loops with reversals")
    threshold = reversal_threshold(x) if min_excursion is None else float(min_excursion)
    try:
        split = split_cycles(x, min_excursion=threshold)
    except FitError as error:
        raise FitError(f"{what}: {error}") from None
    if split.branch_start.size == 0:
        raise FitError(
            f"{what} deflection: found {split.reversals.size} reversal, expected at least 2 "
            "(one complete branch between reversals)"
        )
    n_branches = split.branch_start.size
    if points_per_set is None:
        first, last = int(split.reversals[0]), int(split.reversals[-1])
        path_x, path_f = x[first : last + 1], f[first : last + 1]
        reversals = np.concatenate([split.reversals - first])
    else:
        if int(points_per_set) != points_per_set or points_per_set < MIN_POINTS:
            raise FitError(f"points_per_set: found {points_per_set!r}, expected an integer >= {MIN_POINTS}")
        per_branch = max(2, int(math.ceil((points_per_set - 1) / n_branches)) + 1)
        loops = resample_loops(x, f, split=split, points_per_branch=per_branch)
        path_x, path_f = loops.deflection, loops.force
        reversals = np.arange(n_branches + 1) * (per_branch - 1)
    if path_x.size < MIN_POINTS:
        raise FitError(f"{what}: found {path_x.size} points between the first and last reversal, "
                       f"expected at least {MIN_POINTS}")
    if not np.any(path_f):
        raise FitError(f"{what} force: found all zeros, expected a measured force (the error (7.1) divides by it)")
    unloaded = (abs(x[0]) <= UNLOADED_FRACTION * np.max(np.abs(x))
                and abs(f[0]) <= UNLOADED_FRACTION * np.max(np.abs(f)))
    return LoopSet(deflection=np.ascontiguousarray(path_x), force=np.ascontiguousarray(path_f),
                   reversals=reversals.astype(np.intp), name=name, starts_unloaded=bool(unloaded))


# --------------------------------------------------------------------------- compiled objective


@numba.njit(cache=True)
def _stop_step(state, stiffness, friction, step):
    total = 0.0
    for j in range(state.shape[0]):
        trial = state[j] + stiffness[j] * step
        limit = friction[j]
        if trial > limit:
            trial = limit
        elif trial < -limit:
            trial = -limit
        state[j] = trial
        total += trial
    return total


@numba.njit(cache=True)
def _start_state(state, stiffness, friction, x, a, b, cycled):
    """Element forces at the first point of set ``x[a:b]``; returns their sum (N).

    Unloaded at x = 0 and loaded to the first point; if ``cycled``, the set is run
    once and closed back to its first point (module docstring).
    """
    for j in range(state.shape[0]):
        state[j] = 0.0
    _stop_step(state, stiffness, friction, x[a])
    if cycled:
        for i in range(a + 1, b):
            _stop_step(state, stiffness, friction, x[i] - x[i - 1])
        _stop_step(state, stiffness, friction, x[a] - x[b - 1])
    jenkin = 0.0
    for j in range(state.shape[0]):
        jenkin += state[j]
    return jenkin


@numba.njit(cache=True)
def _iwan_set_forces(x, offsets, g1, g2, g3, stiffness, friction, cycled, out):
    """Model force of every set of a concatenated path (``offsets`` delimit the sets;
    ``cycled[s]`` selects the start state of set ``s``)."""
    state = np.empty(stiffness.shape[0])
    for s in range(offsets.shape[0] - 1):
        a = offsets[s]
        b = offsets[s + 1]
        jenkin = _start_state(state, stiffness, friction, x, a, b, cycled[s])
        for i in range(a, b):
            if i > a:
                jenkin = _stop_step(state, stiffness, friction, x[i] - x[i - 1])
            xi = x[i]
            out[i] = xi * (g1 + xi * (g2 + xi * g3)) + jenkin


@numba.njit(cache=True)
def _iwan_set_errors(x, f, offsets, norm2, g1, g2, g3, stiffness, friction, cycled, out):
    """Relative RMS error (7.1) of every set, written to ``out``; no allocation per point."""
    state = np.empty(stiffness.shape[0])
    for s in range(offsets.shape[0] - 1):
        a = offsets[s]
        b = offsets[s + 1]
        jenkin = _start_state(state, stiffness, friction, x, a, b, cycled[s])
        acc = 0.0
        for i in range(a, b):
            if i > a:
                jenkin = _stop_step(state, stiffness, friction, x[i] - x[i - 1])
            xi = x[i]
            diff = xi * (g1 + xi * (g2 + xi * g3)) + jenkin - f[i]
            acc += diff * diff
        out[s] = math.sqrt(acc / norm2[s])


class _Packed:
    """Sets concatenated into flat arrays for the compiled objective."""

    def __init__(self, sets: Sequence[LoopSet], initial_state: str):
        self.names = tuple(s.name for s in sets)
        self.start_states = tuple(_set_start_state(s, initial_state) for s in sets)
        self.cycled = np.array([state == "cycled" for state in self.start_states], dtype=np.bool_)
        self.x = np.ascontiguousarray(np.concatenate([s.deflection for s in sets]))
        self.f = np.ascontiguousarray(np.concatenate([s.force for s in sets]))
        self.offsets = np.concatenate([[0], np.cumsum([s.deflection.size for s in sets])]).astype(np.int64)
        self.norm = np.array([math.sqrt(float(np.sum(s.force**2))) for s in sets])
        self.norm2 = self.norm**2
        self.errors = np.empty(len(sets))

    def set_errors(self, g1, g2, g3, stiffness, friction) -> np.ndarray:
        _iwan_set_errors(self.x, self.f, self.offsets, self.norm2, g1, g2, g3, stiffness, friction,
                         self.cycled, self.errors)
        return self.errors.copy()

    def residuals(self, g1, g2, g3, stiffness, friction) -> np.ndarray:
        """Per-set normalised residuals ``(F_model - F_meas) / |F_meas|_set``."""
        model = np.empty_like(self.x)
        _iwan_set_forces(self.x, self.offsets, g1, g2, g3, stiffness, friction, self.cycled, model)
        scale = np.repeat(self.norm, np.diff(self.offsets))
        return (model - self.f) / scale


def iwan_set_errors(model: IwanModel, sets: Sequence[LoopSet], *, initial_state: str = "auto") -> np.ndarray:
    """Relative RMS error (7.1) of ``model`` on each prepared set (fractions, 0.01 = 1 %).

    Parameters
    ----------
    model : IwanModel
    sets : sequence of LoopSet
        From :func:`prepare_loops`.
    initial_state : {"auto", "cycled", "virgin"}
        Element forces at the first point (module docstring).
    """
    packed = _Packed(list(sets), _check_state(initial_state))
    return packed.set_errors(model.g1, model.g2, model.g3, np.array(model.k, dtype=np.float64),
                             np.array(model.fc, dtype=np.float64))


def iwan_set_forces(model: IwanModel, sets: Sequence[LoopSet], *, initial_state: str = "auto") -> list[np.ndarray]:
    """Model force (N) along each prepared set, with the initial element state used by the fit."""
    packed = _Packed(list(sets), _check_state(initial_state))
    forces = np.empty_like(packed.x)
    _iwan_set_forces(packed.x, packed.offsets, model.g1, model.g2, model.g3, np.array(model.k, dtype=np.float64),
                     np.array(model.fc, dtype=np.float64), packed.cycled, forces)
    return [forces[a:b].copy() for a, b in zip(packed.offsets[:-1], packed.offsets[1:])]


def _check_state(initial_state: str) -> str:
    if initial_state not in START_STATES:
        raise FitError(f"initial_state: found {initial_state!r}, expected one of {START_STATES}")
    return initial_state


def _set_start_state(loop_set: LoopSet, initial_state: str) -> str:
    """``"virgin"`` or ``"cycled"`` for one set; ``"auto"`` reads it off the record's start."""
    if initial_state == "auto":
        return "virgin" if loop_set.starts_unloaded else "cycled"
    return initial_state


# --------------------------------------------------------------------------- automatic start


def _branches(loop_set: LoopSet):
    """(travel u >= 0, force change dF >= 0 in the travel direction, total travel) per branch."""
    for start, stop in zip(loop_set.reversals[:-1], loop_set.reversals[1:]):
        x = loop_set.deflection[start : stop + 1]
        f = loop_set.force[start : stop + 1]
        direction = 1.0 if x[-1] >= x[0] else -1.0
        yield direction * (x - x[0]), direction * (f - f[0]), abs(x[-1] - x[0])


def _initial_slope(sets: Sequence[LoopSet]) -> float:
    """Median stuck slope of the shortest third of all branches (first 10 % of travel)."""
    slopes, travels = [], []
    for loop_set in sets:
        for travel_u, change, total in _branches(loop_set):
            if total <= 0 or travel_u.size < 4:
                continue
            near = travel_u <= 0.1 * total
            near[: min(4, travel_u.size)] = True
            u, df = travel_u[near], change[near]
            denominator = float(np.dot(u, u))
            if denominator > 0:
                slopes.append(float(np.dot(u, df)) / denominator)
                travels.append(total)
    if not slopes:
        raise FitError("loops: found no branch with a measurable initial slope, expected loops with reversals")
    order = np.argsort(travels)
    shortest = np.asarray(slopes)[order[: max(1, len(order) // 3)]]
    return float(np.median(shortest))


def _largest_loop(sets: Sequence[LoopSet]):
    """Deflection range, tip forces, and centre half-height of the largest loop."""
    loop_set = max(sets, key=lambda s: s.amplitude)
    x, f = loop_set.deflection, loop_set.force
    high, low = int(np.argmax(x)), int(np.argmin(x))
    amplitude = 0.5 * (x[high] - x[low])
    centre = 0.5 * (x[high] + x[low])
    secant = (f[high] - f[low]) / (x[high] - x[low])
    rising, falling = [], []
    for start, stop in zip(loop_set.reversals[:-1], loop_set.reversals[1:]):
        xb, fb = x[start : stop + 1], f[start : stop + 1]
        if min(xb[0], xb[-1]) <= centre <= max(xb[0], xb[-1]):
            order = np.argsort(xb, kind="stable")
            value = float(np.interp(centre, xb[order], fb[order]))
            (rising if xb[-1] > xb[0] else falling).append(value)
    if rising and falling:
        half_height = 0.5 * (float(np.mean(rising)) - float(np.mean(falling)))
    else:
        half_height = 0.0
    return loop_set, amplitude, secant, half_height


def _slip_distribution(sets: Sequence[LoopSet], g1: float, order: int, grid_points: int = 40):
    """Jenkin elements from the Masing branches: NNLS on a slip-travel grid, then merged.

    Every branch after a reversal follows ``dF(u) - g1 u = sum_i k_i min(u, d_i)``
    (Masing rule for the Iwan model; ``d_i = 2 fc_i / k_i`` is the travel after which
    element i slips again). With ``d`` fixed on a geometric grid from the smallest
    to the largest travel this is linear in ``k >= 0``: non-negative least squares.
    The (sparse) solution is merged into ``order`` elements by joining the element
    of smallest ``fc`` to its neighbour closest in ``log d`` (summing ``k`` and
    ``fc``; noise creates such small spurious elements) or split (the
    stiffest element into two at ``d / 1.5`` and ``d * 1.5``) until the count fits.
    """
    rows, targets = [], []
    for loop_set in sets:
        for travel_u, change, _ in _branches(loop_set):
            rows.append(travel_u[1:])
            targets.append(change[1:] - g1 * travel_u[1:])
    if not rows:
        return None, None
    u = np.concatenate(rows)
    target = np.concatenate(targets)
    positive = u[u > 0]
    if positive.size < 2 or np.ptp(positive) <= 0:
        return None, None
    grid = np.geomspace(positive.min(), positive.max(), grid_points)
    design = np.minimum(u[:, None], grid[None, :])
    weights = 1.0 / np.maximum(u, positive.min())  # relative fit: short travels count as much as long ones
    try:  # older SciPy caps the active-set iterations at 3 x columns; allow ten times that
        solution, _ = scipy.optimize.nnls(design * weights[:, None], target * weights, maxiter=30 * grid.size)
    except RuntimeError:  # still no convergence: the caller falls back to geometric slip travels
        return None, None
    keep = solution > 1e-9 * max(solution.max(), 1e-300)
    if not np.any(keep):
        return None, None
    stiffness = list(solution[keep])
    friction = list(0.5 * solution[keep] * grid[keep])
    while len(stiffness) > order:
        travel = np.log(2.0 * np.asarray(friction) / np.asarray(stiffness))
        j = int(np.argmin(friction))  # the element contributing least to the loop height ...
        neighbours = [i for i in (j - 1, j + 1) if 0 <= i < len(stiffness)]
        i = min(neighbours, key=lambda i: abs(travel[i] - travel[j]))  # ... joins its nearest neighbour
        low, high = min(i, j), max(i, j)
        stiffness[low : high + 1] = [stiffness[low] + stiffness[high]]
        friction[low : high + 1] = [friction[low] + friction[high]]
    while len(stiffness) < order:
        j = int(np.argmax(stiffness))
        k_half, travel = 0.5 * stiffness[j], 2.0 * friction[j] / stiffness[j]
        stiffness[j : j + 1] = [k_half, k_half]
        friction[j : j + 1] = [0.5 * k_half * travel / 1.5, 0.5 * k_half * travel * 1.5]
    return np.asarray(stiffness), np.asarray(friction)


def iwan_start(small: Sequence[LoopSet], large: Sequence[LoopSet], order: int) -> IwanStart:
    """Starting parameters of an order-``n`` Iwan model read off the loops.

    1. **Stuck stiffness** ``K_s = g1 + sum k_i``: least-squares slope of force
       change against travel over the first 10 % of each branch after a reversal;
       median over the shortest third of all branches (where no element slips yet).
    2. **Loop height**: on the largest loop, half the force difference between the
       loading (upper) and unloading (lower) branch at the centre deflection, ``H ~ sum fc_i``
       (exact when all elements slip there).
    3. **g1**: tip-to-tip secant slope of the largest loop ``(F_max - F_min) /
       (x_max - x_min) = g1 + g3 A^2 + sum fc / A``, minus ``H / A``; kept within
       [1 %, 90 %] of ``K_s`` so that ``sum k_i > 0``.
    4. **Slip onset**: on the branches of the largest loop, the travel ``s_on``
       where the force change first falls 10 % below the stuck line ``K_s u``
       and ``s_full`` where it first reaches 90 % of the fully slipping asymptote
       ``g1 u + 2 H`` (used only by the fallback below).
    5. **Elements**: the small-loop branches after each reversal are Masing
       curves ``dF(u) - g1 u = sum_i k_i min(u, 2 fc_i / k_i)``; a non-negative
       least-squares fit on a grid of slip travels, merged to ``n`` elements
       (:func:`_slip_distribution`), gives ``k_i`` and ``fc_i``. Fallback when no
       branch is usable: ``k_i = (K_s - g1) / n``, slip travels geometric between
       ``s_on`` and ``s_full``, ``fc_i`` scaled to ``sum fc_i = H``.
    """
    if int(order) != order or order < 1:
        raise FitError(f"order: found {order!r}, expected an integer >= 1")
    stuck = _initial_slope(list(small) + list(large))
    loop_set, amplitude, secant, half_height = _largest_loop(large)
    if not (stuck > 0 and math.isfinite(stuck)):
        raise FitError(f"loops: found an initial slope of {stuck:g} N/m, expected a positive stiffness "
                       "(is force in N and deflection in m with tension positive?)")
    if not half_height > 0:
        # no measurable hysteresis at the centre: take 1 % of the tip force as a seed
        half_height = 0.01 * max(abs(loop_set.force).max(), 1e-12)
    g1 = secant - half_height / amplitude
    g1 = min(max(g1, 0.01 * stuck), 0.9 * stuck)
    jenkin = stuck - g1
    effective = 2.0 * half_height / jenkin  # travel where the bilinear asymptotes meet
    onsets, fulls = [], []
    for travel_u, change, total in _branches(loop_set):
        positive = travel_u > 0
        u, df = travel_u[positive], change[positive]
        if u.size == 0:
            continue
        below = np.flatnonzero(df < 0.9 * stuck * u)
        reached = np.flatnonzero(df >= g1 * u + 0.9 * 2.0 * half_height)
        onsets.append(u[below[0]] if below.size else effective)
        fulls.append(u[reached[0]] if reached.size else total)
    slip_onset = float(np.median(onsets)) if onsets else effective
    slip_full = float(np.median(fulls)) if fulls else effective
    slip_onset = min(slip_onset, effective)
    slip_full = max(slip_full, effective)
    k, fc = _slip_distribution(list(small), g1, int(order))
    if k is None:  # no usable branch: spread geometrically between onset and full slip
        k = np.full(int(order), jenkin / order)
        travels = np.geomspace(slip_onset, slip_full, int(order))
        fc = 0.5 * k * travels
        fc *= half_height / fc.sum()
    travels = 2.0 * np.asarray(fc) / np.asarray(k)
    slip_onset, slip_full = float(travels.min()), float(travels.max())
    model = IwanModel(g1=g1, k=k, fc=fc)
    return IwanStart(stuck_stiffness=float(stuck), half_height=float(half_height), g1=float(g1), slip_onset=slip_onset,
                     slip_full=slip_full, model=model)


# --------------------------------------------------------------------------- Nelder-Mead backends


class _Tracked:
    """Objective wrapper counting evaluations and keeping the best point."""

    def __init__(self, function):
        self.function = function
        self.evaluations = 0
        self.best_u = None
        self.best_value = math.inf

    def __call__(self, u, grad=None):
        value = float(self.function(u))
        if not math.isfinite(value):
            value = _PENALTY
        self.evaluations += 1
        if value < self.best_value:
            self.best_value = value
            self.best_u = np.array(u, dtype=float)
        return value


def _nelder_mead_once(tracked: _Tracked, u0, step, bounds, *, backend, max_evals, xtol, ftol) -> str:
    n = u0.size
    lower, upper = bounds
    if backend == "nlopt":
        opt = nlopt.opt(nlopt.LN_NELDERMEAD, n)
        opt.set_min_objective(tracked)
        opt.set_lower_bounds(lower)
        opt.set_upper_bounds(upper)
        opt.set_initial_step(np.full(n, step))
        opt.set_xtol_abs(xtol)
        # no ftol for nlopt: its Nelder-Mead stops on one small improvement of the best
        # vertex, which ended stage 2 far from the optimum in tests; xtol and restarts decide
        opt.set_maxeval(int(max_evals))
        try:
            opt.optimize(np.array(u0, dtype=float))
            code = opt.last_optimize_result()
        except nlopt.RoundoffLimited:
            return "nlopt: roundoff limited"
        names = {nlopt.SUCCESS: "success", nlopt.FTOL_REACHED: "ftol reached",
                 nlopt.XTOL_REACHED: "xtol reached", nlopt.MAXEVAL_REACHED: "max_evals reached"}
        return "nlopt: " + names.get(code, f"code {code}")
    simplex = np.clip(np.vstack([u0, u0 + step * np.eye(n)]), lower, upper)
    result = scipy.optimize.minimize(
        tracked, u0, method="Nelder-Mead", bounds=scipy.optimize.Bounds(lower, upper),
        options={"initial_simplex": simplex, "xatol": xtol, "fatol": ftol, "maxfev": int(max_evals)},
    )
    if result.nfev >= max_evals and not result.success:
        return "scipy: max_evals reached"
    return "scipy: " + ("converged" if result.success else str(result.message))


def _nelder_mead(function, u0, step, bounds, *, backend, max_evals, xtol, ftol, restarts):
    """Bounded Nelder-Mead with restarts from the best point (a fresh simplex escapes stalls)."""
    tracked = _Tracked(function)
    u0 = np.clip(np.asarray(u0, dtype=float), *bounds)
    message = _nelder_mead_once(tracked, u0, step, bounds, backend=backend, max_evals=max_evals,
                                xtol=xtol, ftol=ftol)
    done = 0
    for _ in range(restarts):
        before = tracked.best_value
        remaining = max_evals - tracked.evaluations
        if remaining <= 0 or "max_evals" in message:
            break
        message = _nelder_mead_once(tracked, tracked.best_u, step, bounds, backend=backend,
                                    max_evals=remaining, xtol=xtol, ftol=ftol)
        done += 1
        if before - tracked.best_value <= ftol:
            break
    return tracked.best_u, tracked.best_value, tracked.evaluations, done, message


# --------------------------------------------------------------------------- the three stages


def _prepare_group(sets, group: str, points_per_set) -> list[LoopSet]:
    if sets is None or len(sets) == 0:
        raise FitError(f"{group}: found no data set, expected at least one loop set")
    prepared = []
    for index, item in enumerate(sets):
        if isinstance(item, LoopSet):
            prepared.append(item if item.name else LoopSet(item.deflection, item.force, item.reversals,
                                                           f"{group}{index}"))
            continue
        deflection, force, name = _as_pair(item, index, group)
        prepared.append(prepare_loops(deflection, force, points_per_set=points_per_set, name=name))
    return prepared


_STAGE_FREE = {
    "stage 1": ("g1", "k", "fc"),
    "stage 2": ("g1", "g2", "g3", "k", "fc"),
    "stage 3": ("k", "fc"),
}


def fit_iwan(
    small,
    large,
    *,
    order: int = 2,
    start: IwanModel | None = None,
    backend: str = "nlopt",
    points_per_set: int | None = 200,
    max_evals: int | None = None,
    xtol: float = 1e-7,
    ftol: float = 1e-12,
    restarts: int = 2,
    initial_step: float = 0.3,
    initial_state: str = "auto",
    seed: int = 0,
    valid_range: tuple[float, float] | None = None,
    stage2_starts: int = 1,
) -> IwanFitResult:
    """Identify an order-``n`` modified Iwan model in three Nelder-Mead stages (SPEC 4).

    Parameters
    ----------
    small, large : sequence
        Small-amplitude and large-amplitude loop sets. Each item is a
        :class:`LoopSet` (used as is), a ``(deflection, force)`` pair of arrays
        in m and N, or any object with ``.deflection`` and ``.force`` (e.g.
        :class:`idkit.analysis.ResampledLoops`); raw items are prepared with
        :func:`prepare_loops` (cut at the reversals, resampled to
        ``points_per_set`` points).
    order : int, default 2
        Number of Jenkin elements, >= 1.
    start : IwanModel, optional
        Starting model (its order wins over ``order``); default: :func:`iwan_start`.
    backend : {"nlopt", "scipy"}
        ``nlopt.LN_NELDERMEAD`` or ``scipy.optimize.minimize(method="Nelder-Mead")``,
        both from the same initial simplex ``u0 + initial_step * e_i``.
    points_per_set : int or None, default 200
    max_evals : int, optional
        Evaluation limit per stage (restarts included); default
        ``max(10000, 1500 x free parameters)`` (a simplex needs more steps in more dimensions,
        and crawls along the valid-range barrier).
    xtol, ftol : float
        Absolute tolerances on the internal coordinates (log: relative change of
        the value) and on the mean error (fraction).
    restarts : int, default 2
        Fresh simplices started from the best point after convergence; stops
        early when a restart gains less than ``ftol``.
    initial_step : float, default 0.3
        Simplex edge in internal coordinates (0.3 ~ 35 % change of a log parameter).
    initial_state : {"auto", "cycled", "virgin"}
        Element forces at the first point of a set (module docstring); ``"auto"``
        takes "virgin" for a set whose record starts unloaded, else "cycled".
    seed : int
        Seeds nlopt's generator (Nelder-Mead itself is deterministic); recorded.
    valid_range : (float, float), optional
        Deflections (m, ``x_min < 0 < x_max``) over which the fitted parallel spring must
        keep a non-negative local stiffness ``g1 + 2 g2 x + 3 g3 x^2`` (SPEC 1.2): the
        large-loop stage adds a barrier ``1 + violation / g1`` to the objective wherever it
        turns negative there. Default: no constraint (the thesis's fit).

    stage2_starts : int, default 1
        Starts of stage 2 (all parameters, large loops): the stage-1 result and
        ``stage2_starts - 1`` seeded perturbations of it (:func:`_extra_starts`); the
        end point with the lowest large-loop error is kept (its evaluations count them
        all). Default 1: judged on the large loops alone, an extra start can win by
        over-fitting them (docs/fitting.md).

    Returns
    -------
    IwanFitResult
        ``result.params`` (alias ``result.parameters``) carries standard errors and
        correlations from the covariance ``redchi (J^T J)^-1`` of the per-point residuals
        of all small and large sets at the final parameters, which it does not move
        (:func:`idkit.fit._params.jacobian_statistics`): ``r = (F_model - F_meas) /
        (|F_meas|_set sqrt(e_set))``, each set normalised as the objective (7.1) does and
        weighted by its error at the optimum so that ``chisqr = sum e_set`` and the
        least-squares optimum of ``r`` is the objective's. ``J`` by central differences
        (step 1e-4) in the internal coordinates, mapped by ``stderr(p) = p stderr(log p)``
        (``g2``, ``g3``: linear). ``result.chisqr``, ``redchi``, ``aic``, ``bic``,
        ``fit_report()`` as in lmfit; a parameter without stderr is named with the reason
        in ``result.stderr_notes``. Calibrated on synthetic loops in docs/fitting.md.

    Raises
    ------
    FitError
        Bad sets (too few points, no reversals, NaN), ``order < 1``, unknown backend.

    Examples
    --------
    >>> import numpy as np
    >>> from idkit.models import IwanModel
    >>> truth = IwanModel(g1=3e3, k=[6e3], fc=[10.0])
    >>> x = np.concatenate([a * np.sin(np.linspace(0, 4 * np.pi, 400)) for a in (2e-3, 8e-3)])
    >>> pair = lambda a: (a * x[:400] / 2e-3, truth.force(a * x[:400] / 2e-3))
    >>> result = fit_iwan([pair(1e-3), pair(2e-3)], [pair(8e-3)], order=1)
    >>> bool(result.error_small < 1e-3)
    True
    """
    t0 = time.perf_counter()
    if backend not in _BACKENDS:
        raise FitError(f"backend: found {backend!r}, expected one of {_BACKENDS}")
    if isinstance(stage2_starts, bool) or int(stage2_starts) != stage2_starts or stage2_starts < 1:
        raise FitError(f"stage2_starts: found {stage2_starts!r}, expected an integer >= 1")
    if start is None and (int(order) != order or order < 1):
        raise FitError(f"order: found {order!r}, expected an integer >= 1")
    _check_state(initial_state)
    small_sets = _prepare_group(small, "small", points_per_set)
    large_sets = _prepare_group(large, "large", points_per_set)
    start_info = iwan_start(small_sets, large_sets, order if start is None else start.order)
    model0 = start_info.model if start is None else start
    n = model0.order
    nlopt.srand(int(seed))
    small_packed, large_packed = _Packed(small_sets, initial_state), _Packed(large_sets, initial_state)
    all_packed = _Packed(small_sets + large_sets, initial_state)
    x_ref = max(float(np.max(np.abs(s.deflection))) for s in large_sets)
    if valid_range is not None:
        x_min, x_max = (float(v) for v in valid_range)
        if not (np.isfinite(x_min) and np.isfinite(x_max) and x_min < 0.0 < x_max):
            raise FitError(f"valid_range: found {valid_range!r}, expected (x_min, x_max) in m with x_min < 0 < x_max")

    stiffness_ref = start_info.stuck_stiffness
    force_ref = max(float(np.max(np.abs(s.force))) for s in small_sets + large_sets)
    refs = {"g1": f"{STIFFNESS_BOX} x the stuck stiffness {stiffness_ref:.4g} N/m",
            "k": f"{STIFFNESS_BOX} x the stuck stiffness {stiffness_ref:.4g} N/m",
            "fc": f"{FRICTION_BOX} x the largest |force| {force_ref:.4g} N",
            "g2": f"+-{POLYNOMIAL_BOX:g} x g1 / x_ref", "g3": f"+-{POLYNOMIAL_BOX:g} x g1 / x_ref^2"}

    current = {"g1": model0.g1, "g2": model0.g2, "g3": model0.g3,
               "k": np.array(model0.k, float), "fc": np.array(model0.fc, float)}
    stages, reasons = [], []
    for stage_name, data in (("stage 1", "small"), ("stage 2", "large"), ("stage 3", "all")):
        t_stage = time.perf_counter()
        packed = {"small": small_packed, "large": large_packed, "all": all_packed}[data]
        if stage_name == "stage 1":
            current["g2"] = current["g3"] = 0.0
        g1_ref = current["g1"]
        transforms = _stage_transforms(_STAGE_FREE[stage_name], n, x_ref, g1_ref, stiffness_ref, force_ref)
        bounds = _internal_bounds(transforms)
        stage_evals = max(10000, 1500 * len(transforms)) if max_evals is None else int(max_evals)
        u0 = _to_internal(current, transforms)
        unpack = _make_unpack(current, transforms, n)

        def objective(u, packed=packed, unpack=unpack):
            g1, g2, g3, k, fc = unpack(u)
            _iwan_set_errors(packed.x, packed.f, packed.offsets, packed.norm2, g1, g2, g3, k, fc,
                             packed.cycled, packed.errors)
            error = packed.errors.mean()
            if valid_range is not None:
                lowest = _lowest_spring_stiffness(g1, g2, g3, x_min, x_max)
                if lowest < 0.0:
                    error += 1.0 - lowest / g1
            return error

        start_params = _flat_params(current)
        start_error = objective(np.clip(u0, *bounds))
        best_u, best_value, evaluations, done, message = _nelder_mead(
            objective, u0, initial_step, bounds, backend=backend, max_evals=stage_evals,
            xtol=xtol, ftol=ftol, restarts=restarts)
        if stage_name == "stage 2":  # the global stage: several starts against local minima
            for extra in _extra_starts(u0, bounds, stage2_starts - 1, seed):
                u, value, used, more, note = _nelder_mead(
                    objective, extra, initial_step, bounds, backend=backend, max_evals=stage_evals,
                    xtol=xtol, ftol=ftol, restarts=restarts)
                evaluations += used
                if value < best_value:
                    best_u, best_value, done, message = u, value, more, note
        g1, g2, g3, k, fc = unpack(best_u)
        by_travel = np.argsort(fc / k, kind="stable")  # one order of the exchangeable elements
        current = {"g1": float(g1), "g2": float(g2), "g3": float(g3), "k": k[by_travel], "fc": fc[by_travel]}
        errors = packed.set_errors(g1, g2, g3, k, fc)
        if "max_evals" in message:
            reasons.append(f"{stage_name} stopped at the evaluation limit max_evals={stage_evals}")
        if stage_name != "stage 1":  # stage 1 only starts stage 2; its bounds are the final stages' too
            reasons.extend(f"{stage_name}: {r}" for r in _bound_reasons(transforms, _to_internal(current, transforms),
                                                                       refs))
        stages.append(StageResult(
            name=stage_name, data=data, free=tuple(t.name for t in transforms), start=start_params,
            params=_flat_params(current), set_names=packed.names, set_errors=errors,
            mean_error=float(errors.mean()), start_error=float(start_error), evaluations=evaluations,
            restarts=done, message=message, elapsed_s=time.perf_counter() - t_stage))
    elapsed = time.perf_counter() - t0
    travel = max(float(np.ptp(s.deflection)) for s in small_sets + large_sets)
    for i, (k_i, fc_i) in enumerate(zip(current["k"], current["fc"]), start=1):
        if 2.0 * fc_i / k_i > travel:
            reasons.append(f"fc_{i} is not determined: element {i} never slips within the data (slip travel "
                           f"2 fc/k = {1e3 * 2.0 * fc_i / k_i:.4g} mm > largest loop travel {1e3 * travel:.4g} mm)")

    model = IwanModel(g1=current["g1"], g2=current["g2"], g3=current["g3"], k=current["k"], fc=current["fc"])
    low = min(float(np.min(s.deflection)) for s in small_sets + large_sets)
    high = max(float(np.max(s.deflection)) for s in small_sets + large_sets)
    lower, upper = model.valid_deflection_range()
    if not (lower <= low and high <= upper):
        reasons.append(f"the fitted spring turns negative-stiff at {1e3 * lower:.4g} / {1e3 * upper:.4g} mm, inside "
                       f"the loops' own deflections ({1e3 * low:.4g} to {1e3 * high:.4g} mm): the model cannot be "
                       "simulated over its data")
    parameters, statistics = _iwan_lmfit(model, small_packed, large_packed, x_ref, stiffness_ref, force_ref)
    settings = IwanFitSettings(order=n, backend=backend, points_per_set=points_per_set, max_evals=max_evals,
                               xtol=xtol, ftol=ftol, restarts=restarts, initial_step=initial_step,
                               initial_state=initial_state, seed=int(seed),
                               valid_range=None if valid_range is None else (x_min, x_max),
                               stage2_starts=int(stage2_starts))
    args = (model.g1, model.g2, model.g3, np.array(model.k, dtype=np.float64), np.array(model.fc, dtype=np.float64))
    return IwanFitResult(
        model=model, stages=tuple(stages),
        small_errors=small_packed.set_errors(*args), large_errors=large_packed.set_errors(*args),
        small_names=small_packed.names, large_names=large_packed.names, start=start_info,
        settings=settings, parameters=parameters, elapsed_s=elapsed, reasons=tuple(dict.fromkeys(reasons)),
        start_states=dict(zip(all_packed.names, all_packed.start_states)), statistics=statistics)


def _extra_starts(u0: np.ndarray, bounds, count: int, seed: int) -> list[np.ndarray]:
    """``count`` seeded starts around ``u0``: each coordinate moved by N(0, 0.5) in the
    internal coordinates (a log parameter by a factor e^0.5 = 1.6 typically; g2, g3 by half
    their share of the linear force), clipped into the search box."""
    rng = np.random.default_rng([int(seed), 2])
    return [np.clip(u0 + rng.normal(0.0, 0.5, u0.size), *bounds) for _ in range(max(0, int(count)))]


def _lowest_spring_stiffness(g1: float, g2: float, g3: float, x_min: float, x_max: float) -> float:
    """Minimum of ``g1 + 2 g2 x + 3 g3 x^2`` (N/m) over ``[x_min, x_max]``."""
    candidates = [x_min, x_max]
    if g3 > 0.0:
        vertex = -g2 / (3.0 * g3)
        if x_min < vertex < x_max:
            candidates.append(vertex)
    return min(g1 + x * (2.0 * g2 + 3.0 * g3 * x) for x in candidates)


# Search box of every parameter, relative to scales read off the data (see fit_iwan):
STIFFNESS_BOX = (1e-6, 1e2)  # g1, k_i: x the stuck stiffness of the loops (N/m)
FRICTION_BOX = (1e-6, 1e1)  # fc_i: x the largest |force| of the loops (N)
POLYNOMIAL_BOX = 1e3  # |g2 x_ref| and |g3 x_ref^2|: x the stage-1 linear force g1 x_ref
_AT_BOUND = 1e-3  # internal distance below which a parameter counts as sitting on its bound


def _stage_transforms(free: tuple[str, ...], n: int, x_ref: float, g1_ref: float,
                      stiffness_ref: float, force_ref: float) -> list[Transform]:
    k_low, k_high = (b * stiffness_ref for b in STIFFNESS_BOX)
    f_low, f_high = (b * force_ref for b in FRICTION_BOX)
    g2_scale, g3_scale = g1_ref / x_ref, g1_ref / x_ref**2
    transforms = []
    for group in free:
        if group == "g1":
            transforms.append(Transform("g1", "N/m", "log", k_low, k_high))
        elif group == "g2":
            bound = POLYNOMIAL_BOX * g2_scale
            transforms.append(Transform("g2", "N/m^2", "scaled", -bound, bound, scale=g2_scale))
        elif group == "g3":
            bound = POLYNOMIAL_BOX * g3_scale
            transforms.append(Transform("g3", "N/m^3", "scaled", -bound, bound, scale=g3_scale))
        elif group == "k":
            transforms.extend(Transform(f"k_{i}", "N/m", "log", k_low, k_high) for i in range(1, n + 1))
        else:
            transforms.extend(Transform(f"fc_{i}", "N", "log", f_low, f_high) for i in range(1, n + 1))
    return transforms


def _internal_bounds(transforms: list[Transform]) -> tuple[np.ndarray, np.ndarray]:
    lower = np.array([float(t.to_internal(t.lower)) for t in transforms])
    upper = np.array([float(t.to_internal(t.upper)) for t in transforms])
    return lower, upper


def _bound_reasons(transforms: list[Transform], u: np.ndarray, refs: dict) -> list[str]:
    """One sentence per parameter sitting on its search bound at internal point ``u``."""
    reasons = []
    lower, upper = _internal_bounds(transforms)
    for t, value, low, high in zip(transforms, u, lower, upper):
        for side, bound in (("lower", low), ("upper", high)):
            if abs(value - bound) <= _AT_BOUND * max(1.0, abs(bound)):
                reasons.append(
                    f"{t.name} = {float(t.to_physical(value)):.4g} {t.unit} sits at its {side} search bound "
                    f"({refs[t.name.split('_')[0]]}): the loops do not determine it")
    return reasons


def _to_internal(current: dict, transforms: list[Transform]) -> np.ndarray:
    values = []
    for t in transforms:
        if "_" in t.name:
            group, index = t.name.split("_")
            values.append(current[group][int(index) - 1])
        else:
            values.append(current[t.name])
    return np.array([float(t.to_internal(v)) for t, v in zip(transforms, values)])


def _make_unpack(current: dict, transforms: list[Transform], n: int):
    """Fast internal -> (g1, g2, g3, k, fc) for one stage (fixed values from ``current``)."""
    names = [t.name for t in transforms]
    log_mask = np.array([t.kind == "log" for t in transforms])
    scales = np.array([t.scale for t in transforms])
    index = {name: i for i, name in enumerate(names)}
    g1_fixed, g2_fixed, g3_fixed = current["g1"], current["g2"], current["g3"]
    k_fixed, fc_fixed = np.array(current["k"], float), np.array(current["fc"], float)
    k_slice = slice(index["k_1"], index["k_1"] + n) if "k_1" in index else None
    fc_slice = slice(index["fc_1"], index["fc_1"] + n) if "fc_1" in index else None

    def unpack(u):
        u = np.asarray(u, dtype=float)
        values = np.where(log_mask, np.exp(np.minimum(u, 700.0)), scales * u)
        g1 = values[index["g1"]] if "g1" in index else g1_fixed
        g2 = values[index["g2"]] if "g2" in index else g2_fixed
        g3 = values[index["g3"]] if "g3" in index else g3_fixed
        k = np.ascontiguousarray(values[k_slice]) if k_slice else k_fixed
        fc = np.ascontiguousarray(values[fc_slice]) if fc_slice else fc_fixed
        return float(g1), float(g2), float(g3), k, fc

    return unpack


def _flat_params(current: dict) -> dict:
    values = {"g1": float(current["g1"]), "g2": float(current["g2"]), "g3": float(current["g3"])}
    values.update({f"k_{i}": float(v) for i, v in enumerate(current["k"], start=1)})
    values.update({f"fc_{i}": float(v) for i, v in enumerate(current["fc"], start=1)})
    return values


def _iwan_lmfit(model: IwanModel, small: _Packed, large: _Packed, x_ref: float, stiffness_ref: float,
                force_ref: float):
    """lmfit view of the final model and its statistics at the optimum (see :func:`fit_iwan`).

    Returns ``(parameters, statistics)``: :class:`lmfit.Parameters` in physical units
    with ``stderr`` and ``correl``, and the :class:`lmfit.minimizer.MinimizerResult` of
    :func:`idkit.fit._params.jacobian_statistics` mapped to them.
    """
    n = model.order
    transforms = _stage_transforms(_STAGE_FREE["stage 2"], n, x_ref, model.g1, stiffness_ref, force_ref)
    current = {"g1": model.g1, "g2": model.g2, "g3": model.g3,
               "k": np.array(model.k, float), "fc": np.array(model.fc, float)}
    u_opt = _to_internal(current, transforms)
    unpack = _make_unpack(current, transforms, n)
    # weights 1 / sqrt(e_s) frozen at the optimum: sum r^2 = sum_s e_s (the stage objective
    # times the number of sets) and its gradient is the objective's, so the least-squares
    # optimum of these residuals is the Nelder-Mead one when the stages reached it
    errors = np.concatenate([small.set_errors(*unpack(u_opt)), large.set_errors(*unpack(u_opt))])
    sizes = np.concatenate([np.diff(small.offsets), np.diff(large.offsets)])
    weights = np.repeat(1.0 / np.sqrt(np.maximum(errors, 1e-300)), sizes)

    def residuals(u):
        args = unpack(u)
        return weights * np.concatenate([small.residuals(*args), large.residuals(*args)])

    names = [t.name for t in transforms]
    internal = jacobian_statistics(residuals, u_opt, names,
                                   method="Jacobian of the per-point residuals at the Nelder-Mead optimum")
    specs = {spec.name: spec for spec in model.param_specs()}
    parameters = to_lmfit(
        names + ["c_visc"], [float(t.to_physical(u)) for t, u in zip(transforms, u_opt)] + [0.0],
        units=[specs[name].unit for name in names] + ["N s/m"],
        lower=[t.lower for t in transforms] + [0.0],
        upper=[t.upper for t in transforms] + [math.inf],
        vary=[True] * len(names) + [False],
    )
    return parameters, to_physical_statistics(internal, transforms, parameters)


# --------------------------------------------------------------------------- order table


def _smallest_branch_secant(sets: Sequence[LoopSet]) -> float:
    """Tip-to-tip secant stiffness (N/m) of the shortest branch between two reversals."""
    branches = [(total, float(change[-1]) / total) for loop_set in sets
                for _, change, total in _branches(loop_set) if total > 0]
    return min(branches)[1]

#: Order rule: the lowest order whose mean loop error (small and large sets weighted
#: equally) is within this factor of the best order's in the table. An element more
#: must earn its two parameters by cutting the error by more than a tenth.
ORDER_RULE_FACTOR = 1.10


def iwan_order_table(small, large, *, orders: Sequence[int] = (1, 2, 3, 4, 5, 6), **options) -> pd.DataFrame:
    """Fit orders ``orders`` on the same loops and tabulate what each identifies (SPEC 4).

    One row per order: ``order``, ``n_params`` (``3 + 2 n``), ``error_small_percent``,
    ``error_large_percent``, ``stuck_stiffness [N/m]`` (``g1 + sum k_i``),
    ``smallest_loop_secant [N/m]`` (tip-to-tip secant of the smallest measured loop, the
    data's own stuck-stiffness reading), ``spring_negative_below [m]`` and
    ``spring_negative_above [m]`` (where ``g1 + 2 g2 x + 3 g3 x^2`` turns negative,
    +-inf if never), ``success``, ``reasons`` and ``recommended`` (the order chosen by
    :data:`ORDER_RULE_FACTOR`). ``options`` go to :func:`fit_iwan`.
    """
    small_sets = _prepare_group(small, "small", options.get("points_per_set", 200))
    large_sets = _prepare_group(large, "large", options.get("points_per_set", 200))
    secant = _smallest_branch_secant(small_sets + large_sets)
    rows = []
    for order in orders:
        result = fit_iwan(small_sets, large_sets, order=int(order), **options)
        below, above = result.model.valid_deflection_range()
        rows.append({"order": int(order), "n_params": 3 + 2 * int(order),
                     "error_small_percent": 100 * result.error_small, "error_large_percent": 100 * result.error_large,
                     "stuck_stiffness [N/m]": float(result.model.stuck_stiffness),
                     "smallest_loop_secant [N/m]": secant,
                     "spring_negative_below [m]": below, "spring_negative_above [m]": above,
                     "success": result.success, "reasons": "; ".join(result.reasons)})
    table = pd.DataFrame(rows)
    mean_error = 0.5 * (table["error_small_percent"] + table["error_large_percent"])
    table["recommended"] = table["order"] == table.loc[mean_error <= ORDER_RULE_FACTOR * mean_error.min(), "order"].min()
    return table
