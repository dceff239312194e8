"""Composite-spheres bulk modulus with an imperfect (spring) interface.

Used for the particulate composite of 000 Sec 3 (Fig 12-13), where the numerical
methods compute K from energy, K = 2 (U_strain + U_interface)/(9 V eps0^2)
(000 Eq 34-35), or from the mean stress, K = P/(3 eps0) (000 Eq 36). The
perfect-interface limit is Hashin's composite spheres assemblage (CSA, Hashin
1962); the imperfect form is that of Hashin (1991b), re-derived here.

Derivation. A particle of radius a (bulk modulus K_p) in a matrix shell of outer
radius b (K_m, G_m), phi = (a/b)^3, under the uniform radial displacement
u(b) = eps0 b. Lame solutions: u = A r in the particle (sigma_rr = 3 K_p A), and
u = B r + C/r^2 in the shell (sigma_rr = 3 K_m B - 4 G_m C/r^3). Conditions:

    sigma_rr continuous at r = a:      3 K_p A = 3 K_m B - 4 G_m C/a^3
    spring interface (000 Eq 4):       3 K_p A = Dn (B a + C/a^2 - A a)
    outer boundary:                    B + C/b^3 = eps0

Eliminating A from the first two gives 3 K_p A = 3 K_e (B + C/a^3) with the
series combination 1/K_e = 1/K_p + 3/(a Dn): the interface acts as a softer
particle. Solving for B and c = C/a^3 and K* = sigma_rr(b)/(3 eps0):

    K* = [K_m (3 K_e + 4 G_m) + 4 G_m phi (K_e - K_m)] / [3 K_e + 4 G_m - 3 phi (K_e - K_m)]
       = K_m + phi (K_e - K_m) / (1 + (1 - phi)(K_e - K_m)/(K_m + 4 G_m/3)),

Hashin's CSA formula with K_p replaced by K_e. Dn = inf gives K_e = K_p (CSA);
Dn = 0 gives K_e = 0, the empty-cavity value 4 G_m K_m (1 - phi)/(4 G_m + 3 phi K_m).
The particle shear modulus and Dt do not enter (spherical symmetry). A negative Dn
(stiff interphase, 002 Eq 52) is accepted down to the rigid limit 1/K_e = 0.

Units: MPa, mm, MPa/mm; energies in N mm.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from interfaces.analytic._checks import CaseError, interface_stiffness, points, positive
from interfaces.errors import check_number

__all__ = ["CompositeSpheres", "bulk_shear_from_young_poisson", "hashin_bulk_modulus",
           "composite_spheres_bulk_modulus", "sphere_in_cube_volume_fraction"]


def bulk_shear_from_young_poisson(E: float, nu: float) -> tuple[float, float]:
    """Isotropic (K, G) = (E/(3(1-2nu)), E/(2(1+nu))) in MPa from Young's modulus and Poisson ratio."""
    E = positive("E", E)
    nu = check_number("nu", nu, low=-1.0, high=0.5, low_open=True, high_open=True)
    return E / (3.0 * (1.0 - 2.0 * nu)), E / (2.0 * (1.0 + nu))


def sphere_in_cube_volume_fraction(radius: float, side: float, *, octant: bool = False) -> float:
    """Particle volume fraction of a sphere in a cubic cell (simple cubic array).

    ``octant=False``: a whole sphere of ``radius`` centred in a cube of ``side``
    (needs 2 radius <= side), phi = (4/3) pi r^3 / s^3. ``octant=True``: the 1/8
    symmetry model of 000 Sec 3, one eighth of the sphere at a corner of the cube
    (needs radius <= side), phi = (pi/6) r^3 / s^3. The 000 particulate composite,
    radius 700 um in a cube of side 1000 um with octant=True (equivalently a sphere
    of diameter 700 um centred in a 1000 um cube), gives phi = 0.1796.
    """
    r, s = positive("radius", radius), positive("side", side)
    limit = s if octant else 0.5 * s
    if r > limit:
        raise CaseError(f"radius must be <= {limit:g} (the sphere must fit in the cube of side "
                        f"{s:g}{' with its centre at a corner' if octant else ''}), got {r:g}")
    return (math.pi / 6.0 if octant else 4.0 * math.pi / 3.0) * (r / s) ** 3


