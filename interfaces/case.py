"""The case description every solver reads: bodies, interfaces, loads, measurements.

A :class:`Case` is plain data, validated at construction (errors name the offending
field, e.g. ``bodies[1].material``) and round-trips through TOML unchanged
(:meth:`Case.to_toml`, :meth:`Case.from_toml`). See ``docs/case_api.md``.
Units: mm, N, MPa, s, tonne/mm^3; Dn, Dt in MPa/mm.
"""
from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from .errors import CaseError, check_number
from .geometry import CURVE_SIDE, SIDES, Shape, shape_from_dict
from .laws import InterfaceLaw, law_from_dict
from .materials import Material, check_analysis, material_from_dict

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover
    import tomli as tomllib
import tomli_w

RAMPS = ("linear", "cosine")
ALL_BODIES = "*"
"""Body name of a condition on a side of the whole specimen's bounding box (every body there)."""
BC_KINDS = ("fixed", "displacement", "traction", "velocity", "deformation_gradient")
COMPONENTS = ("x", "y", "z")
METHODS = ("analytic", "fem", "mpm", "cpd")
#: measurement name -> its fields ("positive": a length/volume/strain > 0; "any": checked by
#: the methods that measure it)
MEASUREMENTS = {
    "stiffness": {"load": "any", "support": "any", "direction": "any"},
    "interface_energy": {"per_volume": "positive"},
    "strain_energy": {},
    "bulk_modulus": {"strain": "positive", "volume": "positive"},
    "transmitted_energy": {"x_incident": "any", "x_interface": "any", "x_transmitted": "any",
                           "duration": "positive"},
    "contact_time": {"body": "any", "component": "any", "sample_every": "positive",
                     "threshold": "positive"},
    "axial_stress": {"bodies": "any", "component": "any", "sample_every": "positive"},
    "interpenetration": {"bodies": "any", "container": "any"},
    "shock_front": {"sample_every": "positive", "wall": "any", "window": "any"},
}


@dataclass
class Body:
    """A body: a shape filled with one material, minus optional holes.

    ``within`` clips the shape (e.g. the 1/8 sphere of 000 Fig 4C is a Sphere within
    the unit-cell Box).
    """

    name: str
    shape: Shape
    material: str
    holes: list = field(default_factory=list)
    within: Shape | None = None

    def contains(self, points, tol: float = 0.0) -> np.ndarray:
        """Points inside the shape (and inside ``within``, if set) and outside every hole."""
        inside = self.shape.contains(points, tol)
        if self.within is not None:
            inside &= self.within.contains(points, tol)
        for h in self.holes:
            inside &= ~h.contains(points, -tol) if tol > 0 else ~h.contains(points)
        return inside

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        """Bounding box of the shape, clipped by ``within``."""
        lo, hi = (np.asarray(v, dtype=float) for v in self.shape.bounds())
        if self.within is not None:
            wlo, whi = self.within.bounds()
            lo, hi = np.maximum(lo, wlo), np.minimum(hi, whi)
        return lo, hi

    def to_dict(self) -> dict:
        d = {"name": self.name, "material": self.material, "shape": self.shape.to_dict()}
        if self.holes:
            d["holes"] = [h.to_dict() for h in self.holes]
        if self.within is not None:
            d["within"] = self.within.to_dict()
        return d


