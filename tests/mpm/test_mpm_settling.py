"""The quasi-static stop of ``mpm.solve`` (mpm/solver.py ``_Runner._settled``) on
synthetic energy histories: a residual vibration about the static state is rest, a creep
is not."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from mpm.solver import HIST_COLUMNS, _Runner

WINDOW = 400          # steps in half a period
U0 = 3.5e-4           # stored energy (N mm) of the DCB at P = 0.01 N


def _runner(strain: np.ndarray, kinetic: np.ndarray, chunk: int = 37) -> _Runner:
    """A runner whose history holds ``strain`` energy and grid ``kinetic`` energy per step,
    in chunks of ``chunk`` steps like the output intervals."""
    runner = _Runner(SimpleNamespace(opts={"tol": 1e-6, "tol_energy": 1e-4}))
    hist = np.zeros((strain.size, len(HIST_COLUMNS)))
    hist[:, 2], hist[:, 7] = strain, kinetic
    runner.hist_chunks = [hist[i:i + chunk] for i in range(0, strain.size, chunk)]
    return runner


def _vibration(energy_ratio: float, steps: int = 5 * WINDOW) -> tuple[np.ndarray, np.ndarray]:
    """Stored and kinetic energy of a vibration of energy ``energy_ratio`` x U0 about a
    static state U0 whose deformation it overlaps: U = U0 + 2 sqrt(e U0) sin + e sin^2
    (the cross term dominates), KE = e cos^2. A higher mode: 7.3 periods per window."""
    phase = 2.0 * math.pi * np.arange(steps) * 7.3 / WINDOW
    e = energy_ratio * U0
    return U0 + 2.0 * math.sqrt(e * U0) * np.sin(phase) + e * np.sin(phase) ** 2, e * np.cos(phase) ** 2


def test_a_residual_vibration_about_the_static_state_is_rest():
    """The DCB (0.3 mm cells) kept 1e-7 of its stored energy in vibration: its stored energy
    swung by 1.3e-3 of itself (the cross term with the static deformation), which the
    spread test of the stop (below tol_energy = 1e-4 over half a period) never passed."""
    strain, kinetic = _vibration(1e-7)
    assert np.ptp(strain[-WINDOW:]) > 10 * 1e-4 * U0
    assert _runner(strain, kinetic)._settled(WINDOW)


def test_a_creep_is_not_rest_however_small_the_kinetic_energy():
    """An over-damped mode creeping by 2e-4 of the stored energy per half period, with
    kinetic energy 1e-9 of it, is not rest; at 5e-5 per half period it is."""
    steps = np.arange(5 * WINDOW)
    kinetic = np.full(steps.size, 1e-9 * U0)
    assert not _runner(U0 * (1.0 + 2e-4 * steps / WINDOW), kinetic)._settled(WINDOW)
    assert _runner(U0 * (1.0 + 5e-5 * steps / WINDOW), kinetic)._settled(WINDOW)


def test_kinetic_energy_above_tol_is_not_rest():
    """A vibration of 2e-6 of the stored energy exceeds tol = 1e-6: not settled; a history
    shorter than two windows is never settled."""
    strain, kinetic = _vibration(2e-6)
    assert not _runner(strain, kinetic)._settled(WINDOW)
    strain, kinetic = _vibration(1e-8, steps=2 * WINDOW - 1)
    assert not _runner(strain, kinetic)._settled(WINDOW)
