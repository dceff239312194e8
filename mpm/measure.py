"""Specimen measurements from MPM particles: stiffness (002 Eq 43-45), interface jump profile."""
from __future__ import annotations

import numpy as np

from interfaces.bulk import bulk_modulus, bulk_modulus_from_pressure
from interfaces.errors import CaseError

from .particles import side_particles


def stiffness_quantities(case, particles, loads: list[dict], stored_energy: float, result) -> dict:
    """``stiffness`` k = P / (<u_load> - <u_support>) (002 Eq 43) and ``stiffness_energy``
    k = P^2 / (2U) (Eq 45, U = strain + interface energy) for ``case.measurements['stiffness']``.
    ``direction`` is an axis name or a vector (rotated specimens); displacements and
    forces are projected on it.

    <u> are averages over the particles in the first row along each listed side,
    extrapolated from the particle centre to the side itself with the particle strain
    (u + eps . offset, exact for a linear field; finite-strain particles use their
    displacement gradient F - I; ``stiffness_particle_rows`` uses the
    particle-centre values as they are); P is the total
    applied traction force in ``direction`` on the load sides. Empty dict if the case
    asks for no stiffness; a warning if no traction acts on the load sides.
    """
    spec = (case.measurements or {}).get("stiffness")
    if not spec:
        return {}
    D = particles.x.shape[1]
    e = _direction(spec.get("direction", "y"), D)
    u = (particles.x - particles.x0) @ e

    def mean_u(sides, key):
        """(<u_d> of the side particles, <u_d> extrapolated to the side itself)."""
        if not sides:
            raise CaseError(f"measurements.stiffness.{key} must list [body, side] pairs")
        rows, edge = [], []
        for b, s in sides:
            idx = side_particles(case, particles, b, s)[0]
            normal = np.asarray(case.body(b).shape.edge_normal(s), float)
            off = normal * (0.5 * float(np.abs(normal) @ particles.spacing))
            rows.append(u[idx])
            edge.append(u[idx] + (_displacement_gradient(particles, idx) @ off) @ e)
        return float(np.mean(np.concatenate(rows))), float(np.mean(np.concatenate(edge)))

    u_load_p, u_load = mean_u(spec.get("load", []), "load")
    u_sup_p, u_sup = mean_u(spec.get("support", []), "support")
    load_sides = {(b, s) for b, s in spec.get("load", [])}
    P = float(sum(ld["force"] @ e for ld in loads if (ld["body"], ld["side"]) in load_sides))
    out = {"load_displacement": u_load, "support_displacement": u_sup, "load": P}
    if P == 0.0:
        result.warn("mpm: no traction acts on the stiffness load sides; stiffness not computed")
        return out
    delta = u_load - u_sup
    delta_p = u_load_p - u_sup_p
    out["stiffness"] = P / delta if delta != 0.0 else float("inf")
    out["stiffness_particle_rows"] = P / delta_p if delta_p != 0.0 else float("inf")
    out["stiffness_energy"] = P * P / (2.0 * stored_energy) if stored_energy > 0 else float("inf")
    return out


def bulk_quantities(case, particles, stored_energy: float, ring: float) -> dict:
    """``bulk_modulus`` by energy (000 Eq 35, ``stored_energy`` = strain + interfacial
    energy of the cell) and ``bulk_modulus_pressure`` from the volume-averaged pressure
    (Eq 36) for ``case.measurements['bulk_modulus']``; ``ring`` = 2 pi for axisymmetric
    runs (per-radian particle volumes), else 1. Empty dict if the case asks for none."""
    meas = (case.measurements or {}).get("bulk_modulus")
    if not meas:
        return {}
    stress = particles.stress
    if case.analysis == "axisymmetric":
        stress = stress[:, [0, 1, 3]]          # [rr, zz, tt] of the order [rr, zz, rz, tt]
    return {"bulk_modulus": bulk_modulus(meas, stored_energy, case.analysis),
            "bulk_modulus_pressure": bulk_modulus_from_pressure(
                meas, ring * particles.volume0, stress, case.analysis)}


#: interface nodes with less contact area than this fraction of the largest node's are
#: not part of the jump profile (:func:`interface_profile`)
SLIVER_AREA = 1e-2


