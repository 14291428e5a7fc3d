"""Drop records -> impact, impact velocity and shock peaks (SPEC 3, 5)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pandas as pd

from idkit.checks import Instance, accepts
from idkit.errors import DataError
from idkit.signal.drop import DropResult, process_drop
from idkit.io import DropMeasurement
from idkit.observe._common import MeasuredRecord


@dataclass(frozen=True)
class DropMeasurementResult(MeasuredRecord):
    """Characteristic values of one drop test.

    Attributes
    ----------
    measurement_id, isolator, top_mass_kg
        The record (:class:`~idkit.observe._common.MeasuredRecord`).
    drop_height_m : float or None
        Declared drop height, m.
    result : DropResult
        Impact, impact velocities (measured and from the height), phase peaks, peak
        deflections and the processed records.
    """

    drop_height_m: float | None
    result: DropResult

    @property
    def impact_velocity(self) -> float:
        """Measured impact velocity, m/s (negative)."""
        return self.result.impact_velocity

    @property
    def impact_velocity_from_height(self) -> float:
        """``-sqrt(2 g h)`` from the declared height, m/s."""
        return self.result.impact_velocity_from_height

    @property
    def peak_acceleration(self) -> float:
        """Rest shock level: largest acceleration magnitude after the impact, m/s^2."""
        return self.result.peak_acceleration

    def to_dataframe(self) -> pd.DataFrame:
        """One-row table (see :meth:`DropResult.to_dataframe`) with id, masses and height."""
        table = self.result.to_dataframe()
        table.insert(0, "drop_height [m]", self.drop_height_m)
        table.insert(0, "top_mass [kg]", self.top_mass_kg)
        table.insert(0, "isolator", self.isolator)
        table.insert(0, "measurement_id", self.measurement_id)
        return table


@accepts(measurement=Instance((DropMeasurement,)), error=DataError)
def process_drop_measurement(measurement: DropMeasurement, *, window: int = 5,
                             impact_fraction: float = 0.5) -> DropMeasurementResult:
    """Process one drop test (SPEC 3): mean of the two accelerometers, zero-phase 5-sample
    moving average, impact from the step in relative velocity, shock peaks.

    The relative velocity is the recorded ``v_rel`` (laser vibrometer) when present,
    otherwise the derivative of the deflection. Accelerations are used as recorded
    (kinematic, 1 g offset removed at rest), see :func:`~idkit.signal.drop.process_drop`.

    Parameters
    ----------
    measurement : DropMeasurement
        The drop record; ``info.drop_height_m`` gives the height-based impact velocity.
    window : int, default 5
        Moving-average length, samples.
    impact_fraction : float, default 0.5
        Fraction of the most negative relative velocity that marks the impact.

    Returns
    -------
    DropMeasurementResult
    """
    result = process_drop(measurement.time, measurement.deflection,
                          np.vstack([measurement.a_top_1, measurement.a_top_2]),
                          relative_velocity=measurement.v_rel,
                          drop_height=measurement.info.drop_height_m, window=window,
                          impact_fraction=impact_fraction)
    info = measurement.info
    return DropMeasurementResult(measurement_id=measurement.id, isolator=info.isolator,
                                 top_mass_kg=info.top_mass_kg, drop_height_m=info.drop_height_m,
                                 result=result)


