"""Named closed-form models for the case-level dispatcher.

``MODELS[name](**params) -> dict[str, float]`` returns scalar quantities named as in
docs/case_api.md (``stiffness`` N/mm, ``compliance`` mm/N, ``beta_l``,
``transmitted_energy``, ``bulk_modulus`` MPa, ...). ``PROFILES[name](**params)``
returns ``{profile_name: {column: ndarray}}`` curves for plots. Both take the same
keyword parameters, the ``case.analytic`` table without its ``model`` key; an
unknown or missing parameter raises :class:`CaseError` naming it and listing the
accepted ones. Interface parameters accept ``math.inf`` or the string ``"inf"``.

Parameters per model (units mm, N, MPa, s, tonne/mm^3, MPa/mm):

* ``dls_shear_lag`` (002 Eq 40-42, App. A): t1, E1, G1 (outer strip; aliases t, E_yy,
  G_xy), t2, E2, G2 (central strip, default = outer), l, W, L = 0, Dt = inf,
  layer_shear = False; profile options P = 1, n_points = 201, origin = (0, 0) and
  axis = (0, 1) (the bond line start, at the loaded end of the central strip, and direction).
* ``dcb_beam_foundation`` (002 Eq 46-47, App. B): a, h, W, E_xx, Dn = inf, kb = inf;
  profile options P = 1, n_points = 201, x_max = 10 Delta (bonded length shown),
  origin = (0, 0) and axis = (1, 0) (crack tip and direction into the bonded region).
* ``wave_transmission`` (002 Eq 48, ERRATA 6): f, Dn, and either Z1 [, Z2] or
  rho, E or v [, rho2, E2 or v2] (material 2 defaults to material 1);
  nonlinear = False and pulse = "tensile" | "compressive" (bilinear law perfect in
  compression); measure = "harmonic" | "pulse_energy" | "pulse_peak" (what
  ``transmitted_energy`` holds); profile options n_points = 61.
* ``composite_spheres`` (000 Sec 3): K_p or (E_p, nu_p); K_m, G_m or (E_m, nu_m);
  a (particle radius); phi, or b (outer radius), or cube_side [+ octant = False];
  Dn = inf; Dt, G_p accepted and unused (spherical symmetry); profile options
  eps0 = 1, n_points = 201.
* ``shock_hugoniot`` (004 Sec 4.3, Eq 51, Rankine-Hugoniot): K, rho, S1, gamma0, Y = 0
  (yield stress of the deviatoric part) or G = 0 (its elastic neo-Hookean shear, Eq 18), impact_speed (mm/s), impact = "wall" (u_p = v)
  | "symmetric" (u_p = v / 2); profile options n_points = 41, up_max = 1.5 u_p.
* ``gap_closure`` (004 Fig 2): gap (mm), speed (mm/s) of the pushed face, height of the
  pushed body and its wave_speed (mm/s; default inf): contact_time = gap / speed +
  height / wave_speed (the push reaches the body's leading face after one transit).
* ``composite_cylinders`` (plane strain, transverse bulk modulus): K_p, G_p or (E_p,
  nu_p) of the fibre; K_m, G_m or (E_m, nu_m); a (fibre radius); phi or b; Dn = inf;
  Dt accepted and unused (axial symmetry).
* ``shock_hugoniot`` (004 Sec 4.3 reference): rho0, C0, S1, impact_speed (mm/s),
  symmetric = False (True: up = v / 2); profile options n_points = 101.
"""
from __future__ import annotations

import functools
import math
from typing import Any, Callable

import numpy as np

from interfaces.analytic._checks import CaseError, interface_stiffness, nonnegative, positive
from interfaces.analytic.composite_spheres import (CompositeSpheres, bulk_shear_from_young_poisson,
                                                    sphere_in_cube_volume_fraction)
from interfaces.analytic.composite_cylinders import CompositeCylinders, plane_strain_bulk_modulus
from interfaces.analytic.dcb import DoubleCantileverBeam
from interfaces.analytic.dls import DoubleLapShear
from interfaces.analytic.hugoniot import ShockHugoniot
from interfaces.analytic.waves import impedance, pulse_transmission, wave_reflection, wave_transmission
from interfaces.errors import check_number

__all__ = ["MODELS", "PROFILES", "model_names"]

_INF = math.inf


