"""Time-temperature superposition: shift factors estimated from isotherms, WLF and polynomial laws.

A thermorheologically simple material has one master curve ``M`` of the reduced
frequency ``f aT(T)``: an isotherm measured at temperature ``T`` is the master curve
shifted horizontally on a log-frequency axis, ``E_T(log f) = M(log f + log aT(T))``,
with ``log aT(T_ref) = 0``. Two isotherms ``a`` and ``b`` that overlap in modulus
therefore satisfy ``E_b(x) = E_a(x + log aT_b - log aT_a)``.

Method of :func:`estimate_shift_factors` (documented choice):

1. Rows are grouped into isotherms by temperature (a gap wider than ``group_tol_k``
   between sorted temperatures starts a new isotherm; each isotherm's temperature is
   the mean of its rows).
2. Adjacent isotherms (in temperature) are shifted pairwise: the relative shift
   ``delta = log aT_b - log aT_a`` (decades) minimises the mean squared difference of
   ``log10 |E*|`` between each curve's points and the other curve interpolated
   (linearly in ``log10 f``) at the shifted abscissa, both ways, over the points that
   fall inside the other curve's range. ``|E*|`` is used because it is monotonic in
   frequency for a passive viscoelastic solid (the storage part alone is too, and may be
   chosen with ``quantity="storage"``). The minimum is located on a 0.02-decade scan
   and refined by a bounded scalar minimisation.
3. The shifts are summed from the isotherm nearest the reference temperature outwards;
   if no isotherm lies within ``group_tol_k`` of the reference, the fitted polynomial's
   value at the reference is subtracted so that ``log aT(T_ref) = 0``.

The pairwise RMS residual (decades of ``log |E*|``) is reported for every pair: a pair
whose curves do not overlap in modulus cannot be shifted and raises an error naming
the two temperatures.

:func:`fit_wlf` fits ``log aT = -C1 (T - T_ref) / (C2 + T - T_ref)`` (Williams, Landel and
Ferry 1955) by least squares in ``log aT``; :func:`fit_shift_polynomial` fits a polynomial
in ``T - T_ref`` without constant term. :func:`compare_shift_factors` checks given shift
factors against estimated ones after bringing both to the same reference temperature.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy.optimize import least_squares, minimize_scalar

from idkit.checks import Choice, Real, Samples, Whole, accepts
from idkit.errors import DataError

__all__ = [
    "ShiftFactorCheck",
    "ShiftFactorEstimate",
    "ShiftLawFit",
    "compare_shift_factors",
    "estimate_shift_factors",
    "fit_shift_polynomial",
    "fit_wlf",
    "group_isotherms",
    "wlf_log_shift",
]

#: Scan step of the pairwise shift search, decades of frequency.
SCAN_STEP_DECADES = 0.02
#: Smallest tolerance when checking given shift factors, decades (a quarter decade is
#: where the isotherms of a master curve start to show visible steps). The tolerance at
#: each temperature is the larger of this and 3 x the estimate's standard error there.
CHECK_TOLERANCE_DECADES = 0.25


@dataclass(frozen=True)
class ShiftFactorEstimate:
    """Shift factors estimated from isotherms.

    Attributes
    ----------
    temperature_k : numpy.ndarray
        Isotherm temperatures in K, ascending.
    log_a_t : numpy.ndarray
        Decimal log of the shift factor of each isotherm (0 at the reference).
    reference_temperature_k : float
        Reference temperature in K.
    pair_shift_decades : numpy.ndarray
        Relative shift ``log aT[i+1] - log aT[i]`` of each adjacent pair, decades.
    pair_residual_decades : numpy.ndarray
        RMS difference of ``log10 |E*|`` (decades) over the overlap of each pair at its shift.
    pair_overlap_points : numpy.ndarray
        Number of points that entered each pair's residual.
    pair_shift_stderr_decades : numpy.ndarray
        Standard error of each pair's shift, linearised: residual variance over the sum
        of squared local slopes of the curves: large where the curves are flat (glassy
        or rubbery plateau).
    log_a_t_stderr : numpy.ndarray
        Standard error of ``log_a_t``: the pair errors between the isotherm and the
        reference summed in quadrature.
    """

    temperature_k: np.ndarray
    log_a_t: np.ndarray
    reference_temperature_k: float
    pair_shift_decades: np.ndarray
    pair_residual_decades: np.ndarray
    pair_overlap_points: np.ndarray
    pair_shift_stderr_decades: np.ndarray
    log_a_t_stderr: np.ndarray

    def to_dataframe(self) -> pd.DataFrame:
        """Columns ``temperature [K]``, ``temperature [C]``, ``log_aT [-]``."""
        return pd.DataFrame({"temperature [K]": self.temperature_k,
                             "temperature [C]": self.temperature_k - 273.15,
                             "log_aT [-]": self.log_a_t, "log_aT stderr [-]": self.log_a_t_stderr})


@dataclass(frozen=True)
class ShiftLawFit:
    """A shift-factor law fitted to ``(T, log aT)`` points.

    Attributes
    ----------
    law : str
        ``"wlf"`` or ``"polynomial"``.
    reference_temperature_k : float
        Reference temperature in K.
    coefficients : dict
        WLF: ``C1`` (-) and ``C2`` (K); polynomial: ``c1``, ``c2``, ... of
        ``sum c_k (T - T_ref)**k`` (units 1/K**k).
    rms_residual_decades : float
        RMS of ``log aT`` fitted minus given, decades.
    max_residual_decades : float
        Largest absolute residual, decades.
    """

    law: str
    reference_temperature_k: float
    coefficients: dict
    rms_residual_decades: float
    max_residual_decades: float

    def log_a_t(self, temperature_k) -> np.ndarray:
        """Decimal log of the shift factor at ``temperature_k`` (K)."""
        dt = np.asarray(temperature_k, dtype=float) - self.reference_temperature_k
        if self.law == "wlf":
            return wlf_log_shift(temperature_k, c1=self.coefficients["C1"], c2_k=self.coefficients["C2"],
                                 reference_temperature_k=self.reference_temperature_k)
        degree = len(self.coefficients)
        return sum(self.coefficients[f"c{k}"] * dt ** k for k in range(1, degree + 1))


@dataclass(frozen=True)
class ShiftFactorCheck:
    """Given shift factors against estimated ones, at the estimate's reference temperature.

    Attributes
    ----------
    table : pandas.DataFrame
        ``temperature [K]``, ``given log_aT [-]`` (re-referenced), ``estimated log_aT [-]``,
        ``difference [decades]``, ``tolerance [decades]`` (the larger of the floor and 3
        standard errors of the estimate at that temperature), ``agrees``.
    max_difference_decades : float
        Largest absolute difference.
    tolerance_decades : float
        The floor of the tolerance.
    agrees : bool
        Every difference within its row's tolerance.
    """

    table: pd.DataFrame
    max_difference_decades: float
    tolerance_decades: float
    agrees: bool

    def summary(self) -> str:
        """One line: agreement and the largest difference."""
        word = "agree" if self.agrees else "DISAGREE"
        excess = np.abs(self.table["difference [decades]"]) / self.table["tolerance [decades]"]
        worst = self.table.iloc[int(np.argmax(excess))]
        return (f"given shift factors {word} with the isotherms: {int((~self.table['agrees']).sum())} of "
                f"{len(self.table)} temperatures outside tolerance; worst {worst['difference [decades]']:+.2f} "
                f"decades at {worst['temperature [K]'] - 273.15:.1f} C (tolerance {worst['tolerance [decades]']:.2f})")


@accepts(c1=Real(), c2_k=Real(unit="K"), reference_temperature_k=Real(unit="K", gt=0), error=DataError)
def wlf_log_shift(temperature_k, *, c1: float, c2_k: float, reference_temperature_k: float) -> np.ndarray:
    """WLF law ``log10 aT = -C1 (T - T_ref) / (C2 + T - T_ref)``.

    Parameters
    ----------
    temperature_k : array_like
        Temperature in K.
    c1 : float
        WLF constant C1 (dimensionless).
    c2_k : float
        WLF constant C2 in K.
    reference_temperature_k : float
        Reference temperature in K.

    Returns
    -------
    numpy.ndarray
        ``log10 aT`` (NaN where ``C2 + T - T_ref <= 0``: the law has no meaning there).

    Examples
    --------
    >>> round(float(wlf_log_shift(303.15, c1=17.44, c2_k=51.6, reference_temperature_k=293.15)), 3)
    -2.831
    """
    dt = np.asarray(temperature_k, dtype=float) - reference_temperature_k
    denominator = c2_k + dt
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(denominator > 0, -c1 * dt / denominator, np.nan)


@accepts(temperature_k=Samples(unit="K"), group_tol_k=Real(unit="K", gt=0), error=DataError)
def group_isotherms(temperature_k, *, group_tol_k: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Group rows into isotherms by temperature.

    Parameters
    ----------
    temperature_k : array_like
        Temperature of each row in K.
    group_tol_k : float
        A gap wider than this between sorted temperatures starts a new isotherm.

    Returns
    -------
    labels : numpy.ndarray
        Isotherm index of each row (0 = coldest).
    temperatures : numpy.ndarray
        Mean temperature of each isotherm, K, ascending.

    Examples
    --------
    >>> labels, temps = group_isotherms([300.0, 300.1, 280.0, 279.9])
    >>> labels.tolist(), temps.round(2).tolist()
    ([1, 1, 0, 0], [279.95, 300.05])
    """
    temperature = temperature_k
    order = np.argsort(temperature, kind="stable")
    starts = np.concatenate([[True], np.diff(temperature[order]) > group_tol_k])
    sorted_labels = np.cumsum(starts) - 1
    labels = np.empty_like(sorted_labels)
    labels[order] = sorted_labels
    temperatures = np.array([temperature[labels == i].mean() for i in range(sorted_labels[-1] + 1)])
    return labels, temperatures


