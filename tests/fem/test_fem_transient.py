"""Transient FEM with imperfect interface elements (fem/transient.py) on the 002 Sec 3.3 wave.

References: the exact transmission of the Eq 49 half-sine pulse through a spring
interface in uniaxial strain (interfaces.analytic.pulse_transmission, Z = rho c_p);
the exact energy of that pulse, A Z v0^2 T / 2 with v0 = pi f |x0| (the energy flux
sigma^2 / Z of a plane wave, sigma = Z v); energy conservation of Newmark average
acceleration for a linear system; the 1D lumped-mass stability limit h / c_p.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

import fem
from cases.registry import build
from interfaces import BoundaryCondition
from interfaces.analytic import solve as analytic_solve
from interfaces.analytic.waves import dilatational_wave_speed
from interfaces.errors import CaseError

#: 002 Fig 10 range: T (peak measure of 002) = 0.05 ... 0.95
DN_VALUES = (3800.0, 7000.0, 12000.0, 20000.0, 30000.0, 50000.0, 121000.0)
F, X0, HEIGHT = 100.0e3, 1.0e-4, 2.0
RHO = 15.0e-9
C_P = dilatational_wave_speed(410.0e3, 0.28, RHO, "plane_strain")


def _wave(Dn, h=1.0, **kw):
    return build("wave", Dn=Dn, fem_h=h, height=HEIGHT, **kw)


def _energy(r):
    h = r.diagnostics["history"]
    t = np.asarray(h["time"])
    return t, np.asarray(h["kinetic"]) + np.asarray(h["strain"]) + np.asarray(h["interface"])


def test_fem_transmitted_energy_matches_the_exact_pulse_solution():
    """Newmark average acceleration, consistent mass, Q1 at h = 1 mm (30 elements per
    pulse), T = 0.05 ... 0.95: measured within 0.0032 of the exact value on the 002
    measure (peak ratio squared) and within 0.0012 on the pulse energy ratio."""
    for Dn in DN_VALUES:
        case = _wave(Dn)
        r, a = fem.solve(case), analytic_solve(case)
        assert r.quantities["transmitted_energy"] == pytest.approx(
            a.quantities["transmitted_energy"], abs=0.006), Dn
        assert r.quantities["pulse_transmitted_energy"] == pytest.approx(
            a.quantities["pulse_transmitted_energy"], abs=0.003), Dn


@pytest.mark.slow
@pytest.mark.parametrize("scheme", ["newmark", "central"])
def test_fem_transmitted_energy_at_half_millimetre(scheme):
    """h = 0.5 mm, largest error over the Dn values (peak measure / pulse energy):
    Newmark with consistent mass 0.0008 / 0.0003, central differences with lumped mass
    at 0.9 of the stable step 0.0018 / 0.0004 (h = 1: 0.0032 / 0.0012 and 0.0057 /
    0.0018; h = 0.25: 0.0001 / 0.0001 and 0.0007 / 0.0001)."""
    for Dn in DN_VALUES:
        case = _wave(Dn, h=0.5)
        r, a = fem.solve(case, dynamics=scheme), analytic_solve(case)
        assert r.quantities["transmitted_energy"] == pytest.approx(
            a.quantities["transmitted_energy"], abs=0.004), Dn
        assert r.quantities["pulse_transmitted_energy"] == pytest.approx(
            a.quantities["pulse_transmitted_energy"], abs=0.001), Dn


@pytest.mark.parametrize("Dn", [math.inf, 3.0e4])
def test_newmark_conserves_the_energy_of_the_pulse(Dn):
    """Once the Eq 49 pulse is launched (t > 1/(2f)) the left edge stands still and no
    load works: the total energy is constant to round-off (Newmark average acceleration
    is exactly conservative), without an interface (free pulse) and with the spring; it
    equals the exact pulse energy A Z v0^2 T / 2 to the mesh's dispersion error."""
    r = fem.solve(_wave(Dn))
    t, E = _energy(r)
    after = E[t > 0.5 / F]
    assert (after.max() - after.min()) / after.max() < 1e-6
    v0 = math.pi * F * X0
    exact = HEIGHT * 1.0 * RHO * C_P * v0 ** 2 * (0.5 / F) / 2.0
    assert after[-1] == pytest.approx(exact, rel=2e-3)
    assert r.quantities["incident_pulse_energy"] == pytest.approx(exact, rel=5e-3)
    assert abs(r.quantities["energy_balance_error"]) < 1e-4


