"""Figures of continuation branches: stable parts solid, unstable parts dashed, special points marked.

Compute first (:mod:`idkit.responses.continuation`), plot second: the function takes ``ax``
(default: a new figure), returns the Axes it drew on and never calls ``show``; matplotlib is
imported lazily.
"""

from __future__ import annotations

import numpy as np
from idkit.plot._figure import axes_or_new

__all__ = ["plot_branch"]

_MARKERS = {"fold": ("o", "fold"), "period doubling": ("D", "period doubling")}


def _branch_values(branch, quantity):
    if quantity in ("ratio", "half_range"):
        return branch.amplitude_ratio, "peak-peak/2 $x_m/x_b$ [-]"
    order = float(quantity)
    name = "1/2 subharmonic" if order == 0.5 else f"harmonic {order:g}"
    return np.abs(branch.hosidf(order)), f"|H| {name} [-]"


def _map_values(hmap, quantity):
    if quantity in ("ratio", "half_range"):
        return hmap.amplitude_ratio
    return hmap.magnitude(float(quantity))


def plot_branch(branch, quantity="ratio", *, hmap=None, ax=None, color=None, label=None):
    """Draw a :class:`~idkit.responses.continuation.Branch` against its continuation parameter.

    Parameters
    ----------
    branch : Branch
    quantity : "ratio" or float
        "ratio" (peak-peak/2 of the top mass over the base amplitude, as the maps) or a HOSIDF
        order (0.5, 1, 2, ...), magnitude.
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
    ax = axes_or_new(ax, figsize=(6.4, 4.4))
    values, ylabel = _branch_values(branch, quantity)
    x = branch.values
    if hmap is not None:
        grid = _map_values(hmap, quantity)
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
        if quantity in ("ratio", "half_range"):
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
