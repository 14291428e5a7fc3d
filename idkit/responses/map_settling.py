"""Settling and classifying the points of a harmonic map that its time runs leave.

:func:`idkit.responses.harmonic_map.harmonic_map` runs every point in time first; this module holds
what follows (docs/responses.md, docs/periodic.md): a run that stopped on one window change is
taken only if the Newton distance from its classification period is within the tolerance (else it
runs on), the points whose runs reach the period cap are settled by batched Newton on the period map from the runs' end states (or shot one by one), every
settled orbit is classified by its Floquet multipliers, and an unstable one is carried to what a long
run reaches (period 2 after a period doubling, the other branch after a fold).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from idkit.responses.periodic import (
    STABILITY_MARGIN,
    PeriodMap,
    classify_multiplier_rows,
    classify_multipliers,
    leading_multipliers,
    monodromy,
    newton_steps,
    periodic_response,
    stability_margin,
)
from idkit.simulate import harmonic_response
from idkit.simulate._kernel import FLAG_OK, FLAG_REASONS
from idkit.simulate._parallel import run_chunked

#: Default period cap of a map's time integration when the points left over are shot one by one
#: (:func:`harmonic_map` with ``newton=False``, or a system without the propagated Jacobian).
SHOOTING_AFTER_PERIODS = 200

#: Newton iterations on the period map a map point may spend, one period with the propagated
#: Jacobian each, to come within the steady-state tolerance of its orbit (:func:`settle_by_newton`);
#: a point that does not is left to the time run.
NEWTON_TANGENT_PERIODS = 3
#: Windows of two plain periods a Newton point may run to verify its orbit, with a chord step between
#: them, before it is left to the time run.
NEWTON_WINDOWS = 2
#: Farthest (in units of the state scale, every component) a Newton orbit may lie from the state it
#: started from and still be taken: where friction makes orbits coexist, a longer step may land on one
#: the time run from that state would not reach.
NEWTON_REACH = 0.1
#: Period cap of a map's time runs before Newton settles the points left (the default cap): long
#: enough that the transient has chosen the member of a friction-memory family of orbits a long run
#: reaches, which Newton cannot choose (shorter caps and their measured effect: docs/responses.md).
NEWTON_AFTER_PERIODS = 48
#: A time run that stops before this many periods (three windows of two) has measured no ratio of
#: window changes for its geometric extrapolation (its first window is compared with nothing): its
#: end state is taken only if the Newton distance to its orbit, from the classification's own period
#: with the Jacobian, is within the tolerance (:func:`confirm_early_stops`); else it runs on.
RATIO_PERIODS = 6


#: A carried point shows a period-2 orbit when its 1/2 subharmonic exceeds this many steady-state
#: tolerances of its first harmonic (a settled period-1 orbit keeps about one tolerance of it).
SUBHARMONIC_TOLERANCES = 10
#: An unstable orbit is left by pushing the masses this fraction of the state scale along its
#: unstable eigenvector; the run then spans the periods the push needs to grow to the scale.
CARRY_PUSH = 1e-2
#: At most this many periods of growth: a multiplier closer to the unit circle (|mu|^4000 < 100,
#: |mu| < 1.00115) is pushed further, ``|mu|^-4000`` of the scale, so that it still grows to the
#: scale within them.
CARRY_PERIODS = 4000


@dataclass
class MapPoints:
    """The map's per-point values (flat, frequency-major) while they are settled and classified."""

    freq: NDArray[np.float64]
    amplitude: NDArray[np.float64]
    hosidf_values: NDArray[np.complex128]
    half_range: NDArray[np.float64]
    bias: NDArray[np.float64]
    peak: NDArray[np.float64]
    periods: NDArray[np.float64]
    change: NDArray[np.float64]
    converged: NDArray[np.bool_]
    flags: NDArray[np.int64]
    reasons: list
    shot: NDArray[np.bool_]
    states: tuple  # the time runs' end states (harmonic_response's end_states layout)
    stability: list
    multiplier: NDArray[np.complex128]
    # index -> (multipliers, scaled monodromy matrix) of orbits classified already at their end state
    classified: dict = field(default_factory=dict)

    @classmethod
    def of(cls, response, orders):
        n = response.freq.size
        return cls(freq=response.freq, amplitude=response.amplitude,
                   hosidf_values=np.stack([response.hosidf(order) for order in orders]),
                   half_range=response.half_range.copy(), bias=response.bias.copy(),
                   peak=response.peak_acceleration.copy(), periods=np.asarray(response.periods, dtype=float).copy(),
                   change=response.change.copy(), converged=response.converged.astype(bool).copy(),
                   flags=np.asarray(response.flags, dtype=np.int64).copy(), reasons=list(response.reasons),
                   shot=np.zeros(n, dtype=bool), states=tuple(values.copy() for values in response.end_states),
                   stability=[""] * n, multiplier=np.full(n, np.nan, dtype=complex))

    def take_orbit(self, index, orbit, row, orders):
        """Point ``index`` settled by shooting: ``orbit.*[row]``, a stable orbit."""
        for slot, order in enumerate(orders):
            self.hosidf_values[slot, index] = orbit.hosidf(order)[row]
        self.half_range[index] = orbit.half_range[row, 0]
        self.bias[index] = orbit.deflection_coefficients[row, 0].real
        self.peak[index] = orbit.peak_acceleration[row]
        self.change[index] = orbit.residual[row]
        self.converged[index] = True
        self.shot[index] = True
        self.reasons[index] = "ok"
        self.stability[index] = "period-2" if orbit.periods == 2 else "stable"
        self.multiplier[index] = _leading(orbit.multipliers[row], stability_margin(orbit.residual[row]))

    def take_runs(self, indices, runs, orders, *, continued=False):
        """Points ``indices`` run again (``runs``, one row each; ``continued``: from where they were,
        so the periods add up); settled rows replace them. Returns the rows that settled."""
        settled = np.asarray(runs.converged, dtype=bool) & (np.asarray(runs.flags) == 0)
        for row, index in enumerate(indices):
            self.periods[index] = runs.periods[row] + (self.periods[index] if continued else 0)
            self.flags[index] = runs.flags[row]
            if not settled[row]:
                self.reasons[index] = f"{self.reasons[index]}; then {runs.reasons[row]}"
                continue
            for slot, order in enumerate(orders):
                self.hosidf_values[slot, index] = runs.hosidf(order)[row]
            self.half_range[index] = runs.half_range[row]
            self.bias[index] = runs.bias[row]
            self.peak[index] = runs.peak_acceleration[row]
            self.change[index] = runs.change[row]
            self.converged[index] = True
            self.reasons[index] = "ok"
            for kept, values in zip(self.states, runs.end_states):
                kept[index] = values[row]
        return settled