def _named(fn: Callable) -> Callable:
    """Prefix argument errors with ``analytic.`` so they name the case field.

    The closed form runs with numpy's floating-point errors raised: an overflow, a division
    by zero or an undefined operation (inf - inf, 0 * inf) anywhere in its arrays becomes
    the one-line error below, never an inf or NaN profile handed on in silence.
    """
    @functools.wraps(fn)
    def wrapper(**params):
        try:
            with np.errstate(over="raise", divide="raise", invalid="raise"):
                out = fn(**params)
        except TypeError as e:   # a table or list where a number or a name belongs
            raise CaseError(f"analytic: a parameter has the wrong type ({e}); parameters: "
                            f"{', '.join(f'{k} = {v!r}' for k, v in params.items() if not isinstance(v, (int, float, str)))}") from None
        except (OverflowError, ZeroDivisionError, FloatingPointError) as e:
            raise CaseError(f"analytic: the closed form overflows or is undefined for these parameters "
                            f"({e}); "
                            "check the magnitudes of the analytic.* lengths and moduli (mm, MPa)") from None
        except CaseError as e:
            msg = str(e)
            first = msg.split(" ", 1)[0]
            if first in params or first in _PARAMETER_NAMES:
                msg = f"analytic.{msg}"
            raise CaseError(msg) from None
        bad = [k for k, v in out.items() if isinstance(v, float) and math.isnan(v)]
        if bad:
            raise CaseError(f"analytic: {bad[0]} is NaN for these parameters; check the magnitudes of "
                            "the analytic.* lengths and moduli (mm, MPa)")
        return out
    return wrapper


def _take(params: dict[str, Any], model: str, allowed: dict[str, Any],
          aliases: dict[str, str] | None = None) -> dict[str, Any]:
    """Resolve aliases, reject unknown keys, fill defaults; ``...`` marks required keys."""
    p = dict(params)
    for alias, name in (aliases or {}).items():
        if alias in p:
            if name in p:
                raise CaseError(f"analytic.{alias} and analytic.{name} are the same parameter "
                                f"of {model}; give only one")
            p[name] = p.pop(alias)
    unknown = sorted(set(p) - set(allowed))
    if unknown:
        raise CaseError(f"analytic.{unknown[0]} is not a parameter of model {model!r}; "
                        f"accepted: {', '.join(sorted(set(allowed) | set(aliases or {})))}")
    out = {}
    for k, default in allowed.items():
        if k in p:
            out[k] = p[k]
        elif default is ...:
            raise CaseError(f"analytic.{k} is required by model {model!r}")
        else:
            out[k] = default
    return out


def _n_points(value) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 2 <= value <= 100000:
        raise CaseError(f"analytic.n_points must be an integer in [2, 100000], got {value!r}")
    return int(value)


# ---- double lap shear ------------------------------------------------------------
_DLS = {"t1": ..., "E1": ..., "G1": ..., "t2": None, "E2": None, "G2": None, "l": ..., "W": ...,
        "L": 0.0, "Dt": _INF, "layer_shear": False, "P": 1.0, "n_points": 201,
        "origin": (0.0, 0.0), "axis": (0.0, 1.0)}
_DLS_ALIASES = {"t": "t1", "E_yy": "E1", "G_xy": "G1"}


def _dls(params: dict[str, Any]) -> tuple[DoubleLapShear, dict[str, Any]]:
    p = _take(params, "dls_shear_lag", _DLS, _DLS_ALIASES)
    for k in ("t", "E", "G"):
        if p[k + "2"] is None:
            p[k + "2"] = p[k + "1"]
    model = DoubleLapShear(p["t1"], p["E1"], p["G1"], p["t2"], p["E2"], p["G2"], p["l"], p["W"],
                           p["L"], p["Dt"], p["layer_shear"])
    return model, p


@_named
def dls_shear_lag(**params) -> dict[str, float]:
    """DLS specimen (002 Eq 40-42, Appendix A): stiffness with arms, bonded compliance, beta l."""
    m, p = _dls(params)
    k = m.stiffness
    printed = DoubleLapShear(p["t1"], p["E1"], p["G1"], p["t2"], p["E2"], p["G2"], p["l"], p["W"],
                             p["L"], p["Dt"], False).stiffness
    return {"stiffness": k, "stiffness_eq40_42": printed, "compliance": m.compliance,
            "specimen_compliance": math.inf if k == 0.0 else 1.0 / k,
            "arm_compliance": m.arm_compliance, "beta": m.beta, "beta_l": m.beta_l,
            "long_bond_stiffness": 1.0 / m.compliance_long_bond}


