"""Can the H1 estimates resolve their resonances? The Maxwell fit's check of its own data.

The H1 estimator's Hann window widens a measured resonance peak and lowers it
(:func:`idkit.signal.frf.window_peak_bias`); a fit that compares exact model curves with such
peaks reads too much damping near resonance. :func:`resolution_checks` names the worst H1 when its
peak loss exceeds :data:`WINDOW_BIAS_LIMIT`.
"""

from __future__ import annotations

import math

import numpy as np

from idkit.models.laws import sdof_transmissibility
from idkit.models.maxwell import preloaded
from idkit.signal.frf import HANN_ENBW_BINS, half_power_damping, window_peak_bias

__all__ = ["WINDOW_BIAS_LIMIT", "resolution_checks"]


#: Largest peak loss of a measured resonance through the H1 estimator's Hann window
#: (:func:`idkit.signal.frf.window_peak_bias`) for a Maxwell fit to be trusted near resonance.
#: 10 %: the damping read from such a peak is then about 10 % high, a quarter of the FRF
#: validation's 3 dB damping limit.
WINDOW_BIAS_LIMIT = 0.10


def resolution_checks(frfs, model=None) -> tuple[str, ...]:
    """A check when an H1 cannot resolve its resonance: the window's bandwidth against the
    resonance's half-power width (the fit compares exact model curves with biased peaks).

    The width is the narrower of the one read off the measured H1 and, given ``model`` (the fitted
    isolator), the one of its exact transmissibility about the set's preload on a grid 20 times
    finer than the H1's, when its resonance lies inside the set's band: the window widens the
    measured peak (the bias read off it is low), and a peak whose half-power point lies outside the
    band gives no measured width at all.
    """
    worst = None
    for item in frfs:
        step = float(np.median(np.diff(item.freq)))
        widths = []
        resonance, zeta = half_power_damping(item.freq, np.abs(item.transmissibility))
        if math.isfinite(zeta) and zeta > 0:
            widths.append((2.0 * zeta * resonance, "read off the H1"))
        if model is not None:
            local = preloaded(model, item.static_stiffness)
            low, high = float(np.min(item.freq)), float(np.max(item.freq))
            grid = np.arange(low / 4.0, high, step / 20.0)
            curve = np.abs(sdof_transmissibility(local.complex_stiffness(grid), item.mass + local.m_eff,
                                                 2 * np.pi * grid))
            resonance, zeta = half_power_damping(grid, curve)
            if low <= resonance <= high and math.isfinite(zeta) and zeta > 0:
                widths.append((2.0 * zeta * resonance, "of the fitted model's exact curve"))
        if not widths:
            continue
        width, source = min(widths)
        bias = window_peak_bias(step, width)
        if worst is None or bias > worst[0]:
            worst = (bias, item.name, step, width, source)
    if worst is None or worst[0] <= WINDOW_BIAS_LIMIT:
        return ()
    bias, name, step, width, source = worst
    loss = (f"loses about {100 * bias:.0f} % of the peak" if bias < 1.0
            else "cannot hold the peak (first-order loss above 100 %)")
    return (f"the H1 of {name} cannot resolve its resonance: a {step:g} Hz step (window bandwidth "
            f"{HANN_ENBW_BINS * step:g} Hz) against a half-power width of {width:.3g} Hz ({source}) {loss} "
            f"(limit {100 * WINDOW_BIAS_LIMIT:g} %), so the damping near resonance is biased; longer white-noise "
            "records (a finer resolution_hz) resolve it",)
