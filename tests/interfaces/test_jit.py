"""interfaces.jit: one compiled overload per non-literal signature for calls from
compiled code, and the literal types only where a function cannot be typed without."""
from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
from numba.core.registry import CPUDispatcher

from interfaces.jit import NonLiteralDispatcher, njit

ROOT = Path(__file__).resolve().parents[2]


@njit
def _callee(i, switch, pair):
    return i + (1 if switch else 0) + pair[0]


@njit
def _index(values, k):
    return values[k]


@njit
def _caller(x):
    # constants (literal types in numba's typing) and a variable, to the same callee
    return _callee(0, True, (x, 5)) + _callee(x, False, (1, 2)) + _callee(-1, True, (2, x))


@njit
def _caller_needing_literals(x):
    return _index((x, 2.5), 1) + _index((x, 2.5), 0)


def test_constants_from_compiled_code_share_one_overload():
    assert _caller(3) == (0 + 1 + 3) + (3 + 0 + 1) + (-1 + 1 + 2)
    assert [str(s) for s in _callee.signatures] == ["(int64, bool, UniTuple(int64, 2))"]


def test_a_function_that_needs_literal_arguments_still_compiles():
    """Indexing a heterogeneous tuple needs the index's value at compile time."""
    assert _caller_needing_literals(4) == 2.5 + 4
    assert all("Literal[int]" in str(s[1]) for s in _index.signatures)


def test_decorator_forms_and_options_are_numba_s():
    @njit(cache=False, fastmath=True)
    def f(a):
        return a.sum()

    assert isinstance(f, NonLiteralDispatcher) and isinstance(f, CPUDispatcher)
    assert f.targetoptions["fastmath"]
    assert f(np.ones(3)) == 3.0


def test_every_kernel_module_uses_the_project_njit():
    """A module importing numba's own njit would bring the literal copies back."""
    offenders = []
    for package in ("mpm", "peridynamics", "fem", "interfaces", "cases"):
        for path in (ROOT / package).rglob("*.py"):
            if path.name == "jit.py" and package == "interfaces":
                continue
            for node in ast.walk(ast.parse(path.read_text())):
                if isinstance(node, ast.ImportFrom) and node.module == "numba" and \
                        any(a.name in ("njit", "jit") for a in node.names):
                    offenders.append(str(path.relative_to(ROOT)))
                if isinstance(node, ast.Attribute) and node.attr in ("njit", "jit") and \
                        isinstance(node.value, ast.Name) and node.value.id == "numba":
                    offenders.append(str(path.relative_to(ROOT)))
    assert offenders == []
