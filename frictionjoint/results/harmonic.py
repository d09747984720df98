"""Harmonic-balance results: one frequency (:class:`HarmonicBalance`)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Optional

import numpy as np

__all__ = ["HarmonicBalance"]


@dataclass
class HarmonicBalance:
    """Multi-harmonic balance of a :class:`~frictionjoint.system.FrictionSystem` at one frequency.

    Attributes
    ----------
    omega : float
        Excitation angular frequency [rad/s].
    n_harmonics : int
        Harmonics kept, ``H``.
    harmonics : (H + 1, n_dof) complex ndarray
        Fourier coefficients of every DOF: ``x(t) = Re(sum_h harmonics[h] e^{i h omega t})``
        (row 0 the mean, real) [m].
    harmonic_amplitude : (n_dof,) ndarray
        First-harmonic amplitude ``|harmonics[1]|`` [m].
    phase : (n_dof,) ndarray
        Lag of the first harmonic behind ``cos(omega t)``, ``-arg harmonics[1]`` [rad].
    amplitude : (n_dof,) ndarray
        Max ``|x|`` over the reconstructed period [m].
    converged : bool
        Newton's residual reached the tolerance.
    message : str
        What happened.
    iterations : int
        Newton iterations.
    residual : float
        Final residual, relative to the joint coordinates' size.
    dissipated_per_cycle : float
        Friction energy per period of the balanced orbit [J].
    stable : bool or None
        Stability of the orbit (None: not computed).
    slider_positions : (n_sliders,) ndarray
        Jenkins slider positions at ``t = 0`` on the balanced orbit [m] (the start of an exact
        time-domain check).
    truncation_error : float or None
        With ``check``: the first harmonics' error against the exact time-domain steady state of
        the same system, ``max |X1_hbm - X1_exact| / max |X1_exact|``.
    amplitude_error : float or None
        With ``check``: the same for the peak amplitudes.
    exact : PeriodicResponse or None
        With ``check``: the exact steady state.
    """

    omega: float
    n_harmonics: int
    harmonics: np.ndarray
    harmonic_amplitude: np.ndarray
    phase: np.ndarray
    amplitude: np.ndarray
    converged: bool
    message: str
    iterations: int = 0
    residual: float = float("nan")
    dissipated_per_cycle: float = float("nan")
    stable: Optional[bool] = None
    slider_positions: Optional[np.ndarray] = None
    truncation_error: Optional[float] = None
    amplitude_error: Optional[float] = None
    exact: Optional[Any] = None

    @property
    def success(self) -> bool:
        """Whether the balance converged (the result contract)."""
        return bool(self.converged)

    @property
    def status(self) -> str:
        """``'converged'`` or ``'not converged'``."""
        return "converged" if self.converged else "not converged"
