"""White-noise runs -> transmissibility H1/H2 and coherence (SPEC 3)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.signal.frf import estimate_frf, FrfEstimate
from idkit.errors import DataError
from idkit.io import (
    WhiteNoiseMeasurement,
)
from idkit.observe._common import _require, _sample_rate


# ---------------------------------------------------------------------------------------------
# white noise


@dataclass(frozen=True)
class WhiteNoiseFrf:
    """Transmissibility estimate of one white-noise run.

    Attributes
    ----------
    measurement_id : str
        ``info.id``.
    top_mass_kg : float or None
        Top mass, kg.
    signals : str
        ``"velocity"`` (v_base -> v_top) or ``"acceleration"`` (a_base -> a_top).
    estimate : FrfEstimate
        Frequencies (Hz), H1, H2, coherence, Welch settings.
    band : tuple of float
        Band kept, Hz.
    """

    measurement_id: str
    top_mass_kg: float | None
    signals: str
    estimate: FrfEstimate
    band: tuple[float, float]

    @property
    def freq(self) -> np.ndarray:
        """Frequencies, Hz."""
        return self.estimate.freq

    @property
    def h1(self) -> np.ndarray:
        """H1 transmissibility (dimensionless)."""
        return self.estimate.h1

    @property
    def h2(self) -> np.ndarray:
        """H2 transmissibility (dimensionless)."""
        return self.estimate.h2

    @property
    def coherence(self) -> np.ndarray:
        """Ordinary coherence in [0, 1]."""
        return self.estimate.coherence

    @property
    def min_coherence(self) -> float:
        """Lowest coherence in the band."""
        return float(self.coherence.min())

    @property
    def mean_coherence(self) -> float:
        """Mean coherence in the band."""
        return float(self.coherence.mean())

    def to_dataframe(self) -> pd.DataFrame:
        """One row per frequency (see :meth:`FrfEstimate.to_dataframe`)."""
        table = self.estimate.to_dataframe()
        table.insert(0, "measurement_id", self.measurement_id)
        return table

    def report(self) -> str:
        """Short text summary."""
        peak = int(np.argmax(np.abs(self.h1)))
        return (f"{self.measurement_id}: {self.band[0]:g}-{self.band[1]:g} Hz, peak |H1| "
                f"{abs(self.h1[peak]):.3g} at {self.freq[peak]:.3g} Hz, coherence mean "
                f"{self.mean_coherence:.3f} min {self.min_coherence:.3f}, "
                f"{self.estimate.n_segments} segments of {self.estimate.nperseg}")


def frf_from_white_noise(measurement: WhiteNoiseMeasurement, *,
                         band: tuple[float, float] | None = None,
                         nperseg: int | None = None, overlap: float = 0.5,
                         signals: str | None = None) -> WhiteNoiseFrf:
    """H1, H2 and coherence of a white-noise shaker run (Welch, Hann window).

    Parameters
    ----------
    measurement : WhiteNoiseMeasurement
        Base and top-mass velocities (or accelerations).
    band : (float, float), optional
        Band kept, Hz. Default: the declared excitation band (``info.excitation.band``)
        clipped to the Nyquist frequency, or 0 - Nyquist. SPEC 3 identifies on (1, 100).
    nperseg : int, optional
        Samples per segment. Default ``min(round(2 fs), n // 4)``: 0.5 Hz resolution when
        the record holds at least 4 segments (7 averages at 50 % overlap).
    overlap : float, default 0.5
        Segment overlap fraction.
    signals : {"velocity", "acceleration"}, optional
        Which pair to use; default velocity when present.

    Returns
    -------
    WhiteNoiseFrf

    Raises
    ------
    DataError
        Wrong measurement type, requested signals missing, or the errors of
        :func:`~idkit.signal.frf.estimate_frf`.
    """
    _require(measurement, WhiteNoiseMeasurement, "frf_from_white_noise")
    if signals is None:
        signals = "velocity" if measurement.v_base is not None else "acceleration"
    if signals == "velocity":
        base, top = measurement.v_base, measurement.v_top
    elif signals == "acceleration":
        base, top = measurement.a_base, measurement.a_top
    else:
        raise DataError(f"signals: found {signals!r}, expected 'velocity' or 'acceleration'")
    if base is None:
        raise DataError(f"{measurement.id}: no {signals} signals in the measurement")
    fs = _sample_rate(measurement.time)
    if band is None:
        declared = measurement.band
        band = (0.0, fs / 2) if declared is None else (declared[0], min(declared[1], fs / 2))
    band = (float(band[0]), float(band[1]))
    if nperseg is None:
        nperseg = int(min(round(2 * fs), base.size // 4))
    estimate = estimate_frf(base, top, fs=fs, nperseg=nperseg, overlap=overlap,
                            f_lo=band[0], f_hi=band[1])
    return WhiteNoiseFrf(measurement_id=measurement.id, top_mass_kg=measurement.info.top_mass_kg,
                         signals=signals, estimate=estimate, band=band)


