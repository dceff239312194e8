"""Nodal velocity conditions on perfectly bonded multimaterial nodes.

The phase-1 contact correction (004 Eq 31) runs after the core has imposed the nodal
conditions; a fixed node shared with a perfectly bonded body must keep its condition
(mpm.multimaterial.apply_velocity_conditions), and a body split by a perfect interface
that crosses the fixed side must equal the uncut body (004 Eq 34).
"""
from __future__ import annotations

import numpy as np
import pytest

import mpm
from interfaces import Body, BoundaryCondition, Case, IsotropicElastic, Rectangle
from mpm.options import merge
from mpm.solver import Model, _Runner

W, H = 4.0, 4.0


def split_bar(split=None) -> Case:
    """W x H bar, bottom fixed in x and y, shear + tension traction on top; optionally
    cut by a vertical perfect interface at x = split (crossing the fixed bottom)."""
    mat = IsotropicElastic(E=1000.0, nu=0.25, rho=2e-9)
    if split is None:
        bodies = [Body("b", Rectangle(0, 0, W, H), "m")]
    else:
        bodies = [Body("l", Rectangle(0, 0, split, H), "m"),
                  Body("r", Rectangle(split, 0, W - split, H), "m")]
    bcs = []
    for b in bodies:
        bcs += [BoundaryCondition("fixed", b.name, "ymin", ("x", "y"), (0.0, 0.0)),
                BoundaryCondition("traction", b.name, "ymax", ("x", "y"), (0.5, 1.0))]
    return Case(name="split_bar", analysis="plane_stress", thickness=1.0,
                materials={"m": mat}, bodies=bodies, boundary_conditions=bcs)


@pytest.mark.parametrize("split", [2.0, 2.25])      # interface on a grid line / mid-cell
def test_fixed_nodes_keep_zero_velocity_after_the_phase1_correction(split):
    """Without re-imposing the conditions the bonded bottom nodes at the interface move
    (measured 0.05 mm/s on the grid line and 6.4 mm/s at mid-cell after 200 steps)."""
    case = split_bar(split)
    model = Model(case, merge(case, {"cell": 0.5, "progress": False}))
    _Runner(model)._advance(200)
    nd, bc = model.nodal, model.bcs
    shared = bc.node[(nd.mass[bc.node] > 0).sum(axis=1) >= 2]
    assert shared.size > 0                        # the condition does reach bonded nodes
    assert np.abs(nd.velocity).max() > 1.0        # the bar is moving
    # every field at every constrained node (both conditions fix x and y)
    assert np.abs(nd.velocity[bc.node]).max() == 0.0


@pytest.mark.parametrize("split", [2.0, 2.25])
def test_bar_split_across_the_fixed_side_equals_the_uncut_bar(split):
    """Measured: particle displacements equal to 5e-12 (grid line) and 3e-14 (mid-cell)
    of the largest one; without the fix 7e-4 and 6.5e-2."""
    one = mpm.solve(split_bar(), cell=0.5, progress=False)
    two = mpm.solve(split_bar(split), cell=0.5, progress=False)
    o1 = np.lexsort(one.fields["position"].T)
    o2 = np.lexsort(two.fields["position"].T)
    np.testing.assert_allclose(two.fields["position"][o2], one.fields["position"][o1], atol=1e-12)
    u1, u2 = one.fields["displacement"][o1], two.fields["displacement"][o2]
    assert np.abs(u2 - u1).max() < 1e-9 * np.abs(u1).max()
    assert np.abs(two.fields["stress"][o2] - one.fields["stress"][o1]).max() < 1e-6
    assert two.quantities["energy_balance_error"] == pytest.approx(
        one.quantities["energy_balance_error"], abs=1e-9)
