"""Arc-length continuation (Riks normal plane, ``path = "arc_length"``): a snap-through that load
control cannot pass, the same equilibrium as load control where both work, the option's refusal."""
import math

import numpy as np
import pytest

import peridynamics
from cases import library
from interfaces.errors import CaseError, SolverError
from peridynamics.assembly import CPDSystem, MaterialBlock, neighbour_lists
from peridynamics.newton import NewtonOptions, newton_solve

A, RISE = 1.0, 0.2          # von Mises truss: supports at (-A, 0), (A, 0), apex at (0, RISE)


def _truss():
    """Two CPD bonds (one-neighbour interactions only, unit volumes, C1 = 1) meeting at the apex;
    the horizon (1.5) holds the bars, not the span between the supports (2)."""
    X = np.array([[-A, 0.0], [A, 0.0], [0.0, RISE]])
    nptr, nidx = neighbour_lists(X, np.arange(3), 1.5)
    blk = MaterialBlock("bar", np.arange(3, dtype=np.int64), nptr, nidx, np.array([1.0, 0.0, 0.0]))
    return CPDSystem(X, np.ones(3), [blk], 1.5)


def _apex_force(w):
    """Closed form: each bond stores psi1 V^2 = 1/2 k (l - L)^2 with k = C1 V^2 / L (003 Eq 7, 10),
    so the downward apex force in equilibrium at deflection w is 2 k (L - l)(RISE - w) / l."""
    L = math.hypot(A, RISE)
    l = np.hypot(A, RISE - w)
    return 2.0 / L * (L - l) * (RISE - w) / l


def test_arc_length_passes_the_snap_through_of_a_two_bond_truss():
    """Force 1.5 x the limit load at the apex: load control stops at the limit point (the tangent
    turns indefinite); the arc length follows the path over the limit point, through negative
    load factors (the snap-back between w = RISE and 2 RISE) up to load factor 1 on the inverted
    branch, w > 2 RISE, where the closed-form equilibrium holds to round-off."""
    f_limit = _apex_force(np.linspace(0.0, RISE, 200001)).max()
    F = 1.5 * f_limit
    fixed = np.arange(4)
    f_ext = np.zeros(6)
    f_ext[5] = -F
    with pytest.raises(SolverError, match="indefinite"):
        newton_solve(_truss(), fixed, np.zeros(6), f_ext, NewtonOptions(load_steps=10, max_cuts=3))
    out = newton_solve(_truss(), fixed, np.zeros(6), f_ext, NewtonOptions(load_steps=10, path="arc_length"))
    w = -out.u[5]
    assert w > 2 * RISE
    assert abs(_apex_force(w) - F) < 1e-12 * F
    loads = np.array([h["load"] for h in out.history])
    assert loads[-1] == 1.0 and out.history[-1]["residuals"][-1] <= 1e-11
    first_turn = int(np.flatnonzero(np.diff(loads) < 0)[0])                      # the path turned back
    assert loads[: first_turn + 1].max() <= 1.0 / 1.5 * (1 + 1e-9)               # not above the limit load
    assert loads.min() < 0                                                         # and snapped through
    assert out.history[0]["t_lam"] > 0 and any(h["t_lam"] < 0 for h in out.history)
    # two limit points flagged, each on the first arc past it: the limit load (t_lam turns negative)
    # and the snap-back minimum (t_lam positive again)
    flags = [h["limit_point"] for h in out.history]
    assert sum(flags) == 2
    i, j = [k for k, f in enumerate(flags) if f]
    signs = np.sign([h["t_lam"] for h in out.history])
    assert np.all(signs[:i] > 0) and np.all(signs[i:j] < 0) and np.all(signs[j:] > 0)


def test_arc_length_reaches_the_load_control_equilibrium_at_finite_stretch():
    """003 Sec 4.4: 100 % stretch of the bimaterial square (a curved path). Two equilibria exist at
    load factor 1 on this coarse grid: 20 load steps and the arc length (4 arcs) follow the path to
    the one of lower energy, 003 Table 3's five steps jump to another (measured: energy 8.515883e-6
    against 8.515901e-6, displacements 7e-4 apart). The arc length ends on the first to the Newton
    tolerance."""
    case = library.bimaterial_square(parameter_set=2, load_case=1, interface="vertical", strain_scale=1000.0)
    ref = peridynamics.solve(case, h=0.1, load_steps=20)
    res = peridynamics.solve(case, h=0.1, load_steps=4, path="arc_length")
    hist = res.diagnostics["newton_history"]
    assert [h["path"] for h in hist][-1] == "final load step" and len(hist) >= 2
    assert hist[-1]["residuals"][-1] <= 1e-11
    u, u_ref = res.fields["displacement"], ref.fields["displacement"]
    assert np.abs(u - u_ref).max() < 1e-9 * np.abs(u_ref).max()
    assert res.quantities["strain_energy"] == pytest.approx(ref.quantities["strain_energy"], rel=1e-10)


def test_path_option_is_checked():
    case = library.bimaterial_square(parameter_set=1, load_case=1)
    with pytest.raises(CaseError, match="cpd.path must be one of load, arc_length"):
        peridynamics.solve(case, h=0.1, path="riks")


def _same_equilibrium(res, ref):
    hist = res.diagnostics["newton_history"]
    assert hist[-1]["path"] == "final load step" and hist[-1]["residuals"][-1] <= 1e-11
    u, u_ref = res.fields["displacement"], ref.fields["displacement"]
    assert np.abs(u - u_ref).max() < 1e-8 * np.abs(u_ref).max()
    assert res.quantities["strain_energy"] == pytest.approx(ref.quantities["strain_energy"], rel=1e-9)
    return hist


def test_arc_length_on_a_small_cuboid_with_three_neighbour_interactions():
    """3D, C3 < 0 in material A (003 Sec 4.5 materials, coarse grid): two arcs to the load-control
    equilibrium; the path rises all along (t_lam > 0: no limit point at 0.1 %)."""
    case = library.cuboid(interface="horizontal", load_case=1, size=(0.4, 0.2, 0.2))
    ref = peridynamics.solve(case, h=0.05, delta_factor=2.01)
    res = peridynamics.solve(case, h=0.05, delta_factor=2.01, path="arc_length", load_steps=2)
    hist = _same_equilibrium(res, ref)
    assert all(h["t_lam"] > 0 for h in hist)


@pytest.mark.slow
def test_arc_length_on_the_cuboid_with_soft_surface_modes():
    """0.5 x 0.4 x 0.4 at the paper's spacing (3024 points; 4 negative tangent eigenvalues at A's
    free faces, C3 < 0): the arc length ends on the equilibrium of plain Newton (which converges at
    this size), with indefinite factors along the path (negative pivots > 0) and a rising path."""
    case = library.cuboid(interface="horizontal", load_case=2, size=(0.5, 0.4, 0.4))
    ref = peridynamics.solve(case, h=0.035, progress=False)
    res = peridynamics.solve(case, h=0.035, progress=False, path="arc_length", load_steps=2)
    hist = _same_equilibrium(res, ref)
    assert all(h["t_lam"] > 0 for h in hist)
    assert all(h["negative_pivots"] > 0 for h in hist)
