"""Contact on the XPIC(m) grid velocity v~ (004 Sec 3.3 with the contact rules of Sec 3.2).

An XPIC(m) run moves its particles with the grid velocity v~ = m (v_alpha - v*_alpha) +
a_alpha dt of :mod:`mpm.xpic` (004 Eq 35, 41-44), not with the contact-corrected v+.
The series S+_alpha S mixes each field's velocities over neighbouring nodes, so at a
contact node v~ no longer obeys the contact law that v+ obeys there: a field pressed
against another (or against a rigid body) regains part of its approach velocity from
the nodes behind it and its particles move into the partner's domain (a bar striking
a rigid wall went 0.031 cell into it with XPIC(5), against 0.003 with FLIP; two
colliding bars overlapped 0.073 cell, against 0.009).

Here v~ is corrected once, after the series, on the step's multimaterial nodes, as v+
was by the second contact correction (004 Eq 31: normals and separations of the step,
the separation advanced to the end of the step with the velocities being corrected;
:func:`mpm.multimaterial_kernels.correct_momentum_kernel`), on scratch momenta m v~:
``NodalState.force`` is not touched (the accelerations a_alpha in v~ are already those
of the corrected v+, 004 Eq 33) and the caller re-imposes the nodal velocity conditions.

Only the laws that are contact conditions are applied to v~ (:func:`contact_laws`):

* stick and Coulomb friction (frictionless included): the no-penetration condition
  the particles would otherwise break;
* a perfect bond to a rigid body: the body imposes the field's velocity there, as a
  velocity condition does (those keep the conditioned v+ on v~ too);
* an imperfect interface perfect in compression only (000 Eq 17 with D_n,c -> inf):
  its compressive no-penetration part, as frictionless contact.

Left out are perfect bonds between deformable fields and every finite interface
stiffness. A perfect bond is not a contact condition but the single-body limit: the
corrected multimaterial series (Eq 37, 47) is what makes bonded fields follow
single-material XPIC(m); forcing the fields onto their centre-of-mass v~ at every
bonded node changes that result (the bonded split bar of tests/mpm/test_mpm_xpic.py
then departs from the one-body bar by 3.4e-4 of the peak stress near the interface,
where the corrected series alone keeps it below 3e-4).
An imperfect interface's spring traction (000 Eq 17-27) is already in a_alpha, hence
in the a_alpha dt of v~: correcting v~ for it would count it twice. Its bonded
directions (D = inf in tension, or tangentially) are left as perfect bonds are.

The same nodes matter once more in a MUSL step (mpm/step.py ``phase_musl``): the
updated particle velocities S v~ are re-extrapolated to the grid, S+_alpha S v~, and
corrected for contact (004 Eq 26) before the strain increment. That re-extrapolation
smooths each field's interior velocity into its contact nodes, where the correction
reads it as an approach v~ had already resolved and pushes the field's surface back
at the partner's velocity, every step: the surface particles' J ratchets down (two
ellipses struck at 100 m/s, DF, CPDI, 35 %: smallest J 0.54 with XPIC(5), 0.76 with
PIC, against 0.86 with FLIP; the whole 20-ellipse packing's median axial stress 5x
FLIP's). :func:`musl_contact_momenta` therefore gives those nodes the velocity the
particles moved with, (1 - pic) v+ + pic v~, before the correction (smallest J 0.85 and
0.87). Nodes where no pair obeys a contact condition (perfect bonds, interface springs)
keep the re-extrapolated momenta, so bonded fields still follow single-material MUSL.
So does a field holding less than ``MUSL_LIGHT_FIELD`` (1e-3) of its contact node's
mass: its v+ is (p + f dt) / m of a few particle tails whose shape functions barely
reach the node, where the weight is small and the gradient is not. In the 20-ellipse
packing at 0.025 mm (LR, explicit 3+ nodes) such a field held 6e-16 of a node's
4.5e-12 and had v+ of 1e7 to 5e7 mm/s in a packing moving at 1e5; taken into the
strain increment through the gradient, it inverted a particle and the run stopped on
NaN energies. The re-extrapolated momentum is a mean of particle velocities, hence
bounded. A threshold of 1e-2 also left fields between 1e-3 and 1e-2 uncorrected,
whose tail particles then grew into the partner (531 particles inside another ellipse
against 164 at 0.0143 mm, docs/mpm.md "Explicit 3+ nodes at fine grids"). The node's
mass counts every field, rigid ones included (their material sets it), so a tail field
beside a wall is caught as it is beside another body; the price is that beside a rigid
body some 1000x denser than the deformable material whole fields would fall under the
threshold and lose the pass (no case has such a body).

NairnMPM imposes its contact laws on every increment of the XPIC series, with the
contact state of the step kept from the momentum correction; here the series of
:mod:`mpm.xpic` runs uncorrected and its result is corrected once, with the contact
state evaluated on v~ itself.
"""
from __future__ import annotations

import math

import numpy as np

from interfaces.jit import njit

from .multimaterial_constants import (
    LAW_FRICTION, LAW_IMPERFECT, LAW_NONE, LAW_PERFECT, LAW_STICK, P_DN_COMPRESSION,
    P_DN_TENSION, P_DT,
)
from .multimaterial_kernels import _pair_law, correct_momentum_kernel

MUSL_LIGHT_FIELD = 1e-3
"""Share of a contact node's mass below which a field keeps its re-extrapolated momentum
in the MUSL step of an XPIC run (:func:`musl_contact_momenta`, module docstring)."""


