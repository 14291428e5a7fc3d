"""The force laws and small-amplitude laws every model, fitter and validator calls.

Plain functions of arrays (numba-compiled where a compiled loop calls them). The dynamic
simulator in :mod:`idkit.simulate` uses the same update rules inside its step.

* Jenkin elements: :func:`jenkin_step` (one deflection step of parallel elements, the
  stop operator ``F <- clip(F + k dx, -Fc, Fc)``) and :func:`stop_operator` (a history);
* the slip-modulated Iwan model: :func:`slip_scale` ``s(y) = 1 - a t + b t^2`` and
  :func:`scaled_jenkin_step`, the stop operator with limits ``s(y) Fc``;
* the Iwan parallel spring: :func:`polynomial_spring_force` ``x (g1 + x (g2 + x g3))``,
  :func:`polynomial_spring_stiffness` ``g1 + 2 g2 x + 3 g3 x^2`` and
  :func:`lowest_spring_stiffness` over an interval;
* Maxwell element states and the Bouc-Wen ``z`` equation;
* small-amplitude transmissibilities: :func:`sdof_transmissibility`
  ``k* / (k* - m omega^2)`` and :func:`hybrid_transmissibility` (two masses in series).
"""

from __future__ import annotations

import math

import numba
import numpy as np

import idkit._numba_cache  # noqa: F401 - process-safe numba cache writes (before anything compiles)


def kernel_array(values) -> np.ndarray:
    """``values`` as a C-contiguous, writeable float64 array (copied only if needed).

    numba compiles one specialisation per array type, and read-only or strided
    arrays are different types: passing every array through here keeps one
    compiled version per kernel.
    """
    return np.require(values, dtype=np.float64, requirements=["C", "W", "A"])


@numba.njit(cache=True)
def jenkin_step(state, stiffness, friction_force, step):
    """Advance parallel Jenkin elements by one deflection step, in place (SPEC 1.1).

    Parameters
    ----------
    state : ndarray, shape (n_elements,)
        Element forces in N, overwritten by ``clip(F + k * step, -Fc, Fc)``.
    stiffness, friction_force : ndarray, shape (n_elements,)
        Spring stiffness in N/m and Coulomb slip force in N of each element.
    step : float
        Deflection change in m.

    Returns
    -------
    float
        Sum of the element forces after the step, N.

    Examples
    --------
    >>> state = np.array([0.0, 0.0])
    >>> jenkin_step(state, np.array([1e3, 2e3]), np.array([1.0, 5.0]), 2e-3)
    5.0
    """
    total = 0.0
    for j in range(state.shape[0]):
        trial = state[j] + stiffness[j] * step
        limit = friction_force[j]
        if trial > limit:
            trial = limit
        elif trial < -limit:
            trial = -limit
        state[j] = trial
        total += trial
    return total


@numba.njit(cache=True, inline="always")
def slip_scale(deflection, modulation, growth, length):
    """Slip-force scale ``s(y) = 1 - a t + b t^2``, ``t = tanh(y / y_ref)`` (dimensionless) of
    the slip-modulated Iwan model at deflection ``y`` in m; exactly 1 when ``a = b = 0``.

    Examples
    --------
    >>> round(slip_scale(0.01, 0.3, 0.0, 0.005), 4), slip_scale(0.01, 0.0, 0.0, 0.005)
    (0.7108, 1.0)
    """
    if modulation == 0.0 and growth == 0.0:
        return 1.0
    t = math.tanh(deflection / length)
    return 1.0 - modulation * t + growth * t * t


@numba.njit(cache=True, inline="always")
def scaled_jenkin_step(state, stiffness, friction_force, scale, step):
    """Advance parallel Jenkin elements whose slip forces are scaled by ``scale`` (the slip
    scale at the new deflection) by one deflection step, in place: ``F <- clip(F + k step,
    -scale Fc, scale Fc)``. :func:`jenkin_step` is the case ``scale = 1``.

    Examples
    --------
    >>> state = np.array([0.0, 0.0])
    >>> scaled_jenkin_step(state, np.array([1e3, 2e3]), np.array([1.0, 5.0]), 0.5, 2e-3)
    >>> state.tolist()
    [0.5, 2.5]
    """
    for j in range(state.shape[0]):
        trial = state[j] + stiffness[j] * step
        limit = scale * friction_force[j]
        if trial > limit:
            trial = limit
        elif trial < -limit:
            trial = -limit
        state[j] = trial


