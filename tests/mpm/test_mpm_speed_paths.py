"""The fast MPM paths against their references.

* the block-parallel P2G/G2P (mpm/parallel.py) against one serial block: equal to
  round-off (only the order of the nodal sums changes), and bit-identical whatever the
  number of threads executing the blocks;
* the scalar 1D shape weights of the hot loops against the uGIMP formula.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cases.library import dls
from mpm.options import merge
from mpm.parallel import BlockBuffers
from mpm.shape import LINEAR, SNAP, UGIMP, axis_weights_tuple, gimp_1d, snapped
from mpm.solver import Model, _Runner

ROOT = Path(__file__).resolve().parents[2]


def _run(case, overrides: dict, steps: int, blocks: int = 1):
    model = Model(case, merge(case, dict({"progress": False}, **overrides)))
    run = _Runner(model)
    run.block_buffers = BlockBuffers(blocks, model.grid.N, model.M, model.M > 1)
    hist = run._advance(steps)
    return model, run, hist


def _state(model, run, hist) -> dict:
    pt = model.particles
    out = {"x": pt.x, "v": pt.v, "stress": pt.stress, "strain": pt.strain, "volume": pt.volume,
           "hist": hist, "mass": model.nodal.mass, "force": model.nodal.force}
    if model.node_out is not None:
        out["node_out"] = model.node_out
    return out


def _block():
    """One body (a single material field): fixed bottom, sheared top."""
    from interfaces import Body, BoundaryCondition, Case, IsotropicElastic, Rectangle
    mat = IsotropicElastic(E=1000.0, nu=0.3, rho=1e-9)
    return Case(name="block", analysis="plane_strain", thickness=1.0, materials={"m": mat},
                bodies=[Body("b", Rectangle(0, 0, 10, 10), "m")],
                boundary_conditions=[
                    BoundaryCondition("fixed", "b", "ymin", ("x", "y"), (0.0, 0.0)),
                    BoundaryCondition("traction", "b", "ymax", ("x", "y"), (1.0, -5.0))])


def _rel(a, b) -> float:
    return float(np.abs(a - b).max() / max(np.abs(a).max(), 1e-300))


@pytest.mark.parametrize("name,case,overrides", [
    ("single_block", lambda: _block(), {"cell": 0.25}),
    ("dls_imperfect", lambda: dls(Dt=5.0, Dn=50.0, mpm_cell=0.4), {}),
])
def test_mpm_parallel_blocks_equal_serial(name, case, overrides):
    c = case()
    serial = _state(*_run(c, overrides, 120, blocks=1))
    for blocks in (2, 3):
        par = _state(*_run(c, overrides, 120, blocks=blocks))
        for key in ("x", "v", "stress", "strain"):
            assert _rel(serial[key], par[key]) < 1e-12, (name, blocks, key)
        h0, h1 = serial["hist"], par["hist"]
        for col in range(8):
            scale = max(np.abs(h0[:, col]).max(), 1e-300)
            assert np.abs(h0[:, col] - h1[:, col]).max() <= 1e-11 * scale, (name, blocks, col)


_THREADS_SCRIPT = """
import json, sys
import numpy as np
sys.path.insert(0, {root!r})
import numba
from cases.library import dls
from mpm.options import merge
from mpm.parallel import BlockBuffers
from mpm.solver import Model, _Runner
case = dls(Dt=5.0, Dn=50.0, mpm_cell=0.4)
m = Model(case, merge(case, {{"progress": False}}))
r = _Runner(m)
r.block_buffers = BlockBuffers(2, m.grid.N, m.M, True)
h = r._advance(60)
print(json.dumps({{"threads": numba.get_num_threads(), "x": m.particles.x.tolist(),
                   "hist": h.tolist()}}))
"""


def _python(script: str, timeout: float, **env) -> str:
    """Run ``script`` in a new Python process with ``env`` added; its standard output."""
    res = subprocess.run([sys.executable, "-c", script], env=dict(os.environ, **env),
                         capture_output=True, text=True, timeout=timeout)
    assert res.returncode == 0, res.stderr[-2000:]
    return res.stdout


def test_mpm_parallel_blocks_independent_of_thread_count():
    """Same blocks on 1 and 2 threads: bit-identical (the block sums are added in
    block order, never in thread order)."""
    out = []
    for threads in (1, 2):
        stdout = _python(_THREADS_SCRIPT.format(root=str(ROOT)), 600, NUMBA_NUM_THREADS=str(threads))
        out.append(json.loads(stdout.strip().splitlines()[-1]))
    assert [o["threads"] for o in out] == [1, 2]
    assert out[0]["x"] == out[1]["x"]
    assert out[0]["hist"] == out[1]["hist"]


_CACHE_SCRIPT = """
import sys
sys.path.insert(0, {root!r})
import numpy as np
import cases
from cases.methods import run
from mpm.step import run_steps
case = cases.build("ellipse_compaction", contact="LR", mpm_cell=0.025, strain=0.02,
                   three_material="lump")
