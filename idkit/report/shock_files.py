"""Write a :class:`idkit.studies.shock.ShockAnalysis` into a folder: tables and figures.

Files (written into a staging folder that replaces the target only when complete):
``pulses.csv``, ``spectra.csv``, ``ratio_<channel>.csv``; for every channel
``<channel>_pulses.{png,svg}`` and ``<channel>_srs.{png,svg}`` (pseudo-velocity, absolute
acceleration and relative displacement SRS); ``<channel>_ratio.{png,svg}`` with an input.
"""

from __future__ import annotations

import re
from pathlib import Path

import pandas as pd

from idkit.atomic import atomic_output_folder, write_text_atomic
from idkit.plot._figure import new_axes, save_figure
from idkit.plot.shock import plot_response_ratio, plot_shock_pulses, plot_shock_spectra

__all__ = ["write_shock_analysis"]


def _stem(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name) or "record"


def write_shock_analysis(analysis, folder, *, force: bool = False) -> list[Path]:
    """Write tables and figures of ``analysis`` into ``folder`` (replaced only with ``force``)."""
    written = []
    with atomic_output_folder(folder, force=force) as staging:
        tables = {"pulses.csv": analysis.pulse_table(),
                  "spectra.csv": pd.concat([s.to_dataframe() for s in analysis.spectra], ignore_index=True)}
        for ratio in analysis.ratios:
            tables[f"ratio_{_stem(ratio.response_channel)}.csv"] = ratio.to_dataframe()
        for name, frame in tables.items():
            write_text_atomic(staging / name, frame.to_csv(index=False))
            written.append(Path(folder) / name)
        for shock, spectra in zip(analysis.conditioned, analysis.spectra):
            stem = _stem(shock.record.channel)
            figure = plot_shock_pulses(shock.record, ax=new_axes(figsize=(6.4, 4.0))).figure
            srs_axes = new_axes(3, 1, sharex=True, figsize=(6.4, 9.6))
            for ax, kind in zip(srs_axes, ("pseudo_velocity", "absolute_acceleration", "relative_displacement")):
                plot_shock_spectra(spectra, kind=kind, ax=ax)
            figure_srs = srs_axes[0].figure
            for suffix in ("png", "svg"):
                for fig, name in ((figure, f"{stem}_pulses.{suffix}"), (figure_srs, f"{stem}_srs.{suffix}")):
                    save_figure(fig, staging / name)
                    written.append(Path(folder) / name)
        for ratio in analysis.ratios:
            figure = plot_response_ratio(ratio, ax=new_axes(figsize=(6.4, 4.0))).figure
            for suffix in ("png", "svg"):
                name = f"{_stem(ratio.response_channel)}_ratio.{suffix}"
                save_figure(figure, staging / name)
                written.append(Path(folder) / name)
    return written
