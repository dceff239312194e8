"""Unit tests of mpm.multimaterial on synthetic nodal arrays (000, 002 Sec 2.4, 004).

Every expected value is a closed form from the papers' equations evaluated here
independently of the kernels, or a physical invariant (momentum balance, equal
velocities, energy of a spring).
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from interfaces.case import InterfacePair
from interfaces.errors import CaseError
from interfaces.laws import BilinearNormalInterface, CoulombFriction, LinearInterface, StickContact
from mpm import multimaterial as mm
from mpm.extrapolation import field_volumes
from mpm.multimaterial_constants import (
    NODE_OUT_COLUMNS, OUT_AREA, OUT_ENERGY, OUT_JUMP_N, OUT_JUMP_T, OUT_STATUS, OUT_TRACTION_N,
    OUT_TRACTION_T, STATUS_LIMITED_N, STATUS_LIMITED_T, STATUS_OVER_LIMIT, STATUS_SCREENED,
)

RNG = np.random.default_rng(1234)


def make_case(n_bodies=2, pairs=(), dim=2):
    bodies = [SimpleNamespace(name=f"b{k}") for k in range(n_bodies)]
    interfaces = [InterfacePair(f"b{p[0]}", f"b{p[1]}", p[2], list(p[3:])) for p in pairs]
    return SimpleNamespace(bodies=bodies, interfaces=interfaces, dimension=dim)


def nodal(n_nodes=4, n_fields=2, dim=2, cell=1.0, thickness=1.0):
    """Random but physical nodal state with all fields present on every node."""
    mass = RNG.uniform(0.5, 2.0, (n_nodes, n_fields))
    mom = RNG.normal(size=(n_nodes, n_fields, dim)) * mass[:, :, None]
    force = RNG.normal(size=(n_nodes, n_fields, dim))
    cellv = cell ** dim * (thickness if dim == 2 else 1.0)
    vol = np.full((n_nodes, n_fields), cellv / n_fields)
    grad = np.zeros((n_nodes, n_fields, dim))
    disp = np.zeros((n_nodes, n_fields, dim))
    pos = np.zeros((n_nodes, n_fields, dim))
    return dict(mass=mass, momentum=mom, force=force, volume=vol, volume_gradient=grad,
                displacement=disp, position=pos, cell=np.full(dim, cell))


def correct(phase, s, tables, dt=1e-3, thickness=1.0):
    return mm.correct_momentum(phase, s["mass"], s["momentum"], s["force"], s["volume"],
                               s["volume_gradient"], s["displacement"], s["position"], s["cell"],
                               tables, dt, thickness)


def interface(s, tables, dt=1e-3, thickness=1.0, out=None):
    return mm.add_interface_forces(s["mass"], s["momentum"], s["volume"], s["volume_gradient"],
                                   s["displacement"], s["position"], s["cell"], thickness, tables,
                                   dt, s["force"], out)


def velocities(s):
    return s["momentum"] / s["mass"][:, :, None]


def sn(law, normal, **opts):
    return mm.build_pair_tables(make_case(2, [(0, 1, law)], dim=len(normal)),
                                {"normal": "SN", "normal_vector": normal, **opts})


# ---------------------------------------------------------------- momentum corrections


@pytest.mark.parametrize("dim", [2, 3])
@pytest.mark.parametrize("phase", [0, 1])
def test_perfect_pair_moves_with_centre_of_mass(dim, phase):
    """000 Eq 7-8: a perfect (bonded) pair ends at the centre-of-mass velocity, sum p kept;
    phase 1 adds dp/dt to the force (004 Eq 33, f_C,1)."""
    s = nodal(5, 2, dim)
    p0 = s["momentum"].copy()
    f0 = s["force"].copy()
    tables = mm.build_pair_tables(make_case(2, [(0, 1, LinearInterface(math.inf, math.inf))], dim), {})
    dt = 2e-3
    assert correct(phase, s, tables, dt) == 5
    v = velocities(s)
    vcm = p0.sum(axis=1) / s["mass"].sum(axis=1)[:, None]
    np.testing.assert_allclose(v[:, 0], vcm, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(v[:, 1], vcm, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(s["momentum"].sum(axis=1), p0.sum(axis=1), rtol=1e-13, atol=1e-13)
    if phase == 0:
        np.testing.assert_array_equal(s["force"], f0)
    else:
        np.testing.assert_allclose(s["force"] - f0, (s["momentum"] - p0) / dt, rtol=1e-10, atol=1e-9)


def test_default_law_for_unlisted_pair_is_perfect_and_configurable():
    case = make_case(2, [])
    s = nodal(3)
    correct(0, s, mm.build_pair_tables(case, {}))
    v = velocities(s)
    np.testing.assert_allclose(v[:, 0], v[:, 1], atol=1e-12)
    s = nodal(3)
    p0 = s["momentum"].copy()
    assert correct(0, s, mm.build_pair_tables(case, {"default_law": "none"})) == 0
    np.testing.assert_array_equal(s["momentum"], p0)


def two_field_contact_state(v_a, v_b, m_a=1.0, m_b=3.0, gap=0.0, normal=(1.0, 0.0)):
    """One node, a at velocity v_a, b at v_b, displacement separation gap along normal."""
    dim = len(v_a)
    s = nodal(1, 2, dim)
    s["mass"][0] = (m_a, m_b)
    s["momentum"][0, 0] = m_a * np.asarray(v_a, float)
    s["momentum"][0, 1] = m_b * np.asarray(v_b, float)
    s["displacement"][0, 1] = gap * np.asarray(normal, float)
    return s


def test_stick_contact_equalises_velocities_only_when_approaching_and_touching():
    n = np.array([0.6, 0.8])
    tables = sn(StickContact(), n)
    # approaching (b moves against n relative to a) and touching (zero separation)
    s = two_field_contact_state([1.0, 0.5], [-0.5, -1.0], normal=n)
    p0 = s["momentum"].sum(axis=1).copy()
    assert correct(0, s, tables) == 1
    v = velocities(s)
    np.testing.assert_allclose(v[0, 0], v[0, 1], atol=1e-13)
    np.testing.assert_allclose(s["momentum"].sum(axis=1), p0, atol=1e-13)
    # separating: unchanged
    s = two_field_contact_state([-1.0, -0.5], [0.5, 1.0], normal=n)
    p_before = s["momentum"].copy()
    assert correct(0, s, tables) == 0
    np.testing.assert_array_equal(s["momentum"], p_before)
    # approaching but still apart (positive displacement separation): unchanged
    s = two_field_contact_state([1.0, 0.5], [-0.5, -1.0], gap=0.01, normal=n)
    p_before = s["momentum"].copy()
    assert correct(0, s, tables) == 0
    np.testing.assert_array_equal(s["momentum"], p_before)


def test_offset_separation_uses_contact_offset():
    """000 Eq 14: with extrapolated positions, touching bodies show delta_n ~ 0.8 dx."""
    n = np.array([1.0, 0.0])
    tables = sn(StickContact(), n, separation="offset", contact_offset=0.8)
    for gap, touching in ((0.79, True), (0.81, False)):
        s = two_field_contact_state([1.0, 0.0], [-1.0, 0.0])
        s["position"][0, 1] = gap * n
        assert correct(0, s, tables) == int(touching)


def test_df_detects_touching_from_the_edge_distances():
    """One node at the origin, a and b seen at s_a = -3/8 and s_b = s cells along n: the
    edges meet at the node for s = +3/8 (DF gap 0); closer is contact, farther is not.
    The offset method with delta_c = 0.8 would call s_b = 0.40 (0.775 apart) touching."""
    n = np.array([1.0, 0.0])
    case = make_case(2, [(0, 1, StickContact())])
    tables = mm.build_pair_tables(case, {"normal": "SN", "normal_vector": n.tolist(),
                                         "separation": "DF", "shape": "ugimp", "ppc": 2})
    for s_b, touching in ((0.36, True), (0.40, False)):
        st = two_field_contact_state([1.0, 0.0], [-1.0, 0.0])
        st["position"][0, 0] = -0.375 * n
        st["position"][0, 1] = s_b * n
        changed = mm.correct_momentum(0, st["mass"], st["momentum"], st["force"], st["volume"],
                                      st["volume_gradient"], st["displacement"], st["position"],
                                      st["cell"], tables, 1e-3, origin=[0.0, 0.0], nn=[1, 1])
        assert changed == int(touching)


def test_velocity_only_detection_contacts_bodies_still_apart():
    """004 Eq 14 alone: approaching is taken for contact, even with a positive gap
    (the early contact of 004 Fig 2); the displacement separation waits for the gap."""
    n = np.array([1.0, 0.0])
    for sep, expected in (("velocity", 1), ("displacement", 0)):
        s = two_field_contact_state([1.0, 0.0], [-1.0, 0.0], gap=0.05, normal=n)
        assert correct(0, s, sn(StickContact(), n, separation=sep)) == expected
    s = two_field_contact_state([-1.0, 0.0], [1.0, 0.0], gap=0.05, normal=n)    # separating
    assert correct(0, s, sn(StickContact(), n, separation="velocity")) == 0


def test_df_needs_node_positions_and_one_ppc():
    case = make_case(2, [(0, 1, StickContact())])
    tables = mm.build_pair_tables(case, {"separation": "DF"})
    st = two_field_contact_state([1.0, 0.0], [-1.0, 0.0])
    with pytest.raises(ValueError, match="needs the grid's origin and nn"):
        mm.correct_momentum(0, st["mass"], st["momentum"], st["force"], st["volume"],
                            st["volume_gradient"], st["displacement"], st["position"], st["cell"],
                            tables, 1e-3)
    with pytest.raises(CaseError, match="same integer ppc along every axis"):
        mm.build_pair_tables(case, {"separation": "DF", "ppc": [2, 3]})
    with pytest.raises(CaseError, match="separation must be one of"):
        mm.build_pair_tables(case, {"separation": "edge"})


def test_frictionless_contact_removes_only_approaching_normal_velocity():
    n = np.array([math.cos(0.3), math.sin(0.3)])
    t = np.array([-n[1], n[0]])
    tables = sn(CoulombFriction(0.0), n)
    va = 2.0 * n + 1.5 * t
    vb = -1.0 * n - 0.7 * t
    s = two_field_contact_state(va, vb, m_a=2.0, m_b=0.5)
    p0 = s["momentum"].sum(axis=1).copy()
    correct(0, s, tables)
    v = velocities(s)[0]
    dv = v[1] - v[0]
    assert abs(dv @ n) < 1e-13                               # normal approach removed
    assert dv @ t == pytest.approx((vb - va) @ t, rel=1e-13)  # tangential slip untouched
    np.testing.assert_allclose(s["momentum"].sum(axis=1), p0, atol=1e-13)


@pytest.mark.parametrize("mu", [0.1, 0.3])
def test_coulomb_friction_limits_tangential_change(mu):
    """004 Eq 8-10 (ERRATA 7, 13): sliding gives |dp_t| = mu |dp_n| opposing the slip;
    a small slip sticks (dp = dp0, equal velocities)."""
    n = np.array([0.0, 1.0, 0.0])
    t = np.array([1.0, 0.0, 0.0])
    tables = sn(CoulombFriction(mu), n)
    m_a, m_b = 1.5, 2.5
    va = np.array([3.0, 1.0, 0.0])    # large slip along x, approaching along y
    vb = np.array([0.0, -1.0, 0.0])
    s = two_field_contact_state(va, vb, m_a, m_b, normal=n)
    p0 = s["momentum"].copy()
    correct(0, s, tables)
    dpa = s["momentum"][0, 0] - p0[0, 0]
    m_red = m_a * m_b / (m_a + m_b)
    dp0 = m_red * (vb - va)
    assert dpa @ n == pytest.approx(dp0 @ n, rel=1e-13)
    assert dpa @ t == pytest.approx(np.sign(dp0 @ t) * mu * abs(dp0 @ n), rel=1e-12)
    assert abs(dpa @ t) == pytest.approx(mu * abs(dpa @ n), rel=1e-12)
    np.testing.assert_allclose(s["momentum"].sum(axis=1), p0.sum(axis=1), atol=1e-13)
    # small slip: sticks
    va = np.array([0.05, 1.0, 0.0])
    s = two_field_contact_state(va, vb, m_a, m_b, normal=n)
    correct(0, s, tables)
    v = velocities(s)[0]
    np.testing.assert_allclose(v[0], v[1], atol=1e-13)


def test_imperfect_interface_perfect_tangential_direction_is_momentum_corrected():
    """002 Sec 2.4: a perfect (inf) direction uses stick conditions, the finite one forces."""
    n = np.array([1.0, 0.0])
    tables = sn(LinearInterface(5.0, math.inf), n)
    s = two_field_contact_state([1.0, 2.0], [3.0, -1.0])
    correct(0, s, tables)
    v = velocities(s)[0]
    assert v[0, 1] == pytest.approx(v[1, 1], abs=1e-13)        # tangential equal
    assert v[1, 0] - v[0, 0] == pytest.approx(2.0, rel=1e-13)  # normal (finite Dn) untouched


def test_bilinear_perfect_in_compression_only_when_closing():
    n = np.array([1.0, 0.0])
    tables = sn(BilinearNormalInterface(2.0, 1.0, math.inf), n)
    s = two_field_contact_state([1.0, 0.0], [-1.0, 0.0], gap=-0.01)   # closed, approaching
    correct(0, s, tables)
    v = velocities(s)[0]
    assert v[0, 0] == pytest.approx(v[1, 0], abs=1e-13)
    s = two_field_contact_state([1.0, 0.0], [-1.0, 0.0], gap=0.01)    # open: tension branch
    p0 = s["momentum"].copy()
    correct(0, s, tables)
    np.testing.assert_array_equal(s["momentum"], p0)


def test_three_material_lumping_conserves_momentum():
    """000 Sec 2.6 / 004 Eq 50 lumping; perfect -> all at the centre of mass; contact laws
    conserve momentum thanks to the common-velocity restoration."""
    case = make_case(3, [(0, 1, CoulombFriction(0.2)), (1, 2, StickContact()),
                         (0, 2, CoulombFriction(0.0))])
    tables = mm.build_pair_tables(case, {"normal": "AVG"})
    s = nodal(6, 3, 2)
    s["volume_gradient"][:] = RNG.normal(size=s["volume_gradient"].shape)
    p0 = s["momentum"].copy()
    correct(0, s, tables)
    assert not np.allclose(s["momentum"], p0)
    np.testing.assert_allclose(s["momentum"].sum(axis=1), p0.sum(axis=1), atol=1e-12)
    s = nodal(6, 3, 2)
    p0 = s["momentum"].copy()
    correct(0, s, mm.build_pair_tables(make_case(3, []), {}))
    v = velocities(s)
    vcm = p0.sum(axis=1) / s["mass"].sum(axis=1)[:, None]
    for k in range(3):
        np.testing.assert_allclose(v[:, k], vcm, atol=1e-12)


def test_rigid_partner_keeps_its_velocity():
    """000 Eq 28-31: v_c = v_rigid, only the non-rigid field changes."""
    case = make_case(2, [(0, 1, StickContact())])
    tables = mm.build_pair_tables(case, {"normal": "SN", "normal_vector": [1, 0], "rigid_bodies": ["b1"]})
    s = two_field_contact_state([1.0, 0.3], [-0.2, 0.0])
    pb = s["momentum"][0, 1].copy()
    correct(0, s, tables)
    v = velocities(s)[0]
    np.testing.assert_allclose(v[0], [-0.2, 0.0], atol=1e-13)
    np.testing.assert_array_equal(s["momentum"][0, 1], pb)


def rigid_contact_state(velocity, gradients, volumes):
    """One node: a deformable field 0 at ``velocity``, rigid fields 1.. with the given
    outward volume gradients and volumes (rigid velocities 0, -1 along y, ...)."""
    n_fields = len(gradients)
    s = nodal(1, n_fields, 2)
    s["mass"][0] = 1.0
    s["volume"][0] = volumes
    s["volume_gradient"][0] = gradients
    s["momentum"][0, 0] = velocity
    for c in range(1, n_fields):
        s["momentum"][0, c] = (0.0, -float(c - 1))
    return s


def test_thin_rigid_body_holds_a_field_at_a_node_beyond_its_mid_plane():
    """A deformable field (outward gradient g_a up) pushes up into a rigid plate one cell
    thick at a node above the plate's mid-plane, where the plate's outward gradient g_r
    also points up (out of its far face). Frictionless contact must stop the field's
    normal approach: v_y = the plate's velocity, v_x kept. With the AG normal
    (g_a - g_r: the vertical parts cancel, n lies nearly along the face) the field kept
    most of its upward velocity and went through the plate (004 Fig 6 piston)."""
    case = make_case(2, [(0, 1, CoulombFriction(0.0))])
    tables = mm.build_pair_tables(case, {"normal": "AG", "separation": "velocity", "rigid_bodies": ["b1"]})
    s = rigid_contact_state((0.5, 3.0), [(0.3, 1.0), (0.0, 0.9)], (0.4, 0.6))
    pr = s["momentum"][0, 1].copy()
    correct(1, s, tables)
    np.testing.assert_allclose(velocities(s)[0, 0], (0.5, 0.0), atol=1e-12)
    np.testing.assert_array_equal(s["momentum"][0, 1], pr)


@pytest.mark.parametrize("round_off", [1e-18, 0.0, -1e-18])
def test_a_corner_node_beside_a_rigid_face_keeps_the_rigid_normal(round_off):
    """A field's corner node below a piston moving down at 1: the field's outward
    gradient points along x, the piston's along -y, perpendicular. Its normal (up, into
    the piston) must not turn with the sign of the round-off x part of g_r: it did, so a
    1e-15 mm move of the particles decided contact at the piston's first touch (004 Fig 6,
    uGIMP). Frictionless contact: the field takes the piston's normal velocity."""
    case = make_case(2, [(0, 1, CoulombFriction(0.0))])
    tables = mm.build_pair_tables(case, {"normal": "AG", "separation": "velocity", "rigid_bodies": ["b1"]})
    s = rigid_contact_state((0.0, 0.0), [(0.02, 0.0), (round_off, -1e-3)], (0.3, 0.7))
    s["momentum"][0, 1] = (0.0, -1.0)
    correct(1, s, tables)
    np.testing.assert_allclose(velocities(s)[0, 0], (0.0, -1.0), atol=1e-12)