#: Degree of the polynomial in log10 f that represents each isotherm (fewer when an
#: isotherm has fewer points): smooth, so the pair cost has one minimum near the shift.
SMOOTHING_DEGREE = 3


@dataclass(frozen=True)
class _Isotherm:
    """One isotherm: points ``(log10 f, log10 |E*|)`` sorted by frequency and their
    least-squares polynomial ``P(x) = V(x) @ hat @ y``."""

    x: np.ndarray
    y: np.ndarray
    centre: float
    scale: float
    hat: np.ndarray  # (degree + 1, n): coefficients = hat @ y

    @classmethod
    def of(cls, log_f: np.ndarray, log_e: np.ndarray, degree: int = SMOOTHING_DEGREE) -> _Isotherm:
        order = np.argsort(log_f, kind="stable")
        x, y = log_f[order], log_e[order]
        centre = float(x.mean())
        scale = max(float(np.ptp(x)) / 2, 1e-12)
        degree = min(degree, x.size - 1)
        hat = np.linalg.pinv(np.vander((x - centre) / scale, degree + 1))
        return cls(x, y, centre, scale, hat)

    def basis(self, at: np.ndarray) -> np.ndarray:
        return np.vander((at - self.centre) / self.scale, self.hat.shape[0])

    def value(self, at: np.ndarray) -> np.ndarray:
        return self.basis(at) @ (self.hat @ self.y)

    def slope(self, at: np.ndarray) -> np.ndarray:
        coefficients = np.polyder(self.hat @ self.y)
        return np.polyval(coefficients, (at - self.centre) / self.scale) / self.scale

    def covers(self, at: np.ndarray) -> np.ndarray:
        return (at >= self.x[0]) & (at <= self.x[-1])


