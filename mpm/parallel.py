"""Parallel P2G and G2P over contiguous particle blocks (numba ``prange``).

numba has no CPU atomics, so P2G cannot scatter into shared nodal arrays from several
threads. The particles are cut into ``B`` contiguous blocks (``B`` = the first
dimension of the :class:`BlockBuffers`); each block scatters into its own copy of the
nodal arrays (:func:`mpm.kernels.p2g_range_2d`) and the copies are then summed node by
node, in block order. G2P (:func:`mpm.kernels.g2p_range_2d`) only writes particle data;
its energy sums are formed per block and added in block order.

The result therefore depends on ``B`` only through the order of the floating-point
sums (round-off, ~1e-16 relative) and never on the number of threads executing the
blocks: a run gives bit-identical results with 1 or 2 threads for the same ``B``.
"""
from __future__ import annotations

import numpy as np
from numba import njit, prange

from .kernels import (g2p_range_2d, normalise_fields, p2g_range_2d, p2g_tractions_2d,
                      zero_nodal)

#: below this many particles the blocks run serially (the parallel-region overhead,
#: tens of microseconds per launch, would exceed the gain)
MIN_PARTICLES_PARALLEL = 20_000


class BlockBuffers:
    """Per-block copies of the nodal arrays P2G scatters into (allocated once per run).

    ``blocks`` < 2 gives zero-size buffers: the kernels then run serially, straight
    into the nodal arrays."""

    def __init__(self, blocks: int, N: int, M: int, multi: bool):
        nb = int(blocks) if blocks >= 2 else 0
        nm = nb if multi else 0
        self.blocks = max(nb, 1)
        self.mass = np.zeros((nb, N, M))
        self.mom = np.zeros((nb, N, M, 2))
        self.force = np.zeros((nb, N, M, 2))
        self.volume = np.zeros((nm, N, M))
        self.volgrad = np.zeros((nm, N, M, 2))
        self.disp = np.zeros((nm, N, M, 2))
        self.pos = np.zeros((nm, N, M, 2))

    def arrays(self) -> tuple:
        """(mass, mom, force, volume, volgrad, disp, pos) buffers, kernel argument order."""
        return (self.mass, self.mom, self.force, self.volume, self.volgrad, self.disp,
                self.pos)


def default_blocks(n_particles: int) -> int:
    """Blocks for a run: numba's thread count, 1 for small runs."""
    import numba
    threads = numba.get_num_threads()
    return threads if threads > 1 and n_particles >= MIN_PARTICLES_PARALLEL else 1


@njit(cache=True, parallel=True)
def _scatter_blocks(x, v, pmass, pvol, stress, field, x0, origin, cell, nn, lp, kind, multi,
                    internal, bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos, lost):
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
            lost[ib] = p2g_range_2d(lo, hi, x, v, pmass, pvol, stress, field, x0, origin, cell,
                                    nn, lp, kind, True, internal, bmass[ib], bmom[ib],
                                    bforce[ib], bvolume[ib], bvolgrad[ib], bdisp[ib], bpos[ib])
        else:
            lost[ib] = p2g_range_2d(lo, hi, x, v, pmass, pvol, stress, field, x0, origin, cell,
                                    nn, lp, kind, False, internal, bmass[ib], bmom[ib],
                                    bforce[ib], bmass[ib], bmom[ib], bmom[ib], bmom[ib])  # unused


@njit(cache=True, parallel=True)
def _reduce_blocks(multi, mass, mom, force, volume, volgrad, disp, pos,
                   bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos):
    nb = bmass.shape[0]
    N, M = mass.shape
    for n in prange(N):
        for f in range(M):
            sm = bmass[0, n, f]
            m0 = bmom[0, n, f, 0]
            m1 = bmom[0, n, f, 1]
            f0 = bforce[0, n, f, 0]
            f1 = bforce[0, n, f, 1]
            for ib in range(1, nb):
                sm += bmass[ib, n, f]
                m0 += bmom[ib, n, f, 0]
                m1 += bmom[ib, n, f, 1]
                f0 += bforce[ib, n, f, 0]
                f1 += bforce[ib, n, f, 1]
            mass[n, f] = sm
            mom[n, f, 0] = m0
            mom[n, f, 1] = m1
            force[n, f, 0] = f0
            force[n, f, 1] = f1
            if multi:
                vv = bvolume[0, n, f]
                g0 = bvolgrad[0, n, f, 0]
                g1 = bvolgrad[0, n, f, 1]
                d0 = bdisp[0, n, f, 0]
                d1 = bdisp[0, n, f, 1]
                q0 = bpos[0, n, f, 0]
                q1 = bpos[0, n, f, 1]
                for ib in range(1, nb):
                    vv += bvolume[ib, n, f]
                    g0 += bvolgrad[ib, n, f, 0]
                    g1 += bvolgrad[ib, n, f, 1]
                    d0 += bdisp[ib, n, f, 0]
                    d1 += bdisp[ib, n, f, 1]
                    q0 += bpos[ib, n, f, 0]
                    q1 += bpos[ib, n, f, 1]
                volume[n, f] = vv
                volgrad[n, f, 0] = g0
                volgrad[n, f, 1] = g1
                disp[n, f, 0] = d0
                disp[n, f, 1] = d1
                pos[n, f, 0] = q0
                pos[n, f, 1] = q1