def test_inside_a_rigid_body_its_round_off_gradient_is_not_a_normal():
    """At a node inside a thick rigid body its volume gradient is round-off; the normal
    then comes from the method (AG: the deformable field's outward gradient, up), not
    from the round-off direction (here along x)."""
    case = make_case(2, [(0, 1, CoulombFriction(0.0))])
    tables = mm.build_pair_tables(case, {"normal": "AG", "separation": "velocity", "rigid_bodies": ["b1"]})
    s = rigid_contact_state((0.5, 3.0), [(0.0, 1.0), (1e-20, 0.0)], (0.2, 0.8))
    correct(1, s, tables)
    np.testing.assert_allclose(velocities(s)[0, 0], (0.5, 0.0), atol=1e-12)


@pytest.mark.parametrize("normal", ["AG", "LR"])
def test_field_in_a_corner_of_two_rigid_bodies_is_held_by_both(normal):
    """A deformable field at a node shared by a fixed wall (to its right, larger volume)
    and a piston above it moving down at 1: frictionless contact with both, v = (0, -1).
    Against the largest rigid body alone the field kept moving up into the piston."""
    case = make_case(3, [(0, 1, CoulombFriction(0.0)), (0, 2, CoulombFriction(0.0))])
    tables = mm.build_pair_tables(case, {"normal": normal, "separation": "velocity",
                                         "rigid_bodies": ["b1", "b2"]})
    s = rigid_contact_state((2.0, 3.0), [(1.0, 1.0), (-1.0, 0.0), (0.0, -1.0)], (0.3, 0.5, 0.2))
    lr = (np.zeros((1, 3, 2)), np.full((1, 3), np.nan))     # no LR plane: the rigid normals
    mm.correct_momentum(1, s["mass"], s["momentum"], s["force"], s["volume"], s["volume_gradient"],
                        s["displacement"], s["position"], s["cell"], tables, 1e-3, 1.0,
                        lr=lr if normal == "LR" else None)
    np.testing.assert_allclose(velocities(s)[0, 0], (0.0, -1.0), atol=1e-12)
    np.testing.assert_allclose(velocities(s)[0, 1:], [(0.0, 0.0), (0.0, -1.0)], atol=1e-15)



