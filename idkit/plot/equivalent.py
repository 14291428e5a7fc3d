"""Equivalent stiffness and loss factor of hysteresis loops versus amplitude (measured and model)."""

from __future__ import annotations

import numpy as np

from idkit.plot._figure import axes_or_new

__all__ = ["plot_complex_stiffness_comparison", "plot_drop_shock_spectra", "plot_equivalent_linearization",
           "plot_frf_residuals", "plot_loop_residuals"]


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


def plot_complex_stiffness_comparison(result, *, axes=None, max_curves: int = 6):
    """Measured |k*| and loss factor per top mass (thin) and the model's (dashed); returns both Axes.

    Parameters
    ----------
    result : ComplexStiffnessComparison
        From :func:`idkit.studies.equivalent.complex_stiffness_comparison`.
    axes : pair of Axes, optional
    max_curves : int
        Most top masses drawn (evenly picked when there are more).
    """
    stiffness_ax, loss_ax = axes_or_new(axes, 2, sharex=True)
    picks = np.unique(np.linspace(0, len(result.mass_kg) - 1, min(max_curves, len(result.mass_kg))).round().astype(int))
    for colour, i in enumerate(picks):
        freq, measured, model = result.freq_hz[i], result.measured[i], result.model[i]
        label = f"{result.mass_kg[i]:.2f} kg"
        stiffness_ax.loglog(freq, np.abs(measured), lw=0.8, color=f"C{colour}", label=label)
        loss_ax.semilogx(freq, measured.imag / measured.real, lw=0.8, color=f"C{colour}")
    freq = result.freq_hz[picks[0]]
    model = result.model[picks[0]]
    stiffness_ax.loglog(freq, np.abs(model), "k--", lw=1.4, label="model")
    loss_ax.semilogx(freq, model.imag / model.real, "k--", lw=1.4)
    finite = np.concatenate([np.abs(m)[np.isfinite(m)] for m in (result.measured[i] for i in picks)] + [np.abs(model)])
    stiffness_ax.set_ylim(0.5 * finite.min(), 2.0 * finite.max())
    eta = np.abs(model.imag / model.real)
    loss_ax.set_ylim(-0.5 * eta.max(), 3.0 * eta.max())
    stiffness_ax.set_ylabel("|k*| [N/m]")
    loss_ax.set_ylabel("loss factor [-]")
    loss_ax.set_xlabel("frequency [Hz]")
    stiffness_ax.legend(fontsize="x-small", ncol=2, title="measured per top mass", title_fontsize="x-small")
    for ax in (stiffness_ax, loss_ax):
        ax.grid(True, which="both", alpha=0.3)
    return stiffness_ax, loss_ax


def plot_drop_shock_spectra(result, *, ax=None, max_curves: int = 6):
    """Absolute-acceleration SRS of drops, one colour per height (at most ``max_curves``).

    Solid the measured top acceleration; with the model's and the impact's spectra
    (:func:`idkit.studies.equivalent.drop_shock_spectra` given ``histories``) dashed the model's
    top acceleration and dotted the impact itself (a rigid mount): the gap between the dotted
    and the solid curve is what the isolator takes off.
    """
    from matplotlib.lines import Line2D

    ax = axes_or_new(ax)
    picks = np.unique(np.linspace(0, len(result.height_m) - 1, min(max_curves, len(result.height_m))).round().astype(int))
    model, impact = getattr(result, "model_acceleration", None), getattr(result, "input_acceleration", None)
    for colour, i in enumerate(picks):
        ax.loglog(result.freq_hz, result.acceleration[i], color=f"C{colour}",
                  label=f"h = {100 * result.height_m[i]:.3g} cm")
        if model is not None:
            ax.loglog(result.freq_hz, model[i], color=f"C{colour}", ls="--")
        if impact is not None:
            ax.loglog(result.freq_hz, impact[i], color=f"C{colour}", ls=":", lw=1.0)
    ax.set_xlabel("natural frequency [Hz]")
    ax.set_ylabel("maximax absolute acceleration [m/s$^2$]")
    ax.set_title(f"{result.isolator}, top mass {result.top_mass_kg:.2f} kg, damping {result.damping_ratio:g}",
                 fontsize="small")
    handles, labels = ax.get_legend_handles_labels()
    if model is not None or impact is not None:
        styles = [("-", "measured top"), ("--", "model top")] if model is not None else [("-", "measured top")]
        styles += [(":", "impact (rigid mount)")] if impact is not None else []
        handles += [Line2D([], [], color="0.3", ls=style) for style, _ in styles]
        labels += [label for _, label in styles]
    ax.legend(handles, labels, fontsize="x-small", ncol=2)
    ax.grid(True, which="both", alpha=0.3)
    return ax


