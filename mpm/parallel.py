"""Parallel P2G and G2P over contiguous particle blocks (numba ``prange``).

numba has no CPU atomics, so P2G cannot scatter into shared nodal arrays from several
threads. The particles are cut into ``B`` contiguous blocks (``B`` = the first
dimension of the :class:`BlockBuffers`); each block scatters into its own copy of the
nodal arrays (:func:`p2g_range`: the 2D or 3D kernel) and the copies are then summed
node by node, in block order. G2P (:func:`g2p_range`) only writes particle data;
its energy sums are formed per block and added in block order.

The result therefore depends on ``B`` only through the order of the floating-point
sums (round-off, ~1e-16 relative) and never on the number of threads executing the
blocks: a run gives bit-identical results with 1 or 2 threads for the same ``B``.
"""
from __future__ import annotations

import numpy as np
from numba import prange

from interfaces.jit import njit

from .kernels import (g2p_range_2d, normalise_fields, p2g_range_2d, p2g_tractions_2d,
                      zero_nodal)
from .kernels3d import g2p_range_3d, p2g_range_3d, p2g_tractions_3d

#: below this many particles the blocks run serially (the parallel-region overhead,
#: tens of microseconds per launch, would exceed the gain)
MIN_PARTICLES_PARALLEL = 20_000


class BlockBuffers:
    """Per-block copies of the nodal arrays P2G scatters into (allocated once per run).

    ``blocks`` < 2 gives zero-size buffers: the kernels then run serially, straight
    into the nodal arrays."""

    def __init__(self, blocks: int, N: int, M: int, multi: bool, D: int = 2):
        nb = int(blocks) if blocks >= 2 else 0
        nm = nb if multi else 0
        self.blocks = max(nb, 1)
        self.mass = np.zeros((nb, N, M))
        self.mom = np.zeros((nb, N, M, D))
        self.force = np.zeros((nb, N, M, D))
        self.volume = np.zeros((nm, N, M))
        self.volgrad = np.zeros((nm, N, M, D))
        self.disp = np.zeros((nm, N, M, D))
        self.pos = np.zeros((nm, N, M, D))

    def arrays(self) -> tuple:
        """(mass, mom, force, volume, volgrad, disp, pos) buffers, kernel argument order."""
        return (self.mass, self.mom, self.force, self.volume, self.volgrad, self.disp,
                self.pos)


def default_blocks(n_particles: int) -> int:
    """Blocks for a run: numba's thread count, 1 for small runs."""
    import numba
    threads = numba.get_num_threads()
    return threads if threads > 1 and n_particles >= MIN_PARTICLES_PARALLEL else 1


@njit(cache=True, inline="always")
def p2g_range(lo, hi, x, v, pmass, pvol, stress, field, x0, origin, cell, nn, lp, kind, multi,
              internal, mass, mom, force, volume, volgrad, disp, pos, xnode=None, xweight=None):
    """:func:`mpm.kernels.p2g_range_2d` or :func:`mpm.kernels3d.p2g_range_3d` by the
    particles' dimension (``xnode``, ``xweight``: the 2D XPIC stencils, written by P2G)."""
    if x.shape[1] == 3:
        return p2g_range_3d(lo, hi, x, v, pmass, pvol, stress, field, x0, origin, cell, nn, lp,
                            kind, multi, internal, mass, mom, force, volume, volgrad, disp, pos)
    return p2g_range_2d(lo, hi, x, v, pmass, pvol, stress, field, x0, origin, cell, nn, lp, kind,
                        multi, internal, mass, mom, force, volume, volgrad, disp, pos, xnode,
                        xweight)


