"""Figures of validation results: measured against simulated, side by side."""

from __future__ import annotations

import numpy as np

from idkit.plot._figure import axes_or_new

__all__ = ["plot_drop_validation", "plot_frf_validation", "plot_harmonic_validation"]


def plot_harmonic_validation(result, *, axes=None):
    """|H1| versus frequency per amplitude level, measured (markers) and simulated (lines).

    Left: magnitudes; right: magnitude error in dB. Returns the two axes.
    """
    axes = axes_or_new(axes, 1, 2, figsize=(10, 4))
    magnitude_ax, error_ax = axes
    table = result.metrics.sort_values("freq [Hz]")
    for level, group in table.groupby("level"):
        (line,) = magnitude_ax.loglog(group["freq [Hz]"], group["|H1| simulated [-]"], label=f"model, level {level:g}")
        magnitude_ax.loglog(group["freq [Hz]"], group["|H1| measured [-]"], "o", color=line.get_color(),
                            markersize=4, label=f"measured, level {level:g}")
        error_ax.semilogx(group["freq [Hz]"], group["magnitude error [dB]"], "o-", color=line.get_color(),
                          markersize=3)
    magnitude_ax.set_xlabel("frequency [Hz]")
    magnitude_ax.set_ylabel("|HOSIDF 1| [-]")
    magnitude_ax.legend(fontsize="x-small")
    error_ax.axhline(0.0, color="0.5", linewidth=0.8)
    error_ax.set_xlabel("frequency [Hz]")
    error_ax.set_ylabel("model - measured [dB]")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    magnitude_ax.set_title(result.name, fontsize="small")
    return axes


def plot_frf_validation(result, *, axes=None):
    """Measured H1 and model transmissibility per mass: magnitude and phase."""
    axes = axes_or_new(axes, 2, sharex=True)
    magnitude_ax, phase_ax = axes
    for key, curve in result.details["curves"].items():
        freq = curve["freq [Hz]"].to_numpy()
        measured = curve["H1 measured"].to_numpy(complex)
        model = curve["H model"].to_numpy(complex)
        (line,) = magnitude_ax.loglog(freq, np.abs(model), label=f"model {key}")
        magnitude_ax.loglog(freq, np.abs(measured), ".", color=line.get_color(), markersize=2)
        phase_ax.semilogx(freq, np.degrees(np.angle(model)), color=line.get_color())
        phase_ax.semilogx(freq, np.degrees(np.angle(measured)), ".", color=line.get_color(), markersize=2)
    magnitude_ax.set_ylabel("|T| [-]")
    phase_ax.set_ylabel("phase [deg]")
    phase_ax.set_xlabel("frequency [Hz]")
    magnitude_ax.legend(fontsize="x-small", ncol=2)
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    return axes


def plot_drop_validation(result, *, axes=None):
    """Peak accelerations (compression, tension) and peak compression versus impact speed."""
    axes = axes_or_new(axes, 1, 2, figsize=(10, 4))
    accel_ax, deflection_ax = axes
    table = result.metrics
    for mass, group in table.groupby("top mass [kg]"):
        speed = np.abs(group["relative velocity step [m/s]"])
        for phase, marker in (("compression", "o"), ("tension", "s")):
            (line,) = accel_ax.plot(speed, group[f"peak accel {phase} simulated [m/s^2]"], marker, fillstyle="none",
                                    label=f"model {phase}, {mass:g} kg")
            accel_ax.plot(speed, group[f"peak accel {phase} measured [m/s^2]"], marker, color=line.get_color(),
                          label=f"measured {phase}, {mass:g} kg")
        (line,) = deflection_ax.plot(speed, 1e3 * group["peak compression simulated [m]"], "o", fillstyle="none",
                                     label=f"model, {mass:g} kg")
        deflection_ax.plot(speed, 1e3 * group["peak compression measured [m]"], "o", color=line.get_color(),
                           label=f"measured, {mass:g} kg")
    accel_ax.set_xlabel("impact speed |v0| [m/s]")
    accel_ax.set_ylabel("peak acceleration [m/s$^2$]")
    deflection_ax.set_xlabel("impact speed |v0| [m/s]")
    deflection_ax.set_ylabel("peak compression [mm]")
    for ax in axes:
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="x-small")
    return axes