@pytest.mark.parametrize("separation", ["LR", "velocity"])
def test_two_fields_beside_a_rigid_body_meet_each_other_with_lr(separation):
    """A node seen by two deformable fields closing on each other along x (field 0 moving
    +x at 2, field 1 -x at 1, outward gradients +-x, LR normals +-x, LR separation
    -0.01) and a fixed rigid floor below them (its outward gradient +y). Frictionless
    contact everywhere. With LR separations the pair takes its common normal velocity
    (0.5, by momentum with equal masses), then each field sits on the floor (v_y = 0):
    skipping the pair at nodes that see a rigid body (NairnMPM's rule) let the ellipses
    of 004 Fig 6 pass through each other along the walls and the piston. With grid
    separations NairnMPM's rule is kept (docs/mpm.md): only the floor acts."""
    case = make_case(3, [(0, 1, CoulombFriction(0.0)), (0, 2, CoulombFriction(0.0)),
                         (1, 2, CoulombFriction(0.0))])
    normal = "LR" if separation == "LR" else "AG"
    tables = mm.build_pair_tables(case, {"normal": normal, "separation": separation,
                                         "rigid_bodies": ["b2"]})
    s = nodal(1, 3, 2)
    s["mass"][0] = 1.0
    s["volume"][0] = (0.3, 0.3, 0.4)
    s["volume_gradient"][0] = [(1.0, -0.1), (-1.0, -0.1), (0.0, 1.0)]
    s["momentum"][0] = [(2.0, -0.5), (-1.0, -0.3), (0.0, 0.0)]
    lr = (np.array([[(1.0, 0.0), (-1.0, 0.0), (0.0, 0.0)]]), np.array([[-0.01, -0.01, np.nan]]))
    mm.correct_momentum(1, s["mass"], s["momentum"], s["force"], s["volume"], s["volume_gradient"],
                        s["displacement"], s["position"], s["cell"], tables, 1e-3, 1.0,
                        lr=lr if separation == "LR" else None)
    vx = (0.5, 0.5) if separation == "LR" else (2.0, -1.0)
    np.testing.assert_allclose(velocities(s)[0], [(vx[0], 0.0), (vx[1], 0.0), (0.0, 0.0)], atol=1e-12)