def _leading(multipliers, margin):
    """The multiplier of largest modulus other than the friction-memory ones at +1 (NaN if none)."""
    return complex(leading_multipliers(np.asarray(multipliers)[None, :], margin)[0])


def confirm_early_stops(system, one, points: MapPoints, steps, orders, tolerance, workers, executor, cap):
    """Check the points whose time runs stopped before :data:`RATIO_PERIODS` periods.

    Their window test stopped on one window change below the tolerance, without a measured ratio
    for its extrapolation. Each is classified here, one period with the propagated Jacobian from its
    end state ``x`` (the classification :func:`settle_stability` needs anyway, kept for it), and the
    Newton step to its orbit, ``(J - I)^-1 (Phi(x) - x)`` with friction memory kept as
    :func:`_newton_batch` keeps it, estimates the distance left; every state component in units of its
    scale and carried to the top's first harmonic (times ``max(1, L / |X1|)``), it must be within
    ``tolerance``, the test Newton's points pass. A point that fails runs on from ``Phi(x)`` (its
    period counted) with three windows at least, up to ``cap`` periods in all; one that does not settle
    then is left to Newton and shooting like the runs that reach the cap.
    """
    early = np.flatnonzero(points.converged & (points.flags == 0) & (points.periods < RATIO_PERIODS))
    if not early.size:
        return
    freq, amplitude = points.freq[early], points.amplitude[early]
    states = one.pack(*(values[early] for values in points.states))
    _, multipliers, jacobians, flags, ends = monodromy(one, freq, amplitude, states, steps[early], workers=workers,
                                                       with_ends=True)
    length = np.maximum(amplitude, np.max(np.abs(states[:, :one.ndof]), axis=1))  # as monodromy scales
    scale = one.scales(freq, amplitude, length)
    good = np.flatnonzero((flags == FLAG_OK) & np.isfinite(ends).all(axis=1))
    error = np.full(early.size, np.inf)
    if good.size:
        memory = (np.abs(multipliers[good] - 1.0) <= STABILITY_MARGIN).sum(axis=1)
        step, _ = newton_steps(jacobians[good], (ends[good] - states[good]) / scale[good], None, memory,
                               one.conserved_gradients(scale[good]))
        first = np.abs(points.hosidf_values[list(orders).index(1.0), early[good]]) * amplitude[good]
        error[good] = np.max(np.abs(step), axis=1) * np.maximum(1.0, length[good] / np.maximum(first, 1e-300))
    accepted = error <= tolerance
    for row in np.flatnonzero(accepted):
        points.classified[early[row]] = (multipliers[row], jacobians[row])
    again = np.flatnonzero(~accepted)
    if not again.size:
        return
    indices = early[again]
    moved = np.isin(again, good)  # run on from Phi(x), one period on
    starts = np.where(moved[:, None], ends[again], states[again])
    for row, index in zip(again, indices):
        points.converged[index] = False
        points.reasons[index] = (f"the window test stopped after {points.periods[index]:g} periods, but the "
                                 f"distance to its orbit was {error[row]:.3g}")
    points.periods[indices] += moved
    runs = harmonic_response(system, freq[again], amplitude[again], n_harmonics=len(orders) - 1, tolerance=tolerance,
                             steps_per_period=steps[indices], min_periods=RATIO_PERIODS,
                             max_periods=max(RATIO_PERIODS, int(cap) - RATIO_PERIODS), workers=workers,
                             executor=executor, start=one.unpack(starts))
    points.take_runs(indices, runs, orders, continued=True)
    for row, index in enumerate(indices):  # Newton and shooting go on from where the run is
        if runs.flags[row] == FLAG_OK:
            for kept, values in zip(points.states, runs.end_states):
                kept[index] = values[row]


