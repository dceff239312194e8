"""Shapes of bodies and holes, point-in-shape tests and named sides.

2D: :class:`Rectangle` (optionally rotated), :class:`Polygon`, :class:`Ellipse`,
:class:`Circle`; 3D: :class:`Box`, :class:`Sphere`. Lengths in mm, angles in degrees.

Rectangles and boxes have named sides ``xmin xmax ymin ymax (zmin zmax)`` in their own
(possibly rotated) frame; boundary conditions and measurements refer to a body's side.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, fields
from typing import ClassVar

import numpy as np

from .errors import CaseError, build_tagged, check_number

SIDES = ("xmin", "xmax", "ymin", "ymax", "zmin", "zmax")
CURVE_SIDE = "boundary"
"""The one side of a circle or ellipse: its whole curve (e.g. the outer surface of a composite sphere)."""


class Shape:
    """Base class: ``contains(points, tol)``, ``bounds()``, ``dimension``."""

    kind: ClassVar[str] = ""
    dimension: ClassVar[int] = 2

    def contains(self, points, tol: float = 0.0) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def bounds(self) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover - abstract
        raise NotImplementedError

    def to_dict(self) -> dict:
        d = {"type": self.kind}
        for f in fields(self):
            v = getattr(self, f.name)
            d[f.name] = [list(p) for p in v] if f.name == "vertices" else v
        return d

    def _points(self, points) -> np.ndarray:
        p = np.asarray(points, dtype=float)
        if p.ndim == 1:
            p = p[None, :]
        if p.shape[1] != self.dimension:
            raise CaseError(f"{self.kind}: points must have {self.dimension} coordinates, got shape {p.shape}")
        return p


#: largest |coordinate| or size of a shape (mm): beyond it the sums of the geometry
#: (bounds, corners) overflow or lose all precision
MAX_COORDINATE = 1e30


def _pos(name, v):
    return check_number(name, v, low=0, high=MAX_COORDINATE, low_open=True)


def _checked(shape, numbers=(), positives=()) -> None:
    """Validate and store fields of a frozen shape: ``numbers`` within +-MAX_COORDINATE,
    ``positives`` in (0, MAX_COORDINATE]."""
    for n in numbers:
        object.__setattr__(shape, n, check_number(n, getattr(shape, n), low=-MAX_COORDINATE,
                                                  high=MAX_COORDINATE))
    for n in positives:
        object.__setattr__(shape, n, _pos(n, getattr(shape, n)))


class _Sided(Shape):
    """Axis-aligned box in its own frame (origin + size), rotated by ``angle`` in 2D."""

    def _rotation(self) -> np.ndarray:
        a = math.radians(getattr(self, "angle", 0.0))
        if self.dimension == 2:
            return np.array([[math.cos(a), -math.sin(a)], [math.sin(a), math.cos(a)]])
        return np.eye(3)

    @property
    def origin(self) -> np.ndarray:
        return np.array([self.x0, self.y0] + ([self.z0] if self.dimension == 3 else []), dtype=float)

    @property
    def size(self) -> np.ndarray:
        if self.dimension == 2:
            return np.array([self.width, self.height], dtype=float)
        return np.array([self.wx, self.wy, self.wz], dtype=float)

    def to_local(self, points) -> np.ndarray:
        """Coordinates in the shape's frame (origin at its min corner, axes along its sides)."""
        return (self._points(points) - self.origin) @ self._rotation()

    def to_global(self, local) -> np.ndarray:
        return np.asarray(local, dtype=float) @ self._rotation().T + self.origin

    def contains(self, points, tol: float = 0.0) -> np.ndarray:
        q = self.to_local(points)
        return np.all((q >= -tol) & (q <= self.size + tol), axis=1)

    def corners(self) -> np.ndarray:
        s = self.size
        if self.dimension == 2:
            loc = np.array([[0, 0], [s[0], 0], [s[0], s[1]], [0, s[1]]], dtype=float)
        else:
            loc = np.array([[i * s[0], j * s[1], k * s[2]] for k in (0, 1) for j in (0, 1) for i in (0, 1)], dtype=float)
        return self.to_global(loc)

    def bounds(self):
        c = self.corners()
        return c.min(axis=0), c.max(axis=0)

    def _side(self, side: str) -> tuple[int, bool]:
        valid = SIDES[: 2 * self.dimension]
        if side not in valid:
            raise CaseError(f"side must be one of {', '.join(valid)}, got {side!r}")
        return valid.index(side) // 2, side.endswith("max")

    def edge_distance(self, points, side: str) -> np.ndarray:
        """Signed distance of the points from the named side along its inward normal
        (positive inside the shape)."""
        axis, is_max = self._side(side)
        q = self.to_local(points)[:, axis]
        return self.size[axis] - q if is_max else q

    def edge_mask(self, points, side: str, tol: float) -> np.ndarray:
        """Points within ``tol`` of the named side (and within the side's extent)."""
        q = self.to_local(points)
        inside = np.all((q >= -tol) & (q <= self.size + tol), axis=1)
        return inside & (np.abs(self.edge_distance(points, side)) <= tol)

    def edge_length(self, side: str) -> float:
        """Length (2D) or area (3D) of the named side."""
        axis, _ = self._side(side)
        return float(np.prod(np.delete(self.size, axis)))

    def edge_normal(self, side: str) -> np.ndarray:
        """Outward unit normal of the named side in global axes."""
        axis, is_max = self._side(side)
        n = np.zeros(self.dimension)
        n[axis] = 1.0 if is_max else -1.0
        return self._rotation() @ n

    def edge_segment(self, side: str) -> np.ndarray:
        """2D: the side's two end points in global axes (counter-clockwise order)."""
        c = self.corners()
        return {"ymin": c[[0, 1]], "xmax": c[[1, 2]], "ymax": c[[2, 3]], "xmin": c[[3, 0]]}[side]


