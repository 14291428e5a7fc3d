"""The numerical studies of thesis chapters 3-5: wire rope, elastomer, hybrid (SPEC 2, 5).

``run_study(name, out_dir)`` simulates the study's systems and writes, into an output folder
that appears whole or not at all, the figures and the numbers behind them:

- ``wire-rope`` (chapter 3, Table A.1, 8 kg; symmetric and asymmetric): frequency-amplitude
  maps 1-100 Hz x 1e-5-1 m (symmetric) / 1e-5-1e-2 m (asymmetric): peak-peak/2 and first
  harmonic surfaces (figs. 3.7, 3.9, 3.12, 3.13), top views of the 2nd, 3rd and 1/2
  harmonics (3.11, 3.15, 3.16, 3.19), Bode cross sections at three amplitudes (3.10, 3.14),
  resonance versus amplitude; conditioned free falls versus |v0| and h: rest shock level,
  compression / tension peaks, peak deflection (3.21, A.7, A.8).
- ``elastomer`` (chapter 4, Table B.1 low / medium / high, 5 kg): complex stiffness and loss
  factor (4.3), transmissibility (4.4), resonance and damping ratios (-3 dB and eta/2), a
  time-domain check of the first HOSIDF against the transmissibility, rest shock level
  versus |v0| and h (4.5).
- ``hybrid`` (chapter 5, Table A.1 + Table B.1 medium, 2 kg + 0.02 kg; symmetric and
  asymmetric): maps as for the wire rope (5.2-5.6, 5.9-5.14), small-amplitude component
  stiffnesses and transmissibility (5.7, 5.8), shock with per-component deflection (5.15,
  5.16).

Chapters 3-5 have no random-vibration analysis (that is chapter 8, the transport study), so
these studies write no PSDs. Files: ``*.png`` figures, ``map_<case>.csv`` (long format,
:meth:`HarmonicMap.to_dataframe`), ``resonance_<case>.csv``, ``shock_<case>_velocity.csv`` /
``shock_<case>_height.csv``, ``linear_<case>.csv`` and ``summary.json`` (settings, key
numbers, timings). ``quick=True`` shrinks every grid (for tests and a first look).
"""

from __future__ import annotations

import json
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from idkit import __version__
from idkit.responses.harmonic_map import harmonic_map
from idkit.responses.linear import linear_frf
from idkit.responses.shock import shock_sweep
from idkit.errors import IdkitError
from idkit.models import library
from idkit.plot import (
    plot_complex_stiffness,
    plot_map_cross_sections,
    plot_map_surface,
    plot_map_top_view,
    plot_resonance_vs_amplitude,
    plot_shock_deflection,
    plot_shock_sweep,
    plot_transmissibility,
    save_figure,
)
from idkit.atomic import atomic_output_folder
from idkit.simulate import harmonic_response

__all__ = ["STUDY_NAMES", "StudyError", "run_study"]

STUDY_NAMES = ("wire-rope", "elastomer", "hybrid")


class StudyError(IdkitError, ValueError):
    """Unknown study name or unusable study settings."""


@dataclass(frozen=True)
class _Grid:
    freq: np.ndarray
    amplitude_symmetric: np.ndarray
    amplitude_asymmetric: np.ndarray
    n_drops: int
    n_heights: int
    max_periods: int


def _grid(quick: bool) -> _Grid:
    if quick:
        return _Grid(np.geomspace(1.0, 100.0, 8), np.geomspace(1e-5, 1.0, 4), np.geomspace(1e-5, 1e-2, 4),
                     n_drops=6, n_heights=4, max_periods=300)
    return _Grid(np.geomspace(1.0, 100.0, 50), np.geomspace(1e-5, 1.0, 30), np.geomspace(1e-5, 1e-2, 30),
                 n_drops=60, n_heights=25, max_periods=4000)


class _Progress:
    """Maps per-stage ``(done, total)`` calls onto one study-wide ``progress(done, total)``."""

    def __init__(self, callback, total: int):
        self.callback = callback
        self.total = int(total)
        self.offset = 0

    def stage(self, size: int):
        offset = self.offset
        self.offset += int(size)

        def report(done, _total):
            if self.callback is not None:
                self.callback(offset + int(done), self.total)

        return report

    def advance(self, size: int) -> None:
        self.stage(size)(size, size)


def _figure(nrows=1, ncols=1, *, figsize=(6.4, 4.8), **kwargs):
    from matplotlib.figure import Figure

    figure = Figure(figsize=figsize, layout="constrained")
    return figure, figure.subplots(nrows, ncols, **kwargs)


