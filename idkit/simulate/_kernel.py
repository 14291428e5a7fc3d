"""Compiled time stepping of base-excited isolator systems (numba).

Scheme (documented in ``docs/simulator.md``):

* Mechanics: average-acceleration Newmark (trapezoidal rule, beta = 1/4,
  gamma = 1/2) in absolute mass coordinates ``q``, ``M q'' + f(q - x_b, q' - v_b) =
  -M g``; the base enters through the exact base displacement and velocity at
  the step ends, so a small response to a large base motion is not computed as
  the difference of two large numbers. Unconditionally stable and second-order accurate, so the
  small intermediate mass of the hybrid does not force small steps.
* Constitutive updates, exact for deflection linear over a step: the Jenkin
  stop operator ``F <- clip(F + k dy, -Fc, Fc)`` (with a slip modulation, ``Fc`` is
  ``s(y) Fc`` at the end-of-step deflection, ``s(y) = 1 - a t + b t^2``, ``t = tanh(y / y_ref)``, an element
  force above a shrunken limit is clipped to it: :mod:`idkit.models.iwan_modulated`) and the
  Maxwell exponential
  update ``u <- e u + g dy`` with ``e = exp(-rate h)``, ``g = (1 - e) / (rate h)``. Behind a
  clearance the stop operator runs on the elements' virtual forces and passes on their dead zone;
  rate-dependent slip forces are taken at the end-of-step deflection rate (docs/elements.md).
  Bouc-Wen's ``z`` (pinched or not) is advanced by Runge-Kutta sub-steps in deflection.
* The implicit equation of each step is solved by Newton's method with the
  consistent tangent and backtracking (the residual is monotone while every
  local stiffness is non-negative).

A run that leaves the model's valid range stops and reports a flag; the other
members of the batch go on.

Here: the one step dispatcher (:func:`structure_step`) and the drivers compiled per structure
(:data:`time_kernel`: a time grid, :data:`harmonic_kernel`: harmonic base motion to steady state). The steps are in
:mod:`idkit.simulate._structured` (one per structure) and :mod:`idkit.simulate._generic_step`
(every other system), the packed layout of parameters and states they read in
:mod:`idkit.simulate._layout`; the drop rig's chain of masses in :mod:`idkit.simulate._rig_kernel`.
"""

from __future__ import annotations

import math
import threading

import numba
import numpy as np
from numba.core import types
from numba.extending import overload

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.simulate._generic_step import _initial_acceleration, _isolator_forces_now, _step
from idkit.simulate._layout import _pack, _pack_states
from idkit.simulate._structured import (
    FLAG_NEGATIVE_STIFFNESS,
    FLAG_NO_CONVERGENCE,
    FLAG_NON_FINITE,
    FLAG_OK,
    GENERIC,
    HYBRID,
    HYBRID_MODULATED,
    SDOF_IWAN,
    SDOF_IWAN_MODULATED,
    SDOF_MAXWELL,
    STRUCTURE_KEYS,
    step_hybrid,
    step_sdof,
)

#: What each flag of a step says (the flags: :mod:`idkit.simulate._structured`).
FLAG_REASONS = {
    FLAG_OK: "ok",
    FLAG_NEGATIVE_STIFFNESS: "negative local stiffness of the parallel spring (model outside its valid range)",
    FLAG_NON_FINITE: "non-finite state",
    FLAG_NO_CONVERGENCE: "Newton iteration of a step did not converge",
}


# The steps and the isolator force are compiled once each and called by every driver (numba's IR
# inlining re-types a body at each call site: minutes of compile time); they allocate nothing,
# so they are compiled without reference counting (``_nrt=False``: an array argument otherwise
# costs an atomic increment and decrement per call) and with NumPy's error model (a division
# by zero gives inf/NaN, caught as a failed Newton iteration or a non-finite state, instead of
# raising). The packed parameters and states they read: :mod:`idkit.simulate._layout`.


