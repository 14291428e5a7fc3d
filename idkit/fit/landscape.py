"""Error landscape of the one-element Maxwell problem (why a global cross-check is worth having)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from idkit.checks import Real, Reals, Seed, Whole, accepts
from idkit.errors import FitError
from idkit.fit.frf_objective import as_transmissibility_sets, band_points, check_band, mean_squared_relative_error
from idkit.fit.maxwell import fit_maxwell
from idkit.models.laws import sdof_transmissibility

__all__ = ["ErrorLandscape", "maxwell_error_landscape"]


@dataclass(frozen=True)
class ErrorLandscape:
    """Objective (7.5) of ``k0 + k_1 s / (s + rate_1)`` on a grid of ``(k_1, rate_1)``.

    Attributes
    ----------
    k : ndarray, shape (n_k,)
        Element stiffnesses, N/m.
    rate : ndarray, shape (n_rate,)
        Relaxation rates, 1/s.
    error : ndarray, shape (n_rate, n_k)
        RMS relative complex error (fraction) at each grid point.
    k0, m_eff : float
        Fixed static stiffness (N/m) and moving isolator mass (kg).
    optimum : (float, float)
        ``(k_1, rate_1)`` of the SQP fit of order 1 (when ``m_eff`` was fitted), else the
        minimum over the feasible grid points.
    feasible : ndarray of bool, shape (n_rate, n_k)
        Where the loss factor is non-decreasing over the band (SPEC 4's constraint, on 25
        log-spaced frequencies). A single element's loss factor peaks near
        ``rate_1 sqrt(1 + k_1 / k0) / (2 pi)``; grid points with that peak inside the band
        are infeasible, which is why the unconstrained minimum can lie below the fit.
    """

    k: np.ndarray
    rate: np.ndarray
    error: np.ndarray
    k0: float
    m_eff: float
    optimum: tuple[float, float]
    feasible: np.ndarray


@accepts(k0=Real(unit="N/m", gt=0), k_values=Reals(unit="N/m", gt=0, optional=True),
         rate_values=Reals(unit="1/s", gt=0, optional=True), m_eff=Real(unit="kg", ge=0, optional=True),
         points=Whole(ge=2), seed=Seed(), error=FitError)
def maxwell_error_landscape(frfs, *, k0: float, k_values=None, rate_values=None, m_eff: float | None = None,
                            band=(1.0, 100.0), points: int = 41, seed: int = 0) -> ErrorLandscape:
    """Objective (7.5) of one Maxwell element over a (k_1, rate_1) grid.

    Parameters
    ----------
    frfs : sequence
        Transmissibility sets as for :func:`idkit.fit.fit_maxwell`.
    k0 : float
        Static stiffness in N/m.
    k_values, rate_values : array_like, optional
        Grid axes in N/m and 1/s; default ``points`` log-spaced values over the
        fit bounds (0.1 k0 .. 10 k0, 1 .. 1e4 1/s).
    m_eff : float, optional
        Moving isolator mass in kg; default from an order-1 fit (whose optimum is marked).
    band : (float, float)
    points : int, default 41
    seed : int
        Seed of the order-1 fit's start.
    """
    band = check_band(band)
    sets = as_transmissibility_sets(frfs)
    k_values = np.geomspace(0.1 * k0, 10 * k0, points) if k_values is None else k_values
    rate_values = np.geomspace(1.0, 1e4, points) if rate_values is None else rate_values
    optimum = None
    if m_eff is None:
        fitted = fit_maxwell(sets, k0=k0, order=1, band=band, seed=seed)
        m_eff = fitted.model.m_eff
        optimum = (float(fitted.model.k[0]), float(fitted.model.rate[0]))
    error2 = np.zeros((rate_values.size, k_values.size))
    for item in sets:
        freq, measured = band_points(item.freq, item.transmissibility, band, f"frfs {item.name!r}", min_points=1)
        s = 2j * np.pi * freq
        stiffness = k0 + k_values[None, :, None] * s[None, None, :] / (s[None, None, :] + rate_values[:, None, None])
        prediction = sdof_transmissibility(stiffness, item.mass + m_eff, 2 * np.pi * freq)
        error2 += mean_squared_relative_error(prediction, measured, axis=2)
    error = np.sqrt(error2 / len(sets))
    s = 2j * np.pi * np.geomspace(band[0], band[1], 25)
    stiffness = k0 + k_values[None, :, None] * s[None, None, :] / (s[None, None, :] + rate_values[:, None, None])
    loss = stiffness.imag / stiffness.real
    feasible = np.all(np.diff(loss, axis=2) >= -1e-12, axis=2)
    if optimum is None:
        masked = np.where(feasible, error, np.inf)
        i, j = np.unravel_index(np.argmin(masked), masked.shape)
        optimum = (float(k_values[j]), float(rate_values[i]))
    return ErrorLandscape(k=k_values, rate=rate_values, error=error, k0=float(k0), m_eff=float(m_eff),
                          optimum=optimum, feasible=feasible)
