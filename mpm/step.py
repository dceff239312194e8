"""The one explicit MPM time step, and the compiled loop that runs chunks of them.

Every run (one material or several, contact or imperfect interfaces, normals and
separations from the volume gradients or from logistic regression) goes through
:func:`run_steps`: the state travels in the bundles of :mod:`mpm.state` and each
step is assembled from named phases, in the order of 004 Sec 3.2 (Eq 26-34) and
mpm/LAYOUT.md:

1. :func:`phase_p2g`: mass, momentum, internal and external forces (000 Eq 5-6) and,
   with 2+ fields, volumes, volume gradients, displacements, positions (Eq 10-13, 32);
   axisymmetric runs add the hoop force (:func:`phase_axisymmetric`); B2 runs fold
   the reflected material of their symmetry sides (:func:`phase_fold`);
2. :func:`phase_multimaterial_nodes`: the nodes seen by 2+ fields, the nodal
   displacements taken to the node (mpm/extrapolation.py) and, with LR, the logistic-
   regression normals and separations of this particle cloud (004 Eq 19-25);
3. :func:`phase_contact` 0: the contact-corrected extrapolation (004 Eq 26);
4. USF only: :func:`phase_stress` from the extrapolated momenta, internal force again;
5. :func:`phase_interface_forces`: the imperfect-interface forces (000 Eq 17-27);
6. :func:`phase_grid_update`: grid damping, momentum update, nodal velocity conditions;
7. :func:`phase_contact` 1 and the bonded velocity conditions (004 Eq 31, 33);
8. :func:`phase_g2p`: FLIP/PIC particle update, x += dt sum S v+, velocity gradient,
   and (USL) the stress update (axisymmetric: with the hoop strain; the fields with a
   deformation gradient: :func:`phase_finite_strain`, mpm/finite_strain.py);
   XPIC(m) runs (mpm/xpic.py): the XPIC grid velocity before it (with the v_alpha and
   Delta v_alpha kept around step 3), the XPIC(m) blend of velocities and positions
   after it (004 Eq 35-44);
9. MUSL only: :func:`phase_musl` (stress from the updated particle momenta
   re-extrapolated with the start-of-step shape functions);
10. kinetic damping and the history row.

The variant switches (update scheme, LR, interfaces, force-limit check) are read once
per step from :class:`mpm.state.StepControl`; the particle and node loops themselves
are those of :mod:`mpm.kernels`, :mod:`mpm.parallel` and
:mod:`mpm.multimaterial_kernels`.

``hist[s] = (t, kinetic, strain, work_ext, dissipated, work_bc, interface, grid
kinetic)`` after step s (work and dissipation columns are that step's increments), the
columns of ``mpm.solver.HIST_COLUMNS``.
"""
from __future__ import annotations

import numpy as np

from interfaces.jit import njit

from .axisymmetric import (hoop_force, hoop_from_motion, hoop_stress_update,
                           interface_volumes, radial_velocity, zero_axis_gradients)
from .extrapolation import displacement_to_nodes
from .kernels import (MUSL, USF, USL, fold_ghosts, grid_update, multimaterial_nodes,
                      nodal_kinematics, p2g_internal_force_2d, p2g_momentum_2d, ramp,
                      reflect_ghosts, set_velocity_bc, step_velocities, stress_from_grid_2d)
from .finite_strain import finite_strain_update
from .multimaterial_constants import OUT_STATUS, STATUS_OVER_LIMIT
from .multimaterial_kernels import (bonded_velocity_bc_kernel, correct_momentum_kernel,
                                    interface_forces_kernel, stick_limited_kernel)
from .multimaterial_lr import lr_kernel
from .kernels3d import p2g_internal_force_3d, p2g_momentum_3d, stress_from_grid_3d
from .parallel import g2p_blocks, p2g_blocks
from .cpdi import g2p_cpdi, internal_force_cpdi, is_cpdi, momentum_cpdi, p2g_cpdi, stress_cpdi
from .xpic import VS as XPIC_VS, phase_xpic_grid, phase_xpic_particles, phase_xpic_save, phase_xpic_start
from .xpic_contact import musl_contact_momenta

