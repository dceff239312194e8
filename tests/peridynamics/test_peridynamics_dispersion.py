"""Plane waves on the CPD lattice (peridynamics/dispersion.py) against the kernels.

The wave stiffness D(q) is written from 003 Eq 7, 10 with numpy alone; the kernels'
exact gradient must give, at a lattice point whose whole neighbourhood (2 horizons) is
present, the force 2 D(q) a cos(q . X_p) for a small wave u = a cos(q . X). This checks the
kernels' tangent at finite wavelengths, where the uniform-strain patch tests see nothing.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

from peridynamics.assembly import CPDSystem, MaterialBlock, neighbour_lists
from peridynamics.dispersion import lattice_horizon, softest_wave, wave_stiffness
from peridynamics.parameters import cpd_from_elastic, lattice_ratios


def _kernel_force(C, h, delta, q, a, eps=1e-7):
    """Force on the centre of a lattice cube (2 horizons + 1 spacing each side) under
    u = eps a cos(q . X), per unit eps."""
    dim = len(q)
    m = int(math.ceil(2 * delta / h)) + 1
    axes = [np.arange(-m, m + 1) * h] * dim
    X = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, dim)
    centre = int(np.argmin(np.linalg.norm(X, axis=1)))
    members = np.arange(len(X), dtype=np.int64)
    nptr, nidx = neighbour_lists(X, members, delta)
    system = CPDSystem(X, np.full(len(X), h ** dim), [MaterialBlock("m", members, nptr, nidx,
                                                                    np.asarray(C, float))], delta)
    u = eps * np.outer(np.cos(X @ q), a)
    return system.evaluate(u, False).residual[centre] / eps


@pytest.mark.parametrize("dim,C", [(2, (1.3, 0.0, 0.0)), (2, (1.3, 0.7, 0.0)), (2, (1.0, -0.4, 0.0)),
                                   (3, (1.3, 0.0, 0.0)), (3, (1.3, 0.6, 0.0)), (3, (1.0, 0.0, -0.5)),
                                   (3, (1.0, 0.3, 0.8))])
def test_kernel_force_of_a_plane_wave_equals_the_wave_stiffness(dim, C):
    h, delta = 1.0, 2.01
    rng = np.random.default_rng(dim * 10 + int(10 * C[1]))
    for q in (np.array([0.7, 0.0, 0.0][:dim]), rng.uniform(-math.pi, math.pi, dim)):
        a = rng.standard_normal(dim)
        expected = 2.0 * wave_stiffness(q, C, h, delta) @ a
        got = _kernel_force(C, h, delta, q, a)
        assert np.linalg.norm(got - expected) < 2e-8 * np.linalg.norm(expected)   # measured <= 5e-9


def test_long_waves_give_the_kernels_lattice_moduli():
    """q -> 0: D / (V_p q^2 / 2) = the moduli of a uniform strain, which
    lattice_ratios measures on the kernels (3D, delta = 3.01 h, 003 Sec 4.5 spacing)."""
    h, delta = 0.035, 3.01 * 0.035
    C1 = 1.0
    mu = math.pi * C1 * delta ** 4 / 30.0                  # ERRATA 12, pairs alone: lambda = mu
    ratios = lattice_ratios(h, delta, 3)
    q = 1e-3 / h
    D = wave_stiffness(np.array([q, 0.0, 0.0]), (C1, 0.0, 0.0), h, delta) / (h ** 3 * q * q / 2)
    assert D[1, 1] / mu == pytest.approx(ratios.pairs_shear, rel=1e-5)
    assert D[0, 0] / (3 * mu) == pytest.approx(ratios.pairs_uniaxial, rel=1e-5)
    assert len(lattice_horizon(h, delta, 3)) == 122


def test_material_a_of_the_003_cuboid_has_waves_of_negative_energy():
    """003 Sec 4.5: nu_A = 0.1 gives C3^A = -1.7e6 (delta = 0.105); on the lattice it runs on
    the wave q = (1, 1, 0) pi / 3h stores negative energy (docs/cpd_stability.md), material
    B (nu = 0.4) and A with nu = 0.25 (C3 = 0) do not."""
    h, delta = 0.035, 3.01 * 0.035
    q = np.array([1.0, 1.0, 0.0]) * math.pi / (3 * h)
    mu = math.pi * delta ** 4 / 30.0

    def lowest(C1, nu):
        C = cpd_from_elastic(2 * C1 * mu * (1 + nu), nu, delta, 3)
        return np.linalg.eigvalsh(wave_stiffness(q, C, h, delta))[0]

    assert cpd_from_elastic(2 * mu * 1.1, 0.1, delta, 3)[2] == pytest.approx(-1.7e6, rel=0.01)
    assert lowest(1.0, 0.1) < 0.0 < lowest(1.0, 0.25)
    assert lowest(20.0, 0.4) > 0.0


def test_softest_wave_scans_the_zone():
    """2D, pairs only (plane bond-based material): stable, margin > 0; a strongly negative
    C2 (below the plane Poisson bound) turns it negative."""
    margin, _ = softest_wave((1.0, 0.0, 0.0), 1.0, 3.01, 2, samples=4)
    assert margin > 0.0
    margin, q = softest_wave((1.0, -0.05, 0.0), 1.0, 3.01, 2, samples=4)
    assert margin < 0.0 and q[0] > 0.0


def test_the_solver_names_the_unstable_material_of_the_cuboid():
    """The 003 cuboid's material A (nu = 0.1) is reported with its wavelength; B is not."""
    from peridynamics.dispersion import unstable_materials
    h, delta = 0.035, 3.01 * 0.035
    mu = math.pi * delta ** 4 / 30.0
    used = {}
    for name, C1, nu in (("A", 1.0, 0.1), ("B", 20.0, 0.4)):
        C = cpd_from_elastic(2 * C1 * mu * (1 + nu), nu, delta, 3)
        used[name] = {"C1": C[0], "C2": C[1], "C3": C[2]}
    msgs = unstable_materials(used, h, delta, 3)
    assert len(msgs) == 1 and "body A" in msgs[0] and "wavelength 0.148 mm" in msgs[0]
    assert len(unstable_materials({"P": {"C1": 1.0, "C2": -0.05, "C3": 0.0}}, 1.0, 3.01, 2)) == 1