def settle_stability(system, points: MapPoints, steps, orders, tolerance, workers):
    """Classify the orbit of every point the time runs settled; carry the unstable ones to the stable
    orbit a longer run reaches from them (module docstring). Points shot are classified already."""
    one = PeriodMap(system, 1)
    margin = stability_margin()
    timed = np.flatnonzero(points.converged & (points.flags == 0) & ~points.shot)
    if not timed.size:
        return
    states = one.pack(*(values[timed] for values in points.states))
    multipliers = np.full((timed.size, one.size), np.nan, dtype=complex)
    flags = np.zeros(timed.size, dtype=np.int64)
    known = np.array([index in points.classified for index in timed], dtype=bool)
    if known.any():  # classified when its early stop was confirmed, same end state
        multipliers[known] = [points.classified[index][0] for index in timed[known]]
    fresh = np.flatnonzero(~known)
    fresh_jacobians = None
    if fresh.size:
        _, multipliers[fresh], fresh_jacobians, flags[fresh] = monodromy(
            one, points.freq[timed[fresh]], points.amplitude[timed[fresh]], states[fresh], steps[timed[fresh]],
            workers=workers)
    for index, flag in zip(timed[flags != 0], flags[flags != 0]):
        # one period more from a valid end state: not expected, but not hidden
        points.converged[index] = False
        points.reasons[index] = f"stability not classified: one more period flagged ({FLAG_REASONS[int(flag)]})"
    rows = np.flatnonzero(flags == 0)
    stable, kinds = classify_multiplier_rows(multipliers[rows], margin)
    points.multiplier[timed[rows]] = leading_multipliers(multipliers[rows], margin)
    unstable = []
    for row, index, kind, settled in zip(rows, timed[rows], kinds, stable | (kinds == "neutral")):
        if settled:
            points.stability[index] = str(kind)
        else:
            unstable.append((row, index, str(kind)))
    if unstable:  # the monodromy matrices of the unstable rows (scaled), for their eigenvectors
        jacobians = {row: (points.classified[timed[row]][1] if known[row]
                           else fresh_jacobians[np.searchsorted(fresh, row)]) for row, _, _ in unstable}
        _carry(system, one, points, steps, orders, tolerance, workers, states, multipliers, jacobians, unstable)


