"""Measured and model HOSIDFs of one setup's stepped sines: the maps and Bode sections of the study.

The thesis (chapter 3, figures 3.7-3.19) reads a nonlinear isolator off its higher-order
sinusoidal input describing functions over frequency and amplitude: the first harmonic
(resonance moving with amplitude), the odd third harmonic of hysteresis, the even second
harmonic of asymmetry and the 1/2 subharmonic of period doubling. :func:`sweep_maps`
gathers, for the setup with most stepped-sine records of a measurement set (one top
mass, or one pair of masses for a hybrid):

* every record's measured HOSIDFs of orders 1, 2, 3 and 1/2
  (:func:`idkit.observe.stepped_sine.hosidf_from_stepped_sine`: harmonics of the top
  velocity over the first harmonic of the base velocity, least squares over the largest
  even number of periods);
* the model's steady state at the same frequency and measured first-harmonic base
  amplitude (:func:`idkit.simulate.harmonic_response`, started from the linear steady
  state), so measured and model values can be compared point by point;
* the model's :class:`~idkit.responses.harmonic_map.HarmonicMap` on a log grid spanning
  the measured frequencies and base amplitudes (shooting where the time integration did
  not settle), for the top view.

Compute only; :func:`idkit.plot.validation.plot_sweep_maps` and
:func:`~idkit.plot.validation.plot_sweep_bode` draw the result.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.errors import DataError
from idkit.observe.stepped_sine import hosidf_from_stepped_sine
from idkit.responses.harmonic_map import HarmonicMap, harmonic_map
from idkit.simulate import harmonic_response
from idkit.validate.systems import system_for

__all__ = ["MAP_ORDERS", "SweepMaps", "sweep_maps"]

#: HOSIDF orders shown: the first harmonic, the second and third, the 1/2 subharmonic
MAP_ORDERS = (1.0, 2.0, 3.0, 0.5)


@dataclass(frozen=True)
class SweepMaps:
    """Measured and model HOSIDFs of one setup.

    Attributes
    ----------
    setup : str
        The masses, e.g. ``"top mass 7.39 kg"``.
    points : DataFrame
        One row per (record, order): ``id``, ``split``, ``level`` (nominal base velocity
        amplitude, m/s), ``freq [Hz]``, ``base amplitude [m]`` (measured first harmonic),
        ``order``, ``H measured`` and ``H model`` (complex, dimensionless), ``status``
        (``"ok"`` where the model reached a valid steady state, else why not; the model
        value is NaN there).
    model : HarmonicMap
        The model on a log grid over the measured frequencies and base amplitudes.
    """

    setup: str
    points: pd.DataFrame
    model: HarmonicMap

    def order(self, order: float) -> pd.DataFrame:
        """The rows of one order."""
        return self.points[np.isclose(self.points["order"], order)]

    @property
    def levels(self) -> list[float]:
        """Nominal excitation levels, ascending."""
        return sorted(self.points["level"].dropna().unique())


def _setup_key(info) -> tuple:
    return (info.top_mass_kg, info.intermediate_mass_kg)


def sweep_maps(measurements, *, isolator=None, upper=None, lower=None, n_freq: int = 24, n_amplitude: int = 8,
               workers: int | None = None) -> SweepMaps | None:
    """HOSIDFs of the most-recorded setup's stepped sines, measured and modelled (module docstring).

    Parameters
    ----------
    measurements : iterable of Measurement
        Records of any kind; the stepped sines are used (every split).
    isolator, upper, lower :
        The model, as :func:`idkit.validate.systems.system_for` takes it: one isolator on
        the top mass, or the hybrid's upper (elastomer) and lower (wire rope) parts.
    n_freq, n_amplitude : int
        Grid of the model map (log spaced over the measured ranges).
    workers : int, optional
        Simulation threads.

    Returns
    -------
    SweepMaps or None
        None when the set holds fewer than three stepped-sine records of one setup.
    """
    sweeps = [m for m in measurements if getattr(m, "kind", None) == "stepped_sine"]
    if not sweeps:
        return None
    counts = Counter(_setup_key(m.info) for m in sweeps)
    key, count = counts.most_common(1)[0]
    if count < 3:
        return None
    chosen = sorted((m for m in sweeps if _setup_key(m.info) == key), key=lambda m: m.info.excitation.freq)
    rows = []
    for measurement in chosen:
        info = measurement.info
        try:
            point = hosidf_from_stepped_sine(measurement, n_harmonics=3, subharmonic=True).result
        except DataError:
            continue  # too few periods or above Nyquist: the validation reports such records
        freq = float(info.excitation.freq)
        values = {1.0: point.hosidf[0], 0.5: point.subharmonic}
        for order in (2.0, 3.0):
            values[order] = point.hosidf[int(order) - 1] if point.hosidf.size >= order else np.nan
        for order in MAP_ORDERS:
            rows.append({"id": info.id, "split": info.split, "level": info.excitation.amplitude, "freq [Hz]": freq,
                         "base amplitude [m]": point.input_amplitude / (2 * np.pi * freq), "order": order,
                         "H measured": complex(values[order])})
    if len(rows) < 3 * len(MAP_ORDERS):
        return None
    points = pd.DataFrame(rows)
    system = system_for(chosen[0], isolator=isolator, upper=upper, lower=lower)
    first = points[np.isclose(points["order"], 1.0)]
    freq, amplitude = first["freq [Hz]"].to_numpy(float), first["base amplitude [m]"].to_numpy(float)
    response = harmonic_response(system, freq, amplitude, n_harmonics=3, start="linear", workers=workers)
    settled = np.asarray(response.converged, dtype=bool) & (np.asarray(response.flags) == 0)
    model_values, status = [], []
    for index in range(len(first)):
        for order in MAP_ORDERS:
            model_values.append(complex(response.hosidf(order)[index]) if settled[index] else complex(np.nan, np.nan))
            status.append("ok" if settled[index] else response.reasons[index] if response.reasons[index] != "ok"
                          else "did not reach steady state")
    points["H model"] = model_values
    points["status"] = status
    grid = harmonic_map(system, np.geomspace(freq.min(), freq.max(), n_freq),
                        np.geomspace(amplitude.min(), amplitude.max(), n_amplitude) if amplitude.max() > amplitude.min()
                        else np.array([amplitude.min()]), n_harmonics=3, workers=workers)
    top, middle = key
    setup = f"top mass {top:.3g} kg" + ("" if middle is None else f", intermediate mass {middle:.3g} kg")
    return SweepMaps(setup=setup, points=points, model=grid)
