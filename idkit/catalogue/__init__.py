"""Catalogues of identified parts, and the scaling laws of a family over its dimensions.

:func:`build_catalogue` identifies every part of a folder of measurement sets (each with a
``part.json`` naming its family and dimensions) into a catalogue folder: model files with
provenance, covariance, valid range and verdicts, and one table of parts.
:func:`fit_scaling_laws` fits a family's summary quantities as power laws of its dimensions
with their covariance, predicts unmeasured parts with a prediction band and reports the
leave-one-part-out coverage. ``docs/catalogue.md`` describes both.
"""

from idkit.catalogue.build import (
    CATALOGUE_FILE,
    FAMILY_DIMENSIONS,
    Catalogue,
    build_catalogue,
    find_parts,
    load_catalogue,
    read_part,
)
from idkit.catalogue.identify import FITTERS, Identified, covariance_of, identify_measurements, part_quantities
from idkit.catalogue.table import parts_table

__all__ = [
    "CATALOGUE_FILE",
    "FAMILY_DIMENSIONS",
    "FITTERS",
    "Catalogue",
    "Identified",
    "build_catalogue",
    "covariance_of",
    "find_parts",
    "identify_measurements",
    "load_catalogue",
    "part_quantities",
    "parts_table",
    "read_part",
]