_SHAPES: dict[str, type] = {}


def _register(cls):
    _SHAPES[cls.kind] = cls
    return cls


@_register
@dataclass(frozen=True)
class Rectangle(_Sided):
    """Rectangle with min corner (x0, y0), size width x height, rotated by ``angle`` degrees about (x0, y0)."""

    x0: float
    y0: float
    width: float
    height: float
    angle: float = 0.0
    kind: ClassVar[str] = "rectangle"
    dimension: ClassVar[int] = 2

    def __post_init__(self):
        _checked(self, ("x0", "y0", "angle"), ("width", "height"))


@_register
@dataclass(frozen=True)
class Box(_Sided):
    """Axis-aligned box with min corner (x0, y0, z0) and sizes wx, wy, wz."""

    x0: float
    y0: float
    z0: float
    wx: float
    wy: float
    wz: float
    kind: ClassVar[str] = "box"
    dimension: ClassVar[int] = 3

    def __post_init__(self):
        _checked(self, ("x0", "y0", "z0"), ("wx", "wy", "wz"))


@_register
@dataclass(frozen=True)
class Polygon(Shape):
    """Simple polygon given by its vertices (counter-clockwise or clockwise)."""

    vertices: tuple
    kind: ClassVar[str] = "polygon"
    dimension: ClassVar[int] = 2

    def __post_init__(self):
        try:
            v = np.asarray(self.vertices, dtype=float)
        except (TypeError, ValueError):
            raise CaseError(f"vertices must be a list of [x, y] pairs, got {self.vertices!r}") from None
        if v.ndim != 2 or v.shape[1] != 2 or len(v) < 3 or not np.all(np.abs(v) <= MAX_COORDINATE):
            raise CaseError(f"vertices must be at least 3 [x, y] pairs within +-{MAX_COORDINATE:g} mm, "
                            f"got {self.vertices!r}")
        if abs(_polygon_area(v)) == 0:
            raise CaseError("vertices enclose no area")
        object.__setattr__(self, "vertices", tuple(tuple(map(float, p)) for p in v))

    def contains(self, points, tol: float = 0.0) -> np.ndarray:
        p = self._points(points)
        v = np.asarray(self.vertices)
        x, y = p[:, 0:1], p[:, 1:2]
        x1, y1 = v[:, 0], v[:, 1]
        x2, y2 = np.roll(x1, -1), np.roll(y1, -1)
        cond = (y1 > y) != (y2 > y)
        with np.errstate(divide="ignore", invalid="ignore"):
            xint = x1 + (y - y1) * (x2 - x1) / (y2 - y1)
        inside = np.count_nonzero(cond & (x < xint), axis=1) % 2 == 1
        if tol > 0:
            inside |= _segment_distance(p, v) <= tol
        return inside

    def bounds(self):
        v = np.asarray(self.vertices)
        return v.min(axis=0), v.max(axis=0)


