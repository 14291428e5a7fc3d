"""Where an FRF fit's residual is systematic: bands no noise explains and no top mass contradicts.

A fit can succeed (its error within the limits, its parameters determined) while the model
misses a feature of the data, e.g. an internal resonance of the isolator above the fitted
ones. The tell is a residual with a pattern: the same sign on every top mass and every
repetition over a band of frequencies, far above the random error of the estimate.
:func:`systematic_residual_bands` finds such bands in the log-magnitude residual
``ln(|H_model| / |H_measured|)`` of every transmissibility:

1. a frequency is *systematic* when the residual has the same sign on every transmissibility
   and exceeds :data:`NOISE_MULTIPLE` times its normalized random error on each
   (:attr:`~idkit.observe.white_noise.TransmissibilitySet.random_error`; the chance that noise
   does this on n independent estimates is below 0.0027**n);
2. a band is a run of at least :data:`MIN_BAND_POINTS` consecutive systematic frequencies of one
   sign (runs of one sign fewer than that many frequencies apart are one band);
3. a band is reported when its largest |residual| reaches ``level`` (the fit's own mean
   relative error, objective 7.5): smaller systematic deviations are the trade-offs every
   fit of a finite-order model makes, not a missing feature.

The magnitude alone is judged: the phase follows it where the model misses a mode. Compute
only; :mod:`idkit.report.main_report` states the bands.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from idkit.models.laws import sdof_transmissibility
from idkit.models.maxwell import preloaded

__all__ = ["MIN_BAND_POINTS", "NOISE_MULTIPLE", "ResidualBand", "systematic_residual_bands"]

#: a residual counts as systematic beyond this many normalized random errors (3: 0.27 % two-sided
#: for a Gaussian estimate, on every transmissibility at once)
NOISE_MULTIPLE = 3.0

#: consecutive systematic frequencies a band needs (shorter runs are a crossing of the residual,
#: not a band)
MIN_BAND_POINTS = 5


@dataclass(frozen=True)
class ResidualBand:
    """A frequency band over which an FRF fit's residual is systematic.

    Attributes
    ----------
    low_hz, high_hz : float
        First and last frequency of the band.
    sign : int
        +1 when the model's magnitude is above the measured one on every transmissibility, -1 below.
    peak : float
        Largest ``|ln(|H_model| / |H_measured|)|`` in the band (about the relative magnitude error).
    """

    low_hz: float
    high_hz: float
    sign: int
    peak: float


def systematic_residual_bands(model, frfs, *, level: float, band=(1.0, 100.0),
                              noise_multiple: float = NOISE_MULTIPLE,
                              min_points: int = MIN_BAND_POINTS) -> tuple[ResidualBand, ...]:
    """Bands where the magnitude residual of ``model`` on every transmissibility is systematic (module docstring).

    Parameters
    ----------
    model : GeneralizedMaxwell or VoigtModel
        Drawn on each top mass as the fit sees it (its small-amplitude stiffness about the
        static preload, :func:`idkit.models.maxwell.preloaded`).
    frfs : sequence of TransmissibilitySet
        Every repetition of every top mass; those without a random error are left out.
    level : float
        Smallest peak |log-magnitude residual| reported (e.g. the fit's error, 7.5).
    band : (float, float)
        Frequencies judged, Hz; the frequency grid is the first transmissibility's (the others
        are interpolated onto it).
    noise_multiple : float
    min_points : int

    Returns
    -------
    tuple of ResidualBand
        In increasing frequency; empty when no transmissibility has a random error.

    Examples
    --------
    >>> from idkit.models import GeneralizedMaxwell
    >>> from idkit.observe.white_noise import TransmissibilitySet
    >>> model = GeneralizedMaxwell(k0=2.0e4, k=[1.0e4], rate=[200.0])
    >>> freq = np.linspace(1.0, 100.0, 200)
    >>> truth = sdof_transmissibility(model.complex_stiffness(freq), 1.0, 2 * np.pi * freq)
    >>> measured = truth * np.where(freq > 60.0, 1.2, 1.0)  # 20 % more above 60 Hz, no noise
    >>> frf = TransmissibilitySet(1.0, freq, measured, random_error=np.full(freq.size, 0.01))
    >>> [(round(b.low_hz), round(b.high_hz), b.sign) for b in systematic_residual_bands(model, [frf], level=0.1)]
    [(60, 100, -1)]
    """
    usable = [frf for frf in frfs if frf.random_error is not None]
    if not usable:
        return ()
    grid = np.asarray(usable[0].freq, dtype=float)
    grid = grid[(grid >= band[0]) & (grid <= band[1])]
    if grid.size == 0:
        return ()
    residuals, significant = [], []
    for frf in usable:
        freq = np.asarray(frf.freq, dtype=float)
        stiffness = preloaded(model, frf.static_stiffness).small_amplitude_stiffness(freq)
        predicted = sdof_transmissibility(stiffness, frf.mass + model.m_eff, 2 * np.pi * freq)
        with np.errstate(divide="ignore", invalid="ignore"):
            residual = np.log(np.abs(predicted) / np.abs(np.asarray(frf.transmissibility)))
        residual = np.interp(grid, freq, residual)
        error = np.interp(grid, freq, np.asarray(frf.random_error, dtype=float))
        residuals.append(residual)
        significant.append(np.abs(residual) > noise_multiple * error)
    residuals = np.array(residuals)
    signs = np.sign(residuals)
    systematic = np.all(significant, axis=0) & np.all(signs == signs[0], axis=0) & (signs[0] != 0)
    # runs of systematic frequencies of one sign; runs of one sign less than min_points apart
    # are one band (a point or two of the band that one estimate's noise pushed under the bar)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], systematic.astype(np.int8), [0]])))
    runs = [run for start, stop in zip(edges[::2], edges[1::2]) for run in _same_sign_runs(signs[0], start, stop)]
    merged: list[list[int]] = []
    for first, last in runs:
        if merged and signs[0][first] == signs[0][merged[-1][0]] and first - merged[-1][1] < min_points:
            merged[-1][1] = last
        else:
            merged.append([first, last])
    bands = []
    for first, last in merged:
        if last - first < min_points:
            continue
        peak = float(np.max(np.abs(residuals[:, first:last])))
        if peak >= level:
            bands.append(ResidualBand(float(grid[first]), float(grid[last - 1]), int(signs[0][first]), peak))
    return tuple(bands)


def _same_sign_runs(signs: np.ndarray, start: int, stop: int) -> list[tuple[int, int]]:
    """``[start, stop)`` cut where ``signs`` changes: ``(first, last + 1)`` per run."""
    cuts = [start] + [i for i in range(start + 1, stop) if signs[i] != signs[i - 1]] + [stop]
    return list(zip(cuts[:-1], cuts[1:]))
