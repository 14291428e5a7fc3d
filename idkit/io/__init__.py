"""Files -> typed measurement objects (the lowest layer of idkit).

Measurement sets are folders with a ``manifest.json`` and CSV (or ``.mat``)
files whose headers declare units (``force [daN]``); everything is converted
to SI on reading and checked at the boundary (:class:`idkit.errors.DataError`
names file, column, 1-based row, found and expected). The format is written
down in ``docs/data-format.md``.
"""

from idkit.io.complex_stiffness import (
    ComplexStiffnessTable,
    ShiftFactorTable,
    read_complex_stiffness,
    read_shift_factors,
    write_complex_stiffness,
)
from idkit.io.csv_measurement import (
    build_measurement,
    read_csv_measurement,
    write_csv_measurement,
)
from idkit.io.info import Excitation, MeasurementInfo
from idkit.io.manifest import (
    Manifest,
    ManifestEntry,
    MeasurementSet,
    load_measurement_set,
    read_manifest,
    write_measurement_set,
)
from idkit.io.contract import SAMPLE_RATE_TOLERANCE
from idkit.io.matfile import MatColumn, read_mat
from idkit.io.measurements import (
    AccelerationRecord,
    DropMeasurement,
    Measurement,
    QuasiStaticMeasurement,
    SteppedSineMeasurement,
    WhiteNoiseMeasurement,
)
from idkit.io.provenance import Source, file_sha256
from idkit.io.shock_csv import read_shock_csv
from idkit.io.units import accepted_units

__all__ = [
    "SAMPLE_RATE_TOLERANCE",
    "AccelerationRecord",
    "ComplexStiffnessTable",
    "DropMeasurement",
    "Excitation",
    "Manifest",
    "ManifestEntry",
    "MatColumn",
    "Measurement",
    "MeasurementInfo",
    "MeasurementSet",
    "QuasiStaticMeasurement",
    "ShiftFactorTable",
    "Source",
    "SteppedSineMeasurement",
    "WhiteNoiseMeasurement",
    "accepted_units",
    "build_measurement",
    "file_sha256",
    "load_measurement_set",
    "read_complex_stiffness",
    "read_csv_measurement",
    "read_manifest",
    "read_mat",
    "read_shock_csv",
    "read_shift_factors",
    "write_complex_stiffness",
    "write_csv_measurement",
    "write_measurement_set",
]
