"""Time grid of ``idkit simulate drop``: the given duration and step, or the defaults of the system's resonance.

The defaults (:func:`idkit.responses.shock.default_shock_grid`: 4 periods of the
small-amplitude resonance, 2000 steps a period) need that resonance; it is searched in
:data:`idkit.simulate.harmonic.RESONANCE_BAND_HZ` (0.1 Hz - 5 kHz), and a transmissibility
largest at an end of the band has not located it. Such a system is refused instead of
simulated over a grid that does not follow the drop: a 1e6 kg mass on the 1e3 N/m
Table B.1 elastomer (5 mHz) was simulated 40 s, a fifth of its compression, and the travel
reported "ok"; a 1e-300 kg mass reported no peak at all.
"""

from __future__ import annotations

from idkit.errors import SimulationError
from idkit.responses.shock import default_shock_grid
from idkit.simulate.harmonic import RESONANCE_BAND_HZ, small_amplitude_resonance

__all__ = ["drop_grid"]


def drop_grid(system, duration: float | None, time_step: float | None, *, what: str = "system") -> tuple[float, float]:
    """``(duration, time_step)`` in s: the given ones, a missing one from the resonance.

    Parameters
    ----------
    system : SDOFSystem, HybridSystem or CoulombSpringSystem
    duration, time_step : float or None
        Given values (s); ``None`` takes the default.
    what : str
        How the system is named in the message (``"--mass 1e+06 kg on model.json"``).

    Raises
    ------
    SimulationError
        When a default is needed and the resonance is not located inside the band.
    """
    if duration is not None and time_step is not None:
        return duration, time_step
    low, high = RESONANCE_BAND_HZ
    found = small_amplitude_resonance(system)
    if not low * (1 + 1e-9) < found < high * (1 - 1e-9):
        edge = low if found <= low * (1 + 1e-9) else high
        raise SimulationError(
            f"{what}: the small-amplitude transmissibility is largest at {edge:g} Hz, an end of the band "
            f"{low:g}-{high:g} Hz searched for the resonance (it lies beyond, or the curve has no peak), so the "
            "default --duration (4 resonance periods) and --time-step (2000 steps a period) would not follow the "
            "drop; expected a mass and isolator resonating inside the band, or give --duration and --time-step")
    auto_duration, auto_step = default_shock_grid(system)
    return (auto_duration if duration is None else duration), (auto_step if time_step is None else time_step)
