"""Reports and the demo job (top layer: may import every other layer)."""

from idkit.report.demo import run_demo
from idkit.atomic import atomic_output_folder

__all__ = ["run_demo", "atomic_output_folder"]