@dataclass
class InterfacePair:
    """Interface between bodies ``a`` and ``b`` with a default law and optional zones.

    ``zones`` is a list of ``(shape, law)``: interface points inside ``shape`` use
    ``law`` (first match wins), e.g. 002 Fig 6 with Dn = 1 below y = 12.5.
    The normal of the jump [u] = u_b - u_a points from a to b.
    """

    a: str
    b: str
    law: InterfaceLaw
    zones: list = field(default_factory=list)

    def zone_index(self, points) -> np.ndarray:
        """Index into ``zones`` for each point, -1 where the default law applies."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        idx = np.full(len(p), -1, dtype=int)
        for k in range(len(self.zones) - 1, -1, -1):
            idx[self.zones[k][0].contains(p)] = k
        return idx

    def law_at(self, points) -> list:
        """The law that applies at each point."""
        laws = [z[1] for z in self.zones]
        return [self.law if k < 0 else laws[k] for k in self.zone_index(points)]

    def to_dict(self) -> dict:
        d = {"a": self.a, "b": self.b, "law": self.law.to_dict()}
        if self.zones:
            d["zones"] = [{"shape": s.to_dict(), "law": l.to_dict()} for s, l in self.zones]
        return d


@dataclass
class BoundaryCondition:
    """A condition on one side of a body.

    kind: ``fixed`` (listed components zero), ``displacement`` (value in mm),
    ``traction`` (value = traction vector in MPa, global axes, all components),
    ``velocity`` (mm/s, dynamic methods), ``deformation_gradient`` (value = the D*D
    entries of H = F - I, row-major; the listed components of u(X) = H X are prescribed,
    X the reference position: the uniform-deformation load cases of 003 Sec 4.1).
    ``ramp_time`` (s): dynamic methods ramp the load from 0 to ``value`` over this
    time (None = applied at once), ``ramp`` = ``linear`` or ``cosine`` (x0/2 (1 - cos(pi t /
    ramp_time)): the pulse of 002 Eq 49 with ramp_time = 1/(2f)). ``body = "*"`` means
    the side of the bounding box of all bodies (e.g. symmetry planes of 000 Fig 4C).
    """

    def ramp_factor(self, t):
        """Load fraction at time ``t`` (s)."""
        if self.ramp_time is None:
            return np.ones_like(np.asarray(t, dtype=float))
        s = np.clip(np.asarray(t, dtype=float) / self.ramp_time, 0.0, 1.0)
        return s if self.ramp == "linear" else 0.5 * (1.0 - np.cos(np.pi * s))

    kind: str
    body: str
    side: str
    components: tuple = ("x", "y")
    value: tuple = (0.0, 0.0)
    ramp_time: float | None = None
    ramp: str = "linear"

    def __post_init__(self):
        for name in ("kind", "body", "side", "ramp"):
            if not isinstance(getattr(self, name), str) or not getattr(self, name):
                raise CaseError(f"{name} must be a name, got {getattr(self, name)!r}")
        if self.ramp not in RAMPS:
            raise CaseError(f"ramp must be one of {', '.join(RAMPS)}, got {self.ramp!r}")
        if self.kind not in BC_KINDS:
            raise CaseError(f"kind must be one of {', '.join(BC_KINDS)}, got {self.kind!r}")
        if self.side not in SIDES + (CURVE_SIDE,):
            raise CaseError(f"side must be one of {', '.join(SIDES + (CURVE_SIDE,))}, got {self.side!r}")
        comps = tuple(self.components) if isinstance(self.components, (list, tuple, str)) else None
        if (not comps or any(not isinstance(c, str) or c not in COMPONENTS for c in comps)
                or len(set(comps)) != len(comps)):
            raise CaseError(f"components must be distinct letters from x, y, z, got {self.components!r}")
        self.components = comps
        if isinstance(self.value, (list, tuple)):
            vals = tuple(self.value)
        elif isinstance(self.value, (int, float)) and not isinstance(self.value, bool):
            vals = (self.value,)
        else:
            raise CaseError(f"value must be a list of numbers, got {self.value!r}")
        if self.kind == "fixed" and vals == (0.0, 0.0) and len(comps) != 2:
            vals = (0.0,) * len(comps)
        if self.kind == "deformation_gradient":
            if len(vals) not in (4, 9):
                raise CaseError(f"value of a deformation_gradient must hold the 4 (2D) or 9 (3D) entries of H = F - I, got {self.value!r}")
        elif len(vals) != len(comps):
            raise CaseError(f"value must have one number per component {comps}, got {self.value!r}")
        self.value = tuple(check_number(f"value[{i}]", v) for i, v in enumerate(vals))
        if self.kind == "fixed" and any(v != 0 for v in self.value):
            raise CaseError(f"value of a fixed condition must be zero, got {self.value!r} (use kind 'displacement')")
        if self.ramp_time is not None:
            self.ramp_time = check_number("ramp_time", self.ramp_time, low=0, low_open=True)

    def gradient(self, dimension: int) -> np.ndarray:
        """H = F - I of a ``deformation_gradient`` condition as a (D, D) array."""
        H = np.asarray(self.value, dtype=float)
        if H.size != dimension * dimension:
            raise CaseError(f"value has {H.size} entries, a {dimension}D deformation gradient needs {dimension * dimension}")
        return H.reshape(dimension, dimension)

    def displacement_at(self, points) -> np.ndarray:
        """Prescribed displacement at reference ``points`` (N, D): constant or H X."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        if self.kind == "deformation_gradient":
            return p @ self.gradient(p.shape[1]).T
        return np.tile(self.vector(p.shape[1]), (len(p), 1))

    def vector(self, dimension: int) -> np.ndarray:
        """The value as a full vector of length ``dimension`` (unlisted components 0)."""
        if self.kind == "deformation_gradient":
            raise CaseError("a deformation_gradient condition has no single vector; use displacement_at(points)")
        v = np.zeros(dimension)
        for c, x in zip(self.components, self.value):
            v[COMPONENTS.index(c)] = x
        return v

    def component_indices(self) -> list[int]:
        return [COMPONENTS.index(c) for c in self.components]

    def to_dict(self) -> dict:
        d = {"kind": self.kind, "body": self.body, "side": self.side,
             "components": list(self.components), "value": list(self.value)}
        if self.ramp_time is not None:
            d["ramp_time"] = self.ramp_time
        if self.ramp != "linear":
            d["ramp"] = self.ramp
        return d


