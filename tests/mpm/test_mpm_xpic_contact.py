"""XPIC(m) grid velocity held to the contact conditions (mpm/xpic_contact.py).

A bar moving at V0 strikes a fixed rigid wall (frictionless contact). While it is in
contact, the contact holds the struck end: its particles must not move into the wall.
With FLIP they move with the corrected v+; with XPIC(5) they move with v~, which the
series S+_alpha S mixes with the velocities of the nodes behind the contact node (V0).
Largest advance into the wall over the half transit of the impact wave: FLIP 0.0031
cell, XPIC(5) 0.0032 (0.031 before v~ was corrected), uncorrected XPIC(5) 0, XPIC(1)
0.0025; the bound is 0.01 cell. Two equal bars colliding at +-V0 (deformable contact):
overlap FLIP 0.0094 cell, XPIC(5) 0.011 (0.073 before), uncorrected XPIC(5) 0; the
bound is 0.03 cell.
"""
from __future__ import annotations

import numpy as np
import pytest

from interfaces import (
    Body, Case, CoulombFriction, InterfacePair, IsotropicElastic, LinearInterface, Rectangle,
)
from mpm.multimaterial_constants import (
    LAW_FRICTION, LAW_IMPERFECT, LAW_NONE, LAW_PERFECT, LAW_STICK, P_MU,
)
from mpm.options import merge
from mpm.solver import Model, _Runner
from mpm.xpic_contact import MUSL_LIGHT_FIELD, contact_laws, musl_contact_momenta

L, H, E, RHO = 20.0, 4.0, 1000.0, 1e-9
C = (E / RHO) ** 0.5
V0 = 0.01 * C


def _impact(second: Rectangle, rigid: bool, opts: dict) -> float:
    """A bar (0 < x < L) moving at V0 strikes ``second`` (at rest if ``rigid``, else
    moving at -V0) in frictionless contact. Largest overlap of the two bodies' particle
    domains (x_p + l_p of the bar against x_p - l_p of the other body, or the wall face
    x = L), over the first half transit of the impact wave, in cells."""
    mat = IsotropicElastic(E=E, nu=0.0, rho=RHO)
    case = Case(name="bar_impact", analysis="plane_strain", thickness=1.0, materials={"m": mat},
                bodies=[Body("bar", Rectangle(0.0, 0.0, L, H), "m"), Body("other", second, "m")],
                interfaces=[InterfacePair("bar", "other", CoulombFriction(0.0))])
    v = {"bar": [V0, 0.0]} if rigid else {"bar": [V0, 0.0], "other": [-V0, 0.0]}
    model = Model(case, merge(case, dict({"cell": 1.0, "damping": "none", "update": "usl",
                                          "progress": False, "normal": "AG",
                                          "rigid_bodies": ["other"] if rigid else [],
                                          "separation": "velocity", "initial_velocity": v},
                                         **opts)))
    run = _Runner(model)
    pt = model.particles
    bar, other = pt.field == 0, pt.field == 1
    worst = 0.0
    for _ in range(int(0.5 * L / C / model.dt)):
        run._advance(1)
        face = L if rigid else float(np.min(pt.x[other, 0] - pt.lp[0]))
        worst = max(worst, float(np.max(pt.x[bar, 0] + pt.lp[0])) - face)
    return worst


@pytest.mark.parametrize("opts", [{}, {"xpic": 5}, {"xpic": 5, "xpic_correction": False}])
def test_bar_striking_a_rigid_wall_stays_out_of_it(opts):
    assert _impact(Rectangle(L, -1.0, 3.0, H + 2.0), True, opts) < 0.01


@pytest.mark.parametrize("opts", [{}, {"xpic": 5}, {"xpic": 5, "xpic_correction": False}])
def test_colliding_bars_stay_out_of_each_other(opts):
    assert _impact(Rectangle(L, 0.0, L, H), False, opts) < 0.03


def _ellipse_pair_J(opts: dict) -> tuple[float, float]:
    """Two ellipses in a rigid box struck by the piston at 100 m/s (004 Fig 6 case, DF
    contact, CPDI, 0.05 mm cells) to 35 % compression with the MUSL update: (mean,
    smallest) J of the ellipse particles."""
    import cases
    from cases.methods import run
    case = cases.build("ellipse_compaction", contact="DF", mpm_cell=0.05, strain=0.35, n=2)
    res = run(case, "mpm", progress=False, shape="cpdi", update="musl", **opts)
    F = res.fields["deformation_gradient"].reshape(-1, 3, 3)[:, :2, :2]
    names = [b.name for b in case.bodies]
    rigid = set(case.discretization["mpm"]["rigid_bodies"])
    J = np.linalg.det(F)[[names[m] not in rigid for m in res.fields["material"]]]
    return float(J.mean()), float(J.min())


def test_musl_with_xpic_does_not_crush_the_contact_surfaces():
    """MUSL re-extrapolates S v~ and corrects it for contact; on contact nodes the
    momenta are those of v~ the particles moved with (mpm.xpic_contact
    musl_contact_momenta). Measured (mean, smallest J): FLIP 0.9936, 0.871; XPIC(5)
    0.9915, 0.863; PIC 0.9923, 0.888. Re-extrapolated momenta at the contact nodes gave
    XPIC(5) 0.9808, 0.535 and PIC 0.9865, 0.762 (when FLIP read 0.9928, 0.861)."""
    mean_flip, low_flip = _ellipse_pair_J({})
    for opts in ({"xpic": 5}, {"xpic": 1}):
        mean, low = _ellipse_pair_J(opts)
        assert low > low_flip - 0.04, opts
        assert abs(mean - mean_flip) < 0.003, opts


