"""Property tests of the whole command line against bad input: every named case's TOML
mutated at a random field (bad value, deleted field, unknown field), and random --set and
--option assignments. Whatever the input, `imperfect run` either succeeds with finite
numbers in results.json or ends with one line `error: ...` and exit code 2 or 3; never a
raw traceback (any exception other than the documented errors fails the test).

The default run draws a few hundred examples with the analytic method (fast); `-m slow`
draws thousands and adds FEM on a coarse mesh.
"""
from __future__ import annotations

import json
import math
import os

import pytest
from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

import cases
from cases.cli import main

NAMES = cases.names()
#: examples per default property test (IMPERFECT_FUZZ_EXAMPLES=2000 for a long run)
EXAMPLES = int(os.environ.get("IMPERFECT_FUZZ_EXAMPLES", "120"))
BAD_VALUES = [math.nan, math.inf, -math.inf, -1.0, 0.0, 1e-300, 1e308, -1e308, 1.7e308, "", "x", "inf",
              [], [1.0], [1.0, 2.0, 3.0], {}, {"type": "nonsense"}, True, False, 10**30, -7, 0.5]
DELETE = object()
UNKNOWN = object()
FEM_CHEAP = {"dls": {"fem_h": 0.5}, "two_layer": {"fem_h": 1.0}, "dcb": {"fem_h": 0.3},
             "bimaterial_square": {"fem_h": 0.1}}


