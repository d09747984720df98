"""The machine's available memory, and a refusal of work that would not fit in it (issue 39).

A model whose size is known from its parameters (a mesh's element counts, a grid's length) is
checked here before anything is allocated: :func:`check_fits` raises a
:class:`~frictionjoint.errors.ParameterError` naming the parameter, the estimate and what is
available, where the allocation would otherwise take minutes of swapping or end in a raw
``MemoryError``.

Available memory: the kernel's ``MemAvailable`` (``/proc/meminfo``, Linux: free memory plus what
the page cache can give back), or ``os.sysconf``'s available physical pages elsewhere on POSIX,
and no more than a control group's limit less its usage (``/sys/fs/cgroup/memory.max``,
``memory.current``: a container's limit is not what ``/proc/meminfo`` shows). Where none can be
read (Windows), nothing is refused.
"""
from __future__ import annotations

import ctypes
import functools
import os

from .errors import ParameterError

__all__ = ["available_memory", "computation_budget", "check_fits", "format_bytes", "release_freed_memory"]


def _meminfo_available() -> int | None:
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def _sysconf_available() -> int | None:
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_AVPHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        return None


def _cgroup_available() -> int | None:
    try:
        with open("/sys/fs/cgroup/memory.max") as f:
            limit = f.read().strip()
        if limit == "max":
            return None
        with open("/sys/fs/cgroup/memory.current") as f:
            return max(0, int(limit) - int(f.read().strip()))
    except (OSError, ValueError):
        return None


def available_memory() -> int | None:
    """Memory [bytes] this process can allocate without swapping (module docstring), or None
    where the platform does not say."""
    found = [v for v in (_meminfo_available() or _sysconf_available(), _cgroup_available()) if v is not None]
    return min(found) if found else None


def computation_budget(floor: int = 2 * 2 ** 30) -> int:
    """The memory one computation may take [bytes]: a quarter of the machine's physical memory, at
    least ``floor``; ``floor`` where the platform does not say (Windows). Fixed for a machine, so
    that what fits (a harmonic count, a configuration cache) does not change from run to run with
    what other processes hold."""
    try:
        total = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):  # no sysconf, or no such name
        return floor
    return max(floor, total // 4)


def format_bytes(n: float) -> str:
    """``n`` bytes in binary units, three significant digits (``"5.4 GiB"``)."""
    for unit in ("B", "KiB", "MiB", "GiB", "TiB", "PiB"):
        if abs(n) < 1024.0 or unit == "PiB":
            return f"{n:.3g} {unit}"
        n /= 1024.0
    return f"{n:.3g} PiB"  # pragma: no cover


def check_fits(estimate: float, parameter: str, what: str, available: int | None = None) -> None:
    """Raise :class:`ParameterError` if ``estimate`` bytes exceed the available memory.

    Parameters
    ----------
    estimate : float
        The work's peak memory [bytes], estimated from its parameters.
    parameter : str
        The parameter that sets the size, with its value (``"n_elements = (1000000, 1, 1)"``).
    what : str
        What needs the memory and how it was estimated (``"the blade's sparse matrices: 2.2e9
        stored entries"``).
    available : int, optional
        Bytes available (default :func:`available_memory`; None: nothing is refused).
    """
    if available is None:
        available = available_memory()
    if available is not None and estimate > available:
        raise ParameterError(f"{parameter} needs about {format_bytes(estimate)} ({what}), more than the "
                             f"{format_bytes(available)} this machine has available: make it smaller")


@functools.lru_cache(maxsize=None)
def _malloc_trim():
    """glibc's ``malloc_trim`` (None elsewhere: musl, macOS, Windows)."""
    try:  # glibc's soname (find_library would run ldconfig in a subprocess to learn it)
        trim = ctypes.CDLL("libc.so.6").malloc_trim
    except (OSError, AttributeError):
        return None
    trim.argtypes = [ctypes.c_size_t]
    trim.restype = ctypes.c_int
    return trim


def release_freed_memory() -> bool:
    """Give the memory this process freed back to the operating system, where the C library keeps
    it (glibc: ``malloc_trim(0)``, as Dask's workers do after a task); whether it could.

    glibc raises its threshold for serving an allocation by ``mmap`` to the size of each large
    block freed (up to 32 MiB), so that after a computation that freed thousands of arrays of a few
    MB (a marcher's cached configurations: 5 GB at 400 DOFs) the next ones come from its heap, and
    the freed heap stays with the process: 0.8 GB after a steady state at 200 DOFs whose arrays
    were all freed, and a second steady state at 400 DOFs went past 12 GB resident where one takes
    8. Trimming costs about 50 ms per GB returned; a no-op where the C library is not glibc."""
    trim = _malloc_trim()
    if trim is None:
        return False
    trim(0)
    return True