@_named
def dls_profiles(**params) -> dict[str, dict[str, np.ndarray]]:
    """Stresses and interface slip along the bond for the load P (002 Eq A.2, A.7, A.8).

    ``bond``: y from the loaded end of the central strip, <s1>, <s2>, tau, jump_t.
    ``interface_jump`` (the shared profile convention of docs/case_api.md): s = y,
    x, y = origin + s axis, jump_t = tau/Dt = u_central - u_outer along the bond
    direction, traction_t = tau (on the outer strip); jump_n, traction_n are NaN
    (the shear-lag model does not describe the normal direction).
    """
    m, p = _dls(params)
    y = np.linspace(0.0, m.l, _n_points(p["n_points"]))
    s1, s2 = m.axial_stress(y, p["P"])
    tau = m.shear_stress(y, p["P"])
    jump = m.interface_slip(y, p["P"])
    nan = np.full_like(y, np.nan)
    return {"bond": {"y": y, "shear_stress": tau, "axial_stress_outer": s1,
                     "axial_stress_central": s2, "jump_t": jump},
            "interface_jump": {"s": y, **_placed(y, p), "jump_n": nan, "jump_t": jump,
                               "traction_n": nan, "traction_t": tau}}


def _placed(s: np.ndarray, p: dict[str, Any]) -> dict[str, np.ndarray]:
    """x, y of points at arc length s on the straight interface origin + s axis."""
    try:
        o = np.asarray(p["origin"], dtype=float).reshape(2)
        d = np.asarray(p["axis"], dtype=float).reshape(2)
    except (TypeError, ValueError):
        raise CaseError(f"analytic.origin and analytic.axis must be 2-vectors, got "
                        f"{p['origin']!r} and {p['axis']!r}") from None
    norm = float(np.hypot(*d))
    if not (np.all(np.isfinite(o)) and np.isfinite(norm) and norm > 0.0):
        raise CaseError(f"analytic.axis must be a finite non-zero 2-vector and origin finite, "
                        f"got axis {p['axis']!r}, origin {p['origin']!r}")
    d = d / norm
    return {"x": o[0] + s * d[0], "y": o[1] + s * d[1]}


# ---- double cantilever beam ------------------------------------------------------
_DCB = {"a": ..., "h": ..., "W": ..., "E_xx": ..., "Dn": _INF, "kb": _INF,
        "P": 1.0, "n_points": 201, "x_max": None, "origin": (0.0, 0.0), "axis": (1.0, 0.0)}


def _dcb(params: dict[str, Any]) -> tuple[DoubleCantileverBeam, dict[str, Any]]:
    p = _take(params, "dcb_beam_foundation", _DCB)
    return DoubleCantileverBeam(p["a"], p["h"], p["W"], p["E_xx"], p["Dn"], p["kb"]), p


@_named
def dcb_beam_foundation(**params) -> dict[str, float]:
    """DCB specimen (002 Eq 46-47): load-point stiffness and compliance, C0 and Delta."""
    m, _ = _dcb(params)
    return {"stiffness": m.stiffness, "compliance": m.compliance, "beam_compliance": m.C0,
            "Delta": m.Delta}


@_named
def dcb_profiles(**params) -> dict[str, dict[str, np.ndarray]]:
    """Arm deflection v(x) (002 Eq B.3, B.6) and opening 2v for -a <= x <= x_max; and
    ``interface_jump`` along the bond (s = x >= 0 from the crack tip, placed at
    origin + s axis): traction_n = k1 v/W (the foundation load over the width),
    [u_n] = traction_n/Dn (= 2v when kb = inf), no shear (symmetry)."""
    m, p = _dcb(params)
    x_max = p["x_max"]
    x_max = (10.0 * m.Delta if m.Delta > 0.0 else m.a) if x_max is None else positive("x_max", x_max)
    x = np.linspace(-m.a, x_max, _n_points(p["n_points"]))
    v = m.deflection(x, p["P"])
    # the interface spring carries the foundation load k1 v per unit length over the width W
    xb = np.linspace(0.0, x_max, _n_points(p["n_points"]))
    if m.foundation_compliance == 0.0:  # clamped arms: concentrated reaction, no distributed traction
        traction = np.full_like(xb, np.nan)
        jump = np.zeros_like(xb)
    else:
        traction = m.deflection(xb, p["P"]) / (m.W * m.foundation_compliance)
        jump = np.zeros_like(xb) if math.isinf(m.Dn) else traction / m.Dn
    return {"deflection": {"x": x, "v": v, "opening": 2.0 * v},
            "interface_jump": {"s": xb, **_placed(xb, p), "jump_n": jump, "jump_t": np.zeros_like(xb),
                               "traction_n": traction, "traction_t": np.zeros_like(xb)}}


