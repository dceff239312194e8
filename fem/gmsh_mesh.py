"""Unstructured quadratic triangle meshes of curved bodies with gmsh (002 Sec 2).

Circles, ellipses, rectangles (rotated or not) and polygons, clipped by a body's
``within`` shape and minus its holes, are built in gmsh's OpenCASCADE kernel and
fragmented together, so that bodies sharing a boundary get conforming meshes there.
Each fragment belongs to the first body (``case.bodies`` order) containing it, as in the
structured mesher. Triangles are second order with their mid-edge nodes placed on the
exact curves (6-node isoparametric triangles, scikit-fem ``MeshTri2``): the interface
elements built on them are the curved 6-node elements of 002 Eq 26-29 (ERRATA 1).
``curved=False`` keeps the same vertices with straight edges (mid-edge nodes at the chord
midpoints), for comparisons at equal DOFs.

Every body owns its nodes (duplicated along every shared boundary), so declared
interfaces can open. The size of the mesh is estimated from the bodies' areas before
gmsh meshes anything; a mesh above ``max_dofs`` is refused naming ``element_size``.
gmsh is optional: it is imported only here, when a case needs it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from interfaces.errors import CaseError

from .mesh import check_size

CURVED_KINDS = ("circle", "ellipse")
DOFS_PER_TRIANGLE = 4.2       # P2 vector DOFs per triangle (2 per node, ~2.1 nodes per triangle)
CURVATURE_ELEMENTS = 8        # at least this many elements around a full circle or ellipse


@dataclass
class GmshMesh:
    """Nodes (2, N) and 6-node triangles (6, Ne) (vertices, then mid-edge nodes of edges
    01, 12, 20, counter-clockwise) with nodes duplicated per body; body index per triangle."""

    nodes: np.ndarray
    t6: np.ndarray
    element_body: np.ndarray


def gmsh_module():
    """The gmsh Python API, or a one-line CaseError saying how to install it."""
    try:
        import gmsh
    except ImportError:
        raise CaseError("bodies: fem meshes curved shapes with gmsh, which is not installed "
                        "(pip install gmsh)") from None
    return gmsh


def needs_gmsh(case) -> bool:
    """True when a body, hole or clipping shape is curved (the structured mesher cannot follow it)."""
    for b in case.bodies:
        for s in [b.shape, b.within, *b.holes]:
            if s is not None and getattr(s, "kind", "") in CURVED_KINDS:
                return True
    return False


def _polygon_surface(occ, pts: np.ndarray) -> int:
    tags = [occ.addPoint(float(x), float(y), 0.0) for x, y in pts]
    lines = [occ.addLine(tags[k], tags[(k + 1) % len(tags)]) for k in range(len(tags))]
    return occ.addPlaneSurface([occ.addCurveLoop(lines)])


def _surface(occ, shape, where: str) -> list[tuple[int, int]]:
    """One gmsh surface for a 2D shape of ``interfaces.geometry``."""
    kind = getattr(shape, "kind", type(shape).__name__)
    if kind == "rectangle":
        return [(2, _polygon_surface(occ, shape.corners()))]
    if kind == "polygon":
        return [(2, _polygon_surface(occ, np.asarray(shape.vertices, dtype=float)))]
    if kind == "circle":
        return [(2, occ.addDisk(shape.cx, shape.cy, 0.0, shape.r, shape.r))]
    if kind == "ellipse":   # gmsh needs the first semi-axis to be the larger one
        a, b, angle = shape.a, shape.b, shape.angle
        if a < b:
            a, b, angle = b, a, angle + 90.0
        tag = occ.addDisk(shape.cx, shape.cy, 0.0, a, b)
        if angle:
            occ.rotate([(2, tag)], shape.cx, shape.cy, 0.0, 0.0, 0.0, 1.0, math.radians(angle))
        return [(2, tag)]
    raise CaseError(f"{where}: fem meshes rectangles, polygons, circles and ellipses in 2D, got a {kind}")


def _body_surfaces(occ, body, index: int) -> list[tuple[int, int]]:
    where = f"bodies[{index}]"
    s = _surface(occ, body.shape, f"{where}.shape")
    if body.within is not None:
        s, _ = occ.intersect(s, _surface(occ, body.within, f"{where}.within"))
    if body.holes:
        s, _ = occ.cut(s, [h for j, hole in enumerate(body.holes) for h in _surface(occ, hole, f"{where}.holes[{j}]")])
    if not s:
        raise CaseError(f"{where} ({body.name!r}): nothing is left of the shape after 'within' and 'holes'")
    return s


def _check_size(areas: np.ndarray, h: float, max_dofs: float) -> None:
    """Refuse before meshing when the DOFs estimated from the areas are too many (``fem.mesh.check_size``)."""
    check_size(DOFS_PER_TRIANGLE * float(areas.sum()) / (math.sqrt(3.0) / 4.0 * h * h), f"{h:g}", max_dofs)


def build_gmsh_mesh(case, h: float, max_dofs: float) -> GmshMesh:
    """Mesh all bodies of a 2D ``case`` into 6-node triangles of size ``h`` (mm)."""
    if case.dimension != 2:
        raise CaseError(f"analysis: fem solves 2D problems, got {case.analysis!r}")
    gmsh = gmsh_module()
    own = not gmsh.isInitialized()
    if own:
        gmsh.initialize(readConfigFiles=False, interruptible=False)   # no SIGINT handler: usable from threads
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    name = f"imperfect_{id(case)}"
    gmsh.model.add(name)
    try:
        return _mesh(gmsh, case, h, max_dofs)
    finally:
        gmsh.model.remove()
        if own:
            gmsh.finalize()


def _mesh(gmsh, case, h: float, max_dofs: float) -> GmshMesh:
    owner = _fragments(gmsh.model.occ, case)
    _check_size(np.array([gmsh.model.occ.getMass(2, tag) for tag in owner]), h, max_dofs)
    for key, value in (("Mesh.MeshSizeMax", h), ("Mesh.MeshSizeMin", 0.0), ("Mesh.ElementOrder", 2),
                       ("Mesh.MeshSizeFromCurvature", CURVATURE_ELEMENTS), ("Mesh.Algorithm", 6),
                       ("Mesh.HighOrderOptimize", 0), ("Mesh.SecondOrderLinear", 0)):
        gmsh.option.setNumber(key, value)
    try:
        gmsh.model.mesh.generate(2)
    except Exception as e:
        raise CaseError(f"element_size: gmsh could not mesh the bodies with h = {h:g} mm ({e})") from None
    return _per_body_mesh(gmsh, case, owner)


def _fragments(occ, case) -> dict[int, int]:
    """Build every body's surface and fragment them all together (conforming shared curves);
    returns the owning body index of each resulting surface (the first body containing it)."""
    inputs = []
    for i, body in enumerate(case.bodies):
        try:
            inputs.append(_body_surfaces(occ, body, i))
        except CaseError:
            raise
        except Exception as e:    # gmsh raises plain Exceptions with its log line
            raise CaseError(f"bodies[{i}] ({body.name!r}): gmsh rejected the shape ({e})") from None
    flat = [s for group in inputs for s in group]
    owner_of_input = [i for i, group in enumerate(inputs) for _ in group]
    try:
        _, out_map = occ.fragment(flat[:1], flat[1:]) if len(flat) > 1 else (flat, [flat])
        occ.synchronize()
    except Exception as e:
        raise CaseError(f"bodies: gmsh could not combine the shapes ({e})") from None
    owner: dict[int, int] = {}
    for k, pieces in enumerate(out_map):
        for _, tag in pieces:
            owner.setdefault(tag, owner_of_input[k])
    for i, body in enumerate(case.bodies):
        if i not in owner.values():
            raise CaseError(f"bodies[{i}] ({body.name!r}) is covered by earlier bodies: it gets no elements")
    return owner


def _per_body_mesh(gmsh, case, owner: dict[int, int]) -> GmshMesh:
    """The generated 6-node triangles, each body with its own copy of its nodes."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    xy = np.zeros((int(tags.max()) + 1, 2))
    xy[tags.astype(np.int64)] = coords.reshape(-1, 3)[:, :2]
    nodes, t6, eb, offset = [], [], [], 0
    for k in range(len(case.bodies)):
        conn = []
        for tag in (t for t, o in owner.items() if o == k):
            types, _, enodes = gmsh.model.mesh.getElements(2, tag)
            for etype, en in zip(types, enodes):
                if etype != 9:
                    raise CaseError(f"bodies[{k}]: gmsh returned element type {etype}, not 6-node triangles")
                conn.append(en.astype(np.int64).reshape(-1, 6))
        conn = np.concatenate(conn)
        used, local = np.unique(conn, return_inverse=True)
        nodes.append(xy[used])
        t6.append(local.reshape(conn.shape) + offset)
        eb.append(np.full(len(conn), k))
        offset += len(used)
    nodes, t6 = np.concatenate(nodes), np.concatenate(t6)
    _orient(nodes, t6)
    return GmshMesh(nodes=np.ascontiguousarray(nodes.T), t6=np.ascontiguousarray(t6.T), element_body=np.concatenate(eb))


def _orient(nodes: np.ndarray, t6: np.ndarray) -> None:
    """Make every triangle counter-clockwise (swap vertices 1, 2 and mid-edge nodes 01, 20)."""
    a, b, c = nodes[t6[:, 0]], nodes[t6[:, 1]], nodes[t6[:, 2]]
    cw = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]) < 0
    t6[cw] = t6[cw][:, [0, 2, 1, 5, 4, 3]]


__all__ = ["GmshMesh", "build_gmsh_mesh", "gmsh_module", "needs_gmsh", "CURVED_KINDS"]
