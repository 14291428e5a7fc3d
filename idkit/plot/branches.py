"""Figures of continuation branches: stable parts solid, unstable parts dashed, special points marked.

Compute first (:mod:`idkit.responses.continuation`), plot second: the function takes ``ax``
(default: a new figure), returns the Axes it drew on and never calls ``show``; matplotlib is
imported lazily.
"""

from __future__ import annotations

import numbers

import numpy as np

from idkit.errors import ParameterError
from idkit.plot._figure import axes_or_new

__all__ = ["HARMONIC_FLOOR", "plot_branch"]

_MARKERS = {"fold": ("o", "fold"), "period doubling": ("D", "period doubling")}

#: A higher harmonic below this fraction of the first is not drawn (log axes): the orbits close to
#: 1e-9 of their state scale (``tolerance``), so harmonics of a linear branch come out at 1e-15 to
#: 1e-9 of the first; 1e-6 keeps a factor 1000 above that round-off (120 dB below the fundamental,
#: beyond any measurement).
HARMONIC_FLOOR = 1e-6


def _order_of(branch, quantity) -> float | None:
    """None for the amplitude ratio, else the checked harmonic order of ``quantity``."""
    if isinstance(quantity, str) and quantity in ("ratio", "half_range"):
        return None
    n_orders = (branch.coefficients.shape[1] - 1) / 2
    step = 1.0 / branch.periods
    expected = (f"'ratio' (or 'half_range') or a harmonic order: a multiple of {step:g} from {step:g} to {n_orders:g} "
                f"(orbits of {branch.periods} period(s); order 0, the bias, is not a HOSIDF)")
    if isinstance(quantity, (bool, np.bool_)) or not isinstance(quantity, numbers.Real):
        raise ParameterError(f"quantity: found {quantity!r}, expected {expected}")
    order = float(quantity)
    if not (np.isfinite(order) and step <= order <= n_orders and abs(order / step - round(order / step)) < 1e-9):
        why = ""
        if np.isfinite(order) and branch.periods == 1 and abs(2 * order - round(2 * order)) < 1e-9 \
                and 0 < order <= n_orders:
            why = "; a period-1 orbit has no half-order harmonics (they are zero up to round-off)"
        raise ParameterError(f"quantity: found {quantity!r}, expected {expected}{why}")
    return order


def _branch_values(branch, order):
    if order is None:
        return branch.amplitude_ratio, "peak-peak/2 $x_m/x_b$ [-]"
    name = "1/2 subharmonic" if order == 0.5 else f"harmonic {order:g}"
    values = np.abs(branch.hosidf(order))
    if order != 1:
        # round-off of the orbit, not a harmonic: left out (a log axis would draw it as a curve)
        floor = HARMONIC_FLOOR * np.abs(branch.hosidf(1))
        values = np.where(values > floor, values, np.nan)
        if not np.any(np.isfinite(values)):
            raise ParameterError(f"quantity: {name} is below {HARMONIC_FLOOR:g} of the first harmonic at every "
                                 f"point of the branch (largest {np.nanmax(np.abs(branch.hosidf(order)) / np.abs(branch.hosidf(1))):.2g} "
                                 "of it): zero up to the orbits' round-off, nothing to draw on a log axis")
    return values, f"|H| {name} [-]"


def _map_values(hmap, order):
    if order is None:
        return hmap.amplitude_ratio
    values = hmap.magnitude(order)
    if order != 1:  # below the map's steady-state tolerance of the first harmonic: unresolved
        values = np.where(values > hmap.tolerance * hmap.magnitude(1), values, np.nan)
    return values


def plot_branch(branch, quantity="ratio", *, hmap=None, ax=None, color=None, label=None):
    """Draw a :class:`~idkit.responses.continuation.Branch` against its continuation parameter.

    Parameters
    ----------
    branch : Branch
    quantity : "ratio" or float
        "ratio" (peak-peak/2 of the top mass over the base amplitude, as the maps) or a HOSIDF
        order, magnitude: 1, 2, ... up to the branch's harmonics (and 0.5, 1.5, ... for a branch of
        period-2 orbits). Anything else raises :class:`~idkit.errors.ParameterError`. Points where
        a higher harmonic is below :data:`HARMONIC_FLOOR` of the first (round-off) are left out,
        and a harmonic below it everywhere is refused; the map's points below its steady-state
        tolerance of the first harmonic are left out too.
    hmap : HarmonicMap, optional
        Time-integration map drawn under the branch as dots: its column at the grid amplitude
        nearest the branch's (frequency branch), or its row at the nearest frequency (amplitude
        branch); only points that settled.
    ax : Axes, optional
    color, label : optional
        Line colour and legend label of the branch.

    Returns
    -------
    Axes
        Stable parts solid, neutral ones (undamped) dotted, unstable parts dashed; folds (circles) and period-doubling points
        (diamonds) at their located parameter value, on log axes.
    """
    order = _order_of(branch, quantity)
    values, ylabel = _branch_values(branch, order)
    ax = axes_or_new(ax, figsize=(6.4, 4.4))
    x = branch.values
    if hmap is not None:
        grid = _map_values(hmap, order)
        if branch.parameter == "freq":
            column = hmap.amplitude_index(float(branch.amplitude[0]))
            ax.plot(hmap.freq, np.where(hmap.valid[:, column], grid[:, column], np.nan), ".", color="0.45",
                    label=f"time integration, {hmap.amplitude[column]:.3g} m")
        else:
            row = int(np.argmin(np.abs(np.log(hmap.freq / branch.freq[0]))))
            ax.plot(hmap.amplitude, np.where(hmap.valid[row], grid[row], np.nan), ".", color="0.45",
                    label=f"time integration, {hmap.freq[row]:.4g} Hz")
    line_color = color
    start = 0
    first = True
    # solid stable, dotted neutral (undamped: attracts nothing), dashed unstable
    kinds = list(getattr(branch, "instability", ()) or ())
    style = ([{"stable": "-", "neutral": ":"}.get(kind, "--") for kind in kinds] if len(kinds) == x.size
             else ["-" if ok else "--" for ok in np.asarray(branch.stable)])
    # one line per run of equal stability; neighbouring runs share their end point
    while start < x.size:
        stop = start
        while stop + 1 < x.size and style[stop + 1] == style[start]:
            stop += 1
        segment = slice(start, min(stop + 2, x.size))
        (line,) = ax.plot(x[segment], values[segment], style[start], color=line_color,
                          label=(label or "periodic branch") if first else None)
        line_color = line.get_color()
        first = False
        start = stop + 1
    for kind, (marker, name) in _MARKERS.items():
        points = branch.points(kind)
        if not points:
            continue
        location = np.array([p.freq if branch.parameter == "freq" else p.amplitude for p in points])
        height = np.interp(location, *_sorted_pairs(x, values)) if branch.n_points > 1 else values[:1]
        if order is None:
            height = np.array([p.half_range / p.amplitude for p in points])
        ax.plot(location, height, marker, color=line_color, markerfacecolor="none", linestyle="none", label=name)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("frequency [Hz]" if branch.parameter == "freq" else "base amplitude [m]")
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    return ax


def _sorted_pairs(x, y):
    order = np.argsort(x, kind="stable")
    return x[order], y[order]