def _first_tension_speed(sweep) -> float | None:
    """Lowest speed from which on tension governs every faster drop (None if it never does)."""
    order = np.argsort(sweep.impact_speed)
    compression = np.flatnonzero(sweep.governing_phase[order] != "tension")
    if compression.size and compression[-1] == order.size - 1:
        return None
    start = compression[-1] + 1 if compression.size else 0
    return float(sweep.impact_speed[order][start])


def _map_case(folder: Path, case: str, system, amplitude, grid: _Grid, cross_amplitudes, progress, workers,
              timings: dict) -> dict:
    start = time.perf_counter()
    hmap = harmonic_map(system, grid.freq, amplitude, n_harmonics=3, max_periods=grid.max_periods,
                        workers=workers, progress=progress)
    timings[f"map_{case}"] = time.perf_counter() - start
    hmap.to_dataframe().to_csv(folder / f"map_{case}.csv", index=False)
    resonance = hmap.resonance_frequency()
    import pandas as pd

    pd.DataFrame({"amplitude_m": hmap.amplitude, "resonance_Hz": resonance}).to_csv(
        folder / f"resonance_{case}.csv", index=False)
    for quantity, tag in (("ratio", "ratio"), (1, "h1")):
        figure = _figure(figsize=(7.0, 5.5))[0]
        ax = figure.add_subplot(1, 1, 1, projection="3d")
        plot_map_surface(hmap, quantity, ax=ax)
        ax.set_title(f"{case}: {'peak-peak/2' if tag == 'ratio' else '1st harmonic'}", fontsize="small")
        save_figure(figure, folder / f"map_{case}_{tag}_surface.png")
    orders = [2, 3] + ([0.5] if "asymmetric" in case else [])
    figure, axes = _figure(1, len(orders), figsize=(5.0 * len(orders), 4.2))
    for ax, order in zip(np.atleast_1d(axes), orders):
        plot_map_top_view(hmap, order, ax=ax)
        ax.set_title(f"{case}: {'1/2 subharmonic' if order == 0.5 else f'harmonic {order}'}", fontsize="small")
    save_figure(figure, folder / f"map_{case}_top_views.png")
    figure, axes = _figure(2, 1, sharex=True)
    plot_map_cross_sections(hmap, cross_amplitudes, axes=axes)
    axes[0].set_title(f"{case}: 1st harmonic cross sections", fontsize="small")
    save_figure(figure, folder / f"cross_sections_{case}.png")
    figure, ax = _figure(figsize=(6.4, 4.0))
    plot_resonance_vs_amplitude(hmap, ax=ax)
    ax.set_title(f"{case}: resonance (peak of |H1|)", fontsize="small")
    save_figure(figure, folder / f"resonance_{case}.png")
    return {
        "points": int(hmap.converged.size), "converged": int(hmap.converged.sum()),
        "flagged": int((hmap.flags != 0).sum()),
        "resonance_Hz": {f"{a:.3g}": (None if np.isnan(f) else float(f)) for a, f in zip(hmap.amplitude, resonance)},
        "max_first_harmonic": float(np.nanmax(np.where(hmap.valid, hmap.magnitude(1), np.nan))),
    }


def _shock_case(folder: Path, case: str, system, max_speed: float, max_height: float, grid: _Grid, progress,
                workers, timings: dict):
    start = time.perf_counter()
    by_speed = shock_sweep(system, impact_velocity=-np.linspace(max_speed / grid.n_drops, max_speed, grid.n_drops),
                           workers=workers)
    progress.advance(grid.n_drops)
    by_height = shock_sweep(system, drop_height=np.linspace(max_height / grid.n_heights, max_height, grid.n_heights),
                            workers=workers)
    progress.advance(grid.n_heights)
    timings[f"shock_{case}"] = time.perf_counter() - start
    by_speed.to_dataframe().to_csv(folder / f"shock_{case}_velocity.csv", index=False)
    by_height.to_dataframe().to_csv(folder / f"shock_{case}_height.csv", index=False)
    summary = {
        "max_speed_m_s": max_speed, "max_height_m": max_height, "valid": int(by_speed.ok.sum() + by_height.ok.sum()),
        "runs": int(by_speed.ok.size + by_height.ok.size),
        "duration_s": by_speed.duration, "time_step_s": by_speed.time_step,
        "rest_shock_level_at_max_speed_m_s2": float(by_speed.rest_shock_level[-1]),
        "tension_governs_from_m_s": _first_tension_speed(by_speed),
    }
    return by_speed, by_height, summary