def _directions(delta: float, a: _Isotherm, b: _Isotherm):
    """Both residual directions: b's points against a's polynomial at ``x + delta`` and
    a's points against b's polynomial at ``x - delta``: (points, other, at, sign)."""
    for own, other, sign in ((b, a, 1.0), (a, b, -1.0)):
        at = own.x + sign * delta
        inside = np.flatnonzero(other.covers(at))
        yield own, other, inside, at[inside], sign


def _pair_cost(delta: float, a: _Isotherm, b: _Isotherm) -> tuple[float, int]:
    """Mean squared log-modulus difference over both directions, and the point count."""
    residual = [own.y[inside] - other.value(at) for own, other, inside, at, _ in _directions(delta, a, b)]
    residual = np.concatenate(residual)
    if residual.size == 0:
        return np.inf, 0
    return float(np.mean(residual ** 2)), residual.size


def _pair_shift(a: _Isotherm, b: _Isotherm, *, min_points: int) -> tuple[float, float, int, float]:
    """Relative shift delta (decades) with b(x) = a(x + delta), RMS residual, points, stderr."""
    # a horizontal shift can only superpose curves whose modulus ranges overlap
    low_e, high_e = max(a.y.min(), b.y.min()), min(a.y.max(), b.y.max())
    shared = np.sum((a.y >= low_e) & (a.y <= high_e)) + np.sum((b.y >= low_e) & (b.y <= high_e))
    if shared < min_points:
        return np.nan, np.nan, 0, np.nan
    low, high = a.x[0] - b.x[-1], a.x[-1] - b.x[0]
    grid = np.arange(low, high + SCAN_STEP_DECADES, SCAN_STEP_DECADES)
    costs = np.array([c if n >= min_points else np.inf for c, n in (_pair_cost(d, a, b) for d in grid)])
    if not np.any(np.isfinite(costs)):
        return np.nan, np.nan, 0, np.nan
    best = int(np.argmin(costs))
    bracket = (grid[max(best - 1, 0)], grid[min(best + 1, grid.size - 1)])
    refined = minimize_scalar(lambda d: _pair_cost(d, a, b)[0], bounds=bracket, method="bounded",
                              options={"xatol": 1e-7})
    delta = float(refined.x) if refined.fun <= costs[best] else float(grid[best])
    cost, points = _pair_cost(delta, a, b)
    return delta, float(np.sqrt(cost)), points, _shift_stderr(delta, a, b)


