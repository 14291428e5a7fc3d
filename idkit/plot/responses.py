"""Figures of model responses: harmonic maps, linear FRFs, shock sweeps, random vibration.

Compute first (:mod:`idkit.responses`), plot second. Every function takes ``ax``/``axes``
(default: a new figure from :mod:`idkit.plot._figure`), returns the Axes it drew into and
never calls ``show``; matplotlib is imported lazily. Thesis figures reproduced: 3.7/3.9/3.11-3.16/3.19 (maps), 3.10/3.14
(cross sections), 4.3/4.4/5.7/5.8 (linear), 3.21/4.5/5.15/5.16 (shock).
"""

from __future__ import annotations

import numpy as np

from idkit.plot._figure import axes_or_new

__all__ = [
    "plot_complex_stiffness",
    "plot_map_cross_sections",
    "plot_map_surface",
    "plot_map_top_view",
    "plot_output_psd",
    "plot_resonance_vs_amplitude",
    "plot_shock_deflection",
    "plot_shock_sweep",
    "plot_transmissibility",
]


def _map_values(hmap, quantity, part):
    """Grid values and a label for a HarmonicMap quantity: "ratio" (peak-peak/2) or an order."""
    if quantity in ("ratio", "half_range"):
        if part != "magnitude":
            raise ValueError(f"part: found {part!r}; peak-peak/2 has a magnitude only")
        return hmap.amplitude_ratio, "peak-peak/2 $x_m/x_b$ [-]"
    order = float(quantity)
    name = "1/2 subharmonic" if order == 0.5 else f"harmonic {order:g}"
    if part == "magnitude":
        return hmap.magnitude(order), f"|H| {name} [-]"
    if part == "phase":
        return np.degrees(hmap.phase(order)), f"phase {name} [deg]"
    raise ValueError(f"part: found {part!r}, expected 'magnitude' or 'phase'")


def plot_map_surface(hmap, quantity="ratio", *, part="magnitude", ax=None):
    """3D surface of a :class:`~idkit.responses.harmonic_map.HarmonicMap` over log10 frequency and log10 amplitude.

    Parameters
    ----------
    hmap : HarmonicMap
    quantity : "ratio" or float
        "ratio" (peak-peak/2 over the base amplitude) or a HOSIDF order (0.5, 1, 2, ...).
    part : "magnitude" or "phase"
        Magnitudes are drawn as log10 (3D axes have no log scale); phases in degrees.
    ax : Axes3D, optional

    Returns
    -------
    Axes3D
        Points that did not converge or were flagged are left out (NaN).
    """
    ax = axes_or_new(ax, projection="3d", figsize=(7.0, 5.5))
    values, label = _map_values(hmap, quantity, part)
    values = np.where(hmap.valid, values, np.nan)
    if part == "magnitude":
        with np.errstate(divide="ignore"):
            values = np.log10(values)
        label = f"log10 {label}"
    log_f, log_a = np.meshgrid(np.log10(hmap.freq), np.log10(hmap.amplitude), indexing="ij")
    ax.plot_surface(log_f, log_a, values, cmap="viridis", linewidth=0, antialiased=True)
    ax.set_xlabel("log10 frequency [Hz]")
    ax.set_ylabel("log10 amplitude [m]")
    ax.set_zlabel(label)
    return ax


def plot_map_top_view(hmap, quantity=1, *, part="magnitude", ax=None):
    """Top view (colour map) of a HarmonicMap on log frequency / log amplitude axes.

    Magnitudes use a logarithmic colour scale. Returns the Axes (a colour bar is added).
    """
    from matplotlib.colors import LogNorm

    ax = axes_or_new(ax)
    values, label = _map_values(hmap, quantity, part)
    values = np.where(hmap.valid, values, np.nan)
    norm = None
    if part == "magnitude":
        positive = values[np.isfinite(values) & (values > 0)]
        if positive.size:
            norm = LogNorm(vmin=max(positive.min(), positive.max() * 1e-8), vmax=positive.max())
        values = np.where(values > 0, values, np.nan)
    mesh = ax.pcolormesh(hmap.freq, hmap.amplitude, values.T, shading="nearest", norm=norm, cmap="viridis")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("base amplitude [m]")
    ax.figure.colorbar(mesh, ax=ax, label=label)
    return ax


def plot_map_cross_sections(hmap, amplitudes, *, order=1, axes=None):
    """Bode cross sections (magnitude, phase) of a HOSIDF at the grid amplitudes nearest ``amplitudes`` (m).

    Returns the (magnitude, phase) axes.
    """
    axes = axes_or_new(axes, 2, sharex=True)
    magnitude_ax, phase_ax = axes
    for amplitude in np.atleast_1d(amplitudes):
        column = hmap.amplitude_index(float(amplitude))
        valid = hmap.valid[:, column]
        value = np.where(valid, hmap.hosidf(order)[:, column], np.nan)
        label = f"{hmap.amplitude[column]:.1e} m"
        magnitude_ax.loglog(hmap.freq, np.abs(value), label=label)
        phase = np.full(value.shape, np.nan)
        if valid.any():
            phase[valid] = np.degrees(np.unwrap(np.angle(value[valid])))
        phase_ax.semilogx(hmap.freq, phase, label=label)
    magnitude_ax.set_ylabel(f"|H{order:g}| [-]")
    phase_ax.set_ylabel("phase [deg]")
    phase_ax.set_xlabel("frequency [Hz]")
    magnitude_ax.legend(fontsize="small", title="base amplitude")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    return axes


