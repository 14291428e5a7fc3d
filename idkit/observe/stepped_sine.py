"""Stepped-sine points -> HOSIDFs and sweeps with the input report (SPEC 5)."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.signal.harmonics import hosidf, HosidfResult, input_flatness, InputFlatness
from idkit.checks import Instance, accepts
from idkit.errors import DataError
from idkit.io import SteppedSineMeasurement
from idkit.observe._common import MeasuredRecord


@dataclass(frozen=True)
class SteppedSinePoint(MeasuredRecord):
    """HOSIDFs of one stepped-sine point (v_base -> v_top).

    Attributes
    ----------
    measurement_id, isolator, top_mass_kg
        The record (:class:`~idkit.observe._common.MeasuredRecord`).
    freq : float
        Excitation frequency, Hz.
    nominal_amplitude : float or None
        Declared amplitude (SI unit of ``info.excitation.amplitude_quantity``).
    result : HosidfResult
        Harmonic fits of input and output and the HOSIDFs.
    """

    freq: float
    nominal_amplitude: float | None
    result: HosidfResult

    @property
    def hosidf(self) -> np.ndarray:
        """Complex HOSIDFs of orders 1..K."""
        return self.result.hosidf

    @property
    def input_amplitude(self) -> float:
        """First-harmonic amplitude of v_base, m/s."""
        return self.result.input_amplitude

    @property
    def input_distortion(self) -> np.ndarray:
        """``|C2| / |C1|`` and ``|C3| / |C1|`` of v_base."""
        return self.result.input_distortion

    def to_dataframe(self) -> pd.DataFrame:
        """One row per order (see :meth:`HosidfResult.to_dataframe`) with the id."""
        table = self.result.to_dataframe()
        table.insert(0, "measurement_id", self.measurement_id)
        return table


@accepts(measurement=Instance((SteppedSineMeasurement,)), error=DataError)
def hosidf_from_stepped_sine(measurement: SteppedSineMeasurement, *, n_harmonics: int = 5,
                             subharmonic: bool = True) -> SteppedSinePoint:
    """HOSIDFs of one stepped-sine point: harmonics of v_top over the first harmonic of v_base.

    The whole record is analysed over the largest even number of excitation periods that fits,
    aligned with its end (:func:`~idkit.signal.harmonics.fit_harmonics`). The number of
    harmonics is reduced so that the highest one stays below the Nyquist frequency.

    Parameters
    ----------
    measurement : SteppedSineMeasurement
        One (frequency, amplitude) point.
    n_harmonics : int, default 5
        Output harmonics 1..K (fewer if K f reaches fs/2).
    subharmonic : bool, default True
        Fit the 1/2 subharmonic.

    Returns
    -------
    SteppedSinePoint
    """
    fs = measurement.sample_rate_hz
    freq = measurement.freq
    usable = int(np.ceil(fs / 2 / freq)) - 1
    if usable < 1:
        raise DataError(f"{measurement.id}: frequency {freq:g} Hz is at or above the Nyquist "
                        f"frequency {fs / 2:g} Hz")
    result = hosidf(measurement.v_base, measurement.v_top, fs=fs, freq=freq,
                    n_harmonics=min(int(n_harmonics), usable), subharmonic=subharmonic)
    return SteppedSinePoint(measurement_id=measurement.id, isolator=measurement.info.isolator,
                            top_mass_kg=measurement.info.top_mass_kg, freq=freq, nominal_amplitude=measurement.nominal_amplitude,
                            result=result)


@dataclass(frozen=True)
class SteppedSineSweep:
    """HOSIDFs of a set of stepped-sine points with the input-quality report.

    Attributes
    ----------
    points : tuple of SteppedSinePoint
        Every point, in the order given.
    flatness : dict
        ``{(isolator, top_mass_kg, nominal_amplitude): InputFlatness}``: first-harmonic base
        amplitude versus frequency of each sweep (one nominal level of one setup).
    """

    points: tuple[SteppedSinePoint, ...]
    flatness: dict

    @property
    def max_input_distortion(self) -> float:
        """Largest ``|C2|/|C1|`` or ``|C3|/|C1|`` of the input over all points."""
        values = np.array([p.input_distortion for p in self.points], dtype=float)
        return float(np.nanmax(values)) if values.size else float("nan")

    def to_dataframe(self) -> pd.DataFrame:
        """One row per point: id, isolator, freq, nominal and measured input amplitude,
        input distortion (2nd, 3rd), |HOSIDF| and phase of orders 1..3, |subharmonic|."""
        rows = []
        for p in self.points:
            row = {"measurement_id": p.measurement_id, "isolator": p.isolator, "freq [Hz]": p.freq,
                   "nominal_amplitude": p.nominal_amplitude, "input_amplitude": p.input_amplitude,
                   "input_distortion_2": p.input_distortion[0],
                   "input_distortion_3": p.input_distortion[1]}
            for order in range(1, 4):
                value = p.hosidf[order - 1] if order <= p.hosidf.size else np.nan
                row[f"abs_H{order}"] = abs(value)
                row[f"phase_H{order}_rad"] = float(np.angle(value))
            row["abs_H0.5"] = abs(p.result.subharmonic)
            rows.append(row)
        return pd.DataFrame(rows)

    def report(self) -> str:
        """Input distortion and flatness per sweep."""
        lines = [f"{len(self.points)} stepped-sine points; input distortion up to "
                 f"{self.max_input_distortion:.2%} of the first harmonic"]
        for (isolator, mass, nominal), flat in self.flatness.items():
            lines.append(f"  {isolator} {mass} kg, nominal {nominal:g}: base amplitude max/min "
                         f"{flat.ratio:.2f} ({flat.ratio_db:.1f} dB), min at {flat.freq_of_min:g} Hz, "
                         f"max at {flat.freq_of_max:g} Hz")
        return "\n".join(lines)


def stepped_sine_sweep(measurements: Iterable[SteppedSineMeasurement], *, n_harmonics: int = 5,
                       subharmonic: bool = True) -> SteppedSineSweep:
    """HOSIDFs of every point and the input flatness of every sweep.

    Points are grouped into sweeps by (isolator, top mass, nominal amplitude); the flatness of
    each sweep is :func:`~idkit.signal.harmonics.input_flatness` of the measured first
    harmonic of v_base over frequency (SPEC 3: the shaker does not keep it flat).

    Parameters
    ----------
    measurements : iterable of SteppedSineMeasurement
    n_harmonics, subharmonic : see :func:`hosidf_from_stepped_sine`.

    Returns
    -------
    SteppedSineSweep
    """
    points = tuple(hosidf_from_stepped_sine(m, n_harmonics=n_harmonics, subharmonic=subharmonic)
                   for m in measurements)
    groups: dict = {}
    for p in points:
        groups.setdefault((p.isolator, p.top_mass_kg, p.nominal_amplitude), []).append(p)
    flatness: dict[tuple, InputFlatness] = {}
    for key, members in groups.items():
        members = sorted(members, key=lambda q: q.freq)
        flatness[key] = input_flatness([q.freq for q in members],
                                       [q.input_amplitude for q in members])
    return SteppedSineSweep(points=points, flatness=flatness)


