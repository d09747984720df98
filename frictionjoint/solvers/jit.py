"""The compiled kernels' switch, shared by the engines: numba's ``njit`` where it is importable and
this is the installed library (not the copy an FMU carries in its resources, which runs the
NumPy paths and does not even import numba)."""
from __future__ import annotations

numba = None
if __name__.startswith("frictionjoint."):  # not in an FMU's bundled copy: not even imported there
    try:
        import numba
    except ImportError:  # pragma: no cover - numba is a dependency of the installed library
        numba = None

__all__ = ["ENABLED"]

#: whether the compiled search is used: numba is importable and this is the installed library
#: (not the copy an FMU carries in its resources)
ENABLED = numba is not None and __name__.startswith("frictionjoint.")


def _jit(fun):
    # error_model "numpy": a division by zero gives inf or nan as in C (the Brent steps mirror
    # scipy's brentq.c, whose guards reject such a step), instead of raising
    return numba.njit(cache=True, error_model="numpy")(fun) if ENABLED else fun
