"""Shock: conditioned free-fall sweeps over impact velocity or drop height (SPEC 5, thesis 3.4.3).

The base stands still; every mass starts at the impact velocity ``v0 < 0``
(``v0 = -sqrt(2 g h)`` for a drop height ``h``, eq. 3.19) and the system is integrated by
:func:`idkit.simulate.free_fall`. Per drop:

- **rest shock level**: ``max |a_top|`` over the record, the absolute (kinematic)
  acceleration of the top mass in m/s^2 (with ``gravity`` it is 0 at rest and ``-g`` in
  flight);
- **compression / tension phase**: the samples where the top mass is below / above its
  position relative to the base at impact, i.e. where the deflection summed over the
  isolators (``x_top - x_base``, the quantity a drop rig measures; the isolator's own
  deflection in an SDOF system) is below / above its value at the start. This is the one
  reduction of :func:`idkit.signal.drop.drop_phase_peaks`, which the measured drops, the drop
  validation and ``idkit simulate drop`` use too. The peak ``|a_top|`` in each phase, and
  which phase **governs** (holds the rest shock level; thesis fig. 3.21b: compression below
  about 0.9 m/s for the asymmetric wire rope, the subsequent tension above);
- **peak travel** of the top mass relative to the base, and **peak deflection** of every
  isolator (hybrid: elastomer and wire rope separately, fig. 5.16), in compression and
  tension, measured from the deflection at impact, m, positive numbers.

Runs that leave the model's valid range (simulator flag) get NaN summary values and keep
their flag and reason.

Automatic time grid (when ``duration`` / ``time_step`` are not given), from the
small-amplitude resonance ``f0`` (:func:`idkit.simulate.small_amplitude_resonance`):
``duration = 4 / f0`` (softening or slipping lowers the frequency by up to about 2x for the
Table A.1 ropes, so the first compression and the following tension always fit), and
``time_step = 1 / max(2000 f0, 40 f_in)`` where ``f_in`` is the frequency of the
intermediate mass on both isolators' small-amplitude stiffness (hybrid only). A peak
sampled at 2000 points per period is within ``1 - cos(pi / 2000) ~ 1e-6`` of the true one.

Relaxation (``relaxation=True``, SPEC 5 validation reading): every isolator starts elongated
by the static deflection (:func:`idkit.simulate.relaxation_deflection`) under the weight of
the masses it carries (top isolator: top mass; hybrid lower isolator: top plus
intermediate mass), i.e. the spring has relaxed from its resting compression to tension
during the fall.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from idkit.gravity import gravity_acceleration, impact_velocity_from_height
from idkit.signal.drop import drop_phase_peaks
from idkit.signal.srs import ShockResponseSpectrum, shock_response_spectrum
from idkit.errors import SimulationError
from idkit.limits import MAX_IMPACT_SPEED
from idkit.checks import Choice, Flag, Real, Reals, accepts, unchecked
from idkit.responses.linear import LINEAR_SYSTEM
from idkit.models import HybridSystem
from idkit.simulate import (
    DEFAULT_CONTACT,
    STANDARD_GRAVITY,
    ContactModel,
    drop_rig,
    free_fall,
    relaxation_deflection,
    small_amplitude_resonance,
)
from idkit.simulate.harmonic import RESONANCE_BAND_HZ

__all__ = ["ShockSweep", "shock_sweep", "default_shock_grid", "NO_MOTION"]

#: Status of a conditioned drop that cannot move: no impact speed, no gravity, no initial
#: deflection. Its run is valid (flag 0) but has no compression or tension phase, so its peaks
#: are NaN (``drop_height=[0.0]`` without gravity said "ok" beside NaN peaks).
NO_MOTION = ("no motion: v0 = 0 without gravity or initial deflection, the mass stays at rest "
             "(no compression or tension phase: peaks NaN)")


def _internal_frequency(system) -> float:
    """Frequency (Hz) of the hybrid's intermediate mass between both isolators (0 for SDOF)."""
    if not isinstance(system, HybridSystem):
        return 0.0
    m_in = float(system.masses[1])
    freq = np.sqrt(system.lower.small_amplitude_stiffness(1.0).real / m_in) / (2 * np.pi)
    for _ in range(20):  # fixed point: stiffness of the elastomer grows with frequency
        stiffness = abs(system.upper.small_amplitude_stiffness(freq)) + abs(system.lower.small_amplitude_stiffness(freq))
        freq = float(np.sqrt(stiffness / m_in) / (2 * np.pi))
    return freq


