"""Equivalent stiffness and loss factor of hysteresis loops versus amplitude (measured and model)."""

from __future__ import annotations

import numpy as np

from idkit.plot._figure import axes_or_new

__all__ = ["plot_equivalent_linearization"]


def plot_equivalent_linearization(result, *, axes=None, label: str = "model"):
    """Secant stiffness and loss factor per cycle versus amplitude; returns both Axes.

    Parameters
    ----------
    result : EquivalentLinearization
        From :func:`idkit.studies.equivalent.equivalent_linearization`.
    axes : pair of Axes, optional
    label : str
        Legend label of the model points.
    """
    stiffness_ax, loss_ax = axes_or_new(axes, 2, sharex=True)
    amplitude_mm = 1e3 * np.asarray(result.amplitude_m)
    for ax, measured, model, unit in (
            (stiffness_ax, result.secant_stiffness_n_per_m, result.model_secant_stiffness_n_per_m,
             "secant stiffness k_eq [N/m]"),
            (loss_ax, result.loss_factor, result.model_loss_factor, "loss factor eta_eq [-]")):
        ax.semilogx(amplitude_mm, measured, "o", ms=3.5, color="0.35", label="measured")
        ax.semilogx(amplitude_mm, model, "x", ms=4.5, color="C1", label=label)
        ax.set_ylabel(unit)
        ax.grid(True, which="both", alpha=0.3)
    stiffness_ax.set_yscale("log")
    loss_ax.set_xlabel("cycle amplitude X [mm]")
    stiffness_ax.legend(fontsize="small")
    return stiffness_ax, loss_ax
