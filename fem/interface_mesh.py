"""Interface elements along the shared edges of two bodies (002 Fig 3).

For every ``InterfacePair(a, b)`` the boundary facets of body a and body b that coincide
become 2n-node interface elements (n = 2 for linear, 3 for quadratic bulk elements).
Side 1 of 002 is body b, traversed with b on its right, so the element normal
n1 = (y', -x')/|x'| points from a into b and the jump [u] = u_b - u_a (the case API's
convention): ``jump_n > 0`` opens the interface. Side-2 nodes (body a) follow 002 Eq 8:
node 2n+1-i of the element sits at the position of node i.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from interfaces.errors import CaseError
from interfaces.laws import BilinearNormalInterface, LinearInterface

from .interface_element import frame


@dataclass
class InterfaceElements:
    """Interface elements of one pair: side-1 coordinates ``xy`` (m, n, 2), element DOFs
    ``dofs`` (m, 4n) in 002 Eq 9 order, per-element ``Dn``/``Dt`` (inf = perfect) and the
    x-DOFs of the coincident node pairs ``node_b``/``node_a`` (m, n) (y-DOF = x-DOF + 1)."""

    pair: int
    a: str
    b: str
    xy: np.ndarray
    dofs: np.ndarray
    Dn: np.ndarray
    Dt: np.ndarray
    node_b: np.ndarray
    node_a: np.ndarray
    Dn_tension: np.ndarray | None = None       # bilinear normal law branches (002 Sec 3.1)
    Dn_compression: np.ndarray | None = None

    compressed: np.ndarray | None = None       # current branch of each element

    def __post_init__(self):
        if self.Dn_tension is None:
            self.Dn_tension = self.Dn.copy()
        if self.Dn_compression is None:
            self.Dn_compression = self.Dn.copy()
        self.compressed = np.zeros(len(self.Dn), dtype=bool)
        self.set_compressed(self.compressed)

    @property
    def bilinear(self) -> bool:
        """A bilinear normal law (different branches) acts on some element."""
        return bool(np.any(self.Dn_tension != self.Dn_compression))

    def set_compressed(self, compressed: np.ndarray) -> None:
        """Pick the normal branch of each element: Dn_compression where ``compressed``."""
        self.compressed = np.asarray(compressed, dtype=bool)
        self.Dn = np.where(self.compressed, self.Dn_compression, self.Dn_tension)

    @property
    def finite_Dn(self) -> np.ndarray:
        """Dn with perfect directions set to 0: their jump is constrained to zero exactly."""
        return np.where(np.isinf(self.Dn), 0.0, self.Dn)

    @property
    def finite_Dt(self) -> np.ndarray:
        return np.where(np.isinf(self.Dt), 0.0, self.Dt)


def _boundary_facet_data(mesh, element_body):
    bf = mesh.boundary_facets()
    fb = element_body[mesh.f2t[0, bf]]
    mid = mesh.p[:, mesh.facets[:, bf]].mean(axis=1).T
    return bf, fb, mid


def _laws(pair, index: int, midpoints: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per-element (Dn tension, Dn compression, Dt) from the pair's default law and its zones
    (002 Fig 6). Linear laws have equal branches; ``BilinearNormalInterface`` (002 Sec 3.1:
    perfect or stiffer in compression) is solved by the contact iteration of ``fem.solve``."""
    laws = [pair.law] + [z[1] for z in pair.zones]
    rows = []
    for k, law in enumerate(laws):
        if isinstance(law, LinearInterface):
            rows.append((law.Dn, law.Dn, law.Dt))
        elif isinstance(law, BilinearNormalInterface):
            rows.append((law.Dn_tension, law.Dn_compression, law.Dt))
        else:
            where = "law" if k == 0 else f"zones[{k - 1}].law"
            raise CaseError(f"interfaces[{index}].{where}: fem handles LinearInterface and "
                            f"BilinearNormalInterface, got {type(law).__name__} (use mpm for contact laws)")
    table = np.array(rows, dtype=float)
    k = pair.zone_index(midpoints) + 1
    return table[k, 0], table[k, 1], table[k, 2]


