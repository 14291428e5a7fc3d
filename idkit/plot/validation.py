"""Figures of validation results: measured against simulated, side by side."""

from __future__ import annotations

import numpy as np

from idkit.plot._figure import axes_or_new, column_grid, finish_bode_grid, panel_groups

__all__ = ["MAP_DECADES", "plot_drop_histories", "plot_drop_validation", "plot_frf_validation", "plot_harmonic_validation", "plot_sweep_bode",
           "plot_sweep_maps"]


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
    """Measured H1 and model transmissibility per mass: magnitude and phase.

    Without ``axes``, at most :data:`~idkit.plot._figure.MAX_PER_PANEL` masses a column
    (a 2 x n_columns grid is returned when split); with a (magnitude, phase) pair, every
    mass is drawn into it.
    """
    curves = result.details["curves"]
    groups = panel_groups(list(curves)) if axes is None else [list(curves)]
    grid = column_grid(axes, len(groups), sharex=True)
    for column, group in enumerate(groups):
        magnitude_ax, phase_ax = grid[0, column], grid[1, column]
        for index, key in enumerate(group):
            curve = curves[key]
            colour = f"C{index % 10}"
            freq = curve["freq [Hz]"].to_numpy()
            measured = curve["H1 measured"].to_numpy(complex)
            model = curve["H model"].to_numpy(complex)
            magnitude_ax.loglog(freq, np.abs(model), color=colour, label=f"model {key}")
            magnitude_ax.loglog(freq, np.abs(measured), ".", color=colour, markersize=2)
            phase_ax.semilogx(freq, np.degrees(np.angle(model)), color=colour)
            phase_ax.semilogx(freq, np.degrees(np.angle(measured)), ".", color=colour, markersize=2)
    return finish_bode_grid(grid, legend_title="lines model, dots measured", magnitude_label="|T| [-]")