res = run(case, "mpm", progress=False, shape="cpdi", xpic=5)
np.save({out!r}, res.fields["position"] + res.fields["displacement"])
print(sum(run_steps.stats.cache_hits.values()), sum(run_steps.stats.cache_misses.values()))
"""


@pytest.mark.slow
def test_kernels_compiled_in_the_process_equal_their_cached_copies(tmp_path):
    """The first run after the kernels compile and a run on numba's cache are bit-identical
    (interfaces/jit.py, fast math: with reassociation they were 1.1e-15 mm apart here).
    004 Fig 6 at 0.025 mm to 2 % compression, LR, CPDI + XPIC(5): the chaotic packing
    carries any round-off difference on. Cold compile in a fresh cache folder: ~6 min."""
    loaded = []
    for which in ("compiled", "cached"):
        script = _CACHE_SCRIPT.format(root=str(ROOT), out=str(tmp_path / f"{which}.npy"))
        # NUMBA_CACHE_DIR empty counts as unset (numba and interfaces/numba_cache.py)
        stdout = _python(script, 1800, IMPERFECT_CACHE_DIR=str(tmp_path / "numba"),
                         NUMBA_CACHE_DIR="")
        loaded.append(tuple(int(k) for k in stdout.split()[-2:]))
    assert loaded == [(0, 1), (1, 0)]     # the time step compiled, then loaded from the cache
    compiled, cached = (np.load(tmp_path / f"{which}.npy") for which in ("compiled", "cached"))
    assert np.array_equal(compiled, cached)


@settings(max_examples=300, deadline=None)
@given(x=st.floats(min_value=-3.0, max_value=40.0, allow_nan=False),
       h=st.sampled_from([0.1, 0.25, 1.0, 3.0]),
       lp_ratio=st.sampled_from([0.1, 0.25, 0.5]))
def test_mpm_axis_weights_tuple_matches_gimp_formula(x, h, lp_ratio):
    o = -5.0
    lp = lp_ratio * h
    i0, n, *wd = axis_weights_tuple(x, o, h, lp, UGIMP)
    w, dw = wd[:3], wd[3:]
    assert n in (2, 3)
    # a support end within SNAP cells of a node line is on it (the reference is taken
    # there: the stencil moved by the end's distance to the line)
    base = o + (np.floor((x - o) / h + 0.5) - 1.0) * h
    r0 = x - base
    for end in (h + lp, h - lp):
        if abs(r0 - end) < SNAP * h:
            x = base + end
    # round-off of the local coordinate (x - x_i) / h grows with |x - o| / h, and the
    # uGIMP gradient divides it by l_p (fused multiply-adds change the last bits)
    tol_w = 64.0 * np.finfo(float).eps * (abs(x - o) / h + 1.0)
    tol_dw = tol_w / lp
    listed = {}
    for k in range(n):
        ref_w, ref_dw = gimp_1d(x - (o + (i0 + k) * h), h, lp)
        assert abs(w[k] - ref_w) < tol_w and abs(dw[k] - ref_dw) < tol_dw
        listed[i0 + k] = w[k]
    # every node with a nonzero weight or gradient is listed
    for i in range(i0 - 2, i0 + 5):
        if i not in listed:
            w_i, dw_i = gimp_1d(x - (o + i * h), h, lp)
            assert abs(w_i) < tol_w and abs(dw_i) < tol_dw   # zero up to round-off
    assert abs(sum(w[:n]) - 1.0) < 1e-13          # partition of unity
    assert abs(sum(dw[:n])) * h < 1e-12
    i0, n, *wd = axis_weights_tuple(x, o, h, lp, LINEAR)
    r = snapped((x - o) / h) - i0            # a point within SNAP cells of a node is on it
    assert n == 2 and 0.0 <= r < 1.0 and wd[0] == 1.0 - r and wd[1] == r


@pytest.mark.parametrize("end", [1.0, -1.0])
@pytest.mark.parametrize("offset", [0.0, 1e-15, -1e-15, 3e-13])
def test_a_ugimp_support_end_near_a_node_line_gets_the_weights_of_the_tie(end, offset):
    """A particle filling its cells (l_p = h/4) has its support end on a node line; put
    there or moved by round-off, it reaches the same nodes with the tie's weights (the
    node beyond: 0; else the limits of the tail and linear piece), not a ~1e-32 tail."""
    o, h, lp = -5.0, 0.05, 0.0125
    x = o + 7 * h + end * lp + offset   # nearest node 7, support end on node 6 / 8
    i0, n, *wd = axis_weights_tuple(x, o, h, lp, UGIMP)
    w, dw = wd[:n], wd[3:3 + n]
    a = lp / h
    assert n == 2
    if end > 0:
        assert i0 == 7 and np.allclose(w, [1 - a, a], rtol=0, atol=1e-12)
    else:
        assert i0 == 6 and np.allclose(w, [a, 1 - a], rtol=0, atol=1e-12)
    assert np.allclose(np.array(dw) * h, [-1, 1], rtol=0, atol=1e-12)


def test_ugimp_compaction_does_not_depend_on_round_off_of_its_lattice():
    """004 Fig 6 packing with uGIMP and DF contact, up to the piston's first contact
    (0.5 %): particles moved by 1e-15 mm give the stress of the unmoved lattice to
    round-off. Before, ties decided it: the shape functions' (a support end on a node
    line) and then the rigid normal's (a corner node beside the piston's flat face,
    tests/mpm/test_mpm_multimaterial.py): -0.13 MPa unmoved against exactly 0 moved."""
    import cases
    case = cases.build("ellipse_compaction", mpm_cell=0.05, strain=0.005, contact="DF")
    stress = []
    for eps in (0.0, 1e-15):
        model = Model(case, merge(case, {"progress": False, "shape": "ugimp"}))
        model.particles.x += eps * np.random.default_rng(1).uniform(-1, 1, model.particles.x.shape)
        run = _Runner(model)
        run.run()
        stress.append(model.particles.stress.copy())
    peak = np.abs(stress[0]).max()
    assert peak > 1.0                        # MPa: the piston has reached the packing
    assert np.abs(stress[1] - stress[0]).max() < 1e-9 * peak