def _shift_stderr(delta: float, a: _Isotherm, b: _Isotherm) -> float:
    """Standard error of a pair's shift by linear propagation of independent point noise.

    At the minimum the Gauss-Newton step gives ``delta`` as a linear function of the
    measured values: ``d delta = s^T D dy / (s^T s)`` with ``s`` the slopes of the other
    curve's polynomial (``d log10 |E*| / d log10 f``) at the shifted points and
    ``D = dr/dy`` the residuals' dependence on every measured point (1 for the point
    itself, minus the polynomial's weights on the other curve's points). Each point
    enters several residuals, so counting residuals as independent would understate the
    error; here ``var = sigma^2 |s^T D|^2 / (s^T s)^2`` with the point noise
    ``sigma^2 = |r|^2 / trace(D D^T)`` estimated from the residuals themselves. Large
    where the curves are flat (glassy or rubbery plateau).
    """
    offset = {id(a): 0, id(b): a.x.size}
    residuals, slopes, rows = [], [], []
    for own, other, inside, at, sign in _directions(delta, a, b):
        d = np.zeros((inside.size, a.x.size + b.x.size))
        d[np.arange(inside.size), offset[id(own)] + inside] = 1.0
        d[:, offset[id(other)]:offset[id(other)] + other.x.size] -= other.basis(at) @ other.hat
        residuals.append(own.y[inside] - other.value(at))
        slopes.append(sign * other.slope(at))  # the reverse direction moves the other way
        rows.append(d)
    residual, slope, d = np.concatenate(residuals), np.concatenate(slopes), np.concatenate(rows)
    if residual.size < 2 or not np.any(slope):
        return np.inf
    noise_variance = float(residual @ residual) / float(np.sum(d * d)) * residual.size / (residual.size - 1)
    gain = slope @ d / float(slope @ slope)
    return float(np.sqrt(noise_variance * float(gain @ gain)))


@accepts(reference_temperature_k=Real(unit="K", gt=0), quantity=Choice(("magnitude", "storage")), group_tol_k=Real(unit="K", gt=0),
         min_overlap_points=Whole(ge=1), polynomial_degree=Whole(ge=1), error=DataError)
