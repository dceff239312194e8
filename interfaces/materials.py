"""Linear elastic and hyperelastic materials with stiffness matrices for every analysis.

Units: moduli in MPa, density in tonne/mm^3 (1 g/cm^3 = 1e-9), wave speeds in mm/s.

Every material gives its small-strain stiffness in *global* axes for an analysis:
``"plane_stress"``, ``"plane_strain"`` (Voigt ``[xx, yy, xy]``, engineering shear),
``"axisymmetric"`` (``[rr, zz, tt, rz]`` with x = r, y = z) or ``"3d"``
(``[xx, yy, zz, yz, xz, xy]``). Plane stress is obtained from the 3D compliance
(rows/columns xx, yy, xy), plane strain from the 3D stiffness, so orthotropic
materials with any in-plane fibre direction reduce correctly.

The wood strands of 002 Sec 3.1 and 000 Sec 3 are transversely isotropic:
``TransverselyIsotropicElastic(E_A=10000, E_T=1000, G_A=500, nu_A=0.2, fiber=(0, 1))``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import ClassVar

import numpy as np

from .errors import CaseError, build_tagged, check_number

ANALYSES = ("plane_stress", "plane_strain", "axisymmetric", "3d")
_VOIGT = ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))
_INDEX = {"plane_stress": [0, 1, 5], "plane_strain": [0, 1, 5],
          "axisymmetric": [0, 1, 2, 5], "3d": [0, 1, 2, 3, 4, 5]}
DEFAULT_DENSITY = 1.0e-9
"""1 g/cm^3 in tonne/mm^3."""


def check_analysis(analysis: str, field_name: str = "analysis") -> str:
    if analysis not in ANALYSES:
        raise CaseError(f"{field_name} must be one of {', '.join(ANALYSES)}, got {analysis!r}")
    return analysis


def voigt_to_tensor(C: np.ndarray) -> np.ndarray:
    """6x6 Voigt stiffness (engineering shear strains) -> 3x3x3x3 tensor."""
    T = np.zeros((3, 3, 3, 3))
    for I, (i, j) in enumerate(_VOIGT):
        for J, (k, l) in enumerate(_VOIGT):
            v = C[I, J]
            T[i, j, k, l] = T[j, i, k, l] = T[i, j, l, k] = T[j, i, l, k] = v
    return T


def tensor_to_voigt(T: np.ndarray) -> np.ndarray:
    """3x3x3x3 stiffness tensor -> 6x6 Voigt (engineering shear strains)."""
    C = np.empty((6, 6))
    for I, (i, j) in enumerate(_VOIGT):
        for J, (k, l) in enumerate(_VOIGT):
            C[I, J] = T[i, j, k, l]
    return C


def reduce_stiffness(C3: np.ndarray, analysis: str) -> np.ndarray:
    """Reduce a global 6x6 stiffness to the Voigt matrix of ``analysis``."""
    check_analysis(analysis)
    idx = _INDEX[analysis]
    if analysis == "plane_stress":
        S = np.linalg.inv(C3)
        return np.linalg.inv(S[np.ix_(idx, idx)])
    return C3[np.ix_(idx, idx)].copy()


class Material:
    """Base class: subclasses define ``stiffness3d()`` (global 6x6) and ``rho``."""

    kind: ClassVar[str] = ""
    rho: float

    def stiffness3d(self) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def compliance3d(self) -> np.ndarray:
        """Global 6x6 compliance (engineering shear strains)."""
        return np.linalg.inv(self.stiffness3d())

    def stiffness(self, analysis: str) -> np.ndarray:
        """Small-strain stiffness in global axes for ``analysis`` (see module docstring)."""
        return reduce_stiffness(self.stiffness3d(), analysis)

    def wave_speed(self, analysis: str = "3d") -> float:
        """Largest quasi-longitudinal (dilatational) wave speed in mm/s.

        Found as the largest eigenvalue of the acoustic tensor C_ijkl n_j n_l over
        propagation directions n (in the x-y plane for 2D analyses; for plane stress the
        reduced in-plane stiffness is used), divided by rho.
        """
        check_analysis(analysis)
        if analysis == "plane_stress":
            C2 = self.stiffness("plane_stress")
            C3 = np.zeros((6, 6))
            idx = [0, 1, 5]
            C3[np.ix_(idx, idx)] = C2
            T = voigt_to_tensor(C3)
        else:
            T = voigt_to_tensor(self.stiffness3d())
        if analysis == "3d":
            rng = np.random.default_rng(0)
            n = rng.normal(size=(400, 3))
            n = np.vstack([n, np.eye(3), np.ones((1, 3))])
        else:
            th = np.linspace(0.0, math.pi, 181)
            n = np.stack([np.cos(th), np.sin(th), 0 * th], axis=1)
        n /= np.linalg.norm(n, axis=1, keepdims=True)
        gamma = np.einsum("ijkl,nj,nl->nik", T, n, n)
        lam = np.linalg.eigvalsh(gamma).max()
        return math.sqrt(lam / self.rho)

    # ---- serialisation -------------------------------------------------
    def to_dict(self) -> dict:
        d = {"type": self.kind}
        for f in fields(self):
            v = getattr(self, f.name)
            d[f.name] = list(v) if isinstance(v, tuple) else v
        return d


_MATERIALS: dict[str, type] = {}


#: largest modulus / density accepted (as for the analytic models): the stiffness matrices
#: of larger ones overflow in their inversion
MAX_CONSTANT = 1e30


def _positive(obj, *names: str) -> None:
    """Validate (0 < value <= MAX_CONSTANT) and store the named fields of a frozen dataclass."""
    for name in names:
        v = check_number(name, getattr(obj, name), low=0, low_open=True)
        object.__setattr__(obj, name, check_number(name, v, high=MAX_CONSTANT))


def _register(cls):
    _MATERIALS[cls.kind] = cls
    return cls


def material_from_dict(d: dict, where: str = "material") -> Material:
    """Build a material from its TOML table; errors name ``where.field``."""
    return build_tagged(_MATERIALS, d, where, convert_lists=True)


@_register
@dataclass(frozen=True)
class IsotropicElastic(Material):
    """Isotropic linear elasticity: Young's modulus E (MPa), Poisson ratio nu, density rho (t/mm^3)."""

    E: float
    nu: float
    rho: float = DEFAULT_DENSITY
    kind: ClassVar[str] = "isotropic"

    def __post_init__(self):
        _positive(self, "E", "rho")
        object.__setattr__(self, "nu", check_number("nu", self.nu, low=-1, high=0.5, low_open=True, high_open=True))

    @property
    def G(self) -> float:
        return self.E / (2 * (1 + self.nu))

    @property
    def K(self) -> float:
        return self.E / (3 * (1 - 2 * self.nu))

    @property
    def lame(self) -> tuple[float, float]:
        """(lambda, mu) of 3D elasticity."""
        return self.E * self.nu / ((1 + self.nu) * (1 - 2 * self.nu)), self.G

    def stiffness3d(self) -> np.ndarray:
        lam, mu = self.lame
        C = np.zeros((6, 6))
        C[:3, :3] = lam
        C[np.arange(3), np.arange(3)] = lam + 2 * mu
        C[np.arange(3, 6), np.arange(3, 6)] = mu
        return C


