"""Shock Hugoniot of a Mie-Grueneisen solid (004 Sec 4.3, Eq 51): the jump conditions.

A steady plane shock moving at U_s into material at rest (density rho0, zero stress and
energy) leaves it at particle speed u_p. Mass, momentum and energy across the front
(Rankine-Hugoniot) give

    J = rho0 / rho = 1 - u_p / U_s,    sigma = rho0 U_s u_p,    U = u_p^2 / 2,

with sigma the longitudinal compressive stress behind the front and U the specific
internal energy (per unit mass, all of it: an explicit code integrating sigma : D / rho
tracks the same total). The material closes the system: sigma = p(J, U) + 2 Y / 3, with
p of 004 Eq 51 (``interfaces.materials.MieGruneisen.pressure``, compression branch) and
an elastic-perfectly-plastic deviatoric part at yield stress Y (uniaxial strain past the
elastic limit; Y = 0 is the hydrodynamic Hugoniot), or the elastic neo-Hookean shear term
of 004 Eq 18 that 004 keeps beside Eq 51 (shear modulus G): in uniaxial strain,
F = diag(J, 1, 1), its deviatoric stress adds (2/3) G J^(-5/3) (1 - J^2) to sigma, and its
work, the isochoric energy, is part of U. For Y = G = 0 the Mie-Grueneisen form
built on the linear U_s-u_p fit gives back that fit exactly, U_s = C0 + S1 u_p with
C0 = sqrt(K / rho0); the root finder is checked against it.

An impact of a bar on a rigid wall at speed v drives u_p = v; a symmetric impact of two
identical bars, u_p = v / 2.
Units: mm, MPa, s, tonne/mm^3 (speeds in mm/s; 1 m/s = 1e3 mm/s).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from interfaces.analytic._checks import CaseError, nonnegative, positive
from interfaces.materials import MieGruneisen

__all__ = ["ShockHugoniot", "ShockState"]


@dataclass(frozen=True)
class ShockState:
    """The state behind a steady shock: particle speed u_p and shock speed U_s (mm/s),
    volume ratio J, pressure p and longitudinal compressive stress sigma (MPa), specific
    internal energy U (mm^2/s^2 = N mm / tonne)."""

    particle_speed: float
    shock_speed: float
    volume_ratio: float
    pressure: float
    longitudinal_stress: float
    specific_internal_energy: float


@dataclass(frozen=True)
class ShockHugoniot:
    """Mie-Grueneisen solid of 004 Eq 51: bulk modulus K (MPa), rho0, S1, gamma0, and its
    deviatoric part: an elastic-perfectly-plastic one of yield stress Y, or the elastic
    neo-Hookean term of 004 Eq 18 of shear modulus G (MPa); both 0: hydrodynamic."""

    K: float
    rho: float
    S1: float
    gamma0: float
    Y: float = 0.0
    G: float = 0.0

    def __post_init__(self):
        positive("K", self.K)
        positive("rho", self.rho)
        nonnegative("S1", self.S1)
        nonnegative("gamma0", self.gamma0)
        nonnegative("Y", self.Y)
        nonnegative("G", self.G)
        if self.Y > 0.0 and self.G > 0.0:
            raise CaseError("ShockHugoniot: give either the yield stress Y (perfectly plastic "
                            "deviatoric part) or the shear modulus G (elastic neo-Hookean), not both")

    def deviatoric(self, J: float) -> float:
        """The deviatoric part of the longitudinal compressive stress at volume ratio J."""
        return 2.0 * self.Y / 3.0 + 2.0 * self.G / 3.0 * J ** (-5.0 / 3.0) * (1.0 - J * J)

    @property
    def bulk_wave_speed(self) -> float:
        """C0 = sqrt(K / rho0) (mm/s)."""
        return math.sqrt(self.K / self.rho)

    def _eos(self) -> MieGruneisen:
        return MieGruneisen(C0=self.bulk_wave_speed, S1=self.S1, gamma0=self.gamma0, G=1.0, rho=self.rho)

    def state(self, particle_speed: float) -> ShockState:
        """The shocked state at particle speed u_p >= 0 (mm/s)."""
        up = nonnegative("particle_speed", particle_speed)
        if up == 0.0:   # the acoustic limit: bulk wave, or longitudinal with elastic shear
            c = math.sqrt((self.K + 4.0 * self.G / 3.0) / self.rho)
            return ShockState(0.0, c, 1.0, 0.0, 0.0, 0.0)
        eos, e = self._eos(), self.rho * 0.5 * up * up      # energy per unit reference volume

        def momentum(eta: float) -> float:
            """sigma(J, U) - rho0 U_s u_p at compression eta = 1 - J: zero on the Hugoniot."""
            return float(eos.pressure(1.0 - eta, e)) + self.deviatoric(1.0 - eta) - self.rho * up * up / eta

        # eta in (0, 1 / S1): momentum() rises from -inf (eta -> 0: U_s -> inf) to +inf
        # at the Eq 51 singularity eta -> 1 / S1 (or to its value at J -> 0 when S1 <= 1)
        eta_max = 1.0 / self.S1 if self.S1 > 1.0 else 1.0
        lo, hi = 1e-12 * min(1.0, up / self.bulk_wave_speed), eta_max * (1.0 - 1e-12)
        if not (momentum(lo) < 0.0 < momentum(hi)):
            raise CaseError(f"particle_speed {up:g} mm/s has no shocked state on this Mie-Grueneisen "
                            f"Hugoniot (gamma0 = {self.gamma0:g}, S1 = {self.S1:g}); lower it")
        eta = brentq(momentum, lo, hi, xtol=1e-16, rtol=1e-14, maxiter=200)
        J = 1.0 - eta
        Us = up / eta
        return ShockState(up, Us, J, float(eos.pressure(J, e)), self.rho * Us * up, 0.5 * up * up)

    def curve(self, particle_speeds) -> dict[str, np.ndarray]:
        """The Hugoniot over particle speeds: u_p, U_s, J, p, sigma, U arrays."""
        states = [self.state(u) for u in np.atleast_1d(np.asarray(particle_speeds, dtype=float))]
        return {"particle_speed": np.array([s.particle_speed for s in states]),
                "shock_speed": np.array([s.shock_speed for s in states]),
                "volume_ratio": np.array([s.volume_ratio for s in states]),
                "pressure": np.array([s.pressure for s in states]),
                "longitudinal_stress": np.array([s.longitudinal_stress for s in states]),
                "specific_internal_energy": np.array([s.specific_internal_energy for s in states])}
