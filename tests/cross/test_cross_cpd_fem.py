"""CPD (nonlocal, overlap interface) against plane-strain FEM (local, sharp perfect
interface) on the bimaterial square of 003 Sec 4.1-4.2, through cases.compare.

CPD converges to the local solution only as the horizon delta -> 0 (003 Sec 4.2,
delta-convergence with delta/h fixed); at a finite horizon the nonlocal boundary layer
and the overlap band (which takes the stiffer material's behaviour) differ from FEM by
an amount proportional to delta. So the test asserts the rate, not a fixed agreement:
the L2 error of u_x along the horizontal line (crossing the interface) must fall at
least like delta (measured 0.093 -> 0.045 for delta = 0.15 -> 0.075) and be below 6 %
at delta = 0.075; the strain-energy difference must fall too.
"""
import numpy as np
import pytest

import cases
from cases.compare import compare


def _errors(h):
    case = cases.build("bimaterial_square", parameter_set=3, load_case=1, interface="vertical", h=h, fem_h=0.02)
    comp = compare(case, "cpd,fem", progress=False)
    assert comp.reference == "fem"
    cpd, fem = comp.results["cpd"].profiles["horizontal"], comp.results["fem"].profiles["horizontal"]
    u_fem = np.interp(cpd["s"], fem["s"], fem["ux"])
    return np.linalg.norm(cpd["ux"] - u_fem) / np.linalg.norm(u_fem), abs(comp.relative_difference("cpd", "strain_energy"))


@pytest.fixture(scope="module")
def errors():
    return {h: _errors(h) for h in (0.05, 0.025)}


def test_cpd_approaches_fem_as_horizon_shrinks(errors):
    (e_coarse, w_coarse), (e_fine, w_fine) = errors[0.05], errors[0.025]
    assert e_fine < 0.06
    assert e_fine < 0.6 * e_coarse          # at least first order in delta
    assert w_fine < w_coarse


def test_perfect_interface_limit_identical_materials_matches_fem():
    """Set 4 (identical materials): the overlap interface must be invisible far from the
    boundary layers, so CPD equals FEM on a homogeneous square up to the horizon effect."""
    case = cases.build("bimaterial_square", parameter_set=4, load_case=2, interface="vertical", h=0.025, fem_h=0.02)
    comp = compare(case, "cpd,fem", progress=False)
    cpd, fem = comp.results["cpd"].profiles["horizontal"], comp.results["fem"].profiles["horizontal"]
    u_fem = np.interp(cpd["s"], fem["s"], fem["ux"])
    assert np.linalg.norm(cpd["ux"] - u_fem) / np.linalg.norm(u_fem) < 0.02  # measured 0.013
