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
"""

from __future__ import annotations

import math
import threading

import numba
import numpy as np

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.models.laws import boucwen_substeps, boucwen_z_step, pinched_boucwen_z_step, pinched_substeps
from idkit.simulate._structured import (
    GENERIC,
    HYBRID,
    HYBRID_MODULATED,
    SDOF_IWAN,
    SDOF_IWAN_MODULATED,
    SDOF_MAXWELL,
    STRUCTURE_KEYS,
    commit_jenkin,
    commit_maxwell,
    jenkin_elements,
    jenkin_kind,
    step_hybrid,
    step_sdof,
)

FLAG_OK = 0
FLAG_NEGATIVE_STIFFNESS = 1
FLAG_NON_FINITE = 2
FLAG_NO_CONVERGENCE = 3
FLAG_REASONS = {
    FLAG_OK: "ok",
    FLAG_NEGATIVE_STIFFNESS: "negative local stiffness of the parallel spring (model outside its valid range)",
    FLAG_NON_FINITE: "non-finite state",
    FLAG_NO_CONVERGENCE: "Newton iteration of a step did not converge",
}

_NEWTON_MAX_ITER = 60
_RES_TOL = 1e-13
_BW_SUBSTEPS = 4


# Packed layout. Parameters P[j, row, i] of isolator j (0 below the top mass):
#   row 0: g1, g2, g3, c_visc, mgsum, n_jenkin, n_maxwell, Bouc-Wen[10] (columns 0..16),
#          slip modulation a, y_ref, 1 / y_ref, b (columns 17, 18, 19, 20), clearance gap (21),
#          rate-dependent slip r, 1 / v_ref (22, 23), Bouc-Wen pinching pinch, width, shift (24-26)
#   row 1: Jenkin stiffness, row 2: Jenkin slip force,
#   row 3: Maxwell stiffness, row 4: exp(-rate h), row 5: (1 - exp(-rate h)) / (rate h)
# States S[j, row, i]: row 0 Jenkin forces, row 1 Maxwell elongations,
#   row 2: [Bouc-Wen z, mbase, z of the last trial], row 3: the Jenkin forces of the last
#   trial (a step's last evaluation is at its end point: it commits them by a copy). Packing
#   keeps the number of arrays handed between the functions small. The steps and the isolator
#   force are compiled once each and called by every driver (numba's IR inlining re-types a
#   body at each call site: minutes of compile time); they allocate nothing, so they are compiled without reference counting
#   (``_nrt=False``: an array argument otherwise costs an atomic increment and decrement per
#   call) and with NumPy's error model (a division by zero gives inf/NaN, caught as a failed
#   Newton iteration or a non-finite state, instead of raising).
_P_WIDTH = 27
_MGSUM, _NJ, _NM, _BW, _SM = 4, 5, 6, 7, 17
_GAP, _RATE, _PINCH = 21, 22, 24


@numba.njit(cache=True)
def _pack(poly, cvisc, jk, jfc, mk, mrate, bw, sm, h):
    """Parameter block for step ``h`` (see the layout above); ``mgsum = sum k_i g_i``."""
    ndof = poly.shape[0]
    width = max(_P_WIDTH, jk.shape[1], mk.shape[1])
    packed = np.zeros((ndof, 6, width))
    for j in range(ndof):
        packed[j, 0, 0] = poly[j, 0]
        packed[j, 0, 1] = poly[j, 1]
        packed[j, 0, 2] = poly[j, 2]
        packed[j, 0, 3] = cvisc[j]
        n_jenkin = 0
        for i in range(jk.shape[1]):
            if jk[j, i] > 0.0:  # padding has zero stiffness; real ones are > 0
                packed[j, 1, n_jenkin] = jk[j, i]
                packed[j, 2, n_jenkin] = jfc[j, i]
                n_jenkin += 1
        n_maxwell = 0
        gain_sum = 0.0
        for i in range(mk.shape[1]):
            if mk[j, i] > 0.0:
                x = mrate[j, i] * h
                decay = math.exp(-x)
                gain = -math.expm1(-x) / x if x > 0.0 else 1.0
                packed[j, 3, n_maxwell] = mk[j, i]
                packed[j, 4, n_maxwell] = decay
                packed[j, 5, n_maxwell] = gain
                gain_sum += mk[j, i] * gain
                n_maxwell += 1
        packed[j, 0, _MGSUM] = gain_sum
        packed[j, 0, _NJ] = n_jenkin
        packed[j, 0, _NM] = n_maxwell
        for i in range(10):
            packed[j, 0, _BW + i] = bw[j, i]
        packed[j, 0, _SM] = sm[j, 0]
        packed[j, 0, _SM + 1] = sm[j, 1]
        packed[j, 0, _SM + 2] = 1.0 / sm[j, 1] if sm[j, 1] > 0.0 else 0.0  # the steps multiply by 1 / y_ref
        packed[j, 0, _SM + 3] = sm[j, 2]
        if sm.shape[1] >= 6:
            packed[j, 0, _GAP] = sm[j, 3]
            packed[j, 0, _RATE] = sm[j, 4]
            packed[j, 0, _RATE + 1] = 1.0 / sm[j, 5] if sm[j, 5] > 0.0 else 0.0
        if bw.shape[1] >= 13:
            for i in range(3):
                packed[j, 0, _PINCH + i] = bw[j, 10 + i]
    return packed


@numba.njit(cache=True)
def _pack_states(packed, jforce, mstate, bwz):
    """State block from Jenkin forces (N), Maxwell elongations (m) and Bouc-Wen z (N)."""
    ndof = packed.shape[0]
    width = max(3, jforce.shape[1], mstate.shape[1])
    states = np.zeros((ndof, 4, width))
    for j in range(ndof):
        for i in range(jforce.shape[1]):
            states[j, 0, i] = jforce[j, i]
        base = 0.0
        for i in range(int(packed[j, 0, _NM])):
            states[j, 1, i] = mstate[j, i]
            base += packed[j, 3, i] * packed[j, 4, i] * mstate[j, i]
        states[j, 2, 0] = bwz[j]
        states[j, 2, 1] = base
    return states


@numba.njit(cache=True, error_model="numpy", _nrt=False)
def _isolator_force(j, y, dy, vrel, h, P, S):
    """Force (N) and tangent (N/m, including 2 c / h) of isolator ``j`` at a trial deflection ``y``.

    ``dy`` is the deflection increment over the step, ``vrel`` the end-of-step deflection rate.
    The trial's Jenkin forces (``S[j, 3]``) and Bouc-Wen ``z`` (``S[j, 2, 2]``) are kept for
    :func:`_commit_isolator`; the committed states are not touched.
    """
    g1 = P[j, 0, 0]
    g2 = P[j, 0, 1]
    g3 = P[j, 0, 2]
    force = y * (g1 + y * (g2 + y * g3)) + P[j, 0, 3] * vrel
    tangent = g1 + y * (2.0 * g2 + 3.0 * g3 * y) + P[j, 0, 3] * 2.0 / h
    # the Jenkin elements: slip forces scaled by s(y) when the isolator's slip is modulated, behind a
    # clearance, or following the deflection rate (otherwise the plain stop operator: the same
    # numbers as s = 1, slope 0)
    kind = jenkin_kind(j, P)
    force, tangent = jenkin_elements(kind, j, y, dy, vrel, h, P, S, force, tangent)
    # Maxwell elements are affine in dy within a step: sum k_i u_i = mbase + mgsum dy
    # with mbase = sum k_i e_i u_i (start of step) and mgsum = sum k_i g_i.
    force += S[j, 2, 1] + P[j, 0, _MGSUM] * dy
    tangent += P[j, 0, _MGSUM]
    if P[j, 0, _BW] != 0.0:
        b_base = P[j, 0, _BW + 8]
        b_exp = P[j, 0, _BW + 9]
        k1 = P[j, 0, _BW + 1]
        k2 = P[j, 0, _BW + 2]
        k3 = P[j, 0, _BW + 3]
        # at least _BW_SUBSTEPS, more where the step is long against z's relaxation length (np.int64:
        # the same compiled functions as the model's history; a bare constant is typed as a literal)
        alpha, beta, gamma, exponent = P[j, 0, _BW + 4], P[j, 0, _BW + 5], P[j, 0, _BW + 6], P[j, 0, _BW + 7]
        pinch = P[j, 0, _PINCH]
        if pinch != 0.0:
            width = P[j, 0, _PINCH + 1]
            z, dz = pinched_boucwen_z_step(S[j, 2, 0], dy, alpha, beta, gamma, exponent, pinch, width,
                                           P[j, 0, _PINCH + 2],
                                           pinched_substeps(dy, alpha, beta, gamma, exponent, pinch, width,
                                                            np.int64(_BW_SUBSTEPS)))
        else:
            z, dz = boucwen_z_step(S[j, 2, 0], dy, alpha, beta, gamma, exponent,
                                   boucwen_substeps(dy, alpha, beta, gamma, exponent, np.int64(_BW_SUBSTEPS)))
        factor = b_base ** (b_exp * y)
        bw_force = factor * (y * (k1 + k2 * abs(y) + k3 * y * y) + z)
        force += bw_force
        tangent += math.log(b_base) * b_exp * bw_force + factor * (k1 + 2.0 * k2 * abs(y) + 3.0 * k3 * y * y + dz)
        S[j, 2, 2] = z
    return force, tangent


@numba.njit(cache=True, error_model="numpy", _nrt=False)
def _commit_isolator(j, dy, P, S):
    """Commit isolator ``j``'s internal states at the end of a converged step whose last
    evaluation of :func:`_isolator_force` was at the step's end point (increment ``dy``): its
    Jenkin forces and Bouc-Wen ``z`` are copied, the Maxwell elongations updated. One compiled
    function with no constant flag: a literal ``commit`` argument had numba compile the
    isolator force and the rig's residual twice each."""
    commit_jenkin(j, P, S)
    commit_maxwell(j, dy, P, S)
    if P[j, 0, _BW] != 0.0:
        S[j, 2, 0] = S[j, 2, 2]


