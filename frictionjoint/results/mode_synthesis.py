"""The forced response synthesised from a nonlinear mode (:class:`SynthesisedResponse`): an
:class:`~frictionjoint.results.OutputSweep` whose points are the branch given by the mode, with the
mode's amplitude at each point and the backbone."""
from __future__ import annotations

import os
from dataclasses import dataclass
from typing import TYPE_CHECKING, Optional

import numpy as np

from .frequency import OutputSweep

if TYPE_CHECKING:  # pragma: no cover
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

__all__ = ["SynthesisedResponse"]


@dataclass(eq=False)
class SynthesisedResponse(OutputSweep):
    """Forced response of one output near a resonance, synthesised from a nonlinear mode
    (:func:`~frictionjoint.solvers.frequency_domain.mode_synthesis.mode_synthesis`).

    The points are an :class:`~frictionjoint.results.OutputSweep`'s, in branch order from the
    low-frequency end: the linear tail below the branch (the requested frequencies there), the
    side below the peak (the mode's amplitudes ascending), the peak, the side above it (the mode's
    amplitudes descending), the linear tail above. So the table, the CSV, :meth:`peak` and the
    comparison with :meth:`BladeAssembly.frequency_response
    <frictionjoint.structures.BladeAssembly.frequency_response>` are the sweep's.

    Attributes
    ----------
    mode_amplitude : (n,) ndarray
        The mode's first-harmonic amplitude at its DOF at each point [m].
    backbone_omega : (m,) ndarray
        The mode's frequency at its converged amplitudes, ascending in amplitude [rad/s].
    backbone_response : (m,) complex ndarray
        The output's first harmonic on the mode at those amplitudes [m].
    peak_found : bool
        The branch's two sides meet inside the mode's amplitudes (the peak is one of the points).
    note : str
        What the synthesis did (the peak's refinement, tails left out), appended to
        :attr:`message`.
    omega, output, response, limits, stuck, converged, dissipated_per_cycle, messages, fold
        As :class:`~frictionjoint.results.OutputSweep`'s; ``stuck`` and ``dissipated_per_cycle``
        are the mode's at the point's amplitude (friction is rate-independent: the mode's orbit
        and the forced one dissipate alike); ``stable`` and ``truncation_error`` are not judged
        (None).
    """

    mode_amplitude: Optional[np.ndarray] = None
    backbone_omega: Optional[np.ndarray] = None
    backbone_response: Optional[np.ndarray] = None
    peak_found: bool = False
    note: str = ""

    @property
    def status(self) -> str:
        """``'ok'`` (the peak found), ``'partial'`` (points but no peak: the mode's amplitudes end
        below it) or ``'failed'`` (no point)."""
        status = super().status
        return "partial" if status == "ok" and not self.peak_found else status

    @property
    def message(self) -> str:
        """How many points, and :attr:`note`."""
        return f"{super().message}; {self.note}" if self.note else super().message

    def plot(self, ax: Axes | None = None, path: str | os.PathLike | None = None) -> Figure:
        """The output's amplitude against frequency with the linear limits
        (:func:`frictionjoint.plotting.plot_output_sweep`) and the mode's backbone (dashed).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            The axes to draw the branch, its limits and the backbone in (default a new figure's).
        path : str or os.PathLike, optional
            Where to save the figure (PNG, PDF, SVG, by the name's suffix).

        Returns
        -------
        matplotlib.figure.Figure
            The figure drawn in.
        """
        from ..plotting import plot_output_sweep, plot_target

        ax, path = plot_target(ax, path)
        fig = plot_output_sweep(self, ax=ax, label=f"synthesised from the mode, {self.output}")
        axis = fig.axes[0] if ax is None else ax
        if self.backbone_omega is not None and self.backbone_omega.size:
            axis.plot(self.backbone_omega, np.abs(self.backbone_response), "--", lw=1.0, color="C1",
                      label="backbone (the mode)")
            axis.legend(fontsize="small")
        if path is not None:
            fig.savefig(path, dpi=130)
        return fig
