"""Starting point of the Iwan fit read off the loops (SPEC 4).

:func:`iwan_start` turns the loops into a first model without any optimisation: the
stuck stiffness from the branches just after the reversals, the loop height and the
parallel spring from the largest loop, the Jenkin elements from the Masing branches of
the small loops (:func:`_slip_distribution`, non-negative least squares on a grid of
slip travels). The Bouc-Wen fit starts from the same numbers.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import scipy.optimize

from idkit.checks import Whole, accepts
from idkit.errors import FitError
from idkit.fit.result import IwanStart
from idkit.models import IwanModel
from idkit.observe.quasi_static import LoopSet

__all__ = ["iwan_start", "smallest_branch_secant"]


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


@accepts(order=Whole(ge=1, meaning="Jenkin elements"), error=FitError)
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


def smallest_branch_secant(sets: Sequence[LoopSet]) -> float:
    """Tip-to-tip secant stiffness (N/m) of the shortest branch between two reversals.

    The data's own reading of the stuck stiffness ``g1 + sum k_i`` (no element slips on
    the shortest branch when it is short enough); :func:`idkit.fit.iwan_order_table`
    tabulates it beside each order's.

    Parameters
    ----------
    sets : sequence of LoopSet

    Returns
    -------
    float
    """
    branches = [(total, float(change[-1]) / total) for loop_set in sets
                for _, change, total in _branches(loop_set) if total > 0]
    return min(branches)[1]