@numba.njit(cache=True)
def start_member(ndof, masses, q, v, jforce, mstate, bwz, load, xb, vb, P):
    """A member's ``state = [q0, q1, v0, v1, a0, a1]`` and state block ``S`` at its start:
    displacements ``q`` (m) and velocities ``v`` (m/s) of its masses, internal states ``jforce``
    (N), ``mstate`` (m), ``bwz`` (N) in the layout of a driver's inputs, and the accelerations of
    equilibrium there (gravity ``load`` in m/s^2, base at ``xb`` (m) moving at ``vb`` (m/s))."""
    state = np.zeros(6)
    for d in range(ndof):
        state[d] = q[d]
        state[2 + d] = v[d]
    S = _pack_states(P, jforce, mstate, bwz)
    _initial_acceleration(ndof, masses, state, load, xb, vb, P, S)
    return state, S


@numba.njit(cache=True)
def harmonic_member(b, freq, steps_per_period, amplitude, poly, cvisc, jk, jfc, mk, mrate, bw, sm):
    """Member ``b`` of a harmonic batch: its angular frequency (rad/s), steps per period, step
    ``h = 1 / (freq n_per)`` (s), base amplitude (m) and its parameters packed for ``h``."""
    n_per = steps_per_period[b]
    h = 1.0 / (freq[b] * n_per)
    return 2.0 * math.pi * freq[b], n_per, h, amplitude[b], _pack(poly, cvisc, jk, jfc, mk, mrate, bw, sm, h)


@numba.njit(cache=True, _nrt=False)
def _store_end_state(b, ndof, state, S, end_q, end_v, end_jforce, end_mstate, end_bwz):
    """Member ``b``'s state after its last step into a driver's outputs, in the layout of the
    driver's inputs: displacements and velocities (m, m/s) from ``state``, Jenkin forces (N),
    Maxwell elongations (m) and Bouc-Wen ``z`` (N) from ``S``."""
    for d in range(ndof):
        end_q[b, d] = state[d]
        end_v[b, d] = state[2 + d]
        end_bwz[b, d] = S[d, 2, 0]
        for i in range(end_jforce.shape[2]):
            end_jforce[b, d, i] = S[d, 0, i]
        for i in range(end_mstate.shape[2]):
            end_mstate[b, d, i] = S[d, 1, i]


# Step dispatch. Each driver (the time and harmonic drivers below, the period map's, the
# parameter sets') is compiled per structure, ``structure`` a constant of its
# closure, and calls :func:`structure_step` with it: the call resolves at compile time to that
# structure's step alone, so a driver types and compiles its own step only. The resolved
# function is a separate compiled function without reference counting that LLVM inlines into
# the driver: the driver passes ``state``, ``P`` and ``S`` straight through. (A numba
# ``inline="always"`` helper binds them to new variables first, and the driver then increments
# and decrements their reference counts around every step.)

#: Structures that run their own step and its kind argument; the others run the generic
#: :func:`_step`.
_OWN_STEPS = {SDOF_IWAN: (step_sdof, 1), SDOF_MAXWELL: (step_sdof, 2), SDOF_IWAN_MODULATED: (step_sdof, 3),
              HYBRID: (step_hybrid, 1), HYBRID_MODULATED: (step_hybrid, 3)}
#: Structures that run their specialised step (the others run the generic one); tests empty it
#: to run the generic drivers on the same inputs.
SPECIALISED = frozenset(_OWN_STEPS)


def _own_step(structure: int):
    """The step of ``structure`` (generic unless it has its own) with the arguments of
    :func:`structure_step`."""
    step, kind = _OWN_STEPS.get(structure, (_step, 0))
    if step is step_sdof:
        def own(structure, ndof, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale):
            return step_sdof(kind, m0, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale)
    elif step is step_hybrid:
        def own(structure, ndof, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale):
            return step_hybrid(kind, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale)
    else:
        def own(structure, ndof, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale):
            return _step(ndof, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale)
    return own


def structure_step(structure, ndof, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale):
    """Advance one step of a system of ``structure`` in place; returns a flag (0 ok).

    The arguments are :func:`_step`'s after the structure. Called from a driver compiled per
    structure (``structure`` a constant there), it runs that structure's own step
    (:mod:`idkit.simulate._structured`; :func:`_step` for the others) and compiles no other.
    """
    return _own_step(structure)(structure, ndof, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale)


@overload(structure_step, prefer_literal=True, jit_options={"error_model": "numpy", "_nrt": False})
def _structure_step_typed(structure, ndof, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale):
    """The compiled :func:`structure_step`: the step of a constant ``structure`` (none else)."""
    if isinstance(structure, types.IntegerLiteral):
        return _own_step(structure.literal_value)
    return None