def default_shock_grid(system) -> tuple[float, float]:
    """``(duration, time_step)`` in s chosen from the small-amplitude resonance (module docstring).

    The resonance is searched in :data:`idkit.simulate.harmonic.RESONANCE_BAND_HZ`; a
    transmissibility largest at an end of that band has not located it, and a grid built on
    the band's end would not follow the drop (a 1e6 kg mass on the Table B.1 elastomer, 5 mHz:
    40 s simulated, a fifth of its compression, reported "ok"). Such a system raises
    :class:`~idkit.errors.SimulationError`: give ``duration`` and ``time_step``.
    """
    f0 = small_amplitude_resonance(system)
    low, high = RESONANCE_BAND_HZ
    if not low * (1 + 1e-9) < f0 < high * (1 - 1e-9):
        raise SimulationError(
            f"the small-amplitude transmissibility is largest at {f0:g} Hz, an end of the band {low:g}-{high:g} Hz "
            "searched for the resonance (it lies beyond, or the curve has no peak), so the default duration "
            "(4 resonance periods) and time step (2000 steps a period) would not follow the drop; expected a "
            "system resonating inside the band, or a duration and time step given")
    duration = 4.0 / f0
    time_step = 1.0 / max(2000.0 * f0, 40.0 * _internal_frequency(system))
    return duration, time_step


