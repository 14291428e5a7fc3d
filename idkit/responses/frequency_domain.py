"""The batched frequency-domain screen of floor runs: the RMS ``random_response`` would return for
many alike systems, each under its own floor record, where the frequency domain gives it.

The design search evaluates thousands of (candidate, parameter draw) pairs under floor vibration;
for a linear system, or one whose small-amplitude response keeps every friction element stuck,
:func:`idkit.responses.random_vibration.random_response` returns the expected Welch estimate
(``|H|^2 S`` on the record's lines, folded and smoothed by the Hann kernel) instead of simulating.
:func:`frequency_domain_rms` computes that RMS for all of them at once and marks the others
(NaN) for the time domain; :func:`small_amplitude_transfer` gives the transfer functions it needs.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from idkit.errors import SimulationError
from idkit.models.laws import hybrid_displacements, sdof_transmissibility
from idkit.responses.random_vibration import is_linear_system
from idkit.responses.small_amplitude import isolator_stuck_at, line_amplitudes, peak_deflection

__all__ = ["frequency_domain_rms", "small_amplitude_transfer"]

def _expected_output_rms(gains: NDArray[np.float64], level: NDArray[np.float64], band: NDArray[np.bool_],
                         record: int, fs: float) -> NDArray[np.float64]:
    """The output RMS of the expected Welch estimate (:func:`~idkit.responses.random_vibration._expected_linear_response`) of each row
    of ``gains`` (``|H|^2`` on the lines of ``band``, those where ``level`` > 0); ``inf`` for a row
    that is not finite there (an undamped resonance on a line: the frequency method refuses it).

    The trapezoidal integral of the folded, Hann-smoothed spectrum in closed form, one weight per
    line (:func:`_smoothed_line_weights`): the RMS of :func:`~idkit.responses.random_vibration._hann_line_smoothing` of
    :func:`~idkit.responses.random_vibration._folded_lines` to round-off, without forming the spectrum."""
    bounded = np.isfinite(gains).all(axis=1)
    weights = _smoothed_line_weights(level.size, record)[band] * level[band]
    power = np.where(bounded[:, None], gains, 0.0) @ weights
    return np.where(bounded, np.sqrt(power * (float(fs) / record)), np.inf)


def _smoothed_line_weights(n_lines: int, record: int) -> NDArray[np.float64]:
    """Weight of each line's power in the trapezoidal integral (over bins of width 1) of the
    one-sided spectrum :func:`~idkit.responses.random_vibration._hann_line_smoothing` makes of :func:`~idkit.responses.random_vibration._folded_lines`.

    The smoothing (1/6, 2/3, 1/6) of the periodic two-sided spectrum keeps its total, which is
    the sum of the folded one-sided powers ``P``; the trapezoidal rule takes half of the first
    and last one-sided bins away: ``(4 P_0 + P_1) / 12`` at DC and ``(P_{H-1} + 4 P_H) / 12`` at
    ``H = record // 2`` for an even record (Nyquist), ``(P_{H-1} + 5 P_H) / 12`` for an odd one
    (its last bin's neighbour above is its own mirror). A line weighs one less the share of the
    bin it folds onto.
    """
    half = record // 2
    share = np.zeros(half + 1)
    share[0] += 4.0 / 12.0
    share[1] += 1.0 / 12.0
    share[half - 1] += 1.0 / 12.0
    share[half] += (4.0 if record % 2 == 0 else 5.0) / 12.0
    index = np.arange(n_lines) % record
    index = np.where(index > half, record - index, index)
    return 1.0 - share[index]


def frequency_domain_rms(systems, input_psd, signals: NDArray[np.float64], *, fs: float = 800.0,
                         freq_step: float = 0.05, oversample: int = 1, lines=None,
                         transfer=None) -> NDArray[np.float64]:
    """``random_response(method="auto", n_realizations=1).output_rms`` of many alike systems, each
    under its own floor record, where the frequency domain gives it; NaN where it takes the time
    domain.

    The batched form of :func:`random_response`'s frequency paths: a linear system (or one whose
    small-amplitude response under its record keeps every element stuck, :func:`stays_stuck`)
    gets the RMS of its expected Welch estimate (``|H|^2 S`` on the lines, folded and smoothed);
    ``inf`` when that is unbounded (an undamped resonance on a line: the frequency method
    refuses it). The stuck test's rule is :func:`~idkit.responses.small_amplitude.isolator_stuck_at`;
    each isolator's peak deflection is first bounded above by the sum of its line amplitudes and
    below by its RMS over the record (the rule is monotone in the peak, so an isolator stuck at the
    upper bound is stuck, one that slips at the lower bound slips), and only the others are
    sampled over the record. Only
    the lines where ``input_psd`` is above zero enter (the others carry no power; their
    amplitudes in a synthesized record are the FFT's round-off).

    Parameters
    ----------
    systems : sequence of SDOFSystem or HybridSystem, all alike (one kind, one number of masses)
    input_psd : PsdProfile or callable
    signals : ndarray, shape (n_systems, fs * oversample / freq_step)
        Each system's floor acceleration record (``synthesize_random`` at ``fs * oversample``).
    fs, freq_step, oversample : as :func:`random_response`
    lines : ndarray, optional
        The records' one-sided line amplitudes when the caller keeps them
        (``np.fft.rfft(signals, axis=1)[:, 1:] * 2 / n_samples``).
    transfer : (freq, top, middle), optional
        The systems' :func:`small_amplitude_transfer` at ``freq`` (Hz, increasing) when the caller
        has it (one computation for several floor profiles); used at the lines ``freq`` holds
        exactly, computed at the others.
    """
    signals = np.atleast_2d(signals)
    rate = float(fs) * int(oversample)
    n_samples = round(rate / float(freq_step))
    if signals.shape != (len(systems), n_samples):
        raise SimulationError(f"signals: found shape {signals.shape}, expected ({len(systems)}, {n_samples}): one "
                              "record per system at fs * oversample / freq_step samples")
    record = n_samples // int(oversample)
    grid = np.arange(n_samples // 2 + 1) * float(freq_step)  # the lines of _expected_linear_response
    level = np.asarray(input_psd(grid), dtype=float)
    level[0] = 0.0  # the synthesized DC and Nyquist lines are zero
    if n_samples % 2 == 0:
        level[-1] = 0.0
    band = level > 0
    masses = np.array([system.masses for system in systems])
    n_isolators = masses.shape[1]
    linear = np.array([is_linear_system(system) for system in systems])
    frequency = linear.copy()
    rms = np.full(len(systems), np.nan)
    gains = np.full((len(systems), int(band.sum())), np.nan)
    nonlinear = np.flatnonzero(~linear)
    if nonlinear.size:
        freq = np.fft.rfftfreq(n_samples, d=1.0 / rate)[1:]  # the lines of small_amplitude_lines
        keep = np.asarray(input_psd(freq), dtype=float) > 0
        amplitudes = (line_amplitudes(signals[nonlinear])[:, keep] if lines is None
                      else np.atleast_2d(lines)[np.ix_(nonlinear, keep)])
        omega = 2.0 * np.pi * freq[keep]
        base = -amplitudes / omega**2
        top, middle = _transfer_at(systems, masses, nonlinear, freq[keep], transfer)
        with np.errstate(invalid="ignore", over="ignore"):
            if n_isolators == 1:
                deflections = [top * base - base]
            else:
                deflections = [top * base - middle * base, middle * base - base]
        magnitudes = [np.abs(part) for part in deflections]
        bounds = np.column_stack([part.sum(axis=1) for part in magnitudes])
        # the record's RMS deflection (Parseval: its lines lie strictly between DC and Nyquist) is at
        # most its sampled peak; less a margin for the round-off of the sampled values
        lower = np.column_stack([np.sqrt(0.5 * (part * part).sum(axis=1)) for part in magnitudes]) * (1.0 - 1e-9)
        # per system and isolator: stuck at the upper bound (1), slipping at the lower one (-1), else
        # to be sampled (0); unbounded: slipping
        verdict = np.full(bounds.shape, -1, dtype=np.int8)
        arrays = [[isolator.kernel_arrays() for isolator in systems[index].isolators] for index in nonlinear]
        for row in range(nonlinear.size):
            if not np.isfinite(bounds[row]).all():
                continue  # unbounded: slips
            for j, isolator in enumerate(arrays[row]):
                if not isolator_stuck_at(isolator, bounds[row, j], j):
                    verdict[row, j] = 1
                elif isolator_stuck_at(isolator, lower[row, j], j):
                    verdict[row] = -1  # one isolator slips: the system does
                    break
                else:
                    verdict[row, j] = 0
        for j, part in enumerate(deflections):
            rows = np.flatnonzero(verdict[:, j] == 0)
            if rows.size:
                full = np.zeros((rows.size, freq.size), dtype=complex)
                full[:, keep] = part[rows]
                for row, peak in zip(rows, peak_deflection(full, n_samples)):
                    verdict[row, j] = -1 if isolator_stuck_at(arrays[row][j], peak, j) else 1
        frequency[nonlinear] = (verdict == 1).all(axis=1)
        if np.array_equal(freq[keep], grid[band]):  # the transfer on the band already computed: reuse it
            gains[nonlinear] = np.abs(np.where(grid[band] > 0, top, 1.0)) ** 2
    need = np.flatnonzero(frequency & np.isnan(gains).all(axis=1))
    if need.size:
        with np.errstate(divide="ignore", invalid="ignore"):
            top, _ = _transfer_at(systems, masses, need, grid[band], transfer)
        gains[need] = np.abs(np.where(grid[band] > 0, top, 1.0)) ** 2
    chosen = np.flatnonzero(frequency)
    if chosen.size:
        rms[chosen] = _expected_output_rms(gains[chosen], level, band, record, fs)
    return rms


def _transfer_at(systems, masses: NDArray[np.float64], rows: NDArray[np.int64], freq: NDArray[np.float64], given):
    """:func:`small_amplitude_transfer` of ``systems[rows]`` at ``freq``, taken from ``given`` (``(freq,
    top, middle)`` of every system, or None) when it holds exactly these frequencies."""
    if given is not None:
        known, top, middle = given
        position = np.minimum(np.searchsorted(known, freq), len(known) - 1)
        if np.array_equal(known[position], freq):
            return top[np.ix_(rows, position)], None if middle is None else middle[np.ix_(rows, position)]
    return small_amplitude_transfer([systems[i] for i in rows], masses[rows], freq)


def small_amplitude_transfer(systems, masses: NDArray[np.float64], freq: NDArray[np.float64]):
    """Top and (hybrid, else None) intermediate displacement over base displacement of alike systems
    at ``freq`` (Hz), shape (systems, freq): each system's ``transmissibility`` for all at once.
    ``masses``: the systems' ``masses`` stacked, (systems, n_masses)."""
    omega = 2.0 * np.pi * freq
    stiffness = [np.array([system.isolators[j].small_amplitude_stiffness(freq) for system in systems])
                 for j in range(masses.shape[1])]
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        if masses.shape[1] == 1:
            return sdof_transmissibility(stiffness[0], masses[:, :1], omega), None
        return hybrid_displacements(stiffness[0], stiffness[1], masses[:, :1], masses[:, 1:], omega)
