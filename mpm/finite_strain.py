"""Finite-strain (hyperelastic) stress update of MPM particles: the deformation
gradient F per particle and the neo-Hookean Cauchy stress of 004 Eq 18.

Which fields take this update is a per-field table built once per run
(:func:`material_tables`): ``kind[f]`` is ``LINEAR`` (the small-strain update inlined
in the G2P / stress kernels of :mod:`mpm.kernels` and :mod:`mpm.kernels3d`) or
``NEO_HOOKEAN``. For a finite-strain field those kernels only store the particle's
velocity gradient L = sum v_i (x) grad S_ip (its shape functions and nodal velocities
are those of the update scheme: USL, MUSL or USF), and :func:`finite_strain_update`
then, per particle,

* updates F_{n+1} = (I + dt L) F_n, the incremental form NairnMPM uses for its
  hyperelastic materials (NairnMPM also offers a truncated exponential of dt L; the
  first-order form is kept because x_{n+1} = x_n + dt v is the same first-order map, so
  F stays the gradient of the particle motion: in a homogeneous deformation the
  particle spacing and F agree to round-off);
* out of plane: F_zz = 1 (plane strain) or the hoop stretch F_tt = r / r_0
  (axisymmetric, x = r; 000 Sec 2.3);
* sets V = J V_0, the Cauchy stress sigma = G J^(-5/3) dev(F F^T) + U'(J) I and the
  Green-Lagrange strain E = (F^T F - I) / 2 (engineering shear) in the particle's
  strain row (the small-strain strain of a linear field);
* adds V_0 W(F) (004 Eq 18, per unit reference volume) to the strain energy, so that
  the history and the Result report the hyperelastic energy at any strain;
* carries the offset from the particle centre to its loaded edge (tractions) with F.

A ``MIE_GRUNEISEN`` field (004 Sec 4.3) keeps the neo-Hookean shear term and replaces
U'(J) by minus the Mie-Grueneisen pressure of 004 Eq 51 with the artificial viscosity of
Eq 52 (:mod:`mpm.mie_gruneisen`, its internal energy tracked per particle in ``eos``);
its energy term is the particle's internal energy V_0 rho_0 U.

Plane stress would need the out-of-plane stretch solved per particle for sigma_zz = 0
(NairnMPM does it by Newton iteration); it is refused (:func:`material_tables`).
"""
from __future__ import annotations

import math

import numpy as np

from interfaces.errors import CaseError
from interfaces.jit import FMA, njit
from interfaces.materials import VOLUMETRIC_TERMS, MieGruneisen, NeoHookean

from . import mie_gruneisen as MG

#: material kinds of the stress update per field
LINEAR = 0
NEO_HOOKEAN = 1
MIE_GRUNEISEN = 2

#: volumetric term codes (``interfaces.materials.VOLUMETRIC_TERMS`` order)
U_EQ18 = 0                # K/2 ((J^2 - 1)/2 - ln J), 004 Eq 18
U_J_MINUS_1_SQUARED = 1   # K/2 (J - 1)^2
U_LN_J_SQUARED = 2        # K/2 (ln J)^2

#: columns of the per-field parameter table
P_K = 0
P_G = 1
P_VOLUMETRIC = 2
N_PARAMS = MG.N_PARAMS      # Mie-Grueneisen fields: S1, gamma0, rho0, A1, A2, cell size


def unsupported_material(case) -> str | None:
    """The one-line reason MPM cannot run the materials of ``case``, or None."""
    for body in case.bodies:
        mat = case.materials[body.material]
        if isinstance(mat, (NeoHookean, MieGruneisen)) and case.analysis == "plane_stress":
            name = "neo-Hookean" if isinstance(mat, NeoHookean) else "Mie-Grueneisen"
            return (f"body {body.name!r}: {name} materials need analysis plane_strain, "
                    "axisymmetric or 3d in mpm (plane stress would need the out-of-plane "
                    "stretch solved per particle)")
    return None


