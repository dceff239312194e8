"""Checkpoint and resume of an MPM run (mpm/checkpoint.py): an interrupted run continued
from its checkpoint ends exactly where the uninterrupted run ends."""
from __future__ import annotations

import json

import numpy as np
import pytest

import mpm
from cases.library import two_layer
from interfaces import CaseError


def test_interrupted_run_resumes_to_the_uninterrupted_result(tmp_path, interrupt_mpm):
    case = two_layer(mpm_cell=1.0)
    ref = mpm.solve(case, progress=False)
    path = tmp_path / "mpm.npz"
    opts = {"progress": False, "checkpoint": str(path), "checkpoint_every": 1e9}
    patch = interrupt_mpm(5)
    with pytest.raises(KeyboardInterrupt):
        mpm.solve(case, **opts)
    patch.undo()
    assert path.exists()
    wall_before = json.loads(bytes(np.load(path)["scalars"]).decode())["wall"]
    res = mpm.solve(case, resume=True, **opts)
    # the run's wall time (hence its particle-steps/s) counts the part before the resume
    assert 0.0 < wall_before < res.timings["run"] <= res.timings["total"]
    assert res.diagnostics["time_steps"] == ref.diagnostics["time_steps"]
    for key in ("displacement", "stress", "velocity"):
        assert np.array_equal(res.fields[key], ref.fields[key]), key
    for q in ("strain_energy", "interface_energy", "external_work", "dissipated_energy"):
        assert res.quantities[q] == ref.quantities[q], q
    assert res.diagnostics["history"] == ref.diagnostics["history"]


def test_a_checkpoint_of_another_case_is_refused(tmp_path, interrupt_mpm):
    path = tmp_path / "mpm.npz"
    opts = {"progress": False, "checkpoint": str(path), "checkpoint_every": 1e9}
    interrupt_mpm(2)
    with pytest.raises(KeyboardInterrupt):
        mpm.solve(two_layer(mpm_cell=1.0), **opts)
    with pytest.raises(CaseError, match="another case or other options"):
        mpm.solve(two_layer(mpm_cell=1.0, Dt=7.0), resume=True, **opts)
    with pytest.raises(CaseError, match="resume needs the checkpoint"):
        mpm.solve(two_layer(mpm_cell=1.0), resume=True, progress=False)