# ---- wave transmission -----------------------------------------------------------
_WAVE = {"f": ..., "Dn": ..., "Z1": None, "Z2": None, "rho": None, "E": None, "v": None,
         "rho2": None, "E2": None, "v2": None, "nonlinear": False, "pulse": "tensile",
         "measure": "harmonic", "n_points": 61}
_WAVE_MEASURES = {"harmonic": "harmonic", "pulse_energy": "pulse_transmitted_energy",
                  "pulse_peak": "pulse_peak_ratio_squared"}


def _wave(params: dict[str, Any]) -> tuple[float, float, float, float, dict[str, Any]]:
    p = _take(params, "wave_transmission", _WAVE)
    if p["Z1"] is not None:
        if any(p[k] is not None for k in ("rho", "E", "v")):
            raise CaseError("give analytic.Z1 or analytic.rho (with E or v), not both")
        Z1 = positive("Z1", p["Z1"])
    elif p["rho"] is not None:
        if p["E"] is None and p["v"] is None:
            raise CaseError("wave_transmission needs analytic.E or analytic.v with analytic.rho")
        Z1 = impedance(p["rho"], v=p["v"], E=p["E"])
    else:
        raise CaseError("wave_transmission needs analytic.Z1 or analytic.rho with E or v")
    if p["Z2"] is not None:
        Z2 = positive("Z2", p["Z2"])
    elif any(p[k] is not None for k in ("rho2", "E2", "v2")):
        if p["E2"] is None and p["v2"] is None:
            raise CaseError("material 2 of wave_transmission needs analytic.E2 or analytic.v2")
        rho2 = p["rho2"] if p["rho2"] is not None else p["rho"]
        if rho2 is None:
            raise CaseError("material 2 of wave_transmission needs analytic.rho2")
        Z2 = impedance(positive("rho2", rho2), v=None if p["v2"] is None else positive("v2", p["v2"]),
                       E=None if p["E2"] is None else positive("E2", p["E2"]))
    else:
        Z2 = Z1
    if not isinstance(p["nonlinear"], (bool, np.bool_)):
        raise CaseError(f"analytic.nonlinear must be true or false, got {p['nonlinear']!r}")
    if not isinstance(p["pulse"], str) or p["pulse"] not in ("tensile", "compressive"):
        raise CaseError(f"analytic.pulse must be 'tensile' or 'compressive', got {p['pulse']!r}")
    if not isinstance(p["measure"], str) or p["measure"] not in _WAVE_MEASURES:
        raise CaseError(f"analytic.measure must be one of {', '.join(_WAVE_MEASURES)}, got {p['measure']!r}")
    Dn = interface_stiffness("Dn", p["Dn"])
    if p["nonlinear"] and p["pulse"] == "compressive":
        # bilinear law, perfect in compression (002 Sec 3.3): a compressive pulse keeps the
        # interface closed, so it crosses a perfect interface; a tensile one keeps it open (Dn)
        Dn = math.inf
    return p["f"], Dn, Z1, Z2, p


@_named
def wave_transmission_model(**params) -> dict[str, float]:
    """Normal-incidence energy transmission through a spring interface (002 Eq 48, general Z1, Z2),
    harmonic and for the single half-sine pulse of Eq 49.

    ``transmitted_energy`` is the harmonic value of Eq 48 unless ``measure`` selects the
    pulse energy ratio (``"pulse_energy"``) or the squared peak-stress ratio
    (``"pulse_peak"``, the amplitude measure of 002 Sec 3.3); all three are always
    returned under their own names. ``nonlinear`` with ``pulse = "compressive"``: the
    bilinear law is perfect in compression, so Dn = inf is used."""
    f, Dn, Z1, Z2, p = _wave(params)
    pulse = pulse_transmission(f, Dn, Z1, Z2)
    out = {"transmitted_energy": wave_transmission(f, Dn, Z1, Z2),
           "reflected_energy": wave_reflection(f, Dn, Z1, Z2),
           "pulse_transmitted_energy": pulse["transmitted_energy"],
           "pulse_peak_ratio_squared": pulse["peak_ratio_squared"],
           "harmonic_transmitted_energy": pulse["harmonic_transmission"],
           "Z1": Z1, "Z2": Z2}
    key = _WAVE_MEASURES[p["measure"]]
    if key != "harmonic":
        out["transmitted_energy"] = out[key]
        out["reflected_energy"] = 1.0 - out[key] if key == "pulse_peak_ratio_squared" \
            else pulse["reflected_energy"]
    return out


