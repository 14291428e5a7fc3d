"""The generic step (numba): one step of any system, every part of each isolator read off its
packed parameters at run time (:mod:`idkit.simulate._kernel` for the scheme,
:mod:`idkit.simulate._layout` for the layout).

Structures with a specialised step (:mod:`idkit.simulate._structured`) run the same operations
on their parts only; everything else (Bouc-Wen, pinched Bouc-Wen, clearance or rate-dependent
Jenkin elements, mixed isolators) runs :func:`_step`. The isolator force and its commit are
also the drop rig's (:mod:`idkit.simulate._rig_kernel`).
"""

from __future__ import annotations

import math

import numba
import numpy as np

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.models.laws import (
    boucwen_substeps,
    boucwen_z_step,
    pinched_boucwen_z_step,
    pinched_substeps,
    polynomial_spring_force,
    polynomial_spring_stiffness,
)
from idkit.simulate._layout import _BW, _GAP, _MGSUM, _NJ, _NM, _PINCH
from idkit.simulate._structured import (
    _RES_TOL,
    FLAG_NEGATIVE_STIFFNESS,
    FLAG_NO_CONVERGENCE,
    FLAG_NON_FINITE,
    FLAG_OK,
    SEARCH_END,
    SEARCH_HALVE,
    commit_jenkin,
    commit_maxwell,
    end_of_step,
    jenkin_elements,
    jenkin_kind,
    newton_search,
    two_mass_direction,
)

#: Bouc-Wen sub-steps of ``z`` per step at least (more where a step is long against z's
#: relaxation length: :func:`idkit.models.laws.boucwen_substeps`).
_BW_SUBSTEPS = 4


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
    force = polynomial_spring_force(y, g1, g2, g3) + P[j, 0, 3] * vrel
    tangent = polynomial_spring_stiffness(y, g1, g2, g3) + P[j, 0, 3] * 2.0 / h
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
    # constant-acceleration predictor, then damped Newton corrections (the line search of
    # idkit.simulate._structured.newton_search, as the specialised steps run it)
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
    while True:
        r0, r1, t0, t1, magnitude = _residual(ndof, m0, m1, qn0, qn1, vn0, vn1, an0, an1, trial0, trial1, h, load,
                                              xb_old, xb_new, vb_new, P, S)
        outcome, accepted_trials, halvings, scale, rnorm, converged = newton_search(
            accepted_trials, halvings, scale, math.sqrt(r0 * r0 + r1 * r1), rnorm,
            _RES_TOL * (magnitude + force_scale), abs(scale * dq0) + abs(scale * dq1),
            abs(trial0) + abs(trial1) + abs(qn0))
        if outcome == SEARCH_HALVE:
            trial0 = q0 + scale * dq0
            trial1 = q1 + scale * dq1
            continue
        q0 = trial0
        q1 = trial1
        if outcome == SEARCH_END:
            break
        if ndof == 1:
            dq0 = -r0 / (c4 * m0 + t0)
            dq1 = 0.0
        else:
            dq0, dq1 = two_mass_direction(c4, m0, m1, r0, r1, t0, t1)
        scale = 1.0
        halvings = 0
        trial0 = q0 + dq0
        trial1 = q1 + dq1
    if not converged:
        return FLAG_NO_CONVERGENCE
    # commit the internal states at the converged point (the last evaluation was there)
    for j in range(ndof):  # a loop: j typed as a variable (a constant j compiles a copy per value)
        if ndof == 2 and j == 0:
            dy = (q0 - q1) - (qn0 - qn1)
        elif ndof == 1:
            dy = (q0 - xb_new) - (qn0 - xb_old)
        else:
            dy = (q1 - xb_new) - (qn1 - xb_old)
        _commit_isolator(j, dy, P, S)
    end_of_step(state, 0, q0, qn0, vn0, an0, c2, c4)
    if ndof == 2:
        end_of_step(state, 1, q1, qn1, vn1, an1, c2, c4)
    for d in range(6):
        if not math.isfinite(state[d]):
            return FLAG_NON_FINITE
    for j in range(ndof):
        y = q0 - q1 if (ndof == 2 and j == 0) else (q0 if ndof == 1 else q1) - xb_new
        if polynomial_spring_stiffness(y, P[j, 0, 0], P[j, 0, 1], P[j, 0, 2]) < 0.0:
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
        f = polynomial_spring_force(y, P[j, 0, 0], P[j, 0, 1], P[j, 0, 2]) + P[j, 0, 3] * vr
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
