"""Material points generated from the case bodies, and particle traction loads.

Each grid cell overlapping a body is filled with ppc x ppc (x ppc in 3D) particles at
the centres of the sub-cells; a particle belongs to the body that contains its centre
(holes excluded, clipped by the body's ``within`` shape). Particle volume = cell volume / ppc^D (x thickness in 2D), mass =
rho x volume. The particle field (= material field of mpm/LAYOUT.md) is the body index.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from interfaces.errors import CaseError, check_vector

from .finite_strain import identity_gradients
from .grid import Grid


@dataclass
class Particles:
    """Particle state arrays (P particles, dimension D, Voigt size nv)."""

    x: np.ndarray       # (P, D) current position
    x0: np.ndarray      # (P, D) initial position
    v: np.ndarray       # (P, D) velocity
    mass: np.ndarray    # (P,)
    volume0: np.ndarray  # (P,) initial volume (x thickness in 2D)
    volume: np.ndarray  # (P,) current volume
    field: np.ndarray   # (P,) int64 body (= material field) index
    stress: np.ndarray  # (P, nv) Voigt Cauchy stress [xx, yy, xy]
    strain: np.ndarray  # (P, nv) Voigt small strain (finite-strain fields: Green-Lagrange), engineering shear
    fext: np.ndarray    # (P, D) full (un-ramped) traction force on the particle
    foff: np.ndarray    # (P, D) offset from the particle centre to its loaded edge
    spacing: np.ndarray  # (D,) particle spacing = cell / ppc
    lp: np.ndarray      # (D,) particle half-width (uGIMP)
    F: np.ndarray | None = None  # (P, 3, 3) deformation gradient (mpm.finite_strain); identity
    foff0: np.ndarray | None = None  # (P, D) undeformed foff (finite-strain fields: foff = F foff0)
    eos: np.ndarray | None = None    # (P, 2) Mie-Grueneisen (e, P) (mpm.mie_gruneisen), else (0, 2)

    def __post_init__(self):
        if self.F is None:
            self.F = identity_gradients(self.P)

    @property
    def P(self) -> int:
        return int(self.mass.size)


def parse_ppc(ppc, D: int) -> np.ndarray:
    """Particles per cell per axis from an int or a sequence; validated."""
    message = f"mpm option ppc must be an integer in [1, 8] (or {D} of them), got {ppc!r}"
    try:
        arr = check_vector("mpm option ppc", ppc, D, broadcast=True)
    except CaseError:
        raise CaseError(message) from None
    if not np.all(np.equal(np.mod(arr, 1), 0)) or np.any(arr < 1) or np.any(arr > 8):
        raise CaseError(message)
    return arr.astype(np.int64)


def generate(case, grid: Grid, ppc) -> Particles:
    """Fill every body of ``case`` with particles on ``grid`` (``ppc`` per axis per cell)."""
    D = grid.D
    ppc = parse_ppc(ppc, D)
    spacing = grid.cell / ppc
    axisymmetric = case.analysis == "axisymmetric"
    thickness = case.thickness if D == 2 and not axisymmetric else 1.0
    vol = float(np.prod(spacing)) * thickness
    xs, fields, masses = [], [], []
    taken = None
    for b, body in enumerate(case.bodies):
        lo, hi = (np.asarray(a, float) for a in body.bounds())
        c0 = np.floor((lo - grid.origin) / grid.cell + 1e-9).astype(np.int64)
        c1 = np.ceil((hi - grid.origin) / grid.cell - 1e-9).astype(np.int64)
        axes = [grid.origin[d] + spacing[d] * (np.arange(c0[d] * ppc[d], c1[d] * ppc[d]) + 0.5)
                for d in range(D)]
        pts = np.stack([m.ravel() for m in np.meshgrid(*axes, indexing="ij")], axis=1)
        pts = pts[body.contains(pts)]
        # order along the flattened node index (x fastest) for cache-friendly scatter/gather
        pts = pts[np.lexsort(pts.T)]
        if taken is not None and taken.size:
            # a point claimed by an earlier body stays there (overlapping bodies)
            key = np.round((pts - grid.origin) / spacing - 0.5).astype(np.int64)
            dup = _member(key, taken, ppc * (grid.nn - 1))
            pts = pts[~dup]
        if pts.shape[0] == 0:
            raise CaseError(f"bodies[{b}] ({body.name}) contains no particle centre at cell "
                            f"{grid.cell.tolist()} and ppc {ppc.tolist()}: refine the grid")
        key = np.round((pts - grid.origin) / spacing - 0.5).astype(np.int64)
        taken = key if taken is None else np.vstack([taken, key])
        xs.append(pts)
        fields.append(np.full(pts.shape[0], b, np.int64))
    x = np.ascontiguousarray(np.vstack(xs))
    P = x.shape[0]
    field = np.concatenate(fields)
    # volumes per radian (area x r_p) in axisymmetric runs (000 Sec 2.3)
    volume = vol * x[:, 0] if axisymmetric else np.full(P, vol)
    rho = np.array([case.materials[body.material].rho for body in case.bodies])
    nv = 6 if D == 3 else (4 if axisymmetric else 3)
    return Particles(
        x=x, x0=x.copy(), v=np.zeros((P, D)), mass=rho[field] * volume,
        volume0=volume.copy(), volume=volume.copy(), field=field,
        stress=np.zeros((P, nv)), strain=np.zeros((P, nv)), fext=np.zeros((P, D)),
        foff=np.zeros((P, D)),
        spacing=spacing, lp=0.5 * spacing)


def _member(key: np.ndarray, table: np.ndarray, extent: np.ndarray) -> np.ndarray:
    """Rows of integer ``key`` present in ``table`` (both (n, D)), via linear codes."""
    mult = np.cumprod(np.concatenate([[1], extent[:-1] + 1]))
    return np.isin(key @ mult, table @ mult)


def side_particles(case, particles: Particles, body_name: str, side: str) -> tuple[np.ndarray, float]:
    """Indices of the particles of ``body_name`` in the first row along ``side``.

    The first row is the one nearest to the side: on a side along the grid axes, the
    centres within half a spacing of the nearest centre, which lies up to one spacing
    inside (half a spacing where the side is on the particle lattice; 0.125 mm for a
    35 mm strip at 0.15 mm spacing); on a rotated side, the centres within half a
    spacing of the side (measured along its normal). Returns (indices, side length or
    area).
    """
    names = [b.name for b in case.bodies]
    if body_name not in names:
        raise CaseError(f"boundary body {body_name!r} is not one of the bodies {names}")
    b = names.index(body_name)
    shape = case.bodies[b].shape
    if not hasattr(shape, "edge_normal"):
        raise CaseError(f"boundary side {side!r} of body {body_name!r}: mpm loads and measures "
                        f"sides of Rectangle/Box shapes only, got {type(shape).__name__}")
    normal = np.asarray(shape.edge_normal(side), float)
    spacing = float(np.abs(normal) @ particles.spacing)
    own = np.flatnonzero(particles.field == b)
    tol = 0.5 * spacing * (1.0 + 1e-6)                  # a rotated side
    if np.count_nonzero(np.abs(normal) > 1e-12) == 1 and own.size:
        nearest = float(np.min(shape.edge_distance(particles.x0[own], side)))
        tol = nearest + 0.5 * spacing if nearest <= spacing * (1.0 + 1e-6) else 0.0
    idx = own[shape.edge_mask(particles.x0[own], side, tol)] if tol > 0.0 else own[:0]
    if idx.size == 0:
        raise CaseError(f"no particle of body {body_name!r} lies within one particle spacing "
                        f"({spacing:g} mm) of side {side!r}: refine the grid (mpm cell)")
    return idx, float(shape.edge_length(side))


def _equivalent_shares(shape, side: str, points: np.ndarray, traction: np.ndarray,
                       length: float) -> np.ndarray:
    """Side lengths carried by the loaded particles of a 2D side that cuts the particle
    lattice (rotated body), statically equivalent to the uniform traction: the shares
    sum to the side length (resultant) and give its moment about the side's start.

    The particles of the first row along a rotated side sit irregularly along it (the
    lattice is the grid's): equal shares put a net moment on the side, which a free
    specimen loaded at both ends (000 Fig 9) cannot balance, so it turns steadily and a
    damped run never settles. Each particle first takes the part of the side nearest to
    it (1D Voronoi cells along the side), then a linear correction in the moment arm
    makes the moment exact; the arm counts the particle's depth inside the side for
    the tangential part of the traction."""
    axis, is_max = shape._side(side)
    q = shape.to_local(points)
    along = 1 - axis
    s = np.clip(q[:, along], 0.0, length)
    depth = (shape.size[axis] - q[:, axis]) if is_max else q[:, axis]   # >= 0 inside
    order = np.argsort(s, kind="stable")
    ss = s[order]
    edges = np.concatenate([[0.0], 0.5 * (ss[1:] + ss[:-1]), [length]])
    share = np.empty(s.size)
    share[order] = np.diff(edges)
    # moment of the forces share_p t about the side's start, per unit traction: in the
    # side frame (tangent tau, inward normal -n) a point (s, depth) has arm s tau - depth n
    R = shape._rotation()
    tau = R[:, along]
    n = np.asarray(shape.edge_normal(side), float)
    cross = lambda a, b: a[0] * b[1] - a[1] * b[0]  # noqa: E731
    arm = s * cross(tau, traction) - depth * cross(n, traction)
    target = 0.5 * length * length * cross(tau, traction)
    dev = arm - arm.mean()
    denom = float(dev @ arm)
    if s.size > 1 and abs(denom) > 1e-12 * max(float(arm @ arm), 1e-300):
        corrected = share + (target - float(share @ arm)) / denom * dev
        if np.all(corrected > 0.0):
            share = corrected
    return share


def apply_tractions(case, particles: Particles, D: int) -> list[dict]:
    """Set ``particles.fext`` from the case's traction boundary conditions.

    A loaded particle gets traction x its edge length (spacing along the side) x
    thickness (2D) or x its face area (3D), acting at the particle's edge on that side
    (``foff``: half a particle spacing along the outward normal); the shares are normalised so
    that the total force is exactly traction x side length x thickness. On 2D sides that
    cut the particle lattice (rotated bodies) the shares are the side lengths nearest to
    each particle, corrected so that the resultant and the moment equal those of the
    uniform traction (:func:`_equivalent_shares`), and the force acts at the particle. Returns one record per traction
    condition: particle indices, total force vector, ramp time and ramp name.
    """
    axisymmetric = case.analysis == "axisymmetric"
    thickness = case.thickness if D == 2 and not axisymmetric else 1.0
    loads = []
    for k, bc in enumerate(case.boundary_conditions):
        if bc.kind != "traction":
            continue
        idx, length = side_particles(case, particles, bc.body, bc.side)
        traction = _vector(bc, D, f"boundary_conditions[{k}]")
        shape = case.body(bc.body).shape
        normal = np.asarray(shape.edge_normal(bc.side), float)
        # particle extent along the side: the spacing in the tangential directions
        extent = np.prod(np.where(np.abs(normal) > 0.5, 1.0, particles.spacing)) if D == 3 else \
            abs(normal[1]) * particles.spacing[0] + abs(normal[0]) * particles.spacing[1]
        aligned = np.count_nonzero(np.abs(normal) > 1e-12) == 1
        if aligned or D != 2:
            share = np.full(idx.size, extent)
            share *= length / share.sum()
        else:
            share = _equivalent_shares(shape, bc.side, particles.x0[idx], traction, length)
        if axisymmetric:
            # per radian: each share times the radius of the loaded edge point (exact
            # for the midpoint rule of int t r ds along sides on grid lines)
            offset = normal[0] * 0.5 * float(np.abs(normal) @ particles.spacing) if aligned else 0.0
            share = share * (particles.x0[idx, 0] + offset)
            total = traction * float(share.sum())
        else:
            total = traction * length * thickness
        particles.fext[idx] += np.outer(share * thickness, traction)
        # the force acts on the particle's edge on that side (half a spacing outward) when
        # the side is aligned with the grid axes; otherwise at the particle (S_ip weights)
        if aligned:
            particles.foff[idx] = normal * (0.5 * float(np.abs(normal) @ particles.spacing))
        loads.append({"particles": idx, "force": total, "ramp_time": bc.ramp_time, "ramp": bc.ramp,
                      "body": bc.body, "side": bc.side})
    return loads


def _vector(bc, D: int, where: str) -> np.ndarray:
    """Full D-vector from a boundary condition's components/value."""
    names = "xyz"[:D]
    out = np.zeros(D)
    comps = list(bc.components)
    vals = list(np.atleast_1d(bc.value))
    if len(vals) != len(comps):
        raise CaseError(f"{where}.value must have one entry per component {comps}, got {vals}")
    for c, v in zip(comps, vals):
        if c not in names:
            raise CaseError(f"{where}.components entries must be in {list(names)}, got {c!r}")
        out[names.index(c)] = float(v)
    return out
