"""Figures of ``idkit simulate`` tables: the frequency-amplitude map and the drops.

The command line writes a table (:func:`idkit.studies.harmonic_grid.harmonic_grid_table`,
:meth:`idkit.responses.shock.ShockSweep.to_dataframe`); these figures show what an engineer
reads off it first:

* :func:`plot_harmonic_table_map` - the magnitude of the first harmonic over frequency and
  base amplitude (log colour scale) with the resonance line (the peak of ``|H1|`` at each
  amplitude), and one smaller map per other HOSIDF order (1/2 subharmonic, 2, 3, ...) on
  the colour scale of ``|H1|`` down to :data:`HARMONIC_FLOOR` of its peak, so a harmonic's
  colour says how large it is next to the response;
* :func:`plot_harmonic_table_sections` - ``|H1|`` against frequency, one line per amplitude
  (the map's cross sections; the only readable view of a grid with one amplitude);
* :func:`plot_drop_histories` - the top-mass acceleration of every drop against time.

Points whose status is not ``ok`` are left blank (NaN), never drawn as values. Functions
return what they drew and import matplotlib lazily (through :mod:`idkit.plot._figure`).
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from idkit.plot._figure import axes_or_new, new_figure, save_figure

__all__ = ["HarmonicTableGrid", "harmonic_table_grid", "plot_harmonic_table_map", "plot_harmonic_table_sections",
           "plot_drop_histories", "harmonic_plot_paths", "drop_plot_paths", "save_harmonic_plots",
           "save_drop_plots"]

HARMONIC_PLOTS = ("harmonic_map.png", "harmonic_sections.png")
DROP_PLOTS = ("drop_histories.png", "drop_peaks.png")

_ORDER_COLUMN = re.compile(r"^\|H([0-9.]+)\| \[-\]$")


@dataclass(frozen=True)
class HarmonicTableGrid:
    """A harmonic grid table laid out as arrays (rows: frequencies, columns: amplitudes).

    Attributes
    ----------
    freq : ndarray, shape (n_freq,)
        Distinct frequencies of the table, Hz, increasing.
    amplitude : ndarray, shape (n_amp,)
        Distinct base amplitudes, m, increasing.
    magnitude : dict of float to ndarray, shape (n_freq, n_amp)
        ``|H_k|`` of each HOSIDF order k in the table (0.5, 1, 2, ...); NaN where the
        point is not ``ok`` or the grid has no point.
    """

    freq: np.ndarray
    amplitude: np.ndarray
    magnitude: dict

    def resonance(self) -> np.ndarray:
        """Frequency (Hz) of the largest ``|H1|`` at each amplitude, refined by a parabola in
        log-log (:func:`idkit.signal.harmonics.resonance_peak`); NaN for an amplitude without a
        valid point."""
        from idkit.signal.harmonics import resonance_peak

        return np.array([resonance_peak(self.freq, column)[0] for column in self.magnitude[1.0].T])


def harmonic_table_grid(table) -> HarmonicTableGrid:
    """Lay out a :func:`~idkit.studies.harmonic_grid.harmonic_grid_table` as a grid.

    A (frequency, amplitude) point given twice keeps its first row (the same point
    computed again gives the same value).
    """
    freq = np.unique(table["freq [Hz]"].to_numpy(dtype=float))
    amplitude = np.unique(table["amplitude [m]"].to_numpy(dtype=float))
    rows = np.searchsorted(freq, table["freq [Hz]"].to_numpy(dtype=float))
    columns = np.searchsorted(amplitude, table["amplitude [m]"].to_numpy(dtype=float))
    first = np.zeros(len(table), dtype=bool)
    first[np.unique(rows * amplitude.size + columns, return_index=True)[1]] = True
    ok = (table["status"].to_numpy() == "ok") & first
    magnitude = {}
    for name in table.columns:
        match = _ORDER_COLUMN.match(name)
        if match:
            grid = np.full((freq.size, amplitude.size), np.nan)
            grid[rows[ok], columns[ok]] = table[name].to_numpy(dtype=float)[ok]
            magnitude[float(match.group(1))] = grid
    return HarmonicTableGrid(freq=freq, amplitude=amplitude, magnitude=magnitude)


def _order_name(order: float) -> str:
    return "1/2 subharmonic" if order == 0.5 else f"harmonic {order:g}"


#: The other orders' maps share |H1|'s colour scale down to this fraction of its peak: a
#: harmonic below it is as good as absent (round-off of the Fourier coefficients is ~1e-5 and
#: below) and is drawn in the floor colour instead of a full scale of noise.
HARMONIC_FLOOR = 1e-4


def _colour_map(ax, grid: HarmonicTableGrid, order: float):
    from matplotlib.colors import LogNorm

    values = grid.magnitude[order]
    first = grid.magnitude[1.0]
    peak = np.nanmax(first) if np.isfinite(first).any() else np.nan
    norm = None
    if order == 1.0 and np.isfinite(first).any() and np.nanmax(first) > 0:
        positive = first[first > 0]
        norm = LogNorm(vmin=positive.min(), vmax=positive.max())
    elif np.isfinite(peak) and peak > 0:
        norm = LogNorm(vmin=HARMONIC_FLOOR * peak, vmax=peak, clip=True)
    mesh = ax.pcolormesh(grid.freq, grid.amplitude, np.where(values > 0, values, np.nan).T, shading="nearest",
                         norm=norm, cmap="viridis")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.figure.colorbar(mesh, ax=ax, label=f"|H{order:g}| [-]")
    return mesh


def plot_harmonic_table_map(table, *, axes=None):
    """Maps of ``|H_k|`` over frequency and base amplitude, the resonance line on ``|H1|``.

    Parameters
    ----------
    table : DataFrame
        A :func:`~idkit.studies.harmonic_grid.harmonic_grid_table` (the CSV of
        ``idkit simulate harmonic``), at least two frequencies and two amplitudes.
    axes : sequence of Axes, optional
        One per HOSIDF order of the table, ``|H1|`` first; default a new figure.

    Returns
    -------
    list of Axes
        ``|H1|`` first, then the other orders in increasing order.

    Raises
    ------
    ValueError
        Fewer than two frequencies or two amplitudes (a map needs both axes; draw
        :func:`plot_harmonic_table_sections`), or a table without ``|H1|``.
    """
    grid = harmonic_table_grid(table)
    if grid.freq.size < 2 or grid.amplitude.size < 2:
        raise ValueError(f"table: found {grid.freq.size} frequencies x {grid.amplitude.size} amplitudes, expected "
                         "at least 2 of each for a map")
    if 1.0 not in grid.magnitude:
        raise ValueError("table: found no '|H1| [-]' column, expected a harmonic grid table")
    orders = [1.0] + sorted(order for order in grid.magnitude if order != 1.0)
    if axes is None:
        others = len(orders) - 1
        ncols = min(max(others, 1), 3)
        nrows = -(-others // ncols)
        figure = new_figure((6.4 * max(1.0, 0.55 * ncols), 4.6 + 2.9 * nrows))
        spec = figure.add_gridspec(1 + nrows, ncols, height_ratios=[1.7] + [1.0] * nrows)
        axes = [figure.add_subplot(spec[0, :])] + [figure.add_subplot(spec[1 + k // ncols, k % ncols])
                                                   for k in range(others)]
    main = axes[0]
    _colour_map(main, grid, 1.0)
    resonance = grid.resonance()
    main.plot(resonance, grid.amplitude, color="white", linewidth=2.2, marker="o", markersize=3.5,
              markeredgecolor="black", label="resonance (peak of |H1|)")
    main.legend(loc="lower left", fontsize="small", framealpha=0.8)
    invalid = int(np.isnan(grid.magnitude[1.0]).sum())
    main.set_title("first harmonic |H1| = top / base displacement" + (f" ({invalid} points not ok: blank)"
                                                                        if invalid else ""), fontsize="medium")
    main.set_xlabel("frequency [Hz]")
    main.set_ylabel("base amplitude [m]")
    from matplotlib.ticker import NullFormatter

    for ax, order in zip(axes[1:], orders[1:]):
        _colour_map(ax, grid, order)
        ax.plot(resonance, grid.amplitude, color="white", linewidth=1.0, linestyle="--")
        ax.set_title(f"{_order_name(order)} (scale of |H1|)", fontsize="small")
        ax.xaxis.set_minor_formatter(NullFormatter())  # minor labels of a narrow log axis overlap
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel("base amplitude [m]")
    return list(axes)


def plot_harmonic_table_sections(table, *, max_lines: int = 8, ax=None):
    """``|H1|`` against frequency, one line per base amplitude (at most ``max_lines``, spread
    evenly over the amplitudes), each amplitude's resonance marked. Returns the Axes."""
    grid = harmonic_table_grid(table)
    ax = axes_or_new(ax)
    picked = np.unique(np.linspace(0, grid.amplitude.size - 1, min(max_lines, grid.amplitude.size)).round()
                       .astype(int))
    resonance = grid.resonance()
    from matplotlib import colormaps

    colours = colormaps["viridis"](np.linspace(0.0, 0.9, picked.size))
    for colour, column in zip(colours, picked):
        values = grid.magnitude[1.0][:, column]
        ax.loglog(grid.freq, values, marker="." if grid.freq.size < 30 else None, color=colour,
                  label=f"{grid.amplitude[column]:.3g} m")
        if np.isfinite(resonance[column]):
            ax.axvline(resonance[column], color=colour, linewidth=0.8, linestyle=":")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("|H1| [-]")
    ax.set_title("first harmonic at each base amplitude (dotted: its resonance)", fontsize="medium")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(title="base amplitude", fontsize="small")
    return ax


