"""Names and the seed of the synthetic data, in a light module: the ``idkit data generate``
options offer them without importing the generator (scipy, numba)."""

from __future__ import annotations

__all__ = ["DEFAULT_SEED", "SET_NAMES", "TRUTH_NAMES"]

#: Master seed of the bundled ``data/``.
DEFAULT_SEED = 2026

#: The measurement sets the generator writes, one folder each.
SET_NAMES = ("wire_rope", "elastomer", "hybrid")

#: Named truths of the generator: ``"a"`` made the bundled data, ``"b"`` is the second truth.
TRUTH_NAMES = ("a", "b")
