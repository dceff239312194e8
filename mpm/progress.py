"""A minimal progress bar on stderr for long MPM runs (no extra dependency)."""
from __future__ import annotations

import sys
import time


class ProgressBar:
    """``bar.update(fraction, note)`` redraws at most ~4 times a second; ``close()`` ends the line."""

    def __init__(self, label: str, enabled: bool = True, width: int = 30, stream=None):
        self.label = label
        self.enabled = enabled
        self.width = width
        self.stream = stream or sys.stderr
        self.start = time.perf_counter()
        self._last = 0.0

    def update(self, fraction: float, note: str = "", force: bool = False) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if not force and now - self._last < 0.25:
            return
        self._last = now
        f = min(max(fraction, 0.0), 1.0)
        n = int(round(f * self.width))
        elapsed = now - self.start
        self.stream.write(f"\r{self.label} [{'#' * n}{'.' * (self.width - n)}] "
                          f"{100 * f:5.1f}% {elapsed:6.1f}s {note}")
        self.stream.flush()

    def close(self, note: str = "") -> None:
        if self.enabled:
            self.update(1.0, note, force=True)
            self.stream.write("\n")
            self.stream.flush()
