"""Double lap shear (DLS) specimen by generalized shear lag with an imperfect interface.

Source: 002 Sec 3.1 (Eq 40-42, 50, 51) and Appendix A (Eq A.1-A.10), with the
corrections of ERRATA items 3 and 4:

* A.3: the far-field stress in layer 1 is sigma_inf = E1 P / ((2 t1 E1 + t2 E2) W);
* A.9: the integral over the outer strip divides by E1, not E2.

Geometry (002 Fig 4): two outer strips (thickness t1, axial modulus E1, shear
modulus G1) bonded over a length ``l`` to a central strip (t2, E2, G2); width W.
The central strip is loaded by P at y = 0, the two outer strips by P/2 each at
y = l; outside the bond each loaded strip runs free over an arm length L.
By symmetry half the specimen is analysed: layer 1 = one outer strip (t1),
layer 2 = half of the central strip (t2/2).

Re-derivation (checked against the printed appendix, independent of it):
the interface shear traction on layer 1 is tau = -t1 d<s1>/dy (A.8) and, with a
linear shear profile through each layer (zero on the outer free surface and on
the mid-plane of the central strip) plus the interface slip tau/Dt,
<u2> - <u1> = tau R with R = t1/(3 G1) + t2/(6 G2) + 1/Dt. Differentiating
and using force balance t1 <s1> + (t2/2) <s2> = P/(2W) gives A.1 with beta of
A.4, beta^2 = (1/(t1 E1) + 2/(t2 E2)) / R. With <s1>(0) = 0 and
<s1>(l) = s0 = P/(2 t1 W) (A.5) the solution of A.2/A.6 is written here in the
overflow-free form

    <s1>(y) = s_inf + (s0 - s_inf) sinh(beta y)/sinh(beta l) - s_inf sinh(beta (l-y))/sinh(beta l).

The bonded-region deformation follows A.9 (with the E1 correction): the central
strip from y = 0 to l/2, the slip |tau(l/2)|/Dt at mid-bond, the outer strip
from l/2 to l. Evaluated in closed form (h = beta l / 2, m = l/2):

    P C = [m s2_inf - (2 t1/t2) I0] / E2 + [m s_inf + I1] / E1 + |tau(m)| / Dt
    I0 = ((s0 - s_inf) g1 - s_inf g2) / beta,   I1 = ((s0 - s_inf) g2 - s_inf g1) / beta
    g1 = (cosh h - 1)/sinh 2h,   g2 = (cosh 2h - cosh h)/sinh 2h,
    |tau(m)| = t1 beta s0 / (2 sinh h)   (A.10),   s2_inf = E2 P/((2 t1 E1 + t2 E2) W),

which equals Eq 40 exactly for identical strips (tested to 1e-10).
Option ``layer_shear=True`` adds the shear deformation of the strips to the
mid-bond jump, |tau(l/2)| (t1/(3 G1) + t2/(6 G2)), i.e. the jump between the
layer-*average* displacements implied by the same shear-lag model; the result
then no longer depends on where the bond is split. 002 uses the interface slip
only (the default); the two agree for long bonds (002 specimen: 1e-6 with a perfect
interface, 0.05 .. 0.22 % in stiffness for Dt = 1 .. 100) but
part for short well-bonded overlaps (+7 % at beta l = 4.6, +135 % at 1.4), where
the slip-only compliance misses the overlap's own shear compliance (docs/analytic.md).

Units: mm, N, MPa; Dt in MPa/mm; compliance in mm/N, stiffness in N/mm.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from interfaces.analytic._checks import CaseError, interface_stiffness, nonnegative, points, positive

__all__ = [
    "DoubleLapShear",
    "dls_compliance",
    "dls_stiffness",
    "dls_shear_stress",
    "dls_axial_stress",
    "dls_identical_beta",
    "dls_identical_compliance",
    "dls_identical_stiffness",
    "dls_beta_l_max",
    "dls_long_bond_stiffness",
]


def _sech(x: float) -> float:
    """1/cosh(x) without overflow for large x."""
    e = math.exp(-abs(x))
    return 2.0 * e / (1.0 + e * e)


def _csch(x: float) -> float:
    """1/sinh(x) for x > 0 without overflow for large x."""
    return 2.0 * math.exp(-x) / (-math.expm1(-2.0 * x))


def _sinh_ratio(x: np.ndarray, B: float) -> np.ndarray:
    """sinh(x)/sinh(B) for 0 <= x <= B, B > 0, overflow-free."""
    return np.exp(x - B) * (-np.expm1(-2.0 * x)) / (-math.expm1(-2.0 * B))


def _cosh_ratio(x: np.ndarray, B: float) -> np.ndarray:
    """cosh(x)/sinh(B) for 0 <= x <= B, B > 0, overflow-free."""
    return np.exp(x - B) * (1.0 + np.exp(-2.0 * x)) / (-math.expm1(-2.0 * B))


@dataclass(frozen=True)
class DoubleLapShear:
    """General two-material DLS shear-lag model (002 Appendix A, ERRATA 3 and 4).

    Parameters (mm, MPa, MPa/mm): ``t1, E1, G1`` one outer strip; ``t2, E2, G2``
    the central strip (full thickness); ``l`` bond length; ``W`` width; ``L``
    free arm length at each end (0 for the bonded region only); ``Dt``
    tangential interface parameter (``math.inf`` perfect, 0 debonded; negative
    values of a stiff interphase, 002 Eq 52, are accepted while
    t1/(3 G1) + t2/(6 G2) + 1/Dt > 0). ``G1``/``G2`` may be ``math.inf``
    (strips rigid in shear). ``layer_shear``: see the module docstring.
    """

    t1: float
    E1: float
    G1: float
    t2: float
    E2: float
    G2: float
    l: float
    W: float
    L: float = 0.0
    Dt: float = math.inf
    layer_shear: bool = False

    def __post_init__(self) -> None:
        set_ = lambda k, v: object.__setattr__(self, k, v)  # noqa: E731 (frozen dataclass)
        for name in ("t1", "E1", "t2", "E2", "l", "W"):
            set_(name, positive(name, getattr(self, name)))
        for name in ("G1", "G2"):
            set_(name, positive(name, getattr(self, name), allow_inf=True))
        set_("L", nonnegative("L", self.L))
        set_("Dt", interface_stiffness("Dt", self.Dt, allow_negative=True))
        if not isinstance(self.layer_shear, (bool, np.bool_)):
            raise CaseError(f"layer_shear must be True or False, got {self.layer_shear!r}")
        if self.Dt < 0.0:
            if self.strip_shear_compliance == 0.0:
                raise CaseError(f"Dt = {self.Dt:g} MPa/mm: a negative Dt needs strips of finite shear "
                                f"modulus (G1 = G2 = inf leaves no compliance to offset it); use Dt >= 0")
            limit = -1.0 / self.strip_shear_compliance
            if not self.Dt < limit:
                raise CaseError(
                    f"Dt = {self.Dt:g} MPa/mm is beyond the rigid-interphase limit: a negative Dt "
                    f"must satisfy Dt < -1/(t1/(3 G1) + t2/(6 G2)) = {limit:g} MPa/mm")

    # ---- shear-lag constants -------------------------------------------------
    @property
    def strip_shear_compliance(self) -> float:
        """t1/(3 G1) + t2/(6 G2) (mm/MPa), the strips' part of R in A.4."""
        return self.t1 / (3.0 * self.G1) + self.t2 / (6.0 * self.G2)

    @property
    def slip_compliance(self) -> float:
        """1/Dt (mm/MPa); 0 for a perfect interface, inf for a debonded one."""
        return math.inf if self.Dt == 0.0 else 1.0 / self.Dt

    @property
    def debonded(self) -> bool:
        """True when Dt = 0: no shear transfer, zero stiffness."""
        return self.Dt == 0.0

    @property
    def beta(self) -> float:
        """Optimal shear-lag parameter beta (1/mm), 002 Eq A.4."""
        if self.debonded:
            return 0.0
        R = self.strip_shear_compliance + self.slip_compliance
        if R == 0.0:  # rigid strips and perfect interface: no shear lag
            return math.inf
        return math.sqrt((1.0 / (self.t1 * self.E1) + 2.0 / (self.t2 * self.E2)) / R)

    @property
    def beta_l(self) -> float:
        """Dimensionless end-effect number beta*l (002 Sec 3.4)."""
        return self.beta * self.l

    def sigma_inf(self, P: float = 1.0) -> float:
        """Far-field axial stress in layer 1 (MPa), 002 Eq A.3 as corrected (ERRATA 3)."""
        return self.E1 * P / ((2.0 * self.t1 * self.E1 + self.t2 * self.E2) * self.W)

    def sigma0(self, P: float = 1.0) -> float:
        """Axial stress of the loaded outer strip at y = l (MPa), 002 Eq A.5."""
        return P / (2.0 * self.t1 * self.W)

    # ---- compliance and stiffness ------------------------------------------
    @property
    def compliance_long_bond(self) -> float:
        """C_inf = l / (W (2 t1 E1 + t2 E2)) (mm/N): the bond as a three-strip tensile bar (Eq 50)."""
        return self.l / (self.W * (2.0 * self.t1 * self.E1 + self.t2 * self.E2))

    @property
    def compliance(self) -> float:
        """Compliance of the bonded region (mm/N), 002 Eq A.9 (ERRATA 4); inf if Dt = 0."""
        if self.debonded:
            return math.inf
        beta = self.beta
        sinf, s0 = self.sigma_inf(), self.sigma0()
        ds = s0 - sinf
        m = 0.5 * self.l
        s2inf = self.E2 / ((2.0 * self.t1 * self.E1 + self.t2 * self.E2) * self.W)
        if math.isinf(beta):  # no shear lag: load transfer at the bond ends
            i0_excess = i1_excess = 0.0
            tau_mid = 0.0
        else:
            h = 0.5 * beta * self.l
            g1 = math.tanh(0.5 * h) * _sech(h) / 2.0      # (cosh h - 1)/sinh 2h
            g2 = math.tanh(h) - g1                        # (cosh 2h - cosh h)/sinh 2h
            i0_excess = (ds * g1 - sinf * g2) / beta      # int_0^m (s1 - s_inf) dy
            i1_excess = (ds * g2 - sinf * g1) / beta      # int_m^l (s1 - s_inf) dy
            tau_mid = self.t1 * beta * s0 * _csch(h) / 2.0  # |tau(l/2)|, Eq A.10
        central = (m * s2inf - 2.0 * self.t1 / self.t2 * i0_excess) / self.E2
        outer = (m * sinf + i1_excess) / self.E1
        jump = self.slip_compliance + (self.strip_shear_compliance if self.layer_shear else 0.0)
        slip = tau_mid * jump if tau_mid > 0.0 else 0.0
        return central + outer + slip

    @property
    def arm_compliance(self) -> float:
        """Compliance of the two free arms (mm/N): P in the central strip over L at one
        end, P/2 in each outer strip over L at the other (generalizes 3L/(2 t W E) of Eq 42)."""
        return self.L / self.W * (1.0 / (self.t2 * self.E2) + 1.0 / (2.0 * self.t1 * self.E1))

    @property
    def stiffness(self) -> float:
        """Specimen stiffness k = 1/(C + C_arms) (N/mm), generalized 002 Eq 42; 0 if Dt = 0."""
        C = self.compliance
        return 0.0 if math.isinf(C) else 1.0 / (C + self.arm_compliance)

    # ---- profiles along the bond -------------------------------------------
    def _profile_check(self, y) -> np.ndarray:
        if self.debonded:
            raise CaseError("Dt = 0 (debonded): the bonded strips carry no load, "
                            "no stress profile exists; use Dt > 0")
        if math.isinf(self.beta):
            raise CaseError("G1 = G2 = inf with a perfect interface has no shear-lag "
                            "profile (load transfer is concentrated at the bond ends)")
        return points("y", y, 0.0, self.l)

    def axial_stress(self, y, P: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
        """Average axial stresses (<s1>, <s2>) (MPa) at positions y in [0, l] (Eq A.2, A.7).

        <s2> is the stress in the central strip from t1 <s1> + (t2/2) <s2> = P/(2W).
        """
        y = self._profile_check(y)
        P = positive("P", P)
        B = self.beta_l
        sinf, s0 = self.sigma_inf(P), self.sigma0(P)
        s1 = sinf + (s0 - sinf) * _sinh_ratio(self.beta * y, B) \
            - sinf * _sinh_ratio(self.beta * (self.l - y), B)
        s2 = (P / self.W - 2.0 * self.t1 * s1) / self.t2
        return s1, s2

    def shear_stress(self, y, P: float = 1.0) -> np.ndarray:
        """Interface shear traction tau(y) = -t1 d<s1>/dy (MPa), 002 Eq A.8.

        tau is the traction exerted by the central strip on the outer strip in +y;
        with the specimen in tension it is negative all along the bond, and
        int_0^l tau dy = -P/(2W).
        """
        y = self._profile_check(y)
        P = positive("P", P)
        B = self.beta_l
        sinf, s0 = self.sigma_inf(P), self.sigma0(P)
        return -self.t1 * self.beta * ((s0 - sinf) * _cosh_ratio(self.beta * y, B)
                                       + sinf * _cosh_ratio(self.beta * (self.l - y), B))

    def interface_slip(self, y, P: float = 1.0) -> np.ndarray:
        """Tangential displacement jump [u] = u_central - u_outer = tau/Dt (mm); 0 if perfect."""
        tau = self.shear_stress(y, P)
        return tau * (0.0 if math.isinf(self.Dt) else 1.0 / self.Dt)


def dls_compliance(t1: float, E1: float, G1: float, t2: float, E2: float, G2: float,
                   l: float, W: float, Dt: float = math.inf, *, layer_shear: bool = False) -> float:
    """Bonded-region compliance C (mm/N) of the general DLS model, 002 Appendix A (A.9)."""
    return DoubleLapShear(t1, E1, G1, t2, E2, G2, l, W, 0.0, Dt, layer_shear).compliance


def dls_stiffness(t1: float, E1: float, G1: float, t2: float, E2: float, G2: float,
                  l: float, W: float, L: float, Dt: float = math.inf, *,
                  layer_shear: bool = False) -> float:
    """Specimen stiffness k (N/mm) including the arms, generalized 002 Eq 42."""
    return DoubleLapShear(t1, E1, G1, t2, E2, G2, l, W, L, Dt, layer_shear).stiffness


def dls_shear_stress(y, t1: float, E1: float, G1: float, t2: float, E2: float, G2: float,
                     l: float, W: float, Dt: float = math.inf, P: float = 1.0) -> np.ndarray:
    """Interface shear traction tau(y) (MPa) along the bond, 002 Eq A.8 (see DoubleLapShear)."""
    return DoubleLapShear(t1, E1, G1, t2, E2, G2, l, W, 0.0, Dt).shear_stress(y, P)


def dls_axial_stress(y, t1: float, E1: float, G1: float, t2: float, E2: float, G2: float,
                     l: float, W: float, Dt: float = math.inf,
                     P: float = 1.0) -> tuple[np.ndarray, np.ndarray]:
    """Average axial stresses (<s1> outer, <s2> central) (MPa), 002 Eq A.2, A.7."""
    return DoubleLapShear(t1, E1, G1, t2, E2, G2, l, W, 0.0, Dt).axial_stress(y, P)


# ---- identical strips: the printed closed form --------------------------------------
def _identical_args(t, E_yy, G_xy, Dt):
    return (positive("t", t), positive("E_yy", E_yy), positive("G_xy", G_xy),
            interface_stiffness("Dt", Dt))


def dls_identical_beta(t: float, E_yy: float, G_xy: float, Dt: float = math.inf) -> float:
    """beta = sqrt(6 G / (t^2 E (1 + 2 G/(t Dt)))) (1/mm), 002 Eq 41 (identical strips)."""
    t, E, G, Dt = _identical_args(t, E_yy, G_xy, Dt)
    if Dt == 0.0:
        return 0.0
    return math.sqrt(6.0 * G / (t * t * E * (1.0 + 2.0 * G / (t * Dt))))


def dls_identical_compliance(t: float, E_yy: float, G_xy: float, l: float, W: float,
                             Dt: float = math.inf) -> float:
    """Bonded-region compliance for identical strips (mm/N), 002 Eq 40 with beta of Eq 41:

    C/C_inf = 1 + (tanh(l beta/2) + 9 tanh(l beta/4))/(4 l beta)
                + 3 E t beta/(4 l Dt) csch(l beta/2),   C_inf = l/(3 t W E).
    Dt >= 0 here (the closed form as printed); inf if Dt = 0.
    """
    t, E, G, Dt = _identical_args(t, E_yy, G_xy, Dt)
    l, W = positive("l", l), positive("W", W)
    if Dt == 0.0:
        return math.inf
    beta = dls_identical_beta(t, E, G, Dt)
    bl = beta * l
    c_inf = l / (3.0 * t * W * E)
    slip = 0.0 if math.isinf(Dt) else 3.0 * E * t * beta / (4.0 * l * Dt) * _csch(bl / 2.0)
    return c_inf * (1.0 + (math.tanh(bl / 2.0) + 9.0 * math.tanh(bl / 4.0)) / (4.0 * bl) + slip)


def dls_identical_stiffness(t: float, E_yy: float, G_xy: float, l: float, W: float, L: float,
                            Dt: float = math.inf) -> float:
    """Specimen stiffness k = 1/(C + 3L/(2 t W E)) (N/mm), 002 Eq 42 (identical strips)."""
    C = dls_identical_compliance(t, E_yy, G_xy, l, W, Dt)
    L = nonnegative("L", L)
    return 0.0 if math.isinf(C) else 1.0 / (C + 3.0 * L / (2.0 * t * W * E_yy))


def dls_beta_l_max(t: float, E_yy: float, G_xy: float, l: float) -> float:
    """Perfect-interface beta*l = (l/t) sqrt(6 G/E), 002 Eq 51 (22.8 for the 002 wood strand)."""
    t, E, G = positive("t", t), positive("E_yy", E_yy), positive("G_xy", G_xy)
    return positive("l", l) / t * math.sqrt(6.0 * G / E)


def dls_long_bond_stiffness(t: float, E_yy: float, l: float, W: float) -> float:
    """Long-bond limit k -> 3 t W E/l (N/mm) of the bonded region, 002 Eq 50."""
    return 3.0 * positive("t", t) * positive("W", W) * positive("E_yy", E_yy) / positive("l", l)
