"""MPM with imperfect interfaces on the papers' specimens vs FEM and shear lag.

Default runs are reduced (short DLS bond, 0.2 mm cells = 3 cells per strand, short
ramp); the paper-size runs are marked slow. Case builders: cases.library.
"""
from __future__ import annotations

import math

import pytest

from cases.library import dls, two_layer
from interfaces.analytic.registry import dls_shear_lag

import fem
import mpm


#: measured MPM - FEM stiffness gap of the paper-size DLS at 0.1 mm cells: at most
#: 0.06 % (SN, MVG), 0.26 % (AVG with edge screening; docs/mpm_validation/dls_01_normals.csv)
TOL_DLS_01 = 5e-3


def _shear_lag(case) -> float:
    return dls_shear_lag(**{k: v for k, v in case.analytic.items() if k != "model"})["stiffness"]


@pytest.mark.parametrize("Dt", [5.0, math.inf])
def test_short_dls_stiffness_matches_fem_and_shear_lag(Dt):
    """002 Fig 5 at reduced size: l = 5, L = 2 mm, t = 0.6 mm, 0.2 mm cells.

    Observed: MPM is 0.9 % stiffer than quadratic FEM for Dt = 5 and Dt = inf; the
    shear-lag model (002 Eq 40-42) is within 1 % for Dt = 5 and 3 % above FEM for a
    perfect interface on this short bond.
    """
    case = dls(Dt=Dt, l=5.0, L=2.0, mpm_cell=0.2)
    rm = mpm.solve(case, ramp_time=5e-5, progress=False)
    rf = fem.solve(case)
    k_fem = rf.quantities["stiffness"]
    assert rm.diagnostics["stopped_by"] == "kinetic_energy"
    assert rm.quantities["stiffness"] == pytest.approx(k_fem, rel=1.5e-2)
    assert rm.quantities["stiffness_energy"] == pytest.approx(k_fem, rel=1.5e-2)
    if Dt < math.inf:
        assert rm.quantities["stiffness"] == pytest.approx(_shear_lag(case), rel=1.5e-2)
        assert rm.quantities["interface_energy"] > 0
    else:
        assert rm.quantities["interface_energy"] == 0.0



def test_gradient_normals_at_layer_ends_and_edge_screening():
    """000 Sec 3 (Fig 7, 11): at the nodes where one layer stops while the other goes
    on, MVG takes the continuing layer's (right) normal, AVG averages it with the
    stopped layer's 45 deg one; with a perfect normal direction (Dn = inf) the tilted
    normal locks part of the slip there, so AVG is too stiff, and screening nodes with
    Omega_i < 0.85 A_cell (000 Sec 3, Fig 11) removes the error.

    Measured on the short DLS (l = 5, L = 2, 0.2 mm cells, Dt = 2; FEM 196.15 N/mm):
    SN and MVG -0.10 %, AVG +46 %, AVG screened -0.47 % (SN screened -4.1 %: on
    this short bond the screened end nodes carry a visible part of the shear). On the
    paper-size specimen at 0.1 mm: AVG +9.0 / +3.7 / +1.8 / +0.4 / 0.0 % for Dt = 2 /
    5 / 10 / 50 / inf, screened within TOL_DLS_01 (slow test below).
    """
    case = dls(Dt=2.0, l=5.0, L=2.0, mpm_cell=0.2)
    k_fem = fem.solve(case).quantities["stiffness"]
    k = {}
    for label, opts in (("MVG", dict(normal="MVG")), ("AVG", dict(normal="AVG")),
                        ("AVG screened", dict(normal="AVG", edge_cutoff=0.85))):
        rm = mpm.solve(case, ramp_time=5e-5, progress=False, **opts)
        k[label] = rm.quantities["stiffness"] / k_fem - 1.0
    assert abs(k["MVG"]) < 5e-3
    assert k["AVG"] > 0.2
    assert abs(k["AVG screened"]) < 1.5e-2


