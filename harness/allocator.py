"""glibc's ``malloc`` held at one state for timings (:func:`steady`).

glibc serves a block above its mmap threshold (128 KiB when a process starts) by a fresh ``mmap``: page faults and
zeroed pages at every allocation. When such a block is freed it raises the threshold to that block's size (and the
heap's trim threshold to twice it), so the same allocation comes from the heap afterwards. A batched evaluation's
temporaries (``(n², N)`` arrays of 2 MB for ``N = 10⁴``) were mapped afresh at every call in a process that had never
freed a larger block, and came from the heap in one that had: measured on tower_crane's batched C·q̇ (``harness bench
--parts evaluation``), 750–1140 ns per state in a fresh process, 400–480 ns after freeing one 4–16 MB block or
compiling a MuJoCo model; its goal ratio against Pinocchio read 0.31–0.33 × as the first system of a process and
0.175–0.19 × after another one. Held at their adjusted values from the start, both thresholds give every process the
same allocator: 380–440 ns fresh and afterwards.
"""

from __future__ import annotations

import ctypes
import ctypes.util
from functools import cache

M_TRIM_THRESHOLD, M_MMAP_THRESHOLD = -1, -3     # mallopt's parameters (malloc.h)
MMAP_THRESHOLD = 32 * 1024 * 1024               # glibc's largest (DEFAULT_MMAP_THRESHOLD_MAX on 64 bit)
TRIM_THRESHOLD = 2 * MMAP_THRESHOLD             # what glibc's own adjustment sets beside it


@cache
def steady() -> bool:
    """Set both thresholds once per process (setting them also ends glibc's adjustment); False where the C library
    is not glibc (nothing set)."""
    name = ctypes.util.find_library("c")
    try:
        mallopt = ctypes.CDLL(name).mallopt
    except (OSError, AttributeError, TypeError):
        return False
    mallopt.argtypes, mallopt.restype = [ctypes.c_int, ctypes.c_int], ctypes.c_int
    return bool(mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD)) and bool(mallopt(M_TRIM_THRESHOLD, TRIM_THRESHOLD))
