"""Figures of identification results: loops, FRFs, complex stiffness, error landscape.

Compute first, plot second: the model forces along the loops and the error landscape come
from :mod:`idkit.fit.predictions` (this module runs no fitter and no loop model); the
transmissibility of a model is the law :func:`idkit.models.laws.sdof_transmissibility`. Every
function accepts ``ax``/``axes=None`` (a new figure then) and returns the Axes it drew
into. :func:`save_fit_plots` writes the figures of a fit (``idkit fit ... --plots DIR``).
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from idkit.models.laws import sdof_transmissibility
from idkit.models.maxwell import preloaded
from idkit.plot._figure import axes_or_new, column_grid, finish_bode_grid, panel_groups, save_figure

if TYPE_CHECKING:  # types only: plotting never runs a fitter
    from idkit.fit.landscape import ErrorLandscape
    from idkit.fit.predictions import FitPrediction, LoopFitPrediction

__all__ = [
    "FIT_PLOT_NAMES",
    "plot_error_landscape",
    "plot_frf_fit",
    "plot_loop_fit",
    "plot_parameter_spread",
    "plot_storage_loss",
    "save_fit_plots",
]

#: colour of every model curve of :func:`plot_loop_fit` (the legend names it once)
MODEL_COLOUR = "C0"

#: file names written by :func:`save_fit_plots` per fit kind (prefixed with the kind)
FIT_PLOT_NAMES = {"iwan": ("loops.png",), "boucwen": ("loops.png",),
                  "maxwell": ("frf.png", "complex_stiffness.png", "landscape.png")}


def plot_loop_fit(prediction: LoopFitPrediction, *, axes=None, label: str = "model"):
    """Measured (grey) and model (dashed, one colour) force-deflection loops, small and large sets side by side.

    Parameters
    ----------
    prediction : LoopFitPrediction
        From :func:`idkit.fit.predictions.predict_loops`.
    axes : pair of Axes, optional
    label : str
        Legend label of the model curves.

    Returns
    -------
    (Axes, Axes)
        Small-loop and large-loop axes.
    """
    axes = axes_or_new(axes, 1, 2, figsize=(6.4 * 1.6, 3.6))
    for ax, loops, title in zip(axes, (prediction.small, prediction.large), ("small loops", "large loops")):
        for index, loop in enumerate(loops):
            ax.plot(1e3 * loop.deflection, loop.measured_force, color="0.75", lw=2.5,
                    label="measured" if index == 0 else None)
            ax.plot(1e3 * loop.deflection, loop.model_force, color=MODEL_COLOUR, lw=1.0, ls="--",
                    label=label if index == 0 else None)
        ax.set_title(title)
        ax.set_xlabel("deflection [mm] (+ tension)")
        ax.set_ylabel("force [N]")
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize="small")
    return axes


def plot_frf_fit(model, frfs, *, band=(1.0, 100.0), axes=None):
    """Measured and model transmissibility magnitude and phase, one colour per top mass.

    Parameters
    ----------
    model : GeneralizedMaxwell or VoigtModel
        Its transmissibility on each top mass is :func:`idkit.models.laws.sdof_transmissibility`.
    frfs : sequence of TransmissibilitySet
        Every repetition is drawn (thin); the model once per mass (dashed).
    band : (float, float)
        Frequency range drawn, Hz.
    axes : pair of Axes (magnitude, phase), optional
        Every top mass is drawn into them. Without axes, a new figure holds at most
        :data:`~idkit.plot._figure.MAX_PER_PANEL` top masses per column.

    Returns
    -------
    (Axes, Axes) or ndarray of Axes, shape (2, n_columns)
        Magnitude and phase axes; a grid (magnitude row, phase row) when split.
    """
    masses = sorted({item.mass for item in frfs})
    groups = panel_groups(masses) if axes is None else [masses]
    grid = column_grid(axes, len(groups), sharex=True)
    freq = np.geomspace(band[0], band[1], 400)
    for column, group in enumerate(groups):
        magnitude_ax, phase_ax = grid[0, column], grid[1, column]
        for index, mass in enumerate(group):
            colour = f"C{index % 10}"
            for item in frfs:
                if item.mass != mass:
                    continue
                inside = (item.freq >= band[0]) & (item.freq <= band[1])
                magnitude_ax.loglog(item.freq[inside], np.abs(item.transmissibility[inside]), color=colour, lw=0.6,
                                    alpha=0.6)
                phase_ax.semilogx(item.freq[inside], np.degrees(np.angle(item.transmissibility[inside])),
                                  color=colour, lw=0.6, alpha=0.6)
            static = next((item.static_stiffness for item in frfs if item.mass == mass), None)
            response = sdof_transmissibility(preloaded(model, static).small_amplitude_stiffness(freq), mass + model.m_eff,
                                             2 * np.pi * freq)
            magnitude_ax.loglog(freq, np.abs(response), color=colour, ls="--", lw=1.2, label=f"{mass:.2f} kg")
            phase_ax.semilogx(freq, np.degrees(np.angle(response)), color=colour, ls="--", lw=1.2)
    return finish_bode_grid(grid, legend_title="measured (thin), model (dashed)", magnitude_label="|H| [-]")


def plot_storage_loss(model, freq=None, *, axes=None, label=None):
    """Storage and loss stiffness (N/m; moduli in Pa for a modulus model) and loss factor of a Maxwell model.

    Parameters
    ----------
    model : GeneralizedMaxwell or VoigtModel
    freq : array_like, optional
        Frequencies in Hz; default 0.1-1000 Hz.
    axes : pair of Axes (stiffness, loss factor), optional

    Returns
    -------
    (Axes, Axes)
        Stiffness (modulus, in Pa, for a modulus model) and loss-factor axes.
    """
    axes = axes_or_new(axes, 2, sharex=True)
    freq = np.geomspace(0.1, 1000.0, 400) if freq is None else np.asarray(freq, float)
    stiffness = model.complex_stiffness(freq)
    stiffness_ax, loss_ax = axes
    stiffness_ax.loglog(freq, stiffness.real, label=f"storage {label or ''}".strip())
    stiffness_ax.loglog(freq, np.abs(stiffness.imag), ls="--", label=f"loss {label or ''}".strip())
    loss_ax.semilogx(freq, stiffness.imag / stiffness.real, label=label)
    modulus = getattr(model, "quantity", "stiffness") == "modulus"
    stiffness_ax.set_ylabel("E', E'' [Pa]" if modulus else "k', k'' [N/m]")
    loss_ax.set_ylabel("loss factor [-]")
    loss_ax.set_xlabel("frequency [Hz]")
    stiffness_ax.legend(fontsize="small")
    for ax in axes:
        ax.grid(True, which="both", alpha=0.3)
    return axes


def plot_error_landscape(landscape: ErrorLandscape, *, ax=None, levels: int = 20):
    """Contours of log10 of the one-element Maxwell error over (k_1, rate_1), infeasible region hatched.

    Parameters
    ----------
    landscape : ErrorLandscape
        From :func:`idkit.fit.maxwell_error_landscape`.
    ax : Axes, optional
    levels : int

    Returns
    -------
    Axes
    """
    ax = axes_or_new(ax, figsize=(6.4, 4.2))
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
    return ax


def fit_plot_paths(kind: str, folder) -> list[Path]:
    """The files :func:`save_fit_plots` writes for a fit of ``kind`` into ``folder``."""
    return [Path(folder) / f"{kind}_{name}" for name in FIT_PLOT_NAMES[kind]]


def save_fit_plots(prediction: FitPrediction, folder, *, overwrite: bool = False) -> list[Path]:
    """Write the figures of a fit as PNG files into ``folder``.

    Loop fits: ``<kind>_loops.png``. Maxwell fits: ``maxwell_frf.png``,
    ``maxwell_complex_stiffness.png`` and, when the prediction holds one,
    ``maxwell_landscape.png``. Refuses (FileExistsError, before drawing) to replace an
    existing file unless ``overwrite``.

    Parameters
    ----------
    prediction : FitPrediction
        From :func:`idkit.fit.predictions.predict_fit`.
    folder : path
        Created if missing.

    Returns
    -------
    list of pathlib.Path
        The written files.
    """
    targets = fit_plot_paths(prediction.kind, folder)
    existing = [str(p) for p in targets if p.exists()]
    if existing and not overwrite:
        raise FileExistsError(f"refusing to overwrite existing plot(s): {', '.join(existing)}")
    Path(folder).mkdir(parents=True, exist_ok=True)
    if prediction.loops is not None:
        axes = plot_loop_fit(prediction.loops, label=prediction.kind)
        return [save_figure(axes[0].figure, targets[0])]
    written = [save_figure(plot_frf_fit(prediction.model, prediction.frfs, band=prediction.band)[0].figure,
                           targets[0]),
               save_figure(plot_storage_loss(prediction.model, label="identified")[0].figure, targets[1])]
    if prediction.landscape is not None:
        written.append(save_figure(plot_error_landscape(prediction.landscape).figure, targets[2]))
    return written



def plot_parameter_spread(fit, *, ax=None, title: str | None = None):
    """Each fitted parameter's uncertainty relative to its value: Jacobian standard error and refits.

    ``fit`` is an :class:`idkit.fit.MeasurementFit` (its :meth:`parameters_table` and, when
    present, its :attr:`spread` across repetitions). Per fitted parameter (one row each): a
    bar of +-1 and a lighter one of +-2 standard errors (residual Jacobian at the optimum)
    and one dot per refit on a single repetition, all as percent of the fitted value. A dot
    far outside the bars means the repetitions differ more than the residual noise
    explains. The axis is linear within +-1 % and logarithmic beyond. Returns the Axes.
    """
    table = fit.parameters_table()
    rows = table[table["fitted"]].reset_index(drop=True)
    refits = {}
    if fit.spread is not None:
        refits = {name: np.asarray(fit.spread.samples[:, index], dtype=float)
                  for index, name in enumerate(fit.spread.names)}
    ax = axes_or_new(ax, figsize=(6.4, 1.4 + 0.38 * len(rows)))
    labelled = set()  # each legend entry once, on the first row that draws it

    def label(text):
        if text in labelled:
            return None
        labelled.add(text)
        return text

    for position, row in rows.iterrows():
        value = float(row["value"])
        stderr = row["stderr"]
        if stderr is not None and np.isfinite(stderr) and value != 0:
            relative = 100.0 * float(stderr) / abs(value)
            ax.barh(position, 4 * relative, left=-2 * relative, height=0.5, color="C0", alpha=0.25,
                    label=label("±2 standard errors"))
            ax.barh(position, 2 * relative, left=-relative, height=0.5, color="C0", alpha=0.5,
                    label=label("±1 standard error"))
        samples = refits.get(row["parameter"], np.array([]))
        if samples.size and value != 0:
            ax.plot(100.0 * (samples / value - 1.0), np.full(samples.size, position), "o", color="C3",
                    markersize=4, label=label("refit on one repetition"))
    ax.axvline(0.0, color="0.3", linewidth=0.8)
    # linear within +-1 %, logarithmic beyond: a 0.1 % and a 90 % uncertainty both stay readable
    ax.set_xscale("symlog", linthresh=1.0, linscale=1.0)
    ax.set_yticks(range(len(rows)), [f"{name} [{unit}]" if unit else name
                                     for name, unit in zip(rows["parameter"], rows["unit"])])
    ax.invert_yaxis()
    ax.set_xlabel("deviation from the fitted value [%] (linear within ±1 %, log beyond)")
    ax.grid(True, axis="x", alpha=0.3)
    if labelled:
        ax.legend(fontsize="x-small", loc="best")
    else:  # no standard error and no refit anywhere: say so rather than draw an empty panel
        ax.text(0.5, 0.5, "no standard errors and no refits to show", transform=ax.transAxes, ha="center",
                va="center", fontsize="small", color="0.4")
    if title:
        ax.set_title(title, fontsize="small")
    return ax
