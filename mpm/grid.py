"""Structured background grid and the nodal field arrays (layout: mpm/LAYOUT.md).

Node (i, j[, k]) sits at ``origin + (i, j[, k]) * cell`` and has the flattened index
``n = i + nx*(j + ny*k)``. Cell sizes may differ per axis.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from interfaces.errors import CaseError


@dataclass
class Grid:
    """Axis-aligned structured grid of dimension D = len(cell)."""

    origin: np.ndarray  # (D,) position of node 0
    cell: np.ndarray    # (D,) cell sizes dx, dy(, dz)
    nn: np.ndarray      # (D,) node counts nx, ny(, nz)

    def __post_init__(self):
        self.origin = np.ascontiguousarray(self.origin, dtype=np.float64)
        self.cell = np.ascontiguousarray(self.cell, dtype=np.float64)
        self.nn = np.ascontiguousarray(self.nn, dtype=np.int64)
        if not (self.origin.shape == self.cell.shape == self.nn.shape):
            raise CaseError("grid origin, cell and node counts must have the same dimension")
        if np.any(self.cell <= 0):
            raise CaseError(f"discretization.mpm.cell must be > 0, got {self.cell.tolist()}")

    @property
    def D(self) -> int:
        return int(self.cell.size)

    @property
    def N(self) -> int:
        return int(np.prod(self.nn))

    @property
    def cell_volume(self) -> float:
        return float(np.prod(self.cell))

    @classmethod
    def around(cls, lo, hi, cell, padding: int = 3, anchor=None) -> "Grid":
        """Grid covering the box [lo, hi] with at least ``padding`` empty cells on every side.

        Node lines pass through ``anchor`` (default ``lo``, so that body edges aligned
        with ``lo`` lie on grid lines, where boundary conditions are applied). A fixed
        anchor such as the coordinate origin gives a grid fixed in space, so that moving
        a specimen moves it relative to the grid (000 Fig 8, interface at mid-cell).
        """
        lo = np.asarray(lo, float)
        hi = np.asarray(hi, float)
        cell = np.broadcast_to(np.asarray(cell, float), lo.shape).copy()
        if anchor is None:
            start = lo
        else:
            anchor = np.broadcast_to(np.asarray(anchor, float), lo.shape)
            start = anchor + np.floor((lo - anchor) / cell + 1e-9) * cell
        ncell = np.ceil((hi - start) / cell - 1e-9).astype(np.int64)
        origin = start - padding * cell
        nn = ncell + 2 * padding + 1
        return cls(origin, cell, nn)

    def node_index(self, ijk: np.ndarray) -> np.ndarray:
        """Flattened index n = i + nx*(j + ny*k) of integer node coordinates (..., D)."""
        ijk = np.asarray(ijk, dtype=np.int64)
        n = ijk[..., -1].copy()
        for d in range(self.D - 2, -1, -1):
            n = n * self.nn[d] + ijk[..., d]
        return n

    def node_positions(self) -> np.ndarray:
        """(N, D) node coordinates in flattened-index order."""
        axes = [self.origin[d] + self.cell[d] * np.arange(self.nn[d]) for d in range(self.D)]
        mesh = np.meshgrid(*axes, indexing="ij")
        # flattened index runs fastest along x: Fortran order of the (nx, ny, nz) array
        return np.stack([m.ravel(order="F") for m in mesh], axis=1)


@dataclass
class NodalFields:
    """Nodal arrays of mpm/LAYOUT.md for N nodes, M material fields, dimension D."""

    N: int
    M: int
    D: int
    mass: np.ndarray = field(init=False)
    momentum: np.ndarray = field(init=False)
    force: np.ndarray = field(init=False)
    volume: np.ndarray = field(init=False)
    volume_gradient: np.ndarray = field(init=False)
    displacement: np.ndarray = field(init=False)
    position: np.ndarray = field(init=False)
    velocity: np.ndarray = field(init=False)      # core only: p/m for G2P
    acceleration: np.ndarray = field(init=False)  # core only: f/m for G2P

    def __post_init__(self):
        N, M, D = self.N, self.M, self.D
        self.mass = np.zeros((N, M))
        self.momentum = np.zeros((N, M, D))
        self.force = np.zeros((N, M, D))
        self.velocity = np.zeros((N, M, D))
        self.acceleration = np.zeros((N, M, D))
        multi = M > 1
        # the multimaterial-only arrays are allocated with zero nodes in single-material runs
        Nm = N if multi else 0
        self.volume = np.zeros((Nm, M))
        self.volume_gradient = np.zeros((Nm, M, D))
        self.displacement = np.zeros((Nm, M, D))
        self.position = np.zeros((Nm, M, D))
