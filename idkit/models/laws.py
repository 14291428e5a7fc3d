"""Compiled force laws shared by the models' quasi-static methods.

Plain functions of arrays (numba-compiled). The dynamic simulator in
:mod:`idkit.simulate` uses the same update rules inside its step.
"""

from __future__ import annotations

import math

import numba
import numpy as np


def kernel_array(values) -> np.ndarray:
    """``values`` as a C-contiguous, writeable float64 array (copied only if needed).

    numba compiles one specialisation per array type, and read-only or strided
    arrays are different types: passing every array through here keeps one
    compiled version per kernel.
    """
    return np.require(values, dtype=np.float64, requirements=["C", "W", "A"])


@numba.njit(cache=True)
def stop_operator(deflection, stiffness, friction_force, initial_force):
    """Forces of parallel Jenkin elements along a deflection history (SPEC 1.1).

    Parameters
    ----------
    deflection : ndarray, shape (n_samples,)
        Deflection history in m. The first sample is the reference state.
    stiffness, friction_force : ndarray, shape (n_elements,)
        Spring stiffness in N/m and Coulomb slip force in N of each element.
    initial_force : ndarray, shape (n_elements,)
        Element forces in N at the first sample.

    Returns
    -------
    ndarray, shape (n_samples, n_elements)
        Element forces in N. Exact for deflection piecewise linear between samples:
        ``F <- clip(F + k * dx, -Fc, Fc)``.
    """
    n_samples = deflection.shape[0]
    n_elements = stiffness.shape[0]
    forces = np.empty((n_samples, n_elements))
    for j in range(n_elements):
        forces[0, j] = initial_force[j]
    for i in range(1, n_samples):
        step = deflection[i] - deflection[i - 1]
        for j in range(n_elements):
            trial = forces[i - 1, j] + stiffness[j] * step
            limit = friction_force[j]
            if trial > limit:
                trial = limit
            elif trial < -limit:
                trial = -limit
            forces[i, j] = trial
    return forces


@numba.njit(cache=True)
def maxwell_states(deflection, time, rate, initial_state):
    """Elongations of Maxwell elements along a sampled deflection history (SPEC 1.4).

    Exact for deflection linear in time between samples:
    ``u <- exp(-rate h) u + (dr/h) (1 - exp(-rate h)) / rate``.

    Parameters
    ----------
    deflection : ndarray, shape (n_samples,)
        Deflection over the isolator in m.
    time : ndarray, shape (n_samples,)
        Strictly increasing sample times in s.
    rate : ndarray, shape (n_elements,)
        Relaxation rates ``k_i / d_i`` in 1/s.
    initial_state : ndarray, shape (n_elements,)
        Spring elongations in m at the first sample.

    Returns
    -------
    ndarray, shape (n_samples, n_elements)
        Spring elongations ``u_i`` in m; element force is ``k_i * u_i``.
    """
    n_samples = deflection.shape[0]
    n_elements = rate.shape[0]
    states = np.empty((n_samples, n_elements))
    for j in range(n_elements):
        states[0, j] = initial_state[j]
    for i in range(1, n_samples):
        step = time[i] - time[i - 1]
        slope = (deflection[i] - deflection[i - 1]) / step
        for j in range(n_elements):
            decay = math.exp(-rate[j] * step)
            states[i, j] = decay * states[i - 1, j] + slope * (-math.expm1(-rate[j] * step)) / rate[j]
    return states


@numba.njit(cache=True)
def boucwen_z_step(z, dx, alpha, beta, gamma, exponent, n_substeps):
    """Advance the Bouc-Wen hysteretic force ``z`` (N) over a deflection step ``dx`` (m).

    Integrates ``dz/dx = alpha - (gamma + beta sgn(dx z)) |z|^n`` (eq. 3.6, rate
    independent) with ``n_substeps`` classical Runge-Kutta steps in ``x``.
    Returns the new ``z`` and ``dz/dx`` at the end (for Newton tangents).
    """
    if dx == 0.0:
        direction = 0.0
    else:
        direction = 1.0 if dx > 0.0 else -1.0
    sub = dx / n_substeps

    for _ in range(n_substeps):
        k1 = _boucwen_slope(z, direction, alpha, beta, gamma, exponent)
        k2 = _boucwen_slope(z + 0.5 * sub * k1, direction, alpha, beta, gamma, exponent)
        k3 = _boucwen_slope(z + 0.5 * sub * k2, direction, alpha, beta, gamma, exponent)
        k4 = _boucwen_slope(z + sub * k3, direction, alpha, beta, gamma, exponent)
        z = z + sub * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0
    return z, _boucwen_slope(z, direction, alpha, beta, gamma, exponent)


@numba.njit(cache=True)
def _boucwen_slope(z, direction, alpha, beta, gamma, exponent):
    sign_product = direction * z
    if sign_product > 0.0:
        s = 1.0
    elif sign_product < 0.0:
        s = -1.0
    else:
        s = 0.0
    return alpha - (gamma + beta * s) * abs(z) ** exponent


@numba.njit(cache=True)
def boucwen_z_history(deflection, alpha, beta, gamma, exponent, initial_z, n_substeps):
    """Bouc-Wen hysteretic force ``z`` in N along a deflection history in m."""
    n_samples = deflection.shape[0]
    z_history = np.empty(n_samples)
    z_history[0] = initial_z
    z = initial_z
    for i in range(1, n_samples):
        z, _ = boucwen_z_step(
            z, deflection[i] - deflection[i - 1], alpha, beta, gamma, exponent, n_substeps
        )
        z_history[i] = z
    return z_history
