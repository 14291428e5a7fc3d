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
* Maxwell element states and the Bouc-Wen ``z`` equation, with the Baber-Noori pinching factor
  (:func:`pinching_factor`, :func:`pinched_boucwen_z_step`);
* the clearance in series with a Jenkin element (:func:`dead_zone` applied to a stop operator of
  widened limits, :func:`clearance_jenkin_forces`) and the rate-dependent slip force
  (:func:`rate_dependent_slip_force`, :func:`rate_dependent_stop_operator`): docs/elements.md;
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


#: ``(modulation, growth, length)`` of :func:`stop_operator` for constant slip forces, its defaults.
#: Python callers pass them: a call to a compiled kernel that leaves defaults out goes through
#: numba's slow dispatch (it resolves the call's types again every time).
CONSTANT_SLIP = (0.0, 0.0, 1.0)


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
    scale = np.empty(deflection.shape[0])
    for i in range(deflection.shape[0]):
        scale[i] = slip_scale(deflection[i], modulation, growth, length)
    return _scaled_stop_history(deflection, stiffness, friction_force, scale, initial_force)


@numba.njit(cache=True)
def _scaled_stop_history(deflection, stiffness, friction_force, scale, initial_force):
    """Element forces (N), shape ``(n_samples, n_elements)``, of the stop operator with the limits
    ``scale[i] Fc`` at each new sample ``i`` (:func:`scaled_jenkin_step`); the first sample holds
    ``initial_force``. The history every stop operator of this module runs."""
    n_samples = deflection.shape[0]
    n_elements = stiffness.shape[0]
    forces = np.empty((n_samples, n_elements))
    state = np.empty(n_elements)
    for j in range(n_elements):
        state[j] = initial_force[j]
        forces[0, j] = state[j]
    for i in range(1, n_samples):
        scaled_jenkin_step(state, stiffness, friction_force, scale[i], deflection[i] - deflection[i - 1])
        for j in range(n_elements):
            forces[i, j] = state[j]
    return forces


@numba.njit(cache=True, inline="always")
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


@numba.njit(cache=True, inline="always")
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


@numba.njit(cache=True, inline="always")
def _step_direction(dx):
    """Sign of a deflection step ``dx``: 1.0, -1.0, or 0.0 for no step."""
    if dx == 0.0:
        return 0.0
    return 1.0 if dx > 0.0 else -1.0