@njit(cache=True)
def _contact_law(code: int, params, rigid_pair: bool, out) -> int:
    """The part of one pair law (``code``, ``params``) that v~ obeys; its parameters into
    ``out``. Returns LAW_NONE where the law sets no contact condition."""
    out[:] = params
    if code == LAW_STICK or code == LAW_FRICTION:
        return code
    if code == LAW_PERFECT:
        return code if rigid_pair else LAW_NONE
    if code == LAW_IMPERFECT and math.isinf(params[P_DN_COMPRESSION]) and \
            not math.isinf(params[P_DN_TENSION]):
        out[P_DT] = 0.0                          # the tangential spring: already in a_alpha
        return code
    return LAW_NONE


@njit(cache=True)
def contact_laws(kind, params, zone_pairs, zone_kind, zone_params, rigid):
    """Pair and zone law tables reduced to their contact conditions (module docstring);
    returns (kind, params, zone_kind, zone_params, any contact condition left)."""
    m = kind.shape[0]
    kind_c = np.empty_like(kind)
    params_c = np.empty_like(params)
    zone_kind_c = np.empty_like(zone_kind)
    zone_params_c = np.empty_like(zone_params)
    left = False
    for a in range(m):
        for b in range(m):
            kind_c[a, b] = _contact_law(kind[a, b], params[a, b], rigid[a] != 0 or rigid[b] != 0,
                                        params_c[a, b])
            left = left or kind_c[a, b] != LAW_NONE
    for z in range(zone_kind.shape[0]):
        a = zone_pairs[z, 0]
        b = zone_pairs[z, 1]
        zone_kind_c[z] = _contact_law(zone_kind[z], zone_params[z], rigid[a] != 0 or rigid[b] != 0,
                                      zone_params_c[z])
        left = left or zone_kind_c[z] != LAW_NONE
    return kind_c, params_c, zone_kind_c, zone_params_c, left


@njit(cache=True)
def contact_grid_velocity(vs, mass, vol, grad, disp, pos, cell, origin, nn, pairs, dt,
                          nodes) -> int:
    """Correct the XPIC grid velocity ``vs`` [N, M, D] (v~) in place on the multimaterial
    ``nodes`` for the contact conditions of ``pairs`` (module docstring); returns the
    number of nodes changed."""
    kind, params, zone_kind, zone_params, left = contact_laws(
        pairs.law_kind, pairs.law_params, pairs.zone_pairs, pairs.zone_kind, pairs.zone_params,
        pairs.rigid)
    if not left or nodes.size == 0:
        return 0
    N, M, D = vs.shape
    mom = np.empty((N, M, D))
    force = np.empty((N, M, D))
    for q in range(nodes.size):
        i = nodes[q]
        for f in range(M):
            for d in range(D):
                mom[i, f, d] = mass[i, f] * vs[i, f, d]
                force[i, f, d] = 0.0
    changed = correct_momentum_kernel(
        1, mass, mom, force, vol, grad, disp, pos, cell, origin, nn, pairs.thickness, kind, params,
        pairs.settings, pairs.rigid, pairs.node_zone, pairs.zone_pairs, zone_kind, zone_params,
        pairs.lr_normal, pairs.lr_separation, pairs.lr_pair_normal, pairs.lr_pair_separation,
        pairs.lr_rigid_separation, pairs.df_curve, dt, nodes)
    for q in range(nodes.size):
        i = nodes[q]
        for f in range(M):
            if mass[i, f] > 0.0:
                for d in range(D):
                    vs[i, f, d] = mom[i, f, d] / mass[i, f]
    return changed


@njit(cache=True)
def musl_contact_momenta(mom, mass, vel, vs, blend, pairs, nodes) -> int:
    """MUSL step of an XPIC(m) run: on the multimaterial ``nodes`` where some pair of the
    fields present obeys a contact condition (:func:`contact_laws`), the momenta ``mom``
    [N, M, D] re-extrapolated from the particles become m ((1 - blend) v+ + blend v~)
    (``vel`` v+, ``vs`` v~: the grid velocity the particles moved with; module
    docstring); fields under ``MUSL_LIGHT_FIELD`` of the node's mass keep theirs. Returns
    the number of nodes changed."""
    kind, params, zone_kind, zone_params, left = contact_laws(
        pairs.law_kind, pairs.law_params, pairs.zone_pairs, pairs.zone_kind, pairs.zone_params,
        pairs.rigid)
    if not left:
        return 0
    M = mass.shape[1]
    D = mom.shape[2]
    law = np.empty(params.shape[2])
    changed = 0
    for q in range(nodes.size):
        i = nodes[q]
        contact = False
        for a in range(M):
            for b in range(a + 1, M):
                if mass[i, a] > 0.0 and mass[i, b] > 0.0 and _pair_law(
                        i, a, b, kind, params, pairs.node_zone, pairs.zone_pairs, zone_kind,
                        zone_params, law) != LAW_NONE:
                    contact = True
        if not contact:
            continue
        changed += 1
        light = MUSL_LIGHT_FIELD * np.sum(mass[i])
        for f in range(M):
            if mass[i, f] < light:
                continue
            for d in range(D):
                mom[i, f, d] = mass[i, f] * ((1.0 - blend) * vel[i, f, d] + blend * vs[i, f, d])
    return changed