def test_central_differences_refuse_a_step_above_the_stable_limit():
    """The limit is 2 / omega_max of the lumped-mass mesh: h / c_p for Q1 in 1D."""
    case = _wave(3.0e4)
    with pytest.raises(CaseError, match=r"exceeds the stable central-difference limit "
                                        r"2/omega_max = (\S+) s") as err:
        fem.solve(case, dynamics="central", dt=1.0 / C_P * 1.2)
    limit = float(str(err.value).split("2/omega_max = ")[1].split(" s")[0])
    assert limit == pytest.approx(1.0 / C_P, rel=2e-3)
    r = fem.solve(case, dynamics="central")
    assert r.diagnostics["dt"] <= r.diagnostics["dt_stable_limit"]
    assert r.quantities["transmitted_energy"] == pytest.approx(
        analytic_solve(case).quantities["transmitted_energy"], abs=0.005)


def test_a_linear_displacement_ramp_launches_the_step_pulse_of_its_velocity():
    """A prescribed displacement x0 t / T (linear ramp) drives the edge at x0 / T for T:
    the strip then holds the work Z (x0/T)^2 T A (velocity jumps at 0 and T enter as
    impulses on the free unknowns); lumped mass, Newmark."""
    case = _wave(math.inf)
    bc = case.boundary_conditions[0]
    case.boundary_conditions[0] = BoundaryCondition(bc.kind, bc.body, bc.side, bc.components,
                                                    bc.value, ramp_time=bc.ramp_time, ramp="linear")
    r = fem.solve(case, mass="lumped")
    t, E = _energy(r)
    V = X0 / bc.ramp_time
    exact = RHO * C_P * V ** 2 * bc.ramp_time * HEIGHT
    assert E[-1] == pytest.approx(exact, rel=0.02)
    assert r.quantities["incident_peak_stress"] > 0.0  # x0 < 0 pulls the edge: a tensile pulse


@pytest.mark.parametrize("amplitude", [-X0, X0])
def test_the_nl_interface_of_002_fig10_is_linear_in_tension_and_perfect_in_compression(amplitude):
    """002 Fig 10 "NL" (bilinear, perfect in compression): a tensile pulse opens the
    interface and transmits as through the linear spring, a compressive one keeps it
    closed and crosses it whole (T = 1); central differences, 1 mm Q1. Measured:
    tensile 0.2607 / pulse energy 0.4036 (exact 0.2607 / 0.4020), compressive 1.005 /
    0.9999."""
    case = _wave(12000.0, nonlinear=True, amplitude=amplitude)
    r, a = fem.solve(case), analytic_solve(case)
    assert r.diagnostics["dynamics"] == "central"
    linear = analytic_solve(_wave(12000.0, amplitude=amplitude)).quantities
    expected = linear if amplitude < 0 else {"transmitted_energy": 1.0, "pulse_transmitted_energy": 1.0}
    for key in ("transmitted_energy", "pulse_transmitted_energy"):
        assert a.quantities[key] == pytest.approx(expected[key], abs=1e-12)
        assert r.quantities[key] == pytest.approx(expected[key], abs=0.01), key


def test_transient_refusals_are_one_line_errors():
    with pytest.raises(CaseError, match="perfect in compression"):
        fem.solve(_wave(3.0e4, nonlinear=True), dynamics="newmark")
    with pytest.raises(CaseError, match="mass = 'lumped'"):
        fem.solve(_wave(3.0e4), dynamics="central", mass="consistent")
    with pytest.raises(CaseError, match="fem option dynamics must be"):
        fem.solve(_wave(3.0e4), dynamics="leapfrog")
    case = _wave(3.0e4)
    bc = case.boundary_conditions[0]
    case.boundary_conditions[0] = BoundaryCondition("velocity", bc.body, bc.side, ("x",), (1.0,))
    with pytest.raises(CaseError, match=r"boundary_conditions\[0\]\.kind: transient fem"):
        fem.solve(case)
