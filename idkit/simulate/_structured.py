"""Steps specialised to one system structure (numba), the same scheme as the generic step.

The generic step (:mod:`idkit.simulate._generic_step`) tests at run time which parts each isolator
has (Jenkin elements, Maxwell elements, Bouc-Wen, slip modulation) and how many masses the
system has; the compiled step carries every part. The steps here are written for one
structure each and carry only its parts:

* :data:`SDOF_IWAN`: one mass on an isolator of Jenkin elements (Iwan, the wire ropes), a
  cubic spring and a dashpot; :data:`SDOF_IWAN_MODULATED` the same with a slip modulation
  (:mod:`idkit.models.iwan_modulated`; a separate structure, so the plain rope's step does
  not carry the modulation's branch and multiplications);
* :data:`SDOF_MAXWELL`: one mass on Maxwell elements (generalized Maxwell, Voigt), a cubic
  spring and a dashpot;
* :data:`HYBRID`: the series hybrid, a Maxwell-only isolator under the top mass above an
  Iwan-only isolator on the base; :data:`HYBRID_MODULATED` with a slip-modulated Iwan there.

They perform the same floating-point operations as the generic step in the same order on the
parts the structure has (the generic step's absent parts add exact zeros), so both paths give
the same records to round-off; ``tests/simulate/test_structured_kernel.py`` runs both on the
same inputs. Any other structure (Bouc-Wen, pinched Bouc-Wen, clearance or rate-dependent Jenkin elements,
mixed isolators) runs the generic
step. A driver is compiled once per structure (:data:`idkit.simulate._kernel.time_kernel`) and
calls its step through :func:`idkit.simulate._kernel.structure_step` with the structure a
compile-time constant, so it compiles only the step it runs.
"""

from __future__ import annotations

import math

import numba

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)
from idkit.models.laws import polynomial_spring_force, polynomial_spring_stiffness
from idkit.simulate._layout import _COMMITTED, _GAP, _MGSUM, _NJ, _NM, _RATE, _SM, _TRIAL

GENERIC = 0
SDOF_IWAN = 1
SDOF_MAXWELL = 2
HYBRID = 3
SDOF_IWAN_MODULATED = 4
HYBRID_MODULATED = 5
STRUCTURE_NAMES = {GENERIC: "generic", SDOF_IWAN: "SDOF Iwan", SDOF_MAXWELL: "SDOF Maxwell",
                   HYBRID: "hybrid Maxwell over Iwan", SDOF_IWAN_MODULATED: "SDOF slip-modulated Iwan",
                   HYBRID_MODULATED: "hybrid Maxwell over slip-modulated Iwan"}
#: the structures as identifiers: the suffix of their drivers' compiled names
STRUCTURE_KEYS = {GENERIC: "generic", SDOF_IWAN: "sdof_iwan", SDOF_MAXWELL: "sdof_maxwell", HYBRID: "hybrid",
                  SDOF_IWAN_MODULATED: "sdof_iwan_modulated", HYBRID_MODULATED: "hybrid_modulated"}

# The flags every step returns (idkit.simulate._kernel.FLAG_REASONS says them) and the Newton
# settings of every step: defined here, below every kernel module that reads them.
FLAG_OK = 0
FLAG_NEGATIVE_STIFFNESS = 1
FLAG_NON_FINITE = 2
FLAG_NO_CONVERGENCE = 3
_NEWTON_MAX_ITER = 60
_RES_TOL = 1e-13

_IWAN = 1
_MAXWELL = 2
_IWAN_MODULATED = 3
_IWAN_CLEARANCE = 4
_IWAN_RATE = 5


def structure_of(arrays) -> int:
    """The specialised structure of a system's kernel arrays, or :data:`GENERIC`.

    ``arrays`` is a :class:`idkit.simulate._arrays.SystemArrays`.
    """
    kinds = []
    for j in range(arrays.ndof):
        jenkin = bool((arrays.jk[j] > 0.0).any())  # the method: a third of np.any's call overhead
        maxwell = bool((arrays.mk[j] > 0.0).any())
        modulated = arrays.sm[j, 0] != 0.0 or arrays.sm[j, 2] != 0.0
        other_slip_law = arrays.sm.shape[1] >= 6 and (arrays.sm[j, 3] != 0.0 or arrays.sm[j, 4] != 0.0)
        if arrays.bw[j, 0] != 0.0 or (jenkin and maxwell) or (modulated and maxwell) or other_slip_law:
            return GENERIC
        kinds.append(_MAXWELL if maxwell else _IWAN_MODULATED if modulated else _IWAN)
    if arrays.ndof == 1:
        return {_IWAN: SDOF_IWAN, _MAXWELL: SDOF_MAXWELL, _IWAN_MODULATED: SDOF_IWAN_MODULATED}[kinds[0]]
    if kinds == [_MAXWELL, _IWAN]:
        return HYBRID
    if kinds == [_MAXWELL, _IWAN_MODULATED]:
        return HYBRID_MODULATED
    return GENERIC


