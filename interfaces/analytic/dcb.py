"""Double cantilever beam (DCB) on an elastic foundation with an imperfect interface.

Source: 002 Sec 3.2, Eq 46-47 and Appendix B (B.1-B.6); ERRATA item 5 (Eq 46-47
are consistent with Appendix B).

Each arm (depth h, width W, axial modulus E_xx, I = W h^3/12) carries the load P
at x = -a (crack length a, crack tip at x = 0). In the bonded region x >= 0 the
arm rests on a foundation of two springs in series (B.2): the interface, whose
opening is twice the arm deflection (stiffness 2 W Dn per unit length), and the
effective stiffness kb of the other arm (shear and root rotation, [17, 18]):

    1/k1 = 1/(2 W Dn) + 1/kb,        Delta^4 = 4 E I / k1 = (W E h^3/3) (1/(2 W Dn) + 1/kb)   (Eq 47)

The load-point compliance (both arms, 2 v(-a)/P) is Eq 46,

    C/C0 = 1 + 3 (Delta/a) + 3 (Delta/a)^2 + (3/2) (Delta/a)^3,     C0 = 8 a^3/(W E h^3).

Dn = inf and kb = inf give Delta = 0 and C = C0 (clamped arms). Dn = 0 leaves the
arms unconnected (C = inf, k = 0). A negative Dn (stiff interphase, 002 Eq 52)
is accepted while 1/(2 W Dn) + 1/kb >= 0.

Units: mm, N, MPa; Dn in MPa/mm; kb in MPa (N/mm per mm of length).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from interfaces.analytic._checks import CaseError, interface_stiffness, points, positive

__all__ = ["DoubleCantileverBeam", "dcb_compliance", "dcb_stiffness", "dcb_deflection",
           "dcb_kb_from_stiffness"]


@dataclass(frozen=True)
class DoubleCantileverBeam:
    """DCB beam-on-elastic-foundation model, 002 Eq 46-47 and Appendix B.

    ``a`` crack length, ``h`` arm depth, ``W`` width (mm); ``E_xx`` axial modulus
    of the arms (MPa); ``Dn`` normal interface parameter (MPa/mm, inf = perfect);
    ``kb`` foundation stiffness of the other arm (MPa, inf = rigid foundation).
    """

    a: float
    h: float
    W: float
    E_xx: float
    Dn: float = math.inf
    kb: float = math.inf

    def __post_init__(self) -> None:
        set_ = lambda k, v: object.__setattr__(self, k, v)  # noqa: E731 (frozen dataclass)
        for name in ("a", "h", "W", "E_xx"):
            set_(name, positive(name, getattr(self, name)))
        set_("Dn", interface_stiffness("Dn", self.Dn, allow_negative=True))
        set_("kb", positive("kb", self.kb, allow_inf=True))
        if self.foundation_compliance < 0.0 and math.isinf(self.kb):
            raise CaseError(f"Dn = {self.Dn:g} MPa/mm: a negative Dn needs a finite foundation "
                            f"stiffness kb to offset it (kb = inf); use Dn >= 0 or give kb")
        if self.foundation_compliance < 0.0:
            raise CaseError(
                f"Dn = {self.Dn:g} MPa/mm is beyond the rigid-interphase limit: a negative Dn "
                f"must satisfy 1/(2 W Dn) + 1/kb >= 0, i.e. Dn <= {-self.kb / (2 * self.W):g} MPa/mm")

    @property
    def I(self) -> float:  # noqa: E743 (the paper's symbol)
        """Second moment of area of one arm, W h^3/12 (mm^4)."""
        return self.W * self.h ** 3 / 12.0

    @property
    def foundation_compliance(self) -> float:
        """1/k1 = 1/(2 W Dn) + 1/kb (1/MPa), 002 Eq B.2; inf if Dn = 0."""
        if self.Dn == 0.0:
            return math.inf
        inv_n = 0.0 if math.isinf(self.Dn) else 1.0 / (2.0 * self.W * self.Dn)
        inv_b = 0.0 if math.isinf(self.kb) else 1.0 / self.kb
        return inv_n + inv_b

    @property
    def Delta(self) -> float:
        """Foundation length scale Delta (mm), 002 Eq 47; 0 for Dn = kb = inf, inf for Dn = 0."""
        return (self.W * self.E_xx * self.h ** 3 / 3.0 * self.foundation_compliance) ** 0.25

    @property
    def C0(self) -> float:
        """Simple-beam-theory compliance 8 a^3/(W E h^3) (mm/N), 002 Eq 46."""
        return 8.0 * self.a ** 3 / (self.W * self.E_xx * self.h ** 3)

    @property
    def compliance(self) -> float:
        """Load-point compliance (mm/N), 002 Eq 46; inf if Dn = 0."""
        x = self.Delta / self.a
        if math.isinf(x):
            return math.inf
        return self.C0 * (1.0 + 3.0 * x + 3.0 * x * x + 1.5 * x ** 3)

    @property
    def stiffness(self) -> float:
        """Load-point stiffness 1/C (N/mm); 0 if Dn = 0."""
        C = self.compliance
        return 0.0 if math.isinf(C) else 1.0 / C

    def deflection(self, x, P: float = 1.0) -> np.ndarray:
        """Deflection v(x) of the upper arm (mm) for x >= -a, 002 Eq B.3 (x >= 0) and B.6 (x <= 0).

        The opening of the specimen is 2 v(x); 2 v(-a) = C P.
        """
        if self.Dn == 0.0:
            raise CaseError("Dn = 0 (debonded): the arms are not connected and have no "
                            "equilibrium deflection; use Dn > 0")
        x = points("x", x, -self.a, math.inf)
        shape = x.shape
        x = np.atleast_1d(x)
        P = positive("P", P)
        a, D, EI = self.a, self.Delta, self.E_xx * self.I
        v = np.empty_like(x)
        free = x <= 0.0
        xf = x[free]
        v[free] = P / (6.0 * EI) * (xf ** 3 + 3.0 * a * (xf - D) ** 2 - 3.0 * xf * D * D + 3.0 * D ** 3)
        xb = x[~free]
        if D == 0.0:
            v[~free] = 0.0
        else:
            s = xb / D
            v[~free] = P * D * D / (2.0 * EI) * ((a + D) * np.cos(s) - a * np.sin(s)) * np.exp(-s)
        return v.reshape(shape)


def dcb_compliance(a: float, h: float, W: float, E_xx: float, Dn: float = math.inf,
                   kb: float = math.inf) -> float:
    """Load-point compliance C (mm/N) of a DCB specimen, 002 Eq 46-47."""
    return DoubleCantileverBeam(a, h, W, E_xx, Dn, kb).compliance


def dcb_stiffness(a: float, h: float, W: float, E_xx: float, Dn: float = math.inf,
                  kb: float = math.inf) -> float:
    """Load-point stiffness k = 1/C (N/mm) of a DCB specimen, 002 Eq 46-47."""
    return DoubleCantileverBeam(a, h, W, E_xx, Dn, kb).stiffness


def dcb_deflection(x, a: float, h: float, W: float, E_xx: float, Dn: float = math.inf,
                   kb: float = math.inf, P: float = 1.0) -> np.ndarray:
    """Upper-arm deflection v(x) (mm), 002 Eq B.3 and B.6 (crack tip at x = 0, load at x = -a)."""
    return DoubleCantileverBeam(a, h, W, E_xx, Dn, kb).deflection(x, P)


def dcb_kb_from_stiffness(k_perfect: float, a: float, h: float, W: float, E_xx: float) -> float:
    """Foundation stiffness kb (MPa) reproducing a perfect-interface stiffness (Dn = inf).

    Inverts 002 Eq 46 for x = Delta/a (1 + 3x + 3x^2 + 1.5x^3 = (1+x)^3 + x^3/2 = C/C0
    has exactly one positive root when C > C0) and Eq 47 with 1/Dn = 0:
    kb = W E h^3 / (3 Delta^4). 002 obtained kb = 7808 MPa from a perfect-interface FEA.
    """
    k = positive("k_perfect", k_perfect)
    model = DoubleCantileverBeam(a, h, W, E_xx)
    ratio = 1.0 / (k * model.C0)
    if not ratio > 1.0:
        raise CaseError(f"k_perfect = {k:g} N/mm must be < 1/C0 = {1.0 / model.C0:g} N/mm "
                        f"(the simple-beam stiffness 8 a^3/(W E h^3) inverted): a finite kb "
                        f"always lowers the stiffness")
    # (1 + x)^3 + x^3/2 = C/C0 is increasing for x >= 0: the root lies in [0, (C/C0)^(1/3) - 1]
    f = lambda x: (1.0 + x) ** 3 + 0.5 * x ** 3 - ratio  # noqa: E731
    x = brentq(f, 0.0, ratio ** (1.0 / 3.0) - 1.0, xtol=1e-300, rtol=4.0 * np.finfo(float).eps)
    delta = x * model.a
    return model.W * model.E_xx * model.h ** 3 / (3.0 * delta ** 4)