# ---------------------------------------------------------------- interface forces


def interface_state(jump, normal, cell=(1.0, 1.0), omega=(0.7, 0.3), masses=(1.0, 1.0),
                    thickness=2.0):
    dim = len(jump)
    s = nodal(1, 2, dim, thickness=thickness)
    s["cell"] = np.asarray(cell, float)
    s["mass"][0] = masses
    s["momentum"][:] = 0.0
    s["force"][:] = 0.0
    cellv = float(np.prod(cell)) * (thickness if dim == 2 else 1.0)
    s["volume"][0] = np.asarray(omega) * cellv
    s["displacement"][0, 0] = 0.0
    s["displacement"][0, 1] = jump
    return s, cellv


@pytest.mark.parametrize("area_correction", [True, False])
def test_interface_force_and_energy_closed_form_2d(area_correction):
    """000 Eq 17, 20 (ERRATA 8), 22 (ERRATA 9), ERRATA 10 on an unequal cell."""
    theta = math.radians(25.0)
    n = np.array([math.cos(theta), math.sin(theta)])
    t = np.array([-n[1], n[0]])
    jn, jt = 0.012, -0.007
    Dn, Dt, thick = 40.0, 15.0, 2.0
    cell = (0.5, 1.0)
    s, cellv = interface_state(jn * n + jt * t, n, cell=cell, thickness=thick)
    tables = sn(LinearInterface(Dn, Dt), n, area_correction=area_correction, force_limiting=False)
    out = np.zeros((1, NODE_OUT_COLUMNS))
    U = interface(s, tables, thickness=thick, out=out)
    h = math.sqrt(n[0] ** 2 * cell[0] ** 2 + n[1] ** 2 * cell[1] ** 2)
    om = s["volume"][0]
    A = (math.sqrt(2.0 * om.sum() * om.min()) if area_correction else om.sum()) / h
    f_expected = (Dn * jn * n + Dt * jt * t) * A
    np.testing.assert_allclose(s["force"][0, 0], f_expected, rtol=1e-12)
    np.testing.assert_allclose(s["force"][0, 1], -f_expected, rtol=1e-12)
    assert U == pytest.approx(0.5 * (Dn * jn ** 2 + Dt * jt ** 2) * A, rel=1e-12)
    assert out[0, OUT_AREA] == pytest.approx(A, rel=1e-12)
    assert out[0, OUT_JUMP_N] == pytest.approx(jn, rel=1e-12)
    assert out[0, OUT_JUMP_T] == pytest.approx(jt, rel=1e-12)
    assert out[0, OUT_TRACTION_N] == pytest.approx(Dn * jn, rel=1e-12)
    assert out[0, OUT_TRACTION_T] == pytest.approx(Dt * jt, rel=1e-12)
    assert out[0, OUT_ENERGY] == pytest.approx(U, rel=1e-14)
    # a state quantity: evaluating again gives the same energy, not twice it (ERRATA 10)
    assert interface(s, tables, thickness=thick) == pytest.approx(U, rel=1e-14)


