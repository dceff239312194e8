"""CPD kernels: residual = exact gradient, tangent = exact Hessian, patch test (003 Eq 7, 10)."""
import numpy as np
import pytest

from peridynamics.assembly import CPDSystem, MaterialBlock, neighbour_lists


def _random_system(dim, C, n, seed, delta=0.6, two_materials=False):
    rng = np.random.default_rng(seed)
    X = rng.random((n, dim))
    blocks = []
    if two_materials:  # two overlapping point sets sharing the points with 0.4 < x < 0.6
        setA = np.flatnonzero(X[:, 0] < 0.6)
        setB = np.flatnonzero(X[:, 0] > 0.4)
        for name, mem, scale in (("A", setA, 1.0), ("B", setB, 3.0)):
            nptr, nidx = neighbour_lists(X, mem, delta)
            blocks.append(MaterialBlock(name, mem, nptr, nidx, scale * np.asarray(C, float)))
    else:
        mem = np.arange(n)
        nptr, nidx = neighbour_lists(X, mem, delta)
        blocks.append(MaterialBlock("A", mem, nptr, nidx, np.asarray(C, float)))
    vol = 0.05 + 0.1 * rng.random(n)
    system = CPDSystem(X, vol, blocks, delta)
    u = 0.15 * rng.standard_normal((n, dim))
    return system, u


def _fd_check(system, u, eps=1e-6):
    ev = system.evaluate(u)
    n = u.size
    g = np.empty(n)
    K = np.empty((n, n))
    for k in range(n):
        up = u.ravel().copy()
        um = u.ravel().copy()
        up[k] += eps
        um[k] -= eps
        ep, em = system.evaluate(up, False), system.evaluate(um, False)
        g[k] = (ep.energy - em.energy) / (2 * eps)
        K[:, k] = (ep.residual.ravel() - em.residual.ravel()) / (2 * eps)
    Ka = ev.tangent.toarray()
    err_g = np.linalg.norm(g - ev.residual.ravel()) / np.linalg.norm(g)
    err_K = np.linalg.norm(K - Ka) / np.linalg.norm(K)
    return ev, err_g, err_K, Ka


@pytest.mark.parametrize("dim,C", [(2, (1.3, 0.7, 0.0)), (2, (0.0, -0.9, 0.0)), (3, (1.3, 0.7, 0.9)),
                                   (3, (0.0, 0.0, -1.1))])
def test_residual_and_tangent_are_exact_derivatives(dim, C):
    system, u = _random_system(dim, C, 26 if dim == 2 else 20, seed=dim)
    ev, err_g, err_K, Ka = _fd_check(system, u)
    assert (C[0] == 0 or ev.tuples["pairs"] > 0) and (C[1] == 0 or ev.tuples["triples"] > 0)
    if dim == 3 and C[2] != 0:
        assert ev.tuples["quadruples"] > 0
    assert err_g < 1e-6
    assert err_K < 1e-6
    assert np.allclose(Ka, Ka.T, atol=1e-12 * np.abs(Ka).max())


@pytest.mark.parametrize("dim", [2, 3])
def test_overlapping_materials_share_dofs_exactly(dim):
    """Two material sets on shared points (003 Sec 3.2): derivatives stay exact."""
    C = (1.0, 0.5, 0.3 if dim == 3 else 0.0)
    system, u = _random_system(dim, C, 24 if dim == 2 else 18, seed=7, two_materials=True)
    ev, err_g, err_K, _ = _fd_check(system, u)
    assert err_g < 1e-6 and err_K < 1e-6
    # the energy is the sum of the two materials' energies
    e = [CPDSystem(system.X, system.vol, [b], system.delta).evaluate(u, False).energy for b in system.blocks]
    assert ev.energy == pytest.approx(sum(e), rel=1e-12)


def test_energy_of_one_pair_and_one_triple_by_hand():
    """003 Eq 10 on 3 points: psi1 = 1/2 C1 L (l/L-1)^2, psi2 = 1/2 C2 A (a/A-1)^2 with weights."""
    X = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    u = np.array([[0.0, 0.0], [0.5, 0.0], [0.0, 0.2]])
    vol = np.array([1.0, 1.0, 1.0])
    mem = np.arange(3)
    nptr, nidx = neighbour_lists(X, mem, 1.5)
    C1, C2 = 2.0, 3.0
    W1 = CPDSystem(X, vol, [MaterialBlock("A", mem, nptr, nidx, np.array([C1, 0, 0.0]))], 1.5).evaluate(u, False).energy
    W2 = CPDSystem(X, vol, [MaterialBlock("A", mem, nptr, nidx, np.array([0, C2, 0.0]))], 1.5).evaluate(u, False).energy
    x = X + u
    # pairs: each unordered pair counted from both ends with factor 1/2 -> once
    pairs = [(0, 1), (0, 2), (1, 2)]
    ref1 = sum(0.5 * C1 * np.linalg.norm(X[j] - X[i]) * (np.linalg.norm(x[j] - x[i]) / np.linalg.norm(X[j] - X[i]) - 1) ** 2
               for i, j in pairs)
    # triples: each point is central of one unordered neighbour pair, weight 2 x 1/3
    A = 1.0
    e1, e2 = x[1] - x[0], x[2] - x[0]
    a = abs(e1[0] * e2[1] - e1[1] * e2[0])
    ref2 = 3 * (2.0 / 3.0) * 0.5 * C2 * A * (a / A - 1) ** 2
    assert W1 == pytest.approx(ref1, rel=1e-13)
    assert W2 == pytest.approx(ref2, rel=1e-13)