def hashin_bulk_modulus(K_p: float, K_m: float, G_m: float, phi: float) -> float:
    """Hashin's composite-spheres bulk modulus with a perfect interface (MPa):
    K* = K_m + phi (K_p - K_m) / (1 + (1 - phi)(K_p - K_m)/(K_m + 4 G_m/3))."""
    K_p, K_m, G_m = positive("K_p", K_p), positive("K_m", K_m), positive("G_m", G_m)
    phi = check_number("phi", phi, low=0.0, high=1.0, high_open=True)
    return K_m + phi * (K_p - K_m) / (1.0 + (1.0 - phi) * (K_p - K_m) / (K_m + 4.0 * G_m / 3.0))


def series_inverse_modulus(K: float, d: float, a: float, Dn: float) -> float:
    """1/K_e = 1/K + d/(a Dn) (1/MPa): an inclusion of radius a and modulus K in series with a
    spring interface Dn (d = 3 for a sphere's bulk modulus, 2 for a cylinder's plane-strain
    one); inf when debonded (Dn = 0), 1/K when perfect."""
    if Dn == 0.0:
        return math.inf
    return 1.0 / K + (0.0 if math.isinf(Dn) else d / (a * Dn))


def modulus_from_inverse(s: float) -> float:
    """K_e from 1/K_e: 0 for a debonded inclusion (inf), inf at the rigid-interphase limit (0)."""
    return 0.0 if math.isinf(s) else (math.inf if s == 0.0 else 1.0 / s)


def check_coated_inclusion(model, moduli: tuple[str, ...], inclusion: str, d: float) -> None:
    """Validate the fields of a frozen composite sphere/cylinder in place: positive ``moduli``
    and radius a, 0 <= phi < 1, and Dn (inf, 0, or negative down to the rigid-interphase
    limit 1/K + d/(a Dn) >= 0 of the ``inclusion`` modulus K; 002 Eq 52)."""
    set_ = lambda k, v: object.__setattr__(model, k, v)  # noqa: E731 (frozen dataclass)
    for name in moduli + ("a",):
        set_(name, positive(name, getattr(model, name)))
    set_("phi", check_number("phi", model.phi, low=0.0, high=1.0, high_open=True))
    set_("Dn", interface_stiffness("Dn", model.Dn, allow_negative=True))
    K = getattr(model, inclusion)
    if model.Dn < 0.0 and series_inverse_modulus(K, d, model.a, model.Dn) < 0.0:
        raise CaseError(f"Dn = {model.Dn:g} MPa/mm is beyond the rigid-interphase limit: a negative Dn must "
                        f"satisfy 1/{inclusion} + {d:g}/(a Dn) >= 0, i.e. Dn <= {-d * K / model.a:g} MPa/mm")


