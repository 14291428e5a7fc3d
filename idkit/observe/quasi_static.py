"""Quasi-static records -> cycles, amplitudes and resampled loops (SPEC 4)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.signal.cycles import (
    CycleSplit,
    noise_level,
    resample_loops,
    ResampledLoops,
    reversal_threshold,
    split_cycles,
)
from idkit.io import (
    QuasiStaticMeasurement,
)
from idkit.observe._common import _require


# ---------------------------------------------------------------------------------------------
# quasi-static


@dataclass(frozen=True)
class QuasiStaticResult:
    """Cycles and resampled loops of one quasi-static measurement.

    Attributes
    ----------
    measurement_id : str
        ``info.id`` of the measurement.
    cycles : CycleSplit
        Reversals, branches, cycles, amplitudes (m) and the small/large flags.
    loops : ResampledLoops
        Every complete branch resampled to ``points_per_branch`` points (deflection m, force N).
    min_excursion : float
        Reversal threshold used, m.
    deflection_noise : float
        Estimated deflection noise standard deviation, m (:func:`noise_level`).
    """

    measurement_id: str
    cycles: CycleSplit
    loops: ResampledLoops
    min_excursion: float
    deflection_noise: float

    @property
    def n_cycles(self) -> int:
        """Number of complete cycles."""
        return self.cycles.n_cycles

    @property
    def amplitude(self) -> np.ndarray:
        """Cycle amplitudes, m."""
        return self.cycles.amplitude

    @property
    def is_large(self) -> np.ndarray:
        """Large-cycle flags (all false without a threshold)."""
        return self.cycles.is_large

    def to_dataframe(self) -> pd.DataFrame:
        """One row per cycle (see :meth:`CycleSplit.to_dataframe`) with the measurement id."""
        table = self.cycles.to_dataframe()
        table.insert(0, "measurement_id", self.measurement_id)
        return table

    def report(self) -> str:
        """Short text summary."""
        amp = self.amplitude * 1e3
        span = f"{amp.min():.3g}-{amp.max():.3g} mm" if amp.size else "none"
        return (f"{self.measurement_id}: {self.n_cycles} cycles, amplitudes {span}, "
                f"{int(self.is_large.sum())} large; min_excursion {self.min_excursion * 1e6:.3g} um, "
                f"deflection noise {self.deflection_noise * 1e6:.3g} um")


def process_quasi_static(measurement: QuasiStaticMeasurement, *,
                         min_excursion: float | None = None,
                         large_threshold: float | None = None,
                         points_per_branch: int = 100,
                         spacing: str = "deflection") -> QuasiStaticResult:
    """Split a quasi-static record into cycles and resample its loops (SPEC 4, eq. 7.1).

    Parameters
    ----------
    measurement : QuasiStaticMeasurement
        Force-deflection record.
    min_excursion : float, optional
        Reversal threshold in m (:func:`~idkit.signal.cycles.find_reversals`). Default
        ``max(10 * noise, 1e-3 * range)``: ten times the estimated deflection noise
        (:func:`noise_level`), at least a thousandth of the deflection range; well below the
        smallest loop of SPEC 3 (0.05 mm amplitude) for a micrometre-level sensor.
    large_threshold : float, optional
        Amplitude in m above which a cycle is "large"; e.g. 4.5e-3 m for the wire-rope sets.
    points_per_branch : int, default 100
        Points per resampled branch, reversals included.
    spacing : {"deflection", "index"}
        Spacing of the resampled points along a branch.

    Returns
    -------
    QuasiStaticResult

    Raises
    ------
    DataError
        If ``measurement`` is not a :class:`~idkit.io.QuasiStaticMeasurement`.
    FitError
        If no reversal is found.

    Examples
    --------
    >>> from idkit.io import QuasiStaticMeasurement
    >>> t = np.linspace(0, 40, 4001)
    >>> x = 2e-3 * np.sin(2 * np.pi * t / 10)
    >>> result = process_quasi_static(QuasiStaticMeasurement(time=t, deflection=x, force=1e4 * x))
    >>> result.n_cycles, round(float(result.amplitude[0]) * 1e3, 3)
    (3, 2.0)
    """
    _require(measurement, QuasiStaticMeasurement, "process_quasi_static")
    x = measurement.deflection
    noise = noise_level(x)
    if min_excursion is None:
        min_excursion = reversal_threshold(x)
    cycles = split_cycles(x, min_excursion=min_excursion, large_threshold=large_threshold)
    loops = resample_loops(x, measurement.force, split=cycles, points_per_branch=points_per_branch,
                           spacing=spacing)
    return QuasiStaticResult(measurement_id=measurement.id, cycles=cycles, loops=loops,
                             min_excursion=float(min_excursion), deflection_noise=noise)