@pytest.mark.parametrize("dim,n,dfac,C", [(2, 17, 3.01, (1.0, -37.0, 0.0)), (3, 11, 1.51, (1.0, 0.4, 2.5))])
def test_patch_uniform_deformation_gives_zero_interior_residual(dim, n, dfac, C):
    """Uniform F (finite) on a homogeneous grid: zero force at points whose neighbours have full horizons."""
    h = 0.1
    ax = h * np.arange(n)
    X = np.stack(np.meshgrid(*([ax] * dim), indexing="ij"), axis=-1).reshape(-1, dim)
    delta = dfac * h
    mem = np.arange(len(X))
    nptr, nidx = neighbour_lists(X, mem, delta)
    system = CPDSystem(X, np.full(len(X), h ** dim), [MaterialBlock("A", mem, nptr, nidx, np.asarray(C, float))], delta)
    rng = np.random.default_rng(3)
    F = np.eye(dim) + 0.3 * rng.standard_normal((dim, dim))
    assert np.linalg.det(F) > 0.2
    u = X @ (F - np.eye(dim)).T + 0.37            # plus a rigid translation
    ev = system.evaluate(u, False)
    far = np.all((X > 2 * delta + 1e-9) & (X < ax[-1] - 2 * delta - 1e-9), axis=1)
    assert far.sum() >= 1
    scale = np.abs(ev.residual).max()
    assert scale > 0
    assert np.abs(ev.residual[far]).max() < 1e-11 * scale
    # and the points near the free surface do feel a force (the check is not vacuous)
    assert np.abs(ev.residual[~far]).max() > 1e-3 * scale


def test_pattern_refill_is_consistent_between_calls():
    system, u = _random_system(2, (1.0, 0.5, 0.0), 30, seed=11)
    K1 = system.evaluate(u).tangent
    K2 = system.evaluate(u).tangent
    assert K1.nnz == system.pattern.nnz
    assert np.array_equal(K1.indices, K2.indices) and np.allclose(K1.data, K2.data, rtol=0, atol=0)


def test_coloured_parallel_assembly_is_race_free_and_thread_independent():
    """Blocks of one colour never share a node: same result as the serial kernel in the
    original order (to round-off) and bit for bit the same for 1 and 2 threads."""
    import numba

    from peridynamics.kernels import assemble, horizon_radius2

    h = 0.05
    ax = h * np.arange(24)
    X = np.stack(np.meshgrid(ax, ax, indexing="ij"), axis=-1).reshape(-1, 2)
    delta = 3.01 * h
    mem = np.arange(len(X))
    nptr, nidx = neighbour_lists(X, mem, delta)
    C = np.array([1.0, 0.4, 0.0])
    system = CPDSystem(X, np.full(len(X), h * h), [MaterialBlock("A", mem, nptr, nidx, C)], delta)
    colours, blocks = system._colours[0]
    assert len(colours) == 5 and len(blocks) - 1 >= 9
    u = 0.01 * np.random.default_rng(2).standard_normal(X.shape)
    # serial reference: one call over the central points in their original order
    f = np.zeros_like(X)
    data = np.zeros(system.pattern.nnz)
    e_node = np.zeros(len(X))
    c = np.full(len(X), 1.0), np.full(len(X), 0.4), np.zeros(len(X))
    e_ref = assemble(X, u, mem, nptr, nidx, *c, system.vol, True, system.pattern.rowptr, system.pattern.cols,
                     data, f, e_node, horizon_radius2(delta))[0]
    runs = []
    for threads in sorted({1, min(2, numba.config.NUMBA_NUM_THREADS)}):
        numba.set_num_threads(threads)
        runs.append(system.evaluate(u))
    numba.set_num_threads(numba.config.NUMBA_NUM_THREADS)
    ev = runs[-1]
    assert ev.energy == pytest.approx(e_ref, rel=1e-13)
    assert np.allclose(ev.residual, f, rtol=0, atol=1e-13 * np.abs(f).max())
    assert np.allclose(ev.tangent.data, data, rtol=0, atol=1e-13 * np.abs(data).max())
    assert all(np.array_equal(r.tangent.data, runs[0].tangent.data) and r.energy == runs[0].energy for r in runs)


