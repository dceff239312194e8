"""Interface laws: linear imperfect interfaces, a bilinear normal law, and contact.

A linear imperfect interface transmits the traction T_n = Dn [u_n], T_t = Dt [u_t]
(002 Eq 1; 000 Eq 4) where [u] = u_b - u_a is the displacement jump, normal n pointing
from body a to body b. Dn, Dt are in MPa/mm: ``math.inf`` means perfect (no jump) in
that direction and 0 debonded (no traction). The energy per unit area is
1/2 (Dn [u_n]^2 + Dt [u_t]^2) (000 Eq 4, 18 with the 1/2 of ERRATA 10).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .errors import CaseError, build_tagged, check_number


class InterfaceLaw:
    """Base class of interface laws; ``to_dict`` gives the TOML table."""

    kind: ClassVar[str] = ""

    def to_dict(self) -> dict:
        d = {"type": self.kind}
        for k, v in self.__dict__.items():
            d[k] = "inf" if isinstance(v, float) and math.isinf(v) else v
        return d


def _stiffness(name: str, value, allow_negative: bool = False) -> float:
    return check_number(name, value, low=None if allow_negative else 0.0, allow_inf=True)


def _spring(D: float, jump):
    """Traction D * jump with D = inf meaning an undetermined (perfect) traction."""
    jump = np.asarray(jump, dtype=float)
    if math.isinf(D):
        if np.any(jump != 0):
            raise CaseError("a perfect (D = inf) direction cannot carry a non-zero jump; "
                            "its traction is a reaction found by the solver")
        return np.zeros_like(jump)
    return D * jump


def _energy(D: float, jump):
    jump = np.asarray(jump, dtype=float)
    if math.isinf(D):
        return np.zeros_like(jump) if not np.any(jump != 0) else np.full_like(jump, np.inf)
    return 0.5 * D * jump**2


@dataclass(frozen=True)
class LinearInterface(InterfaceLaw):
    """Linear imperfect interface (002 Eq 1): T_n = Dn [u_n], T_t = Dt [u_t], Dn, Dt in MPa/mm.

    ``math.inf`` = perfect in that direction, 0 = debonded. Negative values describe a
    stiff interphase (002 Eq 52); build those with :meth:`from_interphase`, which checks
    the rigid-interphase limit.
    """

    Dn: float
    Dt: float
    kind: ClassVar[str] = "linear"

    def __post_init__(self):
        neg = getattr(self, "_allow_negative", False)
        object.__setattr__(self, "Dn", _stiffness("Dn", self.Dn, neg))
        object.__setattr__(self, "Dt", _stiffness("Dt", self.Dt, neg))

    def to_dict(self) -> dict:
        d = {"type": self.kind, "Dn": _inf_str(self.Dn), "Dt": _inf_str(self.Dt)}
        return d

    @property
    def perfect_normal(self) -> bool:
        return math.isinf(self.Dn)

    @property
    def perfect_tangential(self) -> bool:
        return math.isinf(self.Dt)

    @property
    def perfect(self) -> bool:
        return self.perfect_normal and self.perfect_tangential

    def normal_stiffness(self, jump_n=0.0):
        """Dn (the same in tension and compression for the linear law)."""
        return np.full(np.shape(jump_n), self.Dn) if np.ndim(jump_n) else self.Dn

    def traction(self, jump_n, jump_t):
        """(T_n, T_t) in MPa for jumps in mm (002 Eq 1)."""
        return _spring(self.Dn, jump_n), _spring(self.Dt, jump_t)

    def energy_density(self, jump_n, jump_t):
        """Interface energy per unit area, 1/2 (Dn [u_n]^2 + Dt [u_t]^2) (N/mm)."""
        return _energy(self.Dn, jump_n) + _energy(self.Dt, jump_t)

    @classmethod
    def from_interphase(cls, t_i: float, E_i: float, G_i: float, E1: float, E2: float,
                        G1: float, G2: float) -> "LinearInterface":
        """Interface equivalent to an interphase of thickness t_i (002 Eq 52).

        1/Dn = t_i [1/E_i - (1/E1 + 1/E2)/2], 1/Dt = t_i [1/G_i - (1/G1 + 1/G2)/2].
        A stiffer interphase than the substrates gives negative D, allowed down to the
        rigid-interphase limit (E_i, G_i -> inf); non-positive interphase moduli are rejected.
        """
        from .analytic.interphase import interphase_to_interface  # the one implementation of Eq 52

        Dn, Dt = interphase_to_interface(t_i, E_i, G_i, E1, E2, G1, G2)
        obj = cls.__new__(cls)
        object.__setattr__(obj, "_allow_negative", True)
        object.__setattr__(obj, "Dn", Dn)
        object.__setattr__(obj, "Dt", Dt)
        return obj


@dataclass(frozen=True)
class BilinearNormalInterface(InterfaceLaw):
    """Imperfect interface whose normal stiffness differs in tension and compression (002 Sec 2.4).

    Dn_tension applies for an opening jump [u_n] > 0, Dn_compression (default inf:
    perfect, no interpenetration) for [u_n] <= 0; Dt tangential. MPa/mm.
    """

    Dn_tension: float
    Dt: float
    Dn_compression: float = math.inf
    kind: ClassVar[str] = "bilinear_normal"

    def __post_init__(self):
        for name in ("Dn_tension", "Dt", "Dn_compression"):
            object.__setattr__(self, name, _stiffness(name, getattr(self, name)))

    def to_dict(self) -> dict:
        return {"type": self.kind, "Dn_tension": _inf_str(self.Dn_tension), "Dt": _inf_str(self.Dt),
                "Dn_compression": _inf_str(self.Dn_compression)}

    def normal_stiffness(self, jump_n):
        """Dn of the active branch for the jump [u_n] (mm)."""
        j = np.asarray(jump_n, dtype=float)
        out = np.where(j > 0, self.Dn_tension, self.Dn_compression)
        return float(out) if out.ndim == 0 else out

    def traction(self, jump_n, jump_t):
        j = np.asarray(jump_n, dtype=float)
        tn = np.where(j > 0, _spring(self.Dn_tension, np.where(j > 0, j, 0.0)),
                      _spring(self.Dn_compression, np.where(j > 0, 0.0, j)))
        return tn, _spring(self.Dt, jump_t)

    def energy_density(self, jump_n, jump_t):
        j = np.asarray(jump_n, dtype=float)
        en = np.where(j > 0, _energy(self.Dn_tension, np.where(j > 0, j, 0.0)),
                      _energy(self.Dn_compression, np.where(j > 0, 0.0, j)))
        return en + _energy(self.Dt, jump_t)


@dataclass(frozen=True)
class StickContact(InterfaceLaw):
    """Contact that sticks when in contact and separates freely (004 Eq 7-10 with mu = inf)."""

    kind: ClassVar[str] = "stick"


@dataclass(frozen=True)
class CoulombFriction(InterfaceLaw):
    """Coulomb frictional contact with coefficient mu >= 0 (004 Eq 8-10; 000 Eq 16, ERRATA 7)."""

    mu: float
    kind: ClassVar[str] = "coulomb"

    def __post_init__(self):
        object.__setattr__(self, "mu", check_number("mu", self.mu, low=0))


_LAWS = {c.kind: c for c in (LinearInterface, BilinearNormalInterface, StickContact, CoulombFriction)}


def _inf_str(v: float):
    return "inf" if math.isinf(v) else v


def law_from_dict(d: dict, where: str = "law") -> InterfaceLaw:
    """Build an interface law from its TOML table (``"inf"`` strings mean math.inf).

    Negative Dn, Dt of a linear law (a stiff interphase, 002 Eq 52) are accepted here
    since a case file stores the values :meth:`LinearInterface.from_interphase` produced.
    """
    def make(cls, kwargs):
        if cls is LinearInterface and any(_is_negative(v) for v in kwargs.values()):
            obj = cls.__new__(cls)
            object.__setattr__(obj, "_allow_negative", True)
            obj.__init__(**kwargs)
            return obj
        return cls(**kwargs)

    return build_tagged(_LAWS, d, where, make=make)


def _is_negative(v) -> bool:
    try:
        return float(v) < 0
    except (TypeError, ValueError):
        return False
