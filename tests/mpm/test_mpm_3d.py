"""3D MPM (mpm/kernels3d.py) against closed forms and against the 2D kernels.

Uniaxial bar with uGIMP and the quadratic B-spline (B2, whose sides with conditions
are planes of symmetry: mpm.boundary.GhostNodes), a block split by a perfect
interface against the uncut block, and a plane-strain slab against the same slab in
3D, one cell thick between two symmetry faces.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import mpm
from interfaces import (Body, BoundaryCondition, Box, Case, CaseError, InterfacePair,
                        IsotropicElastic, LinearInterface, Rectangle)

E, NU = 1000.0, 0.3
MAT = IsotropicElastic(E=E, nu=NU, rho=1e-9)


def _case(bodies, bcs, interfaces=(), analysis="3d", **mpm_opts) -> Case:
    return Case(name="block3d", analysis=analysis, thickness=1.0, materials={"m": MAT},
                bodies=bodies, interfaces=list(interfaces), boundary_conditions=bcs,
                discretization={"mpm": dict({"cell": 0.5}, **mpm_opts)})


def _symmetric(body: str) -> list[BoundaryCondition]:
    return [BoundaryCondition("fixed", body, side, (axis,), (0.0,))
            for side, axis in (("xmin", "x"), ("ymin", "y"), ("zmin", "z"))]


@pytest.mark.parametrize("shape", ["ugimp", "b2"])
def test_uniaxial_bar_matches_the_closed_form(shape):
    """1/8 of a bar (three symmetry planes) under an end traction t: u = (t x, -nu t y,
    -nu t z) / E and U = t^2 V / 2E. Measured at 4 cells across (h = 0.5): max error
    1.06e-3 (uGIMP) / 1.06e-3 (B2) of t L / E along the bar and 6e-5 across, U +0.11 %;
    the same at h = 0.25 (the residual is the damped run's stopping tolerance, not the
    discretisation). Without the B2 symmetry treatment (conditions on the side nodes
    only) the error was 26 % at h = 0.5 and 10 % at 0.25."""
    L, W, t = 4.0, 2.0, 1.0
    case = _case([Body("bar", Box(0.0, 0.0, 0.0, L, W, W), "m")],
                 _symmetric("bar") + [BoundaryCondition("traction", "bar", "xmax", ("x",), (t,))],
                 shape=shape)
    res = mpm.solve(case, progress=False)
    x, u = np.asarray(res.fields["position"]), np.asarray(res.fields["displacement"])
    exact = np.stack([x[:, 0], -NU * x[:, 1], -NU * x[:, 2]], axis=1) * t / E
    err = np.abs(u - exact).max(axis=0) / (t * L / E)
    assert err[0] < 3e-3
    assert err[1] < 3e-4 and err[2] < 3e-4
    assert res.quantities["strain_energy"] == pytest.approx(0.5 * t * t / E * L * W * W, rel=3e-3)
    assert np.abs(np.asarray(res.fields["stress"])[:, 0] - t).max() < 3e-3 * t


def test_block_split_by_a_perfect_interface_equals_the_uncut_block(tmp_path):
    """A perfect interface on the grid plane x = 1 (momentum-corrected bond) under a
    shear-and-tension load: the split block moves as the uncut one, to round-off. The
    3D VTK series (one VTU per output step and a .pvd) holds the final 3D state."""
    def load(body):
        return [BoundaryCondition("fixed", body, "ymin", ("x", "y", "z"), (0.0, 0.0, 0.0)),
                BoundaryCondition("traction", body, "ymax", ("x", "y"), (0.3, 1.0))]
    split = _case([Body("a", Box(0.0, 0.0, 0.0, 1.0, 2.0, 1.0), "m"),
                   Body("b", Box(1.0, 0.0, 0.0, 1.0, 2.0, 1.0), "m")],
                  load("a") + load("b"),
                  [InterfacePair("a", "b", LinearInterface(Dn=math.inf, Dt=math.inf))],
                  max_time=1e-4)
    whole = _case([Body("ab", Box(0.0, 0.0, 0.0, 2.0, 2.0, 1.0), "m")], load("ab"), max_time=1e-4)
    a = mpm.solve(split, progress=False, ramp_time=5e-5)
    b = mpm.solve(whole, progress=False, ramp_time=5e-5)
    xa, xb = np.asarray(a.fields["position"]), np.asarray(b.fields["position"])
    ua, ub = np.asarray(a.fields["displacement"]), np.asarray(b.fields["displacement"])
    oa, ob = np.lexsort(xa.T), np.lexsort(xb.T)
    assert np.array_equal(xa[oa], xb[ob])
    scale = np.abs(ub).max()
    assert scale > 0.0
    assert np.abs(ua[oa] - ub[ob]).max() < 1e-9 * scale
    assert a.quantities["strain_energy"] == pytest.approx(b.quantities["strain_energy"], rel=1e-9)
    # (the frames cut the output intervals, at whose ends the adaptive damping is
    # updated: a run with frames is compared with its own particles)
    import meshio
    c = mpm.solve(whole, progress=False, ramp_time=5e-5, vtk_dir=str(tmp_path), vtk_frames=4)
    vtus = sorted(tmp_path.glob("*.vtu"))
    assert len(vtus) >= 2 and (tmp_path / "block3d.pvd").exists()
    last = meshio.read(vtus[-1])
    xc, uc = np.asarray(c.fields["position"]), np.asarray(c.fields["displacement"])
    assert np.allclose(np.sort(last.points, axis=0), np.sort(xc + uc, axis=0), rtol=0, atol=1e-12)
    assert last.point_data["stress"].shape == (xc.shape[0], 6)


@pytest.mark.parametrize("shape", ["ugimp", "b2"])
def test_plane_strain_slab_equals_a_3d_slab_one_cell_thick(shape):
    """A 2D plane-strain cantilever-like block (fixed base, shear and tension on top)
    and the same block in 3D, one cell thick, with zero normal displacement on both
    faces z = 0 and z = h: the in-plane fields and energies agree to round-off along the
    whole damped trajectory (the 3D kernels, the 3D Voigt order, the symmetry faces
    holding the particle tails beyond their edges and, for B2, the reflection of both
    faces). Measured: 1e-15 relative (B2), 2e-12 (uGIMP)."""
    h = 0.5
    top = ("ymax", ("x", "y"), (0.4, 0.6))
    plane = Case(name="slab", analysis="plane_strain", thickness=h, materials={"m": MAT},
                 bodies=[Body("s", Rectangle(0.0, 0.0, 2.0, 3.0), "m")],
                 boundary_conditions=[BoundaryCondition("fixed", "s", "ymin", ("x", "y"), (0.0, 0.0)),
                                      BoundaryCondition("traction", "s", *top)],
                 discretization={"mpm": {"cell": h, "shape": shape}})
    slab = _case([Body("s", Box(0.0, 0.0, 0.0, 2.0, 3.0, h), "m")],
                 [BoundaryCondition("fixed", "s", "ymin", ("x", "y"), (0.0, 0.0)),
                  BoundaryCondition("fixed", "s", "zmin", ("z",), (0.0,)),
                  BoundaryCondition("fixed", "s", "zmax", ("z",), (0.0,)),
                  BoundaryCondition("traction", "s", *top)], shape=shape)
    # one fixed grid damping: the adaptive one follows a Rayleigh quotient of the last
    # increments, which amplifies round-off into a different damping history
    a = mpm.solve(plane, progress=False, max_time=2e-4, alpha=3e5)
    b = mpm.solve(slab, progress=False, max_time=2e-4, alpha=3e5)
    assert a.diagnostics["time_steps"] == b.diagnostics["time_steps"]
    xa, ua = np.asarray(a.fields["position"]), np.asarray(a.fields["displacement"])
    xb, ub = np.asarray(b.fields["position"]), np.asarray(b.fields["displacement"])
    first = np.abs(xb[:, 2] - xb[:, 2].min()) < 1e-12      # one layer of the 3D particles
    ob = np.flatnonzero(first)[np.lexsort(xb[first, :2].T)]
    oa = np.lexsort(xa.T)
    assert np.array_equal(xa[oa], xb[ob, :2])
    scale = np.abs(ua).max()
    assert np.abs(ua[oa] - ub[ob, :2]).max() < 1e-9 * scale
    assert np.abs(ub[:, 2]).max() < 1e-12 * scale
    for q in ("strain_energy", "external_work"):
        assert b.quantities[q] == pytest.approx(a.quantities[q], rel=1e-9)
    # plane strain: sigma_zz = nu (sigma_xx + sigma_yy) in 3D, as the 2D stress implies
    sb = np.asarray(b.fields["stress"])
    assert np.abs(sb[:, 2] - NU * (sb[:, 0] + sb[:, 1])).max() < 1e-9 * np.abs(sb).max()


def test_3d_refusals_name_the_option():
    bar = _case([Body("bar", Box(0.0, 0.0, 0.0, 2.0, 1.0, 1.0), "m"),
                 Body("cap", Box(2.0, 0.0, 0.0, 1.0, 1.0, 1.0), "m")], _symmetric("bar"),
                [InterfacePair("bar", "cap", LinearInterface(Dn=10.0, Dt=10.0))])
    with pytest.raises(CaseError, match="LR"):
        mpm.solve(bar, progress=False, normal="LR")
    off_grid = _case([Body("bar", Box(0.0, 0.0, 0.0, 2.1, 1.0, 1.0), "m")],
                     [BoundaryCondition("fixed", "bar", "xmax", ("x",), (0.0,))], shape="b2")
    with pytest.raises(CaseError, match="grid node line"):
        mpm.solve(off_grid, progress=False)
