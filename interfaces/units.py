"""The one unit system of the project.

Lengths in mm, forces in N, stresses and moduli in MPa (N/mm^2), time in s,
density in tonne/mm^3 (1 g/cm^3 = 1e-9 t/mm^3), energy in N mm (= mJ),
interface stiffness Dn, Dt in MPa/mm, stiffness of a specimen in N/mm.
"""
from __future__ import annotations

MM = 1.0
N = 1.0
MPA = 1.0
GPA = 1.0e3
S = 1.0
MS = 1.0e-3
US = 1.0e-6
G_PER_CM3 = 1.0e-9
"""1 g/cm^3 expressed in tonne/mm^3."""
M_PER_S = 1.0e3
"""1 m/s expressed in mm/s."""


def density_from_g_cm3(rho_g_cm3: float) -> float:
    """Convert a density in g/cm^3 to tonne/mm^3."""
    return rho_g_cm3 * G_PER_CM3