@dataclass(frozen=True)
class ShockSweep:
    """Peak responses of a series of conditioned free falls.

    Attributes
    ----------
    impact_velocity : ndarray, shape (n,)
        ``v0`` in m/s (negative: downward).
    drop_height : ndarray, shape (n,)
        ``v0^2 / (2 g)`` in m.
    rest_shock_level : ndarray, shape (n,)
        ``max |a_top|``, m/s^2.
    peak_acceleration_compression, peak_acceleration_tension : ndarray, shape (n,)
        ``max |a_top|`` while the top mass is below / above its position at impact relative to
        the base (module docstring), m/s^2 (``nan`` for a phase that never occurs).
    governing_phase : ndarray of str, shape (n,)
        "compression" or "tension": the phase holding the rest shock level ("" if flagged).
    travel_compression, travel_tension : ndarray, shape (n,)
        Largest travel of the top mass relative to the base below / above its value at
        impact (the deflection summed over the isolators), m, >= 0.
    peak_compression, peak_tension : ndarray, shape (n, n_isolators)
        Largest compression and extension of each isolator from its deflection at impact, m
        (top isolator first), >= 0.
    isolator_names : tuple of str
        ``("isolator",)`` or ``("upper", "lower")``.
    time : ndarray, shape (n_records,)
        s.
    top_acceleration : ndarray, shape (n, n_records)
        Absolute top-mass acceleration records, m/s^2 (NaN after a flag).
    flags : ndarray of int, shape (n,); reasons : tuple of str
        Simulator validity flags and their text; a valid drop that cannot move (``v0 = 0``
        without gravity or relaxation) has flag 0 and the reason :data:`NO_MOTION`.
    duration, time_step : float
        s.
    gravity : float
        m/s^2 (0: without gravity).
    relaxation : bool
    initial_deflection : ndarray, shape (n_isolators,)
        m, positive = tension (rig: the statically loaded rest state before release).
    drop_model : str
        ``"conditioned"`` or ``"rig"`` (:func:`idkit.simulate.drop_rig`).
    lifted_off : ndarray of bool, shape (n,), or None
        Rig only: the bottom mass left the floor after the first contact.
    """

    impact_velocity: NDArray[np.float64]
    drop_height: NDArray[np.float64]
    rest_shock_level: NDArray[np.float64]
    peak_acceleration_compression: NDArray[np.float64]
    peak_acceleration_tension: NDArray[np.float64]
    governing_phase: NDArray[np.str_]
    travel_compression: NDArray[np.float64]
    travel_tension: NDArray[np.float64]
    peak_compression: NDArray[np.float64]
    peak_tension: NDArray[np.float64]
    isolator_names: tuple[str, ...]
    time: NDArray[np.float64]
    top_acceleration: NDArray[np.float64]
    flags: NDArray[np.int64]
    reasons: tuple[str, ...]
    duration: float
    time_step: float
    gravity: float
    relaxation: bool
    initial_deflection: NDArray[np.float64]
    drop_model: str = "conditioned"
    lifted_off: NDArray[np.bool_] | None = None

    @property
    def impact_speed(self) -> NDArray[np.float64]:
        """``|v0|`` in m/s."""
        return np.abs(self.impact_velocity)

    @property
    def ok(self) -> NDArray[np.bool_]:
        """Runs that stayed inside the model's valid range."""
        return self.flags == 0

    def srs(self, index: int, freq: ArrayLike, *, damping_ratio: float = 0.05) -> ShockResponseSpectrum:
        """Shock response spectrum of drop ``index``'s top-mass acceleration (:mod:`idkit.signal.srs`).

        ``freq`` in Hz must lie below half the record's sample rate ``1 / (time[1] - time[0])``.
        """
        if not (-self.flags.size <= index < self.flags.size):
            raise SimulationError(f"index: found {index}, expected one of the {self.flags.size} drops")
        if self.flags[index] != 0:
            raise SimulationError(f"drop {index}: flagged ({self.reasons[index]}); no SRS of an invalid record")
        fs = 1.0 / float(self.time[1] - self.time[0])
        return shock_response_spectrum(self.top_acceleration[index], fs=fs, freq=freq, damping_ratio=damping_ratio)

    def to_dataframe(self) -> pd.DataFrame:
        """One row per drop; unit-bearing column names."""
        columns = {
            "impact_velocity [m/s]": self.impact_velocity,
            "impact_speed [m/s]": self.impact_speed,
            "drop_height [m]": self.drop_height,
            "rest_shock_level [m/s^2]": self.rest_shock_level,
            "peak_accel_compression [m/s^2]": self.peak_acceleration_compression,
            "peak_accel_tension [m/s^2]": self.peak_acceleration_tension,
            "governing_phase": self.governing_phase,
            "travel_compression [m]": self.travel_compression,
            "travel_tension [m]": self.travel_tension,
        }
        for j, name in enumerate(self.isolator_names):
            columns[f"max_compression_{name} [m]"] = self.peak_compression[:, j]
            columns[f"max_tension_{name} [m]"] = self.peak_tension[:, j]
        columns["flag"] = self.flags
        columns["status"] = list(self.reasons)
        return pd.DataFrame(columns)

    def report(self) -> str:
        """Short text: grid, validity and the largest rest shock level."""
        ok = self.ok
        lines = [
            f"ShockSweep: {self.flags.size} drops, |v0| {self.impact_speed.min():.3g}-{self.impact_speed.max():.3g} m/s, "
            f"duration {self.duration:.3g} s, step {self.time_step:.3g} s, gravity {self.gravity:g} m/s^2, "
            f"relaxation {self.relaxation}",
            f"  {int(ok.sum())}/{ok.size} runs valid",
        ]
        if ok.any():
            best = int(np.nanargmax(np.where(ok, self.rest_shock_level, np.nan)))
            lines.append(
                f"  largest rest shock level {self.rest_shock_level[best]:.4g} m/s^2 at |v0| "
                f"{self.impact_speed[best]:.3g} m/s ({self.governing_phase[best]})"
            )
        return "\n".join(lines)


@accepts(system=LINEAR_SYSTEM, impact_velocity=Reals(unit="m/s", optional=True, meaning="drop: < 0"),
         duration=Real(unit="s", gt=0, optional=True), time_step=Real(unit="s", gt=0, optional=True),
         drop_model=Choice(("conditioned", "rig")), relaxation=Flag(), error=SimulationError)
