"""The project's ``njit``: numba's, compiling one machine code per non-literal signature.

When compiled code calls a numba function with a constant argument (``phase_contact(0,
...)``, ``b = -1`` for "the lump of all others", ``True`` for a switch), numba types the
argument as a literal (``Literal[int](0)``) and compiles a separate copy of the callee, and
of everything it calls, for each constant. Over this project's kernels that made 85 extra
copies (``_interaction_dp`` alone 24), and the first MPM run compiled 1.8x as long as it
does with the dispatcher here. That dispatcher types such calls with the plain types
(``int64``, ``bool``) and falls back to the literal types only when a function cannot be
typed without them (indexing a heterogeneous tuple by an argument). Calls from Python
never pass literals. Cost: the kernels no longer fold such constants (MPM throughput
0.95-1.00 of before, measured in benchmarks/bench_mpm_xpic.py).

``refcount=False`` compiles a kernel without numba's reference counting (its ``_nrt``
option). numba counts the references of every array a compiled function binds: each
array argument and each view it takes (``work[0]``, ``grad[i, a]``) costs an atomic
increment and decrement per call, which the reference-count pruning removes only in
straight-line code. The multimaterial kernels called once per node with some thirty
array arguments spent about two thirds of the time step of a static double lap shear
(1260 particles) there. A kernel compiled so must not allocate (numba refuses to compile
``np.empty`` in it) nor keep an array returned by a call; the functions it calls inherit
the setting unless they set ``refcount=True``, which a kernel that allocates and is
called from such a kernel must therefore state.

Fast math is ``fastmath=FMA``: LLVM may fuse a multiply and an add into one fused
multiply-add, and nothing else. numba's ``fastmath=True`` also lets LLVM reassociate
floating-point sums, and then a kernel compiled in the running process and the same
kernel loaded from numba's cache gave different results: ellipse_compaction (0.025 mm,
LR, CPDI + XPIC(5)) had positions 1e-15 mm apart after 2 % compression and 3.6e-13 mm
after 10 %, which the jammed packing amplified into another final state, so the first run
after the kernels compiled never matched the runs after it. Which function's two copies
differ was not traced (a callee optimised on its own in one process and inside its
caller in the other would do it); with reassociation off the two runs are bit-identical
to the end of the 75 % compression. Cost on the uGIMP block of benchmarks/bench_mpm_xpic.py, against
``fastmath=True`` in the same run: 0.94-0.98 of its throughput (without any fast math
0.82-0.88). :func:`njit` refuses other fast-math settings.
"""
from __future__ import annotations

from numba import njit as _numba_njit
from numba import types
from numba.core.cpu import CPUTargetOptions
from numba.core.errors import TypingError
from numba.core.registry import CPUDispatcher

#: numba's (private) ``_nrt`` option exists; without it ``refcount`` is ignored and the
#: kernels keep their reference counting (slower, the same results)
HAS_NRT_OPTION = hasattr(CPUTargetOptions, "_nrt")

#: the one fast-math setting of the project's kernels: fused multiply-add only
#: (module docstring); every dispatcher holds this very set: never change it
FMA = {"contract"}


class NonLiteralDispatcher(CPUDispatcher):
    """A CPU dispatcher that compiles calls from compiled code for unliteral types."""

    def get_call_template(self, args, kws):
        plain = tuple(types.unliteral(a) for a in args)
        plain_kws = {k: types.unliteral(v) for k, v in kws.items()}
        if plain != tuple(args) or plain_kws != kws:
            try:
                return super().get_call_template(plain, plain_kws)
            except TypingError:
                pass
        return super().get_call_template(args, kws)


def njit(*args, refcount: bool | None = None, **options):
    """``numba.njit`` (same arguments, bare or called) returning a
    :class:`NonLiteralDispatcher`; ``refcount`` False / True compiles without / with
    numba's reference counting (module docstring), None inherits it from the caller."""
    fastmath = options.get("fastmath", False)
    if fastmath is not False and fastmath != FMA:
        raise ValueError(f"njit: fastmath={fastmath!r} is not allowed; use fastmath=FMA "
                         "(interfaces.jit: with reassociation a kernel compiled in the "
                         "process and its cached copy differ at round-off)")
    if refcount is not None and HAS_NRT_OPTION:
        options["_nrt"] = bool(refcount)
    if args and callable(args[0]):
        return _as_non_literal(_numba_njit(*args, **options))

    def wrap(func):
        return _as_non_literal(_numba_njit(*args, **options)(func))
    return wrap


def _as_non_literal(dispatcher):
    """numba builds the dispatcher from its options (caching, inlining, fastmath); only its
    class changes here. NUMBA_DISABLE_JIT returns the plain function, left as it is."""
    if type(dispatcher) is CPUDispatcher:
        dispatcher.__class__ = NonLiteralDispatcher
    return dispatcher
