"""Basic plots of loops, frequency responses and shock levels.

Every function draws into ``ax``/``axes`` (default: a new figure from
:mod:`idkit.plot._figure`) and returns the Axes it drew into.
"""

from __future__ import annotations

import numpy as np

from idkit.plot._figure import axes_or_new, save_figure

__all__ = ["plot_bode", "plot_harmonic_cross_sections", "plot_loops", "plot_shock_levels", "save_figure"]


def plot_loops(deflection, force, *, label=None, ax=None):
    """Force (N) versus deflection (m, drawn in mm) loops.

    Returns
    -------
    Axes
    """
    ax = axes_or_new(ax)
    ax.plot(np.asarray(deflection) * 1e3, force, label=label)
    ax.set_xlabel("deflection [mm] (+ tension)")
    ax.set_ylabel("force [N]")
    ax.grid(True, alpha=0.3)
    return ax


def plot_bode(freq, response, *, label=None, axes=None):
    """Magnitude (log-log) and phase (deg) of a complex response over ``freq`` (Hz).

    Returns
    -------
    (Axes, Axes)
        Magnitude and phase axes.
    """
    axes = axes_or_new(axes, 2, sharex=True)
    magnitude_ax, phase_ax = axes
    magnitude_ax.loglog(freq, np.abs(response), label=label)
    phase_ax.semilogx(freq, np.degrees(np.unwrap(np.angle(response))), label=label)
    magnitude_ax.set_ylabel("magnitude [-]")
    phase_ax.set_ylabel("phase [deg]")
    phase_ax.set_xlabel("frequency [Hz]")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    return axes


def plot_harmonic_cross_sections(freq, amplitudes, hosidf, *, axes=None):
    """Bode cross sections of a first-order HOSIDF at several base amplitudes (m).

    ``hosidf`` has shape (n_freq, n_amplitudes). Returns the (magnitude, phase) axes.
    """
    axes = axes_or_new(axes, 2, sharex=True)
    for column, amplitude in enumerate(amplitudes):
        plot_bode(freq, hosidf[:, column], label=f"{amplitude:.0e} m", axes=axes)
    axes[0].legend(fontsize="small", title="base amplitude")
    return axes


def plot_shock_levels(impact_speed, peak_acceleration, *, label=None, ax=None):
    """Rest shock level (max |a| of the top mass, m/s^2) versus impact speed |v0| (m/s).

    Returns
    -------
    Axes
    """
    ax = axes_or_new(ax)
    ax.plot(impact_speed, peak_acceleration, marker=".", label=label)
    ax.set_xlabel("impact speed |v0| [m/s]")
    ax.set_ylabel("rest shock level [m/s$^2$]")
    ax.grid(True, alpha=0.3)
    return ax