def interface_profile(grid, node_out: np.ndarray, mass: np.ndarray | None = None,
                      pair: tuple[int, int] | None = None) -> dict | None:
    """Jump and traction at the interface nodes of the last step (helper columns of
    mpm.multimaterial_constants OUT_*), ordered along the interface.

    With ``mass`` (N, M) and ``pair`` (field indices a, b) only the nodes whose two
    heaviest fields are that pair are kept, so each interface of a case gets its own
    profile (as FEM reports the first interface pair of the case as "interface_jump").
    ``s`` is the coordinate along the mean interface tangent (from the node normals).

    Slivers are left out: nodes of a neighbouring node row that one field's particle
    domains just reach where the faces press together (000 Eq 20 area below
    ``SLIVER_AREA`` of the largest; on the DCB's bond 4e-8 to 4e-4 of it). Their jumps
    are read from a few particle tails and zig-zag from node to node (+-9e-5 mm
    tangential on a bond whose particles have none); they hold a negligible share of
    the interfacial energy, which the energies still count.
    """
    from .multimaterial_constants import (OUT_AREA, OUT_ENERGY, OUT_JUMP_N, OUT_JUMP_T,
                                          OUT_NX, OUT_NY, OUT_TRACTION_N, OUT_TRACTION_T)
    area = node_out[:, OUT_AREA]
    active = area > SLIVER_AREA * area.max(initial=0.0)
    if mass is not None and pair is not None and mass.shape[1] > 2:
        top2 = np.sort(np.argsort(mass, axis=1)[:, -2:], axis=1)
        active &= (top2[:, 0] == min(pair)) & (top2[:, 1] == max(pair))
    rows = np.flatnonzero(active)
    if rows.size == 0 or grid.D != 2:
        return None      # a 3D interface is a surface: no profile along one coordinate
    X = grid.node_positions()[rows]
    n = node_out[rows][:, [OUT_NX, OUT_NY]].mean(axis=0)
    t = np.array([-n[1], n[0]]) / max(np.linalg.norm(n), 1e-300)
    s = X @ t
    order = np.argsort(s, kind="stable")
    r = rows[order]
    return {"s": s[order] - s[order][0], "x": X[order, 0], "y": X[order, 1],
            "jump_n": node_out[r, OUT_JUMP_N], "jump_t": node_out[r, OUT_JUMP_T],
            "traction_n": node_out[r, OUT_TRACTION_N], "traction_t": node_out[r, OUT_TRACTION_T],
            "area": node_out[r, OUT_AREA], "energy": node_out[r, OUT_ENERGY]}


def _direction(direction, D: int) -> np.ndarray:
    """Unit vector of a measurement direction given as 'x'/'y'/'z' or as a vector."""
    names = "xyz"[:D]
    if isinstance(direction, str):
        if direction not in names:
            raise CaseError(f"measurements.stiffness.direction must be one of {list(names)} "
                            f"or a vector, got {direction!r}")
        return np.eye(D)[names.index(direction)]
    v = np.asarray(direction, float).ravel()
    if v.size != D or not np.all(np.isfinite(v)) or np.linalg.norm(v) == 0:
        raise CaseError(f"measurements.stiffness.direction must be a nonzero {D}-vector, got {direction!r}")
    return v / np.linalg.norm(v)


#: tensor index pairs of the Voigt rows: 2D [xx, yy, gamma_xy], 3D [xx, yy, zz, yz, xz, xy]
_VOIGT_PAIRS = {3: ((0, 0), (1, 1), (0, 1)), 6: ((0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1))}


def _displacement_gradient(particles, idx: np.ndarray) -> np.ndarray:
    """(n, D, D) displacement gradients of particles ``idx``: the small strain of a
    linear field, F - I where the particle carries a deformation gradient (finite-strain
    fields, mpm/finite_strain.py; a linear field's F stays the identity)."""
    H = _strain_tensor(particles.strain[idx])
    D = H.shape[1]
    F = particles.F[idx]
    moved = np.any(F != np.eye(3), axis=(1, 2))
    H[moved] = F[moved][:, :D, :D] - np.eye(D)
    return H


def _strain_tensor(voigt: np.ndarray) -> np.ndarray:
    """(n, D, D) small-strain tensors from Voigt rows (engineering shear); the 4-row
    axisymmetric order [rr, zz, rz, tt] gives the in-plane (r, z) tensor."""
    pairs = _VOIGT_PAIRS[6 if voigt.shape[1] == 6 else 3]
    D = 3 if voigt.shape[1] == 6 else 2
    e = np.zeros((voigt.shape[0], D, D))
    for k, (i, j) in enumerate(pairs):
        scale = 1.0 if i == j else 0.5
        e[:, i, j] = e[:, j, i] = scale * voigt[:, k]
    return e


def line_profiles(case, x0: np.ndarray, u: np.ndarray, spacing: float, n_bins: int | None = None) -> dict:
    """Displacement along each of ``case.lines`` from the particles (reference positions
    ``x0``, displacements ``u``): particles within half a particle ``spacing`` of the
    line are averaged in bins one spacing long. Returns {line: {"s", "x", "y", "ux", "uy"}}
    in the shared profile convention of docs/case_api.md.
    """
    out = {}
    D = x0.shape[1]
    for name, (p0, p1) in case.lines.items():
        p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
        length = float(np.linalg.norm(p1 - p0))
        if length == 0.0 or p0.size != D:
            continue
        d = (p1 - p0) / length
        rel = x0 - p0
        s = rel @ d
        dist = np.linalg.norm(rel - np.outer(s, d), axis=1)
        near = (dist <= 0.5 * spacing * (1 + 1e-9)) & (s >= -1e-9) & (s <= length + 1e-9)
        if not near.any():
            continue
        nb = n_bins or max(1, int(round(length / spacing)))
        idx = np.minimum((s[near] / length * nb).astype(int), nb - 1)
        count = np.bincount(idx, minlength=nb)
        keep = count > 0
        prof = {"s": ((np.arange(nb) + 0.5) * length / nb)[keep]}
        pos = p0 + np.outer(prof["s"], d)
        for k, c in enumerate("xyz"[:D]):
            prof[c] = pos[:, k]
            prof[f"u{c}"] = (np.bincount(idx, weights=u[near, k], minlength=nb) / np.maximum(count, 1))[keep]
        out[name] = prof
    return out
