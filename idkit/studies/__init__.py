"""Studies: whole computations of the thesis chapters and the transport study.

Compute only: every function returns a typed result; figures are drawn by :mod:`idkit.plot`
and files written by :mod:`idkit.report`.

- :mod:`~idkit.studies.transport` - the transport systems, their tuning and the study itself.
"""

from idkit.studies.transport import (
    RK_VALUES,
    transport_systems,
    TransportSystem,
    tuning_table,
)

__all__ = [
    "RK_VALUES",
    "transport_systems",
    "TransportSystem",
    "tuning_table",
]
