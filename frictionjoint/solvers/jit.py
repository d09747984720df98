"""The compiled kernels' switch, shared by the engines: numba's ``njit`` where it is importable and
this is the installed library (not the copy an FMU carries in its resources, which runs the
NumPy paths and does not even import numba); and the small compiled helpers that kernels of both
engines call (:func:`row_dot`, :func:`matvec`)."""
from __future__ import annotations

import numpy as np

numba = None
if __name__.startswith("frictionjoint."):  # not in an FMU's bundled copy: not even imported there
    try:
        import numba
    except ImportError:  # pragma: no cover - numba is a dependency of the installed library
        numba = None

__all__ = ["ENABLED", "matvec", "row_dot"]

#: whether the compiled search is used: numba is importable and this is the installed library
#: (not the copy an FMU carries in its resources)
ENABLED = numba is not None and __name__.startswith("frictionjoint.")


def _jit(fun=None, *, inline=False):
    """``fun`` compiled where :data:`ENABLED`, else ``fun`` itself; ``@_jit(inline=True)``: numba
    inlines it into its compiled callers (a kernel's step, named for the reader, without the cost
    of a call per use: some 2 % of a hysteresis loop's time for its pieces' calls)."""
    if fun is None:
        return lambda f: _jit(f, inline=inline)
    # error_model "numpy": a division by zero gives inf or nan as in C (the Brent steps mirror
    # scipy's brentq.c, whose guards reject such a step), instead of raising
    return (numba.njit(cache=True, error_model="numpy", inline="always" if inline else "never")(fun) if ENABLED
            else fun)


@_jit
def row_dot(a, i, x):
    """``a[i] @ x``, summed from the first column on, in a plain loop (inside a compiled kernel: no
    temporary and no call into BLAS for a few numbers; the same rounding wherever a kernel uses
    it)."""
    s = 0.0
    for k in range(x.size):
        s += a[i, k] * x[k]
    return s


@_jit
def matvec(a, x):
    """``a @ x`` of a real ``(r, c)`` matrix and a ``(c,)`` vector, each row summed as by
    :func:`row_dot` (its loop written out: the consistency test's piece start, a dozen products per
    call, is 1-2 % faster so)."""
    r, c = a.shape
    out = np.zeros(r)
    for i in range(r):
        s = 0.0
        for k in range(c):
            s += a[i, k] * x[k]
        out[i] = s
    return out
