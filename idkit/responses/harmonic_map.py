"""Frequency-amplitude maps of the steady-state harmonic response (SPEC 5, thesis 3.4.1-3.4.2, 5.3).

A grid of harmonic base excitations ``x_b = A sin(2 pi f t)`` (frequency axis in Hz times
amplitude axis in m) is run to steady state by :func:`idkit.simulate.harmonic_response`,
and reduced per point to

- peak-peak/2 of the top-mass displacement and its ratio to the base amplitude,
- the higher-order sinusoidal input describing functions (HOSIDF) of orders 1/2, 1, ..., K:
  the k-th harmonic of the top velocity over the first harmonic of the base velocity,
  ``k X_k / X_b1`` (magnitude and phase; order 1 of a linear system = transmissibility),
- the bias (mean isolator deflection over the last window, m).

The points of one frequency form a chain up the amplitude axis: the first starts from
``start``, every next one from the steady state of the amplitude below it, scaled to its own
amplitude (``chained``; chains are never split between workers, so the map does not depend on
them). Steady-state criterion (the simulator's, ``docs/simulator.md``): over consecutive windows
of two excitation periods, the largest change of any Fourier coefficient relative to the
first harmonic, and its geometric extrapolation ``change r / (1 - r)``, are both below
``tolerance``, after at least ``min_periods`` (:data:`MAP_MIN_PERIODS`, two windows). A run that
stops before :data:`RATIO_PERIODS` (three windows) has no measured ratio ``r``: its point is taken
only if the Newton step to its orbit, from the classification's period with the propagated
Jacobian, is within the tolerance (else it runs on). Points that reach ``max_periods`` without meeting it (lightly damped wire ropes
far from resonance, where a 5 Hz free oscillation outlives thousands of excitation periods) are
settled by shooting: with the default cap and a propagated Jacobian, after
:data:`NEWTON_AFTER_PERIODS` by batched Newton on the period map from the runs' end states, each
iteration one period with the propagated Jacobian, until the step is within the tolerance of the
state scale; the last Jacobian classifies the orbit, and a window of two periods from the Newton
point gives its harmonics and, by its closing, the distance left (``docs/responses.md``). Points
that Newton does not settle on a stable orbit within :data:`NEWTON_REACH` of the run, and every point
with ``newton=False``, are shot one by one (:mod:`idkit.responses.periodic`: Newton on the period
map of the same integrator, from 20 periods of the linear start). Both are marked in
:attr:`HarmonicMap.shooting`. Points shooting does not close are run on to the plain grid's
4000 periods (default cap only). Points that still fail keep their last window's values,
``converged = False`` and a reason naming both attempts. Points where the model left its valid
range (negative local stiffness, non-finite state) carry a non-zero ``flag`` and a reason.

Stability: the orbit of every settled point is classified by its Floquet multipliers over one
period (:func:`idkit.responses.periodic.monodromy`: the Jacobian propagated through the steps
from the run's end state; :func:`~idkit.responses.periodic.classify_multipliers`). The window
test cannot see an instability that grows by less than the tolerance a period, so a run can
settle on an unstable orbit (Table A.1 rope, 10.65 Hz, 1.41 mm: period doubling, multiplier
-1.003). Such a point is carried to what a long run reaches: pushed along its unstable
eigenvector (:data:`CARRY_PUSH` of the state scale, more for a multiplier so close to the unit
circle that it would not grow within :data:`CARRY_PERIODS`), run until the push has grown to the
scale and then to steady state (or shot from where the run is, period 2 where the 1/2
subharmonic has grown). :attr:`HarmonicMap.stability` says which: ``stable``, ``neutral``,
``period-2``, ``jumped`` (another period-1 orbit, after a fold or a torus), or ``unstable`` (no
stable orbit reached; then not converged).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from idkit.checks import Choice, Flag, Real, Reals, Whole, accepts
from idkit.errors import SimulationError
from idkit.responses.map_settling import (
    NEWTON_AFTER_PERIODS,
    RATIO_PERIODS,
    SHOOTING_AFTER_PERIODS,
    MapPoints,
    confirm_early_stops,
    settle_by_newton,
    settle_stability,
    shoot_pending,
)
from idkit.responses.periodic import STABILITY_MARGIN, PeriodMap
from idkit.signal.harmonics import resonance_peak
from idkit.simulate import harmonic_response

__all__ = ["HarmonicMap", "harmonic_map", "MAP_MIN_PERIODS", "NEWTON_AFTER_PERIODS", "RATIO_PERIODS",
           "SHOOTING_AFTER_PERIODS"]

#: Fewest periods of a map point's time run (:func:`harmonic_map`'s ``min_periods``): two windows of two
#: periods. A run that stops before :data:`RATIO_PERIODS` (three windows, the least on which the window
#: test measures a ratio of window changes for its extrapolation) is taken only if the Newton distance
#: from its classification period is within the tolerance (:func:`confirm_early_stops`).
MAP_MIN_PERIODS = 4

#: Period cap of a map's time integration without shooting, and of the fallback run of the
#: points that shooting could not close after the default :data:`SHOOTING_AFTER_PERIODS`.
PLAIN_MAX_PERIODS = 4000


#: Stability of the orbits a settled map point may show (:attr:`HarmonicMap.stability`).
SETTLED_KINDS = ("stable", "neutral", "period-2", "jumped")


@dataclass(frozen=True)
class HarmonicMap:
    """Steady-state harmonic response over a (frequency x amplitude) grid.

    Every grid array has shape ``(n_freq, n_amp)``: rows follow :attr:`freq`, columns
    :attr:`amplitude`.

    Attributes
    ----------
    freq : ndarray, shape (n_freq,)
        Excitation frequencies, Hz.
    amplitude : ndarray, shape (n_amp,)
        Base displacement amplitudes, m.
    orders : tuple of float
        HOSIDF orders held in :attr:`hosidf_values`: 0.5, 1, 2, ..., K.
    hosidf_values : ndarray, complex, shape (n_orders, n_freq, n_amp)
        HOSIDF of each order, dimensionless (use :meth:`hosidf`).
    half_range : ndarray, shape (n_freq, n_amp)
        Peak-peak/2 of the top-mass displacement over the last window, m.
    bias : ndarray, shape (n_freq, n_amp)
        Mean deflection of the isolator stack (top mass relative to base), m.
    peak_acceleration : ndarray, shape (n_freq, n_amp)
        Largest |absolute top acceleration| over the last window, m/s^2.
    periods : ndarray, shape (n_freq, n_amp)
        Excitation periods simulated.
    change : ndarray, shape (n_freq, n_amp)
        Last window-to-window change relative to the first harmonic.
    converged : ndarray of bool, shape (n_freq, n_amp)
        Steady-state criterion met (see module docstring).
    flags : ndarray of int, shape (n_freq, n_amp)
        0 when the run stayed valid; else a simulator code, explained by :attr:`reasons`.
    reasons : ndarray of str, shape (n_freq, n_amp)
        ``"ok"`` for a valid run that reached steady state, else why not.
        Text of each point's flag ("ok" when valid).
    tolerance : float
        Steady-state tolerance used.
    shooting : ndarray of bool, shape (n_freq, n_amp)
        Points whose steady state was found by shooting after the time integration did not
        settle (their :attr:`change` is the closing error of the periodic orbit; after batched
        Newton, the distance left to it, in units of the state scale carried to the first harmonic).
    stability : ndarray of str, shape (n_freq, n_amp), optional
        Floquet stability of each settled point's orbit (module docstring): ``"stable"``,
        ``"neutral"`` (a multiplier on the unit circle within the margin: undamped),
        ``"period-2"`` (the period-1 orbit was unstable by period doubling; the point shows
        the stable orbit of two periods the run reached, with its 1/2 subharmonic),
        ``"jumped"`` (the orbit was unstable, by a fold or a torus; the point shows the
        stable period-1 orbit the run reached), ``"unstable"`` (no stable orbit was reached:
        the point is not converged) or ``""`` (not settled or flagged: not classified).
    multiplier : ndarray of complex, shape (n_freq, n_amp), optional
        Largest Floquet multiplier of the orbit shown, over its own period (two periods for
        ``"period-2"``), other than the friction-memory multipliers at +1 (NaN if none, or not
        classified). An ``"unstable"`` point's :attr:`reasons` name the multiplier of the orbit
        it left.
    """

    freq: NDArray[np.float64]
    amplitude: NDArray[np.float64]
    orders: tuple[float, ...]
    hosidf_values: NDArray[np.complex128]
    half_range: NDArray[np.float64]
    bias: NDArray[np.float64]
    peak_acceleration: NDArray[np.float64]
    periods: NDArray[np.float64]
    change: NDArray[np.float64]
    converged: NDArray[np.bool_]
    flags: NDArray[np.int64]
    reasons: NDArray[np.str_]
    tolerance: float
    shooting: NDArray[np.bool_] | None = None
    stability: NDArray[np.str_] | None = None
    multiplier: NDArray[np.complex128] | None = None

    def __post_init__(self):
        # the map's invariant: a settled point shows an orbit a long run stays on
        if self.stability is None:
            return
        settled = np.asarray(self.converged, dtype=bool) & (np.asarray(self.flags) == 0)
        kinds = np.isin(self.stability, SETTLED_KINDS)
        growing = np.abs(self.multiplier) > 1.0 + STABILITY_MARGIN
        bad = np.argwhere(settled & (~kinds | growing))
        if bad.size:
            row, column = bad[0]
            raise SimulationError(
                f"HarmonicMap: the point {self.freq[row]:g} Hz, {self.amplitude[column]:g} m is settled but its orbit "
                f"is {self.stability[row, column] or 'not classified'} (multiplier "
                f"{abs(self.multiplier[row, column]):.6g}); expected a settled point on a stable orbit "
                f"({', '.join(SETTLED_KINDS)}, every |multiplier| <= 1 + {STABILITY_MARGIN:g})")

    @property
    def shape(self) -> tuple[int, int]:
        """``(n_freq, n_amp)``."""
        return (self.freq.size, self.amplitude.size)

    @property
    def n_harmonics(self) -> int:
        """Highest harmonic order K."""
        return int(max(self.orders))

    @property
    def amplitude_ratio(self) -> NDArray[np.float64]:
        """Peak-peak/2 of the top mass over the base amplitude, ``x_m / x_b`` (thesis fig. 3.7)."""
        return self.half_range / self.amplitude[None, :]

    @property
    def valid(self) -> NDArray[np.bool_]:
        """Points that converged and stayed inside the model's valid range."""
        return self.converged & (self.flags == 0)

    @accepts(order=Real(ge=0, meaning="0.5, 1, ..., K"), error=SimulationError)
    def hosidf(self, order: float) -> NDArray[np.complex128]:
        """Complex HOSIDF of ``order`` (0.5, 1, ..., K), shape (n_freq, n_amp), dimensionless."""
        for index, held in enumerate(self.orders):
            if abs(held - order) < 1e-9:
                return self.hosidf_values[index]
        raise SimulationError(f"order: found {order!r}, expected one of {list(self.orders)}")

    def magnitude(self, order: float) -> NDArray[np.float64]:
        """``|HOSIDF|`` of ``order``, shape (n_freq, n_amp)."""
        return np.abs(self.hosidf(order))

    def phase(self, order: float, *, unwrap: bool = True) -> NDArray[np.float64]:
        """Phase of the HOSIDF of ``order`` in rad, unwrapped along frequency by default."""
        angle = np.angle(self.hosidf(order))
        return np.unwrap(angle, axis=0) if unwrap else angle

    @accepts(amplitude=Real(unit="m", gt=0), error=SimulationError)
    def amplitude_index(self, amplitude: float) -> int:
        """Index of the grid amplitude nearest (in log) to ``amplitude`` (m)."""
        return int(np.argmin(np.abs(np.log(self.amplitude / amplitude))))

    def resonance_frequency(self, order: float = 1) -> NDArray[np.float64]:
        """Frequency (Hz) of the peak of ``|HOSIDF_order|`` at every amplitude.

        The peak sample of ``log |H|`` versus ``log f`` and its two neighbours are fitted
        by a parabola (:func:`idkit.signal.harmonics.resonance_peak`); its vertex is the
        resonance. Points that did not converge or carry a flag are ignored. NaN where the
        maximum lies at an end of the frequency axis (the resonance is outside the grid).

        Returns
        -------
        ndarray, shape (n_amp,)
        """
        magnitude = np.where(self.valid, self.magnitude(order), np.nan)
        result = np.full(self.amplitude.size, np.nan)
        for column, values in enumerate(magnitude.T):
            if not np.isnan(values).all() and 0 < int(np.nanargmax(values)) < self.freq.size - 1:
                result[column] = resonance_peak(self.freq, values)[0]
        return result

    def to_dataframe(self) -> pd.DataFrame:
        """Long table: one row per (freq, amplitude, order).

        Columns: ``freq_Hz``, ``amplitude_m``, ``order``, ``magnitude`` (|HOSIDF|, -),
        ``phase_deg`` (wrapped), and per point ``half_range_m``, ``amplitude_ratio``,
        ``bias_m``, ``peak_acceleration_m_s2``, ``periods``, ``converged``, ``flag``,
        ``status``.
        """
        grid_freq, grid_amp = np.meshgrid(self.freq, self.amplitude, indexing="ij")
        point_columns = {
            "half_range [m]": self.half_range.ravel(),
            "amplitude_ratio": self.amplitude_ratio.ravel(),
            "bias [m]": self.bias.ravel(),
            "peak_acceleration [m/s^2]": self.peak_acceleration.ravel(),
            "periods": self.periods.ravel(),
            "converged": self.converged.ravel(),
            "flag": self.flags.ravel(),
            "status": self.reasons.ravel(),
            "shooting": (np.zeros(self.shape, dtype=bool) if self.shooting is None else self.shooting).ravel(),
        }
        if self.stability is not None:
            point_columns["stability"] = self.stability.ravel()
            point_columns["|mu| [-]"] = np.abs(self.multiplier).ravel()
        frames = []
        for index, order in enumerate(self.orders):
            value = self.hosidf_values[index].ravel()
            frames.append(pd.DataFrame({
                "freq [Hz]": grid_freq.ravel(), "amplitude [m]": grid_amp.ravel(), "order": order,
                "magnitude": np.abs(value), "phase [deg]": np.degrees(np.angle(value)), **point_columns,
            }))
        return pd.concat(frames, ignore_index=True)

    def report(self) -> str:
        """A few lines for people: grid, convergence, resonance per amplitude."""
        n_points = self.freq.size * self.amplitude.size
        lines = [
            f"HarmonicMap: {self.freq.size} frequencies {self.freq[0]:g}-{self.freq[-1]:g} Hz x "
            f"{self.amplitude.size} amplitudes {self.amplitude[0]:.3g}-{self.amplitude[-1]:.3g} m, "
            f"orders {', '.join(f'{o:g}' for o in self.orders)}",
            f"  steady state (tolerance {self.tolerance:g}): {int(self.converged.sum())}/{n_points} converged, "
            f"{int((self.flags != 0).sum())} flagged outside the valid range"
            + ("" if self.shooting is None else f", {int(self.shooting.sum())} settled by shooting")
            + ("" if self.stability is None else "".join(
                f", {int((self.stability == kind).sum())} {kind}" for kind in ("period-2", "jumped", "neutral")
                if (self.stability == kind).any())),
            "  amplitude [m]  resonance [Hz]  max |H1|",
        ]
        resonance = self.resonance_frequency()
        peak = np.nanmax(np.where(self.valid, self.magnitude(1), np.nan), axis=0, initial=0.0)
        for amplitude, freq, height in zip(self.amplitude, resonance, peak):
            lines.append(f"  {amplitude:13.3g}  {freq:14.4g}  {height:8.4g}")
        return "\n".join(lines)

    summary = report