@njit(cache=True, inline="always")
def g2p_range(lo, hi, x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff, load_scale, C,
              origin, cell, nn, lp, kind, dt, pic, update_stress, nvel, nacc, velgrad, mkind,
              beta, vtil):
    """:func:`mpm.kernels.g2p_range_2d` (with the XPIC blend ``beta``, ``vtil``) or
    :func:`mpm.kernels3d.g2p_range_3d` (``vtil`` None: mpm/xpic.py blends 3D runs after
    G2P) by the particles' dimension; (ke, U, work, lost, ke_grid, ke before the
    blend)."""
    if x.shape[1] == 3:
        ke, U, work, lost, keg = g2p_range_3d(lo, hi, x, v, pmass, pvol, pvol0, stress, strain,
                                              field, fext, foff, load_scale, C, origin, cell,
                                              nn, lp, kind, dt, pic, update_stress, nvel, nacc,
                                              velgrad, mkind)
        return ke, U, work, lost, keg, ke
    return g2p_range_2d(lo, hi, x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff,
                        load_scale, C, origin, cell, nn, lp, kind, dt, pic, update_stress, nvel,
                        nacc, velgrad, mkind, beta, vtil)


@njit(cache=True, parallel=True)
def _scatter_blocks(x, v, pmass, pvol, stress, field, x0, origin, cell, nn, lp, kind, multi,
                    internal, bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos, lost, xnode,
                    xweight):
    nb = bmass.shape[0]
    P = x.shape[0]
    for ib in prange(nb):
        lo = ib * P // nb
        hi = (ib + 1) * P // nb
        bmass[ib] = 0.0
        bmom[ib] = 0.0
        bforce[ib] = 0.0
        if multi:
            bvolume[ib] = 0.0
            bvolgrad[ib] = 0.0
            bdisp[ib] = 0.0
            bpos[ib] = 0.0
            lost[ib] = p2g_range(lo, hi, x, v, pmass, pvol, stress, field, x0, origin, cell,
                                 nn, lp, kind, True, internal, bmass[ib], bmom[ib],
                                    bforce[ib], bvolume[ib], bvolgrad[ib], bdisp[ib], bpos[ib],
                                 xnode, xweight)
        else:
            lost[ib] = p2g_range(lo, hi, x, v, pmass, pvol, stress, field, x0, origin, cell,
                                 nn, lp, kind, False, internal, bmass[ib], bmom[ib],
                                    bforce[ib], bmass[ib], bmom[ib], bmom[ib], bmom[ib],  # unused
                                 xnode, xweight)


@njit(cache=True, parallel=True)
def _reduce_blocks(multi, mass, mom, force, volume, volgrad, disp, pos,
                   bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos):
    nb = bmass.shape[0]
    N, M = mass.shape
    D = mom.shape[2]
    for n in prange(N):
        for f in range(M):
            sm = bmass[0, n, f]
            for ib in range(1, nb):
                sm += bmass[ib, n, f]
            mass[n, f] = sm
            for d in range(D):
                m0 = bmom[0, n, f, d]
                f0 = bforce[0, n, f, d]
                for ib in range(1, nb):
                    m0 += bmom[ib, n, f, d]
                    f0 += bforce[ib, n, f, d]
                mom[n, f, d] = m0
                force[n, f, d] = f0
            if multi:
                vv = bvolume[0, n, f]
                for ib in range(1, nb):
                    vv += bvolume[ib, n, f]
                volume[n, f] = vv
                for d in range(D):
                    g0 = bvolgrad[0, n, f, d]
                    d0 = bdisp[0, n, f, d]
                    q0 = bpos[0, n, f, d]
                    for ib in range(1, nb):
                        g0 += bvolgrad[ib, n, f, d]
                        d0 += bdisp[ib, n, f, d]
                        q0 += bpos[ib, n, f, d]
                    volgrad[n, f, d] = g0
                    disp[n, f, d] = d0
                    pos[n, f, d] = q0


