"""Bad case input reported in the tracker: each is a one-line CaseError naming the field,
never a traceback from deep inside numpy, nor an exit-0 run with nonsense."""
import math
import re

import pytest

import cases
from cases.compare import compare
from interfaces import Case, CaseError


def _dls_dict():
    return cases.build("dls").to_dict()


def _edit(d, path, value):
    cur = d
    for k in path[:-1]:
        cur = cur[k]
    if value is _DELETE:
        del cur[path[-1]]
    else:
        cur[path[-1]] = value
    return d


_DELETE = object()

BAD = [
    (("boundary_conditions", 0, "components"), ["z"], r"boundary_conditions\[0\]\.components has z in a 2D case"),
    (("materials", "wood", "type"), [], r"materials\.wood\.type must be one of"),
    (("analytic", "E2"), 1.7e308, r"analytic\.E2 must be in \(0, 1e\+30\]"),
    (("interfaces", 0, "bogus"), 1, r"interfaces\[0\]\.bogus is not a field of an interface"),
    (("measurements", "stiffness", "bogus"), 3, r"measurements\.stiffness\.bogus is not a field of stiffness"),
    (("measurements", "bogus"), {}, r"measurements\.bogus is not a measurement"),
    (("boundary_conditions",), [], r"measurements\.stiffness: no boundary condition loads the specimen"),
    (("bodies", 2, "shape", "x0"), 1.0, r"bodies 'center' and 'outer_right' overlap \(about 5 mm\^2"),
    (("materials", "wood", "E_A"), 1.7e308, r"materials\.wood\.E_A must be <= 1e\+30"),     # FEM property suite
    (("discretization", "fem"), math.inf, r"discretization\.fem must be a table of fem options"),  # FEM property suite
    (("lines", "axis", 0, 0), math.nan, r"lines\.axis\[0\]\[0\] must be a number, got NaN"),   # FEM property suite
]


@pytest.mark.parametrize("path,value,message", BAD, ids=[m.split("\\")[0][:30] for *_, m in BAD])
def test_bad_case_field_is_one_line_error(path, value, message):
    d = _edit(_dls_dict(), path, value)
    with pytest.raises(CaseError) as e:
        case = Case.from_dict(d)
        compare(case, "analytic", progress=False, skip_unavailable=False)
    assert re.search(message, str(e.value)), str(e.value)
    assert "\n" not in str(e.value)


def test_interface_measurement_number_checked():
    d = cases.build("two_layer").to_dict()
    d["measurements"]["interface_energy"]["per_volume"] = math.nan
    with pytest.raises(CaseError, match=r"measurements\.interface_energy\.per_volume must be a number, got NaN"):
        Case.from_dict(d)


def test_stale_analytic_table_is_refused():
    """An edited interface with the old Dt left in [analytic] would compare FEM with a
    model of another specimen (-79 % in the tracker's report)."""
    d = _dls_dict()
    d["interfaces"][0]["law"]["Dt"] = 2.0
    d["interfaces"][1]["law"]["Dt"] = 2.0
    case = Case.from_dict(d)
    with pytest.raises(CaseError, match=r"analytic\.Dt = inf but interfaces\[0\]\.law has Dt = 2"):
        compare(case, "analytic", progress=False, skip_unavailable=False)
    d["analytic"]["Dt"] = 2.0
    comp = compare(Case.from_dict(d), "analytic", progress=False, skip_unavailable=False)
    assert comp.value("analytic", "stiffness") == pytest.approx(750.1, abs=0.05)   # 002 Fig 5 at Dt = 2


def test_touching_bodies_are_not_overlaps():
    for name in cases.names():
        cases.build(name)          # every named case: bodies abut (or fill holes), none overlap


@pytest.mark.parametrize("option,value,message", [
    ("element_size", True, "element_size"), ("order", True, "order must be 1 or 2")])
def test_fem_boolean_options_refused(option, value, message):
    import fem
    with pytest.raises(CaseError, match=message):
        fem.solve(cases.build("two_layer", fem_h=1.0), **{option: value})


@pytest.mark.parametrize("option,value,message", [
    ("intorder", "x", r"fem option intorder must be an integer in \[1, 19\], got 'x'"),
    ("intorder", 0, r"intorder must be an integer in \[1, 19\], got 0"),
    ("line_points", 2.5, r"line_points must be an integer >= 2, got 2\.5"),
    ("max_contact_iterations", "z", "max_contact_iterations must be an integer >= 1"),
    ("max_dofs", "a", "max_dofs must be a number"),
    ("pin_rigid_modes", "false", "pin_rigid_modes must be true or false, got 'false'"),
    ("fields", 0, "fields must be true or false, got 0")])
