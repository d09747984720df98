"""Exceptions and input validators shared by the whole package.

Validators return the cleaned value (as in ``scipy.integrate._ivp``) and raise
:class:`ParameterError` naming the argument and its allowed range.
"""
from __future__ import annotations

import math
from numbers import Real

import numpy as np

__all__ = [
    "ParameterError",
    "ConvergenceError",
    "check_real",
    "check_positive",
    "check_nonnegative",
    "check_grid",
    "FMUError",
    "NoSolutionError",
    "check_poisson_ratio",
    "check_count",
    "check_vector",
    "check_system",
    "check_bool",
    "check_whole",
]


class ParameterError(ValueError):
    """An argument is outside its allowed range (the message names it)."""


class ConvergenceError(RuntimeError):
    """An iterative solver did not converge (the message says why)."""


class FMUError(RuntimeError):
    """An FMI call returned an error status, or an FMU does not build or validate (the message has
    the call and the FMU's log)."""


class WorkerError(RuntimeError):
    """A worker process of a study died (the message says how; the finished points are kept)."""


class NoSolutionError(ParameterError):
    """The requested closed form does not exist for these parameters (message says why)."""


def check_real(name: str, value) -> float:
    """Return ``value`` as a finite float or raise :class:`ParameterError`."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (Real, np.number)):
        raise ParameterError(f"{name} must be a real number, got {value!r}")
    value = float(value)
    if not math.isfinite(value):
        raise ParameterError(f"{name} must be finite, got {value!r}")
    return value


def check_positive(name: str, value) -> float:
    """Return ``value`` as a float in (0, inf) or raise :class:`ParameterError`."""
    value = check_real(name, value)
    if value <= 0.0:
        raise ParameterError(f"{name} must be > 0 (allowed range (0, inf)), got {value!r}")
    return value


def check_nonnegative(name: str, value) -> float:
    """Return ``value`` as a float in [0, inf) or raise :class:`ParameterError`."""
    value = check_real(name, value)
    if value < 0.0:
        raise ParameterError(f"{name} must be >= 0 (allowed range [0, inf)), got {value!r}")
    return value


def check_poisson_ratio(name: str, value) -> float:
    """Return ``value`` as a float in (-1, 0.5) (an isotropic elastic solid's Poisson ratio)."""
    value = check_real(name, value)
    if not -1.0 < value < 0.5:
        raise ParameterError(f"{name} must be in (-1, 0.5), got {value!r}")
    return value


def check_count(name: str, value, minimum: int = 1) -> int:
    """Return ``value`` as an int >= ``minimum`` or raise :class:`ParameterError`."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ParameterError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def check_vector(name: str, value, n: int, what: str = "") -> np.ndarray:
    """Return ``value`` as a finite float array of shape ``(n,)`` (a scalar is repeated).

    ``what`` names the length in the message (e.g. ``"n_dof"``).
    """
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a real number or a sequence of {n} real numbers, "
                             f"got {value!r}") from None
    if arr.ndim == 0:
        arr = np.full(n, float(arr))
    elif arr.shape != (n,):
        size = f"{what} = {n}" if what else str(n)
        raise ParameterError(f"{name} must be a scalar or have shape ({size},), got shape {arr.shape}")
    else:
        arr = arr.copy()
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} must be finite, got {value!r}")
    return arr


def check_whole(name: str, value) -> int:
    """Return a whole number ``value`` (an int, or a float such as ``5.0`` read from text) as an
    int, or raise :class:`ParameterError` (``5.5`` is never truncated)."""
    if isinstance(value, (bool, np.bool_)):
        raise ParameterError(f"{name} must be a whole number, got {value!r}")
    if isinstance(value, (int, np.integer)):
        return int(value)
    number = check_real(name, value)
    if not number.is_integer():
        raise ParameterError(f"{name} must be a whole number, got {value!r}")
    return int(number)


_TRUE = {"true", "yes", "on", "1", "1.0"}
_FALSE = {"false", "no", "off", "0", "0.0"}


def check_bool(name: str, value) -> bool:
    """Return ``value`` as a bool or raise :class:`ParameterError`.

    Every interface's way of writing a switch is taken: ``True``/``False`` (Python, TOML's
    ``true``/``false``), the numbers 1 and 0 (``--set NAME=1``, an FMU's Real or Integer
    variable), and the words ``true``/``false``/``yes``/``no``/``on``/``off`` in any case.
    """
    if isinstance(value, (bool, np.bool_)):
        return bool(value)
    if isinstance(value, (Real, np.number)) and value in (0, 1):
        return bool(value)
    if isinstance(value, str) and value.strip().lower() in _TRUE | _FALSE:
        return value.strip().lower() in _TRUE
    raise ParameterError(f"{name} must be True or False (or 1 or 0), got {value!r}")


def check_system(name: str, value, cls: type):
    """Return ``value`` if it is an instance of ``cls``, else raise :class:`ParameterError`."""
    if not isinstance(value, cls):
        raise ParameterError(f"{name} must be a {cls.__name__}, got {type(value).__name__}")
    return value


def check_grid(name: str, values, positive: bool = True, unit: str = "") -> np.ndarray:
    """Return ``values`` as a non-empty 1-D float array of finite numbers > 0 (or >= 0)."""
    suffix = f" [{unit}]" if unit else ""
    try:
        arr = np.atleast_1d(np.array(values, dtype=float))
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a 1-D sequence of real numbers{suffix}, got {values!r}") from None
    if arr.ndim != 1 or arr.size == 0:
        raise ParameterError(f"{name} must be a non-empty 1-D sequence{suffix}, got shape {arr.shape}")
    check = check_positive if positive else check_nonnegative
    for i, value in enumerate(arr):
        check(f"{name}[{i}]", float(value))
    return arr


def check_oscillator(mass, stiffness, slip_force, force_amplitude, base_amplitude):
    """Validate the harmonically excited Coulomb oscillator's data.

    Returns ``(m, k, F, P, Y, P0)`` as floats with ``P0 = P + k Y``, which must be finite and
    nonzero (a closed form or a sweep needs excitation).
    """
    m = check_positive("mass", mass)
    k = check_positive("stiffness", stiffness)
    f = check_nonnegative("slip_force", slip_force)
    p = check_real("force_amplitude", force_amplitude)
    y = check_real("base_amplitude", base_amplitude)
    p0 = p + k * y
    if p0 == 0.0 or not math.isfinite(p0):
        raise ParameterError("force_amplitude + stiffness * base_amplitude must be finite and nonzero "
                             f"(allowed range (-inf, 0) U (0, inf)), got {p0!r}")
    return m, k, f, p, y, p0