@numba.njit(cache=True)
def stop_operator(deflection, stiffness, friction_force, initial_force, modulation=0.0, growth=0.0, length=1.0):
    """Forces of parallel Jenkin elements along a deflection history (SPEC 1.1).

    Parameters
    ----------
    deflection : ndarray, shape (n_samples,)
        Deflection history in m. The first sample is the reference state.
    stiffness, friction_force : ndarray, shape (n_elements,)
        Spring stiffness in N/m and Coulomb slip force in N of each element.
    initial_force : ndarray, shape (n_elements,)
        Element forces in N at the first sample.
    modulation, growth, length : float, optional
        Slip modulation ``a``, ``b`` and ``y_ref`` (m) of the slip-modulated Iwan model: the slip
        forces are ``s(y) Fc`` (:func:`slip_scale`) at each new sample; the defaults leave them ``Fc``.

    Returns
    -------
    ndarray, shape (n_samples, n_elements)
        Element forces in N. Exact for deflection piecewise linear between samples:
        ``F <- clip(F + k * dx, -s Fc, s Fc)``.
    """
    n_samples = deflection.shape[0]
    n_elements = stiffness.shape[0]
    forces = np.empty((n_samples, n_elements))
    state = np.empty(n_elements)
    for j in range(n_elements):
        state[j] = initial_force[j]
        forces[0, j] = state[j]
    for i in range(1, n_samples):
        scaled_jenkin_step(state, stiffness, friction_force, slip_scale(deflection[i], modulation, growth, length),
                           deflection[i] - deflection[i - 1])
        for j in range(n_elements):
            forces[i, j] = state[j]
    return forces


@numba.njit(cache=True)
def polynomial_spring_force(deflection, g1, g2, g3):
    """Iwan parallel spring force ``x (g1 + x (g2 + x g3))`` in N (SPEC 1.2).

    Parameters
    ----------
    deflection : float or ndarray
        Deflection in m.
    g1, g2, g3 : float
        Coefficients in N/m, N/m^2, N/m^3.

    Returns
    -------
    float or ndarray
        Force in N.

    Examples
    --------
    >>> polynomial_spring_force(2e-3, 1e3, 1e5, 0.0)
    2.4
    """
    return deflection * (g1 + deflection * (g2 + deflection * g3))


@numba.njit(cache=True)
def polynomial_spring_stiffness(deflection, g1, g2, g3):
    """Local stiffness ``g1 + 2 g2 x + 3 g3 x^2`` (N/m) of the Iwan parallel spring at ``deflection`` m.

    Examples
    --------
    >>> polynomial_spring_stiffness(1e-3, 1e3, 1e5, 0.0)
    1200.0
    """
    return g1 + deflection * (2.0 * g2 + 3.0 * g3 * deflection)


def lowest_spring_stiffness(g1: float, g2: float, g3: float, x_min: float, x_max: float) -> float:
    """Minimum of the parallel spring's local stiffness ``g1 + 2 g2 x + 3 g3 x^2`` over ``[x_min, x_max]``.

    Parameters
    ----------
    g1, g2, g3 : float
        Coefficients in N/m, N/m^2, N/m^3.
    x_min, x_max : float
        Deflection interval in m.

    Returns
    -------
    float
        Lowest local stiffness in N/m (at an end, or at the vertex ``-g2 / (3 g3)`` when
        ``g3 > 0`` and it lies inside).

    Examples
    --------
    >>> lowest_spring_stiffness(1e3, 0.0, 1e8, -1e-2, 1e-2)
    1000.0
    """
    candidates = [x_min, x_max]
    if g3 > 0.0:
        vertex = -g2 / (3.0 * g3)
        if x_min < vertex < x_max:
            candidates.append(vertex)
    return min(float(polynomial_spring_stiffness(x, g1, g2, g3)) for x in candidates)


def sdof_transmissibility(stiffness, moving_mass, omega):
    """Transmissibility ``k* / (k* - m omega^2)`` of a mass on an isolator (top over base motion).

    Parameters
    ----------
    stiffness : complex or ndarray
        Complex (dynamic) stiffness ``k*`` of the isolator in N/m at ``omega``.
    moving_mass : float or ndarray
        Mass that moves with the top, kg: the top mass plus the isolator's ``m_eff``.
    omega : float or ndarray
        Angular frequency in rad/s.

    Returns
    -------
    complex or ndarray
        Dimensionless transmissibility (any kinematic quantity: displacement, velocity,
        acceleration).

    Examples
    --------
    >>> float(abs(sdof_transmissibility(1e4, 1.0, 0.0)))
    1.0
    """
    # m omega^2 beyond float64 (a huge mass or frequency): its limit, T = -0, not a warning
    with np.errstate(over="ignore"):
        return stiffness / (stiffness - moving_mass * np.asarray(omega) ** 2)


def hybrid_transmissibility(upper_stiffness, lower_stiffness, top_mass, intermediate_mass, omega):
    """Transmissibility top over base of two masses in series on two isolators (SPEC 1.5, eq. 5.1).

    top mass -- upper isolator -- intermediate mass -- lower isolator -- base. The 2x2
    dynamic-stiffness system of [top, intermediate] is solved by Cramer's rule.

    Parameters
    ----------
    upper_stiffness, lower_stiffness : complex or ndarray
        Complex stiffness of the upper and lower isolator in N/m at ``omega``.
    top_mass, intermediate_mass : float
        Moving masses in kg (each with the ``m_eff`` of the isolator below it).
    omega : float or ndarray
        Angular frequency in rad/s.

    Returns
    -------
    complex or ndarray
        Dimensionless transmissibility.

    Examples
    --------
    >>> float(abs(hybrid_transmissibility(2e4, 2e4, 1.0, 0.0, 0.0)))
    1.0
    """
    return hybrid_displacements(upper_stiffness, lower_stiffness, top_mass, intermediate_mass, omega)[0]


