"""Basic plots of loops, frequency responses and shock levels."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from idkit.atomic import write_bytes_atomic


def _axes(ax, nrows=1):
    if ax is not None:
        return ax
    from matplotlib.figure import Figure

    figure = Figure(figsize=(6.4, 2.4 + 2.2 * nrows), layout="constrained")
    axes = figure.subplots(nrows, 1, sharex=True)
    return axes


def plot_loops(deflection, force, *, label=None, ax=None):
    """Force (N) versus deflection (mm on the axis) loops; returns the line."""
    ax = _axes(ax)
    (line,) = ax.plot(np.asarray(deflection) * 1e3, force, label=label)
    ax.set_xlabel("deflection [mm] (+ tension)")
    ax.set_ylabel("force [N]")
    ax.grid(True, alpha=0.3)
    return line


def plot_bode(freq, response, *, label=None, axes=None):
    """Magnitude (log-log) and phase (deg) of a complex response; returns the two lines."""
    axes = _axes(axes, nrows=2) if axes is None else axes
    magnitude_ax, phase_ax = axes
    (magnitude,) = magnitude_ax.loglog(freq, np.abs(response), label=label)
    (phase,) = phase_ax.semilogx(freq, np.degrees(np.unwrap(np.angle(response))), label=label)
    magnitude_ax.set_ylabel("magnitude [-]")
    phase_ax.set_ylabel("phase [deg]")
    phase_ax.set_xlabel("frequency [Hz]")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    return magnitude, phase


def plot_harmonic_cross_sections(freq, amplitudes, hosidf, *, axes=None):
    """Bode cross sections of a first-order HOSIDF at several base amplitudes.

    ``hosidf`` has shape (n_freq, n_amplitudes). Returns the magnitude lines.
    """
    axes = _axes(axes, nrows=2) if axes is None else axes
    lines = []
    for column, amplitude in enumerate(amplitudes):
        magnitude, _ = plot_bode(freq, hosidf[:, column], label=f"{amplitude:.0e} m", axes=axes)
        lines.append(magnitude)
    axes[0].legend(fontsize="small", title="base amplitude")
    return lines


def plot_shock_levels(impact_speed, peak_acceleration, *, label=None, ax=None):
    """Rest shock level (max |a| of the top mass, m/s^2) versus impact speed |v0| (m/s)."""
    ax = _axes(ax)
    (line,) = ax.plot(impact_speed, peak_acceleration, marker=".", label=label)
    ax.set_xlabel("impact speed |v0| [m/s]")
    ax.set_ylabel("rest shock level [m/s$^2$]")
    ax.grid(True, alpha=0.3)
    return line


def save_figure(figure, path, *, overwrite: bool = True) -> Path:
    """Save a figure atomically (:func:`idkit.atomic.write_bytes_atomic`); the format follows the suffix."""
    path = Path(path)
    buffer = io.BytesIO()
    figure.savefig(buffer, format=path.suffix.lstrip(".") or "png", dpi=110)
    return write_bytes_atomic(path, buffer.getvalue(), overwrite=overwrite)
