"""CPD material constants (C1, C2, C3) <-> isotropic linear elasticity.

Continuum convention (ERRATA 12): the energies of 003 Eq 7, 10 integrated over a full
continuum horizon of radius delta under a small uniform strain, every neighbour pair
(triple) inside the central point's horizon, give

* 2D (plane, per unit thickness): mu = pi C1 delta^3 / 24,
  lambda = pi C1 delta^3 / 24 + 8 pi C2 delta^6 / 27; nu_2D = lambda / (lambda + 2 mu)
  reproduces 003 Eq 25; plane strain: nu_3D = nu_2D / (1 + nu_2D).
* 3D (C2 = 0): mu = pi C1 delta^4 / 30, lambda = mu + pi^4 C3 delta^12 / 32.

(the pair part: W1 = 1/4 C1 int L (n.eps.n)^2 dV; the triple part: a/A = det F exactly
for a uniform deformation, so W2 = 1/6 C2 (J - 1)^2 int int A dV dV with
int int |Xi x Xj| = 8 pi delta^6 / 9; the quadruple part likewise with
int int int |det| = pi^4 delta^12 / 8.)

A discrete lattice sums slightly differently; :func:`lattice_ratios` measures the
energy density of an interior grid point under small uniform strains with the actual
kernels, and :func:`calibrate` rescales the constants so that it matches (``"lattice"``).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from interfaces.errors import CaseError


def nu2d_from_nu3d(nu3d: float) -> float:
    """Plane-strain conversion nu_2D = nu_3D / (1 - nu_3D) (inverse of 003 Sec 4.1)."""
    return nu3d / (1.0 - nu3d)


def nu3d_from_nu2d(nu2d: float) -> float:
    """nu_3D = nu_2D / (1 + nu_2D) (003 Sec 4.1, ERRATA 12)."""
    return nu2d / (1.0 + nu2d)


def poisson_2d(C1: float, C2: float, delta: float) -> float:
    """003 Eq 25: the plane Poisson ratio nu_2D(C1, C2, delta)."""
    r = C2 / C1 * delta ** 3
    return (r + 9.0 / 64.0) / (r + 27.0 / 64.0)


def lame_from_cpd(C1: float, C2: float, C3: float, delta: float, dim: int) -> tuple[float, float]:
    """(lambda, mu) of the continuum-horizon CPD energy (ERRATA 12).

    2D returns the plane constants (per unit thickness); 3D requires C2 = 0.
    """
    if dim == 2:
        mu = math.pi * C1 * delta ** 3 / 24.0
        return mu + 8.0 * math.pi * C2 * delta ** 6 / 27.0, mu
    if dim == 3:
        if C2 != 0.0:
            raise CaseError("C2 must be 0 for the 3D conversion (003 Sec 4.5 uses C1 and C3 only)")
        mu = math.pi * C1 * delta ** 4 / 30.0
        return mu + math.pi ** 4 * C3 * delta ** 12 / 32.0, mu
    raise CaseError(f"dimension must be 2 or 3, got {dim}")


def cpd_from_lame(lam: float, mu: float, delta: float, dim: int) -> tuple[float, float, float]:
    """(C1, C2, C3) with the given (plane, in 2D) Lame constants; inverse of :func:`lame_from_cpd`."""
    if not mu > 0:
        raise CaseError(f"shear modulus mu must be > 0, got {mu:g}")
    if not delta > 0:
        raise CaseError(f"delta must be > 0, got {delta:g}")
    if dim == 2:
        C1 = 24.0 * mu / (math.pi * delta ** 3)
        return C1, 27.0 * (lam - mu) / (8.0 * math.pi * delta ** 6), 0.0
    if dim == 3:
        C1 = 30.0 * mu / (math.pi * delta ** 4)
        return C1, 0.0, 32.0 * (lam - mu) / (math.pi ** 4 * delta ** 12)
    raise CaseError(f"dimension must be 2 or 3, got {dim}")


def cpd_from_elastic(E: float, nu: float, delta: float, dim: int) -> tuple[float, float, float]:
    """(C1, C2, C3) for an isotropic material (E, nu) in the 3D / plane-strain sense.

    2D is plane strain: the plane Lame constants equal the 3D ones, so
    nu_2D = lambda / (lambda + 2 mu) = nu / (1 - nu).
    """
    if not E > 0:
        raise CaseError(f"E must be > 0, got {E:g}")
    if not -1.0 < nu < 0.5:
        raise CaseError(f"nu must be in (-1, 0.5), got {nu:g}")
    mu = E / (2.0 * (1.0 + nu))
    lam = E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    return cpd_from_lame(lam, mu, delta, dim)


def elastic_from_cpd(C1: float, C2: float, C3: float, delta: float, dim: int) -> tuple[float, float]:
    """(E, nu) in the 3D / plane-strain sense; inverse of :func:`cpd_from_elastic`."""
    lam, mu = lame_from_cpd(C1, C2, C3, delta, dim)
    nu = lam / (2.0 * (lam + mu))
    return 2.0 * mu * (1.0 + nu), nu


# ---------------------------------------------------------------------------
# lattice check and calibration
# ---------------------------------------------------------------------------
@dataclass
class LatticeRatios:
    """Discrete / continuum energy density of an interior point, per interaction type.

    ``pairs_dilatation`` (uniform expansion: the isotropic part of the pair sum),
    ``pairs_uniaxial`` (lambda + 2 mu), ``pairs_shear`` (mu); ``triples`` and
    ``quadruples`` depend on J only (a/A = v/V = det F), so one ratio each is exact.
    """

    pairs_dilatation: float
    pairs_uniaxial: float
    pairs_shear: float
    triples: float
    quadruples: float

    def factors(self) -> tuple[float, float, float]:
        """Multipliers of (C1, C2, C3) making the interior energy density match."""
        return 1.0 / self.pairs_dilatation, 1.0 / self.triples, 1.0 / self.quadruples


def _interior_energy_density(h: float, delta: float, dim: int, C: tuple, H: np.ndarray) -> float:
    """Energy density (per reference volume) of the central point of a grid patch under u = H X."""
    from .assembly import neighbour_lists
    from .kernels import assemble, horizon_radius2

    m = int(math.ceil(delta / h)) + 1
    ax = np.arange(-m, m + 1) * h
    X = np.stack(np.meshgrid(*([ax] * dim), indexing="ij"), axis=-1).reshape(-1, dim)
    X = X[np.linalg.norm(X, axis=1) <= delta * (1 + 1e-9)]
    center = int(np.argmin(np.linalg.norm(X, axis=1)))
    # every patch point is a central point (the kernels evaluate each tuple once at one
    # of its central vertices); the centre's own share is read from the per-point energy
    members = np.arange(len(X), dtype=np.int64)
    nptr, nidx = neighbour_lists(X, members, delta)
    vol = np.full(len(X), h ** dim)
    u = X @ H.T
    f = np.zeros_like(X)
    e_node = np.zeros(len(X))
    Cs = [np.full(len(X), C[k], dtype=float) for k in range(3)]
    assemble(X, u, members, nptr, nidx, Cs[0], Cs[1], Cs[2], vol, False,
             np.zeros(1, np.int64), np.zeros(1, np.int64), np.zeros(0), f, e_node, horizon_radius2(delta))
    e = e_node[center]
    return e / h ** dim


@lru_cache(maxsize=32)
def lattice_ratios(h: float, delta: float, dim: int, strain: float = 1e-7) -> LatticeRatios:
    """Measure the discrete interior energy density against the continuum formulas.

    Uses the production kernel on one interior point with a full grid horizon under
    small uniform strains (the quadratic terms dominate; the relative error of the
    measurement is O(strain)).
    """
    e = strain
    I = np.eye(dim)
    dil = e * I
    uni = np.zeros((dim, dim))
    uni[0, 0] = e
    shear = np.zeros((dim, dim))
    shear[0, 1] = shear[1, 0] = e
    lam1, mu1 = lame_from_cpd(1.0, 0.0, 0.0, delta, dim)   # pairs only, C1 = 1

    def w_lin(lam, mu, eps):
        return 0.5 * lam * np.trace(eps) ** 2 + mu * np.sum(eps * eps)

    r_dil = _interior_energy_density(h, delta, dim, (1.0, 0.0, 0.0), dil) / w_lin(lam1, mu1, dil)
    r_uni = _interior_energy_density(h, delta, dim, (1.0, 0.0, 0.0), uni) / w_lin(lam1, mu1, uni)
    r_sh = _interior_energy_density(h, delta, dim, (1.0, 0.0, 0.0), shear) / w_lin(lam1, mu1, shear)
    if dim == 2:
        lam2 = lame_from_cpd(0.0, 1.0, 0.0, delta, 2)[0]
        r2 = _interior_energy_density(h, delta, 2, (0.0, 1.0, 0.0), dil) / w_lin(lam2, 0.0, dil)
        r3 = 1.0
    else:
        lam3 = lame_from_cpd(0.0, 0.0, 1.0, delta, 3)[0]
        r3 = _interior_energy_density(h, delta, 3, (0.0, 0.0, 1.0), dil) / w_lin(lam3, 0.0, dil)
        r2 = 1.0
    return LatticeRatios(r_dil, r_uni, r_sh, r2, r3)


def calibrate(C: tuple[float, float, float], h: float, delta: float, dim: int,
              calibration: str = "continuum") -> tuple[float, float, float]:
    """Constants used on the grid: ``"continuum"`` (003's, unchanged) or ``"lattice"``.

    ``"lattice"`` divides each constant by the measured lattice ratio so that the
    interior energy density under a uniform dilatation (pairs) and under any uniform
    strain (triples, quadruples) equals the continuum value exactly.
    """
    if calibration == "continuum":
        return tuple(float(c) for c in C)
    if calibration != "lattice":
        raise CaseError(f"calibration must be 'continuum' or 'lattice', got {calibration!r}")
    k = lattice_ratios(h, delta, dim).factors()
    return tuple(float(c) * f for c, f in zip(C, k))
