"""``mpm.solve``: explicit (multimaterial) MPM run of a Case to its quasi-static state.

Step sequence (004 Sec 3.2, Eq 26-34; mpm/LAYOUT.md): P2G -> contact correction
phase 0 -> imperfect-interface forces (000 Eq 17-27) -> momentum update with grid
damping and nodal conditions -> contact correction phase 1 -> G2P (FLIP, PIC blend) ->
stress update (USL; USF, MUSL optional). Every run executes whole chunks of steps of
the one compiled time step (:func:`mpm.step.run_steps`) on the state bundles of
:mod:`mpm.state`; Python runs only between output intervals.

Tractions are ramped over ``ramp_time`` (linearly, or along the cosine ramp the case
gives them); prescribed displacements and velocities follow their own ramps
(``mpm.boundary``); grid damping (or kinetic damping)
removes the dynamic response so that the run settles on the static answer; the run
stops when, after the ramp, kinetic energy stays below ``tol`` x (strain +
interface energy) for half an estimated fundamental period and the mean stored energy
of that half period is within ``tol_energy`` of the half period before, or at
``max_time``.
"""
from __future__ import annotations

import math
import os
import signal
import threading
import time

import numpy as np

from interfaces.errors import CaseError, SolverError
from interfaces.numba_cache import cache_is_cold
from interfaces.result import Result

from . import axisymmetric as AX
from . import checkpoint
from . import state as S
from .boundary import ghost_nodes, nodal_conditions, ramp_code, with_axis_conditions
from .finite_strain import (LINEAR, MIE_GRUNEISEN, eos_state, material_tables,
                            unsupported_material)
from .signal_speed import max_signal_speed
from .shock_front import ShockFrontGauge
from .contact_gauge import AxialStressGauge, ContactGauge
from .interpenetration import interpenetration_quantities
from .gauges import StressGauges
from .grid import Grid, NodalFields
from .parallel import p2g_range
from .measure import bulk_quantities, interface_profile, line_profiles, stiffness_quantities
from .options import merge
from .particles import apply_tractions, generate
from .progress import ProgressBar, compile_notice
from .rigid import with_rigid_conditions
from .cpdi import CPDI_SHAPES, cpdi_refusal, reference_scatter_cpdi
from .shape import SHAPE_CODES
from .step import run_steps
from .vtk import write_vtk_series

from .multimaterial_constants import (OUT_AREA, OUT_STATUS, S_FORCE_LIMIT, STATUS_INTERFACE,
                                      STATUS_LIMITED_N, STATUS_LIMITED_T)

#: warn about force-limited interface nodes when min(D) h / E is below this and they
#: hold more than this fraction of the interface's contact area (000 Eq 20)
LIMITED_COMPLIANCE_RATIO = 10.0
LIMITED_AREA_FRACTION = 0.05


def _law_stiffnesses(law, names=("Dn", "Dt", "Dn_tension")) -> list[float]:
    """Finite, nonzero stiffnesses (MPa/mm) of an interface law's springs ``names``."""
    values = [getattr(law, name, None) for name in names]
    return [float(v) for v in values
            if isinstance(v, (int, float)) and math.isfinite(v) and v > 0.0]


#: the springs of each direction, by law attribute (normal: 000 Eq 17 D_n, tangential D_t)
_DIRECTION_SPRINGS = {"normal": ("Dn", "Dn_tension", "Dn_compression"), "tangential": ("Dt",)}


#: adaptive damping follows periods up to this multiple of the axial estimate T1 = 4 L / c
MAX_PERIOD_RATIO = 50.0

#: samples of the gauges over the pulse duration (the shortest load ramp)
GAUGE_SAMPLES = 100

#: steps per compiled chunk of a run with finite-strain fields (dt is recomputed between
#: chunks from the current state, :meth:`Model.current_time_step`)
STATE_DT_CHUNK = 10

HIST_COLUMNS = ("time", "kinetic", "strain", "work_ext", "dissipated", "work_bc", "interface",
                "kinetic_grid")


def _energy_ratio_text(kinetic: float, stored: float) -> str:
    """KE/U of the progress line; before any strain energy is stored (a body moving
    freely toward contact) the ratio is meaningless and is not shown."""
    if stored > 1e-12 * kinetic and stored > 0.0:
        return f"KE/U={kinetic / stored:.2e}"
    return "KE/U=- (U = 0)"


def supports(case) -> str | None:
    """None when MPM can run ``case``, else the one-line reason (used by ``imperfect list``
    and ``--methods all``, so no method is advertised for a case it refuses)."""
    if case.analysis not in ("plane_stress", "plane_strain", "axisymmetric", "3d"):
        return (f"analysis {case.analysis!r} is not supported; the MPM core implements "
                "plane_stress, plane_strain, axisymmetric and 3d")
    if case.analysis == "axisymmetric":
        lo, _ = case.bounds()
        if lo[0] < 0.0:
            return (f"axisymmetric bodies must lie at r = x >= 0, the case reaches x = "
                    f"{lo[0]:g} mm")
    return unsupported_material(case)


