"""The compiled drop rig: a free chain of masses (top, [intermediate], bottom) falling onto a
unilateral floor (:func:`run_drop_batch`, driven by :mod:`idkit.simulate.drop_rig`).

The isolators between the masses are the generic step's (:mod:`idkit.simulate._kernel`'s packed
parameters and states, :mod:`idkit.simulate._generic_step`'s force and commit); the chain's step is average-acceleration Newmark solved by Newton's
method on its tridiagonal Jacobian, halved where the iteration stalls at a kink of the contact
or slip laws.
"""

from __future__ import annotations

import math

import numba
import numpy as np

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.models.laws import polynomial_spring_stiffness
from idkit.simulate._generic_step import _commit_isolator, _isolator_force
from idkit.simulate._layout import _pack, _pack_states
from idkit.simulate._structured import (
    _NEWTON_MAX_ITER,
    _RES_TOL,
    FLAG_NEGATIVE_STIFFNESS,
    FLAG_NO_CONVERGENCE,
    FLAG_NON_FINITE,
    FLAG_OK,
)


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
        if polynomial_spring_stiffness(y, P[j, 0, 0], P[j, 0, 1], P[j, 0, 2]) < 0.0:
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
