"""Overview figures of ``idkit inspect --plots``: one per measurement kind.

Each function takes observables (:class:`idkit.studies.inspection.InspectionOverview`
entries), draws into ``ax``/``axes`` (default: a new figure from :mod:`idkit.plot._figure`)
and returns the Axes.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from idkit.plot._figure import axes_or_new
from idkit.plot.basic import plot_loops, plot_shock_levels

if TYPE_CHECKING:
    from idkit.observe.stepped_sine import SteppedSineSweep
    from idkit.studies.inspection import InspectionOverview

__all__ = [
    "overview_figures",
    "plot_drop_overview",
    "plot_quasi_static_overview",
    "plot_stepped_sine_overview",
    "plot_white_noise_overview",
]

# at most this many records get a legend entry (every sweep and drop group always does)
_LEGEND_LIMIT = 12


def plot_quasi_static_overview(measurements, *, ax=None):
    """Force-deflection loops of every quasi-static record as recorded; returns the Axes."""
    ax = axes_or_new(ax)
    for measurement in measurements:
        plot_loops(measurement.deflection, measurement.force, label=measurement.id, ax=ax)
    ax.set_title("quasi-static loops")
    if len(measurements) <= _LEGEND_LIMIT:
        ax.legend(fontsize="x-small")
    return ax


def plot_white_noise_overview(frfs, *, axes=None):
    """|H1| (log-log) and coherence of every white-noise run (:class:`~idkit.observe.white_noise.WhiteNoiseFrf`).

    Returns
    -------
    (Axes, Axes)
    """
    axes = axes_or_new(axes, 2, sharex=True)
    for frf in frfs:
        axes[0].loglog(frf.freq, np.abs(frf.h1), lw=0.8, label=frf.measurement_id)
        axes[1].semilogx(frf.freq, frf.coherence, lw=0.8)
    axes[0].set_ylabel("|H1| [-]")
    axes[1].set_ylabel("coherence [-]")
    axes[1].set_xlabel("frequency [Hz]")
    axes[0].set_title("white noise: transmissibility v_top / v_base")
    if len(frfs) <= _LEGEND_LIMIT:
        axes[0].legend(fontsize="x-small")
    return axes


def plot_stepped_sine_overview(sweep: SteppedSineSweep, *, axes=None):
    """Base first-harmonic amplitude and |HOSIDF 1| versus frequency, one line per sweep.

    Returns
    -------
    (Axes, Axes)
    """
    axes = axes_or_new(axes, 2, sharex=True)
    for (isolator, mass, nominal), flat in sweep.flatness.items():
        axes[0].loglog(flat.freq, flat.amplitude, marker=".", label=f"{isolator} {mass} kg, {nominal:g}")
        points = sorted((p for p in sweep.points if (p.isolator, p.top_mass_kg, p.nominal_amplitude)
                         == (isolator, mass, nominal)), key=lambda p: p.freq)
        axes[1].loglog([p.freq for p in points], [abs(p.hosidf[0]) for p in points], marker=".")
    axes[0].set_ylabel("base 1st harmonic")
    axes[1].set_ylabel("|HOSIDF 1| [-]")
    axes[1].set_xlabel("frequency [Hz]")
    axes[0].set_title("stepped sine: input amplitude and first HOSIDF")
    axes[0].legend(fontsize="x-small")
    return axes


def plot_drop_overview(groups: dict, *, ax=None):
    """Rest shock level versus impact speed of measured drops, one line per (isolator, top mass).

    Parameters
    ----------
    groups : dict
        ``{(isolator, top mass kg): [DropMeasurementResult, ...]}`` sorted by impact speed.

    Returns
    -------
    Axes
    """
    ax = axes_or_new(ax)
    for (isolator, mass), results in groups.items():
        plot_shock_levels([abs(r.impact_velocity) for r in results], [r.peak_acceleration for r in results],
                          label=f"{isolator} {mass} kg", ax=ax)
    ax.set_title("drops: rest shock level")
    ax.legend(fontsize="x-small")
    return ax


def overview_figures(overview: InspectionOverview) -> dict:
    """One figure per kind present, keyed by kind.

    Returns
    -------
    dict of str to Figure
    """
    figures = {}
    if overview.drop is not None:
        figures["drop"] = plot_drop_overview(overview.drop).figure
    if overview.quasi_static is not None:
        figures["quasi_static"] = plot_quasi_static_overview(overview.quasi_static).figure
    if overview.stepped_sine is not None:
        figures["stepped_sine"] = plot_stepped_sine_overview(overview.stepped_sine)[0].figure
    if overview.white_noise is not None:
        figures["white_noise"] = plot_white_noise_overview(overview.white_noise)[0].figure
    return figures