@numba.njit(cache=True, inline="always")
def jenkin_kind(j, P):
    """The slip law of isolator ``j``'s Jenkin elements read off its packed parameters: 3 modulated,
    4 behind a clearance, 5 rate-dependent, else 1 (constant slip forces)."""
    if P[j, 0, _SM] != 0.0 or P[j, 0, _SM + 3] != 0.0:
        return 3
    if P[j, 0, _GAP] != 0.0:
        return 4
    if P[j, 0, _RATE] != 0.0:
        return 5
    return 1


@numba.njit(cache=True, inline="always")
def jenkin_elements(kind, j, y, dy, vrel, h, P, S, force, tangent):
    """Add the Jenkin elements of isolator ``j`` to its ``force`` (N) and ``tangent`` (N/m);
    the one copy of the stop operator every step uses (the specialised steps with a constant
    ``kind``, the generic step with ``kind`` read off the isolator, :func:`jenkin_kind`).

    ``kind`` 1: constant slip forces; 3 (:data:`_IWAN_MODULATED`): slip forces ``s(y) fc`` with
    ``s(y) = 1 - a t + b t^2``, ``t = tanh(y / y_ref)``, at the end-of-step deflection, an element force above the
    shrunken limit clipped to it, and the limit's slope in the tangent of a slipping element;
    4 (:data:`_IWAN_CLEARANCE`): each element behind a clearance of half-width ``gap``: the
    stop operator runs on the virtual force (limits ``fc + k gap``, packed so) and passes on its
    dead zone of width ``k gap`` (:func:`idkit.models.laws.dead_zone`), tangent ``k`` only while
    in contact and sticking; 5 (:data:`_IWAN_RATE`): slip forces ``fc (1 + r tanh(|v| / v_ref))``
    at the end-of-step deflection rate ``vrel`` (m/s), whose derivative along the step is ``2 / h``
    (trapezoidal rule), in the tangent of a slipping element.
    The trial's element forces (virtual ones behind a clearance) are kept in ``S[j, 3]``
    (:data:`_TRIAL`); a step commits them by a copy once it has converged (:func:`commit_jenkin`:
    its last evaluation is at the converged point).
    """
    if kind == 4:
        gap = P[j, 0, _GAP]
        for i in range(int(P[j, 0, _NJ])):
            stiffness = P[j, 1, i]
            trial = S[j, 0, i] + stiffness * dy
            limit = P[j, 2, i]
            sticking = True
            if trial > limit:
                trial = limit
                sticking = False
            elif trial < -limit:
                trial = -limit
                sticking = False
            S[j, _TRIAL, i] = trial
            dead = stiffness * gap
            if trial > dead:
                force += trial - dead
            elif trial < -dead:
                force += trial + dead
            else:
                sticking = False  # within the clearance: no force, no stiffness
            if sticking:
                tangent += stiffness
    elif kind == 5 or kind == 3:
        if kind == 5:
            gain = P[j, 0, _RATE]
            inverse_speed = P[j, 0, _RATE + 1]  # 1 / v_ref, packed once
            x = abs(vrel) * inverse_speed
            e = math.exp(-2.0 * x)
            th = (1.0 - e) / (1.0 + e)  # tanh(x), x >= 0, as the modulated law computes it
            slip_scale = 1.0 + gain * th
            slip_slope = gain * (1.0 - th * th) * inverse_speed * (2.0 / h)
            if vrel < 0.0:
                slip_slope = -slip_slope
        else:
            # tanh(x) = (1 - e) / (1 + e) with e = exp(-2 |x|): within 2.3e-16 of libm's tanh and
            # cheaper; it runs at every Newton evaluation
            inverse_length = P[j, 0, _SM + 2]  # 1 / y_ref, packed once
            x = y * inverse_length
            e = math.exp(-2.0 * abs(x))
            th = (1.0 - e) / (1.0 + e)
            if x < 0.0:
                th = -th
            growth = P[j, 0, _SM + 3]
            slip_scale = 1.0 + th * (growth * th - P[j, 0, _SM])
            slip_slope = (2.0 * growth * th - P[j, 0, _SM]) * (1.0 - th * th) * inverse_length
        for i in range(int(P[j, 0, _NJ])):  # limits slip_scale fc_i, their slope in a slipping element's tangent
            trial = S[j, 0, i] + P[j, 1, i] * dy
            limit = P[j, 2, i] * slip_scale
            if trial > limit:
                trial = limit
                tangent += P[j, 2, i] * slip_slope
            elif trial < -limit:
                trial = -limit
                tangent -= P[j, 2, i] * slip_slope
            else:
                tangent += P[j, 1, i]
            force += trial
            S[j, _TRIAL, i] = trial
    else:
        for i in range(int(P[j, 0, _NJ])):
            trial = S[j, 0, i] + P[j, 1, i] * dy
            limit = P[j, 2, i]
            if trial > limit:
                trial = limit
            elif trial < -limit:
                trial = -limit
            else:
                tangent += P[j, 1, i]
            force += trial
            S[j, _TRIAL, i] = trial
    return force, tangent


