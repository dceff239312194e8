"""What every method returns: scalar quantities, fields, profiles, timings, diagnostics.

Quantity names shared by all methods: ``stiffness`` and ``stiffness_energy`` (N/mm),
``strain_energy``, ``interface_energy``, ``kinetic_energy`` (N mm), ``bulk_modulus``
(MPa), ``transmitted_energy`` (fraction). Fields are arrays on points (``position`` is
required to write VTK). ``to_json`` writes everything; ``to_vtk`` writes the fields
through meshio (as cells when ``cells`` is given, else as a point cloud).
"""
from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import CaseError


@dataclass
class Result:
    """Output of one method on one case (see ``docs/case_api.md``)."""

    method: str
    case_name: str
    quantities: dict = field(default_factory=dict)
    fields: dict = field(default_factory=dict)
    cells: dict | None = None
    profiles: dict = field(default_factory=dict)
    timings: dict = field(default_factory=dict)
    diagnostics: dict = field(default_factory=dict)

    def warn(self, message: str) -> None:
        """Record a warning shown to the user with the result."""
        self.diagnostics.setdefault("warnings", []).append(message)

    # ---- JSON ------------------------------------------------------------
    def to_dict(self, include_fields: bool = True) -> dict:
        d = {"method": self.method, "case_name": self.case_name,
             "quantities": _jsonable(self.quantities), "profiles": _jsonable(self.profiles),
             "timings": _jsonable(self.timings), "diagnostics": _jsonable(self.diagnostics)}
        if include_fields:
            d["fields"] = _jsonable(self.fields)
            if self.cells is not None:
                d["cells"] = _jsonable(self.cells)
        return d

    def to_json(self, path: str | os.PathLike | None = None, include_fields: bool = True) -> str:
        """JSON text (inf and NaN written as strings); also written to ``path`` if given."""
        text = json.dumps(self.to_dict(include_fields), indent=1)
        if path is not None:
            Path(path).write_text(text)
        return text

    @classmethod
    def from_json(cls, source: str | os.PathLike) -> "Result":
        text = Path(source).read_text() if not str(source).lstrip().startswith("{") else str(source)
        d = json.loads(text)
        return cls(method=d["method"], case_name=d["case_name"], quantities=_unjson(d.get("quantities", {})),
                   fields={k: np.asarray(_unjson(v)) for k, v in d.get("fields", {}).items()},
                   cells=_cells_from_json(d.get("cells")),
                   profiles={k: {kk: np.asarray(_unjson(vv)) if isinstance(vv, list) else _unjson(vv)
                                 for kk, vv in v.items()} for k, v in d.get("profiles", {}).items()},
                   timings=d.get("timings", {}), diagnostics=_unjson(d.get("diagnostics", {})))

    # ---- VTK -------------------------------------------------------------
    def to_vtk(self, path: str | os.PathLike) -> Path:
        """Write the fields to a VTK XML file (``.vtu``) through meshio."""
        import meshio

        if "position" not in self.fields:
            raise CaseError(f"result of {self.method} has no 'position' field to write to VTK")
        pts = np.asarray(self.fields["position"], dtype=float)
        n = len(pts)
        if pts.shape[1] == 2:
            pts = np.hstack([pts, np.zeros((n, 1))])
        if self.cells is not None:
            cells = [(self.cells["type"], np.asarray(self.cells["connectivity"], dtype=np.int64))]
        else:
            cells = [("vertex", np.arange(n, dtype=np.int64)[:, None])]
        point_data = {}
        for k, v in self.fields.items():
            if k == "position":
                continue
            a = np.asarray(v)
            if a.shape[:1] != (n,) or not np.issubdtype(a.dtype, np.number):
                continue
            if a.ndim == 2 and a.shape[1] == 2 and k in ("displacement", "velocity"):
                a = np.hstack([a, np.zeros((n, 1))])
            point_data[k] = a
        path = Path(path)
        if path.suffix != ".vtu":
            path = path.with_suffix(".vtu")
        meshio.write(str(path), meshio.Mesh(pts, cells, point_data=point_data))
        return path


def _jsonable(obj: Any):
    if isinstance(obj, dict):
        return {str(k): _jsonable(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_jsonable(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _jsonable(obj.tolist())
    if isinstance(obj, np.generic):
        return _jsonable(obj.item())
    if isinstance(obj, float) and (math.isinf(obj) or math.isnan(obj)):
        return str(obj)
    return obj


def _unjson(obj: Any):
    if isinstance(obj, dict):
        return {k: _unjson(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_unjson(v) for v in obj]
    if obj in ("inf", "-inf", "nan"):
        return float(obj)
    return obj


def _cells_from_json(c):
    if c is None:
        return None
    return {"type": c["type"], "connectivity": np.asarray(c["connectivity"], dtype=np.int64)}