@numba.njit(cache=True)
def boucwen_z_step(z, dx, alpha, beta, gamma, exponent, n_substeps):
    """Advance the Bouc-Wen hysteretic force ``z`` (N) over a deflection step ``dx`` (m).

    Integrates ``dz/dx = alpha - (gamma + beta sgn(dx z)) |z|^n`` (eq. 3.6, rate
    independent) with ``n_substeps`` classical Runge-Kutta steps in ``x``.
    Returns the new ``z`` and ``dz/dx`` at the end (for Newton tangents).
    """
    direction = _step_direction(dx)
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
    at least ``n_substeps`` Runge-Kutta sub-steps (:func:`boucwen_substeps`): the pinched history
    without pinching (:func:`pinched_boucwen_z_history`)."""
    return pinched_boucwen_z_history(deflection, alpha, beta, gamma, exponent, 0.0, 1.0, 0.0, initial_z, n_substeps)


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


def dead_zone(force, width):
    """``sign(F) max(|F| - width, 0)``: the force (N) a clearance passes on (docs/elements.md).

    A clearance of half-width ``gap`` (m) in series with a Jenkin element of stiffness ``k``
    (N/m) and slip force ``fc`` (N) is a Jenkin element of slip force ``fc + k gap`` whose
    force ``F_v`` (the *virtual* force, ``k`` times the travel from the middle of the
    clearance) is passed on through this dead zone of width ``k gap``: the contact carries
    nothing while the travel lies within the clearance.

    Examples
    --------
    >>> dead_zone(np.array([-5.0, -1.0, 0.5, 3.0]), 2.0)
    array([-3.,  0.,  0.,  1.])
    """
    force = np.asarray(force, dtype=float)
    return np.where(force > width, force - width, np.where(force < -width, force + width, 0.0))


def clearance_jenkin_forces(deflection, stiffness, friction_force, gap, initial_virtual_force):
    """Forces (N) of parallel Jenkin elements, each behind a clearance of half-width ``gap`` (m).

    Parameters
    ----------
    deflection : ndarray, shape (n_samples,)
        Deflection history in m.
    stiffness, friction_force : ndarray, shape (n_elements,)
        Contact-and-element stiffness ``k_i`` in N/m and slip force ``fc_i`` in N.
    gap : float
        Half-width of the clearance in m (>= 0; 0 is the plain stop operator).
    initial_virtual_force : ndarray, shape (n_elements,)
        Virtual forces ``k_i e_i`` in N at the first sample (``e_i`` the travel from the middle of
        the clearance; 0: centred in the clearance).

    Returns
    -------
    ndarray, shape (n_samples, n_elements)
        Element forces in N: :func:`dead_zone` of width ``k_i gap`` of the stop operator with slip
        forces ``fc_i + k_i gap`` (exact for a deflection piecewise linear between samples).

    Examples
    --------
    >>> x = np.array([0.0, 2e-3, 5e-3, 3e-3, 1e-3, -2e-3])
    >>> clearance_jenkin_forces(x, np.array([1e3]), np.array([2.0]), 1e-3, np.zeros(1))[:, 0].round(6)
    array([ 0.,  1.,  2.,  0.,  0., -2.])
    """
    stiffness = np.asarray(stiffness, dtype=float)
    dead = stiffness * float(gap)
    virtual = stop_operator(kernel_array(deflection), kernel_array(stiffness),
                            kernel_array(np.asarray(friction_force, dtype=float) + dead),
                            kernel_array(initial_virtual_force), *CONSTANT_SLIP)
    return dead_zone(virtual, dead)


def rate_dependent_slip_force(speed, friction_force, rate_gain, slip_speed):
    """Slip force ``fc(v) = fc (1 + r tanh(|v| / v_ref))`` in N at deflection rates ``v`` (m/s).

    ``fc`` (N) is the slip force at rest, ``fc0`` of ``fc0 + fc1 tanh(|v| / v_ref)``; ``r =
    fc1 / fc0`` (``rate_gain``, > -1: the slip force rises with speed for ``r > 0``, falls towards
    ``fc (1 + r)`` for ``r < 0``, a Stribeck-like drop); ``v_ref`` (``slip_speed``, m/s) the
    speed over which it changes.

    Examples
    --------
    >>> [round(float(rate_dependent_slip_force(v, 10.0, 0.5, 0.1)), 4) for v in (0.0, -1.0)]
    [10.0, 15.0]
    """
    return friction_force * (1.0 + rate_gain * np.tanh(np.abs(speed) / slip_speed))


@numba.njit(cache=True)
def rate_dependent_stop_operator(deflection, time, stiffness, friction_force, rate_gain, slip_speed, initial_force):
    """Jenkin forces (N) with slip forces ``fc_i (1 + r tanh(|v| / v_ref))`` along a history.

    ``v`` is the deflection rate of each step, ``(x_i - x_{i-1}) / (t_i - t_{i-1})`` (exact for a
    deflection linear in time between samples: the sliding speed of a slipping element). Each step
    is the stop operator ``F <- clip(F + k dx, -fc(v), fc(v))``. Shape ``(n_samples, n_elements)``;
    ``deflection`` in m, ``time`` in s (strictly increasing), ``initial_force`` in N.
    """
    scale = np.ones(deflection.shape[0])
    for i in range(1, deflection.shape[0]):
        speed = abs((deflection[i] - deflection[i - 1]) / (time[i] - time[i - 1]))
        scale[i] = 1.0 + rate_gain * math.tanh(speed / slip_speed)
    return _scaled_stop_history(deflection, stiffness, friction_force, scale, initial_force)


@numba.njit(cache=True)
def pinching_factor(z, direction, pinch, width, shift):
    """Baber-Noori pinching factor ``h = 1 - pinch exp(-((z sgn(dx) - shift) / width)^2)`` (-).

    ``z``, ``width`` and ``shift`` in N (``width > 0``); ``direction`` the sign of the deflection
    step. ``pinch = 0`` gives exactly 1.0.

    Examples
    --------
    >>> pinching_factor(0.0, 1.0, 0.8, 2.0, 0.0), pinching_factor(3.0, 1.0, 0.0, 2.0, 0.0)
    (0.19999999999999996, 1.0)
    """
    if pinch == 0.0:
        return 1.0
    u = (z * direction - shift) / width
    return 1.0 - pinch * math.exp(-u * u)


@numba.njit(cache=True)
def pinched_boucwen_z_step(z, dx, alpha, beta, gamma, exponent, pinch, width, shift, n_substeps):
    """Advance a pinched Bouc-Wen ``z`` (N) over a deflection step ``dx`` (m) (docs/elements.md).

    ``dz/dx = h(z) (alpha - (gamma + beta sgn(dx z)) |z|^n)`` with the pinching factor ``h``
    (:func:`pinching_factor`), by ``n_substeps`` classical Runge-Kutta steps in ``x``; ``pinch =
    0`` gives the numbers of :func:`boucwen_z_step`. Returns the new ``z`` and ``dz/dx`` there.
    """
    direction = _step_direction(dx)
    sub = dx / n_substeps
    for _ in range(n_substeps):
        z1 = z
        k1 = pinching_factor(z1, direction, pinch, width, shift) * _boucwen_slope(z1, direction, alpha, beta, gamma,
                                                                                  exponent)
        z2 = z + 0.5 * sub * k1
        k2 = pinching_factor(z2, direction, pinch, width, shift) * _boucwen_slope(z2, direction, alpha, beta, gamma,
                                                                                  exponent)
        z3 = z + 0.5 * sub * k2
        k3 = pinching_factor(z3, direction, pinch, width, shift) * _boucwen_slope(z3, direction, alpha, beta, gamma,
                                                                                  exponent)
        z4 = z + sub * k3
        k4 = pinching_factor(z4, direction, pinch, width, shift) * _boucwen_slope(z4, direction, alpha, beta, gamma,
                                                                                  exponent)
        z = z + sub * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0
    return z, pinching_factor(z, direction, pinch, width, shift) * _boucwen_slope(z, direction, alpha, beta, gamma,
                                                                                    exponent)


@numba.njit(cache=True)
def pinched_substeps(dx, alpha, beta, gamma, exponent, pinch, width, minimum):
    """Sub-steps of :func:`pinched_boucwen_z_step`: those of :func:`boucwen_substeps`, and with
    pinching enough that ``z`` crosses at most a quarter of the pinching ``width`` (N) in one
    (``z`` moves by at most about ``alpha |dx|`` over the step), so that RK4 resolves the dip."""
    count = boucwen_substeps(dx, alpha, beta, gamma, exponent, minimum)
    if pinch != 0.0 and width > 0.0:
        needed = math.ceil(min(4.0 * alpha * abs(dx) / width, float(BOUCWEN_MAX_SUBSTEPS)))
        count = max(count, np.int64(needed))
    return count


@numba.njit(cache=True)
def pinched_boucwen_z_history(deflection, alpha, beta, gamma, exponent, pinch, width, shift, initial_z, n_substeps):
    """Pinched Bouc-Wen ``z`` in N along a deflection history in m (:func:`pinched_boucwen_z_step`,
    at least ``n_substeps`` sub-steps a sample, :func:`pinched_substeps`); ``pinch = 0`` runs the
    plain step (:func:`boucwen_z_step`, the same numbers without the factor's evaluations)."""
    n_samples = deflection.shape[0]
    z_history = np.empty(n_samples)
    z_history[0] = initial_z
    z = initial_z
    for i in range(1, n_samples):
        dx = deflection[i] - deflection[i - 1]
        if pinch == 0.0:
            z, _ = boucwen_z_step(z, dx, alpha, beta, gamma, exponent,
                                  boucwen_substeps(dx, alpha, beta, gamma, exponent, n_substeps))
        else:
            z, _ = pinched_boucwen_z_step(z, dx, alpha, beta, gamma, exponent, pinch, width, shift,
                                          pinched_substeps(dx, alpha, beta, gamma, exponent, pinch, width, n_substeps))
        z_history[i] = z
    return z_history