def _leaf_paths(node, prefix=()):
    """Every path to a value or a table inside a case dict (tables too: replaced whole)."""
    out = [prefix] if prefix else []
    if isinstance(node, dict):
        for k, v in node.items():
            out += _leaf_paths(v, prefix + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            out += _leaf_paths(v, prefix + (i,))
    return out


_DICTS = {n: cases.build(n).to_dict() for n in NAMES}
_PATHS = {n: _leaf_paths(d) for n, d in _DICTS.items()}


@st.composite
def mutated_case(draw):
    name = draw(st.sampled_from(NAMES))
    d = json.loads(json.dumps(_DICTS[name]))
    path = draw(st.sampled_from(_PATHS[name]))
    action = draw(st.sampled_from(["value"] * 6 + ["delete", "unknown"]))
    parent = d
    for k in path[:-1]:
        parent = parent[k]
    key = path[-1]
    if action == "delete":
        parent.pop(key)                  # list index or table key
    elif action == "unknown" and isinstance(parent, dict):
        parent["bogus_field"] = 1.0
    else:
        parent[key] = draw(st.sampled_from(BAD_VALUES))
    return name, d


def _toml_text(d) -> str | None:
    import tomli_w

    def encode(x):
        if isinstance(x, float) and math.isinf(x):
            return "inf" if x > 0 else "-inf"
        if isinstance(x, float) and math.isnan(x):
            return "nan"
        if isinstance(x, dict):
            return {k: encode(v) for k, v in x.items()}
        if isinstance(x, list):
            return [encode(v) for v in x]
        return x
    try:
        return tomli_w.dumps(encode(d))
    except (TypeError, ValueError):
        return None      # not representable in TOML (e.g. a list of mixed tables)


def _check_run(argv, tmp_path, capsys) -> None:
    out = tmp_path / "out"
    code = main(argv + ["--out", str(out), "--no-vtk"])
    event(f"exit {code}")
    captured = capsys.readouterr()
    assert "Traceback" not in captured.err
    if code == 0:
        data = json.loads((out / "results.json").read_text())
        for method, res in data["results"].items():
            for q, v in res["quantities"].items():
                if isinstance(v, float):
                    assert math.isfinite(v), (argv, method, q, v)
    else:
        assert code in (2, 3), (argv, code, captured.err)
        last = [x for x in captured.err.splitlines() if x.startswith("error:")]
        assert last, (argv, captured.err)
        assert all(len(x) < 600 for x in last)


def _methods_for(name: str, slow: bool) -> str:
    ms = ["analytic"] if _DICTS[name].get("analytic") else []
    if slow and name in FEM_CHEAP:
        ms.append("fem")
    return ",".join(ms)


def _run_mutated(name, d, tmp_path, capsys, slow: bool) -> None:
    text = _toml_text(d)
    if text is None:
        event("not representable in TOML")
        return
    f = tmp_path / "case.toml"
    f.write_text(text)
    methods = _methods_for(name, slow)
    if not methods:
        # no method cheap enough: the case must still validate or refuse in one line
        assert main(["show", str(f)]) in (0, 2)
        assert "Traceback" not in capsys.readouterr().err
        return
    _check_run(["run", str(f), "--methods", methods], tmp_path, capsys)


@settings(max_examples=EXAMPLES, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(case=mutated_case())
def test_mutated_case_files_never_crash(case, tmp_path, capsys):
    name, d = case
    if "discretization" in d and isinstance(d["discretization"], dict) and "fem" in d["discretization"]:
        d["discretization"].pop("fem", None)       # keep the default run on analytic + validation
    _run_mutated(name, d, tmp_path, capsys, slow=False)


@pytest.mark.slow
@settings(max_examples=2500, deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(case=mutated_case())
def test_mutated_case_files_never_crash_with_fem(case, tmp_path, capsys):
    name, d = case
    disc = d.get("discretization")
    fem = disc.get("fem") if isinstance(disc, dict) else None      # the mutation may replace the table
    if isinstance(fem, dict) and name in FEM_CHEAP:
        fem["element_size"] = FEM_CHEAP[name]["fem_h"]
    _run_mutated(name, d, tmp_path, capsys, slow=True)


_SET_VALUES = st.sampled_from(["nan", "inf", "-inf", "-1", "0", "1e308", "true", "x", "1,2", "", "000",
                               "0.5", "3"])


@settings(max_examples=max(EXAMPLES // 2, 1), deadline=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(name=st.sampled_from([n for n in NAMES if _DICTS[n].get("analytic")]), data=st.data())
def test_random_set_and_option_assignments(name, data, tmp_path, capsys):
    params = list(cases.registry.parameters(name)) + ["bogus"]
    key = data.draw(st.sampled_from(params))
    value = data.draw(_SET_VALUES)
    argv = ["run", name, "--methods", "analytic", "--set", f"{key}={value}"]
    if data.draw(st.booleans()):
        okey = data.draw(st.sampled_from(["profiles", "bogus", "Dt"]))
        argv += ["--option", f"analytic.{okey}={data.draw(_SET_VALUES)}"]
    _check_run(argv, tmp_path, capsys)


#: magnitudes that pass a field's range check and may still overflow a closed form
EXTREMES = [math.inf, -1.0, 0.0, 1e-300, 1e-30, 1e-6, 0.5, 1e6, 1e30, 1e308, -1e308, 1.7e308]


def _numeric_paths(d: dict) -> list[tuple]:
    out = []
    for path in _leaf_paths(d):
        v = d
        for k in path:
            v = v[k]
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            out.append(path)
    return out


@pytest.mark.parametrize("name", [n for n in NAMES if _DICTS[n].get("analytic")])
def test_every_numeric_field_at_extreme_magnitudes_answers_or_refuses(name):
    """Every number of the case set in turn to each of EXTREMES (not drawn at random: all of
    them): the analytic method returns finite quantities or refuses with a CaseError, and
    raises no numpy or scipy warning on the way (an overflow or an unconverged quadrature
    is an answer nobody should trust; the random draws above once met the first)."""
    import warnings

    from cases.methods import run
    from interfaces.case import Case
    from interfaces.errors import CaseError

    answered = 0
    for path in _numeric_paths(_DICTS[name]):
        for value in EXTREMES:
            d = json.loads(json.dumps(_DICTS[name]))
            parent = d
            for k in path[:-1]:
                parent = parent[k]
            parent[path[-1]] = value
            with warnings.catch_warnings():
                warnings.simplefilter("error")
                try:
                    res = run(Case.from_dict(d), "analytic")
                except CaseError:
                    continue
            answered += 1
            bad = {q: v for q, v in res.quantities.items() if isinstance(v, float) and not math.isfinite(v)}
            assert not bad, (path, value, bad)
    assert answered > 0
