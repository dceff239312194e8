"""K_ff, the tangent over the free independent DOFs, against P^T K P restricted to the free DOFs."""
import math

import numpy as np
import pytest
import scipy.sparse as sp

from cases import library
from peridynamics.discretization import discretize
from peridynamics.interface import split_band
from peridynamics.reduction import ReducedMatrix
from peridynamics.solver import boundary_vectors, build_system


def _system(case, h):
    delta = 3.01 * h
    disc = discretize(case, h, delta, delta)
    disc, springs, ties = split_band(case, disc)
    system, _ = build_system(case, disc, "continuum", None, springs, ties)
    return disc, system


@pytest.mark.parametrize("Dn,Dt,injective", [(math.inf, math.inf, True), (2e-4, 1e-4, True),
                                              (math.inf, 1e-4, False)])
def test_reduced_tangent_equals_the_projected_tangent(Dn, Dt, injective):
    case = library.bimaterial_square(parameter_set=3, load_case=3, interface="vertical", Dn=Dn, Dt=Dt)
    disc, system = _system(case, 0.1)
    fixed, u_bar, _ = boundary_vectors(disc)
    dofs = system.dofs
    free = np.setdiff1d(np.arange(dofs.n), np.unique(dofs.index[fixed]))
    rng = np.random.default_rng(4)
    K = system.evaluate(0.02 * 0.1 * rng.standard_normal(disc.X.shape)).tangent
    red = ReducedMatrix(system, free)
    assert red.injective == injective
    P = sp.csr_matrix((np.ones(disc.X.size), (np.arange(disc.X.size), dofs.index)), shape=(disc.X.size, dofs.n))
    ref = (P.T @ K @ P).tocsr()[free][:, free].toarray()
    Kff = red(K.data)
    assert Kff.has_sorted_indices and not np.any(np.diff(Kff.indptr) < 0)
    assert np.abs(Kff.toarray() - ref).max() <= 1e-14 * np.abs(ref).max()
    # every reduced entry has a source: the pattern holds exactly the structurally coupled pairs
    assert Kff.nnz == sp.csr_matrix(P.T @ sp.csr_matrix((np.ones(K.nnz), K.indices, K.indptr), K.shape) @ P)[free][:, free].nnz
    if injective:
        out = np.empty(Kff.nnz)
        assert np.shares_memory(red(K.data, out=out).data, out) and red.gather.dtype == np.int32


@pytest.mark.parametrize("Dn,Dt,direct", [(math.inf, math.inf, True), (2e-4, 1e-4, True), (math.inf, 1e-4, False)])
def test_tangent_assembled_into_the_free_dofs_equals_the_reduced_one(Dn, Dt, direct):
    """The kernels adding straight into K_ff (reduced_target: no full tangent, no gather) give
    K_ff bit for bit, springs and partly fixed nodes (rollers) included, and with the pair part
    evaluated in the same pass the pair tangent of the separate (C1, 0, 0) system bit for bit;
    the ties of a perfect direction (DOFs identified) keep the two-pass path."""
    from peridynamics.assembly import reduced_target
    from peridynamics.preconditioner import PairTangent

    case = library.bimaterial_square(parameter_set=3, load_case=3, interface="vertical", Dn=Dn, Dt=Dt)
    disc, system = _system(case, 0.1)
    fixed, _, _ = boundary_vectors(disc)
    dofs = system.dofs
    rng = np.random.default_rng(5)
    rollers = rng.choice(dofs.n, 40, replace=False)          # one component of some nodes fixed too
    free = np.setdiff1d(np.arange(dofs.n), np.concatenate([np.unique(dofs.index[fixed]), rollers]))
    u = 0.02 * 0.1 * rng.standard_normal(disc.X.shape)
    red = ReducedMatrix(system, free)
    target = reduced_target(system, red)
    assert (target is not None) == direct
    if not direct:
        return
    assert np.any(np.isin(np.arange(dofs.n), free).reshape(-1, system.dim).sum(axis=1) == 1)    # partly fixed
    ref = red(system.evaluate(u).tangent.data)
    pairs = PairTangent(system, free)
    P_ref = pairs(u).copy()
    buf = np.full(target.nnz, np.nan)
    ev = system.evaluate(u, out=buf, target=target, pairs=pairs.fused)
    assert np.shares_memory(ev.tangent.data, buf)
    assert np.array_equal(ev.tangent.indptr, ref.indptr) and np.array_equal(ev.tangent.indices, ref.indices)
    assert np.array_equal(ev.tangent.data, ref.data)
    assert np.array_equal(ev.pair_tangent.indices, P_ref.indices) and np.array_equal(ev.pair_tangent.data, P_ref.data)
    assert system.evaluate(u, target=target).pair_tangent is None
