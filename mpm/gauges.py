"""Stress gauges for dynamic runs: the wave-transmission measurement of 002 Sec 3.3.

002 Fig 10 sends the half-sine displacement pulse of Eq 49 through an imperfect
interface and reports the transmitted energy as the squared ratio of the peak normal
stress of the transmitted pulse to that of the incident pulse, read at two gauges: one
in the incident body and one in the transmitted body
(``measurements["transmitted_energy"]``); the measures themselves, with the pulse
energies, are computed by :func:`interfaces.wave_gauges.pulse_measures`, shared with the
transient FEM.

A gauge is the column of particles whose initial position lies nearest the gauge
coordinate along the propagation axis (x), restricted to the middle half of the
specimen across it (away from lateral edges); it records their mean normal stress
sigma_xx at every sample.
"""
from __future__ import annotations

import numpy as np

from interfaces.wave_gauges import (GAUGE_KEYS, body_at, gauge_spec, longitudinal_impedance,
                                    pulse_measures, reflection_arrival)


class StressGauges:
    """Mean sigma_xx over the particle columns at the case's gauge positions."""

    def __init__(self, case, x0: np.ndarray, spacing: np.ndarray):
        spec = gauge_spec(case)
        lo, hi = case.bounds()
        mid = 0.5 * (lo[1] + hi[1])
        quarter = 0.25 * (hi[1] - lo[1])
        across = np.abs(x0[:, 1] - mid) <= quarter
        self.positions = {}
        self.members = {}
        for key in GAUGE_KEYS:
            dist = np.abs(x0[:, 0] - spec[key])
            nearest = dist[across].min()
            sel = np.flatnonzero(across & (dist <= nearest + 0.25 * spacing[0]))
            self.positions[key] = float(np.mean(x0[sel, 0]))
            self.members[key] = sel
        self.reflection_arrival = reflection_arrival(case, dict(spec, x_incident=self.positions["x_incident"]))
        self.Z = [longitudinal_impedance(body_at(case, spec[k]), case.analysis) for k in GAUGE_KEYS]
        self.area = float(hi[1] - lo[1]) * case.thickness
        self.times: list[float] = []
        self.samples: list[tuple[float, float]] = []

    def sample(self, t: float, particles) -> None:
        """Record the gauges' mean sigma_xx at time t (``particles``: the run's
        :class:`mpm.particles.Particles`; a gauge's particles share one volume)."""
        stress = particles.stress
        self.times.append(t)
        self.samples.append(tuple(float(stress[sel, 0].mean()) for sel in self.members.values()))

    def quantities(self) -> dict:
        """The 002 Sec 3.3 measures (:func:`interfaces.wave_gauges.pulse_measures`)."""
        if not self.samples:
            return {}
        s = np.asarray(self.samples)
        return pulse_measures(self.times, s[:, 0], s[:, 1], self.reflection_arrival,
                              self.Z[0], self.Z[1], self.area)

    def history(self) -> dict:
        """Gauge records for plotting: time (s), positions (mm), sigma_xx (MPa) per gauge."""
        s = np.asarray(self.samples) if self.samples else np.zeros((0, 2))
        return {"time": list(self.times),
                "positions": dict(self.positions),
                **{f"sigma_xx_{key}": s[:, j].tolist() for j, key in enumerate(self.members)}}
