"""Nodes seen by three materials (004 Sec 3.4): two contact laws solved together (Eq 49),
checked against the laws themselves, and the explicit treatment in the time step against
single-material MPM (004 Fig 4)."""
from __future__ import annotations

import numpy as np
import pytest

from mpm.multimaterial_constants import LAW_FRICTION, LAW_PERFECT, LAW_STICK
from mpm.multimaterial_three import two_pair_impulses


def _solve(masses, vel, normals, codes, mu):
    J = np.zeros((2, len(vel[0])))
    mask = two_pair_impulses(np.asarray(masses, float), np.asarray(vel, float),
                             np.asarray(normals, float), np.asarray(codes, np.int64),
                             np.asarray(mu, float), J)
    v = np.asarray(vel, float)
    after = v.copy()
    after[0] += J[0] / masses[0]
    after[1] += J[1] / masses[1]
    after[2] -= (J[0] + J[1]) / masses[2]
    return mask, J, after


def _unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


@pytest.mark.parametrize("dim", [2, 3])
def test_stick_pairs_end_at_the_centre_of_mass_velocity(dim):
    rng = np.random.default_rng(3)
    masses = rng.uniform(0.5, 2.0, 3)
    normals = [_unit(rng.normal(size=dim)) for _ in range(2)]
    # alpha and beta at rest, gamma pressing on both: both stick impulses are compressive
    vel = np.zeros((3, dim))
    vel[2] = -2.0 * (normals[0] + normals[1])
    mask, J, after = _solve(masses, vel, normals, [LAW_STICK, LAW_PERFECT], [0.0, 0.0])
    assert mask == 3
    com = (masses[:, None] * vel).sum(0) / masses.sum()
    np.testing.assert_allclose(after, np.broadcast_to(com, after.shape), atol=1e-12)


@pytest.mark.parametrize("dim", [2, 3])
def test_frictionless_pairs_close_their_normal_velocities_only(dim):
    rng = np.random.default_rng(7)
    for _ in range(20):
        masses = rng.uniform(0.5, 2.0, 3)
        normals = np.array([_unit(rng.normal(size=dim)) for _ in range(2)])
        vel = rng.normal(size=(3, dim))
        mask, J, after = _solve(masses, vel, normals, [LAW_FRICTION] * 2, [0.0, 0.0])
        momentum = (masses[:, None] * after).sum(0) - (masses[:, None] * vel).sum(0)
        np.testing.assert_allclose(momentum, 0.0, atol=1e-12)
        for k in range(2):
            if mask & (1 << k):
                jn = J[k] @ normals[k]
                assert jn <= 1e-14                                   # compressive
                np.testing.assert_allclose(J[k], jn * normals[k], atol=1e-12)   # no friction
                assert (after[2] - after[k]) @ normals[k] == pytest.approx(0.0, abs=1e-12)
            else:
                np.testing.assert_array_equal(J[k], 0.0)


def test_a_pair_the_other_contact_would_pull_is_released():
    """Gamma over alpha and beta (both normals +y): alpha strikes gamma fast, beta only
    creeps up. Solved together, beta would be pulled up behind gamma (a tensile impulse):
    beta-gamma is not a contact, and alpha-gamma is solved alone (gamma leaves beta)."""
    masses = [1.0, 1.0, 1.0]
    vel = [[0.0, 1.0], [0.0, 0.01], [0.0, 0.0]]
    normals = [[0.0, 1.0], [0.0, 1.0]]
    mask, J, after = _solve(masses, vel, normals, [LAW_FRICTION] * 2, [0.0, 0.0])
    assert mask == 1
    np.testing.assert_allclose(after[0], [0.0, 0.5])
    np.testing.assert_allclose(after[2], [0.0, 0.5])
    np.testing.assert_allclose(after[1], vel[1])


@pytest.mark.parametrize("dim", [2, 3])
def test_coulomb_pairs_stick_inside_and_slide_on_their_cone(dim):
    rng = np.random.default_rng(11)
    seen = set()
    for _ in range(200):
        masses = rng.uniform(0.5, 2.0, 3)
        normals = np.array([_unit(rng.normal(size=dim)) for _ in range(2)])
        vel = rng.normal(size=(3, dim))
        mu = rng.uniform(0.05, 0.6, 2)
        mask, J, after = _solve(masses, vel, normals, [LAW_FRICTION] * 2, mu)
        for k in range(2):
            if not mask & (1 << k):
                continue
            n = normals[k]
            jn = J[k] @ n
            jt = np.linalg.norm(J[k] - jn * n)
            rel = after[2] - after[k]
            assert jn <= 1e-13
            assert jt <= -mu[k] * jn * (1 + 1e-9) + 1e-13            # inside or on the cone
            assert rel @ n == pytest.approx(0.0, abs=1e-11)
            if jt < -mu[k] * jn * (1 - 1e-9):                         # strictly inside: stuck
                np.testing.assert_allclose(rel, 0.0, atol=1e-11)
                seen.add("stick")
            else:
                seen.add("slide")
    assert seen == {"stick", "slide"}
