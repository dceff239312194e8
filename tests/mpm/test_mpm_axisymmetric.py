"""Axisymmetric MPM (000 Sec 2.3; mpm/axisymmetric.py) against closed forms and limits.

x = r, y = z, per radian inside the run, whole-ring quantities in the Result.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import mpm
from interfaces import (Body, BoundaryCondition, Case, CaseError, InterfacePair, IsotropicElastic,
                        LinearInterface, Rectangle)

E, NU = 1000.0, 0.3
MAT = IsotropicElastic(E=E, nu=NU, rho=1e-9)


def _case(bodies, bcs, interfaces=(), cell=0.25, **mpm_opts) -> Case:
    return Case(name="axi", analysis="axisymmetric", thickness=1.0, materials={"m": MAT},
                bodies=bodies, interfaces=list(interfaces), boundary_conditions=bcs,
                discretization={"mpm": dict({"cell": cell, "grid_anchor": "origin"}, **mpm_opts)})


def _rod(R=2.0, L=8.0, t=1.0) -> Case:
    """Solid rod r < R, 0 < z < L on a roller base, axial traction t on its top."""
    return _case([Body("rod", Rectangle(0.0, 0.0, R, L), "m")],
                 [BoundaryCondition("fixed", "rod", "ymin", ("y",), (0.0,)),
                  BoundaryCondition("traction", "rod", "ymax", ("y",), (t,))])


def test_solid_rod_in_uniaxial_tension_matches_the_closed_form():
    """u_r = -nu t r / E (the hoop strain couples r and z through nu), u_z = t z / E and
    U = t^2 / 2E x pi R^2 L for the whole ring; the particles next to the axis (r = h/4)
    carry the hoop term sigma_tt / r_p without trouble. Measured at h = R / 8:
    u_r 0.048 %, u_z 0.11 %, U 0.12 % (damped run stopped at the kinetic-energy tolerance)."""
    R, L, t = 2.0, 8.0, 1.0
    res = mpm.solve(_rod(R, L, t), progress=False)
    x, u, s = (np.asarray(res.fields[k]) for k in ("position", "displacement", "stress"))
    ur_ratio = u[:, 0] / (-NU * t * x[:, 0] / E)
    assert np.abs(ur_ratio - 1.0).max() < 2e-3
    assert np.median(u[:, 1] / (t * x[:, 1] / E)) == pytest.approx(1.0, abs=4e-3)
    assert res.quantities["strain_energy"] == pytest.approx(
        0.5 * t * t / E * math.pi * R * R * L, rel=5e-3)
    # the energy history is the whole ring's too (the run itself is per radian)
    assert res.diagnostics["history"]["strain"][-1] == pytest.approx(
        res.quantities["strain_energy"], rel=1e-12)
    # no hoop or radial stress in uniaxial tension (sigma_tt is the 4th component)
    assert np.abs(s[:, 3]).max() < 2e-3 * t and np.abs(s[:, 0]).max() < 4e-3 * t


def test_thick_tube_under_internal_pressure_matches_lame():
    """Open-ended thick tube a < r < b under internal pressure p (sigma_z = 0, so the
    plane-stress Lame solution is exact): u_r = p a^2 / (E (b^2 - a^2)) ((1 - nu) r +
    (1 + nu) b^2 / r) and u_z = -2 nu p a^2 / (E (b^2 - a^2)) z. This one is governed by the
    hoop stress. Measured at h = 0.125 (8 cells through the wall): max error 0.22 % (u_r)
    and 0.35 % (u_z) of u_r(a)."""
    a, b, L, p = 1.0, 2.0, 1.0, 1.0
    case = _case([Body("tube", Rectangle(a, 0.0, b - a, L), "m")],
                 [BoundaryCondition("fixed", "tube", "ymin", ("y",), (0.0,)),
                  BoundaryCondition("traction", "tube", "xmin", ("x",), (p,))], cell=0.125)
    res = mpm.solve(case, progress=False)
    x, u = np.asarray(res.fields["position"]), np.asarray(res.fields["displacement"])
    r = x[:, 0]
    exact = p * a * a / (E * (b * b - a * a)) * ((1 - NU) * r + (1 + NU) * b * b / r)
    ua = p * a * a / (E * (b * b - a * a)) * ((1 - NU) * a + (1 + NU) * b * b / a)
    assert np.abs(u[:, 0] - exact).max() < 8e-3 * ua
    uz = -2.0 * NU * p * a * a / (E * (b * b - a * a)) * x[:, 1]
    assert np.abs(u[:, 1] - uz).max() < 1.2e-2 * ua


def test_stacked_rods_with_an_imperfect_interface_open_by_t_over_dn():
    """Two rods stacked along the axis, joined by an imperfect interface of normal
    stiffness Dn across z = L: uniaxial tension t opens it by t / Dn everywhere, from
    the axis (where the radial normal component is zeroed, 000 Sec 2.5) to the rim;
    the interfacial energy is t^2 / (2 Dn) pi R^2 (whole ring). The load keeps the
    opening at 0.4 % of a cell: the contact area of 000 Eq 20 is evaluated on the
    current particle positions, so an opening of 9 % of a cell (t = 1 here) lowers it
    by 15 % (plane stress alike: MPM's geometric nonlinearity, not the axisymmetry).
    Measured: top displacement -0.23 %, energy +0.22 %."""
    R, L, t, Dn = 2.0, 4.0, 0.05, 50.0
    bodies = [Body("lower", Rectangle(0.0, 0.0, R, L), "m"),
              Body("upper", Rectangle(0.0, L, R, L), "m")]
    case = _case(bodies, [BoundaryCondition("fixed", "lower", "ymin", ("y",), (0.0,)),
                          BoundaryCondition("traction", "upper", "ymax", ("y",), (t,))],
                 [InterfacePair("lower", "upper", LinearInterface(Dn=Dn, Dt=math.inf))],
                 normal="AVG")
    res = mpm.solve(case, progress=False)
    x, u = np.asarray(res.fields["position"]), np.asarray(res.fields["displacement"])
    mat = np.asarray(res.fields["material"])
    # top displacement: t (2L) / E + t / Dn
    top = x[:, 1] > 2 * L - 0.25
    assert np.mean(u[top, 1]) == pytest.approx(t * 2 * L / E + t / Dn, rel=1e-2)
    near = np.abs(x[:, 1] - L) < 0.2
    jump = np.mean(u[near & (mat == 1), 1]) - np.mean(u[near & (mat == 0), 1])
    assert jump == pytest.approx(t / Dn + t * 0.25 / E, rel=1e-2)
    assert res.quantities["interface_energy"] == pytest.approx(
        t * t / (2 * Dn) * math.pi * R * R, rel=1e-2)


def test_rod_split_by_a_perfect_interface_equals_the_uncut_rod():
    """A perfect interface on a grid line at r = 1 (momentum-corrected bond): the split
    rod moves as the uncut one, to round-off."""
    R, L = 2.0, 4.0
    bcs = [BoundaryCondition("fixed", "core", "ymin", ("y",), (0.0,)),
           BoundaryCondition("fixed", "shell", "ymin", ("y",), (0.0,)),
           BoundaryCondition("traction", "core", "ymax", ("y",), (1.0,)),
           BoundaryCondition("traction", "shell", "ymax", ("y",), (1.0,))]
    split = _case([Body("core", Rectangle(0.0, 0.0, 1.0, L), "m"),
                   Body("shell", Rectangle(1.0, 0.0, R - 1.0, L), "m")], bcs,
                  [InterfacePair("core", "shell", LinearInterface(Dn=math.inf, Dt=math.inf))],
                  max_time=2e-4)
    whole = _case([Body("rod", Rectangle(0.0, 0.0, R, L), "m")],
                  [BoundaryCondition("fixed", "rod", "ymin", ("y",), (0.0,)),
                   BoundaryCondition("traction", "rod", "ymax", ("y",), (1.0,))], max_time=2e-4)
    a = mpm.solve(split, progress=False, ramp_time=1e-4)
    b = mpm.solve(whole, progress=False, ramp_time=1e-4)
    xa, xb = np.asarray(a.fields["position"]), np.asarray(b.fields["position"])
    ua, ub = np.asarray(a.fields["displacement"]), np.asarray(b.fields["displacement"])
    order_a = np.lexsort(xa.T)
    order_b = np.lexsort(xb.T)
    assert np.array_equal(xa[order_a], xb[order_b])
    scale = np.abs(ub).max()
    assert scale > 0.0
    assert np.abs(ua[order_a] - ub[order_b]).max() < 1e-9 * scale


def test_axisymmetric_refusals_name_the_field():
    rod = _rod()
    with pytest.raises(CaseError, match="update"):
        mpm.solve(rod, progress=False, update="usf")
    off_axis = _case([Body("rod", Rectangle(-1.0, 0.0, 2.0, 2.0), "m")],
                     [BoundaryCondition("fixed", "rod", "ymin", ("y",), (0.0,))])
    assert "r = x >= 0" in mpm.supports(off_axis)
    with pytest.raises(CaseError, match="r = x >= 0"):
        mpm.solve(off_axis, progress=False)


def _core_sleeve(Dt: float, h: float) -> tuple[dict, dict]:
    import fem
    from cases.library import core_sleeve
    a = mpm.solve(core_sleeve(Dt=Dt, mpm_cell=h), progress=False).quantities
    b = fem.solve(core_sleeve(Dt=Dt, fem_h=0.125)).quantities
    return a, b


def test_core_sleeve_pull_out_matches_axisymmetric_fem():
    """Glass core pulled out of a polymer sleeve through an imperfect interface (Dt = 10,
    Dn = inf; `cases.library.core_sleeve`) at 0.5 mm cells (2 across the core radius):
    stiffness and interfacial energy against axisymmetric FEM (converged to 4e-6 at
    0.125 mm). Measured +0.03 % and +0.02 % (at 0.25 mm: -0.30 %, +0.26 %)."""
    a, b = _core_sleeve(10.0, 0.5)
    assert a["stiffness"] == pytest.approx(b["stiffness"], rel=5e-3)
    assert a["interface_energy"] == pytest.approx(b["interface_energy"], rel=5e-3)


def test_core_sleeve_perfect_bond_held_outside_matches_fem_energy():
    """Dt = inf, the sleeve held on its outer surface (no singular corner on the bond:
    with the base support the perfect-bond stiffness keeps falling under refinement).
    The stored energy under the applied load, MPM at 0.25 mm against FEM at 0.0625 mm
    (FEM converged to 6e-5 there): measured +0.048 % (+0.004 % at 0.125 mm). FEM's
    reported load on the core top is below sigma pi a^2 here (3.122 at 0.0625 mm), so the
    energy, not FEM's P / delta, is compared."""
    import fem
    from cases.library import core_sleeve
    a = mpm.solve(core_sleeve(Dt=math.inf, support="outer", mpm_cell=0.25),
                  progress=False).quantities
    b = fem.solve(core_sleeve(Dt=math.inf, support="outer", fem_h=0.0625)).quantities
    assert a["strain_energy"] == pytest.approx(b["strain_energy"], rel=2e-3)
    assert a["load"] == pytest.approx(math.pi, rel=1e-12)


@pytest.mark.slow
@pytest.mark.parametrize("Dt", [1.0, 10.0, 100.0])
def test_core_sleeve_within_fem_over_dt(Dt):
    """MPM at 0.25 mm against FEM for Dt = 1, 10, 100 MPa/mm (measured -0.28, -0.30,
    +0.10 % in stiffness). Dt = inf with this base support is not here: with a perfect
    bond its stiffness does not converge in FEM (-1.1 % per halving of h down to 0.016 mm,
    a singular corner), and MPM follows the same trend (+3.9 / +3.2 / +2.6 % above FEM at
    equal h = 0.5 / 0.25 / 0.125); the outer support is the perfect-bond test."""
    a, b = _core_sleeve(Dt, 0.25)
    assert a["stiffness"] == pytest.approx(b["stiffness"], rel=1e-2)
    assert a["interface_energy"] == pytest.approx(b["interface_energy"], rel=1e-2)
