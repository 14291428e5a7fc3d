"""Typed results of the Maxwell and Voigt fits: settings, global cross-check, verdict and report.

As the loop fits' results (:mod:`idkit.fit.result`): frozen dataclasses with an lmfit
:class:`~lmfit.Parameters` view, ``reasons`` and ``success``, ``report()`` text and
``to_dataframe()``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import lmfit
import numpy as np
import pandas as pd

from idkit.fit.result import (
    _LmfitStatistics,
    _parameter_lines,
    _statistics_lines,
    _undetermined_lines,
    determinacy_reasons,
)
from idkit.models import GeneralizedMaxwell, VoigtModel

__all__ = ["MaxwellFitSettings", "CrossCheck", "MaxwellFitResult", "DUPLICATE_RATE_RATIO", "CONSTRAINT_STEP_LIMIT",
           "NULL_PREDICTION_ERROR", "constraint_step"]


#: Two relaxation rates closer than this ratio are one element split in two.
DUPLICATE_RATE_RATIO = 1.01

#: A Maxwell fit whose least-squares optimum of the same residuals (one Gauss-Newton step,
#: ``statistics.gauss_newton_step``) lies more than this many standard errors from its parameters
#: is not a success: the loss-factor constraint moved them (when imposed) or the optimiser stopped
#: short of the optimum (without it; at a converged optimum the step is below 1e-5), and their
#: standard errors (statistics of an unconstrained minimum) do not describe them. 2: a success must
#: recover a truth within the 5 standard errors of the recovery tests, and a bias of 2 leaves 3 for
#: the noise (p = 0.3 % per parameter).
CONSTRAINT_STEP_LIMIT = 2.0


def constraint_step(statistics) -> tuple[str, float] | None:
    """The parameter and the size (in its standard errors) of the largest Gauss-Newton step of the
    statistics, or None when none was computed."""
    steps = getattr(statistics, "gauss_newton_step", {}) or {}
    if not steps:
        return None
    name = max(steps, key=lambda key: abs(steps[key]))
    return name, abs(float(steps[name]))


@dataclass(frozen=True)
class MaxwellFitSettings:
    """Algorithm settings of a Maxwell / Voigt fit (recorded for provenance)."""

    model: str
    order: int
    data: str
    backend: str
    band: tuple[float, float]
    bounds: dict
    monotone_loss: bool
    loss_grid_points: int
    max_evals: int
    ftol: float
    seed: int
    global_method: str | None
    global_max_evals: int | None
    loss_rule: str = ""


@dataclass(frozen=True)
class CrossCheck:
    """Global cross-check of the local SQP optimum.

    A population-based global search (nlopt GN_ISRES or scipy
    differential_evolution, seeded) on the same objective and constraints,
    polished by the same SQP. ``gap = sqp_error - global_error`` (fractions);
    ``reached_global`` is true when the gap is within ``tolerance``.
    """

    method: str
    sqp_error: float
    global_error: float
    gap: float
    tolerance: float
    reached_global: bool
    global_params: dict
    evaluations: int
    seed: int
    elapsed_s: float


#: Relative error (fraction) of the null prediction 0 under the RMS relative complex error (7.5):
#: ``|0 - H| / |H| = 1`` at every point. A fit that does not beat it explains nothing of the data.
NULL_PREDICTION_ERROR = 1.0


def _elements_outside_the_band(model, at_bound, band) -> list[str]:
    """What a Maxwell element on a search bound stands for when it relaxes outside the fitted band.

    An element ``k s / (s + rate)`` with ``rate`` above the band's top angular frequency
    ``w = 2 pi f_high`` is nearly a dashpot ``c = k / rate`` there (it departs from one by
    ``|1 - 1 / (1 + i w / rate)|`` at the top); one with ``rate`` below ``2 pi f_low`` is nearly
    a spring ``k`` in parallel with ``k0``. The data then set that one combination, not ``k`` and
    ``rate`` each, and the search runs along it to a bound (a broad-spectrum elastomer fitted
    with more elements than its band resolves). Only elements with a parameter in ``at_bound``.
    """
    k, rate = getattr(model, "k", None), getattr(model, "rate", None)
    if k is None or rate is None:
        return []
    omega_low, omega_high = (2 * np.pi * float(f) for f in band)
    notes = []
    for i, (k_i, rate_i) in enumerate(zip(np.asarray(k, dtype=float), np.asarray(rate, dtype=float)), start=1):
        if f"k_{i}" not in at_bound and f"rate_{i}" not in at_bound:
            continue
        if rate_i > omega_high:
            departure = abs(1 - 1 / (1 + 1j * omega_high / rate_i))
            notes.append(f"element {i} relaxes at {rate_i:.4g} 1/s, above the band's top 2 pi x {band[1]:g} Hz = "
                         f"{omega_high:.4g} rad/s: over the band it is nearly a dashpot c = k_{i} / rate_{i} = "
                         f"{k_i / rate_i:.4g} N s/m (within {100 * departure:.2g} % at the top), so the data set "
                         f"that ratio and not k_{i} and rate_{i} each (a lower order, or the band extended upward)")
        elif rate_i < omega_low:
            departure = abs(1 - 1 / (1 + rate_i / (1j * omega_low)))
            notes.append(f"element {i} relaxes at {rate_i:.4g} 1/s, below the band's bottom 2 pi x {band[0]:g} Hz "
                         f"= {omega_low:.4g} rad/s: over the band it is nearly a spring k_{i} = {k_i:.4g} N/m beside "
                         f"k0 (within {100 * departure:.2g} % at the bottom), so the data set k0 + k_{i} and not "
                         f"rate_{i} (a lower order, or the band extended downward)")
    return notes


@dataclass(frozen=True)
class MaxwellFitResult(_LmfitStatistics):
    """Result of :func:`idkit.fit.fit_maxwell`, :func:`fit_voigt` or :func:`fit_complex_stiffness`.

    Attributes
    ----------
    model : GeneralizedMaxwell or VoigtModel
        The best model found (the SQP optimum, or the polished global optimum
        when the cross-check found a lower error; ``source`` says which).
    error : float
        Objective (7.5) of ``model``: RMS relative complex error, fraction.
    set_errors : ndarray
        RMS relative error per data set (fraction).
    set_names : tuple of str
    sqp_error : float
        Error at the SQP optimum from the (default or given) start.
    at_bound : tuple of str
        Free parameters within 1e-6 (in scaled [0, 1] coordinates) of a bound.
    evaluations : int
        Objective evaluations of the SQP run.
    message : str
        Optimiser stop reason.
    source : {"sqp", "global"}
    cross_check : CrossCheck or None
    settings : MaxwellFitSettings
    parameters : lmfit.Parameters
        Values, bounds, stderr from the analytic Jacobian (parameters at a bound: none).
    elapsed_s : float
        Wall time of the SQP run (s).
    status : str
        End state of the SQP run as :mod:`idkit.fit._optim` set it from the optimiser's
        return code (``"converged"``, ``"stalled"``, ``"max_evals"``, ``"failed"``,
        ``"infeasible"``); :attr:`reasons` reads it.
    statistics : lmfit.minimizer.MinimizerResult or None
        Least-squares statistics at ``model`` (not moved) over the free parameters not at
        a bound; None when every one is at a bound. ``params`` (alias of ``parameters``),
        ``chisqr`` (= ``error**2``), ``redchi``, ``aic``, ``bic``, ``nfev``,
        ``stderr_notes`` and ``fit_report()`` expose them as lmfit does.
    """

    model: GeneralizedMaxwell | VoigtModel
    error: float
    set_errors: np.ndarray
    set_names: tuple[str, ...]
    sqp_error: float
    at_bound: tuple[str, ...]
    evaluations: int
    message: str
    source: str
    cross_check: CrossCheck | None
    settings: MaxwellFitSettings
    parameters: lmfit.Parameters = field(repr=False)
    elapsed_s: float
    statistics: lmfit.minimizer.MinimizerResult | None = field(default=None, repr=False)
    status: str = "converged"
    set_floors: np.ndarray | None = None
    model_form_reasons: tuple[str, ...] = ()

    @property
    def nfev(self) -> int:
        """Objective evaluations of the SQP run plus the residual evaluation of the statistics."""
        return self.evaluations + (0 if self.statistics is None else int(self.statistics.nfev))

    @property
    def stderr_notes(self) -> tuple[str, ...]:
        """Why a free parameter has no standard error: at a search bound, or the statistics' reason."""
        bound = tuple(f"{name}: at a search bound, where the least-squares statistics do not hold "
                      "(the optimum is the bound, not a minimum)" for name in self.at_bound)
        return bound + super().stderr_notes

    @property
    def reasons(self) -> tuple[str, ...]:
        """Why the fit is not a success (empty when it is).

        The error is not below that of the prediction 0 (:data:`NULL_PREDICTION_ERROR`, 100 %);
        the SQP found no point meeting the constraints, stopped on its evaluation limit or
        failed; a free parameter sits on its
        search bound (the data do not place it inside the box); two relaxation rates
        coincide within :data:`DUPLICATE_RATE_RATIO` (the elements are one element
        split in two: a lower order fits as well); the least-squares optimum lies more than
        :data:`CONSTRAINT_STEP_LIMIT` standard errors away (the loss constraint binds, or the
        optimiser stopped short of it); a transmissibility set's error exceeds its noise floor by
        more than a held-out run may miss (``model_form_reasons``,
        :func:`idkit.fit.frf_objective.frf_model_form_reasons`).
        """
        reasons = []
        if not self.error < NULL_PREDICTION_ERROR:
            reasons.append(f"error {100 * self.error:.4g} % >= {100 * NULL_PREDICTION_ERROR:g} %: the model predicts the "
                           "data no better than zero would (a prediction of 0 has a relative error of exactly 100 %); "
                           "the parameters are not an identification (a k0 far from the data, e.g. --k0)")
        if self.status == "infeasible":
            reasons.append("no point met the constraints (loss factor non-decreasing over the band): the start "
                           f"was kept, error {100 * self.error:.3g} % ({self.message})")
        elif self.status in ("max_evals", "failed"):
            reasons.append(f"the optimiser stopped without converging: {self.message}")
        if self.at_bound:
            reasons.append(f"at a search bound (not determined inside the box): {', '.join(self.at_bound)}"
                           + "".join(f"; {note}" for note in _elements_outside_the_band(self.model, self.at_bound,
                                                                                     self.settings.band)))
        rates = np.sort(np.asarray(getattr(self.model, "rate", ()), dtype=float))
        close = np.flatnonzero(rates[1:] / rates[:-1] < DUPLICATE_RATE_RATIO) if rates.size > 1 else []
        if len(close):
            pairs = ", ".join(f"{rates[i]:.4g} and {rates[i + 1]:.4g} 1/s" for i in close)
            reasons.append(f"relaxation rates coincide ({pairs}): redundant elements, a lower order fits as well")
        step = constraint_step(self.statistics)
        if step is not None and step[1] > CONSTRAINT_STEP_LIMIT and self.settings.monotone_loss:
            reasons.append(f"the loss-factor constraint binds: the least-squares optimum of the data lies {step[1]:.3g} "
                           f"standard errors away ({step[0]}; limit {CONSTRAINT_STEP_LIMIT:g}), so the constraint moved "
                           "the parameters and their standard errors do not describe them (monotone_loss=False fits "
                           "without it)")
        elif step is not None and step[1] > CONSTRAINT_STEP_LIMIT:
            reasons.append(f"the optimiser stopped short of the least-squares optimum: it lies {step[1]:.3g} standard "
                           f"errors away ({step[0]}; limit {CONSTRAINT_STEP_LIMIT:g}, one Gauss-Newton step), so the "
                           "parameters are not the optimum their standard errors describe (a tighter ftol, more "
                           "max_evals)")
        reasons.extend(determinacy_reasons(self.parameters, self.statistics, excused=self.at_bound))
        reasons.extend(self.model_form_reasons)
        return tuple(reasons)

    @property
    def success(self) -> bool:
        """True unless :attr:`reasons` names a problem."""
        return not self.reasons

    def to_dataframe(self) -> pd.DataFrame:
        """One row per data set: name and RMS relative error in %."""
        return pd.DataFrame({"set": list(self.set_names), "error_percent": 100.0 * np.asarray(self.set_errors)})

    def report(self) -> str:
        """Readable summary: parameters, errors, bounds hit, cross-check."""
        s = self.settings
        title = f"{s.model} order {s.order}" if s.model == "maxwell" else s.model
        lines = [
            f"[[{title} fit to {s.data}, bounded SQP ({s.backend}), band {s.band[0]:g}-{s.band[1]:g} Hz]]",
            f"    error (7.5) {100 * self.error:.3f} % (SQP {100 * self.sqp_error:.3f} %, model from {self.source}), "
            f"{self.evaluations} evaluations, {self.elapsed_s:.3f} s, {self.message}",
            f"    at a bound: {', '.join(self.at_bound) if self.at_bound else 'none'}; "
            f"loss factor non-decreasing constraint: {s.monotone_loss}"
            + (f" ({s.loss_rule})" if s.loss_rule else ""),
            "    per set [%]: " + ", ".join(f"{n}: {100 * e:.2f}" for n, e in zip(self.set_names, self.set_errors)),
            *(["    noise floor per set [%] (H1 random error): " + ", ".join(
                f"{n}: {100 * f:.2f}" for n, f in zip(self.set_names, self.set_floors))]
              if self.set_floors is not None else []),
            f"    success {self.success}",
            *(f"    not a success: {reason}" for reason in self.reasons),
        ]
        if self.cross_check is not None:
            c = self.cross_check
            verdict = "reached" if c.reached_global else "did NOT reach"
            lines.append(
                f"    global cross-check ({c.method}, seed {c.seed}, {c.evaluations} evaluations, "
                f"{c.elapsed_s:.2f} s): SQP {verdict} the global optimum; global {100 * c.global_error:.4f} %, "
                f"gap {100 * c.gap:.4f} % (tolerance {100 * c.tolerance:.4f} %)"
            )
        lines.append("[[Variables]] (stderr from the analytic residual Jacobian at the optimum)")
        lines.extend(_parameter_lines(self.parameters))
        lines.extend(f"    no stderr: {note}" for note in self.stderr_notes)
        lines.extend(_undetermined_lines(self.undetermined))
        lines.extend(_statistics_lines(self.statistics))
        return "\n".join(lines)
