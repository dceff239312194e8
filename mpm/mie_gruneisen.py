"""Mie-Grueneisen material of the MPM finite-strain update (004 Sec 4.3, Eq 51-52).

004 models nickel under shock with "the hyperelastic shear term in Eq (18)" and the bulk
term replaced by the Mie-Grueneisen pressure of Eq 51, plus the artificial viscosity q
of Eq 52 in compression. Per particle, with eta = 1 - J (compression positive):

* pressure (Eq 51): p = K eta (1 - gamma0 eta / 2) / (1 - S1 eta)^2 + rho0 gamma0 U for
  eta > 0, p = K eta in tension (the text extraction of Eq 51 prints the two branches'
  conditions with the sign of eta swapped; compression is eta > 0, as in the Hugoniot
  fit the law comes from and in NairnMPM's HEMGEOSMaterial); K = rho0 C0^2;
* deviatoric stress: the neo-Hookean term of Eq 18, G J^(-5/3) dev(F F^T), whose work is
  exactly the isochoric energy W = G/2 (J^(-2/3) tr(F F^T) - 3) per unit reference volume;
* U, the internal energy per unit mass, is the whole work done on the particle (as
  NairnMPM tracks it and as the Rankine-Hugoniot energy jump counts it,
  ``interfaces.analytic.hugoniot``): rho0 U = e + W, with e the work of the pressure and
  viscosity, integrated by the trapezoidal rule, de = -(P_n + P_n+1) / 2 dJ (P = p + q).
  P_n+1 depends on e_n+1 linearly through rho0 gamma0 U, so the rule is solved in closed
  form: it is time-symmetric, and a compression retraced back to J = 1 without viscosity
  returns e to round-off (tests/mpm/test_mpm_mie_gruneisen.py);
* artificial viscosity (Eq 52), only while the volume decreases (D_kk < 0):
  q = rho dx |D_kk| (A1 C + A2 dx |D_kk|), rho = rho0 / J the current density, dx the
  cell size, D_kk = ln(J_n+1 / J_n) / dt the volumetric strain rate of the step and C the
  current bulk wave speed (:func:`bulk_wave_speed`). Its work heats the particle (it is
  part of e), so the run's total energy stays conserved.

The per-particle state ``eos[p] = (e, P)`` (MPa) carries e and the last total pressure.
Time step: :func:`mpm.signal_speed.max_signal_speed` gives the largest wave speed of the
current state (longitudinal speed with C as the bulk term, viscous term and particle
speed), from which the solver sets dt between compiled chunks of steps.
"""
from __future__ import annotations

import math

from interfaces.jit import FMA, njit

#: columns of the per-field parameter table of mpm.finite_strain after K, G, volumetric code
P_S1 = 3
P_GAMMA0 = 4
P_RHO0 = 5
P_A1 = 6
P_A2 = 7
P_DX = 8
N_PARAMS = 9

#: per-particle state columns
E_WORK = 0       # e: pressure + viscosity work per unit reference volume (MPa)
E_PRESSURE = 1   # P = p + q of the last update (MPa)
N_STATE = 2


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def cold_pressure(eta, K, S1, gamma0):
    """(f, df/deta): the energy-free part of Eq 51 and its slope; NaN at S1 eta >= 1
    (the Hugoniot singularity), so the run stops with the divergence message."""
    if eta <= 0.0:
        return K * eta, K
    d = 1.0 - S1 * eta
    if d <= 0.0:
        return math.nan, math.nan
    num = eta * (1.0 - 0.5 * gamma0 * eta)
    dnum = 1.0 - gamma0 * eta
    return K * num / (d * d), K * (dnum * d + 2.0 * S1 * num) / (d * d * d)


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def bulk_wave_speed(J, p, K, S1, gamma0, rho0):
    """Current bulk wave speed C = sqrt(dp/drho) along the isentrope: with
    d(rho0 U)/deta = p there (no heat), dp/deta = f'(eta) + gamma0 p in compression and
    drho/deta = rho0 / J^2."""
    eta = 1.0 - J
    f, df = cold_pressure(eta, K, S1, gamma0)
    slope = df + gamma0 * p if eta > 0.0 else df
    return J * math.sqrt(max(slope, 0.0) / rho0)


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def pressure_update(J, J_old, W, dt, prm, eos, p):
    """The total pressure P = p + q of Eq 51-52 at J (``J_old`` the step's start) and the
    trapezoidal energy update of the module docstring; ``W`` the particle's isochoric
    energy at J, ``prm`` its field's parameter row, ``eos[p]`` its (e, P) updated in
    place. Returns P."""
    K = prm[0]
    S1, gamma0, rho0 = prm[P_S1], prm[P_GAMMA0], prm[P_RHO0]
    e_old, P_old = eos[p, E_WORK], eos[p, E_PRESSURE]
    eta = 1.0 - J
    f, df = cold_pressure(eta, K, S1, gamma0)
    q = 0.0
    if J < J_old and (prm[P_A1] > 0.0 or prm[P_A2] > 0.0):
        rate = math.log(J_old / J) / dt                 # |D_kk|
        C = bulk_wave_speed(J, max(P_old, 0.0), K, S1, gamma0, rho0)
        dx = prm[P_DX]
        q = rho0 / J * dx * rate * (prm[P_A1] * C + prm[P_A2] * dx * rate)
    half = 0.5 * (J - J_old)
    if eta > 0.0:
        # e = e_old - half (P_old + f + gamma0 (e + W) + q), solved for e
        e = (e_old - half * (P_old + f + gamma0 * W + q)) / (1.0 + half * gamma0)
        P = f + gamma0 * (e + W) + q
    else:
        P = f + q
        e = e_old - half * (P_old + P)
    eos[p, E_WORK] = e
    eos[p, E_PRESSURE] = P
    return P


@njit(cache=True, inline="always")
def determinant(A):
    """det of a 3 x 3 matrix."""
    return (A[0, 0] * (A[1, 1] * A[2, 2] - A[1, 2] * A[2, 1])
            - A[0, 1] * (A[1, 0] * A[2, 2] - A[1, 2] * A[2, 0])
            + A[0, 2] * (A[1, 0] * A[2, 1] - A[1, 1] * A[2, 0]))