def plot_drop_validation(result, *, axes=None):
    """Peak acceleration in compression, in tension, and peak compression versus impact speed.

    One panel per quantity, one colour per top mass: filled markers measured, open markers
    model (at most four series a panel). Returns the three axes.
    """
    axes = axes_or_new(axes, 1, 3, figsize=(12, 4))
    compression_ax, tension_ax, deflection_ax = axes
    table = result.metrics
    for index, (mass, group) in enumerate(table.groupby("top mass [kg]")):
        colour = f"C{index % 10}"
        speed = np.abs(group["relative velocity step [m/s]"])
        for ax, phase, marker in ((compression_ax, "compression", "o"), (tension_ax, "tension", "s")):
            ax.plot(speed, group[f"peak accel {phase} simulated [m/s^2]"], marker, color=colour, fillstyle="none",
                    label=f"model, {mass:g} kg")
            ax.plot(speed, group[f"peak accel {phase} measured [m/s^2]"], marker, color=colour,
                    label=f"measured, {mass:g} kg")
        deflection_ax.plot(speed, 1e3 * group["peak compression simulated [m]"], "o", color=colour, fillstyle="none",
                           label=f"model, {mass:g} kg")
        deflection_ax.plot(speed, 1e3 * group["peak compression measured [m]"], "o", color=colour,
                           label=f"measured, {mass:g} kg")
    compression_ax.set_ylabel("peak acceleration [m/s²]")
    compression_ax.set_title("while compressed", fontsize="small")
    tension_ax.set_title("while in tension", fontsize="small")
    deflection_ax.set_ylabel("peak compression [mm]")
    for ax in axes:
        ax.set_xlabel("impact speed |v0| [m/s]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="x-small")
    return axes


def _order_name(order: float) -> str:
    return {0.5: "1/2 subharmonic", 1.0: "first harmonic", 2.0: "second harmonic", 3.0: "third harmonic"}.get(
        float(order), f"harmonic {order:g}")


#: decades of |H| shown below a map panel's largest value (lower values are the numerical
#: floor of the simulation or the noise floor of the measurement)
MAP_DECADES = 4.0


def plot_sweep_maps(maps, *, axes=None):
    """Top views of |HOSIDF| orders 1, 2, 3 and 1/2: the model on its grid, measured points on top.

    ``maps`` is a :class:`~idkit.studies.sweep_maps.SweepMaps`. Each panel shares one
    logarithmic colour scale between the model grid (cells) and the measured records
    (squares with a black edge), spanning :data:`MAP_DECADES` decades below the largest
    value; a square whose colour stands out from the cells around it is a point the model
    misses. Grid cells where the model did not reach a valid steady state are left blank.
    Returns the 2 x 2 axes.
    """
    from matplotlib.colors import LogNorm

    from idkit.studies.sweep_maps import MAP_ORDERS

    axes = axes_or_new(axes, 2, 2, figsize=(10, 7.5))
    hmap = maps.model
    for ax, order in zip(np.ravel(axes), MAP_ORDERS):
        model = np.where(hmap.valid, hmap.magnitude(order), np.nan)
        rows = maps.order(order)
        measured = np.abs(rows["H measured"].to_numpy(complex))
        finite = np.concatenate([model[np.isfinite(model)], measured[np.isfinite(measured)]])
        finite = finite[finite > 0]
        if finite.size == 0:
            ax.set_axis_off()
            continue
        top = float(finite.max())
        norm = LogNorm(vmin=top * 10.0 ** -MAP_DECADES, vmax=top, clip=True)
        mesh = ax.pcolormesh(hmap.freq, hmap.amplitude, np.where(model > 0, model, np.nan).T, shading="nearest",
                             norm=norm, cmap="viridis")
        ax.scatter(rows["freq [Hz]"], rows["base amplitude [m]"], c=np.where(measured > 0, measured, np.nan),
                   norm=norm, cmap="viridis", marker="s", s=22, edgecolors="black", linewidths=0.6)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("frequency [Hz]")
        ax.set_ylabel("base amplitude [m]")
        ax.set_title(f"|H| {_order_name(order)}", fontsize="small")
        ax.figure.colorbar(mesh, ax=ax, label="|HOSIDF| [-]", extend="min")
    return axes


def plot_sweep_bode(maps, *, max_levels: int = 6, axes=None):
    """Bode cross sections of the first HOSIDF per excitation level: measured (markers), model (lines).

    ``maps`` is a :class:`~idkit.studies.sweep_maps.SweepMaps`; at most ``max_levels``
    levels are drawn (spread over the range when there are more). The model is evaluated
    at each record's frequency and measured base amplitude; points where it did not reach
    a valid steady state are left out. Returns the (magnitude, phase) axes.
    """
    axes = axes_or_new(axes, 2, sharex=True, figsize=(8, 6))
    magnitude_ax, phase_ax = axes
    levels = maps.levels
    if len(levels) > max_levels:
        levels = [levels[i] for i in np.unique(np.round(np.linspace(0, len(levels) - 1, max_levels)).astype(int))]
    rows = maps.order(1.0)
    for level in levels:
        group = rows[np.isclose(rows["level"], level)].sort_values("freq [Hz]")
        freq = group["freq [Hz]"].to_numpy(float)
        measured = group["H measured"].to_numpy(complex)
        model = group["H model"].to_numpy(complex)
        (line,) = magnitude_ax.loglog(freq, np.abs(model), label=f"{level:g} m/s")
        magnitude_ax.loglog(freq, np.abs(measured), "o", color=line.get_color(), markersize=3.5, fillstyle="none")
        for values, style in ((model, "-"), (measured, "o")):
            keep = np.isfinite(values)
            phase = np.degrees(np.unwrap(np.angle(values[keep]))) if keep.any() else np.array([])
            phase_ax.semilogx(freq[keep], phase, style, color=line.get_color(), markersize=3.5, fillstyle="none")
    magnitude_ax.set_ylabel("|H1| [-]")
    phase_ax.set_ylabel("phase of H1 [deg]")
    phase_ax.set_xlabel("frequency [Hz]")
    magnitude_ax.legend(fontsize="x-small", title="base velocity amplitude", title_fontsize="x-small")
    magnitude_ax.set_title(f"{maps.setup}: lines model, circles measured", fontsize="small")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    return axes


def plot_drop_histories(histories, *, axes=None):
    """Top acceleration and deflection over time from the impact: measured (dots) and model (lines).

    ``histories`` is a :class:`~idkit.studies.drop_histories.DropHistories`; one colour per
    drop height. A model curve that went invalid ends there and its legend entry says so.
    Returns the (acceleration, deflection) axes.
    """
    axes = axes_or_new(axes, 2, sharex=True, figsize=(8, 6))
    accel_ax, deflection_ax = axes
    for drop in histories.drops:
        note = "" if drop.status == "ok" else f" (model ends: {drop.status})"
        (line,) = accel_ax.plot(1e3 * drop.simulated_time, drop.simulated_acceleration, linewidth=1.2,
                                label=f"{100 * drop.drop_height_m:.3g} cm{note}")
        accel_ax.plot(1e3 * drop.measured_time, drop.measured_acceleration, ".", color=line.get_color(),
                      markersize=1.5)
        deflection_ax.plot(1e3 * drop.simulated_time, 1e3 * drop.simulated_deflection, color=line.get_color(),
                           linewidth=1.2)
        deflection_ax.plot(1e3 * drop.measured_time, 1e3 * drop.measured_deflection, ".", color=line.get_color(),
                           markersize=1.5)
    accel_ax.set_ylabel("top acceleration [m/s²]")
    deflection_ax.set_ylabel("deflection [mm]\n(tension positive)")
    deflection_ax.set_xlabel("time from the impact [ms]")
    accel_ax.legend(fontsize="x-small", title="drop height", title_fontsize="x-small")
    accel_ax.set_title(f"{histories.setup}: lines model, dots measured", fontsize="small")
    for ax in axes:
        ax.grid(True, alpha=0.3)
    return axes
