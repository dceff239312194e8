"""interfaces.numba_cache: the numba cache of a package is dropped when any of its
sources changes (numba itself only checks the file defining each function)."""
from __future__ import annotations

from interfaces.numba_cache import drop_stale_cache


def test_cache_dropped_when_any_source_changes(tmp_path):
    (tmp_path / "kernels.py").write_text("x = 1\n")
    (tmp_path / "chunk.py").write_text("y = 2\n")
    cache = tmp_path / "__pycache__"
    cache.mkdir()
    entry = cache / "chunk.run-12.py311.nbi"
    entry.write_bytes(b"index")
    (cache / "chunk.run-12.py311.1.nbc").write_bytes(b"code")
    assert drop_stale_cache(tmp_path)            # no stamp yet: a cache of unknown sources
    assert not any(cache.glob("*.nb?"))
    entry.write_bytes(b"index")
    assert not drop_stale_cache(tmp_path)        # same sources: kept
    assert entry.exists()
    (tmp_path / "kernels.py").write_text("x = 3\n")   # a callee's module edited
    assert drop_stale_cache(tmp_path)
    assert not entry.exists()


def test_missing_directory_is_harmless(tmp_path):
    assert drop_stale_cache(tmp_path / "absent") is False


def test_kernels_cached_outside_the_package(tmp_path, monkeypatch):
    """A package registered with use_project_cache gets its numba cache in the per-user
    folder, not in its own __pycache__ (which pip uninstall would leave behind)."""
    import subprocess
    import sys
    import textwrap

    pkg = tmp_path / "src" / "kpkg"
    pkg.mkdir(parents=True)
    (pkg / "__init__.py").write_text(textwrap.dedent("""
        from interfaces.numba_cache import use_project_cache
        CACHE = use_project_cache(__path__[0])
        from .k import twice
    """))
    (pkg / "k.py").write_text(textwrap.dedent("""
        from numba import njit
        @njit(cache=True)
        def twice(x):
            return 2 * x
    """))
    root = tmp_path / "cache"
    env = {**__import__("os").environ, "IMPERFECT_CACHE_DIR": str(root),
           "PYTHONPATH": f"{tmp_path / 'src'}:{__import__('os').getcwd()}"}
    env.pop("NUMBA_CACHE_DIR", None)
    code = "import kpkg; assert kpkg.twice(21) == 42; print(kpkg.CACHE)"
    out = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True)
    cache = out.stdout.strip()
    assert cache.startswith(str(root))
    assert list(__import__("pathlib").Path(cache).glob("k.twice-*.nbi"))
    assert not list(pkg.glob("__pycache__/*.nb?"))
    assert not (pkg / "__pycache__" / "numba_sources.sha1").exists()