def shock_sweep(system, *, impact_velocity: ArrayLike | None = None, drop_height: ArrayLike | None = None,
                duration: float | None = None, time_step: float | None = None, gravity: bool | float = False,
                relaxation: bool = False, workers: int | None = None, executor=None,
                drop_model: str = "conditioned", bottom_mass: float | None = None,
                contact: ContactModel | None = None) -> ShockSweep:
    """Conditioned free falls (or rig drops) of ``system`` over impact velocities or drop heights.

    With ``drop_model="rig"`` the drops are simulated by :func:`idkit.simulate.drop_rig` (the
    stack released from its statically loaded rest state onto ``bottom_mass`` on a unilateral
    floor ``contact``, default :data:`idkit.simulate.DEFAULT_CONTACT`): heights come from
    ``drop_height`` or ``v0^2 / (2 g)``; ``gravity`` and ``relaxation`` do not apply (gravity is
    on, the fall sets the state at impact); ``time_step`` default
    :func:`idkit.simulate.drop_rig.rig_time_step`. The phases are read from the first floor
    contact on, by the same rule; ``impact_velocity`` is then the bottom mass's velocity at
    the first contact.

    Parameters
    ----------
    system : SDOFSystem or HybridSystem
    impact_velocity : array_like, shape (n,), optional
        ``v0`` in m/s, negative downward (a positive value throws the mass upward, i.e.
        starts in tension: useful for symmetry checks; 0 sets the mass down without speed,
        which only moves under ``gravity`` or ``relaxation``: otherwise its status is
        :data:`NO_MOTION` and its peaks NaN). Give this or ``drop_height``.
    drop_height : array_like, shape (n,), optional
        Heights in m, ``v0 = -sqrt(2 g h)`` (:func:`idkit.gravity.impact_velocity_from_height`).
    duration, time_step : float, optional
        Simulated time and integration step in s; default :func:`default_shock_grid`.
    gravity : bool or float, default False
        Include gravity (True: 9.80665 m/s^2) - the thesis's conditioned fall has none.
    relaxation : bool, default False
        Start with every isolator elongated by its static deflection under the weight it
        carries (module docstring).
    workers, executor : see :func:`idkit.simulate.harmonic_response`.

    Returns
    -------
    ShockSweep

    Examples
    --------
    >>> from idkit.models import SDOFSystem, VoigtModel
    >>> system = SDOFSystem(1.0, VoigtModel(k=(2 * np.pi * 5.0) ** 2, damping=0.0))
    >>> sweep = shock_sweep(system, impact_velocity=[-0.5])
    >>> round(float(sweep.rest_shock_level[0] / (2 * np.pi * 5.0 * 0.5)), 5)
    1.0
    """
    if (impact_velocity is None) == (drop_height is None):
        raise SimulationError("shock_sweep: give exactly one of impact_velocity (m/s) and drop_height (m)")
    if drop_model == "rig":
        return _rig_sweep(system, impact_velocity=impact_velocity, drop_height=drop_height, duration=duration,
                          time_step=time_step, bottom_mass=bottom_mass, contact=contact, workers=workers,
                          executor=executor)
    if drop_height is not None:
        velocity = np.atleast_1d(impact_velocity_from_height(drop_height))
        if velocity.ndim != 1:
            raise SimulationError(f"drop_height: found shape {np.shape(drop_height)}, expected a 1-D array of m")
    else:
        velocity = np.atleast_1d(impact_velocity)
        if velocity.ndim != 1:
            raise SimulationError(f"impact_velocity: found shape {velocity.shape}, expected a 1-D array of m/s")
        with np.errstate(over="ignore"):
            too_fast = ~np.isfinite(velocity**2 / (2.0 * STANDARD_GRAVITY))
        if too_fast.any():
            raise SimulationError(f"impact_velocity: found {float(velocity[too_fast][0])!r} m/s, whose drop "
                                  f"height v0^2 / (2 g) overflows float64; expected |v0| below "
                                  f"{MAX_IMPACT_SPEED:.3g} m/s")
    if duration is None or time_step is None:  # only then is the resonance needed
        auto_duration, auto_step = default_shock_grid(system)
        duration = auto_duration if duration is None else duration
        time_step = auto_step if time_step is None else time_step
    g = gravity_acceleration(gravity)
    n_isolators = len(system.isolators)
    initial = relaxation_deflection(system) if relaxation else np.zeros(n_isolators)
    given = {"impact_velocity": velocity} if drop_height is None else {"drop_height": np.atleast_1d(drop_height)}
    response = unchecked(free_fall)(system, **given, duration=duration, time_step=time_step, gravity=g,
                                    initial_deflection=initial if relaxation else None, workers=workers,
                                    executor=executor)
    accel = response.acceleration[:, 0, :]
    ok = response.flags == 0
    total = drop_phase_peaks(response.deflection.sum(axis=1), accel)
    each = drop_phase_peaks(response.deflection, np.broadcast_to(accel[:, None, :], response.deflection.shape))
    names = ("isolator",) if n_isolators == 1 else ("upper", "lower")
    still = ok & (velocity == 0) & (g == 0.0) & (not np.any(initial))  # nothing can move: no phase
    reasons = tuple(NO_MOTION if at_rest else reason for at_rest, reason in zip(still, response.reasons))
    return ShockSweep(
        impact_velocity=velocity, drop_height=velocity**2 / (2.0 * STANDARD_GRAVITY), **_phase_fields(ok, total, each),
        isolator_names=names, time=response.time, top_acceleration=accel,
        flags=np.asarray(response.flags, dtype=np.int64), reasons=reasons, duration=duration,
        time_step=time_step, gravity=g, relaxation=bool(relaxation), initial_deflection=initial,
    )


