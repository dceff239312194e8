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
