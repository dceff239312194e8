"""The shared language of the toolkit: units, materials, interface laws, geometry, Case, Result.

Units everywhere: mm, N, MPa (N/mm^2), s, tonne/mm^3; interface stiffness Dn, Dt in MPa/mm.
"""
from .case import Body, BoundaryCondition, Case, InterfacePair
from .errors import CaseError, SolverError
from .geometry import Box, Circle, Ellipse, Polygon, Rectangle, Sphere
from .laws import BilinearNormalInterface, CoulombFriction, LinearInterface, StickContact
from .materials import IsotropicElastic, MieGruneisen, NeoHookean, TransverselyIsotropicElastic, isotropic_from_KG
from .result import Result

__all__ = [
    "Body", "BoundaryCondition", "Case", "InterfacePair", "CaseError", "SolverError",
    "Box", "Circle", "Ellipse", "Polygon", "Rectangle", "Sphere",
    "BilinearNormalInterface", "CoulombFriction", "LinearInterface", "StickContact",
    "IsotropicElastic", "MieGruneisen", "NeoHookean", "TransverselyIsotropicElastic", "isotropic_from_KG",
    "Result",
]
