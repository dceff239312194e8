"""Non-overlapping ellipses in a rectangle, reproducible from a seed (004 Fig 6).

004 Sec 4.2 compacts "a box arbitrarily filled with elliptical objects" drawn by hand in
a bitmap. Here the objects are placed by random sequential addition: ``n`` ellipses,
largest first, with areas that sum to ``fill`` of the box (log-normal spread), aspect
ratios in [1.2, 2.5] and any orientation, each at the first random position (from
``seed``) where it keeps ``gap`` from the box's sides and from every ellipse already
placed; an ellipse that finds no place in 1024 tries is shrunk by 5 % and tried again.
The same arguments always give the same ellipses (numpy's PCG64 generator).
"""
from __future__ import annotations

import math

import numpy as np

from interfaces import CaseError, Ellipse

#: boundary points per ellipse in the overlap test (the chord sag at 1.5 aspect ratio and
#: 0.25 mm semi-axis is < 0.1 um, far below any gap in use)
_RIM = 256
_TRIES = 1024
_BATCH = 64


def ellipse_packing(n: int, width: float, height: float, fill: float, gap: float,
                    seed: int) -> list[Ellipse]:
    """``n`` disjoint ellipses in [0, width] x [0, height] covering about ``fill`` of it
    (less if some had to shrink), at least ``gap`` apart and from the sides (mm)."""
    if not (isinstance(n, int) and 1 <= n <= 200):
        raise CaseError(f"n (ellipses) must be an integer in [1, 200], got {n!r}")
    if not 0.0 < fill <= 0.7:
        raise CaseError(f"fill must be in (0, 0.7] (random packings of ellipses jam above), got {fill!r}")
    rng = np.random.default_rng(seed)
    areas = np.sort(rng.lognormal(0.0, 0.35, n))[::-1]
    areas *= fill * width * height / areas.sum()
    placed = np.zeros((0, 5))                 # cx, cy, a, b, angle (rad)
    rims = np.zeros((0, _RIM, 2))
    for area in areas:
        aspect = rng.uniform(1.2, 2.5)
        angle = math.radians(rng.uniform(0.0, 180.0))
        while True:
            a = math.sqrt(area * aspect / math.pi)
            e = _place(rng, a, a / aspect, angle, width, height, gap, placed, rims)
            if e is not None:
                placed = np.vstack([placed, e])
                rims = np.concatenate([rims, _rim(e)[None]])
                break
            area *= 0.95
    return [Ellipse(float(cx), float(cy), float(a), float(b), math.degrees(t)) for cx, cy, a, b, t in placed]


def _place(rng, a, b, angle, width, height, gap, placed, rims) -> np.ndarray | None:
    """The first of ``_TRIES`` random positions (drawn in batches) where the ellipse
    (a, b, angle) keeps ``gap`` from the sides and from the ``placed`` ellipses (their
    boundary points ``rims``), or None."""
    hx = math.hypot(a * math.cos(angle), b * math.sin(angle))
    hy = math.hypot(a * math.sin(angle), b * math.cos(angle))
    x_range = (gap + hx, width - gap - hx)
    y_range = (gap + hy, height - gap - hy)
    if x_range[0] > x_range[1] or y_range[0] > y_range[1]:
        return None
    rim0 = _rim(np.array([0.0, 0.0, a, b, angle]))
    for _ in range(_TRIES // _BATCH):
        c = np.column_stack([rng.uniform(*x_range, _BATCH), rng.uniform(*y_range, _BATCH)])
        ok = np.ones(_BATCH, bool)
        if placed.shape[0]:
            # their rims inside the candidates, the candidates' rims inside them
            cand = np.column_stack([c, np.tile([a, b, angle], (_BATCH, 1))])
            hit = _inside(cand, np.broadcast_to(rims.reshape(1, -1, 2), (_BATCH, rims.shape[0] * _RIM, 2)), gap)
            ok &= ~hit.any(axis=1)
            pts = (rim0[None, :, :] + c[:, None, :]).reshape(-1, 2)
            hit = _inside(placed, np.broadcast_to(pts[None], (placed.shape[0],) + pts.shape), gap)
            ok &= ~hit.reshape(placed.shape[0], _BATCH, _RIM).any(axis=(0, 2))
        first = np.flatnonzero(ok)
        if first.size:
            return np.array([c[first[0], 0], c[first[0], 1], a, b, angle])
    return None


def _rim(e: np.ndarray) -> np.ndarray:
    """Boundary points of the ellipse e = (cx, cy, a, b, angle)."""
    s = np.linspace(0.0, 2.0 * math.pi, _RIM, endpoint=False)
    u, w = e[2] * np.cos(s), e[3] * np.sin(s)
    c, t = math.cos(e[4]), math.sin(e[4])
    return np.column_stack([e[0] + u * c - w * t, e[1] + u * t + w * c])


def _inside(es: np.ndarray, pts: np.ndarray, gap: float) -> np.ndarray:
    """Which points ``pts[k]`` lie inside ellipse ``es[k]`` grown by ``gap`` (K, R)."""
    px = pts[..., 0] - es[:, :1]
    py = pts[..., 1] - es[:, 1:2]
    c, t = np.cos(es[:, 4:5]), np.sin(es[:, 4:5])
    u = px * c + py * t
    w = -px * t + py * c
    return (u / (es[:, 2:3] + gap)) ** 2 + (w / (es[:, 3:4] + gap)) ** 2 <= 1.0