def test_only_contact_conditions_reach_the_grid_velocity():
    """Friction and stick are kept, a perfect bond only to a rigid partner, an imperfect
    interface only as its compressive no-penetration part (its springs are in a_alpha);
    zones are reduced by the same rule."""
    inf = np.inf
    kind = np.array([[LAW_NONE, LAW_PERFECT, LAW_IMPERFECT, LAW_FRICTION],
                     [LAW_PERFECT, LAW_NONE, LAW_IMPERFECT, LAW_PERFECT],
                     [LAW_IMPERFECT, LAW_IMPERFECT, LAW_NONE, LAW_STICK],
                     [LAW_FRICTION, LAW_PERFECT, LAW_STICK, LAW_NONE]], dtype=np.int64)
    params = np.zeros((4, 4, 4))
    params[0, 3, P_MU] = params[3, 0, P_MU] = 0.3
    params[0, 2] = params[2, 0] = (10.0, 5.0, inf, 0.0)     # springs, perfect in compression
    params[1, 2] = params[2, 1] = (inf, 5.0, inf, 0.0)      # bonded normal direction
    rigid = np.array([0, 0, 0, 1], dtype=np.int64)
    zone_pairs = np.array([[0, 1], [0, 1]], dtype=np.int64)
    zone_kind = np.array([LAW_FRICTION, LAW_IMPERFECT], dtype=np.int64)
    zone_params = np.array([[0.0, 0.0, 0.0, 0.5], [1.0, 2.0, 3.0, 0.0]])
    k, p, zk, zp, left = contact_laws(kind, params, zone_pairs, zone_kind, zone_params, rigid)
    assert left
    assert k[0, 1] == k[1, 0] == LAW_NONE                        # perfect bond: none
    assert k[1, 3] == k[3, 1] == LAW_PERFECT                     # ... to a rigid body: kept
    assert k[0, 3] == LAW_FRICTION and p[0, 3, P_MU] == 0.3
    assert k[2, 3] == LAW_STICK
    assert k[0, 2] == LAW_IMPERFECT and tuple(p[0, 2]) == (10.0, 0.0, inf, 0.0)
    assert k[1, 2] == LAW_NONE
    assert list(zk) == [LAW_FRICTION, LAW_NONE] and zp[0, P_MU] == 0.5
    bonded = np.where(kind == LAW_PERFECT, LAW_PERFECT, LAW_NONE)
    assert not contact_laws(bonded, params, zone_pairs[:0], zone_kind[:0], zone_params[:0],
                            np.zeros(4, dtype=np.int64))[4]


def test_musl_contact_momenta_leave_a_light_field_its_reextrapolated_momentum():
    """On a contact node, a heavy field takes the velocity its particles moved with,
    (1 - pic) v+ + pic v~, while a field under MUSL_LIGHT_FIELD of the node's mass keeps
    its re-extrapolated momentum: its v+ is f dt / m of particle tails and unbounded
    (1e7 mm/s in a packing moving at 1e5, docs/mpm.md "Explicit 3+ nodes at fine
    grids"). A node whose pair obeys no contact condition is left alone."""
    from mpm.multimaterial import build_pair_tables
    from mpm.state import pair_tables

    def pairs_for(law):
        """Pair tables of two blocks meeting under ``law``, for one node of two fields."""
        case = Case(name="pair", analysis="plane_strain", thickness=1.0,
                    materials={"m": IsotropicElastic(E=E, nu=0.0, rho=RHO)},
                    bodies=[Body("a", Rectangle(0.0, 0.0, 1.0, 1.0), "m"),
                            Body("b", Rectangle(1.0, 0.0, 1.0, 1.0), "m")],
                    interfaces=[InterfacePair("a", "b", law)])
        return pair_tables(build_pair_tables(case, merge(case, {"cell": 1.0})), None, 1.0, 1, 2, 2)

    pairs = pairs_for(CoulombFriction(0.0))
    mass = np.array([[1.0, 0.1 * MUSL_LIGHT_FIELD]])
    mom = np.array([[[3.0, -1.0], [5e-4, 2e-4]]])
    vel = np.array([[[4.0, 2.0], [1e7, -3e7]]])
    vs = np.array([[[2.0, 0.0], [-1.0, 1.0]]])
    blend = 0.25
    kept = mom[0, 1].copy()
    assert musl_contact_momenta(mom, mass, vel, vs, blend, pairs, np.array([0])) == 1
    assert np.allclose(mom[0, 0], (1 - blend) * vel[0, 0] + blend * vs[0, 0], rtol=1e-15)
    assert np.array_equal(mom[0, 1], kept)
    mass[0, 1] = 10 * MUSL_LIGHT_FIELD                          # above the threshold: corrected
    musl_contact_momenta(mom, mass, vel, vs, blend, pairs, np.array([0]))
    assert np.allclose(mom[0, 1], mass[0, 1] * ((1 - blend) * vel[0, 1] + blend * vs[0, 1]))
    pairs = pairs_for(LinearInterface(np.inf, np.inf))         # bonded: no contact condition
    before = mom.copy()
    assert musl_contact_momenta(mom, mass, vel, vs, blend, pairs, np.array([0])) == 0
    assert np.array_equal(mom, before)