def material_tables(case, cell: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Per field (= body): the material kind (int64, ``LINEAR`` / ``NEO_HOOKEAN`` /
    ``MIE_GRUNEISEN``) and the parameters (float64 [M, N_PARAMS]: K, G, volumetric term
    code; Mie-Grueneisen: K = rho0 C0^2, G, then S1, gamma0, rho0, A1, A2 and the grid
    ``cell`` size of the artificial viscosity, 004 Eq 52)."""
    reason = unsupported_material(case)
    if reason is not None:
        raise CaseError(f"mpm: {reason}")
    M = len(case.bodies)
    kind = np.zeros(M, np.int64)
    params = np.zeros((M, N_PARAMS))
    for f, body in enumerate(case.bodies):
        mat = case.materials[body.material]
        if isinstance(mat, NeoHookean):
            kind[f] = NEO_HOOKEAN
            params[f, P_K] = mat.K
            params[f, P_G] = mat.G
            params[f, P_VOLUMETRIC] = VOLUMETRIC_TERMS.index(mat.volumetric)
        elif isinstance(mat, MieGruneisen):
            kind[f] = MIE_GRUNEISEN
            params[f, P_K] = mat.K
            params[f, P_G] = mat.G
            params[f, [MG.P_S1, MG.P_GAMMA0, MG.P_RHO0, MG.P_A1, MG.P_A2, MG.P_DX]] = \
                (mat.S1, mat.gamma0, mat.rho, mat.A1, mat.A2, cell)
    return kind, params


def eos_state(P: int, kind: np.ndarray) -> np.ndarray:
    """The per-particle Mie-Grueneisen state (e, P) of :mod:`mpm.mie_gruneisen`, zero:
    (P, 2) when some field is Mie-Grueneisen, else (0, 2)."""
    return np.zeros((P if np.any(kind == MIE_GRUNEISEN) else 0, MG.N_STATE))


def identity_gradients(P: int) -> np.ndarray:
    """(P, 3, 3) deformation gradients of the undeformed particles."""
    return np.ascontiguousarray(np.broadcast_to(np.eye(3), (P, 3, 3)))


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def volumetric_terms(J, K, code):
    """(U(J), U'(J)) of the volumetric term ``code``."""
    if code == U_J_MINUS_1_SQUARED:
        return 0.5 * K * (J - 1.0) ** 2, K * (J - 1.0)
    if code == U_LN_J_SQUARED:
        lj = math.log(J)
        return 0.5 * K * lj * lj, K * lj / J
    return 0.5 * K * (0.5 * (J * J - 1.0) - math.log(J)), 0.5 * K * (J - 1.0 / J)


@njit(cache=True, inline="always", fastmath=FMA, error_model="numpy")
def volumetric_stiffness(J, K, code):
    """J^2 U''(J) of the volumetric term ``code``: the bulk term of the acoustic tensor
    (:mod:`mpm.signal_speed`; K at rest for every code)."""
    if code == U_J_MINUS_1_SQUARED:
        return K * J * J
    if code == U_LN_J_SQUARED:
        return K * (1.0 - math.log(J))
    return 0.5 * K * (J * J + 1.0)


@njit(cache=True, inline="always")
def _right_cauchy_green(F, i, j):
    """C_ij = sum_k F_ki F_kj."""
    return F[0, i] * F[0, j] + F[1, i] * F[1, j] + F[2, i] * F[2, j]


@njit(cache=True, fastmath=FMA, error_model="numpy")
def finite_strain_update(velgrad, F, stress, strain, pvol, pvol0, x, x0, foff, foff0, field,
                         kind, params, dt, axisymmetric, eos) -> float:
    """The update of the module docstring for every particle of a finite-strain field,
    and its loaded-edge offset carried by the deformation, foff = F foff_0 (the traction
    of a loaded particle acts at its deformed edge; with the undeformed offset the
    edge rows of a block compressed 20 % by a dead load strain 5 % more than the
    rest). Returns the strain energy sum V_0 W(F) (NaN when a particle inverted,
    J <= 0, so the run stops with the divergence message). Voigt rows: 2D [xx, yy, xy],
    axisymmetric [rr, zz, rz, tt], 3D [xx, yy, zz, yz, xz, xy]. ``eos``: the (e, P)
    state of the Mie-Grueneisen particles (:func:`eos_state`)."""
    D = velgrad.shape[1]
    U = 0.0
    A = np.empty((3, 3))
    Fn = np.empty((3, 3))
    B = np.empty((3, 3))
    for p in range(field.shape[0]):
        f = field[p]
        if kind[f] == LINEAR:
            continue
        for i in range(3):
            for j in range(3):
                A[i, j] = 0.0
            A[i, i] = 1.0
        for i in range(D):
            for j in range(D):
                A[i, j] += dt * velgrad[p, i, j]
        for i in range(3):
            for j in range(3):
                s = 0.0
                for k in range(3):
                    s += A[i, k] * F[p, k, j]
                Fn[i, j] = s
        if D == 2:
            Fn[0, 2] = 0.0
            Fn[1, 2] = 0.0
            Fn[2, 0] = 0.0
            Fn[2, 1] = 0.0
            Fn[2, 2] = x[p, 0] / x0[p, 0] if axisymmetric else 1.0
        J = (Fn[0, 0] * (Fn[1, 1] * Fn[2, 2] - Fn[1, 2] * Fn[2, 1])
             - Fn[0, 1] * (Fn[1, 0] * Fn[2, 2] - Fn[1, 2] * Fn[2, 0])
             + Fn[0, 2] * (Fn[1, 0] * Fn[2, 1] - Fn[1, 1] * Fn[2, 0]))
        J_old = MG.determinant(F[p]) if kind[f] == MIE_GRUNEISEN else 1.0
        for i in range(3):
            for j in range(3):
                F[p, i, j] = Fn[i, j]
        for i in range(D):
            s = 0.0
            for k in range(D):
                s += Fn[i, k] * foff0[p, k]
            foff[p, i] = s
        if not J > 0.0:
            U = math.nan
            continue
        K = params[f, P_K]
        G = params[f, P_G]
        for i in range(3):
            for j in range(3):
                B[i, j] = Fn[i, 0] * Fn[j, 0] + Fn[i, 1] * Fn[j, 1] + Fn[i, 2] * Fn[j, 2]
        I1 = B[0, 0] + B[1, 1] + B[2, 2]
        Jm23 = J ** (-2.0 / 3.0)          # one power per particle
        Gs = G * Jm23 / J
        if kind[f] == MIE_GRUNEISEN:
            dU = -MG.pressure_update(J, J_old, 0.5 * G * (I1 * Jm23 - 3.0), dt, params[f],
                                     eos, p)
            Uv = eos[p, MG.E_WORK]
        else:
            Uv, dU = volumetric_terms(J, K, int(params[f, P_VOLUMETRIC]))
        mean = dU - Gs * I1 / 3.0
        # Green-Lagrange E = (F^T F - I) / 2, engineering shear 2 E_ij = C_ij
        if D == 3:
            stress[p, 0] = Gs * B[0, 0] + mean
            stress[p, 1] = Gs * B[1, 1] + mean
            stress[p, 2] = Gs * B[2, 2] + mean
            stress[p, 3] = Gs * B[1, 2]
            stress[p, 4] = Gs * B[0, 2]
            stress[p, 5] = Gs * B[0, 1]
            strain[p, 0] = 0.5 * (_right_cauchy_green(Fn, 0, 0) - 1.0)
            strain[p, 1] = 0.5 * (_right_cauchy_green(Fn, 1, 1) - 1.0)
            strain[p, 2] = 0.5 * (_right_cauchy_green(Fn, 2, 2) - 1.0)
            strain[p, 3] = _right_cauchy_green(Fn, 1, 2)
            strain[p, 4] = _right_cauchy_green(Fn, 0, 2)
            strain[p, 5] = _right_cauchy_green(Fn, 0, 1)
        else:
            stress[p, 0] = Gs * B[0, 0] + mean
            stress[p, 1] = Gs * B[1, 1] + mean
            stress[p, 2] = Gs * B[0, 1]
            strain[p, 0] = 0.5 * (_right_cauchy_green(Fn, 0, 0) - 1.0)
            strain[p, 1] = 0.5 * (_right_cauchy_green(Fn, 1, 1) - 1.0)
            strain[p, 2] = _right_cauchy_green(Fn, 0, 1)
            if axisymmetric:
                stress[p, 3] = Gs * B[2, 2] + mean
                strain[p, 3] = 0.5 * (Fn[2, 2] * Fn[2, 2] - 1.0)
        pvol[p] = J * pvol0[p]
        U += pvol0[p] * (0.5 * G * (I1 * Jm23 - 3.0) + Uv)
    return U
