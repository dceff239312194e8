"""Memory estimate of a CPD run, made before the point grid is allocated.

The largest allocations of a CPD solve (003 Sec 3.2) grow with the number of points N
and with the interaction pattern: every node is coupled with the nodes within 2 delta
(the tuples of a central point span its whole horizon on both sides), so the tangent
holds d^2 m entries per node, m = the grid points in a ball of radius 2 delta. Per point,
the estimate adds

* ``BYTES_PER_POINT``: neighbour lists and per-point vectors;
* ``BYTES_PER_ENTRY`` d^2 m: the tangent's values and indices and the assembly buffers;
* ``BYTES_PER_FILL`` d^2 m g(N): the sparse Cholesky factors, whose fill per point grows
  as log2 N in 2D and N^(1/3) in 3D (nested dissection; the PARDISO factors measured
  3-10 kB per point at N = 11k-41k in 2D);
* the scatter slots of the tangent assembly (peridynamics/assembly.py): 4 bytes per
  (centre, neighbour, neighbour) of a horizon of k points, 4 N k^2, in ``SLOT_COPIES``
  arrays (the full and the free-DOF targets of the tangent and of the pair
  preconditioner), each dropped above ``SLOT_BUDGET`` (the kernels then search the
  pattern instead). They dominate at large horizons: 99 of 138 kB per point at
  delta/h = 5.01 in 2D.

The constants are fitted to the measured peak memory (resident, above that before the
solve, one thread, numba compiled) of ``peridynamics.solve``: the 003 bimaterial square,
parameter set 2, at delta/h = 2.01-5.01 and N = 2.8k-42k: within -4 .. +10 % from
delta/h = 3.01 up, +24 % at 2.01; parameter set 1 (its overlap band couples 50 % more
entries than the pattern counts) -5 .. -11 % at delta/h = 3.01; the 3D cuboid
(nu_A = 0.25) at delta/h = 2.01, N = 20k and 44k: +6 .. +19 %. Small 3D grids, mostly
boundary points with part of a horizon, come out high: x1.6 at delta/h = 3.01,
N = 15k (216 kB per point measured). :func:`check_memory` counts the padded grid, the
boundary layers of every side included, more points than the solve keeps (2.3x on that
cuboid, 7 % on the square). Not in the estimate: an indefinite tangent (materials that
store negative energy in short waves, which solve() warns of) is factorised by LDL^T in
double precision beside approximate factors, and took 1.3-1.4x the estimate at
delta/h = 5.01 in 2D.

Units: mm; memory in bytes.
"""
from __future__ import annotations

import itertools
import math
import warnings

from interfaces.errors import CaseError
from interfaces.resources import available_memory

__all__ = ["estimate_bytes", "check_memory", "pattern_neighbours"]

BYTES_PER_POINT = 6e3        # neighbour lists, per-point vectors (fit, see above)
BYTES_PER_ENTRY = 15.0       # per tangent entry: values, indices, assembly buffers
BYTES_PER_FILL = 0.4         # per tangent entry and unit of g(N): the factors' fill
SLOT_BYTES = 4               # one int32 scatter slot per (centre, neighbour, neighbour)
SLOT_COPIES = 4              # full and free-DOF targets, of the tangent and of the pair preconditioner
#: bytes one copy of the scatter slots may take; above it the kernels find each block of the
#: tangent by binary search in the pattern (same result, slower; peridynamics/assembly.py)
SLOT_BUDGET = 512 * 2 ** 20
WARN_BYTES = 2e9             # warn (with the figure) above this, or a quarter of what is available
MAX_DOFS = 2 ** 31 - 1       # the tangent's 32-bit column indices


def pattern_neighbours(radius_over_h: float, dim: int) -> int:
    """Grid points (the point itself included) within ``radius_over_h`` grid spacings."""
    R = int(math.floor(radius_over_h * (1.0 + 1e-9)))
    r2 = radius_over_h * radius_over_h * (1.0 + 1e-9)
    span = range(-R, R + 1)
    return sum(1 for k in itertools.product(span, repeat=dim) if sum(x * x for x in k) <= r2)


def fill_growth(n_points: float, dim: int) -> float:
    """g(N) of the factors' fill per point: log2 N (2D), N^(1/3) (3D)."""
    n = max(float(n_points), 2.0)
    return math.log2(n) if dim == 2 else n ** (1.0 / 3.0)


def estimate_bytes(n_points: float, dim: int, delta_over_h: float) -> float:
    """Peak memory (bytes) of a CPD solve with ``n_points`` points and horizon delta/h."""
    m = min(pattern_neighbours(2.0 * delta_over_h, dim), n_points)
    k = min(pattern_neighbours(delta_over_h, dim), n_points)
    entries = dim * dim * m
    per_entry = BYTES_PER_ENTRY + BYTES_PER_FILL * fill_growth(n_points, dim)
    slots = min(SLOT_BYTES * n_points * k * k, SLOT_BUDGET)
    return n_points * (BYTES_PER_POINT + entries * per_entry) + SLOT_COPIES * slots


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