def plot_drop_histories(sweep, *, ax=None):
    """Top-mass acceleration against time of every drop of a
    :class:`~idkit.responses.shock.ShockSweep`, labelled by drop height and impact speed;
    a flagged drop is drawn up to its flag. Returns the Axes."""
    ax = axes_or_new(ax)
    for index in range(sweep.impact_velocity.size):
        ax.plot(sweep.time * 1e3, sweep.top_acceleration[index],
                label=f"h {100 * sweep.drop_height[index]:.3g} cm, |v0| {abs(sweep.impact_velocity[index]):.3g} m/s")
    ax.set_xlabel("time after impact [ms]")
    ax.set_ylabel("top-mass acceleration [m/s$^2$]")
    ax.set_title("drops: absolute top-mass acceleration", fontsize="medium")
    ax.grid(True, alpha=0.3)
    if sweep.impact_velocity.size <= 12:
        ax.legend(fontsize="small")
    return ax


def harmonic_plot_paths(folder) -> list[Path]:
    """The files :func:`save_harmonic_plots` writes into ``folder``."""
    return [Path(folder) / name for name in HARMONIC_PLOTS]


def drop_plot_paths(folder) -> list[Path]:
    """The files :func:`save_drop_plots` writes into ``folder``."""
    return [Path(folder) / name for name in DROP_PLOTS]