class Model:
    """Everything a run needs: grid, particles, nodal fields, loads, conditions, tables."""

    def __init__(self, case, opts: dict):
        reason = supports(case)
        if reason is not None:
            raise CaseError(f"mpm: {reason}")
        self.case = case
        self.opts = opts
        lo, hi = case.bounds()
        self.grid = Grid.around(lo, hi, opts["cell"], opts["padding"], opts["grid_anchor"])
        self.kind = SHAPE_CODES[opts["shape"]]
        self.cpdi = opts["shape"] in CPDI_SHAPES
        reason = cpdi_refusal(case, opts["shape"])
        if reason is not None:
            raise CaseError(f"mpm option shape: {reason}")
        self.particles = generate(case, self.grid, opts["ppc"])
        if self.kind == SHAPE_CODES["linear"]:
            self.particles.lp[:] = 0.0
        D = self.grid.D
        self.loads = apply_tractions(case, self.particles, D)
        for name, vel in opts["initial_velocity"].items():        # an impact at t = 0
            self.particles.v[self.particles.field == case.body_index(name)] = vel
        self.initial_kinetic = 0.5 * float(np.einsum("p,pd,pd->", self.particles.mass,
                                                     self.particles.v, self.particles.v))
        self.particles.foff0 = self.particles.foff.copy()   # finite strain: foff = F foff0
        self.M = len(case.bodies)
        self.nodal = NodalFields(self.grid.N, self.M, D)
        mats = [case.materials[b.material] for b in case.bodies]
        self.axisymmetric = case.analysis == "axisymmetric"
        if self.axisymmetric and opts["update"] == "usf":
            raise CaseError("mpm option update: 'usf' is not available in axisymmetric runs; "
                            "use usl, musl or auto")
        C = [m.stiffness(case.analysis) for m in mats]
        if self.axisymmetric:
            C = [AX.stiffness_rzt(c) for c in C]   # particle order [rr, zz, rz, tt]
        self.C = np.ascontiguousarray(np.array(C, float))
        # the stress update of each field: small-strain linear or finite-strain (F)
        self.material_kind, self.material_params = material_tables(case, float(np.min(self.grid.cell)))
        self.particles.eos = eos_state(self.particles.P, self.material_kind)
        self.mie_gruneisen = bool(np.any(self.material_kind == MIE_GRUNEISEN))
        self.tracks_F = bool(np.any(self.material_kind)) or self.cpdi    # particles carry F
        self.rho0 = np.array([m.rho for m in mats], float)
        self.tables = None
        self.node_out = None
        rigid = np.zeros(self.M, bool)
        if self.M > 1:
            from . import multimaterial as mm
            self.tables = mm.build_pair_tables(case, opts, node_coordinates=self.grid.node_positions())
            if D == 3 and self.tables.uses_lr:
                raise CaseError("mpm options normal / separation 'LR' (logistic regression, 004 "
                                "Eq 19-25) are 2D only; in 3d use normal SN, MVG, AVG or AG")
            self.node_out = np.zeros((self.grid.N, mm.NODE_OUT_COLUMNS))
            rigid = self.tables.rigid.astype(bool)
        if rigid.all():
            raise CaseError("mpm option rigid_bodies: at least one body must be deformable")
        self.rigid = rigid
        # rigid bodies driven by a velocity or displacement do work that the run's energy
        # sums do not track (their motion is imposed on the grid, not forced)
        self.moving_rigid = sorted({bc.body for bc in case.boundary_conditions
                                    if bc.kind in ("velocity", "displacement") and bc.body != "*"
                                    and rigid[case.body_index(bc.body)]})
        for k, bc in enumerate(case.boundary_conditions):
            if bc.kind == "traction" and rigid[case.body_index(bc.body)]:
                raise CaseError(f"boundary_conditions[{k}]: body {bc.body!r} is rigid; give it a "
                                "velocity or displacement instead of a traction")
        # time scales: CFL step and an estimated lowest period T1 = 4 L / c (fixed-free bar),
        # from the deformable bodies (a rigid body's material only sets its mass)
        deformable = [(C, m) for C, m, r in zip(self.C, mats, rigid) if not r]
        c_max = max(m.wave_speed(case.analysis) for _, m in deformable)
        self.wave_speed = c_max
        c_min = min(math.sqrt(min(np.diag(C)[:D]) / m.rho) for C, m in deformable)
        dt_stable = float(np.min(self.grid.cell)) / c_max      # one cell per wave transit
        if opts["dt"] and opts["dt"] > dt_stable:
            raise CaseError(f"mpm option dt = {opts['dt']:.3g} s is above the stable explicit limit "
                            f"cell / wave speed = {dt_stable:.3g} s; lower dt or leave it to cfl")
        self.dt = opts["dt"] or opts["cfl"] * dt_stable
        if self.mie_gruneisen and opts["dt"]:
            raise CaseError("mpm option dt: runs with Mie-Grueneisen materials take their time "
                            "step from the current wave speeds (option cfl); leave dt unset")
        # finite-strain fields stiffen as they deform: unless dt is given, it follows the
        # current state between chunks of steps (rigid fields keep F = I)
        self.state_dt = not opts["dt"] and bool(np.any(self.material_kind[~rigid] != LINEAR))
        if self.state_dt:
            self.dt = min(self.dt, self.current_time_step())
        length = float(np.max(hi - lo))
        self.T1 = 4.0 * length / c_min
        self.ramp_time, self.ramp_code = _traction_ramp(self.loads, opts["ramp_time"], self.T1)
        # lowest period of the loaded deformation: starts at T1, then follows the Rayleigh
        # quotient of the current displacement field (adaptive damping, see rayleigh_period)
        self.period = self.T1
        self.fixed_max_time = opts["max_time"] is not None
        self.max_time = opts["max_time"] or self.ramp_time + 40.0 * self.T1
        self.adaptive_alpha = opts["damping"] == "grid" and opts["alpha"] is None
        if opts["damping"] == "grid":
            self.alpha = opts["alpha"] if opts["alpha"] is not None else 2.0 * (2.0 * math.pi / self.T1)
        else:
            self.alpha = 0.0
        if self.alpha * self.dt > 0.5:
            if opts["alpha"] is not None:
                raise CaseError(f"mpm option alpha = {self.alpha:g} 1/s is too large for dt = {self.dt:g} s "
                                "(alpha dt must be <= 0.5): lower alpha")
            raise CaseError(f"mpm time step dt = {self.dt:.3g} s is too long for the grid damping the "
                            f"specimen needs (2 omega = {self.alpha:.3g} 1/s, alpha dt must be <= 0.5): "
                            f"lower dt (or cfl) below {0.5 / self.alpha:.3g} s")
        # particle tails reach one cell beyond the edges of a side (B2 always, uGIMP once
        # the particles move): with B2 every condition covers that band, in 3D the
        # symmetry faces do (conditions on the side's normal component only), so that a
        # symmetry face holds every node of the particles on it; 2D uGIMP / linear runs
        # keep the side's extent, as their results always had
        b2 = self.kind in (SHAPE_CODES["b2"], SHAPE_CODES["b2cpdi"])
        self.bcs = nodal_conditions(case, self.grid, self.ramp_time,
                                    band="all" if b2 else ("normal" if D == 3 else "none"))
        self.axis_nodes = np.zeros(0, np.int64)
        if self.axisymmetric:
            self.axis_nodes = AX.axis_nodes(self.grid.node_positions(), self.grid.cell)
            self.bcs = with_axis_conditions(self.bcs, self.axis_nodes, self.M)
        if rigid.any():
            self.bcs = with_rigid_conditions(case, self.bcs, rigid, self.grid.N, self.grid.D,
                                             self.ramp_time)
        if b2:
            if opts["update"] == "usf":
                raise CaseError(f"mpm option update: 'usf' is not available with shape "
                                f"{opts['shape']!r} (its "
                                "symmetry sides fold the internal force before the stress "
                                "update); use usl, musl or auto")
            self.bcs.ghosts = ghost_nodes(case, self.grid, self.bcs)
        if opts["update"] == "auto":
            opts["update"] = "usl" if _grid_aligned(case, self.grid) else "musl"
        self.force_limiting = self.tables is None or \
            bool(self.tables.settings[S_FORCE_LIMIT] != 0.0)

    @property
    def damped(self) -> bool:
        """A quasi-static run: damped, it stops when it comes to rest (an undamped run is
        dynamic and ends at max_time by design)."""
        return self.opts["damping"] != "none"

    def current_time_step(self, velgrad: np.ndarray | None = None) -> float:
        """cfl x cell / the largest signal speed of the finite-strain particles in their
        current state (:func:`mpm.signal_speed.max_signal_speed`; at least the wave speed
        of the run's materials at rest, which covers its linear fields)."""
        pt = self.particles
        D = pt.x.shape[1]
        deformable = np.where(self.rigid, LINEAR, self.material_kind)
        speed = max_signal_speed(pt.F, pt.eos, np.zeros((0, D, D)) if velgrad is None else velgrad,
                                 pt.v, pt.field, deformable, self.material_params, self.rho0)
        return self.opts["cfl"] * float(np.min(self.grid.cell)) / max(speed, self.wave_speed)

    def bundles(self, buffers) -> tuple:
        """The state bundles of :func:`mpm.step.run_steps` (views of this model's arrays;
        ``buffers`` the :class:`mpm.parallel.BlockBuffers` of P2G)."""
        g = self.grid
        # out-of-plane extent of a node's cell: the thickness, or r_i per radian (000 Eq 20)
        thickness = AX.node_radii(g.node_positions(), g.cell) if self.axisymmetric \
            else self.case.thickness
        return (S.step_control(self), S.particle_state(self.particles, self.axisymmetric,
                                                   self.opts["update"] == "musl",
                                                   bool(np.any(self.material_kind)),
                                                   self.opts["xpic"], self.cpdi),
                S.grid_spec(g, self.kind, self.axis_nodes),
                S.nodal_state(self.nodal, self.bcs.ghosts is not None and
                              self.bcs.ghosts.node.size > 0, self.opts["xpic"]),
                S.conditions(self.bcs),
                S.pair_tables(self.tables, self.node_out, thickness, g.N, self.M, g.D,
                              self.reference_area_volumes()),
                S.blocks(buffers))

    def reference_area_volumes(self) -> np.ndarray | None:
        """The nodal volumes of 000 Eq 20 with option interface_area = reference: one
        scatter of the particles' initial volumes from their initial positions
        (mpm.multimaterial.AREA_VOLUMES); None for the current volumes."""
        if self.tables is None or not self.tables.area_reference:
            return None
        g, pt = self.grid, self.particles
        nd = NodalFields(g.N, self.M, g.D)
        if self.cpdi:
            lost = reference_scatter_cpdi(pt, g, self.kind, nd)
        else:
            lost = p2g_range(0, pt.P, pt.x0, np.zeros_like(pt.x0), pt.mass, pt.volume0,
                             pt.stress, pt.field, pt.x0, g.origin, g.cell, g.nn, pt.lp, self.kind,
                             True, False, nd.mass, nd.momentum, nd.force, nd.volume,
                             nd.volume_gradient, nd.displacement, nd.position)
        if lost >= 0:
            raise SolverError(f"mpm: particle {lost} starts outside the background grid")
        return nd.volume


