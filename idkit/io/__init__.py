"""Files -> typed measurement objects (the lowest layer of idkit).

Measurement sets are folders with a ``manifest.json`` and CSV (or ``.mat``)
files whose headers declare units (``force [daN]``); everything is converted
to SI on reading and checked at the boundary (:class:`idkit.errors.DataError`
names file, column, 1-based row, found and expected). The format is written
down in ``docs/data-format.md``.
"""

from typing import TYPE_CHECKING

from idkit.exports import lazy_exports

if TYPE_CHECKING:  # for type checkers and editors: the names below (tests/test_exports.py keeps them equal)
    from idkit.io.complex_stiffness import (ComplexStiffnessTable, ShiftFactorTable, read_complex_stiffness,
                                            read_shift_factors, write_complex_stiffness)
    from idkit.io.contract import SAMPLE_RATE_TOLERANCE
    from idkit.io.csv_measurement import build_measurement, read_csv_measurement, write_csv_measurement
    from idkit.io.info import Excitation, MeasurementInfo
    from idkit.io.manifest import (Manifest, ManifestEntry, MeasurementSet, load_measurement_set, read_manifest,
                                   write_measurement_set)
    from idkit.io.matfile import MatColumn, read_mat
    from idkit.io.measurements import (AccelerationRecord, DropMeasurement, Measurement, QuasiStaticMeasurement,
                                       SteppedSineMeasurement, WhiteNoiseMeasurement)
    from idkit.io.provenance import Source, file_sha256
    from idkit.io.shock_csv import read_shock_csv
    from idkit.io.units import accepted_units

# imported on first use: reading a light module (idkit.io.columns) does not import pandas
__all__, __getattr__, __dir__ = lazy_exports(__name__, {
    "complex_stiffness": ("ComplexStiffnessTable", "ShiftFactorTable", "read_complex_stiffness", "read_shift_factors",
                          "write_complex_stiffness"),
    "contract": ("SAMPLE_RATE_TOLERANCE",),
    "csv_measurement": ("build_measurement", "read_csv_measurement", "write_csv_measurement"),
    "info": ("Excitation", "MeasurementInfo"),
    "manifest": ("Manifest", "ManifestEntry", "MeasurementSet", "load_measurement_set", "read_manifest",
                 "write_measurement_set"),
    "matfile": ("MatColumn", "read_mat"),
    "measurements": ("AccelerationRecord", "DropMeasurement", "Measurement", "QuasiStaticMeasurement",
                     "SteppedSineMeasurement", "WhiteNoiseMeasurement"),
    "provenance": ("Source", "file_sha256"),
    "shock_csv": ("read_shock_csv",),
    "units": ("accepted_units",),
})