@numba.njit(cache=True, inline="always")
def _forces(ndof, qn0, qn1, q0, q1, v0, v1, xb_old, xb_new, vb_new, h, P, S):
    """Forces and tangents ``(f0, t0, f1, t1)`` of the isolators for a trial state.

    Absolute coordinates: isolator 0 sits below mass 0, the last stands on the base. One call
    site of :func:`_isolator_force` (a loop over the isolators) keeps the compiled step small.
    """
    f0 = t0 = f1 = t1 = 0.0
    for j in range(ndof):
        if ndof == 2 and j == 0:
            y = q0 - q1
            dy = y - (qn0 - qn1)
            vrel = v0 - v1
        elif ndof == 1:
            y = q0 - xb_new
            dy = y - (qn0 - xb_old)
            vrel = v0 - vb_new
        else:
            y = q1 - xb_new
            dy = y - (qn1 - xb_old)
            vrel = v1 - vb_new
        f, t = _isolator_force(j, y, dy, vrel, h, P, S)
        if j == 0:
            f0 = f
            t0 = t
        else:
            f1 = f
            t1 = t
    return f0, t0, f1, t1


@numba.njit(cache=True, inline="always")
def _residual(ndof, m0, m1, qn0, qn1, vn0, vn1, an0, an1, q0, q1, h, load, xb_old, xb_new, vb_new, P, S):
    """Step residual ``M (a + g) + f`` at trial positions ``(q0, q1)``.

    Returns ``(r0, r1, t0, t1, magnitude)``: residuals (N), isolator tangents
    (N/m, including the viscous ``2 c / h``) and the size of the residual's terms
    (N), which sets its round-off floor.
    """
    c2 = 2.0 / h
    c4 = c2 * c2
    v0 = c2 * (q0 - qn0) - vn0
    a0 = c4 * (q0 - qn0) - 2.0 * c2 * vn0 - an0
    v1 = 0.0
    a1 = 0.0
    if ndof == 2:
        v1 = c2 * (q1 - qn1) - vn1
        a1 = c4 * (q1 - qn1) - 2.0 * c2 * vn1 - an1
    f0, t0, f1, t1 = _forces(ndof, qn0, qn1, q0, q1, v0, v1, xb_old, xb_new, vb_new, h, P, S)
    r0 = m0 * (a0 + load) + f0
    magnitude = m0 * (abs(a0) + abs(load) + c4 * (abs(q0) + abs(qn0))) + abs(f0)
    r1 = 0.0
    if ndof == 2:
        r1 = m1 * (a1 + load) - f0 + f1
        magnitude += m1 * (abs(a1) + abs(load) + c4 * (abs(q1) + abs(qn1))) + abs(f1)
    return r0, r1, t0, t1, magnitude


