"""Files -> typed measurement objects (the lowest layer of idkit).

Measurement sets are folders with a ``manifest.json`` and CSV (or ``.mat``)
files whose headers declare units (``force [daN]``); everything is converted
to SI on reading and checked at the boundary (:class:`idkit.errors.DataError`
names file, column, 1-based row, found and expected). The format is written
down in ``docs/data-format.md``.
"""

from idkit.exports import lazy_exports

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