@pytest.mark.parametrize("Dt", [1.0, 10.0, 100.0])
def test_two_layer_shear_energies_match_fem(Dt):
    """000 Fig 4A two-layer shear (height 8 mm, 0.5 mm cells, Dn = inf) against FEM.

    Measured: interfacial energy +0.2 / +0.3 / +0.9 % and strain energy -0.04 / -0.05 /
    -0.09 % for Dt = 1 / 10 / 100; W = U + K + D to 0.4 %. Two things had to be right for
    this (both were wrong before): the run must reach the static state (adaptive damping
    for the bending mode; the axial-period damping stopped it while the bending crept:
    +9 % at Dt = 1) and the jump must be read at the node, not at the fields' centroids
    (000 Eq 13 as printed, ``nodal_displacement="average"``: 0.0 / +2.9 / +13 %, from the
    specimen rotation; mpm/extrapolation.py).
    """
    case = two_layer(Dt=Dt, height=8.0, mpm_cell=0.5)
    rm = mpm.solve(case, progress=False)
    rf = fem.solve(case)
    assert rm.diagnostics["stopped_by"] == "kinetic_energy"
    assert rm.quantities["strain_energy"] == pytest.approx(rf.quantities["strain_energy"], rel=3e-3)
    assert rm.quantities["interface_energy"] == pytest.approx(rf.quantities["interface_energy"],
                                                              rel=2.5e-2)
    q = rm.quantities
    assert q["external_work"] == pytest.approx(q["strain_energy"] + q["interface_energy"]
                                               + q["kinetic_energy"] + q["dissipated_energy"],
                                               rel=1e-2)


@pytest.mark.slow
@pytest.mark.parametrize("Dt", [1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0])
def test_two_layer_interfacial_energy_at_the_papers_grid(Dt):
    """Issue #4 target: the full 000 Fig 4A specimen (20 mm tall) at 0.25 mm cells,
    interfacial energy within 5 % of FEM for Dt = 1..100 (docs/two_layer_sweep_Dt.csv)."""
    case = two_layer(Dt=Dt)
    rm = mpm.solve(case, progress=False)
    rf = fem.solve(case)
    assert rm.quantities["interface_energy"] == pytest.approx(rf.quantities["interface_energy"],
                                                              rel=5e-2)
    assert rm.quantities["strain_energy"] == pytest.approx(rf.quantities["strain_energy"], rel=1e-2)


@pytest.mark.slow
@pytest.mark.parametrize("Dt", [2.0, 5.0, 50.0, math.inf])
def test_paper_dls_stiffness_over_dt(Dt):
    """002 Sec 3.1 DLS (l = 25, L = 5, t = 0.6, W = 10) at 0.2 mm cells vs FEM / shear lag.

    Observed: MPM 0.15-0.3 % above quadratic FEM for Dt = 2, 5, 50, inf, and within
    0.4 % of the shear-lag model (002 Fig 5 agreement).
    """
    case = dls(Dt=Dt, mpm_cell=0.2)
    rm = mpm.solve(case, ramp_time=1e-4, progress=False)
    k_fem = fem.solve(case).quantities["stiffness"]
    assert rm.quantities["stiffness"] == pytest.approx(k_fem, rel=1e-2)
    assert rm.quantities["stiffness_energy"] == pytest.approx(k_fem, rel=1e-2)
    assert rm.quantities["stiffness"] == pytest.approx(_shear_lag(case), rel=1e-2)


@pytest.mark.slow
@pytest.mark.parametrize("normal", [dict(normal="SN"), dict(normal="MVG"),
                                    dict(normal="AVG", edge_cutoff=0.85)], ids=["SN", "MVG", "AVG"])
