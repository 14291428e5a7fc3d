"""Figures of DMA / complex stiffness tables and of their fits (``--plots`` of ``idkit inspect``
and ``idkit fit maxwell`` on a table file).

* :func:`plot_table_isotherms` - storage and loss against frequency as measured, one colour
  per test temperature (the isotherms before any shift);
* :func:`plot_master_fit` - the master curve (dots) and the fitted Prony series (lines);
* :func:`plot_shift_factors` - the shift factors estimated from the isotherms with one
  standard error, the WLF and polynomial laws fitted to them and given factors if any.

Functions take ``axes``/``ax`` (default a new figure), return what they drew and never show.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from idkit.plot._figure import axes_or_new, save_figure

__all__ = ["plot_table_isotherms", "plot_master_fit", "plot_shift_factors", "dma_table_plot_paths",
           "dma_fit_plot_paths", "save_dma_table_plots", "save_dma_fit_plots"]

TABLE_PLOTS = ("table_isotherms.png",)
FIT_PLOTS = ("maxwell_master_curve.png", "maxwell_shift_factors.png")


def _unit(table) -> str:
    return "Pa" if table.quantity == "modulus" else "N/m"


def plot_table_isotherms(table, *, axes=None):
    """Storage (solid) and loss (dashed) against frequency of a
    :class:`~idkit.io.ComplexStiffnessTable`, one colour per temperature (one series for a
    table without temperatures). Returns the (storage and loss, loss factor) axes."""
    from matplotlib import colormaps

    stiffness_ax, factor_ax = axes_or_new(axes, 2, sharex=True)
    temperatures = [None] if table.temperature is None else list(np.unique(table.temperature))
    colours = colormaps["coolwarm"](np.linspace(0.0, 1.0, len(temperatures)))
    for colour, temperature in zip(colours, temperatures):
        rows = np.ones(table.freq.size, bool) if temperature is None else table.temperature == temperature
        order = np.argsort(table.freq[rows], kind="stable")
        freq, storage, loss = (values[rows][order] for values in (table.freq, table.storage, table.loss))
        label = None if temperature is None else f"{temperature - 273.15:.4g} C"
        stiffness_ax.loglog(freq, storage, color=colour, marker=".", label=label)
        stiffness_ax.loglog(freq, np.abs(loss), color=colour, marker=".", linestyle="--")
        factor_ax.semilogx(freq, loss / storage, color=colour, marker=".")
    name = "E', E''" if table.quantity == "modulus" else "k', k''"
    stiffness_ax.set_ylabel(f"{name} [{_unit(table)}]")
    stiffness_ax.set_title("as measured: storage (solid), loss (dashed)" + (
        "" if temperatures == [None] else ", one colour per temperature"), fontsize="medium")
    factor_ax.set_ylabel("loss factor [-]")
    factor_ax.set_xlabel("frequency [Hz]")
    if temperatures != [None]:
        stiffness_ax.legend(fontsize="small", ncols=2, title="temperature")
    for ax in (stiffness_ax, factor_ax):
        ax.grid(True, which="both", alpha=0.3)
    return stiffness_ax, factor_ax


def plot_master_fit(fit, *, axes=None):
    """Master curve of a :class:`~idkit.fit.dma.DmaTableFit` (dots) and its Prony series
    (lines) over the master curve's frequencies. Returns the (stiffness, loss factor) axes."""
    from idkit.plot.fits import plot_storage_loss

    master = fit.master
    stiffness_ax, factor_ax = axes_or_new(axes, 2, sharex=True)
    order = np.argsort(master.freq, kind="stable")
    freq, storage, loss = master.freq[order], master.storage[order], master.loss[order]
    stiffness_ax.loglog(freq, storage, ".", color="C0", label="storage, measured")
    stiffness_ax.loglog(freq, np.abs(loss), ".", color="C1", label="loss, measured")
    factor_ax.semilogx(freq, loss / storage, ".", color="C2", label="measured")
    model_freq = np.geomspace(freq[0], freq[-1], 400)
    plot_storage_loss(fit.model, model_freq, axes=(stiffness_ax, factor_ax), label="model")
    for line in stiffness_ax.lines[-2:]:  # the model's storage and loss in the dots' colours
        line.set_color("C0" if line.get_linestyle() == "-" else "C1")
    factor_ax.lines[-1].set_color("C2")
    estimate = fit.shift_estimate
    shifted = "" if estimate is None else \
        f" at {estimate.reference_temperature_k - 273.15:.4g} C (reduced frequency)"
    stiffness_ax.set_title(f"master curve{shifted} and Prony series, order {fit.model.order}", fontsize="medium")
    stiffness_ax.legend(fontsize="small")
    factor_ax.legend(fontsize="small")
    for ax in (stiffness_ax, factor_ax):
        ax.grid(True, which="both", alpha=0.3)
    return stiffness_ax, factor_ax


def plot_shift_factors(fit, *, ax=None):
    """Shift factors of a :class:`~idkit.fit.dma.DmaTableFit` estimated from its isotherms
    (one standard error), the shift laws fitted to them and given factors. Returns the Axes."""
    ax = axes_or_new(ax)
    estimate = fit.shift_estimate
    celsius = estimate.temperature_k - 273.15
    ax.errorbar(celsius, estimate.log_a_t, yerr=estimate.log_a_t_stderr, fmt="o", ms=3,
                label="estimated from the isotherms")
    for law in (fit.wlf, fit.polynomial):
        if law is not None:
            ax.plot(celsius, law.log_a_t(estimate.temperature_k), label=law.law)
    if fit.check is not None:
        given = fit.check.table
        ax.plot(given["temperature [K]"] - 273.15, given["given log_aT [-]"], "x", label="given")
    ax.set_xlabel("temperature [C]")
    ax.set_ylabel("log10 aT [-]")
    ax.legend(fontsize="small")
    ax.grid(True, alpha=0.3)
    return ax


def dma_table_plot_paths(folder) -> list[Path]:
    """The files :func:`save_dma_table_plots` writes into ``folder``."""
    return [Path(folder) / name for name in TABLE_PLOTS]


def dma_fit_plot_paths(folder) -> list[Path]:
    """The files :func:`save_dma_fit_plots` may write into ``folder`` (the shift factors only
    for a table of isotherms)."""
    return [Path(folder) / name for name in FIT_PLOTS]


def save_dma_table_plots(table, folder, *, overwrite: bool = False) -> list[Path]:
    """Write ``table_isotherms.png`` into ``folder`` (created) atomically; an existing file is
    replaced only with ``overwrite`` (FileExistsError before drawing otherwise)."""
    targets = dma_table_plot_paths(folder)
    existing = [str(path) for path in targets if path.exists()]
    if existing and not overwrite:
        raise FileExistsError(f"refusing to overwrite {', '.join(existing)} (use --force)")
    Path(folder).mkdir(parents=True, exist_ok=True)
    return [save_figure(plot_table_isotherms(table)[0].figure, targets[0], overwrite=True)]


def save_dma_fit_plots(fit, folder) -> list[Path]:
    """Write ``maxwell_master_curve.png`` and, for a table of isotherms,
    ``maxwell_shift_factors.png`` into ``folder`` (created), atomically, never over an existing
    file (FileExistsError). Returns the written paths."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    master, shifts = dma_fit_plot_paths(folder)
    written = [save_figure(plot_master_fit(fit)[0].figure, master, overwrite=False)]
    if fit.shift_estimate is not None:
        written.append(save_figure(plot_shift_factors(fit).figure, shifts, overwrite=False))
    return written
