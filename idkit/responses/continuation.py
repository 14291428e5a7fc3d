"""Branches of periodic steady states by pseudo-arclength continuation (shooting on the exact kernel).

A branch follows the periodic solutions of :mod:`idkit.responses.periodic` as the excitation
frequency varies at a fixed base amplitude (:func:`continue_in_frequency`), or the amplitude at
a fixed frequency (:func:`continue_in_amplitude`), through folds where a grid of time
integrations jumps. Unknowns: the scaled state at t = 0 and ``p = ln(parameter)``.

* Predictor: a step ``ds`` along the unit tangent, the null vector of ``[dG/dx, dG/dp]`` with
  ``G = Phi(x) - x`` (scaled), oriented like the previous tangent.
* Corrector: Newton on ``G = 0`` plus the arclength condition ``t . (y - y_predicted) = 0``;
  conserved quantities of sticking friction (zero singular values of ``dG/dx``, see
  :mod:`~idkit.responses.periodic`) are held at the previous point's value.
* Step control: ``ds`` grows by 1.5 after a corrector that needed at most 3 iterations,
  halves after a failure, between ``min_step`` and ``max_step``.
* Stability: Floquet multipliers of every point (eigenvalues of ``dPhi/dx``).
* Special points: a **fold** where the parameter component of the tangent changes sign (located
  by the vertex of a parabola through the three points around it, parameter versus arclength);
  **period doubling** where the number of real multipliers below -1 changes (located by linear
  interpolation of the multiplier of most negative real part).

Scales follow :meth:`~idkit.responses.periodic.PeriodMap.scales` with the response length of
the start point, proportional to the amplitude along an amplitude branch.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from idkit.checks import Choice, Real, Reals, Whole, accepts
from idkit.errors import SimulationError
from idkit.responses.periodic import (
    NULL_TOLERANCE,
    HarmonicAccessors,
    PeriodMap,
    check_steps_per_period,
    classify_multipliers,
    conserved_directions,
    orbit_harmonics,
    periodic_response,
    stability_margin,
)
from idkit.simulate._kernel import FLAG_OK, FLAG_REASONS

__all__ = ["Branch", "SpecialPoint", "continue_in_amplitude", "continue_in_frequency"]

#: A corrector iterate further than this from its prediction (scaled state and ``ln`` of the
#: parameter: the whole response, or a factor e in the parameter) has left the branch.
CORRECTOR_REACH = 1.0
#: A unit tangent whose parameter component is below this (round-off of the null vector) does not
#: move the parameter: the branch is following a family of orbits at a fixed parameter.
TANGENT_NOISE = 1e-12


@dataclass(frozen=True)
class SpecialPoint:
    """A fold or a period-doubling point located between two branch points.

    Attributes
    ----------
    kind : str
        ``"fold"`` or ``"period doubling"``.
    index : int
        The special point lies between branch points ``index`` and ``index + 1``.
    freq : float
        Hz. amplitude : float, m. half_range : float, peak-peak/2 of the top mass, m
        (interpolated like the parameter).
    """

    kind: str
    index: int
    freq: float
    amplitude: float
    half_range: float


@dataclass(frozen=True)
class Branch(HarmonicAccessors):
    """A branch of periodic steady states under ``x_b = A sin(2 pi f t)``.

    Attributes
    ----------
    parameter : str
        ``"freq"`` (frequency varies, amplitude fixed) or ``"amplitude"``.
    freq : (n_points,) Hz
    amplitude : (n_points,) m
    periods : int
        Excitation periods of the orbits (1, or 2 for a 1/2 subharmonic branch).
    steps_per_period : int
        Integration steps per excitation period, fixed along the branch.
    state_names : tuple of str
        Names and units of the state components (:class:`~idkit.responses.periodic.PeriodMap`).
    states : (n_points, n_states)
        Periodic state at t = 0, SI units of ``state_names``.
    multipliers : complex (n_points, n_states)
        Floquet multipliers by decreasing modulus, dimensionless.
    stable : (n_points,) bool, ``instability == "stable"``
    coefficients, deflection_coefficients : complex (n_points, 2 K + 1)
        Complex amplitudes (m) of the top displacement (absolute; relative to the base) at
        ``m/2`` times the excitation frequency, as :class:`idkit.simulate.HarmonicResponse`.
    half_range : (n_points, ndof) peak-peak/2 of every mass displacement, m
    residual : (n_points,) closing error of the periodic orbit over its state scale (dimensionless)
    arclength : (n_points,) cumulative arclength in scaled variables (dimensionless)
    special_points : tuple of SpecialPoint
    success : bool
        The branch left its parameter range at either end without a failure (a branch stopped
        by ``max_points`` inside the range is not a success).
    reason : str
        ``"ok"`` or why the branch stopped early.
    instability : tuple of str
        Per point ``"stable"``, ``"neutral"`` (undamped: a multiplier on the unit circle, not
        stable), ``"period doubling"``, ``"fold"`` or ``"torus"``
        (:func:`~idkit.responses.periodic.classify_multipliers`).
    """

    parameter: str
    freq: NDArray[np.float64]
    amplitude: NDArray[np.float64]
    periods: int
    steps_per_period: int
    state_names: tuple[str, ...]
    states: NDArray[np.float64]
    multipliers: NDArray[np.complex128]
    stable: NDArray[np.bool_]
    coefficients: NDArray[np.complex128]
    deflection_coefficients: NDArray[np.complex128]
    half_range: NDArray[np.float64]
    residual: NDArray[np.float64]
    arclength: NDArray[np.float64]
    special_points: tuple[SpecialPoint, ...]
    success: bool
    reason: str
    instability: tuple[str, ...] = ()

    @property
    def n_points(self) -> int:
        return int(self.freq.size)

    @property
    def values(self) -> NDArray[np.float64]:
        """The continuation parameter along the branch (Hz or m)."""
        return self.freq if self.parameter == "freq" else self.amplitude

    @property
    def amplitude_ratio(self) -> NDArray[np.float64]:
        """Peak-peak/2 of the top mass over the base amplitude (as :attr:`HarmonicMap.amplitude_ratio`)."""
        return self.half_range[:, 0] / self.amplitude

    def points(self, kind: str) -> tuple[SpecialPoint, ...]:
        """Special points of ``kind`` ("fold" or "period doubling")."""
        if kind not in ("fold", "period doubling"):  # any other name returned () as if none were found
            raise SimulationError(f"kind: found {kind!r}, expected 'fold' or 'period doubling'")
        return tuple(point for point in self.special_points if point.kind == kind)

    def to_dataframe(self) -> pd.DataFrame:
        """One row per branch point.

        Columns ``freq [Hz]``, ``amplitude [m]``, ``x1 [m]`` (``x2 [m]``: peak-peak/2 of each
        mass, top first), ``|H1| [-]``, ``|H0.5| [-]``, ``bias [m]``, ``max |mu| [-]``,
        ``stable``, ``stability`` (:attr:`instability`), ``fold`` and ``period_doubling`` (True at the branch point nearest each
        special point), ``residual [-]``, ``arclength [-]``.
        """
        columns = {"freq [Hz]": self.freq, "amplitude [m]": self.amplitude}
        for d in range(self.half_range.shape[1]):
            columns[f"x{d + 1} [m]"] = self.half_range[:, d]
        marks = {"fold": np.zeros(self.n_points, dtype=bool), "period doubling": np.zeros(self.n_points, dtype=bool)}
        for point in self.special_points:
            values = self.values
            target = point.freq if self.parameter == "freq" else point.amplitude
            pair = [point.index, min(point.index + 1, self.n_points - 1)]
            nearest = pair[int(np.argmin(np.abs(values[pair] - target)))]
            marks[point.kind][nearest] = True
        columns.update({
            "|H1| [-]": np.abs(self.hosidf(1)), "|H0.5| [-]": np.abs(self.hosidf(0.5)),
            "bias [m]": self.deflection_coefficients[:, 0].real, "max |mu| [-]": np.abs(self.multipliers[:, 0]),
            "stable": self.stable, "stability": list(self.instability) or [""] * self.n_points, "fold": marks["fold"], "period_doubling": marks["period doubling"],
            "residual [-]": self.residual, "arclength [-]": self.arclength,
        })
        return pd.DataFrame(columns)

    def report(self) -> str:
        """A few lines for people: range, stability, special points, closing errors."""
        fixed = (f"amplitude {self.amplitude[0]:.3g} m" if self.parameter == "freq"
                 else f"frequency {self.freq[0]:.4g} Hz")
        unit = "Hz" if self.parameter == "freq" else "m"
        lines = [
            f"Branch in {self.parameter} at {fixed}: {self.n_points} points, {self.values.min():.4g}-"
            f"{self.values.max():.4g} {unit}, orbits of {self.periods} period(s), {self.steps_per_period} steps/period",
            f"  stable points: {int(self.stable.sum())}/{self.n_points}"
            + (f" ({self.instability.count('neutral')} neutral: undamped)" if "neutral" in self.instability else "")
            + "; largest closing error "
            f"{np.nanmax(self.residual, initial=0.0):.2g}; {'complete' if self.success else 'stopped: ' + self.reason}",
        ]
        for point in self.special_points:
            lines.append(f"  {point.kind:16s} at {point.freq:.5g} Hz, {point.amplitude:.4g} m, "
                         f"top peak-peak/2 {point.half_range:.4g} m")
        return "\n".join(lines)


def _derivative_of_scales(period_map, parameter, freq, amplitude, length_of):
    """``d s / d p`` with ``p = ln(parameter)``, by central differences (the scales are explicit)."""
    step = 1e-6
    if parameter == "freq":
        up = period_map.scales(freq * math.exp(step), amplitude, length_of(amplitude))[0]
        down = period_map.scales(freq * math.exp(-step), amplitude, length_of(amplitude))[0]
    else:
        up = period_map.scales(freq, amplitude * math.exp(step), length_of(amplitude * math.exp(step)))[0]
        down = period_map.scales(freq, amplitude * math.exp(-step), length_of(amplitude * math.exp(-step)))[0]
    return (up - down) / (2 * step)


class _Problem:
    """``G(z, p) = Phi(z s) / s - z`` in scaled unknowns ``z`` and ``p = ln(parameter)``."""

    def __init__(self, period_map: PeriodMap, parameter: str, fixed: float, steps: int, length0: float,
                 value0: float):
        self.map = period_map
        self.parameter = parameter
        self.fixed = fixed
        self.steps = steps
        self.length0 = length0
        self.value0 = value0

    def point(self, p):
        value = math.exp(p)
        return (value, self.fixed) if self.parameter == "freq" else (self.fixed, value)

    def length(self, amplitude):
        return self.length0 * (amplitude / self.value0 if self.parameter == "amplitude" else 1.0)

    def scale(self, p):
        freq, amplitude = self.point(p)
        return self.map.scales(freq, amplitude, self.length(amplitude))[0]

    def evaluate(self, z, p):
        """``(G, dG/dz, dG/dp, J = dPhi~/dz, flag)`` at ``(z, p)``."""
        freq, amplitude = self.point(p)
        scale = self.scale(p)
        phi, jacobian, phi_p, flag = self.map.jacobian(freq, amplitude, z * scale, scale, self.steps,
                                                       parameter=self.parameter)
        if flag != FLAG_OK:
            return None, None, None, None, flag
        relative = _derivative_of_scales(self.map, self.parameter, freq, amplitude, self.length) / scale
        phi_scaled = phi / scale
        g_p = jacobian @ (z * relative) + phi_p - phi_scaled * relative
        return phi_scaled - z, jacobian - np.eye(z.size), g_p, jacobian, flag


def _conserved(g_z, g_p):
    """Left singular vectors of ``g_z`` and the indices of its conserved directions: zero singular
    values along which the parameter does not act either (``u . g_p = 0``). A zero singular value
    with ``u . g_p != 0`` is a fold, where the arclength condition, not a constraint, closes the
    system."""
    u, _, _, null = conserved_directions(g_z)
    scale = max(1.0, float(np.linalg.norm(g_p)))
    null = np.array([k for k in null if abs(u[:, k] @ g_p) <= NULL_TOLERANCE * scale], dtype=int)
    return u, null


def _tangent(g_z, g_p, previous):
    """Unit null vector of ``[g_z, g_p]`` (conserved directions held), oriented along ``previous``."""
    n = g_z.shape[0]
    u, null = _conserved(g_z, g_p)
    keep = np.setdiff1d(np.arange(n), null)
    extended = np.column_stack([g_z, g_p])
    rows = [u[:, keep].T @ extended]
    if null.size:
        rows.append(np.column_stack([u[:, null].T, np.zeros(null.size)]))
    rows.append(previous[None, :])
    matrix = np.vstack(rows)
    rhs = np.zeros(matrix.shape[0])
    rhs[-1] = 1.0
    tangent = np.linalg.lstsq(matrix, rhs, rcond=None)[0]
    return tangent / np.linalg.norm(tangent)


def _correct(problem: _Problem, predicted, tangent, anchor, tolerance, max_iterations):
    """Newton on ``[G; t . (y - y_predicted)] = 0``; returns ``((y, evaluation, iterations), flag)``,
    or ``(None, flag)`` when it does not converge: ``flag`` is the time step's failure if one
    failed, else ``FLAG_OK``. An iterate further than :data:`CORRECTOR_REACH` from the prediction
    (scaled), or not finite, has left the branch: the corrector stops there."""
    y = predicted.copy()
    n = y.size - 1
    for iteration in range(max_iterations + 1):
        if not (np.all(np.isfinite(y)) and np.linalg.norm(y - predicted) <= CORRECTOR_REACH):
            return None, FLAG_OK
        g, g_z, g_p, jacobian, flag = problem.evaluate(y[:n], y[n])
        if flag != FLAG_OK:
            return None, flag
        if np.max(np.abs(g)) <= tolerance:
            return (y, (g, g_z, g_p, jacobian), iteration), FLAG_OK
        if iteration == max_iterations:
            return None, FLAG_OK
        u, null = _conserved(g_z, g_p)
        keep = np.setdiff1d(np.arange(n), null)
        extended = np.column_stack([g_z, g_p])
        rows = [u[:, keep].T @ extended]
        rhs = [-(u[:, keep].T @ g)]
        if null.size:
            rows.append(np.column_stack([u[:, null].T, np.zeros(null.size)]))
            rhs.append(-(u[:, null].T @ (y[:n] - anchor[:n])))
        rows.append(tangent[None, :])
        rhs.append(np.array([-(tangent @ (y - predicted))]))
        delta = np.linalg.lstsq(np.vstack(rows), np.concatenate(rhs), rcond=None)[0]
        y = y + delta
    return None, FLAG_OK


def _most_negative(multipliers):
    return multipliers[int(np.argmin(multipliers.real))]


def _count_below_minus_one(multipliers):
    real = np.abs(multipliers.imag) <= 1e-6 * np.abs(multipliers)
    return int(np.sum(real & (multipliers.real < -1.0)))


def _special_points(parameter, p_values, tangent_p, multipliers, arclength, half_range, fixed):
    points = []
    for index in range(p_values.size - 1):
        if tangent_p[index] * tangent_p[index + 1] < 0 and min(abs(tangent_p[index]), abs(tangent_p[index + 1])) \
                >= TANGENT_NOISE:  # a sign of round-off is no turn
            # parabola p(s) through three points around the turn; its vertex is the fold
            centre = index if 0 < index else index + 1
            centre = min(max(centre, 1), p_values.size - 2) if p_values.size >= 3 else index
            location, height = p_values[index], half_range[index]
            if p_values.size >= 3:
                s = arclength[centre - 1:centre + 2]
                coefficients = np.polyfit(s - s[1], p_values[centre - 1:centre + 2], 2)
                if coefficients[0] != 0:
                    vertex = -coefficients[1] / (2 * coefficients[0])
                    if s[0] - s[1] <= vertex <= s[2] - s[1]:
                        location = np.polyval(coefficients, vertex)
                        height = np.interp(vertex + s[1], s, half_range[centre - 1:centre + 2])
            points.append(("fold", index, location, height))
        if _count_below_minus_one(multipliers[index]) != _count_below_minus_one(multipliers[index + 1]):
            a = _most_negative(multipliers[index]).real + 1.0
            b = _most_negative(multipliers[index + 1]).real + 1.0
            weight = a / (a - b) if a != b else 0.5
            weight = min(max(weight, 0.0), 1.0)
            location = p_values[index] + weight * (p_values[index + 1] - p_values[index])
            height = half_range[index] + weight * (half_range[index + 1] - half_range[index])
            points.append(("period doubling", index, location, height))
    result = []
    for kind, index, location, height in points:
        value = math.exp(location)
        freq, amplitude = (value, fixed) if parameter == "freq" else (fixed, value)
        result.append(SpecialPoint(kind=kind, index=int(index), freq=float(freq), amplitude=float(amplitude),
                                   half_range=float(height)))
    return tuple(result)


def _continue(system, parameter, fixed, bounds, start, *, periods, steps_per_period, step, min_step, max_step,
              max_points, n_harmonics, tolerance, initial_state, settle_periods, direction, jacobian) -> Branch:
    unit = "Hz" if parameter == "freq" else "m"
    name = "freq_range" if parameter == "freq" else "amplitude_range"
    low, high = (float(value) for value in bounds)
    given_start = start
    start = (low if direction == 1 else high) if start is None else start
    if not (low <= start <= high):
        raise SimulationError(f"start: found {given_start!r}, expected a value within {name} [{low:g}, {high:g}] "
                              f"{unit}")
    step = max_step / 5 if step is None else step
    if not min_step <= step <= max_step:
        raise SimulationError(f"step: found min_step={min_step!r}, step={step!r}, max_step={max_step!r}, "
                              "expected 0 < min_step <= step <= max_step")
    period_map = PeriodMap(system, periods, jacobian=jacobian)
    freq0, amplitude0 = (start, fixed) if parameter == "freq" else (fixed, start)
    if steps_per_period is not None and np.ndim(steps_per_period) != 0:
        raise SimulationError(f"steps_per_period: found {steps_per_period!r}, expected one even integer >= 8 "
                              "(fixed along the branch)")
    lowest_freq = low if parameter == "freq" else fixed
    steps = int(check_steps_per_period(period_map, [lowest_freq], steps_per_period, n_harmonics)[0])
    first = periodic_response(period_map.system, freq0, amplitude0, periods=periods, steps_per_period=steps,
                              jacobian=jacobian,
                              initial_states=None if initial_state is None else [initial_state],
                              settle_periods=settle_periods, n_harmonics=n_harmonics, tolerance=tolerance)
    if not first.converged[0]:
        raise SimulationError(f"start: no periodic solution at {freq0:g} Hz, {amplitude0:g} m "
                              f"({first.reasons[0]})")
    # response length scale: the largest small-amplitude (linear) response over the range, so
    # that scaled states stay of order one through a resonance
    probe = np.geomspace(low, high, 400) if parameter == "freq" else np.array([fixed])
    linear_peak = float(np.max(np.abs(period_map.system.transmissibility(probe))))
    length0 = max(amplitude0 * linear_peak, amplitude0, float(first.half_range[0].max()))
    problem = _Problem(period_map, parameter, fixed, steps, length0, start)
    p_low, p_high = math.log(low), math.log(high)
    p0 = math.log(start)
    z0 = first.states[0] / problem.scale(p0)
    g, g_z, g_p, monodromy, flag = problem.evaluate(z0, p0)
    y = np.append(z0, p0)
    tangent = _tangent(g_z, g_p, np.append(np.zeros(z0.size), float(direction)))
    ys, tangents, jacobians, residuals = [y], [tangent], [monodromy], [float(np.max(np.abs(g)))]
    ds = step
    reason = "ok"
    success = True
    while len(ys) < max_points:
        predicted = y + ds * tangent
        outcome, flag = _correct(problem, predicted, tangent, y, tolerance, 8)
        if outcome is None:
            # a failed step or a corrector that wandered off: try a shorter step; the reason of the
            # last failure is kept for the report
            failure = (f"the time step failed near {math.exp(predicted[-1]):.5g} {unit}: {FLAG_REASONS[flag]}"
                       if flag != FLAG_OK else None)
            ds *= 0.5
            if ds < min_step:
                reason = (f"corrector did not converge with the smallest step {min_step:g} near "
                          f"{math.exp(y[-1]):.5g} {unit}" + (f" ({failure})" if failure else ""))
                success = False
                break
            continue
        y_new, (g, g_z, g_p, monodromy), iterations = outcome
        tangent = _tangent(g_z, g_p, tangent)
        y = y_new
        ys.append(y)
        tangents.append(tangent)
        jacobians.append(monodromy)
        residuals.append(float(np.max(np.abs(g))))
        if iterations <= 3:
            ds = min(ds * 1.5, max_step)
        if not (p_low - 1e-12 <= y[-1] <= p_high + 1e-12):
            break
        if abs(tangent[-1]) < TANGENT_NOISE:
            reason = (f"at {math.exp(y[-1]):.5g} {unit} the branch has no direction in {parameter} left: it goes on "
                      f"only along a family of orbits at that {parameter} (sticking friction memory, a multiplier "
                      f"at 1, that the {parameter} does not leave conserved); not a fold")
            success = False
            break
    else:
        if success:  # the cap, not the end of the range, stopped the branch
            success = False
            reason = (f"max_points ({max_points}) reached at {math.exp(y[-1]):.5g} {unit}, inside "
                      f"{name} [{low:g}, {high:g}] {unit}")
    ys = np.array(ys)
    p_values = ys[:, -1]
    states = np.array([row[:-1] * problem.scale(p) for row, p in zip(ys, p_values)])
    values = np.exp(p_values)
    freq = values if parameter == "freq" else np.full(values.size, fixed)
    amplitude = np.full(values.size, fixed) if parameter == "freq" else values
    multipliers = np.array([np.sort_complex(np.linalg.eigvals(j))[::-1] for j in jacobians])
    order = np.argsort(-np.abs(multipliers), axis=1, kind="stable")
    multipliers = np.take_along_axis(multipliers, order, axis=1)
    classes = [classify_multipliers(row, stability_margin(tolerance)) for row in multipliers]
    stable = np.array([stable for stable, _ in classes], dtype=bool)
    coefficients, deflection, half_range, _, _ = orbit_harmonics(period_map, freq, amplitude, states, steps,
                                                                 n_harmonics)
    steps_taken = np.linalg.norm(np.diff(ys, axis=0), axis=1)
    arclength = np.concatenate([[0.0], np.cumsum(steps_taken)])
    special = _special_points(parameter, p_values, np.array(tangents)[:, -1], multipliers, arclength,
                              half_range[:, 0], fixed)
    return Branch(
        parameter=parameter, freq=freq, amplitude=amplitude, periods=period_map.periods, steps_per_period=steps,
        state_names=period_map.state_names, states=states, multipliers=multipliers, stable=stable,
        coefficients=coefficients, deflection_coefficients=deflection, half_range=half_range,
        residual=np.array(residuals), arclength=arclength, special_points=special, success=success, reason=reason,
        instability=tuple(kind for _, kind in classes),
    )


#: The contract of the options both continuations take (the steps are in ln f or ln A).
_BRANCH_OPTIONS = {"n_harmonics": Whole(ge=1), "max_points": Whole(ge=2), "step": Real(gt=0, optional=True),
                   "min_step": Real(gt=0), "max_step": Real(gt=0), "direction": Choice((1, -1))}


@accepts(amplitude=Real(unit="m", gt=0), freq_range=Reals(unit="Hz", gt=0, min_size=2, max_size=2, increasing=True),
         start=Real(unit="Hz", gt=0, optional=True), **_BRANCH_OPTIONS, error=SimulationError)
def continue_in_frequency(system, amplitude: float, freq_range, *, start: float | None = None, periods: int = 1,
                          steps_per_period: int | None = None, step: float | None = None, min_step: float = 1e-6,
                          max_step: float = 0.05, max_points: int = 400, n_harmonics: int = 3,
                          tolerance: float = 1e-9, initial_state=None, settle_periods: int = 20,
                          direction: int = 1, jacobian: str = "auto") -> Branch:
    """Branch of periodic responses over frequency at a fixed base amplitude.

    Parameters
    ----------
    system : SDOFSystem, HybridSystem or CoulombSpringSystem
    amplitude : float
        Base displacement amplitude in m.
    freq_range : (float, float)
        Frequencies in Hz; the branch stops when it leaves this range (either end).
    start : float, optional
        Start frequency in Hz (default: the end of the range the branch leaves from).
    direction : {1, -1}
        The branch leaves the start towards higher (1) or lower (-1) frequency.
    periods : {1, 2}
        Orbits of one excitation period, or two (a 1/2 subharmonic branch; start it inside
        the period-doubling range).
    steps_per_period : int, optional
        Fixed along the branch; default :func:`idkit.simulate.default_steps_per_period` at the
        lowest frequency of the range (the map's value there, finer elsewhere).
    step, min_step, max_step : float
        Arclength steps in scaled unknowns (state over its scale, ``ln f``); ``step`` (the
        first one) defaults to ``max_step / 5``. ``max_step`` also bounds the relative change
        of frequency per step: keep it below the width of features to be resolved (the
        Table A.1 period-doubling range at 1.2 mm is 0.5 % wide: ``max_step=0.002``).
    max_points : int
        Cap on the number of branch points; a branch it stops inside the range has
        ``success=False`` (the reason says where it stopped).
    n_harmonics : int
        Harmonics kept (orders 0, 1/2, ..., K).
    tolerance : float
        Closing error of every orbit (scaled), as in :func:`~idkit.responses.periodic.periodic_response`.
    initial_state : array_like, optional
        Guess at t = 0 for the start point (default: linear start and ``settle_periods``).
    settle_periods : int
        Time integration before shooting the start point.
    jacobian : {"auto", "exact", "finite differences"}
        Jacobian of the period map (:func:`~idkit.responses.periodic.periodic_response`).

    Returns
    -------
    Branch

    Examples
    --------
    >>> from idkit.models import library
    >>> branch = continue_in_frequency(library.get("system_a1_asymmetric"), 1e-3, (20.0, 25.0), max_step=0.2)
    >>> bool(branch.success), bool(branch.stable.all())
    (True, True)
    """
    return _continue(system, "freq", amplitude, freq_range, start, periods=periods,
                     steps_per_period=steps_per_period, step=step, min_step=min_step, max_step=max_step,
                     max_points=max_points, n_harmonics=n_harmonics, tolerance=tolerance,
                     initial_state=initial_state, settle_periods=settle_periods, direction=direction,
                     jacobian=jacobian)


@accepts(freq=Real(unit="Hz", gt=0), amplitude_range=Reals(unit="m", gt=0, min_size=2, max_size=2, increasing=True),
         start=Real(unit="m", gt=0, optional=True), **_BRANCH_OPTIONS, error=SimulationError)
def continue_in_amplitude(system, freq: float, amplitude_range, *, start: float | None = None, periods: int = 1,
                          steps_per_period: int | None = None, step: float | None = None, min_step: float = 1e-6,
                          max_step: float = 0.2, max_points: int = 400, n_harmonics: int = 3,
                          tolerance: float = 1e-9, initial_state=None, settle_periods: int = 20,
                          direction: int = 1, jacobian: str = "auto") -> Branch:
    """Branch of periodic responses over base amplitude at a fixed frequency.

    Parameters are those of :func:`continue_in_frequency`, with ``freq`` (Hz) fixed and
    ``amplitude_range`` (m) followed in ``ln A``; state scales grow with the amplitude.

    Examples
    --------
    >>> from idkit.models import library
    >>> branch = continue_in_amplitude(library.get("system_a1_asymmetric"), 20.0, (1e-4, 1e-3))
    >>> bool(branch.success), bool(branch.amplitude[-1] >= 1e-3)
    (True, True)
    """
    return _continue(system, "amplitude", freq, amplitude_range, start, periods=periods,
                     steps_per_period=steps_per_period, step=step, min_step=min_step, max_step=max_step,
                     max_points=max_points, n_harmonics=n_harmonics, tolerance=tolerance,
                     initial_state=initial_state, settle_periods=settle_periods, direction=direction,
                     jacobian=jacobian)