@numba.njit(cache=True, error_model="numpy", _nrt=False)
def _step(ndof, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale):
    """Advance one step in place; returns a flag (0 ok).

    ``state`` = ``[q0, q1, v0, v1, a0, a1]`` (absolute, top first); ``load`` is
    gravity in m/s^2; ``xb_old``, ``xb_new``, ``vb_new``: base displacement (m) at
    both ends of the step and base velocity (m/s) at its end.
    """
    qn0 = state[0]
    qn1 = state[1]
    vn0 = state[2]
    vn1 = state[3]
    an0 = state[4]
    an1 = state[5]
    c2 = 2.0 / h
    c4 = c2 * c2
    # constant-acceleration predictor, then at least one Newton correction, each direction
    # tried at full length and halved up to 40 times; one evaluation site, the specialised
    # steps' loop (idkit.simulate._structured), so the last evaluation is at the end point
    q0 = qn0 + h * vn0 + 0.5 * h * h * an0
    q1 = qn1 + h * vn1 + 0.5 * h * h * an1
    trial0 = q0
    trial1 = q1
    dq0 = 0.0
    dq1 = 0.0
    scale = 1.0
    rnorm = 0.0
    accepted_trials = -1  # -1 while the predictor is evaluated
    halvings = 0
    converged = False
    while True:
        r0, r1, t0, t1, magnitude = _residual(ndof, m0, m1, qn0, qn1, vn0, vn1, an0, an1, trial0, trial1, h, load,
                                              xb_old, xb_new, vb_new, P, S)
        new_norm = math.sqrt(r0 * r0 + r1 * r1)
        floor = _RES_TOL * (magnitude + force_scale)
        if accepted_trials >= 0:
            if new_norm < rnorm or new_norm <= floor:
                q0 = trial0
                q1 = trial1
                rnorm = new_norm
                if rnorm <= floor:
                    converged = True
                    break
                if abs(scale * dq0) + abs(scale * dq1) <= 1e-15 * (abs(q0) + abs(q1) + abs(qn0)):
                    converged = rnorm <= 1e3 * floor
                    break
                accepted_trials += 1
                if accepted_trials == _NEWTON_MAX_ITER:
                    break
            else:
                scale *= 0.5
                halvings += 1
                if halvings < 40:
                    trial0 = q0 + scale * dq0
                    trial1 = q1 + scale * dq1
                    continue
                q0 = trial0  # no decrease along the direction: stop where the search ended
                q1 = trial1
                rnorm = new_norm
                converged = rnorm <= 1e3 * floor
                break
        else:
            rnorm = new_norm
            accepted_trials = 0
        if ndof == 1:
            dq0 = -r0 / (c4 * m0 + t0)
            dq1 = 0.0
        else:
            j00 = c4 * m0 + t0
            j01 = -t0
            j11 = c4 * m1 + t0 + t1
            det = j00 * j11 - j01 * j01
            dq0 = -(j11 * r0 - j01 * r1) / det
            dq1 = -(j00 * r1 - j01 * r0) / det
        scale = 1.0
        halvings = 0
        trial0 = q0 + dq0
        trial1 = q1 + dq1
    if not converged:
        return FLAG_NO_CONVERGENCE
    v0 = c2 * (q0 - qn0) - vn0
    v1 = c2 * (q1 - qn1) - vn1 if ndof == 2 else 0.0
    # commit the internal states at the converged point (the last evaluation was there)
    for j in range(ndof):  # a loop: j typed as a variable (a constant j compiles a copy per value)
        if ndof == 2 and j == 0:
            dy = (q0 - q1) - (qn0 - qn1)
        elif ndof == 1:
            dy = (q0 - xb_new) - (qn0 - xb_old)
        else:
            dy = (q1 - xb_new) - (qn1 - xb_old)
        _commit_isolator(j, dy, P, S)
    state[0] = q0
    state[2] = v0
    state[4] = c4 * (q0 - qn0) - 2.0 * c2 * vn0 - an0
    if ndof == 2:
        state[1] = q1
        state[3] = v1
        state[5] = c4 * (q1 - qn1) - 2.0 * c2 * vn1 - an1
    for d in range(6):
        if not math.isfinite(state[d]):
            return FLAG_NON_FINITE
    for j in range(ndof):
        y = q0 - q1 if (ndof == 2 and j == 0) else (q0 if ndof == 1 else q1) - xb_new
        if P[j, 0, 0] + y * (2.0 * P[j, 0, 1] + 3.0 * P[j, 0, 2] * y) < 0.0:
            return FLAG_NEGATIVE_STIFFNESS
    return FLAG_OK


