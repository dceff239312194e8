"""Multimaterial node handling: contact, perfect bonds and imperfect interfaces.

Reference: 000 = Nairn, CMES 2013 (imperfect interfaces in multimaterial MPM);
002 = Nairn, numerical implementation of imperfect interfaces (Sec 2.4);
004 = Nairn et al., MPM contact by logistic regression, two corrections per step.

Data layout (shared with the MPM time loop, see mpm/LAYOUT.md): M material fields,
one per body (field index = body index in ``case.bodies``), D = 2 or 3, N nodes with
a flattened node index.  Nodal arrays are float64 and C-contiguous:

* ``mass[N, M]``, ``momentum[N, M, D]``, ``force[N, M, D]``;
* ``volume[N, M]`` = sum_p S_ip V_p (000 Eq 19; V_p is the particle volume, in 2D the
  particle area times the out-of-plane thickness, so volumes are in mm^3);
* ``volume_gradient[N, M, D]`` = sum_p G_ip V_p (000 Eq 33; points *out of* the field);
* ``displacement[N, M, D]`` = sum_p S_ip m_p (x_p - x_p0) / m_i (000 Eq 13);
* ``position[N, M, D]`` = sum_p S_ip m_p x_p / m_i (000 Eq 10);
* ``cell = [dx, dy(, dz)]``; ``thickness`` is a float64 array of length 1 (planar 2D
  thickness t, or 1.0 in 3D) or of length N (axisymmetric: the node radius r_i, with
  V_p = A_p r_p per radian, 000 Sec 2.3).

Call order in one time step (004 Sec 3.2, "two contact corrections per step"):

1. extrapolate (P2G) -> ``correct_momentum(0, ...)`` (contact-corrected extrapolation,
   004 Eq 26; changes momenta only, not forces);
2. internal + external forces -> ``add_interface_forces(...)`` (000 Eq 17-27);
3. momentum update p += f dt -> ``correct_momentum(1, ...)`` (004 Eq 31), which also adds
   the contact force Delta p+ / dt to ``force`` so the particle acceleration uses
   f_C,1 of 004 Eq 33-34;
4. G2P with the corrected momenta and forces.

With ``normal="LR"`` or ``separation="LR"`` (004 Sec 3.1) the caller computes, once
per step after P2G, ``lr = lr_normals_separations(x, field, half_width, origin, cell,
nn, mass, nodes)`` and passes ``lr=lr`` to both functions.

Pairs of bodies without an entry in ``case.interfaces`` get ``options["default_law"]``
(default ``"perfect"``: bodies that touch without a declared interface are bonded,
the same continuum the FEM solver builds when it merges nodes; 004 Eq 34 shows a
perfect pair reverts exactly to single-material MPM).  Other choices: ``"stick"``,
``"frictionless"``, ``"none"``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from interfaces.errors import CaseError, check_flag, check_number, check_vector
from mpm import multimaterial_kernels as _k
from mpm.multimaterial_constants import (
    HPERP_CODES, LAW_FRICTION, LAW_IMPERFECT, LAW_NONE, LAW_PERFECT, LAW_STICK, N_PARAMS,
    N_SETTINGS, NODE_OUT_COLUMNS, NORMAL_CODES, NORMAL_LR, NORMAL_RMVG, NORMAL_SN,
    NORMAL_SN_RADIAL,
    P_DN_COMPRESSION, P_DN_TENSION, P_DT, P_MU, S_AREA_CORRECTION, S_CONTACT_OFFSET,
    S_EDGE_CUTOFF, S_FORCE_LIMIT, S_HPERP, S_LUMP_CONSERVE, S_MASS_TOL, S_NORMAL,
    S_DF_DS, S_DF_S0, S_SEPARATION, S_SN_X, S_THREE_MATERIAL, SEP_LR, SEPARATION_CODES,
    THREE_MATERIAL_CODES,
)
from mpm.contact_separation import separation_table
from mpm.multimaterial_lr import lr_normals_separations  # noqa: F401  (re-exported)
from mpm.multimaterial_normals import (  # noqa: F401  (re-exported public normals)
    h_perp, normal_ag, normal_avg, normal_mvg, normal_rmvg, normal_sn,
)

__all__ = [
    "MultimaterialTables", "build_pair_tables", "correct_momentum", "add_interface_forces",
    "apply_velocity_conditions",
    "empty_lr_arrays", "lr_normals_separations", "DEFAULT_OPTIONS", "NODE_OUT_COLUMNS",
    "normal_sn", "normal_mvg", "normal_avg", "normal_ag", "normal_rmvg", "h_perp",
]

AREA_VOLUMES = ("current", "reference")
"""The nodal volumes Omega_ia of the contact area, 000 Eq 20. ``current``: of the particles
where they are now (000). ``reference``: of the particles at their initial positions,
fixed for the run, as the small-strain interface law and the FEM interface elements use
the undeformed interface. Eq 20 measures the node's distance to the interface by the
mismatch of the two materials' nodal domains, so with current volumes an opening [u_n]
moves both materials' particles off the node and the area falls by about [u_n] / h
(relative): at a compliant interface under normal load (a bimaterial square at D ~ E/L,
[u_n] = 2.4 % of a 0.025 mm cell) the interface force is that much too low, an error
that grows as the cells shrink. ``reference`` is for small displacements (particles
that move much less than a cell, apart from the jump itself)."""

DEFAULT_OPTIONS: dict = {
    "normal": "AVG",              # SN | MVG | AVG | AG | RMVG | LR (AVG: right at free-edge
                                  # nodes where MVG tilts 45 deg, 000 Sec 3; SN when known)
    "normal_vector": None,        # SN: unit normal from the lower to the higher body index
    "normal_center": None,        # SN: radial normals from this point instead (000 Fig 4C)
    "separation": "displacement",  # displacement (000 Eq 13) | offset (Eq 14) | LR (004 Eq 24)
                                   # | DF (004 Eq 15: edge distances d(x), mpm/contact_separation.py)
                                   # | velocity (contact whenever approaching, 004 Eq 14 alone)
    "contact_offset": 0.8,        # delta_con = 0.8 h (000 Eq 14 with h = h_perp)
    "area_correction": True,      # 000 Eq 20 (else A_i = Omega_i / h)
    "interface_area": "current",  # current | reference: the nodal volumes of Eq 20 (see AREA_VOLUMES)
    "h_perp": "ellipse_tangent",  # none | ellipse_tangent (000 Eq 22, method 1) | ellipse_normal
    "force_limiting": True,       # 000 Eq 23-27
    "edge_cutoff": 0.0,           # screen nodes with Omega_i < cutoff * cell volume (000 Sec 3)
    "default_law": "perfect",     # law for body pairs not listed in case.interfaces
    "rigid_bodies": (),           # names of rigid bodies (000 Eq 28-31)
    "mass_tolerance": 0.0,        # field present at a node if m_k > tol * m_total (0: any mass)
    "lump_conserve": True,        # restore momentum balance on 3+ material nodes
    "three_material": "lump",     # 3+ material nodes: lump (004 Eq 50) | explicit (Eq 49,
                                  # pairs in contact solved simultaneously; contact laws only)
}


@dataclass
class MultimaterialTables:
    """Numeric description of all material pairs, built once per run.

    ``law_kind[a, b]`` (int64, symmetric) holds a ``LAW_*`` code and
    ``law_params[a, b, :]`` = (Dn_tension, Dt, Dn_compression, mu) in MPa/mm (inf =
    perfect direction).  ``settings`` holds the method switches (slots ``S_*`` in
    :mod:`mpm.multimaterial_constants`), ``rigid[M]`` flags rigid fields (000 Eq 28-31).
    ``node_zone[N]`` (or empty) indexes ``zone_pairs[Z, 2]``, ``zone_kind[Z]``,
    ``zone_params[Z, 4]``: a node inside an ``InterfacePair.zones`` shape uses that law
    for that pair (002 Fig 6 two-zone Dn).
    """

    law_kind: np.ndarray
    law_params: np.ndarray
    settings: np.ndarray
    rigid: np.ndarray
    node_zone: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    zone_pairs: np.ndarray = field(default_factory=lambda: np.zeros((0, 2), dtype=np.int64))
    zone_kind: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    zone_params: np.ndarray = field(default_factory=lambda: np.zeros((0, N_PARAMS)))
    body_names: tuple = ()
    sn_normal: np.ndarray | None = None   # radial SN: per node, from body 0 to the others
    area_reference: bool = False          # Eq 20 on the reference nodal volumes (AREA_VOLUMES)
    df_curve: np.ndarray = field(default_factory=lambda: np.zeros(0))  # DF: d(s), 004 Eq 15

    @property
    def explicit_three_material(self) -> bool:
        """Nodes seen by 3+ materials are corrected pair by pair (004 Sec 3.4)."""
        return int(self.settings[S_THREE_MATERIAL]) == THREE_MATERIAL_CODES["explicit"]

    def node_normals(self, N: int, D: int) -> np.ndarray:
        """The per-node normal buffer [N, M, D] of the step: the radial SN normals
        (from the lower to the higher body index) or, with LR, zeros for the step to
        fill; empty otherwise."""
        M = self.n_materials
        if self.sn_normal is not None:
            out = np.zeros((N, M, D))
            out[:, 0] = self.sn_normal
            out[:, 1:] = -self.sn_normal[:, None, :]
            return out
        return np.zeros((N if self.uses_lr else 0, M, D))

    @property
    def n_materials(self) -> int:
        return int(self.law_kind.shape[0])

    @property
    def uses_lr(self) -> bool:
        """True when normals or separations come from logistic regression (004 Sec 3.1)."""
        return (int(self.settings[S_NORMAL]) == NORMAL_LR
                or int(self.settings[S_SEPARATION]) == SEP_LR)

    @property
    def has_interfaces(self) -> bool:
        """True if some pair (or zone) is an imperfect interface needing forces."""
        return bool(np.any(self.law_kind == LAW_IMPERFECT) or np.any(self.zone_kind == LAW_IMPERFECT))


def _err(msg: str) -> Exception:
    return CaseError(msg)


def _law_to_numbers(law, where: str) -> tuple[int, np.ndarray]:
    """Map an interface-law object (interfaces.laws) to (LAW_* code, params[4])."""
    params = np.zeros(N_PARAMS)
    if isinstance(law, str):
        name = law.strip().lower()
        if name == "perfect":
            return LAW_PERFECT, params
        if name == "stick":
            return LAW_STICK, params
        if name == "frictionless":
            return LAW_FRICTION, params
        if name == "none":
            return LAW_NONE, params
        raise _err(f"{where} must be one of 'perfect', 'stick', 'frictionless', 'none', got {law!r}")
    cls = type(law).__name__
    if cls == "StickContact":
        return LAW_STICK, params
    if cls == "CoulombFriction":
        mu = float(law.mu)
        if not (mu >= 0.0 and math.isfinite(mu)):
            raise _err(f"{where}.mu must be a finite number >= 0, got {law.mu!r}")
        params[P_MU] = mu
        return LAW_FRICTION, params
    if cls in ("LinearInterface", "BilinearNormalInterface"):
        if cls == "LinearInterface":
            dn_t = dn_c = float(law.Dn)
        else:
            dn_t = float(law.Dn_tension)
            dn_c = float(law.Dn_compression)
        dt_ = float(law.Dt)
        for nm, v in (("Dn", dn_t), ("Dt", dt_), ("Dn_compression", dn_c)):
            if math.isnan(v) or v < 0.0:
                raise _err(f"{where}.{nm} must be >= 0 (math.inf = perfect) for MPM, got {v}")
        params[P_DN_TENSION], params[P_DT], params[P_DN_COMPRESSION] = dn_t, dt_, dn_c
        if math.isinf(dn_t) and math.isinf(dn_c) and math.isinf(dt_):
            return LAW_PERFECT, params
        return LAW_IMPERFECT, params
    raise _err(f"{where}: unsupported interface law {cls}; expected LinearInterface, "
               "BilinearNormalInterface, StickContact or CoulombFriction")


def _merged_options(options: dict | None) -> dict:
    opts = dict(DEFAULT_OPTIONS)
    for key, val in (options or {}).items():
        if key in opts:
            opts[key] = val
    return opts


def _radial_normals(opts: dict, node_coordinates, dim: int, m: int) -> np.ndarray:
    """Unit normals (x_i - c) / |x_i - c| of the nodes about ``normal_center`` c (SN of a
    spherical or cylindrical inclusion, 000 Sec 3: from body 0, the inclusion, to the
    others); zero at the centre itself."""
    c = check_vector("mpm option normal_center", opts["normal_center"], dim)
    if opts["normal_vector"] is not None:
        raise _err("mpm options normal_vector and normal_center exclude each other; give one")
    if m != 2:
        raise _err(f"mpm option normal_center (radial SN normals) needs exactly 2 bodies, the "
                   f"inclusion first; the case has {m}")
    if node_coordinates is None:
        raise _err("radial SN normals need node_coordinates in build_pair_tables")
    r = np.asarray(node_coordinates, dtype=float) - c
    norm = np.linalg.norm(r, axis=1)
    return np.ascontiguousarray(r / np.where(norm > 0.0, norm, 1.0)[:, None])


def _df_table(options: dict, settings: np.ndarray) -> np.ndarray:
    """separation = DF (004 Eq 15): the edge-distance curve d(s) of the run's shape
    function and particles per cell (the same along every axis), tabulated for the
    kernels; its start and spacing go into ``settings``."""
    shape = str(options.get("shape", "ugimp")).lower()
    ppc = np.unique(np.atleast_1d(np.asarray(options.get("ppc", 2))))
    if ppc.size != 1 or not float(ppc[0]).is_integer():
        raise _err(f"mpm option separation = DF needs the same integer ppc along every axis, got "
                   f"{options.get('ppc')!r}")
    s0, ds, table = separation_table(shape, int(ppc[0]))
    settings[S_DF_S0] = s0
    settings[S_DF_DS] = ds
    return table


def build_pair_tables(case, options: dict | None = None,
                      node_coordinates: np.ndarray | None = None) -> MultimaterialTables:
    """Build the numeric pair tables for one run (Python level, called once).

    ``case.bodies`` fixes the field order; ``case.interfaces`` gives the law of each
    listed pair (``InterfacePair(a, b, law, zones)``); unlisted pairs get
    ``options["default_law"]``.  ``options`` keys (unknown keys are ignored so the
    caller can pass its whole MPM option dict): see :data:`DEFAULT_OPTIONS`.
    ``node_coordinates[N, D]`` is needed only when some pair has ``zones``.
    Raises ``CaseError`` naming the offending option or pair.
    """
    opts = _merged_options(options)
    names = [b.name for b in case.bodies]
    m = len(names)
    if m == 0:
        raise _err("case.bodies must list at least one body")
    dim = int(getattr(case, "dimension", 2))

    settings = np.zeros(N_SETTINGS)
    normal = str(opts["normal"]).upper() if opts["normal"] is not None else "AVG"
    if normal not in NORMAL_CODES:
        raise _err(f"mpm option normal must be one of {sorted(NORMAL_CODES)}, got {opts['normal']!r}")
    settings[S_NORMAL] = NORMAL_CODES[normal]
    sep = str(opts["separation"])
    sep = sep.upper() if sep.upper() in ("LR", "DF") else sep.lower()
    if sep not in SEPARATION_CODES:
        raise _err(f"mpm option separation must be one of {sorted(SEPARATION_CODES)}, got {opts['separation']!r}")
    settings[S_SEPARATION] = SEPARATION_CODES[sep]
    df_curve = _df_table(options or {}, settings) if sep == "DF" else np.zeros(0)
    hp = str(opts["h_perp"]).lower()
    if hp not in HPERP_CODES:
        raise _err(f"mpm option h_perp must be one of {sorted(HPERP_CODES)}, got {opts['h_perp']!r}")
    settings[S_HPERP] = HPERP_CODES[hp]
    settings[S_AREA_CORRECTION] = float(check_flag("mpm option area_correction", opts["area_correction"]))
    area = str(opts["interface_area"]).lower()
    if area not in AREA_VOLUMES:
        raise _err(f"mpm option interface_area must be one of {list(AREA_VOLUMES)}, got {opts['interface_area']!r}")
    settings[S_FORCE_LIMIT] = float(check_flag("mpm option force_limiting", opts["force_limiting"]))
    settings[S_LUMP_CONSERVE] = float(check_flag("mpm option lump_conserve", opts["lump_conserve"]))
    three = str(opts["three_material"]).lower()
    if three not in THREE_MATERIAL_CODES:
        raise _err(f"mpm option three_material must be one of {sorted(THREE_MATERIAL_CODES)}, "
                   f"got {opts['three_material']!r}")
    settings[S_THREE_MATERIAL] = THREE_MATERIAL_CODES[three]
    settings[S_EDGE_CUTOFF] = _number("edge_cutoff", opts["edge_cutoff"], 0.0, 1.0)
    settings[S_CONTACT_OFFSET] = _number("contact_offset", opts["contact_offset"], 0.0, 2.0)
    settings[S_MASS_TOL] = _number("mass_tolerance", opts["mass_tolerance"], 0.0, 1.0e-2)

    sn_normal = None
    if settings[S_NORMAL] == NORMAL_SN and opts["normal_center"] is not None:
        settings[S_NORMAL] = NORMAL_SN_RADIAL
        sn_normal = _radial_normals(opts, node_coordinates, dim, m)
    elif settings[S_NORMAL] == NORMAL_SN:
        vec = opts["normal_vector"]
        if vec is None:
            raise _err("mpm option normal='SN' needs normal_vector (from the lower to the higher "
                       "body index) or normal_center (radial normals)")
        v = check_vector("mpm option normal_vector", vec, dim)
        if np.linalg.norm(v) == 0.0:
            raise _err(f"mpm option normal_vector must be a nonzero finite vector of {dim} numbers, got {vec!r}")
        settings[S_SN_X:S_SN_X + dim] = v / np.linalg.norm(v)

    rigid = np.zeros(m, dtype=np.int64)
    rigid_names = opts["rigid_bodies"] or ()
    if not isinstance(rigid_names, (list, tuple)):
        raise _err(f"mpm option rigid_bodies must be a list of body names of {names}, got "
                   f"{rigid_names!r}")
    for rname in rigid_names:
        if rname not in names:
            raise _err(f"mpm option rigid_bodies: unknown body {rname!r}; bodies are {names}")
        rigid[names.index(rname)] = 1
    if settings[S_NORMAL] == NORMAL_RMVG and not rigid.any():
        raise _err("mpm option normal='RMVG' needs at least one body in rigid_bodies")

    kind = np.full((m, m), LAW_NONE, dtype=np.int64)
    params = np.zeros((m, m, N_PARAMS))
    dkind, dparams = _law_to_numbers(opts["default_law"], "mpm option default_law")
    for a in range(m):
        for b in range(m):
            if a != b:
                kind[a, b] = dkind
                params[a, b] = dparams

    zone_pairs, zone_kind, zone_params, zone_shapes = [], [], [], []
    for ip, pair in enumerate(getattr(case, "interfaces", []) or []):
        where = f"interfaces[{ip}]"
        for side in ("a", "b"):
            if getattr(pair, side) not in names:
                raise _err(f"{where}.{side} = {getattr(pair, side)!r} is not a body; bodies are {names}")
        ia, ib = names.index(pair.a), names.index(pair.b)
        if ia == ib:
            raise _err(f"{where}: a and b must be different bodies, got {pair.a!r} twice")
        code, pr = _law_to_numbers(pair.law, f"{where}.law")
        kind[ia, ib] = kind[ib, ia] = code
        params[ia, ib] = params[ib, ia] = pr
        for iz, (shape, zlaw) in enumerate(getattr(pair, "zones", None) or []):
            zc, zp = _law_to_numbers(zlaw, f"{where}.zones[{iz}].law")
            zone_pairs.append((ia, ib))
            zone_kind.append(zc)
            zone_params.append(zp)
            zone_shapes.append(shape)
    if rigid.any():
        for r in np.flatnonzero(rigid):
            for a in range(m):
                if a != r and kind[a, r] == LAW_IMPERFECT and rigid[a]:
                    raise _err("two rigid bodies cannot share an imperfect interface")

    tables = MultimaterialTables(kind, params, settings, rigid, body_names=tuple(names),
                                 sn_normal=sn_normal, area_reference=area == "reference",
                                 df_curve=df_curve)
    if zone_shapes:
        if node_coordinates is None:
            raise _err("interfaces with zones need node_coordinates in build_pair_tables")
        xyz = np.asarray(node_coordinates, dtype=float)
        node_zone = np.full(xyz.shape[0], -1, dtype=np.int64)
        for iz in range(len(zone_shapes) - 1, -1, -1):  # first listed zone wins
            node_zone[np.asarray(zone_shapes[iz].contains(xyz), dtype=bool)] = iz
        tables.node_zone = node_zone
        tables.zone_pairs = np.asarray(zone_pairs, dtype=np.int64).reshape(-1, 2)
        tables.zone_kind = np.asarray(zone_kind, dtype=np.int64)
        tables.zone_params = np.asarray(zone_params, dtype=float).reshape(-1, N_PARAMS)
    return tables


def _number(name: str, value, low: float, high: float) -> float:
    return check_number(f"mpm option {name}", value, low=low, high=high)


def empty_lr_arrays(n_nodes: int, n_materials: int, dim: int) -> tuple[np.ndarray, np.ndarray]:
    """Placeholder (normal, separation) arrays when LR is not used (zero-sized)."""
    return np.zeros((0, n_materials, dim)), np.zeros((0, n_materials))


def _thickness_array(thickness, n: int) -> np.ndarray:
    t = np.ascontiguousarray(np.atleast_1d(np.asarray(thickness, dtype=np.float64)))
    if t.ndim != 1 or t.size not in (1, n) or not np.all(t >= 0.0) or (t.size == 1 and t[0] <= 0.0):
        raise ValueError(f"thickness must be one value > 0 or one value >= 0 per node ({n}) "
                         f"(axisymmetric: node radius), got {t if t.size < 5 else t.shape}")
    return t


def _node_list(nodes, n: int) -> np.ndarray:
    if nodes is None:
        return np.arange(n, dtype=np.int64)
    return np.ascontiguousarray(nodes, dtype=np.int64)


def _check_arrays(tables: MultimaterialTables, cell, **arrays) -> tuple[int, int, int]:
    """Shapes and dtypes of the nodal arrays against the layout (mpm/LAYOUT.md)."""
    mass = arrays["mass"]
    if not (isinstance(mass, np.ndarray) and mass.ndim == 2):
        raise ValueError("mass must be a float64 array of shape (N, M)")
    n, m = mass.shape
    if m != tables.n_materials:
        raise ValueError(f"mass has {m} fields but the tables were built for {tables.n_materials} bodies")
    d = int(np.asarray(cell).size)
    if d not in (2, 3):
        raise ValueError(f"cell must hold 2 or 3 sizes, got {np.asarray(cell)!r}")
    expect = {"mass": (n, m), "volume": (n, m), "momentum": (n, m, d), "force": (n, m, d),
              "volume_gradient": (n, m, d), "displacement": (n, m, d), "position": (n, m, d)}
    for name, arr in arrays.items():
        if not isinstance(arr, np.ndarray) or arr.shape != expect[name]:
            got = getattr(arr, "shape", type(arr).__name__)
            raise ValueError(f"{name} must have shape {expect[name]}, got {got}")
        if arr.dtype != np.float64 or not arr.flags.c_contiguous:
            raise ValueError(f"{name} must be a C-contiguous float64 array")
    return n, m, d


def _check_lr(tables: MultimaterialTables, lr, n, m, d):
    if lr is None:
        if tables.uses_lr:
            raise _err("normal/separation 'LR' needs the lr=(normal, separation) arrays from "
                       "mpm.multimaterial_lr.lr_normals_separations for this step")
        return empty_lr_arrays(n, m, d)
    return lr


def correct_momentum(phase: int, mass: np.ndarray, momentum: np.ndarray, force: np.ndarray,
                     volume: np.ndarray, volume_gradient: np.ndarray, displacement: np.ndarray,
                     position: np.ndarray, cell: np.ndarray, tables: MultimaterialTables,
                     dt: float, thickness=1.0, lr=None, nodes: np.ndarray | None = None,
                     origin=None, nn=None) -> int:
    """Contact / perfect-bond momentum correction on multimaterial nodes (004 Eq 26-34).

    ``phase`` 0: after the initial extrapolation (004 Eq 26, Delta p^alpha; momenta
    only).  ``phase`` 1: after the momentum update (004 Eq 31, Delta p^alpha+); also
    adds Delta p^alpha+ / dt to ``force`` (004 Eq 33 f_C,1) so the particle
    acceleration is consistent.  Works in place on ``momentum`` (and ``force``).

    Per pair law: perfect -> centre-of-mass velocity (000 Eq 7-8); stick/friction ->
    only if approaching (000 Eq 9, Delta p . n < 0) and touching (separation <= 0,
    000 Eq 12-14 or 004 Eq 24), with Coulomb friction by 004 Eq 8-10 (ERRATA 7, 13);
    imperfect interfaces -> only their perfect (inf) directions here (002 Sec 2.4),
    the finite directions get forces in :func:`add_interface_forces`.  Nodes with 3+
    materials lump the others into a virtual material (000 Sec 2.6, 004 Eq 50); rigid
    fields follow 000 Eq 28-31, after the deformable fields at the node met each other.
    (This wrapper's LR arrays carry no separate rigid separations: the time step's,
    ``PairTables.lr_rigid_separation``, separate a field from a rigid body by the rigid
    body's particles alone.)  In phase 1 the separation is advanced to the end of
    the step, delta + dt (v_b - v_a).  ``nodes`` (int64) restricts the work to those
    node indices (e.g. the core's list of nodes with 2+ fields); default all nodes.
    ``origin``, ``nn``: the grid's node 0 and node counts per axis (node positions, for
    separation = DF). Returns the number of nodes changed.
    """
    n, m, d = _check_arrays(tables, cell, mass=mass, momentum=momentum, force=force,
                            volume=volume, volume_gradient=volume_gradient,
                            displacement=displacement, position=position)
    if phase not in (0, 1):
        raise ValueError(f"phase must be 0 (after extrapolation) or 1 (after the update), got {phase!r}")
    lr_normal, lr_sep = _check_lr(tables, lr, n, m, d)[:2]
    pair_normal, pair_sep = (lr[2], lr[3]) if lr is not None and len(lr) == 4 else \
        (np.zeros((0, 0, d)), np.zeros((0, 0)))
    origin, nn = _grid_geometry(tables, origin, nn, n, d)
    return _k.correct_momentum_kernel(
        int(phase), mass, momentum, force, volume, volume_gradient, displacement, position,
        np.asarray(cell, dtype=np.float64), origin, nn, _thickness_array(thickness, n),
        tables.law_kind, tables.law_params, tables.settings, tables.rigid, tables.node_zone,
        tables.zone_pairs, tables.zone_kind, tables.zone_params, lr_normal, lr_sep,
        pair_normal, pair_sep, np.zeros((0, m)), tables.df_curve, float(dt), _node_list(nodes, n))


def _grid_geometry(tables: MultimaterialTables, origin, nn, n: int, d: int):
    """Node 0 and node counts of the grid as kernel arrays; required by separation = DF
    (node positions), else defaulted (unused)."""
    if origin is None or nn is None:
        if tables.df_curve.size:
            raise ValueError("separation = DF needs the grid's origin and nn (node positions)")
        return np.zeros(d), np.array([n] + [1] * (d - 1), dtype=np.int64)
    origin = np.asarray(origin, dtype=np.float64).reshape(d)
    nn = np.asarray(nn, dtype=np.int64).reshape(d)
    if int(np.prod(nn)) != n:
        raise ValueError(f"nn {nn.tolist()} does not match the {n} nodes of the arrays")
    return origin, nn


def add_interface_forces(mass: np.ndarray, momentum: np.ndarray, volume: np.ndarray,
                         volume_gradient: np.ndarray, displacement: np.ndarray,
                         position: np.ndarray, cell: np.ndarray, thickness,
                         tables: MultimaterialTables, dt: float, force: np.ndarray,
                         node_out: np.ndarray | None = None, lr=None,
                         nodes: np.ndarray | None = None, origin=None, nn=None) -> float:
    """Imperfect-interface forces on multimaterial nodes (000 Eq 17-27, 002 Eq 37-39).

    For every node where an imperfect-interface pair meets: jump [u] = u_b - u_a
    (000 Eq 11/13, or positions minus the contact offset, Eq 14), split along the
    normal n (a -> b); T_n = Dn [u_n] (Dn_compression when [u_n] < 0, bilinear law of
    002 Sec 2.4), T_t = Dt [u_t]; force on a = (T_n n + T_t t) A_i, on b the opposite.
    A_i by 000 Eq 20 (ERRATA 8) with dx replaced by h_perp (Eq 22, ERRATA 9); finite
    directions are capped at the velocity-equalizing force of 000 Eq 26-27 (then
    flagged perfect for this step, zero energy); perfect (inf) directions get no force
    (they are momentum-corrected).  Nodes with Omega_i < edge_cutoff * cell volume
    are skipped.  Adds to ``force`` in place; ``force`` may already hold the other
    nodal forces, which enter the Delta f term of Eq 27.
    Returns U = sum_i 1/2 (Dn [u_n]^2 + Dt [u_t]^2) A_i (ERRATA 10).  If ``node_out``
    (N, NODE_OUT_COLUMNS) is given it is overwritten with per-node jump, traction,
    normal, area, energy and status (columns OUT_* in mpm.multimaterial_constants).
    ``nodes`` (int64) restricts the work to those node indices (default all nodes).
    """
    n, m, d = _check_arrays(tables, cell, mass=mass, momentum=momentum, force=force,
                            volume=volume, volume_gradient=volume_gradient,
                            displacement=displacement, position=position)
    lr_normal, lr_sep = _check_lr(tables, lr, n, m, d)[:2]
    if node_out is None:
        node_out = np.zeros((0, NODE_OUT_COLUMNS))
    elif node_out.shape != (n, NODE_OUT_COLUMNS):
        raise ValueError(f"node_out must have shape ({n}, {NODE_OUT_COLUMNS}), got {node_out.shape}")
    origin, nn = _grid_geometry(tables, origin, nn, n, d)
    return _k.interface_forces_kernel(
        mass, momentum, volume, np.zeros((0, m)), volume_gradient, displacement, position,
        np.asarray(cell, dtype=np.float64), origin, nn, _thickness_array(thickness, n),
        tables.law_kind, tables.law_params, tables.settings, tables.rigid, tables.node_zone,
        tables.zone_pairs, tables.zone_kind, tables.zone_params, lr_normal, lr_sep,
        np.zeros((0, m)), tables.df_curve, float(dt), force, node_out, _node_list(nodes, n))


def apply_velocity_conditions(mass: np.ndarray, momentum: np.ndarray, force: np.ndarray,
                              tables: MultimaterialTables, dt: float, bc_node: np.ndarray,
                              bc_field: np.ndarray, bc_comp: np.ndarray, bc_vel: np.ndarray,
                              with_force: bool = True) -> float:
    """Re-impose nodal velocity / fixed conditions after :func:`correct_momentum`.

    The phase-1 correction runs after the core's boundary conditions (mpm/LAYOUT.md step
    5) and would move a constrained field that is perfectly bonded to a free one.  Each
    condition (node ``bc_node``, field ``bc_field``, component ``bc_comp``, velocity
    ``bc_vel``) is set again on its field and on every field perfectly bonded to it at
    that node (pair or zone law ``perfect``); ``with_force`` also adds the reaction
    (p_bc - p)/dt to ``force``.  Imperfect pairs with one perfect (inf) direction keep
    their own momentum correction (the condition then acts on the named field only).
    Returns the work of the added reactions this step (mm N).
    """
    n, m, d = _check_arrays(tables, np.zeros(momentum.shape[2]), mass=mass,
                            momentum=momentum, force=force)
    return _k.bonded_velocity_bc_kernel(
        mass, momentum, force, bc_node, bc_field, bc_comp, bc_vel, tables.law_kind,
        tables.law_params, tables.settings, tables.node_zone, tables.zone_pairs,
        tables.zone_kind, tables.zone_params, float(dt), bool(with_force))
