"""Axisymmetric MPM (000 Sec 2.3, 2.5; Nairn and Guilkey 2013): x = r, y = z, per radian.

The planar kernels do the in-plane part of every step unchanged: a particle's volume
and mass are per radian (area x r_p), so the nodal sums of mpm/LAYOUT.md are per
radian too. What axisymmetry adds is done here:

* the hoop term of the internal force, f_i,r -= V_p sigma_tt S_ip / r_p
  (:func:`hoop_force`);
* the hoop strain increment d eps_tt = dt v_r / r_p, with v_r = sum S_ip v_i,r the
  particle's grid velocity, and its coupling to the in-plane stresses through the
  4 x 4 stiffness (:func:`hoop_stress_update`). The stress and strain of a particle
  are ordered [rr, zz, rz, tt] (the planar kernels see the first three);
* the nodal volumes of the contact area (000 Eq 20, t -> r_i) from the particles'
  planar areas (:func:`interface_volumes`);
* the nodes on the axis r = 0: their radial velocity is held at zero (symmetry), the
  radial component of their volume gradients is zeroed (000 Sec 2.5: such nodes are
  at the core of the body, not on an edge) and their cell volume per radian is that
  of the half cell next to the axis, (integral of the hat function times r) = dx dy dx / 6
  (:func:`node_radii`), in place of r_i in the interface area of 000 Eq 20, where
  "t is replaced by r_i".
"""
from __future__ import annotations

import numpy as np

from interfaces.jit import FMA, njit

from .shape import shape_2d_work, stencil_work

#: Voigt order of an axisymmetric particle: in-plane first, as the planar kernels expect
AXISYMMETRIC_ORDER = ("rr", "zz", "rz", "tt")


def stiffness_rzt(C_fem: np.ndarray) -> np.ndarray:
    """The 4 x 4 stiffness in the particle order [rr, zz, rz, tt] from the
    ``Material.stiffness('axisymmetric')`` order [rr, zz, tt, rz]."""
    order = [0, 1, 3, 2]
    return np.ascontiguousarray(np.asarray(C_fem, float)[np.ix_(order, order)])


def node_radii(node_positions: np.ndarray, cell: np.ndarray) -> np.ndarray:
    """Per-node 'thickness' of the axisymmetric interface area (000 Eq 20 with t -> r_i):
    r_i, and dx / 6 on the axis (the hat function's first moment over the half cell,
    int_0^dx (1 - r/dx) r dr = dx^2 / 6, so Omega_i / (cell volume) stays the volume
    fraction there)."""
    r = np.asarray(node_positions, float)[:, 0].copy()
    on_axis = np.abs(r) <= 1e-9 * float(cell[0])
    r[on_axis] = float(cell[0]) / 6.0
    return np.ascontiguousarray(r)


def axis_nodes(node_positions: np.ndarray, cell: np.ndarray) -> np.ndarray:
    """Indices of the nodes on the axis r = 0."""
    r = np.asarray(node_positions, float)[:, 0]
    return np.flatnonzero(np.abs(r) <= 1e-9 * float(cell[0])).astype(np.int64)


@njit(cache=True, fastmath=FMA, error_model="numpy")
def hoop_force(x, pvol, stress, field, origin, cell, nn, lp, kind, force):
    """Add the hoop term -V_p sigma_tt S_ip / r_p to the radial nodal force."""
    idx, S, G, wx, dwx, wy, dwy = stencil_work()
    for p in range(x.shape[0]):
        c = shape_2d_work(x[p, 0], x[p, 1], origin, cell, nn, lp, kind, idx, S, G,
                          wx, dwx, wy, dwy)
        f = field[p]
        q = pvol[p] * stress[p, 3] / x[p, 0]
        for k in range(c):
            force[idx[k], f, 0] -= q * S[k]


