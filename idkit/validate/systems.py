"""Build the system a measurement describes from identified isolator models."""

from __future__ import annotations

from idkit.errors import ValidationError
from idkit.models import HybridSystem, IsolatorModel, SDOFSystem

__all__ = ["system_for"]


def system_for(measurement, *, isolator: IsolatorModel | None = None, upper: IsolatorModel | None = None,
               lower: IsolatorModel | None = None, system=None):
    """The system of one measurement: a given system, an SDOF with ``isolator``, or a hybrid.

    Masses come from the measurement's ``info`` (``top_mass_kg``,
    ``intermediate_mass_kg``); the hybrid is built from the two identified
    components (SPEC 1.5): top mass - ``upper`` (elastomer) - intermediate - ``lower``
    (wire rope) - base.
    """
    if system is not None:
        return system
    info = measurement.info
    where = info.id or "measurement"
    if info.top_mass_kg is None:
        raise ValidationError(f"{where}: top_mass_kg missing, needed to build the system to simulate")
    if isolator is not None:
        return SDOFSystem(info.top_mass_kg, isolator)
    if upper is not None and lower is not None:
        if info.intermediate_mass_kg is None:
            raise ValidationError(f"{where}: intermediate_mass_kg missing, needed for a hybrid system")
        return HybridSystem(info.top_mass_kg, upper, info.intermediate_mass_kg, lower)
    raise ValidationError("give system=, isolator= or both upper= and lower=")