def _shock_figures(folder: Path, sweeps: dict) -> None:
    figure, axes = _figure(1, 2, figsize=(11.0, 4.2))
    for case, (by_speed, by_height) in sweeps.items():
        plot_shock_sweep(by_speed, label=case, ax=axes[0])
        plot_shock_sweep(by_height, versus="height", label=case, ax=axes[1])
    for ax in axes:
        ax.legend(fontsize="small")
    save_figure(figure, folder / "shock_rest_level.png")
    figure, axes = _figure(1, len(sweeps), figsize=(5.5 * len(sweeps), 4.2), squeeze=False)
    for ax, (case, (by_speed, _)) in zip(axes[0], sweeps.items()):
        plot_shock_sweep(by_speed, quantity="phases", ax=ax)
        ax.set_title(case, fontsize="small")
        ax.legend(fontsize="small")
    save_figure(figure, folder / "shock_phases.png")
    figure, axes = _figure(1, len(sweeps), figsize=(5.5 * len(sweeps), 4.2), squeeze=False)
    for ax, (case, (by_speed, _)) in zip(axes[0], sweeps.items()):
        plot_shock_deflection(by_speed, ax=ax)
        ax.set_title(case, fontsize="small")
        ax.legend(fontsize="small")
    save_figure(figure, folder / "shock_deflection.png")


