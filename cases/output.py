"""Output folders that are never left half written.

``staged_output(out)`` gives a temporary sibling folder to write into; when the block
ends normally the folder replaces ``out`` in two renames (the old one is moved aside
first and deleted last), so an interrupt leaves either the old outputs or the new
ones, never a mix. ``atomic_write_text`` does the same for one file (sweep points).
``check_output_dir`` refuses an impossible ``--out`` before any computation.
"""
from __future__ import annotations

import contextlib
import os
import shutil
import tempfile
from pathlib import Path

from interfaces import CaseError


def check_output_dir(out: str | Path, replaceable=None) -> Path:
    """``out`` as a Path if a folder can be created or replaced there; a CaseError
    naming ``--out`` otherwise (a file in the way, no permission, ...). With
    ``replaceable`` (glob patterns), a folder holding anything else is refused too."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise CaseError(f"--out {out} is a file, not a folder; name a folder")
    foreign = foreign_files(out, replaceable) if replaceable is not None else []
    if foreign:
        shown = ", ".join(foreign[:3]) + (", ..." if len(foreign) > 3 else "")
        raise CaseError(f"--out {out} holds other files ({shown}); name a new folder or an earlier "
                        "run's folder")
    parent = out.resolve().parent
    for above in (parent, *parent.parents):
        if above.exists():
            if not above.is_dir():
                raise CaseError(f"--out {out}: {above} is a file, not a folder")
            break
    try:
        parent.mkdir(parents=True, exist_ok=True)
        probe = tempfile.mkdtemp(prefix=f".{out.name}.probe-", dir=parent)
        os.rmdir(probe)
    except OSError as e:
        raise CaseError(f"--out {out}: cannot write there ({e.strerror or e})") from None
    return out


#: what ``imperfect run`` writes into its folder (anything else there is the user's)
RUN_OUTPUTS = ("case.toml", "results.json", "comparison.csv", "*_comparison.png", "*.vtu", "*.pvd",
               "*_vtk")


def foreign_files(out: Path, patterns=RUN_OUTPUTS) -> list[str]:
    """Entries of ``out`` that an earlier run did not write."""
    if not out.is_dir():
        return []
    return sorted(p.name for p in out.iterdir()
                  if not p.name.startswith(".") and not any(p.match(g) for g in patterns))


@contextlib.contextmanager
def staged_output(out: str | Path):
    """Yield a fresh temporary folder beside ``out``; on success it becomes ``out``.
    A folder holding files of its own (not an earlier run's outputs) is refused, never
    replaced."""
    out = check_output_dir(out, RUN_OUTPUTS)
    parent = out.resolve().parent
    stage = Path(tempfile.mkdtemp(prefix=f".{out.name}.new-", dir=parent))
    os.chmod(stage, 0o777 & ~_umask())      # mkdtemp makes it private; a run's folder is not
    try:
        yield stage
    except BaseException:
        shutil.rmtree(stage, ignore_errors=True)
        raise
    old = None
    if out.exists():
        old = Path(tempfile.mkdtemp(prefix=f".{out.name}.old-", dir=parent))
        os.rmdir(old)
        os.replace(out, old)
    os.replace(stage, out)
    if old is not None:
        shutil.rmtree(old, ignore_errors=True)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def atomic_write_text(path: str | Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file and a rename."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        raise


__all__ = ["check_output_dir", "staged_output", "atomic_write_text", "foreign_files", "RUN_OUTPUTS"]
