"""Progress of long MPM runs on stderr: tqdm (a dependency) with a plain fallback.

``bar.update(fraction, note)`` moves the bar to ``fraction`` of the run (never back) and
shows ``note``; ``close(note)`` ends the line. An ``open_ended`` run (quasi-static: it
stops when it comes to rest, often long before the time limit the bar measures) shows no
remaining-time estimate, which would count to the limit (35 min for a 4 min DCB run).
The first run of an installation also says that numba is compiling the kernels
(:func:`compile_notice`), so minutes of silence are explained.
"""
from __future__ import annotations

import sys
import time

_RESOLUTION = 1000      # bar units per run


class ProgressBar:
    """A run's progress in [0, 1] with a short note (time, kinetic/stored energy)."""

    def __init__(self, label: str, enabled: bool = True, stream=None, open_ended: bool = False):
        self.label = label
        self.enabled = enabled
        self.stream = stream or sys.stderr
        self._bar = None
        self._start = time.perf_counter()
        self._last = 0.0
        if enabled:
            try:
                from tqdm import tqdm
                timing = "{elapsed}" if open_ended else "{elapsed}<{remaining}"
                self._bar = tqdm(total=_RESOLUTION, desc=label, file=self.stream, dynamic_ncols=True,
                                 bar_format="{desc} {percentage:5.1f}%|{bar}| " + timing + "{postfix}",
                                 mininterval=0.25)
            except ImportError:          # plain fallback
                self._bar = None

    def update(self, fraction: float, note: str = "", force: bool = False) -> None:
        if not self.enabled:
            return
        f = min(max(fraction, 0.0), 1.0)
        if self._bar is not None:
            target = int(round(f * _RESOLUTION))
            if target > self._bar.n:
                self._bar.update(target - self._bar.n)
            self._bar.set_postfix_str(note, refresh=force)
            return
        now = time.perf_counter()
        if not force and now - self._last < 0.25:
            return
        self._last = now
        self.stream.write(f"\r{self.label} {100 * f:5.1f}% {now - self._start:6.1f}s {note}")
        self.stream.flush()

    def close(self, note: str = "") -> None:
        if not self.enabled:
            return
        self.update(1.0, note, force=True)
        if self._bar is not None:
            self._bar.close()
        else:
            self.stream.write("\n")
            self.stream.flush()


def compile_notice(cold: bool, what: str = "MPM", stream=None) -> None:
    """Say once that the kernels are being compiled (first run of an installation)."""
    if cold:
        (stream or sys.stderr).write(f"{what}: compiling the numba kernels for this installation "
                                     "(first run only; a few minutes, cached afterwards) ...\n")
        (stream or sys.stderr).flush()
