"""Particles of one material inside another's domain (004 Sec 4.2, Fig 6).

004 judges contact methods on the compaction of ellipses by the material points of one
ellipse "penetrating into other ellipses". Counted here: a particle p of one of the named
bodies is inside another material when its centre lies in the current domain of a
particle q of a different named body: the parallelogram (parallelepiped) F_q [-l, l]^D
around x_q, with l the undeformed half spacing and F_q the particle's deformation
gradient (the CPDI domain; runs that do not track F take the square of the particle's
volume, F = (V / V_0)^(1/D) I). Particles of two materials in contact have touching
domains, none of their centres inside the other's; a centre inside means the particle
crossed the contact surface by more than half its size.

Where the bodies fill a container of rigid walls (``container``: the bodies on its
``left``, ``right``, ``bottom`` and ``top`` sides, 2D), their current area, the sum of
the particle volumes over the thickness, over the container's current area is the
measure that still holds when the particle domains are strongly sheared: above 1,
material overlaps material (``material_area_over_container``).
"""
from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from interfaces.errors import CaseError


def interpenetration_quantities(case, x: np.ndarray, field: np.ndarray, volume: np.ndarray,
                                volume0: np.ndarray, spacing, F: np.ndarray | None = None) -> dict:
    """``interpenetration`` (count of particles inside another material),
    ``interpenetration_fraction`` (of the named bodies' particles) and
    ``interpenetration_cut_off`` (particles whose four nearest neighbours all belong to
    other materials, :func:`cut_off_from_own_material`), for
    ``case.measurements["interpenetration"]["bodies"]`` (default: every body). ``F``:
    the particles' deformation gradients (P, D, D), None where the run does not track
    them."""
    spec = case.measurements.get("interpenetration")
    if spec is None:
        return {}
    names = [b.name for b in case.bodies]
    bodies = spec.get("bodies", names)
    if not isinstance(bodies, (list, tuple)) or not bodies or any(b not in names for b in bodies):
        raise CaseError(f"measurements.interpenetration.bodies must name bodies of {names}, "
                        f"got {bodies!r}")
    members = np.flatnonzero(np.isin(field, [names.index(b) for b in bodies]))
    D = x.shape[1]
    spacing = np.broadcast_to(np.asarray(spacing, float), (D,))
    out = {}
    if "container" in spec:
        area = float(np.sum(volume[members])) / case.thickness
        out["material_area_over_container"] = area / container_area(
            spec["container"], names, x, field, spacing)
    if F is None:
        F = (np.abs(volume / volume0) ** (1.0 / D))[:, None, None] * np.eye(D)
    half = 0.5 * spacing
    count = int(inside_other_material(x[members], field[members], F[members], half).sum())
    cut_off = int(cut_off_from_own_material(x[members], field[members]).sum())
    return {"interpenetration": count, "interpenetration_fraction": count / max(members.size, 1),
            "interpenetration_cut_off": cut_off, **out}


CONTAINER_SIDES = ("left", "right", "bottom", "top")


def container_area(sides: dict, names: list, x: np.ndarray, field: np.ndarray,
                   spacing: np.ndarray) -> float:
    """Current area of the 2D container whose ``sides`` (``left``, ``right``, ``bottom``,
    ``top``: body names) are rigid bodies: between the facing edges of their particle
    domains (centres -+ half the spacing)."""
    if not isinstance(sides, dict) or sorted(sides) != sorted(CONTAINER_SIDES) \
            or any(sides[k] not in names for k in CONTAINER_SIDES):
        raise CaseError(f"measurements.interpenetration.container must name a body of {names} "
                        f"for each of {', '.join(CONTAINER_SIDES)}, got {sides!r}")
    if x.shape[1] != 2:
        raise CaseError("measurements.interpenetration.container is 2D only")
    h = 0.5 * spacing
    side = {k: x[field == names.index(sides[k])] for k in CONTAINER_SIDES}
    width = (side["right"][:, 0].min() - h[0]) - (side["left"][:, 0].max() + h[0])
    height = (side["top"][:, 1].min() - h[1]) - (side["bottom"][:, 1].max() + h[1])
    if width <= 0.0 or height <= 0.0:
        raise CaseError(f"measurements.interpenetration.container: the sides {sides} do not "
                        f"enclose a region (width {width:.4g}, height {height:.4g} mm)")
    return float(width * height)


def inside_pairs(x: np.ndarray, field: np.ndarray, F: np.ndarray, half: np.ndarray) -> np.ndarray:
    """Pairs (p, q), rows of an (K, 2) array, of particles of different materials
    (positions ``x`` (P, D), materials ``field``) whose p centre lies inside the domain
    F_q [-half, half]^D of q."""
    if x.shape[0] < 2:
        return np.zeros((0, 2), np.int64)
    reach = np.linalg.norm(np.abs(F) @ half, axis=1)         # circumscribed radius per domain
    pairs = cKDTree(x).query_pairs(float(reach.max()), output_type="ndarray")
    if pairs.size == 0:
        return np.zeros((0, 2), np.int64)
    pairs = pairs[field[pairs[:, 0]] != field[pairs[:, 1]]]
    both = np.vstack((pairs, pairs[:, ::-1]))                 # p's centre in q's domain, and back
    xi = np.linalg.solve(F[both[:, 1]], (x[both[:, 0]] - x[both[:, 1]])[:, :, None])[:, :, 0]
    return both[np.all(np.abs(xi) < half, axis=1)]


def cut_off_from_own_material(x: np.ndarray, field: np.ndarray, k: int = 4) -> np.ndarray:
    """Mask of the particles (positions ``x`` (P, D), materials ``field``) whose ``k``
    nearest neighbours all belong to other materials: particles carried into another
    material, away from their own. Unlike :func:`inside_other_material` it does not read
    the particle domains, so a domain sheared across a contact line does not count; it
    counts the particles that crossed it by about a particle or more."""
    k = min(k, x.shape[0] - 1)
    if k < 1:
        return np.zeros(x.shape[0], bool)
    _, near = cKDTree(x).query(x, k + 1)
    return np.all(field[near[:, 1:]] != field[:, None], axis=1)


def inside_other_material(x: np.ndarray, field: np.ndarray, F: np.ndarray,
                          half: np.ndarray) -> np.ndarray:
    """Mask of the particles (positions ``x`` (P, D), materials ``field``) whose centre
    lies inside the domain F_q [-half, half]^D of a particle q of another material."""
    inside = np.zeros(x.shape[0], bool)
    inside[inside_pairs(x, field, F, half)[:, 0]] = True
    return inside
