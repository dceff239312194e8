"""Edge distances d(x) of 004 Fig 1B (the DF separation of 004 Eq 15-17; its use in the
contact kernel is tested in test_mpm_multimaterial.py)."""
from __future__ import annotations

import numpy as np
import pytest

from mpm.contact_separation import critical_separation, edge_distance_curve


@pytest.mark.parametrize("shape,paper", [("ugimp", 0.92), ("cpdi", 0.96)])
def test_linear_fit_gives_the_papers_critical_offset(shape, paper):
    """004 Fig 1B: the straight-line fits to d(x) give delta_c = 0.92 (GIMP) and 0.96
    (CPDI) at two particles per cell; our exact curves fitted over their whole range
    give 0.911 and 0.957 (the paper does not give its fit range)."""
    assert critical_separation(shape, 2) == pytest.approx(paper, abs=0.012)


def test_touching_point_and_ends_of_the_ugimp_curve():
    """Edge on the node (d = 0): particles at -1/4 and -3/4 cells with uGIMP weights 3/4
    and 1/4 put the extrapolated centre at -3/8. The curve runs from d = -1 (the first
    particle reaches the node's support; its centre is then 5/4 cells away) to full
    cover (s -> 0, d = 1)."""
    s, d = edge_distance_curve("ugimp", 2)
    assert np.interp(0.0, d, s) == pytest.approx(-0.375, abs=1e-6)
    assert d[0] == pytest.approx(-1.0, abs=1e-3) and s[0] == pytest.approx(-1.25, abs=1e-3)
    assert s[-1] == pytest.approx(0.0, abs=1e-9) and d[-1] == pytest.approx(1.0, abs=1e-3)
    assert np.all(np.diff(d) > 0)


def test_b2_points_are_ugimp_particles_of_a_full_cell():
    """The quadratic B-spline is the hat function convolved with a one-cell box: B2 at
    one particle per cell and uGIMP with l_p = h / 2 give the same curve."""
    s1, d1 = edge_distance_curve("b2", 1)
    s2, d2 = edge_distance_curve("ugimp", 1)
    np.testing.assert_allclose(np.interp(d1[5:-5], d2, s2), s1[5:-5], atol=2e-6)
