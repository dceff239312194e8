"""The state bundle of an MPM run: numba-compatible named tuples of arrays.

The compiled time step (:mod:`mpm.step`) takes a run's state as seven bundles instead
of dozens of loose arrays. Each bundle is a ``NamedTuple`` whose fields are views of
the arrays owned by the run's :class:`mpm.solver.Model` (particles, grid, nodal fields,
conditions, pair tables), so the step updates the model in place and a bundle costs
nothing to rebuild. Field names follow mpm/LAYOUT.md.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .kernels import UPDATE_CODES
from .multimaterial_constants import NODE_OUT_COLUMNS, S_SEPARATION, SEP_LR


class ParticleState(NamedTuple):
    """Particle arrays (P particles, D = 2): positions, velocities, mass, volumes, stress
    and strain (Voigt, engineering shear), body index, traction loads and offsets, uGIMP
    half-widths and the LR radii R_0 (004 Eq 25)."""
    x: np.ndarray
    v: np.ndarray
    mass: np.ndarray
    volume: np.ndarray
    volume0: np.ndarray
    stress: np.ndarray
    strain: np.ndarray
    field: np.ndarray
    x0: np.ndarray
    fext: np.ndarray
    foff: np.ndarray
    lp: np.ndarray
    half_width: np.ndarray
    x_before: np.ndarray       # MUSL: start-of-step positions (zero rows otherwise)
    r_before: np.ndarray       # axisymmetric work arrays (zero rows otherwise)
    strain_before: np.ndarray
    d_hoop: np.ndarray
    F: np.ndarray              # (P, 3, 3) deformation gradients (mpm.finite_strain)
    velgrad: np.ndarray        # (P, D, D) velocity gradients of finite-strain fields (else 0 rows)
    foff0: np.ndarray          # (P, D) undeformed loaded-edge offsets (foff = F foff0)
    eos: np.ndarray            # (P, 2) Mie-Grueneisen (e, P) (mpm.mie_gruneisen; else 0 rows)
    xpic: np.ndarray           # (2, P, D) XPIC(m) particle extrapolations (mpm.xpic; else 0 rows)
    xpic_node: np.ndarray      # XPIC(m) stencils: nodes (mpm.xpic.stencil_arrays; else 0 rows)
    xpic_weight: np.ndarray    # ... and weights


class GridSpec(NamedTuple):
    """Structured background grid: node 0 position, cell sizes, node counts, shape code."""
    origin: np.ndarray
    cell: np.ndarray
    nn: np.ndarray
    kind: int
    axis_nodes: np.ndarray     # nodes on r = 0 (axisymmetric; empty otherwise)


class NodalState(NamedTuple):
    """Nodal fields of mpm/LAYOUT.md ([N, M] and [N, M, D])."""
    mass: np.ndarray
    momentum: np.ndarray
    force: np.ndarray
    volume: np.ndarray
    volume_gradient: np.ndarray
    displacement: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    real_mass: np.ndarray      # B2 symmetry folds: the masses before the fold (else [0, M])
    xpic: np.ndarray           # [7, N, M, D] XPIC(m) work slots (mpm.xpic; else 0 rows)


class Conditions(NamedTuple):
    """Nodal velocity / fixed conditions with their histories, and the reflected ghost
    nodes of B2 runs (mpm.boundary)."""
    node: np.ndarray
    field: np.ndarray
    comp: np.ndarray
    vel: np.ndarray
    t_end: np.ndarray
    ramp: np.ndarray
    t_ramp: np.ndarray
    ghost_node: np.ndarray     # B2 reflected ghost nodes (mpm.boundary.GhostNodes)
    ghost_field: np.ndarray
    ghost_comp: np.ndarray
    ghost_mirror: np.ndarray
    ghost_ref: np.ndarray
    ghost_plane: np.ndarray
    plane_node: np.ndarray
    plane_field: np.ndarray
    plane_of: np.ndarray


class PairTables(NamedTuple):
    """Multimaterial pair tables (:class:`mpm.multimaterial.MultimaterialTables`), the
    out-of-plane thickness (one value or one per node), the per-node output columns
    and the per-node normals (LR: of the current step; radial SN: fixed) and LR
    separations, the reference nodal volumes of 000 Eq 20 (option interface_area =
    reference; empty: the current volumes), the DF edge-distance table d(s) of 004
    Eq 15 (separation = DF; empty otherwise) and, with LR and three_material = explicit,
    the LR normals and separations of every material pair at nodes seen by 3+ materials
    (004 Sec 3.4; slot :func:`mpm.multimaterial_lr.pair_index`), and with LR and rigid
    bodies each field's separation from the rigid fields (:func:`mpm.multimaterial_lr.lr_kernel`)."""
    thickness: np.ndarray
    law_kind: np.ndarray
    law_params: np.ndarray
    settings: np.ndarray
    rigid: np.ndarray
    node_zone: np.ndarray
    zone_pairs: np.ndarray
    zone_kind: np.ndarray
    zone_params: np.ndarray
    node_out: np.ndarray
    lr_normal: np.ndarray
    lr_separation: np.ndarray
    area_volume: np.ndarray
    df_curve: np.ndarray
    lr_pair_normal: np.ndarray      # [N, M (M - 1) / 2, D]: LR per pair at 3+ nodes (three_material = explicit)
    lr_pair_separation: np.ndarray  # [N, M (M - 1) / 2] (zero rows otherwise)
    lr_rigid_separation: np.ndarray  # [N, M]: LR separation of each field from the rigid fields (LR with rigid bodies)


