"""Resumable ``imperfect run``: nothing computed is lost to an interrupt.

While a run works, its output folder holds ``.checkpoint/``: the command (case TOML,
methods, options), the Result of each method as soon as it finishes, and MPM's state
(mpm/checkpoint.py, saved every few minutes and on Ctrl-C). ``imperfect run --resume
DIR`` reads the command back, keeps the finished methods, continues MPM from its state
and runs what is missing. A run that completes replaces the folder with its outputs,
so the checkpoint goes with the old contents.
"""
from __future__ import annotations

import json
import shutil
from pathlib import Path

from interfaces import Case, CaseError
from interfaces.result import Result

from .output import atomic_write_text

CHECKPOINT = ".checkpoint"


class RunRecord:
    """The ``.checkpoint`` folder of one run's output folder ``out``."""

    def __init__(self, out: Path):
        self.folder = Path(out) / CHECKPOINT

    def start(self, case: Case, methods: str, options: dict, no_vtk: bool, series: int) -> None:
        """A new run: forget an earlier run's checkpoint, record this command."""
        if self.folder.exists():
            shutil.rmtree(self.folder)
        self.folder.mkdir(parents=True)
        spec = {"case": case.to_toml(), "methods": methods, "options": options,
                "no_vtk": no_vtk, "series": series}
        atomic_write_text(self.folder / "run.json", json.dumps(spec, indent=1))

    def load(self) -> dict:
        """The recorded command of an interrupted run (``--resume``)."""
        path = self.folder / "run.json"
        if not path.exists():
            raise CaseError(f"--resume {self.folder.parent}: no interrupted run is recorded there "
                            f"(no {CHECKPOINT}/run.json); start it with imperfect run CASE --out "
                            f"{self.folder.parent}")
        spec = json.loads(path.read_text())
        spec["case"] = Case.from_toml(spec["case"])
        return spec

    def finished(self) -> dict[str, Result]:
        """Results of the methods that finished before the interrupt."""
        out = {}
        for path in sorted(self.folder.glob("result_*.json")):
            out[path.stem[len("result_"):]] = Result.from_json(path)
        return out

    def save_result(self, method: str, result: Result) -> None:
        atomic_write_text(self.folder / f"result_{method}.json", result.to_json())

    def with_mpm_checkpoint(self, options: dict, resume: bool) -> dict:
        """``options`` with MPM saving its state here (and continuing from it)."""
        return with_mpm_checkpoint(options, self.folder / "mpm.npz", resume)


def with_mpm_checkpoint(options: dict, path: Path, resume: bool) -> dict:
    """Per-method ``options`` with MPM saving its state to ``path`` every few minutes and
    on Ctrl-C, and continuing from it when ``resume`` (a checkpoint option given by the
    user is kept)."""
    out = {k: dict(v) for k, v in options.items()}
    mpm = out.setdefault("mpm", {})
    mpm.setdefault("checkpoint", str(path))
    mpm["resume"] = resume
    return out
