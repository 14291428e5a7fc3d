"""Steady-state harmonic response at every (frequency, amplitude) pair of two axes, as one table.

``idkit simulate harmonic`` prints or writes this table. The points are settled by
:func:`idkit.responses.harmonic_map.harmonic_map` (one map: chained along the amplitude axis,
shooting where the time integration does not settle, every orbit's stability classified and an
unstable one carried to the stable orbit a long run reaches); the axes are taken as given (any
order, repeated values), the map computing each distinct value once.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from idkit.responses.harmonic_map import harmonic_map

__all__ = ["harmonic_grid_table"]


def harmonic_grid_table(system, freq, amplitude, *, n_harmonics: int = 3, tolerance: float = 1e-3,
                        progress=None, workers: int | None = None) -> pd.DataFrame:
    """One row per (frequency, amplitude) point, frequency-major, in the order of the axes given.

    Parameters
    ----------
    system : SDOFSystem or HybridSystem
    freq : array_like
        Frequencies in Hz.
    amplitude : array_like
        Base displacement amplitudes in m.
    n_harmonics : int
        Highest harmonic order K; orders 1/2, 1, ..., K are tabulated.
    tolerance : float
        Steady-state tolerance (relative change per period).
    progress : callable(done, total), optional
    workers : int, optional
        Simulation threads (default: all usable cores).

    Returns
    -------
    DataFrame
        ``freq [Hz]``, ``amplitude [m]``, ``half_range [m]``, ``|H<k>| [-]`` and
        ``phase H<k> [deg]`` per order, ``bias [m]``, ``periods``, ``converged``, ``status``,
        ``stability`` and ``|mu| [-]`` (:class:`~idkit.responses.harmonic_map.HarmonicMap`).

    Examples
    --------
    >>> from idkit.models import library
    >>> table = harmonic_grid_table(library.get("system_b1_medium"), [2.0, 20.0], [1e-3], n_harmonics=1)
    >>> list(table["freq [Hz]"]), bool(table["converged"].all())
    ([2.0, 20.0], True)
    """
    freq = np.atleast_1d(np.asarray(freq, dtype=float))
    amplitude = np.atleast_1d(np.asarray(amplitude, dtype=float))
    freq_axis, freq_row = np.unique(freq, return_inverse=True)
    amplitude_axis, amplitude_column = np.unique(amplitude, return_inverse=True)
    result = harmonic_map(system, freq_axis, amplitude_axis, n_harmonics=n_harmonics, tolerance=tolerance,
                          progress=progress, workers=workers)
    rows, columns_ = np.meshgrid(freq_row.ravel(), amplitude_column.ravel(), indexing="ij")
    rows, columns_ = rows.ravel(), columns_.ravel()
    grid_freq, grid_amplitude = np.meshgrid(freq, amplitude, indexing="ij")
    columns = {"freq [Hz]": grid_freq.ravel(), "amplitude [m]": grid_amplitude.ravel(),
               "half_range [m]": result.half_range[rows, columns_]}
    for order in result.orders:
        value = result.hosidf(order)[rows, columns_]
        columns[f"|H{order:g}| [-]"] = np.abs(value)
        columns[f"phase H{order:g} [deg]"] = np.degrees(np.angle(value))
    columns.update({"bias [m]": result.bias[rows, columns_], "periods": result.periods[rows, columns_].astype(np.int64),
                    "converged": result.converged[rows, columns_], "status": list(result.reasons[rows, columns_]),
                    "stability": list(result.stability[rows, columns_]),
                    "|mu| [-]": np.abs(result.multiplier[rows, columns_])})
    return pd.DataFrame(columns)
