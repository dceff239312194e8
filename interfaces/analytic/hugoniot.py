"""Shock Hugoniot of a material with the linear shock-speed relation Us = C0 + S1 up
(the reference of the shock-bar case of 004 Sec 4.3, Fig 7).

For a piston (impact) driving particle speed ``up`` into material at rest with
density rho0, the Rankine-Hugoniot jump conditions give

* shock speed Us = C0 + S1 up;
* pressure behind the shock p = rho0 Us up (momentum);
* volume ratio J = V / V0 = 1 - up / Us, i.e. compression eta = 1 - J = up / Us (mass);
* specific internal energy jump U = up^2 / 2 = p eta / (2 rho0) (energy).

Along the Hugoniot p = rho0 C0^2 eta / (1 - S1 eta)^2, which is the Mie-Grueneisen
pressure of 004 Eq 51 (``interfaces.materials.MieGruneisen.pressure``) with the energy of
the jump: K eta (1 - gamma0 eta / 2) / (1 - S1 eta)^2 + rho0 gamma0 U, K = rho0 C0^2. For
a symmetric impact at speed v the particle speed is up = v / 2; a bar struck by a
rigid wall moving at v (004 Fig 7: impact on the right, walls on the other sides) has
up = v. Units: mm/s, tonne/mm^3, MPa; U in mm^2/s^2 (N mm per tonne).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from interfaces.errors import CaseError, check_number


@dataclass(frozen=True)
class HugoniotState:
    """The shocked state for particle speeds ``up`` (arrays)."""

    up: np.ndarray        # particle speed behind the shock (mm/s)
    Us: np.ndarray        # shock speed (mm/s)
    pressure: np.ndarray  # MPa
    J: np.ndarray         # V / V0 behind the shock
    energy: np.ndarray    # specific internal energy jump U (mm^2/s^2)


def hugoniot(rho0: float, C0: float, S1: float, up) -> HugoniotState:
    """Shocked state behind a steady shock driven at particle speed ``up`` (>= 0)."""
    rho0 = check_number("rho0", rho0, low=0, low_open=True)
    C0 = check_number("C0", C0, low=0, low_open=True)
    S1 = check_number("S1", S1, low=0)
    u = np.atleast_1d(np.asarray(up, dtype=float))
    if not np.all(np.isfinite(u)) or np.any(u < 0.0):
        raise CaseError(f"up must be finite and >= 0 (mm/s), got {up!r}")
    Us = C0 + S1 * u
    return HugoniotState(u, Us, rho0 * Us * u, 1.0 - u / Us, 0.5 * u * u)


def hugoniot_pressure_of_compression(rho0: float, C0: float, S1: float, eta) -> np.ndarray:
    """p_H(eta) = rho0 C0^2 eta / (1 - S1 eta)^2 for compressions 0 <= eta < 1 / S1."""
    eta = np.asarray(eta, dtype=float)
    if np.any(eta < 0.0) or np.any(S1 * eta >= 1.0):
        raise CaseError(f"eta must lie in [0, 1/S1) = [0, {1.0 / S1 if S1 else np.inf:g}), got {eta!r}")
    return rho0 * C0 * C0 * eta / (1.0 - S1 * eta) ** 2