@dataclass(frozen=True)
class CompositeSpheres:
    """One composite sphere: particle (K_p, radius a) in a matrix shell (K_m, G_m), phi = (a/b)^3,
    spring interface sigma_rr = Dn [u_r] (Dn in MPa/mm, inf perfect, 0 debonded)."""

    K_p: float
    K_m: float
    G_m: float
    phi: float
    a: float
    Dn: float = math.inf

    def __post_init__(self) -> None:
        check_coated_inclusion(self, ("K_p", "K_m", "G_m"), "K_p", 3.0)

    @property
    def b(self) -> float:
        """Outer radius a / phi^(1/3) (mm); inf for phi = 0."""
        return math.inf if self.phi == 0.0 else self.a / self.phi ** (1.0 / 3.0)

    @property
    def inverse_effective_particle_modulus(self) -> float:
        """1/K_e = 1/K_p + 3/(a Dn) (1/MPa): particle and interface in series."""
        return series_inverse_modulus(self.K_p, 3.0, self.a, self.Dn)

    @property
    def effective_particle_modulus(self) -> float:
        """K_e (MPa); 0 for a debonded particle, inf at the rigid-interphase limit."""
        return modulus_from_inverse(self.inverse_effective_particle_modulus)

    @property
    def bulk_modulus(self) -> float:
        """Effective bulk modulus K* (MPa) of the composite spheres assemblage (module docstring)."""
        Ke, Km, Gm, phi = self.effective_particle_modulus, self.K_m, self.G_m, self.phi
        if math.isinf(Ke):  # rigid particle
            return (3.0 * Km + 4.0 * Gm * phi) / (3.0 * (1.0 - phi))
        return (Km * (3.0 * Ke + 4.0 * Gm) + 4.0 * Gm * phi * (Ke - Km)) / \
            (3.0 * Ke + 4.0 * Gm - 3.0 * phi * (Ke - Km))

    def coefficients(self, eps0: float = 1.0) -> tuple[float, float, float]:
        """(A, B, C) of u = A r (particle), u = B r + C/r^2 (matrix) for u(b) = eps0 b."""
        eps0 = check_number("eps0", eps0)
        Km, Gm, phi, a = self.K_m, self.G_m, self.phi, self.a
        s = self.inverse_effective_particle_modulus
        # with q = 3 K_e: c = C/a^3 = B (3 K_m - q)/(q + 4 G_m), written in terms of 1/K_e
        if math.isinf(s):
            ratio = 3.0 * Km / (4.0 * Gm)
        else:
            ratio = (3.0 * Km * s - 3.0) / (3.0 + 4.0 * Gm * s)
        B = eps0 / (1.0 + phi * ratio)
        c = B * ratio
        if s == 0.0:  # rigid-interphase limit: A from traction continuity 3 K_p A = 3 K_m B - 4 G_m c
            A = (3.0 * Km * B - 4.0 * Gm * c) / (3.0 * self.K_p)
        else:  # 3 K_p A = 3 K_e (B + c), free of cancellation for a soft interface
            A = 0.0 if math.isinf(s) else (B + c) / (self.K_p * s)
        return A, B, c * a ** 3

    def radial_displacement(self, r, eps0: float = 1.0) -> np.ndarray:
        """u_r(r) (mm) for 0 <= r <= b; at r = a the particle-side value (the jump is at a+)."""
        r = points("r", r, 0.0, self.b)
        A, B, C = self.coefficients(eps0)
        rr = np.atleast_1d(r)
        out = A * rr
        m = rr > self.a
        out[m] = B * rr[m] + C / rr[m] ** 2
        return out.reshape(r.shape)

    def radial_stress(self, r, eps0: float = 1.0) -> np.ndarray:
        """sigma_rr(r) (MPa) for 0 <= r <= b (continuous across r = a)."""
        r = points("r", r, 0.0, self.b)
        A, B, C = self.coefficients(eps0)
        rr = np.atleast_1d(r)
        out = np.full_like(rr, 3.0 * self.K_p * A)
        m = rr > self.a
        out[m] = 3.0 * self.K_m * B - 4.0 * self.G_m * C / rr[m] ** 3
        return out.reshape(r.shape)

    def interface_jump(self, eps0: float = 1.0) -> float:
        """Radial displacement jump [u_r] = u_matrix(a) - u_particle(a) (mm)."""
        A, B, C = self.coefficients(eps0)
        return B * self.a + C / self.a ** 2 - A * self.a

    def energies(self, eps0: float = 1.0) -> dict[str, float]:
        """Strain energy of particle and matrix and interface energy (N mm) of one composite
        sphere, from the fields (not from K*): U_p = (9/2) K_p A^2 V_p,
        U_m = (9/2) K_m B^2 (V - V_p) + 8 pi G_m C^2 (1/a^3 - 1/b^3), U_i = (1/2) Dn [u]^2 4 pi a^2.
        Their sum equals (9/2) K* eps0^2 V (000 Eq 34)."""
        if self.phi == 0.0:
            raise CaseError("phi = 0 has no finite composite sphere; use phi > 0")
        A, B, C = self.coefficients(eps0)
        a, b = self.a, self.b
        vp = 4.0 / 3.0 * math.pi * a ** 3
        v = 4.0 / 3.0 * math.pi * b ** 3
        up = 4.5 * self.K_p * A * A * vp
        um = 4.5 * self.K_m * B * B * (v - vp) + 8.0 * math.pi * self.G_m * C * C * (a ** -3 - b ** -3)
        if self.Dn == 0.0 or math.isinf(self.Dn):
            ui = 0.0
        else:
            ui = 0.5 * self.Dn * self.interface_jump(eps0) ** 2 * 4.0 * math.pi * a * a
        return {"strain_energy": up + um, "interface_energy": ui, "volume": v,
                "particle_strain_energy": up, "matrix_strain_energy": um}


def composite_spheres_bulk_modulus(K_p: float, K_m: float, G_m: float, phi: float,
                                   a: float = 1.0, Dn: float = math.inf) -> float:
    """Composite-spheres bulk modulus with a spring interface (MPa) (module docstring;
    Hashin 1991b form, used for 000 Sec 3 Fig 12-13). ``a`` is the particle radius
    (mm): the interface enters only through a Dn, the particle-size effect of 000 Fig 13."""
    return CompositeSpheres(K_p, K_m, G_m, phi, a, Dn).bulk_modulus