@numba.njit(cache=True)
def _isolator_forces_now(ndof, state, xb, vb, P, S, out):
    """Isolator forces (N) of the current ``state = [q0, q1, v0, v1, a0, a1]``."""
    for j in range(ndof):
        if ndof == 2 and j == 0:
            y = state[0] - state[1]
            vr = state[2] - state[3]
        else:
            y = state[j] - xb
            vr = state[2 + j] - vb
        f = y * (P[j, 0, 0] + y * (P[j, 0, 1] + y * P[j, 0, 2])) + P[j, 0, 3] * vr
        gap = P[j, 0, _GAP]
        for i in range(int(P[j, 0, _NJ])):
            if gap > 0.0:  # a clearance passes on the virtual force less its dead zone
                dead = P[j, 1, i] * gap
                virtual = S[j, 0, i]
                f += virtual - dead if virtual > dead else virtual + dead if virtual < -dead else 0.0
            else:
                f += S[j, 0, i]
        for i in range(int(P[j, 0, _NM])):
            f += P[j, 3, i] * S[j, 1, i]
        if P[j, 0, _BW] != 0.0:
            f += P[j, 0, _BW + 8] ** (P[j, 0, _BW + 9] * y) * (
                y * (P[j, 0, _BW + 1] + P[j, 0, _BW + 2] * abs(y) + P[j, 0, _BW + 3] * y * y) + S[j, 2, 0])
        out[j] = f


@numba.njit(cache=True)
def _initial_acceleration(ndof, masses, state, load, xb, vb, P, S):
    """Accelerations ``state[4:6]`` from equilibrium at t = 0 with the given internal states."""
    frc = np.zeros(2)
    _isolator_forces_now(ndof, state, xb, vb, P, S, frc)
    state[4] = -frc[0] / masses[0] - load
    if ndof == 2:
        state[5] = (frc[0] - frc[1]) / masses[1] - load


