"""Memory estimate of a CPD run, made before the point grid is allocated.

The largest allocations of a CPD solve (003 Sec 3.2) grow with the number of points N
and with the interaction pattern: every node is coupled with the nodes within 2 delta
(the tuples of a central point span its whole horizon on both sides), so the tangent
holds d^2 m entries per node, m = the grid points in a ball of radius 2 delta, and the
neighbour lists, the assembly buffers and the sparse factorisation scale with it. The
estimate is

    bytes = N (BYTES_PER_POINT + BYTES_PER_ENTRY d^2 m),

fitted to measured peak resident memory (above the interpreter's, one thread) of
``peridynamics.solve`` on the 003 bimaterial square (N = 2.9k .. 42k, delta/h = 3.01:
45 kB per point, 5.01: 96 kB) and checked on the 3D cuboid (delta/h = 2.01, N = 3025:
143 kB measured, 162 kB estimated). Materials with pair interactions only couple
within delta, so the estimate is an upper bound for them.

Units: mm; memory in bytes.
"""
from __future__ import annotations

import itertools
import math
import warnings

from interfaces.errors import CaseError
from interfaces.resources import available_memory

__all__ = ["estimate_bytes", "check_memory", "pattern_neighbours"]

BYTES_PER_POINT = 17e3       # neighbour lists, per-point buffers (fit, see above)
BYTES_PER_ENTRY = 62.5       # per tangent entry: values, indices, assembly and factorisation
WARN_BYTES = 2e9             # warn (with the figure) above this, or a quarter of what is available
MAX_DOFS = 2 ** 31 - 1       # the tangent's 32-bit column indices


def pattern_neighbours(radius_over_h: float, dim: int) -> int:
    """Grid points (the point itself included) within ``radius_over_h`` grid spacings."""
    R = int(math.floor(radius_over_h * (1.0 + 1e-9)))
    r2 = radius_over_h * radius_over_h * (1.0 + 1e-9)
    span = range(-R, R + 1)
    return sum(1 for k in itertools.product(span, repeat=dim) if sum(x * x for x in k) <= r2)


def estimate_bytes(n_points: float, dim: int, delta_over_h: float) -> float:
    """Peak memory (bytes) of a CPD solve with ``n_points`` points and horizon delta/h."""
    m = min(pattern_neighbours(2.0 * delta_over_h, dim), n_points)
    return n_points * (BYTES_PER_POINT + BYTES_PER_ENTRY * dim * dim * m)


def check_memory(axis_points: list[int], h: float, delta: float) -> None:
    """Refuse (CaseError naming cpd.h) a grid of ``axis_points`` per axis whose solve would need
    more memory than is available, warn with the figure when it is large; call before the
    grid is allocated."""
    dim = len(axis_points)
    n = float(math.prod(axis_points))
    grid = f"cpd.h = {h:g} mm (delta = {delta:g} mm) gives {' x '.join(map(str, axis_points))} = {n:.3g} grid points"
    if n * dim > MAX_DOFS:
        raise CaseError(f"{grid}, more DOFs than the sparse tangent can index ({MAX_DOFS:.3g}): use a larger cpd.h")
    need = estimate_bytes(n, dim, delta / h)
    free = available_memory()
    if free is not None and need > 0.8 * free:
        raise CaseError(f"{grid}, needing about {need / 1e9:.3g} GB, more than the {free / 1e9:.3g} GB of memory "
                        "available: use a larger cpd.h or a smaller cpd.delta_factor")
    if need > min(WARN_BYTES, 0.25 * free if free is not None else math.inf):
        of = f" of the {free / 1e9:.3g} GB available" if free is not None else ""
        warnings.warn(f"CPD: {grid}; the solve needs about {need / 1e9:.3g} GB{of}", RuntimeWarning, stacklevel=2)