_OVER_LIMIT = int(STATUS_OVER_LIMIT)


@njit(cache=True, inline="always")
def phase_p2g(pt, grid, nd, blocks, scale, multi, internal) -> int:
    """Step 1: P2G over the particle blocks (race-free, mpm/parallel.py). ``internal``
    False (USF) leaves the internal force for after the stress update. Returns the
    index of a particle outside the grid, or -1. CPDI shapes: mpm/cpdi.py. 2D XPIC(m)
    runs: P2G also writes the particles' stencils for the XPIC passes (mpm/xpic.py)."""
    if is_cpdi(grid.kind):
        return p2g_cpdi(pt.x, pt.v, pt.mass, pt.volume, pt.stress, pt.field, pt.x0, pt.F,
                        pt.half_width, pt.fext, pt.foff, pt.foff0, scale, grid.origin,
                        grid.cell, grid.nn, grid.kind, multi, internal, nd.mass, nd.momentum,
                        nd.force, nd.volume, nd.volume_gradient, nd.displacement, nd.position)
    return p2g_blocks(pt.x, pt.v, pt.mass, pt.volume, pt.stress, pt.field, pt.x0, pt.fext,
                      pt.foff, scale, grid.origin, grid.cell, grid.nn, pt.lp, grid.kind,
                      multi, internal, nd.mass, nd.momentum, nd.force, nd.volume,
                      nd.volume_gradient, nd.displacement, nd.position, blocks.mass,
                      blocks.mom, blocks.force, blocks.volume, blocks.volgrad, blocks.disp,
                      blocks.pos, pt.xpic_node, pt.xpic_weight)


@njit(cache=True, inline="always")
def phase_axisymmetric(pt, grid, nd, pairs) -> None:
    """Step 1, axisymmetric (mpm/axisymmetric.py): the hoop term of the internal force;
    with 2+ fields the nodal volumes of 000 Eq 20 with t -> r_i and no radial volume
    gradient on the axis (000 Sec 2.5)."""
    hoop_force(pt.x, pt.volume, pt.stress, pt.field, grid.origin, grid.cell, grid.nn, pt.lp,
               grid.kind, nd.force)
    if nd.volume.shape[0]:
        interface_volumes(pt.x, pt.volume, pt.field, grid.origin, grid.cell, grid.nn, pt.lp,
                          grid.kind, pairs.thickness, nd.volume, nd.volume_gradient)
        zero_axis_gradients(nd.volume_gradient, grid.axis_nodes)


@njit(cache=True, inline="always")
def phase_multimaterial_nodes(ctl, pt, grid, nd, pairs):
    """Step 2: the nodes where 2+ fields have mass, their nodal displacements taken to
    the node (``linear_u``) and, with LR, this step's normals and separations (004 Eq
    19-25) into ``pairs.lr_normal`` / ``pairs.lr_separation``."""
    nodes = multimaterial_nodes(nd.mass)
    if nodes.size == 0:
        return nodes
    if ctl.linear_u:
        displacement_to_nodes(nd.mass, nd.displacement, nd.position, nodes, grid.origin,
                              grid.cell, grid.nn, pairs.law_kind, pairs.law_params,
                              pairs.node_zone, pairs.zone_pairs, pairs.zone_kind,
                              pairs.zone_params,
                              np.empty((nodes.size, nd.mass.shape[1], nd.momentum.shape[2])))
    phase_lr(ctl, pt, grid, nd, pairs, nodes)
    return nodes


@njit(cache=True, inline="always")
def phase_lr(ctl, pt, grid, nd, pairs, nodes) -> None:
    """LR normals and separations of the point clouds of ``nodes`` (004 Eq 19-25; the
    clouds depend on the shape functions ``grid.kind``, mpm/multimaterial_lr.py): the
    particle radii R_p of Eq 25 from the undeformed half widths ``pt.half_width``,
    deformed by F in finite-strain runs (linear fields keep F = I) and in CPDI runs
    (every particle carries F)."""
    if ctl.uses_lr and nodes.size:
        lr_kernel(pt.x, pt.field, pt.half_width, pt.F, ctl.finite_strain or is_cpdi(grid.kind),
                  grid.kind, grid.origin, grid.cell, grid.nn, nd.mass, nodes,
                  ctl.mass_tolerance, pairs.rigid, pairs.lr_normal, pairs.lr_separation,
                  pairs.lr_pair_normal, pairs.lr_pair_separation, pairs.lr_rigid_separation)