@njit(cache=True, fastmath=FMA, error_model="numpy")
def interface_volumes(x, pvol, field, origin, cell, nn, lp, kind, node_t, volume, volgrad):
    """Nodal volumes and volume gradients of each field for the contact area and the
    normals: sum_p S_ip A_p t_i and sum_p grad S_ip A_p t_i, with A_p = V_p / r_p the
    particle's area in the r-z plane and t_i the node's radius (:func:`node_radii`).

    000 Eq 20 in axisymmetric MPM replaces t by r_i: A_i = r_i sqrt(2 w_i min(w_a, w_b))
    / dx with the planar areas w. The per-radian particle volumes V_p = A_p r_p would
    weight the field outside the interface by its larger radius: for an interface at
    r = a on a grid line the area comes out a (1 - dx / 6a) instead of a (4 % soft at
    a = 4 dx). With t_i inside the sums the kernels' sqrt(2 Omega_i min) / dx is the
    exact r_i form, and the cell volume per radian (cell area x t_i) stays consistent."""
    volume[:] = 0.0
    volgrad[:] = 0.0
    idx, S, G, wx, dwx, wy, dwy = stencil_work()
    for p in range(x.shape[0]):
        c = shape_2d_work(x[p, 0], x[p, 1], origin, cell, nn, lp, kind, idx, S, G,
                          wx, dwx, wy, dwy)
        f = field[p]
        area = pvol[p] / x[p, 0]
        for k in range(c):
            n = idx[k]
            w = area * node_t[n]
            volume[n, f] += S[k] * w
            volgrad[n, f, 0] += G[k, 0] * w
            volgrad[n, f, 1] += G[k, 1] * w


@njit(cache=True, fastmath=FMA, error_model="numpy")
def radial_velocity(x, field, origin, cell, nn, lp, kind, mass, mom, out):
    """out[p] = sum_i S_ip p_i,r / m_i over the particle's own field (MUSL: from the
    re-extrapolated momenta)."""
    idx, S, G, wx, dwx, wy, dwy = stencil_work()
    for p in range(x.shape[0]):
        c = shape_2d_work(x[p, 0], x[p, 1], origin, cell, nn, lp, kind, idx, S, G,
                          wx, dwx, wy, dwy)
        f = field[p]
        vr = 0.0
        for k in range(c):
            m = mass[idx[k], f]
            if m > 0.0:
                vr += S[k] * mom[idx[k], f, 0] / m
        out[p] = vr


@njit(cache=True, fastmath=FMA, error_model="numpy")
def hoop_stress_update(d_hoop, strain_before, stress, strain, pvol, pvol0, field, C,
                       mkind) -> float:
    """Complete a step's stress update with the hoop strain increment ``d_hoop``
    (d eps_tt per particle): the planar kernels have added C[:3, :3] d eps_in, where
    d eps_in = strain[:, :3] - strain_before[:, :3]; this adds C[:3, 3] d eps_tt to the
    in-plane stresses and C[3, :3] d eps_in + C[3, 3] d eps_tt to sigma_tt, scales the
    volume by 1 + d eps_tt and returns the strain energy sum 1/2 V0 sigma . eps (per
    radian, four components). The particles of finite-strain fields (``mkind[f]``
    nonzero) are left to :mod:`mpm.finite_strain` (hoop stretch r / r_0 in F)."""
    U = 0.0
    for p in range(stress.shape[0]):
        f = field[p]
        if mkind[f] != 0:
            continue
        dt_ = d_hoop[p]
        s3 = C[f, 3, 3] * dt_
        for a in range(3):
            de = strain[p, a] - strain_before[p, a]
            stress[p, a] += C[f, a, 3] * dt_
            s3 += C[f, 3, a] * de
        stress[p, 3] += s3
        strain[p, 3] += dt_
        pvol[p] *= 1.0 + dt_
        e = 0.0
        for a in range(4):
            e += stress[p, a] * strain[p, a]
        U += 0.5 * pvol0[p] * e
    return U


@njit(cache=True)
def hoop_from_motion(x, r_before, out) -> None:
    """USL: d eps_tt = dt v_r / r_p = (r_p+ - r_p) / r_p, since G2P moved the particle
    by dt sum S_ip v_i+ from ``r_before``."""
    for p in range(x.shape[0]):
        out[p] = (x[p, 0] - r_before[p]) / r_before[p]


@njit(cache=True)
def zero_axis_gradients(volume_gradient, nodes) -> None:
    """000 Sec 2.5: no radial volume gradient (hence normal) on the axis."""
    if volume_gradient.shape[0] == 0:
        return
    for k in range(nodes.shape[0]):
        for f in range(volume_gradient.shape[1]):
            volume_gradient[nodes[k], f, 0] = 0.0