def _polygon_area(v: np.ndarray) -> float:
    x, y = v[:, 0], v[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _segment_distance(p: np.ndarray, v: np.ndarray) -> np.ndarray:
    a, b = v, np.roll(v, -1, axis=0)
    ab = b - a
    t = np.clip(np.einsum("pkd,kd->pk", p[:, None, :] - a[None], ab) / np.einsum("kd,kd->k", ab, ab), 0, 1)
    proj = a[None] + t[..., None] * ab[None]
    return np.linalg.norm(p[:, None, :] - proj, axis=2).min(axis=1)


@_register
@dataclass(frozen=True)
class Ellipse(Shape):
    """Ellipse with centre (cx, cy), semi-axes a (along the rotated x) and b, rotated by ``angle`` degrees."""

    cx: float
    cy: float
    a: float
    b: float
    angle: float = 0.0
    kind: ClassVar[str] = "ellipse"
    dimension: ClassVar[int] = 2

    def __post_init__(self):
        _checked(self, ("cx", "cy", "angle"), ("a", "b"))

    def contains(self, points, tol: float = 0.0) -> np.ndarray:
        p = self._points(points) - [self.cx, self.cy]
        t = math.radians(self.angle)
        u = p[:, 0] * math.cos(t) + p[:, 1] * math.sin(t)
        w = -p[:, 0] * math.sin(t) + p[:, 1] * math.cos(t)
        with np.errstate(over="ignore"):     # far from a tiny ellipse: inf, outside
            return (u / (self.a + tol)) ** 2 + (w / (self.b + tol)) ** 2 <= 1.0

    def edge_mask(self, points, side: str, tol: float) -> np.ndarray:
        """Points within ``tol`` of the curve (side ``"boundary"``, the only side of an ellipse)."""
        _curve_side(side, self.kind)
        p = self._points(points) - [self.cx, self.cy]
        t = math.radians(self.angle)
        u = p[:, 0] * math.cos(t) + p[:, 1] * math.sin(t)
        w = -p[:, 0] * math.sin(t) + p[:, 1] * math.cos(t)
        # distance to the curve to first order: |F| / |grad F| with F = (u/a)^2 + (w/b)^2 - 1
        with np.errstate(over="ignore", divide="ignore", invalid="ignore"):  # tiny ellipse: inf
            F = (u / self.a) ** 2 + (w / self.b) ** 2 - 1.0
            g = 2.0 * np.hypot(u / self.a ** 2, w / self.b ** 2)
            return np.isfinite(F) & (np.abs(F) <= tol * np.maximum(g, 1e-300))

    def bounds(self):
        t = math.radians(self.angle)
        hx = math.hypot(self.a * math.cos(t), self.b * math.sin(t))
        hy = math.hypot(self.a * math.sin(t), self.b * math.cos(t))
        return np.array([self.cx - hx, self.cy - hy]), np.array([self.cx + hx, self.cy + hy])


@_register
@dataclass(frozen=True)
class Circle(Shape):
    """Circle with centre (cx, cy) and radius r."""

    cx: float
    cy: float
    r: float
    kind: ClassVar[str] = "circle"
    dimension: ClassVar[int] = 2

    def __post_init__(self):
        _checked(self, ("cx", "cy"), ("r",))

    def contains(self, points, tol: float = 0.0) -> np.ndarray:
        p = self._points(points)
        return np.hypot(p[:, 0] - self.cx, p[:, 1] - self.cy) <= self.r + tol

    def edge_mask(self, points, side: str, tol: float) -> np.ndarray:
        """Points within ``tol`` of the circle (side ``"boundary"``, the only side of a circle)."""
        _curve_side(side, self.kind)
        p = self._points(points)
        return np.abs(np.hypot(p[:, 0] - self.cx, p[:, 1] - self.cy) - self.r) <= tol

    def bounds(self):
        return np.array([self.cx - self.r, self.cy - self.r]), np.array([self.cx + self.r, self.cy + self.r])


def _curve_side(side: str, kind: str) -> None:
    if side != CURVE_SIDE:
        raise CaseError(f"side of a {kind} must be {CURVE_SIDE!r} (its whole curve), got {side!r}")


@_register
@dataclass(frozen=True)
class Sphere(Shape):
    """Sphere with centre (cx, cy, cz) and radius r."""

    cx: float
    cy: float
    cz: float
    r: float
    kind: ClassVar[str] = "sphere"
    dimension: ClassVar[int] = 3

    def __post_init__(self):
        _checked(self, ("cx", "cy", "cz"), ("r",))

    def contains(self, points, tol: float = 0.0) -> np.ndarray:
        p = self._points(points)
        return np.linalg.norm(p - [self.cx, self.cy, self.cz], axis=1) <= self.r + tol

    def bounds(self):
        c = np.array([self.cx, self.cy, self.cz])
        return c - self.r, c + self.r


def shape_from_dict(d: dict, where: str = "shape") -> Shape:
    """Build a shape from its TOML table; errors name ``where.field``."""
    return build_tagged(_SHAPES, d, where)