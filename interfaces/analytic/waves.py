"""Normal-incidence plane waves through a linear spring interface (1D, longitudinal).

Source: 002 Sec 3.3, Eq 48 (written there for two identical materials, refs [20, 21])
with ERRATA item 6: T = K^2 / (K^2 + (pi f Z)^2), Z = rho v, omega = 2 pi f.

General form for two materials, derived here. Material 1 (impedance Z1 = rho1 v1)
holds the incident and reflected waves, material 2 (Z2) the transmitted wave; at
the interface x = 0 the traction is continuous and equals K [u] (K = Dn, MPa/mm),
[u] = u2 - u1. With u = A e^{i(wt - x/v1)} + B e^{i(wt + x/v1)} in 1 and
u = C e^{i(wt - x/v2)} in 2 and sigma = rho v^2 du/dx:

    traction continuity   Z1 (A - B) = Z2 C
    spring law            -i w Z2 C = K (C - A - B)

so C/A = 2 Z1 / (Z1 + Z2 + i w Z1 Z2 / K) and the energy-flux ratios are

    T = 4 Z1 Z2 / ((Z1 + Z2)^2 + (w Z1 Z2 / K)^2),
    R = ((Z1 - Z2)^2 + (w Z1 Z2 / K)^2) / ((Z1 + Z2)^2 + (w Z1 Z2 / K)^2),   R + T = 1.

Z1 = Z2 = Z gives Eq 48 (T = K^2/(K^2 + (pi f Z)^2)); K -> inf gives the perfect
interface 4 Z1 Z2/(Z1 + Z2)^2; K -> 0 gives T -> 0.

Time domain (the 002 MPM test, Eq 49): a stress pulse sigma_i(t) arriving at the
interface transmits sigma_t(t) obeying (from the same two interface conditions
with sigma = -Z v for a right-going and +Z v for a left-going wave)

    d sigma_t/dt + lambda sigma_t = (2 K / Z1) sigma_i,     lambda = K (1/Z1 + 1/Z2),

a first-order low-pass filter; :func:`pulse_transmission` solves it in closed form
for the half-sine pulse produced by the Eq 49 displacement ramp.

Units: f in Hz (1/s), rho in tonne/mm^3, v in mm/s, Z in MPa s/mm, K = Dn in MPa/mm.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate import quad
from scipy.optimize import minimize_scalar

from interfaces.analytic._checks import CaseError, interface_stiffness, positive
from interfaces.errors import check_number

__all__ = ["bar_wave_speed", "dilatational_wave_speed", "impedance", "wave_transmission",
           "wave_reflection", "wave_amplitude_ratios", "wave_transmission_identical",
           "pulse_transmission", "pulse_histories"]


def bar_wave_speed(E: float, rho: float) -> float:
    """Tensile (bar) wave speed v = sqrt(E/rho) (mm/s), as used in 002 Eq 48."""
    return math.sqrt(positive("E", E) / positive("rho", rho))


def dilatational_wave_speed(E: float, nu: float, rho: float, analysis: str = "3d") -> float:
    """Dilatational wave speed (mm/s): sqrt(E (1-nu)/((1+nu)(1-2nu) rho)) in 3D and plane strain,
    sqrt(E/((1-nu^2) rho)) in plane stress."""
    E, rho = positive("E", E), positive("rho", rho)
    nu = check_number("nu", nu, low=-1.0, high=0.5, low_open=True, high_open=True)
    if analysis in ("3d", "plane_strain", "axisymmetric"):
        return math.sqrt(E * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu) * rho))
    if analysis == "plane_stress":
        return math.sqrt(E / ((1.0 - nu * nu) * rho))
    raise CaseError(f"analysis must be one of 3d, plane_strain, axisymmetric, plane_stress, "
                    f"got {analysis!r}")


def impedance(rho: float, v: float | None = None, E: float | None = None) -> float:
    """Acoustic impedance Z = rho v (MPa s/mm); v defaults to the bar speed sqrt(E/rho)."""
    rho = positive("rho", rho)
    if v is None:
        if E is None:
            raise CaseError("impedance needs the wave speed v or the modulus E")
        v = bar_wave_speed(E, rho)
    return rho * positive("v", v)


def _omega_over_K(f: float, Dn: float) -> float:
    f = positive("f", f)
    Dn = interface_stiffness("Dn", Dn)
    if Dn == 0.0:
        return math.inf
    return 0.0 if math.isinf(Dn) else 2.0 * math.pi * f / Dn


def wave_amplitude_ratios(f: float, Dn: float, Z1: float, Z2: float | None = None) -> tuple[complex, complex]:
    """Complex displacement amplitude ratios (B/A reflected, C/A transmitted) at x = 0."""
    Z1 = positive("Z1", Z1)
    Z2 = Z1 if Z2 is None else positive("Z2", Z2)
    wk = _omega_over_K(f, Dn)
    if math.isinf(wk):
        return complex(1.0), complex(0.0)
    C = 2.0 * Z1 / (Z1 + Z2 + 1j * wk * Z1 * Z2)
    B = C * (1.0 + 1j * wk * Z2) - 1.0
    return complex(B), complex(C)


def wave_transmission(f: float, Dn: float, Z1: float, Z2: float | None = None) -> float:
    """Transmitted energy fraction T through a spring interface, general two-material form
    (derived in the module docstring; reduces to 002 Eq 48 / ERRATA 6 for Z1 = Z2)."""
    Z1 = positive("Z1", Z1)
    Z2 = Z1 if Z2 is None else positive("Z2", Z2)
    wk = _omega_over_K(f, Dn)
    if math.isinf(wk):
        return 0.0
    return 4.0 * Z1 * Z2 / ((Z1 + Z2) ** 2 + (wk * Z1 * Z2) ** 2)


def wave_reflection(f: float, Dn: float, Z1: float, Z2: float | None = None) -> float:
    """Reflected energy fraction R = 1 - T (computed directly, not as 1 - T)."""
    Z1 = positive("Z1", Z1)
    Z2 = Z1 if Z2 is None else positive("Z2", Z2)
    wk = _omega_over_K(f, Dn)
    if math.isinf(wk):
        return 1.0
    q = (wk * Z1 * Z2) ** 2
    return ((Z1 - Z2) ** 2 + q) / ((Z1 + Z2) ** 2 + q)


def wave_transmission_identical(f: float, Dn: float, rho: float, E: float | None = None,
                                v: float | None = None) -> float:
    """002 Eq 48 (ERRATA 6): T = Dn^2 / (Dn^2 + (pi f rho v)^2) for identical materials.

    ``v`` is the wave speed (mm/s); when omitted, the bar speed sqrt(E/rho) of 002 is used.
    Pass e.g. :func:`dilatational_wave_speed` for a plane-strain or 3D block.
    """
    f = positive("f", f)
    Dn = interface_stiffness("Dn", Dn)
    Z = impedance(rho, v=v, E=E)
    if math.isinf(Dn):
        return 1.0
    return Dn * Dn / (Dn * Dn + (math.pi * f * Z) ** 2)


def _transmitted(t, w: float, lam: float, c: float):
    """s_t(t) per unit incident amplitude (see :func:`pulse_transmission`), any t >= 0."""
    t = np.asarray(t, dtype=float)
    t_end = math.pi / w
    tc = np.minimum(t, t_end)
    during = c * (lam * np.sin(w * tc) - w * np.cos(w * tc) + w * np.exp(-lam * tc)) / (lam * lam + w * w)
    out = np.where(t <= t_end, during, during * np.exp(-lam * np.maximum(t - t_end, 0.0)))
    return float(out) if out.ndim == 0 else out


def pulse_histories(f: float, Dn: float, Z1: float, Z2: float | None = None, t=None,
                    s0: float = 1.0) -> dict:
    """Stress histories at the interface of the Eq 49 pulse (002 Fig 11), t (s) from the
    incident pulse's arrival: incident s0 sin(2 pi f t) for t <= 1/(2f), transmitted
    s_t (exact solution of the module docstring's filter, free decay after the pulse)
    and reflected s_r = s_t - s_i (traction continuity). Dn = inf: s_t = 2 Z2/(Z1 + Z2) s_i."""
    f = positive("f", f)
    Dn = interface_stiffness("Dn", Dn)
    Z1 = positive("Z1", Z1)
    Z2 = Z1 if Z2 is None else positive("Z2", Z2)
    t = np.asarray(t, dtype=float)
    w = 2.0 * math.pi * f
    s_i = s0 * np.where((t >= 0.0) & (t <= math.pi / w), np.sin(w * np.clip(t, 0.0, None)), 0.0)
    if math.isinf(Dn):
        s_tr = 2.0 * Z2 / (Z1 + Z2) * s_i
    elif Dn == 0.0:
        s_tr = np.zeros_like(t)
    else:
        s_tr = s0 * np.where(t >= 0.0, _transmitted(np.clip(t, 0.0, None), w, Dn * (1.0 / Z1 + 1.0 / Z2),
                                                    2.0 * Dn / Z1), 0.0)
    return {"time": t, "incident": s_i, "transmitted": s_tr, "reflected": s_tr - s_i}


def pulse_transmission(f: float, Dn: float, Z1: float, Z2: float | None = None) -> dict[str, float]:
    """Transmission of the single half-sine stress pulse of 002 Eq 49 through a spring interface.

    The displacement x(t) = x0/2 (1 - cos 2 pi f t), 0 <= t <= 1/(2f), applied to the
    left edge launches sigma_i(t) = s0 sin(2 pi f t) for 0 <= t <= 1/(2f) (then 0).
    The transmitted stress is the exact solution of d s_t/dt + lambda s_t = (2K/Z1) s_i
    (module docstring): for w = 2 pi f, c = 2 K s0/Z1 and 0 <= t <= pi/w

        s_t(t) = c (lambda sin wt - w cos wt + w e^{-lambda t}) / (lambda^2 + w^2),

    followed by the free decay s_t(pi/w) e^{-lambda (t - pi/w)}.

    Returns ``transmitted_energy`` (energy-flux ratio (Z1/Z2) int s_t^2 / int s_i^2),
    ``reflected_energy`` (from the reflected stress s_r = s_t - s_i, computed independently
    of the transmitted one), ``peak_ratio_squared`` ((Z1/Z2)(max s_t / s0)^2, the
    amplitude measure used with MPM in 002 Sec 3.3) and ``harmonic_transmission``
    (Eq 48 general form at the same f) for comparison.
    """
    f = positive("f", f)
    Dn = interface_stiffness("Dn", Dn)
    Z1 = positive("Z1", Z1)
    Z2 = Z1 if Z2 is None else positive("Z2", Z2)
    harmonic = wave_transmission(f, Dn, Z1, Z2)
    if Dn == 0.0:
        return {"transmitted_energy": 0.0, "reflected_energy": 1.0, "peak_ratio_squared": 0.0,
                "harmonic_transmission": 0.0}
    w = 2.0 * math.pi * f
    t_end = math.pi / w
    if math.isinf(Dn):
        T = 4.0 * Z1 * Z2 / (Z1 + Z2) ** 2
        return {"transmitted_energy": T, "reflected_energy": 1.0 - T, "peak_ratio_squared": T,
                "harmonic_transmission": harmonic}
    lam = Dn * (1.0 / Z1 + 1.0 / Z2)

    def s_t(t: float) -> float:
        return _transmitted(t, w, lam, 2.0 * Dn / Z1)

    def s_r(t: float) -> float:
        return s_t(t) - math.sin(w * t)

    s_end = s_t(t_end)
    brk = [min(t_end, 1.0 / lam)] if 1.0 / lam < t_end else None
    opts = dict(limit=200, epsabs=0.0, epsrel=1e-12, points=brk)
    inc = t_end / 2.0  # int_0^{pi/w} sin^2 = pi/(2w)
    tail = s_end * s_end / (2.0 * lam)  # int of the free exponential decay
    e_t = (quad(lambda t: s_t(t) ** 2, 0.0, t_end, **opts)[0] + tail) / inc * Z1 / Z2
    e_r = (quad(lambda t: s_r(t) ** 2, 0.0, t_end, **opts)[0] + tail) / inc
    # s_t rises while c sin wt > lam s_t and decays once, so it has one maximum in (0, pi/w]
    t_peak = minimize_scalar(lambda t: -s_t(t), bounds=(0.0, t_end), method="bounded",
                             options={"xatol": 1e-12 * t_end}).x
    peak = s_t(t_peak)
    return {"transmitted_energy": e_t, "reflected_energy": e_r,
            "peak_ratio_squared": peak * peak * Z1 / Z2, "harmonic_transmission": harmonic}
