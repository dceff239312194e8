"""Contact time of two bodies closing a gap (004 Sec 2.2, Fig 2).

004 Fig 2 pushes one block onto another across a gap and reads, from the average
axial stress, when each contact method lets the blocks touch. Here the gauge records
the mean axial stress of the *struck* body (``measurements["contact_time"]["body"]``),
which is held at its far side and untouched until momentum crosses the gap: its stress
is exactly zero until the first contact correction (real or false) reaches it. The
contact time is the first sample at which that mean stress leaves zero by more than
``threshold`` (MPa; default 1e-9 of the body's largest modulus, far below any
elastic signal and far above round-off of a body at rest, which is exactly 0).
Samples are ``sample_every`` seconds apart (the solver's output interval is shortened
to it), so the time is resolved to that interval.

Same interface as :class:`mpm.gauges.StressGauges` (``times``, ``samples``,
``sample``, ``quantities``, ``history``), so the runner and the checkpoints treat both
alike.
"""
from __future__ import annotations

import numpy as np

from interfaces.errors import CaseError, check_number

_COMPONENTS = {"xx": 0, "yy": 1}


class ContactGauge:
    """Mean axial stress of one body's particles over time and its first departure from 0."""

    def __init__(self, case, field: np.ndarray, C: list):
        spec = dict(case.measurements["contact_time"])     # fields checked by Case
        names = [b.name for b in case.bodies]
        if spec.get("body") not in names:
            raise CaseError(f"measurements.contact_time.body must be one of {names}, got {spec.get('body')!r}")
        comp = spec.get("component", "yy")
        if comp not in _COMPONENTS:
            raise CaseError(f"measurements.contact_time.component must be 'xx' or 'yy', got {comp!r}")
        index = names.index(spec["body"])
        self.members = np.flatnonzero(field == index)
        self.component = _COMPONENTS[comp]
        self.sample_every = check_number("measurements.contact_time.sample_every",
                                         spec.get("sample_every"), low=0.0, low_open=True)
        modulus = float(np.max(np.diag(C[index])))
        self.threshold = check_number("measurements.contact_time.threshold",
                                      spec.get("threshold", 1e-9 * modulus), low=0.0, low_open=True)
        self.times: list[float] = []
        self.samples: list[tuple[float]] = []

    def sample(self, t: float, stress: np.ndarray) -> None:
        """Record the body's mean axial stress at time t."""
        self.times.append(t)
        self.samples.append((float(stress[self.members, self.component].mean()),))

    def contact_time(self) -> float:
        """First sample time with |mean stress| > threshold (inf if never)."""
        s = np.abs(np.asarray(self.samples, float).reshape(-1))
        hit = np.flatnonzero(s > self.threshold)
        return float(self.times[hit[0]]) if hit.size else float("inf")

    def quantities(self) -> dict:
        return {"contact_time": self.contact_time()} if self.samples else {}

    def history(self) -> dict:
        """Time (s) and the body's mean axial stress (MPa), for the plots."""
        return {"time": list(self.times),
                "axial_stress": [s[0] for s in self.samples]}