def estimate_shift_factors(freq_hz, storage, loss, temperature_k, *, reference_temperature_k: float,
                           quantity: str = "magnitude", group_tol_k: float = 1.0,
                           min_overlap_points: int = 3, polynomial_degree: int = 4,
                           source: str = "isotherms") -> ShiftFactorEstimate:
    """Estimate shift factors from isotherm sweeps (method in the module docstring).

    Parameters
    ----------
    freq_hz, storage, loss, temperature_k : array_like
        One row per measured point: frequency in Hz (> 0), storage and loss part
        (Pa or N/m; only ratios matter), test temperature in K.
    reference_temperature_k : float
        Temperature in K where ``log aT = 0``.
    quantity : {"magnitude", "storage"}
        Curve that is superposed: ``log10 |E*|`` or ``log10 E'``.
    group_tol_k : float
        Temperature gap in K that separates isotherms.
    min_overlap_points : int
        Fewest points of a pair that must overlap at the chosen shift.
    polynomial_degree : int
        Degree of the polynomial used to re-reference when no isotherm lies at the
        reference temperature.
    source : str
        Name used in error messages (file name).

    Returns
    -------
    ShiftFactorEstimate

    Raises
    ------
    DataError
        Fewer than two isotherms, a non-positive frequency or modulus, or a pair of
        adjacent isotherms that do not overlap.

    Examples
    --------
    >>> import numpy as np
    >>> f = np.logspace(-1, 2, 10)
    >>> law = lambda fr: 1e6 * (1 + (2j * np.pi * fr / 10) ** 0.5)
    >>> rows = [(f, law(f * 10.0 ** s), t) for s, t in [(1.0, 270.0), (0.0, 280.0), (-1.0, 290.0)]]
    >>> freq, e, temp = (np.concatenate(c) for c in zip(*[(r[0], r[1], np.full(10, r[2])) for r in rows]))
    >>> est = estimate_shift_factors(freq, e.real, e.imag, temp, reference_temperature_k=280.0)
    >>> np.round(est.log_a_t, 2).tolist()
    [1.0, 0.0, -1.0]
    """
    freq = np.asarray(freq_hz, dtype=float)
    storage = np.asarray(storage, dtype=float)
    loss = np.asarray(loss, dtype=float)
    if not (freq.shape == storage.shape == loss.shape == np.shape(temperature_k)) or freq.ndim != 1:
        raise DataError(f"{source}: found column shapes {freq.shape}, {storage.shape}, {loss.shape}, "
                        f"{np.shape(temperature_k)}, expected equal 1-D columns")
    value = np.abs(storage + 1j * loss) if quantity == "magnitude" else storage
    for name, column in (("frequency", freq), (quantity, value)):
        bad = np.flatnonzero(~(np.isfinite(column) & (column > 0)))
        if bad.size:
            raise DataError(f"{source}: column {name}, row {int(bad[0]) + 1}: found {column[bad[0]]!r}, "
                            "expected a finite positive value (log-log superposition)")
    labels, temperatures = group_isotherms(temperature_k, group_tol_k=group_tol_k)  # checks the temperatures
    if temperatures.size < 2:
        raise DataError(f"{source}: found one isotherm ({temperatures[0] - 273.15:.1f} C), expected at "
                        "least two temperatures to estimate shift factors")
    curves = [_Isotherm.of(np.log10(freq[labels == i]), np.log10(value[labels == i])) for i in range(temperatures.size)]
    shifts, residuals, points, errors = [], [], [], []
    for i in range(temperatures.size - 1):
        delta, residual, n, stderr = _pair_shift(curves[i], curves[i + 1], min_points=min_overlap_points)
        if not np.isfinite(delta):
            raise DataError(
                f"{source}: isotherms at {temperatures[i] - 273.15:.1f} C and {temperatures[i + 1] - 273.15:.1f} C "
                f"do not overlap: fewer than {min_overlap_points} points lie in the modulus range both cover; "
                "expected adjacent isotherms whose modulus ranges overlap (measure at a temperature between them)")
        shifts.append(delta)
        residuals.append(residual)
        points.append(n)
        errors.append(stderr)
    shifts, errors = np.array(shifts), np.array(errors)
    cumulative = np.concatenate([[0.0], np.cumsum(shifts)])
    nearest = int(np.argmin(np.abs(temperatures - reference_temperature_k)))
    log_a_t = cumulative - cumulative[nearest]
    # standard error of each isotherm's shift: pair errors summed in quadrature from the
    # reference isotherm outwards (pairs are independent: disjoint point sets per pair)
    variance = np.concatenate([[0.0], np.cumsum(errors ** 2)])
    log_a_t_stderr = np.sqrt(np.abs(variance - variance[nearest]))
    if abs(temperatures[nearest] - reference_temperature_k) > group_tol_k:
        provisional = fit_shift_polynomial(temperatures, log_a_t, reference_temperature_k=temperatures[nearest],
                                           degree=min(polynomial_degree, temperatures.size - 1))
        log_a_t = log_a_t - float(provisional.log_a_t(reference_temperature_k))
    return ShiftFactorEstimate(temperature_k=temperatures, log_a_t=log_a_t,
                               reference_temperature_k=float(reference_temperature_k),
                               pair_shift_decades=shifts, pair_residual_decades=np.array(residuals),
                               pair_overlap_points=np.array(points), pair_shift_stderr_decades=errors,
                               log_a_t_stderr=log_a_t_stderr)


