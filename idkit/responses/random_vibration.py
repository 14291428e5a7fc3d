"""Random floor vibration through an isolation system (SPEC 5, thesis 8.2).

A one-sided floor-acceleration PSD (:class:`~idkit.signal.psd.PsdProfile`: a flat level
over a band or a breakpoint table, log-log interpolated) becomes ``n_realizations`` time
signals by seeded random phases (:func:`~idkit.signal.psd.synthesize_random`: conjugate
symmetric spectrum, ``fs`` = 800 Hz, frequency step 0.05 Hz, i.e. 20 s records). Each
realization drives the base of the system (:func:`idkit.simulate.simulate` with
``base_acceleration``); the top-mass absolute acceleration is reduced to a Welch PSD (Hann
window, 2/3 overlap, averaged over segments and realizations), its RMS and cumulative RMS.

Resolution: by default one Welch segment is one whole record, so the PSD has the
resolution of the synthesized spectrum, ``freq_step`` = 0.05 Hz (thesis 8.2: five points
within the half-power band of a 5 Hz resonance down to a damping ratio of
``4 freq_step / (2 f0)`` = 0.02). The analysed span is one record plus the 2/3 overlap of
the next, so the three segments are the periodic record shifted by thirds: averaging them
cancels the cross terms that the Hann window makes between neighbouring spectral lines of
random phase. For a linear system the estimate is then free of random scatter: it is
``|H|^2 S_xx`` on the line grid smoothed by the Hann kernel (1/6, 2/3, 1/6), which widens
a resonance's half-power band ``B`` by the relative amount ``2 (freq_step / B)^2`` (1 % at
``zeta`` = 0.07 and 5 Hz). Shorter segments (``nperseg``) trade resolution for smoothing
of nonlinear responses; at 1/8 record (0.4 Hz) a 5 Hz resonance of damping ratio 0.02,
0.03 or 0.07 reads 0.09, 0.095 or 0.115 from the half-power band.

Start-up: the synthesized records are periodic (their lines are multiples of
``freq_step``), so the drive runs ``settle_records`` records (a fraction allowed) before the
analysed record (plus the overlap); the first ones let the start-from-rest transient
decay (one record = 20 s = about 7 time constants of a 5 Hz resonance with 1 % damping; use
more for lighter damping). A run still not periodic then (``settle_until``) is continued
from its exact end state by further periods of the *same* realization: this is periodic
random excitation (a random-phase multisine repeated until the transient has gone, one
period analysed, realizations averaged). The estimate is the PSD of each realization's
periodic steady state, averaged over realizations: its statistics come from the
realizations, and a settled run returns to its state after one record, which is what the
settling error measures. Continuing with fresh input of the same PSD instead would make
the drive non-periodic: the analysed window would hold part of a new transient, the
third-shifted segments would no longer cancel the Hann cross terms (the linear estimate
would gain random scatter), and no state would be expected to recur.

For linear systems the output PSD is also ``|H|^2 S_xx`` (:func:`linear_output_psd`) with
``H`` the transmissibility; for hysteretic systems that is the all-stuck (small-amplitude)
approximation, and :attr:`RandomResponse.is_linear` says which. It is more than an
approximation where the floor is quiet enough that no Jenkin element reaches its slip
force: then the all-stuck periodic steady state is a steady state of the hysteretic system
(the one a run from rest settles into, the elements never having slipped), so
``method="auto"`` checks every realization's small-amplitude deflections against the slip
forces and the spring's linearity (:func:`~idkit.responses.small_amplitude.stays_stuck`)
and, where they pass, returns the frequency-domain estimate instead of simulating
(``method="frequency (stays stuck)"``). In the transport study that is 28 of the 48 nonlinear (system, level) pairs.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from idkit.checks import Choice, Instance, Real, Reals, Whole, accepts, unchecked
from idkit.errors import SimulationError
from idkit.limits import MAX_SAMPLES
from idkit.responses.linear import LINEAR_SYSTEM
from idkit.signal.psd import (
    PsdEstimate,
    PsdProfile,
    cumulative_rms,
    rms_from_psd,
    welch_psd,
)
from idkit.responses.small_amplitude import (
    linear_start,
    stays_stuck,
    synthesized_records,
)
from idkit.simulate import simulate

__all__ = [
    "FLAT_LEVELS",
    "WELCH_OVERLAP",
    "RandomResponse",
    "flat_input_psds",
    "is_linear_system",
    "linear_output_psd",
    "random_response",
    "settle_records_for",
]

WELCH_OVERLAP = 2.0 / 3.0
"""Overlap fraction of the Welch segments (SPEC 5, thesis 8.2)."""

FLAT_LEVELS = (1e-8, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2)
"""Flat floor-acceleration levels of SPEC 5 / thesis ch. 8, (m/s^2)^2/Hz over 0.1-100 Hz."""

#: Highest frequency (Hz) of a flat input PSD: the Nyquist frequency of the smallest time step
#: idkit integrates with (:data:`idkit.limits.MIN_TIME_STEP`); a floor band above it can be
#: neither synthesized nor simulated.
MAX_PSD_FREQ = 5e8  # 0.5 / MIN_TIME_STEP, written exactly


@accepts(levels=Reals(unit="(m/s^2)^2/Hz", ge=0), f_lo=Real(unit="Hz", gt=0, le=MAX_PSD_FREQ),
         f_hi=Real(unit="Hz", gt=0, le=MAX_PSD_FREQ), error=SimulationError)
def flat_input_psds(levels: ArrayLike = FLAT_LEVELS, *, f_lo: float = 0.1,
                    f_hi: float = 100.0) -> dict[float, PsdProfile]:
    """The flat input PSDs of SPEC 5 as profiles, keyed by level in (m/s^2)^2/Hz.

    ``f_lo < f_hi`` in Hz, each > 0 and at most :data:`MAX_PSD_FREQ` (5e8 Hz); anything else
    raises :class:`~idkit.errors.SimulationError` naming the argument.

    Examples
    --------
    >>> profiles = flat_input_psds()
    >>> sorted(profiles)[0], round(profiles[1e-2].rms(), 4)
    (1e-08, 0.9995)
    """
    if not f_lo < f_hi:
        raise SimulationError(f"f_lo, f_hi: found {f_lo!r} and {f_hi!r} Hz, expected f_lo < f_hi")
    return {float(level): PsdProfile.flat(float(level), f_lo=f_lo, f_hi=f_hi) for level in np.ravel(levels)}


@accepts(system=LINEAR_SYSTEM, error=SimulationError)
def is_linear_system(system) -> bool:
    """True when every isolator is linear (no Jenkin/Bouc-Wen part, no ``g2``/``g3``)."""
    for isolator in system.isolators:
        arrays = isolator.kernel_arrays()
        if arrays.poly[1] != 0 or arrays.poly[2] != 0 or arrays.jenkin_stiffness.size or arrays.boucwen[0] != 0:
            return False
    return True


@accepts(freq=Reals(unit="Hz", ge=0, min_size=0), error=SimulationError)
def linear_output_psd(system, input_psd, freq: ArrayLike) -> NDArray[np.float64]:
    """``S_yy = |H(f)|^2 S_xx(f)`` of the top-mass acceleration, (m/s^2)^2/Hz.

    Parameters
    ----------
    system : SDOFSystem or HybridSystem
        ``H`` is its (small-amplitude) transmissibility.
    input_psd : callable
        ``S_xx(freq)`` in (m/s^2)^2/Hz, e.g. a :class:`PsdProfile`.
    freq : array_like
        Hz (0 allowed: ``H(0) = 1``). At the resonance of an undamped system ``|H|`` is
        infinite (NaN where ``S_xx`` is 0 there).
    """
    positive = np.where(freq > 0, freq, 1.0)
    with np.errstate(divide="ignore", invalid="ignore"):  # an undamped resonance: see above
        response = np.where(freq > 0, np.asarray(system.transmissibility(positive)), 1.0)
        return np.abs(response) ** 2 * np.asarray(input_psd(freq), dtype=float)


@dataclass(frozen=True)
class RandomResponse:
    """Input and output acceleration PSDs of a random-vibration simulation.

    Attributes
    ----------
    input_profile : PsdProfile or callable
        The target floor PSD.
    freq : ndarray, shape (n,)
        Welch frequencies, Hz.
    input_psd, output_psd : ndarray, shape (n,)
        Welch PSDs of the base and top-mass absolute accelerations, (m/s^2)^2/Hz.
    linear_output_psd : ndarray, shape (n,)
        ``|H|^2 S_xx`` with the target ``S_xx`` (exact for linear systems).
    is_linear : bool
    input_rms, output_rms : float
        From the Welch PSDs, m/s^2.
    n_realizations, seed, fs, freq_step, oversample, nperseg, noverlap, settle_records
        Settings (``nperseg``, ``noverlap`` in samples at ``fs``; the integration runs at ``oversample * fs``).
    flags : ndarray of int, shape (n_realizations,); reasons : tuple of str
        Kernel flags of the simulated realizations (empty for ``method="frequency"``).
    method : str
        ``"time"`` (simulated realizations) or ``"frequency"`` (the expected Welch
        estimate of a linear system, nothing simulated, ``n_realizations`` = 0).
    settling_error : ndarray, shape (n_realizations,)
        How far each analysed run is from its periodic steady state: the largest change
        of a mass's relative velocity or absolute acceleration over the analysed record
        (the drive is periodic, so a settled run returns to its state), relative to
        sqrt(2) times its RMS over the record. Empty for ``method="frequency"``.
    extra_records : ndarray of int, shape (n_realizations,)
        Records each analysed run was continued by past ``settle_records`` because it had not
        settled (``settle_until``); its analysed record is then its last one. Empty for
        ``method="frequency"``.
    settle_until : float or None
        The settling error the runs were continued to reach (None: not continued);
        :attr:`unsettled_runs` lists those that did not reach it within ``max_extra_records``.
    """

    input_profile: object
    freq: NDArray[np.float64]
    input_psd: NDArray[np.float64]
    output_psd: NDArray[np.float64]
    linear_output_psd: NDArray[np.float64]
    is_linear: bool
    input_rms: float
    output_rms: float
    n_realizations: int
    seed: int
    fs: float
    freq_step: float
    oversample: int
    nperseg: int
    noverlap: int
    settle_records: float
    flags: NDArray[np.int64]
    reasons: tuple[str, ...]
    method: str = "time"
    settling_error: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    extra_records: NDArray[np.int64] = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    settle_until: float | None = None

    @property
    def unsettled_runs(self) -> NDArray[np.int64]:
        """Analysed runs (indices into :attr:`settling_error`) whose settling error is still above
        :attr:`settle_until` after their continuation: the cap ``max_extra_records`` was reached."""
        if self.settle_until is None:
            return np.zeros(0, dtype=np.int64)
        return np.flatnonzero(np.asarray(self.settling_error) > self.settle_until)

    @property
    def input_cumulative_rms(self) -> NDArray[np.float64]:
        """Cumulative RMS of the input over :attr:`freq`, m/s^2."""
        return cumulative_rms(self.freq, self.input_psd)

    @property
    def output_cumulative_rms(self) -> NDArray[np.float64]:
        """Cumulative RMS of the output over :attr:`freq`, m/s^2."""
        return cumulative_rms(self.freq, self.output_psd)

    @property
    def linear_output_rms(self) -> float:
        """RMS of :attr:`linear_output_psd`, m/s^2."""
        return rms_from_psd(self.freq, self.linear_output_psd)

    def to_dataframe(self) -> pd.DataFrame:
        """One row per frequency with the three PSDs and both cumulative RMS."""
        return pd.DataFrame({
            "freq [Hz]": self.freq, "input_psd [(m/s^2)^2/Hz]": self.input_psd,
            "output_psd [(m/s^2)^2/Hz]": self.output_psd, "linear_output_psd [(m/s^2)^2/Hz]": self.linear_output_psd,
            "input_cumulative_rms [m/s^2]": self.input_cumulative_rms,
            "output_cumulative_rms [m/s^2]": self.output_cumulative_rms,
        })

    def report(self) -> str:
        """RMS values in one line."""
        kind = "linear" if self.is_linear else "small-amplitude"
        runs = ("frequency domain" if self.method.startswith("frequency")
                else f"{self.n_realizations} realizations, seed {self.seed}")
        text = (f"random response ({runs}): input RMS "
                f"{self.input_rms:.4g} m/s^2, output RMS {self.output_rms:.4g} m/s^2, {kind} |H|^2 S_xx RMS "
                f"{self.linear_output_rms:.4g} m/s^2")
        unsettled = self.unsettled_runs
        if unsettled.size:
            text += (f"; {unsettled.size} of {self.n_realizations} runs not settled to {self.settle_until:g} after "
                     f"{int(np.max(self.extra_records))} extra records (settling error up to "
                     f"{float(np.max(self.settling_error)):.3g})")
        return text


@accepts(system=LINEAR_SYSTEM, freq_step=Real(unit="Hz", gt=0), time_constants=Real(gt=0),
         freq_range=Reals(unit="Hz", gt=0, min_size=2, max_size=2, increasing=True),
         max_records=Real(gt=0, meaning="records"), n_points=Whole(ge=3, meaning="points of the grid"),
         error=SimulationError)
def settle_records_for(system, *, freq_step: float = 0.05, time_constants: float = 5.0,
                       freq_range: tuple[float, float] = (1.0, 20.0), max_records: float = 1.0,
                       n_points: int = 200_001) -> float:
    """Settling for :func:`random_response`: a few small-amplitude time constants, in records.

    The top-mass resonance is the highest peak of the small-amplitude ``|H|^2`` over
    ``freq_range`` (a grid of ``n_points``, 2e5 by default); its half-power band gives ``zeta``, the time
    constant is ``tau = 1 / (zeta 2 pi f0)`` and the settling ``time_constants * tau``
    (a start-up transient left at ``exp(-5)`` = 0.7 % by default), in records of
    ``1 / freq_step``, at most ``max_records``. An undamped small-amplitude system (a
    stuck wire rope) gets ``max_records``. Slip adds damping, so larger amplitudes settle
    faster; :attr:`RandomResponse.settling_error` checks a run.

    Parameters
    ----------
    system : SDOFSystem or HybridSystem
    freq_step : float
        Line spacing of the random records, Hz (a record lasts ``1 / freq_step``).
    time_constants : float
        Settling time in time constants.
    freq_range : (float, float)
        Hz, where to look for the resonance.
    max_records : float
        Upper bound, records.
    n_points : int
        Points of the grid (its spacing bounds the half-power band it resolves: 9.5e-5 Hz by
        default; 2e4 points resolve ``zeta`` from about 0.01 at 5 Hz, below which the settling
        reaches one record anyway).

    Returns
    -------
    float
        Records to settle.

    Examples
    --------
    >>> from idkit.models import SDOFSystem, VoigtModel
    >>> mass, omega0, zeta = 15.0, 2 * np.pi * 5.0, 0.07
    >>> system = SDOFSystem(mass, VoigtModel(k=mass * omega0**2, damping=2 * zeta * mass * omega0))
    >>> round(settle_records_for(system), 3)  # 5 / (0.0707 * 2 pi 5 Hz) = 2.25 s of 20 s
    0.113
    """
    freq = np.linspace(float(freq_range[0]), float(freq_range[1]), n_points)
    gain = np.abs(np.asarray(system.transmissibility(freq))) ** 2
    peak = int(np.argmax(gain))
    half = 0.5 * gain[peak]
    below = np.nonzero(gain[:peak] <= half)[0]
    above = np.nonzero(gain[peak:] <= half)[0]
    if not (np.isfinite(half) and below.size and above.size):
        return float(max_records)
    width = freq[peak + above[0]] - freq[below[-1]]
    zeta = width / (2.0 * freq[peak])
    if not zeta > 0:
        return float(max_records)
    tau = 1.0 / (zeta * 2.0 * np.pi * freq[peak])
    return float(min(max_records, time_constants * tau * freq_step))


def _folded_lines(level: NDArray[np.float64], record: int) -> NDArray[np.float64]:
    """One-sided line powers of a record resampled (no filter) to ``record`` samples.

    ``level[..., k]`` belongs to line ``k`` of the synthesized spectrum (any length); line ``k``
    lands on line ``k mod record`` of the resampled record, mirrored above ``record / 2``.
    """
    index = np.arange(level.shape[-1]) % record
    index = np.where(index > record // 2, record - index, index)
    if level.ndim == 1:
        return np.bincount(index, weights=level, minlength=record // 2 + 1)
    rows = level.reshape(-1, level.shape[-1])
    folded = np.array([np.bincount(index, weights=row, minlength=record // 2 + 1) for row in rows])
    return folded.reshape(*level.shape[:-1], record // 2 + 1)


def _hann_line_smoothing(power: NDArray[np.float64], record: int) -> NDArray[np.float64]:
    """Expected one-sided Hann periodogram of a periodic record with these line powers (last axis).

    Averaged over the three third-shifted segments the cross terms vanish, and each bin
    gets (1/6, 2/3, 1/6) of the two-sided line powers around it; one-sided bins double
    them except DC and (even ``record``) Nyquist.
    """
    half = record // 2
    two_sided = np.zeros((*power.shape[:-1], record))
    two_sided[..., :half + 1] = power / 2.0
    two_sided[..., 0] = power[..., 0]
    if record % 2 == 0:
        two_sided[..., half] = power[..., half]
    two_sided[..., half + 1:] = two_sided[..., 1:record - half][..., ::-1]  # negative lines mirror positive ones
    smoothed = (np.roll(two_sided, 1, axis=-1) + 4.0 * two_sided + np.roll(two_sided, -1, axis=-1)) / 6.0
    one_sided = smoothed[..., :half + 1].copy()
    one_sided[..., 1:] *= 2.0
    if record % 2 == 0:
        one_sided[..., half] /= 2.0
    return one_sided


def _expected_linear_response(system, input_psd, *, seed, fs, freq_step, oversample,
                              settle_records) -> RandomResponse:
    """What the time method estimates for a linear system, computed in the frequency domain."""
    rate = fs * oversample
    ratio = rate / freq_step
    n_samples = round(ratio)
    if abs(ratio - n_samples) > 1e-9 * ratio or n_samples % oversample or n_samples < 4 * oversample:
        raise SimulationError(f"fs * oversample / freq_step must be a whole number of samples, a "
                              f"multiple of oversample; found {rate:g} / {freq_step:g} = {ratio:.6g}")
    record = n_samples // oversample
    lines = np.arange(n_samples // 2 + 1) * freq_step
    level = np.asarray(input_psd(lines), dtype=float)
    if level.shape != lines.shape or not np.all(np.isfinite(level) & (level >= 0)):
        raise SimulationError(f"input_psd(freq) must return finite levels >= 0 of the shape of freq; "
                              f"found shape {level.shape}")
    level[0] = 0.0  # the synthesized DC and Nyquist lines are zero
    if n_samples % 2 == 0:
        level[-1] = 0.0
    with np.errstate(divide="ignore", invalid="ignore"):  # an undamped resonance on a line: below
        gain = linear_output_psd(system, lambda f: np.ones_like(f), lines)
    unbounded = ~np.isfinite(gain) & (level > 0)
    if unbounded.any():
        raise SimulationError(f"the linear system's response is unbounded: it is undamped and resonates at "
                              f"{lines[unbounded][0]:g} Hz, a line of the floor signal (freq_step {freq_step:g} Hz); "
                              "give an isolator damping or simulate in time (method='time')")
    input_level = _hann_line_smoothing(_folded_lines(level, record), record)
    output_level = _hann_line_smoothing(_folded_lines(gain * level, record), record)
    freq = np.arange(record // 2 + 1) * (fs / record)
    return RandomResponse(
        input_profile=input_psd, freq=freq, input_psd=input_level, output_psd=output_level,
        linear_output_psd=linear_output_psd(system, input_psd, freq), is_linear=True,
        input_rms=rms_from_psd(freq, input_level), output_rms=rms_from_psd(freq, output_level),
        n_realizations=0, seed=int(seed), fs=fs, freq_step=freq_step, oversample=oversample,
        nperseg=record, noverlap=round(WELCH_OVERLAP * record), settle_records=settle_records,
        flags=np.zeros(0, dtype=np.int64), reasons=(), method="frequency",
    )


def _settling_error(velocity: NDArray[np.float64], acceleration: NDArray[np.float64], start,
                    record: int) -> NDArray[np.float64]:
    """Per run: largest change of a relative velocity or absolute acceleration over one record,
    relative to sqrt(2) times its RMS over the record (0 for a run in its periodic steady state;
    deflections are left out: a slow creep of the set point barely touches the PSD). ``start``:
    the first analysed sample, one for all runs or one per run."""
    starts = np.broadcast_to(np.asarray(start, dtype=np.int64), (velocity.shape[0],))
    worst = np.zeros(velocity.shape[0])
    for first in np.unique(starts):
        runs = starts == first
        for values in (velocity[runs], acceleration[runs]):
            span = values[:, :, first + 1:first + record + 1]
            # one sample in: the first sample of a run carries its initial state, which need
            # not be consistent (relaxed Maxwell elements of a linear start)
            change = np.abs(values[:, :, first + record + 1] - values[:, :, first + 1])
            scale = np.sqrt(2.0) * span.std(axis=-1)
            ratio = np.divide(change, scale, out=np.zeros_like(change), where=scale > 0)
            worst[runs] = np.maximum(worst[runs], ratio.max(axis=1))
    return worst


def _continue_until_settled(system, signals, response, *, first: int, analysed: int, record: int, step: int,
                            rate: float, settle_until: float, max_extra_records: int, workers, executor):
    """Continue, record by record from their states, the runs of ``response`` whose settling
    error (:func:`_settling_error` at ``first``) is above ``settle_until``; at most
    ``max_extra_records`` records each.

    The drive is periodic with one record's period, so a run continued by ``k`` records is
    analysed ``k`` records later at the same phase of the drive (the input window is the
    same). Returns the velocity and acceleration records (runs continued fewer times than the
    longest carry NaN at the end), each run's analysed start, its extra records, flags and
    reasons (a continuation may leave the valid range).
    """
    n_runs, n_samples = signals.shape
    if record * step != n_samples:
        raise SimulationError(f"settle_until: the record ({n_samples} samples at fs * oversample) must be a whole "
                              f"number of oversample = {step} steps to be continued in phase; choose fs, "
                              "oversample and freq_step accordingly")
    velocity, acceleration = response.velocity, response.acceleration
    flags = np.asarray(response.flags, dtype=np.int64).copy()
    reasons = list(response.reasons)
    starts = np.full(n_runs, first, dtype=np.int64)
    extra = np.zeros(n_runs, dtype=np.int64)
    state = response.final_state
    ok = flags == 0
    errors = np.full(n_runs, np.inf)
    errors[ok] = _settling_error(velocity[ok], acceleration[ok], first, record)
    cut = (first + analysed) * step  # drive sample at the end of the first run
    grid = np.arange(record * step + 1) / rate
    for round_ in range(1, int(max_extra_records) + 1):
        pending = np.flatnonzero((flags == 0) & (errors > settle_until))
        if pending.size == 0:
            break
        offset = (cut + (round_ - 1) * record * step) % n_samples
        segment = np.roll(signals[pending], -offset, axis=1)
        drive = np.concatenate([segment, segment[:, :1]], axis=1)  # one record and its closing sample
        continued = unchecked(simulate)(system, grid, base_acceleration=drive, record_every=step, workers=workers,
                                        executor=executor, initial_state=state.take(pending))
        length = velocity.shape[2]
        velocity = np.concatenate([velocity, np.full(velocity.shape[:2] + (record,), np.nan)], axis=2)
        acceleration = np.concatenate([acceleration, np.full(acceleration.shape[:2] + (record,), np.nan)], axis=2)
        velocity[pending, :, length:] = continued.velocity[:, :, 1:]
        acceleration[pending, :, length:] = continued.acceleration[:, :, 1:]
        state = state.replace_runs(pending, continued.final_state)
        starts[pending] += record
        extra[pending] += 1
        for index, run in enumerate(pending):
            flags[run] = continued.flags[index]
            reasons[run] = continued.reasons[index]
        still = pending[continued.flags == 0]
        errors[pending] = np.inf
        errors[still] = _settling_error(velocity[still], acceleration[still], starts[still], record)
    return velocity, acceleration, starts, extra, flags, tuple(reasons)


@accepts(system=LINEAR_SYSTEM, n_realizations=Whole(ge=1), fs=Real(unit="Hz", gt=0), freq_step=Real(unit="Hz", gt=0),
         oversample=Whole(ge=1), settle_records=Real(ge=0, meaning="records"),
         nperseg=Whole(ge=8, optional=True, meaning="samples at fs"), method=Choice(("time", "frequency", "auto")),
         start=Choice(("rest", "linear")), settle_until=Real(gt=0, optional=True, meaning="a settling error"),
         max_extra_records=Whole(ge=0), input_psd=Instance((Callable,), what="a PsdProfile (or a callable "
                                                                         "psd(freq_Hz) in (m/s^2)^2/Hz)"),
         error=SimulationError)
def random_response(system, input_psd, *, seed: int, n_realizations: int = 30, fs: float = 800.0,
                    freq_step: float = 0.05, oversample: int = 4, settle_records: float = 1.0,
                    nperseg: int | None = None, method: str = "time", start: str = "rest",
                    settle_until: float | None = None, max_extra_records: int = 8,
                    workers: int | None = None, executor=None) -> RandomResponse:
    """Simulate the top-mass response to random floor acceleration (module docstring).

    Parameters
    ----------
    system : SDOFSystem or HybridSystem
    input_psd : PsdProfile or callable
        One-sided floor-acceleration PSD ``S_xx(freq)``, (m/s^2)^2/Hz.
    seed : int
        Seed of the random phases (required: results are reproducible).
    n_realizations : int, default 30
    fs : float, default 800
        Sample rate of the analysed signals, Hz; the PSDs cover 0 to ``fs / 2``.
    oversample : int, default 4
        Signals are synthesized and integrated at ``oversample * fs`` (step ``1 / (4 fs)``)
        with the same spectral lines. The integrator's trapezoidal frequency warping
        lowers ``|H|^2`` near 100 Hz by about ``(omega h)^2 / 3``: 12 % at 800 Hz, < 1 %
        with 4x oversampling. ``oversample=1`` reproduces the thesis's 800 Hz signals.
    freq_step : float, default 0.05
        Line spacing of the synthesized spectrum, Hz (record length ``1/freq_step``).
    settle_records : float, default 1
        Records (a fraction allowed, rounded to a sample at ``fs``) of the periodic drive
        simulated before the analysed record, which is followed by the 2/3-segment overlap
        (2.67 records simulated in all by default). A well-damped system needs only a few
        time constants ``1 / (zeta 2 pi f0)``: 0.25 record (5 s) is 5.5 of them at
        ``zeta`` = 0.035 and 5 Hz.
    nperseg : int, optional
        Welch segment length in samples at ``fs``, 8 to one record. Default: one record
        (``fs / freq_step`` samples, resolution ``freq_step``).
    method : {"time", "frequency", "auto"}, default "time"
        ``"time"`` simulates the realizations. ``"frequency"`` (linear systems, one
        record per segment) returns what the time method estimates, without simulating:
        ``|H|^2 S_xx`` on the line grid (aliased above ``fs / 2`` as the unfiltered
        resampling folds it), smoothed by the Hann line kernel (module docstring). It
        differs from the simulation only by the integrator's frequency warping (< 1.3 %
        below 100 Hz at ``oversample=4``) and the 1e-4 left of the cross-term
        cancellation. ``"auto"``: ``"frequency"`` where it applies, and also for a
        nonlinear system whose small-amplitude periodic response, checked realization by
        realization, keeps every Jenkin element stuck and its spring linear
        (:func:`stays_stuck`; the result's ``method`` is then ``"frequency (stays stuck)"``);
        else ``"time"``.
    start : {"rest", "linear"}, default "rest"
        Initial state of the simulated runs: at rest with unloaded isolators (the thesis),
        or the small-amplitude (all stuck, linearized) periodic steady state of each
        realization at t = 0 (isolator deflections and mass velocities from the line
        amplitudes and the small-amplitude stiffnesses; Jenkin forces ``k y``, Maxwell
        elements relaxed). Where the isolators stay stuck the run then starts settled, so
        ``settle_records=0`` suffices; where they slip the stuck state can be a worse
        guess than rest (the transport study's wire rope at 1e-6 (m/s^2)^2/Hz: settling
        error 6 against 0.2 from rest after one record): check :attr:`RandomResponse.settling_error`.
    settle_until : float, optional
        Continue every run whose settling error (:attr:`RandomResponse.settling_error`) is
        above this after ``settle_records``, one record at a time from its own state
        (:class:`idkit.simulate.TimeState`: the continued run is the uninterrupted one, bit
        for bit), driven by the same periodic realization, phase-continuous (module
        docstring: the estimate is that of the periodic steady state, which a fresh input
        would restart), until it is at or below it or has run ``max_extra_records`` more
        records; each run is then analysed on its last record
        (:attr:`RandomResponse.extra_records`); those still above are listed by
        :attr:`RandomResponse.unsettled_runs` and in :meth:`RandomResponse.report`. Default:
        no continuation.
    max_extra_records : int, default 8
        Cap of the continuation, records per run.
    workers, executor : see :func:`idkit.simulate.harmonic_response`.

    Returns
    -------
    RandomResponse

    Examples
    --------
    >>> from idkit.models import library
    >>> result = random_response(library.get("system_b1_medium"), PsdProfile.flat(1e-4, f_lo=0.1, f_hi=100.0),
    ...                          seed=1, n_realizations=2)
    >>> result.is_linear, round(result.input_rms, 2)
    (True, 0.1)
    """
    samples = n_realizations * fs * oversample / freq_step
    if samples > MAX_SAMPLES:
        raise SimulationError(f"n_realizations, fs, oversample, freq_step: found {n_realizations:.4g} x {fs:g} Hz x "
                              f"{oversample} / {freq_step:g} Hz = {samples:.3g} floor samples to "
                              f"synthesize, expected at most {MAX_SAMPLES:.0e} ({8 * MAX_SAMPLES / 2**20:.0f} MiB)")
    if isinstance(input_psd, PsdProfile) and input_psd.freq[-1] > fs * oversample / 2:
        raise SimulationError(
            f"input_psd: found a profile reaching {input_psd.freq[-1]:g} Hz, expected none above "
            f"oversample x fs / 2 = {oversample:g} x {fs:g} / 2 = {fs * oversample / 2:g} Hz, the Nyquist "
            "frequency of the simulated floor (the profile's band above would be cut off); raise fs")
    linear = is_linear_system(system)
    if method == "frequency" and not (linear and nperseg is None):
        raise SimulationError(
            f"method='frequency': found a {'linear' if linear else 'nonlinear'} system and "
            f"nperseg={nperseg!r}; expected a linear system (no Jenkin or Bouc-Wen part, no g2/g3) "
            "analysed one record per segment (nperseg=None)")
    if method in ("frequency", "auto") and linear and nperseg is None:
        return _expected_linear_response(system, input_psd, seed=seed, fs=float(fs),
                                         freq_step=float(freq_step), oversample=int(oversample),
                                         settle_records=float(settle_records))
    rate = float(fs) * int(oversample)
    signals = synthesized_records(input_psd, seed, rate, float(freq_step), int(n_realizations))
    if method == "auto" and nperseg is None and stays_stuck(system, signals, rate)[0]:
        # every realization's small-amplitude steady state keeps the isolators stuck: it is the
        # nonlinear system's steady state, and a linear one (module docstring)
        stuck = _expected_linear_response(system, input_psd, seed=seed, fs=float(fs), freq_step=float(freq_step),
                                          oversample=int(oversample), settle_records=float(settle_records))
        return dataclasses.replace(stuck, is_linear=False, method="frequency (stays stuck)",
                                   n_realizations=int(n_realizations))
    n_samples = signals.shape[1]
    step = int(oversample)
    record = n_samples // step  # samples of one record at fs
    segment = record if nperseg is None else nperseg
    if segment > record:
        raise SimulationError(f"nperseg: found {nperseg!r}, expected an integer in [8, {record}] "
                              f"(samples at fs = {float(fs):g} Hz; at most one record of "
                              f"1 / freq_step = {1.0 / float(freq_step):g} s)")
    segment = int(segment)
    overlap = round(WELCH_OVERLAP * segment)  # as welch_psd rounds it
    analysed = record + overlap  # one record and the overlap of the next: whole-record shifts
    first = round(float(settle_records) * record)  # first analysed sample at fs
    # periodic records: repeat the record, settle, analyse one record plus the overlap that
    # follows (any window of one record is a circular shift of it), plus one closing sample
    # so the grid has n_steps + 1 points
    total = (first + analysed) * step
    drive = np.tile(signals, (1, total // n_samples + 1))[:, :total + 1]
    time = np.arange(drive.shape[1]) / rate
    # integrate at the oversampled rate, record at fs: the analysed signals are sampled at
    # fs like the thesis's (the output above fs/2 comes only from nonlinear harmonics of an
    # input band-limited to well below fs/2, and is folded back unfiltered, as a measurement
    # without anti-alias filter would)
    initial = {} if start == "rest" else linear_start(system, signals, rate)
    response = unchecked(simulate)(system, time, base_acceleration=drive, record_every=step, workers=workers,
                                   executor=executor, **initial)
    velocity, acceleration, flags, reasons = response.velocity, response.acceleration, response.flags, response.reasons
    starts = np.full(signals.shape[0], first, dtype=np.int64)
    extra = np.zeros(signals.shape[0], dtype=np.int64)
    if settle_until is not None:
        velocity, acceleration, starts, extra, flags, reasons = _continue_until_settled(
            system, signals, response, first=first, analysed=analysed, record=record, step=step, rate=rate,
            settle_until=float(settle_until), max_extra_records=int(max_extra_records), workers=workers,
            executor=executor)
    ok = flags == 0
    if not ok.any():
        raise SimulationError(f"random_response: every realization was flagged ({reasons[0]})")
    settling = _settling_error(velocity[ok], acceleration[ok], starts[ok], record)
    top = np.stack([acceleration[run, 0, start_at:start_at + analysed]
                    for run, start_at in zip(np.flatnonzero(ok), starts[ok])])
    # the drive repeats every record: a run analysed k records later sees the same input window
    base = drive[ok][:, first * step:(first + analysed) * step:step]
    input_estimate: PsdEstimate = welch_psd(base, fs=float(fs), nperseg=segment, overlap=WELCH_OVERLAP)
    output_estimate = welch_psd(top, fs=float(fs), nperseg=segment, overlap=WELCH_OVERLAP)
    keep = input_estimate.freq <= 0.5 * fs + 1e-9
    freq = input_estimate.freq[keep]
    input_level, output_level = input_estimate.psd[keep], output_estimate.psd[keep]
    return RandomResponse(
        input_profile=input_psd, freq=freq, input_psd=input_level, output_psd=output_level,
        linear_output_psd=linear_output_psd(system, input_psd, freq), is_linear=is_linear_system(system),
        input_rms=rms_from_psd(freq, input_level), output_rms=rms_from_psd(freq, output_level),
        n_realizations=int(ok.sum()), seed=int(seed), fs=float(fs), freq_step=float(freq_step),
        oversample=int(oversample), nperseg=input_estimate.nperseg, noverlap=input_estimate.noverlap, settle_records=float(settle_records),
        flags=np.asarray(flags, dtype=np.int64), reasons=tuple(reasons),
        settling_error=settling, extra_records=extra[ok],
        settle_until=None if settle_until is None else float(settle_until),
    )