@numba.njit(cache=True, inline="always")
def _part_force(kind, j, y, dy, vrel, h, P, S):
    """Force (N) and tangent (N/m) of isolator ``j`` made of the parts ``kind`` only at a trial
    deflection; the same operations as the generic ``_isolator_force`` (a constant ``kind``: the
    other branch is pruned). Jenkin element forces go to the trial row; nothing is committed."""
    force = polynomial_spring_force(y, P[j, 0, 0], P[j, 0, 1], P[j, 0, 2]) + P[j, 0, 3] * vrel
    tangent = polynomial_spring_stiffness(y, P[j, 0, 0], P[j, 0, 1], P[j, 0, 2]) + P[j, 0, 3] * 2.0 / h
    if kind == 1 or kind == 3:  # _IWAN, _IWAN_MODULATED (literals: numba prunes the other branches)
        force, tangent = jenkin_elements(kind, j, y, dy, vrel, h, P, S, force, tangent)
    else:
        force += S[j, 2, 1] + P[j, 0, _MGSUM] * dy
        tangent += P[j, 0, _MGSUM]
    return force, tangent


@numba.njit(cache=True, inline="always")
def commit_jenkin(j, P, S):
    """Commit the Jenkin forces of isolator ``j``'s last evaluation (a step's last evaluation is
    at the point it ends on); every step's commit (specialised, generic, drop rig)."""
    for i in range(int(P[j, 0, _NJ])):
        S[j, _COMMITTED, i] = S[j, _TRIAL, i]


@numba.njit(cache=True, inline="always")
def commit_maxwell(j, dy, P, S):
    """Advance isolator ``j``'s Maxwell elongations over a converged step of increment ``dy``
    (``u <- e u + g dy``) and keep ``sum k_i e_i u_i`` for the next step's force; every
    step's commit."""
    base = 0.0
    for i in range(int(P[j, 0, _NM])):
        u = P[j, 4, i] * S[j, 1, i] + P[j, 5, i] * dy
        S[j, 1, i] = u
        base += P[j, 3, i] * P[j, 4, i] * u
    S[j, 2, 1] = base


@numba.njit(cache=True, inline="always")
def _commit_part(kind, j, dy, P, S):
    """Commit isolator ``j``'s internal states at the converged point: its Jenkin forces, or
    its Maxwell elongations after the increment ``dy``."""
    if kind == 1 or kind == 3:
        commit_jenkin(j, P, S)
    else:
        commit_maxwell(j, dy, P, S)


@numba.njit(cache=True, inline="always")
def _residual_sdof(kind, m0, qn0, vn0, an0, q0, h, c2, c4, load, xb_old, xb_new, vb_new, P, S):
    """Residual (N), tangent (N/m) and size of the residual's terms (N) of a one-mass step."""
    v0 = c2 * (q0 - qn0) - vn0
    a0 = c4 * (q0 - qn0) - 2.0 * c2 * vn0 - an0
    y = q0 - xb_new
    f0, t0 = _part_force(kind, 0, y, y - (qn0 - xb_old), v0 - vb_new, h, P, S)
    r0 = m0 * (a0 + load) + f0
    magnitude = m0 * (abs(a0) + abs(load) + c4 * (abs(q0) + abs(qn0))) + abs(f0)
    return r0, t0, magnitude


#: Outcomes of :func:`newton_search`: take a new Newton direction from the accepted point, try
#: the same direction at half the length, or stop (converged or not).
SEARCH_NEW_DIRECTION = 0
SEARCH_HALVE = 1
SEARCH_END = 2
#: Halvings of one Newton direction before the search stops where it ended.
_MAX_HALVINGS = 40


