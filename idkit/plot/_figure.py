"""The one axes helper of :mod:`idkit.plot`: new figures, caller's axes, atomic saving.

Every plot module asks this module for axes, so every figure is built the same way: a
:class:`matplotlib.figure.Figure` created directly (no pyplot, no figure registry, no
backend switch; the backend is the caller's), ``constrained`` layout, and a size that
grows with the number of rows. matplotlib is imported only when a figure is made.
"""

from __future__ import annotations

import io
from pathlib import Path

from idkit.atomic import write_bytes_atomic

__all__ = ["MAX_PER_PANEL", "axes_or_new", "column_grid", "grid_result", "new_axes", "new_figure", "panel_groups",
           "save_figure"]

#: setups (top masses) one panel shows before a figure is split into columns: with a
#: measured and a model curve each, six curves a panel at most
MAX_PER_PANEL = 3

#: width of a default figure, inches
WIDTH_IN = 6.4


def default_size(nrows: int = 1, ncols: int = 1) -> tuple[float, float]:
    """Width and height in inches of a figure of ``nrows`` x ``ncols`` axes (2.2 in per row)."""
    return WIDTH_IN * max(1.0, 0.8 * ncols), 2.4 + 2.2 * nrows


def new_figure(figsize: tuple[float, float] | None = None):
    """An empty :class:`~matplotlib.figure.Figure` with constrained layout (``figsize`` in inches)."""
    from matplotlib.figure import Figure

    return Figure(figsize=figsize or default_size(), layout="constrained")


def new_axes(nrows: int = 1, ncols: int = 1, *, figsize: tuple[float, float] | None = None,
             sharex: bool = False, projection: str | None = None, squeeze: bool = True):
    """Axes of a new figure: one Axes, or an array of them (``squeeze`` as in ``Figure.subplots``).

    Parameters
    ----------
    nrows, ncols : int
        Grid of axes.
    figsize : (float, float), optional
        Inches; default :func:`default_size`.
    sharex : bool
        Share the x axis (Bode pairs, stacked time series).
    projection : str, optional
        ``"3d"`` for a surface (one axes only).
    squeeze : bool
        As :meth:`matplotlib.figure.Figure.subplots`.

    Examples
    --------
    >>> ax = new_axes()
    >>> top, bottom = new_axes(2, sharex=True)
    >>> ax.figure is not top.figure
    True
    """
    figure = new_figure(figsize or default_size(nrows, ncols))
    if projection is not None:
        return figure.add_subplot(1, 1, 1, projection=projection)
    return figure.subplots(nrows, ncols, sharex=sharex, squeeze=squeeze)


def axes_or_new(axes, nrows: int = 1, ncols: int = 1, **options):
    """``axes`` when the caller gave some, else :func:`new_axes` with ``options``."""
    return axes if axes is not None else new_axes(nrows, ncols, **options)


def panel_groups(items, size: int = MAX_PER_PANEL) -> list[list]:
    """``items`` in order, cut into the fewest groups of at most ``size``, as even as possible.

    Examples
    --------
    >>> panel_groups([1, 2, 3, 4, 5, 6, 7, 8])
    [[1, 2, 3], [4, 5, 6], [7, 8]]
    >>> panel_groups([1, 2, 3, 4, 5, 6, 7])
    [[1, 2, 3], [4, 5], [6, 7]]
    """
    items = list(items)
    count = max(1, -(-len(items) // size))
    base, extra = divmod(len(items), count)  # the first ``extra`` groups hold one more
    groups, start = [], 0
    for index in range(count):
        stop = start + base + (1 if index < extra else 0)
        groups.append(items[start:stop])
        start = stop
    return groups


def column_grid(axes, n_columns: int, *, sharex: bool = False, column_width: float = 4.0, height: float = 6.8):
    """A 2 x ``n_columns`` object array of Axes: a new figure's, or the caller's (magnitude, phase)-like pair
    as one column (the caller then draws every group into it)."""
    import numpy as np

    if axes is None:
        return new_axes(2, n_columns, sharex=sharex, squeeze=False,
                        figsize=(max(WIDTH_IN, column_width * n_columns), height))
    return np.asarray(axes, dtype=object).reshape(2, 1)


def finish_bode_grid(grid, *, legend_title: str, magnitude_label: str):
    """Label a 2 x n magnitude / phase grid (legend in every magnitude panel, log grids) and
    return it as :func:`grid_result` does."""
    for column in range(grid.shape[1]):
        magnitude_ax, phase_ax = grid[0, column], grid[1, column]
        phase_ax.set_xlabel("frequency [Hz]")
        magnitude_ax.legend(fontsize="x-small", title=legend_title, title_fontsize="x-small")
        for ax in (magnitude_ax, phase_ax):
            ax.grid(True, which="both", alpha=0.3)
    grid[0, 0].set_ylabel(magnitude_label)
    grid[1, 0].set_ylabel("phase [deg]")
    return grid_result(grid)


def grid_result(grid):
    """The pair ``(grid[0, 0], grid[1, 0])`` for a one-column grid, else the grid itself."""
    return (grid[0, 0], grid[1, 0]) if grid.shape[1] == 1 else grid


def save_figure(figure, path, *, overwrite: bool = True, dpi: int = 110) -> Path:
    """Save a figure atomically (:func:`idkit.atomic.write_bytes_atomic`); the format follows the suffix.

    Returns
    -------
    pathlib.Path
        The written file.
    """
    path = Path(path)
    buffer = io.BytesIO()
    figure.savefig(buffer, format=path.suffix.lstrip(".") or "png", dpi=dpi)
    return write_bytes_atomic(path, buffer.getvalue(), overwrite=overwrite)
