"""Shock front of a bar struck at one end: shock speed and the shocked state from the
particle histories (004 Sec 4.3, Fig 7).

``measurements["shock_front"] = {"sample_every": s, "wall": "xmax" | "xmin",
"window": [0.2, 0.8]}``: a bar along x, driven against a rigid wall at its ``wall``
end, carries a plane shock away from the wall. Every ``sample_every`` seconds the gauge
averages the particles' stress over each column of particles of equal reference
position X (the particles' x0), giving the profiles sigma_xx(X), sigma_yy(X). In each
profile the front is where the compressive longitudinal stress -sigma_xx first reaches
half its shocked level (the median of the columns above half the largest value),
interpolated between columns. In reference coordinates the unshocked material is at
rest, so the front's X moves at the shock speed U_s relative to the material ahead
(the speed of the Rankine-Hugoniot jump conditions): U_s is the slope of a least-squares
line through X_front(t) over the samples whose front has run ``window`` (fractions of
the bar's length) from the wall. The shocked state is the mean over those samples of
the columns in the middle of the shocked region (between 30 % and 70 % of the way from
the front back to the wall, clear of the front's ringing and of the wall's start-up):
the longitudinal compressive stress -sigma_xx and the pressure -(sigma_xx + 2 sigma_yy) / 3
(uniaxial strain: F = diag(J, 1, 1) gives sigma_zz = sigma_yy).

Same interface as the other gauges (``times``, ``samples``, ``sample``, ``quantities``,
``history``), so the runner and the checkpoints treat all alike.
"""
from __future__ import annotations

import numpy as np

from interfaces.errors import CaseError, check_number


class ShockFrontGauge:
    """Column-averaged stress profiles of a struck bar over time and its shock front."""

    measurement = "shock_front"

    def __init__(self, case, x0: np.ndarray, spacing):
        spec = dict(case.measurements[self.measurement])
        where = f"measurements.{self.measurement}"
        self.sample_every = check_number(f"{where}.sample_every", spec.get("sample_every"),
                                         low=0.0, low_open=True)
        wall = spec.get("wall", "xmax")
        if wall not in ("xmin", "xmax"):
            raise CaseError(f"{where}.wall must be 'xmin' or 'xmax', got {wall!r}")
        window = spec.get("window", [0.2, 0.8])
        if (not isinstance(window, (list, tuple)) or len(window) != 2
                or not 0.0 <= float(window[0]) < float(window[1]) <= 1.0):
            raise CaseError(f"{where}.window must be two fractions 0 <= a < b <= 1, got {window!r}")
        self.window = (float(window[0]), float(window[1]))
        self.sign = 1.0 if wall == "xmax" else -1.0
        h = float(np.asarray(spacing, float)[0])
        X = np.round(x0[:, 0] / (0.25 * h)) * (0.25 * h)
        self.X, self.column = np.unique(X, return_inverse=True)
        self.count = np.bincount(self.column).astype(float)
        self.wall_X = (self.X.max() + 0.5 * h) if wall == "xmax" else (self.X.min() - 0.5 * h)
        self.length = float(self.X.max() - self.X.min()) + h
        self.times: list[float] = []
        self.samples: list[tuple] = []

    def sample(self, t: float, particles) -> None:
        """Record the column-averaged sigma_xx, sigma_yy at time t (at most every
        ``sample_every``; the runner calls after every chunk of steps) from the run's
        :class:`mpm.particles.Particles` (a column's particles share one volume)."""
        stress = particles.stress
        if self.times and t < self.times[-1] + self.sample_every * (1.0 - 1e-9):
            return
        n = self.X.size
        sxx = np.bincount(self.column, stress[:, 0], n) / self.count
        syy = np.bincount(self.column, stress[:, 1], n) / self.count
        self.times.append(float(t))
        self.samples.append(tuple(np.concatenate([sxx, syy]).tolist()))

    def profiles(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(times, sigma_xx [samples, columns], sigma_yy [samples, columns])."""
        S = np.asarray(self.samples, float).reshape(len(self.samples), 2, self.X.size)
        return np.asarray(self.times), S[:, 0], S[:, 1]

    def front(self, sxx: np.ndarray) -> float:
        """Reference X of the front in one profile (NaN before a shock exists)."""
        s = -sxx
        top = s.max()
        if not top > 0.0:
            return float("nan")
        level = 0.5 * float(np.median(s[s > 0.5 * top]))
        # distance from the wall of every column; the front is the farthest column at
        # or above the level, interpolated towards its unshocked neighbour
        order = np.argsort(self.sign * (self.wall_X - self.X))
        s_w = s[order]
        above = np.flatnonzero(s_w >= level)
        k = above.max()
        X_w = self.X[order]
        if k + 1 >= s_w.size:
            return float(X_w[k])
        a, b = s_w[k], s_w[k + 1]
        frac = (a - level) / (a - b) if a != b else 0.0
        return float(X_w[k] + frac * (X_w[k + 1] - X_w[k]))

    def fronts(self) -> tuple[np.ndarray, np.ndarray]:
        """(times, reference X of the front) of every sample."""
        t, sxx, _ = self.profiles()
        return t, np.array([self.front(row) for row in sxx])

    def _fit(self):
        t, X = self.fronts()
        run = self.sign * (self.wall_X - X) / self.length
        ok = np.isfinite(X) & (run >= self.window[0]) & (run <= self.window[1])
        return t, X, ok

    def quantities(self) -> dict:
        """shock_speed (mm/s), longitudinal_stress and pressure (MPa, compression
        positive) of the shocked state; empty until the front crossed the window."""
        if not self.samples:
            return {}
        t, X, ok = self._fit()
        if ok.sum() < 3:
            return {}
        slope = np.polyfit(t[ok], X[ok], 1)[0]
        _, sxx, syy = self.profiles()
        dist = self.sign * (self.wall_X - self.X)
        sig, prs = [], []
        for i in np.flatnonzero(ok):
            d_front = self.sign * (self.wall_X - X[i])
            mid = (dist >= 0.3 * d_front) & (dist <= 0.7 * d_front)
            sig.append(-sxx[i, mid].mean())
            prs.append(-(sxx[i, mid] + 2.0 * syy[i, mid]).mean() / 3.0)
        return {"shock_speed": float(abs(slope)), "longitudinal_stress": float(np.mean(sig)),
                "pressure": float(np.mean(prs))}

    def history(self) -> dict:
        """Times, the columns' reference X, the profiles and the fronts, for the plots."""
        t, sxx, syy = self.profiles()
        return {"time": t.tolist(), "X": self.X.tolist(), "sigma_xx": sxx.tolist(),
                "sigma_yy": syy.tolist(), "front": self.fronts()[1].tolist()}
