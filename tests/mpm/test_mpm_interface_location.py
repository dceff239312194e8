"""000 Fig 8: imperfect interface on a grid line vs at mid-cell, with and without the
contact-area correction of 000 Eq 20 (ERRATA 8), on the two-layer shear specimen
(000 Fig 4A) reduced to a height of 8 mm.

``grid_anchor="origin"`` fixes the grid in space so that the case's ``shift_x`` moves
the interface relative to the node lines (shift_x = cell / 2: interface at mid-cell).
"""
from __future__ import annotations

import numpy as np
import pytest

import cases
import mpm
from interfaces.errors import CaseError
from mpm.grid import Grid


def _interface_energy(Dt: float, shift_x: float, area_correction: bool, cell: float = 0.5,
                      **opts) -> float:
    case = cases.build("two_layer", Dt=Dt, height=8.0, mpm_cell=cell, shift_x=shift_x)
    r = mpm.solve(case, area_correction=area_correction, grid_anchor="origin",
                  progress=False, **opts)
    assert r.diagnostics["stopped_by"] == "kinetic_energy"
    return r.quantities["interface_energy"]


def test_grid_anchor_puts_the_anchor_on_node_lines():
    g = Grid.around([0.25, 0.0], [8.25, 8.0], 0.5, padding=3, anchor=[0.0, 0.0])
    assert np.allclose(np.mod(g.origin, 0.5), 0.0)
    assert np.all(g.origin <= [0.25 - 3 * 0.5, -3 * 0.5] + np.array([1e-12, 1e-12]))
    top = g.origin + (g.nn - 1) * g.cell
    assert np.all(top >= [8.25 + 3 * 0.5, 8.0 + 3 * 0.5])
    b = Grid.around([0.25, 0.0], [8.25, 8.0], 0.5, padding=3)
    assert b.origin[0] == pytest.approx(0.25 - 1.5)
    case = cases.build("two_layer", height=8.0, mpm_cell=0.5)
    with pytest.raises(CaseError, match="grid_anchor"):
        mpm.solve(case, grid_anchor="middle")


def test_fig8_area_correction_makes_the_energy_independent_of_interface_location():
    """Dt = 5 MPa/mm, 0.5 mm cells, USL on both runs so that only the interface location
    differs.  Measured interfacial energy (N mm): grid line 5.892e-5, mid-cell 5.723e-5
    (2.9 % apart; FEM 5.879e-5).  Without Eq 20 at mid-cell: 9.433e-5, equal to the
    corrected mid-cell run with Dt = 10 to 1e-5 (the uncorrected area t Omega_i / dx is
    exactly twice Eq 20 there): the doubled effective Dt of 000 Fig 8. The corrected
    grid-line run at Dt = 10 gives 9.740e-5 (FEM 9.707e-5), 3.1 % above the mid-cell
    runs at this coarse grid; at the issue's 0.25 mm grid the gaps are 2.0 % and 1.9 %
    (slow test below)."""
    h = 0.5
    grid_line = _interface_energy(5.0, 0.0, True, update="usl")
    mid = _interface_energy(5.0, h / 2, True, update="usl")
    assert mid == pytest.approx(grid_line, rel=0.03)
    mid_uncorrected = _interface_energy(5.0, h / 2, False, update="usl")
    assert mid_uncorrected > 1.5 * grid_line                       # not a small bias
    mid_double = _interface_energy(10.0, h / 2, True, update="usl")
    assert mid_uncorrected == pytest.approx(mid_double, rel=1e-3)
    grid_line_double = _interface_energy(10.0, 0.0, True, update="usl")
    assert mid_uncorrected == pytest.approx(grid_line_double, rel=0.04)


def test_fig8_with_the_default_update_against_fem():
    """The default update (auto: USL with the interface on a grid line, MUSL at mid-cell) at
    0.5 mm cells, each location against FEM (independent of the grid). Measured: grid line
    +0.23 %, mid-cell -2.35 % from FEM (5.879e-5 N mm at Dt = 5; -1.9 % at 0.25 mm, slow
    test below); without Eq 20 at mid-cell +61 %."""
    import fem
    case = cases.build("two_layer", Dt=5.0, height=8.0, mpm_cell=0.5)
    U = fem.solve(case, fields=False).quantities["interface_energy"]
    assert _interface_energy(5.0, 0.0, True) == pytest.approx(U, rel=1e-2)
    assert _interface_energy(5.0, 0.25, True) == pytest.approx(U, rel=4e-2)
    assert _interface_energy(5.0, 0.25, False) > 1.5 * U


@pytest.mark.slow
def test_fig8_at_quarter_millimetre_cells_with_the_automatic_update():
    """0.25 mm cells, update='auto' (USL on the grid line; MUSL at mid-cell, where the
    outer edges cut cells).  Measured: grid line 5.886e-5 (FEM 5.879e-5 at Dt = 5),
    mid-cell 5.770e-5 (2.0 % apart), uncorrected mid-cell 9.540e-5 vs grid line at
    Dt = 10 9.723e-5 (1.9 %; FEM 9.707e-5)."""
    h = 0.25
    grid_line = _interface_energy(5.0, 0.0, True, cell=h)
    mid = _interface_energy(5.0, h / 2, True, cell=h)
    assert mid == pytest.approx(grid_line, rel=0.03)
    assert _interface_energy(5.0, h / 2, False, cell=h) == pytest.approx(
        _interface_energy(10.0, 0.0, True, cell=h), rel=0.03)
