"""The wave-transmission measurement of 002 Sec 3.3 from two stress-gauge records.

Shared by the dynamic methods (MPM, transient FEM), which only differ in how they
read the normal stress sigma_xx at the two gauge positions of
``case.measurements["transmitted_energy"] = {x_incident, x_transmitted, x_interface,
duration}``: one in the incident body before the interface, one in the transmitted
body after it.

* ``transmitted_energy``: 002 Sec 3.3 "calculated from the square of ratio of the
  amplitudes of the transmitted stress to the incident stress", times Z1/Z2 (1 for
  identical materials): ``(Z1/Z2) (peak s_t / peak s_i)^2``, the peaks taken with the
  sign of the incident pulse. The exact value of this measure for the Eq 49 pulse is
  ``interfaces.analytic.pulse_transmission(...)["peak_ratio_squared"]``.
* ``pulse_transmitted_energy``: the energy-flux ratio of the two pulses,
  ``(Z1/Z2) int s_t^2 dt / int s_i^2 dt`` (a plane wave carries s^2 / Z per unit area
  and time), exact value ``pulse_transmission(...)["transmitted_energy"]``.
* ``incident_pulse_energy`` (N mm): ``area int s_i^2 / Z1 dt`` through the cross-section.

The incident record is used before the reflection from the interface reaches its gauge
(t < (2 x_interface - x_incident) / c1); the transmitted record over the whole run,
which the case ends before any echo reaches the transmitted gauge.
Units: MPa, s, Z in MPa s/mm, area in mm^2.
"""
from __future__ import annotations

import math

import numpy as np

from .errors import CaseError

GAUGE_KEYS = ("x_incident", "x_transmitted")
_trapezoid = getattr(np, "trapezoid", None) or np.trapz  # numpy < 2 has only trapz


def gauge_spec(case) -> dict:
    """The validated gauge positions (mm) of the case's transmitted_energy measurement."""
    spec = case.measurements.get("transmitted_energy")
    if spec is None:
        raise CaseError("measurements.transmitted_energy is missing: a dynamic wave measurement "
                        "needs the gauge positions x_incident, x_transmitted (mm)")
    lo, hi = case.bounds()
    out = {}
    for key in GAUGE_KEYS:
        if key not in spec:
            raise CaseError(f"measurements.transmitted_energy.{key} (mm) is required for the stress gauges")
        xg = float(spec[key])
        if not lo[0] < xg < hi[0]:
            raise CaseError(f"measurements.transmitted_energy.{key} = {xg:g} mm must lie "
                            f"inside the specimen ({lo[0]:g}, {hi[0]:g})")
        out[key] = xg
    out["x_interface"] = float(spec.get("x_interface", 0.5 * (out["x_incident"] + out["x_transmitted"])))
    return out


def longitudinal_impedance(material, analysis: str) -> float:
    """Z = rho c of the longitudinal wave of the case's 1D state, c = sqrt(C11 / rho)
    from the material's stiffness in ``analysis`` (uniaxial strain in plane strain)."""
    C = np.asarray(material.stiffness(analysis), float)
    return math.sqrt(C[0, 0] * material.rho)


def body_at(case, x: float):
    """The material of the body holding the point (x, mid-height)."""
    lo, hi = case.bounds()
    p = np.array([[x, 0.5 * (lo[1] + hi[1])]])
    for b in case.bodies:
        if b.contains(p)[0]:
            return case.materials[b.material]
    raise CaseError(f"no body holds the gauge at x = {x:g} mm")


def pulse_measures(times, s_incident, s_transmitted, reflection_arrival: float,
                   Z1: float, Z2: float, area: float) -> dict:
    """002 Sec 3.3 measures from gauge records (module docstring); {} when the incident
    record holds no pulse before ``reflection_arrival``."""
    t = np.asarray(times, float)
    si, st = np.asarray(s_incident, float), np.asarray(s_transmitted, float)
    before = t < reflection_arrival
    inc = si[before]
    if inc.size < 2:
        return {}
    k = int(np.argmax(np.abs(inc)))
    sign = math.copysign(1.0, inc[k]) if inc[k] != 0.0 else 1.0
    peak_inc = float(np.max(sign * inc))
    if peak_inc <= 0.0:
        return {}
    peak_tr = max(float(np.max(sign * st)), 0.0)
    e_inc = float(_trapezoid(inc ** 2, t[before])) / Z1
    e_tr = float(_trapezoid(st ** 2, t)) / Z2
    return {"transmitted_energy": (Z1 / Z2) * (peak_tr / peak_inc) ** 2,
            "pulse_transmitted_energy": e_tr / e_inc,
            "incident_pulse_energy": area * e_inc,
            "incident_peak_stress": sign * peak_inc,
            "transmitted_peak_stress": sign * peak_tr}


def reflection_arrival(case, spec: dict) -> float:
    """Time (s) the wave reflected at the interface reaches the incident gauge."""
    c = max(mat.wave_speed(case.analysis) for mat in case.materials.values())
    return (2.0 * spec["x_interface"] - spec["x_incident"]) / c