@dataclass
class Case:
    """One specimen, read by every method (see ``docs/case_api.md``).

    Units: mm, N, MPa, s, tonne/mm^3; interface stiffness Dn, Dt in MPa/mm.
    """

    name: str
    analysis: str
    materials: dict
    bodies: list
    interfaces: list = field(default_factory=list)
    boundary_conditions: list = field(default_factory=list)
    thickness: float = 1.0
    measurements: dict = field(default_factory=dict)
    discretization: dict = field(default_factory=dict)
    analytic: dict | None = None
    reference: str | None = None
    lines: dict = field(default_factory=dict)
    description: str = ""

    def __post_init__(self):
        self.validate()

    # ---- queries ---------------------------------------------------------
    @property
    def dimension(self) -> int:
        return 3 if self.analysis == "3d" else 2

    def body(self, name: str) -> Body:
        for b in self.bodies:
            if b.name == name:
                return b
        raise CaseError(f"no body named {name!r} (bodies: {', '.join(b.name for b in self.bodies)})")

    def body_index(self, name: str) -> int:
        return [b.name for b in self.bodies].index(self.body(name).name)

    def material_of(self, body_name: str) -> Material:
        return self.materials[self.body(body_name).material]

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:
        lo = np.min([b.bounds()[0] for b in self.bodies], axis=0)
        hi = np.max([b.bounds()[1] for b in self.bodies], axis=0)
        return lo, hi

    def interface_between(self, a: str, b: str) -> InterfacePair | None:
        for p in self.interfaces:
            if {p.a, p.b} == {a, b}:
                return p
        return None

    def stiffness_direction(self) -> np.ndarray:
        """Unit vector of measurements.stiffness.direction (an axis letter or a vector)."""
        d = self.measurements.get("stiffness", {}).get("direction", "y")
        if isinstance(d, str):
            if not isinstance(d, str) or d not in COMPONENTS[: self.dimension]:
                raise CaseError(f"direction must be one of {', '.join(COMPONENTS[: self.dimension])} or a vector, got {d!r}")
            v = np.zeros(self.dimension)
            v[COMPONENTS.index(d)] = 1.0
            return v
        try:
            v = np.asarray(d, dtype=float)
        except (TypeError, ValueError):
            v = np.zeros(0)
        if v.shape != (self.dimension,) or not np.all(np.isfinite(v)) or not np.linalg.norm(v) > 0:
            raise CaseError(f"direction must be an axis letter or a non-zero vector of {self.dimension} numbers, got {d!r}")
        return v / np.linalg.norm(v)

    def side_points_mask(self, body: str, side: str, points, tol: float) -> np.ndarray:
        """Points within ``tol`` of a body's side; body ``"*"`` = side of the bounding box of all bodies."""
        p = np.atleast_2d(np.asarray(points, dtype=float))
        if body == ALL_BODIES:
            lo, hi = self.bounds()
            axis = SIDES.index(side) // 2
            target = hi[axis] if side.endswith("max") else lo[axis]
            return np.abs(p[:, axis] - target) <= tol
        return self.body(body).shape.edge_mask(p, side, tol)

    def methods(self) -> list[str]:
        """Methods that support this case: those with a discretization entry, plus analytic."""
        out = ["analytic"] if self.analytic is not None else []
        return out + [m for m in METHODS if m != "analytic" and m in self.discretization]

    def options_for(self, method: str, **overrides) -> dict:
        """The case's discretization defaults for ``method`` updated by ``overrides``."""
        opts = dict(self.discretization.get(method, {}))
        opts.update(overrides)
        return opts

    def replace(self, **changes) -> "Case":
        """A validated copy with some top-level fields changed."""
        d = copy.deepcopy(self.__dict__)
        d.update(changes)
        return Case(**d)

    # ---- validation ------------------------------------------------------
    def validate(self) -> None:
        if not isinstance(self.name, str) or not self.name:
            raise CaseError(f"name must be a non-empty string, got {self.name!r}")
        check_analysis(self.analysis)
        self.thickness = check_number("thickness", self.thickness, low=0, low_open=True)
        if not isinstance(self.materials, dict) or not self.materials:
            raise CaseError("materials must be a non-empty table of named materials")
        for k, m in self.materials.items():
            if not isinstance(m, Material):
                raise CaseError(f"materials.{k} must be a material, got {m!r}")
        if not self.bodies:
            raise CaseError("bodies must list at least one body")
        names = set()
        for i, b in enumerate(self.bodies):
            if not isinstance(b, Body):
                raise CaseError(f"bodies[{i}] must be a Body, got {b!r}")
            if b.name in names:
                raise CaseError(f"bodies[{i}].name {b.name!r} is used twice")
            names.add(b.name)
            if b.material not in self.materials:
                raise CaseError(f"bodies[{i}].material {b.material!r} is not in materials ({', '.join(self.materials)})")
            if b.shape.dimension != self.dimension:
                raise CaseError(f"bodies[{i}].shape is {b.shape.dimension}D but analysis {self.analysis!r} is {self.dimension}D")
        self._check_overlaps()
        for i, p in enumerate(self.interfaces):
            for end in ("a", "b"):
                if getattr(p, end) not in names:
                    raise CaseError(f"interfaces[{i}].{end} {getattr(p, end)!r} is not a body name ({', '.join(sorted(names))})")
            if p.a == p.b:
                raise CaseError(f"interfaces[{i}] joins body {p.a!r} to itself")
            if not isinstance(p.law, InterfaceLaw):
                raise CaseError(f"interfaces[{i}].law must be an interface law, got {p.law!r}")
        for i, bc in enumerate(self.boundary_conditions):
            if bc.body not in names and bc.body != ALL_BODIES:
                raise CaseError(f"boundary_conditions[{i}].body {bc.body!r} is not a body name ({', '.join(sorted(names))})")
            try:
                if any(c == "z" for c in bc.components) and self.dimension == 2:
                    raise CaseError(f"components has z in a 2D case, got {list(bc.components)!r} "
                                    "(2D components: x, y)")
                if bc.kind == "deformation_gradient":
                    bc.gradient(self.dimension)
                elif bc.kind != "traction":
                    bc.vector(self.dimension)
                if bc.side == CURVE_SIDE and (bc.body == ALL_BODIES or
                                              self.body(bc.body).shape.kind not in ("circle", "ellipse")):
                    raise CaseError(f"side {CURVE_SIDE!r} is the curve of a circle or ellipse body, got body {bc.body!r}")
                if bc.side in SIDES and SIDES.index(bc.side) >= 2 * self.dimension:
                    raise CaseError(f"side {bc.side!r} does not exist in {self.dimension}D")
                if bc.body != ALL_BODIES and not hasattr(self.body(bc.body).shape, "edge_mask"):
                    raise CaseError(f"body {bc.body!r} has a {self.body(bc.body).shape.kind} shape without named sides")
            except CaseError as e:
                raise CaseError(f"boundary_conditions[{i}].{e}") from None
        self._validate_measurements()
        if "stiffness" in self.measurements and not any(
                bc.kind in ("traction", "displacement", "velocity", "deformation_gradient")
                and any(v != 0 for v in bc.value) for bc in self.boundary_conditions):
            raise CaseError("measurements.stiffness: no boundary condition loads the specimen (no non-zero "
                            "traction or displacement): add one on the load sides")
        st = self.measurements.get("stiffness")
        if st is not None:
            for key in ("load", "support"):
                if not isinstance(st.get(key, []), (list, tuple)):
                    raise CaseError(f"measurements.stiffness.{key} must be a list of [body, side], "
                                    f"got {st[key]!r}")
                for j, item in enumerate(st.get(key, [])):
                    if not (isinstance(item, (list, tuple)) and len(item) == 2
                            and all(isinstance(x, str) for x in item)
                            and (item[0] in names or item[0] == ALL_BODIES) and item[1] in SIDES):
                        raise CaseError(f"measurements.stiffness.{key}[{j}] must be [body, side] with a known body, got {item!r}")
            try:
                self.stiffness_direction()
            except CaseError as e:
                raise CaseError(f"measurements.stiffness.{e}") from None
        for m, opts in self.discretization.items():
            if m not in METHODS:
                raise CaseError(f"discretization.{m} is not a method ({', '.join(METHODS)})")
            if not isinstance(opts, dict):
                raise CaseError(f"discretization.{m} must be a table of {m} options "
                                f"([discretization.{m}] with key = value lines), got {opts!r}")
        if self.reference is not None and self.reference not in METHODS:
            raise CaseError(f"reference must be one of {', '.join(METHODS)} or absent, got {self.reference!r}")
        if self.analytic is not None and "model" not in self.analytic:
            raise CaseError("analytic must name its model: analytic.model = '...'")
        for k, seg in self.lines.items():
            arr = np.asarray(seg, dtype=float) if _is_numeric_list(seg) else None
            if arr is None or arr.shape != (2, self.dimension):
                raise CaseError(f"lines.{k} must be two points [[x0, y0], [x1, y1]], got {seg!r}")
            for i, j in np.ndindex(arr.shape):
                check_number(f"lines.{k}[{i}][{j}]", arr[i, j], low=-1e30, high=1e30)

    def _check_overlaps(self, samples: int = 4096) -> None:
        """Two bodies must not share volume (each point has one material). Tested on a
        fixed quasi-random sample of the intersection of their bounding boxes: a common
        region of more than ~0.1 % of that box is found; touching sides are not overlaps."""
        if len(self.bodies) < 2:
            return
        boxes = [b.shape.bounds() for b in self.bodies]
        lo_all, hi_all = self.bounds()
        tol = 1e-9 * float(np.max(hi_all - lo_all))      # round-off of rotated sides
        unit = _halton(samples, self.dimension)
        for i in range(len(self.bodies)):
            for j in range(i + 1, len(self.bodies)):
                lo = np.maximum(boxes[i][0], boxes[j][0])
                hi = np.minimum(boxes[i][1], boxes[j][1])
                if np.any(hi - lo <= tol):
                    continue
                pts = lo + unit * (hi - lo)
                both = self.bodies[i].contains(pts) & self.bodies[j].contains(pts)
                if np.count_nonzero(both) > samples // 1000:
                    share = np.count_nonzero(both) / samples * float(np.prod(hi - lo))
                    unit_txt = "mm^3" if self.dimension == 3 else "mm^2"
                    raise CaseError(f"bodies {self.bodies[i].name!r} and {self.bodies[j].name!r} overlap "
                                    f"(about {share:.3g} {unit_txt} in common): every point must belong "
                                    "to one body (use holes or move a body)")

    def _validate_measurements(self) -> None:
        """Known measurement names and fields only; numbers where numbers belong."""
        if not isinstance(self.measurements, dict):
            raise CaseError("measurements must be a table")
        for name, spec in self.measurements.items():
            if name not in MEASUREMENTS:
                raise CaseError(f"measurements.{name} is not a measurement ({', '.join(MEASUREMENTS)})")
            if not isinstance(spec, dict):
                raise CaseError(f"measurements.{name} must be a table, got {spec!r}")
            allowed = MEASUREMENTS[name]
            extra = sorted(set(spec) - set(allowed))
            if extra:
                raise CaseError(f"measurements.{name}.{extra[0]} is not a field of {name} "
                                f"(fields: {', '.join(allowed) or 'none'})")
            for key, kind in allowed.items():
                if key in spec and kind == "positive":
                    spec[key] = check_number(f"measurements.{name}.{key}", spec[key], low=0, low_open=True)

    # ---- serialisation ---------------------------------------------------
    def to_dict(self) -> dict:
        d: dict[str, Any] = {
            "name": self.name, "description": self.description, "analysis": self.analysis,
            "thickness": self.thickness,
            "materials": {k: m.to_dict() for k, m in self.materials.items()},
            "bodies": [b.to_dict() for b in self.bodies],
            "interfaces": [p.to_dict() for p in self.interfaces],
            "boundary_conditions": [bc.to_dict() for bc in self.boundary_conditions],
            "measurements": encode_values(self.measurements),
            "discretization": encode_values(self.discretization),
            "lines": {k: [list(map(float, p)) for p in v] for k, v in self.lines.items()},
        }
        if self.analytic is not None:
            d["analytic"] = encode_values(self.analytic)
        if self.reference is not None:
            d["reference"] = self.reference
        return d

    def to_toml(self) -> str:
        return tomli_w.dumps(self.to_dict())

    @classmethod
    def from_toml(cls, text: str) -> "Case":
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as e:
            raise CaseError(f"case file is not valid TOML: {e}") from None
        return cls.from_dict(data)

    @classmethod
    def from_dict(cls, d: dict) -> "Case":
        if not isinstance(d, dict):
            raise CaseError("a case must be a table")
        known = {"name", "description", "analysis", "thickness", "materials", "bodies", "interfaces",
                 "boundary_conditions", "measurements", "discretization", "analytic", "reference", "lines"}
        extra = set(d) - known
        if extra:
            raise CaseError(f"{sorted(extra)[0]} is not a case field (fields: {', '.join(sorted(known))})")
        for req in ("name", "analysis", "materials", "bodies"):
            if req not in d:
                raise CaseError(f"{req} is missing")
        mats = d["materials"]
        if not isinstance(mats, dict):
            raise CaseError("materials must be a table of named materials")
        materials = {k: material_from_dict(v, f"materials.{k}") for k, v in mats.items()}
        bodies = []
        for i, b in enumerate(_list(d["bodies"], "bodies")):
            w = f"bodies[{i}]"
            _require(b, ("name", "shape", "material"), w)
            holes = [shape_from_dict(h, f"{w}.holes[{j}]") for j, h in enumerate(_list(b.get("holes", []), f"{w}.holes"))]
            extra = set(b) - {"name", "shape", "material", "holes", "within"}
            if extra:
                raise CaseError(f"{w}.{sorted(extra)[0]} is not a body field")
            bodies.append(Body(name=_str(b["name"], f"{w}.name"), shape=shape_from_dict(b["shape"], f"{w}.shape"),
                               material=_str(b["material"], f"{w}.material"), holes=holes,
                               within=shape_from_dict(b["within"], f"{w}.within") if "within" in b else None))
        interfaces = []
        for i, p in enumerate(_list(d.get("interfaces", []), "interfaces")):
            w = f"interfaces[{i}]"
            _require(p, ("a", "b", "law"), w)
            _only(p, ("a", "b", "law", "zones"), w, "an interface")
            zones = []
            for j, z in enumerate(_list(p.get("zones", []), f"{w}.zones")):
                _require(z, ("shape", "law"), f"{w}.zones[{j}]")
                _only(z, ("shape", "law"), f"{w}.zones[{j}]", "a zone")
                zones.append((shape_from_dict(z["shape"], f"{w}.zones[{j}].shape"), law_from_dict(z["law"], f"{w}.zones[{j}].law")))
            interfaces.append(InterfacePair(a=_str(p["a"], f"{w}.a"), b=_str(p["b"], f"{w}.b"),
                                            law=law_from_dict(p["law"], f"{w}.law"), zones=zones))
        bcs = []
        for i, bc in enumerate(_list(d.get("boundary_conditions", []), "boundary_conditions")):
            w = f"boundary_conditions[{i}]"
            _require(bc, ("kind", "body", "side"), w)
            extra = set(bc) - {"kind", "body", "side", "components", "value", "ramp_time", "ramp"}
            if extra:
                raise CaseError(f"{w}.{sorted(extra)[0]} is not a boundary condition field")
            try:
                bcs.append(BoundaryCondition(**{k: (tuple(v) if isinstance(v, list) else v) for k, v in bc.items()}))
            except CaseError as e:
                raise CaseError(f"{w}.{e}") from None
        for key in ("measurements", "discretization", "lines"):
            if not isinstance(d.get(key, {}), dict):
                raise CaseError(f"{key} must be a table")
        if d.get("analytic") is not None and not isinstance(d["analytic"], dict):
            raise CaseError("analytic must be a table")
        return cls(name=_str(d["name"], "name"), description=d.get("description", ""),
                   analysis=_str(d["analysis"], "analysis"), thickness=d.get("thickness", 1.0),
                   materials=materials, bodies=bodies, interfaces=interfaces, boundary_conditions=bcs,
                   measurements=_decode(d.get("measurements", {})),
                   discretization=_decode(d.get("discretization", {})),
                   analytic=_decode(d["analytic"]) if d.get("analytic") is not None else None,
                   reference=d.get("reference"), lines=d.get("lines", {}))