@njit(cache=True, inline="always")
def phase_contact(phase, ctl, grid, nd, pairs, nodes) -> None:
    """Steps 3 and 7: contact / perfect-bond momentum correction on ``nodes`` (004 Eq
    26 for ``phase`` 0, Eq 31 and 33 for ``phase`` 1; see
    :func:`mpm.multimaterial.correct_momentum`)."""
    correct_momentum_kernel(phase, nd.mass, nd.momentum, nd.force, nd.volume,
                            nd.volume_gradient, nd.displacement, nd.position, grid.cell,
                            grid.origin, grid.nn, pairs.thickness, pairs.law_kind,
                            pairs.law_params, pairs.settings, pairs.rigid, pairs.node_zone,
                            pairs.zone_pairs, pairs.zone_kind, pairs.zone_params, pairs.lr_normal,
                            pairs.lr_separation, pairs.lr_pair_normal, pairs.lr_pair_separation,
                            pairs.lr_rigid_separation, pairs.df_curve, ctl.dt, nodes)


@njit(cache=True, inline="always")
def phase_stress(ctl, pt, grid, nd, x) -> float:
    """Stress update from the nodal momenta with the shape functions at positions ``x``
    (USF: before the update, at the particles; MUSL: after the re-extrapolation, at the
    start-of-step positions); returns the strain energy of the linear fields (the
    finite-strain fields get their velocity gradients stored for
    :func:`phase_finite_strain`)."""
    if is_cpdi(grid.kind):
        return stress_cpdi(x, pt.volume, pt.volume0, pt.stress, pt.strain, pt.field, pt.foff,
                           pt.foff0, pt.F, pt.half_width, ctl.C, grid.origin, grid.cell, grid.nn,
                           grid.kind, ctl.dt, nd.mass, nd.momentum, pt.velgrad,
                           ctl.material_kind)
    if x.shape[1] == 3:
        return stress_from_grid_3d(x, pt.volume, pt.volume0, pt.stress, pt.strain, pt.field,
                                   ctl.C, grid.origin, grid.cell, grid.nn, pt.lp, grid.kind,
                                   ctl.dt, nd.mass, nd.momentum, pt.velgrad, ctl.material_kind)
    return stress_from_grid_2d(x, pt.volume, pt.volume0, pt.stress, pt.strain, pt.field,
                               ctl.C, grid.origin, grid.cell, grid.nn, pt.lp, grid.kind, ctl.dt,
                               nd.mass, nd.momentum, pt.velgrad, ctl.material_kind)


@njit(cache=True, inline="always")
def phase_finite_strain(ctl, pt) -> float:
    """The finite-strain fields' stress update from the velocity gradients the stress
    phase stored (mpm/finite_strain.py: F <- (I + dt L) F, V = J V0, neo-Hookean Cauchy
    stress of 004 Eq 18); returns their strain energy (0 without such fields)."""
    if not ctl.finite_strain:
        return 0.0
    return finite_strain_update(pt.velgrad, pt.F, pt.stress, pt.strain, pt.volume, pt.volume0,
                                pt.x, pt.x0, pt.foff, pt.foff0, pt.field, ctl.material_kind,
                                ctl.material_params, ctl.dt, ctl.axisymmetric, pt.eos)