def _carry(system, one, points, steps, orders, tolerance, workers, states, multipliers, jacobians, unstable):
    """Push each unstable orbit along its most unstable eigenvector and run on until the push has
    grown to the orbit's scale and the run settles again; classify what it reached over two
    periods (a period-1 or a period-2 orbit)."""
    rows = np.array([row for row, _, _ in unstable])
    indices = np.array([index for _, index, _ in unstable])
    freq, amplitude = points.freq[indices], points.amplitude[indices]
    length = np.maximum(amplitude, np.max(np.abs(states[rows, :one.ndof]), axis=1))
    scale = one.scales(freq, amplitude, length)
    pushed = np.empty((rows.size, one.size))
    growth_periods = np.empty(rows.size)
    for k, row in enumerate(rows):
        values, vectors = np.linalg.eig(jacobians[row])
        direction = vectors[:, int(np.argmax(np.abs(values)))].real
        direction = direction / np.max(np.abs(direction))
        growth = float(np.abs(multipliers[row][0]))
        size = max(CARRY_PUSH, growth ** -CARRY_PERIODS)
        pushed[k] = one.push(states[row], size * direction[:2 * one.ndof] * scale[k, :2 * one.ndof])
        growth_periods[k] = np.log(1.0 / size) / np.log(growth)
    min_periods = int(min(CARRY_PERIODS, 2 * np.ceil(np.max(growth_periods) / 2)))
    runs = harmonic_response(system, freq, amplitude, n_harmonics=len(orders) - 1, tolerance=tolerance,
                             steps_per_period=steps[indices], min_periods=max(8, min_periods),
                             max_periods=min_periods + SHOOTING_AFTER_PERIODS, workers=workers,
                             start=one.unpack(pushed))
    was = [(kind, multipliers[row][0]) for row, _, kind in unstable]
    for index in indices:  # what the point showed is replaced, or it is no longer settled
        points.converged[index] = False
    settled = points.take_runs(indices, runs, orders, continued=True)
    # a run that has not settled yet (lightly damped) is in the basin of what it will reach:
    # shooting closes that orbit, of two periods where the 1/2 subharmonic has grown
    for k in np.flatnonzero(~settled & (np.asarray(runs.flags) == 0)):
        end = one.pack(*(values[k:k + 1] for values in runs.end_states))
        doubled = np.abs(runs.harmonic(0.5)[k]) > SUBHARMONIC_TOLERANCES * tolerance * np.abs(runs.harmonic(1)[k])
        for periods in ((2,) if doubled else (1, 2)):  # back on the unstable period-1 orbit: the other
            orbit = periodic_response(system, freq[k], amplitude[k], periods=periods, initial_states=end,
                                      settle_periods=0, steps_per_period=steps[indices[k]],
                                      n_harmonics=len(orders) - 1, seek_stable=False)
            doubled = periods == 2
            if orbit.converged[0] and orbit.stable[0]:
                break
        if orbit.converged[0]:
            points.take_orbit(indices[k], orbit, 0, orders)
            if not orbit.stable[0]:
                points.converged[indices[k]] = False
                points.stability[indices[k]] = "unstable"
                points.reasons[indices[k]] = (f"the orbit it settled on first was unstable ({was[k][0]}, multiplier "
                                              f"{_format(was[k][1])}); the orbit shot from a run on from it is "
                                              f"{orbit.instability[0]} too")
            else:
                points.stability[indices[k]] = "period-2" if doubled else "jumped"
                points.reasons[indices[k]] = "ok"
    two = PeriodMap(system, 2)
    margin = stability_margin()
    reached = np.flatnonzero(settled)
    if reached.size:
        ends = two.pack(*(values[indices[reached]] for values in points.states))
        _, again, _, flags = monodromy(two, freq[reached], amplitude[reached], ends, steps[indices[reached]],
                                       workers=workers)
        _, single, _, _ = monodromy(one, freq[reached], amplitude[reached], ends, steps[indices[reached]],
                                    workers=workers)
    for k, index in enumerate(indices):
        kind, mu = was[k]
        before = f"the orbit it settled on first was unstable ({kind}, multiplier {_format(mu)})"
        if points.shot[index]:
            continue
        if not settled[k]:
            points.stability[index] = "unstable"
            points.reasons[index] = f"{before}; run on from it: {runs.reasons[k]}"
            continue
        row = int(np.flatnonzero(reached == k)[0])
        stable, now = classify_multipliers(again[row], margin) if flags[row] == 0 else (False, "not classified")
        if not (stable or now == "neutral"):
            points.converged[index] = False
            points.stability[index] = "unstable"
            points.reasons[index] = f"{before}; the orbit reached from it is {now} too"
            continue
        subharmonic = np.abs(points.hosidf_values[0, index]) / 0.5
        first = np.abs(points.hosidf_values[1, index])
        doubled = subharmonic > SUBHARMONIC_TOLERANCES * tolerance * first
        points.stability[index] = "period-2" if doubled else "jumped"
        points.multiplier[index] = _leading(again[row] if doubled else single[row], margin)
        points.reasons[index] = "ok"
        points.change[index] = runs.change[k]


