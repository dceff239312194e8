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
    S = Z1 + Z2                 # over (Z1 + Z2)^2: a very soft interface's y^2 may be inf, never NaN
    y = wk * Z1 * Z2 / S
    return 4.0 * (Z1 / S) * (Z2 / S) / (1.0 + y * y)


def wave_reflection(f: float, Dn: float, Z1: float, Z2: float | None = None) -> float:
    """Reflected energy fraction R = 1 - T (computed directly, not as 1 - T)."""
    Z1 = positive("Z1", Z1)
    Z2 = Z1 if Z2 is None else positive("Z2", Z2)
    wk = _omega_over_K(f, Dn)
    if math.isinf(wk):
        return 1.0
    S = Z1 + Z2
    y = wk * Z1 * Z2 / S        # a ratio of hypotenuses: no square overflows
    return (math.hypot((Z1 - Z2) / S, y) / math.hypot(1.0, y)) ** 2


def wave_transmission_identical(f: float, Dn: float, rho: float, E: float | None = None,
                                v: float | None = None) -> float:
    """002 Eq 48 (ERRATA 6): T = Dn^2 / (Dn^2 + (pi f rho v)^2) for identical materials.

    ``v`` is the wave speed (mm/s); when omitted, the bar speed sqrt(E/rho) of 002 is used.
    Pass e.g. :func:`dilatational_wave_speed` for a plane-strain or 3D block.
    """
    f = positive("f", f)
    Dn = interface_stiffness("Dn", Dn)
    Z = impedance(rho, v=v, E=E)
    if math.isinf(Dn) or Dn == 0.0:
        return 1.0 if Dn else 0.0
    y = math.pi * f * Z / Dn    # y * y may be inf (T = 0), never an OverflowError
    return 1.0 / (1.0 + y * y)


def _pulse_shape(tau, r: float):
    """g(tau) = r sin tau - cos tau + e^{-r tau}, 0 <= tau = w t <= pi: the transmitted
    stress during the pulse is k g / (r + 1/r) (see :func:`pulse_transmission`)."""
    return r * np.sin(tau) - np.cos(tau) + np.exp(-r * tau)


def _transmitted(tau, r: float, k: float):
    """s_t per unit incident amplitude at normalised times tau = w t >= 0: k h g(tau) during
    the pulse (h = r/(r^2 + 1), written 1/(r + 1/r) so that no r^2 overflows), then the free
    decay s_t(pi) e^{-r (tau - pi)}."""
    tau = np.asarray(tau, dtype=float)
    h = 1.0 / (r + 1.0 / r)
    during = k * h * _pulse_shape(np.minimum(tau, math.pi), r)
    out = np.where(tau <= math.pi, during, during * np.exp(-r * np.maximum(tau - math.pi, 0.0)))
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
        lam = Dn * (1.0 / Z1 + 1.0 / Z2)
        s_tr = s0 * np.where(t >= 0.0, _transmitted(w * np.clip(t, 0.0, None), lam / w,
                                                    2.0 * Z2 / (Z1 + Z2)), 0.0)
    return {"time": t, "incident": s_i, "transmitted": s_tr, "reflected": s_tr - s_i}


def pulse_transmission(f: float, Dn: float, Z1: float, Z2: float | None = None) -> dict[str, float]:
    """Transmission of the single half-sine stress pulse of 002 Eq 49 through a spring interface.

    The displacement x(t) = x0/2 (1 - cos 2 pi f t), 0 <= t <= 1/(2f), applied to the
    left edge launches sigma_i(t) = s0 sin(2 pi f t) for 0 <= t <= 1/(2f) (then 0).
    The transmitted stress is the exact solution of d s_t/dt + lambda s_t = (2K/Z1) s_i
    (module docstring): for w = 2 pi f, c = 2 K s0/Z1 and 0 <= t <= pi/w

        s_t(t) = c (lambda sin wt - w cos wt + w e^{-lambda t}) / (lambda^2 + w^2),

    followed by the free decay s_t(pi/w) e^{-lambda (t - pi/w)}. In normalised time
    tau = w t, with r = lambda/w and k = c/lambda = 2 Z2/(Z1 + Z2), s_t = k g(tau)/(r + 1/r),
    g = r sin tau - cos tau + e^{-r tau}, and the energies are closed forms:
    int_0^pi g^2 = (r^2 + 1) pi/2 + (1 - e^{-2 pi r})/(2r) (the cross terms cancel),
    int_0^pi g sin = r pi/2 + (1 + e^{-pi r})/(1 + r^2), the decay adds g(pi)^2/(2r),
    g(pi) = 1 + e^{-pi r}. They hold for any r > 0 without quadrature (r from 1e-300
    to 1e300 without overflow).

    Returns ``transmitted_energy`` (energy-flux ratio (Z1/Z2) int s_t^2 / int s_i^2),
    ``reflected_energy`` (int s_r^2 / int s_i^2 for the reflected stress s_r = s_t - s_i,
    expanded as int s_t^2 - 2 int s_t s_i + int s_i^2; the energy balance e_t + e_r = 1
    then holds only if the two integrals are right), ``peak_ratio_squared``
    ((Z1/Z2)(max s_t / s0)^2, the amplitude measure used with MPM in 002 Sec 3.3) and ``harmonic_transmission``
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
    if math.isinf(Dn):
        T = 4.0 * Z1 * Z2 / (Z1 + Z2) ** 2
        return {"transmitted_energy": T, "reflected_energy": 1.0 - T, "peak_ratio_squared": T,
                "harmonic_transmission": harmonic}
    r = Dn * (1.0 / Z1 + 1.0 / Z2) / w          # lambda / w
    k = 2.0 * Z2 / (Z1 + Z2)                    # c / lambda, the perfect interface's ratio
    h = 1.0 / (r + 1.0 / r)                     # r / (r^2 + 1)
    e_pulse, e_half = -math.expm1(-2.0 * math.pi * r), math.exp(-math.pi * r)
    # w int s_t^2 dt: during the pulse k^2 h^2 int_0^pi g^2 = k^2 (pi/2 r h + h^2 e_pulse/(2r)),
    # then the free decay k^2 h^2 g(pi)^2 / (2r), g(pi) = 1 + e^{-pi r}
    w_st2 = k * k * (0.5 * math.pi * r * h + h * h * (e_pulse + (1.0 + e_half) ** 2) / (2.0 * r))
    # w int s_t sin(wt) dt = k h int_0^pi g sin = k (pi/2 r h + h^2 (1 + e^{-pi r}) / r)
    w_st_si = k * (0.5 * math.pi * r * h + h * h * (1.0 + e_half) / r)
    inc = 0.5 * math.pi                         # w int_0^{pi/w} sin^2 dt
    e_t = w_st2 / inc * Z1 / Z2
    e_r = (w_st2 - 2.0 * w_st_si + inc) / inc   # int (s_t - s_i)^2, s_i = 0 after the pulse
    # s_t rises while c sin wt > lam s_t and decays once, so it has one maximum in (0, pi]
    tau_peak = minimize_scalar(lambda tau: -_transmitted(tau, r, k), bounds=(0.0, math.pi),
                               method="bounded", options={"xatol": 1e-12}).x
    peak = _transmitted(tau_peak, r, k)
    return {"transmitted_energy": e_t, "reflected_energy": e_r,
            "peak_ratio_squared": peak * peak * Z1 / Z2, "harmonic_transmission": harmonic}
