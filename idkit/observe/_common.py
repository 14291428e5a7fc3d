"""Helpers shared by the observers."""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class MeasuredRecord:
    """The record an observable was read from; the first fields of every per-record observable.

    Attributes
    ----------
    measurement_id : str
        ``info.id``.
    isolator : str or None
        Isolator name.
    top_mass_kg : float or None
        Top mass, kg.
    """

    measurement_id: str
    isolator: str | None
    top_mass_kg: float | None