# Step dispatch. Each driver is compiled per structure (``structure`` is a constant of its
# closure) and calls that structure's step through an if-chain on it, written out in each
# driver: numba prunes the branches on the constant before typing, so a driver types and
# compiles its own step only. The call is direct on purpose: binding ``state``, ``P`` and ``S``
# to new variables first (a helper inlined into the driver did) makes numba increment and
# decrement their reference counts around every call, six atomic operations a step that its
# pruning cannot remove across the call (15-20 ns of a 20-40 ns step, measured).


def _compiled_per_structure(driver, structure: int):
    """``driver`` compiled (cached, releasing the GIL) under a name of its structure's own.

    numba names a compiled function by its qualified name and a counter of the process that
    compiled it, and keeps its cache index by the qualified name: the drivers of two
    structures compiled in two processes could come out under one name and share one index
    file. Each structure's driver now has its own name, symbols and cache files.
    """
    driver.__qualname__ = f"{driver.__qualname__}_{STRUCTURE_KEYS[structure]}"
    return numba.njit(cache=True, nogil=True)(driver)


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
            state = np.zeros(6)
            for d in range(ndof):
                state[d] = q0[b, d]
                state[2 + d] = v0[b, d]
            S = _pack_states(P, jforce0[b], mstate0[b], bwz0[b])
            _initial_acceleration(ndof, masses, state, gravity, base_disp[row, 0], base_vel[row, 0], P, S)
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
                # the step of the driver's structure, called directly (see "Step dispatch" above)
                if structure == SDOF_IWAN:
                    flag = step_sdof(1, m0, state, h, gravity, xb_old, xb_new, vb_new, P, S, scale)
                elif structure == SDOF_MAXWELL:
                    flag = step_sdof(2, m0, state, h, gravity, xb_old, xb_new, vb_new, P, S, scale)
                elif structure == HYBRID:
                    flag = step_hybrid(1, m0, m1, state, h, gravity, xb_old, xb_new, vb_new, P, S, scale)
                elif structure == SDOF_IWAN_MODULATED:
                    flag = step_sdof(3, m0, state, h, gravity, xb_old, xb_new, vb_new, P, S, scale)
                elif structure == HYBRID_MODULATED:
                    flag = step_hybrid(3, m0, m1, state, h, gravity, xb_old, xb_new, vb_new, P, S, scale)
                else:
                    flag = _step(ndof, m0, m1, state, h, gravity, xb_old, xb_new, vb_new, P, S, scale)
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
                for d in range(ndof):
                    end_q[b, d] = state[d]
                    end_v[b, d] = state[2 + d]
                    end_a[b, d] = state[4 + d]
                    for i in range(jforce0.shape[2]):
                        end_jforce[b, d, i] = S[d, 0, i]
                    for i in range(mstate0.shape[2]):
                        end_mstate[b, d, i] = S[d, 1, i]
                    end_bwz[b, d] = S[d, 2, 0]
        return rec_q, rec_v, rec_a, rec_f, flags, flag_step, end_q, end_v, end_a, end_jforce, end_mstate, end_bwz

    return _compiled_per_structure(run_time_batch, structure)


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
            omega = 2.0 * math.pi * freq[b]
            n_per = steps_per_period[b]
            h = 1.0 / (freq[b] * n_per)
            amp = amplitude[b]
            scale = force_scale[b]
            P = _pack(poly, cvisc, jk, jfc, mk, mrate, bw, sm, h)
            state = np.zeros(6)
            after = b - 1 if chain[b] and b > 0 and flags[b - 1] == FLAG_OK else b  # whose end state starts b
            if after == b:
                for d in range(ndof):
                    state[d] = q0[b, d]
                    state[2 + d] = v0[b, d]
                S = _pack_states(P, jforce0[b], mstate0[b], bwz0[b])
            else:
                # along an amplitude axis, the neighbour's state scaled to this amplitude (exact
                # where the response is linear); Jenkin forces kept within their slip limits
                ratio = amp / amplitude[after]
                for d in range(ndof):
                    state[d] = ratio * end_q[after, d]
                    state[2 + d] = ratio * end_v[after, d]
                    start_z[d] = ratio * end_bwz[after, d]
                    for i in range(jforce0.shape[2]):
                        start_j[d, i] = min(max(ratio * end_jforce[after, d, i], -jfc[d, i]), jfc[d, i])
                    for i in range(mstate0.shape[2]):
                        start_m[d, i] = ratio * end_mstate[after, d, i]
                S = _pack_states(P, start_j, start_m, start_z)
            _initial_acceleration(ndof, masses, state, 0.0, 0.0, amp * omega, P, S)
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
                    # the step of the driver's structure, called directly (see "Step dispatch" above)
                    if structure == SDOF_IWAN:
                        flag = step_sdof(1, m0, state, h, 0.0, base, xb_new, vb_new, P, S, scale)
                    elif structure == SDOF_MAXWELL:
                        flag = step_sdof(2, m0, state, h, 0.0, base, xb_new, vb_new, P, S, scale)
                    elif structure == HYBRID:
                        flag = step_hybrid(1, m0, m1, state, h, 0.0, base, xb_new, vb_new, P, S, scale)
                    elif structure == SDOF_IWAN_MODULATED:
                        flag = step_sdof(3, m0, state, h, 0.0, base, xb_new, vb_new, P, S, scale)
                    elif structure == HYBRID_MODULATED:
                        flag = step_hybrid(3, m0, m1, state, h, 0.0, base, xb_new, vb_new, P, S, scale)
                    else:
                        flag = _step(ndof, m0, m1, state, h, 0.0, base, xb_new, vb_new, P, S, scale)
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
                for d in range(ndof):
                    end_q[b, d] = state[d]
                    end_v[b, d] = state[2 + d]
                    end_bwz[b, d] = S[d, 2, 0]
                    for i in range(jforce0.shape[2]):
                        end_jforce[b, d, i] = S[d, 0, i]
                    for i in range(mstate0.shape[2]):
                        end_mstate[b, d, i] = S[d, 1, i]
        return (coeff, half_range, accel_peak, dcoeff, windows, change, converged, flags, end_q, end_v, end_jforce,
                end_mstate, end_bwz)

    return _compiled_per_structure(run_harmonic_batch, structure)


