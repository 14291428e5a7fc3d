"""Figures of the design tool (pyplot imported lazily, figures returned, never shown)."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_pareto"]


def plot_pareto(table, *, best=None, ax=None):
    """Peak (else RMS) payload acceleration against isolator travel (else resonance) of every candidate.

    Candidates that meet every limit with the required probability are filled, the Pareto
    front joined by a line, the re-simulated top (``best``) circled. Returns the figure.
    """
    import matplotlib.pyplot as plt

    if ax is None:
        figure, ax = plt.subplots(figsize=(6.4, 4.4))
    else:
        figure = ax.figure
    use_peak = table["peak_acceleration_m_per_s2"].notna().any()
    acceleration = "peak_acceleration_m_per_s2" if use_peak else "rms_acceleration_m_per_s2"
    use_travel = table["max_deflection_m"].notna().any()
    deflection = "max_deflection_m" if use_travel else "resonance_hz"
    scale = 1e3 if use_travel else 1.0
    for verdict, style in (("meets", dict(marker="o", color="tab:green")),
                           ("meets on the mean model only", dict(marker="o", color="tab:orange")),
                           ("misses", dict(marker="x", color="tab:red"))):
        part = table[table["verdict"] == verdict]
        ax.scatter(scale * part[deflection], part[acceleration], s=18, label=verdict, **style)
    front = table[table["pareto"]].sort_values(deflection)
    ax.plot(scale * front[deflection], front[acceleration], color="0.3", lw=1, label="Pareto front")
    if best is not None and len(best):
        ax.scatter(scale * best[deflection], best[acceleration], s=120, facecolors="none", edgecolors="k",
                   label="re-simulated top")
    ax.set_xlabel("isolator travel under the drops [mm]" if use_travel else "first resonance [Hz]")
    ax.set_ylabel("peak payload acceleration [m/s^2]" if use_peak else "payload RMS acceleration [m/s^2]")
    if np.all(table[acceleration].dropna() > 0):
        ax.set_yscale("log")
    ax.legend(fontsize=8)
    ax.grid(True, alpha=0.3)
    figure.tight_layout()
    return figure
