"""Sweeps keep every finished point: a failing point is recorded with its error, an
interrupt keeps what finished, and --resume completes the sweep to the same numbers."""
import json
import math

import pytest

import cases.sweep as sweep_module
from cases.cli import main
from cases.sweep import sweep
from interfaces import CaseError, SolverError

VALUES = [0.1, 0.3, 1.0, 3.0]
REAL_RUN = sweep_module.run


def _faulty_run(fail_at, interrupt_at):
    real = REAL_RUN

    def run(case, method, **options):
        Dn = case.interfaces[0].law.Dn
        if Dn == fail_at:
            raise SolverError("diverged: lower dt")
        if Dn == interrupt_at:
            raise KeyboardInterrupt
        return real(case, method, **options)
    return run


def test_failed_point_recorded_interrupt_keeps_points_and_resume_completes(tmp_path, monkeypatch):
    reference = sweep("dcb", "Dn", VALUES, methods="analytic", workers=1)
    monkeypatch.setattr(sweep_module, "run", _faulty_run(fail_at=0.3, interrupt_at=3.0))
    rec = tmp_path / "rec"
    with pytest.raises(KeyboardInterrupt):
        sweep("dcb", "Dn", VALUES, methods="analytic", workers=1, record_dir=rec)
    kept = sorted(p.name for p in (rec / "points").iterdir())
    assert kept == ["point_000.json", "point_001.json", "point_002.json"]
    failed = json.loads((rec / "points" / "point_001.json").read_text())["point"]
    assert failed["analytic"] == {"error": "diverged: lower dt"}

    monkeypatch.setattr(sweep_module, "run", _faulty_run(fail_at=0.3, interrupt_at=None))
    calls = []
    real = sweep_module.run_point
    monkeypatch.setattr(sweep_module, "run_point", lambda *a: calls.append(a[1]) or real(*a))
    resumed = sweep("dcb", "Dn", VALUES, methods="analytic", workers=1, record_dir=rec, resume=True)
    assert [c["Dn"] for c in calls] == [3.0]            # only the missing point ran
    assert resumed.errors() == ["Dn=0.3 analytic: diverged: lower dt"]
    for i in (0, 2, 3):
        assert resumed.points[i]["analytic"]["quantities"] == reference.points[i]["analytic"]["quantities"]
    assert "failed" in resumed.table()


def test_resume_refuses_a_different_sweep(tmp_path):
    rec = tmp_path / "rec"
    sweep("dcb", "Dn", VALUES[:2], methods="analytic", workers=1, record_dir=rec)
    with pytest.raises(Exception, match="differs in values"):
        sweep("dcb", "Dn", VALUES, methods="analytic", workers=1, record_dir=rec, resume=True)


def test_cli_sweep_interrupt_then_resume(tmp_path, monkeypatch, capsys):
    out = tmp_path / "sw"
    monkeypatch.setattr(sweep_module, "run", _faulty_run(fail_at=None, interrupt_at=1.0))
    args = ["sweep", "dcb", "--param", "Dn", "--values", "0.1,0.3,1,3", "--methods", "analytic",
            "--workers", "1", "--out", str(out)]
    assert main(args) == 130
    assert f"imperfect sweep --resume {out}" in capsys.readouterr().err
    monkeypatch.undo()
    assert main(["sweep", "--resume", str(out), "--workers", "1"]) == 0
    text = capsys.readouterr().out
    assert text.count("stiffness analytic") == 1      # one summary table
    data = json.loads((out / "sweep.json").read_text())
    assert all(p is not None for p in data["points"])
    k = [p["analytic"]["quantities"]["stiffness"] for p in data["points"]]
    assert all(math.isfinite(x) for x in k) and k == sorted(k)


def test_point_with_a_bug_is_recorded_not_raised(monkeypatch):
    def broken(case, method, **options):
        raise ZeroDivisionError("float division by zero")
    monkeypatch.setattr(sweep_module, "run", broken)
    sw = sweep("dcb", "Dn", [1.0], methods="analytic", workers=1)
    assert sw.errors()[0].startswith("Dn=1.0 analytic: ZeroDivisionError: float division by zero (at ")


def test_interrupted_mpm_point_resumes_from_its_checkpoint(tmp_path, interrupt_mpm):
    """An MPM point interrupted mid-run keeps its solver state next to the record and the
    resumed sweep continues it to the numbers of an uninterrupted sweep, bit for bit."""
    kw = dict(methods="mpm", fixed={"mpm_cell": 1.0}, workers=1)
    reference = sweep("two_layer", "Dt", [5.0, 50.0], **kw)
    rec = tmp_path / "rec"
    patch = interrupt_mpm(4)
    with pytest.raises(KeyboardInterrupt):
        sweep("two_layer", "Dt", [5.0, 50.0], record_dir=rec, **kw)
    patch.undo()
    state = rec / "points" / "point_000.mpm.npz"
    assert state.exists() and not (rec / "points" / "point_000.json").exists()
    resumed = sweep("two_layer", "Dt", [5.0, 50.0], record_dir=rec, resume=True, **kw)
    assert not state.exists()
    for i in range(2):
        mine, ref = resumed.points[i]["mpm"]["quantities"], reference.points[i]["mpm"]["quantities"]
        assert mine == ref, i


def test_sweep_refuses_a_shared_mpm_checkpoint(tmp_path):
    with pytest.raises(CaseError, match="mpm option checkpoint is not for sweeps"):
        sweep("two_layer", "Dt", [5.0, 50.0], methods="mpm", workers=1,
              options={"mpm": {"checkpoint": str(tmp_path / "x.npz")}})


def test_interrupt_of_a_parallel_sweep_keeps_finished_points_and_stops_the_workers(tmp_path,
                                                                                   monkeypatch):
    """Ctrl-C while worker processes run (workers=2): the sweep raises KeyboardInterrupt
    (the CLI turns it into one line), the finished point is kept and no worker is left
    running."""
    real_completed = sweep_module.as_completed

    def interrupted(futures):
        for k, fut in enumerate(real_completed(futures)):
            if k == 1:
                raise KeyboardInterrupt
            yield fut

    stopped = []
    real_stop = sweep_module._stop_workers
    monkeypatch.setattr(sweep_module, "as_completed", interrupted)
    monkeypatch.setattr(sweep_module, "_stop_workers",
                        lambda procs: stopped.extend(procs) or real_stop(procs, grace=5.0))
    rec = tmp_path / "rec"
    with pytest.raises(KeyboardInterrupt):
        sweep("dcb", "Dn", VALUES, methods="analytic", workers=2, record_dir=rec)
    assert len(list((rec / "points").glob("point_*.json"))) >= 1
    assert stopped and not any(proc.is_alive() for proc in stopped)
