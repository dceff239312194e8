"""What the machine has left for a solver's allocations (shared by the solver packages,
which estimate their memory before allocating and refuse or warn beyond it)."""
from __future__ import annotations

import os

__all__ = ["available_memory"]


def available_memory() -> float | None:
    """Bytes of memory available to a new allocation (Linux MemAvailable, else the free
    physical pages of os.sysconf), None if unknown."""
    try:
        with open("/proc/meminfo") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        pass
    try:
        return float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):
        return None
