"""Stress gauges for dynamic runs: the wave-transmission measurement of 002 Sec 3.3.

002 Fig 10 sends a one-period cosine displacement pulse (Eq 49) through an imperfect
interface and reports the transmitted energy as the squared ratio of the peak normal
stress of the transmitted pulse to that of the incident pulse, read at two gauges: one
in the incident body and one in the transmitted body. The case declares them in
``measurements["transmitted_energy"] = {"x_incident", "x_transmitted", "duration"}``;
``interfaces.analytic`` gives the exact value of the same measure for a 1D pulse
(``measure = "pulse_peak"``).

A gauge is the column of particles whose initial position lies nearest the gauge
coordinate along the propagation axis (x), restricted to the middle half of the
specimen across it (away from the lateral free edges, where the 2D plane wave is not
uniaxial strain); it records their mean normal stress sigma_xx at every sample.
"""
from __future__ import annotations

import math

import numpy as np

from interfaces.errors import CaseError


class StressGauges:
    """Mean sigma_xx over the particle columns at the case's gauge positions."""

    def __init__(self, case, x0: np.ndarray, spacing: np.ndarray, spec: dict):
        """``spec``: x_incident, x_transmitted (mm) and optionally x_interface (mm, else
        midway): the incident peak is searched before the wave reflected at the
        interface can reach the incident gauge, t < (2 x_interface - x_incident) / c with
        c the fastest wave speed of the case's materials."""
        names = ("x_incident", "x_transmitted")
        for key in names:
            if key not in spec:
                raise CaseError(f"measurements.transmitted_energy.{key} (mm) is required for "
                                "the MPM stress gauges")
        lo, hi = case.bounds()
        mid = 0.5 * (lo[1] + hi[1])
        quarter = 0.25 * (hi[1] - lo[1])
        across = np.abs(x0[:, 1] - mid) <= quarter
        self.positions = {}
        self.members = {}
        for key in names:
            xg = float(spec[key])
            if not lo[0] < xg < hi[0]:
                raise CaseError(f"measurements.transmitted_energy.{key} = {xg:g} mm must lie "
                                f"inside the specimen ({lo[0]:g}, {hi[0]:g})")
            dist = np.abs(x0[:, 0] - xg)
            nearest = dist[across].min()
            sel = np.flatnonzero(across & (dist <= nearest + 0.25 * spacing[0]))
            self.positions[key] = float(np.mean(x0[sel, 0]))
            self.members[key] = sel
        x_int = float(spec.get("x_interface", 0.5 * (spec["x_incident"] + spec["x_transmitted"])))
        c = max(mat.wave_speed(case.analysis) for mat in case.materials.values())
        self.reflection_arrival = (2.0 * x_int - self.positions["x_incident"]) / c
        self.times: list[float] = []
        self.samples: list[tuple[float, float]] = []

    def sample(self, t: float, stress: np.ndarray) -> None:
        """Record the gauges' mean sigma_xx at time t."""
        self.times.append(t)
        self.samples.append(tuple(float(stress[sel, 0].mean()) for sel in self.members.values()))

    def quantities(self) -> dict:
        """``transmitted_energy`` = (peak transmitted / peak incident sigma_xx)^2, the
        peaks taken with the sign of the incident pulse's largest stress (002 Sec 3.3);
        the incident peak before the reflection arrives at its gauge."""
        if not self.samples:
            return {}
        s = np.asarray(self.samples)
        before = np.asarray(self.times) < self.reflection_arrival
        inc, tr = s[before, 0], s[:, 1]
        if inc.size == 0:
            return {}
        k = int(np.argmax(np.abs(inc)))
        sign = math.copysign(1.0, inc[k]) if inc[k] != 0.0 else 1.0
        peak_inc = float(np.max(sign * inc))
        peak_tr = float(np.max(sign * tr))
        if peak_inc <= 0.0:
            return {}
        return {"transmitted_energy": (max(peak_tr, 0.0) / peak_inc) ** 2,
                "incident_peak_stress": sign * peak_inc,
                "transmitted_peak_stress": sign * max(peak_tr, 0.0)}

    def history(self) -> dict:
        """Gauge records for plotting: time (s), positions (mm), sigma_xx (MPa) per gauge."""
        s = np.asarray(self.samples) if self.samples else np.zeros((0, 2))
        return {"time": list(self.times),
                "positions": dict(self.positions),
                **{f"sigma_xx_{key}": s[:, j].tolist() for j, key in enumerate(self.members)}}