@_named
def wave_profiles(**params) -> dict[str, dict[str, np.ndarray]]:
    """T against Dn around the half-transmission value pi f Z (harmonic and pulse)."""
    f, _, Z1, Z2, p = _wave(params)
    Zh = 2.0 * Z1 * Z2 / (Z1 + Z2)
    Dn = np.pi * positive("f", f) * Zh * np.logspace(-2.0, 2.0, _n_points(p["n_points"]))
    T = np.array([wave_transmission(f, d, Z1, Z2) for d in Dn])
    Tp = np.array([pulse_transmission(f, d, Z1, Z2)["transmitted_energy"] for d in Dn])
    return {"transmission": {"Dn": Dn, "transmitted_energy": T, "pulse_transmitted_energy": Tp}}


# ---- composite spheres -----------------------------------------------------------
_CSA = {"K_p": None, "G_p": None, "E_p": None, "nu_p": None, "K_m": None, "G_m": None,
        "E_m": None, "nu_m": None, "a": ..., "phi": None, "b": None, "cube_side": None,
        "octant": False, "Dn": _INF, "Dt": None, "eps0": 1.0, "n_points": 201}


def _moduli(p: dict[str, Any], phase: str, model: str = "composite_spheres") -> tuple[float, float | None]:
    K, G, E, nu = (p[f"{k}_{phase}"] for k in ("K", "G", "E", "nu"))
    if E is not None or nu is not None:
        if K is not None or G is not None:
            raise CaseError(f"give analytic.K_{phase}, G_{phase} or analytic.E_{phase}, "
                            f"nu_{phase}, not both")
        if E is None or nu is None:
            raise CaseError(f"analytic.E_{phase} and analytic.nu_{phase} must be given together")
        E = positive(f"E_{phase}", E)
        nu = check_number(f"nu_{phase}", nu, low=-1.0, high=0.5, low_open=True, high_open=True)
        return bulk_shear_from_young_poisson(E, nu)
    if K is None:
        raise CaseError(f"{model} needs analytic.K_{phase} (or E_{phase} and nu_{phase})")
    return K, G


def _csa(params: dict[str, Any]) -> tuple[CompositeSpheres, dict[str, Any]]:
    p = _take(params, "composite_spheres", _CSA)
    if p["Dt"] is not None:  # accepted for cases with Dn = Dt; it does not enter the bulk response
        interface_stiffness("Dt", p["Dt"], allow_negative=True)
    if p["G_p"] is not None:
        positive("G_p", p["G_p"])
    K_p, _ = _moduli(p, "p")
    K_m, G_m = _moduli(p, "m")
    if G_m is None:
        raise CaseError("composite_spheres needs analytic.G_m (or E_m and nu_m)")
    given = [k for k in ("phi", "b", "cube_side") if p[k] is not None]
    if len(given) != 1:
        raise CaseError("composite_spheres needs exactly one of analytic.phi, analytic.b, "
                        f"analytic.cube_side, got {given or 'none'}")
    a = positive("a", p["a"])
    if p["phi"] is not None:
        phi = p["phi"]
    elif p["b"] is not None:
        b = positive("b", p["b"])
        if b <= a:
            raise CaseError(f"analytic.b must be > a = {a:g} mm, got {b:g}")
        phi = (a / b) ** 3
    else:
        if not isinstance(p["octant"], (bool, np.bool_)):
            raise CaseError(f"analytic.octant must be true or false, got {p['octant']!r}")
        phi = sphere_in_cube_volume_fraction(a, positive("cube_side", p["cube_side"]), octant=bool(p["octant"]))
    return CompositeSpheres(K_p, K_m, G_m, phi, a, p["Dn"]), p


