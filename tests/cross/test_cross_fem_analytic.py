"""FEM against the closed-form models, through the user's path (cases.compare).

Tolerances: the shear-lag (002 Eq 40-42) and beam-on-foundation (Eq 46-47) models are
1D approximations of the 2D plane-stress problem; 002 reports FEA agreeing with them
to within a few percent, so 3 % is the bar (a wrong interface element, a missing 1/2
in the energy or a wrong arm length changes the stiffness by far more).
"""
import math

import pytest

import cases
from cases.compare import compare
from cases.methods import run
from interfaces.analytic import dcb_kb_from_stiffness, dcb_stiffness


@pytest.mark.parametrize("Dt", [1.0, 5.0, 50.0, math.inf])
def test_dls_fem_matches_shear_lag(Dt):
    comp = compare(cases.build("dls", Dt=Dt, fem_h=0.2), "fem,analytic", progress=False)
    assert comp.reference == "analytic"
    assert abs(comp.relative_difference("fem", "stiffness")) < 0.03
    # displacement method (Eq 43) and energy method (Eq 45) agree: the interface energy is consistent
    q = comp.results["fem"].quantities
    assert q["stiffness_energy"] == pytest.approx(q["stiffness"], rel=1e-6)


@pytest.fixture(scope="module")
def dcb_kb():
    """kb back-computed from a perfect-interface FEM run, as 002 did (it found 7808 MPa)."""
    r = run(cases.build("dcb", Dn=math.inf, fem_h=0.15), "fem")
    return dcb_kb_from_stiffness(r.quantities["stiffness"], a=25.0, h=0.6, W=10.0, E_xx=10000.0)


def test_dcb_kb_close_to_paper(dcb_kb):
    assert dcb_kb == pytest.approx(7808.0, rel=0.05)


@pytest.mark.parametrize("Dn", [0.1, 1.0, 100.0, math.inf])
def test_dcb_fem_matches_beam_on_elastic_foundation(Dn, dcb_kb):
    comp = compare(cases.build("dcb", Dn=Dn, kb=dcb_kb, fem_h=0.15), "fem,analytic", progress=False)
    assert abs(comp.relative_difference("fem", "stiffness")) < 0.03


def test_dcb_soft_interface_is_bracketed_by_finite_bond_bounds(dcb_kb):
    """At Dn = 0.01 MPa/mm the foundation length Delta = 13.8 mm is not small against the
    25 mm bond, so Eq 46-47 (semi-infinite bond) is outside its assumptions. Its value
    must lie between the free-end (softer) and clamped-end (stiffer) finite specimens."""
    k_theory = dcb_stiffness(25.0, 0.6, 10.0, 10000.0, Dn=0.01, kb=dcb_kb)
    k_free = run(cases.build("dcb", Dn=0.01, fem_h=0.15), "fem").quantities["stiffness"]
    k_clamped = run(cases.build("dcb", Dn=0.01, fem_h=0.15, clamp_end=True), "fem").quantities["stiffness"]
    assert k_free < k_theory < k_clamped