@njit(cache=True, inline="always")
def phase_internal_force(pt, grid, nd) -> None:
    """USF: the internal force -V sigma . grad S from the updated stress."""
    if is_cpdi(grid.kind):
        internal_force_cpdi(pt.x, pt.volume, pt.stress, pt.field, pt.F, pt.half_width,
                            grid.origin, grid.cell, grid.nn, grid.kind, nd.force)
    elif pt.x.shape[1] == 3:
        p2g_internal_force_3d(pt.x, pt.volume, pt.stress, pt.field, grid.origin, grid.cell,
                              grid.nn, pt.lp, grid.kind, nd.force)
    else:
        p2g_internal_force_2d(pt.x, pt.volume, pt.stress, pt.field, grid.origin, grid.cell,
                              grid.nn, pt.lp, grid.kind, nd.force)


@njit(cache=True, inline="always")
def _count_over_limit(node_out, nodes) -> int:
    """Multimaterial nodes flagged above the 000 Eq 26 force bound this step."""
    c = 0
    for k in range(nodes.shape[0]):
        if int(node_out[nodes[k], OUT_STATUS]) & _OVER_LIMIT:
            c += 1
    return c


@njit(cache=True, inline="always")
def phase_interface_forces(ctl, t, grid, nd, pairs, nodes, over_limit) -> float:
    """Step 5: imperfect-interface forces into ``nd.force`` (000 Eq 17-27); returns the
    interfacial energy. With force limiting off, counts the nodes above the Eq 26
    bound into ``over_limit`` (steps, most nodes in one step, first time)."""
    u_int = interface_forces_kernel(nd.mass, nd.momentum, nd.volume, pairs.area_volume,
                                    nd.volume_gradient, nd.displacement, nd.position, grid.cell,
                                    grid.origin, grid.nn, pairs.thickness,
                                    pairs.law_kind, pairs.law_params, pairs.settings,
                                    pairs.rigid, pairs.node_zone, pairs.zone_pairs,
                                    pairs.zone_kind, pairs.zone_params, pairs.lr_normal,
                                    pairs.lr_separation, pairs.lr_rigid_separation,
                                    pairs.df_curve, ctl.dt, nd.force,
                                    pairs.node_out, nodes)
    if ctl.check_limit:
        over = _count_over_limit(pairs.node_out, nodes)
        if over:
            over_limit[0] += 1.0
            over_limit[1] = max(over_limit[1], float(over))
            if over_limit[2] < 0.0:
                over_limit[2] = t
    return u_int


@njit(cache=True, inline="always")
def phase_bonded_conditions(ctl, nd, bc, pairs, vel, with_force) -> float:
    """Re-impose the nodal velocity conditions on their fields and the fields perfectly
    bonded to them after a contact correction; returns the reactions' work."""
    if bc.vel.size == 0:
        return 0.0
    work = bonded_velocity_bc_kernel(nd.mass, nd.momentum, nd.force, bc.node, bc.field,
                                     bc.comp, vel, pairs.law_kind, pairs.law_params,
                                     pairs.settings, pairs.node_zone, pairs.zone_pairs,
                                     pairs.zone_kind, pairs.zone_params, ctl.dt, with_force)
    return work + phase_ghosts(ctl, nd, bc, vel, with_force)


@njit(cache=True, inline="always")
def phase_fold(nd, bc, vel, with_force) -> None:
    """B2 runs: the reflected material of the symmetry sides folded onto the nodes
    inside after an extrapolation, and the ghosts given the reflected velocities
    (:class:`mpm.boundary.GhostNodes`)."""
    if bc.ghost_node.size == 0:
        return
    fold_ghosts(nd.mass, nd.momentum, nd.force, bc.ghost_node, bc.ghost_field, bc.ghost_comp,
                bc.ghost_mirror, bc.ghost_ref, bc.ghost_plane, bc.plane_node, bc.plane_field,
                bc.plane_of, vel, with_force, nd.real_mass)
    reflect_ghosts(nd.mass, nd.momentum, nd.force, 1.0, bc.ghost_node, bc.ghost_field,
                   bc.ghost_comp, bc.ghost_mirror, bc.ghost_ref, vel, False, nd.real_mass)


