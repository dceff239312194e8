"""Unit tests of the MPM core: grid indexing, shape functions, particles, P2G, loads, errors."""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from interfaces import (Body, BoundaryCondition, Case, CaseError, IsotropicElastic, Rectangle,
                        Circle, Ellipse, SolverError)
import mpm
from mpm import kernels as K
from mpm.grid import Grid, NodalFields
from mpm.particles import apply_tractions, generate
from mpm.shape import LINEAR, UGIMP, shape_2d

ORIGIN = np.array([-1.0, -2.0])
CELL = np.array([0.5, 0.8])
NN = np.array([12, 9])


def _block_case(width=4.0, height=2.0, holes=(), traction=(0.0, 1.0), thickness=3.0):
    mat = IsotropicElastic(E=1000.0, nu=0.25, rho=2e-9)
    return Case(name="block", analysis="plane_stress", thickness=thickness, materials={"m": mat},
                bodies=[Body("b", Rectangle(0.0, 0.0, width, height), "m", holes=list(holes))],
                boundary_conditions=[
                    BoundaryCondition("fixed", "b", "ymin", ("x", "y"), (0.0, 0.0)),
                    BoundaryCondition("traction", "b", "ymax", ("x", "y"), traction)])


# ---------------------------------------------------------------- grid ----

def test_grid_flat_index_and_positions():
    g = Grid(ORIGIN, CELL, NN)
    X = g.node_positions()
    assert X.shape == (g.N, 2)
    ij = np.array([[3, 5], [0, 0], [11, 8]])
    n = g.node_index(ij)
    np.testing.assert_array_equal(n, ij[:, 0] + NN[0] * ij[:, 1])
    np.testing.assert_allclose(X[n], ORIGIN + ij * CELL)


def test_grid_around_puts_body_edges_on_node_lines():
    g = Grid.around([0.0, 0.0], [4.0, 2.0], [0.5, 0.25], padding=3)
    X = g.node_positions()
    for value, d in ((0.0, 0), (4.0, 0), (0.0, 1), (2.0, 1)):
        assert np.any(np.isclose(X[:, d], value, atol=1e-12))


# ------------------------------------------------------ shape functions ----

@settings(max_examples=60, deadline=None)
@given(st.floats(0.2, 4.3), st.floats(-0.9, 4.0), st.sampled_from([LINEAR, UGIMP]))
def test_shape_partition_of_unity_and_linear_reproduction(x, y, kind):
    lp = 0.5 * CELL / 2 if kind == UGIMP else np.zeros(2)
    idx = np.zeros(9, np.int64)
    S = np.zeros(9)
    G = np.zeros((9, 2))
    c = shape_2d(x, y, ORIGIN, CELL, NN, lp, kind, idx, S, G)
    assert c > 0
    X = Grid(ORIGIN, CELL, NN).node_positions()[idx[:c]]
    assert S[:c].sum() == pytest.approx(1.0, abs=1e-13)
    np.testing.assert_allclose(S[:c] @ X, [x, y], atol=1e-12)       # sum S x_i = x_p
    np.testing.assert_allclose(G[:c].sum(axis=0), 0.0, atol=1e-12)   # sum grad S = 0
    np.testing.assert_allclose(X.T @ G[:c], np.eye(2), atol=1e-12)  # sum x_i (x) grad S = I


@pytest.mark.parametrize("kind", [LINEAR, UGIMP])
def test_shape_gradient_matches_finite_differences(kind):
    rng = np.random.default_rng(3)
    lp = 0.5 * CELL / 2 if kind == UGIMP else np.zeros(2)
    X = Grid(ORIGIN, CELL, NN).node_positions()
    h = 1e-6
    for _ in range(40):
        x, y = rng.uniform(0.3, 3.5), rng.uniform(-0.5, 3.0)

        def weights(px, py):
            idx = np.zeros(9, np.int64)
            S = np.zeros(9)
            G = np.zeros((9, 2))
            c = shape_2d(px, py, ORIGIN, CELL, NN, lp, kind, idx, S, G)
            full = np.zeros(len(X))
            full[idx[:c]] = S[:c]
            grad = np.zeros((len(X), 2))
            grad[idx[:c]] = G[:c]
            return full, grad

        S0, G0 = weights(x, y)
        fdx = (weights(x + h, y)[0] - weights(x - h, y)[0]) / (2 * h)
        fdy = (weights(x, y + h)[0] - weights(x, y - h)[0]) / (2 * h)
        np.testing.assert_allclose(G0[:, 0], fdx, atol=1e-5)
        np.testing.assert_allclose(G0[:, 1], fdy, atol=1e-5)


