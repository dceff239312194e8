"""Logistic-regression normals and separation (004 Sec 3.1, Eq 19-25, Appendix 53-57)."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from interfaces.laws import CoulombFriction
from mpm import multimaterial as mm
from mpm.multimaterial_lr import logistic_plane, lr_normals_separations
from mpm.extrapolation import field_volumes


def extrapolate(x, field, n_fields, origin, cell, nn, spacing):
    """Unit-density field mass (= volume) and volume gradient with uGIMP (mpm.shape)."""
    return field_volumes(x, field, n_fields, origin, cell, nn, spacing)


def block(x0, y0, x1, y1, h):
    xs = np.arange(x0 + h / 2, x1 - 1e-9, h)
    ys = np.arange(y0 + h / 2, y1 - 1e-9, h)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel()])


GRID = dict(origin=np.array([-5.0, -5.0]), cell=np.array([1.0, 1.0]), nn=np.array([11, 11]))
H = 0.5     # particle spacing: 2 x 2 particles per cell


def two_blocks(a_box, b_box, shift_b=(0.0, 0.0)):
    a = block(*a_box, H)
    b = block(*b_box, H) + np.asarray(shift_b)
    x = np.vstack([a, b])
    field = np.r_[np.zeros(len(a), np.int64), np.ones(len(b), np.int64)]
    mass, grad = extrapolate(x, field, 2, GRID["origin"], GRID["cell"], GRID["nn"], H)
    return x, field, mass, grad


def test_first_iteration_is_linear_regression_and_converges_on_separable_cloud():
    """Appendix: phi(0) = 0 makes step 1 the linear least-squares plane; the logistic
    iterations then converge (Eq 57 rule) to the symmetric separating line."""
    pts = np.array([[x, y] for x in (-0.75, -0.25, 0.25, 0.75) for y in (-0.75, -0.25, 0.25, 0.75)])
    cls = np.where(pts[:, 1] > 0, 1.0, -1.0)
    n = np.empty(2)
    it = logistic_plane(pts, cls, len(pts), 1e-7, n)
    assert 1 <= it <= 15
    np.testing.assert_allclose(n, [0.0, 1.0], atol=1e-12)


def test_lr_fixes_the_corner_node_of_fig3c():
    """004 Fig 3C: at a node on the corner of material a over a full edge of b, the AG
    normal (Eq 13) tilts by ~18 deg; LR stays (nearly) on the horizontal plane."""
    x, field, mass, grad = two_blocks((-3, 0, 0, 3), (-3, -3, 3, 0))
    node = 5 + 11 * 5                                     # node at (0, 0)
    out = np.empty(2)
    mm.normal_ag(grad[node, 0], grad[node, 1], out)
    tilt_ag = math.degrees(math.atan2(out[0], -out[1]))
    assert tilt_ag == pytest.approx(math.degrees(math.atan(1.0 / 3.0)), abs=1e-9)   # 18.43 deg
    nrm, sep = lr_normals_separations(x, field, np.array([H / 2, H / 2]), GRID["origin"],
                                      GRID["cell"], GRID["nn"], mass)
    tilt_lr = math.degrees(math.atan2(nrm[node, 0, 0], -nrm[node, 0, 1]))
    assert abs(tilt_lr) < 1.5
    np.testing.assert_allclose(nrm[node, 1], -nrm[node, 0])


@pytest.mark.parametrize("gap", [0.0, 0.1, -0.1, 0.3])
def test_lr_separation_is_the_gap_between_particle_edges(gap):
    """Eq 22-24 with R_p = half the particle spacing: d_LR equals the physical gap."""
    x, field, mass, _ = two_blocks((-4, 0, 4, 3), (-4, -3, 4, 0), shift_b=(0.0, -gap))
    nrm, sep = lr_normals_separations(x, field, np.array([H / 2, H / 2]), GRID["origin"],
                                      GRID["cell"], GRID["nn"], mass)
    multi = np.flatnonzero((mass > 0).sum(axis=1) >= 2)
    xs = GRID["origin"][0] + (multi % 11) * GRID["cell"][0]
    inner = multi[np.abs(xs) <= 2.0]
    assert len(inner) >= 5
    np.testing.assert_allclose(sep[inner, 0], gap, atol=1e-12)
    np.testing.assert_allclose(nrm[inner, 0], np.tile([0.0, -1.0], (len(inner), 1)), atol=1e-12)


def test_lr_radius_follows_the_deformation_gradient():
    """Eq 25: particles compressed along y (F = diag(1, 0.8)) have R_p = 0.8 h/2 along
    n = -y, so touching centres now show a gap of 2 x 0.2 h/2."""
    x, field, mass, _ = two_blocks((-4, 0, 4, 3), (-4, -3, 4, 0))
    F = np.tile(np.diag([1.0, 0.8]), (len(x), 1, 1))
    _, sep = lr_normals_separations(x, field, np.array([H / 2, H / 2]), GRID["origin"],
                                    GRID["cell"], GRID["nn"], mass, F=F)
    node = 5 + 11 * 5
    assert sep[node, 0] == pytest.approx(2 * 0.2 * H / 2, abs=1e-12)


@pytest.mark.parametrize("theta", [30.0, 63.0, 117.0])
def test_lr_normal_on_a_rotated_interface(theta):
    cell, R, h = 0.5, 5.0, 0.25
    k = np.arange(-R / h, R / h) + 0.5
    S, T = np.meshgrid(k * h, k * h, indexing="ij")
    n = np.array([math.cos(math.radians(theta)), math.sin(math.radians(theta))])
    t = np.array([-n[1], n[0]])
    local = np.column_stack([S.ravel(), T.ravel()])
    local = local[np.hypot(*local.T) < R]
    x = np.ascontiguousarray(local[:, :1] * n + local[:, 1:] * t + R + 3 * cell)
    field = (local[:, 0] > 0).astype(np.int64)
    nx = int(math.ceil((2 * R + 6 * cell) / cell)) + 1
    nn = np.array([nx, nx])
    mass, _ = extrapolate(x, field, 2, np.zeros(2), np.full(2, cell), nn, h)
    idx = np.arange(nx * nx)
    node_x = np.column_stack([idx % nx, idx // nx]) * cell
    inner = np.hypot(*(node_x - (R + 3 * cell)).T) < R - 2 * cell
    frac = mass.min(axis=1) / np.maximum(mass.sum(axis=1), 1e-300)
    both = inner & (frac > 1e-9)
    nrm, sep = lr_normals_separations(x, field, np.array([h / 2, h / 2]), np.zeros(2),
                                      np.full(2, cell), nn, mass)
    err = np.degrees(np.arccos(np.clip(nrm[both, 0] @ n, -1.0, 1.0)))
    good = frac[both] >= 0.02
    assert good.sum() >= 10
    assert err[good].max() < 2.0
    assert np.abs(sep[both, 0][good]).max() < 0.03 * cell
    assert err.max() < 15.0     # even nodes with a sliver of one field (MVG: > 90 deg there)


def test_lr_contact_detection_in_correct_momentum():
    """Approaching blocks: no correction while d_LR > 0, frictionless contact once the
    particle edges overlap (004 Eq 14 + 24)."""
    case = SimpleNamespace(bodies=[SimpleNamespace(name="a"), SimpleNamespace(name="b")],
                           interfaces=[SimpleNamespace(a="a", b="b", law=CoulombFriction(0.0), zones=[])],
                           dimension=2)
    tables = mm.build_pair_tables(case, {"normal": "LR", "separation": "LR"})
    for gap, expect in ((0.05, 0), (-0.05, 1)):
        x, field, mass, grad = two_blocks((-4, 0, 4, 3), (-4, -3, 4, 0), shift_b=(0.0, -gap))
        lr = lr_normals_separations(x, field, np.array([H / 2, H / 2]), GRID["origin"],
                                    GRID["cell"], GRID["nn"], mass)
        N = mass.shape[0]
        mom = np.zeros((N, 2, 2))
        mom[:, 0, 1] = -1.0 * mass[:, 0]      # a (top) moves down onto b
        s = dict(force=np.zeros((N, 2, 2)), disp=np.zeros((N, 2, 2)), pos=np.zeros((N, 2, 2)))
        multi = np.flatnonzero((mass > 0).sum(axis=1) >= 2)
        changed = mm.correct_momentum(0, mass, mom, s["force"], mass.copy(), grad, s["disp"],
                                      s["pos"], GRID["cell"], tables, 1e-3, 1.0, lr=lr, nodes=multi)
        if expect:
            assert changed >= 5
            v = mom[multi] / mass[multi][:, :, None]
            np.testing.assert_allclose(v[:, 0, 1], v[:, 1, 1], atol=1e-12)
        else:
            assert changed == 0


def test_lr_in_3d_finds_the_plane_and_gap():
    """3D point clouds (4^3-cell lattice, 2 particles per cell and axis): two boxes
    meeting on z = 0, the upper one lifted by a gap; normal a -> b = -z, d_LR = gap."""
    h, gap = 0.5, 0.2
    g = (np.arange(-4, 4) + 0.5) * h
    X, Y, Z = np.meshgrid(g, g, g, indexing="ij")
    x = np.column_stack([X.ravel(), Y.ravel(), Z.ravel()])
    field = (x[:, 2] < 0).astype(np.int64)          # a = 0 on top (z > 0), b = 1 below
    x[field == 0, 2] += gap
    origin, cell, nn = np.full(3, -3.0), np.ones(3), np.array([7, 7, 7])
    mass = np.zeros((343, 2))
    ij = np.stack(np.meshgrid(np.arange(7), np.arange(7), indexing="ij"), -1).reshape(-1, 2)
    inner = np.all(np.abs(ij - 3) <= 1, axis=1)
    nodes = ij[inner, 0] + 7 * (ij[inner, 1] + 7 * 3)   # nodes on z = 0, |x|, |y| <= 1
    mass[nodes] = 1.0
    nrm, sep = lr_normals_separations(x, field, np.full(3, h / 2), origin, cell, nn, mass,
                                      nodes=nodes)
    np.testing.assert_allclose(nrm[nodes, 0], np.tile([0.0, 0.0, -1.0], (len(nodes), 1)), atol=1e-10)
    np.testing.assert_allclose(sep[nodes, 0], gap, atol=1e-10)


@pytest.mark.parametrize("shape", ["cpdi", "b2cpdi"])
def test_point_cloud_is_the_particles_whose_shape_functions_reach_the_node(shape):
    """004 Sec 3.1: in CPDI runs a node's cloud holds the particles contributing to it.
    The support of each particle (mpm.multimaterial_lr._support_nodes) holds every node
    where its CPDI shape function (mpm.cpdi) is nonzero and none outside its stencil, for
    undeformed and sheared/stretched domains."""
    from mpm.cpdi import shape_cpdi
    from mpm.multimaterial_lr import _support_nodes
    from mpm.shape import SHAPE_CODES
    kind = SHAPE_CODES[shape]
    rng = np.random.default_rng(3)
    origin, cell, nn = np.zeros(2), np.array([1.0, 1.0]), np.array([12, 12])
    P = 300
    x = rng.uniform(4.0, 8.0, (P, 2))
    r0 = np.full((P, 2), 0.25)
    F = np.eye(2) + rng.uniform(-0.6, 0.6, (P, 2, 2))
    F[: P // 3] = np.eye(2)
    idx, S, G = np.empty(64, np.int64), np.empty(64), np.empty((64, 2))
    out = np.empty(64, np.int64)
    work = (np.empty(2), np.empty(2, np.int64), np.empty(2, np.bool_))
    for p in range(P):
        n = shape_cpdi(p, x, F, r0, origin, cell, nn, kind, idx, S, G)
        assert n > 0
        weight = {}
        for k in range(n):
            weight[idx[k]] = weight.get(idx[k], 0.0) + S[k]
        m = _support_nodes(p, x, r0, F, True, kind, origin, cell, nn, out, *work)
        support = set(out[:m].tolist())
        assert {i for i, w in weight.items() if w > 1e-14} <= support
        assert support <= set(weight)


@pytest.mark.parametrize("shape", ["cpdi", "b2cpdi"])
def test_support_clouds_gather_every_particle_reaching_each_node(shape):
    """The CSR clouds (mpm.multimaterial_lr._support_clouds), which enumerate the support
    only of particles with a domain corner near a requested node, equal the clouds read
    off every particle's support (:func:`_support_nodes`), in ascending particle order,
    also for particles at the grid's edges and sheared/stretched domains."""
    from mpm.multimaterial_lr import _support_clouds, _support_nodes
    from mpm.shape import SHAPE_CODES
    kind = SHAPE_CODES[shape]
    rng = np.random.default_rng(5)
    origin, cell, nn = np.zeros(2), np.array([1.0, 1.0]), np.array([12, 12])
    P = 400
    x = rng.uniform(0.1, 10.9, (P, 2))
    x[:40] = np.round(x[:40] * 4.0) / 4.0              # corners on node lines
    r0 = np.full((P, 2), 0.25)
    F = np.eye(2) + rng.uniform(-0.6, 0.6, (P, 2, 2))
    F[: P // 3] = np.eye(2)
    nodes = np.sort(rng.choice(int(nn.prod()), 30, replace=False)).astype(np.int64)
    start, members = _support_clouds(x, r0, F, True, kind, origin, cell, nn, nodes, int(nn.prod()))
    out = np.empty(64, np.int64)
    work = (np.empty(2), np.empty(2, np.int64), np.empty(2, np.bool_))
    expected = {int(i): [] for i in nodes}
    for p in range(P):
        for i in out[:_support_nodes(p, x, r0, F, True, kind, origin, cell, nn, out, *work)]:
            if int(i) in expected:
                expected[int(i)].append(p)
    assert sum(map(len, expected.values())) > 100
    for j, i in enumerate(nodes):
        assert members[start[j]:start[j + 1]].tolist() == expected[int(i)]


@pytest.mark.parametrize("d", [2, 3])
def test_particle_radius_is_the_distance_to_the_deformed_domain_ellipse(d):
    """004 Eq 25: R_p along n is the distance from the centre to the ellipse(oid)
    x(s) = F diag(R_0) s, |s| = 1, where it crosses the ray along n: found from the
    forward map alone (the best of a sampling, refined by minimising the angle to n)."""
    from scipy.optimize import minimize

    from mpm.multimaterial_lr import _particle_radius
    rng = np.random.default_rng(7)
    F = np.eye(d) + rng.uniform(-0.5, 0.5, (20, d, d))
    r0 = rng.uniform(0.1, 1.0, (20, d))

    def unit(a):                                    # angles -> point of the unit sphere
        if d == 2:
            return np.array([np.cos(a[0]), np.sin(a[0])])
        return np.array([np.sin(a[0]) * np.cos(a[1]), np.sin(a[0]) * np.sin(a[1]), np.cos(a[0])])

    grid = np.stack(np.meshgrid(*[np.linspace(0, np.pi * (2 if k == d - 1 else 1), 90)
                                  for k in range(d - 1)], indexing="ij"), -1).reshape(-1, d - 1)
    for p in range(20):
        n = rng.normal(size=d)
        n /= np.linalg.norm(n)

        def miss(a):                                # 1 - cos(angle between x(s) and n)
            xs = F[p] @ (r0[p] * unit(a))
            return 1.0 - xs @ n / np.linalg.norm(xs)

        a0 = grid[np.argmin([miss(a) for a in grid])]
        a = minimize(miss, a0, method="Nelder-Mead", options={"xatol": 1e-12, "fatol": 1e-16}).x
        assert miss(a) < 1e-12
        distance = np.linalg.norm(F[p] @ (r0[p] * unit(a)))
        assert _particle_radius(n, r0, F, p, True) == pytest.approx(distance, rel=1e-6)


def test_bodies_meeting_beside_a_rigid_floor_are_separated_from_each_other():
    """Blocks a (left) and b (right), 0.2 apart, both 0.15 above a rigid floor. At the node
    between them on the floor all three are present. A deformable field's lump is the
    other deformable fields there: the a -> b plane is the vertical mid-line (normal
    (1, 0), separation 0.2, by symmetry), and a's separation from the floor is kept
    apart (Eq 24 against the floor's particles alone). With the floor in a's lump the
    plane tilted towards the floor and a 'touched' b whenever it touched the floor."""
    from mpm.multimaterial_lr import lr_kernel
    from mpm.shape import SHAPE_CODES
    a = block(-3, 0, 0, 3, H) + (-0.1, 0.15)
    b = block(0, 0, 3, 3, H) + (0.1, 0.15)
    floor = block(-3, -3, 3, 0, H)
    x = np.vstack([a, b, floor])
    field = np.repeat(np.arange(3), [len(a), len(b), len(floor)]).astype(np.int64)
    mass, _ = extrapolate(x, field, 3, GRID["origin"], GRID["cell"], GRID["nn"], H)
    node = 5 + 11 * 5                                     # node at (0, 0)
    assert np.all(mass[node] > 0.0)
    n, m = mass.shape
    normal, sep, rigid_sep = np.zeros((n, m, 2)), np.zeros((n, m)), np.zeros((n, m))
    lr_kernel(x, field, np.full((len(x), 2), H / 2), np.zeros((1, 2, 2)), False, SHAPE_CODES["ugimp"],
              GRID["origin"], GRID["cell"], GRID["nn"], mass, np.array([node]), 0.0,
              np.array([0, 0, 1]), normal, sep, np.zeros((0, 0, 2)), np.zeros((0, 0)), rigid_sep)
    np.testing.assert_allclose(normal[node, 0], (1.0, 0.0), atol=1e-9)
    np.testing.assert_allclose(normal[node, 1], (-1.0, 0.0), atol=1e-9)
    np.testing.assert_allclose(sep[node, :2], 0.2, atol=1e-9)
    assert np.isnan(sep[node, 2]) and np.isnan(rigid_sep[node, 2])     # the floor takes no correction
    # the vertical gap is 0.15; the a-floor plane tilts a little (a on one side of the cloud)
    np.testing.assert_allclose(rigid_sep[node, :2], 0.15, atol=0.015)
