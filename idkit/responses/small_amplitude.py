"""The small-amplitude (all stuck) periodic steady state of a system under periodic random floor
records, and the rule that says when it is the nonlinear system's own (SPEC 5, thesis 8.2).

A synthesized floor record is periodic: its acceleration is a sum of lines
(:func:`line_amplitudes`). Every element stuck, each isolator is a linear spring and the masses
follow the lines through the small-amplitude transmissibility (:func:`small_amplitude_lines`).
That periodic motion is a steady state of the hysteretic system, the one a run from rest settles
into, when no Jenkin element reaches its slip force and the polynomial spring stays linear over
it (:func:`stays_stuck`, its rule :func:`stuck_at_peaks`): :func:`idkit.responses.random_response`
then answers in the frequency domain. :func:`linear_start` starts a time run on it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from idkit.errors import SimulationError
from idkit.models.iwan_modulated import lowest_slip_scale
from idkit.models.laws import hybrid_displacements, sdof_transmissibility
from idkit.signal.psd import PsdProfile, synthesize_random

__all__ = ["LINEARITY_TOLERANCE", "isolator_stuck_at", "line_amplitudes", "linear_start", "peak_deflection",
           "small_amplitude_lines", "stays_stuck", "stuck_at_peaks", "synthesized_records"]


#: largest relative nonlinearity of a polynomial spring, ``(|g2| x + |g3| x^2) / g1`` at the
#: largest small-amplitude deflection, for which ``method="auto"`` treats a run as linear
#: (the time method's own accuracy: steady state 1e-3, trapezoidal warping up to 1.3 %)
LINEARITY_TOLERANCE = 1e-3


def small_amplitude_lines(system, signals: NDArray[np.float64], rate: float):
    """Line amplitudes (one-sided, per realization) of the base displacement, the masses'
    positions and the isolators' deflections in the small-amplitude periodic steady state."""
    n_samples = signals.shape[1]
    lines = line_amplitudes(signals)
    freq = np.fft.rfftfreq(n_samples, d=1.0 / rate)[1:]
    omega = 2.0 * np.pi * freq
    base = -lines / omega**2
    masses = system.masses
    stiffness = [isolator.small_amplitude_stiffness(freq) for isolator in system.isolators]
    # an undamped system resonating exactly at a line has no bounded steady state: its lines
    # come out infinite or NaN here, and the callers say so (_unbounded_line)
    with np.errstate(divide="ignore", invalid="ignore"):
        if len(stiffness) == 1:
            positions = [sdof_transmissibility(stiffness[0], masses[0], omega) * base]
            deflections = [positions[0] - base]
        else:
            top, middle = hybrid_displacements(stiffness[0], stiffness[1], masses[0], masses[1], omega)
            positions = [top * base, middle * base]
            deflections = [positions[0] - positions[1], positions[1] - base]
    return omega, base, positions, deflections


def _unbounded_line(omega: NDArray[np.float64], deflections) -> str:
    """Why the small-amplitude steady state does not exist ("" when it does): the first line
    at which a deflection is not finite."""
    for part in deflections:
        bad = ~np.isfinite(part).all(axis=0)
        if bad.any():
            return (f"the small-amplitude (stuck) response is unbounded: the undamped stuck system resonates at "
                    f"{omega[bad][0] / (2.0 * np.pi):g} Hz, a line of the floor signal")
    return ""


_LAST_SIGNALS: dict = {}


def synthesized_records(input_psd, seed, rate: float, freq_step: float, n_realizations: int) -> NDArray[np.float64]:
    """:func:`synthesize_random`, remembering the last floor signals of a :class:`PsdProfile`.

    A study drives many systems with the same seeded floor (the transport study: ten
    systems per level); the realizations are a pure function of the profile's breakpoints,
    the seed and the grid, so the last ones are reused (read-only) when all of these match.
    """
    key = None
    if isinstance(input_psd, PsdProfile) and isinstance(seed, (int, np.integer)):
        key = (input_psd.freq.tobytes(), input_psd.level.tobytes(), int(seed), rate, freq_step, n_realizations)
        kept = _LAST_SIGNALS.get("signals")  # (key, signals): read as one pair
        if kept is not None and kept[0] == key:
            return kept[1]
    signals = synthesize_random(input_psd, seed=seed, fs=rate, freq_step=freq_step, n_realizations=n_realizations)
    if key is not None:
        signals.setflags(write=False)
        _LAST_SIGNALS["signals"] = (key, signals)
    return signals


def line_amplitudes(signals: NDArray[np.float64]) -> NDArray[np.complex128]:
    """One-sided line amplitudes of real periodic records (the DC line dropped; it is zero),
    kept with the last synthesized signals (:func:`synthesized_records`) for the next system."""
    kept = _LAST_SIGNALS.get("lines")  # (signals, lines): the pair, so no other thread's lines are taken
    if kept is not None and kept[0] is signals:
        return kept[1]
    lines = np.fft.rfft(signals, axis=1)[:, 1:] * (2.0 / signals.shape[1])
    kept = _LAST_SIGNALS.get("signals")
    if kept is not None and kept[1] is signals:
        lines.setflags(write=False)
        _LAST_SIGNALS["lines"] = (signals, lines)
    return lines


