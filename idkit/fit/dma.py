"""Material data: Prony series pruned to the terms the data hold, and DMA tables end to end.

:func:`fit_prony` fits generalized Maxwell (Prony) series of every order from 1 to
``max_order`` to a complex modulus (or stiffness) and keeps the **fewest terms whose
error is within** :data:`PRUNE_FACTOR` **of the smallest error in the table**, preferring
fits with no parameter on a search bound and no coinciding rates. When every order within
the factor is flagged, the lowest of them is kept and says why (``success=False``).

:func:`fit_dma_table` takes a :class:`~idkit.io.ComplexStiffnessTable` as read from a file:
isotherms (a temperature column) are shifted into a master curve with shift factors
estimated from the isotherms themselves (:mod:`idkit.signal.shift_factors`), WLF and
polynomial laws are fitted to them, given shift factors (if any) are checked against them
and used only on request; then :func:`fit_prony`. The model is a modulus (Pa) when the
table is one (``quantity``), and its model file says so in its units.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

from idkit.checks import Choice, Either, Flag, Real, Whole, accepts
from idkit.errors import FitError
from idkit.fit.maxwell import ORDER
from idkit.fit.maxwell_table import fit_complex_stiffness
from idkit.fit.measurement_fit import _jsonable
from idkit.fit.maxwell_result import MaxwellFitResult
from idkit.models import GeneralizedMaxwell
from idkit.io.complex_stiffness import ComplexStiffnessTable, ShiftFactorTable
from idkit.signal.shift_factors import (
    ShiftFactorCheck,
    ShiftFactorEstimate,
    ShiftLawFit,
    compare_shift_factors,
    estimate_shift_factors,
    fit_shift_polynomial,
    fit_wlf,
    group_isotherms,
)

__all__ = ["PRUNE_FACTOR", "DmaFit", "PronyFit", "default_max_order", "fit_dma_table", "fit_prony"]

#: Pruning rule: the fewest terms whose RMS relative error is at most this factor times the
#: smallest error of the order table (a stated choice: a further 10 % of the error is not worth
#: the terms that buy it; docs/real-data.md).
PRUNE_FACTOR = 1.10
#: Highest order tried by default: this many terms per decade of the data's frequency span, plus one.
TERMS_PER_DECADE = 1.0
#: Cap on the default highest order (each order is a separate fit).
MAX_DEFAULT_ORDER = 40


def default_max_order(freq_hz) -> int:
    """One term per decade of the frequency span, plus one (at most :data:`MAX_DEFAULT_ORDER`).

    Examples
    --------
    >>> default_max_order([0.1, 100.0])
    4
    """
    freq = np.asarray(freq_hz, dtype=float)
    decades = math.log10(float(freq.max()) / float(freq.min())) if freq.size else 0.0
    return int(min(MAX_DEFAULT_ORDER, max(1, math.ceil(TERMS_PER_DECADE * decades)) + 1))


@dataclass(frozen=True)
class PronyFit:
    """A Prony series pruned by :data:`PRUNE_FACTOR` (see :func:`fit_prony`).

    Attributes
    ----------
    result : MaxwellFitResult
        The kept fit (its ``model`` carries ``quantity``).
    table : pandas.DataFrame
        One row per order tried: ``order``, ``error [%]``, ``within factor``, ``success``,
        ``reasons``, ``kept``.
    factor : float
        The pruning factor used.
    min_error : float
        Smallest error in the table (fraction).
    """

    result: MaxwellFitResult
    table: pd.DataFrame
    factor: float
    min_error: float

    @property
    def model(self):
        return self.result.model

    @property
    def order(self) -> int:
        return int(self.result.model.order)

    @property
    def reasons(self) -> tuple[str, ...]:
        """Why the kept fit is not a success (empty when it is)."""
        if self.result.success:
            return ()
        return (*self.result.reasons,
                f"every order within {self.factor:g} x the smallest error ({100 * self.min_error:.3g} %) "
                "has a flag; the lowest of them is kept")

    @property
    def success(self) -> bool:
        return not self.reasons

    def report(self) -> str:
        """Order table, the rule and the kept fit's report."""
        lines = [f"[[Prony order table: kept the fewest terms within {self.factor:g} x the smallest error "
                 f"({100 * self.min_error:.3g} %), preferring fits with nothing on a bound]]",
                 self.table.drop(columns=["reasons"]).to_string(index=False),
                 f"    kept order {self.order}; success {self.success}",
                 *(f"    not a success: {reason}" for reason in self.reasons)]
        return "\n".join(lines) + "\n" + self.result.report()