def hybrid_displacements(upper_stiffness, lower_stiffness, top_mass, intermediate_mass, omega):
    """Top and intermediate displacement over base displacement of the hybrid (2x2 solve).

    Parameters are those of :func:`hybrid_transmissibility`.

    Returns
    -------
    (complex or ndarray, complex or ndarray)
        ``X_top / X_base`` and ``X_intermediate / X_base``.

    Examples
    --------
    >>> top, middle = hybrid_displacements(2e4, 2e4, 1.0, 0.5, 0.0)
    >>> float(abs(top)), float(abs(middle))
    (1.0, 1.0)
    """
    omega = np.asarray(omega)
    a11 = upper_stiffness - top_mass * omega**2
    a12 = -upper_stiffness
    a22 = upper_stiffness + lower_stiffness - intermediate_mass * omega**2
    determinant = a11 * a22 - a12 * a12
    # right-hand side [0, k_lower] x_base, Cramer's rule
    return -a12 * lower_stiffness / determinant, a11 * lower_stiffness / determinant


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


#: Most Runge-Kutta sub-steps :func:`boucwen_substeps` gives one deflection step.
BOUCWEN_MAX_SUBSTEPS = 1 << 16


@numba.njit(cache=True)
def boucwen_substeps(dx, alpha, beta, gamma, exponent, minimum):
    """Runge-Kutta sub-steps of :func:`boucwen_z_step` over a deflection step ``dx`` (m).

    At least ``minimum``, and enough that none is longer than a quarter of the relaxation
    length of ``z`` near saturation, ``1 / (n (beta + gamma) z_max^(n-1))`` with ``z_max =
    (alpha / (beta + gamma))^(1/n)``: the explicit scheme is stable only below about 2.8
    relaxation lengths a sub-step, and a step many of them long made ``z`` oscillate or
    overflow (a stiff ``z`` law, e.g. a yield travel ``z_max / alpha`` of 10 um, at 128 steps
    a period); at a quarter, RK4's error on the relaxing part is about ``0.25^5 / 120 = 8e-6``
    of it a sub-step. Where four sub-steps already keep to a quarter, ``minimum`` (4 in the
    simulator) stays and nothing changes. Laws without saturation (``beta + gamma <= 0``) keep
    ``minimum``. At most :data:`BOUCWEN_MAX_SUBSTEPS`.
    """
    total = beta + gamma
    if not (total > 0.0 and alpha > 0.0 and exponent > 0.0):
        return minimum
    rate = exponent * total ** (1.0 / exponent) * alpha ** ((exponent - 1.0) / exponent)  # 1/m
    needed = math.ceil(min(4.0 * abs(dx) * rate, float(BOUCWEN_MAX_SUBSTEPS)))
    return max(minimum, np.int64(needed))


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
    """Bouc-Wen hysteretic force ``z`` in N along a deflection history in m; each step with
    at least ``n_substeps`` Runge-Kutta sub-steps (:func:`boucwen_substeps`)."""
    n_samples = deflection.shape[0]
    z_history = np.empty(n_samples)
    z_history[0] = initial_z
    z = initial_z
    for i in range(1, n_samples):
        dx = deflection[i] - deflection[i - 1]
        z, _ = boucwen_z_step(z, dx, alpha, beta, gamma, exponent,
                              boucwen_substeps(dx, alpha, beta, gamma, exponent, n_substeps))
        z_history[i] = z
    return z_history


def stiffness_from_transmissibility(transmissibility, moving_mass, omega):
    """Complex stiffness ``k* = m omega^2 H / (H - 1)`` that gives the transmissibility ``H``.

    The inverse of :func:`sdof_transmissibility` (``H = k* / (k* - m omega^2)``): a measured
    FRF of a mass on an isolator read as the isolator's complex stiffness. Ill-conditioned
    where ``H`` is close to 1 (far below the resonance the top follows the base and the
    isolator is barely deformed): a relative error ``e`` of ``H`` becomes ``e |H| / |H - 1|``
    in ``k*``; callers keep the frequencies where ``|H - 1|`` is large enough.

    Parameters
    ----------
    transmissibility : complex or ndarray
        Top over base motion (dimensionless).
    moving_mass : float or ndarray
        Top mass plus the isolator's ``m_eff``, kg.
    omega : float or ndarray
        Angular frequency in rad/s.

    Returns
    -------
    complex or ndarray
        ``k*`` in N/m (NaN where ``H == 1``).

    Examples
    --------
    >>> k = 1.2e4 + 1.5e3j
    >>> h = sdof_transmissibility(k, 2.0, 2 * np.pi * 20.0)
    >>> complex(np.round(stiffness_from_transmissibility(h, 2.0, 2 * np.pi * 20.0), 6))
    (12000+1500j)
    """
    h = np.asarray(transmissibility, dtype=complex)
    with np.errstate(divide="ignore", invalid="ignore"):
        value = np.asarray(moving_mass) * np.asarray(omega) ** 2 * h / (h - 1.0)
    return np.where(h == 1.0, np.nan + 0j, value)
