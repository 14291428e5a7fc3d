"""Time simulation of base-excited and free-falling isolator systems, in batches."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pandas as pd

from idkit.checks import Instance, Real, Reals, Samples, Whole, accepts, unchecked
from idkit.errors import SimulationError
from idkit.limits import MAX_STEPS
from idkit.models.laws import kernel_array
from idkit.models.base import IsolatorModel
from idkit.gravity import gravity_acceleration, impact_velocity_from_height
from idkit.simulate._arrays import (
    MAX_FORCE_SCALE,
    STANDARD_GRAVITY,
    force_scale,
    resolve_system,
    system_arrays,
)
from idkit.simulate._kernel import FLAG_REASONS, time_kernel
from idkit.simulate._parallel import run_chunked
from idkit.simulate._structured import structure_of
from idkit.simulate.base_motion import BaseMotion, integrate_acceleration

__all__ = ["IntegratorState", "TimeResponse", "TimeState", "simulate", "free_fall", "static_deflection", "initial_states", "relaxation_deflection"]


@dataclass(frozen=True)
class IntegratorState:
    """The integrator's own numbers at the end of a batch of runs (absolute frame).

    What :func:`simulate` needs, beyond a :class:`TimeState`'s relative state, to continue a
    run as the very same run: the trapezoidal rule carries the accelerations from step to
    step (restarting them from equilibrium changes them at the solver's tolerance), the
    deflections are differences of absolute coordinates (another frame rounds them
    differently), and the Newton tolerances scale with the run's force magnitude. With them
    a continued run repeats the uninterrupted one bit for bit (a hysteretic run can amplify
    a last-digit difference to 1e-7 over a record).

    Attributes
    ----------
    position, velocity, acceleration : (batch, ndof) absolute mass displacement (m), velocity
        (m/s) and acceleration (m/s^2), top first
    base_displacement, base_velocity : (batch,) absolute base displacement (m) and velocity (m/s)
    time_step : float
        The step of the run, s.
    force_scale : (batch,) N, each run's force magnitude for its convergence tests
    jenkin_force, maxwell_elongation, boucwen_z : the internal states as the run left them
        (a :class:`TimeState` whose own fields differ from these was changed since, and is
        continued from its fields alone)
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    base_displacement: np.ndarray
    base_velocity: np.ndarray
    time_step: float
    force_scale: np.ndarray
    jenkin_force: np.ndarray
    maxwell_elongation: np.ndarray
    boucwen_z: np.ndarray

    def take(self, runs) -> "IntegratorState":
        """The numbers of some runs (an index array or a boolean mask over the batch)."""
        return IntegratorState(**{name: (value if name == "time_step" else np.asarray(value)[runs])
                                  for name, value in vars(self).items()})


@dataclass(frozen=True)
class TimeState:
    """The complete state of a batch of runs at one instant, to continue them later.

    Positions and velocities are relative to the base: the equations of motion only see
    deflections and deflection rates (and a constant gravity), so a run continued from this
    state by :func:`simulate` with a base that starts at rest again is the same physical run
    (the base's own displacement and velocity at the cut drop out). The ``final_state`` of a
    :func:`simulate` run also holds the integrator's own numbers (``integrator``), with which
    a continuation driven by the following base-acceleration samples equals the uninterrupted
    run bit for bit.

    Attributes
    ----------
    displacement, velocity : (batch, ndof) mass displacement (m) and velocity (m/s) relative
        to the base, top first
    jenkin_force : (batch, ndof, n_j) N; maxwell_elongation : (batch, ndof, n_m) m;
    boucwen_z : (batch, ndof) N. Rows of an isolator without such parts are zero; a run that
        was flagged carries NaN.
    integrator : IntegratorState or None
        The integrator's numbers where these fields were taken (None for a state built by
        hand). A run whose fields were changed since is continued from the fields alone.
    """

    displacement: np.ndarray
    velocity: np.ndarray
    jenkin_force: np.ndarray
    maxwell_elongation: np.ndarray
    boucwen_z: np.ndarray
    integrator: IntegratorState | None = field(default=None, repr=False, compare=False)

    def __len__(self) -> int:
        return int(self.displacement.shape[0])

    def take(self, runs) -> "TimeState":
        """The state of some runs (an index array or a boolean mask over the batch)."""
        return TimeState(*(np.asarray(values)[runs] for values in (
            self.displacement, self.velocity, self.jenkin_force, self.maxwell_elongation, self.boucwen_z)),
            integrator=None if self.integrator is None else self.integrator.take(runs))

    def replace_runs(self, runs, other: "TimeState") -> "TimeState":
        """This state with the runs ``runs`` (indices) replaced by ``other``'s, in order (a
        batch continued in parts). The integrator's numbers are kept where both have them."""
        runs = np.asarray(runs)

        def merged(mine, theirs):
            values = np.array(mine, copy=True)
            values[runs] = theirs
            return values

        fields = [merged(getattr(self, name), getattr(other, name)) for name in _STATE_FIELDS]
        integrator = None
        if self.integrator is not None and other.integrator is not None \
                and self.integrator.time_step == other.integrator.time_step:
            integrator = IntegratorState(**{
                name: (value if name == "time_step" else merged(value, getattr(other.integrator, name)))
                for name, value in vars(self.integrator).items()})
        return TimeState(*fields, integrator=integrator)


_STATE_FIELDS = ("displacement", "velocity", "jenkin_force", "maxwell_elongation", "boucwen_z")


@dataclass(frozen=True)
class TimeResponse:
    """Recorded response of a batch of runs on a common time grid.

    Attributes
    ----------
    time : (n_records,) s
    displacement : (batch, ndof, n_records) mass displacement relative to the base, m (top first)
    velocity : (batch, ndof, n_records) relative velocity, m/s
    acceleration : (batch, ndof, n_records) absolute acceleration, m/s^2 (what an accelerometer reads,
        without gravity)
    deflection : (batch, n_isolators, n_records) isolator deflections, m (positive = tension),
        isolator 0 is the one below the top mass
    isolator_force : (batch, n_isolators, n_records) isolator forces, N (positive = tension)
    flags : (batch,) 0 if the run finished, else a code; ``reasons`` gives the text
    flag_time : (batch,) s, time of the step that failed (NaN when ok)
    final_state : TimeState or None
        Every run's state after the last step (``simulate(..., initial_state=...)`` continues
        from it); None where the response was not computed by :func:`simulate`.
    """

    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    deflection: np.ndarray
    isolator_force: np.ndarray
    flags: np.ndarray
    flag_time: np.ndarray
    reasons: tuple[str, ...] = field(default=())
    final_state: TimeState | None = field(default=None, repr=False)

    @property
    def ok(self) -> np.ndarray:
        """Boolean mask of runs that finished inside the model's valid range."""
        return self.flags == 0

    def to_dataframe(self, member: int = 0) -> pd.DataFrame:
        """One run as a table with unit-bearing column names."""
        columns = {"time [s]": self.time}
        for d in range(self.displacement.shape[1]):
            name = "top" if d == 0 else "intermediate"
            columns[f"x_{name} [m]"] = self.displacement[member, d]
            columns[f"v_{name} [m/s]"] = self.velocity[member, d]
            columns[f"a_{name} [m/s^2]"] = self.acceleration[member, d]
        for j in range(self.deflection.shape[1]):
            columns[f"deflection_{j} [m]"] = self.deflection[member, j]
            columns[f"force_{j} [N]"] = self.isolator_force[member, j]
        return pd.DataFrame(columns)


@accepts(load=Real(unit="N", meaning="positive in tension"), tolerance=Real(gt=0, lt=1), error=SimulationError)
def static_deflection(isolator: IsolatorModel, load: float, *, tolerance: float = 1e-12) -> float:
    """Deflection (m) at which the isolator's monotonic quasi-static force equals ``load`` (N).

    Loading from the unloaded state; positive load = tension. Solved by
    bisection on the (monotonic while valid) backbone curve.
    """
    if load == 0:
        return 0.0

    def backbone(y):
        path = np.linspace(0.0, y, 65)
        if isinstance(isolator, IsolatorModel) and isolator.kind in ("generalized_maxwell", "voigt"):
            return float(isolator.small_amplitude_stiffness(0.0).real * y)
        return float(isolator.force(path)[-1])

    direction = np.sign(load)
    high = direction * 1e-6
    while abs(backbone(high)) < abs(load):
        high *= 2.0
        if abs(high) > 10.0:
            raise SimulationError(f"static_deflection: no deflection within 10 m carries {load:g} N")
    low = 0.0
    while abs(high - low) > tolerance * max(abs(high), 1e-9):
        middle = 0.5 * (low + high)
        if abs(backbone(middle)) < abs(load):
            low = middle
        else:
            high = middle
    return 0.5 * (low + high)


def relaxation_deflection(system) -> np.ndarray:
    """Initial isolator elongations (m) for the relaxation reading of a drop (SPEC 5).

    Each isolator starts stretched by its static deflection under the weight it
    carries: the top isolator ``m_top g``, a hybrid's lower isolator also the
    intermediate mass (masses include ``m_eff``). Positive = tension.
    """
    system = resolve_system(system)
    carried = np.cumsum(np.asarray(system.masses, dtype=float)) * STANDARD_GRAVITY
    return np.array([static_deflection(isolator, load) for isolator, load in zip(system.isolators, carried)])


def initial_states(system, deflections):
    """Internal states after monotonic loading to ``deflections`` (m, one per isolator).

    Jenkin elements carry ``clip(k y, -s(y) Fc, s(y) Fc)`` (``s = 1`` unless the slip forces
    are modulated, :mod:`idkit.models.iwan_modulated`); Maxwell elements are relaxed
    (held long at that deflection); Bouc-Wen ``z`` follows the loading branch.
    Returns ``(jenkin_force (ndof, nj), maxwell_state (ndof, nm), boucwen_z (ndof,))``.
    """
    system = resolve_system(system)
    arrays = system_arrays(system)
    deflections = np.broadcast_to(np.asarray(deflections, dtype=float), (arrays.ndof,))
    scale = np.ones(arrays.ndof)
    modulated = (arrays.sm[:, 0] != 0.0) | (arrays.sm[:, 2] != 0.0)
    t = np.tanh(deflections[modulated] / arrays.sm[modulated, 1])
    scale[modulated] = 1.0 - arrays.sm[modulated, 0] * t + arrays.sm[modulated, 2] * t * t
    limit = arrays.jfc * scale[:, None]
    jforce = np.clip(arrays.jk * deflections[:, None], -limit, limit)
    mstate = np.zeros_like(arrays.mk)
    bwz = np.zeros(arrays.ndof)
    for j, isolator in enumerate(system.isolators):
        if isolator.kind in ("bouc_wen", "bouc_wen_pinched") and deflections[j] != 0:
            bwz[j] = isolator.hysteretic_force(np.linspace(0.0, deflections[j], 257))[-1]
    return jforce, mstate, bwz


@accepts(time=Samples(unit="s", min_size=2), base_acceleration=Samples(unit="m/s^2", ndim=(1, 2), optional=True),
         initial_velocity=Reals(unit="m/s", optional=True), initial_deflection=Reals(unit="m", optional=True),
         initial_state=Instance((TimeState,), optional=True, what="a TimeState (the final_state of an earlier "
                                                                   "response)"),
         record_every=Whole(ge=1), error=SimulationError)
def simulate(system, time, *, base: BaseMotion | None = None, base_acceleration=None,
             initial_velocity=None, initial_deflection=None, initial_state: TimeState | None = None,
             gravity: bool | float = False, record_every: int = 1, workers: int | None = None,
             executor=None) -> TimeResponse:
    """Simulate a batch of runs of ``system`` on a uniform time grid.

    Parameters
    ----------
    system : SDOFSystem, HybridSystem or CoulombSpringSystem
    time : array_like, shape (n_steps + 1,)
        Uniform, increasing time grid in s; its spacing is the integration step.
    base : BaseMotion, optional
        One base motion shared by the whole batch (default: base at rest).
    base_acceleration : array_like, shape (batch, n_steps + 1), optional
        Sampled base accelerations in m/s^2, one row per run (e.g. random
        realizations); overrides ``base``. Integrated with the integrator's rule
        from zero base displacement and velocity (a continued run: see ``initial_state``).
    initial_velocity : array_like, shape (batch, ndof) or (ndof,), optional
        Absolute initial velocities of the masses in m/s, top first (drops: ``v0 < 0``).
        Default: at rest.
    initial_deflection : array_like, shape (batch, n_isolators) or (n_isolators,), optional
        Initial isolator deflections in m (positive = tension); internal states follow
        :func:`initial_states`. Default: unloaded.
    initial_state : TimeState, optional
        Continue runs from a state (``final_state`` of an earlier response of the same system):
        relative displacements, velocities and every internal state. Excludes
        ``initial_velocity`` and ``initial_deflection``. A ``final_state`` also carries the
        integrator's own numbers (:class:`IntegratorState`): a run continued with them is the
        same run, bit for bit, when the base continues where it was (``base_acceleration``:
        integrated from the base's displacement and velocity where the run ended; a
        ``base`` motion: when it is there at ``time[0]``), the grid's spacing is the run's step
        (within the 1e-9 allowed, the run's own step is taken) and the run's force scale is
        at least this part's (it is the larger of the two). A run whose state fields were
        changed since continues from them alone, its accelerations from equilibrium.
    gravity : bool or float
        Include gravity (True: 9.80665 m/s^2, or a value in m/s^2) acting downward.
    record_every : int
        Record every n-th step.
    workers, executor : see :func:`idkit.simulate.harmonic_response`.

    Returns
    -------
    TimeResponse
    """
    system = resolve_system(system)
    arrays = system_arrays(system)
    ndof = arrays.ndof
    t = time
    steps = np.diff(t)
    h = float(steps.mean())
    if not (h > 0 and np.allclose(steps, h, rtol=1e-9, atol=0)):
        raise SimulationError("time: found a non-uniform or non-increasing grid, expected uniform spacing")
    if initial_state is not None:
        if initial_velocity is not None or initial_deflection is not None:
            raise SimulationError("simulate: found initial_state with initial_velocity or initial_deflection, "
                                  "expected initial_state alone (it holds both)")
        _check_state(initial_state, arrays)
    integrator = None if initial_state is None else initial_state.integrator
    if integrator is not None and abs(h - integrator.time_step) <= 1e-9 * h:
        h = integrator.time_step  # the continued run's own step (the grid's, within its 1e-9 tolerance)
    accel = None
    if base_acceleration is not None:
        accel = np.atleast_2d(base_acceleration)
        if accel.shape[1] != t.size:
            raise SimulationError(
                f"base_acceleration: found {accel.shape[1]} samples per run, expected {t.size} (one per time point)"
            )
        batch_sizes = {accel.shape[0]}
    else:
        base_disp, base_vel = (values[None, :] for values in (base or BaseMotion.at_rest()).on_grid(t))
        batch_sizes = {base_disp.shape[0]}
    if initial_state is not None:
        batch_sizes.add(len(initial_state))
    v_abs = np.zeros((1, ndof)) if initial_velocity is None else np.atleast_2d(initial_velocity)
    y0 = np.zeros((1, ndof)) if initial_deflection is None else np.atleast_2d(initial_deflection)
    for name, values in (("initial_velocity", v_abs), ("initial_deflection", y0)):
        if values.ndim != 2 or values.shape[0] == 0:
            raise SimulationError(f"{name}: found shape {values.shape}, expected (batch, {ndof}) or ({ndof},) "
                                  "with at least one run")
        if values.shape[1] != ndof:
            raise SimulationError(f"{name}: found {values.shape[1]} columns, expected {ndof} (one per mass/isolator)")
        batch_sizes.add(values.shape[0])
    batch_sizes.discard(1)
    if len(batch_sizes) > 1:
        raise SimulationError(f"batch sizes differ between inputs: {sorted(batch_sizes)}")
    batch = batch_sizes.pop() if batch_sizes else 1
    # runs continued from the integrator's own numbers (their state unchanged since)
    exact = np.zeros(batch, dtype=bool) if integrator is None else _unchanged_runs(initial_state)
    if accel is not None:
        if exact.any():  # each continued run's base goes on from where it was
            accel = np.broadcast_to(accel, (batch, t.size))
            base_disp, base_vel = integrate_acceleration(
                accel, h, np.where(exact, integrator.base_displacement, 0.0),
                np.where(exact, integrator.base_velocity, 0.0))
        else:
            base_disp, base_vel = integrate_acceleration(accel, h)
    v_abs = kernel_array(np.broadcast_to(v_abs, (batch, ndof)))
    y0 = np.broadcast_to(y0, (batch, ndof))
    x_base0 = np.broadcast_to(base_disp[:, :1], (batch, 1))
    # absolute positions: the last isolator stands on the base, isolator 0 carries the top mass
    q0 = x_base0 + (y0 if ndof == 1 else np.column_stack([y0[:, 0] + y0[:, 1], y0[:, 1]]))
    jforce0 = np.empty((batch, ndof, arrays.jk.shape[1]))
    mstate0 = np.empty((batch, ndof, arrays.mk.shape[1]))
    bwz0 = np.empty((batch, ndof))
    a0 = np.full((batch, ndof), np.nan)  # NaN: accelerations from equilibrium
    if initial_state is None:
        for b in range(batch):
            jforce0[b], mstate0[b], bwz0[b] = initial_states(system, y0[b])
    else:
        q0 = x_base0 + initial_state.displacement
        v_abs = kernel_array(initial_state.velocity + np.broadcast_to(base_vel[:, :1], (batch, 1)))
        jforce0[:] = initial_state.jenkin_force
        mstate0[:] = initial_state.maxwell_elongation
        bwz0[:] = initial_state.boucwen_z
        if exact.any():
            a0[exact] = integrator.acceleration[exact]
            # the same absolute frame where the base is where the run left it
            same_frame = exact & (np.broadcast_to(base_disp[:, 0], (batch,)) == integrator.base_displacement) \
                & (np.broadcast_to(base_vel[:, 0], (batch,)) == integrator.base_velocity)
            q0[same_frame] = integrator.position[same_frame]
            v_abs[same_frame] = integrator.velocity[same_frame]
    g = gravity_acceleration(gravity)
    # each run's own acceleration scale (a shared base: the same for all), so that no run's
    # convergence tests depend on the other runs of the batch
    accel_scale = (np.abs(np.diff(base_vel, axis=-1)).max(axis=-1) / h if t.size > 1
                   else np.zeros(base_vel.shape[0]))
    kernel_arrays = arrays.as_tuple()
    base_disp = kernel_array(base_disp)
    base_vel = kernel_array(base_vel)
    q0 = kernel_array(q0)
    scale = np.broadcast_to(force_scale(arrays, accel_scale), (batch,)).copy()
    if exact.any():  # a run's scale covers all of it: the larger of its parts'
        scale[exact] = np.maximum(scale[exact], integrator.force_scale[exact])
    run_time_batch = time_kernel(structure_of(arrays))

    def task(part: slice):
        rows = part if base_disp.shape[0] > 1 else slice(0, 1)
        return run_time_batch(
            *kernel_arrays, h, base_disp[rows], base_vel[rows], g, q0[part], v_abs[part], jforce0[part],
            mstate0[part], bwz0[part], int(record_every), scale[part], a0[part],
        )

    (rec_q, rec_v, rec_a, rec_f, flags, flag_step, end_q, end_v, end_a, end_jforce, end_mstate,
     end_bwz) = run_chunked(task, batch, workers=workers, executor=executor)
    n_records = rec_q.shape[2]
    record_time = t[:: int(record_every)][:n_records]
    base_x = base_disp[:, :: int(record_every)][:, :n_records]
    base_v = base_vel[:, :: int(record_every)][:, :n_records]
    displacement = rec_q - base_x[:, None, :]
    velocity = rec_v - base_v[:, None, :]
    if ndof == 1:
        deflection = displacement
    else:
        deflection = np.stack([displacement[:, 0] - displacement[:, 1], displacement[:, 1]], axis=1)
    flag_time = np.where(flag_step >= 0, t[0] + flag_step * h, np.nan)
    end_base_disp = np.broadcast_to(base_disp[:, -1], (batch,)).copy()
    end_base_vel = np.broadcast_to(base_vel[:, -1], (batch,)).copy()
    final_state = TimeState(
        displacement=end_q - end_base_disp[:, None], velocity=end_v - end_base_vel[:, None], jenkin_force=end_jforce,
        maxwell_elongation=end_mstate, boucwen_z=end_bwz,
        integrator=IntegratorState(position=end_q, velocity=end_v, acceleration=end_a, base_displacement=end_base_disp,
                                   base_velocity=end_base_vel, time_step=h, force_scale=scale.copy(),
                                   jenkin_force=end_jforce.copy(), maxwell_elongation=end_mstate.copy(),
                                   boucwen_z=end_bwz.copy()))
    return TimeResponse(
        time=record_time, displacement=displacement, velocity=velocity, acceleration=rec_a,
        deflection=deflection, isolator_force=rec_f, flags=flags, flag_time=flag_time,
        reasons=tuple(FLAG_REASONS[int(f)] for f in flags), final_state=final_state,
    )


def _unchanged_runs(state: TimeState) -> np.ndarray:
    """Per run: its fields are still those its :class:`IntegratorState` was taken with."""
    integrator = state.integrator
    same = (np.asarray(state.displacement) == integrator.position - integrator.base_displacement[:, None]).all(axis=1)
    same &= (np.asarray(state.velocity) == integrator.velocity - integrator.base_velocity[:, None]).all(axis=1)
    for name in ("jenkin_force", "maxwell_elongation", "boucwen_z"):
        values = np.asarray(getattr(state, name)) == getattr(integrator, name)
        same &= values.reshape(len(state), -1).all(axis=1)
    return same


def _check_state(state: TimeState, arrays) -> None:
    """``state`` fits the system (``arrays``): shapes, one batch size, finite values."""
    ndof = arrays.ndof
    batch = len(state)
    expected = {"displacement": (batch, ndof), "velocity": (batch, ndof),
                "jenkin_force": (batch, ndof, arrays.jk.shape[1]),
                "maxwell_elongation": (batch, ndof, arrays.mk.shape[1]), "boucwen_z": (batch, ndof)}
    for name, shape in expected.items():
        values = np.asarray(getattr(state, name))
        if values.shape != shape:
            raise SimulationError(f"initial_state.{name}: found shape {values.shape}, expected {shape} "
                                  "(a state of this system)")
        if not np.all(np.isfinite(values)):
            run = int(np.argwhere(~np.isfinite(values))[0][0])
            raise SimulationError(f"initial_state.{name}: found a non-finite value in run {run} "
                                  "(a flagged run cannot be continued)")
    integrator = state.integrator
    if integrator is None:
        return
    if not isinstance(integrator, IntegratorState):
        raise SimulationError(f"initial_state.integrator: found {type(integrator).__name__}, expected an "
                              "IntegratorState or None")
    expected = {"position": (batch, ndof), "velocity": (batch, ndof), "acceleration": (batch, ndof),
                "base_displacement": (batch,), "base_velocity": (batch,), "force_scale": (batch,),
                "jenkin_force": (batch, ndof, arrays.jk.shape[1]),
                "maxwell_elongation": (batch, ndof, arrays.mk.shape[1]), "boucwen_z": (batch, ndof)}
    for name, shape in expected.items():
        values = np.asarray(getattr(integrator, name))
        if values.shape != shape or not np.all(np.isfinite(values)):
            raise SimulationError(f"initial_state.integrator.{name}: found shape {values.shape}, expected {shape} "
                                  "with finite values (the integrator part of a final_state of this system)")
    if not (np.isfinite(integrator.time_step) and integrator.time_step > 0):
        raise SimulationError(f"initial_state.integrator.time_step: found {integrator.time_step!r}, expected a "
                              "step > 0 s")


@accepts(impact_velocity=Reals(unit="m/s", optional=True), duration=Real(unit="s", gt=0),
         time_step=Real(unit="s", gt=0), initial_deflection=Reals(unit="m", optional=True), record_every=Whole(ge=1),
         error=SimulationError)
def free_fall(system, *, impact_velocity=None, drop_height=None, duration: float, time_step: float,
              gravity: bool | float = False, initial_deflection=None, record_every: int = 1,
              workers: int | None = None, executor=None) -> TimeResponse:
    """Conditioned free fall (SPEC 5): base fixed, every mass hits with the same velocity.

    Parameters
    ----------
    impact_velocity : array_like (batch,), m/s
        Velocity at impact, negative downward. A positive value is accepted on purpose: it
        throws the masses upward from the same state, so the run starts in tension (the mirror
        image of a drop, used for symmetry checks by :func:`idkit.responses.shock.shock_sweep`);
        0 sets the masses down without speed. Give this or ``drop_height``.
    drop_height : array_like (batch,), m
        Drop heights; ``v0 = -sqrt(2 g h)`` (eq. 3.19).
    duration, time_step : float, s
        The run covers at least ``duration``: it takes ``ceil(duration / time_step)`` steps of
        ``time_step`` (a ratio within 1e-9 of a whole number counts as that number), so it ends
        less than one step after ``duration`` and the step is never changed;
        ``response.time[-1]`` is the simulated end.
    gravity, initial_deflection : see :func:`simulate`.

    Examples
    --------
    >>> from idkit.models import SDOFSystem, VoigtModel
    >>> run = free_fall(SDOFSystem(1.0, VoigtModel(k=1e4, damping=0.0)), impact_velocity=-0.5,
    ...                 duration=0.1, time_step=0.03)
    >>> [round(float(t), 2) for t in run.time]
    [0.0, 0.03, 0.06, 0.09, 0.12]
    """
    if (impact_velocity is None) == (drop_height is None):
        raise SimulationError("free_fall: give exactly one of impact_velocity and drop_height")
    if drop_height is not None:
        v0 = np.atleast_1d(impact_velocity_from_height(drop_height))
    else:
        v0 = np.atleast_1d(impact_velocity)
    if v0.ndim != 1 or v0.size == 0:
        name = "impact_velocity" if drop_height is None else "drop_height"
        raise SimulationError(f"{name}: found shape {v0.shape}, expected one value or a 1-D batch of at least one")
    if time_step > duration:
        raise SimulationError(f"free_fall: found time_step={time_step!r} > duration={duration!r}, "
                              "expected a step <= the duration")
    if duration / time_step >= MAX_STEPS:
        raise SimulationError(f"free_fall: found duration={duration!r} / time_step={time_step!r} = "
                              f"{duration / time_step:.3g} steps, expected fewer than {MAX_STEPS:.0e}")
    arrays = system_arrays(system)
    _check_impact_force(arrays, v0, time_step, drop_height)
    n_steps = _steps_covering(duration, time_step)
    time = np.arange(n_steps + 1) * time_step
    ndof = arrays.ndof
    velocities = np.repeat(v0[:, None], ndof, axis=1)
    return unchecked(simulate)(system, time, initial_velocity=velocities, initial_deflection=initial_deflection,
                               gravity=gravity, record_every=record_every, workers=workers, executor=executor)


def _check_impact_force(arrays, v0, time_step: float, drop_height) -> None:
    """Refuse an impact whose arrest within one step gives forces beyond :data:`MAX_FORCE_SCALE`.

    The rule of every simulation (:func:`~idkit.simulate._arrays.force_scale`): total mass times an
    acceleration scale, plus the slip forces, must stay below ``sqrt`` of the largest float64, or
    the residual norm of a step can overflow. A base motion's scale is its largest velocity change
    over a step divided by the step; an impact's is ``|v0| / time_step``, the mass stopped within
    one step. ``drop_height=1e300`` (4.4e150 m/s) ran "ok" with 1e148 m of travel.
    """
    mass, slip = float(arrays.masses.sum()), float(arrays.jfc.sum())
    with np.errstate(over="ignore"):
        if not mass * STANDARD_GRAVITY + slip < MAX_FORCE_SCALE:
            return  # the system itself is refused by force_scale, naming its masses
    speed = np.abs(v0)
    with np.errstate(over="ignore", invalid="ignore"):
        forces = mass * (speed / time_step + STANDARD_GRAVITY) + slip
    bad = np.isfinite(speed) & ~(forces < MAX_FORCE_SCALE)
    if not bad.any():
        return
    index = int(np.flatnonzero(bad)[0])
    limit = max((MAX_FORCE_SCALE - slip) / mass - STANDARD_GRAVITY, 0.0) * time_step
    if drop_height is None:
        found = f"impact_velocity: found {float(v0[index]):.4g} m/s"
    else:
        found = (f"drop_height: found {float(np.ravel(drop_height)[index]):.4g} m "
                 f"(impact at {float(speed[index]):.4g} m/s)")
    with np.errstate(over="ignore"):
        height = limit**2 / (2.0 * STANDARD_GRAVITY)
    raise SimulationError(
        f"{found}: stopped within one time step of {time_step:.4g} s, the masses {mass:.4g} kg meet forces "
        f"of {float(forces[index]):.4g} N, whose squares overflow float64 in the integrator's residual norm; "
        f"expected |v0| below {limit:.4g} m/s (a drop height below {height:.4g} m) at this step, forces below "
        f"{MAX_FORCE_SCALE:.4g} N (the limit of every simulation)")


def _steps_covering(duration: float, time_step: float) -> int:
    """The fewest whole steps of ``time_step`` that cover ``duration`` (a ratio within a relative
    1e-9 of a whole number is that number: ``0.3 / 2e-5`` is 15000 steps, not 15001)."""
    ratio = duration / time_step
    nearest = round(ratio)
    return int(nearest if abs(ratio - nearest) <= 1e-9 * ratio else np.ceil(ratio))
