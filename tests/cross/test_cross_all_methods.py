"""Cross-method consistency through the user's path, ``cases.compare(case, "all")``.

The perfect-interface limit (Dt = Dn = inf) is where every method must agree with the
others and with the theory: there MPM's interface forces are replaced by the shared
velocity of a perfect pair and FEM eliminates the jump exactly, so a disagreement
points at the bulk discretisation or the load/measurement, not the interface law.
Short DLS (l = 5, L = 2 mm, t = 0.6 mm) at 0.2 mm MPM cells (3 per strand) keeps the
default suite fast; tolerances: FEM vs shear lag 1 % (shear lag with the strips' own
shear, a 1D model; measured 0.02-0.03 % here), MPM vs FEM 1.5 % (measured 0.9 %, the MPM excess
from uGIMP smoothing over 3 cells per strand). The full 002 specimen runs in the
slow suite with 1 %.
"""
import math

import pytest

import cases
from cases.compare import compare


def _check(comp, mpm_tol):
    q = {m: r.quantities["stiffness"] for m, r in comp.results.items()}
    assert set(q) == {"analytic", "fem", "mpm"}
    assert abs(comp.relative_difference("fem", "stiffness")) < 0.01
    assert q["mpm"] == pytest.approx(q["fem"], rel=mpm_tol)
    # the methods name the load side's mean displacement alike, so comparison.csv pairs it
    assert abs(comp.relative_difference("mpm", "load_displacement")) < mpm_tol
    # displacement (Eq 43) and energy (Eq 45) stiffness agree within each numerical method
    for m in ("fem", "mpm"):
        r = comp.results[m].quantities
        assert r["stiffness_energy"] == pytest.approx(r["stiffness"], rel=mpm_tol if m == "mpm" else 1e-6)


def test_perfect_interface_limit_all_methods_agree_short_dls():
    case = cases.build("dls", Dt=math.inf, l=5.0, L=2.0, mpm_cell=0.2, fem_h=0.1)
    comp = compare(case, "all", progress=False)
    _check(comp, 0.015)


def test_imperfect_interface_all_methods_agree_short_dls():
    case = cases.build("dls", Dt=5.0, l=5.0, L=2.0, mpm_cell=0.2, fem_h=0.1)
    comp = compare(case, "all", progress=False)
    _check(comp, 0.015)


@pytest.mark.slow
@pytest.mark.parametrize("Dt", [2.0, 5.0, 50.0, math.inf])
def test_full_002_dls_all_methods_agree(Dt):
    comp = compare(cases.build("dls", Dt=Dt, mpm_cell=0.1), "all", progress=False)
    _check(comp, 0.01)


def test_two_layer_mpm_vs_fem_energies():
    """000 Fig 4A two-layer shear (reduced: 8 mm tall, 0.5 mm cells, Dt = 5, Dn = inf)
    through the comparison layer. Measured: strain energy -0.05 %, interfacial energy
    +0.2 % (Dt = 5); the 2 % bound catches a lost area correction (Eq 20: a factor 2),
    a missing 1/2 in the energy (Eq 18, ERRATA 10); reading the jumps at the fields'
    centroids instead of the node costs +1.4 % here and +13 % at Dt = 100 (checked in
    tests/mpm/test_mpm_validation_interfaces.py).
    """
    comp = compare(cases.build("two_layer", Dt=5.0, height=8.0, mpm_cell=0.5), "fem,mpm", progress=False)
    assert comp.reference == "fem"
    assert abs(comp.relative_difference("mpm", "strain_energy")) < 0.005
    assert abs(comp.relative_difference("mpm", "interface_energy")) < 0.02


@pytest.mark.slow
def test_mpm_dcb_converges_to_fem():
    """002 Fig 9's MPM points (perfect bond; 002 used 0.1 mm cells and found MPM "slightly
    lower" than FEA) against FEM at 0.05 mm elements (0.15384 N/mm; 0.15391 at 0.1 mm).
    Measured: MPM -5.8 % at 0.3 mm cells (each 0.6 mm arm two cells deep), -1.19 % at
    0.15 mm; the energy stiffness P^2 / 2U within 0.45 % / 0.21 % of P / opening. Both runs
    stop by kinetic energy, after 6.0 / 5.1 ms of model time (the arms' bending period is
    1.56 ms); 3.5 and 22 minutes on a shared core. At 002's 0.1 mm cells (76 minutes, not
    run here): -0.19 %."""
    import fem
    import mpm
    k_fem = fem.solve(cases.build("dcb"), h=0.05, fields=False).quantities["stiffness"]
    errors = []
    for cell in (0.3, 0.15):
        r = mpm.solve(cases.build("dcb", mpm_cell=cell), progress=False)
        q = r.quantities
        assert r.diagnostics["stopped_by"] == "kinetic_energy"
        assert q["stiffness_energy"] == pytest.approx(q["stiffness"], rel=0.01)
        errors.append(q["stiffness"] / k_fem - 1.0)
    assert -0.02 < errors[1] < 0.0
    assert abs(errors[1]) < abs(errors[0]) / 3.0
