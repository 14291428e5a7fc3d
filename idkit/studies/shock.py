"""Shock-record study: from loaded records to pulses, spectra and response ratios.

Compute only (no files, no figures): :func:`analyse_shock` conditions every record, reads
its pulses and its three shock response spectra, and, given the input (fixture) channel,
the response-over-input ratio of every other channel. ``idkit shock`` calls it and
:mod:`idkit.report.shock_files` writes the result.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike

from idkit.errors import DataError
from idkit.io import AccelerationRecord
from idkit.observe.shock import (
    ConditionedShock,
    RecordSpectra,
    ResponseRatio,
    ShockPulses,
    condition_shock,
    default_srs_band,
    record_spectra,
    response_ratio,
    shock_pulses,
)

__all__ = ["ShockAnalysis", "analyse_shock"]


@dataclass(frozen=True)
class ShockAnalysis:
    """Conditioned records, pulses, spectra and ratios of a set of shock channels.

    Attributes
    ----------
    conditioned : tuple of ConditionedShock
        One per channel, input channel last when given.
    pulses : tuple of ShockPulses
    spectra : tuple of RecordSpectra
        On the common natural frequencies ``freq``.
    ratios : tuple of ResponseRatio
        Every non-input channel over the input channel (empty without an input).
    freq : ndarray
        Natural frequencies, Hz.
    damping_ratio : float
    input_channel : str or None
    """

    conditioned: tuple[ConditionedShock, ...]
    pulses: tuple[ShockPulses, ...]
    spectra: tuple[RecordSpectra, ...]
    ratios: tuple[ResponseRatio, ...]
    freq: np.ndarray
    damping_ratio: float
    input_channel: str | None

    def pulse_table(self) -> pd.DataFrame:
        """Pulse characteristics of every channel and test, with the removed offset."""
        frames = []
        for shock, pulses in zip(self.conditioned, self.pulses):
            frame = pulses.to_dataframe()
            frame["offset_removed [m/s^2]"] = shock.offset
            frames.append(frame)
        return pd.concat(frames, ignore_index=True)

    def report(self) -> str:
        """Conditioning and the pulse table as text."""
        lines = [shock.report() for shock in self.conditioned]
        lines.append(self.pulse_table().to_string(index=False, float_format=lambda v: f"{v:.4g}"))
        for ratio in self.ratios:
            low = ratio.freq <= ratio.freq[0] * 3
            lines.append(f"{ratio.response_channel} / {ratio.input_channel}: SRS ratio "
                         f"{np.median(ratio.ratio[:, low]):.3g} (lowest half-decade), "
                         f"{np.median(ratio.ratio[:, -3:]):.3g} (top of the band)")
        return "\n".join(lines)


def analyse_shock(records, *, input: AccelerationRecord | None = None, freq: ArrayLike | None = None,
                  n_points: int = 60, damping_ratio: float = 0.05, offset: str = "pre-trigger",
                  lowpass_hz: float | None = None) -> ShockAnalysis:
    """Condition, characterise and compare shock channels (``idkit shock``).

    Parameters
    ----------
    records : sequence of AccelerationRecord
        Response channels (at least one unless ``input`` is given).
    input : AccelerationRecord, optional
        The input (fixture) channel; ratios are computed against it.
    freq : array_like, optional
        Natural frequencies, Hz; default ``n_points`` over the band of the first record
        (:func:`idkit.observe.shock.default_srs_band`).
    n_points : int, default 60
        Natural frequencies of the default band (unused when ``freq`` is given).
    damping_ratio : float, default 0.05
    offset, lowpass_hz
        See :func:`idkit.observe.shock.condition_shock`.

    Returns
    -------
    ShockAnalysis
    """
    records = list(records)
    channels = records + ([input] if input is not None else [])
    if not channels:
        raise DataError("analyse_shock: no shock records given, expected at least one")
    seen = {}
    for record in channels:  # tables, figures and ratios are keyed by channel: a repeat would overwrite one
        if record.channel in seen:
            raise DataError(f"analyse_shock: channel {record.channel!r} given twice ({seen[record.channel]} and "
                            f"{record.source.path}), expected one record per channel (rename a file or set "
                            "its channel)")
        seen[record.channel] = record.source.path
    conditioned = tuple(condition_shock(record, offset=offset, lowpass_hz=lowpass_hz) for record in channels)
    band = default_srs_band(conditioned[0].record, n_points) if freq is None else np.asarray(freq, dtype=float)
    spectra = tuple(record_spectra(shock.record, freq=band, damping_ratio=damping_ratio) for shock in conditioned)
    ratios = ()
    if input is not None:
        base = conditioned[-1].record
        ratios = tuple(response_ratio(shock.record, base, freq=band, damping_ratio=damping_ratio)
                       for shock in conditioned[:-1])
    return ShockAnalysis(conditioned=conditioned, pulses=tuple(shock_pulses(s.record) for s in conditioned),
                         spectra=spectra, ratios=ratios, freq=spectra[0].freq, damping_ratio=float(damping_ratio),
                         input_channel=None if input is None else conditioned[-1].record.channel)
