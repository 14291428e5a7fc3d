"""Steady-state response to harmonic base displacement, for a batch of points."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.checks import Real, Whole, accepts
from idkit.errors import SimulationError
from idkit.simulate._arrays import force_scale, resolve_system, system_arrays
from idkit.simulate._kernel import FLAG_OK, FLAG_REASONS, harmonic_kernel
from idkit.simulate._parallel import CHUNK_SIZE, WORKERS, default_workers, run_chunked
from idkit.simulate._structured import structure_of
from idkit.models.laws import hybrid_displacements, sdof_transmissibility
from idkit.signal.harmonics import search_resonance

__all__ = ["HarmonicResponse", "harmonic_response", "default_steps_per_period", "small_amplitude_resonance",
           "linear_initial_state", "MAX_PERIOD_TABLE"]

#: Most entries ``(2 K + 1) x 2 n_per`` of a run's Fourier tables (one window of two periods of
#: ``n_per`` steps, cosine and sine each): 2^25, 256 MiB a table. A frequency far below the
#: system's resonance takes ``48 f_res / f`` steps a period; without this limit 1e-6 Hz asks
#: for terabytes (and 1e-20 Hz overflows the step count).
MAX_PERIOD_TABLE = 2**25
#: Most integration steps of one point (``max_periods`` x steps per period), as
#: :func:`idkit.simulate.simulate`'s limit on a time response.
MAX_POINT_STEPS = 10**8


@dataclass(frozen=True)
class HarmonicResponse:
    """Steady-state response of a batch of (frequency, amplitude) points.

    The base moves as ``x_b = A sin(2 pi f t)``. Coefficients are complex amplitudes
    ``X_m`` of the absolute top-mass displacement at ``m/2`` times the excitation
    frequency, ``x(t) = X_0 + Re sum_{m>=1} X_m exp(i m pi f t)``, from the last
    window of two periods.

    Attributes
    ----------
    freq, amplitude : (n_points,) Hz, m
    coefficients : complex (n_points, 2 K + 1), m
    deflection_coefficients : complex (n_points, 2 K + 1), m, same for the top deflection
        (top displacement relative to the base)
    half_range : (n_points,) peak-peak/2 of the top displacement, m
    peak_acceleration : (n_points,) max |top acceleration| in the last window, m/s^2
    periods : (n_points,) excitation periods simulated
    change : (n_points,) last window-to-window change relative to the first harmonic
    converged : (n_points,) bool; flags, reasons: validity of each run (``reasons`` is
        ``"ok"`` only for a valid run that reached steady state)
    steps_per_period : (n_points,)
    end_states : tuple of arrays, optional
        State after the last window (whole periods, so at the phase of t = 0), in the layout of
        :func:`linear_initial_state`: ``q, v`` (n_points, ndof), ``jforce`` (n_points, ndof, nj),
        ``mstate`` (n_points, ndof, nm), ``bwz`` (n_points, ndof); NaN for flagged points.
    """

    freq: np.ndarray
    amplitude: np.ndarray
    coefficients: np.ndarray
    deflection_coefficients: np.ndarray
    half_range: np.ndarray
    peak_acceleration: np.ndarray
    periods: np.ndarray
    change: np.ndarray
    converged: np.ndarray
    flags: np.ndarray
    reasons: tuple[str, ...]
    steps_per_period: np.ndarray
    end_states: tuple | None = None

    @property
    def n_harmonics(self) -> int:
        return (self.coefficients.shape[1] - 1) // 2

    def harmonic(self, order: float) -> np.ndarray:
        """Complex amplitude (m) of the top displacement at ``order`` x f (0, 0.5, 1, 2, ...)."""
        index = int(round(2 * order))
        if not (0 <= index < self.coefficients.shape[1]) or abs(2 * order - index) > 1e-9:
            raise SimulationError(
                f"harmonic order: found {order!r}, expected 0, 0.5, 1, ..., {self.n_harmonics}"
            )
        return self.coefficients[:, index]

    @property
    def base_first_harmonic(self) -> np.ndarray:
        """Complex amplitude of the base displacement, ``-i A`` for ``A sin``."""
        return -1j * self.amplitude

    def hosidf(self, order: float) -> np.ndarray:
        """Higher-order sinusoidal input describing function of order ``order``.

        k-th harmonic of the top velocity over the first harmonic of the base
        velocity, ``k X_k / X_b1`` (SPEC 5); for a linear system order 1 is the
        transmissibility and the others vanish.
        """
        return order * self.harmonic(order) / self.base_first_harmonic

    @property
    def bias(self) -> np.ndarray:
        """Mean of the top deflection over the last window (m); non-zero for asymmetric isolators."""
        return self.deflection_coefficients[:, 0].real

    def to_dataframe(self) -> pd.DataFrame:
        """Long-format table: one row per point and harmonic order."""
        rows = []
        orders = np.arange(self.coefficients.shape[1]) / 2
        for index, order in enumerate(orders):
            value = order * self.coefficients[:, index] / self.base_first_harmonic if order else self.bias
            rows.append(pd.DataFrame({
                "freq [Hz]": self.freq, "amplitude [m]": self.amplitude, "order": order,
                "magnitude [-]": np.abs(value) if order else value,
                "phase [rad]": np.angle(value) if order else 0.0,
                "converged": self.converged, "flag": self.flags,
            }))
        return pd.concat(rows, ignore_index=True)


#: resonances already searched, keyed by the system's kernel arrays (which fix its
#: small-amplitude transmissibility): the 2000-point search costs about 0.2 ms, twice what a
#: one-point call spends integrating (the 8-period points of bench_simulator)
_RESONANCES: dict[bytes, float] = {}
_RESONANCES_KEPT = 256


#: Band (Hz) searched by :func:`small_amplitude_resonance`; a result at either end means the
#: resonance lies at or beyond it (not located).
RESONANCE_BAND_HZ = (0.1, 5e3)

#: Points of the log grid :func:`small_amplitude_resonance` searches (a step of 0.54 %).
RESONANCE_GRID_POINTS = 2000


def small_amplitude_resonance(system, *, arrays=None) -> float:
    """Frequency (Hz) of the peak of the small-amplitude transmissibility (0.1 Hz - 5 kHz): the
    maximum of a 2000-point log grid (:func:`idkit.signal.harmonics.search_resonance`, not
    refined: within a grid step, 0.54 %, of the refined peak of
    :func:`idkit.responses.linear_resonance`).

    ``arrays``: the system's :func:`~idkit.simulate._arrays.system_arrays`, when the caller
    has them (they key the cache of searched resonances)."""
    system = resolve_system(system)
    arrays = system_arrays(system) if arrays is None else arrays
    key = b"".join(np.asarray(values, dtype=float).tobytes() + repr(np.shape(values)).encode()
                   for values in arrays.as_tuple())
    found = _RESONANCES.get(key)
    if found is None:
        found = search_resonance(lambda freq: np.abs(system.transmissibility(freq)), f_min=RESONANCE_BAND_HZ[0],
                                 f_max=RESONANCE_BAND_HZ[1], n_grid=RESONANCE_GRID_POINTS, refine=False).freq
        if len(_RESONANCES) >= _RESONANCES_KEPT:
            _RESONANCES.clear()
        _RESONANCES[key] = found
    return found


def linear_initial_state(system, freq, amplitude):
    """Small-amplitude steady state at t = 0 under base displacement ``A sin(2 pi f t)``.

    Every isolator is replaced by its small-amplitude complex stiffness (stuck Jenkin
    elements, linearized Bouc-Wen ``k1 + alpha``, Maxwell ``k*``); the complex
    amplitudes of the masses give positions and velocities at t = 0, and the internal
    states follow: Jenkin forces ``k_i y`` (clipped to ``+-Fc_i``), Maxwell elongations
    ``Re(U_i)`` with ``U_i = i w Y / (i w + rate_i)``, Bouc-Wen ``z = alpha y``.

    Returns ``q0, v0`` (n, ndof), ``jforce0`` (n, ndof, nj), ``mstate0`` (n, ndof, nm),
    ``bwz0`` (n, ndof), the arrays the harmonic kernel starts from.
    """
    system = resolve_system(system)
    arrays = system_arrays(system)
    freq = np.asarray(freq, dtype=float)
    omega = 2.0 * np.pi * freq
    base = -1j * np.asarray(amplitude, dtype=float)  # x_b = Re(X_b exp(i w t)) = A sin(w t)
    masses = arrays.masses
    stiffness = [isolator.small_amplitude_stiffness(freq) for isolator in system.isolators]
    if arrays.ndof == 1:
        top = sdof_transmissibility(stiffness[0], masses[0], omega) * base
        positions = top[:, None]
        deflections = (top - base)[:, None]
    else:
        top, middle = hybrid_displacements(stiffness[0], stiffness[1], masses[0], masses[1], omega)
        top, middle = top * base, middle * base
        positions = np.column_stack([top, middle])
        deflections = np.column_stack([top - middle, middle - base])
    q0 = positions.real
    v0 = (1j * omega[:, None] * positions).real
    y0 = deflections.real
    jforce0 = np.clip(arrays.jk[None] * y0[:, :, None], -arrays.jfc[None], arrays.jfc[None])
    response = 1j * omega[:, None, None] / (1j * omega[:, None, None] + arrays.mrate[None])
    mstate0 = (response * deflections[:, :, None]).real * (arrays.mk[None] > 0)
    bwz0 = arrays.bw[None, :, 4] * y0 * (arrays.bw[None, :, 0] != 0)
    return q0, v0, jforce0, mstate0, bwz0


def default_steps_per_period(system, freq, *, per_period: int = 128, per_resonance: int = 48,
                             arrays=None) -> np.ndarray:
    """Steps per excitation period: at least ``per_period``, and at least ``per_resonance``
    per period of the small-amplitude resonance, rounded up to an even number (``arrays``:
    as for :func:`small_amplitude_resonance`)."""
    resonance = small_amplitude_resonance(system, arrays=arrays)
    freq = np.asarray(freq, dtype=float)
    if not (np.isfinite(freq) & (freq > 0)).all():  # a negative or infinite one read as 128 steps
        raise SimulationError(f"freq: found {freq[~(np.isfinite(freq) & (freq > 0))].ravel()[0]!r} Hz, "
                              "expected positive finite frequencies")
    steps = np.maximum(per_period, np.ceil(per_resonance * resonance / freq))
    if not (steps < 2.0**62).all():  # before the cast: 1e-20 Hz would wrap to a negative count
        raise SimulationError(f"freq: found {np.min(freq):g} Hz, which takes {np.max(steps):.3g} steps per period "
                              f"({per_resonance} per period of the {resonance:.4g} Hz small-amplitude "
                              f"resonance); expected a frequency within a few decades of the resonance")
    return (2 * np.ceil(steps / 2)).astype(np.int64)


def _reasons(flags, converged, periods, change, tolerance) -> tuple[str, ...]:
    """Why each point is not a steady state ("ok" only for a valid, settled run)."""
    reasons = []
    for flag, settled, count, last in zip(flags, converged, periods, change):
        if flag != FLAG_OK:
            reasons.append(FLAG_REASONS[int(flag)])
        elif not settled:
            reasons.append(f"not settled after {int(count)} periods (window change {last:.2g}, "
                           f"tolerance {float(tolerance):g})")
        else:
            reasons.append(FLAG_REASONS[FLAG_OK])
    return tuple(reasons)


_SMALLEST_NORMAL = float(np.finfo(float).tiny)  # 2.2e-308: below it float64 keeps fewer digits


@accepts(n_harmonics=Whole(ge=1), tolerance=Real(gt=0, lt=1, meaning="a relative change"),
         min_periods=Whole(ge=1), max_periods=Whole(ge=1), workers=WORKERS, chunk_size=CHUNK_SIZE,
         chain_length=Whole(ge=1), error=SimulationError)
def harmonic_response(system, freq, amplitude, *, n_harmonics: int = 3, tolerance: float = 1e-3,
                      steps_per_period=None, min_periods: int = 8, max_periods: int = 4000,
                      progress=None, workers: int | None = None, executor=None,
                      chunk_size: int | None = None, start="rest", chain_length: int = 1) -> HarmonicResponse:
    """Run every (freq, amplitude) point of a batch to steady state.

    Parameters
    ----------
    system : SDOFSystem, HybridSystem or CoulombSpringSystem
    freq, amplitude : array_like, broadcast to (n_points,)
        Excitation frequency in Hz and base displacement amplitude in m.
    n_harmonics : int
        Highest harmonic K; orders 0, 1/2, 1, ..., K are extracted.
    tolerance : float
        Steady-state criterion: the change of every coefficient between consecutive
        two-period windows, relative to the first harmonic, and its geometric
        extrapolation (remaining change) both below ``tolerance``.
    steps_per_period : int or array_like, optional
        Default :func:`default_steps_per_period`.
    min_periods, max_periods : int
        Bounds on the simulated periods; points that hit ``max_periods`` are
        returned with ``converged = False``; ``max_periods`` times the steps per period below
        :data:`MAX_POINT_STEPS` (1e8).
    progress : callable(done, total), optional
        Called after each chunk of points (progress bars).
    workers : int, optional
        Threads running chunks of the batch (default: all usable cores).
    executor : concurrent.futures.Executor-like, optional
        Runs the chunks instead of a local thread pool (e.g. a Dask ``Client``).
    chunk_size : int, optional
        Points per chunk (default: about four chunks per worker; with ``chain_length``, rounded
        up to whole chains).
    start : {"rest", "linear"} or tuple of arrays
        Initial state: ``"rest"`` (masses at rest, isolators unloaded; the thesis) or
        ``"linear"``, the small-amplitude (all stuck, linearized) steady state at t = 0
        (:func:`linear_initial_state`). Where the isolators stay linear the run then
        starts in its steady state, which spares lightly damped systems thousands of
        transient periods; elsewhere it is only a better first guess. Or the states
        themselves, ``(q, v, jforce, mstate, bwz)`` in the layout of
        :attr:`HarmonicResponse.end_states` (one row per point).
    chain_length : int, default 1
        Points per chain: the points form consecutive chains of this length (the number of
        points must be a multiple of it), and every point of a chain after the first starts
        from the steady state the previous one ended in (a stepped sweep: a neighbour's steady
        state is a closer start than rest, and it follows a branch as an experiment does).
        Chains are never split between workers, so the result does not depend on them.

    Examples
    --------
    >>> from idkit.models import library
    >>> response = harmonic_response(library.get("system_b1_medium"), [5.0, 20.0], 1e-3)
    >>> response.converged.tolist()
    [True, True]
    """
    system = resolve_system(system)
    arrays = system_arrays(system)
    try:
        freq, amplitude = np.broadcast_arrays(np.asarray(freq, dtype=float), np.asarray(amplitude, dtype=float))
    except ValueError:
        raise SimulationError(f"freq, amplitude: found shapes {np.shape(freq)} and {np.shape(amplitude)}, "
                              "expected shapes that broadcast together") from None
    freq = np.ascontiguousarray(freq.ravel())
    amplitude = np.ascontiguousarray(amplitude.ravel())
    if freq.size == 0:
        raise SimulationError("freq, amplitude: found no points, expected at least one")
    # ndarray methods, not np.any / np.all: a one-point call spends microseconds on each wrapper
    if not ((freq > 0).all() and np.isfinite(freq).all()):
        bad = freq[~((freq > 0) & np.isfinite(freq))][:1]
        raise SimulationError(f"freq: found {bad}, expected positive finite frequencies in Hz")
    # subnormal amplitudes lose their digits in the base motion: |H1| came out inf with "ok"
    if not ((amplitude >= _SMALLEST_NORMAL).all() and np.isfinite(amplitude).all()):
        bad = amplitude[~((amplitude >= _SMALLEST_NORMAL) & np.isfinite(amplitude))][:1]
        raise SimulationError(f"amplitude: found {bad}, expected finite amplitudes >= {_SMALLEST_NORMAL:.3g} m "
                              "(positive and not subnormal)")
    with np.errstate(over="ignore"):
        base_accel = amplitude * (2 * np.pi * freq) ** 2
    if not np.isfinite(base_accel).all():  # it scales the point's convergence test (force_scale)
        worst = int(np.argmin(np.isfinite(base_accel)))
        raise SimulationError(f"freq, amplitude: found {freq[worst]:g} Hz and {amplitude[worst]:g} m, whose base "
                              f"acceleration A (2 pi f)^2 overflows; expected a finite one")
    if max_periods < min_periods:
        raise SimulationError(f"max_periods: found {max_periods}, expected a whole number >= min_periods "
                              f"({min_periods})")
    if steps_per_period is None:
        steps = default_steps_per_period(system, freq, arrays=arrays)
    else:
        given = np.asarray(steps_per_period, dtype=float)
        if not ((given >= 8).all() and (given % 2 == 0).all()):  # 128.7 is refused, never truncated
            raise SimulationError(f"steps_per_period: found {steps_per_period!r}, expected even integers >= 8")
        steps = np.broadcast_to(given.astype(np.int64), freq.shape).copy()
    n_coeff = 2 * n_harmonics + 1
    if not (steps <= MAX_PERIOD_TABLE // (2 * n_coeff)).all():  # before the kernel allocates them
        worst = int(np.argmax(steps))
        raise SimulationError(
            f"freq: found {freq[worst]:g} Hz with {steps[worst]} steps per period; with n_harmonics="
            f"{n_harmonics} a period may take at most {MAX_PERIOD_TABLE // (2 * n_coeff)} steps (its Fourier "
            f"tables would not fit in memory): expected a higher frequency, fewer steps per period or "
            f"fewer harmonics")
    if max_periods * int(steps.max()) >= MAX_POINT_STEPS:  # 1e300 ended in numpy's "int too big to convert"
        raise SimulationError(f"max_periods: found {max_periods:.4g} periods of up to {int(steps.max())} steps, "
                              f"{max_periods * int(steps.max()):.3g} steps for a point that never settles; expected "
                              f"fewer than {MAX_POINT_STEPS:.0e} (the simulator's limit, as for time responses)")
    scale = force_scale(arrays, base_accel)  # each point's own: no point loosens another's tolerance
    min_windows = max(1, int(np.ceil(min_periods / 2)))
    max_windows = max(1, int(np.ceil(max_periods / 2)))
    kernel_arrays = arrays.as_tuple()
    run_harmonic_batch = harmonic_kernel(structure_of(arrays))

    if freq.size % chain_length:
        raise SimulationError(f"chain_length: found {chain_length} for {freq.size} points, expected a divisor of "
                              "the number of points (whole chains)")
    if isinstance(start, str) and start == "rest":
        q0 = np.zeros((freq.size, arrays.ndof))
        v0 = np.zeros((freq.size, arrays.ndof))
        jforce0 = np.zeros((freq.size,) + arrays.jk.shape)
        mstate0 = np.zeros((freq.size,) + arrays.mk.shape)
        bwz0 = np.zeros((freq.size, arrays.ndof))
    elif isinstance(start, str) and start == "linear":
        q0, v0, jforce0, mstate0, bwz0 = linear_initial_state(system, freq, amplitude)
    elif isinstance(start, tuple) and len(start) == 5:
        q0, v0, jforce0, mstate0, bwz0 = (np.asarray(values, dtype=float) for values in start)
        shapes = [(freq.size, arrays.ndof)] * 2 + [(freq.size,) + arrays.jk.shape, (freq.size,) + arrays.mk.shape,
                                                   (freq.size, arrays.ndof)]
        if [values.shape for values in (q0, v0, jforce0, mstate0, bwz0)] != shapes or not all(
                np.isfinite(values).all() for values in (q0, v0, jforce0, mstate0, bwz0)):
            raise SimulationError(f"start: found states of shapes {[np.shape(v) for v in start]}, expected finite "
                                  f"arrays of shapes {shapes} (q, v, jforce, mstate, bwz)")
    else:
        raise SimulationError(f"start: found {start!r:.80}, expected 'rest', 'linear' or the states "
                              "(q, v, jforce, mstate, bwz)")
    chain = np.zeros(freq.size, dtype=np.bool_)
    chain[np.arange(freq.size) % chain_length != 0] = True
    # Deal the points out like cards so that every chunk mixes cheap and costly ones
    # (a grid in order would hand one worker all the high frequencies); chains are dealt whole.
    # (one point: nothing to deal, and no copies)
    n_chains = freq.size // chain_length
    dealt_chains = np.argsort(np.arange(n_chains) % max(1, min(n_chains, 64)), kind="stable")
    order = (np.zeros(1, dtype=np.int64) if freq.size == 1 else
             (dealt_chains[:, None] * chain_length + np.arange(chain_length)[None, :]).ravel())
    if chain_length > 1:
        workers_used = default_workers() if workers is None else workers
        chains_per_chunk = (max(1, -(-n_chains // (4 * workers_used))) if chunk_size is None
                            else -(-chunk_size // chain_length))
        chunk_size = chains_per_chunk * chain_length
    if freq.size == 1:
        dealt_freq, dealt_amplitude, dealt_steps, dealt_scale = freq, amplitude, np.ascontiguousarray(steps), scale
        dealt_states = tuple(np.ascontiguousarray(values) for values in (q0, v0, jforce0, mstate0, bwz0))
    else:
        dealt_freq, dealt_amplitude = freq[order], amplitude[order]
        dealt_steps = np.ascontiguousarray(steps[order])
        dealt_scale = scale[order]
        dealt_states = tuple(np.ascontiguousarray(values[order]) for values in (q0, v0, jforce0, mstate0, bwz0))

    def task(part: slice):
        return run_harmonic_batch(
            *kernel_arrays, dealt_freq[part], dealt_amplitude[part], dealt_steps[part], n_coeff,
            float(tolerance), min_windows, max_windows, dealt_scale[part], *(values[part] for values in dealt_states),
            chain[part],
        )

    dealt = run_chunked(task, freq.size, workers=workers, chunk_size=chunk_size, progress=progress,
                        executor=executor)
    if freq.size > 1:
        restore = np.argsort(order, kind="stable")
        dealt = tuple(field[restore] for field in dealt)
    coeff, half_range, peak, dcoeff, windows, change, converged, flags = dealt[:8]
    return HarmonicResponse(
        freq=freq, amplitude=amplitude, coefficients=coeff, deflection_coefficients=dcoeff,
        half_range=half_range, peak_acceleration=peak, periods=2 * windows, change=change,
        converged=converged, flags=flags, reasons=_reasons(flags, converged, 2 * windows, change, tolerance),
        steps_per_period=steps, end_states=tuple(dealt[8:]),
    )
