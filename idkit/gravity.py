"""Gravity and the free fall of a drop test: one value of ``g``, one ``v0 = -sqrt(2 g h)``.

Every layer that turns a drop height into an impact velocity (the simulator's
:func:`~idkit.simulate.free_fall`, the drop sweep of :mod:`idkit.responses.shock`, the drop
processing of :mod:`idkit.signal.drop`, the unit conversion of ``g`` in :mod:`idkit.io.units`)
uses this module, so a height means the same velocity everywhere.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from idkit.errors import ParameterError, SimulationError

__all__ = ["STANDARD_GRAVITY", "gravity_acceleration", "impact_velocity_from_height"]

#: Standard acceleration of gravity, m/s^2 (CGPM 1901 conventional value).
STANDARD_GRAVITY = 9.80665


def gravity_acceleration(gravity, *, name: str = "gravity") -> float:
    """The acceleration of gravity a simulation runs with, m/s^2 (acting downward).

    ``True`` is :data:`STANDARD_GRAVITY`, ``False`` or ``None`` none (0), a number itself
    when finite and >= 0. Anything else (text, NaN, an upward value, an array) is refused
    naming ``name``, rather than being read as something else.

    Raises
    ------
    SimulationError
        Anything but a boolean, None or a finite number >= 0 (every caller is a simulation
        taking ``gravity=``: :func:`~idkit.simulate.simulate`, :func:`~idkit.simulate.free_fall`,
        :func:`~idkit.simulate.solve_ivp_reference`, :func:`~idkit.responses.shock_sweep`).

    Examples
    --------
    >>> gravity_acceleration(True), gravity_acceleration(False), gravity_acceleration(1.62)
    (9.80665, 0.0, 1.62)
    """
    if gravity is True or gravity is np.True_:
        return STANDARD_GRAVITY
    if gravity is False or gravity is np.False_ or gravity is None:
        return 0.0
    if not (isinstance(gravity, (int, float, np.integer, np.floating)) and np.isfinite(gravity) and gravity >= 0):
        raise SimulationError(f"{name}: found {gravity!r}, expected True, False or a finite acceleration "
                              ">= 0 m/s^2 (acting downward)")
    return float(gravity)


def impact_velocity_from_height(height: ArrayLike, *, g: float = STANDARD_GRAVITY,
                                name: str = "drop_height") -> NDArray[np.float64] | float:
    """Impact velocity of a frictionless fall from ``height``: ``v0 = -sqrt(2 g h)``.

    Thesis eq. (3.18); negative because the top mass moves down (compression). A height of
    0 gives 0 (the mass is set down without speed).

    Parameters
    ----------
    height : float or array_like
        Drop height(s), m, finite and >= 0.
    g : float, default 9.80665
        Gravitational acceleration, m/s^2, > 0.
    name : str, default "drop_height"
        Name of the argument in the caller, used in the error message.

    Returns
    -------
    float or ndarray
        Impact velocity, m/s (<= 0); a float for a scalar height.

    Raises
    ------
    ParameterError
        A height that is negative or not finite, or ``g <= 0``.

    Examples
    --------
    >>> round(impact_velocity_from_height(0.08), 4)
    -1.2526
    >>> impact_velocity_from_height([0.0, 0.5 / STANDARD_GRAVITY])
    array([-0., -1.])
    """
    if isinstance(height, (str, bytes)):
        raise ParameterError(f"{name}: found {height!r}, expected finite heights >= 0 m")
    try:
        h = np.asarray(height, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"{name}: found {str(height)[:80]!r}, expected finite heights >= 0 m") from None
    bad = ~(np.isfinite(h) & (h >= 0))
    if np.any(bad):
        found = h[bad].ravel()[0] if h.ndim else float(h)
        raise ParameterError(f"{name}: found {found!r} m, expected finite heights >= 0 m")
    if not (np.isfinite(g) and g > 0):
        raise ParameterError(f"g: found {g!r} m/s^2, expected a positive acceleration")
    v0 = -np.sqrt(2.0 * g * h)
    return float(v0) if v0.ndim == 0 else v0
