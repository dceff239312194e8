"""interfaces.jit: one compiled overload per non-literal signature for calls from
compiled code, the literal types only where a function cannot be typed without, and
kernels compiled without reference counting (``refcount=False``)."""
from __future__ import annotations

import ast
from pathlib import Path

import numpy as np
import pytest
from numba.core.errors import TypingError
from numba.core.registry import CPUDispatcher

from interfaces.jit import FMA, HAS_NRT_OPTION, NonLiteralDispatcher, njit

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
    @njit(cache=False, fastmath=FMA)
    def f(a):
        return a.sum()

    assert isinstance(f, NonLiteralDispatcher) and isinstance(f, CPUDispatcher)
    assert f.targetoptions["fastmath"] == {"contract"}
    assert f(np.ones(3)) == 3.0


@pytest.mark.parametrize("fastmath", [True, {"contract", "reassoc"}, {"fast"}])
def test_fast_math_beyond_fused_multiply_add_is_refused(fastmath):
    """Reassociation made a freshly compiled kernel and its cached copy differ."""
    with pytest.raises(ValueError, match="fastmath=FMA"):
        njit(cache=False, fastmath=fastmath)


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


def _views(a, w):
    s = 0.0
    for i in range(a.shape[0]):
        row = a[i]                       # a view: counted by numba unless refcount=False
        if row[0] > 0.0:
            w[0] = row[1]
        s += w[0]
    return s


@pytest.mark.skipif(not HAS_NRT_OPTION, reason="this numba has no _nrt option")
def test_refcount_false_compiles_views_without_reference_counting():
    """interfaces.jit ``refcount=False``: the same results, and no NRT_incref / NRT_decref
    left in the machine code of a function that takes views in a loop (numba's default
    keeps some there: the atomic operations behind 2/3 of a multimaterial time step)."""
    counted, borrowed = njit(_views), njit(refcount=False)(_views)
    a = np.arange(12.0).reshape(6, 2) - 3.0          # rows (-3, -2) ... (7, 8)
    assert borrowed(a, np.zeros(1)) == counted(a, np.zeros(1)) == 2.0 + 4.0 + 6.0 + 8.0
    ir_counted = "".join(counted.inspect_llvm().values())
    ir_borrowed = "".join(borrowed.inspect_llvm().values())
    assert "NRT_incref" in ir_counted
    assert "NRT_incref" not in ir_borrowed and "NRT_decref" not in ir_borrowed
    assert not borrowed.targetoptions["_nrt"]


@pytest.mark.skipif(not HAS_NRT_OPTION, reason="this numba has no _nrt option")
def test_refcount_false_refuses_to_allocate_and_a_callee_may_opt_back_in():
    """An allocation in a kernel compiled without reference counting is a compile error
    (never a leak), also in a callee that inherits the setting; a callee that states
    ``refcount=True`` allocates and is called as usual."""
    @njit
    def inherits(n):
        return np.zeros(n).sum()

    @njit(refcount=True)
    def opts_in(n):
        return np.ones(n).sum()

    @njit(refcount=False)
    def calls_inherit(n):
        return inherits(n)

    @njit(refcount=False)
    def calls_opt_in(n):
        return opts_in(n) + 1.0

    with pytest.raises(TypingError):
        calls_inherit(3)
    assert calls_opt_in(3) == 4.0
