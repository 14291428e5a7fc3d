"""The packed layout every compiled step reads: its row and column numbers and the two packers.

Parameters ``P[j, row, i]`` of isolator ``j`` (0 below the top mass):

* row 0: g1, g2, g3, c_visc, mgsum, n_jenkin, n_maxwell, Bouc-Wen[10] (columns 0..16), slip
  modulation a, y_ref, 1 / y_ref, b (columns 17, 18, 19, 20), clearance gap (21), rate-dependent
  slip r, 1 / v_ref (22, 23), Bouc-Wen pinching pinch, width, shift (24-26);
* row 1: Jenkin stiffness, row 2: Jenkin slip force, row 3: Maxwell stiffness, row 4:
  ``exp(-rate h)``, row 5: ``(1 - exp(-rate h)) / (rate h)``.

States ``S[j, row, i]``: row 0 Jenkin forces, row 1 Maxwell elongations, row 2: [Bouc-Wen z,
mbase, z of the last trial], row 3: the Jenkin forces of the last trial (a step's last
evaluation is at its end point: it commits them by a copy). Packing keeps the number of arrays
handed between the compiled functions small.
"""

from __future__ import annotations

import math

import numba
import numpy as np

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)

#: columns of row 0 of the packed parameters
_MGSUM, _NJ, _NM, _BW, _SM = 4, 5, 6, 7, 17
_GAP, _RATE, _PINCH = 21, 22, 24
#: rows of the state block holding the committed Jenkin forces and those of the last trial
_COMMITTED = 0
_TRIAL = 3
_P_WIDTH = 27


@numba.njit(cache=True)
def _pack(poly, cvisc, jk, jfc, mk, mrate, bw, sm, h):
    """Parameter block for step ``h`` (the layout of this module's docstring); ``mgsum = sum k_i g_i``."""
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