def _nested_fits(freq, storage, loss, orders, quantity: str, options: dict) -> dict[int, MaxwellFitResult]:
    """One fit per order (ascending), each from the previous order's optimum (:func:`_nested_start`)."""
    fits, previous = {}, None
    for order in orders:
        start = None if previous is None else _nested_start(previous, order)
        fits[order] = fit_complex_stiffness(freq, storage, loss, order=order, quantity=quantity, start=start,
                                            **options)
        previous = fits[order]
    return fits


def _nested_start(previous: MaxwellFitResult, order: int) -> GeneralizedMaxwell:
    """The previous order's optimum with weak terms added up to ``order`` (warm start).

    Each new term starts at 1e-3 of the smallest existing modulus (inside the search box),
    at the geometric middle of the widest gap between the rates and the rate bounds, so
    the start scores what the previous optimum scored and the table's errors do not rise
    with the order for want of a start.
    """
    model, bounds = previous.model, previous.settings.bounds
    rate_low, rate_high = bounds["rate_1"]
    k_low, k_high = bounds["k_1"]
    k, rate = list(np.asarray(model.k, float)), list(np.asarray(model.rate, float))
    while len(k) < order:
        edges = np.log(np.sort(np.concatenate([[rate_low, rate_high], rate])))
        widest = int(np.argmax(np.diff(edges)))
        k.append(float(min(max(1e-3 * min(k), k_low * 1.01), k_high)))
        rate.append(float(np.exp(0.5 * (edges[widest] + edges[widest + 1]))))
    ordered = np.argsort(rate)
    k0 = model.k0
    if "k0" in bounds:
        k0 = float(np.clip(k0, *bounds["k0"]))
    return GeneralizedMaxwell(k0=k0, k=np.asarray(k)[ordered], rate=np.asarray(rate)[ordered])


@accepts(factor=Real(ge=1, meaning="error allowed above the smallest"), max_order=Whole(ge=1, optional=True),
         error=FitError)
def fit_prony(freq, storage, loss, *, quantity: str = "modulus", max_order: int | None = None,
              orders=None, factor: float = PRUNE_FACTOR, **options) -> PronyFit:
    """Fit Prony series of increasing order and keep the fewest terms the data hold.

    Parameters
    ----------
    freq, storage, loss : array_like
        Frequency in Hz, storage and loss parts (Pa for a modulus, N/m for a stiffness).
    quantity : {"modulus", "stiffness"}
        What the parts are.
    max_order : int, optional
        Highest order tried (default :func:`default_max_order`, at most the number of distinct
        frequencies - 1: order n has 2 n + 1 parameters, each frequency gives two numbers).
    orders : sequence of int, optional
        Orders tried (default ``1 .. max_order``).
    factor : float
        Pruning factor (> 1), default :data:`PRUNE_FACTOR`.
    **options
        Passed to :func:`~idkit.fit.fit_complex_stiffness` (bounds, backend, seed, ...).

    Each order starts from the previous order's optimum with one weak term added (the
    first from the default start), so an order never scores worse than the one below for
    want of a start.

    Returns
    -------
    PronyFit
    """
    if orders is None:
        # the default: as many orders as the distinct frequencies identify (order n needs n + 1)
        top = min(default_max_order(freq), max(1, np.unique(np.asarray(freq, dtype=float)).size - 1)) \
            if max_order is None else max_order
        orders = range(1, int(top) + 1)
    orders = sorted({int(o) for o in orders})
    fits = _nested_fits(freq, storage, loss, orders, quantity, options)
    errors = {order: fit.error for order, fit in fits.items()}
    min_error = min(errors.values())
    within = [order for order in orders if errors[order] <= factor * min_error]
    clean = [order for order in within if fits[order].success]
    kept = (clean or within)[0]
    table = pd.DataFrame({
        "order": orders,
        "error [%]": [100 * errors[o] for o in orders],
        "within factor": [o in within for o in orders],
        "success": [fits[o].success for o in orders],
        "reasons": ["; ".join(fits[o].reasons) for o in orders],
        "kept": [o == kept for o in orders],
    })
    return PronyFit(result=fits[kept], table=table, factor=float(factor), min_error=float(min_error))


