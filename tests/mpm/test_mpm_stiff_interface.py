"""Stiff imperfect interfaces in explicit MPM (000 Eq 23-27, force limiting).

Reduced DLS (002 Sec 3.1 with l = 5, L = 2 mm, 0.2 mm cells): Dn = Dt = 1e12 MPa/mm
must run stably with force limiting and reproduce the perfect-interface (inf) run;
without limiting it must stop with advice, never return a silently wrong answer.
"""
from __future__ import annotations

import math

import pytest

import cases
import mpm
from interfaces.errors import SolverError


def _dls(D: float):
    return cases.build("dls", Dt=D, Dn=D, l=5.0, L=2.0, mpm_cell=0.2)


def test_stiff_interface_with_force_limiting_equals_the_perfect_interface():
    """Measured: k(1e12) / k(inf) - 1 = -1.0e-6 (displacement), -0.9e-6 (energy stiffness);
    every interface node is limited, i.e. stick with zero energy.  With the printed
    factors 2 of Eq 26 (midpoint rule) the same run diverged after 570 steps."""
    perfect = mpm.solve(_dls(math.inf), ramp_time=5e-5, progress=False)
    stiff = mpm.solve(_dls(1e12), ramp_time=5e-5, progress=False)
    assert stiff.diagnostics["stopped_by"] == "kinetic_energy"
    assert not stiff.diagnostics["warnings"]
    for key in ("stiffness", "stiffness_energy"):
        assert stiff.quantities[key] == pytest.approx(perfect.quantities[key], rel=5e-6)
    assert stiff.quantities["interface_energy"] == pytest.approx(0.0, abs=1e-12)
    # W = U + K + D: measured 3.9e-5 (perfect) and 4.1e-5 (stiff) (it was -3e9 when round-off
    # momenta on fields with ~1e-70 GIMP weights entered the damping dissipation)
    for r in (perfect, stiff):
        assert abs(r.quantities["energy_balance_error"]) < 2e-4


def test_stiff_interface_without_force_limiting_stops_with_advice():
    with pytest.raises(SolverError, match="enable force_limiting") as err:
        mpm.solve(_dls(1e12), ramp_time=5e-5, progress=False, force_limiting=False)
    assert "lower Dn/Dt" in str(err.value) and "dt" in str(err.value)


def _block(Dn: float):
    """4 x 4 mm block cut at mid-cell (y = 2.25) by an interface Dn = Dt, bottom held in
    y, 1 MPa tension on top."""
    from interfaces import (Body, BoundaryCondition, Case, InterfacePair, IsotropicElastic,
                            LinearInterface, Rectangle)
    return Case(
        name="block", analysis="plane_stress", thickness=1.0,
        materials={"m": IsotropicElastic(E=1000.0, nu=0.25, rho=2e-9)},
        bodies=[Body("lo", Rectangle(0, 0, 4.0, 2.25), "m"),
                Body("hi", Rectangle(0, 2.25, 4.0, 1.75), "m")],
        interfaces=[InterfacePair("lo", "hi", LinearInterface(Dn, Dn))],
        boundary_conditions=[BoundaryCondition("fixed", "lo", "ymin", ("y",), (0.0,)),
                             BoundaryCondition("traction", "hi", "ymax", ("x", "y"), (0.0, 1.0))],
        measurements={"stiffness": {"load": [["hi", "ymax"]], "support": [["lo", "ymin"]],
                                    "direction": "y"}})


def test_interface_above_the_eq26_bound_without_limiting_is_flagged():
    """Dn = Dt = 1e3 MPa/mm at 0.5 mm cells: nodes where one field holds only particle
    tails (tiny reduced mass) exceed the Eq 26 bound; without limiting the run is
    flagged in diagnostics['warnings'] (here it still settles, on the limited answer to
    2e-8); with limiting it is not flagged."""
    off = mpm.solve(_block(1e3), cell=0.5, progress=False, force_limiting=False)
    on = mpm.solve(_block(1e3), cell=0.5, progress=False)
    assert any("force_limiting is off" in w and "000 Eq 26" in w
               for w in off.diagnostics["warnings"])
    assert not on.diagnostics["warnings"]
    assert off.quantities["stiffness"] == pytest.approx(on.quantities["stiffness"], rel=1e-6)


def test_perfect_normal_direction_held_by_limiting_is_not_reported():
    """Dn = inf with a soft Dt (the DLS of 002): force limiting keeps the normal
    direction perfect on the interface nodes, which is the law itself; only a limited
    direction with a finite, non-negligible spring is worth a warning."""
    r = mpm.solve(cases.build("dls", Dt=5.0, l=5.0, L=2.0, mpm_cell=0.2), ramp_time=5e-5,
                  progress=False)
    assert not any("force limiting" in w for w in r.diagnostics["warnings"])


@pytest.mark.parametrize("damping,interfaces,named", [
    ("none", False, ["cfl"]), ("grid", False, ["cfl", "damping"]),
    ("none", True, ["cfl", "Dn/Dt"]), ("grid", True, ["cfl", "damping", "Dn/Dt"])])
def test_divergence_advice_names_only_the_remedies_the_run_has(damping, interfaces, named):
    """An undamped contact run (004 Fig 6) was told to increase its damping (alpha = 0)
    or lower an interface stiffness it does not have."""
    from types import SimpleNamespace

    from mpm.solver import _Runner
    tables = SimpleNamespace(has_interfaces=interfaces)
    model = SimpleNamespace(dt=1e-9, alpha=0.0, damped=damping != "none", tables=tables,
                            force_limiting=True)
    run = SimpleNamespace(m=model, t=1e-5, steps=7000, _advice=lambda: "")
    text = _Runner._diverged(run, "energies became NaN/inf")
    assert text.startswith("mpm diverged at t = 1e-05 s (step 7000): energies became NaN/inf. "
                           "Reduce the time step (cfl, now dt = 1e-09 s)")
    for remedy, word in (("cfl", "cfl"), ("damping", "increase damping"), ("Dn/Dt", "Dn/Dt")):
        assert (word in text) == (remedy in named)
