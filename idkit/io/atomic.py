"""Atomic file writing for the io layer (the implementation is shared: :mod:`idkit.atomic`)."""

from idkit.atomic import write_bytes_atomic

__all__ = ["write_bytes_atomic"]