def test_fem_numeric_and_flag_options_are_checked_not_coerced(option, value, message):
    """A string or a fraction is refused with the option's name and range: int("x")
    leaked a bare ValueError, int(2.5) truncated silently and bool("false") was True."""
    import fem
    with pytest.raises(CaseError, match=message):
        fem.solve(cases.build("two_layer", fem_h=1.0), **{option: value})


@pytest.mark.parametrize("option", ["area_correction", "force_limiting", "lump_conserve",
                                    "xpic_correction"])
def test_mpm_flag_options_refuse_a_string(option):
    """bool("false") is True: a flag given as text switched the method on silently."""
    from mpm.multimaterial import build_pair_tables
    from mpm.options import merge
    case = cases.build("two_layer", mpm_cell=1.0)
    with pytest.raises(CaseError, match=f"mpm option {option} must be true or false, got 'false'"):
        build_pair_tables(case, merge(case, {option: "false"}))


@pytest.mark.parametrize("option,value,message", [
    ("cell", "abc", r"mpm option cell must be one number or 2 finite numbers, got 'abc'"),
    ("cell", True, "mpm option cell must be one number or 2"),
    ("grid_anchor", True, "mpm option grid_anchor must be 'bounds', 'origin' or a point"),
    ("padding", 2.5, r"mpm option padding must be an integer in \[2, 100\], got 2\.5"),
    ("vtk_frames", 2.5, "mpm option vtk_frames must be an integer"),
    ("xpic", math.nan, "mpm option xpic must be an integer order"),
    ("progress", "abc", "mpm option progress .* must be true or false"),
    ("vtk_dir", 3, "mpm option vtk_dir must be a folder path"),
    ("ppc", "abc", r"mpm option ppc must be an integer in \[1, 8\]"),
    ("ppc", True, r"mpm option ppc must be an integer in \[1, 8\]"),
    ("rigid_bodies", "floor", "mpm option rigid_bodies must be a list of body names"),
    ("edge_cutoff", True, "mpm option edge_cutoff must be a number, got True"),
    ("normal_vector", "abc", "mpm option normal_vector must be 2 finite numbers")])
def test_mpm_options_name_the_field_instead_of_leaking_numpy_errors(option, value, message):
    """Each of these passed through float(), np.asarray or iteration: a bare ValueError
    or TypeError from numpy, or a silent 1.0 for True, or 2 for 2.5."""
    from mpm.multimaterial import build_pair_tables
    from mpm.options import merge
    from mpm.particles import parse_ppc
    case = cases.build("two_layer", mpm_cell=1.0)
    with pytest.raises(CaseError, match=message):
        opts = merge(case, {option: value})
        build_pair_tables(case, opts)
        parse_ppc(opts["ppc"], 2)


def test_cpd_line_search_refuses_a_string():
    from peridynamics.solver import _options
    with pytest.raises(CaseError, match="cpd.line_search must be true or false, got 'no'"):
        _options(cases.build("bimaterial_square"), {"line_search": "no"})


def test_a_tiny_ellipse_answers_without_overflow_warnings():
    """A semi-axis of 1e-200 mm passes the range check (positive, at most 1e30); points
    far from it are outside and off its curve, without numpy overflow warnings (the
    fuzzed case files met this)."""
    import warnings

    import numpy as np

    from interfaces.geometry import Ellipse

    tiny = Ellipse(0.0, 0.0, 1e-200, 1.0)
    points = np.array([[1e10, 0.0], [0.0, 0.5], [1e-201, 0.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert tiny.contains(points).tolist() == [False, True, True]
        assert tiny.edge_mask(points, "boundary", 1e-9).tolist() == [False, False, True]


def test_an_overflowing_closed_form_profile_is_refused_not_returned_as_inf():
    """DCB profiles with W = 1e-300 mm and Dn = 1e30 MPa/mm pass the range checks; the
    traction k1 v / W overflows (numpy gave inf with a RuntimeWarning). With h = 1e6 mm
    and Dn = 1e-300, 0 * inf gave NaN. Both now end in the one-line CaseError."""
    import warnings

    import numpy as np

    from interfaces.analytic.registry import PROFILES

    base = dict(a=20.0, h=5.0, W=2.0, E_xx=1e4, Dn=100.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        for extreme in (dict(W=1e-300, Dn=1e30), dict(h=1e6, Dn=1e-300)):
            with pytest.raises(CaseError, match="closed form overflows or is undefined"):
                PROFILES["dcb_beam_foundation"](**{**base, **extreme})
        assert np.isfinite(PROFILES["dcb_beam_foundation"](**base)["interface_jump"]["traction_n"]).all()