@njit(cache=True, inline="always")
def phase_ghosts(ctl, nd, bc, vel, with_force) -> float:
    """B2 runs: the ghost nodes beyond the sides reflected from their mirror nodes
    (:class:`mpm.boundary.GhostNodes`), after every imposition of the conditions;
    returns the reactions' work."""
    if bc.ghost_node.size == 0:
        return 0.0
    return reflect_ghosts(nd.mass, nd.momentum, nd.force, ctl.dt, bc.ghost_node, bc.ghost_field,
                          bc.ghost_comp, bc.ghost_mirror, bc.ghost_ref, vel, with_force,
                          nd.real_mass)


@njit(cache=True, inline="always")
def phase_grid_update(ctl, alpha, nd, bc, vel):
    """Step 6: grid damping, p+ = p + f dt, nodal velocity conditions ``vel`` of the
    step; returns (dissipated, work_bc)."""
    diss, wbc = grid_update(nd.mass, nd.momentum, nd.force, ctl.dt, alpha, bc.node, bc.field,
                            bc.comp, vel, nd.real_mass)
    return diss, wbc + phase_ghosts(ctl, nd, bc, vel, True)


@njit(cache=True, inline="always")
def phase_g2p(ctl, pt, grid, nd, blocks, scale):
    """Step 8: nodal velocity and acceleration, then G2P over the particle blocks (FLIP
    with the ``pic`` blend; USL also updates the stress, the finite-strain fields' after
    the particles moved, so the hoop stretch is r+ / r0). Returns (kinetic, strain
    energy of the linear fields (USL and USF: of every field but the finite-strain
    fields' of USF, added by the caller), external work increment, lost particle or -1,
    grid kinetic energy, kinetic energy before an XPIC blend). XPIC(m) runs reuse the
    nodal kinematics of :func:`mpm.xpic.phase_xpic_grid` (the nodal momenta and forces
    are those it read); with the 2D tensor-product shapes G2P also blends the XPIC
    velocity v~ in (004 Eq 35, :func:`mpm.kernels.g2p_range_2d`)."""
    if ctl.xpic < 1:
        nodal_kinematics(nd.mass, nd.momentum, nd.force, nd.velocity, nd.acceleration)
    if ctl.mode == MUSL:
        pt.x_before[:] = pt.x
    hoop = ctl.axisymmetric and ctl.mode == USL
    if hoop:
        pt.r_before[:] = pt.x[:, 0]
        pt.strain_before[:] = pt.strain
    if is_cpdi(grid.kind):
        ke, U, work, lost, ke_grid = g2p_cpdi(
            pt.x, pt.v, pt.mass, pt.volume, pt.volume0, pt.stress, pt.strain, pt.field, pt.fext,
            pt.foff, pt.foff0, pt.F, pt.half_width, scale, ctl.C, grid.origin, grid.cell,
            grid.nn, grid.kind, ctl.dt, ctl.pic, ctl.mode == USL, nd.velocity, nd.acceleration,
            pt.velgrad, ctl.material_kind)
        ke_flip = ke
    else:
        nb = blocks.mass.shape[0]
        # the 2D tensor-product XPIC runs keep no particle extrapolations (mpm/xpic.py);
        # without XPIC the G2P loop is compiled without the blend
        if ctl.xpic >= 1 and pt.xpic.shape[0] == 0:
            ke, U, work, lost, ke_grid, ke_flip = g2p_blocks(
                nb, pt.x, pt.v, pt.mass, pt.volume, pt.volume0, pt.stress, pt.strain, pt.field,
                pt.fext, pt.foff, scale, ctl.C, grid.origin, grid.cell, grid.nn, pt.lp,
                grid.kind, ctl.dt, ctl.pic, ctl.mode == USL, nd.velocity, nd.acceleration,
                pt.velgrad, ctl.material_kind, ctl.xpic_blend, nd.xpic[XPIC_VS].reshape(-1))
        else:
            ke, U, work, lost, ke_grid, ke_flip = g2p_blocks(
                nb, pt.x, pt.v, pt.mass, pt.volume, pt.volume0, pt.stress, pt.strain, pt.field,
                pt.fext, pt.foff, scale, ctl.C, grid.origin, grid.cell, grid.nn, pt.lp,
                grid.kind, ctl.dt, ctl.pic, ctl.mode == USL, nd.velocity, nd.acceleration,
                pt.velgrad, ctl.material_kind, 0.0, None)
    if hoop and lost < 0:
        hoop_from_motion(pt.x, pt.r_before, pt.d_hoop)
        U = hoop_stress_update(pt.d_hoop, pt.strain_before, pt.stress, pt.strain, pt.volume,
                               pt.volume0, pt.field, ctl.C, ctl.material_kind)
    if ctl.mode == USL and lost < 0:
        U += phase_finite_strain(ctl, pt)
    return ke, U, work, lost, ke_grid, ke_flip