@numba.njit(cache=True, inline="always")
def newton_search(accepted_trials, halvings, scale, new_norm, rnorm, floor, step_norm, size):
    """The damped Newton iteration's decision after one evaluation of the residual: the one line
    search every Newmark step runs (the specialised steps here, the generic step).

    The constant-acceleration predictor is evaluated first (``accepted_trials`` -1); then each
    Newton direction is tried at full length and halved up to :data:`_MAX_HALVINGS` times until
    the residual's norm drops; :data:`_NEWTON_MAX_ITER` accepted trials at most. A step converges
    when the norm is at most ``floor``, or, once the step length ``step_norm`` is below ``1e-15``
    of the state's ``size``, when it is within ``1e3 floor``.

    Parameters: the search's state (``accepted_trials``, ``halvings``, ``scale``: the length
    factor of the trial along the current direction, ``rnorm``: the accepted point's norm), the
    trial's residual norm ``new_norm`` and ``floor`` (N), ``step_norm`` (sum of ``|scale dq|``,
    m) and ``size`` (sum of the trial's and the start's ``|q|``, m).

    Returns ``(outcome, accepted_trials, halvings, scale, rnorm, converged)``; on every outcome
    but :data:`SEARCH_HALVE` the trial becomes the accepted point (the caller's ``q <- trial``),
    so the last evaluation is always at the point a step ends on and its Jenkin forces are
    committed by a copy (:func:`commit_jenkin`) instead of a second evaluation.
    """
    if accepted_trials < 0:
        return SEARCH_NEW_DIRECTION, 0, halvings, scale, new_norm, False
    if new_norm < rnorm or new_norm <= floor:
        if new_norm <= floor:
            return SEARCH_END, accepted_trials, halvings, scale, new_norm, True
        if step_norm <= 1e-15 * size:
            return SEARCH_END, accepted_trials, halvings, scale, new_norm, new_norm <= 1e3 * floor
        accepted_trials += 1
        if accepted_trials == _NEWTON_MAX_ITER:
            return SEARCH_END, accepted_trials, halvings, scale, new_norm, False
        return SEARCH_NEW_DIRECTION, accepted_trials, halvings, scale, new_norm, False
    scale *= 0.5
    halvings += 1
    if halvings < _MAX_HALVINGS:
        return SEARCH_HALVE, accepted_trials, halvings, scale, rnorm, False
    return SEARCH_END, accepted_trials, halvings, scale, new_norm, new_norm <= 1e3 * floor  # no decrease: stop


@numba.njit(cache=True, inline="always")
def two_mass_direction(c4, m0, m1, r0, r1, t0, t1):
    """The Newton direction ``(dq0, dq1)`` (m) of a two-mass step: its Jacobian
    ``[[c4 m0 + t0, -t0], [-t0, c4 m1 + t0 + t1]]`` (the masses' ``4 / h^2`` terms and the
    isolators' tangents, N/m) solved for minus the residuals ``(r0, r1)`` (N)."""
    j00 = c4 * m0 + t0
    j01 = -t0
    j11 = c4 * m1 + t0 + t1
    det = j00 * j11 - j01 * j01
    return -(j11 * r0 - j01 * r1) / det, -(j00 * r1 - j01 * r0) / det


@numba.njit(cache=True, inline="always")
def end_of_step(state, d, q, qn, vn, an, c2, c4):
    """Mass ``d``'s position ``q`` (m) at the end of a step into ``state = [q0, q1, v0, v1, a0,
    a1]``, with the trapezoidal rule's velocity and acceleration (``c2 = 2 / h``, ``c4 = c2^2``;
    ``qn, vn, an``: the step's start)."""
    state[d] = q
    state[2 + d] = c2 * (q - qn) - vn
    state[4 + d] = c4 * (q - qn) - 2.0 * c2 * vn - an


