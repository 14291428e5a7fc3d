"""Figures of shock records: the pulses and their shock response spectra.

Compute with :mod:`idkit.observe.shock`, draw here. Each function takes ``ax=None`` (a new
:class:`matplotlib.figure.Figure` without pyplot) and returns the Axes it drew on.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from idkit.plot._figure import axes_or_new

if TYPE_CHECKING:
    from idkit.io import AccelerationRecord
    from idkit.observe.shock import RecordSpectra, ResponseRatio

__all__ = ["plot_shock_pulses", "plot_shock_spectra", "plot_response_ratio"]

#: Labels of the three ISO 18431-4 spectra: attribute, axis label.
SPECTRA = {
    "absolute_acceleration": ("absolute acceleration", "peak absolute acceleration [g]", 1 / 9.80665),
    "pseudo_velocity": ("pseudo-velocity", "pseudo-velocity [m/s]", 1.0),
    "relative_displacement": ("relative displacement", "peak relative displacement [mm]", 1e3),
}


def plot_shock_pulses(record: AccelerationRecord, *, ax=None):
    """Acceleration (g) versus time (ms) of every test of a record; returns the Axes."""
    ax = axes_or_new(ax, figsize=(6.4, 4.2))
    time_ms = (np.asarray(record.time) - record.time[0]) * 1e3
    for j in range(record.n_tests):
        ax.plot(time_ms, record.accel[:, j] / 9.80665, lw=0.8, label=f"test {j + 1}")
    ax.set_xlabel("time [ms]")
    ax.set_ylabel("acceleration [g]")
    ax.set_title(record.channel or "shock record")
    ax.grid(True, alpha=0.3)
    if record.n_tests <= 6:
        ax.legend(fontsize="small")
    return ax


def plot_shock_spectra(spectra: RecordSpectra, *, kind: str = "pseudo_velocity", ax=None):
    """One ISO 18431-4 spectrum of every test on log-log axes; returns the Axes.

    ``kind`` is ``"absolute_acceleration"`` (g), ``"pseudo_velocity"`` (m/s) or
    ``"relative_displacement"`` (mm).
    """
    if kind not in SPECTRA:
        raise ValueError(f"kind: found {kind!r}, expected one of {sorted(SPECTRA)}")
    name, label, scale = SPECTRA[kind]
    ax = axes_or_new(ax, figsize=(6.4, 4.2))
    for j, spectrum in enumerate(spectra.spectra):
        ax.loglog(spectrum.freq, getattr(spectrum, kind) * scale, label=f"test {j + 1}")
    damping = spectra.spectra[0].damping_ratio
    ax.set_xlabel("natural frequency [Hz]")
    ax.set_ylabel(label)
    ax.set_title(f"{spectra.channel or 'record'}: {name} SRS, damping ratio {damping:g}")
    ax.grid(True, which="both", alpha=0.3)
    if len(spectra.spectra) <= 6:
        ax.legend(fontsize="small")
    return ax


def plot_response_ratio(ratio: ResponseRatio, *, ax=None):
    """Response SRS over input SRS per test (log frequency); returns the Axes."""
    ax = axes_or_new(ax, figsize=(6.4, 4.2))
    for j, row in enumerate(ratio.ratio):
        ax.semilogx(ratio.freq, row, label=f"test {j + 1}")
    ax.axhline(1.0, color="0.5", lw=0.8)
    ax.set_xlabel("natural frequency [Hz]")
    ax.set_ylabel("SRS ratio [-]")
    ax.set_title(f"{ratio.response_channel} over {ratio.input_channel}")
    ax.grid(True, which="both", alpha=0.3)
    if ratio.ratio.shape[0] <= 6:
        ax.legend(fontsize="small")
    return ax
