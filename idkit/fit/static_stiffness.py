"""The elastomer's static stiffness ``k0`` from quasi-static loops that have not fully relaxed.

The secant estimate (:func:`idkit.observe.k0.k0_from_records`) is the slope of the
loops around zero deflection. It is ``k0`` only if every Maxwell element has relaxed when
the loops cross zero; an element whose relaxation time is comparable with the time since the
last reversal (seconds, on a lathe at ~1 mm/s) still carries force there and biases the slope
high.

:func:`k0_with_relaxation` fits the loops' whole time history instead: over the points with
``|deflection| <= window`` (where the spring is linear),

``F(t) = k0 x(t) + sum_j c_j u_j(t) + F_offset,r``,

``u_j`` the elongation of a unit Maxwell element of rate ``r_j`` driven by the record's own
deflection history (:func:`idkit.models.laws.maxwell_states`, exact for a piecewise-linear
deflection, elements relaxed at the record's start), ``r_j`` on the grid
:data:`RELAXATION_RATES`, ``c_j >= 0`` and ``k0 >= 0`` by non-negative least squares
(``scipy.optimize.nnls``), one free force offset per record. The elements are a basis, not an
identification: the FRF fit identifies the Maxwell elements; only ``k0`` is kept.

Its standard error is the least-squares one of the columns the solution uses (``k0``, the
positive ``c_j``, the offsets), or the spread of the per-record values when larger, as for
the secant estimate.

**When the loops cannot tell k0 from the basis** the secant slope stands in, with the reason in
``K0FromLoops.fallback`` (the fit's report and the model file's provenance print it): the
relaxation fit's ``k0`` is not positive, or its 95 % interval ``k0 +- 1.96 stderr`` reaches zero
(the verdicts' rule for a positive parameter, :data:`~idkit.fit.result.INTERVAL_Z`). Sinusoidal
loops of one amplitude and frequency per record, the common lab practice, do that: a slow basis
element is a spring over a sine's period, so the NNLS may put the whole stiffness in it and leave
``k0 = 0``.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import scipy.optimize

from idkit.checks import Reals, accepts
from idkit.errors import FitError, Message, Suggestion
from idkit.fit.result import INTERVAL_Z
from idkit.models.laws import kernel_array, maxwell_states
from idkit.observe.k0 import K0FromLoops, k0_from_records

__all__ = ["RELAXATION_RATES", "k0_with_relaxation", "K0_METHODS"]

#: Relaxation rates (1/s) of the basis: two per decade from 0.01 to 100 1/s. Loop records last
#: minutes and reverse every few seconds to tens of seconds; an element faster than 100 1/s
#: has relaxed within a sample of a lathe record (20 ms), one slower than 0.01 1/s acts as a
#: spring over the whole record and is not told apart from k0 by any quasi-static test.
RELAXATION_RATES = np.logspace(-2.0, 2.0, 9)

#: ``k0_method`` of :func:`idkit.fit.elastomer_data`: the relaxation fit (default) or the secant.
K0_METHODS = ("relaxation", "secant")


def _solve(blocks, n_rates: int):
    """NNLS of the stacked blocks ``(x, U, f)``: ``(k0, c, offsets, stderr of k0)``."""
    n_records = len(blocks)
    rows = sum(x.size for x, _, _ in blocks)
    width = 1 + n_rates + 2 * n_records
    if rows <= 1 + n_rates + n_records:
        raise FitError(Message(f"k0 with relaxation: found {rows} points in the window for {1 + n_rates + n_records} "
                               "unknowns, expected more (widen the window or use ", Suggestion("k0_method", "secant"),
                               ")"))
    design = np.zeros((rows, width))
    target = np.empty(rows)
    start = 0
    for index, (x, states, force) in enumerate(blocks):
        stop = start + x.size
        design[start:stop, 0] = x
        design[start:stop, 1:1 + n_rates] = states
        design[start:stop, 1 + n_rates + index] = 1.0  # offsets of either sign: a + and a - column
        design[start:stop, 1 + n_rates + n_records + index] = -1.0
        target[start:stop] = force
        start = stop
    scale = np.maximum(np.abs(design).max(axis=0), 1e-300)  # column scaling for the solver only
    solution, _ = scipy.optimize.nnls(design / scale, target, maxiter=50 * width)
    solution = solution / scale
    k0 = float(solution[0])
    stiffness = solution[1:1 + n_rates]
    offsets = solution[1 + n_rates:1 + n_rates + n_records] - solution[1 + n_rates + n_records:]
    used = np.concatenate([[0], 1 + np.flatnonzero(stiffness > 0), 1 + n_rates + np.arange(n_records)])
    active = design[:, used]
    active[:, -n_records:] = design[:, 1 + n_rates:1 + n_rates + n_records]
    coefficients = np.concatenate([[k0], stiffness[stiffness > 0], offsets])
    residual = target - active @ coefficients
    variance = float(residual @ residual) / max(rows - used.size, 1)
    try:
        covariance = variance * np.linalg.inv(active.T @ active)
        stderr = float(math.sqrt(max(covariance[0, 0], 0.0)))
    except np.linalg.LinAlgError:
        stderr = math.inf
    return k0, stiffness, offsets, stderr


@accepts(rates=Reals(unit="1/s", gt=0), error=FitError)
def k0_with_relaxation(records, *, window: float = 1e-3, rates=RELAXATION_RATES) -> K0FromLoops:
    """Static stiffness from quasi-static records with the relaxation of the loops fitted (module docstring).

    Parameters
    ----------
    records : sequence of QuasiStaticMeasurement
        The elastomer's loop records (each with its sample times).
    window : float, default 1e-3
        Half-width (m) of the deflection window whose points enter the fit.
    rates : array_like, default :data:`RELAXATION_RATES`
        Relaxation rates of the basis, 1/s (positive, distinct).

    Returns
    -------
    K0FromLoops
        ``method="relaxation"``; ``k0`` and ``stderr`` of the fit, ``per_record`` each record's
        own fit, ``secant_k0`` the secant slope of the same points
        (:func:`~idkit.observe.k0.k0_from_records`), ``relaxation`` the basis
        stiffness per rate (N/m, 0 for rates the loops do not use).

    Raises
    ------
    FitError
        Everything :func:`~idkit.observe.k0.k0_from_records` refuses, too few points
        for the unknowns, bad rates. A k0 the loops do not separate from the basis is not an
        error: the secant estimate is returned with ``fallback`` saying why (module docstring).

    Examples
    --------
    >>> import numpy as np
    >>> from idkit.io import MeasurementInfo, QuasiStaticMeasurement
    >>> from idkit.models import GeneralizedMaxwell
    >>> corners = [0.0, 1e-3, -1e-3, 2e-3, -2e-3, 3e-3, -3e-3, 4e-3, -4e-3, 0.0]   # SPEC 3 ramps
    >>> x = np.concatenate([[0.0], *(np.linspace(a, b, int(abs(b - a) / 2e-5) + 1)[1:]
    ...                              for a, b in zip(corners[:-1], corners[1:]))])
    >>> t = 0.02 * np.arange(x.size)                         # 1 mm/s
    >>> truth = GeneralizedMaxwell(k0=9000.0, k=[900.0], rate=[2.0])
    >>> record = QuasiStaticMeasurement(time=t, deflection=x, force=truth.force(x, t),
    ...                                 info=MeasurementInfo(id="loops", sample_rate_hz=50.0))
    >>> round(k0_with_relaxation([record]).k0 / 9000, 4), round(k0_from_records([record]).k0 / 9000, 4)
    (0.9999, 1.0094)

    Notes
    -----
    The loops must cross zero at various times after their reversals (ramps of several
    amplitudes, as SPEC 3's protocol): a record of one sine determines only the in-phase and
    quadrature stiffness at its frequency, and the fit then leans on the basis.
    """
    records = list(records)
    secant = k0_from_records(records, window=window)
    if rates.ndim != 1 or np.unique(rates).size != rates.size:
        raise FitError(f"rates: found {rates!r}, expected distinct positive relaxation rates in 1/s")
    blocks, names = [], []
    for index, record in enumerate(records, start=1):
        x = np.asarray(record.deflection, dtype=float)
        states = maxwell_states(kernel_array(x), kernel_array(np.asarray(record.time, dtype=float)),
                                kernel_array(rates), np.zeros(rates.size))
        inside = np.abs(x) <= window
        blocks.append((x[inside], states[inside], np.asarray(record.force, dtype=float)[inside]))
        names.append(record.id or f"record{index}")
    k0, stiffness, _, stderr = _solve(blocks, rates.size)
    per_record = {}
    for name, block in zip(names, blocks):
        try:
            per_record[name] = _solve([block], rates.size)[0]
        except FitError:  # a record too short on its own still counts in the pooled fit
            per_record[name] = math.nan
    values = np.array([v for v in per_record.values() if math.isfinite(v)])
    spread = float(np.std(values, ddof=1) / math.sqrt(values.size)) if values.size > 1 else 0.0
    uncertainty = max(stderr, spread)
    if not (k0 > 0 and k0 - INTERVAL_Z * uncertainty > 0):
        interval = f"k0 = {k0:.5g} +- {uncertainty:.2g} N/m" if k0 > 0 else f"k0 = {k0:g} N/m"
        return dataclasses.replace(secant, fallback=(
            f"secant slope {secant.k0:.5g} N/m used: the relaxation fit cannot tell k0 from its relaxation basis "
            f"({interval}, {INTERVAL_Z:g} standard errors reach zero; loops that cross zero at one time after "
            "their reversals, e.g. sinusoids, do not separate a static spring from a slow element)"))
    return dataclasses.replace(secant, k0=k0, stderr=uncertainty, per_record=per_record,
                               method="relaxation", secant_k0=secant.k0,
                               relaxation={float(r): float(c) for r, c in zip(rates, stiffness)})