@njit(cache=True, inline="always")
def phase_musl(ctl, pt, grid, nd, bc, pairs, vel, nodes) -> float:
    """Step 9 (MUSL): the updated particle momenta re-extrapolated to the grid with the
    start-of-step shape functions (``pt.x_before``: the masses, hence the multimaterial
    ``nodes``, and the LR normals of this step stay those of the first extrapolation;
    the reference code re-extrapolates at the updated positions on the contact nodes it
    already knows, which changed the smallest J of a two-ellipse impact by < 0.05), the
    velocity conditions, the contact correction (XPIC(m): on contact nodes from the
    velocity the particles moved with, :func:`mpm.xpic_contact.musl_contact_momenta`)
    and the stick of the force-limited interface directions on ``nodes`` applied to
    them, then the strain increment from them
    with the same shape-function gradients (finite-strain fields: F from them, hoop
    stretch r+ / r0); returns the strain energy."""
    x = pt.x_before
    if is_cpdi(grid.kind):
        momentum_cpdi(x, pt.v, pt.mass, pt.field, pt.F, pt.half_width, grid.origin, grid.cell,
                      grid.nn, grid.kind, nd.mass, nd.momentum)
    elif x.shape[1] == 3:
        p2g_momentum_3d(x, pt.v, pt.mass, pt.field, grid.origin, grid.cell, grid.nn, pt.lp,
                        grid.kind, nd.mass, nd.momentum)
    else:
        p2g_momentum_2d(x, pt.v, pt.mass, pt.field, grid.origin, grid.cell, grid.nn, pt.lp,
                        grid.kind, nd.mass, nd.momentum)
    phase_fold(nd, bc, vel, False)
    set_velocity_bc(nd.mass, nd.momentum, bc.node, bc.field, bc.comp, vel)
    phase_ghosts(ctl, nd, bc, vel, False)
    if nodes.size:
        if ctl.xpic >= 1:
            musl_contact_momenta(nd.momentum, nd.mass, nd.velocity, nd.xpic[XPIC_VS],
                                 ctl.xpic_blend, pairs, nodes)
        phase_contact(0, ctl, grid, nd, pairs, nodes)
        if ctl.with_interface:
            stick_limited_kernel(nd.mass, nd.momentum, pairs.node_out, nodes)
        phase_bonded_conditions(ctl, nd, bc, pairs, vel, False)
    if not ctl.axisymmetric:
        return phase_stress(ctl, pt, grid, nd, x) + phase_finite_strain(ctl, pt)
    pt.strain_before[:] = pt.strain
    phase_stress(ctl, pt, grid, nd, x)
    radial_velocity(x, pt.field, grid.origin, grid.cell, grid.nn, pt.lp, grid.kind,
                    nd.mass, nd.momentum, pt.d_hoop)
    for p in range(x.shape[0]):
        pt.d_hoop[p] *= ctl.dt / x[p, 0]
    return hoop_stress_update(pt.d_hoop, pt.strain_before, pt.stress, pt.strain, pt.volume,
                              pt.volume0, pt.field, ctl.C, ctl.material_kind) \
        + phase_finite_strain(ctl, pt)


@njit(cache=True, inline="always")
def kinetic_damping_step(kinetic_damping, ke, ke_prev, v):
    """Kinetic damping: zero the particle velocities when the kinetic energy has just
    peaked. Updates ``ke_prev`` (last two kinetic energies) in place; returns (ke,
    energy dissipated)."""
    diss = 0.0
    if kinetic_damping and ke < ke_prev[0] and ke_prev[0] >= ke_prev[1]:
        v[:] = 0.0
        diss = ke
        ke = 0.0
    ke_prev[1] = ke_prev[0]
    ke_prev[0] = ke
    return ke, diss