def _nonlinear_study(folder, name, grid, progress, workers, timings, summary):
    cases = {
        "wire-rope": {"symmetric": "system_a1_symmetric", "asymmetric": "system_a1_asymmetric"},
        "hybrid": {"symmetric": "hybrid_symmetric", "asymmetric": "hybrid_asymmetric"},
    }[name]
    shock_range = {"wire-rope": (1.5, 0.05), "hybrid": (3.0, 0.25)}[name]
    sweeps = {}
    for symmetry, library_name in cases.items():
        system = library.get(library_name)
        amplitude = grid.amplitude_symmetric if symmetry == "symmetric" else grid.amplitude_asymmetric
        cross = (amplitude[0], amplitude[len(amplitude) // 2], amplitude[-1])
        case = f"{name}_{symmetry}"
        summary["cases"][case] = {
            "system": library.describe(library_name),
            "map": _map_case(folder, case, system, amplitude, grid, cross, progress.stage(amplitude.size * grid.freq.size),
                             workers, timings),
            "linear": linear_frf(system, [1.0]).resonance.to_dict(),
        }
        by_speed, by_height, shock_summary = _shock_case(folder, case, system, *shock_range, grid, progress, workers,
                                                         timings)
        summary["cases"][case]["shock"] = shock_summary
        sweeps[symmetry] = (by_speed, by_height)
    _shock_figures(folder, sweeps)
    if name == "hybrid":
        _hybrid_linear_figures(folder, library.get("hybrid_symmetric"))


def _hybrid_linear_figures(folder: Path, system) -> None:
    freq = np.geomspace(1e-2, 1e6, 600)
    frf = linear_frf(system, freq)
    frf.to_dataframe().to_csv(folder / "linear_hybrid.csv", index=False)
    figure, axes = _figure(2, 1, sharex=True, figsize=(6.4, 6.0))
    plot_complex_stiffness(freq, frf.component_stiffness[0], label="elastomer (Table B.1 medium)", axes=axes)
    plot_complex_stiffness(freq, frf.component_stiffness[1], label="wire rope, stuck (Table A.1)", axes=axes)
    plot_complex_stiffness(freq, frf.stiffness, label="hybrid (series)", axes=axes)
    axes[0].legend(fontsize="small")
    save_figure(figure, folder / "linear_hybrid_stiffness.png")
    figure, axes = _figure(2, 1, sharex=True, figsize=(6.4, 6.0))
    plot_transmissibility(frf, label="hybrid, small amplitude", axes=axes)
    axes[0].legend(fontsize="small")
    save_figure(figure, folder / "linear_hybrid_transmissibility.png")


def _elastomer_study(folder, grid, progress, workers, timings, summary, quick):
    import pandas as pd

    freq = np.geomspace(1e-2, 1e6, 200 if quick else 800)
    stiffness_fig, stiffness_axes = _figure(2, 1, sharex=True, figsize=(6.4, 6.0))
    frf_fig, frf_axes = _figure(2, 1, sharex=True, figsize=(6.4, 6.0))
    sweeps = {}
    check_freq = np.geomspace(1.0, 100.0, 5 if quick else 9)
    for variant in ("low", "medium", "high"):
        case = f"elastomer_{variant}"
        system = library.get(f"system_b1_{variant}")
        frf = linear_frf(system, freq)
        frf.to_dataframe().to_csv(folder / f"linear_{case}.csv", index=False)
        plot_complex_stiffness(freq, frf.stiffness, label=variant, axes=stiffness_axes)
        plot_transmissibility(frf, label=variant, axes=frf_axes)
        start = time.perf_counter()
        check = harmonic_response(system, check_freq, 1e-3, workers=workers)
        timings[f"harmonic_check_{case}"] = time.perf_counter() - start
        analytic = system.transmissibility(check_freq)
        deviation = np.abs(check.hosidf(1) - analytic) / np.abs(analytic)
        pd.DataFrame({"freq_Hz": check_freq, "H1_time_domain_magnitude": np.abs(check.hosidf(1)),
                      "H_linear_magnitude": np.abs(analytic), "relative_deviation": deviation}).to_csv(
            folder / f"harmonic_check_{case}.csv", index=False)
        progress.advance(check_freq.size)
        by_speed, by_height, shock_summary = _shock_case(folder, case, system, 1.5, 0.1, grid, progress, workers,
                                                         timings)
        sweeps[variant] = (by_speed, by_height)
        summary["cases"][case] = {
            "system": library.describe(f"system_b1_{variant}"),
            "linear": frf.resonance.to_dict(),
            "harmonic_check_max_relative_deviation": float(deviation.max()),
            "shock": shock_summary,
            "shock_slope_s^-1": float(np.polyfit(by_speed.impact_speed, by_speed.rest_shock_level, 1)[0]),
        }
    stiffness_axes[0].legend(fontsize="small", title="Table B.1")
    frf_axes[0].legend(fontsize="small", title="Table B.1, 5 kg")
    save_figure(stiffness_fig, folder / "elastomer_complex_stiffness.png")
    save_figure(frf_fig, folder / "elastomer_transmissibility.png")
    figure, axes = _figure(1, 2, figsize=(11.0, 4.2))
    for variant, (by_speed, by_height) in sweeps.items():
        plot_shock_sweep(by_speed, label=variant, ax=axes[0])
        plot_shock_sweep(by_height, versus="height", label=variant, ax=axes[1])
    for ax in axes:
        ax.legend(fontsize="small")
    save_figure(figure, folder / "shock_rest_level.png")


def _total_work(name: str, grid: _Grid, quick: bool) -> int:
    shocks = grid.n_drops + grid.n_heights
    if name == "elastomer":
        return 3 * ((5 if quick else 9) + shocks)
    return grid.freq.size * (grid.amplitude_symmetric.size + grid.amplitude_asymmetric.size) + 2 * shocks


def run_study(name: str, out_dir, *, force: bool = False, quick: bool = False, workers: int | None = None,
              progress=None) -> dict:
    """Run the chapter 3 (``"wire-rope"``), 4 (``"elastomer"``) or 5 (``"hybrid"``) study.

    Parameters
    ----------
    name : {"wire-rope", "elastomer", "hybrid"}
    out_dir : path
        Output folder; must not exist unless ``force``. Written atomically.
    force : bool
        Replace an existing folder.
    quick : bool
        Small grids (8 frequencies x 4 amplitudes, 6 + 4 drops per case, at most 300 periods
        per harmonic point): seconds instead of minutes.
    workers : int, optional
        Threads for the simulations (default: all usable cores).
    progress : callable(done, total), optional
        Study-wide progress in work units (harmonic points and drops), e.g.
        :class:`idkit.cli.progress.ProgressBar`.

    Returns
    -------
    dict
        The content of ``summary.json``.
    """
    if name not in STUDY_NAMES:
        raise StudyError(f"study: found {name!r}, expected one of {list(STUDY_NAMES)}")
    grid = _grid(quick)
    tracker = _Progress(progress, _total_work(name, grid, quick))
    timings: dict = {}
    summary: dict = {
        "study": name, "idkit_version": __version__, "quick": bool(quick),
        "grid": {"freq_Hz": [float(grid.freq[0]), float(grid.freq[-1]), int(grid.freq.size)],
                 "amplitude_symmetric_m": [float(grid.amplitude_symmetric[0]), float(grid.amplitude_symmetric[-1]),
                                           int(grid.amplitude_symmetric.size)],
                 "amplitude_asymmetric_m": [float(grid.amplitude_asymmetric[0]),
                                            float(grid.amplitude_asymmetric[-1]), int(grid.amplitude_asymmetric.size)],
                 "max_periods": grid.max_periods, "steady_state_tolerance": 1e-3},
        "cases": {},
    }
    started = time.perf_counter()
    with atomic_output_folder(out_dir, force=force) as folder:
        if name == "elastomer":
            _elastomer_study(folder, grid, tracker, workers, timings, summary, quick)
        else:
            _nonlinear_study(folder, name, grid, tracker, workers, timings, summary)
        timings["total"] = time.perf_counter() - started
        summary["timings_s"] = {key: round(value, 3) for key, value in timings.items()}
        summary["files"] = sorted(path.name for path in folder.iterdir()) + ["summary.json"]
        (folder / "summary.json").write_text(json.dumps(summary, indent=1) + "\n")
    return summary
