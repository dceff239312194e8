"""XPIC(m) and multimaterial XPIC(m) particle updates (mpm/xpic.py; 004 Sec 3.3, Eq 35-48).

* XPIC(1) is PIC (004 Eq 38): the same run with ``xpic = 1`` and with ``pic = 1``
  agrees to round-off, one material or two bonded ones, uGIMP, linear, B2, CPDI and
  B2-CPDI shapes;
* velocity conditions (and B2 ghost nodes) keep their v+ in the XPIC grid velocity;
* the projection conserves the total momentum (the S+ S passes preserve the
  mass-weighted sums, and the Delta v terms of the fields cancel);
* a free bar vibrating in its first axial mode (closed form: v = v0 cos(pi x / L)
  cos(omega t), omega = pi c / L) with null-space noise added to the particle
  velocities: PIC dissipates the mode, FLIP keeps the noise, XPIC(5) does neither;
* a bar split in two bodies bonded by a perfect interface: multimaterial XPIC(m)
  follows single-material XPIC(m) away from the interface (004 Eq 47) and the
  uncorrected variant departs from it at the interface by more (Eq 48).
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import mpm
from cases.library import two_layer
from interfaces import (Body, Case, CaseError, InterfacePair, IsotropicElastic, LinearInterface,
                        Rectangle)
from mpm.options import merge
from mpm.solver import Model, _Runner

L, H, E, RHO, V0 = 40.0, 4.0, 1000.0, 1e-9, 1.0
C = math.sqrt(E / RHO)            # nu = 0: the plane-strain bar wave speed
PERIOD = 2.0 * L / C              # first free-free axial mode


def _bar(split: bool = False, contact: bool = False) -> Case:
    mat = IsotropicElastic(E=E, nu=0.0, rho=RHO)
    if not split:
        return Case(name="bar", analysis="plane_strain", thickness=1.0, materials={"m": mat},
                    bodies=[Body("a", Rectangle(0.0, 0.0, L, H), "m")])
    law = LinearInterface(Dn=math.inf, Dt=math.inf)
    return Case(name="bar", analysis="plane_strain", thickness=1.0, materials={"m": mat},
                bodies=[Body("a", Rectangle(0.0, 0.0, 0.4 * L, H), "m"),
                        Body("b", Rectangle(0.4 * L, 0.0, 0.6 * L, H), "m")],
                interfaces=[InterfacePair("a", "b", law)])


def _model(case: Case, opts: dict, noise: float = 0.0, seed: int = 1) -> tuple[Model, _Runner]:
    """The bar in its first mode, v = V0 cos(pi x / L), plus particle noise."""
    model = Model(case, merge(case, dict({"cell": 1.0, "damping": "none", "update": "usl",
                                          "progress": False}, **opts)))
    pt = model.particles
    pt.v[:, 0] = V0 * np.cos(np.pi * pt.x[:, 0] / L)
    if noise:
        pt.v += noise * V0 * np.random.default_rng(seed).standard_normal(pt.v.shape)
    return model, _Runner(model)


def _advance(case: Case, opts: dict, steps: int, noise: float = 0.0):
    model, run = _model(case, opts, noise)
    hist = run._advance(steps)
    return model, hist


def test_xpic_options_are_checked_naming_the_field():
    case = _bar()
    for bad in (-1, 2.5, "five", True, 51):
        with pytest.raises(CaseError, match="option xpic must be an integer"):
            merge(case, {"cell": 1.0, "xpic": bad})
    with pytest.raises(CaseError, match="xpic_correction must be true or false"):
        merge(case, {"cell": 1.0, "xpic": 2, "xpic_correction": "no"})
    assert merge(case, {"cell": 1.0})["pic"] == 0.0
    opts = merge(case, {"cell": 1.0, "xpic": 5})
    assert opts["pic"] == 1.0 and opts["xpic"] == 5 and opts["xpic_correction"] is True
    assert merge(case, {"cell": 1.0, "xpic": None})["xpic"] == 0


@pytest.mark.parametrize("split, shape", [(False, "ugimp"), (True, "ugimp"), (False, "linear"),
                                          (True, "b2"), (True, "cpdi"), (False, "b2cpdi")])
def test_xpic1_is_pic_to_round_off(split, shape):
    """004 Eq 38: XPIC(1) maps the updated grid velocity of each field to its particles."""
    steps = 60
    a, _ = _advance(_bar(split), {"xpic": 1, "shape": shape}, steps, noise=0.05)
    b, _ = _advance(_bar(split), {"pic": 1.0, "shape": shape}, steps, noise=0.05)
    for key in ("x", "v", "stress"):
        pa, pb = getattr(a.particles, key), getattr(b.particles, key)
        assert np.abs(pa - pb).max() <= 1e-12 * np.abs(pb).max(), key
    # and the blend: pic = 0.3 of XPIC(1) is pic = 0.3 of PIC
    a, _ = _advance(_bar(split), {"xpic": 1, "pic": 0.3}, steps, noise=0.05)
    b, _ = _advance(_bar(split), {"pic": 0.3}, steps, noise=0.05)
    assert np.abs(a.particles.v - b.particles.v).max() <= 1e-12 * np.abs(b.particles.v).max()


@pytest.mark.parametrize("split", [False, True])
@pytest.mark.parametrize("m, update", [(2, "usl"), (5, "usl"), (5, "musl"), (5, "usf")])
def test_xpic_conserves_momentum_and_mass(split, m, update):
    model, run = _model(_bar(split), {"xpic": m, "update": update}, noise=0.3)
    pt = model.particles
    p0 = (pt.mass[:, None] * pt.v).sum(axis=0)
    run._advance(40)
    p1 = (pt.mass[:, None] * pt.v).sum(axis=0)
    scale = (pt.mass * np.abs(pt.v).max()).sum()
    assert np.abs(p1 - p0).max() < 1e-12 * scale
    assert model.nodal.mass.sum() == pytest.approx(pt.mass.sum(), rel=1e-12)


def test_xpic_keeps_the_velocity_conditions():
    """A bar fixed at x = 0 (B2: a symmetry side with ghost nodes): the XPIC(5) grid
    velocity keeps the conditioned components (and the reflected ghosts), so the
    particles at the fixed end stay."""
    from interfaces import BoundaryCondition
    for shape in ("ugimp", "b2"):
        case = _bar()
        case.boundary_conditions.append(BoundaryCondition("fixed", "a", "xmin", ("x",), (0.0,)))
        model, run = _model(case, {"xpic": 5, "shape": shape})
        run._advance(30)
        bc, nd = model.bcs, run.bundles[3]
        vt = nd.xpic[6]          # slot VS: the XPIC grid velocity v~ of the last step
        assert np.array_equal(vt[bc.node, bc.field, bc.comp],
                              nd.velocity[bc.node, bc.field, bc.comp])
        if bc.ghosts is not None and bc.ghosts.node.size:   # B2: reflected, as G2P sees them
            g = bc.ghosts
            assert np.array_equal(vt[g.node, g.field], nd.velocity[g.node, g.field])
        else:
            assert np.all(vt[bc.node, bc.field, bc.comp] == 0.0)
        pt = model.particles
        first = pt.x0[:, 0] < 0.3
        assert np.abs(pt.x[first, 0] - pt.x0[first, 0]).max() < 0.02


def _mode_and_noise(model) -> tuple[float, float]:
    """(amplitude of the first mode in the particle velocities, rms of the rest) / V0."""
    pt = model.particles
    shape = np.cos(np.pi * pt.x0[:, 0] / L)
    amp = float((pt.mass * pt.v[:, 0] * shape).sum() / (pt.mass * shape ** 2).sum())
    rest = pt.v.copy()
    rest[:, 0] -= amp * shape
    rms = float(np.sqrt((pt.mass[:, None] * rest ** 2).sum() / pt.mass.sum()))
    return amp / V0, rms / V0


def _vibrate(opts: dict, periods: float = 2.0, noise: float = 0.05):
    model, run = _model(_bar(), opts, noise)
    steps = int(round(periods * PERIOD / model.dt))
    hist = run._advance(steps)
    energy = hist[:, 1] + hist[:, 2]
    amp, rest = _mode_and_noise(model)
    return {"amplitude": amp, "noise": rest, "energy_loss": 1.0 - energy[-1] / energy[0],
            "time": float(hist[-1, 0])}


def test_vibrating_bar_xpic_keeps_the_mode_and_filters_the_noise():
    """Two periods of the first mode with 5 % particle noise; closed form: amplitude
    cos(omega t) = 1 at t = 2 T, no energy lost. Measured (amplitude, rms of the rest
    / V0, energy lost): FLIP 0.9976, 0.059, 0.6 %; PIC 0.830, 0.0033, 31 %; XPIC(5)
    0.9976, 0.0041, 0.5 %."""
    flip = _vibrate({})
    pic = _vibrate({"pic": 1.0})
    xpic = _vibrate({"xpic": 5})
    closed = math.cos(2.0 * math.pi * xpic["time"] / PERIOD)
    assert closed == pytest.approx(1.0, abs=1e-9)
    # PIC dissipates the mode, XPIC(5) keeps it as FLIP does
    assert pic["amplitude"] < 0.9 and pic["energy_loss"] > 0.2
    assert abs(xpic["amplitude"] - closed) < 0.008
    assert abs(xpic["amplitude"] - flip["amplitude"]) < 1e-3
    assert xpic["energy_loss"] < 0.015
    # FLIP keeps the null-space noise, XPIC(5) filters it nearly as well as PIC
    assert flip["noise"] > 0.04
    assert xpic["noise"] < 0.012 and xpic["noise"] < 0.2 * flip["noise"]


def _sorted_state(opts: dict, split: bool, steps: int):
    model, run = _model(_bar(split), opts)
    run._advance(steps)
    pt = model.particles
    order = np.lexsort((pt.x0[:, 1], pt.x0[:, 0]))
    return pt.x0[order], pt.v[order], pt.stress[order]


def _split_departure(opts: dict, steps: int = 400) -> dict:
    """Largest particle velocity / stress departure of the bonded split bar from the
    one-body bar under the same options, within two cells of the interface and beyond."""
    base = {k: v for k, v in opts.items() if k != "xpic_correction"}
    x0, v1, s1 = _sorted_state(base, False, steps)
    _, v2, s2 = _sorted_state(opts, True, steps)
    near = np.abs(x0[:, 0] - 0.4 * L) <= 2.0
    dv = np.abs(v2 - v1).max(axis=1) / V0
    ds = np.abs(s2 - s1).max(axis=1) / np.abs(s1).max()
    return {"v_near": dv[near].max(), "v_far": dv[~near].max(),
            "s_near": ds[near].max(), "s_far": ds[~near].max()}


def test_bonded_split_bar_multimaterial_xpic_follows_single_material():
    """2.5 periods of the first mode, perfect interface at 0.4 L. FLIP: identical to
    round-off (004 Eq 34). Multimaterial XPIC(5) (Eq 47), measured |dV| / V0: 1.4e-6
    beyond two cells of the interface, 2.0e-5 within. Uncorrected (Eq 48): 1.7e-3
    and 3.2e-2, the stresses 10-25 % of their peak."""
    flip = _split_departure({})
    assert max(flip.values()) < 1e-12
    mm = _split_departure({"xpic": 5})
    assert mm["v_far"] < 5e-6 and mm["v_near"] < 1e-4
    assert mm["s_far"] < 3e-4 and mm["s_near"] < 3e-4
    unc = _split_departure({"xpic": 5, "xpic_correction": False})
    assert unc["v_near"] > 100.0 * mm["v_near"] and unc["v_near"] > 5.0 * unc["v_far"]
    assert unc["s_near"] > 100.0 * mm["s_near"]


@pytest.mark.parametrize("shape", ["cpdi", "b2cpdi"])
def test_bonded_split_bar_xpic_with_cpdi_shapes_follows_single_material(shape):
    """The CPDI shapes' node lists (mpm/xpic.py stencils_cpdi) in the test above. Measured
    |dV| / V0 beyond two cells of the interface / within: FLIP 2e-15 (both shapes);
    XPIC(5) 1.3e-6 / 1.9e-5 (CPDI), 2.7e-6 / 3.5e-5 (B2-CPDI), stresses 5e-5 / 2.3e-4 of
    their peak; uncorrected 1.7e-3 / 3.2e-2 and 5.7e-3 / 4.4e-2, stresses 26 / 57 %."""
    flip = _split_departure({"shape": shape})
    assert max(flip.values()) < 1e-12
    mm = _split_departure({"xpic": 5, "shape": shape})
    assert mm["v_far"] < 1e-5 and mm["v_near"] < 1.5e-4
    assert mm["s_far"] < 1e-3 and mm["s_near"] < 1e-3
    unc = _split_departure({"xpic": 5, "xpic_correction": False, "shape": shape})
    assert unc["v_near"] > 100.0 * mm["v_near"] and unc["v_near"] > 5.0 * unc["v_far"]
    assert unc["s_near"] > 100.0 * mm["s_near"]


def test_uncorrected_xpic_changes_nothing_without_contact_corrections():
    """The Delta v term only exists where the initial extrapolation was corrected: one
    body, and XPIC(1) of a split body, are the same with and without it."""
    for split, m in ((False, 5), (True, 1)):
        _, a, _ = _sorted_state({"xpic": m}, split, 50)
        _, b, _ = _sorted_state({"xpic": m, "xpic_correction": False}, split, 50)
        assert np.array_equal(a, b)


def test_xpic_in_3d_conserves_momentum():
    """The kernels are written for any D: a free 3D block with random velocities."""
    from interfaces import Box
    mat = IsotropicElastic(E=E, nu=0.3, rho=RHO)
    case = Case(name="box", analysis="3d", thickness=1.0, materials={"m": mat},
                bodies=[Body("a", Box(0.0, 0.0, 0.0, 4.0, 3.0, 3.0), "m"),
                        Body("b", Box(4.0, 0.0, 0.0, 3.0, 3.0, 3.0), "m")],
                interfaces=[InterfacePair("a", "b", LinearInterface(Dn=math.inf, Dt=math.inf))])
    model = Model(case, merge(case, {"cell": 1.0, "damping": "none", "xpic": 4,
                                     "progress": False}))
    pt = model.particles
    pt.v[:] = np.random.default_rng(3).standard_normal(pt.v.shape)
    p0 = (pt.mass[:, None] * pt.v).sum(axis=0)
    ke0 = 0.5 * (pt.mass[:, None] * pt.v ** 2).sum()
    hist = _Runner(model)._advance(20)
    p1 = (pt.mass[:, None] * pt.v).sum(axis=0)
    assert np.abs(p1 - p0).max() < 1e-12 * (pt.mass * np.abs(pt.v).max()).sum()
    # the filter removes the random (mostly null-space) velocities; counted as dissipated
    assert hist[:, 4].sum() > 0.5 * ke0


def test_checkpoint_resume_is_bit_identical_with_xpic(tmp_path, interrupt_mpm):
    case = two_layer(mpm_cell=1.0)
    ref = mpm.solve(case, progress=False, xpic=3)
    path = tmp_path / "mpm.npz"
    opts = {"progress": False, "checkpoint": str(path), "checkpoint_every": 1e9, "xpic": 3}
    patch = interrupt_mpm(5)
    with pytest.raises(KeyboardInterrupt):
        mpm.solve(case, **opts)
    patch.undo()
    res = mpm.solve(case, resume=True, **opts)
    assert res.diagnostics["time_steps"] == ref.diagnostics["time_steps"]
    for key in ("displacement", "stress", "velocity"):
        assert np.array_equal(res.fields[key], ref.fields[key]), key
    assert res.diagnostics["history"] == ref.diagnostics["history"]


def _stencil_cloud(kind: int, nx: int, ny: int, M: int = 2, seed: int = 4):
    """Particles of a 2-per-cell lattice over the grid (uGIMP supports within one cell:
    P2G's 2-node supports in a 3-node window) and 40 displaced ones (supports across a
    node line), of ``M`` random fields, with their P2G stencils: (x, pmass, field, grid
    origin, cell, nn, lp, node, wgt)."""
    from mpm import xpic
    from mpm.kernels import p2g_range_2d
    rng = np.random.default_rng(seed)
    h = 1.0
    origin, cell = np.zeros(2), np.full(2, h)
    nn = np.array([nx, ny])
    gx = (np.arange(2, 2 * nx - 6) + 0.5) * 0.5 * h
    gy = (np.arange(2, 2 * ny - 6) + 0.5) * 0.5 * h
    lattice = np.array([(a, b) for a in gx for b in gy])
    x = np.concatenate([lattice, lattice[:40] + rng.uniform(-0.2, 0.2, (40, 2)) * h])
    P, N = x.shape[0], nx * ny
    lp = np.full(2, 0.25 * h)
    field = rng.integers(0, M, P)
    pmass = rng.uniform(0.5, 2.0, P)
    _, node, wgt = xpic.stencil_arrays(P, 2, False, 5)
    nodal = [np.zeros((N, M)), np.zeros((N, M, 2)), np.zeros((N, M, 2))]
    lost = p2g_range_2d(0, P, x, np.zeros((P, 2)), pmass, np.ones(P), np.zeros((P, 3)), field,
                        x, origin, cell, nn, lp, kind, False, True, *nodal, nodal[0],
                        nodal[1], nodal[1], nodal[1], node, wgt)
    assert lost == -1
    return x, pmass, field, origin, cell, nn, lp, node, wgt


@pytest.mark.parametrize("kind", [mpm.shape.LINEAR, mpm.shape.UGIMP, mpm.shape.B2])
def test_projection_passes_equal_the_shape_function_matrices(kind):
    """The 2D passes on the step's 3 x 3 stencils (written by P2G: mpm/kernels.py
    p2g_range_2d) against matrices built particle by particle from mpm.shape.shape_2d:
    the S+ S pass is sum_p m_p S_ip (S w)_p per field (two series in one loop: the V and
    Delta v slots); and G2P's XPIC blend (mpm/kernels.py g2p_range_2d, beta = 1/2, dt =
    1, from V = 0), on the particles of :func:`_stencil_cloud`."""
    import scipy.sparse as sp

    from mpm import xpic
    from mpm.shape import shape_2d
    rng = np.random.default_rng(4)
    nx, ny, M = 9, 8, 2
    x, pmass, field, origin, cell, nn, lp, node, wgt = _stencil_cloud(kind, nx, ny, M)
    P, N = x.shape[0], nx * ny
    idx, S, G = np.empty(9, np.int64), np.empty(9), np.empty((9, 2))
    rows, cols, vals = [], [], []
    for p in range(P):
        c = shape_2d(x[p, 0], x[p, 1], origin, cell, nn, lp, kind, idx, S, G)
        rows += [p] * c
        cols += list(idx[:c])
        vals += list(S[:c])
    Smat = sp.csr_matrix((vals, (rows, cols)), shape=(P, N))
    work = np.zeros((xpic.N_SLOTS, N, M, 2))
    for slot in (xpic.VK, xpic.DK, xpic.VS):
        work[slot] = rng.standard_normal((N, M, 2))
    nvel = rng.standard_normal((N, M, 2))
    xpic.scatter_passes(x, pmass, field, origin, cell, nn, lp, kind, work, xpic.VK, xpic.VN,
                        xpic.DK, xpic.DN, node, wgt, np.ones(N * M, np.bool_))
    v, dx = _g2p_blend(x, pmass, field, origin, cell, nn, lp, kind, work[xpic.VS], nvel, 0.5)
    for f in range(M):
        Sf = sp.diags((field == f).astype(float)) @ Smat
        for src, dst in ((xpic.VK, xpic.VN), (xpic.DK, xpic.DN)):
            expected = Sf.T @ (pmass[:, None] * (Sf @ work[src, :, f]))
            assert np.allclose(work[dst, :, f], expected, rtol=1e-13, atol=1e-13)
        mine = field == f
        s_vtil, s_vel = (Smat @ work[xpic.VS, :, f])[mine], (Smat @ nvel[:, f])[mine]
        assert np.allclose(v[mine], 0.5 * s_vtil, rtol=1e-13, atol=1e-13)
        assert np.allclose(dx[mine], s_vel + 0.5 * (s_vtil - s_vel), rtol=1e-13, atol=1e-13)


def _g2p_blend(x, pmass, field, origin, cell, nn, lp, kind, vtil, nvel, beta):
    """G2P with the XPIC blend ``beta`` from V = 0, dt = 1, no acceleration and no
    stress update: (V, x change), i.e. (beta S v~, S v+ + beta S (v~ - v+))."""
    from mpm.kernels import g2p_range_2d
    P, M = x.shape[0], nvel.shape[1]
    v, xb = np.zeros((P, 2)), x.copy()
    zeros3 = np.zeros((P, 3))
    g2p_range_2d(0, P, xb, v, pmass, np.ones(P), np.ones(P), zeros3, zeros3.copy(), field,
                 np.zeros((P, 2)), np.zeros((P, 2)), 1.0, np.zeros((M, 3, 3)), origin, cell, nn,
                 lp, kind, 1.0, 0.0, False, nvel, np.zeros_like(nvel), np.zeros((P, 2, 2)),
                 np.zeros(M, np.int64), beta, vtil.reshape(-1))
    return v, xb - x


@pytest.mark.parametrize("m", [3, 5, 8])
def test_delta_v_series_on_its_band_equals_the_series_over_every_particle(m):
    """Delta v (004 Eq 26) lives on the multimaterial nodes; the 2D passes scatter its
    series (Eq 44) only for the particles whose window is centred within 2 m - 5 nodes of
    one (mpm.xpic.delta_v_band). On a 40 x 12 grid with Delta v on two nodes of one
    column, v~ equals, bit for bit, the v~ of the series scattered by every particle
    (the band of all nodes), and the band is narrower than the grid."""
    from mpm import xpic
    nx, ny, M = 40, 12, 2
    x, pmass, field, origin, cell, nn, lp, node, wgt = _stencil_cloud(mpm.shape.UGIMP, nx, ny, M)
    N = nx * ny
    rng = np.random.default_rng(5)
    mass = rng.uniform(1.0, 2.0, (N, M))
    nacc = rng.standard_normal((N, M, 2))
    nodes = np.array([5 * nx + 20, 6 * nx + 20])
    v0 = rng.standard_normal((N, M, 2))
    vtil = []
    for band_nodes in (nodes, np.arange(N)):
        work = np.zeros((xpic.N_SLOTS, N, M, 2))
        work[xpic.V0] = v0
        work[xpic.DV, nodes] = np.array([[[0.3, -0.2], [-0.1, 0.4]], [[0.2, 0.1], [0.0, -0.5]]])
        xpic.xpic_grid_velocity(m, True, x, pmass, field, origin, cell, nn, lp,
                                mpm.shape.UGIMP, mass, nacc, 1e-3, work, node, wgt, band_nodes)
        vtil.append(work[xpic.VS].copy())
    assert np.array_equal(vtil[0], vtil[1])
    assert xpic.delta_v_band(m, nn, M, nodes).sum() < N * M