class Blocks(NamedTuple):
    """Per-block copies of the nodal arrays of the race-free parallel P2G
    (:class:`mpm.parallel.BlockBuffers`; zero blocks: serial)."""
    mass: np.ndarray
    mom: np.ndarray
    force: np.ndarray
    volume: np.ndarray
    volgrad: np.ndarray
    disp: np.ndarray
    pos: np.ndarray


class StepControl(NamedTuple):
    """The variant switches and constants of a run's time step."""
    dt: float
    ramp_time: float
    ramp_code: int
    pic: float
    mode: int
    kinetic_damping: bool
    linear_u: bool
    with_interface: bool
    check_limit: bool
    uses_lr: bool
    mass_tolerance: float
    axisymmetric: bool
    C: np.ndarray
    finite_strain: bool        # some field takes the finite-strain update (mpm.finite_strain)
    material_kind: np.ndarray  # per field: mpm.finite_strain.LINEAR / NEO_HOOKEAN
    material_params: np.ndarray
    xpic: int                  # XPIC(m) order (0: FLIP with the pic blend; mpm.xpic)
    xpic_blend: float          # XPIC fraction blended into FLIP (the pic option when xpic >= 1)
    xpic_correction: bool      # multimaterial XPIC with the Delta v term (004 Eq 37)


def particle_state(pt, axisymmetric: bool, musl: bool, finite_strain: bool = False,
                   xpic: int = 0, cpdi: bool = False) -> ParticleState:
    """Bundle of :class:`mpm.particles.Particles` (LR radii: half the spacing) with the
    work arrays of MUSL, axisymmetric, finite-strain and XPIC(m) runs (``cpdi``: the
    CPDI shapes' XPIC node lists)."""
    from .xpic import stencil_arrays
    half_width = np.ascontiguousarray(np.broadcast_to(0.5 * np.asarray(pt.spacing, float),
                                                      pt.x.shape))
    n = pt.P if axisymmetric else 0
    if pt.foff0 is None:              # particles without a Model (the loads as they are)
        pt.foff0 = pt.foff.copy()
    return ParticleState(pt.x, pt.v, pt.mass, pt.volume, pt.volume0, pt.stress, pt.strain,
                         pt.field, pt.x0, pt.fext, pt.foff, pt.lp, half_width,
                         np.zeros((pt.P if musl else 0, pt.x.shape[1])), np.zeros(n),
                         np.zeros((n, pt.strain.shape[1])), np.zeros(n), pt.F,
                         np.zeros((pt.P if finite_strain else 0, pt.x.shape[1], pt.x.shape[1])),
                         pt.foff0, pt.eos if pt.eos is not None else np.zeros((0, 2)),
                         *stencil_arrays(pt.P, pt.x.shape[1], cpdi, xpic))


def grid_spec(grid, kind: int, axis_nodes: np.ndarray) -> GridSpec:
    return GridSpec(grid.origin, grid.cell, grid.nn, int(kind),
                    np.ascontiguousarray(axis_nodes, dtype=np.int64))


