"""Frequency grids: the one convention of the Python API, the command line and study files.

The frequencies of a sweep [rad/s] are written in one of two ways, everywhere:

- ``"START:STOP:N"``: ``N`` equally spaced angular frequencies from ``START`` to ``STOP``
  (the command line's ``--omega``, a study file's ``omega = "1950:2100:40"``, and any Python
  call that takes frequencies); :func:`omega_range` builds the same grid as an array;
- the frequencies themselves: a NumPy array, a list or a tuple, visited in the given order.

A list or tuple of three numbers whose last is an integer, ``(0.5, 2.5, 60)``, could be either:
three frequencies or a range of 60. It is refused with a :class:`ParameterError` that shows the
unambiguous forms. A count is an integer, so a last number written as a float (``60.0``, TOML's
``2100.0``) is a frequency: ``[1950.0, 2000.0, 2100.0]`` in a study file is three frequencies. Functions that need only the ends of a range (a harmonic-balance
branch) take the same forms and use the first and the last frequency.
"""
from __future__ import annotations

import math
from numbers import Integral, Real

import numpy as np

from .errors import ParameterError, check_grid

__all__ = ["omega_range", "check_omegas", "parse_range", "FORM"]

#: How a frequency range is written (shown in every refusal).
FORM = "'START:STOP:N' (e.g. '0.5:2.5:60') or an array of the frequencies (e.g. np.linspace(0.5, 2.5, 60))"


def omega_range(start: float, stop: float, n: int) -> np.ndarray:
    """``n`` equally spaced angular frequencies from ``start`` to ``stop`` [rad/s].

    Parameters
    ----------
    start, stop : float
        First and last frequency [rad/s], finite and > 0 (``stop < start`` gives a downward grid).
    n : int
        Number of frequencies, >= 1 (``n = 1`` needs ``start == stop``).

    Returns
    -------
    (n,) ndarray
    """
    return _grid("omega", start, stop, n, text=None)


def parse_range(name: str, text: str) -> tuple[float, float, int]:
    """Read ``"START:STOP:N"`` and return ``(start, stop, n)``; a :class:`ParameterError` names
    ``name`` and the right form otherwise."""
    parts = str(text).split(":")
    if len(parts) != 3:
        raise ParameterError(f"{name} must be written START:STOP:N (e.g. '0.5:2.5:60'), got {text!r}")
    try:
        start, stop = float(parts[0]), float(parts[1])
    except ValueError:
        raise ParameterError(f"{name} must be START:STOP:N with numbers START and STOP [rad/s], got {text!r}") from None
    try:
        n = int(parts[2])
    except ValueError:
        raise ParameterError(f"{name} must be START:STOP:N with a whole number N of frequencies, got {text!r}") from None
    _grid(name, start, stop, n, text)
    return start, stop, n


def _grid(name, start, stop, n, text):
    shown = text if text is not None else f"({start!r}, {stop!r}, {n!r})"
    for label, value in (("START", start), ("STOP", stop)):
        if isinstance(value, bool) or not isinstance(value, (Real, np.number)) or not math.isfinite(value) or value <= 0:
            raise ParameterError(f"{name}: {label} must be a finite angular frequency > 0 [rad/s], got {shown}")
    if isinstance(n, bool) or not isinstance(n, (Integral, np.integer)) or n < 1:
        raise ParameterError(f"{name}: N must be a whole number >= 1 of frequencies, got {shown}")
    if n == 1 and start != stop:
        raise ParameterError(f"{name}: N = 1 needs START == STOP, got {shown}")
    if n > MAX_POINTS:
        raise ParameterError(f"{name}: N must be <= {MAX_POINTS} frequencies, got {shown}")
    return np.linspace(float(start), float(stop), int(n))


#: The largest number of frequencies of one grid (a sweep of more is a typing error, and its
#: array alone would not fit in memory long before it could run).
MAX_POINTS = 1_000_000


def _ambiguous(values) -> bool:
    """A list or tuple ``(a, b, n)`` with an integer ``n >= 2`` reads as a range too (a float
    ``n`` is a frequency: a count is never written ``60.0``)."""
    if not isinstance(values, (list, tuple)) or len(values) != 3:
        return False
    last = values[-1]
    if isinstance(last, (bool, np.bool_)) or not isinstance(last, (Integral, np.integer)):
        return False
    return last >= 2


def check_omegas(name: str, values) -> np.ndarray:
    """Return the frequencies ``values`` [rad/s] (any form of the module docstring) as a
    non-empty 1-D array of finite numbers > 0.

    Raises
    ------
    ParameterError
        Naming ``name``: a form that could mean two things, a malformed range, or frequencies
        that are not finite and > 0.
    """
    if isinstance(values, str):
        return omega_range(*parse_range(name, values))
    if _ambiguous(values):
        a, b, n = values
        raise ParameterError(
            f"{name} = {values!r} could be the three frequencies {a!r}, {b!r}, {n!r} rad/s or {int(n)} "
            f"frequencies from {a!r} to {b!r}: write '{a!r}:{b!r}:{int(n)}' (or omega_range({a!r}, {b!r}, {int(n)})) "
            f"for the range; for the three frequencies, write the last with a decimal point "
            f"([{a!r}, {b!r}, {float(n)!r}], also in a study file) or pass an array")
    arr = check_grid(name, values, unit="rad/s")
    if arr.size > MAX_POINTS:
        raise ParameterError(f"{name} must hold at most {MAX_POINTS} frequencies, got {arr.size}")
    return arr