@_named
def composite_spheres(**params) -> dict[str, float]:
    """Bulk modulus of the composite spheres assemblage with a spring interface (000 Sec 3);
    ``bulk_modulus_pressure`` is the same K, the reference of the pressure measure (000
    Eq 36) that the numerical methods report beside the energy one (Eq 35)."""
    m, _ = _csa(params)
    perfect = CompositeSpheres(m.K_p, m.K_m, m.G_m, m.phi, m.a, _INF).bulk_modulus
    debonded = CompositeSpheres(m.K_p, m.K_m, m.G_m, m.phi, m.a, 0.0).bulk_modulus
    return {"bulk_modulus": m.bulk_modulus, "bulk_modulus_pressure": m.bulk_modulus,
            "bulk_modulus_perfect": perfect,
            "bulk_modulus_debonded": debonded, "effective_particle_modulus": m.effective_particle_modulus,
            "phi": m.phi}


@_named
def composite_spheres_profiles(**params) -> dict[str, dict[str, np.ndarray]]:
    """Radial displacement and stress through particle and shell for u(b) = eps0 b."""
    m, p = _csa(params)
    if m.phi == 0.0:
        raise CaseError("analytic.phi = 0 has no finite shell to plot; use phi > 0")
    return _radial_profile(m, p)


