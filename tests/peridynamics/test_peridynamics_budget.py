"""The memory estimate made before a CPD grid is allocated (peridynamics/budget.py)."""
import math

import pytest

import peridynamics
import peridynamics.budget as budget
from cases import library
from interfaces.errors import CaseError
from peridynamics.discretization import discretize


def _square():
    return library.bimaterial_square(parameter_set=1, load_case=1)


def test_pattern_neighbours_count_grid_points_in_the_ball():
    assert budget.pattern_neighbours(1.0, 2) == 5 and budget.pattern_neighbours(1.0, 3) == 7
    assert budget.pattern_neighbours(6.02, 2) == 113                 # 2 delta at delta/h = 3.01
    # Gauss circle / sphere: pi r^2, 4/3 pi r^3 to within the boundary layer of points
    assert budget.pattern_neighbours(40.0, 2) == pytest.approx(math.pi * 1600, rel=1e-2)
    assert budget.pattern_neighbours(12.0, 3) == pytest.approx(4 / 3 * math.pi * 12 ** 3, rel=2e-2)


def test_a_run_beyond_the_machine_is_refused_before_the_grid_is_built(monkeypatch):
    monkeypatch.setattr(budget, "available_memory", lambda: 1e9)     # 1 GB left
    with pytest.raises(CaseError, match=r"^cpd.h = 0.005 mm \(delta = 0.01505 mm\) gives 211 x 211 = 4.45e\+04 "
                                        r"grid points, needing about 1.29 GB, more than the 1 GB"):
        peridynamics.solve(_square(), h=0.005)
    with pytest.raises(CaseError, match="more DOFs than the sparse tangent can index"):
        peridynamics.solve(_square(), h=1e-7)                        # never allocated (1e14 points)


def test_a_large_run_is_announced_with_its_figure(monkeypatch):
    # measured peak of the solve at h = 0.005: 1.35 GB above the resident memory before it
    monkeypatch.setattr(budget, "available_memory", lambda: 2e9)     # warn above a quarter: 0.5 GB
    with pytest.warns(RuntimeWarning, match=r"needs about 0.676 GB of the 2 GB available"):
        discretize(_square(), 0.007, 3.01 * 0.007, 3.01 * 0.007)
    monkeypatch.setattr(budget, "available_memory", lambda: None)    # unknown: the fixed figure
    with pytest.warns(RuntimeWarning, match=r"needs about 2.56 GB$"):
        discretize(_square(), 0.0035, 3.01 * 0.0035, 3.01 * 0.0035)


def test_the_estimate_follows_the_measured_peaks():
    """Peak memory measured above the resident memory before the solve (one thread): the
    bimaterial square, parameter set 2 (Cholesky), and the cuboid (peridynamics/budget.py)."""
    measured = {(41607, 2, 3.01): 1.23e9, (19296, 2, 5.01): 2.76e9, (11009, 2, 4.01): 0.684e9,
                (43928, 3, 2.01): 3.77e9}
    for (n, dim, ratio), peak in measured.items():
        assert budget.estimate_bytes(n, dim, ratio) == pytest.approx(peak, rel=0.1)