def drivers_per_structure(factory):
    """``structure -> compiled driver`` from a driver ``factory(structure)`` (a Python function
    whose closure holds ``structure``): the driver of ``structure``, or the generic one if it is
    not in :data:`SPECIALISED` (read at each call); one dispatcher per structure and process, so
    nothing is compiled twice, shared by threads.

    Each driver is compiled (cached, releasing the GIL) under a name of its structure's own:
    numba names a compiled function by its qualified name and a counter of the process that
    compiled it, and keeps its cache index by the qualified name, so the drivers of two
    structures compiled in two processes could otherwise come out under one name and share one
    index file.
    """
    compiled = {}
    lock = threading.Lock()

    def driver_of(structure: int):
        structure = structure if structure in SPECIALISED else GENERIC
        with lock:
            if structure not in compiled:
                driver = factory(structure)
                driver.__qualname__ = f"{driver.__qualname__}_{STRUCTURE_KEYS[structure]}"
                compiled[structure] = numba.njit(cache=True, nogil=True)(driver)
            return compiled[structure]

    return driver_of


def _time_kernel(structure):
    """The compiled :func:`run_time_batch` of one structure (:mod:`idkit.simulate._structured`)."""

    def run_time_batch(masses, poly, cvisc, jk, jfc, mk, mrate, bw, sm, h, base_disp, base_vel, gravity,
                       q0, v0, jforce0, mstate0, bwz0, record_every, force_scale, a0):
        """Simulate a batch on a common time grid; record every ``record_every`` steps.

        Parameters (arrays are float64)
        ----------
        base_disp, base_vel : (n_base, n_steps + 1) base displacement (m) and velocity
            (m/s) at every step time; ``n_base`` is 1 (shared) or the batch size.
        q0, v0 : (batch, ndof) initial absolute displacement (m) and velocity (m/s).
        jforce0 : (batch, ndof, nj) initial Jenkin forces (N); mstate0 : (batch, ndof, nm)
            initial Maxwell elongations (m); bwz0 : (batch, ndof) initial Bouc-Wen z (N).
        force_scale : (batch,) each run's force magnitude (N) for its convergence tests
            (:func:`idkit.simulate._arrays.force_scale`): a run's records do not depend on the
            other runs of the batch.
        a0 : (batch, ndof) initial absolute accelerations (m/s^2) of a continued run (the
            integrator's own, ``end_a`` of the run it continues); a NaN row: from equilibrium.

        Returns
        -------
        q, v, a, force : (batch, ndof, n_records) absolute records and isolator forces;
        flags, flag_step : (batch,);
        end_q, end_v, end_a : (batch, ndof) absolute displacement (m), velocity (m/s) and
        acceleration (m/s^2) after the last step, end_jforce (batch, ndof, nj), end_mstate
        (batch, ndof, nm), end_bwz (batch, ndof): the internal states there, in the layout of
        the inputs (NaN for a flagged run)
        """
        batch = q0.shape[0]
        ndof = masses.shape[0]
        m0 = masses[0]
        m1 = masses[1] if ndof == 2 else 1.0
        n_steps = base_disp.shape[1] - 1
        n_records = n_steps // record_every + 1
        rec_q = np.full((batch, ndof, n_records), np.nan)
        rec_v = np.full((batch, ndof, n_records), np.nan)
        rec_a = np.full((batch, ndof, n_records), np.nan)
        rec_f = np.full((batch, ndof, n_records), np.nan)
        flags = np.zeros(batch, dtype=np.int64)
        flag_step = np.full(batch, -1, dtype=np.int64)
        end_q = np.full((batch, ndof), np.nan)
        end_v = np.full((batch, ndof), np.nan)
        end_a = np.full((batch, ndof), np.nan)
        end_jforce = np.full((batch, ndof, jforce0.shape[2]), np.nan)
        end_mstate = np.full((batch, ndof, mstate0.shape[2]), np.nan)
        end_bwz = np.full((batch, ndof), np.nan)
        P = _pack(poly, cvisc, jk, jfc, mk, mrate, bw, sm, h)
        frc = np.zeros(2)
        for b in range(batch):
            row = np.int64(b) if base_disp.shape[0] > 1 else np.int64(0)
            scale = force_scale[b]
            state, S = start_member(ndof, masses, q0[b], v0[b], jforce0[b], mstate0[b], bwz0[b], gravity,
                                    base_disp[row, 0], base_vel[row, 0], P)
            if not math.isnan(a0[b, 0]):  # a continued run: the trapezoidal rule's own accelerations
                for d in range(ndof):
                    state[4 + d] = a0[b, d]
            _isolator_forces_now(ndof, state, base_disp[row, 0], base_vel[row, 0], P, S, frc)
            for d in range(ndof):
                rec_q[b, d, 0] = state[d]
                rec_v[b, d, 0] = state[2 + d]
                rec_a[b, d, 0] = state[4 + d]
                rec_f[b, d, 0] = frc[d]
            until_record = record_every  # a countdown: an integer division per step cost ~15 ns
            r = 0
            for n in range(1, n_steps + 1):
                xb_old = base_disp[row, n - 1]
                xb_new = base_disp[row, n]
                vb_new = base_vel[row, n]
                flag = structure_step(structure, ndof, m0, m1, state, h, gravity, xb_old, xb_new, vb_new, P, S, scale)
                if flag != FLAG_OK:
                    flags[b] = flag
                    flag_step[b] = n
                    break
                until_record -= 1
                if until_record == 0:
                    until_record = record_every
                    r += 1
                    _isolator_forces_now(ndof, state, base_disp[row, n], base_vel[row, n], P, S, frc)
                    for d in range(ndof):
                        rec_q[b, d, r] = state[d]
                        rec_v[b, d, r] = state[2 + d]
                        rec_a[b, d, r] = state[4 + d]
                        rec_f[b, d, r] = frc[d]
            if flags[b] == FLAG_OK:
                _store_end_state(b, ndof, state, S, end_q, end_v, end_jforce, end_mstate, end_bwz)
                for d in range(ndof):
                    end_a[b, d] = state[4 + d]
        return rec_q, rec_v, rec_a, rec_f, flags, flag_step, end_q, end_v, end_a, end_jforce, end_mstate, end_bwz

    return run_time_batch


