"""The elastomer's static stiffness read off quasi-static loops (SPEC 4).

* :func:`estimate_k0` / :class:`K0Estimate` - the least-squares slope around the origin of one
  force-deflection record;
* :func:`k0_from_measurements`, :func:`k0_from_records` / :class:`K0FromLoops` - the same over
  the quasi-static records of a measurement set, with the spread across records;
* :func:`static_operating_point` / :class:`StaticOperatingPoint` - the static deflection under a
  top mass's weight and the tangent stiffness there (the preload a Maxwell fit linearises about).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from idkit.checks import Instance, Items, Real, Samples, accepts
from idkit.errors import DataError, FitError
from idkit.io import QuasiStaticMeasurement
from idkit.io.selection import select_measurements

__all__ = ["K0Estimate", "estimate_k0", "K0FromLoops", "k0_from_measurements", "k0_from_records",
           "MIN_WINDOW_FRACTION", "StaticOperatingPoint", "static_operating_point"]


@dataclass(frozen=True)
class K0Estimate:
    """Static stiffness from the quasi-static slope around the origin.

    ``k0`` (N/m) is the least-squares slope of ``force = a + k0 * deflection`` over
    the points with ``|deflection| <= window``; ``stderr`` its standard error from
    the residual variance (N/m); ``intercept`` ``a`` in N; ``n_points`` used.
    """

    k0: float
    stderr: float
    intercept: float
    n_points: int
    window: float


#: The declared ``window`` of every k0 estimate.
WINDOW = Real(unit="m", gt=0, meaning="half-width of the deflection window")


@accepts(deflection=Samples(unit="m"), force=Samples(unit="N"), window=WINDOW, error=FitError)
def estimate_k0(deflection, force, window: float) -> K0Estimate:
    """Least-squares slope of force over deflection around the origin, with its standard error.

    Parameters
    ----------
    deflection, force : array_like
        Quasi-static record in m and N.
    window : float
        Half-width in m of the deflection window around 0 (e.g. 1e-3).

    Returns
    -------
    K0Estimate

    Raises
    ------
    FitError
        Fewer than 3 points in the window, non-finite values, a non-positive slope.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(-2e-3, 2e-3, 101)
    >>> round(estimate_k0(x, 1.4e4 * x + 0.1, window=1e-3).k0)
    14000
    """
    x, f = deflection, force
    if x.shape != f.shape:
        raise FitError(f"estimate_k0: found deflection shape {x.shape} and force shape {f.shape}, "
                       "expected equal shapes")
    inside = np.abs(x) <= window
    n = int(inside.sum())
    if n < 3 or np.ptp(x[inside]) <= 0:
        raise FitError(f"estimate_k0: found {n} points with |deflection| <= {window:g} m, "
                       "expected at least 3 distinct deflections (widen the window)")
    design = np.column_stack([np.ones(n), x[inside]])
    coefficients, _, _, _ = np.linalg.lstsq(design, f[inside], rcond=None)
    residual = f[inside] - design @ coefficients
    variance = float(residual @ residual) / max(n - 2, 1)
    covariance = variance * np.linalg.inv(design.T @ design)
    slope = float(coefficients[1])
    if not slope > 0:
        raise FitError(f"estimate_k0: found slope {slope:g} N/m, expected a positive stiffness "
                       "(is tension positive in both deflection and force?)")
    return K0Estimate(k0=slope, stderr=float(math.sqrt(covariance[1, 1])), intercept=float(coefficients[0]),
                      n_points=n, window=float(window))


@dataclass(frozen=True)
class K0FromLoops:
    """Static stiffness of the elastomer from its quasi-static loops.

    Attributes
    ----------
    k0 : float
        Pooled least-squares slope around the origin, N/m.
    stderr : float
        Its uncertainty (N/m): the larger of the regression standard error of the
        pooled fit and the standard error of the mean of the per-record slopes
        (records differ by more than the regression within one record admits).
    pooled : K0Estimate
    per_record : dict
        Measurement id -> slope (N/m).
    window : float
        Half-width of the deflection window, m.
    method : {"secant", "relaxation"}
        ``"secant"``: the slope above; ``"relaxation"``: the loops' time history fitted with
        the relaxation of unrelaxed elements (:func:`idkit.fit.static_stiffness.k0_with_relaxation`,
        which sets ``k0``, ``stderr`` and ``per_record``).
    secant_k0 : float or None
        ``"relaxation"``: the secant slope of the same points, N/m.
    relaxation : dict or None
        ``"relaxation"``: basis stiffness (N/m) per relaxation rate (1/s).
    fallback : str or None
        Why the secant slope stands in for the relaxation fit that was asked for (the loops do
        not tell ``k0`` apart from the relaxation basis, e.g. sinusoids of one amplitude per
        record); None when the method asked for gave ``k0``.
    """

    k0: float
    stderr: float
    pooled: K0Estimate
    per_record: dict
    window: float
    method: str = "secant"
    secant_k0: float | None = None
    relaxation: dict | None = None
    fallback: str | None = None


@accepts(window=WINDOW, error=FitError)
def k0_from_measurements(
    measurements,
    *,
    window: float = 1e-3,
    isolator: str | None = "elastomer",
    split: str | None = "fit",
) -> K0FromLoops:
    """Static stiffness from the quasi-static loops: slope around the origin with its uncertainty.

    Parameters
    ----------
    measurements : MeasurementSet or sequence of QuasiStaticMeasurement
    window : float, default 1e-3
        Half-width (m) of the deflection window around 0.
    isolator, split : as :func:`loop_sets`

    Returns
    -------
    K0FromLoops
        The pooled slope (:func:`estimate_k0` on all records' points), its uncertainty and
        each record's own slope.

    Raises
    ------
    FitError
        Fewer than 3 points in the window, a non-positive slope (:func:`estimate_k0`).
    DataError
        No quasi-static record matches the selection.
    """
    records, _ = select_measurements(measurements, kind="quasi_static", isolator=isolator, split=split)
    return k0_from_records(records, window=window)


#: The quasi-static records of :func:`k0_from_records` and :func:`static_operating_point` (an item of
#: another kind is a DataError; no record at all a FitError).
_RECORDS = Items(Instance((QuasiStaticMeasurement,)))


@accepts(window=WINDOW, error=FitError)
def k0_from_records(records, *, window: float = 1e-3) -> K0FromLoops:
    """Static stiffness from quasi-static records already selected (:func:`k0_from_measurements`).

    Parameters
    ----------
    records : sequence of QuasiStaticMeasurement
        At least one record.
    window : float, default 1e-3
        Half-width (m) of the deflection window around 0.

    Returns
    -------
    K0FromLoops

    Raises
    ------
    FitError
        No record, fewer than 3 points in the window, a non-positive slope.
    DataError
        An item that is not a :class:`~idkit.io.QuasiStaticMeasurement`.
    """
    records = _RECORDS.check(records, "records", DataError)
    if not records:
        raise FitError("records: found none, expected at least one quasi-static record")
    x = np.concatenate([r.deflection for r in records])
    f = np.concatenate([r.force for r in records])
    pooled = estimate_k0(x, f, window)
    per_record = {r.id or f"record{i}": estimate_k0(r.deflection, r.force, window).k0
                  for i, r in enumerate(records, start=1)}
    values = np.array(list(per_record.values()))
    spread = float(np.std(values, ddof=1) / math.sqrt(values.size)) if values.size > 1 else 0.0
    return K0FromLoops(k0=pooled.k0, stderr=max(pooled.stderr, spread), pooled=pooled, per_record=per_record,
                       window=float(window))


#: Near the end of the loops the window of :func:`static_operating_point` narrows to what
#: they cover, down to this fraction of its half-width (a quadratic through 1/4 of the window
#: still reads the slope; beyond, the curve is not measured).
MIN_WINDOW_FRACTION = 0.25


@dataclass(frozen=True)
class StaticOperatingPoint:
    """Where a static load puts the isolator on its measured quasi-static curve.

    Attributes
    ----------
    load : float
        Compressive static load, N (a top mass times g).
    deflection : float
        Static deflection under it, m (negative: compression).
    stiffness : float
        Tangent stiffness there, N/m: the slope of a least-squares quadratic through every
        loop point within ``window`` of ``deflection`` (loading and unloading branches
        pooled, so the slope of the loops' mid-curve).
    window : float
        Half-width of the deflection window, m.
    """

    load: float
    deflection: float
    stiffness: float
    window: float


@accepts(load=Real(unit="N", ge=0, meaning="compressive load"), window=WINDOW, error=FitError)
def static_operating_point(records, load: float, *, window: float = 1e-3) -> StaticOperatingPoint | None:
    """Static deflection and tangent stiffness of the loops under a compressive ``load`` (N).

    Small-amplitude dynamics of a top mass on a softening elastomer happen around the static
    deflection its weight causes, where the tangent stiffness is lower than at the origin.
    The deflection solves
    ``F(y) = -load`` on the loops' local least-squares curve (Newton, from ``-load / k0``);
    the stiffness is that curve's slope (a quadratic through the loop points within ``window``,
    loading and unloading pooled: the loops' mid-curve, exact for a quadratic law).

    Parameters
    ----------
    records : sequence of QuasiStaticMeasurement
    load : float
        Compressive load, N (>= 0).
    window : float, default 1e-3
        Half-width (m) of the deflection window of each local line.

    Returns
    -------
    StaticOperatingPoint or None
        None when the loops do not reach the static deflection plus a quarter of the window
        (:data:`MIN_WINDOW_FRACTION`) on both sides: the curve there is not measured. Near the
        ends of the loops the window narrows to what they cover.

    Examples
    --------
    >>> from idkit.io import QuasiStaticMeasurement
    >>> x = 8e-3 * np.sin(np.linspace(0, 4 * np.pi, 4001))
    >>> loop = QuasiStaticMeasurement(time=np.arange(x.size) * 0.01, deflection=x,
    ...                               force=1e4 * x + 2e5 * x**2)
    >>> point = static_operating_point([loop], 30.0)
    >>> round(point.deflection * 1e3, 4), round(point.stiffness)
    (-3.2055, 8718)
    """
    records = _RECORDS.check(records, "records", DataError)
    x = np.concatenate([r.deflection for r in records])
    f = np.concatenate([r.force for r in records])

    def local_curve(centre):  # force and slope at ``centre`` from a quadratic in the window
        half = min(window, centre - x.min(), x.max() - centre)  # narrower at the loops' ends
        if not half >= MIN_WINDOW_FRACTION * window:
            return None
        inside = np.abs(x - centre) <= half
        if inside.sum() < 5:
            return None
        _, c1, c0 = np.polyfit((x[inside] - centre) / half, f[inside], 2)
        return c0, c1 / half

    y = -load / estimate_k0(x, f, window).k0
    for _ in range(50):
        curve = local_curve(y)
        if curve is None or not curve[1] > 0:
            return None
        step = (-load - curve[0]) / curve[1]
        y += step
        if abs(step) < 1e-9 * window:
            break
    curve = local_curve(y)
    if curve is None or not curve[1] > 0:
        return None
    return StaticOperatingPoint(load=float(load), deflection=float(y), stiffness=float(curve[1]), window=float(window))