def _clip_jenkin(one: PeriodMap, states):
    """``states`` (packed, modified in place) with every Jenkin force within its slip limit."""
    limits = one.arrays.jfc[one.jenkin[:, 0], one.jenkin[:, 1]]
    columns = slice(2 * one.ndof, 2 * one.ndof + limits.size)
    states[:, columns] = np.clip(states[:, columns], -limits, limits)
    return states


@dataclass
class _NewtonPoints:
    """What :func:`_newton_batch` found, one row a point: ``accepted`` points carry their orbit's
    two-period window (``response``), end state and multipliers; every point its start state and the
    periods it spent."""

    accepted: NDArray[np.bool_]
    starts: NDArray[np.float64]
    ends: NDArray[np.float64]
    multipliers: NDArray[np.complex128]
    periods: NDArray[np.float64]
    distance: NDArray[np.float64]
    coefficients: NDArray[np.complex128]
    deflection: NDArray[np.complex128]
    half_range: NDArray[np.float64]
    peak: NDArray[np.float64]

    @classmethod
    def start(cls, starts, n_harmonics):
        """Nothing found yet for points starting from ``starts`` (n, size)."""
        n, size = starts.shape
        n_coeff = 2 * n_harmonics + 1
        return cls(accepted=np.zeros(n, dtype=bool), starts=np.array(starts, dtype=float),
                   ends=np.full((n, size), np.nan), multipliers=np.full((n, size), np.nan, dtype=complex),
                   periods=np.zeros(n), distance=np.full(n, np.nan),
                   coefficients=np.full((n, n_coeff), np.nan, dtype=complex),
                   deflection=np.full((n, n_coeff), np.nan, dtype=complex), half_range=np.full(n, np.nan),
                   peak=np.full(n, np.nan))