@numba.njit(cache=True)
def base_motion_table(n_per):
    """``sin`` and ``cos`` of the phases ``2 pi k / n_per`` of one excitation period of ``n_per``
    steps (``omega h = 2 pi / n_per``): the harmonic base motion read from a table instead of
    two sines and a cosine per step, with exact phases (``omega * step * h`` loses ~1e-12 rad
    after 4000 periods). Shared by the map's kernel and the period map's."""
    base_sin = np.empty(n_per)
    base_cos = np.empty(n_per)
    for k in range(n_per):
        angle = 2.0 * math.pi * k / n_per
        base_sin[k] = math.sin(angle)
        base_cos[k] = math.cos(angle)
    return base_sin, base_cos


def _harmonic_kernel(structure):
    """The compiled :func:`run_harmonic_batch` of one structure (:mod:`idkit.simulate._structured`)."""

    def run_harmonic_batch(masses, poly, cvisc, jk, jfc, mk, mrate, bw, sm, freq, amplitude, steps_per_period,
                           n_coeff, tolerance, min_windows, max_windows, force_scale, q0, v0, jforce0, mstate0, bwz0,
                           chain):
        """Run harmonic base displacement ``A sin(2 pi f t)`` to steady state, per member.

        From the initial state ``q0, v0`` (batch, ndof; absolute m and m/s) and internal
        states ``jforce0, mstate0, bwz0`` (zeros: at rest with unloaded isolators, thesis 3.4).
        Every window of two excitation periods, the Fourier coefficients of the
        absolute top displacement at multiples ``m/2`` of ``f`` (``m = 0 .. n_coeff-1``)
        are computed; the run stops when the change between consecutive windows,
        relative to the first-harmonic amplitude, and its geometric extrapolation to
        infinity are both below ``tolerance``.

        Returns
        -------
        coeff : complex (batch, n_coeff) amplitudes X_m with x(t) = Re(sum X_m exp(i m w t / 2))
            (X_0 is the mean), of the last window.
        half_range : (batch,) peak-peak/2 of the absolute top displacement (m), last window.
        accel_peak : (batch,) max |absolute top acceleration| (m/s^2), last window.
        deflection_coeff : complex (batch, n_coeff) same for the top deflection (q_top).
        windows, change, converged, flags.

        ``force_scale`` (batch,): each member's force magnitude (N) for its convergence tests
        (:func:`idkit.simulate._arrays.force_scale` of its own base acceleration), so a
        member's result does not depend on the other members of the batch.

        ``chain`` (batch,) bool: a member with ``chain[b]`` starts from the end state of member
        ``b - 1`` (its last window ends after whole periods, at the phase of t = 0) instead of
        its own initial state, unless that member was flagged: a stepped sweep, whose chains a
        caller keeps whole within one call. The end states ``end_q, end_v`` (batch, ndof),
        ``end_jforce``, ``end_mstate``, ``end_bwz`` (layout of the inputs; NaN for a flagged
        member) are returned after ``flags``.
        """
        batch = freq.shape[0]
        ndof = masses.shape[0]
        m0 = masses[0]
        m1 = masses[1] if ndof == 2 else 1.0
        coeff = np.zeros((batch, n_coeff), dtype=np.complex128)
        dcoeff = np.zeros((batch, n_coeff), dtype=np.complex128)
        half_range = np.full(batch, np.nan)
        accel_peak = np.full(batch, np.nan)
        windows = np.zeros(batch, dtype=np.int64)
        change = np.full(batch, np.nan)
        converged = np.zeros(batch, dtype=np.bool_)
        flags = np.zeros(batch, dtype=np.int64)
        end_q = np.full((batch, ndof), np.nan)
        end_v = np.full((batch, ndof), np.nan)
        end_jforce = np.full(jforce0.shape, np.nan)
        end_mstate = np.full(mstate0.shape, np.nan)
        end_bwz = np.full((batch, ndof), np.nan)
        start_j = np.empty(jforce0.shape[1:])
        start_m = np.empty(mstate0.shape[1:])
        start_z = np.empty(ndof)
        start_q = np.empty(ndof)
        start_v = np.empty(ndof)
        # the window's twiddle factors and the base motion's table depend on the steps per
        # period only: built once for a run of points with the same n_per (a map's points mostly
        # share it), from one table of cos / sin(2 pi k / window) indexed by m n mod window
        # (n_coeff x window trigonometric calls per point were about 30 us of a one-point call)
        table_n = -1
        cos_t = np.empty((n_coeff, 0))
        sin_t = np.empty((n_coeff, 0))
        base_sin = np.empty(0)
        base_cos = np.empty(0)
        for b in range(batch):
            omega, n_per, h, amp, P = harmonic_member(b, freq, steps_per_period, amplitude, poly, cvisc, jk, jfc, mk,
                                                      mrate, bw, sm)
            scale = force_scale[b]
            after = b - 1 if chain[b] and b > 0 and flags[b - 1] == FLAG_OK else b  # whose end state starts b
            if after == b:
                state, S = start_member(ndof, masses, q0[b], v0[b], jforce0[b], mstate0[b], bwz0[b], 0.0, 0.0,
                                        amp * omega, P)
            else:
                # along an amplitude axis, the neighbour's state scaled to this amplitude (exact
                # where the response is linear); Jenkin forces kept within their slip limits
                ratio = amp / amplitude[after]
                for d in range(ndof):
                    start_q[d] = ratio * end_q[after, d]
                    start_v[d] = ratio * end_v[after, d]
                    start_z[d] = ratio * end_bwz[after, d]
                    for i in range(jforce0.shape[2]):
                        start_j[d, i] = min(max(ratio * end_jforce[after, d, i], -jfc[d, i]), jfc[d, i])
                    for i in range(mstate0.shape[2]):
                        start_m[d, i] = ratio * end_mstate[after, d, i]
                state, S = start_member(ndof, masses, start_q, start_v, start_j, start_m, start_z, 0.0, 0.0,
                                        amp * omega, P)
            window = 2 * n_per
            if n_per != table_n:
                one_cos, one_sin = np.empty(window), np.empty(window)
                for k in range(window):
                    angle = 2.0 * math.pi * k / window
                    one_cos[k] = math.cos(angle)
                    one_sin[k] = math.sin(angle)
                cos_t = np.empty((n_coeff, window))
                sin_t = np.empty((n_coeff, window))
                for m in range(n_coeff):
                    for n in range(window):
                        k = (m * n) % window
                        cos_t[m, n] = one_cos[k]
                        sin_t[m, n] = one_sin[k]
                base_sin, base_cos = base_motion_table(n_per)
                table_n = n_per
            at = 0  # step % n_per
            previous = np.zeros(n_coeff, dtype=np.complex128)
            current = np.zeros(n_coeff, dtype=np.complex128)
            dcurrent = np.zeros(n_coeff, dtype=np.complex128)
            last_change = np.inf
            flag = FLAG_OK
            # the window's samples, transformed when it is complete (a tight loop per
            # coefficient instead of n_coeff complex updates between two steps)
            tops = np.empty(window)
            deflections = np.empty(window)
            for w in range(max_windows):
                lo = np.inf
                hi = -np.inf
                apeak = 0.0
                for n in range(window):
                    # sample at the start of the step (t = step * h), then advance
                    base = amp * base_sin[at]
                    top = state[0]
                    tops[n] = top
                    deflections[n] = top - base
                    lo = min(lo, top)
                    hi = max(hi, top)
                    apeak = max(apeak, abs(state[4]))
                    at = at + 1 if at + 1 < n_per else 0
                    xb_new = amp * base_sin[at]
                    vb_new = amp * omega * base_cos[at]
                    flag = structure_step(structure, ndof, m0, m1, state, h, 0.0, base, xb_new, vb_new, P, S, scale)
                    if flag != FLAG_OK:
                        break
                if flag != FLAG_OK:
                    break
                for m in range(n_coeff):
                    re, im, dre, dim = 0.0, 0.0, 0.0, 0.0
                    for n in range(window):
                        re += tops[n] * cos_t[m, n]
                        im -= tops[n] * sin_t[m, n]
                        dre += deflections[n] * cos_t[m, n]
                        dim -= deflections[n] * sin_t[m, n]
                    current[m] = complex(re, im)
                    dcurrent[m] = complex(dre, dim)
                for m in range(n_coeff):
                    scale = 1.0 / window if m == 0 else 2.0 / window
                    current[m] *= scale
                    dcurrent[m] *= scale
                first = abs(current[2]) if n_coeff > 2 else abs(current[0])
                diff = 0.0
                for m in range(n_coeff):
                    diff = max(diff, abs(current[m] - previous[m]))
                relative = diff / max(first, 1e-300)
                # geometric extrapolation of the remaining change: r/(1-r) * relative
                if relative == 0.0:
                    remaining = 0.0
                elif last_change > 0.0 and math.isfinite(last_change) and relative < last_change:
                    ratio = relative / last_change
                    remaining = relative * ratio / (1.0 - ratio)
                else:
                    remaining = np.inf
                last_change = relative
                for m in range(n_coeff):
                    previous[m] = current[m]
                windows[b] = w + 1
                change[b] = relative
                half_range[b] = 0.5 * (hi - lo)
                accel_peak[b] = apeak
                if w + 1 >= min_windows and relative < tolerance and remaining < tolerance:
                    converged[b] = True
                    break
            flags[b] = flag
            if flag != FLAG_OK:
                half_range[b] = np.nan
                accel_peak[b] = np.nan
                for m in range(n_coeff):
                    coeff[b, m] = np.nan
                    dcoeff[b, m] = np.nan
            else:
                for m in range(n_coeff):
                    coeff[b, m] = previous[m]
                    dcoeff[b, m] = dcurrent[m]
                _store_end_state(b, ndof, state, S, end_q, end_v, end_jforce, end_mstate, end_bwz)
        return (coeff, half_range, accel_peak, dcoeff, windows, change, converged, flags, end_q, end_v, end_jforce,
                end_mstate, end_bwz)

    return run_harmonic_batch


#: :func:`run_time_batch` compiled for a structure, one per structure and process
#: (:func:`idkit.simulate._kernel.drivers_per_structure`).
time_kernel = drivers_per_structure(_time_kernel)
#: :func:`run_harmonic_batch` compiled for a structure (as :data:`time_kernel`).
harmonic_kernel = drivers_per_structure(_harmonic_kernel)
#: The generic drivers (every structure; the reference of the specialised ones).
run_time_batch = time_kernel(GENERIC)
run_harmonic_batch = harmonic_kernel(GENERIC)
