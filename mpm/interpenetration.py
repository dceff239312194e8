"""Particles of one material inside another's domain (004 Sec 4.2, Fig 6).

004 judges contact methods on the compaction of ellipses by the material points of one
ellipse "penetrating into other ellipses". Counted here: a particle p of one of the named
bodies is inside another material when the centre of a particle q of a different named
body is closer than half the sum of their current radii, |x_p - x_q| < (r_p + r_q) / 2,
with r = (s / 2) J^(1/D) (s the undeformed particle spacing, J = V / V_0 the particle's
volume ratio). Particles of two materials in contact sit about r_p + r_q apart (their
domains touch); a particle whose domain overlaps another material's particle by more
than half its size has crossed the contact surface.
"""
from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from interfaces.errors import CaseError


def interpenetration_quantities(case, x: np.ndarray, field: np.ndarray, volume: np.ndarray,
                                volume0: np.ndarray, spacing: float) -> dict:
    """``interpenetration`` (count of particles inside another material) and
    ``interpenetration_fraction`` (of the named bodies' particles), for
    ``case.measurements["interpenetration"]["bodies"]`` (default: every body)."""
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
    r = 0.5 * spacing * np.abs(volume[members] / volume0[members]) ** (1.0 / D)
    count = int(inside_other_material(x[members], field[members], r).sum())
    return {"interpenetration": count, "interpenetration_fraction": count / max(members.size, 1)}


def inside_other_material(x: np.ndarray, field: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Mask of the particles (positions ``x``, materials ``field``, current radii ``r``)
    closer to a particle of another material than half the sum of their radii."""
    inside = np.zeros(x.shape[0], bool)
    if x.shape[0] < 2:
        return inside
    pairs = cKDTree(x).query_pairs(float(r.max()), output_type="ndarray")
    if pairs.size:
        p, q = pairs[:, 0], pairs[:, 1]
        hit = (field[p] != field[q]) & (np.linalg.norm(x[p] - x[q], axis=1) < 0.5 * (r[p] + r[q]))
        inside[p[hit]] = True
        inside[q[hit]] = True
    return inside