def test_ugimp_weight_is_the_convolution_of_particle_and_node_functions():
    """004 Eq 2: S = (1/V_p) int chi_p N_i dx; check the 1D function by quadrature."""
    h, lp = 1.0, 0.25
    from mpm.shape import gimp_1d
    xs = np.linspace(-1.4, 1.4, 57)
    q = np.linspace(-lp, lp, 20001)
    for x in xs:
        exact = np.trapezoid(np.clip(1 - np.abs(x + q) / h, 0, None), q) / (2 * lp)
        assert gimp_1d(x, h, lp)[0] == pytest.approx(exact, abs=1e-7)


# ------------------------------------------------------------ particles ----

def test_particles_fill_bodies_with_holes_and_carry_mass():
    case = _block_case(holes=[Circle(2.0, 1.0, 0.5)])
    g = Grid.around(*case.bounds(), 0.25)
    pt = generate(case, g, 2)
    assert not np.any(np.hypot(pt.x[:, 0] - 2.0, pt.x[:, 1] - 1.0) < 0.5)
    area = 4.0 * 2.0 - math.pi * 0.25
    rho = case.materials["m"].rho
    # particle lattice resolves the hole to one particle area per boundary cell
    assert pt.mass.sum() == pytest.approx(rho * area * 3.0, rel=0.03)
    np.testing.assert_allclose(pt.volume0, 0.125 ** 2 * 3.0)
    assert pt.P == 128 * 4 - np.count_nonzero(
        np.hypot(*(generate(_block_case(), g, 2).x - [2.0, 1.0]).T) < 0.5)


def test_particles_per_cell_option_and_validation():
    case = _block_case()
    g = Grid.around(*case.bounds(), 0.5)
    assert generate(case, g, 3).P == 8 * 4 * 9
    assert generate(case, g, (1, 2)).P == 8 * 4 * 2
    with pytest.raises(CaseError, match="ppc"):
        generate(case, g, 0)


def test_traction_total_force_and_edge_offset():
    case = _block_case(traction=(0.5, -2.0), thickness=3.0)
    g = Grid.around(*case.bounds(), 0.5)
    pt = generate(case, g, 2)
    loads = apply_tractions(case, pt, 2)
    np.testing.assert_allclose(pt.fext.sum(axis=0), np.array([0.5, -2.0]) * 4.0 * 3.0)
    np.testing.assert_allclose(loads[0]["force"], [6.0, -24.0])
    loaded = np.any(pt.fext != 0, axis=1)
    # the loaded particles are the top row; their force acts on their top edge (y = 2)
    np.testing.assert_allclose(pt.x[loaded, 1] + pt.foff[loaded, 1], 2.0)


def test_traction_on_a_side_off_the_particle_lattice_loads_the_outermost_row():
    # height 2.1 at 0.25 mm spacing: the top centres are 0.225 mm below the side,
    # beyond half a spacing (0.125), where a side on the lattice has its first row
    case = _block_case(height=2.1, traction=(0.0, 1.0), thickness=3.0)
    pt = generate(case, Grid.around(*case.bounds(), 0.5, anchor=(0.0, 0.0)), 2)
    loads = apply_tractions(case, pt, 2)
    loaded = np.any(pt.fext != 0, axis=1)
    np.testing.assert_allclose(pt.x[loaded, 1], pt.x[:, 1].max())
    assert np.count_nonzero(loaded) == 16
    np.testing.assert_allclose(loads[0]["force"], [0.0, 4.0 * 3.0])
    np.testing.assert_allclose(pt.fext.sum(axis=0), [0.0, 4.0 * 3.0])


def test_traction_on_an_ellipse_curve_is_refused_by_mpm_naming_the_side():
    mat = IsotropicElastic(E=1000.0, nu=0.25, rho=2e-9)
    case = Case(name="e", analysis="plane_stress", thickness=1.0, materials={"m": mat},
                bodies=[Body("b", Ellipse(0.0, 0.0, 2.0, 1.0), "m")],
                boundary_conditions=[BoundaryCondition("traction", "b", "boundary", ("x", "y"),
                                                       (0.0, 1.0))])
    with pytest.raises(CaseError, match="side 'boundary' of body 'b'.*Rectangle/Box"):
        mpm.solve(case, cell=0.5, progress=False, max_time=1e-6)


# -------------------------------------------------------------- P2G -----

