"""Largest signal speed of the finite-strain particles in their current state, for the
explicit time step dt = cfl dx / speed (004 Sec 2: the neo-Hookean material of Eq 18
and the Mie-Grueneisen material of Sec 4.3 stiffen in compression, so the step is set
from the deformed state, not from the wave speed at rest).

Acoustic tensor. For the decoupled neo-Hookean energy W = G/2 (J^(-2/3) tr b - 3) + U(J)
(b = F F^T, Cauchy stress G J^(-5/3) dev b + U'(J) I), a plane wave travelling along
the current unit direction n has rho0 c^2 equal to an eigenvalue of

    Q(n) = (mu + n.s.n) I + (mu / 3 + B) n (x) n - 2/3 (s n (x) n + n (x) s n),

with s = G dev(b_bar) the deviatoric Kirchhoff stress, b_bar = J^(-2/3) b,
mu = G tr(b_bar) / 3 and B = J^2 U''(J) the current bulk stiffness times J (the
push-forward of A = dP/dF: Q_ik = A_iJkL N_J N_L, N = F^T n; at rest Q = G I + (K + G/3)
n (x) n, so rho0 c^2 = K + 4G/3 along n and G across). For the Mie-Grueneisen material
B = rho0 C^2, with C its isentropic bulk speed (:func:`mpm.mie_gruneisen.bulk_wave_speed`).

Its largest eigenvalue for a given n is mu + sigma + h / 2 + sqrt(h^2 / 4 + 4 tau^2 / 9),
with sigma = n.s.n, tau = |s n - sigma n| and h = beta - 4 sigma / 3, beta = B + mu / 3.
Over the directions a wave can take (the plane for plane strain and axisymmetric runs,
where s has no out-of-plane shear; space in 3D), tau^2 <= (s_max - sigma)(sigma - s_min),
s_min and s_max the extreme eigenvalues of s over those directions (Mohr's outer circle;
an equality in the plane). With it the square root's argument is linear in sigma,
a + b sigma (a = beta^2 / 4 - 4 s_min s_max / 9, b = 4 (s_min + s_max) / 9 - 2 beta / 3),
and the bound mu + beta / 2 + sigma / 3 + sqrt(a + b sigma) is concave in sigma: its
maximum over [s_min, s_max] is in closed form. The result is the exact largest
rho0 c^2 in the plane, and in 3D exact when the fastest direction lies in the plane of
the extreme principal axes of s, above the exact value otherwise, never below it.
"""
from __future__ import annotations

import math

import numpy as np

from interfaces.jit import FMA, njit

from .finite_strain import (LINEAR, MIE_GRUNEISEN, P_G, P_K, P_VOLUMETRIC,
                            volumetric_stiffness)
from . import mie_gruneisen as MG


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def _extreme_eigenvalues(s, D):
    """(smallest, largest) eigenvalue of the symmetric 3 x 3 ``s`` (D = 3) or of its
    upper-left 2 x 2 block (D = 2): closed form, the trigonometric one in 3D."""
    if D == 2:
        mean = 0.5 * (s[0, 0] + s[1, 1])
        r = math.sqrt(0.25 * (s[0, 0] - s[1, 1]) ** 2 + s[0, 1] * s[0, 1])
        return mean - r, mean + r
    q = (s[0, 0] + s[1, 1] + s[2, 2]) / 3.0
    off = s[0, 1] * s[0, 1] + s[0, 2] * s[0, 2] + s[1, 2] * s[1, 2]
    p2 = ((s[0, 0] - q) ** 2 + (s[1, 1] - q) ** 2 + (s[2, 2] - q) ** 2 + 2.0 * off) / 6.0
    if p2 <= 0.0:
        return q, q
    p = math.sqrt(p2)
    a, b, c = (s[0, 0] - q) / p, (s[1, 1] - q) / p, (s[2, 2] - q) / p
    d, e, f = s[0, 1] / p, s[0, 2] / p, s[1, 2] / p
    r = 0.5 * (a * (b * c - f * f) - d * (d * c - f * e) + e * (d * f - b * e))
    r = min(max(r, -1.0), 1.0)
    phi = math.acos(r) / 3.0
    return q + 2.0 * p * math.cos(phi + 2.0 * math.pi / 3.0), q + 2.0 * p * math.cos(phi)