@njit(cache=True, inline="always")
def time_step(ctl, alpha, t, pt, grid, nd, bc, pairs, blocks, vel, over_limit, row) -> int:
    """One complete time step from time ``t`` (module docstring, steps 1-10). The
    energies go into ``row`` (a history row without its time). Returns the index of a
    particle that left the grid, or -1."""
    multi_fields = nd.mass.shape[1] > 1
    scale = ramp(t, ctl.ramp_time, ctl.ramp_code)
    # the nodal conditions' velocities for t -> t + dt (their histories)
    step_velocities(t, ctl.dt, bc.vel, bc.t_end, bc.ramp, bc.t_ramp, vel)
    lost = phase_p2g(pt, grid, nd, blocks, scale, multi_fields, ctl.mode != USF)
    if lost >= 0:
        return lost
    if ctl.axisymmetric:
        phase_axisymmetric(pt, grid, nd, pairs)
    phase_fold(nd, bc, vel, True)
    nodes = phase_multimaterial_nodes(ctl, pt, grid, nd, pairs) if multi_fields \
        else np.empty(0, np.int64)
    multi = nodes.size > 0
    phase_xpic_save(ctl, nd)
    if multi:
        phase_contact(0, ctl, grid, nd, pairs, nodes)
    phase_xpic_start(ctl, nd)
    u_finite = 0.0
    if ctl.mode == USF:
        phase_stress(ctl, pt, grid, nd, pt.x)
        u_finite = phase_finite_strain(ctl, pt)
        phase_internal_force(pt, grid, nd)
    u_int = 0.0
    if multi and ctl.with_interface:
        u_int = phase_interface_forces(ctl, t, grid, nd, pairs, nodes, over_limit)
    diss, wbc = phase_grid_update(ctl, alpha, nd, bc, vel)
    if multi:
        phase_contact(1, ctl, grid, nd, pairs, nodes)
        wbc += phase_bonded_conditions(ctl, nd, bc, pairs, vel, True)
    phase_xpic_grid(ctl, pt, grid, nd, bc, pairs, nodes)
    ke, U, work, lost, ke_grid, ke_flip = phase_g2p(ctl, pt, grid, nd, blocks, scale)
    if lost >= 0:
        return lost
    ke, diss_xpic = phase_xpic_particles(ctl, pt, ke, ke_flip)
    diss += diss_xpic
    if ctl.mode == MUSL:
        U = phase_musl(ctl, pt, grid, nd, bc, pairs, vel, nodes)
    row[1] = ke
    U += u_finite
    row[2] = U
    row[3] = work
    row[4] = diss
    row[5] = wbc
    row[6] = u_int
    row[7] = ke_grid
    return -1


@njit(cache=True)
def run_steps(nsteps, t0, alpha, ctl, pt, grid, nd, bc, pairs, blocks, hist, ke_prev,
              over_limit):
    """``nsteps`` time steps from ``t0`` with grid damping ``alpha`` (constant over the
    chunk), recording ``hist``. Kinetic damping (``ctl.kinetic_damping``) zeroes the
    particle velocities whenever the kinetic energy has just peaked. Returns (steps
    done, index of a lost particle or -1); ``ke_prev`` (last two kinetic energies) and
    ``over_limit`` are updated in place."""
    vel = np.empty_like(bc.vel)
    t = t0
    for s in range(nsteps):
        row = hist[s]
        lost = time_step(ctl, alpha, t, pt, grid, nd, bc, pairs, blocks, vel, over_limit, row)
        if lost >= 0:
            return s, lost
        t += ctl.dt
        row[0] = t
        ke, dk = kinetic_damping_step(ctl.kinetic_damping, row[1], ke_prev, pt.v)
        row[1] = ke
        row[4] += dk
        if not np.isfinite(ke):
            return s + 1, -1
    return nsteps, -1