def _phase_fields(ok, total, each) -> dict:
    """The :class:`ShockSweep` fields read off the drop-phase peaks of the stack (``total``) and of
    each isolator (``each``, :func:`idkit.signal.drop.drop_phase_peaks`); NaN (governing phase "")
    for a drop that did not finish (``ok`` False)."""
    nan = np.full(ok.shape, np.nan)
    rest = np.where(ok, total.rest_shock_level, nan)
    compression = np.where(ok, total.acceleration_compression, nan)
    tension = np.where(ok, total.acceleration_tension, nan)
    with np.errstate(invalid="ignore"):
        governing = np.where(~ok | np.isnan(rest), "",
                             np.where(np.fmax(compression, -np.inf) >= np.fmax(tension, -np.inf),
                                      "compression", "tension"))
    return {"rest_shock_level": rest, "peak_acceleration_compression": compression,
            "peak_acceleration_tension": tension, "governing_phase": governing.astype(str),
            "travel_compression": np.where(ok, total.compression, nan),
            "travel_tension": np.where(ok, total.tension, nan),
            "peak_compression": np.where(ok[:, None], each.compression, np.nan),
            "peak_tension": np.where(ok[:, None], each.tension, np.nan)}


def _rig_sweep(system, *, impact_velocity, drop_height, duration, time_step, bottom_mass, contact, workers,
               executor) -> ShockSweep:
    """:func:`shock_sweep` with ``drop_model="rig"`` (see there)."""
    if bottom_mass is None:
        raise SimulationError("bottom_mass: found None, expected the rig's bottom mass in kg for drop_model='rig'")
    if drop_height is not None:
        heights = np.atleast_1d(np.asarray(drop_height, dtype=float))
    else:
        velocity = np.atleast_1d(np.asarray(impact_velocity, dtype=float))
        if not np.all(velocity < 0):
            raise SimulationError(f"impact_velocity: found {velocity!r}, expected downward (< 0) m/s for a rig drop")
        heights = velocity**2 / (2.0 * STANDARD_GRAVITY)
    contact = DEFAULT_CONTACT if contact is None else contact
    run = drop_rig(system, bottom_mass=bottom_mass, drop_height=heights, contact=contact, duration=duration,
                   time_step=time_step, workers=workers, executor=executor)
    start = run.impact_index
    ok = run.flags == 0
    accel = run.top_acceleration
    total = drop_phase_peaks(run.deflection, accel, start=start)
    each = drop_phase_peaks(run.isolator_deflection,
                            np.broadcast_to(accel[:, None, :], run.isolator_deflection.shape), start=start)
    names = ("isolator",) if run.isolator_deflection.shape[1] == 1 else ("upper", "lower")
    return ShockSweep(
        impact_velocity=run.impact_velocity, drop_height=heights, **_phase_fields(ok, total, each),
        isolator_names=names, time=run.time[start:], top_acceleration=accel[:, start:],
        flags=np.asarray(run.flags, dtype=np.int64), reasons=tuple(run.reasons),
        duration=float(run.time[-1]), time_step=run.time_step, gravity=STANDARD_GRAVITY, relaxation=False,
        initial_deflection=run.static_deflection, drop_model="rig", lifted_off=run.lifted_off,
    )
