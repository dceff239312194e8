"""Test-suite settings. In CI (environment variable CI set) hypothesis draws its examples
from a fixed seed, so a submission's result does not depend on the draw; locally each run
explores new examples (and keeps failing ones in .hypothesis/)."""
import importlib.util
import os
import pathlib
import types

import pytest
from hypothesis import settings

settings.register_profile("ci", derandomize=True, print_blob=True)
if os.environ.get("CI"):
    settings.load_profile("ci")

#: the thread pools of the BLAS / LAPACK / PARDISO libraries
THREAD_VARIABLES = ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS")


def pytest_configure(config):
    """pytest-xdist runs one worker process per core. Their BLAS and PARDISO thread pools
    would each start a thread per core, and a pool thread that waits for a core held by
    the other worker stalls every parallel region it joins: the FEM wave test, 952
    PARDISO solves, took 88 s beside a compiling worker against 3 s alone. The workers
    (started after this hook, inheriting the environment) therefore get cores / workers
    threads each, unless the variables are already set. numba's own pool is left as it
    is: its tests of thread-count independence need two threads."""
    workers = getattr(config.option, "numprocesses", None)
    if not isinstance(workers, int) or workers < 2 or os.environ.get("PYTEST_XDIST_WORKER"):
        return
    threads = str(max(1, (os.cpu_count() or 1) // workers))
    for name in THREAD_VARIABLES:
        os.environ.setdefault(name, threads)


class _InterruptAfter:
    """Stands for the Ctrl-C flag of an MPM run (mpm.solver._InterruptFlag): raised when
    the run starts its ``after``-th output interval, as if Ctrl-C came then."""
    instance = None

    def __init__(self, enabled: bool):
        self.raised = False
        _InterruptAfter.instance = self

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return None


@pytest.fixture
def interrupt_mpm(monkeypatch):
    """``interrupt_mpm(n)``: the next MPM runs stop as on Ctrl-C at their n-th interval
    (saving their checkpoint first)."""
    import mpm.solver as S

    def arm(intervals: int) -> None:
        calls = {"n": 0}
        advance = S._Runner._advance

        def counted(self, nsteps):
            calls["n"] += 1
            if calls["n"] == intervals:
                _InterruptAfter.instance.raised = True
            return advance(self, nsteps)

        monkeypatch.setattr(S, "_InterruptFlag", _InterruptAfter)
        monkeypatch.setattr(S._Runner, "_advance", counted)
        return monkeypatch

    return arm


@pytest.fixture(scope="session")
def references() -> types.SimpleNamespace:
    """The models of tests/references, written without the solver packages (independent
    references for them), loaded by path (the tests folder is not a package)."""
    folder = pathlib.Path(__file__).parent / "references"
    modules = {}
    for path in sorted(folder.glob("*.py")):
        spec = importlib.util.spec_from_file_location(f"references_{path.stem}", path)
        modules[path.stem] = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(modules[path.stem])
    return types.SimpleNamespace(**modules)