def test_p2g_conserves_mass_momentum_and_applied_force():
    case = _block_case()
    g = Grid.around(*case.bounds(), 0.5)
    pt = generate(case, g, 2)
    apply_tractions(case, pt, 2)
    rng = np.random.default_rng(0)
    pt.v[:] = rng.normal(size=pt.v.shape)
    pt.x += rng.uniform(-0.05, 0.05, pt.x.shape)
    pt.stress[:] = rng.normal(size=pt.stress.shape)
    nd = NodalFields(g.N, 1, 2)
    lost = K.p2g_2d(pt.x, pt.v, pt.mass, pt.volume, pt.stress, pt.field, pt.x0, pt.fext, pt.foff,
                    0.7, g.origin, g.cell, g.nn, pt.lp, UGIMP, False, True, nd.mass,
                    nd.momentum, nd.force, nd.volume, nd.volume_gradient, nd.displacement,
                    nd.position)
    assert lost == -1
    assert nd.mass.sum() == pytest.approx(pt.mass.sum(), rel=1e-13)
    np.testing.assert_allclose(nd.momentum.sum(axis=(0, 1)), pt.mass @ pt.v, rtol=1e-12)
    # internal forces are self-equilibrated (sum grad S = 0); the total is the applied load
    np.testing.assert_allclose(nd.force.sum(axis=(0, 1)), 0.7 * pt.fext.sum(axis=0), atol=1e-10)


def test_p2g_multimaterial_arrays_follow_layout():
    mat = IsotropicElastic(E=1000.0, nu=0.25, rho=2e-9)
    case = Case(name="two", analysis="plane_strain", thickness=1.0, materials={"m": mat},
                bodies=[Body("a", Rectangle(0, 0, 2, 1), "m"), Body("b", Rectangle(0, 1, 2, 1), "m")])
    g = Grid.around(*case.bounds(), 0.5)
    pt = generate(case, g, 2)
    pt.x += 0.01  # uniform displacement 0.01
    nd = NodalFields(g.N, 2, 2)
    K.p2g_2d(pt.x, pt.v, pt.mass, pt.volume, pt.stress, pt.field, pt.x0, pt.fext, pt.foff, 1.0,
             g.origin, g.cell, g.nn, pt.lp, UGIMP, True, True, nd.mass, nd.momentum, nd.force,
             nd.volume, nd.volume_gradient, nd.displacement, nd.position)
    has = nd.mass > 0
    np.testing.assert_allclose(nd.displacement[has], 0.01, atol=1e-14)
    assert nd.volume.sum() == pytest.approx(pt.volume.sum())
    # mass-weighted position reproduces node-level centroids: x = sum S m x / m
    for f in (0, 1):
        sel = pt.field == f
        assert (nd.mass[:, f, None] * nd.position[:, f]).sum(axis=0) == pytest.approx(
            pt.mass[sel] @ pt.x[sel])
    nodes = K.multimaterial_nodes(nd.mass)
    X = g.node_positions()[nodes]
    assert nodes.size > 0 and np.all(np.abs(X[:, 1] - 1.01) < 0.51)


# ------------------------------------------------------ inputs and errors ----

def test_solve_rejects_bad_options_naming_the_field():
    case = _block_case()
    with pytest.raises(CaseError, match="cell"):
        mpm.solve(case)
    with pytest.raises(CaseError, match="cell"):
        mpm.solve(case, cell=-1.0)
    with pytest.raises(CaseError, match="shape"):
        mpm.solve(case, cell=0.5, shape="cubic")
    with pytest.raises(CaseError, match="damping"):
        mpm.solve(case, cell=0.5, damping="lots")
    with pytest.raises(CaseError, match="cfl"):
        mpm.solve(case, cell=0.5, cfl=2.0)


def test_time_step_above_the_explicit_limit_is_refused_naming_it():
    case = _block_case()
    c = case.materials["m"].wave_speed("plane_stress")
    with pytest.raises(CaseError, match=rf"dt = {3.0 * 0.5 / c:.3g} s is above the stable explicit "
                                        rf"limit cell / wave speed = {0.5 / c:.3g} s"):
        mpm.solve(case, cell=0.5, dt=3.0 * 0.5 / c, damping="none", progress=False)


