"""Rigid bodies in the time loop (000 Sec 2.5, Eq 28-31).

A body named in the multimaterial option ``rigid_bodies`` moves kinematically: its
velocity is prescribed (zero unless the case gives the body a ``velocity`` or a uniform
``displacement`` condition; ``fixed`` components stay zero) and nothing it meets can
change it. The multimaterial kernels already treat a rigid field as the partner whose
velocity is kept (Eq 28-31: contact and interface forces act on the deformable field
only); here the rigid field's velocity is imposed on every node as a nodal velocity
condition, so the grid update, the phase-1 correction and the MUSL re-extrapolation all
see v_rigid, its particles move with it and, the velocity field being uniform, carry no
strain. The material given to a rigid body only sets its mass (not the time step).
"""
from __future__ import annotations

import numpy as np

from interfaces.errors import CaseError

from . import kernels as K
from .boundary import NodalConditions, history


def rigid_body_velocity(case, body: str, default_ramp: float, D: int) -> tuple[np.ndarray, ...]:
    """Per component: kernel velocity (mm/s), history code, t_end and ramp time of a rigid
    body's motion (:func:`mpm.boundary.history`: constant velocity, ramped velocity,
    displacement along its ramp)."""
    vel = np.zeros(D)
    code = np.full(D, K.HOLD, np.int64)
    t_end = np.full(D, np.inf)
    t_ramp = np.full(D, default_ramp)
    for k, bc in enumerate(case.boundary_conditions):
        if bc.body != body:
            continue
        if bc.kind == "fixed":
            continue
        if bc.kind not in ("velocity", "displacement"):
            raise CaseError(f"boundary_conditions[{k}]: body {body!r} is rigid (mpm option "
                            f"rigid_bodies); it takes fixed, velocity or uniform displacement "
                            f"conditions, not {bc.kind!r}")
        comps = bc.component_indices()
        divisor, c, te, tr = history(bc, default_ramp, f"boundary_conditions[{k}]")
        vel[comps] = bc.vector(D)[comps] / divisor
        code[comps], t_end[comps], t_ramp[comps] = c, te, tr
    return vel, code, t_end, t_ramp


def with_rigid_conditions(case, bcs: NodalConditions, rigid: np.ndarray, n_nodes: int, D: int,
                          default_ramp: float) -> NodalConditions:
    """``bcs`` without the side conditions of rigid fields, plus the rigid velocity of
    every rigid field on every node and component."""
    keep = ~np.isin(bcs.field, np.flatnonzero(rigid))
    arrays = (bcs.node, bcs.field, bcs.comp, bcs.vel, bcs.t_end, bcs.ramp, bcs.t_ramp)
    cols = [[a[keep]] for a in arrays]
    nodes = np.arange(n_nodes, dtype=np.int64)
    for f in np.flatnonzero(rigid):
        vel, code, t_end, t_ramp = rigid_body_velocity(case, case.bodies[f].name, default_ramp, D)
        for c in range(D):
            cols[0].append(nodes)
            cols[1].append(np.full(n_nodes, f, np.int64))
            cols[2].append(np.full(n_nodes, c, np.int64))
            cols[3].append(np.full(n_nodes, vel[c]))
            cols[4].append(np.full(n_nodes, t_end[c]))
            cols[5].append(np.full(n_nodes, code[c], np.int64))
            cols[6].append(np.full(n_nodes, t_ramp[c]))
    return NodalConditions(*(np.ascontiguousarray(np.concatenate(c)) for c in cols))