@njit(cache=True)
def p2g_blocks_2d(x, v, pmass, pvol, stress, field, x0, fext, foff, load_scale,
                  origin, cell, nn, lp, kind, multi, internal,
                  mass, mom, force, volume, volgrad, disp, pos,
                  bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos):
    """:func:`mpm.kernels.p2g_2d` (same arguments and return value) with the particle
    scatter run over the blocks of the buffers ``b*`` in parallel; serial
    :func:`mpm.kernels.p2g_2d` when there are fewer than 2 blocks."""
    nb = bmass.shape[0]
    if nb < 2:
        zero_nodal(multi, mass, mom, force, volume, volgrad, disp, pos)
        lost = p2g_range_2d(0, x.shape[0], x, v, pmass, pvol, stress, field, x0, origin, cell,
                            nn, lp, kind, multi, internal, mass, mom, force, volume, volgrad,
                            disp, pos)
        if lost >= 0:
            return lost
    else:
        lostb = np.empty(nb, np.int64)
        _scatter_blocks(x, v, pmass, pvol, stress, field, x0, origin, cell, nn, lp, kind,
                        multi, internal, bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos,
                        lostb)
        for ib in range(nb):
            if lostb[ib] >= 0:
                return lostb[ib]
        _reduce_blocks(multi, mass, mom, force, volume, volgrad, disp, pos,
                       bmass, bmom, bforce, bvolume, bvolgrad, bdisp, bpos)
    p2g_tractions_2d(x, field, fext, foff, load_scale, origin, cell, nn, lp, kind, force)
    if multi:
        normalise_fields(mass, disp, pos)
    return -1


@njit(cache=True, parallel=True)
def _g2p_blocks(nb, x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff, load_scale, C,
                origin, cell, nn, lp, kind, dt, pic, update_stress, nvel, nacc, out):
    P = x.shape[0]
    for ib in prange(nb):
        lo = ib * P // nb
        hi = (ib + 1) * P // nb
        ke, U, work, lost, keg = g2p_range_2d(lo, hi, x, v, pmass, pvol, pvol0, stress, strain,
                                         field, fext, foff, load_scale, C, origin, cell, nn,
                                         lp, kind, dt, pic, update_stress, nvel, nacc)
        out[ib, 0] = ke
        out[ib, 1] = U
        out[ib, 2] = work
        out[ib, 3] = lost
        out[ib, 4] = keg


@njit(cache=True)
def g2p_blocks_2d(nb, x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff, load_scale,
                  C, origin, cell, nn, lp, kind, dt, pic, update_stress, nvel, nacc):
    """:func:`mpm.kernels.g2p_2d` (same return value) over ``nb`` particle blocks in
    parallel, the energy sums added in block order; serial when ``nb`` < 2."""
    if nb < 2:
        return g2p_range_2d(0, x.shape[0], x, v, pmass, pvol, pvol0, stress, strain, field,
                            fext, foff, load_scale, C, origin, cell, nn, lp, kind, dt, pic,
                            update_stress, nvel, nacc)
    out = np.empty((nb, 5))
    _g2p_blocks(nb, x, v, pmass, pvol, pvol0, stress, strain, field, fext, foff, load_scale, C,
                origin, cell, nn, lp, kind, dt, pic, update_stress, nvel, nacc, out)
    ke = 0.0
    U = 0.0
    work = 0.0
    ke_grid = 0.0
    lost = -1
    for ib in range(nb):
        ke += out[ib, 0]
        U += out[ib, 1]
        work += out[ib, 2]
        ke_grid += out[ib, 4]
        if out[ib, 3] >= 0.0:
            lost = int(out[ib, 3])
    return ke, U, work, lost, ke_grid