def _halton(n: int, dimension: int) -> np.ndarray:
    """n points of the Halton sequence in [0, 1)^dimension (bases 2, 3, 5), offset so
    that none lands on a shared side of two bodies."""
    out = np.empty((n, dimension))
    for d, base in enumerate((2, 3, 5)[:dimension]):
        k = np.arange(1, n + 1)
        f, x = 1.0, np.zeros(n)
        while np.any(k > 0):
            f /= base
            x += f * (k % base)
            k //= base
        out[:, d] = x
    return (out + 0.5 / (7 * n)) % 1.0


def _is_numeric_list(seg) -> bool:
    try:
        np.asarray(seg, dtype=float)
        return True
    except (TypeError, ValueError):
        return False


def _list(v, where: str) -> list:
    if not isinstance(v, list):
        raise CaseError(f"{where} must be a list, got {v!r}")
    return v


def _str(v, where: str) -> str:
    if not isinstance(v, str) or not v or not v.isprintable():
        raise CaseError(f"{where} must be a non-empty string of printable characters, got {v!r}")
    return v


def _only(d: dict, keys, where: str, what: str) -> None:
    extra = sorted(set(d) - set(keys))
    if extra:
        raise CaseError(f"{where}.{extra[0]} is not a field of {what} (fields: {', '.join(keys)})")


def _require(d, keys, where: str) -> None:
    if not isinstance(d, dict):
        raise CaseError(f"{where} must be a table, got {d!r}")
    for k in keys:
        if k not in d:
            raise CaseError(f"{where}.{k} is missing")


def encode_values(obj):
    """TOML and JSON have no inf/None: inf as the string "inf", None entries dropped, tuples as
    lists, numpy scalars as Python numbers (case files, sweep records)."""
    if isinstance(obj, dict):
        return {k: encode_values(v) for k, v in obj.items() if v is not None}
    if isinstance(obj, (list, tuple)):
        return [encode_values(v) for v in obj]
    if isinstance(obj, float) and math.isinf(obj):
        return "inf" if obj > 0 else "-inf"
    if isinstance(obj, np.generic):
        return obj.item()
    return obj


def _decode(obj):
    if isinstance(obj, dict):
        return {k: _decode(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_decode(v) for v in obj]
    if obj == "inf":
        return math.inf
    if obj == "-inf":
        return -math.inf
    return obj
