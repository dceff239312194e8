"""Where numba keeps the compiled kernels of this project's packages, and keeping that
cache consistent with the sources.

Location. numba's default (``cache=True``) writes ``*.nbi``/``*.nbc`` files into the
package's own ``__pycache__``. For an installed package that folder is not pip's: ``pip
uninstall`` leaves it behind (it is not in the wheel's RECORD), and the orphaned
``site-packages/mpm/`` then shadows a later editable install as an empty namespace
package (``module 'mpm' has no attribute 'solve'``). :func:`use_project_cache` therefore
sends the kernels of a package to a per-user cache folder, ``$IMPERFECT_CACHE_DIR`` or
``$XDG_CACHE_HOME/imperfect-interfaces/numba`` (default ``~/.cache/...``), one subfolder
per package location, through a numba cache locator that claims only that package's
files (a user's own numba code keeps numba's defaults). ``NUMBA_CACHE_DIR``, when the
user sets it, wins as numba documents.

Consistency. numba keys each cached function on the modification time of the file that
defines it, not of the files it calls. A kernel that calls (and inlines) a function from
another module therefore keeps running the old machine code after that module is edited:
wrong results, or a segmentation fault when a signature changed (seen while developing
mpm: a chunk of time steps kept the previous P2G). :func:`drop_stale_cache` compares one
digest of all the package's sources with the digest stored beside the cache and empties
the cache when they differ.
"""
from __future__ import annotations

import hashlib
import os
from pathlib import Path

_STAMP = "numba_sources.sha1"
_CLAIMED: dict[str, Path] = {}     # package folder -> its cache folder


def cache_root() -> Path:
    """The per-user folder holding this project's numba caches."""
    env = os.environ.get("IMPERFECT_CACHE_DIR")
    if env:
        return Path(env)
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "imperfect-interfaces" / "numba"


def cache_dir_for(package_dir: str | Path) -> Path:
    """The cache folder of one package location (a checkout and an install differ)."""
    here = os.path.abspath(package_dir)
    digest = hashlib.sha1(here.encode()).hexdigest()[:16]
    return cache_root() / f"{os.path.basename(here)}_{digest}"


def use_project_cache(package_dir: str | Path) -> Path | None:
    """Send the numba cache of the package at ``package_dir`` to :func:`cache_dir_for`
    and drop it if stale. Call before any kernel module of the package is imported.
    Returns the folder used, or None when numba's own locators stay in charge (the user
    set ``NUMBA_CACHE_DIR``, or this numba has no locator hook)."""
    package_dir = os.path.abspath(package_dir)
    if os.environ.get("NUMBA_CACHE_DIR"):
        return None
    target = cache_dir_for(package_dir)
    try:
        target.mkdir(parents=True, exist_ok=True)
    except OSError:
        return None               # unwritable home: numba falls back to its defaults
    if not _install_locator():
        return None
    _CLAIMED[package_dir + os.sep] = target
    drop_stale_cache(package_dir, target)
    return target


def _install_locator() -> bool:
    try:
        from numba.core import caching
    except ImportError:
        return False
    impl = getattr(caching, "CacheImpl", None)
    base = getattr(caching, "UserProvidedCacheLocator", None)
    if impl is None or base is None or not hasattr(impl, "_locator_classes"):
        return False
    if any(getattr(c, "_imperfect_project", False) for c in impl._locator_classes):
        return True

    class ProjectCacheLocator(base):
        """Claims the functions defined in a package registered by use_project_cache."""

        _imperfect_project = True

        def __init__(self, py_func, py_file):
            self._py_file = py_file
            self._lineno = py_func.__code__.co_firstlineno
            self._cache_path = str(_claimed_dir(py_file))

        @classmethod
        def from_function(cls, py_func, py_file):
            if _claimed_dir(py_file) is None:
                return None
            return super(base, cls).from_function(py_func, py_file)

    impl._locator_classes.insert(0, ProjectCacheLocator)
    return True


def cache_is_cold(package_dir: str | Path) -> bool:
    """True when no compiled kernel of the package is cached yet (first run of an
    installation, or sources changed): the next run compiles for minutes."""
    package_dir = os.path.abspath(package_dir)
    cache = _CLAIMED.get(package_dir + os.sep, Path(package_dir) / "__pycache__")
    try:
        return not any(Path(cache).glob("*.nbi"))
    except OSError:
        return False


def _claimed_dir(py_file: str) -> Path | None:
    path = os.path.abspath(py_file)
    for prefix, target in _CLAIMED.items():
        if path.startswith(prefix) and os.sep not in path[len(prefix):]:
            return target
    return None


def drop_stale_cache(package_dir: str | Path, cache: str | Path | None = None) -> bool:
    """Delete the ``*.nbi|*.nbc`` files of ``cache`` (default: ``package_dir/__pycache__``)
    when any ``*.py`` of the package changed since the cache was written. Returns True if
    the cache was dropped. Never raises (a read-only cache simply stays)."""
    try:
        here = Path(package_dir)
        digest = hashlib.sha1()
        for src in sorted(here.glob("*.py")):
            digest.update(src.name.encode())
            digest.update(src.read_bytes())
        value = digest.hexdigest()
        cache = Path(cache) if cache is not None else here / "__pycache__"
        stamp = cache / _STAMP
        if stamp.is_file() and stamp.read_text().strip() == value:
            return False
        dropped = False
        if cache.is_dir():
            for f in list(cache.glob("*.nbi")) + list(cache.glob("*.nbc")):
                f.unlink(missing_ok=True)
                dropped = True
        if not here.is_dir():
            return dropped
        cache.mkdir(parents=True, exist_ok=True)
        stamp.write_text(value)
        return dropped
    except OSError:
        return False