def _traction_ramp(loads: list[dict], option: float | None, T1: float) -> tuple[float, int]:
    """The one load ramp (time, kernel code) every traction follows: the ``ramp_time``
    option, else the tractions' own ramp time, else T1 (a quasi-static ramp); tractions
    with different ramps are refused (the compiled step scales all tractions by one
    load fraction)."""
    times = sorted({ld["ramp_time"] for ld in loads if ld["ramp_time"] is not None})
    names = sorted({ld["ramp"] for ld in loads})
    if len(times) > 1 or len(names) > 1:
        raise CaseError("boundary_conditions: mpm applies every traction with one load ramp, "
                        f"got ramp_time {times} and ramp {names}; give the tractions the same "
                        "ramp_time and ramp")
    ramp_time = option if option is not None else (times[0] if times else T1)
    return ramp_time, ramp_code(names[0] if names else "linear", "boundary_conditions[traction]")


def rayleigh_period(mass: np.ndarray, volume: np.ndarray, C_particle: np.ndarray,
                    du: np.ndarray, dstrain: np.ndarray) -> float:
    """Period 2 pi / omega of the Rayleigh quotient omega^2 = du.K du / du.M du of a
    displacement increment (adaptive dynamic relaxation, Underwood 1983).

    ``du`` (P, D) and ``dstrain`` (P, nv, engineering shear) are the particle
    displacement and strain increments over the last output interval, ``C_particle``
    (P, nv, nv) the particles' stiffness and ``volume`` their volume, so
    du.K du = sum_p V_p deps.C.deps and du.M du = sum_p m_p |du_p|^2. Late in a
    quasi-static run the increment is the slowest mode still creeping towards the static
    state (e.g. the bending of a block loaded in tension on one side), so the quotient
    tracks the mode that limits convergence. The interfacial energy of the increment is
    left out: for interface-dominated modes the estimate is low (damping below critical,
    which still converges, at rate alpha / 2). Returns inf when nothing moved.
    """
    mu2 = float(np.einsum("p,pd,pd->", mass, du, du))
    ku2 = float(np.einsum("p,pi,pij,pj->", volume, dstrain, C_particle, dstrain))
    if not (ku2 > 0.0 and mu2 > 0.0 and math.isfinite(ku2) and math.isfinite(mu2)):
        return math.inf
    return 2.0 * math.pi / math.sqrt(ku2 / mu2)


