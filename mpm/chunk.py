"""Compiled chunks of explicit MPM time steps (2D): Python runs only between output
intervals.

Step order (004 Sec 3.2, Eq 26-34; mpm/LAYOUT.md): P2G -> grid update with damping and
nodal velocity conditions -> nodal kinematics -> G2P + stress update (USL default,
USF, MUSL). P2G and G2P run over the particle blocks of the given
:class:`mpm.parallel.BlockBuffers` (race-free parallel scatter; serial with one block).

``hist[s] = (t, kinetic, strain, work_ext, dissipated, work_bc, interface, grid
kinetic)`` after step s (work and dissipation columns are that step's increments),
the columns of ``mpm.solver.HIST_COLUMNS``.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from .kernels import (MUSL, USF, USL, grid_update, nodal_kinematics, p2g_internal_force_2d,
                      p2g_momentum_2d, ramp, set_velocity_bc, step_velocities,
                      stress_from_grid_2d)
from .parallel import g2p_blocks_2d, p2g_blocks_2d


@njit(cache=True)
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
def record_step(hist, s, t, ke, U, work, diss, wbc, u_int, ke_grid):
    """Row s of the history (columns of ``mpm.solver.HIST_COLUMNS``)."""
    hist[s, 0] = t
    hist[s, 1] = ke
    hist[s, 2] = U
    hist[s, 3] = work
    hist[s, 4] = diss
    hist[s, 5] = wbc
    hist[s, 6] = u_int
    hist[s, 7] = ke_grid


@njit(cache=True)
def run_chunk_2d(nsteps, t0, dt, ramp_time, ramp_code, alpha, kinetic_damping, pic, mode,
                 x, v, pmass, pvol, pvol0, stress, strain, field, x0, fext, foff, C,
                 origin, cell, nn, lp, kind,
                 mass, mom, force, volume, volgrad, disp, pos, nvel, nacc,
                 bc_node, bc_field, bc_comp, bc_vel, bc_tend, bc_ramp, bc_tramp,
                 hist, ke_prev,
                 bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos):
    """``nsteps`` complete time steps of a run without multimaterial nodes.

    Nodal conditions follow their histories (``bc_vel``, ``bc_tend``, ``bc_ramp``,
    ``bc_tramp``: :func:`mpm.kernels.step_velocities`); tractions the load ramp
    (``ramp_time``, ``ramp_code``: :func:`mpm.kernels.ramp`).
    Kinetic damping zeroes the particle velocities whenever the kinetic energy has just
    peaked. P2G/G2P over the blocks of the buffers ``b*``
    (:class:`mpm.parallel.BlockBuffers`). Returns (number of steps done, index of a
    lost particle or -1); ``ke_prev`` (last two kinetic energies) is updated in place.
    """
    vel = np.empty_like(bc_vel)
    nb = bmass.shape[0]
    t = t0
    for s in range(nsteps):
        scale = ramp(t, ramp_time, ramp_code)
        lost = p2g_blocks_2d(x, v, pmass, pvol, stress, field, x0, fext, foff, scale,
                             origin, cell, nn, lp, kind, False, mode != USF,
                             mass, mom, force, volume, volgrad, disp, pos,
                             bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos)
        if lost >= 0:
            return s, lost
        if mode == USF:
            stress_from_grid_2d(x, pvol, pvol0, stress, strain, field, C, origin, cell, nn, lp,
                                kind, dt, mass, mom)
            p2g_internal_force_2d(x, pvol, stress, field, origin, cell, nn, lp, kind, force)
        step_velocities(t, dt, bc_vel, bc_tend, bc_ramp, bc_tramp, vel)
        diss, wbc = grid_update(mass, mom, force, dt, alpha, bc_node, bc_field, bc_comp, vel)
        nodal_kinematics(mass, mom, force, nvel, nacc)
        ke, U, work, lost, ke_grid = g2p_blocks_2d(
            nb, x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff, scale, C, origin,
            cell, nn, lp, kind, dt, pic, mode == USL, nvel, nacc)
        if lost >= 0:
            return s, lost
        if mode == MUSL:
            p2g_momentum_2d(x, v, pmass, field, origin, cell, nn, lp, kind, mass, mom)
            set_velocity_bc(mass, mom, bc_node, bc_field, bc_comp, vel)
            U = stress_from_grid_2d(x, pvol, pvol0, stress, strain, field, C, origin, cell, nn,
                                    lp, kind, dt, mass, mom)
        t += dt
        ke, dk = kinetic_damping_step(kinetic_damping, ke, ke_prev, v)
        diss += dk
        record_step(hist, s, t, ke, U, work, diss, wbc, 0.0, ke_grid)
        if not np.isfinite(ke):
            return s + 1, -1
    return nsteps, -1
