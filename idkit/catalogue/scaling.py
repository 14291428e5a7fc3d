"""Scaling laws: a family's summary quantities as power laws of its dimensions, with uncertainty.

Model (log space, one quantity ``q`` of a family)::

    log q_i = x_i^T beta + e_i + u_i,   e_i ~ N(0, s_i^2),  u_i ~ N(0, tau^2)

* wire rope: ``x = [1, log(d / d_ref), log(n / n_ref), log(H / H_ref), ...]`` (power laws in
  the cable diameter, the number of loops and the loop height by default; the width may be
  added but is collinear with the height in most ranges), for the stuck stiffness
  ``g1 + sum k_i``, the large-amplitude stiffness ``g1`` and the total slip force ``sum fc_i``;
* elastomer: the compression rule of :meth:`idkit.models.GeneralizedMaxwell.to_stiffness`,
  ``k = E_c (1 + 2 S^2) A / h``, as ``x = [one indicator per compound, log(G / G_ref)]`` with
  ``G = (1 + 2 S^2) A / h`` (m): each compound's static modulus and one geometry exponent
  (1 for the rule), for ``k0``.

``s_i`` is the part's own standard error of ``log q`` (from its fit covariance) and ``tau``
the part-to-part scatter, estimated by the Paule-Mandel rule (``sum r_i^2 / (s_i^2 + tau^2)
= n - p``, the residuals' expected sum); ``beta`` by weighted least squares with weights
``1 / (s_i^2 + tau^2)``, its covariance ``(X^T W X)^-1``. A part never measured is predicted
with the variance ``x^T C x + tau^2`` and a band of Student-t quantiles with ``n - p`` degrees
of freedom (:meth:`ScalingLaw.predict`). :func:`leave_one_part_out` refits without each
part and counts how often that part falls inside its band (the stated coverage).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import pandas as pd
from scipy import stats

from idkit.errors import FitError

__all__ = ["DEFAULT_DIMENSIONS", "LAW_QUANTITIES", "Prediction", "ScalingLaw", "fit_scaling_law",
           "leave_one_part_out", "quantity_log_variance"]

#: Dimensions the power laws use by default, per family.
DEFAULT_DIMENSIONS = {"wire_rope": ("cable_diameter_m", "loops", "height_m"), "elastomer": ("geometry",)}
#: Quantities a law can be fitted to, per family, and the model parameters that sum to each.
LAW_QUANTITIES = {
    "wire_rope": {"stuck_stiffness": ("g1", "k_"), "g1": ("g1",), "total_slip_force": ("fc_",)},
    "elastomer": {"k0": ("k0",)},
}


def geometry_factor(dimensions: dict) -> float:
    """``(1 + 2 S^2) A / h`` in m of an elastomer part (the compression rule of ``to_stiffness``)."""
    return (1.0 + 2.0 * dimensions["shape_factor"] ** 2) * dimensions["area_m2"] / dimensions["thickness_m"]


def quantity_log_variance(record: dict, quantity: str) -> float:
    """Variance of ``log q`` of one part from its covariance (0 when the parts are not covered)."""
    prefixes = LAW_QUANTITIES[record["family"]][quantity]
    names = record["covariance"]["names"]
    matrix = np.asarray(record["covariance"]["matrix"], dtype=float).reshape(len(names), len(names))
    pick = np.array([any(name == p or (p.endswith("_") and name.startswith(p)) for p in prefixes) for name in names],
                    dtype=bool)
    value = record["quantities"][quantity]
    if not pick.any() or not value > 0:
        return 0.0
    variance = float(pick.astype(float) @ matrix @ pick.astype(float))
    return max(variance, 0.0) / value**2


@dataclass(frozen=True)
class Prediction:
    """A predicted quantity with its band: ``value`` (median), ``low``, ``high`` and ``log_sd``."""

    value: float
    low: float
    high: float
    log_sd: float
    level: float


@dataclass(frozen=True)
class ScalingLaw:
    """A fitted power law (module docstring).

    Attributes
    ----------
    family, quantity : str
    dimensions : tuple of str
        Regressors (``"geometry"`` stands for ``(1 + 2 S^2) A / h`` of an elastomer).
    reference : dict
        Value each dimension is divided by (geometric mean over the parts).
    names : tuple of str
        Coefficient names: ``log q_ref`` (wire rope) or ``log E [compound]`` (elastomer), then
        one exponent per dimension.
    coefficients : ndarray; covariance : ndarray
    tau : float
        Part-to-part scatter (standard deviation of ``log q``).
    parts : tuple of str
    residuals : ndarray
        ``log q_i - x_i^T beta`` per part.
    """

    family: str
    quantity: str
    dimensions: tuple
    reference: dict
    names: tuple
    coefficients: np.ndarray
    covariance: np.ndarray
    tau: float
    parts: tuple
    residuals: np.ndarray
    compounds: tuple = ()

    @property
    def dof(self) -> int:
        """Degrees of freedom ``n - p``."""
        return len(self.parts) - len(self.coefficients)

    def exponent(self, dimension: str) -> tuple[float, float]:
        """Exponent of ``dimension`` and its standard error."""
        index = self.names.index(f"exponent {dimension}")
        return float(self.coefficients[index]), float(math.sqrt(self.covariance[index, index]))

    def _row(self, dimensions: dict) -> np.ndarray:
        if self.family == "elastomer":
            compound = dimensions["compound"]
            if compound not in self.compounds:
                raise FitError(f"compound: found {compound!r}, expected one the law was fitted on: {self.compounds}")
            row = [1.0 if compound == c else 0.0 for c in self.compounds]
            return np.array(row + [math.log(geometry_factor(dimensions) / self.reference["geometry"])])
        missing = [name for name in self.dimensions if name not in dimensions]
        if missing:
            raise FitError(f"dimensions: missing {missing}, expected {list(self.dimensions)}")
        return np.array([1.0] + [math.log(float(dimensions[name]) / self.reference[name]) for name in self.dimensions])

    def predict(self, dimensions: dict, *, level: float = 0.95) -> Prediction:
        """The quantity of a part with these dimensions, with a ``level`` prediction band."""
        row = self._row(dimensions)
        centre = float(row @ self.coefficients)
        sd = math.sqrt(float(row @ self.covariance @ row) + self.tau**2)
        quantile = float(stats.t.ppf(0.5 + level / 2.0, max(self.dof, 1)))
        return Prediction(math.exp(centre), math.exp(centre - quantile * sd), math.exp(centre + quantile * sd), sd,
                          level)

    def to_dataframe(self) -> pd.DataFrame:
        """One row per coefficient: value and standard error."""
        return pd.DataFrame({"coefficient": self.names, "value": self.coefficients,
                             "stderr": np.sqrt(np.diag(self.covariance))})

    def report(self) -> str:
        """The law in a few lines."""
        lines = [f"{self.family} {self.quantity}: {len(self.parts)} parts, part-to-part scatter tau = {self.tau:.3g} "
                 f"(log), {self.dof} degrees of freedom"]
        lines += [f"    {name} = {value:.4g} +- {se:.2g}" for name, value, se in
                  zip(self.names, self.coefficients, np.sqrt(np.diag(self.covariance)))]
        return "\n".join(lines)

    def to_dict(self) -> dict:
        """JSON-ready law."""
        return {"family": self.family, "quantity": self.quantity, "dimensions": list(self.dimensions),
                "reference": self.reference, "names": list(self.names), "coefficients": self.coefficients.tolist(),
                "covariance": self.covariance.tolist(), "tau": self.tau, "parts": list(self.parts),
                "compounds": list(self.compounds)}


def _paule_mandel(design: np.ndarray, y: np.ndarray, own: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    n, p = design.shape

    def solve(tau2):
        weights = 1.0 / (np.maximum(own, 1e-12) + tau2)
        normal = design.T @ (weights[:, None] * design)
        covariance = np.linalg.inv(normal)
        beta = covariance @ design.T @ (weights * y)
        residual = y - design @ beta
        return beta, covariance, float(np.sum(weights * residual**2))

    beta, covariance, q = solve(0.0)
    if n <= p or q <= n - p:
        return beta, covariance, 0.0
    low, high = 0.0, max(float(np.var(y)), 1e-12)
    while solve(high)[2] > n - p:
        high *= 4.0
    for _ in range(200):  # bisection on the monotone decreasing q(tau^2)
        middle = 0.5 * (low + high)
        if solve(middle)[2] > n - p:
            low = middle
        else:
            high = middle
    tau2 = 0.5 * (low + high)
    beta, covariance, _ = solve(tau2)
    return beta, covariance, tau2


def fit_scaling_law(records: Sequence[dict], quantity: str, *, dimensions: Sequence[str] | None = None) -> ScalingLaw:
    """Fit one quantity of one family over its parts (module docstring).

    Parameters
    ----------
    records : sequence of dict
        Catalogue part records of one family (``Catalogue.usable()``), each with
        ``dimensions``, ``quantities`` and ``covariance``.
    quantity : str
        One of :data:`LAW_QUANTITIES` of the family.
    dimensions : sequence of str, optional
        Wire rope: dimension names (default :data:`DEFAULT_DIMENSIONS`); elastomer: ignored
        (the compression rule's geometry factor and the compounds).

    Returns
    -------
    ScalingLaw

    Raises
    ------
    FitError
        Mixed families, an unknown quantity, fewer parts than coefficients plus one, or a
        design whose dimensions do not vary independently (singular).
    """
    records = list(records)
    if not records:
        raise FitError("records: found none, expected the part records of one family")
    families = {record["family"] for record in records}
    if len(families) != 1:
        raise FitError(f"records: found families {sorted(families)}, expected one")
    family = families.pop()
    if quantity not in LAW_QUANTITIES[family]:
        raise FitError(f"quantity: found {quantity!r}, expected one of {sorted(LAW_QUANTITIES[family])} for {family}")
    y = np.log([float(record["quantities"][quantity]) for record in records])
    own = np.array([quantity_log_variance(record, quantity) for record in records])
    compounds: tuple = ()
    if family == "elastomer":
        dims = ("geometry",)
        factors = np.array([geometry_factor(record["dimensions"]) for record in records])
        reference = {"geometry": float(np.exp(np.mean(np.log(factors))))}
        compounds = tuple(sorted({record["dimensions"]["compound"] for record in records}))
        design = np.column_stack([[1.0 if r["dimensions"]["compound"] == c else 0.0 for r in records] for c in compounds]
                                 + [np.log(factors / reference["geometry"])])
        names = tuple(f"log E [{c}]" for c in compounds) + ("exponent geometry",)
    else:
        dims = tuple(dimensions or DEFAULT_DIMENSIONS[family])
        values = {name: np.array([float(record["dimensions"][name]) for record in records]) for name in dims}
        reference = {name: float(np.exp(np.mean(np.log(v)))) for name, v in values.items()}
        design = np.column_stack([np.ones(len(records))] + [np.log(values[name] / reference[name]) for name in dims])
        names = ("log q_ref",) + tuple(f"exponent {name}" for name in dims)
    n, p = design.shape
    if n < p + 1:
        raise FitError(f"{family} {quantity}: found {n} parts, expected at least {p + 1} for {p} coefficients")
    if np.linalg.matrix_rank(design) < p:
        raise FitError(f"{family} {quantity}: the dimensions {list(dims)} do not vary independently over the parts "
                       "(singular design); drop one or add parts")
    beta, covariance, tau2 = _paule_mandel(design, y, own)
    return ScalingLaw(family=family, quantity=quantity, dimensions=dims, reference=reference, names=names,
                      coefficients=beta, covariance=covariance, tau=math.sqrt(tau2),
                      parts=tuple(record["part"] for record in records), residuals=y - design @ beta,
                      compounds=compounds)


def leave_one_part_out(records: Sequence[dict], quantity: str, *, level: float = 0.95,
                       dimensions: Sequence[str] | None = None) -> pd.DataFrame:
    """Refit without each part and check the part against its ``level`` prediction band.

    Returns one row per part: measured value, prediction, band, and ``inside`` (bool). The
    band counts the left-out part's own measurement variance too. Its mean is the coverage.
    """
    records = list(records)
    rows = []
    for index, record in enumerate(records):
        others = records[:index] + records[index + 1:]
        law = fit_scaling_law(others, quantity, dimensions=dimensions)
        try:
            prediction = law.predict(record["dimensions"], level=level)
        except FitError as problem:  # e.g. the only part of its compound
            rows.append({"part": record["part"], "measured": record["quantities"][quantity], "predicted": np.nan,
                         "low": np.nan, "high": np.nan, "inside": False, "note": str(problem)})
            continue
        own = quantity_log_variance(record, quantity)
        sd = math.sqrt(prediction.log_sd**2 + own)
        quantile = float(stats.t.ppf(0.5 + level / 2.0, max(law.dof, 1)))
        centre = math.log(prediction.value)
        measured = float(record["quantities"][quantity])
        rows.append({"part": record["part"], "measured": measured, "predicted": prediction.value,
                     "low": math.exp(centre - quantile * sd), "high": math.exp(centre + quantile * sd),
                     "inside": bool(abs(math.log(measured) - centre) <= quantile * sd), "note": ""})
    return pd.DataFrame(rows)