@pytest.mark.parametrize("Dt", [2.0, math.inf])
def test_paper_dls_at_01mm_cells_with_each_normal(normal, Dt):
    """Issue #4 target: the 002 Sec 3.1 DLS at 0.1 mm cells, 2x2 particles per cell,
    stiffness within 5 % of FEM and of shear lag with SN, MVG and AVG normals (AVG with
    the edge screening of 000 Sec 3 at 0.85 A_cell: see the layer-ends test above).

    Measured over Dt = 2, 5, 10, 50, inf (docs/mpm_validation/dls_01_normals.csv):
    SN and MVG +0.04..+0.06 % from quadratic FEM and +0.04..+0.12 % from shear lag;
    AVG screened -0.17 / -0.26 / -0.23 / -0.20 / +0.04 % from FEM. Here Dt = 2 (the softest, slowest to settle) and a perfect interface.
    """
    case = dls(Dt=Dt, mpm_cell=0.1)
    rm = mpm.solve(case, ramp_time=5e-5, progress=False, **normal)
    k_fem = fem.solve(case).quantities["stiffness"]
    assert rm.diagnostics["stopped_by"] == "kinetic_energy"
    assert rm.quantities["stiffness"] == pytest.approx(k_fem, rel=TOL_DLS_01)
    assert rm.quantities["stiffness_energy"] == pytest.approx(k_fem, rel=TOL_DLS_01)
    assert rm.quantities["stiffness"] == pytest.approx(_shear_lag(case), rel=TOL_DLS_01)
    assert abs(rm.quantities["energy_balance_error"]) < 1e-2


@pytest.mark.slow
@pytest.mark.parametrize("angle", [45.0])
def test_rotated_dls_stiffness_is_independent_of_angle(angle):
    """000 Fig 9, regular grid: the 000 DLS (Dt = 5, Dn = inf, loaded at both ends)
    rotated against a 0.25 mm grid keeps its stiffness within 3 % of the unrotated one.

    Measured (docs/mpm_validation/dls_rotated.csv; unrotated 166.74 N/mm, FEM 166.44):
    -0.41 / +0.56 / -1.19 / +0.75 / -0.005 % at 15 / 30 / 45 / 60 / 90 deg; the energy
    stiffness (Eq 45) -1.4 / -1.0 / -2.7 / -0.8 / 0.0 %. 45 deg is the worst. The rotated
    runs end at max_time with the particle kinetic energy ~3 % of the strain energy
    (FLIP noise on cut cells), not at the kinetic-energy stop.
    """
    k0 = mpm.solve(dls(variant="000", Dt=5.0, mpm_cell=0.25), progress=False).quantities
    rm = mpm.solve(dls(variant="000", Dt=5.0, mpm_cell=0.25, angle=angle), progress=False)
    assert rm.quantities["stiffness"] == pytest.approx(k0["stiffness"], rel=2e-2)
    assert rm.quantities["stiffness_energy"] == pytest.approx(k0["stiffness_energy"], rel=3e-2)


@pytest.mark.slow
@pytest.mark.parametrize("angle", [30.0, 90.0])
def test_rotated_dls_on_unequal_cells_needs_h_perp(angle):
    """000 Fig 9, dy = 2 dx (0.25 x 0.5 mm): with h-perp method 1 (000 Eq 22) the
    rotated 000 DLS stays close to the regular-grid result; with h-perp = dx ("no
    correction") the contact area of Eq 20 is too large wherever the normal leans
    towards y, an effectively larger Dt.

    Measured (docs/mpm_validation/dls_rotated.csv, vs the regular 0.25 mm grid at 0 deg,
    166.74 N/mm): method 1 +0.18 / -0.98 / -3.8 / +0.07 % at 0 / 30 / 45 / 90 deg,
    no correction +0.18 / +16.3 / +24.9 / +50.5 %. As in 000, method 1 is not as good
    as the regular grid (-1.2 % at 45 deg there): the y resolution is halved.
    """
    k0 = mpm.solve(dls(variant="000", Dt=5.0, mpm_cell=0.25), progress=False).quantities["stiffness"]
    case = dls(variant="000", Dt=5.0, angle=angle)
    k1 = mpm.solve(case, cell=[0.25, 0.5], h_perp="ellipse_tangent", progress=False)
    k_none = mpm.solve(case, cell=[0.25, 0.5], h_perp="none", progress=False)
    assert k1.quantities["stiffness"] == pytest.approx(k0, rel=1.5e-2)
    assert k_none.quantities["stiffness"] > 1.1 * k0