def save_harmonic_plots(table, folder) -> list[Path]:
    """Write ``harmonic_map.png`` (when the grid has two frequencies and two amplitudes at
    least) and ``harmonic_sections.png`` into ``folder`` (created), each atomically, never
    over an existing file (FileExistsError). Returns the written paths."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    grid = harmonic_table_grid(table)
    written = []
    if grid.freq.size >= 2 and grid.amplitude.size >= 2:
        axes = plot_harmonic_table_map(table)
        written.append(save_figure(axes[0].figure, folder / HARMONIC_PLOTS[0], overwrite=False))
    ax = plot_harmonic_table_sections(table)
    written.append(save_figure(ax.figure, folder / HARMONIC_PLOTS[1], overwrite=False))
    return written


def save_drop_plots(sweep, folder) -> list[Path]:
    """Write ``drop_histories.png`` and ``drop_peaks.png`` (rest shock level and the peaks in
    compression and tension against drop height) into ``folder`` (created), each atomically,
    never over an existing file (FileExistsError). Returns the written paths."""
    from idkit.plot.responses import plot_shock_sweep

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    written = [save_figure(plot_drop_histories(sweep).figure, folder / DROP_PLOTS[0], overwrite=False)]
    ax = plot_shock_sweep(sweep, versus="height", quantity="phases")
    ax.plot(sweep.drop_height * 100.0, sweep.rest_shock_level, color="grey", linewidth=5, alpha=0.35, zorder=0,
            label="rest shock level (the larger)")
    ax.legend(fontsize="small")
    ax.set_title("peak top-mass acceleration of each drop", fontsize="medium")
    written.append(save_figure(ax.figure, folder / DROP_PLOTS[1], overwrite=False))
    return written
