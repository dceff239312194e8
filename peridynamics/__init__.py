"""Continuum-kinematics-inspired peridynamics (CPD), implicit, with the kinematically
coupled overlap interface of 003 (Laurien, Javili, Steinmann 2022).

Public surface: :func:`solve` (Case -> Result) and the parameter conversions in
:mod:`peridynamics.parameters`. Units: mm, N, MPa.
"""
from .parameters import (calibrate, cpd_from_elastic, cpd_from_lame, elastic_from_cpd, lame_from_cpd,
                         lattice_ratios, nu2d_from_nu3d, nu3d_from_nu2d, poisson_2d)
from .solver import solve

__all__ = ["solve", "calibrate", "cpd_from_elastic", "cpd_from_lame", "elastic_from_cpd", "lame_from_cpd",
           "lattice_ratios", "nu2d_from_nu3d", "nu3d_from_nu2d", "poisson_2d"]
