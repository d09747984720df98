"""The regime map of the single-DOF Coulomb oscillator (:func:`frictionjoint.regime.regime_map`):
stops per cycle over a grid of friction and frequency ratios."""
from __future__ import annotations

import csv
import os
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from .response import PointsContract

if TYPE_CHECKING:  # computing never imports matplotlib
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["RegimeMap"]


@dataclass(eq=False)
class RegimeMap(PointsContract):
    """Number of stops per cycle over a grid of friction and frequency ratios.

    Rows are friction ratios, columns frequency ratios (``[i, j]`` is
    ``(friction_ratios[i], frequency_ratios[j])``).

    Attributes
    ----------
    friction_ratios : (n_f,) ndarray
        ``f = F/P0`` [-].
    frequency_ratios : (n_r,) ndarray
        ``r = w/wn`` [-].
    regime : (n_f, n_r) ndarray of str
        One of :data:`REGIMES` per point.
    stops_per_cycle : (n_f, n_r) int ndarray
        Stops of finite duration per cycle where ``regime`` is ``'stop-free'`` or ``'stops'``;
        ``-1`` elsewhere (stuck, unbounded, not converged).
    converged, unique : (n_f, n_r) bool ndarray
        As reported by the steady-state solver.
    periods : (n_f, n_r) ndarray
        Excitation periods marched per point.
    messages : (n_f, n_r) ndarray of str
        The solver's message per point (``success``, ``status``, ``message``: the result
        contract of :class:`~frictionjoint.results.response.PointsContract`).
    """

    friction_ratios: np.ndarray
    frequency_ratios: np.ndarray
    regime: np.ndarray
    stops_per_cycle: np.ndarray
    converged: np.ndarray
    unique: np.ndarray
    periods: np.ndarray = field(repr=False)
    messages: np.ndarray = field(repr=False)


    @property
    def shape(self) -> tuple[int, int]:
        """``(n_f, n_r)``."""
        return self.regime.shape

    def category(self) -> np.ndarray:
        """Label of every point: ``'0 stops'``, ``'1 stop'``, ``'2 stops'``, ..., or the regime word.

        Returns
        -------
        (n_f, n_r) ndarray of str
        """
        out = np.empty(self.shape, dtype=object)
        for idx, reg in np.ndenumerate(self.regime):
            if reg in ("stop-free", "stops"):
                n = int(self.stops_per_cycle[idx])
                out[idx] = f"{n} stop" + ("" if n == 1 else "s")
            else:
                out[idx] = str(reg)
        return out.astype(str)

    def at(self, friction_ratio: float, frequency_ratio: float) -> tuple[str, int]:
        """``(regime, stops_per_cycle)`` at the grid point nearest to ``(f, r)``.

        Parameters
        ----------
        friction_ratio : float
            ``f = F/P0`` [-]; the nearest of :attr:`friction_ratios` is taken.
        frequency_ratio : float
            ``r = w/wn`` [-]; the nearest of :attr:`frequency_ratios` is taken.

        Returns
        -------
        regime : str
            One of :data:`REGIMES`.
        stops_per_cycle : int
            Stops of finite duration per cycle; ``-1`` unless ``regime`` is ``'stop-free'`` or
            ``'stops'``.
        """
        i = int(np.argmin(np.abs(self.friction_ratios - friction_ratio)))
        j = int(np.argmin(np.abs(self.frequency_ratios - frequency_ratio)))
        return str(self.regime[i, j]), int(self.stops_per_cycle[i, j])

    def table(self) -> str:
        """Text map: one row per friction ratio (largest first), one column per frequency ratio.

        Entries: the number of stops per cycle, ``S`` permanent stick, ``U`` unbounded,
        ``?`` not converged; ``*`` marks a non-unique orbit (not shown for permanent stick, whose
        rest positions always form a family).
        """
        codes = {"stuck": "S", "unbounded": "U", "not converged": "?"}
        width = 6
        head = "F/P0 \\ r" + "".join(f"{r:{width}.3g}" for r in self.frequency_ratios)
        lines = [head]
        for i in range(self.shape[0] - 1, -1, -1):
            cells = []
            for j in range(self.shape[1]):
                reg = self.regime[i, j]
                c = codes.get(reg, str(self.stops_per_cycle[i, j]))
                if not self.unique[i, j] and reg != "stuck":
                    c += "*"
                cells.append(f"{c:>{width}}")
            lines.append(f"{self.friction_ratios[i]:8.3g}" + "".join(cells))
        lines.append("S permanent stick, U unbounded, ? not converged, * not unique (a family of orbits)")
        return "\n".join(lines)

    def to_csv(self, path: str | os.PathLike) -> None:
        """Write one row per grid point: friction_ratio, frequency_ratio, regime, stops, flags.

        Parameters
        ----------
        path : str or os.PathLike
            Output file.
        """
        with open(path, "w", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            w.writerow(["friction_ratio", "frequency_ratio", "regime", "stops_per_cycle",
                        "converged", "unique", "periods", "message"])
            for (i, j), reg in np.ndenumerate(self.regime):
                w.writerow([repr(float(self.friction_ratios[i])), repr(float(self.frequency_ratios[j])),
                            reg, int(self.stops_per_cycle[i, j]), bool(self.converged[i, j]),
                            bool(self.unique[i, j]), repr(float(self.periods[i, j])), self.messages[i, j]])

    def plot(self, ax: Axes | None = None, path: str | os.PathLike | None = None) -> Figure:
        """Categorical map of the regimes (see :func:`frictionjoint.plotting.plot_regime_map`).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Draw into these axes instead of a new figure. A path given here (the former first
            argument) is taken as ``path``.
        path : str or os.PathLike, optional
            Write the figure there (PNG, SVG, PDF by extension).

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting import plot_regime_map, plot_target

        ax, path = plot_target(ax, path)
        return plot_regime_map(self, path=path, ax=ax)
