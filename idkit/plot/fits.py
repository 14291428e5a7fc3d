"""Figures of identification results: loops, FRFs, complex stiffness, error landscape.

Compute first, plot second: every function takes results or models from
:mod:`idkit.fit`, accepts ``ax``/``axes=None`` (a new figure then), returns what it
drew and never calls ``show``. :func:`save_fit_plots` writes the set of figures of a
:class:`~idkit.fit.MeasurementFit` (used by ``idkit fit ... --plots DIR``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from idkit.plot.basic import save_figure

__all__ = ["plot_loop_fit", "plot_frf_fit", "plot_storage_loss", "plot_error_landscape", "save_fit_plots"]


def _figure(nrows=1, ncols=1, *, sharex=False, width=6.4, height=None):
    from matplotlib.figure import Figure

    figure = Figure(figsize=(width * max(1, ncols * 0.8), height or 2.6 + 2.2 * nrows), layout="constrained")
    return figure.subplots(nrows, ncols, sharex=sharex, squeeze=False)


def _set_forces(model, sets):
    from idkit.fit import boucwen_set_forces, iwan_set_forces
    from idkit.models import BoucWenModel, IwanModel

    if isinstance(model, IwanModel):
        return iwan_set_forces(model, sets)
    if isinstance(model, BoucWenModel):
        return boucwen_set_forces(model, sets)
    raise TypeError(f"model: found {type(model).__name__}, expected IwanModel or BoucWenModel")


def plot_loop_fit(model, small, large, *, axes=None, label="model"):
    """Measured (grey) and fitted (coloured) force-deflection loops, small and large sets side by side.

    Parameters
    ----------
    model : IwanModel or BoucWenModel
    small, large : sequence of LoopSet
        Prepared sets (e.g. ``fit.data.small``); the model runs from the fit's initial state.
    axes : pair of Axes, optional
    label : str
        Legend label of the model curves.

    Returns
    -------
    list of Line2D
        The model lines.
    """
    if axes is None:
        axes = _figure(1, 2, height=3.6)[0]
    lines = []
    for ax, sets, title in zip(axes, (small, large), ("small loops", "large loops")):
        forces = _set_forces(model, list(sets))
        for index, (loop_set, force) in enumerate(zip(sets, forces)):
            ax.plot(1e3 * loop_set.deflection, loop_set.force, color="0.6", lw=1.0,
                    label="measured" if index == 0 else None)
            (line,) = ax.plot(1e3 * loop_set.deflection, force, lw=1.0, ls="--",
                              label=f"{label}" if index == 0 else None)
            lines.append(line)
        ax.set_title(title)
        ax.set_xlabel("deflection [mm] (+ tension)")
        ax.set_ylabel("force [N]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="small")
    return lines


def _transmissibility(model, mass, freq):
    stiffness = model.complex_stiffness(freq)
    return stiffness / (stiffness - (mass + model.m_eff) * (2 * np.pi * freq) ** 2)


def plot_frf_fit(model, frfs, *, band=(1.0, 100.0), axes=None):
    """Measured and fitted transmissibility magnitude and phase, one colour per top mass.

    Parameters
    ----------
    model : GeneralizedMaxwell or VoigtModel
    frfs : sequence of TransmissibilitySet
        Every repetition is drawn (thin); the model once per mass (dashed).
    band : (float, float)
        Frequency range drawn, Hz.
    axes : pair of Axes (magnitude, phase), optional

    Returns
    -------
    list of Line2D
        The model magnitude lines, one per mass.
    """
    if axes is None:
        axes = _figure(2, 1, sharex=True)[:, 0]
    magnitude_ax, phase_ax = axes
    masses = sorted({item.mass for item in frfs})
    colours = [f"C{i % 10}" for i in range(len(masses))]
    lines = []
    for mass, colour in zip(masses, colours):
        for item in frfs:
            if item.mass != mass:
                continue
            inside = (item.freq >= band[0]) & (item.freq <= band[1])
            magnitude_ax.loglog(item.freq[inside], np.abs(item.transmissibility[inside]), color=colour, lw=0.6,
                                alpha=0.6)
            phase_ax.semilogx(item.freq[inside], np.degrees(np.angle(item.transmissibility[inside])), color=colour,
                              lw=0.6, alpha=0.6)
        freq = np.geomspace(band[0], band[1], 400)
        response = _transmissibility(model, mass, freq)
        (line,) = magnitude_ax.loglog(freq, np.abs(response), color=colour, ls="--", lw=1.2, label=f"{mass:.2f} kg")
        phase_ax.semilogx(freq, np.degrees(np.angle(response)), color=colour, ls="--", lw=1.2)
        lines.append(line)
    magnitude_ax.set_ylabel("|H| [-]")
    phase_ax.set_ylabel("phase [deg]")
    phase_ax.set_xlabel("frequency [Hz]")
    magnitude_ax.legend(fontsize="x-small", ncol=2, title="measured (thin), model (dashed)", title_fontsize="x-small")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    return lines


def plot_storage_loss(model, freq=None, *, axes=None, label=None):
    """Storage and loss stiffness (N/m) and loss factor of an elastomer model.

    Parameters
    ----------
    model : GeneralizedMaxwell or VoigtModel
    freq : array_like, optional
        Frequencies in Hz; default 0.1-1000 Hz.
    axes : pair of Axes (stiffness, loss factor), optional

    Returns
    -------
    (Line2D, Line2D, Line2D)
        Storage, loss and loss-factor lines.
    """
    if axes is None:
        axes = _figure(2, 1, sharex=True)[:, 0]
    freq = np.geomspace(0.1, 1000.0, 400) if freq is None else np.asarray(freq, float)
    stiffness = model.complex_stiffness(freq)
    stiffness_ax, loss_ax = axes
    (storage,) = stiffness_ax.loglog(freq, stiffness.real, label=f"storage {label or ''}".strip())
    (loss,) = stiffness_ax.loglog(freq, np.abs(stiffness.imag), ls="--", label=f"loss {label or ''}".strip())
    (eta,) = loss_ax.semilogx(freq, stiffness.imag / stiffness.real, label=label)
    stiffness_ax.set_ylabel("k* [N/m]")
    loss_ax.set_ylabel("loss factor [-]")
    loss_ax.set_xlabel("frequency [Hz]")
    stiffness_ax.legend(fontsize="small")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    return storage, loss, eta


def plot_error_landscape(landscape, *, ax=None, levels=20):
    """Contours of log10 of the one-element Maxwell error over (k_1, rate_1), infeasible region hatched.

    Parameters
    ----------
    landscape : ErrorLandscape
        From :func:`idkit.fit.maxwell_error_landscape`.
    ax : Axes, optional
    levels : int

    Returns
    -------
    QuadContourSet
    """
    if ax is None:
        ax = _figure(1, 1, height=4.2)[0, 0]
    k_grid, rate_grid = np.meshgrid(landscape.k, landscape.rate)
    contours = ax.contourf(k_grid, rate_grid, np.log10(100 * landscape.error), levels=levels, cmap="viridis")
    ax.figure.colorbar(contours, ax=ax, label="log10(error [%])")
    if not np.all(landscape.feasible):
        ax.contourf(k_grid, rate_grid, (~landscape.feasible).astype(float), levels=[0.5, 1.5], colors="none",
                    hatches=["//"])
    ax.plot(*landscape.optimum, marker="*", color="red", ms=12, ls="none", label="constrained optimum")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("k_1 [N/m]")
    ax.set_ylabel("rate_1 [1/s]")
    ax.set_title(f"one-element Maxwell, k0 = {landscape.k0:.4g} N/m, m_eff = {landscape.m_eff:.3g} kg "
                 "(hatched: loss factor decreases)", fontsize="small")
    ax.legend(fontsize="small")
    return contours


def save_fit_plots(fit, folder, *, overwrite: bool = False) -> list[Path]:
    """Write the figures of a :class:`~idkit.fit.MeasurementFit` as PNG files into ``folder``.

    Loop fits: ``loops.png``. Maxwell fits: ``frf.png``, ``complex_stiffness.png``,
    ``landscape.png``. Refuses (FileExistsError, before drawing) to replace an
    existing file unless ``overwrite``.
    """
    folder = Path(folder)
    names = {"iwan": ["loops.png"], "boucwen": ["loops.png"],
             "maxwell": ["frf.png", "complex_stiffness.png", "landscape.png"]}[fit.kind]
    targets = [folder / f"{fit.kind}_{name}" for name in names]
    existing = [str(p) for p in targets if p.exists()]
    if existing and not overwrite:
        raise FileExistsError(f"refusing to overwrite existing plot(s): {', '.join(existing)}")
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    if fit.kind in ("iwan", "boucwen"):
        axes = _figure(1, 2, height=3.6)[0]
        plot_loop_fit(fit.model, fit.data.small, fit.data.large, axes=axes, label=fit.kind)
        written.append(save_figure(axes[0].figure, targets[0]))
        return written
    from idkit.fit import maxwell_error_landscape

    band = fit.result.settings.band
    axes = _figure(2, 1, sharex=True)[:, 0]
    plot_frf_fit(fit.model, fit.data, band=band, axes=axes)
    written.append(save_figure(axes[0].figure, targets[0]))
    axes = _figure(2, 1, sharex=True)[:, 0]
    plot_storage_loss(fit.model, axes=axes, label="identified")
    written.append(save_figure(axes[0].figure, targets[1]))
    landscape = maxwell_error_landscape(fit.data, k0=fit.model.k0, band=band, seed=fit.result.settings.seed)
    ax = _figure(1, 1, height=4.2)[0, 0]
    plot_error_landscape(landscape, ax=ax)
    written.append(save_figure(ax.figure, targets[2]))
    return written
