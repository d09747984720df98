"""Excitation: harmonic forces, harmonic base motion and held external forces.

All harmonic sources of one model share the angular frequency ``omega`` of the model
(see :class:`frictionjoint.system.FrictionSystem`), which keeps the motion between events
in closed form.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .errors import ParameterError, check_nonnegative, check_real

__all__ = ["HarmonicForce", "HarmonicBaseMotion", "ExternalForce"]


@dataclass(frozen=True)
class HarmonicForce:
    """Force ``amplitude * cos(omega t - phase)`` [N] on one DOF.

    Parameters
    ----------
    dof : str or int
        DOF the force acts on.
    amplitude : float
        Force amplitude [N].
    phase : float
        Phase lag [rad] of the force behind ``cos(omega t)``.
    """

    dof: object
    amplitude: float
    phase: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "amplitude", check_real("amplitude", self.amplitude))
        object.__setattr__(self, "phase", check_real("phase", self.phase))


@dataclass(frozen=True)
class HarmonicBaseMotion:
    """A spring (and damper) from a DOF to a base moving as ``amplitude cos(omega t - phase)``.

    The spring and damper are added to the structure; the base motion acts as the
    equivalent force ``stiffness*y_b + damping*y_b'`` on the DOF.

    Parameters
    ----------
    dof : str or int
        DOF connected to the base.
    stiffness : float
        Spring to the base [N/m], >= 0.
    amplitude : float
        Base displacement amplitude [m].
    damping : float
        Damper to the base [N s/m], >= 0.
    phase : float
        Phase lag [rad] of the base motion behind ``cos(omega t)``.
    """

    dof: object
    stiffness: float
    amplitude: float
    damping: float = 0.0
    phase: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "stiffness", check_nonnegative("stiffness", self.stiffness))
        object.__setattr__(self, "damping", check_nonnegative("damping", self.damping))
        object.__setattr__(self, "amplitude", check_real("amplitude", self.amplitude))
        object.__setattr__(self, "phase", check_real("phase", self.phase))


@dataclass(frozen=True)
class ExternalForce:
    """Piecewise-constant (zero-order hold) force signal.

    ``values[i]`` acts on ``dof`` for ``times[i] <= t < times[i+1]``; zero outside.

    Parameters
    ----------
    dof : str or int
        DOF the force acts on.
    times : (k+1,) array_like
        Strictly increasing switching times [s].
    values : (k,) array_like
        Held force values [N].
    """

    dof: object
    times: np.ndarray = field(repr=False)
    values: np.ndarray = field(repr=False)

    def __post_init__(self):
        t = np.asarray(self.times, dtype=float).reshape(-1)
        v = np.asarray(self.values, dtype=float).reshape(-1)
        if t.size < 2 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
            raise ParameterError("times must be a finite, strictly increasing array of >= 2 values")
        if v.shape != (t.size - 1,) or not np.all(np.isfinite(v)):
            raise ParameterError(f"values must be {t.size - 1} finite numbers (one per hold interval)")
        t.setflags(write=False)
        v.setflags(write=False)
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "values", v)

    def value(self, t: float) -> float:
        """Held value at time ``t`` [N].

        Parameters
        ----------
        t : float
            Time [s].

        Returns
        -------
        float
            ``values[i]`` [N] for ``times[i] <= t < times[i+1]``; 0 outside ``[times[0], times[-1])``.
        """
        i = np.searchsorted(self.times, t, side="right") - 1
        if i < 0 or i >= self.values.size:
            return 0.0
        return float(self.values[i])
