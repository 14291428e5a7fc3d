"""Periodic steady states by shooting on the exact integrator, with Floquet stability.

A periodic response to the harmonic base displacement ``x_b = A sin(2 pi f t)`` is a fixed
point of the period map ``Phi``: the state at ``t = 0`` integrated over ``p`` excitation
periods (``p = 1``, or ``p = 2`` for the 1/2 subharmonic) by idkit's own compiled step
(:mod:`idkit.simulate`, average-acceleration Newmark with the exact stop operator and the
exact Maxwell update), with the same steps per period as :func:`idkit.simulate.harmonic_response`.
The fixed point of the *discrete* map is therefore exactly the limit the time integration
approaches; shooting only skips the transient.

State (``x`` below): displacements and velocities of the masses at ``t = 0`` (where the base
is at zero, so they are also the deflections of the stack), then the hysteretic internal
states of the model: Jenkin (stop-operator) forces in N, Maxwell element elongations in m,
Bouc-Wen ``z`` in N. Accelerations follow from equilibrium.

Newton's method solves ``Phi(x) - x = 0`` in scaled variables (displacements over the
response scale ``L``, velocities over ``omega L``, Jenkin forces over ``min(Fc, k L)``,
Maxwell elongations over ``L``, Bouc-Wen ``z`` over ``alpha L``). The Jacobian of the period
map (the monodromy matrix) is, by default, **propagated through the step**
(:mod:`idkit.responses._sensitivity`: implicit function theorem on the converged Newmark
step, derivatives of the exact Jenkin and Maxwell updates), exact for the discrete map
except exactly on a stick/slip switch. Systems with Bouc-Wen elements (and
``jacobian="finite differences"``) use **central finite differences**, each state perturbed by
``FD_STEP = 1e-6`` of its scale: the map is piecewise smooth (the stop operator clips), a
perturbation of 1e-6 crosses a stick/slip switch only for orbits grazing one, where the
central difference returns the average of the two one-sided slopes (still a good Newton
direction); truncation error ``O(1e-12)``, round-off about the step's Newton tolerance
(1e-13 relative) over the perturbation, ``1e-7``. The ``2 n + 1`` integrations of one
difference Jacobian run as one compiled batch. Tests: multipliers of a linear system against
the eigenvalues of the Newmark amplification matrix (1e-11 propagated, 1e-6 by differences),
and both Jacobians against each other on slipping, sticking and Maxwell systems. The
derivative with respect to frequency or amplitude (continuation) is always a central
difference in the logarithm of the parameter.

Friction memory: while Jenkin elements stick, ``F_i - k_i y`` is conserved, so periodic
orbits come in families (a Floquet multiplier exactly 1) and ``I - dPhi/dx`` is singular.
The left singular vectors of its (numerically) zero singular values are the gradients of
those conserved quantities; Newton replaces the corresponding (void) equations by "keep
the conserved quantities of the starting guess", which is what the time integration does.

Floquet multipliers are the eigenvalues of the monodromy matrix ``dPhi/dx`` at the
solution, classified with the margin ``max(STABILITY_MARGIN, tolerance)`` (the coarser Jacobian's
error times 100, or the closing tolerance the orbit was located to if that is coarser;
:func:`classify_multipliers`): unstable when a ``|mu|`` exceeds 1 by more (a real multiplier
below -1 means period doubling: the orbit of twice the period branches off there); neutral when
none does but one other than the friction-memory multipliers at +1 lies within the margin of the
unit circle (an undamped system, or one damped by less than the margin per period: the orbit
attracts nothing a time integration could settle on); stable otherwise.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from idkit.checks import Flag, Real, Reals, Whole, accepts
from idkit.errors import SimulationError
from idkit.limits import MIN_TOLERANCE
from idkit.responses.period_map import FD_STEP, PeriodMap, monodromy, period_map  # noqa: F401 - re-exported
from idkit.simulate import default_steps_per_period
from idkit.simulate._kernel import FLAG_OK, FLAG_REASONS
from idkit.simulate.harmonic import MAX_PERIOD_TABLE

__all__ = ["STABILITY_MARGIN", "PeriodicResponse", "classify_multiplier_rows", "classify_multipliers",
           "leading_multipliers", "monodromy", "period_map",
           "periodic_response", "stability_margin"]

#: A multiplier is unstable when ``|mu| > 1 + margin`` and neutral when within ``margin`` of the unit
#: circle, with ``margin = max(STABILITY_MARGIN, tolerance)``: 100x the error of the difference
#: Jacobian (1e-6; the propagated one is finer, and both must classify an orbit alike), widened to the
#: closing tolerance the orbit was located to. The multipliers of sticking friction memory sit at +1
#: within it (a family of orbits, not a neutral direction). A mode decaying by less than 1e-4 a
#: period needs over 10^4 periods per e-fold: beyond any time run's cap (4000 periods).
STABILITY_MARGIN = 1e-4
#: An unstable orbit left along its eigenvector: the growth of the push integrated before shooting again
#: when a few periods do not reach a stable orbit (``_escape``), and the cap on those periods.
ESCAPE_GROWTH = 1e3
ESCAPE_MAX_PERIODS = 4000
#: Singular values of the scaled ``I - dPhi/dx`` below this are conserved quantities (friction memory).
NULL_TOLERANCE = 1e-5


def conserved_directions(matrix):
    """SVD of the scaled ``dPhi/dx - I``: ``(u, s, vt, null)`` with ``null`` the indices of the
    singular values below :data:`NULL_TOLERANCE` (conserved quantities of stick)."""
    u, s, vt = np.linalg.svd(matrix)
    null = np.flatnonzero(s < NULL_TOLERANCE)
    return u, s, vt, null


def newton_step(jacobian, residual, offset):
    """Newton correction (scaled) for ``Phi(x) - x = 0`` keeping the conserved quantities.

    ``residual = (Phi(x) - x) / s``, ``offset = (x - x_guess) / s``. Equations along the
    numerically zero singular directions of ``J - I`` are void (conserved quantities): they
    are replaced by "keep the conserved quantity of the guess", ``u_k . (x + dx - x_guess) = 0``.
    Returns ``(step, number of conserved quantities)``: :func:`newton_steps` of one point.
    """
    steps, n_conserved = newton_steps(np.asarray(jacobian)[None], np.asarray(residual)[None],
                                      np.asarray(offset)[None])
    return steps[0], int(n_conserved[0])


def newton_steps(jacobians, residuals, offsets=None, memory=None, conserved=None):
    """:func:`newton_step` of many points at once: ``(steps (n, size), n_conserved (n,))``.

    ``jacobians`` (n, size, size), ``residuals`` and ``offsets`` (n, size), scaled as there
    (``offsets`` None: zero, the guess itself). ``memory`` (n,) counts the multipliers near +1 of
    each point (None: unknown), where ``J - I`` may be singular (sticking friction memory).
    ``conserved``, optional: ``(gradients (n, k, size), rows (k,))``, quantities that may be
    conserved and the row of ``J - I`` each replaces (:meth:`PeriodMap.conserved_gradients`);
    where ``g (J - I)`` vanishes (below :data:`NULL_TOLERANCE`) the quantity is conserved, and its
    (void) row of ``(J - I) dx = -r`` is replaced by "keep it at the guess's", ``g dx = -g offset``.
    A point whose conserved quantities found so account for all its multipliers near +1 is then one
    batched LU solve; the others take the singular-value route of :func:`newton_step` (the void
    equations found as singular values below :data:`NULL_TOLERANCE`), one square system a point,
    solved batched."""
    jacobians = np.asarray(jacobians, dtype=float)
    residuals = np.asarray(residuals, dtype=float)
    n, size = residuals.shape
    offsets = np.zeros_like(residuals) if offsets is None else np.asarray(offsets, dtype=float)
    steps = np.empty((n, size))
    n_conserved = np.zeros(n, dtype=np.int64)
    matrices = jacobians - np.eye(size)
    rhs = -residuals.copy()
    if conserved is not None and len(conserved[1]):
        conserved, rows = np.asarray(conserved[0], dtype=float), np.asarray(conserved[1])
        void = np.max(np.abs(np.einsum("nks,nst->nkt", conserved, matrices)), axis=2) < NULL_TOLERANCE
        points, quantities = np.nonzero(void)
        replaced = rows[quantities]
        matrices[points, replaced] = conserved[points, quantities]
        rhs[points, replaced] = -np.einsum("ns,ns->n", conserved[points, quantities], offsets[points])
        n_conserved = void.sum(axis=1)
    memory = (np.ones(n, dtype=bool) if memory is None
              else np.asarray(memory) > n_conserved)
    plain = ~memory
    if plain.any():
        try:
            steps[plain] = np.linalg.solve(matrices[plain], rhs[plain][:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:  # exactly singular without a multiplier near +1: the general route
            memory = np.ones(n, dtype=bool)
    if memory.any():
        u, s, vt = np.linalg.svd(jacobians[memory] - np.eye(size))
        null = s < NULL_TOLERANCE
        system = s[:, :, None] * vt
        transposed = np.swapaxes(u, 1, 2)
        system[null] = transposed[null]
        rhs = -np.einsum("nij,nj->ni", transposed, residuals[memory])
        kept = -np.einsum("nij,nj->ni", transposed, offsets[memory])
        rhs[null] = kept[null]
        try:
            steps[memory] = np.linalg.solve(system, rhs[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:  # a singular replaced system: least squares, as newton_step
            steps[memory] = [np.linalg.lstsq(matrix, values, rcond=None)[0] for matrix, values in zip(system, rhs)]
        n_conserved[memory] = null.sum(axis=1)
    return steps, n_conserved


@dataclass(frozen=True)
class _Shot:
    state: NDArray[np.float64]
    jacobian: NDArray[np.float64]
    residual: float
    iterations: int
    converged: bool
    flag: int
    reason: str
    n_conserved: int


def shoot(period_map: PeriodMap, freq: float, amplitude: float, guess, steps_per_period: int, *,
          tolerance: float = 1e-9, max_iterations: int = 30, length=None) -> _Shot:
    """Newton on ``Phi(x) = x`` from ``guess`` (one point); see the module docstring."""
    state = np.asarray(guess, dtype=float).copy()
    anchor = state.copy()
    if length is None:
        length = max(amplitude, float(np.max(np.abs(state[:period_map.ndof]))))
    scale = period_map.scales(freq, amplitude, length)[0]
    residual = np.inf
    jacobian = np.full((period_map.size, period_map.size), np.nan)
    nulls = 0
    for iteration in range(max_iterations + 1):
        phi, jacobian, _, flag = period_map.jacobian(freq, amplitude, state, scale, steps_per_period)
        if flag != FLAG_OK:
            return _Shot(state, jacobian, np.nan, iteration, False, flag, FLAG_REASONS[flag], nulls)
        error = (phi - state) / scale
        residual = float(np.max(np.abs(error)))
        if residual <= tolerance:
            return _Shot(state, jacobian, residual, iteration, True, FLAG_OK, "ok", nulls)
        if iteration == max_iterations:
            break
        step, nulls = newton_step(jacobian, error, (state - anchor) / scale)
        # backtracking on the closing error: a full step unless it makes things worse
        for _ in range(6):
            trial = state + step * scale
            end, flags, _, _ = period_map.run(freq, amplitude, trial[None], steps_per_period)
            if flags[0] == FLAG_OK and np.max(np.abs((end[0] - trial) / scale)) < max(residual, 10 * tolerance):
                break
            step = 0.5 * step
        state = trial
    return _Shot(state, jacobian, residual, max_iterations, False, FLAG_OK,
                 f"shooting did not converge in {max_iterations} Newton iterations "
                 f"(closing error {residual:.2g} of the state scale, tolerance {tolerance:g})", nulls)


def stability_margin(tolerance: float = 0.0) -> float:
    """The margin of :func:`classify_multipliers` for orbits closed to ``tolerance``:
    ``max(STABILITY_MARGIN, tolerance)``."""
    return max(STABILITY_MARGIN, float(tolerance))


def classify_multipliers(multipliers, margin: float = STABILITY_MARGIN) -> tuple[bool, str]:
    """``(stable, kind)``: kind is "stable", "neutral", "period doubling" (real multiplier < -1),
    "fold" (real multiplier > 1) or "torus" (complex pair outside the unit circle).

    Unstable kinds need a ``|mu| > 1 + margin``. "neutral" (not stable): none is, but a multiplier
    other than +1 (friction memory: a family of orbits, kept by Newton) has ``|mu| >= 1 - margin``:
    a perturbation along it neither grows nor decays by more than the margin a period (an undamped
    system: every multiplier on the unit circle), so no time run settles on the orbit.
    """
    stable, kinds = classify_multiplier_rows(np.asarray(multipliers)[None, :], margin)
    return bool(stable[0]), str(kinds[0])


def classify_multiplier_rows(multipliers, margin: float = STABILITY_MARGIN) -> tuple[NDArray[np.bool_], NDArray[np.str_]]:
    """:func:`classify_multipliers` of every row of ``multipliers`` (n, size) at once (a map
    classifies every point: one vectorised pass instead of a call per point); returns
    ``(stable (n,), kinds (n,))``."""
    multipliers = np.atleast_2d(np.asarray(multipliers, dtype=complex))
    modulus = np.abs(multipliers)
    outside = modulus > 1.0 + margin
    memory = np.abs(multipliers - 1.0) <= margin
    neutral = ((modulus >= 1.0 - margin) & ~memory).any(axis=1)
    real = outside & (np.abs(multipliers.imag) <= 1e-6 * modulus)
    doubling = (real & (multipliers.real < 0)).any(axis=1)
    any_outside = outside.any(axis=1)
    kinds = np.select([~any_outside & neutral, ~any_outside, doubling, real.any(axis=1)],
                      ["neutral", "stable", "period doubling", "fold"], "torus")
    return kinds == "stable", kinds


def leading_multipliers(multipliers, margin: float = STABILITY_MARGIN) -> NDArray[np.complex128]:
    """Per row of ``multipliers`` (n, size), the multiplier of largest modulus other than the
    friction-memory ones within ``margin`` of +1 (NaN if none): the one that decides stability."""
    multipliers = np.atleast_2d(np.asarray(multipliers, dtype=complex))
    kept = np.isfinite(multipliers) & (np.abs(multipliers - 1.0) > margin)
    modulus = np.where(kept, np.abs(np.where(kept, multipliers, 0.0)), -1.0)
    column = np.argmax(modulus, axis=1)
    leading = multipliers[np.arange(multipliers.shape[0]), column]
    return np.where(kept.any(axis=1), leading, complex(np.nan, np.nan))


def orbit_harmonics(period_map: PeriodMap, freq, amplitude, states, steps_per_period, n_harmonics):
    """Harmonics and extremes of periodic orbits over a window of two excitation periods.

    Returns ``(coefficients, deflection_coefficients, half_range (batch, ndof), peak_acceleration, flags)``
    with complex amplitudes at orders ``m / 2`` (``m = 0 .. 2 K``) as in
    :class:`idkit.simulate.HarmonicResponse` (samples at the step starts).
    """
    states = np.atleast_2d(states)
    batch = states.shape[0]
    steps = np.broadcast_to(np.asarray(steps_per_period, dtype=np.int64), (batch,))
    freq = np.broadcast_to(np.asarray(freq, dtype=float), (batch,))
    amplitude = np.broadcast_to(np.asarray(amplitude, dtype=float), (batch,))
    window_max = 2 * int(steps.max())
    _, flags, rec_q, rec_a = period_map.run(freq, amplitude, states, steps, n_periods=2, n_record=window_max)
    n_coeff = 2 * int(n_harmonics) + 1
    coefficients = np.full((batch, n_coeff), np.nan, dtype=complex)
    deflection = np.full((batch, n_coeff), np.nan, dtype=complex)
    half_range = np.full((batch, period_map.ndof), np.nan)
    peak = np.full(batch, np.nan)
    for b in range(batch):
        if flags[b] != FLAG_OK:
            continue
        window = 2 * int(steps[b])
        n = np.arange(window)
        top = rec_q[b, 0, :window]
        base = amplitude[b] * np.sin(2.0 * np.pi * n / steps[b])
        twiddle = np.exp(-2j * np.pi * np.outer(np.arange(n_coeff), n) / window)
        weight = np.where(np.arange(n_coeff) == 0, 1.0 / window, 2.0 / window)
        coefficients[b] = weight * (twiddle @ top)
        deflection[b] = weight * (twiddle @ (top - base))
        half_range[b] = 0.5 * (rec_q[b, :, :window].max(axis=1) - rec_q[b, :, :window].min(axis=1))
        peak[b] = np.abs(rec_a[b, :window]).max()
    return coefficients, deflection, half_range, peak, flags


class HarmonicAccessors:
    """``harmonic`` and ``hosidf`` of a result of orbits (:class:`PeriodicResponse`, a
    continuation :class:`~idkit.responses.continuation.Branch`) holding ``coefficients`` of the
    top displacement at orders 0, 1/2, ..., K, one row a point, and the base ``amplitude`` (m)."""

    @accepts(order=Real(ge=0, meaning="0, 0.5, 1, ..."), error=SimulationError)
    def harmonic(self, order: float) -> NDArray[np.complex128]:
        """Complex amplitude (m) of the top displacement at ``order`` x f (0, 0.5, 1, 2, ...)."""
        index = int(round(2 * order))
        if not (0 <= index < self.coefficients.shape[1]) or abs(2 * order - index) > 1e-9:
            raise SimulationError(f"order: found {order!r}, expected 0, 0.5, 1, ..., "
                                  f"{(self.coefficients.shape[1] - 1) // 2}")
        return self.coefficients[:, index]

    def hosidf(self, order: float) -> NDArray[np.complex128]:
        """``k X_k / X_b1`` (dimensionless), as :meth:`idkit.simulate.HarmonicResponse.hosidf`."""
        return order * self.harmonic(order) / (-1j * self.amplitude)


@dataclass(frozen=True)
class PeriodicResponse(HarmonicAccessors):
    """Periodic steady states found by shooting, one per (frequency, amplitude) point.

    The base moves as ``x_b = A sin(2 pi f t)``. Coefficients follow
    :class:`idkit.simulate.HarmonicResponse`: complex amplitudes ``X_m`` of the absolute top
    displacement at ``m/2`` times the excitation frequency, over two excitation periods.

    Attributes
    ----------
    freq, amplitude : (n_points,) Hz, m
    periods : int
        Excitation periods of the orbit (1, or 2: the 1/2 subharmonic).
    steps_per_period : (n_points,) integration steps per excitation period
    state_names : tuple of str
        Name and unit of every state component (:class:`PeriodMap`).
    states : (n_points, n_states)
        Periodic state at t = 0 (SI units of ``state_names``).
    multipliers : complex (n_points, n_states)
        Floquet multipliers (eigenvalues of the monodromy matrix over ``periods`` periods), by
        decreasing modulus.
    stable : (n_points,) bool, ``instability == "stable"``
    instability : tuple of str
        ``"stable"``, ``"neutral"`` (not stable: undamped, see :func:`classify_multipliers`),
        ``"period doubling"``, ``"fold"`` or ``"torus"``.
    n_conserved : (n_points,) number of conserved quantities (sticking friction memory) held at the guess
    residual : (n_points,) closing error ``max |Phi(x) - x| / scale`` (dimensionless)
    iterations : (n_points,) Newton iterations
    converged : (n_points,) bool; reasons : tuple of str ("ok" only when converged)
    coefficients, deflection_coefficients : complex (n_points, 2 K + 1), m
    half_range : (n_points, ndof) peak-peak/2 of every mass displacement (absolute), m
    peak_acceleration : (n_points,) max |top acceleration|, m/s^2
    """

    freq: NDArray[np.float64]
    amplitude: NDArray[np.float64]
    periods: int
    steps_per_period: NDArray[np.int64]
    state_names: tuple[str, ...]
    states: NDArray[np.float64]
    multipliers: NDArray[np.complex128]
    stable: NDArray[np.bool_]
    instability: tuple[str, ...]
    n_conserved: NDArray[np.int64]
    residual: NDArray[np.float64]
    iterations: NDArray[np.int64]
    converged: NDArray[np.bool_]
    reasons: tuple[str, ...]
    coefficients: NDArray[np.complex128]
    deflection_coefficients: NDArray[np.complex128]
    half_range: NDArray[np.float64]
    peak_acceleration: NDArray[np.float64]

    @property
    def max_multiplier(self) -> NDArray[np.float64]:
        """Largest Floquet multiplier modulus per point (dimensionless)."""
        return np.abs(self.multipliers[:, 0])

    def to_dataframe(self) -> pd.DataFrame:
        """One row per point: ``freq [Hz]``, ``amplitude [m]``, ``x1 [m]`` (peak-peak/2 of the
        top mass), ``|H1| [-]``, ``|H0.5| [-]``, ``bias [m]``, ``max |mu| [-]``, ``stable``,
        ``instability``, ``residual [-]``, ``converged``, ``reason``."""
        columns = {"freq [Hz]": self.freq, "amplitude [m]": self.amplitude}
        for d in range(self.half_range.shape[1]):
            columns[f"x{d + 1} [m]"] = self.half_range[:, d]
        columns.update({
            "|H1| [-]": np.abs(self.hosidf(1)), "|H0.5| [-]": np.abs(self.hosidf(0.5)),
            "bias [m]": self.deflection_coefficients[:, 0].real, "max |mu| [-]": self.max_multiplier,
            "stable": self.stable, "instability": list(self.instability), "residual [-]": self.residual,
            "converged": self.converged, "reason": list(self.reasons),
        })
        return pd.DataFrame(columns)

    def report(self) -> str:
        """A few lines for people: convergence, stability, residuals."""
        n = self.freq.size
        lines = [f"PeriodicResponse: {n} points, orbits of {self.periods} excitation period(s), "
                 f"{int(self.converged.sum())}/{n} converged, {int((self.stable & self.converged).sum())} stable",
                 f"  largest closing error {np.nanmax(self.residual, initial=0.0):.2g} of the state scale"]
        for kind in ("period doubling", "fold", "torus"):
            count = sum(1 for value, ok in zip(self.instability, self.converged) if ok and value == kind)
            if count:
                lines.append(f"  unstable by {kind}: {count}")
        count = sum(1 for value, ok in zip(self.instability, self.converged) if ok and value == "neutral")
        if count:
            lines.append(f"  neutral (a multiplier on the unit circle within the stability margin: undamped, "
                         f"no time run settles there): {count}")
        for reason in sorted(set(self.reasons) - {"ok"}):
            lines.append(f"  {self.reasons.count(reason)} x {reason}")
        return "\n".join(lines)


def settle(period_map: PeriodMap, freq, amplitude, steps_per_period, n_periods: int, guess=None):
    """Time integration over ``n_periods`` from ``guess`` (default: the linear start); packed end states."""
    freq = np.atleast_1d(np.asarray(freq, dtype=float))
    amplitude = np.atleast_1d(np.asarray(amplitude, dtype=float))
    if guess is None:
        guess = period_map.linear_guess(freq, amplitude)
    if n_periods <= 0:
        return np.atleast_2d(guess), np.zeros(freq.size, dtype=np.int64)
    end, flags, _, _ = period_map.run(freq, amplitude, guess, steps_per_period, n_periods=n_periods)
    return end, flags


@accepts(freq=Reals(unit="Hz", gt=0), amplitude=Reals(unit="m", gt=0),
         initial_states=Reals(unit="state units", optional=True), settle_periods=Whole(ge=0),
         n_harmonics=Whole(ge=1), tolerance=Real(ge=MIN_TOLERANCE, lt=1, meaning="closing error over the state scale"),
         max_iterations=Whole(ge=0), seek_stable=Flag(optional=True), error=SimulationError)
def periodic_response(system, freq: ArrayLike, amplitude: ArrayLike, *, periods: int = 1, initial_states=None,
                      settle_periods: int = 20, steps_per_period=None, n_harmonics: int = 3,
                      tolerance: float = 1e-9, max_iterations: int = 30,
                      seek_stable: bool | None = None, jacobian: str = "auto") -> PeriodicResponse:
    """Periodic steady states of ``system`` under ``x_b = A sin(2 pi f t)`` by shooting.

    Parameters
    ----------
    system : SDOFSystem, HybridSystem or CoulombSpringSystem
    freq, amplitude : array_like, broadcast to (n_points,)
        Excitation frequency in Hz and base displacement amplitude in m.
    periods : {1, 2}
        Excitation periods of the sought orbit; 2 finds the 1/2 subharmonic (period doubling).
    initial_states : array_like (n, n_states), optional
        Starting states at t = 0 (layout: :class:`PeriodMap`); default the linear
        (small-amplitude) steady state. Either is integrated over ``settle_periods`` before
        Newton starts. The rows broadcast with the points: ``n`` equal to the number of points
        (one start each), 1 (the same start for every point), or any ``n`` with a single
        ``(freq, amplitude)``, which is then solved from each start (coexisting orbits); other
        shapes raise :class:`~idkit.errors.SimulationError` naming them.
    settle_periods : int, default 20
        Excitation periods integrated from the guess before Newton starts.
    steps_per_period : int or array_like, optional
        Default :func:`idkit.simulate.default_steps_per_period` (as the harmonic maps).
    n_harmonics : int, default 3
        Harmonics kept in the coefficients (orders 0, 1/2, ..., K).
    tolerance : float, default 1e-9
        Newton stops when the closing error ``max |Phi(x) - x| / scale`` is below this
        (:data:`idkit.limits.MIN_TOLERANCE` = 1e-12 to below 1).
    max_iterations : int, default 30
    seek_stable : bool, optional
        If an orbit found is unstable with a real multiplier outside the unit circle, push the
        masses along that eigenvector (1 and 3 state scales), integrate ``settle_periods`` and
        shoot again, keeping the first stable orbit: the attractor a long time integration
        would reach. Default: only for ``periods=2``, where the doubled period-1 orbit inside a
        period-doubling tongue is such an unstable fixed point next to the subharmonic.
    jacobian : {"auto", "exact", "finite differences"}
        Jacobian of the period map: propagated through the step (``"exact"``; "auto" uses it
        unless the system has Bouc-Wen elements) or by central differences (module docstring).

    Returns
    -------
    PeriodicResponse

    Examples
    --------
    >>> from idkit.models import library
    >>> orbit = periodic_response(library.get("system_a1_asymmetric"), 20.0, 1e-3)
    >>> bool(orbit.converged[0]), bool(orbit.stable[0])
    (True, True)
    """
    period_map = PeriodMap(system, periods, jacobian=jacobian)
    try:
        freq, amplitude = np.broadcast_arrays(np.atleast_1d(freq), np.atleast_1d(amplitude))
    except ValueError:
        raise SimulationError(f"freq, amplitude: found shapes {np.shape(freq)} and {np.shape(amplitude)}, "
                              "expected shapes that broadcast together") from None
    freq, amplitude = freq.ravel().copy(), amplitude.ravel().copy()
    if initial_states is not None:
        # rows of starting states broadcast with the points: one (freq, amplitude) from several
        # starts (coexisting orbits), or one start for every point
        guesses = np.atleast_2d(initial_states)
        rows = guesses.shape[0]
        if guesses.ndim != 2 or guesses.shape[1] != period_map.size or not (
                rows == freq.size or rows == 1 or freq.size == 1):
            raise SimulationError(
                f"initial_states: found shape {np.shape(initial_states)} for {freq.size} (freq, amplitude) point(s), "
                f"expected (n, {period_map.size}) with n = {freq.size} (one start a point), 1 (one start for "
                f"every point) or any n when a single (freq, amplitude) is given (columns "
                f"{', '.join(period_map.state_names)})")
        count = max(rows, freq.size)
        freq, amplitude = np.resize(freq, count), np.resize(amplitude, count)
        guesses = np.repeat(guesses, count, axis=0) if rows == 1 and count > 1 else guesses
    with np.errstate(over="ignore"):
        base_accel = amplitude * (2 * np.pi * freq) ** 2
    if not np.isfinite(base_accel).all():
        worst = int(np.argmin(np.isfinite(base_accel)))
        raise SimulationError(f"freq, amplitude: found {freq[worst]:g} Hz and {amplitude[worst]:g} m, whose base "
                              f"acceleration A (2 pi f)^2 overflows; expected a finite one")
    steps = check_steps_per_period(period_map, freq, steps_per_period, n_harmonics)
    if initial_states is None:
        guesses, flags = settle(period_map, freq, amplitude, steps, settle_periods)
    else:
        guesses, flags = settle(period_map, freq, amplitude, steps, settle_periods, guesses)
    return _solve_points(period_map, freq, amplitude, steps, guesses, flags, n_harmonics, tolerance, max_iterations,
                         settle_periods, seek_stable)


def check_steps_per_period(period_map: PeriodMap, freq, steps_per_period, n_harmonics: int) -> NDArray[np.int64]:
    """Steps per period of every point (``freq`` in Hz): ``steps_per_period`` if given (even
    integers >= 8, never truncated), else :func:`idkit.simulate.default_steps_per_period`; at most
    what the harmonic maps allow (:data:`idkit.simulate.harmonic.MAX_PERIOD_TABLE`: the two-period
    Fourier table of :func:`orbit_harmonics` must fit in memory)."""
    freq = np.atleast_1d(np.asarray(freq, dtype=float))
    if steps_per_period is None:
        steps = np.asarray(default_steps_per_period(period_map.system, freq), dtype=np.int64)
    else:
        try:
            given = np.asarray(steps_per_period, dtype=float)
        except (TypeError, ValueError):
            given = np.array(np.nan)
        if not (np.isfinite(given).all() and (given >= 8).all() and (given % 2 == 0).all()):
            raise SimulationError(f"steps_per_period: found {steps_per_period!r}, expected even integers >= 8")
        try:
            steps = np.broadcast_to(given, freq.shape).astype(np.int64)
        except ValueError:
            raise SimulationError(f"steps_per_period: found shape {given.shape}, expected one value or one per "
                                  f"point ({freq.size})") from None
    limit = MAX_PERIOD_TABLE // (2 * (2 * n_harmonics + 1))
    if not (steps <= limit).all():
        worst = int(np.argmax(steps))
        raise SimulationError(
            f"freq: found {freq[worst]:g} Hz with {steps[worst]} steps per period; with n_harmonics="
            f"{n_harmonics} a period may take at most {limit} steps (the orbit's Fourier table would not "
            f"fit in memory): expected a higher frequency, fewer steps per period or fewer harmonics")
    return steps


def _escape(period_map, freq, amplitude, shot, steps, settle_periods, tolerance, max_iterations):
    """From an unstable orbit, push the masses along its most unstable real eigenvector (1 and 3
    state scales, both ways; sticking friction elements follow, see :meth:`PeriodMap.push`),
    integrate ``settle_periods`` and shoot again; the first stable orbit found, else None. If
    none is found, push by 1 scale both ways again and integrate until the unstable mode has
    grown :data:`ESCAPE_GROWTH`-fold (at most :data:`ESCAPE_MAX_PERIODS` periods) before shooting.

    This is what a time integration does from near the unstable orbit, without waiting for the
    slow growth (a multiplier of 1.003 takes about 1500 periods to grow a 1 % perturbation 100x).
    """
    values, vectors = np.linalg.eig(shot.jacobian)
    real = np.abs(values.imag) <= 1e-6 * np.abs(values)
    if not np.any(real & (np.abs(values) > 1.0 + stability_margin(tolerance))):
        return None
    index = int(np.argmax(np.where(real, np.abs(values), -np.inf)))
    direction = vectors[:, index].real
    direction /= np.max(np.abs(direction))
    length = max(amplitude, float(np.max(np.abs(shot.state[:period_map.ndof]))))
    scale = period_map.scales(freq, amplitude, length)[0]
    # then, if the attractor lies further than a few state scales away (a subharmonic much larger
    # than the period-1 orbit), long enough for the unstable mode to grow ESCAPE_GROWTH-fold
    growth = float(np.abs(values[index]))
    periods = min(ESCAPE_MAX_PERIODS, int(math.ceil(period_map.periods * math.log(ESCAPE_GROWTH) / math.log(growth))))
    short = max(settle_periods, 2)
    attempts = [(1.0, 1.0, short), (1.0, -1.0, short), (3.0, 1.0, short), (3.0, -1.0, short)]
    if periods > short:
        attempts += [(1.0, 1.0, periods), (1.0, -1.0, periods)]
    for size, sign, n_periods in attempts:
        guess = period_map.push(shot.state, sign * size * direction[:2 * period_map.ndof] * scale[:2 * period_map.ndof])
        settled, flags = settle(period_map, freq, amplitude, steps, n_periods, guess[None])
        if flags[0] != FLAG_OK:
            continue
        retry = shoot(period_map, freq, amplitude, settled[0], steps, tolerance=tolerance,
                      max_iterations=max_iterations)
        if retry.converged and classify_multipliers(np.linalg.eigvals(retry.jacobian), stability_margin(tolerance))[0]:
            return retry
    return None


def _solve_points(period_map, freq, amplitude, steps, guesses, flags, n_harmonics, tolerance, max_iterations,
                  settle_periods, seek_stable=None):
    n, size = freq.size, period_map.size
    states = np.full((n, size), np.nan)
    multipliers = np.full((n, size), np.nan, dtype=complex)
    stable = np.zeros(n, dtype=bool)
    instability = ["unknown"] * n
    n_conserved = np.zeros(n, dtype=np.int64)
    residual = np.full(n, np.nan)
    iterations = np.zeros(n, dtype=np.int64)
    converged = np.zeros(n, dtype=bool)
    reasons = [""] * n
    margin = stability_margin(tolerance)
    for index in range(n):
        if flags[index] != FLAG_OK:
            reasons[index] = f"time integration before shooting: {FLAG_REASONS[int(flags[index])]}"
            continue
        shot = shoot(period_map, freq[index], amplitude[index], guesses[index], int(steps[index]),
                     tolerance=tolerance, max_iterations=max_iterations)
        if (seek_stable if seek_stable is not None else period_map.periods == 2) and shot.converged \
                and not classify_multipliers(np.linalg.eigvals(shot.jacobian), margin)[0]:
            shot = _escape(period_map, freq[index], amplitude[index], shot, int(steps[index]), settle_periods,
                           tolerance, max_iterations) or shot
        states[index] = shot.state
        residual[index] = shot.residual
        iterations[index] = shot.iterations
        converged[index] = shot.converged
        reasons[index] = shot.reason
        n_conserved[index] = shot.n_conserved
        if shot.converged:
            values = np.linalg.eigvals(shot.jacobian)
            multipliers[index] = values[np.argsort(-np.abs(values), kind="stable")]
            stable[index], instability[index] = classify_multipliers(values, margin)
    coefficients, deflection, half_range, peak, _ = orbit_harmonics(
        period_map, freq, amplitude, np.where(converged[:, None], states, 0.0), steps, n_harmonics)
    for field in (coefficients, deflection, half_range, peak):
        field[~converged] = np.nan
    return PeriodicResponse(
        freq=freq, amplitude=amplitude, periods=period_map.periods, steps_per_period=np.asarray(steps),
        state_names=period_map.state_names, states=states, multipliers=multipliers, stable=stable,
        instability=tuple(instability), n_conserved=n_conserved, residual=residual, iterations=iterations,
        converged=converged, reasons=tuple(reasons), coefficients=coefficients, deflection_coefficients=deflection,
        half_range=half_range, peak_acceleration=peak,
    )