def _points(temperature_k, log_a_t) -> tuple[np.ndarray, np.ndarray]:
    t = np.asarray(temperature_k, dtype=float)
    y = np.asarray(log_a_t, dtype=float)
    if t.shape != y.shape or t.ndim != 1 or t.size == 0 or not (np.all(np.isfinite(t)) and np.all(np.isfinite(y))):
        raise DataError(f"shift factors: found shapes {t.shape} and {y.shape}, expected equal non-empty 1-D "
                        "arrays of finite temperatures (K) and log10 shift factors")
    return t, y


@accepts(reference_temperature_k=Real(unit="K", gt=0), error=DataError)
def fit_wlf(temperature_k, log_a_t, *, reference_temperature_k: float) -> ShiftLawFit:
    """Fit the WLF law to shift factors (least squares in ``log aT``).

    Parameters
    ----------
    temperature_k, log_a_t : array_like
        Temperatures in K and decimal-log shift factors (0 at the reference).
    reference_temperature_k : float
        Reference temperature in K.

    Returns
    -------
    ShiftLawFit
        ``coefficients = {"C1": ..., "C2": ...}`` (C2 in K). Constrained to ``C2 > T_ref -
        min(T)`` so that the law is finite over the data.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(260.0, 380.0, 13)
    >>> fit = fit_wlf(t, wlf_log_shift(t, c1=12.0, c2_k=80.0, reference_temperature_k=290.0),
    ...               reference_temperature_k=290.0)
    >>> round(fit.coefficients["C1"], 6), round(fit.coefficients["C2"], 4)
    (12.0, 80.0)
    """
    t, y = _points(temperature_k, log_a_t)
    if t.size < 3:
        raise DataError(f"shift factors: found {t.size} temperatures, expected at least 3 to fit C1 and C2")
    dt = t - reference_temperature_k
    c2_min = max(-dt.min(), 0.0) + 1e-3

    def residual(p):
        c1, c2 = p
        return -c1 * dt / (c2 + dt) - y

    best = None
    for c2_start in (c2_min + 10.0, c2_min + 50.0, c2_min + 200.0, c2_min + 1000.0):
        # for a given C2 the law is linear in C1: start from that C1
        shape = -dt / (c2_start + dt)
        c1_start = float(shape @ y / (shape @ shape)) if shape @ shape > 0 else 1.0
        run = least_squares(residual, [c1_start, c2_start], bounds=([-np.inf, c2_min], [np.inf, np.inf]),
                            x_scale=[max(abs(c1_start), 1.0), c2_start], xtol=1e-14, ftol=1e-14, gtol=1e-14)
        if best is None or run.cost < best.cost:
            best = run
    r = residual(best.x)
    return ShiftLawFit("wlf", float(reference_temperature_k), {"C1": float(best.x[0]), "C2": float(best.x[1])},
                       float(np.sqrt(np.mean(r ** 2))), float(np.max(np.abs(r))))