def plot_resonance_vs_amplitude(hmap, *, label=None, ax=None):
    """Resonance frequency (peak of |H1|) versus base amplitude; returns the Axes."""
    ax = axes_or_new(ax)
    ax.semilogx(hmap.amplitude, hmap.resonance_frequency(), marker="o", label=label)
    ax.set_xlabel("base amplitude [m]")
    ax.set_ylabel("resonance [Hz]")
    ax.grid(True, which="both", alpha=0.3)
    return ax


def plot_complex_stiffness(freq, stiffness, *, label=None, axes=None, quantity: str = "stiffness"):
    """|k*| (log-log) and loss factor (thesis fig. 4.3) of a complex stiffness; returns both Axes.

    ``quantity="modulus"`` labels a complex modulus |E*| in Pa instead.
    """
    axes = axes_or_new(axes, 2, sharex=True)
    stiffness = np.asarray(stiffness, dtype=complex)
    axes[0].loglog(freq, np.abs(stiffness), label=label)
    axes[1].semilogx(freq, stiffness.imag / stiffness.real, label=label)
    axes[0].set_ylabel("|E*| [Pa]" if quantity == "modulus" else "|k*| [N/m]")
    axes[1].set_ylabel("loss factor [-]")
    axes[1].set_xlabel("frequency [Hz]")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    return axes


def plot_transmissibility(frf, *, label=None, axes=None):
    """Bode diagram of a :class:`~idkit.responses.linear.LinearFrf` with its resonance marked; returns both Axes."""
    axes = axes_or_new(axes, 2, sharex=True)
    h = frf.transmissibility
    (magnitude,) = axes[0].loglog(frf.freq, np.abs(h), label=label)
    axes[1].semilogx(frf.freq, np.degrees(np.unwrap(np.angle(h))), label=label)
    axes[0].plot([frf.resonance.freq], [frf.resonance.peak_magnitude], "x", color=magnitude.get_color())
    axes[0].set_ylabel("|H| [-]")
    axes[1].set_ylabel("phase [deg]")
    axes[1].set_xlabel("frequency [Hz]")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    return axes


def plot_shock_sweep(sweep, *, versus="velocity", quantity="rest", label=None, ax=None):
    """Shock levels of a :class:`~idkit.responses.shock.ShockSweep` (thesis figs. 3.21, 4.5, 5.15).

    Parameters
    ----------
    versus : "velocity" or "height"
        Abscissa: impact speed |v0| in m/s or drop height h in cm.
    quantity : "rest" or "phases"
        The rest shock level, or the peaks in compression and in tension.

    Returns
    -------
    Axes
    """
    ax = axes_or_new(ax)
    if versus == "velocity":
        x, xlabel = sweep.impact_speed, "impact speed |v0| [m/s]"
    elif versus == "height":
        x, xlabel = sweep.drop_height * 100.0, "drop height h [cm]"
    else:
        raise ValueError(f"versus: found {versus!r}, expected 'velocity' or 'height'")
    prefix = f"{label} " if label else ""
    if quantity == "rest":
        lines = ax.plot(x, sweep.rest_shock_level, marker=".", label=label)
    elif quantity == "phases":
        lines = ax.plot(x, sweep.peak_acceleration_compression, marker=".", label=f"{prefix}compression")
        lines += ax.plot(x, sweep.peak_acceleration_tension, marker=".", linestyle="--", label=f"{prefix}tension")
    else:
        raise ValueError(f"quantity: found {quantity!r}, expected 'rest' or 'phases'")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("max |a| top mass [m/s$^2$]")
    ax.grid(True, alpha=0.3)
    return ax


def plot_shock_deflection(sweep, *, label=None, ax=None):
    """Peak compression and tension of every isolator versus |v0| (mm; thesis figs. A.7, 5.16); returns the Axes."""
    ax = axes_or_new(ax)
    prefix = f"{label} " if label else ""
    lines = []
    for j, name in enumerate(sweep.isolator_names):
        lines += ax.plot(sweep.impact_speed, sweep.peak_compression[:, j] * 1e3, marker=".",
                         label=f"{prefix}{name} compression")
        lines += ax.plot(sweep.impact_speed, sweep.peak_tension[:, j] * 1e3, marker=".", linestyle="--",
                         label=f"{prefix}{name} tension")
    ax.set_xlabel("impact speed |v0| [m/s]")
    ax.set_ylabel("max deflection [mm]")
    ax.grid(True, alpha=0.3)
    return ax


def plot_output_psd(result, *, label=None, show_input=True, show_linear=True, ax=None):
    """Input, simulated output and ``|H|^2 S_xx`` PSDs of a :class:`~idkit.responses.random_vibration.RandomResponse`.

    Log-log, (m/s^2)^2/Hz. Returns the Axes.
    """
    ax = axes_or_new(ax)
    prefix = f"{label} " if label else ""
    keep = result.freq > 0
    f = result.freq[keep]
    lines = []
    if show_input:
        lines += ax.loglog(f, result.input_psd[keep], color="0.6", label=f"{prefix}input")
    lines += ax.loglog(f, result.output_psd[keep], label=f"{prefix}output (simulated)")
    if show_linear:
        kind = "linear" if result.is_linear else "small-amplitude"
        lines += ax.loglog(f, result.linear_output_psd[keep], linestyle=":", label=f"{prefix}{kind} |H|$^2$ S$_{{xx}}$")
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("PSD [(m/s$^2$)$^2$/Hz]")
    ax.grid(True, which="both", alpha=0.3)
    return ax
