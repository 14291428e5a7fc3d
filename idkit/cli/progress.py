"""A plain text progress bar on stderr (no dependency)."""

from __future__ import annotations

import sys
import time


class ProgressBar:
    """Callable ``(done, total)`` that redraws one stderr line; silent when disabled."""

    def __init__(self, label: str, *, enabled: bool = True, stream=None):
        self.label = label
        self.enabled = enabled
        self.stream = stream or sys.stderr
        self.start = time.perf_counter()

    def __call__(self, done: int, total: int) -> None:
        if not self.enabled:
            return
        width = 30
        filled = int(width * done / max(total, 1))
        elapsed = time.perf_counter() - self.start
        self.stream.write(f"\r{self.label} [{'#' * filled}{'.' * (width - filled)}] {done}/{total} {elapsed:5.1f} s")
        if done >= total:
            self.stream.write("\n")
        self.stream.flush()


def say(message: str, *, enabled: bool = True) -> None:
    """One status line on stderr."""
    if enabled:
        print(message, file=sys.stderr, flush=True)
