"""Steady-state harmonic response at every (frequency, amplitude) pair of two axes, as one table.

``idkit simulate harmonic`` prints or writes this table. Unlike
:func:`idkit.responses.harmonic_map.harmonic_map` the axes are taken as given (any order,
repeats computed again) and every point starts from rest.
"""

from __future__ import annotations

import numpy as np
import pandas as pd

from idkit.simulate import harmonic_response

__all__ = ["harmonic_grid_table"]


def harmonic_grid_table(system, freq, amplitude, *, n_harmonics: int = 3, tolerance: float = 1e-3,
                        progress=None) -> pd.DataFrame:
    """One row per (frequency, amplitude) point, frequency-major.

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

    Returns
    -------
    DataFrame
        ``freq [Hz]``, ``amplitude [m]``, ``half_range [m]``, ``|H<k>| [-]`` and
        ``phase H<k> [deg]`` per order, ``bias [m]``, ``periods``, ``converged``, ``status``.

    Examples
    --------
    >>> from idkit.models import library
    >>> table = harmonic_grid_table(library.get("system_b1_medium"), [2.0, 20.0], [1e-3], n_harmonics=1)
    >>> list(table["freq [Hz]"]), bool(table["converged"].all())
    ([2.0, 20.0], True)
    """
    grid_freq, grid_amplitude = np.meshgrid(np.asarray(freq, dtype=float), np.asarray(amplitude, dtype=float),
                                            indexing="ij")
    response = harmonic_response(system, grid_freq.ravel(), grid_amplitude.ravel(), n_harmonics=n_harmonics,
                                 tolerance=tolerance, progress=progress)
    columns = {"freq [Hz]": response.freq, "amplitude [m]": response.amplitude,
               "half_range [m]": response.half_range}
    for order in [0.5] + list(range(1, n_harmonics + 1)):
        value = response.hosidf(order)
        columns[f"|H{order:g}| [-]"] = np.abs(value)
        columns[f"phase H{order:g} [deg]"] = np.degrees(np.angle(value))
    columns.update({"bias [m]": response.bias, "periods": response.periods, "converged": response.converged,
                    "status": list(response.reasons)})
    return pd.DataFrame(columns)