def _grid_aligned(case, grid: Grid) -> bool:
    """True when every body is an unrotated rectangle without holes whose exterior
    edges lie on grid lines (an edge shared with another body is interior and may sit
    anywhere). Then no free boundary cuts a cell and USL is exact for uniform states;
    otherwise nodes holding only particle tails appear along the boundary and MUSL
    (stress from re-extrapolated particle momenta) is needed for stability."""
    h = float(np.min(grid.cell))
    for k, body in enumerate(case.bodies):
        shape = body.shape
        if type(shape).__name__ not in ("Rectangle", "Box") or body.holes \
                or abs(getattr(shape, "angle", 0.0)) > 0.0:
            return False
        lo, hi = (np.asarray(b, float) for b in shape.bounds())
        for d in range(grid.D):
            for value, outward in ((lo[d], -1.0), (hi[d], 1.0)):
                q = (value - grid.origin[d]) / grid.cell[d]
                if abs(q - round(q)) <= 1e-9:
                    continue
                # off the grid lines: allowed only if the side is covered by other bodies
                t = np.linspace(0.05, 0.95, 7)
                pts = lo + np.outer(t, hi - lo) if grid.D == 2 else \
                    lo + np.stack(np.meshgrid(t, t, t, indexing="ij"), -1).reshape(-1, 3) * (hi - lo)
                pts[:, d] = value + outward * 1e-6 * h
                covered = np.zeros(len(pts), bool)
                for j, other in enumerate(case.bodies):
                    if j != k:
                        covered |= other.contains(pts)
                if not covered.all():
                    return False
    return True


def solve(case, **options) -> Result:
    """Run explicit multimaterial MPM on ``case`` and return a :class:`interfaces.Result`.

    Options (defaults in :data:`mpm.options.DEFAULTS`, then ``case.discretization['mpm']``,
    then these keywords): ``cell`` (mm), ``ppc``, ``shape`` (ugimp/linear/b2/cpdi/b2cpdi), ``cfl`` or
    ``dt``, ``damping`` (grid/kinetic/none) and ``alpha``, ``pic``, ``xpic`` and
    ``xpic_correction`` (XPIC(m), mpm/xpic.py), ``update`` (auto/usl/musl/usf),
    ``ramp_time``, ``max_time``, ``tol``, ``vtk_dir``, ``progress``; the multimaterial
    options of :data:`mpm.multimaterial.DEFAULT_OPTIONS` (normal, separation,
    area_correction, h_perp, force_limiting, edge_cutoff, default_law, ...).
    Quantities: stiffness (002 Eq 43), stiffness_energy (Eq 45), strain_energy,
    interface_energy, kinetic_energy, external_work, dissipated_energy.
    """
    t_start = time.perf_counter()
    reason = supports(case)
    if reason is not None:
        raise CaseError(f"mpm: {reason}")
    opts = merge(case, options)
    model = Model(case, opts)
    if opts["progress"] is not False:
        compile_notice(cache_is_cold(os.path.dirname(os.path.abspath(__file__))))
    t_setup = time.perf_counter() - t_start
    run = _Runner(model)
    run.run()
    t_run = run.wall()           # with the parts before a resume
    return _result(model, run, {"setup": t_setup, "run": t_run, "total": t_setup + t_run})


