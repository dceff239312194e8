"""Two contact laws solved simultaneously at a node seen by three materials (004 Sec 3.4,
Eq 49).

At a node where material gamma touches both alpha and beta (alpha and beta not in
contact: 004 Fig 4C, a thin gamma between them, or the meeting point of Fig 4A), the
momentum changes of the two contacting pairs interact: correcting alpha against gamma
moves gamma, which changes its contact with beta. 004 Eq 49 keeps the node's momentum
by giving gamma the negative of both changes,

    p'_alpha = p_alpha + J_1,   p'_beta = p_beta + J_2,   p'_gamma = p_gamma - J_1 - J_2,

and asks for J_1, J_2 that satisfy both pairs' contact laws at once (004 gives no
equations; they are derived here). With v'_k = v_k + J_k / m_k (k = alpha, beta) and
v'_gamma = v_gamma - (J_1 + J_2) / m_gamma, a pair in

* stick (a perfect bond, stick contact, or Coulomb friction inside its cone) has no
  relative velocity afterwards: J_k / m_k + (J_1 + J_2) / m_gamma = v_gamma - v_k
  (D equations);
* sliding (Coulomb friction at its cone, or frictionless) has no normal relative
  velocity afterwards, n_k . (J_k / m_k + (J_1 + J_2) / m_gamma) = n_k . (v_gamma - v_k),
  and a tangential impulse mu |J_k . n_k| along the direction t_k of its stick impulse
  (the rule of 004 Eq 8-10 for one pair): e . J_k + mu (n_k . J_k)(t_k . e) = 0 for the
  D - 1 tangents e (t_k and, in 3D, n_k x t_k; mu = 0: any two tangents).

n_k is the unit normal from material k to gamma, so a contact (compressive) impulse has
J_k . n_k <= 0. Starting with every frictional pair in stick, a pair whose stick impulse
leaves its friction cone slides, and a contact pair whose impulse would pull (J_k . n_k
> 0) is not in contact: it is dropped and the other pair solved alone. Each pair changes
state at most twice, so the loop ends after a few linear solves of size 2 D.
"""
from __future__ import annotations

import math

import numpy as np

from interfaces.jit import njit

from .multimaterial_constants import LAW_FRICTION, LAW_PERFECT
from .multimaterial_lr import _solve_small
from .multimaterial_normals import any_tangent

_STICK = 0
_SLIDE = 1


@njit(cache=True, inline="always")
def _dot(u, v) -> float:
    s = 0.0
    for k in range(u.shape[0]):
        s += u[k] * v[k]
    return s


@njit(cache=True)
def _tangents(n, t, mode, e) -> int:
    """The D - 1 tangent rows of a sliding pair into ``e``: its slide direction ``t`` (and
    n x t in 3D) with friction, any orthonormal tangents without; returns their count."""
    d = n.shape[0]
    if mode == _SLIDE and _dot(t, t) > 0.0:
        for k in range(d):
            e[0, k] = t[k]
    else:
        any_tangent(n, e[0])
    if d == 3:
        e[1, 0] = n[1] * e[0, 2] - n[2] * e[0, 1]
        e[1, 1] = n[2] * e[0, 0] - n[0] * e[0, 2]
        e[1, 2] = n[0] * e[0, 1] - n[1] * e[0, 0]
    return d - 1


@njit(cache=True)
def _assemble(masses, vel, normals, mu, active, mode, slide_dir, A, rhs, e) -> None:
    """The 2 D x 2 D system of the module docstring for the unknowns (J_1, J_2)."""
    d = normals.shape[1]
    m_c = masses[2]
    A[:, :] = 0.0
    rhs[:] = 0.0
    for k in range(2):
        r0 = k * d
        if not active[k]:
            for j in range(d):
                A[r0 + j, r0 + j] = 1.0             # J_k = 0
            continue
        n = normals[k]
        if mode[k] == _STICK:
            for j in range(d):
                A[r0 + j, r0 + j] += 1.0 / masses[k]
                for q in range(2):
                    A[r0 + j, q * d + j] += 1.0 / m_c
                rhs[r0 + j] = vel[2, j] - vel[k, j]
            continue
        for j in range(d):                          # normal row
            A[r0, r0 + j] += n[j] / masses[k]
            for q in range(2):
                A[r0, q * d + j] += n[j] / m_c
            rhs[r0] += n[j] * (vel[2, j] - vel[k, j])
        friction = mu[k] if mode[k] == _SLIDE and _dot(slide_dir[k], slide_dir[k]) > 0.0 else 0.0
        nt = _tangents(n, slide_dir[k], mode[k], e)
        for r in range(nt):
            te = _dot(slide_dir[k], e[r]) if friction > 0.0 else 0.0
            for j in range(d):
                A[r0 + 1 + r, r0 + j] = e[r, j] + friction * te * n[j]


@njit(cache=True)
def two_pair_impulses(masses, vel, normals, codes, mu, J) -> int:
    """Momentum changes J[0] of alpha and J[1] of beta (gamma takes -J[0] - J[1]) that
    satisfy the contact laws of the pairs (alpha, gamma) and (beta, gamma) together.

    ``masses`` (m_alpha, m_beta, m_gamma), ``vel[3, D]`` their nodal velocities,
    ``normals[2, D]`` the unit normals from alpha and from beta to gamma, ``codes[2]``
    the pairs' LAW_* codes (perfect, stick or friction), ``mu[2]`` their friction
    coefficients. Returns a bit mask of the pairs left in contact (1: alpha-gamma,
    2: beta-gamma; 0: neither, J = 0)."""
    d = normals.shape[1]
    active = np.ones(2, np.bool_)
    mode = np.empty(2, np.int64)
    slide_dir = np.zeros((2, d))
    for k in range(2):
        frictionless = codes[k] == LAW_FRICTION and mu[k] == 0.0
        mode[k] = _SLIDE if frictionless else _STICK
    A = np.empty((2 * d, 2 * d))
    rhs = np.empty(2 * d)
    x = np.zeros(2 * d)
    e = np.zeros((2, d))
    jt = np.empty(d)
    for _ in range(8):
        _assemble(masses, vel, normals, mu, active, mode, slide_dir, A, rhs, e)
        if not _solve_small(A, rhs, x):
            x[:] = 0.0
            return 0
        changed = False
        for k in range(2):
            if not active[k]:
                continue
            jn = 0.0
            for j in range(d):
                jn += x[k * d + j] * normals[k, j]
            if codes[k] != LAW_PERFECT and jn > 0.0:
                active[k] = False                   # would pull: not in contact
                changed = True
                break
            if codes[k] == LAW_FRICTION and mode[k] == _STICK:
                s = 0.0
                for j in range(d):
                    jt[j] = x[k * d + j] - jn * normals[k, j]
                    s += jt[j] * jt[j]
                s = math.sqrt(s)
                if s > -mu[k] * jn:                 # outside the friction cone: slides
                    mode[k] = _SLIDE
                    for j in range(d):
                        slide_dir[k, j] = jt[j] / s
                    changed = True
        if not changed:
            break
    for k in range(2):
        for j in range(d):
            J[k, j] = x[k * d + j] if active[k] else 0.0
    return (1 if active[0] else 0) + (2 if active[1] else 0)
