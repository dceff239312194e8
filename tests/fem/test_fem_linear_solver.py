"""fem.solve through interfaces.sparse: the chosen direct solver is reported, both back
ends give the same answer, and the negative-pivot check still guards definite systems."""
import pytest

import fem
from cases.library import dls
from interfaces.errors import CaseError
from interfaces.sparse import pardiso_available


def test_solver_choice_is_reported_and_back_ends_agree():
    case = dls(Dt=10.0)
    ref = fem.solve(case, h=0.3, solver="superlu", fields=False)
    assert ref.diagnostics["solver"] == "superlu"
    auto = fem.solve(case, h=0.3, fields=False)
    assert auto.diagnostics["solver"] == ("pardiso" if pardiso_available() else "superlu")
    assert auto.quantities["stiffness"] == pytest.approx(ref.quantities["stiffness"], rel=1e-11)
    assert auto.diagnostics["negative_pivots"] == 0
    assert auto.diagnostics["backward_error"] < 1e-12


@pytest.mark.skipif(pardiso_available(), reason="only where MKL cannot be loaded")
def test_pardiso_request_without_mkl_is_refused():
    with pytest.raises(CaseError, match="solver"):
        fem.solve(dls(Dt=10.0), h=0.3, solver="pardiso")