@numba.njit(cache=True, error_model="numpy", _nrt=False)
def step_sdof(kind, m0, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale):
    """One step of a single mass on a ``kind`` isolator; the generic step's arguments and flags."""
    qn0 = state[0]
    vn0 = state[2]
    an0 = state[4]
    c2 = 2.0 / h
    c4 = c2 * c2
    q0 = qn0 + h * vn0 + 0.5 * h * h * an0
    trial0 = q0
    dq0 = 0.0
    scale = 1.0
    rnorm = 0.0
    accepted_trials = -1  # -1 while the predictor is evaluated
    halvings = 0
    while True:
        r0, t0, magnitude = _residual_sdof(kind, m0, qn0, vn0, an0, trial0, h, c2, c4, load, xb_old, xb_new,
                                           vb_new, P, S)
        outcome, accepted_trials, halvings, scale, rnorm, converged = newton_search(
            accepted_trials, halvings, scale, math.sqrt(r0 * r0), rnorm, _RES_TOL * (magnitude + force_scale),
            abs(scale * dq0), abs(trial0) + abs(qn0))
        if outcome == SEARCH_HALVE:
            trial0 = q0 + scale * dq0
            continue
        q0 = trial0
        if outcome == SEARCH_END:
            break
        dq0 = -r0 / (c4 * m0 + t0)
        scale = 1.0
        halvings = 0
        trial0 = q0 + dq0
    if not converged:
        return FLAG_NO_CONVERGENCE
    y = q0 - xb_new
    _commit_part(kind, 0, y - (qn0 - xb_old), P, S)
    end_of_step(state, 0, q0, qn0, vn0, an0, c2, c4)
    if not (math.isfinite(state[0]) and math.isfinite(state[2]) and math.isfinite(state[4])):
        return FLAG_NON_FINITE
    if polynomial_spring_stiffness(y, P[0, 0, 0], P[0, 0, 1], P[0, 0, 2]) < 0.0:
        return FLAG_NEGATIVE_STIFFNESS
    return FLAG_OK


@numba.njit(cache=True, inline="always")
def _residual_hybrid(lower, m0, m1, qn0, qn1, vn0, vn1, an0, an1, q0, q1, h, c2, c4, load, xb_old, xb_new,
                     vb_new, P, S):
    """Residuals (N), tangents (N/m) and size of the terms (N) of the hybrid's step."""
    v0 = c2 * (q0 - qn0) - vn0
    a0 = c4 * (q0 - qn0) - 2.0 * c2 * vn0 - an0
    v1 = c2 * (q1 - qn1) - vn1
    a1 = c4 * (q1 - qn1) - 2.0 * c2 * vn1 - an1
    y_up = q0 - q1
    f0, t0 = _part_force(2, 0, y_up, y_up - (qn0 - qn1), v0 - v1, h, P, S)
    y_low = q1 - xb_new
    f1, t1 = _part_force(lower, 1, y_low, y_low - (qn1 - xb_old), v1 - vb_new, h, P, S)
    r0 = m0 * (a0 + load) + f0
    magnitude = m0 * (abs(a0) + abs(load) + c4 * (abs(q0) + abs(qn0))) + abs(f0)
    r1 = m1 * (a1 + load) - f0 + f1
    magnitude += m1 * (abs(a1) + abs(load) + c4 * (abs(q1) + abs(qn1))) + abs(f1)
    return r0, r1, t0, t1, magnitude


@numba.njit(cache=True, error_model="numpy", _nrt=False)
def step_hybrid(lower, m0, m1, state, h, load, xb_old, xb_new, vb_new, P, S, force_scale):
    """One step of the hybrid (Maxwell isolator over an Iwan isolator of kind ``lower``, plain or
    slip-modulated); the generic step's arguments and flags."""
    qn0 = state[0]
    qn1 = state[1]
    vn0 = state[2]
    vn1 = state[3]
    an0 = state[4]
    an1 = state[5]
    c2 = 2.0 / h
    c4 = c2 * c2
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
        r0, r1, t0, t1, magnitude = _residual_hybrid(lower, m0, m1, qn0, qn1, vn0, vn1, an0, an1, trial0, trial1, h,
                                                     c2, c4, load, xb_old, xb_new, vb_new, P, S)
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
        dq0, dq1 = two_mass_direction(c4, m0, m1, r0, r1, t0, t1)
        scale = 1.0
        halvings = 0
        trial0 = q0 + dq0
        trial1 = q1 + dq1
    if not converged:
        return FLAG_NO_CONVERGENCE
    y_up = q0 - q1
    _commit_part(2, 0, y_up - (qn0 - qn1), P, S)
    y_low = q1 - xb_new
    _commit_part(lower, 1, y_low - (qn1 - xb_old), P, S)
    end_of_step(state, 0, q0, qn0, vn0, an0, c2, c4)
    end_of_step(state, 1, q1, qn1, vn1, an1, c2, c4)
    for d in range(6):
        if not math.isfinite(state[d]):
            return FLAG_NON_FINITE
    if polynomial_spring_stiffness(y_up, P[0, 0, 0], P[0, 0, 1], P[0, 0, 2]) < 0.0:
        return FLAG_NEGATIVE_STIFFNESS
    if polynomial_spring_stiffness(y_low, P[1, 0, 0], P[1, 0, 1], P[1, 0, 2]) < 0.0:
        return FLAG_NEGATIVE_STIFFNESS
    return FLAG_OK