@dataclass(frozen=True)
class DmaFit:
    """A DMA table fitted end to end (see :func:`fit_dma_table`).

    Attributes
    ----------
    table : ComplexStiffnessTable
        The table as read.
    master : ComplexStiffnessTable
        The master curve that was fitted (the table itself when it has no temperature column).
    shift_estimate : ShiftFactorEstimate or None
        Shift factors estimated from the isotherms.
    wlf, polynomial : ShiftLawFit or None
        Laws fitted to the estimated shift factors.
    check : ShiftFactorCheck or None
        Given shift factors against the estimated ones.
    shift_source : str
        ``"estimated"``, ``"given"`` or ``"none"`` (the table is already a master curve).
    prony : PronyFit or MaxwellFitResult
        The fit (pruned, or at the order asked).
    """

    table: ComplexStiffnessTable
    master: ComplexStiffnessTable
    shift_estimate: ShiftFactorEstimate | None
    wlf: ShiftLawFit | None
    polynomial: ShiftLawFit | None
    check: ShiftFactorCheck | None
    shift_source: str
    prony: PronyFit | MaxwellFitResult

    @property
    def result(self) -> MaxwellFitResult:
        return self.prony.result if isinstance(self.prony, PronyFit) else self.prony

    @property
    def model(self):
        return self.result.model

    @property
    def reasons(self) -> tuple[str, ...]:
        """The fit's reasons, plus given shift factors that disagree with the isotherms when used."""
        reasons = list(self.prony.reasons)
        if self.check is not None and not self.check.agrees and self.shift_source == "given":
            reasons.append("the given shift factors were used although they disagree with the isotherms: "
                           + self.check.summary())
        return tuple(reasons)

    @property
    def success(self) -> bool:
        return not self.reasons

    def shift_lines(self) -> list[str]:
        lines = []
        if self.shift_estimate is not None:
            est = self.shift_estimate
            lines.append(f"[[Shift factors: {est.temperature_k.size} isotherms, reference "
                         f"{est.reference_temperature_k - 273.15:.2f} C, used: {self.shift_source}]]")
            frame = est.to_dataframe()
            lines.append(frame.round(4).to_string(index=False))
            lines.append(f"    pairwise superposition residual (log10 |E*|): max "
                         f"{est.pair_residual_decades.max():.4f} decades")
            for law in (self.wlf, self.polynomial):
                if law is not None:
                    coefficients = ", ".join(f"{k} = {v:.5g}" for k, v in law.coefficients.items())
                    lines.append(f"    {law.law}: {coefficients}; residual rms {law.rms_residual_decades:.3f}, "
                                 f"max {law.max_residual_decades:.3f} decades")
        if self.check is not None:
            lines.append("    " + self.check.summary())
        return lines

    def report(self) -> str:
        unit = self.table.unit
        lines = [f"[[DMA table {self.table.source.path or 'in memory'}: {self.table.freq.size} points, "
                 f"{self.table.quantity} in {unit}; master curve {self.master.freq.min():.3g}-"
                 f"{self.master.freq.max():.3g} Hz]]", *self.shift_lines(),
                 f"    success {self.success}", *(f"    not a success: {r}" for r in self.reasons)]
        return "\n".join(lines) + "\n" + self.prony.report()

    def provenance_dict(self) -> dict:
        """Provenance record for the model file (JSON-ready)."""
        from idkit import __version__

        source = self.table.source
        record = {
            "fitter": "idkit.fit.fit_dma_table",
            "idkit_version": __version__,
            "data": {"path": None if source.path is None else str(source.path), "sha256": source.sha256,
                     "quantity": self.table.quantity, "unit": self.table.unit},
            "shift_factors_used": self.shift_source,
            "success": self.success,
            "reasons": list(self.reasons),
            "error_percent": 100 * float(self.result.error),
            "settings": _jsonable(dataclasses.asdict(self.result.settings)),
        }
        if self.shift_estimate is not None:
            record["shift_factors"] = {
                "reference_temperature_K": self.shift_estimate.reference_temperature_k,
                "temperature_K": self.shift_estimate.temperature_k.tolist(),
                "log_aT": self.shift_estimate.log_a_t.tolist(),
                "log_aT_stderr": self.shift_estimate.log_a_t_stderr.tolist(),
            }
            for law in (self.wlf, self.polynomial):
                if law is not None:
                    record["shift_factors"][law.law] = {"coefficients": law.coefficients,
                                                        "rms_residual_decades": law.rms_residual_decades}
        if self.check is not None:
            record["given_shift_factors_check"] = {"agrees": self.check.agrees,
                                                   "max_difference_decades": self.check.max_difference_decades,
                                                   "summary": self.check.summary()}
        if isinstance(self.prony, PronyFit):
            record["order_table"] = _jsonable(self.prony.table.to_dict(orient="records"))
            record["prune_factor"] = self.prony.factor
        return record

    def save(self, path, *, overwrite: bool = False) -> Path:
        """Write the model file with :meth:`provenance_dict`."""
        from idkit.models import save_model

        return save_model(self.model, path, provenance=self.provenance_dict(), overwrite=overwrite)


@accepts(order=Either((ORDER, Choice(("auto",)))), reference_temperature_k=Real(unit="K", gt=0, optional=True),
         use_given_shift_factors=Flag(), max_order=Whole(ge=1, optional=True), error=FitError)