def settle_by_newton(system, one, points, pending, steps, orders, tolerance, workers, executor):
    """Settle the ``pending`` points (time runs not settled within :data:`NEWTON_AFTER_PERIODS`) by
    Newton on the period map from their runs' end states (:func:`_newton_batch`); the stable orbits
    found replace them, classified by the same Jacobian, their periods added."""
    n = pending.size
    found = _NewtonPoints.start(one.pack(*(values[pending] for values in points.states)), len(orders) - 1)
    _newton_batch(system, one, points.freq[pending], points.amplitude[pending], steps[pending], np.arange(n), found,
                  len(orders) - 1, tolerance, workers, executor)
    points.periods[pending] += found.periods
    margin = stability_margin()
    for row in np.flatnonzero(found.accepted):
        index = pending[row]
        amplitude = points.amplitude[index]
        for slot, order in enumerate(orders):  # as HarmonicResponse.hosidf: k X_k / X_b1
            harmonic = found.coefficients[row, int(round(2 * order))]
            points.hosidf_values[slot, index] = order * harmonic / (-1j * amplitude)
        points.half_range[index] = found.half_range[row]
        points.bias[index] = found.deflection[row, 0].real
        points.peak[index] = found.peak[row]
        points.change[index] = found.distance[row]
        points.converged[index] = True
        points.reasons[index] = "ok"
        points.stability[index] = "stable"
        points.shot[index] = True
        points.multiplier[index] = _leading(found.multipliers[row], margin)
        for kept, values in zip(points.states, one.unpack(found.ends[row])):
            kept[index] = values[0]


