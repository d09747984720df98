"""BLAS threads: the library chooses them for its own dense work.

The solvers' dense linear algebra (eigendecompositions, solves, matrix exponentials, products of
the first-order system of a structure of tens to hundreds of DOFs) is small. On such matrices
OpenBLAS's threads cost more than they save, and on a machine that runs other work (a study's
process pool, a laptop with a few jobs) they contend for the cores: a 50-DOF chain with 10 Jenkins
joints took 2.2 s to its steady state with OpenBLAS's default threads and 0.9 s with one, on 2
cores with one other busy process (``benchmarks/chains.py``'s chain).

So the public solvers (:func:`~frictionjoint.periodic_response`, :func:`~frictionjoint.simulate`,
:func:`~frictionjoint.harmonic_balance`, :func:`~frictionjoint.hbm_sweep` and every sweep and
study built on them) run with :func:`blas_threads` BLAS threads, by default 1, through
threadpoolctl (the well-kept tool for this: it finds every BLAS library loaded in the process,
OpenBLAS, MKL or BLIS, and restores their settings afterwards). Outside these calls the user's
settings are untouched. To choose otherwise: :func:`set_blas_threads` (``None``: leave BLAS as it
is) or the environment variable ``FRICTIONJOINT_BLAS_THREADS`` (a count, or ``default``).
"""
from __future__ import annotations

import functools
import os
import threading
from contextlib import contextmanager

from .errors import ParameterError

__all__ = ["blas_threads", "set_blas_threads", "library_threads", "owns_blas_threads", "ENVIRONMENT_VARIABLE"]

#: The environment variable that overrides the library's choice (a count >= 1, or ``default``).
ENVIRONMENT_VARIABLE = "FRICTIONJOINT_BLAS_THREADS"

_UNSET = object()
_choice = _UNSET
_controller = None
_lock = threading.Lock()
_local = threading.local()


def _from_environment():
    text = os.environ.get(ENVIRONMENT_VARIABLE, "").strip()
    if not text:
        return 1
    if text.lower() == "default":
        return None
    try:
        n = int(text)
    except ValueError:
        n = 0
    if n < 1:
        raise ParameterError(f"{ENVIRONMENT_VARIABLE} must be an integer >= 1 or 'default', got {text!r}")
    return n


def blas_threads() -> int | None:
    """The BLAS threads of the library's solvers: a count, or None (BLAS left as it is).

    Returns
    -------
    int or None
        :func:`set_blas_threads`'s value if it was called, else ``FRICTIONJOINT_BLAS_THREADS``,
        else 1.
    """
    return _from_environment() if _choice is _UNSET else _choice


def set_blas_threads(n: int | None) -> None:
    """Set the BLAS threads of the library's solvers.

    Parameters
    ----------
    n : int or None
        Threads, >= 1; None leaves BLAS as it is (its own default, or what the user set).
    """
    global _choice
    if n is not None and (isinstance(n, bool) or not isinstance(n, int) or n < 1):
        raise ParameterError(f"n must be None or an integer >= 1 (BLAS threads), got {n!r}")
    _choice = n


def _blas_libraries() -> list:
    """threadpoolctl's controllers of the BLAS libraries loaded in the process (scanned once)."""
    global _controller
    with _lock:
        if _controller is None:
            from threadpoolctl import ThreadpoolController

            _controller = [lib for lib in ThreadpoolController().lib_controllers if lib.user_api == "blas"]
        return _controller


@contextmanager
def library_threads():
    """Run the block with :func:`blas_threads` BLAS threads (nested blocks: the outermost sets them).

    Each BLAS library's threads are read and, where they differ, set and restored through its
    threadpoolctl controller's ``get_num_threads``/``set_num_threads`` (two calls into the library
    each): ``ThreadpoolController.limit`` gathers every library's full description to restore it,
    some 36 us a call, which an FMU's ``doStep`` (tens of microseconds of work) paid every step."""
    n = blas_threads()
    if n is None or getattr(_local, "depth", 0):
        _local.depth = getattr(_local, "depth", 0) + 1
        try:
            yield
        finally:
            _local.depth -= 1
        return
    _local.depth = 1
    try:
        changed = []
        try:
            for lib in _blas_libraries():
                old = lib.get_num_threads()
                if old is not None and old != n:
                    lib.set_num_threads(n)
                    changed.append((lib, old))
            yield
        finally:
            for lib, old in changed:
                lib.set_num_threads(old)
    finally:
        _local.depth = 0


def owns_blas_threads(function):
    """Decorator: ``function`` runs inside :func:`library_threads`."""
    @functools.wraps(function)
    def wrapper(*args, **kwargs):
        with library_threads():
            return function(*args, **kwargs)
    return wrapper
