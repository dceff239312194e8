"""Compiled chunk of explicit MPM steps for runs with 2+ material fields (2D).

One compiled loop over ``nsteps`` does, per step, exactly what the Python-driven loop
``mpm.solver._Runner._advance_multimaterial`` does (mpm/LAYOUT.md step order; 004 Sec
3.2, Eq 26-34): P2G with the multimaterial fields, the multimaterial node list, the
nodal displacements extrapolated to the node (``linear_u``, mpm/extrapolation.py),
contact correction phase 0 (004 Eq 26), the imperfect-interface forces (000 Eq 17-27),
the grid update with damping and velocity conditions, contact correction phase 1 (004
Eq 31, 33) and the bonded velocity conditions, nodal kinematics, G2P and the stress
update (USL / USF / MUSL). The node kernels are those of
:mod:`mpm.multimaterial_kernels`, called with the arguments the
:mod:`mpm.multimaterial` wrappers pass, so the arithmetic is identical; only the
per-step Python overhead and the wrappers' argument checks are gone. Runs whose
normals or separations come from logistic regression (004 Eq 19-25) stay in the Python
loop.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .chunk import kinetic_damping_step, record_step
from .extrapolation import displacement_to_nodes
from .kernels import (MUSL, USF, USL, grid_update, multimaterial_nodes, nodal_kinematics,
                      p2g_internal_force_2d, p2g_momentum_2d, ramp, set_velocity_bc, step_velocities,
                      stress_from_grid_2d)
from .multimaterial_constants import OUT_STATUS, STATUS_OVER_LIMIT
from .multimaterial_kernels import (bonded_velocity_bc_kernel, correct_momentum_kernel,
                                    interface_forces_kernel)
from .parallel import g2p_blocks_2d, p2g_blocks_2d

#: internal switch: False sends multimaterial runs through the Python-driven loop
#: (kept as the reference of the equivalence test)
COMPILED = True

_OVER_LIMIT = int(STATUS_OVER_LIMIT)


@njit(cache=True)
def _count_over_limit(node_out, nodes) -> int:
    """Multimaterial nodes flagged above the 000 Eq 26 force bound this step."""
    c = 0
    for k in range(nodes.shape[0]):
        if int(node_out[nodes[k], OUT_STATUS]) & _OVER_LIMIT:
            c += 1
    return c


@njit(cache=True)
def run_chunk_multimaterial_2d(
        nsteps, t0, dt, ramp_time, ramp_code, alpha, kinetic_damping, pic, mode, linear_u,
        with_interface, check_limit,
        x, v, pmass, pvol, pvol0, stress, strain, field, x0, fext, foff, C,
        origin, cell, nn, lp, kind,
        mass, mom, force, volume, volgrad, disp, pos, nvel, nacc,
        bc_node, bc_field, bc_comp, bc_vel, bc_tend, bc_ramp, bc_tramp,
        thick, law_kind, law_params, settings, rigid, node_zone, zone_pairs, zone_kind,
        zone_params, node_out, over_limit,
        hist, ke_prev,
        bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos):
    """``nsteps`` complete multimaterial time steps (see the module docstring).

    Arguments as :func:`mpm.chunk.run_chunk_2d` plus: ``linear_u`` (nodal displacements
    extrapolated to the node), ``with_interface`` (some pair is an imperfect interface),
    ``check_limit`` (force limiting off: count nodes above the bound), the pair tables
    (:class:`mpm.multimaterial.MultimaterialTables` arrays), ``thick`` (1 value or one
    per node), ``node_out`` (N x NODE_OUT_COLUMNS or 0 rows) and ``over_limit`` (float
    [steps with a node above the bound, most such nodes in one step, first time or
    -1], updated in place). ``hist[s, 6]`` is the interfacial energy. Returns (steps
    done, lost particle or -1).
    """
    vel = np.empty_like(bc_vel)
    nb = bmass.shape[0]
    M = mass.shape[1]
    lr_normal = np.zeros((0, M, 2))
    lr_sep = np.zeros((0, M))
    t = t0
    for s in range(nsteps):
        scale = ramp(t, ramp_time, ramp_code)
        lost = p2g_blocks_2d(x, v, pmass, pvol, stress, field, x0, fext, foff, scale,
                             origin, cell, nn, lp, kind, True, mode != USF,
                             mass, mom, force, volume, volgrad, disp, pos,
                             bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos)
        if lost >= 0:
            return s, lost
        nodes = multimaterial_nodes(mass)
        multi = nodes.size > 0
        if multi and linear_u:
            displacement_to_nodes(mass, disp, pos, nodes, origin, cell, nn, law_kind, law_params,
                                  node_zone, zone_pairs, zone_kind, zone_params,
                                  np.empty((nodes.size, M, 2)))
        if multi:
            correct_momentum_kernel(0, mass, mom, force, volume, volgrad, disp, pos, cell, thick,
                                    law_kind, law_params, settings, rigid, node_zone, zone_pairs,
                                    zone_kind, zone_params, lr_normal, lr_sep, dt, nodes)
        if mode == USF:
            stress_from_grid_2d(x, pvol, pvol0, stress, strain, field, C, origin, cell, nn, lp,
                                kind, dt, mass, mom)
            p2g_internal_force_2d(x, pvol, stress, field, origin, cell, nn, lp, kind, force)
        u_int = 0.0
        if multi and with_interface:
            u_int = interface_forces_kernel(mass, mom, volume, volgrad, disp, pos, cell, thick,
                                            law_kind, law_params, settings, rigid, node_zone,
                                            zone_pairs, zone_kind, zone_params, lr_normal,
                                            lr_sep, dt, force, node_out, nodes)
            if check_limit:
                over = _count_over_limit(node_out, nodes)
                if over:
                    over_limit[0] += 1.0
                    over_limit[1] = max(over_limit[1], float(over))
                    if over_limit[2] < 0.0:
                        over_limit[2] = t
        step_velocities(t, dt, bc_vel, bc_tend, bc_ramp, bc_tramp, vel)
        diss, wbc = grid_update(mass, mom, force, dt, alpha, bc_node, bc_field, bc_comp, vel)
        if multi:
            correct_momentum_kernel(1, mass, mom, force, volume, volgrad, disp, pos, cell, thick,
                                    law_kind, law_params, settings, rigid, node_zone, zone_pairs,
                                    zone_kind, zone_params, lr_normal, lr_sep, dt, nodes)
            if bc_vel.size:
                # a bonded node must keep its condition after the phase-1 correction
                wbc += bonded_velocity_bc_kernel(mass, mom, force, bc_node, bc_field, bc_comp,
                                                 vel, law_kind, law_params, settings, node_zone,
                                                 zone_pairs, zone_kind, zone_params, dt, True)
        nodal_kinematics(mass, mom, force, nvel, nacc)
        ke, U, work, lost, ke_grid = g2p_blocks_2d(
            nb, x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff, scale, C, origin,
            cell, nn, lp, kind, dt, pic, mode == USL, nvel, nacc)
        if lost >= 0:
            return s, lost
        if mode == MUSL:
            p2g_momentum_2d(x, v, pmass, field, origin, cell, nn, lp, kind, mass, mom)
            set_velocity_bc(mass, mom, bc_node, bc_field, bc_comp, vel)
            if multi:
                # re-extrapolated masses may cover other nodes
                nodes = multimaterial_nodes(mass)
                correct_momentum_kernel(0, mass, mom, force, volume, volgrad, disp, pos, cell,
                                        thick, law_kind, law_params, settings, rigid, node_zone,
                                        zone_pairs, zone_kind, zone_params, lr_normal, lr_sep,
                                        dt, nodes)
                if bc_vel.size:
                    bonded_velocity_bc_kernel(mass, mom, force, bc_node, bc_field, bc_comp, vel,
                                              law_kind, law_params, settings, node_zone,
                                              zone_pairs, zone_kind, zone_params, dt, False)
            U = stress_from_grid_2d(x, pvol, pvol0, stress, strain, field, C, origin, cell, nn,
                                    lp, kind, dt, mass, mom)
        t += dt
        ke, dk = kinetic_damping_step(kinetic_damping, ke, ke_prev, v)
        diss += dk
        record_step(hist, s, t, ke, U, work, diss, wbc, u_int, ke_grid)
        if not np.isfinite(ke):
            return s + 1, -1
    return nsteps, -1