def _newton_batch(system, one, freq, amplitude, steps, rows, found, n_harmonics, tolerance, workers, executor):
    """Points ``rows`` of ``found`` from their start states (in place): Newton iterations, each a period with
    the propagated Jacobian, until the step is within ``tolerance`` of the state scale (the last
    Jacobian is then taken within the tolerance of the orbit, as a settled time run's end state is,
    and its multipliers classify the orbit); then, for a stable orbit, a window of two plain periods
    from the Newton point for the harmonics, whose closing estimates the distance left to the orbit
    (a chord step with the same Jacobian and another window where it is not small enough)."""
    ndof = one.ndof
    x = found.starts[rows].copy()
    length = np.maximum(amplitude[rows], np.max(np.abs(x[:, :ndof]), axis=1))
    scale = one.scales(freq[rows], amplitude[rows], length)
    anchor = x.copy()
    identity = np.eye(one.size)
    jacobians = np.full((rows.size, one.size, one.size), np.nan)
    multipliers = np.full((rows.size, one.size), np.nan, dtype=complex)
    near = np.zeros(rows.size, dtype=bool)
    family = np.zeros(rows.size, dtype=bool)
    moved = np.zeros(rows.size, dtype=bool)
    valid = np.ones(rows.size, dtype=bool)
    active = np.arange(rows.size)
    for _ in range(NEWTON_TANGENT_PERIODS):
        points = rows[active]

        def tangent_period(part, points=points, states=x[active]):
            return one.run(freq[points[part]], amplitude[points[part]], states[part], steps[points[part]],
                           with_tangent=True)
        end, flags, tangents = run_chunked(tangent_period, points.size, workers=workers, executor=executor)
        found.periods[points] += 1
        good = (flags == FLAG_OK) & np.isfinite(tangents).all(axis=(1, 2))
        valid[active[~good]] = False
        active, end, tangents = active[good], end[good], tangents[good]
        if not active.size:
            break
        matrices = tangents[:, one._tangent_rows] * scale[active][:, None, :] / scale[active][:, :, None]
        values = np.linalg.eigvals(matrices)
        values = np.take_along_axis(values, np.argsort(-np.abs(values), axis=1, kind="stable"), axis=1)
        memory = (np.abs(values - 1.0) <= STABILITY_MARGIN).sum(axis=1)
        residual = (end - x[active]) / scale[active]
        step, conserved = newton_steps(matrices, residual, (x[active] - anchor[active]) / scale[active], memory,
                                       one.conserved_gradients(scale[active]))
        jacobians[active], multipliers[active] = matrices, values
        finite = np.isfinite(step).all(axis=1)
        valid[active[~finite]] = False
        step[~finite] = 0.0
        x[active] = _clip_jenkin(one, x[active] + step * scale[active])
        close = (np.max(np.abs(step), axis=1) <= tolerance) & finite
        # friction memory: the orbits are a family, and a time run's transient (slipping) picks the
        # member, which Newton (keeping the start's memory) does not follow: such a point is settled
        # here only if its start was on an orbit already (no step beyond the tolerance)
        family[active[conserved > 0]] = True
        near[active[close]] = True
        moved[active[~close]] = True
        active = active[~close & finite]
        if not active.size:
            break
    stable, _ = classify_multiplier_rows(multipliers, stability_margin())
    # coexisting orbits (friction): a long Newton step may land on one the time run from the start
    # does not reach; only an orbit within NEWTON_REACH of the start is taken
    reach = np.max(np.abs(x - anchor) / scale, axis=1) <= NEWTON_REACH
    candidates = np.flatnonzero(near & valid & stable & ~(family & moved) & reach)
    memory = (np.abs(multipliers - 1.0) <= STABILITY_MARGIN).sum(axis=1)
    for _ in range(NEWTON_WINDOWS):
        if not candidates.size:
            break
        points = rows[candidates]
        window = harmonic_response(system, freq[points], amplitude[points], n_harmonics=n_harmonics,
                                   tolerance=tolerance, steps_per_period=steps[points], min_periods=2, max_periods=2,
                                   workers=workers, executor=executor, start=one.unpack(x[candidates]))
        found.periods[points] += 2
        end = one.pack(*window.end_states)
        good = (window.flags == FLAG_OK) & np.isfinite(end).all(axis=1)
        valid[candidates[~good]] = False
        candidates, points, end = candidates[good], points[good], end[good]
        matrices = jacobians[candidates]
        closing = (end - x[candidates]) / scale[candidates]
        # distance to the orbit, (J^2 - I)^-1 (Phi^2(x) - x): friction memory kept as Newton keeps it
        gradients, conserved_rows = one.conserved_gradients(scale[candidates])
        step, _ = newton_steps(matrices, closing, None, memory[candidates], (gradients, conserved_rows))
        try:
            distance = np.linalg.solve(matrices + identity, -step[:, :, None])[:, :, 0]
        except np.linalg.LinAlgError:  # a multiplier at -1 exactly: not settled here
            break
        # every component's distance, in units of its scale, carried to the top's first harmonic
        first = np.abs(window.coefficients[good, 2])
        error = np.max(np.abs(distance), axis=1) * np.maximum(1.0, length[candidates] / np.maximum(first, 1e-300))
        settled = np.isfinite(error) & (error <= tolerance)
        chord = ~settled & ~family[candidates]  # a chord step would move a family member: left to the time run
        taken = points[settled]
        found.accepted[taken] = True
        found.ends[taken] = end[settled]
        found.multipliers[taken] = multipliers[candidates[settled]]
        found.distance[taken] = error[settled]
        found.coefficients[taken] = window.coefficients[good][settled]
        found.deflection[taken] = window.deflection_coefficients[good][settled]
        found.half_range[taken] = window.half_range[good][settled]
        found.peak[taken] = window.peak_acceleration[good][settled]
        candidates = candidates[chord]
        x[candidates] = _clip_jenkin(one, x[candidates] - distance[chord] * scale[candidates])


def _format(value: complex) -> str:
    return f"{value.real:.5g}" if abs(value.imag) <= 1e-9 * abs(value) else f"{value:.4g}"


def shoot_pending(system, freq, amplitude, steps, n_harmonics) -> list:
    """Periodic orbits of the points that did not settle, by shooting from 20 periods of the linear
    start: per point ``(PeriodicResponse, row)`` (stable or unstable: the caller carries an unstable
    one to where a time run leaves it for), or a string saying why none was found."""
    first = periodic_response(system, freq, amplitude, steps_per_period=steps, n_harmonics=n_harmonics,
                              seek_stable=False)
    outcome: list = [None] * freq.size
    for index in range(freq.size):
        if first.converged[index] and first.instability[index] == "neutral":
            outcome[index] = (f"the periodic orbit is neutral (largest multiplier {first.max_multiplier[index]:.6g}, "
                              "on the unit circle within the stability margin: undamped, it attracts nothing the "
                              "time integration could settle on)")
        elif first.converged[index]:
            outcome[index] = (first, index)
        else:
            outcome[index] = first.reasons[index]
    return outcome
