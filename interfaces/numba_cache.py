"""Keep numba's on-disk cache of a package consistent with its sources.

numba (``cache=True``) keys each cached function on the modification time of the
file that defines it, not of the files it calls. A kernel that calls (and inlines) a
function from another module therefore keeps running the old machine code after that
module is edited: wrong results, or a segmentation fault when a signature changed
(seen while developing mpm: a chunk of time steps kept the previous P2G). Installs
from a wheel or sdist rewrite every file, so users are not affected; editable installs
and checkouts are. :func:`drop_stale_cache` compares one digest of all the package's
sources with the digest stored beside the cache and empties the cache when they differ.
"""
from __future__ import annotations

import hashlib
from pathlib import Path

_STAMP = "numba_sources.sha1"


def drop_stale_cache(package_dir: str | Path) -> bool:
    """Delete ``package_dir/__pycache__/*.nbi|*.nbc`` when any ``*.py`` of the package
    changed since the cache was written. Returns True if the cache was dropped. Never
    raises (a read-only install simply keeps its cache)."""
    try:
        here = Path(package_dir)
        digest = hashlib.sha1()
        for src in sorted(here.glob("*.py")):
            digest.update(src.name.encode())
            digest.update(src.read_bytes())
        value = digest.hexdigest()
        cache = here / "__pycache__"
        stamp = cache / _STAMP
        if stamp.is_file() and stamp.read_text().strip() == value:
            return False
        dropped = False
        if cache.is_dir():
            for f in list(cache.glob("*.nbi")) + list(cache.glob("*.nbc")):
                f.unlink(missing_ok=True)
                dropped = True
        cache.mkdir(exist_ok=True)
        stamp.write_text(value)
        return dropped
    except OSError:
        return False
