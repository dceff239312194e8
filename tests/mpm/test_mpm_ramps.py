"""Every boundary condition follows its ramp (interfaces.case.RAMPS) in the MPM time loop.

References, independent of the MPM code: the prescribed history of
``BoundaryCondition.ramp_factor`` (u0 R(t), 002 Eq 49 for the cosine ramp) and its
integral by quadrature for velocities; for tractions, Newton's second law for a free
body (total momentum = impulse F0 int_0^t R).
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad

import mpm
from interfaces import Body, BoundaryCondition, Case, IsotropicElastic, Rectangle
from interfaces.errors import CaseError
from mpm import kernels as K
from mpm.boundary import history

RAMPS = ("linear", "cosine")
T_RAMP = 1.0e-5


def _bc(kind: str, ramp: str, value: float = 2.0e-3) -> BoundaryCondition:
    return BoundaryCondition(kind, "base", "xmin", ("x",), (value,), ramp_time=T_RAMP, ramp=ramp)


def _prescribed_displacement(bc: BoundaryCondition, t: float) -> float:
    """u(t) of a displacement condition, or int_0^t v of a velocity condition."""
    if bc.kind == "displacement":
        return bc.value[0] * float(bc.ramp_factor(t))
    return bc.value[0] * quad(lambda s: float(bc.ramp_factor(s)), 0.0, t, epsabs=0.0,
                              epsrel=1e-13, points=[min(t, T_RAMP)])[0]


@pytest.mark.parametrize("kind", ["displacement", "velocity"])
@pytest.mark.parametrize("ramp", RAMPS)
def test_step_velocities_integrate_to_the_prescribed_history(kind, ramp):
    """At every step end the boundary has moved exactly the prescribed distance, with a
    ramp time that is no multiple of dt (the last ramp step is partial)."""
    bc = _bc(kind, ramp)
    divisor, code, t_end, t_ramp = history(bc, 1.0, "boundary_conditions[0]")
    vel0 = np.array([bc.value[0] / divisor])
    dt = T_RAMP / 37.3
    vel, u, t = np.zeros(1), 0.0, 0.0
    for _ in range(60):
        K.step_velocities(t, dt, vel0, np.array([t_end]), np.array([code], np.int64),
                          np.array([t_ramp]), vel)
        u += vel[0] * dt
        t += dt
        assert u == pytest.approx(_prescribed_displacement(bc, t), rel=1e-11, abs=1e-18)


def _rigid_case(bc: BoundaryCondition) -> Case:
    steel = IsotropicElastic(E=200e3, nu=0.3, rho=8e-9)
    return Case(
        name="ramped_rigid", analysis="plane_strain",
        materials={"steel": steel},
        bodies=[Body("base", Rectangle(0.0, 0.0, 4.0, 2.0), "steel"),
                Body("block", Rectangle(0.0, 8.0, 4.0, 2.0), "steel")],
        boundary_conditions=[bc],
        discretization={"mpm": {"cell": 0.5, "ppc": 2, "rigid_bodies": ["base"],
                                "damping": "none", "progress": False}})


@pytest.mark.parametrize("kind", ["displacement", "velocity"])
@pytest.mark.parametrize("ramp", RAMPS)
@pytest.mark.parametrize("fraction", [0.43, 1.6])
def test_a_rigid_body_follows_the_ramped_history(kind, ramp, fraction):
    """A rigid body's particles move exactly with the prescribed history (two material
    fields), stopped mid-ramp and after it."""
    bc = _bc(kind, ramp)
    dt = T_RAMP / 125.1      # below the explicit limit cell / c = 8.6e-8 s of the steel block
    steps = int(round(fraction * T_RAMP / dt))
    r = mpm.solve(_rigid_case(bc), dt=dt, max_time=steps * dt)
    t = r.diagnostics["time"]
    base = np.asarray(r.fields["material"]) == 0
    ux = np.asarray(r.fields["displacement"])[base, 0]
    assert r.diagnostics["time_steps"] == steps
    assert ux == pytest.approx(np.full(ux.size, _prescribed_displacement(bc, t)), rel=1e-10)
    if kind == "velocity":
        # the particles carry the mean velocity of the last step, within O(dt) of v(t)
        vx = np.asarray(r.fields["velocity"])[base, 0]
        assert vx == pytest.approx(np.full(vx.size, bc.value[0] * float(bc.ramp_factor(t))),
                                   abs=2.0 * bc.value[0] * math.pi * dt / T_RAMP)


@pytest.mark.parametrize("ramp", RAMPS)
@pytest.mark.parametrize("fraction", [0.43, 1.6])
def test_a_ramped_traction_gives_its_impulse_to_a_free_block(ramp, fraction):
    """One material field: a free block pulled by a ramped traction holds the
    momentum F0 int_0^t R (internal forces cancel); the force of step k is the ramp at
    the step start, so the impulse falls short of the exact integral by at most F0 dt R(t)
    (mid-ramp, the linear and cosine impulses differ by 1.4 F0 dt here)."""
    rho, t0, height = 8e-6, 3.0, 2.0  # c = 5.8 mm/us: dt below the CFL limit
    bc = BoundaryCondition("traction", "block", "xmax", ("x",), (t0,), ramp_time=T_RAMP, ramp=ramp)
    case = Case(name="ramped_traction", analysis="plane_strain",
                materials={"steel": IsotropicElastic(E=200e3, nu=0.3, rho=rho)},
                bodies=[Body("block", Rectangle(0.0, 0.0, 4.0, height), "steel")],
                boundary_conditions=[bc],
                discretization={"mpm": {"cell": 0.5, "ppc": 2, "damping": "none",
                                        "progress": False}})
    dt = T_RAMP / 41.7
    steps = int(round(fraction * T_RAMP / dt))
    r = mpm.solve(case, dt=dt, max_time=steps * dt)
    t = r.diagnostics["time"]
    force = t0 * height * case.thickness
    impulse = force * quad(lambda s: float(bc.ramp_factor(s)), 0.0, t, points=[min(t, T_RAMP)])[0]
    vol = np.asarray(r.fields["volume"])
    momentum = float(np.sum(rho * vol * np.asarray(r.fields["velocity"])[:, 0]))
    # left Riemann sum of a rising ramp: short of the integral by at most F0 dt R(t)
    assert impulse - force * dt * float(bc.ramp_factor(t)) <= momentum <= impulse * (1.0 + 1e-9)


def test_an_unknown_ramp_is_a_one_line_error_naming_the_field():
    with pytest.raises(CaseError, match=r"^ramp must be one of linear, cosine, got 'smooth'$"):
        BoundaryCondition("displacement", "base", "xmin", ("x",), (1e-3,), ramp_time=1e-5,
                          ramp="smooth")
    text = _rigid_case(_bc("displacement", "cosine")).to_toml().replace('ramp = "cosine"',
                                                                        'ramp = "smooth"')
    with pytest.raises(CaseError, match=r"^boundary_conditions\[0\]\.ramp must be one of"):
        Case.from_toml(text)


def test_tractions_with_different_ramps_are_refused():
    trs = [BoundaryCondition("traction", "block", side, ("x",), (s,), ramp_time=T_RAMP, ramp=ramp)
           for side, s, ramp in (("xmax", 1.0, "linear"), ("xmin", -1.0, "cosine"))]
    case = Case(name="two_ramps", analysis="plane_strain",
                materials={"steel": IsotropicElastic(E=200e3, nu=0.3, rho=8e-9)},
                bodies=[Body("block", Rectangle(0.0, 0.0, 4.0, 2.0), "steel")],
                boundary_conditions=trs, discretization={"mpm": {"cell": 0.5}})
    with pytest.raises(CaseError, match="one load ramp"):
        mpm.solve(case, progress=False)
