"""Particle output as VTK: one VTU per output step plus a ParaView ``.pvd`` index."""
from __future__ import annotations

import os
from pathlib import Path

import numpy as np


def _vtu(path: Path, position: np.ndarray, fields: dict) -> None:
    import meshio

    pts = np.asarray(position, float)
    n = len(pts)
    if pts.shape[1] == 2:
        pts = np.hstack([pts, np.zeros((n, 1))])
    data = {}
    for k, v in fields.items():
        a = np.asarray(v)
        if a.ndim == 2 and a.shape[1] == 2:
            a = np.hstack([a, np.zeros((n, 1))])
        data[k] = a
    meshio.write(str(path), meshio.Mesh(pts, [("vertex", np.arange(n, dtype=np.int64)[:, None])],
                                        point_data=data))


def write_vtk_series(directory: str | os.PathLike, frames: list[tuple[float, np.ndarray, dict]],
                     prefix: str = "mpm") -> Path:
    """Write ``frames`` = [(time, position (P, D), {name: (P, ...) array}), ...].

    One ``{prefix}_{k:05d}.vtu`` per frame and ``{prefix}.pvd`` listing them with their
    times (open the .pvd in ParaView). Returns the .pvd path.
    """
    out = Path(directory)
    out.mkdir(parents=True, exist_ok=True)
    entries = []
    for k, (t, pos, fields) in enumerate(frames):
        name = f"{prefix}_{k:05d}.vtu"
        _vtu(out / name, pos, fields)
        entries.append(f'    <DataSet timestep="{t:.9g}" group="" part="0" file="{name}"/>')
    pvd = out / f"{prefix}.pvd"
    pvd.write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                   "  <Collection>\n" + "\n".join(entries) + "\n  </Collection>\n</VTKFile>\n")
    return pvd