def nodal_state(nd, folds: bool = False, xpic: int = 0) -> NodalState:
    """Bundle of :class:`mpm.grid.NodalFields`; ``folds``: the run has B2 symmetry sides;
    ``xpic``: the XPIC(m) order (its work slots, mpm.xpic)."""
    from .xpic import N_SLOTS
    real_mass = np.zeros((nd.N if folds else 0, nd.M))
    work = np.zeros((N_SLOTS if xpic else 0,) + nd.momentum.shape)
    return NodalState(nd.mass, nd.momentum, nd.force, nd.volume, nd.volume_gradient,
                      nd.displacement, nd.position, nd.velocity, nd.acceleration, real_mass,
                      work)


def conditions(bc) -> Conditions:
    from .boundary import no_ghosts
    g = bc.ghosts if bc.ghosts is not None else no_ghosts()
    return Conditions(bc.node, bc.field, bc.comp, bc.vel, bc.t_end, bc.ramp, bc.t_ramp,
                      g.node, g.field, g.comp, g.mirror, g.ref, g.plane, g.plane_node,
                      g.plane_field, g.plane_of)


def pair_tables(tables, node_out, thickness, N: int, M: int, D: int,
                area_volume: np.ndarray | None = None) -> PairTables:
    """Bundle of the pair tables; a single-material run (``tables`` None) gets empty
    tables of the right types (the multimaterial phases never run for it).
    ``area_volume``: the reference nodal volumes of 000 Eq 20 (None: current volumes)."""
    area = np.zeros((0, M)) if area_volume is None else np.ascontiguousarray(area_volume, dtype=np.float64)
    thick = np.ascontiguousarray(np.atleast_1d(np.asarray(thickness, dtype=np.float64)))
    if tables is None:
        from .multimaterial_constants import N_PARAMS, N_SETTINGS
        return PairTables(thick, np.zeros((M, M), np.int64), np.zeros((M, M, N_PARAMS)),
                          np.zeros(N_SETTINGS), np.zeros(M, np.int64), np.zeros(0, np.int64),
                          np.zeros((0, 2), np.int64), np.zeros(0, np.int64),
                          np.zeros((0, N_PARAMS)), np.zeros((0, NODE_OUT_COLUMNS)), np.zeros((0, M, D)),
                          np.zeros((0, M)), area, np.zeros(0), np.zeros((0, 0, D)), np.zeros((0, 0)),
                          np.zeros((0, M)))
    n_lr = N if tables.uses_lr else 0
    if node_out is None:
        node_out = np.zeros((0, NODE_OUT_COLUMNS))
    n_pair = N if tables.uses_lr and tables.explicit_three_material else 0
    n_pairs = M * (M - 1) // 2 if n_pair else 0
    return PairTables(thick, tables.law_kind, tables.law_params, tables.settings, tables.rigid,
                      tables.node_zone, tables.zone_pairs, tables.zone_kind, tables.zone_params,
                      node_out, tables.node_normals(N, D), np.zeros((n_lr, M)), area, tables.df_curve,
                      np.zeros((n_pair, n_pairs, D)), np.zeros((n_pair, n_pairs)),
                      np.zeros((n_lr if tables.rigid.any() and tables.settings[S_SEPARATION] == SEP_LR
                                else 0, M)))


def blocks(buffers) -> Blocks:
    return Blocks(*buffers.arrays())


def step_control(model) -> StepControl:
    """The switches of ``model`` (:class:`mpm.solver.Model`)."""
    opts, tb = model.opts, model.tables
    with_interface = tb is not None and tb.has_interfaces
    mass_tol = 0.0
    if tb is not None and tb.uses_lr:
        from .multimaterial_constants import S_MASS_TOL
        mass_tol = float(tb.settings[S_MASS_TOL])
    return StepControl(float(model.dt), float(model.ramp_time), int(model.ramp_code),
                       0.0 if opts["xpic"] else float(opts["pic"]),
                       int(UPDATE_CODES[opts["update"]]),
                       opts["damping"] == "kinetic", opts["nodal_displacement"] == "linear",
                       bool(with_interface), bool(with_interface and not model.force_limiting),
                       bool(tb is not None and tb.uses_lr), mass_tol,
                       model.case.analysis == "axisymmetric", model.C,
                       bool(np.any(model.material_kind)), model.material_kind,
                       model.material_params, int(opts["xpic"]), float(opts["pic"]),
                       bool(opts["xpic_correction"]))
