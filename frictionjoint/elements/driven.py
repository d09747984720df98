"""Jenkins sliders driven by a prescribed displacement: the exact play operator.

For a displacement path that is monotone between updates (a held input that jumps at the start
of a step, or any monotone segment) the slider position of a Jenkins slider (spring ``k`` in series
with a slider of strength ``F``) is exactly ``w_new = clip(w, u - F/k, u + F/k)``; its force is
``k (u - w)`` and the energy it dissipates is ``F |w_new - w|``. Parallel sliders (Iwan) are
independent of one another, so the same update holds for every slider.
"""
from __future__ import annotations

import math

import numpy as np

from ..errors import ParameterError

__all__ = ["DrivenSliders"]


class DrivenSliders:
    """Parallel Jenkins sliders on one prescribed displacement ``u`` [m].

    Parameters
    ----------
    stiffness : (n,) array_like
        Slider spring stiffnesses [N/m], > 0.
    slip_force : (n,) array_like
        Slider slip forces [N], > 0.
    u0 : float
        Initial displacement [m]; the springs start unstressed.

    Attributes
    ----------
    u : float
        Current displacement [m].
    w : (n,) ndarray
        Slider positions [m].
    slipping : (n,) bool ndarray
        Sliders that slipped in the last update.
    dissipated_energy : float
        Energy dissipated since the start [J].
    """

    def __init__(self, stiffness, slip_force, u0: float = 0.0):
        k = np.atleast_1d(np.asarray(stiffness, dtype=float))
        f = np.atleast_1d(np.asarray(slip_force, dtype=float))
        if k.shape != f.shape or k.ndim != 1 or k.size == 0:
            raise ParameterError("stiffness and slip_force must be 1-D arrays of the same length")
        if not (np.all(np.isfinite(k)) and np.all(k > 0)):
            raise ParameterError("stiffness must be finite and > 0 (allowed range (0, inf))")
        if not (np.all(np.isfinite(f)) and np.all(f > 0)):
            raise ParameterError("slip_force must be finite and > 0 (allowed range (0, inf))")
        if not math.isfinite(u0):
            raise ParameterError(f"u0 must be finite, got {u0!r}")
        self.stiffness = k
        self.slip_force = f
        self.reach = f / k
        self.u = float(u0)
        self.w = np.full(k.size, float(u0))
        self.slipping = np.zeros(k.size, dtype=bool)
        self.dissipated_energy = 0.0

    def force_at(self, u: float) -> float:
        """Total force [N] at displacement ``u`` reached monotonically from the current state
        (the state is not changed)."""
        w = np.clip(self.w, u - self.reach, u + self.reach)
        return float(self.stiffness @ (u - w))

    def tangent_stiffness_at(self, u: float) -> float:
        """Sum of the stiffnesses [N/m] of the sliders that stick at ``u`` (for a master's
        semi-implicit coupling): a slider that the move to ``u`` pushes to its limit slips."""
        w = np.clip(self.w, u - self.reach, u + self.reach)
        moved = w != self.w
        if u == self.u:
            moved = self.slipping
        return float(self.stiffness[~moved].sum())

    def update(self, u: float) -> None:
        """Move to displacement ``u`` [m] (monotonically from the current one) and commit."""
        if not math.isfinite(u):
            raise ParameterError(f"u must be finite, got {u!r}")
        w = np.clip(self.w, u - self.reach, u + self.reach)
        if u != self.u:
            self.slipping = w != self.w
        self.dissipated_energy += float(self.slip_force @ np.abs(w - self.w))
        self.w = w
        self.u = float(u)

    @property
    def force(self) -> float:
        """Total force [N] at the current displacement."""
        return float(self.stiffness @ (self.u - self.w))

    def copy(self) -> "DrivenSliders":
        new = DrivenSliders.__new__(DrivenSliders)
        new.__dict__ = {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in self.__dict__.items()}
        return new
