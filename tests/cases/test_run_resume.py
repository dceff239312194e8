"""``imperfect run`` keeps what it computed when interrupted and ``--resume DIR``
completes it to the outputs of an uninterrupted run (cases/resume.py, mpm/checkpoint.py)."""
from __future__ import annotations

import json

from cases.cli import main

ARGS = ["two_layer", "--methods", "fem,mpm", "--set", "mpm_cell=1", "--set", "fem_h=1", "--no-vtk"]


def _results(folder) -> dict:
    return json.loads((folder / "results.json").read_text())["results"]


def test_interrupted_run_resumes_to_the_uninterrupted_outputs(tmp_path, capsys, interrupt_mpm):
    ref_dir, run_dir = tmp_path / "ref", tmp_path / "run"
    assert main(["run", *ARGS, "--out", str(ref_dir)]) == 0
    patch = interrupt_mpm(4)
    assert main(["run", *ARGS, "--out", str(run_dir)]) == 130
    patch.undo()
    err = capsys.readouterr().err
    assert f"imperfect run --resume {run_dir}" in err.splitlines()[-1]
    kept = run_dir / ".checkpoint"
    assert (kept / "result_fem.json").exists() and (kept / "mpm.npz").exists()
    assert not (run_dir / "results.json").exists()
    assert main(["run", "--resume", str(run_dir)]) == 0
    assert "[fem] kept from the interrupted run" in capsys.readouterr().err
    assert not kept.exists()                       # a completed run leaves no checkpoint
    ref, res = _results(ref_dir), _results(run_dir)
    for method in ("fem", "mpm"):
        for q in ("strain_energy", "interface_energy"):
            assert res[method]["quantities"][q] == ref[method]["quantities"][q], (method, q)
    assert res["mpm"]["diagnostics"]["time_steps"] == ref["mpm"]["diagnostics"]["time_steps"]


def test_resume_without_a_recorded_run_is_one_line(tmp_path, capsys):
    assert main(["run", "--resume", str(tmp_path / "nothing")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("error: --resume") and "\n" not in err
    assert main(["run", "two_layer", "--resume", str(tmp_path)]) == 2
    assert main(["run", "--out", str(tmp_path / "x")]) == 2
