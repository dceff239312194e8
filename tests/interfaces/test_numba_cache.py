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