def test_interface_force_3d_and_perfect_normal_has_no_force():
    n = np.array([1.0, 2.0, 2.0]) / 3.0
    jump = np.array([0.01, -0.02, 0.005])
    Dt = 7.0
    s, cellv = interface_state(jump, n, cell=(1.0, 1.0, 1.0), omega=(0.5, 0.5))
    tables = sn(LinearInterface(math.inf, Dt), n, force_limiting=False)
    U = interface(s, tables)
    A = math.sqrt(2.0 * cellv * 0.5 * cellv) / 1.0
    jt = jump - (jump @ n) * n
    np.testing.assert_allclose(s["force"][0, 0], Dt * jt * A, rtol=1e-12)
    assert U == pytest.approx(0.5 * Dt * (jt @ jt) * A, rel=1e-12)


def test_area_correction_makes_total_force_independent_of_interface_location():
    """000 Fig 2: interface on a grid line (Omega_a = Omega_b = A_cell/2 at one node) and
    at a cell midplane (7/8, 1/8 at two nodes) give the same total area t dy."""
    dx, dy, t = 1.0, 1.0, 3.0
    tables = sn(LinearInterface(10.0, 10.0), [1.0, 0.0], force_limiting=False)
    totals = []
    for omegas in ([(0.5, 0.5)], [(7 / 8, 1 / 8), (1 / 8, 7 / 8)]):
        area = 0.0
        for om in omegas:
            s, _ = interface_state(np.array([0.01, 0.0]), None, cell=(dx, dy), omega=om, thickness=t)
            out = np.zeros((1, NODE_OUT_COLUMNS))
            interface(s, tables, thickness=t, out=out)
            area += out[0, OUT_AREA]
        totals.append(area)
    assert totals[0] == pytest.approx(t * dy, rel=1e-12)
    assert totals[1] == pytest.approx(t * dy, rel=1e-12)


def test_bilinear_normal_law_branches():
    n = np.array([0.0, 1.0])
    law = BilinearNormalInterface(3.0, 1.0, 50.0)
    for jn, dn in ((0.02, 3.0), (-0.02, 50.0)):
        s, cellv = interface_state(jn * n, n, omega=(0.5, 0.5), thickness=1.0)
        tables = sn(law, n, force_limiting=False)
        U = interface(s, tables)
        A = math.sqrt(2.0 * cellv * 0.5 * cellv)
        np.testing.assert_allclose(s["force"][0, 0], dn * jn * A * n, rtol=1e-12)
        assert U == pytest.approx(0.5 * dn * jn ** 2 * A, rel=1e-12)


def test_force_limiting_switches_a_stiff_direction_to_stick_at_the_eq26_bound():
    """000 Eq 23-27: a stiff interface force above the force that brings both fields to
    the centre-of-mass position in one step makes that direction stick (zero energy).
    The bound is derived for this code's update u+ = u + dt (p + dt f)/m (Eq 26 with the
    factors 2 is for the midpoint rule of Eq 24-25); the applied force equalises the
    end-of-step velocities, as the momentum correction of a perfect direction does."""
    n = np.array([1.0, 0.0])
    jump = np.array([0.01, 0.004])
    m_a, m_b = 2.0, 0.5
    dt = 1e-3

    def state():
        s, _ = interface_state(jump, n, omega=(0.5, 0.5), masses=(m_a, m_b), thickness=1.0)
        s["momentum"][0, 0] = m_a * np.array([0.3, -0.1])
        s["momentum"][0, 1] = m_b * np.array([-0.2, 0.4])
        s["force"][0] = f_other
        return s

    f_other = np.array([[0.5, -0.2], [0.1, 0.3]])
    s = state()
    tables = sn(LinearInterface(1e9, 1e9), n, force_limiting=True)
    out = np.zeros((1, NODE_OUT_COLUMNS))
    U = interface(s, tables, dt=dt, out=out)
    f_int = s["force"][0, 0] - f_other[0]
    np.testing.assert_allclose(s["force"][0, 1] - f_other[1], -f_int, rtol=1e-12)
    assert U == 0.0
    assert int(out[0, OUT_STATUS]) & int(STATUS_LIMITED_N) and int(out[0, OUT_STATUS]) & int(STATUS_LIMITED_T)
    p = s["momentum"][0]
    v_a = (p[0] + dt * (f_other[0] + f_int)) / m_a
    v_b = (p[1] + dt * (f_other[1] - f_int)) / m_b
    np.testing.assert_allclose(v_a, v_b, atol=1e-13)
    # the bound itself: m_red [u]/dt^2 + Delta p/dt + Delta f per direction (Eq 26-27
    # for u+ = u + dt v+); a stiffness just below / above it is not / is limited
    m_red = m_a * m_b / (m_a + m_b)
    dp0 = m_red * (p[1] / m_b - p[0] / m_a)
    df = (m_a * f_other[1] - m_b * f_other[0]) / (m_a + m_b)
    f_max_n = m_red * jump[0] / dt ** 2 + dp0[0] / dt + df[0]
    A = out[0, OUT_AREA]
    dn_bound = f_max_n / (jump[0] * A)
    for factor, limited in ((0.99, False), (1.01, True)):
        s = state()
        out[:] = 0.0
        interface(s, sn(LinearInterface(factor * dn_bound, math.inf), n, force_limiting=True),
                  dt=dt, out=out)
        assert bool(int(out[0, OUT_STATUS]) & int(STATUS_LIMITED_N)) == limited
    # a spring stiffer than m_red / (A dt^2) overshoots the centre of mass for any jump
    # (explicit instability): limited even when the velocities make Eq 26 large
    s = state()
    s["momentum"][0, 1, 0] = m_b * 50.0           # b moves away fast: f_max_n >> k [u]
    out[:] = 0.0
    d_stiff = 1.5 * m_red / (A * dt ** 2)
    interface(s, sn(LinearInterface(d_stiff, math.inf), n, force_limiting=True), dt=dt, out=out)
    assert int(out[0, OUT_STATUS]) & int(STATUS_LIMITED_N)
    # without limiting the force is not capped but the node is flagged
    s = state()
    out[:] = 0.0
    interface(s, sn(LinearInterface(1e9, 1e9), n, force_limiting=False), dt=dt, out=out)
    assert int(out[0, OUT_STATUS]) & int(STATUS_OVER_LIMIT)
    assert not int(out[0, OUT_STATUS]) & int(STATUS_LIMITED_N)
    np.testing.assert_allclose(s["force"][0, 0, 0] - f_other[0, 0], 1e9 * jump[0] * A, rtol=1e-12)
    # a soft interface is not limited
    s2, _ = interface_state(jump, n, omega=(0.5, 0.5), masses=(m_a, m_b), thickness=1.0)
    tables = sn(LinearInterface(1.0, 1.0), n, force_limiting=True)
    out[:] = 0.0
    interface(s2, tables, dt=dt, out=out)
    assert not (int(out[0, OUT_STATUS]) & (int(STATUS_LIMITED_N) | int(STATUS_LIMITED_T)))


