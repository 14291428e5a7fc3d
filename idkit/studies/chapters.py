"""The numerical studies of thesis chapters 3-5: wire rope, elastomer, hybrid (SPEC 2, 5).

Compute only: :func:`compute_chapter_study` simulates a study's systems and returns a typed
:class:`ChapterStudy`; the figures are drawn by :mod:`idkit.plot.studies` and the files
written by :mod:`idkit.report.study_files` (``idkit study NAME``).

- ``wire-rope`` (chapter 3, Table A.1, 8 kg; symmetric and asymmetric): frequency-amplitude
  maps 1-100 Hz x 1e-5-1 m (symmetric) / 1e-5-1e-2 m (asymmetric) (figs. 3.7, 3.9,
  3.11-3.16, 3.19), resonance versus amplitude, the small-amplitude linear resonance;
  conditioned free falls versus |v0| and h: rest shock level, compression / tension peaks,
  peak deflection (3.21, A.7, A.8).
- ``elastomer`` (chapter 4, Table B.1 low / medium / high, 5 kg): linear complex stiffness
  and transmissibility with resonance and damping ratios (4.3, 4.4), a time-domain check
  of the first HOSIDF against the transmissibility, rest shock level versus |v0| and h (4.5).
- ``hybrid`` (chapter 5, Table A.1 + Table B.1 medium, 2 kg + 0.02 kg; symmetric and
  asymmetric): maps and shock as for the wire rope (5.2-5.6, 5.9-5.16), and the
  small-amplitude component stiffnesses and transmissibility (5.7, 5.8).

Chapters 3-5 have no random-vibration analysis (that is chapter 8, :mod:`idkit.studies.transport`).
``quick=True`` shrinks every grid (for tests and a first look).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit import __version__
from idkit.checks import Choice, Flag, accepts
from idkit.errors import IdkitError
from idkit.models import library
from idkit.responses.harmonic_map import HarmonicMap, harmonic_map
from idkit.responses.linear import LinearFrf, linear_frf
from idkit.responses.shock import ShockSweep, shock_sweep
from idkit.simulate import harmonic_response

__all__ = [
    "STUDY_NAMES",
    "ChapterStudy",
    "ElastomerCase",
    "MapCase",
    "ShockCase",
    "StudyError",
    "StudyGrid",
    "compute_chapter_study",
    "study_grid",
]

STUDY_NAMES = ("wire-rope", "elastomer", "hybrid")

#: steady-state tolerance of every harmonic map point (relative change per period)
STEADY_STATE_TOLERANCE = 1e-3


class StudyError(IdkitError, ValueError):
    """Unknown study name or unusable study settings."""


@dataclass(frozen=True)
class StudyGrid:
    """Grids of a chapter study.

    Attributes
    ----------
    freq : ndarray
        Map frequencies in Hz.
    amplitude_symmetric, amplitude_asymmetric : ndarray
        Map base amplitudes in m of the symmetric and asymmetric systems.
    n_drops, n_heights : int
        Drops per shock sweep versus |v0| and versus h.
    max_periods : int
        Cap on simulated periods per map point.
    check_points : int
        Frequencies of the elastomer's time-domain HOSIDF check.
    linear_points : int
        Frequencies of the elastomer's linear FRF (1e-2-1e6 Hz).
    """

    freq: np.ndarray
    amplitude_symmetric: np.ndarray
    amplitude_asymmetric: np.ndarray
    n_drops: int
    n_heights: int
    max_periods: int
    check_points: int
    linear_points: int

    def to_dict(self) -> dict:
        """First value, last value and count of each axis (``summary.json``)."""

        def axis(values):
            return [float(values[0]), float(values[-1]), int(values.size)]

        return {"freq_Hz": axis(self.freq), "amplitude_symmetric_m": axis(self.amplitude_symmetric),
                "amplitude_asymmetric_m": axis(self.amplitude_asymmetric), "max_periods": self.max_periods,
                "steady_state_tolerance": STEADY_STATE_TOLERANCE}


def study_grid(quick: bool) -> StudyGrid:
    """The full grids (50 x 30 map points, 60 + 25 drops) or the quick ones (8 x 4, 6 + 4)."""
    if quick:
        return StudyGrid(np.geomspace(1.0, 100.0, 8), np.geomspace(1e-5, 1.0, 4), np.geomspace(1e-5, 1e-2, 4),
                         n_drops=6, n_heights=4, max_periods=300, check_points=5, linear_points=200)
    return StudyGrid(np.geomspace(1.0, 100.0, 50), np.geomspace(1e-5, 1.0, 30), np.geomspace(1e-5, 1e-2, 30),
                     n_drops=60, n_heights=25, max_periods=4000, check_points=9, linear_points=800)


@dataclass(frozen=True)
class ShockCase:
    """Conditioned free falls of one system versus impact speed and versus drop height.

    Attributes
    ----------
    by_speed, by_height : ShockSweep
    max_speed : float
        Highest impact speed |v0| in m/s.
    max_height : float
        Highest drop height in m.
    seconds : float
        Wall time of the two sweeps.
    """

    by_speed: ShockSweep
    by_height: ShockSweep
    max_speed: float
    max_height: float
    seconds: float = 0.0

    @property
    def tension_governs_from(self) -> float | None:
        """Lowest |v0| (m/s) from which on tension governs every faster drop (None if it never does)."""
        sweep = self.by_speed
        order = np.argsort(sweep.impact_speed)
        compression = np.flatnonzero(sweep.governing_phase[order] != "tension")
        if compression.size and compression[-1] == order.size - 1:
            return None
        start = compression[-1] + 1 if compression.size else 0
        return float(sweep.impact_speed[order][start])

    @property
    def rest_shock_slope(self) -> float:
        """Least-squares slope of the rest shock level over |v0|, 1/s."""
        return float(np.polyfit(self.by_speed.impact_speed, self.by_speed.rest_shock_level, 1)[0])

    def summary(self) -> dict:
        """Key numbers (``summary.json``)."""
        return {
            "max_speed_m_s": self.max_speed, "max_height_m": self.max_height,
            "valid": int(self.by_speed.ok.sum() + self.by_height.ok.sum()),
            "runs": int(self.by_speed.ok.size + self.by_height.ok.size),
            "duration_s": self.by_speed.duration, "time_step_s": self.by_speed.time_step,
            "rest_shock_level_at_max_speed_m_s2": float(self.by_speed.rest_shock_level[-1]),
            "tension_governs_from_m_s": self.tension_governs_from,
        }


@dataclass(frozen=True)
class MapCase:
    """One nonlinear system of the wire-rope or hybrid study.

    Attributes
    ----------
    name : str
        ``"<study>_<symmetric|asymmetric>"``.
    symmetry : {"symmetric", "asymmetric"}
    description : str
        The library's description of the system.
    hmap : HarmonicMap
    cross_amplitudes : tuple of float
        Amplitudes (m) of the Bode cross sections (first, middle and last of the grid).
    linear : LinearFrf
        Small-amplitude response at 1 Hz (its resonance).
    shock : ShockCase
    map_seconds : float
        Wall time of the harmonic map.
    """

    name: str
    symmetry: str
    description: str
    hmap: HarmonicMap
    cross_amplitudes: tuple[float, ...]
    linear: LinearFrf
    shock: ShockCase
    map_seconds: float = 0.0

    @property
    def timings_s(self) -> dict[str, float]:
        """Wall time of the map and of the shock sweeps, s."""
        return {f"map_{self.name}": self.map_seconds, f"shock_{self.name}": self.shock.seconds}

    @property
    def top_view_orders(self) -> tuple[float, ...]:
        """Harmonic orders shown as top views: 2 and 3, and 1/2 for an asymmetric system."""
        return (2, 3, 0.5) if self.symmetry == "asymmetric" else (2, 3)

    def resonance_table(self) -> pd.DataFrame:
        """Resonance (peak of |H1|) per base amplitude."""
        return pd.DataFrame({"amplitude [m]": self.hmap.amplitude, "resonance [Hz]": self.hmap.resonance_frequency()})

    def summary(self) -> dict:
        """Key numbers (``summary.json``)."""
        hmap = self.hmap
        resonance = hmap.resonance_frequency()
        return {
            "system": self.description,
            "map": {
                "points": int(hmap.converged.size), "converged": int(hmap.converged.sum()),
                "flagged": int((hmap.flags != 0).sum()),
                "resonance_Hz": {f"{a:.3g}": (None if np.isnan(f) else float(f))
                                 for a, f in zip(hmap.amplitude, resonance)},
                "max_first_harmonic": float(np.nanmax(np.where(hmap.valid, hmap.magnitude(1), np.nan))),
            },
            "linear": self.linear.resonance.to_dict(),
            "shock": self.shock.summary(),
        }


@dataclass(frozen=True)
class ElastomerCase:
    """One Table B.1 elastomer on 5 kg.

    Attributes
    ----------
    name : str
        ``"elastomer_<variant>"``.
    variant : {"low", "medium", "high"}
    description : str
    frf : LinearFrf
        Linear complex stiffness and transmissibility, 1e-2-1e6 Hz.
    check_freq : ndarray
        Frequencies (Hz) of the time-domain check.
    check_hosidf : ndarray of complex
        First HOSIDF of the simulated steady state at 1 mm.
    check_linear : ndarray of complex
        The linear transmissibility at ``check_freq``.
    shock : ShockCase
    check_seconds : float
        Wall time of the time-domain check.
    """

    name: str
    variant: str
    description: str
    frf: LinearFrf
    check_freq: np.ndarray
    check_hosidf: np.ndarray
    check_linear: np.ndarray
    shock: ShockCase
    check_seconds: float = 0.0

    @property
    def timings_s(self) -> dict[str, float]:
        """Wall time of the time-domain check and of the shock sweeps, s."""
        return {f"harmonic_check_{self.name}": self.check_seconds, f"shock_{self.name}": self.shock.seconds}

    @property
    def check_deviation(self) -> np.ndarray:
        """|H1 (time domain) - H (linear)| / |H (linear)| per check frequency."""
        return np.abs(self.check_hosidf - self.check_linear) / np.abs(self.check_linear)

    def harmonic_check_table(self) -> pd.DataFrame:
        """The time-domain check, one row per frequency."""
        return pd.DataFrame({"freq [Hz]": self.check_freq, "|H1| time domain [-]": np.abs(self.check_hosidf),
                             "|H| linear [-]": np.abs(self.check_linear),
                             "relative deviation [-]": self.check_deviation})

    def summary(self) -> dict:
        """Key numbers (``summary.json``)."""
        return {
            "system": self.description, "linear": self.frf.resonance.to_dict(),
            "harmonic_check_max_relative_deviation": float(self.check_deviation.max()),
            "shock": self.shock.summary(), "shock_slope_s^-1": self.shock.rest_shock_slope,
        }


@dataclass(frozen=True)
class ChapterStudy:
    """The result of one chapter study.

    Attributes
    ----------
    name : {"wire-rope", "elastomer", "hybrid"}
    quick : bool
    grid : StudyGrid
    cases : tuple of MapCase or of ElastomerCase
    hybrid_linear : LinearFrf or None
        Hybrid study: the symmetric hybrid's small-amplitude response, 1e-2-1e6 Hz.
    total_seconds : float
        Wall time of the whole computation.
    """

    name: str
    quick: bool
    grid: StudyGrid
    cases: tuple[MapCase, ...] | tuple[ElastomerCase, ...]
    hybrid_linear: LinearFrf | None = None
    total_seconds: float = 0.0

    @property
    def timings_s(self) -> dict[str, float]:
        """Seconds per computing stage (maps, checks, shock sweeps) and in total."""
        timings: dict[str, float] = {}
        for case in self.cases:
            timings.update(case.timings_s)
        return {**timings, "total": self.total_seconds}

    def case(self, name: str) -> MapCase | ElastomerCase:
        """The case called ``name``."""
        for case in self.cases:
            if case.name == name:
                return case
        raise StudyError(f"case: found {name!r}, expected one of {[c.name for c in self.cases]}")

    def summary(self) -> dict:
        """Settings, key numbers and timings (the content of ``summary.json`` without its file list)."""
        return {
            "study": self.name, "idkit_version": __version__, "quick": bool(self.quick), "grid": self.grid.to_dict(),
            "cases": {case.name: case.summary() for case in self.cases},
            "timings_s": {key: round(value, 3) for key, value in self.timings_s.items()},
        }


class _Progress:
    """Maps per-stage ``(done, total)`` calls onto one study-wide ``progress(done, total)``."""

    def __init__(self, callback: Callable[[int, int], None] | None, total: int):
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


def _total_work(name: str, grid: StudyGrid) -> int:
    shocks = grid.n_drops + grid.n_heights
    if name == "elastomer":
        return 3 * (grid.check_points + shocks)
    return grid.freq.size * (grid.amplitude_symmetric.size + grid.amplitude_asymmetric.size) + 2 * shocks


def _shock_case(system, max_speed: float, max_height: float, grid: StudyGrid, progress: _Progress,
                workers) -> ShockCase:
    start = time.perf_counter()
    by_speed = shock_sweep(system, impact_velocity=-np.linspace(max_speed / grid.n_drops, max_speed, grid.n_drops),
                           workers=workers)
    progress.advance(grid.n_drops)
    by_height = shock_sweep(system, drop_height=np.linspace(max_height / grid.n_heights, max_height, grid.n_heights),
                            workers=workers)
    progress.advance(grid.n_heights)
    return ShockCase(by_speed, by_height, float(max_speed), float(max_height), time.perf_counter() - start)


# library names of the nonlinear studies' systems and the ranges of their shock sweeps (|v0| m/s, h m)
_MAP_SYSTEMS = {
    "wire-rope": {"symmetric": "system_a1_symmetric", "asymmetric": "system_a1_asymmetric"},
    "hybrid": {"symmetric": "hybrid_symmetric", "asymmetric": "hybrid_asymmetric"},
}
_SHOCK_RANGE = {"wire-rope": (1.5, 0.05), "hybrid": (3.0, 0.25), "elastomer": (1.5, 0.1)}


def _map_cases(name: str, grid: StudyGrid, progress: _Progress, workers) -> tuple[MapCase, ...]:
    cases = []
    for symmetry, library_name in _MAP_SYSTEMS[name].items():
        system = library.get(library_name)
        amplitude = grid.amplitude_symmetric if symmetry == "symmetric" else grid.amplitude_asymmetric
        case = f"{name}_{symmetry}"
        start = time.perf_counter()
        hmap = harmonic_map(system, grid.freq, amplitude, n_harmonics=3, max_periods=grid.max_periods,
                            tolerance=STEADY_STATE_TOLERANCE, workers=workers,
                            progress=progress.stage(amplitude.size * grid.freq.size))
        map_seconds = time.perf_counter() - start
        cross = (float(amplitude[0]), float(amplitude[len(amplitude) // 2]), float(amplitude[-1]))
        shock = _shock_case(system, *_SHOCK_RANGE[name], grid, progress, workers)
        cases.append(MapCase(case, symmetry, library.describe(library_name), hmap, cross,
                             linear_frf(system, [1.0]), shock, map_seconds))
    return tuple(cases)


def _elastomer_cases(grid: StudyGrid, progress: _Progress, workers) -> tuple[ElastomerCase, ...]:
    freq = np.geomspace(1e-2, 1e6, grid.linear_points)
    check_freq = np.geomspace(1.0, 100.0, grid.check_points)
    cases = []
    for variant in ("low", "medium", "high"):
        case = f"elastomer_{variant}"
        library_name = f"system_b1_{variant}"
        system = library.get(library_name)
        start = time.perf_counter()
        check = harmonic_response(system, check_freq, 1e-3, workers=workers)
        check_seconds = time.perf_counter() - start
        progress.advance(check_freq.size)
        shock = _shock_case(system, *_SHOCK_RANGE["elastomer"], grid, progress, workers)
        cases.append(ElastomerCase(case, variant, library.describe(library_name), linear_frf(system, freq),
                                   check_freq, check.hosidf(1), system.transmissibility(check_freq), shock,
                                   check_seconds))
    return tuple(cases)


@accepts(name=Choice(STUDY_NAMES), quick=Flag(), error=StudyError)
def compute_chapter_study(name: str, *, quick: bool = False, workers: int | None = None,
                          progress: Callable[[int, int], None] | None = None) -> ChapterStudy:
    """Simulate the chapter 3 (``"wire-rope"``), 4 (``"elastomer"``) or 5 (``"hybrid"``) study.

    Parameters
    ----------
    name : {"wire-rope", "elastomer", "hybrid"}
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
    ChapterStudy

    Raises
    ------
    StudyError
        ``name`` is not one of :data:`STUDY_NAMES`, or ``quick`` is not a bool.
    """
    grid = study_grid(quick)
    tracker = _Progress(progress, _total_work(name, grid))
    started = time.perf_counter()
    if name == "elastomer":
        cases = _elastomer_cases(grid, tracker, workers)
        hybrid_linear = None
    else:
        cases = _map_cases(name, grid, tracker, workers)
        hybrid_linear = linear_frf(library.get("hybrid_symmetric"), np.geomspace(1e-2, 1e6, 600)) \
            if name == "hybrid" else None
    return ChapterStudy(name, bool(quick), grid, cases, hybrid_linear, time.perf_counter() - started)