def find_interface_elements(case, mesh, basis, element_body: np.ndarray, order: int,
                            tol: float) -> list[InterfaceElements]:
    """Match coincident boundary facets of every interface pair and build its elements."""
    names = [b.name for b in case.bodies]
    bf, fbody, mid = _boundary_facet_data(mesh, element_body)
    p = mesh.p
    out = []
    for index, pair in enumerate(case.interfaces):
        ia, ib = names.index(pair.a), names.index(pair.b)
        fa, fbb = bf[fbody == ia], bf[fbody == ib]
        if len(fa) == 0 or len(fbb) == 0:
            raise CaseError(f"interfaces[{index}]: bodies {pair.a!r} and {pair.b!r} share no edge")
        dist, j = cKDTree(mid[fbody == ia]).query(mid[fbody == ib], distance_upper_bound=tol)
        hit = np.isfinite(dist)
        if not np.any(hit):
            raise CaseError(f"interfaces[{index}]: bodies {pair.a!r} and {pair.b!r} share no boundary "
                            "(an interface needs two bodies that touch along an edge or curve)")
        f_b, f_a = fbb[hit], fa[j[hit]]
        # side 1 = body b with b on the right of node 1 -> node n
        v0, v1 = mesh.facets[0, f_b].copy(), mesh.facets[1, f_b].copy()
        cent = p[:, mesh.t[:, mesh.f2t[0, f_b]]].mean(axis=1)
        d = p[:, v1] - p[:, v0]
        left = d[0] * (cent[1] - p[1, v0]) - d[1] * (cent[0] - p[0, v0]) > 0
        v0[left], v1[left] = v1[left], v0[left].copy()
        # body-a vertices at the positions of v0, v1
        a0, a1 = mesh.facets[0, f_a].copy(), mesh.facets[1, f_a].copy()
        swap = np.linalg.norm(p[:, a0] - p[:, v0], axis=0) > tol
        a0[swap], a1[swap] = a1[swap], a0[swap].copy()
        if np.any(np.linalg.norm(p[:, a0] - p[:, v0], axis=0) > tol) or \
                np.any(np.linalg.norm(p[:, a1] - p[:, v1], axis=0) > tol):
            raise CaseError(f"interfaces[{index}]: the meshes of {pair.a!r} and {pair.b!r} do not conform")
        nd = basis.nodal_dofs
        if order == 2:
            fd = basis.facet_dofs
            side1 = [nd[0, v0], fd[0, f_b], nd[0, v1]]
            side2 = [nd[0, a1], fd[0, f_a], nd[0, a0]]
            # the middle node where the bulk element has it: on the curve for curved meshes (002 Eq 26-29)
            xy = np.stack([p[:, v0].T, basis.doflocs[:, fd[0, f_b]].T, p[:, v1].T], axis=1)
        else:
            side1 = [nd[0, v0], nd[0, v1]]
            side2 = [nd[0, a1], nd[0, a0]]
            xy = np.stack([p[:, v0].T, p[:, v1].T], axis=1)
        xdofs = np.stack(side1 + side2, axis=1)                       # (m, 2n) x-DOFs
        dofs = np.stack([xdofs, xdofs + 1], axis=2).reshape(len(xdofs), -1)
        Dn, Dn_c, Dt = _laws(pair, index, xy.mean(axis=1) if order == 1 else xy[:, 1])
        node_b = xdofs[:, :order + 1]
        node_a = xdofs[:, order + 1:][:, ::-1]                         # node 2n+1-i <-> node i
        out.append(InterfaceElements(index, pair.a, pair.b, xy, dofs, Dn, Dt, node_b, node_a,
                                     Dn_tension=Dn, Dn_compression=Dn_c))
    return out


@dataclass
class NodePairs:
    """The coincident node pairs of all interfaces, one entry per body-b node: x-DOFs
    ``a``/``b`` (y-DOF = x-DOF + 1), the side-1 normal ``n`` and tangent ``t`` (unit), whether
    the frame is unique at the node (``straight``: all elements at the node agree), and
    whether the normal / tangential direction is perfect (D = inf) in an element there
    (the D -> inf limit of one element forces the jump to zero at all of its nodes)."""

    a: np.ndarray
    b: np.ndarray
    n: np.ndarray
    t: np.ndarray
    straight: np.ndarray
    perfect_n: np.ndarray
    perfect_t: np.ndarray


def node_pairs(elements: list[InterfaceElements], tol_angle: float = 1e-9) -> NodePairs:
    """Collect the interface node pairs of all elements (vectorized over elements)."""
    if not elements:
        z = np.zeros(0, dtype=np.int64)
        return NodePairs(z, z, np.zeros((0, 2)), np.zeros((0, 2)), z.astype(bool), z.astype(bool), z.astype(bool))
    nb, na, n1, t1, pn, pt = [], [], [], [], [], []
    for el in elements:          # one entry per interface pair (a handful), each vectorized
        m, n = el.node_b.shape
        _, nn, tt, _ = frame(el.xy, np.linspace(-1.0, 1.0, n))
        nb.append(el.node_b.ravel())
        na.append(el.node_a.ravel())
        n1.append(nn.reshape(-1, 2))
        t1.append(tt.reshape(-1, 2))
        pn.append(np.repeat(np.isinf(el.Dn), n))
        pt.append(np.repeat(np.isinf(el.Dt), n))
    nb, na, n1, t1, pn, pt = (np.concatenate(v) for v in (nb, na, n1, t1, pn, pt))
    key, first, inv = np.unique(nb, return_index=True, return_inverse=True)
    any_n = np.zeros(len(key), bool)
    any_t = np.zeros(len(key), bool)
    np.logical_or.at(any_n, inv, pn)
    np.logical_or.at(any_t, inv, pt)
    node_a = na[first]
    if np.any(na != node_a[inv]):
        raise CaseError("interfaces: a node of one body faces two different nodes (overlapping interfaces)")
    ref_n, ref_t = n1[first], t1[first]
    cross = np.abs(n1[:, 0] * ref_n[inv, 1] - n1[:, 1] * ref_n[inv, 0])
    kink = np.zeros(len(key), bool)
    np.logical_or.at(kink, inv, cross > np.sqrt(tol_angle))
    return NodePairs(node_a, key, ref_n, ref_t, ~kink, any_n, any_t)


def pair_index(pairs: NodePairs, node_b: np.ndarray) -> np.ndarray:
    """Index into ``pairs`` of body-b x-DOFs (e.g. an element's side-1 nodes)."""
    return np.searchsorted(pairs.b, node_b)


def check_one_direction_straight(pairs: NodePairs, elements: list[InterfaceElements]) -> None:
    """A one-direction perfect constraint needs a unique interface direction at the node."""
    bad = (pairs.perfect_n ^ pairs.perfect_t) & ~pairs.straight
    if np.any(bad):
        raise CaseError("interfaces: a normal-only or tangential-only perfect interface must be straight at "
                        "every node; found a kink (use finite D there, or a fully perfect interface)")


__all__ = ["InterfaceElements", "NodePairs", "find_interface_elements", "node_pairs", "pair_index", "check_one_direction_straight"]
