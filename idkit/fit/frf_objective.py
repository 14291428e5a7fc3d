"""The transmissibility data of the elastomer fits and their objective (7.5).

* :func:`as_transmissibility_sets` - the one coercion of loose FRF inputs;
* :func:`check_band`, :func:`band_points` - the band of a fit and the points inside it;
* :func:`mean_squared_relative_error` - ``mean |H_model - H_meas|^2 / |H_meas|^2`` of one set;
* :func:`maxwell_objective` - objective (7.5) of a given model on sets of several top masses;
* :func:`frf_noise_floor`, :func:`frf_model_form_reasons` - what the H1's random error alone
  scores under (7.5), and the verdict on a fit whose error the noise does not explain.

:func:`idkit.fit.fit_maxwell` minimises the same objective (its condensed, analytic-gradient
form), :func:`idkit.fit.maxwell_error_landscape` maps it over a grid.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from idkit.errors import FitError
from idkit.models import GeneralizedMaxwell, VoigtModel
from idkit.models.maxwell import preloaded
from idkit.models.laws import sdof_transmissibility
from idkit.observe.white_noise import TransmissibilitySet
from idkit.signal.frf import mean_squared_relative_error

__all__ = ["as_transmissibility_sets", "check_band", "band_points", "mean_squared_relative_error",
           "maxwell_objective", "FRF_MODEL_FORM_LIMIT", "frf_noise_floor", "frf_model_form_reasons"]

#: Largest part of a set's error (7.5) that its measurement noise does not explain,
#: ``sqrt(error^2 - floor^2)``, for a transmissibility fit to be a success: the FRF validation's
#: limit on a held-out run's error (7.5) (``idkit.validate.frf.FRF_THRESHOLDS["max_frf_error"]``,
#: 0.15). A fit that misses its own runs by more than that, beyond their noise, would fail the
#: validation on a repetition of them, so its model form (or order) does not describe the data.
FRF_MODEL_FORM_LIMIT = 0.15


def as_transmissibility_sets(frfs) -> list[TransmissibilitySet]:
    """The one coercion of loose FRF inputs into named :class:`TransmissibilitySet` items.

    Parameters
    ----------
    frfs : sequence
        :class:`TransmissibilitySet` items (kept; named ``set{index}`` when unnamed) or
        ``(mass kg, freq Hz, complex transmissibility)`` triples.

    Returns
    -------
    list of TransmissibilitySet

    Raises
    ------
    FitError
        No item, or an item of another shape.
    """
    if frfs is None or len(frfs) == 0:
        raise FitError("frfs: found no transmissibility set, expected at least one (mass, freq, H)")
    sets = []
    for index, item in enumerate(frfs):
        if isinstance(item, TransmissibilitySet):
            sets.append(item if item.name else dataclasses.replace(item, name=f"set{index}"))
            continue
        try:
            mass, freq, value = item
        except (TypeError, ValueError):
            raise FitError(f"frfs[{index}]: found {type(item).__name__}, expected a TransmissibilitySet or "
                           "(mass kg, freq Hz, complex transmissibility)") from None
        sets.append(TransmissibilitySet(float(mass), np.asarray(freq), np.asarray(value), f"set{index}"))
    return sets


def check_band(band) -> tuple[float, float]:
    """``band`` as ``(f_low, f_high)`` in Hz with ``0 < f_low < f_high < inf``, else a :class:`FitError`."""
    try:
        low, high = (float(v) for v in band)
    except (TypeError, ValueError):
        raise FitError(f"band: found {band!r}, expected (f_low, f_high) in Hz") from None
    if not (0 < low < high < math.inf):
        raise FitError(f"band: found ({low:g}, {high:g}) Hz, expected 0 < f_low < f_high")
    return low, high


def band_points(freq, value, band, what: str, *, min_points: int) -> tuple[np.ndarray, np.ndarray]:
    """The points of ``(freq Hz, complex value)`` inside ``band``, checked for the relative error (7.5).

    Parameters
    ----------
    freq, value : array_like
        Frequencies in Hz and complex values (transmissibility or stiffness), equal 1-D shapes.
    band : (float, float)
        From :func:`check_band`, Hz.
    what : str
        Name of the data in messages.
    min_points : int
        Fewest points the band must hold.

    Returns
    -------
    (ndarray, ndarray)
        Frequencies (Hz) and values inside the band.

    Raises
    ------
    FitError
        Unequal shapes, non-finite frequencies or values, a zero value (the error is
        relative to it), fewer than ``min_points`` points in the band.
    """
    freq = np.asarray(freq, dtype=float)
    value = np.asarray(value, dtype=complex)
    if freq.ndim != 1 or value.shape != freq.shape:
        raise FitError(f"{what}: found freq shape {freq.shape} and values shape {value.shape}, "
                       "expected equal 1-D shapes")
    if not np.all(np.isfinite(freq)):
        raise FitError(f"{what}: found non-finite frequencies, expected finite values in Hz")
    inside = (freq >= band[0]) & (freq <= band[1])
    f_in, v_in = freq[inside], value[inside]
    bad = np.flatnonzero(~np.isfinite(v_in))
    if bad.size:
        raise FitError(f"{what}: found {v_in[bad[0]]} at {f_in[bad[0]]:g} Hz, expected finite complex values")
    zero = np.flatnonzero(v_in == 0)
    if zero.size:
        raise FitError(f"{what}: found 0 at {f_in[zero[0]]:g} Hz, expected non-zero values "
                       "(the error (7.5) is relative to |measured|)")
    if f_in.size < min_points:
        raise FitError(f"{what}: found {f_in.size} points in the band {band[0]:g}-{band[1]:g} Hz, "
                       f"expected at least {min_points}")
    return f_in, v_in


def maxwell_objective(model: GeneralizedMaxwell | VoigtModel, frfs, *, band=(1.0, 100.0)) -> float:
    """Objective (7.5) of a given model on transmissibility sets: RMS relative complex error (fraction).

    ``e = sqrt(mean_sets mean_band |H_model - H_meas|^2 / |H_meas|^2)`` with
    ``H_model`` :func:`idkit.models.laws.sdof_transmissibility` of the set's top mass plus
    the model's ``m_eff`` (a Maxwell model about the set's preload,
    :func:`idkit.models.maxwell.preloaded`): every
    set weighs the same whatever its number of points.

    Parameters
    ----------
    model : GeneralizedMaxwell or VoigtModel
    frfs : sequence
        Transmissibility sets (:func:`as_transmissibility_sets`).
    band : (float, float), default (1, 100)
        Band in Hz.

    Returns
    -------
    float
        Fraction (0.01 = 1 %).
    """
    band = check_band(band)
    sets = as_transmissibility_sets(frfs)
    squares = []
    for item in sets:
        f_in, h_in = band_points(item.freq, item.transmissibility, band, f"frfs {item.name!r}", min_points=1)
        local = preloaded(model, item.static_stiffness)
        h_model = sdof_transmissibility(local.complex_stiffness(f_in), item.mass + model.m_eff, 2 * np.pi * f_in)
        squares.append(mean_squared_relative_error(h_model, h_in))
    return math.sqrt(float(np.mean(squares)))


def frf_noise_floor(item: TransmissibilitySet, band) -> float:
    """What an exactly right model scores under (7.5) on one H1 from its random error alone (fraction).

    ``floor = sqrt(mean_band 2 epsilon^2)`` with ``epsilon`` the normalized random error of the
    H1 (:attr:`TransmissibilitySet.random_error`, ``sqrt(1 - gamma^2) / (|gamma| sqrt(2 n_d))``,
    Bendat & Piersol 9.90): the error (7.5) is complex, and the standard deviation of the H1's
    phase (radians) equals that of its relative magnitude (9.91), so ``E |dH / H|^2 = 2
    epsilon^2``. With 50 % overlapping Hann segments the ``n_d`` averages are not independent and
    the floor reads 10-20 % low; it does not contain the bias of the estimate (a resonance the
    window cannot resolve, :func:`idkit.signal.frf.window_peak_bias`). NaN when the set carries no
    random error (a given table).
    """
    if item.random_error is None:
        return math.nan
    freq = np.asarray(item.freq, dtype=float)
    epsilon = np.asarray(item.random_error, dtype=float)
    inside = (freq >= band[0]) & (freq <= band[1])
    if epsilon.shape != freq.shape or not inside.any() or not np.all(np.isfinite(epsilon[inside])):
        return math.nan
    return math.sqrt(float(np.mean(2.0 * epsilon[inside] ** 2)))


def frf_model_form_reasons(set_names, set_errors, set_floors, *,
                           limit: float = FRF_MODEL_FORM_LIMIT) -> tuple[str, ...]:
    """One reason per set whose error (7.5) the noise does not explain by more than ``limit``.

    The unexplained part is ``sqrt(max(error^2 - floor^2, 0))`` (noise and model error add in
    quadrature); a set without a floor (NaN: no coherence known) is judged on its whole error.
    """
    reasons = []
    for name, error, floor in zip(set_names, set_errors, set_floors):
        known = math.isfinite(floor)
        unexplained = math.sqrt(max(error**2 - (floor**2 if known else 0.0), 0.0))
        if unexplained > limit:
            source = (f"the noise floor {100 * floor:.3g} % (the H1's random error from its coherence and averages) "
                      "explains" if known else "no noise floor is known (no coherence), so the noise explains")
            reasons.append(
                f"the model form misses {name}: its error (7.5) {100 * error:.3g} % is not noise: {source} at most "
                f"{100 * (floor if known else 0.0):.3g} %, leaving {100 * unexplained:.3g} % (sqrt(error^2 - floor^2)) "
                f"above the {100 * limit:g} % a held-out run may miss by (FRF validation max_frf_error): a higher order "
                "or another model form; or, where a resonance is narrower than the H1's resolution, longer white-noise "
                "records (docs/fitting.md)")
    return tuple(reasons)