class _Runner:
    """Advances a :class:`Model` in output intervals; keeps histories and frames."""

    def __init__(self, model: Model):
        self.m = model
        self.t = 0.0
        self.steps = 0
        self.hist_chunks: list[np.ndarray] = []
        self.ke_prev = np.zeros(2)
        self.frames = []
        self.warnings: list[str] = []
        self.stopped_by = "max_time"
        self.snapshot = None  # (displacement, strain) at the previous interval end
        self.gauges: StressGauges | AxialStressGauge | None = None
        # force_limiting off: (steps with a node above the 000 Eq 26 bound, most such
        # nodes in one step, first time)
        self.over_limit = [0, 0, -1.0]
        self.bundles = None   # the state bundles of mpm.step, built at the first step
        self.last_save = time.perf_counter()
        self.started = time.perf_counter()
        self.wall_before = 0.0   # wall time (s) of the run's parts before a resume

    def wall(self) -> float:
        """Wall time (s) spent advancing this run, over all its parts (resumes)."""
        return self.wall_before + time.perf_counter() - self.started

    # -- one interval ----------------------------------------------------------
    def _advance(self, nsteps: int) -> np.ndarray:
        """``nsteps`` steps of the one compiled time step (:func:`mpm.step.run_steps`)."""
        m = self.m
        if self.bundles is None:
            from .parallel import BlockBuffers, default_blocks
            if getattr(self, "block_buffers", None) is None:
                # particle blocks of the race-free parallel P2G/G2P (mpm/parallel.py)
                self.block_buffers = BlockBuffers(default_blocks(m.particles.P), m.grid.N,
                                                  m.M, m.M > 1, m.grid.D)
            self.bundles = m.bundles(self.block_buffers)
        hist = np.zeros((nsteps, len(HIST_COLUMNS)))
        over = np.array(self.over_limit, dtype=float)
        done, lost = run_steps(nsteps, self.t, m.alpha, *self.bundles, hist, self.ke_prev, over)
        self.over_limit = [int(over[0]), int(over[1]), float(over[2])]
        self.steps += done
        if done:
            self.t = float(hist[done - 1, 0])
        if lost >= 0:
            raise SolverError(f"mpm: particle {lost} left the background grid at t = {self.t:.4g} s "
                              f"(step {self.steps}): the run is unstable or deforms beyond the "
                              "grid; reduce the time step (cfl), increase damping or lower Dn, "
                              "or increase the padding option" + self._advice())
        return hist[:done]

    # -- whole run -------------------------------------------------------------
    def run(self) -> None:
        m = self.m
        interval = self._interval()
        total_steps = int(math.ceil(m.max_time / m.dt))
        est_time = 1e-7 * m.particles.P * total_steps
        show = m.opts["progress"] if m.opts["progress"] is not None else est_time > 5.0
        # a damped run stops at rest, mostly long before max_time, which the bar measures
        damped = m.damped
        rest = f" (rest: < {m.opts['tol']:g})" if damped else ""
        bar = ProgressBar(f"mpm {m.case.name}", enabled=bool(show), open_ended=damped)
        vtk_every = max(1, total_steps // m.opts["vtk_frames"]) if m.opts["vtk_dir"] else 0
        resumed = self._resume()
        if resumed:
            total_steps = max(total_steps, int(math.ceil(m.max_time / m.dt)))
        next_frame = (self.steps // vtk_every + 1) * vtk_every if vtk_every else math.inf
        if vtk_every and not resumed:
            self._frame()
        cum_work = m.initial_kinetic + float(sum(h[:, 3].sum() + h[:, 5].sum()
                                                 for h in self.hist_chunks))
        shown = 0.0
        with _InterruptFlag(enabled=bool(m.opts["checkpoint"])) as interrupt:
            while self.steps < total_steps:
                n = min(interval, total_steps - self.steps, next_frame - self.steps)
                h = self._advance(n)
                self.hist_chunks.append(h)
                if self.gauges is not None:
                    self.gauges.sample(self.t, m.particles)
                cum_work += h[:, 3].sum() + h[:, 5].sum()
                self._check_energies(h, cum_work)
                if self.steps >= next_frame:
                    self._frame()
                    next_frame += vtk_every
                # the step limit grows when a slower mode is found: never move the bar back
                shown = max(shown, self.steps / total_steps)
                bar.update(shown, f"t={self.t:.3g}s {_energy_ratio_text(h[-1, 7], h[-1, 2] + h[-1, 6])}{rest}")
                total_steps = self._adapt(total_steps)
                if m.state_dt:
                    total_steps = self._state_time_step()
                window = int(math.ceil(0.5 * m.period / m.dt))
                if self.t > m.ramp_time and self._settled(window):
                    self.stopped_by = "kinetic_energy"
                    break
                self._checkpoint(interrupt)
        bar.close(f"{self.steps} steps, stopped by {self.stopped_by}")
        if self.stopped_by == "max_time" and damped:
            # an undamped run is dynamic: it ends at max_time by design
            self.warnings.append(
                f"mpm: reached max_time = {m.max_time:.4g} s before kinetic energy fell below "
                f"tol = {m.opts['tol']:g} x stored energy; increase max_time or damping")
        if self.over_limit[0]:
            self.warnings.append(self._over_limit_text())
        limited = self._limited_text()
        if limited:
            self.warnings.append(limited)
        if vtk_every and self.frames and self.frames[-1][0] < self.t:
            self._frame()

    def _state_time_step(self) -> int:
        """Finite-strain runs: dt from the current state (Model.current_time_step) for the
        next chunk; returns the total number of steps that reaches max_time with it."""
        m = self.m
        m.dt = m.current_time_step(self.bundles[1].velgrad)
        self.bundles = (S.step_control(m),) + tuple(self.bundles[1:])
        remaining = (m.max_time - self.t) / m.dt
        return self.steps + (int(math.ceil(remaining - 1e-6)) if remaining > 1e-6 else 0)

    def _interval(self) -> int:
        """Steps per output interval (a quarter of T1; the gauges of 002 Sec 3.3 sample
        the pulse, the shortest load ramp, ~GAUGE_SAMPLES times; the contact gauge of
        004 Fig 2 every ``sample_every`` seconds)."""
        m = self.m
        interval = max(1, int(math.ceil(0.25 * m.T1 / m.dt)))
        body_gauges = [g for g in (ContactGauge, AxialStressGauge) if g.measurement in m.case.measurements]
        if body_gauges:
            self.gauges = body_gauges[0](m.case, m.particles.field, m.C)
            interval = min(interval, max(1, int(self.gauges.sample_every / m.dt)))
            self.gauges.sample(self.t, m.particles)
        elif ShockFrontGauge.measurement in m.case.measurements:
            self.gauges = ShockFrontGauge(m.case, m.particles.x0, m.particles.spacing)
            self.gauges.sample(self.t, m.particles)
        elif m.case.measurements.get("transmitted_energy") is not None:
            self.gauges = StressGauges(m.case, m.particles.x0, m.particles.spacing)
            ramps = [bc.ramp_time for bc in m.case.boundary_conditions if bc.ramp_time]
            pulse = min(ramps + [m.ramp_time])
            interval = min(interval, max(1, int(pulse / (GAUGE_SAMPLES * m.dt))))
            self.gauges.sample(self.t, m.particles)
        if m.state_dt:
            interval = min(interval, STATE_DT_CHUNK)
        return interval

    def _check_energies(self, h: np.ndarray, cum_work: float) -> None:
        """SolverError when the energies of the last interval are not finite or the
        kinetic + stored energy exceeds ``blowup`` x the work done (not judged when driven
        rigid bodies do work the sums do not track: NaN and lost particles still stop)."""
        m = self.m
        U, ui = h[-1, 2], h[-1, 6]
        if not (np.all(np.isfinite(h[:, 1:])) and math.isfinite(cum_work)):
            raise SolverError(self._diverged("energies became NaN/inf"))
        if m.moving_rigid:
            return
        scale = abs(cum_work) + 1e-12 * (1.0 + U)
        if h[:, 1].max() + U + ui > m.opts["blowup"] * scale and self.t > 0.05 * m.ramp_time:
            raise SolverError(self._diverged(
                f"kinetic + stored energy {h[:, 1].max() + U + ui:.3g} exceeds "
                f"{m.opts['blowup']:g} x the work done {cum_work:.3g}"))

    def _resume(self) -> bool:
        """Continue from the checkpoint (option ``resume``) when one exists."""
        path = self.m.opts["checkpoint"]
        if not (self.m.opts["resume"] and path and os.path.exists(path)):
            return False
        checkpoint.load(path, self.m, self)
        return True

    def _checkpoint(self, interrupt: "_InterruptFlag") -> None:
        """Save the state every ``checkpoint_every`` seconds of wall time, and on Ctrl-C
        (then stop with KeyboardInterrupt): always between two intervals, where the
        state is consistent."""
        path = self.m.opts["checkpoint"]
        if not path:
            return
        now = time.perf_counter()
        if interrupt.raised or now - self.last_save >= self.m.opts["checkpoint_every"]:
            checkpoint.save(path, self.m, self)
            self.last_save = now
        if interrupt.raised:
            raise KeyboardInterrupt

    def _adapt(self, total_steps: int) -> int:
        """Follow the slowest mode still moving (:func:`rayleigh_period` of the last
        interval's increment): grid damping alpha = 2 omega (critical for that mode; the
        axial T1 = 4 L / c over-damps e.g. the bending of a block loaded on one side,
        whose static state is then approached by a slow creep that a kinetic-energy test
        mistakes for rest), the settling window and, unless max_time was given, the time
        limit ramp + 40 periods (periods capped at MAX_PERIOD_RATIO x T1). Returns the
        updated total number of steps."""
        m = self.m
        pt = m.particles
        u, strain = pt.x - pt.x0, pt.strain.copy()
        prev, self.snapshot = self.snapshot, (u, strain)
        if prev is None:
            return total_steps
        period = rayleigh_period(pt.mass, pt.volume0, m.C[pt.field], u - prev[0], strain - prev[1])
        if not math.isfinite(period):
            return total_steps
        # the slowest mode seen so far sets the damping: once the creep of a slow mode has
        # been seen, its period is kept (late increments of a critically damped run are
        # small and can be dominated by faster oscillations, which would raise alpha and
        # make the slow mode creep again); never faster than the axial estimate T1
        m.period = min(max(m.period, period), MAX_PERIOD_RATIO * m.T1)
        if m.adaptive_alpha:
            m.alpha = min(2.0 * (2.0 * math.pi / m.period), 0.5 / m.dt)
        if not m.fixed_max_time:
            m.max_time = max(m.max_time, m.ramp_time + 40.0 * m.period)
            total_steps = max(total_steps, int(math.ceil(m.max_time / m.dt)))
        return total_steps

    def _settled(self, window: int) -> bool:
        """Static state reached: over the last ``window`` steps (half a period) the grid
        kinetic energy stays below ``tol`` x stored energy, and the mean stored (strain +
        interfacial) energy of those steps differs from that of the ``window`` steps
        before by less than ``tol_energy`` of itself (an over-damped mode creeps with
        almost no kinetic energy).

        Means, not the spread: a vibration of energy e about the static state changes the
        stored energy U by up to 2 sqrt(e U) (the cross term with the static
        deformation), 2e-3 U at the kinetic-energy bound e = 1e-6 U, and a free slender
        specimen (the DCB at 0.3 mm cells) keeps a residual vibration of 1e-7 U, which
        spread it by 1e-4 U per output interval until max_time; a creep moves both tests
        alike."""
        recent = self._last_steps(2 * window)
        if recent is None:
            return False
        stored_hist = recent[:, 2] + recent[:, 6]
        stored = stored_hist[-1]
        if not (stored > 0 and recent[window:, 7].max() < self.m.opts["tol"] * stored):
            return False
        creep = float(stored_hist[window:].mean() - stored_hist[:window].mean())
        return abs(creep) < self.m.opts["tol_energy"] * stored

    def _last_steps(self, count: int) -> np.ndarray | None:
        """The history rows of the last ``count`` steps (None before there are as many)."""
        chunks, total = [], 0
        for h in reversed(self.hist_chunks):
            chunks.append(h)
            total += h.shape[0]
            if total >= count:
                break
        if total < count:
            return None
        return np.vstack(chunks[::-1])[-count:]

    def _over_limit_text(self) -> str:
        n_steps, n_max, t0 = self.over_limit
        return (f"mpm: force_limiting is off and imperfect-interface forces exceeded the "
                f"stability bound of 000 Eq 26 (the force that brings both fields to their "
                f"centre of mass in one step) on {n_steps} steps (up to {n_max} nodes, first "
                f"at t = {t0:.4g} s): the explicit interface is unstable there and the "
                "results are unreliable; enable force_limiting, lower Dn/Dt or reduce dt (cfl)")

    def _limited_text(self) -> str:
        """Warning when force limiting (000 Eq 23-27) holds interface nodes perfect at the
        end although the law's compliance is not negligible: the explicit bound
        D A dt^2 > m_red is a property of the time step and the nodal masses, not of the
        physics, and a limited node has no spring compliance (stiffer answer)."""
        m = self.m
        if m.tables is None or not m.tables.has_interfaces or not m.force_limiting:
            return ""
        status = m.node_out[:, OUT_STATUS].astype(np.int64)
        active = (status & int(STATUS_INTERFACE)) != 0
        area = m.node_out[:, OUT_AREA]
        E = max(float(np.max(np.diag(C)[:2])) for C in m.C)
        h = float(np.min(m.grid.cell))
        active_area = float(area[active].sum())
        laws = [law for pair in m.case.interfaces
                for law in [pair.law] + [zone_law for _, zone_law in pair.zones]]
        worst = None
        for direction, flag in (("normal", STATUS_LIMITED_N), ("tangential", STATUS_LIMITED_T)):
            limited = active & ((status & int(flag)) != 0)
            # nodes holding only particle tails of one field have tiny reduced masses and
            # are limited at any stiffness, harmlessly: judge by the Eq 20 contact area
            share = float(area[limited].sum()) / active_area if active_area > 0.0 else 0.0
            # a limited direction whose springs are all perfect (D = inf) is exact
            stiff = [D for law in laws
                     for D in _law_stiffnesses(law, _DIRECTION_SPRINGS[direction])]
            if not limited.any() or share < LIMITED_AREA_FRACTION or not stiff:
                continue
            ratio = min(stiff) * h / E
            if ratio < LIMITED_COMPLIANCE_RATIO and (worst is None or ratio < worst[2]):
                worst = (direction, int(limited.sum()), ratio, share)
        if worst is None:
            return ""
        direction, count, ratio, share = worst
        return (f"mpm: force limiting (000 Eq 23-27) holds the {direction} direction of "
                f"{count} of {int(active.sum())} interface nodes ({share:.0%} of the contact area) perfect at the end of the run: "
                f"there D A dt^2 exceeds the reduced nodal mass, so the spring is not resolved "
                f"by this time step, yet its compliance is not negligible (D h / E = "
                f"{ratio:.3g} < {LIMITED_COMPLIANCE_RATIO:g}); the result is stiffer than "
                f"the law. Lower cfl (dt = {m.dt:.3g} s) until no node is limited")

    def _advice(self) -> str:
        if self.m.tables is not None and self.m.tables.has_interfaces and not self.m.force_limiting:
            extra = f" ({self._over_limit_text()})" if self.over_limit[0] else ""
            return ("; the interface is stiff for explicit integration without force "
                    "limiting: enable force_limiting (000 Eq 23-27), lower Dn/Dt or reduce "
                    f"dt (cfl){extra}")
        return ""

    def _diverged(self, what: str) -> str:
        """The divergence message: the remedies that apply to this run (damping only where
        the run is damped, Dn/Dt only where it has imperfect interfaces)."""
        m = self.m
        remedies = [f"reduce the time step (cfl, now dt = {m.dt:.3g} s)"]
        if m.damped:
            remedies.append(f"increase damping (alpha = {m.alpha:.3g} 1/s)")
        if m.tables is not None and m.tables.has_interfaces:
            remedies.append("lower the interface stiffness Dn/Dt")
        advice = remedies[0] if len(remedies) == 1 else \
            ", ".join(remedies[:-1]) + " or " + remedies[-1]
        return (f"mpm diverged at t = {self.t:.4g} s (step {self.steps}): {what}. "
                f"{advice[0].upper()}{advice[1:]}" + self._advice())

    def _frame(self) -> None:
        pt = self.m.particles
        fields = {"displacement": pt.x - pt.x0, "velocity": pt.v.copy(), "stress": pt.stress.copy(),
                  "material": pt.field.astype(np.int64)}
        if self.m.tracks_F:
            fields["deformation_gradient"] = pt.F.reshape(pt.P, 9).copy()
        self.frames.append((self.t, pt.x.copy(), fields))

    def history(self) -> np.ndarray:
        return np.vstack(self.hist_chunks) if self.hist_chunks else np.zeros((0, len(HIST_COLUMNS)))


class _InterruptFlag:
    """Within the block, Ctrl-C (SIGINT) only sets ``raised``: the run stops at the end
    of the current interval, with a consistent state to save (a KeyboardInterrupt while
    the compiled step returns could leave the particles a chunk ahead of the clock).
    Inactive (Ctrl-C raises at once) when ``enabled`` is False or off the main thread."""

    def __init__(self, enabled: bool):
        self.enabled = enabled and threading.current_thread() is threading.main_thread()
        self.raised = False
        self._previous = None

    def __enter__(self) -> "_InterruptFlag":
        if self.enabled:
            self._previous = signal.signal(signal.SIGINT, self._handle)
        return self

    def _handle(self, signum, frame) -> None:
        if self.raised:                    # a second Ctrl-C: stop now
            raise KeyboardInterrupt
        self.raised = True

    def __exit__(self, *exc) -> None:
        if self.enabled:
            signal.signal(signal.SIGINT, self._previous)


def _result(model: Model, run: _Runner, timings: dict) -> Result:
    case, pt, opts = model.case, model.particles, model.opts
    hist = run.history()
    last = hist[-1] if hist.size else np.zeros(len(HIST_COLUMNS))
    work = float(hist[:, 3].sum() + hist[:, 5].sum()) + model.initial_kinetic
    diss = float(hist[:, 4].sum())
    strain_e, ke, u_int = float(last[2]), float(last[1]), float(last[6])
    q = {"strain_energy": strain_e, "interface_energy": u_int, "kinetic_energy": ke,
         "kinetic_energy_grid": float(last[7]),
         "external_work": work, "dissipated_energy": diss,
         "energy_balance_error": (work - strain_e - u_int - ke - diss) / max(abs(work), 1e-300)}
    if model.initial_kinetic:
        q["initial_kinetic_energy"] = model.initial_kinetic
        q["external_work"] = work - model.initial_kinetic
    if model.moving_rigid:
        del q["energy_balance_error"]
        run.warnings.append(f"mpm: no energy balance: the work of the driven rigid bodies "
                            f"({', '.join(model.moving_rigid)}) is not in external_work")
    res = Result(method="mpm", case_name=case.name)
    q.update(stiffness_quantities(case, pt, model.loads, strain_e + u_int, res))
    if model.axisymmetric:
        # the run is per radian (000 Sec 2.3); report the whole ring, as FEM does
        for key in _RING_QUANTITIES:
            if key in q:
                q[key] *= 2.0 * math.pi
    q.update(bulk_quantities(case, pt, q["strain_energy"] + q["interface_energy"],
                             2.0 * math.pi if model.axisymmetric else 1.0))
    D = pt.x.shape[1]
    q.update(interpenetration_quantities(case, pt.x, pt.field, pt.volume, pt.volume0, pt.spacing,
                                         pt.F[:, :D, :D] if model.tracks_F else None))
    if run.gauges is not None:
        q.update(run.gauges.quantities())
        res.diagnostics["gauges"] = run.gauges.history()
    res.quantities = q
    res.fields = {"position": pt.x0.copy(), "displacement": pt.x - pt.x0,
                  "stress": pt.stress.copy(), "strain": pt.strain.copy(),
                  "material": pt.field.copy(), "velocity": pt.v.copy(),
                  "volume": pt.volume0.copy()}
    if model.tracks_F:
        res.fields["deformation_gradient"] = pt.F.reshape(pt.P, 9).copy()
    spacing = float(np.max(np.asarray(model.grid.cell, float) / np.asarray(opts["ppc"], float)))
    res.profiles.update(line_profiles(case, pt.x0, pt.x - pt.x0, spacing))
    if model.node_out is not None and u_int != 0.0:
        for k, pair in enumerate(case.interfaces):
            ab = (case.body_index(pair.a), case.body_index(pair.b))
            prof = interface_profile(model.grid, model.node_out, model.nodal.mass, ab)
            if prof is not None:
                res.profiles["interface_jump" if k == 0 else f"interface_jump[{pair.a}|{pair.b}]"] = prof
    if opts["vtk_dir"]:
        res.diagnostics["vtk_series"] = str(write_vtk_series(opts["vtk_dir"], run.frames,
                                                            prefix=case.name))
    step = max(1, hist.shape[0] // opts["history_points"])
    res.timings = dict(timings)
    res.timings["particle_steps_per_s"] = pt.P * run.steps / max(timings["run"], 1e-12)
    res.diagnostics.update({
        "time_steps": run.steps, "dt": model.dt, "time": run.t, "ramp_time": model.ramp_time,
        "max_time": model.max_time, "T1_estimate": model.T1, "period_estimate": model.period,
        "alpha": model.alpha, "adaptive_damping": model.adaptive_alpha,
        "particles": pt.P, "nodes": model.grid.N, "cell": model.grid.cell.tolist(),
        "ppc": opts["ppc"], "shape": opts["shape"], "update": opts["update"],
        "damping": opts["damping"], "stopped_by": run.stopped_by,
        "history": {name: col[::step].tolist()
                    for name, col in zip(HIST_COLUMNS, _cumulative(_ring(model, hist)).T)},
        "warnings": list(res.diagnostics.get("warnings", [])) + run.warnings,
    })
    return res


#: extensive quantities scaled from per radian to the whole ring in axisymmetric runs
_RING_QUANTITIES = ("strain_energy", "interface_energy", "kinetic_energy", "kinetic_energy_grid",
                    "external_work", "dissipated_energy", "load", "stiffness",
                    "stiffness_particle_rows", "stiffness_energy")


def _ring(model: Model, hist: np.ndarray) -> np.ndarray:
    """The energy history of an axisymmetric run (per radian) for the whole ring, as its
    quantities; others unchanged."""
    if not model.axisymmetric:
        return hist
    out = hist.copy()
    out[:, 1:] *= 2.0 * math.pi
    return out


def _cumulative(hist: np.ndarray) -> np.ndarray:
    """History with the per-step work and dissipation columns summed up to each time."""
    out = hist.copy()
    for k in (3, 4, 5):
        out[:, k] = np.cumsum(hist[:, k])
    return out