def plot_loop_residuals(prediction, *, axes=None, label: str = "model"):
    """Force residual (model - measured) along the deflection of every loop set; returns both Axes.

    Small sets left, large sets right, one curve per set (at most six a panel: evenly
    picked when there are more); a model that fits leaves residuals at the noise level
    without a pattern that follows the loop (a pattern at the reversals means the loop shape
    is wrong there).

    Parameters
    ----------
    prediction : LoopFitPrediction
        From :func:`idkit.fit.predictions.predict_loops`.
    axes : pair of Axes, optional
    label : str
        Model name for the y label.
    """
    small_ax, large_ax = axes_or_new(axes, 2)
    for ax, sets, title in ((small_ax, prediction.small, "small loops"), (large_ax, prediction.large, "large loops")):
        picks = np.unique(np.linspace(0, len(sets) - 1, min(6, len(sets))).round().astype(int)) if sets else []
        for i in picks:
            item = sets[i]
            ax.plot(1e3 * np.asarray(item.deflection), np.asarray(item.model_force) - np.asarray(item.measured_force),
                    lw=0.8, label=item.name)
        ax.axhline(0.0, color="0.3", lw=0.8)
        ax.set_title(title, fontsize="small")
        ax.set_xlabel("deflection [mm] (+ tension)")
        ax.grid(True, alpha=0.3)
        if len(picks):
            ax.legend(fontsize="x-small")
    small_ax.set_ylabel(f"{label} - measured force [N]")
    return small_ax, large_ax


def plot_frf_residuals(model, frfs, *, ax=None, band=(1.0, 100.0), max_curves: int = 6, systematic=()):
    """Relative complex residual ``|H_model - H_meas| / |H_meas|`` of an FRF fit per top mass; returns the Axes.

    One curve per top mass (its first repetition; at most ``max_curves``, evenly picked),
    over ``band``: the quantity the Maxwell objective (7.5) averages, so a fit's error shows
    where in frequency it comes from.

    Parameters
    ----------
    model : GeneralizedMaxwell or VoigtModel
    frfs : sequence of TransmissibilitySet
    ax : Axes, optional
    band : (float, float)
        Frequency band in Hz.
    systematic : sequence of ResidualBand
        Bands where the residual is systematic (:func:`idkit.studies.residuals.systematic_residual_bands`),
        shaded and labelled.
    """
    from idkit.models.laws import sdof_transmissibility

    ax = axes_or_new(ax)
    first = {}
    for frf in frfs:
        first.setdefault(float(frf.mass), frf)
    masses = sorted(first)
    picks = np.unique(np.linspace(0, len(masses) - 1, min(max_curves, len(masses))).round().astype(int))
    for i in picks:
        frf = first[masses[i]]
        freq = np.asarray(frf.freq)
        inside = (freq >= band[0]) & (freq <= band[1])
        measured = np.asarray(frf.transmissibility)[inside]
        predicted = sdof_transmissibility(model.complex_stiffness(freq[inside]), masses[i] + model.m_eff,
                                          2 * np.pi * freq[inside])
        ax.semilogx(freq[inside], np.abs(predicted - measured) / np.abs(measured), lw=0.8,
                    label=f"{masses[i]:.2f} kg")
    for index, item in enumerate(systematic):
        ax.axvspan(item.low_hz, item.high_hz, color="0.85", zorder=0,
                   label="systematic residual" if index == 0 else None)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("|H_model - H_meas| / |H_meas| [-]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="x-small", ncol=2)
    return ax