@_register
@dataclass(frozen=True)
class TransverselyIsotropicElastic(Material):
    """Transversely isotropic (e.g. wood strand) linear elasticity with a fibre direction.

    E_A: axial (fibre) modulus, E_T: transverse modulus, G_A: axial shear modulus,
    nu_A: major Poisson ratio (-eps_T/eps_A under axial stress), nu_T: transverse
    Poisson ratio (G_T = E_T / (2 (1 + nu_T))), fiber: axial direction in global axes
    (2 components = in the x-y plane, or 3). Moduli in MPa, rho in tonne/mm^3.
    """

    E_A: float
    E_T: float
    G_A: float
    nu_A: float
    nu_T: float = 0.3
    fiber: tuple = (1.0, 0.0)
    rho: float = DEFAULT_DENSITY
    kind: ClassVar[str] = "transversely_isotropic"

    def __post_init__(self):
        _positive(self, "E_A", "E_T", "G_A")
        object.__setattr__(self, "nu_T", check_number("nu_T", self.nu_T, low=-1, high=1, low_open=True, high_open=True))
        nu_A = check_number("nu_A", self.nu_A, low=-10.0, high=10.0)
        object.__setattr__(self, "nu_A", nu_A)
        _positive(self, "rho")
        if not 1 - self.nu_T - 2 * nu_A**2 * self.E_T / self.E_A > 0:
            lim = math.sqrt((1 - self.nu_T) * self.E_A / (2 * self.E_T))
            raise CaseError(f"nu_A must satisfy |nu_A| < sqrt((1 - nu_T) E_A / (2 E_T)) = {lim:.4g} "
                            f"for a positive definite stiffness, got {nu_A:g}")
        try:
            f = np.asarray(self.fiber, dtype=float)
        except (TypeError, ValueError):
            raise CaseError(f"fiber must be 2 or 3 numbers, got {self.fiber!r}") from None
        if f.shape not in ((2,), (3,)) or not np.all(np.isfinite(f)) or not np.any(f):
            raise CaseError(f"fiber must be a non-zero vector of 2 or 3 finite numbers, got {self.fiber!r}")
        f = f / np.abs(f).max()          # scaled first: the norm of (1e308, 1e308) overflows
        object.__setattr__(self, "fiber", tuple(float(x) for x in f / np.linalg.norm(f)))

    @property
    def G_T(self) -> float:
        return self.E_T / (2 * (1 + self.nu_T))

    def local_compliance(self) -> np.ndarray:
        """6x6 compliance in material axes (1 = fibre, 2, 3 transverse)."""
        S = np.zeros((6, 6))
        S[0, 0] = 1 / self.E_A
        S[1, 1] = S[2, 2] = 1 / self.E_T
        S[0, 1] = S[1, 0] = S[0, 2] = S[2, 0] = -self.nu_A / self.E_A
        S[1, 2] = S[2, 1] = -self.nu_T / self.E_T
        S[3, 3] = 1 / self.G_T
        S[4, 4] = S[5, 5] = 1 / self.G_A
        return S

    def axes(self) -> np.ndarray:
        """Rows: material axes (fibre, transverse 1, transverse 2) in global coordinates."""
        f = np.zeros(3)
        f[: len(self.fiber)] = self.fiber
        helper = np.array([0.0, 0.0, 1.0]) if abs(f[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
        e3 = np.cross(f, helper)
        e3 /= np.linalg.norm(e3)
        e2 = np.cross(e3, f)
        # for an in-plane fibre this gives e2 in the x-y plane and e3 = +/- z
        return np.stack([f, e2, e3])

    def stiffness3d(self) -> np.ndarray:
        C_local = voigt_to_tensor(np.linalg.inv(self.local_compliance()))
        Q = self.axes()  # local_i = Q_ij global_j  -> global = Q^T local
        Cg = np.einsum("ai,bj,ck,dl,abcd->ijkl", Q, Q, Q, Q, C_local)
        return tensor_to_voigt(Cg)


#: volumetric terms U(J) of the neo-Hookean strain energy: 004 Eq 18 (the NairnMPM
#: default, Simo and Hughes Eq 9.2.3) and the two other forms NairnMPM offers
VOLUMETRIC_TERMS = ("eq18", "J_minus_1_squared", "ln_J_squared")


@_register
@dataclass(frozen=True)
class NeoHookean(Material):
    """Compressible neo-Hookean solid with bulk modulus K and shear modulus G (MPa).

    Strain energy per unit reference volume (004 Eq 18)
    W = G/2 (I1 / J^(2/3) - 3) + U(J), with I1 = tr(F F^T), J = det F and, by default
    (``volumetric = "eq18"``), U(J) = K/2 ((J^2 - 1)/2 - ln J). ``"J_minus_1_squared"``
    gives U = K/2 (J - 1)^2 and ``"ln_J_squared"`` U = K/2 (ln J)^2; all three have
    U''(1) = K, so the small-strain stiffness is isotropic with the same K and G.
    Cauchy stress sigma = G J^(-5/3) dev(B) + U'(J) I with B = F F^T.
    """

    K: float
    G: float
    rho: float = DEFAULT_DENSITY
    volumetric: str = "eq18"
    kind: ClassVar[str] = "neo_hookean"

    def __post_init__(self):
        _positive(self, "K", "G", "rho")
        if self.volumetric not in VOLUMETRIC_TERMS:
            raise CaseError(f"volumetric must be one of {', '.join(VOLUMETRIC_TERMS)}, "
                            f"got {self.volumetric!r}")

    def stiffness3d(self) -> np.ndarray:
        return isotropic_from_KG(self.K, self.G).stiffness3d()

    def volumetric_energy(self, J):
        """U(J) (MPa = N mm / mm^3 of reference volume)."""
        J = np.asarray(J, dtype=float)
        if self.volumetric == "J_minus_1_squared":
            return 0.5 * self.K * (J - 1.0) ** 2
        if self.volumetric == "ln_J_squared":
            return 0.5 * self.K * np.log(J) ** 2
        return 0.5 * self.K * (0.5 * (J * J - 1.0) - np.log(J))

    def volumetric_stress(self, J):
        """U'(J), the mean Cauchy stress of the volumetric term (tension positive)."""
        J = np.asarray(J, dtype=float)
        if self.volumetric == "J_minus_1_squared":
            return self.K * (J - 1.0)
        if self.volumetric == "ln_J_squared":
            return self.K * np.log(J) / J
        return 0.5 * self.K * (J - 1.0 / J)

    def energy_density(self, F):
        """W(F) of 004 Eq 18 for deformation gradients F (..., 3, 3)."""
        F = np.asarray(F, dtype=float)
        J = np.linalg.det(F)
        I1 = np.einsum("...ij,...ij->...", F, F)
        return 0.5 * self.G * (I1 / np.cbrt(J) ** 2 - 3.0) + self.volumetric_energy(J)

    def cauchy_stress(self, F):
        """Cauchy stress (..., 3, 3) for deformation gradients F (..., 3, 3)."""
        F = np.asarray(F, dtype=float)
        J = np.linalg.det(F)
        B = F @ np.swapaxes(F, -1, -2)
        I1 = np.trace(B, axis1=-2, axis2=-1)
        eye = np.eye(3)
        dev = B - (I1 / 3.0)[..., None, None] * eye
        return (self.G * J ** (-5.0 / 3.0))[..., None, None] * dev \
            + np.asarray(self.volumetric_stress(J))[..., None, None] * eye


@_register
@dataclass(frozen=True)
class MieGruneisen(Material):
    """Mie-Grueneisen pressure (004 Eq 51) with shear modulus G (MPa).

    Hugoniot parameters: bulk sound speed C0 (mm/s), slope S1, Grueneisen gamma0.
    ``pressure(J, e)`` gives p for the volume ratio J = V/V0 and the internal energy
    per unit reference volume e (MPa): p = rho0 C0^2 eta (1 - gamma0 eta / 2) /
    (1 - S1 eta)^2 + gamma0 e with eta = 1 - J (compression positive).
    A1, A2: the linear and quadratic coefficients of the artificial viscosity of 004
    Eq 52 (004 Fig 7: 0.4 and 4.0; 0 = none), used by the MPM stress update
    (``mpm.mie_gruneisen``).
    """

    C0: float
    S1: float
    gamma0: float
    G: float
    rho: float = DEFAULT_DENSITY
    A1: float = 0.0
    A2: float = 0.0
    kind: ClassVar[str] = "mie_gruneisen"

    def __post_init__(self):
        _positive(self, "C0", "G", "rho")
        for name in ("S1", "gamma0", "A1", "A2"):
            object.__setattr__(self, name, check_number(name, getattr(self, name), low=0))

    @property
    def K(self) -> float:
        """Small-strain bulk modulus rho C0^2."""
        return self.rho * self.C0**2

    def pressure(self, J, e=0.0):
        """Pressure (MPa) of 004 Eq 51 at volume ratio J and energy density e (MPa)."""
        eta = 1.0 - np.asarray(J, dtype=float)
        if np.any(self.S1 * eta >= 1.0):
            raise CaseError(f"MieGruneisen: compression eta = 1 - J reached 1/S1 = {1 / self.S1:g} (shock Hugoniot singularity)")
        return self.rho * self.C0**2 * eta * (1 - self.gamma0 * eta / 2) / (1 - self.S1 * eta) ** 2 + self.gamma0 * np.asarray(e)

    def stiffness3d(self) -> np.ndarray:
        return isotropic_from_KG(self.K, self.G).stiffness3d()


FINITE_STRAIN_KINDS = ("neo_hookean", "mie_gruneisen")


def small_strain_refusal(case, method: str) -> str | None:
    """The one-line reason a small-strain linear method cannot run ``case`` (a material
    defined only at finite strain: neo-Hookean, Mie-Grueneisen), or None. Running such a
    material through its small-strain stiffness would answer a different problem."""
    for name, mat in case.materials.items():
        if getattr(mat, "kind", "") in FINITE_STRAIN_KINDS:
            return (f"materials.{name} is {type(mat).__name__}, a finite-strain material; {method} "
                    "solves small-strain linear elasticity (use mpm)")
    return None


def isotropic_from_KG(K: float, G: float, rho: float = DEFAULT_DENSITY) -> IsotropicElastic:
    """Isotropic material from bulk and shear moduli (MPa)."""
    K = check_number("K", K, low=0, low_open=True)
    G = check_number("G", G, low=0, low_open=True)
    E = 9 * K * G / (3 * K + G)
    nu = (3 * K - 2 * G) / (2 * (3 * K + G))
    return IsotropicElastic(E=E, nu=nu, rho=rho)
