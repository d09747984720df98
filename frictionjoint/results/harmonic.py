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
    stuck : bool
        Every slider sticks over the whole period and no contact opens (a linear orbit: exact).
    stable : bool or None
        With ``check``: the matching exact orbit is not unstable (its Floquet multipliers within
        the unit circle, a neutral family of stuck orbits included); None: not computed.
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
    stuck: bool = False
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


@dataclass
class HarmonicBalanceSweep:
    """Harmonic-balance solutions along a branch (pseudo-arclength continuation in ``omega``).

    Attributes
    ----------
    omega : (n,) ndarray
        Angular frequency of each point, in branch order [rad/s] (not monotonic past a fold).
    harmonics : (n, H + 1, n_dof) complex ndarray
        Every DOF's Fourier coefficients at each point [m].
    harmonic_amplitude, phase, amplitude : (n, n_dof) ndarray
        First-harmonic amplitude [m], its lag [rad], max ``|x|`` over the period [m].
    dissipated_per_cycle : (n,) ndarray
        Friction energy per period [J].
    fold : (n,) bool ndarray
        A turning point (fold) of the branch lies between this point and the previous one.
    stuck : (n,) bool ndarray
        Every slider sticks over the whole period and no contact opens.
    converged : (n,) bool ndarray
        The corrector converged.
    stable : (n,) object ndarray or None
        With ``check``: True/False per checked point (the matching exact orbit's Floquet
        multipliers, :func:`~frictionjoint.solvers.frequency_domain.hbm.lyapunov_stable`), None where not known.
    truncation_error : (n,) ndarray or None
        With ``check``: per checked point, the first harmonics' error against the exact orbit
        started from it (:func:`~frictionjoint.solvers.frequency_domain.hbm.truncation_error`), NaN elsewhere.
    n_harmonics : int
        ``H``.
    messages : tuple of str
        Per point.
    message : str
        How the branch ended.
    """

    omega: np.ndarray
    harmonics: np.ndarray
    harmonic_amplitude: np.ndarray
    phase: np.ndarray
    amplitude: np.ndarray
    dissipated_per_cycle: np.ndarray
    fold: np.ndarray
    converged: np.ndarray
    n_harmonics: int
    messages: tuple = ()
    message: str = ""
    stable: Optional[np.ndarray] = None
    truncation_error: Optional[np.ndarray] = None
    stuck: Optional[np.ndarray] = None

    @property
    def success(self) -> bool:
        """Every point converged and the branch reached the end of its range."""
        return bool(np.all(self.converged)) and self.message.startswith("reached")

    @property
    def status(self) -> str:
        """``'ok'`` or ``'failed'``."""
        return "ok" if self.success else "failed"

    @property
    def n_folds(self) -> int:
        """Turning points passed."""
        return int(np.count_nonzero(self.fold))

    def plot(self, ax=None, path=None, output=0):
        """The branch's first-harmonic amplitude against frequency, stable and unstable parts drawn
        differently (:func:`frictionjoint.plotting.plot_hbm_sweep`).

        Parameters
        ----------
        ax : matplotlib Axes, optional
        path : str or os.PathLike, optional
        output : int or (n_dof,) array_like
            A DOF index or an output's coefficients over the DOFs.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting import plot_hbm_sweep, plot_target

        ax, path = plot_target(ax, path)
        return plot_hbm_sweep(self, output, ax=ax, path=path)