def _radial_profile(m, p: dict[str, Any]) -> dict[str, dict[str, np.ndarray]]:
    """u_r and sigma_rr of a composite sphere or cylinder on r in [0, b], both sides of r = a."""
    n = _n_points(p["n_points"])
    r = np.minimum(np.concatenate([np.linspace(0.0, m.a, n // 2),
                                   np.nextafter(m.a, np.inf) + np.linspace(0.0, m.b - m.a, n - n // 2)]), m.b)
    return {"radial": {"r": r, "u_r": m.radial_displacement(r, p["eps0"]),
                       "sigma_rr": m.radial_stress(r, p["eps0"])}}


# ---- composite cylinders (plane strain) ------------------------------------------
_CCA = {"K_p": None, "G_p": None, "E_p": None, "nu_p": None, "K_m": None, "G_m": None,
        "E_m": None, "nu_m": None, "a": ..., "phi": None, "b": None, "Dn": _INF, "Dt": None,
        "eps0": 1.0, "n_points": 201}


def _cca(params: dict[str, Any]) -> tuple[CompositeCylinders, dict[str, Any]]:
    p = _take(params, "composite_cylinders", _CCA)
    if p["Dt"] is not None:  # accepted for cases with Dn = Dt; it does not enter the transverse dilatation
        interface_stiffness("Dt", p["Dt"], allow_negative=True)
    (K_p, G_p), (K_m, G_m) = _moduli(p, "p", "composite_cylinders"), _moduli(p, "m", "composite_cylinders")
    if G_p is None or G_m is None:
        raise CaseError("composite_cylinders needs analytic.G_p and G_m (or E and nu of each phase)")
    a = positive("a", p["a"])
    given = [k for k in ("phi", "b") if p[k] is not None]
    if len(given) != 1:
        raise CaseError(f"composite_cylinders needs exactly one of analytic.phi, analytic.b, got {given or 'none'}")
    if p["b"] is not None and positive("b", p["b"]) <= a:
        raise CaseError(f"analytic.b must be > a = {a:g} mm, got {p['b']:g}")
    phi = p["phi"] if p["phi"] is not None else (a / p["b"]) ** 2
    return CompositeCylinders(plane_strain_bulk_modulus(K_p, G_p), plane_strain_bulk_modulus(K_m, G_m),
                              G_m, phi, a, p["Dn"]), p


@_named
def composite_cylinders(**params) -> dict[str, float]:
    """Transverse (plane-strain) bulk modulus of composite cylinders with a spring interface."""
    m, _ = _cca(params)
    perfect = CompositeCylinders(m.k_f, m.k_m, m.G_m, m.phi, m.a, _INF).bulk_modulus
    debonded = CompositeCylinders(m.k_f, m.k_m, m.G_m, m.phi, m.a, 0.0).bulk_modulus
    return {"bulk_modulus": m.bulk_modulus, "bulk_modulus_perfect": perfect, "bulk_modulus_debonded": debonded,
            "effective_fibre_modulus": m.effective_fibre_modulus, "phi": m.phi}


@_named
def composite_cylinders_profiles(**params) -> dict[str, dict[str, np.ndarray]]:
    """Radial displacement and stress through fibre and matrix for u(b) = eps0 b."""
    m, p = _cca(params)
    if m.phi == 0.0:
        raise CaseError("analytic.phi = 0 has no finite matrix cylinder to plot; use phi > 0")
    return _radial_profile(m, p)


# ---- shock Hugoniot ---------------------------------------------------------------
_SHOCK = {"K": ..., "rho": ..., "S1": ..., "gamma0": ..., "Y": 0.0, "G": 0.0, "impact_speed": ...,
          "impact": "wall", "n_points": 41, "up_max": None}


def _shock(params: dict[str, Any]) -> tuple[ShockHugoniot, float, dict[str, Any]]:
    p = _take(params, "shock_hugoniot", _SHOCK)
    if p["impact"] not in ("wall", "symmetric"):
        raise CaseError(f"analytic.impact must be 'wall' or 'symmetric', got {p['impact']!r}")
    v = check_number("impact_speed", p["impact_speed"], low=0.0, low_open=True)
    model = ShockHugoniot(p["K"], p["rho"], p["S1"], p["gamma0"], p["Y"], p["G"])
    return model, v if p["impact"] == "wall" else 0.5 * v, p


@_named
def shock_hugoniot(**params) -> dict[str, float]:
    """The shocked state behind the front of an impact (u_p, U_s, J, p, sigma, U)."""
    model, up, _ = _shock(params)
    st = model.state(up)
    return {"particle_speed": st.particle_speed, "shock_speed": st.shock_speed,
            "volume_ratio": st.volume_ratio, "pressure": st.pressure,
            "longitudinal_stress": st.longitudinal_stress,
            "specific_internal_energy": st.specific_internal_energy,
            "bulk_wave_speed": model.bulk_wave_speed}


@_named
def shock_hugoniot_profiles(**params) -> dict[str, dict[str, np.ndarray]]:
    """``hugoniot``: the curve over particle speeds 0 .. up_max (default 1.5 u_p)."""
    model, up, p = _shock(params)
    top = 1.5 * up if p["up_max"] is None else check_number("up_max", p["up_max"], low=0.0, low_open=True)
    return {"hugoniot": model.curve(np.linspace(0.0, top, _n_points(p["n_points"])))}


# ---- gap closure -------------------------------------------------------------------
_GAP = {"gap": ..., "speed": ..., "height": 0.0, "wave_speed": _INF}


@_named
def gap_closure(**params) -> dict[str, float]:
    """Time for a body pushed at ``speed`` to close ``gap`` (004 Fig 2's theoretical
    contact time), the elastic transit of the push through the body included."""
    p = _take(params, "gap_closure", _GAP)
    gap = positive("gap", p["gap"])
    speed = positive("speed", p["speed"])
    transit = nonnegative("height", p["height"]) / positive("wave_speed", p["wave_speed"], allow_inf=True)
    return {"contact_time": gap / speed + transit}


@_named
def gap_closure_profiles(**params) -> dict[str, dict[str, np.ndarray]]:
    """No curves: the model gives one time."""
    _take(params, "gap_closure", _GAP)
    return {}


_PARAMETER_NAMES = set(_DLS) | set(_DLS_ALIASES) | set(_DCB) | set(_WAVE) | set(_CSA) | set(_CCA) | set(_SHOCK) | set(_GAP)

MODELS: dict[str, Callable[..., dict[str, float]]] = {
    "dls_shear_lag": dls_shear_lag,
    "dcb_beam_foundation": dcb_beam_foundation,
    "wave_transmission": wave_transmission_model,
    "composite_spheres": composite_spheres,
    "composite_cylinders": composite_cylinders,
    "shock_hugoniot": shock_hugoniot,
    "gap_closure": gap_closure,
}

PROFILES: dict[str, Callable[..., dict[str, dict[str, np.ndarray]]]] = {
    "dls_shear_lag": dls_profiles,
    "dcb_beam_foundation": dcb_profiles,
    "wave_transmission": wave_profiles,
    "composite_spheres": composite_spheres_profiles,
    "composite_cylinders": composite_cylinders_profiles,
    "shock_hugoniot": shock_hugoniot_profiles,
    "gap_closure": gap_closure_profiles,
}


def model_names() -> list[str]:
    """Names accepted as ``case.analytic["model"]``."""
    return sorted(MODELS)