#: The generic drivers (every structure; the reference of the specialised ones).
run_time_batch = _time_kernel(GENERIC)
run_harmonic_batch = _harmonic_kernel(GENERIC)
_TIME_KERNELS = {GENERIC: run_time_batch}
_HARMONIC_KERNELS = {GENERIC: run_harmonic_batch}
_KERNELS_LOCK = threading.Lock()
#: Structures that run their specialised step (the others run the generic one); tests empty it
#: to run the generic kernel on the same inputs.
SPECIALISED = frozenset({SDOF_IWAN, SDOF_MAXWELL, HYBRID, SDOF_IWAN_MODULATED, HYBRID_MODULATED})


def time_kernel(structure: int):
    """:func:`run_time_batch` compiled for ``structure`` (generic if it is not in :data:`SPECIALISED`);
    one dispatcher per structure and process, so nothing is compiled twice."""
    structure = structure if structure in SPECIALISED else GENERIC
    with _KERNELS_LOCK:  # callers in several threads still share one dispatcher
        if structure not in _TIME_KERNELS:
            _TIME_KERNELS[structure] = _time_kernel(structure)
        return _TIME_KERNELS[structure]


def harmonic_kernel(structure: int):
    """:func:`run_harmonic_batch` compiled for ``structure`` (as :func:`time_kernel`)."""
    structure = structure if structure in SPECIALISED else GENERIC
    with _KERNELS_LOCK:
        if structure not in _HARMONIC_KERNELS:
            _HARMONIC_KERNELS[structure] = _harmonic_kernel(structure)
        return _HARMONIC_KERNELS[structure]


# ------------------------------------------------------------------------------------------
# Drop rig: a free chain of masses (top, [intermediate], bottom) above a unilateral floor


@numba.njit(cache=True, error_model="numpy", _nrt=False)
def _rig_residual(n, masses, qn, vn, an, q, h, load, P, S, k_c, c_c, r, diag, upper, forces):
    """Residuals ``r`` (N) of the rig's step at trial positions ``q`` and the tridiagonal Jacobian.

    Isolator ``j`` connects mass ``j`` (above) with mass ``j + 1``; the last mass meets the floor
    (height 0) through ``max(0, k_c p - c_c v)``, ``p = -q[n-1]`` the penetration. ``forces``
    receives the isolator forces and, last, the contact force (N). Returns the size of the
    residual's terms (N).
    """
    c2 = 2.0 / h
    c4 = c2 * c2
    magnitude = 0.0
    for d in range(n):
        a = c4 * (q[d] - qn[d]) - 2.0 * c2 * vn[d] - an[d]
        r[d] = masses[d] * (a + load)
        diag[d] = c4 * masses[d]
        upper[d] = 0.0
        magnitude += masses[d] * (abs(a) + abs(load) + c4 * (abs(q[d]) + abs(qn[d])))
    for j in range(n - 1):
        y = q[j] - q[j + 1]
        dy = y - (qn[j] - qn[j + 1])
        vrel = (c2 * (q[j] - qn[j]) - vn[j]) - (c2 * (q[j + 1] - qn[j + 1]) - vn[j + 1])
        f, t = _isolator_force(j, y, dy, vrel, h, P, S)
        r[j] += f
        r[j + 1] -= f
        diag[j] += t
        diag[j + 1] += t
        upper[j] = -t
        forces[j] = f
        magnitude += abs(f)
    last = n - 1
    contact = 0.0
    penetration = -q[last]
    if penetration > 0.0:
        v_last = c2 * (q[last] - qn[last]) - vn[last]
        contact = k_c * penetration - c_c * v_last
        if contact > 0.0:
            diag[last] += k_c + c_c * c2
        else:
            contact = 0.0
    r[last] -= contact
    forces[n - 1] = contact
    return magnitude + contact