def fit_dma_table(table: ComplexStiffnessTable, *, order: int | str = "auto",
                  reference_temperature_k: float | None = None,
                  shift_factors: ShiftFactorTable | None = None, use_given_shift_factors: bool = False,
                  max_order: int | None = None, factor: float = PRUNE_FACTOR, **options) -> DmaFit:
    """Fit a DMA (or complex stiffness) table: master curve, shift factors, pruned Prony series.

    Parameters
    ----------
    table : ComplexStiffnessTable
        As read by :func:`idkit.io.read_complex_stiffness` (or an adapter).
    order : int or "auto"
        Prony order; ``"auto"`` (default) prunes with :func:`fit_prony`. A fixed order keeps
        the better of the SQP from the seeded default start and the climb from order 1 that
        the pruning makes (each order from the last optimum), so it does not depend on where
        one start happened to stop.
    reference_temperature_k : float, optional
        Reference temperature of the master curve in K. Default: the given shift factors'
        reference (where their ``log aT`` is 0) if given, else the isotherm nearest the
        median temperature of the rows.
    shift_factors : ShiftFactorTable, optional
        Given shift factors: checked against the estimated ones (always), used instead of
        them only when ``use_given_shift_factors`` is True.
    use_given_shift_factors : bool
        Build the master curve from ``shift_factors`` instead of the estimate.
    max_order, factor, **options
        Passed to :func:`fit_prony` / :func:`~idkit.fit.fit_complex_stiffness`.

    Returns
    -------
    DmaFit

    Raises
    ------
    DataError
        Isotherms that cannot be superposed (see :func:`~idkit.signal.shift_factors.estimate_shift_factors`).
    FitError
        Bad options; ``use_given_shift_factors`` without ``shift_factors``.
    """
    if use_given_shift_factors and shift_factors is None:
        raise FitError("use_given_shift_factors: found True without shift_factors, expected a shift-factor table")
    estimate = wlf = polynomial = check = None
    source_name = str(table.source.path) if table.source.path is not None else "in-memory table"
    if table.temperature is None:
        if shift_factors is not None:
            raise FitError(f"{source_name}: shift factors given but the table has no temperature column: it is "
                           "already a master curve (expected isotherms with 'temperature [C|K]')")
        master, shift_source = table, "none"
    else:
        if reference_temperature_k is None:
            reference = None if shift_factors is None else shift_factors.reference_temperature
            if reference is None:
                temps = np.sort(table.temperature)
                reference = float(temps[np.argmin(np.abs(temps - np.median(temps)))])
            reference_temperature_k = reference
        estimate = estimate_shift_factors(table.freq, table.storage, table.loss, table.temperature,
                                          reference_temperature_k=reference_temperature_k, source=source_name)
        if estimate.temperature_k.size >= 3:
            wlf = fit_wlf(estimate.temperature_k, estimate.log_a_t,
                          reference_temperature_k=estimate.reference_temperature_k)
            polynomial = fit_shift_polynomial(estimate.temperature_k, estimate.log_a_t,
                                              reference_temperature_k=estimate.reference_temperature_k,
                                              degree=min(4, estimate.temperature_k.size))
        if shift_factors is not None:
            check = compare_shift_factors(shift_factors.temperature, shift_factors.log_a_t, estimate)
        if use_given_shift_factors:
            master, shift_source = table.master_curve(shift_factors), "given"
        else:
            used = ShiftFactorTable(temperature=estimate.temperature_k, log_a_t=estimate.log_a_t,
                                    source=table.source)
            labels, _ = group_isotherms(table.temperature)
            spread = float(np.max(np.abs(table.temperature - estimate.temperature_k[labels])))
            master, shift_source = table.master_curve(used, temperature_tol_k=max(1.0, spread)), "estimated"
    if order == "auto":
        prony = fit_prony(master.freq, master.storage, master.loss, quantity=master.quantity,
                          max_order=max_order, factor=factor, **options)
    else:
        prony = fit_complex_stiffness(master.freq, master.storage, master.loss, order=order,
                                      quantity=master.quantity, **options)
        if order > 1 and "start" not in options:
            # one SQP from the seeded default start can stop in a poorer local minimum: also climb
            # to the order as the pruning does, each order from the last optimum, and keep the
            # better of the two
            nested = _nested_fits(master.freq, master.storage, master.loss, range(1, order + 1), master.quantity,
                                  options)[order]
            if nested.error < prony.error:
                prony = nested
    return DmaFit(table=table, master=master, shift_estimate=estimate, wlf=wlf, polynomial=polynomial,
                  check=check, shift_source=shift_source, prony=prony)