def test_edge_node_screening():
    n = np.array([1.0, 0.0])
    s, cellv = interface_state(np.array([0.01, 0.0]), n, omega=(0.3, 0.3))
    tables = sn(LinearInterface(10.0, 10.0), n, edge_cutoff=0.75)
    out = np.zeros((1, NODE_OUT_COLUMNS))
    assert interface(s, tables, thickness=2.0, out=out) == 0.0
    assert np.all(s["force"] == 0.0)
    assert out[0, OUT_STATUS] == STATUS_SCREENED
    s, _ = interface_state(np.array([0.01, 0.0]), n, omega=(0.5, 0.4))
    assert interface(s, tables, thickness=2.0) > 0.0


def test_three_material_interface_forces_balance():
    case = make_case(3, [(0, 1, LinearInterface(5.0, 3.0)), (1, 2, LinearInterface(4.0, 2.0)),
                         (0, 2, LinearInterface(1.0, 1.0))])
    tables = mm.build_pair_tables(case, {"normal": "MVG", "force_limiting": False})
    s = nodal(5, 3, 2)
    s["force"][:] = 0.0
    s["volume_gradient"][:] = RNG.normal(size=s["volume_gradient"].shape)
    s["displacement"][:] = RNG.normal(size=s["displacement"].shape) * 1e-2
    U = interface(s, tables)
    assert U > 0.0
    assert np.abs(s["force"]).max() > 0.0
    np.testing.assert_allclose(s["force"].sum(axis=1), 0.0, atol=1e-13)


@pytest.mark.parametrize("area_correction", [False, True])
def test_three_material_interface_energy_closed_form(area_correction):
    """000 Sec 2.6: at a node of three materials each material a meets the lump of the
    others (mass-weighted displacement, Eq 11) with the law of its largest-volume partner;
    the node's energy is half the sum of the three spring energies (each interface seen
    from both sides), 1/2 sum_a 1/2 (Dn (j_a.n)^2 + Dt |j_a,t|^2) A_a."""
    laws = {(0, 1): (5.0, 3.0), (1, 2): (4.0, 2.0), (0, 2): (1.0, 1.5)}
    case = make_case(3, [(a, b, LinearInterface(*D)) for (a, b), D in laws.items()])
    n = np.array([0.6, 0.8])
    tables = mm.build_pair_tables(case, {"normal": "SN", "normal_vector": n.tolist(),
                                         "force_limiting": False, "area_correction": area_correction})
    s = nodal(1, 3, 2)
    s["force"][:] = 0.0
    s["momentum"][:] = 0.0
    omega = np.array([0.5, 0.3, 0.2])            # node volume shares: partner by volume
    s["volume"][0] = omega
    s["mass"][0] = [1.0, 2.5, 0.7]
    s["displacement"][0] = [[0.010, -0.004], [-0.003, 0.006], [0.007, 0.002]]
    U = interface(s, tables)
    u, m = s["displacement"][0], s["mass"][0]
    partner = {0: 1, 1: 0, 2: 0}
    expected = 0.0
    for a in range(3):
        others = [c for c in range(3) if c != a]
        x_b = sum(m[c] * u[c] for c in others) / sum(m[c] for c in others)
        j = u[a] - x_b
        jn = j @ n
        jt = j - jn * n
        Dn, Dt = laws[tuple(sorted((a, partner[a])))]
        om_b = sum(omega[c] for c in others)
        area = math.sqrt(2.0 * omega.sum() * min(omega[a], om_b)) if area_correction else omega.sum()
        expected += 0.5 * (Dn * jn ** 2 + Dt * (jt @ jt)) * area
    assert U == pytest.approx(0.5 * expected, rel=1e-12)