@numba.njit(cache=True, error_model="numpy", _nrt=False)
def _rig_step(n, masses, q, v, a, h, load, P, S, k_c, c_c, force_scale, forces, work):
    """Advance the rig one step in place (average-acceleration Newmark); returns a flag."""
    qn = work[0]
    trial = work[1]
    r = work[2]
    diag = work[3]
    upper = work[4]
    dq = work[5]
    cprime = work[6]
    for d in range(n):
        qn[d] = q[d]
        trial[d] = q[d] + h * v[d] + 0.5 * h * h * a[d]
    magnitude = _rig_residual(n, masses, qn, v, a, trial, h, load, P, S, k_c, c_c, r, diag, upper, forces)
    rnorm = 0.0
    for d in range(n):
        rnorm += r[d] * r[d]
    rnorm = math.sqrt(rnorm)
    converged = False
    for _iteration in range(_NEWTON_MAX_ITER):
        # Thomas algorithm on the symmetric tridiagonal Jacobian
        cprime[0] = upper[0] / diag[0]
        dq[0] = -r[0] / diag[0]
        for d in range(1, n):
            denom = diag[d] - upper[d - 1] * cprime[d - 1]
            cprime[d] = upper[d] / denom if d < n - 1 else 0.0
            dq[d] = (-r[d] - upper[d - 1] * dq[d - 1]) / denom
        for d in range(n - 2, -1, -1):
            dq[d] -= cprime[d] * dq[d + 1]
        scale = 1.0
        accepted = False
        new_norm = rnorm
        for _ in range(40):
            for d in range(n):
                q[d] = trial[d] + scale * dq[d]
            magnitude = _rig_residual(n, masses, qn, v, a, q, h, load, P, S, k_c, c_c, r, diag, upper, forces)
            new_norm = 0.0
            for d in range(n):
                new_norm += r[d] * r[d]
            new_norm = math.sqrt(new_norm)
            if new_norm < rnorm or new_norm <= _RES_TOL * (magnitude + force_scale):
                accepted = True
                break
            scale *= 0.5
        step_size = 0.0
        size = 0.0
        for d in range(n):
            step_size += abs(scale * dq[d])
            size += abs(q[d]) + abs(qn[d])
            trial[d] = q[d]
        rnorm = new_norm
        if rnorm <= _RES_TOL * (magnitude + force_scale):
            converged = True
            break
        if not accepted or step_size <= 1e-15 * size:
            converged = rnorm <= 1e3 * _RES_TOL * (magnitude + force_scale)
            break
    if not converged:
        return FLAG_NO_CONVERGENCE
    # commit the internal states at the converged point (the last evaluation was there)
    for j in range(n - 1):
        _commit_isolator(j, (trial[j] - trial[j + 1]) - (qn[j] - qn[j + 1]), P, S)
    c2 = 2.0 / h
    c4 = c2 * c2
    for d in range(n):
        q[d] = trial[d]
        v_new = c2 * (q[d] - qn[d]) - v[d]
        a[d] = c4 * (q[d] - qn[d]) - 2.0 * c2 * v[d] - a[d]
        v[d] = v_new
        if not (math.isfinite(q[d]) and math.isfinite(v[d]) and math.isfinite(a[d])):
            return FLAG_NON_FINITE
    for j in range(n - 1):
        y = q[j] - q[j + 1]
        if P[j, 0, 0] + y * (2.0 * P[j, 0, 1] + 3.0 * P[j, 0, 2] * y) < 0.0:
            return FLAG_NEGATIVE_STIFFNESS
    return FLAG_OK


_RIG_HALVINGS = 4


@numba.njit(cache=True, error_model="numpy", _nrt=False)
def _rig_macro_step(n, masses, q, v, a, h, load, Ps, S, k_c, c_c, force_scale, forces, work, saved):
    """One step ``h`` of the rig, split into halves (recursively, to ``h / 2^_RIG_HALVINGS``)
    where the Newton iteration does not converge; returns a flag."""
    units = 1 << _RIG_HALVINGS  # the step in units of the smallest sub-step
    done = 0
    level = 0
    flag = FLAG_OK
    while done < units:
        for d in range(n):
            saved[0, d] = q[d]
            saved[1, d] = v[d]
            saved[2, d] = a[d]
        flag = _rig_step(n, masses, q, v, a, h / 2.0**level, load, Ps[level], S, k_c, c_c, force_scale, forces,
                         work)
        if flag == FLAG_OK:
            done += 1 << (_RIG_HALVINGS - level)
            # back to the coarser step once aligned with it
            while level > 0 and done % (1 << (_RIG_HALVINGS - level + 1)) == 0:
                level -= 1
            continue
        for d in range(n):  # internal states are only committed by a converged step
            q[d] = saved[0, d]
            v[d] = saved[1, d]
            a[d] = saved[2, d]
        if flag != FLAG_NO_CONVERGENCE or level == _RIG_HALVINGS:
            return flag
        level += 1
    return flag


