"""Wave energy transmission through a spring interface (002 Eq 48, ERRATA 6; general Z1, Z2)."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from interfaces.analytic import (bar_wave_speed, dilatational_wave_speed, impedance, pulse_transmission,
                                 wave_amplitude_ratios, wave_reflection, wave_transmission,
                                 wave_transmission_identical)
from interfaces.errors import CaseError

# 002 Sec 3.3: E = 410 GPa, nu = 0.28, rho = 15 g/cm^3, f = 100 kHz
E, NU, RHO, F = 410e3, 0.28, 15e-9, 1e5
Z = RHO * bar_wave_speed(E, RHO)


def _numerical_coefficients(f, K, Z1, Z2):
    """Solve the interface conditions for (B, C) given A = 1 numerically (independent of the
    closed form): traction continuity Z1 (A - B) = Z2 C and spring law -i w Z2 C = K (C - A - B)."""
    w = 2 * math.pi * f
    M = np.array([[-Z1, -Z2], [K, -(K + 1j * w * Z2)]], dtype=complex)
    rhs = np.array([-Z1, -K], dtype=complex)
    B, C = np.linalg.solve(M, rhs)
    return B, C


def test_identical_materials_reduce_to_eq48():
    for Dn in (1e2, 1e4, 2.5e4, 1e5, 1e7):
        T48 = Dn ** 2 / (Dn ** 2 + math.pi ** 2 * F ** 2 * RHO ** 2 * (E / RHO))
        assert wave_transmission_identical(F, Dn, RHO, E=E) == pytest.approx(T48, rel=1e-14)
        assert wave_transmission(F, Dn, Z) == pytest.approx(T48, rel=1e-13)
        assert wave_transmission(F, Dn, Z, Z) == pytest.approx(T48, rel=1e-13)
    # half transmission at Dn = pi f Z (002 Sec 3.4 "tune the frequency")
    assert wave_transmission(F, math.pi * F * Z, Z) == pytest.approx(0.5, rel=1e-14)
    # the wave speed can be passed explicitly (e.g. the dilatational speed of a plane-strain block)
    v = dilatational_wave_speed(E, NU, RHO, "plane_strain")
    assert v == pytest.approx(math.sqrt(E * (1 - NU) / ((1 + NU) * (1 - 2 * NU) * RHO)), rel=1e-15)
    assert wave_transmission_identical(F, 3e4, RHO, v=v) == pytest.approx(
        wave_transmission(F, 3e4, impedance(RHO, v=v)), rel=1e-13)
    # 002 quotes v = 5235 m/s for these constants; the bar speed is 5228 m/s
    assert bar_wave_speed(E, RHO) / 1e3 == pytest.approx(5235.0, rel=2e-3)


@pytest.mark.parametrize("Z2_over_Z1", [1.0, 0.2, 3.0, 17.0])
@pytest.mark.parametrize("Dn", [0.0, 1.0, 1e3, 3e4, 1e6, math.inf])
def test_general_form_against_numerical_interface_conditions(Z2_over_Z1, Dn):
    Z1, Z2 = Z, Z * Z2_over_Z1
    T, R = wave_transmission(F, Dn, Z1, Z2), wave_reflection(F, Dn, Z1, Z2)
    assert R + T == pytest.approx(1.0, rel=1e-14)
    if Dn == 0.0:
        assert T == 0.0 and R == 1.0
        return
    if math.isinf(Dn):
        assert T == pytest.approx(4 * Z1 * Z2 / (Z1 + Z2) ** 2, rel=1e-15)
        return
    B, C = _numerical_coefficients(F, Dn, Z1, Z2)
    assert T == pytest.approx(Z2 / Z1 * abs(C) ** 2, rel=1e-12)
    assert R == pytest.approx(abs(B) ** 2, rel=1e-12)
    Bc, Cc = wave_amplitude_ratios(F, Dn, Z1, Z2)
    assert Bc == pytest.approx(B, rel=1e-12) and Cc == pytest.approx(C, rel=1e-12)


def test_limits():
    assert wave_transmission(F, math.inf, Z) == 1.0
    assert wave_transmission(F, 1e13, Z) == pytest.approx(1.0, abs=1e-10)
    assert wave_transmission(F, 0.0, Z) == 0.0
    assert wave_transmission(F, 1e-6, Z) < 1e-20
    assert wave_transmission(F, 1e14, Z, 4 * Z) == pytest.approx(4 * 4 / 25, rel=1e-10)
    # transmission falls with frequency
    Ts = [wave_transmission(f, 3e4, Z) for f in (1e3, 1e4, 1e5, 1e6)]
    assert np.all(np.diff(Ts) < 0)


@settings(max_examples=200, deadline=None)
@given(logf=st.floats(0, 8), logD=st.floats(-3, 12), logZ1=st.floats(-4, 2), logZ2=st.floats(-4, 2))
def test_energy_conservation(logf, logD, logZ1, logZ2):
    f, Dn, Z1, Z2 = 10 ** logf, 10 ** logD, 10 ** logZ1, 10 ** logZ2
    T, R = wave_transmission(f, Dn, Z1, Z2), wave_reflection(f, Dn, Z1, Z2)
    assert 0.0 <= T <= 1.0 + 1e-15 and 0.0 <= R <= 1.0 + 1e-15   # equal impedances: T = 1 to round-off
    assert T + R == pytest.approx(1.0, rel=1e-13)


def _pulse_numerical(f, K, Z1, Z2):
    """Integrate d s_t/dt + lam s_t = (2K/Z1) s_i for the half-sine pulse numerically."""
    w, lam, c = 2 * math.pi * f, K * (1 / Z1 + 1 / Z2), 2 * K / Z1
    t_end = math.pi / w
    si = lambda t: math.sin(w * t) if t <= t_end else 0.0  # noqa: E731

    def rhs(t, y):
        st_, e_t, e_r, e_i = y
        dst = c * si(t) - lam * st_
        return [dst, st_ ** 2, (st_ - si(t)) ** 2, si(t) ** 2]

    t_stop = t_end + 40.0 / lam
    sol = solve_ivp(rhs, (0, t_end), [0, 0, 0, 0], method="DOP853", rtol=1e-12, atol=1e-14, dense_output=True)
    sol2 = solve_ivp(rhs, (t_end, t_stop), sol.y[:, -1], method="DOP853", rtol=1e-12, atol=1e-14)
    y = sol2.y[:, -1]
    tt = np.linspace(0, t_end, 4001)
    return {"transmitted_energy": y[1] / y[3] * Z1 / Z2, "reflected_energy": y[2] / y[3],
            "peak": sol.sol(tt)[0].max()}


@pytest.mark.parametrize("Z2_over_Z1", [1.0, 0.3, 5.0])
@pytest.mark.parametrize("Dn_over_pifZ", [0.05, 0.4, 1.0, 3.0, 30.0])
def test_pulse_transmission_against_ode_integration(Z2_over_Z1, Dn_over_pifZ):
    Z1, Z2 = Z, Z * Z2_over_Z1
    Dn = Dn_over_pifZ * math.pi * F * Z1
    out = pulse_transmission(F, Dn, Z1, Z2)
    num = _pulse_numerical(F, Dn, Z1, Z2)
    assert out["transmitted_energy"] == pytest.approx(num["transmitted_energy"], rel=1e-7)
    assert out["reflected_energy"] == pytest.approx(num["reflected_energy"], rel=1e-7)
    # energy balance of the pulse (the spring stores nothing at the end): independent of e_t
    assert out["transmitted_energy"] + out["reflected_energy"] == pytest.approx(1.0, rel=1e-9)
    assert out["peak_ratio_squared"] == pytest.approx(num["peak"] ** 2 * Z1 / Z2, rel=1e-6)
    assert out["harmonic_transmission"] == wave_transmission(F, Dn, Z1, Z2)


def test_pulse_ode_has_the_harmonic_transfer_function():
    # steady state of d s_t/dt + lam s_t = (2K/Z1) s_i for s_i = e^{iwt}: the harmonic stress ratio
    Z1, Z2, K = Z, 2.5 * Z, 4e4
    w = 2 * math.pi * F
    ode_ratio = (2 * K / Z1) / (1j * w + K * (1 / Z1 + 1 / Z2))
    _, C = wave_amplitude_ratios(F, K, Z1, Z2)
    assert ode_ratio == pytest.approx(Z2 * C / Z1, rel=1e-13)  # stress ratio s_t/s_i = Z2 C / (Z1 A)


def test_pulse_limits():
    assert pulse_transmission(F, math.inf, Z)["transmitted_energy"] == 1.0
    assert pulse_transmission(F, 0.0, Z)["transmitted_energy"] == 0.0
    # a long pulse (low f) sees an almost perfect interface, a short one a soft interface
    assert pulse_transmission(1.0, 1e3, Z)["transmitted_energy"] == pytest.approx(1.0, abs=1e-6)
    assert pulse_transmission(1e9, 1e3, Z)["transmitted_energy"] < 1e-3


@pytest.mark.parametrize("Z2_over_Z1", [1.0, 0.3])
def test_pulse_transmission_at_extreme_interface_stiffness_reaches_its_limits(Z2_over_Z1):
    """lambda/w from 1e-250 to 1e250 (the closed-form energies, no quadrature): no warning,
    energy conserved, and the limits of a soft interface (nothing through) and of a stiff
    one (the perfect interface's 4 Z1 Z2/(Z1 + Z2)^2, peak included)."""
    import warnings
    Z1, Z2 = Z, Z * Z2_over_Z1
    perfect = 4.0 * Z1 * Z2 / (Z1 + Z2) ** 2
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for Dn in (1e-240, 1e-30, 1e30, 1e260):
            out = pulse_transmission(F, Dn, Z1, Z2)
            assert out["transmitted_energy"] + out["reflected_energy"] == pytest.approx(1.0, rel=1e-12)
        soft, stiff = pulse_transmission(F, 1e-240, Z1, Z2), pulse_transmission(F, 1e260, Z1, Z2)
    assert soft["transmitted_energy"] < 1e-200 and soft["peak_ratio_squared"] < 1e-200
    assert stiff["transmitted_energy"] == pytest.approx(perfect, rel=1e-12)
    assert stiff["peak_ratio_squared"] == pytest.approx(perfect, rel=1e-9)


def test_bad_wave_inputs():
    with pytest.raises(CaseError, match="f must be > 0"):
        wave_transmission(0.0, 1.0, Z)
    with pytest.raises(CaseError, match="Dn must be >= 0"):
        wave_transmission(F, -1.0, Z)
    with pytest.raises(CaseError, match="Z2 must be > 0"):
        wave_transmission(F, 1.0, Z, -Z)
    with pytest.raises(CaseError, match="nu must be in"):
        dilatational_wave_speed(E, 0.5, RHO)
    with pytest.raises(CaseError, match="analysis"):
        dilatational_wave_speed(E, 0.3, RHO, "2d")
    with pytest.raises(CaseError, match="wave speed v or the modulus E"):
        wave_transmission_identical(F, 1.0, RHO)


@pytest.mark.parametrize("Dn", [5e3, 3e4, 2e5])
def test_pulse_histories_solve_the_interface_filter_and_carry_the_pulse_energies(Dn):
    """002 Fig 11 histories: s_t obeys d s_t/dt + lambda s_t = (2 K / Z1) s_i (central
    finite differences), s_r = s_t - s_i, and their energy ratios are pulse_transmission's."""
    from interfaces.analytic.waves import pulse_histories
    Z1, Z2 = 0.0887, 0.05
    t = np.linspace(0.0, 40.0 / F, 400001)
    h = pulse_histories(F, Dn, Z1, Z2, t)
    lam = Dn * (1.0 / Z1 + 1.0 / Z2)
    dsdt = np.gradient(h["transmitted"], t)
    resid = dsdt + lam * h["transmitted"] - 2.0 * Dn / Z1 * h["incident"]
    smooth = np.abs(t - 0.5 / F) > 3 * (t[1] - t[0])   # s_i has a kink at the pulse end
    assert np.abs(resid[smooth][2:-2]).max() < 1e-4 * 2.0 * Dn / Z1
    np.testing.assert_allclose(h["reflected"], h["transmitted"] - h["incident"])
    exact = pulse_transmission(F, Dn, Z1, Z2)
    e_i = np.trapezoid(h["incident"] ** 2, t)
    assert Z1 / Z2 * np.trapezoid(h["transmitted"] ** 2, t) / e_i == pytest.approx(
        exact["transmitted_energy"], rel=1e-5)
    assert np.trapezoid(h["reflected"] ** 2, t) / e_i == pytest.approx(exact["reflected_energy"], rel=1e-5)