def test_zone_law_overrides_pair_law():
    """002 Fig 6: nodes inside a zone use the zone's law for that pair."""
    zone = SimpleNamespace(contains=lambda p: np.asarray(p)[:, 1] > 0.5)
    case = make_case(2, [(0, 1, LinearInterface(1.0, 1.0), (zone, LinearInterface(9.0, 1.0)))])
    coords = np.array([[0.0, 0.0], [0.0, 1.0]])
    tables = mm.build_pair_tables(case, {"normal": "SN", "normal_vector": [1, 0],
                                         "force_limiting": False}, node_coordinates=coords)
    s = nodal(2, 2, 2)
    s["force"][:] = 0.0
    s["momentum"][:] = 0.0
    s["displacement"][:, 1] = [0.01, 0.0]
    interface(s, tables)
    assert s["force"][1, 0, 0] == pytest.approx(9.0 * s["force"][0, 0, 0], rel=1e-12)


# ---------------------------------------------------------------- normals and h_perp


def test_h_perp_eq22_matches_ellipse_tangent_construction():
    """000 method 1: h = dx dy / h1, h1 the distance along t to the ellipse with
    semi-axes dx, dy; equals ERRATA 9 sqrt(nx^2 dx^2 + ny^2 dy^2); all methods give dx
    for a square cell."""
    cell = np.array([1.0, 2.0])
    for ang in np.linspace(0.0, math.pi, 7):
        n = np.array([math.cos(ang), math.sin(ang)])
        t = np.array([-n[1], n[0]])
        h1 = 1.0 / math.sqrt((t[0] / cell[0]) ** 2 + (t[1] / cell[1]) ** 2)
        assert mm.h_perp(n, t, cell, 1) == pytest.approx(cell[0] * cell[1] / h1, rel=1e-12)
        for method in (0, 1, 2):
            assert mm.h_perp(n, t, np.array([0.7, 0.7]), method) == pytest.approx(0.7, rel=1e-12)
    n3 = np.array([0.0, 0.0, 1.0])
    t3 = np.array([1.0, 0.0, 0.0])
    # plane z = const: contact area dx dy, h_perp = dz
    assert mm.h_perp(n3, t3, np.array([1.0, 2.0, 3.0]), 1) == pytest.approx(3.0, rel=1e-12)


def extrapolate(x, field, n_fields, origin, cell, nn, spacing, shape="ugimp"):
    """Field mass (unit density), volume (000 Eq 19) and volume gradient (Eq 33)."""
    vol, grad = field_volumes(x, field, n_fields, origin, cell, nn, spacing, shape)
    return vol, vol.copy(), grad


