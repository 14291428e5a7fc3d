"""Drop rig: the whole falling stack, with a bottom mass that bounces and lifts off (thesis 9.2).

The conditioned free fall (:func:`idkit.simulate.free_fall`) starts at impact with the base
fixed. The rig model simulates what the drop-test rig does (thesis 6.2, SPEC 3):

* **release**: the bottom mass is held at height ``h`` above the floor, the top mass (and the
  hybrid's intermediate mass) rest on the isolator(s), every isolator **statically loaded** by
  the weight it carries (:func:`idkit.simulate.static_deflection`, internal states of a monotonic
  loading, :func:`idkit.simulate.initial_states`); at ``t = 0`` everything is released from rest
  under gravity. During the fall the isolators relax and oscillate (their static load vanishes
  in free fall).
* **floor contact**: the bottom mass (mass ``m_b``, its underside at height ``x_b``) meets the
  floor at height 0 through a unilateral spring-dashpot ``F_c = max(0, k_c p - c_c xdot_b)``
  with penetration ``p = max(0, -x_b)``: no adhesion, so the bottom mass bounces and lifts off
  (in tension the isolator may pull it up) and lands again, as often as the dynamics say.
  ``c_c = 2 zeta sqrt(k_c m_b)`` with ``zeta = -ln e / sqrt(pi^2 + ln^2 e)``, the damping ratio
  whose linear spring-dashpot returns the bottom mass alone with restitution ``e``
  (:class:`ContactModel`).
* **integration**: the simulator's average-acceleration Newmark step with Newton iterations and
  the exact constitutive updates of the isolators (:mod:`idkit.simulate._kernel`), the contact
  in the same implicit step (its tangent ``k_c + 2 c_c / h`` while pressed). The kink of the
  contact law at touch-down and lift-off is met within one step; with the automatic step (at
  least 80 steps per contact period ``2 pi sqrt(m_b / k_c)``) a halved step changes the shock
  peaks by well under 0.5 % (tests/simulate/test_drop_rig.py).

Defaults (:data:`DEFAULT_CONTACT`): ``k_c = 5e7 N/m`` (a steel base plate on a steel floor plate
through a thin interface: stiff compared with every isolator here, ``>= 1000 x`` a 5e4 N/m wire
rope, so the isolator, not the contact, sets the shock) and ``e = 0.3``. Both can be identified
from a measured drop: :func:`contact_from_velocity_step` reads the restitution from the step of
the relative velocity (before impact top and bottom fall together; just after it the bottom mass
rebounds at ``+e v`` while the top mass still moves at ``v``, so the step is ``(1 + e) v``), and
the contact stiffness from the step's rise time.

Validity flags and the batch design are those of :func:`idkit.simulate.simulate`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from idkit.errors import SimulationError
from idkit.gravity import STANDARD_GRAVITY
from idkit.checks import Instance, Real, Reals, Samples, Whole, accepts
from idkit.limits import MAX_STEPS
from idkit.models.laws import kernel_array
from idkit.simulate._arrays import resolve_system, system_arrays
from idkit.simulate._kernel import FLAG_REASONS
from idkit.simulate._rig_kernel import run_drop_batch
from idkit.simulate._parallel import run_chunked
from idkit.simulate.time_response import initial_states, static_deflection

__all__ = [
    "DEFAULT_CONTACT",
    "ContactModel",
    "DropRigResponse",
    "contact_from_velocity_step",
    "drop_rig",
    "rig_time_step",
]

#: Contact steps per contact period ``2 pi sqrt(m_b / k_c)`` of the automatic time step.
STEPS_PER_CONTACT_PERIOD = 80


#: The contract of each :class:`ContactModel` field.
_CONTACT_FIELDS = {"stiffness": Real(unit="N/m", gt=0), "restitution": Real(gt=0, le=1),
                   "damping_ratio_override": Real(ge=0, optional=True)}


@dataclass(frozen=True)
class ContactModel:
    """Unilateral floor contact of the bottom mass (module docstring).

    Attributes
    ----------
    stiffness : float
        ``k_c`` in N/m, > 0.
    restitution : float
        ``e`` in (0, 1]: 1 is an elastic contact (no damping). It sets the damping ratio of the
        linear spring-dashpot; the clipped law (no adhesion) separates when the dashpot cancels
        the spring, slightly before the penetration returns to zero, so the bottom mass leaves
        somewhat faster than ``e`` times its arrival speed when ``e`` is small (about 0.14 for
        ``e = 0.001``).
    damping_ratio_override : float, optional
        Damping ratio used instead of the one from ``restitution`` (e.g. strongly overdamped,
        ``>> 1``, for a floor that does not throw the bottom mass back).
    """

    stiffness: float = 5.0e7
    restitution: float = 0.3
    damping_ratio_override: float | None = None

    def __post_init__(self):
        for name, spec in _CONTACT_FIELDS.items():
            spec.check(getattr(self, name), f"contact {name}", SimulationError)

    @property
    def damping_ratio(self) -> float:
        """``zeta = -ln e / sqrt(pi^2 + ln^2 e)`` (0 for ``e = 1``), unless overridden."""
        if self.damping_ratio_override is not None:
            return float(self.damping_ratio_override)
        log_e = math.log(self.restitution)
        return -log_e / math.sqrt(math.pi**2 + log_e**2)

    def damping(self, bottom_mass: float) -> float:
        """``c_c = 2 zeta sqrt(k_c m_b)`` in N s/m for a bottom mass in kg."""
        return 2.0 * self.damping_ratio * math.sqrt(self.stiffness * bottom_mass)

    def period(self, bottom_mass: float) -> float:
        """Contact period ``2 pi sqrt(m_b / k_c)`` in s."""
        return 2.0 * math.pi * math.sqrt(bottom_mass / self.stiffness)


#: Documented default contact (module docstring).
DEFAULT_CONTACT = ContactModel()


@dataclass(frozen=True)
class DropRigResponse:
    """Records of a batch of rig drops, aligned at the first floor contact.

    Every record has ``n_records`` samples; sample ``impact_index`` is the first contact (the
    first step at which the bottom mass is below the floor), ``time`` is 0 there.

    Attributes
    ----------
    time : ndarray (n_records,)
        s, 0 at the first contact.
    top_acceleration : ndarray (batch, n_records)
        Kinematic acceleration of the top mass, m/s^2 (``-g`` in free fall).
    deflection : ndarray (batch, n_records)
        ``x_top - x_bottom - (x_top - x_bottom)_unloaded``: the deflection summed over the
        isolators, m (what the rig's vibrometer measures; positive = tension).
    relative_velocity : ndarray (batch, n_records)
        ``v_top - v_bottom``, m/s.
    isolator_deflection : ndarray (batch, n_isolators, n_records)
        m, top isolator first.
    bottom_height, bottom_velocity : ndarray (batch, n_records)
        Height of the bottom mass's underside above the floor (m, < 0 while pressed) and its
        velocity (m/s).
    contact_force : ndarray (batch, n_records)
        N, >= 0.
    impact_index : int
    impact_velocity : ndarray (batch,)
        Bottom-mass velocity at the first contact, m/s (``-sqrt(2 g h)`` plus the fall's
        oscillation).
    static_deflection : ndarray (n_isolators,)
        Deflection of each isolator in the statically loaded rest state before release, m.
    lifted_off : ndarray of bool (batch,)
        The bottom mass rose above the floor (height > 0) after the first contact.
    drop_height : ndarray (batch,)
        m.
    flags : ndarray (batch,); reasons : tuple of str
    time_step : float
        s.
    contact : ContactModel
    """

    time: np.ndarray
    top_acceleration: np.ndarray
    deflection: np.ndarray
    relative_velocity: np.ndarray
    isolator_deflection: np.ndarray
    bottom_height: np.ndarray
    bottom_velocity: np.ndarray
    contact_force: np.ndarray
    impact_index: int
    impact_velocity: np.ndarray
    static_deflection: np.ndarray
    lifted_off: np.ndarray
    drop_height: np.ndarray
    flags: np.ndarray
    reasons: tuple[str, ...]
    time_step: float
    contact: ContactModel

    @property
    def ok(self) -> np.ndarray:
        """Runs that stayed inside the model's valid range."""
        return self.flags == 0


def rig_time_step(system, bottom_mass: float, contact: ContactModel = DEFAULT_CONTACT) -> float:
    """Automatic step (s): the shock grid's step, at most 1/80 of the contact period."""
    from idkit.simulate.harmonic import small_amplitude_resonance

    f0 = small_amplitude_resonance(system)
    step = 1.0 / (2000.0 * f0)
    return min(step, contact.period(bottom_mass) / STEPS_PER_CONTACT_PERIOD)


#: Most steps of one rig drop (fall and record): the simulator's limit.
MAX_RIG_STEPS = MAX_STEPS


@accepts(bottom_mass=Real(unit="kg", gt=0), drop_height=Reals(unit="m", gt=0), contact=Instance((ContactModel,)),
         duration=Real(unit="s", gt=0, optional=True), before=Real(unit="s", ge=0),
         time_step=Real(unit="s", gt=0, optional=True), error=SimulationError)
def drop_rig(system, *, bottom_mass: float, drop_height, contact: ContactModel = DEFAULT_CONTACT,
             duration: float | None = None, before: float = 0.0, time_step: float | None = None,
             workers: int | None = None, executor=None) -> DropRigResponse:
    """Simulate rig drops of ``system`` (SDOF or hybrid) on a bottom mass (module docstring).

    Parameters
    ----------
    system : SDOFSystem or HybridSystem
        Top mass (and intermediate mass) with its isolator(s); masses include ``m_eff``.
    bottom_mass : float
        kg, > 0.
    drop_height : array_like (batch,)
        Height of the bottom mass's underside above the floor at release, m, > 0.
    contact : ContactModel
    duration : float, optional
        Time recorded after the first contact, s; default ``4 / f0`` as the conditioned fall
        (:func:`idkit.responses.shock.default_shock_grid`).
    before : float, default 0
        Time recorded before the first contact, s (at most the shortest fall).
    time_step : float, optional
        s; default :func:`rig_time_step`.
    workers, executor : see :func:`idkit.simulate.harmonic_response`.

    Returns
    -------
    DropRigResponse
    """
    from idkit.simulate.harmonic import small_amplitude_resonance

    system = resolve_system(system)
    heights = np.atleast_1d(drop_height)
    if heights.ndim != 1:
        raise SimulationError(f"drop_height: found shape {heights.shape}, expected a 1-D array of heights in m")
    arrays = system_arrays(system)
    f0 = small_amplitude_resonance(system)
    duration = 4.0 / f0 if duration is None else duration
    h = rig_time_step(system, bottom_mass, contact) if time_step is None else time_step
    fall = np.sqrt(2.0 * heights / STANDARD_GRAVITY)
    if not 0.0 <= before <= float(fall.min()):
        raise SimulationError(f"before: found {before!r}, expected 0 .. {float(fall.min()):.4g} s (the shortest fall)")
    masses = np.append(arrays.masses, float(bottom_mass))
    n = masses.size
    # statically loaded rest state: isolator j carries the masses above it
    carried = -np.cumsum(arrays.masses) * STANDARD_GRAVITY
    static = np.array([static_deflection(isolator, load) for isolator, load in zip(system.isolators, carried)])
    jforce, mstate, bwz = initial_states(system, static)
    q0 = np.empty((heights.size, n))
    q0[:, -1] = heights
    for j in range(n - 2, -1, -1):
        q0[:, j] = q0[:, j + 1] + static[j]
    # steps: the fall (with margin for the bottom mass, pushed down by the relaxing isolator) and the record
    raw = (1.05 * fall + duration) / h
    steps = raw + 2
    if not np.all(steps < MAX_RIG_STEPS):  # checked before the step counts are cast to int64
        worst = int(np.argmax(steps))
        fall_max = max(((MAX_RIG_STEPS - 3) * h - duration) / 1.05, 0.0)
        raise SimulationError(
            f"drop_height: found {heights[worst]:.4g} m, whose fall of {fall[worst]:.4g} s and record of {duration:.4g} s "
            f"take {steps[worst]:.4g} steps of {h:.4g} s; expected fewer than {MAX_RIG_STEPS:.0e} (the simulator's "
            f"limit), a height below {STANDARD_GRAVITY * fall_max**2 / 2:.4g} m at this step")
    n_steps = np.ceil(raw).astype(np.int64) + 2
    batch = heights.size
    jforce0 = np.broadcast_to(jforce, (batch, *jforce.shape)).copy()
    mstate0 = np.broadcast_to(mstate, (batch, *mstate.shape)).copy()
    bwz0 = np.broadcast_to(bwz, (batch, bwz.size)).copy()
    damping = contact.damping(float(bottom_mass))
    scale = float(masses.sum() * STANDARD_GRAVITY * 10.0 + arrays.jfc.sum())
    kernel = (kernel_array(masses), *(kernel_array(v) for v in arrays.as_tuple()[1:]))

    def task(part: slice):
        return run_drop_batch(*kernel, h, n_steps[part], int(n_steps.max()), STANDARD_GRAVITY, kernel_array(q0[part]),
                              kernel_array(jforce0[part]), kernel_array(mstate0[part]), kernel_array(bwz0[part]),
                              float(contact.stiffness), damping, 1, scale)

    rec_q, rec_v, rec_a, rec_f, first, flags, _flag_step = run_chunked(task, batch, workers=workers,
                                                                      executor=executor)
    flags = np.asarray(flags, dtype=np.int64).copy()
    before_steps = round(before / h)
    after_steps = round(duration / h)
    length = before_steps + after_steps + 1
    impact_missing = first < 0
    flags[impact_missing & (flags == 0)] = -1
    out = {name: np.full((batch, n, length), np.nan) for name in ("q", "v", "a", "f")}
    for b in range(batch):
        if first[b] < 0:
            continue
        start = first[b] - before_steps
        stop = min(start + length, rec_q.shape[2])
        for name, values in (("q", rec_q), ("v", rec_v), ("a", rec_a), ("f", rec_f)):
            out[name][b, :, : stop - start] = values[b, :, start:stop]
    reasons = tuple("the bottom mass never reached the floor" if f == -1 else FLAG_REASONS[int(f)] for f in flags)
    q, v = out["q"], out["v"]
    iso = q[:, :-1, :] - q[:, 1:, :]
    contact_force = out["f"][:, -1, :]
    with np.errstate(invalid="ignore"):
        lifted = np.any(q[:, -1, before_steps:] > 0.0, axis=1)
    impact_velocity = np.array([rec_v[b, -1, first[b] - 1] if first[b] > 0 else np.nan for b in range(batch)])
    return DropRigResponse(
        time=(np.arange(length) - before_steps) * h, top_acceleration=out["a"][:, 0, :],
        deflection=iso.sum(axis=1), relative_velocity=v[:, 0, :] - v[:, -1, :], isolator_deflection=iso,
        bottom_height=q[:, -1, :], bottom_velocity=v[:, -1, :], contact_force=contact_force,
        impact_index=before_steps, impact_velocity=impact_velocity, static_deflection=static, lifted_off=lifted,
        drop_height=heights, flags=flags, reasons=reasons, time_step=h, contact=contact,
    )


@accepts(relative_velocity=Samples(unit="m/s"), time=Samples(unit="s"), drop_height=Real(unit="m", gt=0),
         bottom_mass=Real(unit="kg", gt=0), window=Whole(ge=1, meaning="samples"), error=SimulationError)
def contact_from_velocity_step(relative_velocity, time, *, drop_height: float, bottom_mass: float,
                               window: int = 5) -> ContactModel:
    """Contact restitution and stiffness read off one measured drop (module docstring).

    ``e = |step| / sqrt(2 g h) - 1`` where the step is the most negative smoothed relative
    velocity of the first stroke (:func:`idkit.signal.drop.process_drop`'s reading) and ``h`` the
    drop height; ``k_c = m_b (pi / t_rise)^2`` from the rise time of the step (10 % to 90 % of
    it, taken as half a contact period), at most the rise a ``window``-sample smoothing
    lets through (a rise shorter than that gives a lower bound only, and the default
    stiffness is kept if it is larger).

    Parameters
    ----------
    relative_velocity : array_like (n,)
        Measured relative velocity over the isolator(s), m/s, uniformly sampled; smoothed here by
        the ``window``-sample moving average run forward and backward, as
        :func:`idkit.signal.drop.zero_phase_moving_average` does.
    time : array_like (n,)
        s.
    drop_height : float
        m.
    bottom_mass : float
        kg.
    window : int
        Samples of the moving average the record is smoothed with.

    Returns
    -------
    ContactModel
        With the restitution clipped to (0.01, 1].
    """
    from scipy.signal import filtfilt

    v = relative_velocity
    if window > 1 and v.size > 3 * window:  # the drop processing's zero-phase moving average
        v = filtfilt(np.full(int(window), 1.0 / window), [1.0], v)
    t = time
    if t.shape != v.shape or t.size < 4 * window:
        raise SimulationError(f"time: found shape {t.shape}, expected {v.shape} (one time per velocity sample)")
    most = float(v.min())
    if not most < 0:
        raise SimulationError("relative_velocity: never negative, no impact step found")
    free_fall_speed = math.sqrt(2.0 * STANDARD_GRAVITY * drop_height)
    restitution = float(np.clip(abs(most) / free_fall_speed - 1.0, 0.01, 1.0))
    low = int(np.flatnonzero(v <= 0.1 * most)[0])
    high = int(np.flatnonzero(v <= 0.9 * most)[0])
    dt = float(t[1] - t[0])
    resolved = high - low > window - 1
    rise = max((high - low), window - 1) * dt
    stiffness = bottom_mass * (math.pi / rise) ** 2
    if not resolved:  # a lower bound only
        stiffness = max(stiffness, DEFAULT_CONTACT.stiffness)
    return ContactModel(stiffness=stiffness, restitution=restitution)
