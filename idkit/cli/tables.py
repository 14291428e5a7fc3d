"""Tables of the commands: printed, or written as CSV or JSON (one writer for every command)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np

__all__ = ["json_records", "write_table"]


def json_records(frame) -> str:
    """``frame`` as JSON records, every number as written by CSV (shortest round-trip repr;
    pandas' ``to_json`` keeps 10 decimals: a 1e-11 m amplitude became 0.0); NaN as null."""
    def value(cell):
        if isinstance(cell, (float, np.floating)):
            return float(cell) if np.isfinite(cell) else None
        return cell.item() if isinstance(cell, np.generic) else cell

    records = [{column: value(cell) for column, cell in row.items()} for row in frame.to_dict(orient="records")]
    return json.dumps(records, indent=1, allow_nan=False) + "\n"


def write_table(frame, output) -> None:
    """Print ``frame``, or write it atomically to ``output`` (JSON records for a .json suffix, else CSV)."""
    from idkit.atomic import write_text_atomic

    if output is None:
        print(frame.to_string(index=False))
        return
    output = Path(output)
    text = json_records(frame) if output.suffix == ".json" else frame.to_csv(index=False)
    write_text_atomic(output, text)
    print(f"wrote {output}", file=sys.stderr)