@accepts(freq_axis=Reals(unit="Hz", gt=0, increasing=True), amplitude_axis=Reals(unit="m", gt=0, increasing=True),
         n_harmonics=Whole(ge=1), tolerance=Real(gt=0, meaning="a relative change"), start=Choice(("linear", "rest")),
         shooting=Flag(), chained=Flag(), newton=Flag(), error=SimulationError)
def harmonic_map(system, freq_axis: ArrayLike, amplitude_axis: ArrayLike, *, n_harmonics: int = 3,
                 tolerance: float = 1e-3, workers: int | None = None, executor=None, progress=None,
                 steps_per_period=None, max_periods: int | None = None, start: str = "linear",
                 shooting: bool = True, chained: bool = True, min_periods: int = MAP_MIN_PERIODS,
                 newton: bool = True) -> HarmonicMap:
    """Steady-state harmonic response on a frequency x amplitude grid (SPEC 5).

    Parameters
    ----------
    system : SDOFSystem or HybridSystem
        The base-excited system.
    freq_axis : array_like, shape (n_freq,)
        Excitation frequencies in Hz, strictly increasing (1-100 Hz in the thesis).
    amplitude_axis : array_like, shape (n_amp,)
        Base displacement amplitudes in m, strictly increasing.
    n_harmonics : int, default 3
        Highest harmonic K; orders 1/2, 1, ..., K are kept.
    tolerance : float, default 1e-3
        Steady-state tolerance (module docstring).
    workers : int, optional
        Threads (default: all usable cores).
    executor : Executor-like, optional
        Runs chunks of points instead of the local pool (e.g. a Dask ``Client``).
    progress : callable(done, total), optional
        Called as chunks of points finish.
    steps_per_period : int or array_like, optional
        Integration steps per period; default of :func:`idkit.simulate.default_steps_per_period`.
    start : {"linear", "rest"}, default "linear"
        Initial state of every point (:func:`idkit.simulate.harmonic_response`): the
        small-amplitude steady state (default; where the isolator stays stuck the point
        starts settled, which spares lightly damped wire ropes thousands of periods) or
        rest, as the thesis did. Both reach the same steady state within the tolerance
        where it is unique (tests compare them).
    max_periods : int, optional
        Cap on simulated periods per point; default :data:`NEWTON_AFTER_PERIODS` (48) with
        ``shooting`` and ``newton`` (where the Jacobian is propagated), :data:`SHOOTING_AFTER_PERIODS`
        (200) with ``shooting`` alone, else 4000. Shooting closes an orbit to 1e-9 in a few Newton iterations
        where a lightly damped point needs thousands of periods to meet the tolerance: on the
        Table A.1 asymmetric 50 x 30 map, 200 periods then shooting settle 1500/1500 points in
        1.6 s on 2 workers (4000 periods: 38 shot, 8.3 s on one worker) and agree with the
        4000-period map to 3.9e-4 in |H1| and |H3| (its own tolerance is 1e-3).
        With the default cap, points that shooting does not close are run on to 4000 periods.
    min_periods : int, default :data:`MAP_MIN_PERIODS` (4)
        Fewest periods a point's time run spans before the steady-state test may stop it. Four
        periods are two windows: the first is compared with nothing, so a stop there rests on one
        window change, without a measured ratio for the geometric extrapolation; such a point is
        taken only if the Newton step to its orbit from the classification's period with the
        Jacobian is within ``tolerance`` (else it runs on, three windows at least). From six
        periods (three windows) the window test alone decides. A point started from its settled
        neighbour mostly stops at four. (``harmonic_response``'s default is 8, for runs from rest.)
    shooting : bool, default True
        Settle the points that reach ``max_periods`` by shooting (module docstring); False
        leaves them unconverged, as a plain grid of time integrations.
    newton : bool, default True
        With ``shooting`` and the default cap, and a propagated Jacobian (no Bouc-Wen, no modulated
        slip limits): cap the time runs at :data:`NEWTON_AFTER_PERIODS` (48) and settle the points
        left by Newton on the period map from their runs' end states, batched, each orbit classified
        by the Jacobian of its Newton step (module docstring). False: the 200-period cap and
        per-point shooting of the points left.
    chained : bool, default True
        Start every point after the first of each frequency from the steady state of the
        amplitude below it, scaled to its own amplitude (an amplitude sweep: fewer periods a
        point); False starts every point from ``start``. Where sticking friction makes the
        orbits a family (a lightly damped rope near its stuck resonance) the start selects the
        member, so the two can differ by more than the tolerance there (Table A.1, 5.43 Hz,
        0.17-0.57 mm: |H1| up to 8 %, as long runs from rest and from the linear start do).

    Returns
    -------
    HarmonicMap

    Examples
    --------
    >>> from idkit.models import library
    >>> result = harmonic_map(library.get("system_b1_medium"), [2.0, 5.0, 20.0], [1e-4, 1e-3])
    >>> result.shape, bool(result.converged.all())
    ((3, 2), True)
    """
    capped = max_periods is None and shooting  # the 200-period cap is ours, not the caller's
    if max_periods is None:
        max_periods = SHOOTING_AFTER_PERIODS if shooting else PLAIN_MAX_PERIODS
    freq, amplitude = np.atleast_1d(freq_axis), np.atleast_1d(amplitude_axis)
    grid_freq, grid_amp = np.meshgrid(freq, amplitude, indexing="ij")
    one = PeriodMap(system, 1)
    # Newton needs the propagated Jacobian (no Bouc-Wen, no modulated slip limits)
    newton = newton and shooting and one.jacobian_method == "exact"
    # frequency-major: each frequency's amplitudes form a chain, every point starting from the
    # steady state of the amplitude below it (scaled to its own amplitude)
    response = harmonic_response(
        system, grid_freq.ravel(), grid_amp.ravel(), n_harmonics=int(n_harmonics), tolerance=tolerance,
        steps_per_period=steps_per_period, max_periods=NEWTON_AFTER_PERIODS if newton and capped else max_periods,
        progress=progress, workers=workers, executor=executor, start=start,
        chain_length=amplitude.size if chained else 1, min_periods=min_periods,
    )
    shape = grid_freq.shape
    orders = (0.5,) + tuple(float(k) for k in range(1, int(n_harmonics) + 1))
    points = MapPoints.of(response, orders)
    confirm_early_stops(system, one, points, response.steps_per_period, orders, float(tolerance), workers, executor,
                        NEWTON_AFTER_PERIODS if newton and capped else max_periods)
    pending = np.flatnonzero(~points.converged & (points.flags == 0))
    if newton and pending.size:
        settle_by_newton(system, one, points, pending, response.steps_per_period, orders, float(tolerance), workers,
                          executor)
    pending = np.flatnonzero(~points.converged & (points.flags == 0))
    if shooting and pending.size:
        shot = shoot_pending(system, response.freq[pending], response.amplitude[pending],
                              response.steps_per_period[pending], int(n_harmonics))
        for position, index in enumerate(pending):
            if shot[position] is None or isinstance(shot[position], str):
                points.reasons[index] = f"{points.reasons[index]}; shooting: {shot[position]}"
                continue
            orbit, row = shot[position]
            points.take_orbit(index, orbit, row, orders)
            if not orbit.stable[row]:  # classified and carried on with the settled points
                points.shot[index] = False
                for field, values in zip(points.states, PeriodMap(system, 1).unpack(orbit.states[row])):
                    field[index] = values[0]
        # Shooting starts from 20 periods of the linear start, not from the capped run, and its
        # Newton iteration can leave the basin of a stable orbit that more periods reach: run
        # those points on to the plain grid's cap, so that the default never settles fewer
        # points than ``shooting=False`` would.
        failed = pending[~points.converged[pending]]
        if capped and failed.size:
            longer = harmonic_response(
                system, response.freq[failed], response.amplitude[failed], n_harmonics=int(n_harmonics),
                tolerance=tolerance, steps_per_period=response.steps_per_period[failed],
                max_periods=PLAIN_MAX_PERIODS, workers=workers, executor=executor, start=start,
                min_periods=max(min_periods, RATIO_PERIODS),  # no early stop is checked after this run
            )
            points.take_runs(failed, longer, orders)
    settle_stability(system, points, response.steps_per_period, orders, float(tolerance), workers)
    return HarmonicMap(
        freq=freq, amplitude=amplitude, orders=orders,
        hosidf_values=points.hosidf_values.reshape((len(orders),) + shape),
        half_range=points.half_range.reshape(shape), bias=points.bias.reshape(shape),
        peak_acceleration=points.peak.reshape(shape), periods=points.periods.reshape(shape),
        change=points.change.reshape(shape), converged=points.converged.reshape(shape),
        flags=points.flags.reshape(shape), reasons=np.asarray(points.reasons, dtype=str).reshape(shape),
        tolerance=float(tolerance), shooting=points.shot.reshape(shape),
        stability=np.asarray(points.stability, dtype=str).reshape(shape), multiplier=points.multiplier.reshape(shape),
    )
