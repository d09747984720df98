"""The stick/slip pattern of a periodic orbit: the status of every slider (a contact node of a
patch, a flank of a dovetail) over one excitation period, piece by piece between its events
(computed by :func:`frictionjoint.solvers.marcher.slip_pattern.slip_pattern`)."""
from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np
from numpy.typing import ArrayLike

if TYPE_CHECKING:  # computing never imports matplotlib
    from matplotlib.axes import Axes

__all__ = ["SlipPattern", "STUCK", "SLIPPING", "OPEN", "STATUS_NAMES"]

#: a slider's status in :attr:`SlipPattern.pattern`: stuck, slipping (either way), open (its
#: contact lifted off: no normal and no friction force)
STUCK, SLIPPING, OPEN = 0, 1, 2
#: the words of the statuses, by code
STATUS_NAMES = ("stuck", "slipping", "open")


@dataclass
class SlipPattern:
    """Status of every slider over one period of a periodic orbit, exact between its events.

    Attributes
    ----------
    omega : float
        Excitation angular frequency [rad/s]; the period is ``2 pi / omega``.
    times : (n_pieces + 1,) ndarray
        Piece boundaries [s], from 0 to the period, in the excitation's time (the force is
        ``cos(omega t)``): every event time of the period, once per slider that changes there.
    pattern : (n_sliders, n_pieces) int8 ndarray
        Each slider's status on each piece: :data:`STUCK`, :data:`SLIPPING` or :data:`OPEN`.
    message : str
        What was computed, in words.
    """

    omega: float
    times: np.ndarray
    pattern: np.ndarray
    message: str = "ok"

    @property
    def success(self) -> bool:
        """Always True: a pattern is made from a converged orbit (the result contract's name)."""
        return True

    @property
    def status(self) -> str:
        """``'ok'`` (the result contract's word)."""
        return "ok"

    @property
    def period(self) -> float:
        """``2 pi / omega`` [s]."""
        return 2.0 * np.pi / self.omega

    @property
    def n_sliders(self) -> int:
        """Number of sliders (rows of :attr:`pattern`)."""
        return int(self.pattern.shape[0])

    def fraction(self, status: int = SLIPPING) -> np.ndarray:
        """Fraction of the period each slider spends in ``status``.

        Parameters
        ----------
        status : int
            :data:`STUCK`, :data:`SLIPPING` or :data:`OPEN`.

        Returns
        -------
        (n_sliders,) ndarray
            In [0, 1].
        """
        return (self.pattern == status) @ np.diff(self.times) / self.period

    def at(self, t: ArrayLike) -> np.ndarray:
        """The statuses at times ``t`` [s] (taken modulo the period; at an event, the status after it).

        Parameters
        ----------
        t : (n_t,) array_like
            Times [s].

        Returns
        -------
        (n_sliders, n_t) int8 ndarray
        """
        tm = np.mod(np.atleast_1d(np.asarray(t, dtype=float)), self.period)
        piece = np.clip(np.searchsorted(self.times, tm, side="right") - 1, 0, self.pattern.shape[1] - 1)
        return self.pattern[:, piece]

    def plot(self, ax: Axes | Sequence[Axes] | None = None, path: str | os.PathLike | None = None,
             **kwargs: Any) -> Axes:
        """The pattern over the cycle (see :func:`frictionjoint.plotting.plot_slip_pattern`).

        Parameters
        ----------
        ax : matplotlib.axes.Axes or (2,) sequence of Axes, optional
            Draw into these axes (a new figure if omitted).
        path : str or os.PathLike, optional
            Write the figure there (format from the extension).
        **kwargs
            Passed to :func:`~frictionjoint.plotting.plot_slip_pattern` (``sliders``,
            ``positions``, ``static_load``, labels).

        Returns
        -------
        matplotlib.axes.Axes
            The axes of the pattern.
        """
        from ..plotting import plot_slip_pattern, plot_target

        ax, path = plot_target(ax, path)
        return plot_slip_pattern(self, ax=ax, path=path, **kwargs)

    def __repr__(self) -> str:
        slipping = self.fraction(SLIPPING)
        return (f"SlipPattern(omega={self.omega:g} rad/s, {self.n_sliders} sliders, {self.pattern.shape[1]} pieces, "
                f"{int(np.count_nonzero(slipping > 0))} slip, {int(np.count_nonzero(self.fraction(OPEN) > 0))} open)")