@njit(cache=True, fastmath=FMA, error_model="numpy")
def longitudinal_modulus_bound(F, G, B, D):
    """Largest rho0 c^2 (MPa) over the wave directions of the module docstring (a bound in
    3D) for
    the deformation gradient ``F`` (3 x 3), shear modulus ``G``, bulk term ``B`` (MPa)
    and ``D`` the directions' dimension (2: in the plane, 3: in space)."""
    J = MG.determinant(F)
    b = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            b[i, j] = F[i, 0] * F[j, 0] + F[i, 1] * F[j, 1] + F[i, 2] * F[j, 2]
    scale = G * J ** (-2.0 / 3.0)
    mu = scale * (b[0, 0] + b[1, 1] + b[2, 2]) / 3.0
    for i in range(3):
        for j in range(3):
            b[i, j] *= scale
        b[i, i] -= mu                       # s = G dev(b_bar)
    s_min, s_max = _extreme_eigenvalues(b, D)
    beta = B + mu / 3.0
    a = 0.25 * beta * beta - 4.0 * s_min * s_max / 9.0
    slope = 4.0 * (s_min + s_max) / 9.0 - 2.0 * beta / 3.0
    sigma = s_max
    if slope < 0.0:                        # stationary point of the concave bound
        sigma = min(max((2.25 * slope * slope - a) / slope, s_min), s_max)
    return mu + 0.5 * beta + sigma / 3.0 + math.sqrt(max(a + slope * sigma, 0.0))


@njit(cache=True, fastmath=FMA, error_model="numpy")
def max_signal_speed(F, eos, velgrad, v, field, kind, params, rho0) -> float:
    """Largest signal speed (mm/s) over the finite-strain particles: c_q + sqrt(c_q^2 +
    c_L^2) + |v|, with c_L^2 = :func:`longitudinal_modulus_bound` / rho0 (``rho0`` per
    field) and, for Mie-Grueneisen particles, the viscous term of Eq 52, c_q = A1 C +
    A2 dx |D_kk| (the usual bound with a viscous pressure; D_kk the trace of the
    particle's last velocity gradient, ``velgrad`` with zero rows: none). 0 when the run
    has no finite-strain particle; NaN when a particle is past Eq 51's singularity or
    inverted (J <= 0), so the run stops with the divergence message."""
    D = v.shape[1]
    best = 0.0
    for p in range(field.shape[0]):
        f = field[p]
        if kind[f] == LINEAR:
            continue
        prm = params[f]
        J = MG.determinant(F[p])
        if not J > 0.0:
            return math.nan
        cq = 0.0
        if kind[f] == MIE_GRUNEISEN:
            C = MG.bulk_wave_speed(J, max(eos[p, MG.E_PRESSURE], 0.0), prm[P_K], prm[MG.P_S1],
                                   prm[MG.P_GAMMA0], rho0[f])
            B = rho0[f] * C * C
            dkk = 0.0
            if velgrad.shape[0]:
                for i in range(velgrad.shape[1]):
                    dkk += velgrad[p, i, i]
            cq = prm[MG.P_A1] * C + prm[MG.P_A2] * prm[MG.P_DX] * abs(dkk)
        else:
            B = volumetric_stiffness(J, prm[P_K], int(prm[P_VOLUMETRIC]))
        cL2 = longitudinal_modulus_bound(F[p], prm[P_G], B, D) / rho0[f]
        vp = 0.0
        for i in range(D):
            vp += v[p, i] * v[p, i]
        speed = cq + math.sqrt(cq * cq + max(cL2, 0.0)) + math.sqrt(vp)
        if not speed <= best:          # NaN propagates
            best = speed
    return best
