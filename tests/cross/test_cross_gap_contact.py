"""004 Fig 2: when do two blocks closing a 7.5 mm gap touch, per contact method?

Reference: the gap over the push speed plus the push's transit through the upper block
(analytic model gap_closure). Measured (contact time / reference, 5 mm cells, 2 x 2
uGIMP particles per cell, AG normals for the grid-based methods):

| plane | velocity only | CP = 0.92 | CP = 0.80 | DF | LR |
|---|---|---|---|---|---|
| grid line | 0.334 | 0.806 | 0.948 | 0.9987 | 0.9987 |
| mid-cell | 0.0035 | 0.664 | 0.664 | 0.664 | 0.9987 |

as 004 reports: on a grid line velocity-only detection contacts early, CP = 0.92 early,
CP = 0.80 closer, DF and LR within 2 %; at mid-cell every grid-based method contacts
early and LR stays within 2 %. (0.9987: the sampling interval is 1/2000 of the time.)
"""
import pytest

import cases
from cases.compare import compare


def _ratio(contact, plane):
    comp = compare(cases.build("gap_contact", contact=contact, plane=plane), "analytic,mpm", progress=False)
    return 1.0 + comp.relative_difference("mpm", "contact_time")


def test_contact_plane_on_a_grid_line():
    r = {c: _ratio(c, "grid") for c in ("velocity", "CP0.92", "CP0.80", "DF", "LR")}
    assert r["velocity"] < r["CP0.92"] < r["CP0.80"] < 0.98      # all early, in 004's order
    assert r["velocity"] < 0.5 and r["CP0.92"] < 0.9
    for c in ("DF", "LR"):
        assert r[c] == pytest.approx(1.0, abs=0.02)


def test_contact_plane_mid_cell():
    assert _ratio("DF", "mid") < 0.8                  # grid-based detection early (0.664)
    assert _ratio("LR", "mid") == pytest.approx(1.0, abs=0.02)


def test_unknown_contact_method_is_refused():
    from interfaces import CaseError
    with pytest.raises(CaseError, match="contact must be one of velocity, CP0.92, CP0.80, DF, LR"):
        cases.build("gap_contact", contact="offset")