@accepts(reference_temperature_k=Real(unit="K", gt=0), degree=Whole(ge=1), error=DataError)
def fit_shift_polynomial(temperature_k, log_a_t, *, reference_temperature_k: float, degree: int = 4) -> ShiftLawFit:
    """Fit ``log aT = sum_{k=1}^{degree} c_k (T - T_ref)**k`` by linear least squares.

    Parameters
    ----------
    temperature_k, log_a_t : array_like
        Temperatures in K and decimal-log shift factors.
    reference_temperature_k : float
        Reference temperature in K (no constant term: ``log aT(T_ref) = 0``).
    degree : int
        Polynomial degree, 1 .. number of points.

    Returns
    -------
    ShiftLawFit

    Examples
    --------
    >>> fit = fit_shift_polynomial([270.0, 280.0, 290.0], [0.2, 0.0, -0.2], reference_temperature_k=280.0, degree=1)
    >>> round(fit.coefficients["c1"], 12)
    -0.02
    """
    t, y = _points(temperature_k, log_a_t)
    if degree > t.size:
        raise DataError(f"degree: found {degree!r}, expected an integer from 1 to the number of temperatures ({t.size})")
    dt = t - reference_temperature_k
    scale = max(float(np.max(np.abs(dt))), 1.0)
    design = np.stack([(dt / scale) ** k for k in range(1, degree + 1)], axis=1)
    coef, *_ = np.linalg.lstsq(design, y, rcond=None)
    r = design @ coef - y
    coefficients = {f"c{k}": float(coef[k - 1] / scale ** k) for k in range(1, degree + 1)}
    return ShiftLawFit("polynomial", float(reference_temperature_k), coefficients,
                       float(np.sqrt(np.mean(r ** 2))), float(np.max(np.abs(r))))


@accepts(tolerance_decades=Real(gt=0), temperature_tol_k=Real(unit="K", gt=0), error=DataError)
def compare_shift_factors(given_temperature_k, given_log_a_t, estimate: ShiftFactorEstimate, *,
                          tolerance_decades: float = CHECK_TOLERANCE_DECADES,
                          temperature_tol_k: float = 1.0) -> ShiftFactorCheck:
    """Check given shift factors against the ones estimated from the isotherms.

    The given set is re-referenced to the estimate's reference (its value at the isotherm
    where the estimate is zero, or linearly interpolated at the reference temperature, is
    subtracted) and compared at the isotherm temperatures within ``temperature_tol_k`` of
    a given temperature (given sets list nominal temperatures, isotherms measured ones).

    Parameters
    ----------
    given_temperature_k, given_log_a_t : array_like
        The given shift factors (K, decades).
    estimate : ShiftFactorEstimate
        Shift factors estimated from the isotherms.
    tolerance_decades : float
        Floor of the accepted difference, decades; at each temperature the tolerance is the
        larger of this and 3 standard errors of the estimate.
    temperature_tol_k : float
        Largest distance between an isotherm and a given temperature to compare them.

    Returns
    -------
    ShiftFactorCheck

    Raises
    ------
    DataError
        If no given temperature is within ``temperature_tol_k`` of an isotherm, or the
        given set does not span the reference temperature.
    """
    t, y = _points(given_temperature_k, given_log_a_t)
    order = np.argsort(t)
    t, y = t[order], y[order]
    t_ref = estimate.reference_temperature_k
    if not (t[0] - temperature_tol_k <= t_ref <= t[-1] + temperature_tol_k):
        raise DataError(f"given shift factors span {t[0] - 273.15:.1f} .. {t[-1] - 273.15:.1f} C, expected the "
                        f"reference temperature {t_ref - 273.15:.1f} C inside")
    distance = np.abs(estimate.temperature_k[:, None] - t[None, :])
    nearest = np.argmin(distance, axis=1)
    matched = distance[np.arange(nearest.size), nearest] <= temperature_tol_k
    if not np.any(matched):
        raise DataError(f"given shift factors: no temperature within {temperature_tol_k} K of an isotherm")
    # re-reference: the given value at the isotherm the estimate is zero at (matched by
    # temperature like every other row: given sets list nominal temperatures), or
    # interpolated at the reference temperature when that isotherm has no given value
    zero = np.flatnonzero((estimate.log_a_t == 0.0) & matched)
    y = y - (y[nearest[zero[0]]] if zero.size else float(np.interp(t_ref, t, y)))
    table = pd.DataFrame({"temperature [K]": estimate.temperature_k[matched],
                          "given log_aT [-]": y[nearest[matched]],
                          "estimated log_aT [-]": estimate.log_a_t[matched]})
    table["difference [decades]"] = table["given log_aT [-]"] - table["estimated log_aT [-]"]
    table["tolerance [decades]"] = np.maximum(tolerance_decades, 3 * estimate.log_a_t_stderr[matched])
    table["agrees"] = np.abs(table["difference [decades]"]) <= table["tolerance [decades]"]
    worst = float(np.max(np.abs(table["difference [decades]"])))
    return ShiftFactorCheck(table, worst, float(tolerance_decades), bool(table["agrees"].all()))
