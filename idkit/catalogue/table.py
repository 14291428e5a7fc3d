"""The table of parts of a catalogue: one row per part, units in the column names.

CSV always (``parts.csv``); Parquet (``parts.parquet``) as well when ``pyarrow`` is installed
(it is not a dependency of idkit; ``catalogue.json`` carries everything the table shows and
more, in a format every tool reads).
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import pandas as pd

from idkit.atomic import write_bytes_atomic

__all__ = ["QUANTITY_COLUMNS", "parts_table", "write_parts_table"]

#: Summary quantities (idkit.catalogue.identify.part_quantities) and their table columns.
QUANTITY_COLUMNS = {
    "stiffness_at_table_freq": "|k*(5 Hz)| [N/m]",
    "stuck_stiffness": "stuck stiffness g1 + sum k_i [N/m]",
    "g1": "g1 [N/m]",
    "total_slip_force": "total slip force sum fc_i [N]",
    "k0": "k0 [N/m]",
    "loss_factor": "loss factor at 5 Hz [-]",
}
_DIMENSION_UNITS = {"cable_diameter_m": "cable diameter [m]", "loops": "loops [-]", "height_m": "height [m]",
                    "width_m": "width [m]", "area_m2": "area [m^2]", "thickness_m": "thickness [m]",
                    "shape_factor": "shape factor [-]", "compound": "compound"}


def parts_table(records) -> pd.DataFrame:
    """One row per part record (``catalogue.json``'s ``parts``).

    Columns: ``part``, ``family``, ``status`` (identified / not a success / failed),
    ``held-out verdict``, the dimensions, ``model``, ``order``, the summary quantities
    (:data:`QUANTITY_COLUMNS`), ``valid range [m]``, ``reasons`` and ``model file``.
    """
    rows = []
    for record in records:
        row = {"part": record["part"], "family": record.get("family", ""), "status": record["status"],
               "held-out verdict": record.get("held_out", {}).get("verdict", "")}
        for name, value in record.get("dimensions", {}).items():
            row[_DIMENSION_UNITS.get(name, name)] = value
        row["model"] = record.get("model_kind", "")
        row["order"] = record.get("order")
        for key, column in QUANTITY_COLUMNS.items():
            row[column] = record.get("quantities", {}).get(key)
        valid = record.get("valid_range_m")
        row["valid range [m]"] = "" if not valid else f"{valid[0]:.4g} to {valid[1]:.4g}"
        row["reasons"] = "; ".join(record.get("reasons", []) + record.get("held_out", {}).get("why", []))
        row["model file"] = record.get("model_file", "")
        rows.append(row)
    return pd.DataFrame(rows)


def write_parts_table(table: pd.DataFrame, folder) -> list[Path]:
    """Write ``parts.csv`` (and ``parts.parquet`` when pyarrow is installed) into ``folder``, atomically."""
    folder = Path(folder)
    written = [write_bytes_atomic(folder / "parts.csv", table.to_csv(index=False).encode(), overwrite=True)]
    if importlib.util.find_spec("pyarrow") is not None:  # optional: not an idkit dependency
        written.append(write_bytes_atomic(folder / "parts.parquet", table.to_parquet(index=False), overwrite=True))
    return written
