"""Case description: TOML round trips and one-line errors naming the field."""
import math

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import cases
from interfaces import Case, CaseError


@pytest.mark.parametrize("name", cases.names())
def test_every_case_round_trips_through_toml(name):
    case = cases.build(name)
    text = case.to_toml()
    again = Case.from_toml(text)
    assert again.to_dict() == case.to_dict()
    assert again.to_toml() == text


def test_overrides_reach_case_and_analytic_model():
    case = cases.build("dls", Dt=5.0, Dn=math.inf)
    assert case.interfaces[0].law.Dt == 5.0
    assert case.analytic["Dt"] == 5.0
    assert math.isinf(Case.from_toml(case.to_toml()).interfaces[0].law.Dn)


def _dls_dict():
    return cases.build("dls").to_dict()


BAD_EDITS = [
    (lambda d: d["materials"]["wood"].__setitem__("E_A", -3.0), "materials.wood.E_A"),
    (lambda d: d["materials"]["wood"].__setitem__("nu_A", 5.0), "materials.wood.nu_A"),
    (lambda d: d["interfaces"][0].__setitem__("a", "nobody"), "interfaces[0].a"),
    (lambda d: d["interfaces"][1]["law"].__setitem__("Dt", "soft"), "interfaces[1].law.Dt"),
    (lambda d: d["bodies"][1]["shape"].__setitem__("width", 0.0), "bodies[1].shape.width"),
    (lambda d: d["bodies"][0].__setitem__("material", "steel"), "bodies[0].material"),
    (lambda d: d["bodies"][1]["shape"].__setitem__("x0", 1.7e308), "bodies[1].shape.x0"),
    (lambda d: d["boundary_conditions"][0].__setitem__("side", "top"), "boundary_conditions[0].side"),
    (lambda d: d["boundary_conditions"][1].__setitem__("body", "nobody"), "boundary_conditions[1].body"),
    (lambda d: d.__setitem__("analysis", "plane"), "analysis"),
    (lambda d: d.__setitem__("thickness", -1.0), "thickness"),
    (lambda d: d.__setitem__("colour", "red"), "colour"),
]


@pytest.mark.parametrize("edit,field", BAD_EDITS)
def test_bad_field_gives_one_line_error_naming_it(edit, field):
    d = _dls_dict()
    edit(d)
    with pytest.raises(CaseError) as err:
        Case.from_dict(d)
    msg = str(err.value)
    assert msg.startswith(field), msg
    assert "\n" not in msg


def test_isotropic_poisson_ratio_out_of_range():
    d = cases.build("two_layer").to_dict()
    d["materials"]["polymer"]["nu"] = 0.5
    with pytest.raises(CaseError, match=r"materials.polymer.nu must be in \(-1, 0.5\)"):
        Case.from_dict(d)


def test_malformed_toml_is_reported():
    with pytest.raises(CaseError, match="not valid TOML"):
        Case.from_toml("name = ")


_values = st.one_of(st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=5), st.integers(),
                    st.none(), st.lists(st.integers(), max_size=2), st.booleans())
_paths = st.sampled_from([
    ("materials", "wood", "E_A"), ("materials", "wood", "E_T"), ("materials", "wood", "G_A"),
    ("materials", "wood", "nu_A"), ("materials", "wood", "nu_T"), ("materials", "wood", "rho"),
    ("materials", "wood", "fiber"), ("interfaces", 0, "law", "Dn"), ("interfaces", 1, "law", "Dt"),
    ("bodies", 0, "shape", "x0"), ("bodies", 2, "shape", "height"), ("bodies", 1, "shape", "angle"),
    ("boundary_conditions", 1, "value"), ("boundary_conditions", 2, "ramp_time"), ("thickness",),
    ("boundary_conditions", 0, "components"), ("bodies", 0, "name"), ("interfaces", 0, "b"),
])


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(path=_paths, value=_values)
def test_random_bad_values_never_raise_raw_tracebacks(path, value):
    """Any value in any field either validates or raises a one-line CaseError naming that
    field (renaming a body may instead be reported where the old name is referenced)."""
    d = _dls_dict()
    node = d
    for k in path[:-1]:
        node = node[k]
    node[path[-1]] = value
    try:
        Case.from_dict(d)
    except CaseError as e:
        msg = str(e)
        assert "\n" not in msg
        dotted = ".".join(str(p) for p in path).replace(".0", "[0]").replace(".1", "[1]").replace(".2", "[2]")
        if path[0] == "materials" and path[-1] in ("E_A", "E_T", "nu_T"):
            # the positive-definiteness bound couples nu_A with E_A, E_T and nu_T
            assert msg.startswith((dotted, "materials.wood.nu_A must satisfy")), msg
        elif path[0] == "bodies" and path[2] == "shape" and " overlap (about " in msg:
            # a moved or resized body now shares area with a neighbour: named by both bodies
            assert msg.startswith("bodies '"), msg
        elif path[0] == "boundary_conditions" and path[-1] == "value" and "no boundary condition loads" in msg:
            assert msg.startswith("measurements.stiffness:"), msg
        elif path[-1] == "name":
            assert msg.startswith(("bodies[0].name", "interfaces[", "boundary_conditions[", "measurements.")), msg
        else:
            assert msg.startswith(dotted), (path, msg)


def test_case_file_via_cli(tmp_path, capsys):
    from cases.cli import main

    f = tmp_path / "c.toml"
    d = _dls_dict()
    d["materials"]["wood"]["E_T"] = -1
    import tomli_w

    f.write_text(tomli_w.dumps(Case.from_dict(_dls_dict()).to_dict()).replace("E_T = 1000.0", "E_T = -1.0"))
    assert main(["show", str(f)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: materials.wood.E_T must be > 0")