@njit(cache=True)
def p2g_blocks(x, v, pmass, pvol, stress, field, x0, fext, foff, load_scale,
                  origin, cell, nn, lp, kind, multi, internal,
                  mass, mom, force, volume, volgrad, disp, pos,
                  bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos, xnode, xweight):
    """:func:`mpm.kernels.p2g_2d` (same arguments and return value) with the particle
    scatter run over the blocks of the buffers ``b*`` in parallel; serial
    :func:`mpm.kernels.p2g_2d` when there are fewer than 2 blocks. ``xnode``,
    ``xweight``: the 2D XPIC stencils P2G writes (zero rows: none)."""
    nb = bmass.shape[0]
    if nb < 2:
        zero_nodal(multi, mass, mom, force, volume, volgrad, disp, pos)
        lost = p2g_range(0, x.shape[0], x, v, pmass, pvol, stress, field, x0, origin, cell,
                         nn, lp, kind, multi, internal, mass, mom, force, volume, volgrad,
                         disp, pos, xnode, xweight)
        if lost >= 0:
            return lost
    else:
        lostb = np.empty(nb, np.int64)
        _scatter_blocks(x, v, pmass, pvol, stress, field, x0, origin, cell, nn, lp, kind,
                        multi, internal, bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos,
                        lostb, xnode, xweight)
        for ib in range(nb):
            if lostb[ib] >= 0:
                return lostb[ib]
        _reduce_blocks(multi, mass, mom, force, volume, volgrad, disp, pos,
                       bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos)
    if x.shape[1] == 3:
        p2g_tractions_3d(x, field, fext, foff, load_scale, origin, cell, nn, lp, kind, force)
    else:
        p2g_tractions_2d(x, field, fext, foff, load_scale, origin, cell, nn, lp, kind, force)
    if multi:
        normalise_fields(mass, disp, pos)
    return -1


@njit(cache=True, parallel=True)
def _g2p_blocks(nb, x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff, load_scale, C,
                origin, cell, nn, lp, kind, dt, pic, update_stress, nvel, nacc, velgrad, mkind,
                beta, vtil, out):
    P = x.shape[0]
    for ib in prange(nb):
        lo = ib * P // nb
        hi = (ib + 1) * P // nb
        ke, U, work, lost, keg, kef = g2p_range(lo, hi, x, v, pmass, pvol, pvol0, stress,
                                                strain, field, fext, foff, load_scale, C,
                                                origin, cell, nn, lp, kind, dt, pic,
                                                update_stress, nvel, nacc, velgrad, mkind,
                                                beta, vtil)
        out[ib, 0] = ke
        out[ib, 1] = U
        out[ib, 2] = work
        out[ib, 3] = lost
        out[ib, 4] = keg
        out[ib, 5] = kef


@njit(cache=True)
def g2p_blocks(nb, x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff, load_scale,
                  C, origin, cell, nn, lp, kind, dt, pic, update_stress, nvel, nacc, velgrad,
                  mkind, beta, vtil):
    """:func:`mpm.kernels.g2p_2d` over ``nb`` particle blocks in parallel, the energy sums
    added in block order; serial when ``nb`` < 2. 2D: with the grid velocity ``vtil`` (None:
    none) the XPIC blend ``beta`` in the same loop (:func:`mpm.kernels.g2p_range_2d`).
    Returns :func:`mpm.kernels.g2p_2d`'s values and the kinetic energy before the blend."""
    if nb < 2:
        return g2p_range(0, x.shape[0], x, v, pmass, pvol, pvol0, stress, strain, field,
                         fext, foff, load_scale, C, origin, cell, nn, lp, kind, dt, pic,
                         update_stress, nvel, nacc, velgrad, mkind, beta, vtil)
    out = np.empty((nb, 6))
    _g2p_blocks(nb, x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff, load_scale, C,
                origin, cell, nn, lp, kind, dt, pic, update_stress, nvel, nacc, velgrad, mkind,
                beta, vtil, out)
    ke = 0.0
    U = 0.0
    work = 0.0
    ke_grid = 0.0
    ke_flip = 0.0
    lost = -1
    for ib in range(nb):
        ke += out[ib, 0]
        U += out[ib, 1]
        work += out[ib, 2]
        ke_grid += out[ib, 4]
        ke_flip += out[ib, 5]
        if out[ib, 3] >= 0.0:
            lost = int(out[ib, 3])
    return ke, U, work, lost, ke_grid, ke_flip
