"""Generalized Maxwell (Prony) fit to a complex stiffness or modulus table (DMA, master curves).

The same law, scaling, SQP and cross-check as the transmissibility fit (:mod:`idkit.fit.maxwell`),
observed directly: the objective is the RMS over the points of ``|k*_model - k*_meas| / |k*_meas|``,
with no mass.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from idkit.checks import Choice, Real, Reals, accepts
from idkit.errors import FitError
from idkit.fit._optim import BACKEND
from idkit.fit._params import spec_units
from idkit.fit.frf_objective import band_points, check_band
from idkit.fit.maxwell import (
    GLOBAL_METHOD,
    LOSS_GRID_POINTS,
    ORDER,
    _check_bounds,
    _loss_grid,
    _maxwell_transforms,
    _MaxwellLaw,
    _solve,
    _StiffnessProblem,
)
from idkit.fit.maxwell_result import MaxwellFitResult
from idkit.models import GeneralizedMaxwell

__all__ = ["fit_complex_stiffness", "TABLE_MAGNITUDE_RANGE", "TABLE_FREQUENCY_RANGE", "TABLE_HIGHEST_FREQUENCY"]


#: Magnitudes of a complex stiffness or modulus table the fit takes (N/m or Pa). Above, the fit's
#: squares overflow; below, lmfit takes bounds closer than 1e-13 (absolute) for equal and refuses
#: them (k0 is bounded by 1e-6 to 1 x the smallest storage). Real parts and materials lie far inside.
TABLE_MAGNITUDE_RANGE = (1e-6, 1e100)
#: Frequencies (Hz) of such a table, for the same reasons; the rates are bounded by 2 pi f_min / 10 to
#: 2 pi f_max x 10, so the highest frequency must also reach :data:`TABLE_HIGHEST_FREQUENCY`. Master
#: curves over 40 decades (pyvisco's reach 3e-18 Hz) lie inside.
TABLE_FREQUENCY_RANGE = (1e-100, 1e100)
TABLE_HIGHEST_FREQUENCY = 1e-12


def _check_table_values(freq, value, order: int, unit: str) -> None:
    """What a Prony series of ``order`` terms can be fitted to: storage > 0 (the model's
    ``k0 + sum k_i w^2 / (w^2 + r_i^2)`` is), magnitudes in :data:`TABLE_MAGNITUDE_RANGE`, frequencies
    in :data:`TABLE_FREQUENCY_RANGE` reaching :data:`TABLE_HIGHEST_FREQUENCY`, and
    ``order + 1`` distinct frequencies (each gives two numbers for the ``2 order + 1`` parameters)."""
    low = int(np.argmin(value.real))
    if not value.real[low] > 0:
        raise FitError(f"complex stiffness: found storage {value.real[low]:g} {unit} at {freq[low]:g} Hz, "
                       "expected storage > 0 (a Maxwell model's storage k0 + sum k_i w^2/(w^2 + r_i^2) is)")
    magnitude = np.abs(value)
    for index in (int(np.argmin(magnitude)), int(np.argmax(magnitude))):
        if not TABLE_MAGNITUDE_RANGE[0] <= magnitude[index] <= TABLE_MAGNITUDE_RANGE[1]:
            raise FitError(f"complex stiffness: found |value| {magnitude[index]:g} {unit} at {freq[index]:g} Hz, "
                           f"expected {TABLE_MAGNITUDE_RANGE[0]:g} to {TABLE_MAGNITUDE_RANGE[1]:g} {unit} "
                           "(outside, the fit's squares overflow or its bounds become indistinguishable)")
    for index in (int(np.argmin(freq)), int(np.argmax(freq))):
        if not TABLE_FREQUENCY_RANGE[0] <= freq[index] <= TABLE_FREQUENCY_RANGE[1]:
            raise FitError(f"complex stiffness: found frequency {freq[index]:g} Hz, expected "
                           f"{TABLE_FREQUENCY_RANGE[0]:g} to {TABLE_FREQUENCY_RANGE[1]:g} Hz (outside, the fit's squares "
                           "overflow or its rate bounds become indistinguishable)")
    if freq.max() < TABLE_HIGHEST_FREQUENCY:
        raise FitError(f"complex stiffness: found the highest frequency {freq.max():g} Hz, expected at least "
                       f"{TABLE_HIGHEST_FREQUENCY:g} Hz (below, the rate bounds become indistinguishable)")
    distinct = np.unique(freq).size
    if distinct < order + 1:
        raise FitError(f"complex stiffness: found {distinct} distinct frequencies in {freq.size} points, expected "
                       f"at least {order + 1} for order {order} ({2 * order + 1} parameters, two numbers a "
                       "frequency)")


@accepts(freq=Reals(unit="Hz", gt=0), order=ORDER, k0=Real(ge=0, optional=True, meaning="N/m or Pa, None: fitted"), backend=BACKEND,
         global_method=GLOBAL_METHOD, loss_grid_points=LOSS_GRID_POINTS, quantity=Choice(("stiffness", "modulus")),
         error=FitError)
def fit_complex_stiffness(
    freq,
    storage,
    loss,
    *,
    order: int,
    k0: float | None = None,
    band=None,
    backend: str = "nlopt",
    k0_bounds=None,
    stiffness_bounds=None,
    rate_bounds=None,
    monotone_loss: bool = False,
    loss_grid_points: int = 25,
    max_evals: int = 1000,
    ftol: float = 1e-12,
    cross_check: bool = False,
    global_method: str | None = None,
    global_max_evals: int = 10000,
    seed: int = 0,
    quantity: str = "stiffness",
    start: GeneralizedMaxwell | None = None,
) -> MaxwellFitResult:
    """Fit a generalized Maxwell (Prony) model to complex stiffness / DMA data.

    Objective: RMS over the points of ``|k*_model - k*_meas| / |k*_meas|`` with
    ``k*_meas = storage + i loss`` (storage and loss parts in N/m, or Pa for a
    modulus). Same SQP, scaling and cross-check as :func:`fit_maxwell`; no mass.
    The model carries ``quantity``: a modulus model (Pa) is labelled so in its report,
    model file and plots, and must be converted with
    :meth:`~idkit.models.GeneralizedMaxwell.to_stiffness` before it enters a system.

    Parameters
    ----------
    freq, storage, loss : array_like
        Frequency in Hz and the real and imaginary part of the complex stiffness.
    order : int
        Number of Maxwell elements, >= 1.
    k0 : float, optional
        Static stiffness, fixed when given; otherwise fitted within ``k0_bounds``
        (default ``1e-6 .. 1`` x the smallest storage value).
    band : (float, float), optional
        Default: the whole frequency range of the data.
    stiffness_bounds : (float, float), optional
        Default ``1e-6 .. 10`` x the largest |k*|.
    rate_bounds : (float, float), optional
        Default ``2 pi f_min / 10 .. 2 pi f_max * 10`` in 1/s (one decade beyond the data).
    monotone_loss : bool, default False
        DMA master curves have a loss peak, so the constraint is off by default.
    quantity : {"stiffness", "modulus"}
        What ``storage`` and ``loss`` are: N/m (a part) or Pa (a material, e.g. a DMA
        table's ``quantity``).
    start : GeneralizedMaxwell, optional
        Start of the SQP (same order; values inside the bounds); default: the seeded
        default start.
    """
    unit = "N/m" if quantity == "stiffness" else "Pa"
    try:
        value = np.asarray(storage, dtype=float) + 1j * np.asarray(loss, dtype=float)
    except ValueError:
        raise FitError(f"storage/loss: found shapes {np.shape(storage)} and {np.shape(loss)}, expected equal") from None
    if freq.ndim != 1:
        raise FitError(f"freq: found shape {freq.shape}, expected a 1-D array of frequencies in Hz")
    band = check_band(band if band is not None else (freq.min(), freq.max() * (1 + 1e-12)))
    f_in, k_in = band_points(freq, value, band, "complex stiffness", min_points=2 * order + 2)
    _check_table_values(f_in, k_in, order, unit)
    magnitude = np.abs(k_in)
    if k0 is None:
        k0_bounds = _check_bounds("k0_bounds", k0_bounds or (1e-6 * k_in.real.min(), k_in.real.min()), unit)
    stiffness_bounds = _check_bounds("stiffness_bounds", stiffness_bounds or (1e-6 * magnitude.max(),
                                                                             10 * magnitude.max()), unit)
    rate_bounds = _check_bounds("rate_bounds", rate_bounds or (2 * np.pi * f_in.min() / 10,
                                                               2 * np.pi * f_in.max() * 10), "1/s")
    transforms = _maxwell_transforms(order, stiffness_bounds, rate_bounds,
                                     k0_bounds=None if k0 is not None else k0_bounds)
    order_index = np.argsort(f_in)
    omega = 2 * np.pi * f_in[order_index]
    law = _MaxwellLaw(order, None if k0 is None else float(k0), with_m_eff=False)
    problem = _StiffnessProblem(law, omega=omega, measured=k_in[order_index], mass=None,
                                weights=np.full(omega.size, 1.0 / omega.size), set_index=np.zeros(omega.size, int),
                                set_names=[f"complex {quantity}"], transforms=transforms,
                                loss_omega=_loss_grid(band, loss_grid_points) if monotone_loss else None,
                                monotone_loss=monotone_loss)
    if start is not None and start.quantity != "stiffness":
        start = GeneralizedMaxwell(k0=start.k0, k=start.k, rate=start.rate)
    result = _solve(problem, start=start, band=band, backend=backend, max_evals=max_evals, ftol=ftol,
                    cross_check=cross_check, global_method=global_method, global_max_evals=global_max_evals,
                    seed=seed, settings_extra={})
    if quantity == "stiffness":
        return result
    model = GeneralizedMaxwell(k0=result.model.k0, k=result.model.k, rate=result.model.rate, quantity="modulus")
    units = spec_units(model)
    parameters = result.parameters.copy()
    for name, parameter in parameters.items():
        parameter.user_data = {**(parameter.user_data or {}), "unit": units.get(name, "")}
    settings = dataclasses.replace(result.settings, data="complex modulus (Pa)")
    return dataclasses.replace(result, model=model, parameters=parameters, settings=settings)