@pytest.mark.parametrize("angle", [17.0, 30.0, 45.0])
@pytest.mark.parametrize("traction", [(0.0, 1.0), (0.6, -0.8)])
def test_rotated_side_load_is_statically_equivalent_to_the_traction(angle, traction):
    """Loaded particles of a side that cuts the particle lattice: their forces have the
    resultant and the moment (about any point) of the uniform traction on the side."""
    from mpm.options import merge
    from mpm.solver import Model
    import math as _m
    c, s = _m.cos(_m.radians(angle)), _m.sin(_m.radians(angle))
    t_local = np.array(traction)
    t = np.array([c * t_local[0] - s * t_local[1], s * t_local[0] + c * t_local[1]])
    shape = Rectangle(0.3, 0.2, 3.0, 6.0, angle=angle)
    case = Case(name="rot", analysis="plane_stress", thickness=2.0,
                materials={"m": IsotropicElastic(E=1000.0, nu=0.3, rho=1e-9)},
                bodies=[Body("b", shape, "m")],
                boundary_conditions=[BoundaryCondition("traction", "b", "ymax", ("x", "y"),
                                                       tuple(t))])
    m = Model(case, merge(case, {"cell": 0.25, "progress": False}))
    pt = m.particles
    loaded = np.flatnonzero(np.any(pt.fext != 0.0, axis=1))
    F = pt.fext[loaded]
    L, T = 3.0, 2.0
    np.testing.assert_allclose(F.sum(axis=0), t * L * T, rtol=1e-12)
    # moment about the side's start corner: uniform traction -> resultant at mid-side
    start = shape.to_global(np.array([[0.0, 6.0]]))[0]
    mid = shape.to_global(np.array([[1.5, 6.0]]))[0]
    arm = pt.x0[loaded] - start
    moment = np.sum(arm[:, 0] * F[:, 1] - arm[:, 1] * F[:, 0])
    ref = (mid - start)[0] * (t * L * T)[1] - (mid - start)[1] * (t * L * T)[0]
    assert moment == pytest.approx(ref, rel=1e-10, abs=1e-12 * L * L * T)
    assert np.all(np.linalg.norm(F, axis=1) > 0.0)


def test_misspelled_option_is_refused_listing_the_valid_ones():
    """--option mpm.force_limting=false used to run silently with force limiting on."""
    with pytest.raises(CaseError, match=r"mpm option 'force_limting' is unknown; options: .*force_limiting"):
        mpm.solve(_block_case(), cell=0.5, force_limting=False, progress=False)


def test_dcb_grid_reaches_the_opened_arms():
    """The DCB's arms open by several millimetres at P = 1 N (002 Eq B.3): the MPM
    grid reaches beyond each arm's load-point deflection, with the ramp's overshoot
    (particles left the grid of 3 empty cells during the ramp)."""
    import cases
    from interfaces.analytic.dcb import dcb_deflection
    from mpm.options import merge
    from mpm.solver import Model
    for kw in ({"mpm_cell": 0.3}, {"mpm_cell": 0.3, "Dn": 0.3}):
        case = cases.build("dcb", P=1.0, **kw)
        grid = Model(case, merge(case, {})).grid
        tip = float(dcb_deflection(-25.0, 25.0, 0.6, 10.0, 10000.0, kw.get("Dn", math.inf),
                                   7808.0, 1.0))
        top = grid.origin[1] + grid.cell[1] * (grid.nn[1] - 1)
        assert grid.origin[1] <= -1.4 * tip and top >= 1.2 + 1.4 * tip


def test_interface_profile_leaves_out_the_slivers_of_a_neighbouring_node_row():
    """The DCB's Dn = 0.1 bond (0.3 mm cells): where the arms press together the lower
    arm's particle domains reach the node row above the bond line, whose nodes then see
    both fields with 4e-8..4e-4 of a bond node's contact area and jumps read from a few
    particle tails (+-9e-5 mm tangential, alternating node to node, on a bond whose
    particles have no tangential jump). The profile keeps the bond line."""
    from mpm.measure import interface_profile
    from mpm.multimaterial_constants import (NODE_OUT_COLUMNS, OUT_AREA, OUT_JUMP_N, OUT_JUMP_T,
                                             OUT_NY)
    grid = Grid(np.array([0.0, 0.0]), np.array([0.3, 0.3]), np.array([11, 5]))
    out = np.zeros((grid.N, NODE_OUT_COLUMNS))
    bond = 2 * 11 + np.arange(11)                       # the node row y = 0.6
    sliver = 3 * 11 + np.arange(6, 11)                  # part of the row above it
    out[bond, OUT_AREA], out[bond, OUT_JUMP_N] = 3.0, np.linspace(1e-3, 0.0, 11)
    out[sliver, OUT_AREA] = [1e-7, 4e-4, 1e-7, 1.3e-3, 4e-4]
    out[sliver, OUT_JUMP_T] = 9e-5 * (-1.0) ** np.arange(5)
    out[np.concatenate([bond, sliver]), OUT_NY] = 1.0
    prof = interface_profile(grid, out)
    np.testing.assert_array_equal(prof["y"], 0.6)
    np.testing.assert_allclose(np.sort(prof["x"]), 0.3 * np.arange(11))
    assert np.all(prof["jump_t"] == 0.0)