def stays_stuck(system, signals: NDArray[np.float64], rate: float) -> tuple[bool, str]:
    """Whether the small-amplitude (all stuck) periodic response is the nonlinear one.

    The small-amplitude steady state of every realization is computed line by line
    (:func:`small_amplitude_lines`) and its deflections sampled over the record. It is a
    periodic solution of the nonlinear system, and the one a run settles into, when over
    every realization and every instant each Jenkin element's force ``k_i x`` stays below
    its slip force (the smallest the slip modulation allows at that deflection) and the
    polynomial spring stays linear to :data:`LINEARITY_TOLERANCE`. Bouc-Wen parts are
    never linear.

    Returns
    -------
    (bool, str)
        The verdict and, when False, why (the first element or spring that rules it out).
    """
    omega, _, _, deflections = small_amplitude_lines(system, signals, rate)
    unbounded = _unbounded_line(omega, deflections)
    if unbounded:
        return False, unbounded
    return stuck_at_peaks(system, [peak_deflection(lines, signals.shape[1]) for lines in deflections])


def peak_deflection(lines: NDArray[np.complex128], n_samples: int) -> NDArray[np.float64]:
    """Largest ``|deflection|`` over the record of each row of one-sided line amplitudes (the DC
    line left out), sampled at ``n_samples`` points; the largest over every row of a 2-D array."""
    spectrum = np.zeros((*lines.shape[:-1], n_samples // 2 + 1), dtype=complex)
    spectrum[..., 1:lines.shape[-1] + 1] = lines * (n_samples / 2.0)
    return np.abs(np.fft.irfft(spectrum, n=n_samples, axis=-1)).max(axis=-1)


def stuck_at_peaks(system, peaks) -> tuple[bool, str]:
    """The rule of :func:`stays_stuck` given each isolator's peak small-amplitude deflection (m,
    top isolator first; an array is reduced to its largest value): every isolator stuck there
    (:func:`isolator_stuck_at`)."""
    for index, (isolator, peak) in enumerate(zip(system.isolators, peaks)):
        reason = isolator_stuck_at(isolator.kernel_arrays(), float(np.max(peak)), index)
        if reason:
            return False, reason
    return True, ""


def isolator_stuck_at(arrays, peak: float, index: int = 0) -> str:
    """Why isolator ``index`` (0 = top; ``arrays``: its ``kernel_arrays()``) of :func:`stuck_at_peaks`
    would not stay stuck at a peak small-amplitude deflection ``peak`` (m), "" when it would: every
    Jenkin element below its lowest slip force there, the spring linear to
    :data:`LINEARITY_TOLERANCE`, no Bouc-Wen part. The rule is monotone in ``peak``: stuck at a
    peak, stuck at every smaller one."""
    if not np.isfinite(peak):
        return f"isolator {index + 1}: the small-amplitude (stuck) response is unbounded"
    if arrays.boucwen[0] != 0:
        return f"isolator {index + 1} has a Bouc-Wen part"
    g1, g2, g3 = (float(v) for v in arrays.poly)
    if (g2 or g3) and not (g1 > 0 and (abs(g2) * peak + abs(g3) * peak**2) / g1 <= LINEARITY_TOLERANCE):
        return f"isolator {index + 1}: the spring is nonlinear by more than {LINEARITY_TOLERANCE:g} at {peak:.3g} m"
    friction = np.asarray(arrays.jenkin_friction, dtype=float)
    a, y_ref, b = (float(v) for v in arrays.slip_modulation)
    if (a or b) and y_ref > 0:  # the lowest slip forces over +-peak
        friction = friction * lowest_slip_scale(a, b, np.tanh(peak / y_ref))
    force = np.asarray(arrays.jenkin_stiffness, dtype=float) * peak
    if np.any(force >= friction):
        element = int(np.argmax(force / np.maximum(friction, np.finfo(float).tiny)))
        return (f"isolator {index + 1}: Jenkin element {element + 1} would slip "
                f"({force[element]:.3g} N >= {friction[element]:.3g} N at {peak:.3g} m)")
    return ""


def linear_start(system, signals: NDArray[np.float64], rate: float) -> dict[str, NDArray[np.float64]]:
    """Small-amplitude periodic steady state at t = 0 of each realization (``start="linear"``).

    The base acceleration is ``sum_k Re(a_k exp(i w_k t))`` (its real FFT); the base
    displacement lines are ``-a_k / w_k^2``, the masses' lines follow from the isolators'
    small-amplitude stiffnesses. The base of :func:`idkit.simulate.simulate` starts at
    rest, i.e. it moves as the periodic motion minus its velocity at t = 0, a rigid drift
    the masses share: their absolute initial velocities are the periodic velocities
    relative to the base.

    Returns
    -------
    dict
        ``initial_deflection`` (n_realizations, n_isolators), m, and ``initial_velocity``
        (n_realizations, n_masses), m/s, top first.
    """
    omega, base, positions, deflections = small_amplitude_lines(system, signals, rate)
    unbounded = _unbounded_line(omega, deflections)
    if unbounded:
        raise SimulationError(f"start='linear': {unbounded}; start from rest (start='rest')")
    return {
        "initial_deflection": np.column_stack([part.real.sum(axis=1) for part in deflections]),
        "initial_velocity": np.column_stack([(1j * omega * (part - base)).real.sum(axis=1)
                                             for part in positions]),
    }