def extrapolated_interface(theta_deg, shape="ugimp", cell=0.5, ppc=2):
    """Two bodies meeting on a straight interface with normal at theta (000 Fig 9: the
    rotated specimen): a particle lattice aligned with the interface, rotated by theta,
    clipped to a disc, extrapolated with the core's shape functions.  Returns the exact
    normal (a -> b) and, on nodes seeing both fields at least 2 cells inside the disc,
    volumes and volume gradients."""
    R = 5.0
    h = cell / ppc
    k = np.arange(-R / h, R / h) + 0.5
    S, T = np.meshgrid(k * h, k * h, indexing="ij")
    th = math.radians(theta_deg)
    n = np.array([math.cos(th), math.sin(th)])
    t = np.array([-n[1], n[0]])
    local = np.column_stack([S.ravel(), T.ravel()])          # (along n, along t)
    local = local[np.hypot(local[:, 0], local[:, 1]) < R]
    x = np.ascontiguousarray(local[:, :1] * n + local[:, 1:] * t + R + 3 * cell)
    field = (local[:, 0] > 0).astype(np.int64)               # a = 0 on the -n side
    nx = int(math.ceil((2 * R + 6 * cell) / cell)) + 1
    nn = np.array([nx, nx], dtype=np.int64)
    mass, vol, grad = extrapolate(x, field, 2, np.zeros(2), np.full(2, cell), nn, (h, h), shape)
    idx = np.arange(int(nn.prod()))
    node_x = np.column_stack([idx % nx, idx // nx]) * cell
    inner = np.hypot(*(node_x - (R + 3 * cell)).T) < R - 2 * cell
    both = (mass[:, 0] > 1e-9 * mass.sum(1)) & (mass[:, 1] > 1e-9 * mass.sum(1)) & inner
    return n, vol[both], grad[both]


@pytest.mark.parametrize("theta", [0.0, 30.0, 45.0, 63.0, 117.0])
@pytest.mark.parametrize("ppc, tol_max, tol_median", [(2, 3.5, 1.0), (4, 2.0, 1.7)])
def test_mvg_and_avg_recover_a_straight_interface(theta, ppc, tol_max, tol_median):
    """000 Sec 2.5 / 004 Eq 13 on a rotated straight interface away from free edges,
    uGIMP.  Nodes where one field holds < 5 % of the nodal volume are left out: there
    both gradients are lattice-aliasing noise (Eq 20 gives them almost no area)."""
    n_exact, vol, grad = extrapolated_interface(theta, ppc=ppc)
    keep = vol.min(axis=1) >= 0.05 * vol.sum(axis=1)
    vol, grad = vol[keep], grad[keep]
    assert len(vol) >= 10
    out = np.empty(2)
    for method in ("MVG", "AVG", "AG"):
        errs = []
        for k in range(len(vol)):
            if method == "MVG":
                ok = mm.normal_mvg(grad[k, 0], grad[k, 1], out)
            elif method == "AVG":
                ok = mm.normal_avg(vol[k, 0], grad[k, 0], vol[k, 1], grad[k, 1], out)
            else:
                ok = mm.normal_ag(grad[k, 0], grad[k, 1], out)
            assert ok
            errs.append(math.degrees(math.acos(min(1.0, out @ n_exact))))
        errs = np.array(errs)
        assert np.max(errs) < tol_max, (method, errs.max())
        assert np.median(errs) < tol_median, (method, np.median(errs))


def test_sn_normal_sign_follows_field_order():
    out = np.empty(2)
    mm.normal_sn(np.array([0.0, 2.0]), 1, 0, out)
    np.testing.assert_allclose(out, [0.0, -1.0])


# ---------------------------------------------------------------- option validation


@pytest.mark.parametrize("opts, word", [
    ({"normal": "XYZ"}, "normal"),
    ({"normal": "SN"}, "normal_vector"),
    ({"separation": "foo"}, "separation"),
    ({"edge_cutoff": 2.0}, "edge_cutoff"),
    ({"h_perp": "bad"}, "h_perp"),
    ({"normal": "RMVG"}, "rigid_bodies"),
    ({"rigid_bodies": ["nope"]}, "rigid_bodies"),
    ({"default_law": "glue"}, "default_law"),
])
def test_bad_options_name_the_field(opts, word):
    with pytest.raises(CaseError, match=word):
        mm.build_pair_tables(make_case(2, []), opts)


def test_negative_stiffness_rejected_for_mpm():
    # a stiff interphase (002 Eq 52) gives Dn < 0: unstable in explicit MPM
    bad = type("LinearInterface", (), {"Dn": -1.0, "Dt": 1.0})()
    case = make_case(2, [])
    case.interfaces = [SimpleNamespace(a="b0", b="b1", law=bad, zones=[])]
    with pytest.raises(CaseError, match="Dn"):
        mm.build_pair_tables(case, {})


def test_lr_without_arrays_is_rejected():
    tables = mm.build_pair_tables(make_case(2, [(0, 1, StickContact())]), {"normal": "LR"})
    s = nodal(1)
    with pytest.raises(CaseError, match="LR"):
        correct(0, s, tables)


# ---------------------------------------------------------------- more paths


def test_rigid_partner_interface_force_acts_on_the_deformable_field_only():
    """000 Eq 28-31 with Eq 17: force on a only; the rigid field is untouched."""
    case = make_case(2, [(0, 1, LinearInterface(20.0, 5.0))])
    tables = mm.build_pair_tables(case, {"normal": "SN", "normal_vector": [0, 1],
                                         "rigid_bodies": ["b1"], "force_limiting": False})
    jump = np.array([0.003, 0.01])
    s, cellv = interface_state(jump, None, omega=(0.5, 0.5), thickness=1.0)
    U = interface(s, tables, thickness=1.0)
    A = math.sqrt(2.0 * cellv * 0.5 * cellv)
    np.testing.assert_allclose(s["force"][0, 0], [5.0 * 0.003 * A, 20.0 * 0.01 * A], rtol=1e-12)
    np.testing.assert_array_equal(s["force"][0, 1], 0.0)
    assert U == pytest.approx(0.5 * (20.0 * 0.01 ** 2 + 5.0 * 0.003 ** 2) * A, rel=1e-12)


def test_phase1_contact_uses_the_end_of_step_separation():
    """In phase 1 the separation is advanced by dt (v_b - v_a): a gap that the updated
    velocities close within the step is treated as contact."""
    n = np.array([1.0, 0.0])
    tables = sn(StickContact(), n)
    dt = 1e-3
    for gap, expect in ((0.9e-3, 1), (1.1e-3, 0)):     # closing speed 1 mm/s x dt = 1e-3
        s = two_field_contact_state([0.5, 0.0], [-0.5, 0.0], m_a=1.0, m_b=1.0, gap=gap)
        assert correct(0, s, tables, dt) == 0          # phase 0: still apart
        assert correct(1, s, tables, dt) == expect


def test_per_node_thickness_sets_the_screening_volume():
    """Axisymmetric use: thickness per node (node radius) scales the cell volume."""
    n = np.array([1.0, 0.0])
    tables = sn(LinearInterface(10.0, 10.0), n, edge_cutoff=0.75)
    s, cellv = interface_state(np.array([0.01, 0.0]), n, omega=(0.5, 0.5), thickness=1.0)
    s2 = {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in s.items()}
    assert interface(s, tables, thickness=np.array([1.0])) > 0.0         # Omega = cell
    assert interface(s2, tables, thickness=np.array([2.0])) == 0.0       # Omega = cell/2



@pytest.mark.parametrize("law", [LinearInterface(math.inf, 5.0), LinearInterface(math.inf, math.inf),
                                 StickContact()])
@pytest.mark.parametrize("light", [0, 1])
def test_roundoff_sized_field_gets_a_finite_velocity(law, light):
    """A field holding only a round-off GIMP weight (m ~ 1e-65 of its partner) at a
    node: the stick / perfect change of the perfect direction ends it at (about) the
    partner's normal velocity. Computed on the heavy side, the round-off of the heavy
    momentum (~1e-16 |p|) made it ~1e30 mm/s and the grid damping booked 3 N mm of
    spurious dissipation on a 0.1 mm DLS whose external work was 0.2 N mm."""
    n = np.array([1.0, 0.0])
    tables = sn(law, n)
    s = nodal(1)
    heavy = 1 - light
    s["mass"][0] = 0.0
    s["mass"][0, heavy] = 3.7e-3
    s["mass"][0, light] = 3.7e-3 * 1.3e-65
    v_heavy = np.array([0.31, -0.17])
    s["momentum"][0, heavy] = s["mass"][0, heavy] * v_heavy
    # approaching along n (from field 0 to field 1), for the contact law
    closing = 0.6 if light == 0 else -0.6
    s["momentum"][0, light] = s["mass"][0, light] * (v_heavy + np.array([closing, 0.4]))
    s["volume"][0] = s["mass"][0] / 1e-9
    p_total = s["momentum"][0].sum(axis=0).copy()
    correct(0, s, tables)
    v = velocities(s)[0]
    assert abs(v[light, 0] - v_heavy[0]) < 1e-9 * abs(v_heavy[0])    # normal velocity equalised
    assert np.all(np.abs(v[light]) < 1.0)
    np.testing.assert_allclose(s["momentum"][0].sum(axis=0), p_total, rtol=1e-14)


def test_wrong_array_shapes_are_reported_by_name():
    tables = mm.build_pair_tables(make_case(2, []), {})
    s = nodal(3)
    with pytest.raises(ValueError, match="volume_gradient"):
        mm.correct_momentum(0, s["mass"], s["momentum"], s["force"], s["volume"],
                            s["volume_gradient"][:, :, :1].copy(), s["displacement"], s["position"],
                            s["cell"], tables, 1e-3)
    with pytest.raises(ValueError, match="fields"):
        mm.correct_momentum(0, s["mass"][:, :1].copy(), s["momentum"], s["force"], s["volume"],
                            s["volume_gradient"], s["displacement"], s["position"], s["cell"],
                            tables, 1e-3)
    with pytest.raises(ValueError, match="phase"):
        correct(2, s, tables)