@numba.njit(cache=True, nogil=True)
def run_drop_batch(masses, poly, cvisc, jk, jfc, mk, mrate, bw, sm, h, n_steps, max_steps, gravity, q0, jforce0,
                   mstate0, bwz0, k_contact, c_contact, record_every, force_scale):
    """Drop-rig runs from rest: masses ``(n,)`` top first, the last one (bottom) meets the floor.

    Parameters (float64 arrays unless said)
    ----------
    masses : (n,) kg, ``n`` = 2 or 3; isolator ``j`` sits between mass ``j`` and ``j + 1``.
    poly ... sm : isolator arrays (``n - 1`` rows) as for :func:`run_time_batch`.
    n_steps : int64 (batch,) steps of each member; max_steps : int, at least their maximum (sets
        the record length, common to every chunk of a batch).
    q0 : (batch, n) initial heights (m) above the floor, at rest.
    jforce0, mstate0, bwz0 : initial internal states, shapes (batch, n-1, nj), (batch, n-1, nm),
        (batch, n-1).
    k_contact, c_contact : floor contact stiffness (N/m) and damping (N s/m).

    Returns
    -------
    q, v, a : (batch, n, n_records) absolute heights (m), velocities (m/s), kinematic
        accelerations (m/s^2); force : (batch, n, n_records) isolator forces (N, tension
        positive) and, in the last row, the contact force (N, >= 0); first_contact :
        (batch,) step of the first contact (-1 if none); flags, flag_step : (batch,).
    """
    batch = q0.shape[0]
    n = masses.shape[0]
    n_records = max_steps // record_every + 1
    rec_q = np.full((batch, n, n_records), np.nan)
    rec_v = np.full((batch, n, n_records), np.nan)
    rec_a = np.full((batch, n, n_records), np.nan)
    rec_f = np.full((batch, n, n_records), np.nan)
    first_contact = np.full(batch, -1, dtype=np.int64)
    flags = np.zeros(batch, dtype=np.int64)
    flag_step = np.full(batch, -1, dtype=np.int64)
    # parameter blocks for the step and its halvings (a step whose Newton iteration stalls at a
    # kink of the contact or slip laws is retried as two half steps, down to h / 2^_RIG_HALVINGS)
    P0 = _pack(poly, cvisc, jk, jfc, mk, mrate, bw, sm, h)
    Ps = np.zeros((_RIG_HALVINGS + 1, P0.shape[0], P0.shape[1], P0.shape[2]))
    for level in range(_RIG_HALVINGS + 1):
        packed = _pack(poly, cvisc, jk, jfc, mk, mrate, bw, sm, h / 2.0**level)
        # element-wise copy: an array assignment compiles numba's shape-mismatch error path,
        # seconds of compile time for a case that cannot occur (same shapes)
        for j in range(P0.shape[0]):
            for row in range(P0.shape[1]):
                for i in range(P0.shape[2]):
                    Ps[level, j, row, i] = packed[j, row, i]
    P = Ps[0]
    work = np.zeros((7, n))
    forces = np.zeros(n)
    saved = np.zeros((3, n))
    for b in range(batch):
        S = _pack_states(P, jforce0[b], mstate0[b], bwz0[b])
        q = np.zeros(n)
        v = np.zeros(n)
        a = np.zeros(n)
        for d in range(n):
            q[d] = q0[b, d]
        # initial accelerations from the forces at rest (zero step: no increment, no rate)
        _rig_residual(n, masses, q, v, a, q, 1.0, 0.0, P, S, k_contact, c_contact, work[2], work[3], work[4], forces)
        for d in range(n):
            a[d] = -work[2][d] / masses[d] - gravity
            rec_q[b, d, 0] = q[d]
            rec_v[b, d, 0] = 0.0
            rec_a[b, d, 0] = a[d]
            rec_f[b, d, 0] = forces[d]
        for step in range(1, n_steps[b] + 1):
            flag = _rig_macro_step(n, masses, q, v, a, h, gravity, Ps, S, k_contact, c_contact, force_scale, forces,
                                   work, saved)
            if flag != FLAG_OK:
                flags[b] = flag
                flag_step[b] = step
                break
            if first_contact[b] < 0 and q[n - 1] < 0.0:
                first_contact[b] = step
            if step % record_every == 0:
                k = step // record_every
                for d in range(n):
                    rec_q[b, d, k] = q[d]
                    rec_v[b, d, k] = v[d]
                    rec_a[b, d, k] = a[d]
                    rec_f[b, d, k] = forces[d]
    return rec_q, rec_v, rec_a, rec_f, first_contact, flags, flag_step
