"""The compliant overlap interface: separate DOFs for A and B in the overlap band, tied by springs.

003 couples the two materials kinematically: every point of the overlap band (total width
l_ov, centred on the sharp interface) belongs to both material point sets and is one node
(shared DOFs, a perfect interface). For a linear imperfect interface T = Dn [u_n] n +
Dt [u_t] (002 Eq 1) this module keeps the band points' two materials apart instead
(derivation: ``docs/cpd_interface.md``):

* every band point p (owned by body o) keeps its node for material o, and gets a
  coincident copy node c carrying the other material's interactions; each material
  therefore still sees its own point set (body + band), as in 003 Sec 3.2;
* p and c are tied by a linear spring of energy
  ``W_p = 1/2 (V_p / w) g^T (Dn n n^T + Dt (I - n n^T)) g``, g = u_c - u_p oriented
  b minus a (the jump [u] of the law), n the interface normal from a to b at p;
* ``w = V_band / A_Gamma`` is the discrete band width: the band volume (sum of the
  body band points' volumes) over the interface measure (length x unit thickness in 2D,
  area in 3D). A uniform jump g across the band then stores exactly
  ``1/2 (Dn g_n^2 + Dt g_t^2) A_Gamma``, the interfacial energy of the law, on any grid
  and for any l_ov: this is the local limit (delta, l_ov -> 0 with u smooth on each side).
* a perfect direction (D = inf) is imposed exactly, never by a large spring: the DOF
  components of c along that direction are identified with those of p (the normal must
  then be a grid axis, as for the straight interfaces of the 003 and 000 specimens);
  with Dn = Dt = inf every component is identified, which is the shared-DOF coupling of
  003, and as Dn, Dt -> inf the springs tend to it continuously (error O(1/D)).

Layer points of a prescribed side inside the band are split likewise (both copies are
prescribed); their springs are not counted in the interfacial energy.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from interfaces.errors import CaseError
from interfaces.laws import LinearInterface
from interfaces.materials import small_strain_refusal

from .discretization import Discretization

AXIS_TOL = 1e-9


@dataclass
class Facet:
    """A flat piece of the sharp interface shared by bodies a and b (segment in 2D,
    axis-aligned rectangle in 3D): ``lo``/``hi`` its corners, ``normal`` from a to b."""

    lo: np.ndarray
    hi: np.ndarray
    normal: np.ndarray
    measure: float

    def distance(self, P: np.ndarray) -> np.ndarray:
        """Distance of points to the facet."""
        if len(self.lo) == 2:
            ab = self.hi - self.lo
            t = np.clip((P - self.lo) @ ab / (ab @ ab), 0.0, 1.0)
            return np.linalg.norm(P - (self.lo + t[:, None] * ab), axis=1)
        lo, hi = np.minimum(self.lo, self.hi), np.maximum(self.lo, self.hi)
        return np.linalg.norm(P - np.clip(P, lo, hi), axis=1)


@dataclass
class Springs:
    """Spring ties of the compliant overlap: node pairs (a-side node, b-side node), their
    (m, d, d) stiffness matrices (N/mm per unit thickness in 2D), and which springs count
    in the interfacial energy (body points, not boundary layers)."""

    node_a: np.ndarray
    node_b: np.ndarray
    S: np.ndarray
    counted: np.ndarray
    normal: np.ndarray
    pair: np.ndarray

    @property
    def count(self) -> int:
        return len(self.node_a)

    @staticmethod
    def empty(d: int) -> "Springs":
        z = np.zeros(0, np.int64)
        return Springs(z, z, np.zeros((0, d, d)), np.zeros(0, bool), np.zeros((0, d)), z)

    def energy(self, u: np.ndarray) -> np.ndarray:
        """Energy of every spring for nodal displacements u (N, d)."""
        g = u[self.node_b] - u[self.node_a]
        return 0.5 * np.einsum("ma,mab,mb->m", g, self.S, g)


def _edges_2d(shape) -> np.ndarray | None:
    if hasattr(shape, "corners") and shape.dimension == 2:
        v = shape.corners()
    elif hasattr(shape, "vertices"):
        v = np.asarray(shape.vertices, dtype=float)
    else:
        return None
    return np.stack([v, np.roll(v, -1, axis=0)], axis=1)


def _facets_2d(sa, sb, tol: float) -> list[Facet] | None:
    ea, eb = _edges_2d(sa), _edges_2d(sb)
    if ea is None or eb is None:
        return None
    out = []
    for p0, p1 in ea:
        L = float(np.linalg.norm(p1 - p0))
        t = (p1 - p0) / L
        for q0, q1 in eb:
            off = [t[0] * (q - p0)[1] - t[1] * (q - p0)[0] for q in (q0, q1)]
            if max(abs(off[0]), abs(off[1])) > tol:
                continue
            s = sorted(float((q - p0) @ t) for q in (q0, q1))
            lo, hi = max(0.0, s[0]), min(L, s[1])
            if hi - lo <= tol:
                continue
            n = np.array([t[1], -t[0]])
            mid = p0 + 0.5 * (lo + hi) * t
            if not sa.contains((mid - 1e-6 * L * n)[None])[0]:
                n = -n
            out.append(Facet(p0 + lo * t, p0 + hi * t, n, hi - lo))
    return out


def _facets_3d(sa, sb, tol: float) -> list[Facet] | None:
    if not all(getattr(s, "kind", "") == "box" for s in (sa, sb)):
        return None
    la, ha = sa.bounds()
    lb, hb = sb.bounds()
    out = []
    for k in range(3):
        for sign, plane_a, plane_b in ((1.0, ha[k], lb[k]), (-1.0, la[k], hb[k])):
            if abs(plane_a - plane_b) > tol:
                continue
            lo, hi = np.maximum(la, lb), np.minimum(ha, hb)
            lo[k] = hi[k] = plane_a
            others = [j for j in range(3) if j != k]
            area = float(np.prod(np.maximum(hi[others] - lo[others], 0.0)))
            if area > tol ** 2:
                n = np.zeros(3)
                n[k] = sign
                out.append(Facet(lo, hi, n, area))
    return out


def shared_facets(case, pair, h: float) -> list[Facet]:
    """The flat pieces of the sharp interface between the bodies of ``pair``.

    Rectangles and polygons (2D) and boxes (3D) are supported; other shapes are refused
    (their interface measure and normal would need a curved-surface description).
    """
    sa, sb = case.body(pair.a).shape, case.body(pair.b).shape
    tol = 1e-9 * h
    facets = _facets_2d(sa, sb, tol) if case.dimension == 2 else _facets_3d(sa, sb, tol)
    if facets is None:
        raise CaseError(f"interfaces[{pair.a}-{pair.b}]: the CPD compliant overlap needs rectangle/polygon "
                        f"(2D) or box (3D) bodies, got {type(sa).__name__} and {type(sb).__name__}")
    if not facets:
        raise CaseError(f"interfaces[{pair.a}-{pair.b}]: the bodies share no boundary (no straight or flat "
                        "common edge/face), so the CPD compliant overlap has no interface to tie")
    return facets


def law_stiffness(law, where: str) -> tuple[float, float]:
    """(Dn, Dt) of a law the compliant overlap represents; one-line refusal otherwise."""
    if type(law) is not LinearInterface:
        raise CaseError(f"{where}: CPD cannot represent the interface law {type(law).__name__} "
                        "(only LinearInterface(Dn, Dt) with 0 <= Dn, Dt <= inf)")
    if law.Dn < 0 or law.Dt < 0:
        raise CaseError(f"{where}: CPD cannot represent negative interface stiffness (Dn = {law.Dn:g}, "
                        f"Dt = {law.Dt:g}; 002 Eq 52 stiff interphase): its energy is not bounded below")
    return float(law.Dn), float(law.Dt)


def check_laws(case) -> None:
    """Refuse (one line naming the law) any interface law the CPD overlap cannot represent."""
    for pair in case.interfaces:
        laws = [pair.law] + [z[1] for z in pair.zones]
        where = [f"interfaces[{pair.a}-{pair.b}]"] + [f"interfaces[{pair.a}-{pair.b}].zones[{k}]"
                                                      for k in range(len(pair.zones))]
        for law, w in zip(laws, where):
            law_stiffness(law, w)


def supports(case) -> str | None:
    """None when CPD can run ``case``'s interface laws, otherwise the one-line reason
    (the hook ``cases.methods.supported_methods`` asks every solver package)."""
    try:
        check_laws(case)
    except CaseError as e:
        return str(e)
    return small_strain_refusal(case, "cpd")


def is_perfect(pair) -> bool:
    """True when the pair (and every zone) is a perfect interface (shared-DOF coupling)."""
    laws = [pair.law] + [z[1] for z in pair.zones]
    return all(isinstance(l, LinearInterface) and l.perfect for l in laws)


def spring_matrix(n: np.ndarray, Dn: float, Dt: float, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """Finite part of scale * (Dn n n^T + Dt (I - n n^T)) and the mask of DOF components
    identified exactly (perfect directions, which must be grid axes)."""
    d = len(n)
    nn = np.outer(n, n)
    S = np.zeros((d, d))
    S += 0.0 if math.isinf(Dn) else Dn * nn
    S += 0.0 if math.isinf(Dt) else Dt * (np.eye(d) - nn)
    axis = np.abs(np.abs(n) - 1.0) < AXIS_TOL
    tie = np.zeros(d, dtype=bool)
    if math.isinf(Dn) or math.isinf(Dt):
        if not axis.any():
            raise CaseError(f"a perfect direction (Dn = {Dn:g}, Dt = {Dt:g}) with finite springs needs an "
                            f"interface normal along a grid axis in CPD, got n = {np.round(n, 6).tolist()}")
        k = int(np.argmax(axis))
        if math.isinf(Dn):
            tie[k] = True
        if math.isinf(Dt):
            tie[np.arange(d) != k] = True
    return scale * S, tie


def split_band(case, disc: Discretization) -> tuple[Discretization, Springs, np.ndarray]:
    """Give the overlap band of every non-perfect pair separate A and B nodes (see module).

    Returns the new discretization (copies appended, ``copy_of`` marks them), the
    springs, and the DOF identification (k, 2) of full-DOF indices (copy dof, original
    dof) for perfect directions.
    """
    d = disc.dim
    names = disc.body_names
    X, vol, owner, member, layer = disc.X, disc.vol, disc.owner, disc.member.copy(), disc.layer
    new_X, new_owner, new_member, new_layer, new_src = [], [], [], [], []
    sp_a, sp_b, sp_S, sp_cnt, sp_n, sp_pair, ties = [], [], [], [], [], [], []
    n0 = len(X)
    for ip, pair in enumerate(case.interfaces):
        if is_perfect(pair):
            continue
        ia, ib = names.index(pair.a), names.index(pair.b)
        band = np.flatnonzero(member[:, ia] & member[:, ib])
        if len(band) == 0:
            continue
        facets = shared_facets(case, pair, disc.h)
        dist = np.stack([f.distance(X[band]) for f in facets], axis=1)
        normal = np.stack([f.normal for f in facets])[np.argmin(dist, axis=1)]
        area = sum(f.measure for f in facets)
        width = float(vol[band][~layer[band]].sum()) / area     # discrete band width V_band / A
        zone = pair.zone_index(X[band])
        laws = [pair.law] + [z[1] for z in pair.zones]
        where = [f"interfaces[{pair.a}-{pair.b}]"] + [f"interfaces[{pair.a}-{pair.b}].zones[{k}]"
                                                      for k in range(len(pair.zones))]
        DnDt = [law_stiffness(l, w) for l, w in zip(laws, where)]
        start = n0 + sum(len(x) for x in new_X)
        copies = start + np.arange(len(band))
        other = np.where(owner[band] == ia, ib, ia)
        member[band, other] = False                          # the original keeps its own material
        m = np.zeros((len(band), len(names)), dtype=bool)
        m[np.arange(len(band)), other] = True
        new_X.append(X[band])
        new_owner.append(other)
        new_member.append(m)
        new_layer.append(layer[band])
        new_src.append(band)
        on_a = owner[band] == ia
        node_a = np.where(on_a, band, copies)
        node_b = np.where(on_a, copies, band)
        S = np.empty((len(band), d, d))
        for k in range(len(band)):
            Dn, Dt = DnDt[zone[k] + 1]
            S[k], tie = spring_matrix(normal[k], Dn, Dt, vol[band[k]] / width)
            for c in np.flatnonzero(tie):
                ties.append((copies[k] * d + c, band[k] * d + c))
        sp_a.append(node_a)
        sp_b.append(node_b)
        sp_S.append(S)
        sp_cnt.append(~layer[band])
        sp_n.append(normal)
        sp_pair.append(np.full(len(band), ip))
    if not new_X:
        return disc, Springs.empty(d), np.zeros((0, 2), np.int64)
    src = np.concatenate(new_src)
    copy_of = np.concatenate([np.full(n0, -1, np.int64), src])
    prescribed = []
    for ps in disc.prescribed:
        extra = n0 + np.flatnonzero(np.isin(src, ps.nodes))
        lay_extra = n0 + np.flatnonzero(np.isin(src, ps.layer_nodes))
        prescribed.append(replace(ps, nodes=np.concatenate([ps.nodes, extra]),
                                  layer_nodes=np.concatenate([ps.layer_nodes, lay_extra])))
    out = replace(disc, X=np.vstack([X, np.concatenate(new_X)]), vol=np.concatenate([vol, vol[src]]),
                  owner=np.concatenate([owner, np.concatenate(new_owner)]),
                  member=np.vstack([member, np.concatenate(new_member)]),
                  layer=np.concatenate([layer, np.concatenate(new_layer)]), prescribed=prescribed,
                  copy_of=copy_of)
    springs = Springs(np.concatenate(sp_a), np.concatenate(sp_b), np.concatenate(sp_S),
                      np.concatenate(sp_cnt), np.concatenate(sp_n), np.concatenate(sp_pair))
    return out, springs, np.asarray(ties, dtype=np.int64).reshape(-1, 2)
