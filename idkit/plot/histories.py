"""Figures of held-out force histories: measured against predicted force, per record."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from idkit.plot._figure import axes_or_new, save_figure

__all__ = ["plot_history", "plot_history_validation", "history_plot_paths", "save_history_plots"]


def plot_history(history, predicted, *, axes=None, window: slice | None = None):
    """One record: force against deflection (left) and force against time (right), measured
    (grey) and predicted (colour); the strong-motion window ``window`` shaded on the time axis.

    Parameters
    ----------
    history : ForceHistory
    predicted : array_like or None
        Predicted force in N (None: the measured force alone).
    axes : pair of Axes, optional
    window : slice, optional

    Returns
    -------
    (Axes, Axes)
    """
    loop_ax, time_ax = axes_or_new(axes, 1, 2, figsize=(10, 3.6))
    loop_ax.plot(1e3 * history.deflection, history.force, color="0.55", linewidth=0.8, label="measured")
    time_ax.plot(history.time, history.force, color="0.55", linewidth=0.8, label="measured")
    if predicted is not None:
        predicted = np.asarray(predicted, dtype=float)
        loop_ax.plot(1e3 * history.deflection, predicted, color="C0", linewidth=0.9, label="model")
        time_ax.plot(history.time, predicted, color="C0", linewidth=0.9, label="model")
    if window is not None:
        time_ax.axvspan(history.time[window.start], history.time[window.stop - 1], color="C1", alpha=0.08,
                        label="strong motion (5-95 %)")
    loop_ax.set_xlabel("deflection [mm] (tension +)")
    loop_ax.set_ylabel("force [N] (tension +)")
    time_ax.set_xlabel("time [s]")
    time_ax.set_ylabel("force [N]")
    loop_ax.set_title(history.name, fontsize="small")
    time_ax.legend(fontsize="x-small")
    for ax in (loop_ax, time_ax):
        ax.grid(True, alpha=0.3)
    return loop_ax, time_ax


def _file_name(name: str) -> str:
    return "history_" + (re.sub(r"[^A-Za-z0-9._-]+", "_", name).strip("_") or "record") + ".png"


def history_plot_paths(result, folder) -> list[Path]:
    """The files :func:`save_history_plots` writes for ``result`` into ``folder`` (one per record)."""
    return [Path(folder) / _file_name(history.name) for history in result.details["histories"]]


def save_history_plots(result, folder) -> list[Path]:
    """One PNG per record of a :func:`~idkit.validate.history.validate_histories` result
    (``history_<record>.png``); existing files are not overwritten. Returns the paths."""
    from idkit.observe.histories import strong_motion_window

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for history, path in zip(result.details["histories"], history_plot_paths(result, folder)):
        predicted = result.details["predictions"][history.name]
        loop_ax, _ = plot_history(history, None if isinstance(predicted, str) else predicted,
                                  window=strong_motion_window(history.time, history.deflection))
        written.append(save_figure(loop_ax.figure, path, overwrite=False))
    return written


def plot_history_validation(result, *, max_records: int = 4):
    """The held-out records of a :func:`~idkit.validate.history.validate_histories` result, one row
    each (force-deflection and force-time, measured and predicted; the worst strong-motion error
    first, at most ``max_records``). Returns the axes (rows x 2)."""
    from idkit.observe.histories import strong_motion_window
    from idkit.plot._figure import new_axes

    table = result.metrics.sort_values("nrms_error_strong_motion", ascending=False, na_position="first")
    by_name = {history.name: history for history in result.details["histories"]}
    names = list(table["record"])[:max_records]
    grid = new_axes(len(names), 2, figsize=(10, 2.8 * len(names)), squeeze=False)
    for row, name in zip(grid, names):
        history = by_name[name]
        predicted = result.details["predictions"][name]
        plot_history(history, None if isinstance(predicted, str) else predicted, axes=row,
                     window=strong_motion_window(history.time, history.deflection))
    return grid
