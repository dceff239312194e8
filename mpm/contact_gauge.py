"""Mean axial stress of bodies over time, and the contact time of two bodies closing a
gap (004 Sec 2.2, Fig 2 and 5).

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

``measurements["axial_stress"]`` (004 Fig 5) records the mean axial stress over the
particles of ``bodies`` (all deformable bodies of a stack) every ``sample_every``
seconds; the quantity is its last value.

The mean is the volume average sum V_p sigma_p / sum V_p over the current particle
volumes V_p = J_p V_p0, the average stress NairnMPM reports (its global ``syy``) and
004 plots (in static equilibrium the integral of the stress over the bodies is the first
moment of the tractions on their boundary). A plain mean over the particles would weigh
the most compressed particles, whose volume has shrunk most, as much as the rest: at
75 % compaction of the 004 Fig 6 ellipses it reads 8 % (0.0143 mm cells) to 17 %
(0.025 mm) higher.

Same interface as :class:`mpm.gauges.StressGauges` (``times``, ``samples``,
``sample``, ``quantities``, ``history``), so the runner and the checkpoints treat all
alike.
"""
from __future__ import annotations

import numpy as np

from interfaces.errors import CaseError, check_number

_COMPONENTS = {"xx": 0, "yy": 1}


class AxialStressGauge:
    """Mean axial stress over the particles of some bodies, over time."""

    measurement = "axial_stress"

    def __init__(self, case, field: np.ndarray, C: list):
        spec = dict(case.measurements[self.measurement])     # fields checked by Case
        names = [b.name for b in case.bodies]
        where = f"measurements.{self.measurement}"
        bodies = spec.get("bodies", [spec.get("body")])
        if not isinstance(bodies, (list, tuple)) or not bodies or any(b not in names for b in bodies):
            raise CaseError(f"{where}.body(ies) must name bodies of {names}, got {bodies!r}")
        comp = spec.get("component", "yy")
        if comp not in _COMPONENTS:
            raise CaseError(f"{where}.component must be 'xx' or 'yy', got {comp!r}")
        index = [names.index(b) for b in bodies]
        self.members = np.flatnonzero(np.isin(field, index))
        self.component = _COMPONENTS[comp]
        self.sample_every = check_number(f"{where}.sample_every", spec.get("sample_every"),
                                         low=0.0, low_open=True)
        self.modulus = max(float(np.max(np.diag(C[k]))) for k in index)
        self.threshold = spec.get("threshold")
        self.times: list[float] = []
        self.samples: list[tuple[float]] = []

    def sample(self, t: float, particles) -> None:
        """Record the bodies' volume-averaged axial stress at time t (``particles``: the
        run's :class:`mpm.particles.Particles`)."""
        volume = particles.volume[self.members]
        stress = particles.stress[self.members, self.component]
        self.times.append(t)
        self.samples.append((float(np.dot(volume, stress) / volume.sum()),))

    def quantities(self) -> dict:
        return {"axial_stress": self.samples[-1][0]} if self.samples else {}

    def history(self) -> dict:
        """Time (s) and the bodies' mean axial stress (MPa), for the plots."""
        return {"time": list(self.times),
                "axial_stress": [s[0] for s in self.samples]}


class ContactGauge(AxialStressGauge):
    """Mean axial stress of the struck body over time and its first departure from 0."""

    measurement = "contact_time"

    def contact_time(self) -> float:
        """First sample time with |mean stress| > threshold (inf if never)."""
        threshold = self.threshold if self.threshold is not None else 1e-9 * self.modulus
        s = np.abs(np.asarray(self.samples, float).reshape(-1))
        hit = np.flatnonzero(s > threshold)
        return float(self.times[hit[0]]) if hit.size else float("inf")

    def quantities(self) -> dict:
        return {"contact_time": self.contact_time()} if self.samples else {}