@pytest.mark.parametrize("dim,C", [(2, (1.0, 0.5, 0.0)), (3, (1.0, 0.0, 0.7)), (2, (1.0, 0.0, 0.0))])
def test_block_slots_and_binary_search_scatter_agree(dim, C):
    """The tangent through the block slots found once per pattern equals the one found by
    binary search (the path taken above the memory budget), also for a pair-only material
    (whose neighbour-neighbour blocks are outside the pattern); a refilled buffer equals a
    fresh array."""
    from peridynamics.assembly import full_target

    system, u = _random_system(dim, C, 40 if dim == 2 else 30, seed=7, two_materials=True)
    assert all(len(s) > 0 for s, _ in system.target.slots)
    ev = system.evaluate(u)
    buf = np.full(system.pattern.nnz, np.nan)
    ev_buf = system.evaluate(u, out=buf)
    assert np.shares_memory(ev_buf.tangent.data, buf) and np.array_equal(buf, ev.tangent.data)
    system.target = full_target(system.blocks, system.pattern, system.target.constant, budget=0)
    assert all(len(s) == 0 for s, _ in system.target.slots)
    ev_bs = system.evaluate(u)
    assert np.array_equal(ev_bs.tangent.data, ev.tangent.data)
    assert np.array_equal(ev_bs.residual, ev.residual)
    with pytest.raises(ValueError, match="float64 array"):
        system.evaluate(u, out=np.zeros(3))


def test_pruned_pattern_drops_only_exact_zeros():
    """The tangent pattern keeps the node pairs some non-degenerate tuple couples: on a grid
    (collinear triples, pairs at 2 delta) it is smaller than the 2-delta candidates, and the
    tangent assembled into the candidates has exact zeros everywhere else and equals the
    pruned one."""
    from cases import library
    from peridynamics.assembly import build_pattern
    from peridynamics.discretization import discretize
    from peridynamics.kernels import assemble, horizon_radius2
    from peridynamics.solver import build_system

    h = 0.1
    case = library.bimaterial_square(parameter_set=3, load_case=1, interface="vertical")
    system, _ = build_system(case, discretize(case, h, 3.01 * h, 3.01 * h, grid="cell"), "continuum", None)
    u = 0.01 * h * np.random.default_rng(3).standard_normal(system.X.shape)
    K = system.evaluate(u).tangent.toarray()
    cand = build_pattern(system.X, system.blocks, system.delta, prune=False)
    assert system.pattern.nnz < 0.9 * cand.nnz          # 13 % here, 17 % at 100 x 100 points
    data = np.zeros(cand.nnz)
    f = np.zeros_like(system.X)
    for blk, c in zip(system.blocks, system._cpar):
        assemble(system.X, u, blk.centers, blk.nptr, blk.nidx, *c, system.vol, True, cand.rowptr, cand.cols,
                 data, f, np.zeros(system.n_nodes), horizon_radius2(system.delta))
    Kc = cand.matrix(data).toarray()
    assert np.abs(Kc - K).max() <= 1e-14 * np.abs(K).max()
    kept = system.pattern.matrix(np.ones(system.pattern.nnz)).toarray() > 0
    assert np.count_nonzero(Kc[~kept]) == 0


@pytest.mark.parametrize("dim,C", [(2, (1.0, 0.5, 0.0)), (3, (1.0, 0.3, 0.7)), (2, (1.0, 0.0, 0.0))])
def test_tangent_into_the_free_dofs_equals_the_gathered_one(dim, C):
    """The kernels adding into K_ff (assembly.reduced_target) give the gather of the full
    tangent bit for bit, in 2D and 3D, two overlapping materials, a pair-only material, nodes
    with some components fixed; without block slots (memory budget) the direct path is not
    offered."""
    from peridynamics.assembly import full_target, reduced_target
    from peridynamics.reduction import ReducedMatrix

    system, u = _random_system(dim, C, 40 if dim == 2 else 30, seed=11, two_materials=True)
    rng = np.random.default_rng(12)
    free = np.sort(rng.choice(u.size, u.size - 2 * dim - 5, replace=False))
    assert np.any(np.isin(np.arange(u.size), free).reshape(-1, dim).sum(axis=1) % dim != 0)
    red = ReducedMatrix(system, free)
    target = reduced_target(system, red)
    ref = red(system.evaluate(u).tangent.data)
    K = system.evaluate(u, target=target).tangent
    assert np.array_equal(K.indptr, ref.indptr) and np.array_equal(K.indices, ref.indices)
    assert np.array_equal(K.data, ref.data)
    system.target = full_target(system.blocks, system.pattern, system.target.constant, budget=0)
    assert reduced_target(system, red) is None
