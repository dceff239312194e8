"""The Mie-Grueneisen stress update of MPM (mpm/mie_gruneisen.py, 004 Eq 51-52) on one
particle driven through prescribed homogeneous uniaxial strains: Eq 51 and the
neo-Hookean shear against ``interfaces.materials.MieGruneisen``, the energy equation
against the isentrope (second order in the step, closing to round-off when a
compression is retraced without viscosity), the artificial viscosity of Eq 52."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from interfaces import (Body, BoundaryCondition, Case, CaseError, MieGruneisen, Rectangle)
from interfaces.analytic.hugoniot import ShockHugoniot
from mpm import finite_strain as FS
from mpm import mie_gruneisen as MG
from mpm.signal_speed import max_signal_speed
from mpm.options import merge

RHO = 8.87e-9
K = 188e3
NICKEL = MieGruneisen(C0=math.sqrt(K / RHO), S1=1.44, gamma0=2.0, G=76e3, rho=RHO)
CELL = 0.25


def _case(mat: MieGruneisen) -> Case:
    return Case(name="mg", analysis="plane_strain", thickness=1.0, materials={"ni": mat},
                bodies=[Body("b", Rectangle(0.0, 0.0, 1.0, 1.0), "ni")],
                boundary_conditions=[BoundaryCondition("fixed", "b", "xmax", ("x",), (0.0,))])


def _drive(mat: MieGruneisen, J_path, dt=1e-9):
    """One plane-strain particle whose F_xx follows ``J_path`` (F = diag(J, 1, 1)):
    the velocity gradient of each step is L_xx = (J_k+1 / J_k - 1) / dt. Returns the
    (e, P) state, stress, V0 W + V0 e and F after each step."""
    kind, params = FS.material_tables(_case(mat), CELL)
    assert kind[0] == FS.MIE_GRUNEISEN
    F = np.eye(3)[None].copy()
    stress, strain = np.zeros((1, 3)), np.zeros((1, 3))
    V0 = np.ones(1)
    V = V0.copy()
    x = np.ones((1, 2))
    foff = np.zeros((1, 2))
    eos = np.zeros((1, 2))
    out = []
    for k in range(len(J_path) - 1):
        L = np.zeros((1, 2, 2))
        L[0, 0, 0] = (J_path[k + 1] / J_path[k] - 1.0) / dt
        U = FS.finite_strain_update(L, F, stress, strain, V, V0, x, x, foff, foff.copy(),
                                    np.zeros(1, np.int64), kind, params, dt, False, eos)
        out.append((eos[0].copy(), stress[0].copy(), U, F[0].copy()))
    return out


def _isochoric(mat, J):
    """W = G/2 (J^(-2/3) tr(F F^T) - 3) of F = diag(J, 1, 1)."""
    return 0.5 * mat.G * (J ** (-2.0 / 3.0) * (J * J + 2.0) - 3.0)


def _compression(J_min, n):
    return np.linspace(1.0, J_min, n + 1)


def test_pressure_is_eq51_with_the_neo_hookean_shear():
    """After a compression to J = 0.8: -(s_xx + 2 s_yy) / 3 (uniaxial strain) is the
    material's Eq 51 pressure at the tracked energy rho0 U = e + W; s_xx - s_yy is the
    neo-Hookean deviator G J^(-5/3) (J^2 - 1); U = V0 (e + W)."""
    out = _drive(NICKEL, _compression(0.8, 200))
    (e, P), s, U, F = out[-1]
    J = F[0, 0]
    assert J == pytest.approx(0.8, rel=1e-12)
    W = _isochoric(NICKEL, J)
    p_mat = float(NICKEL.pressure(J, e + W))
    assert -(s[0] + 2.0 * s[1]) / 3.0 == pytest.approx(p_mat, rel=1e-12)
    assert P == pytest.approx(p_mat, rel=1e-12)
    assert s[0] - s[1] == pytest.approx(NICKEL.G * J ** (-5.0 / 3.0) * (J * J - 1.0), rel=1e-12)
    assert U == pytest.approx(e + W, rel=1e-12)


def test_tension_is_linear_in_eta_without_energy_term():
    """Eq 51 in tension (eta < 0): p = K eta."""
    out = _drive(NICKEL, np.linspace(1.0, 1.01, 11))
    (e, P), s, _, F = out[-1]
    assert P == pytest.approx(K * (1.0 - F[0, 0]), rel=1e-12)


def _isentrope_energy(mat, J_end):
    """e + W along the isentrope from J = 1: d(e + W)/dJ = -(p + deviatoric work), i.e.
    de/dJ = -p(J, e + W) (the isochoric energy W is the deviator's exact work)."""
    def rhs(J, y):
        return [-float(mat.pressure(J, y[0] + _isochoric(mat, J)))]
    sol = solve_ivp(rhs, (1.0, J_end), [0.0], rtol=1e-12, atol=1e-6, method="DOP853")
    return float(sol.y[0, -1])


def test_energy_equation_converges_to_the_isentrope_at_second_order():
    """Without viscosity the pressure work integrated by the trapezoidal rule converges
    to the isentrope's e(J) at order 2 in the strain step (measured: ratio 4.00 per
    halving)."""
    exact = _isentrope_energy(NICKEL, 0.75)
    errors = []
    for n in (25, 50, 100):
        e = _drive(NICKEL, _compression(0.75, n))[-1][0][0]
        errors.append(abs(e - exact) / exact)
    rates = [math.log2(errors[i] / errors[i + 1]) for i in range(2)]
    assert errors[-1] < 1e-4          # measured 4.3e-5 at 100 steps to J = 0.75
    assert all(abs(r - 2.0) < 0.05 for r in rates), rates


def test_retraced_compression_closes_to_round_off():
    """Compression to J = 0.75 and back along the same strains, no viscosity: the
    trapezoidal rule is time-symmetric, so e, the pressure and the stress come back to 0
    to round-off (relative to the largest energy and pressure of the cycle)."""
    down = _compression(0.75, 100)
    path = np.concatenate([down, down[-2::-1]])
    out = _drive(NICKEL, path)
    e_max = max(o[0][0] for o in out)
    p_max = max(o[0][1] for o in out)
    (e, P), s, U, F = out[-1]
    assert F[0, 0] == pytest.approx(1.0, abs=1e-13)
    assert abs(e) < 1e-12 * e_max
    assert abs(P) < 1e-11 * p_max
    assert np.abs(s).max() < 1e-11 * p_max


def test_artificial_viscosity_is_eq52_and_heats():
    """One compressive step: P - p = q = rho dx |D_kk| (A1 C + A2 dx |D_kk|) with the bulk
    wave speed C = sqrt(dp/drho) of the isentrope (at the new J, previous pressure); a retraced cycle with viscosity ends with
    e > 0 (the viscous work stays as heat)."""
    visc = MieGruneisen(C0=NICKEL.C0, S1=1.44, gamma0=2.0, G=76e3, rho=RHO, A1=0.4, A2=4.0)
    dt = 1e-9
    path = [1.0, 0.9, 0.89]
    (e1, P1), *_ = _drive(visc, path[:2], dt)[-1]
    (e2, P2), s, _, F = _drive(visc, path, dt)[-1]
    J, J0 = 0.89, 0.9
    rate = math.log(J0 / J) / dt
    eta = 1.0 - J
    f = K * eta * (1.0 - eta) / (1.0 - 1.44 * eta) ** 2
    p_static = f + 2.0 * (e2 + _isochoric(visc, J))
    # C = dp/drho along the isentrope at the new J with the previous pressure P1
    d = 1.0 - 1.44 * eta
    dfdeta = K * ((1.0 - 2.0 * eta) * d + 2.0 * 1.44 * eta * (1.0 - eta)) / d**3
    C = J * math.sqrt((dfdeta + 2.0 * P1) / RHO)
    q = RHO / J * CELL * rate * (0.4 * C + 4.0 * CELL * rate)
    assert P2 - p_static == pytest.approx(q, rel=1e-10)
    down = _compression(0.8, 50)
    out = _drive(visc, np.concatenate([down, down[-2::-1]]), dt)
    assert out[-1][0][0] > 1e-3 * max(o[0][0] for o in out)


def test_signal_speed_of_the_compressed_state():
    """max_signal_speed: c_q + sqrt(c_q^2 + c_L^2) + |v| with the isentropic bulk speed C
    at (J, P), c_q = A1 C + A2 dx |D_kk| and c_L the longitudinal speed of the acoustic
    tensor (mpm/signal_speed.py) with rho0 C^2 as its bulk term: for F = diag(J, 1, 1)
    the fastest in-plane wave runs along x, rho0 c_L^2 = rho0 C^2 + 4 mu / 3 - s_xx / 3,
    mu = G J^(-2/3) (J^2 + 2) / 3 and s_xx = 2 G J^(-2/3) (J^2 - 1) / 3 (the deviatoric
    Kirchhoff stress)."""
    visc = MieGruneisen(C0=NICKEL.C0, S1=1.44, gamma0=2.0, G=76e3, rho=RHO, A1=0.4, A2=4.0)
    kind, params = FS.material_tables(_case(visc), CELL)
    J, P, dkk, v = 0.8, 9e4, -2e5, np.array([[3e5, -4e5]])
    F = np.diag([J, 1.0, 1.0])[None]
    eos = np.array([[0.0, P]])
    L = np.diag([dkk, 0.0])[None]
    rho0 = np.array([RHO])
    speed = max_signal_speed(F, eos, L, v, np.zeros(1, np.int64), kind, params, rho0)
    eta = 0.2
    d = 1.0 - 1.44 * eta
    dfdeta = K * ((1.0 - 2.0 * eta) * d + 2.0 * 1.44 * eta * (1.0 - eta)) / d**3
    C = J * math.sqrt((dfdeta + 2.0 * P) / RHO)
    mu = 76e3 * J ** (-2.0 / 3.0) * (J * J + 2.0) / 3.0
    s_xx = 2.0 * 76e3 * J ** (-2.0 / 3.0) * (J * J - 1.0) / 3.0
    cL2 = C * C + (4.0 * mu / 3.0 - s_xx / 3.0) / RHO
    cq = 0.4 * C + 4.0 * CELL * abs(dkk)
    assert speed == pytest.approx(cq + math.sqrt(cq * cq + cL2) + 5e5, rel=1e-12)
    assert max_signal_speed(F, eos, L, v, np.zeros(1, np.int64), np.zeros(1, np.int64),
                            params, rho0) == 0.0


def test_bad_input_is_refused():
    """Negative viscosity coefficients, a plane-stress Mie-Grueneisen body, an unknown
    body or a malformed initial velocity, both Y and G in the Hugoniot."""
    for name in ("A1", "A2"):
        with pytest.raises(CaseError, match=name):
            MieGruneisen(C0=NICKEL.C0, S1=1.44, gamma0=2.0, G=76e3, rho=RHO, **{name: -0.1})
    case = _case(NICKEL)
    with pytest.raises(CaseError, match="initial_velocity: unknown body 'nope'"):
        merge(case, {"cell": 0.25, "initial_velocity": {"nope": [1.0, 0.0]}})
    with pytest.raises(CaseError, match="initial_velocity.b must be 2 finite"):
        merge(case, {"cell": 0.25, "initial_velocity": {"b": [1.0]}})
    with pytest.raises(CaseError, match="initial_velocity.b must be 2 finite"):
        merge(case, {"cell": 0.25, "initial_velocity": {"b": ["fast", 0.0]}})
    with pytest.raises(CaseError, match="either the yield stress Y"):
        ShockHugoniot(K=K, rho=RHO, S1=1.44, gamma0=2.0, Y=100.0, G=76e3)


def test_hugoniot_with_neo_hookean_shear_satisfies_the_jump_conditions():
    """sigma = rho0 U_s u_p = p(J, rho0 u_p^2 / 2) + (2/3) G J^(-5/3) (1 - J^2) and
    J = 1 - u_p / U_s; G = 0 gives back U_s = C0 + S1 u_p."""
    h = ShockHugoniot(K=K, rho=RHO, S1=1.44, gamma0=2.0, G=76e3)
    for up in (2e5, 8e5, 1.84e6):
        st = h.state(up)
        assert st.volume_ratio == pytest.approx(1.0 - up / st.shock_speed, rel=1e-12)
        sigma = float(NICKEL.pressure(st.volume_ratio, RHO * 0.5 * up * up)) + \
            2.0 / 3.0 * 76e3 * st.volume_ratio ** (-5.0 / 3.0) * (1.0 - st.volume_ratio ** 2)
        assert st.longitudinal_stress == pytest.approx(sigma, rel=1e-10)
    hydro = ShockHugoniot(K=K, rho=RHO, S1=1.44, gamma0=2.0)
    assert hydro.state(1e6).shock_speed == pytest.approx(NICKEL.C0 + 1.44e6, rel=1e-10)
