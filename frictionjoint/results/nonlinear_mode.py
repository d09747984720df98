"""Nonlinear-mode results: a mode's frequency and damping ratio against amplitude
(:class:`NonlinearMode`), its check against the exact free decay (:class:`DecayCheck`) and the
EPMC orbit solved exactly in time (:class:`ModeOrbit`)."""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

import numpy as np

__all__ = ["NonlinearMode", "DecayCheck", "ModeOrbit"]

#: rows of a mode's points its printout shows (the first and last half of them beyond)
MAX_ROWS = 40


@dataclass
class DecayCheck:
    """One point of a nonlinear mode against the exact free decay from its state: cycle by cycle
    (between successive maxima at the mode's DOF), the decay's frequency and energy lost beside
    the mode's at the cycle's first-harmonic amplitude.

    Attributes
    ----------
    point : int
        The mode's point the decay starts from.
    peak_times : (n_cycles + 1,) ndarray
        Times of the maxima at the DOF [s].
    amplitude : (n_cycles,) ndarray
        Each cycle's first-harmonic amplitude at the DOF (over the cycle, at its frequency) [m].
    frequency : (n_cycles,) ndarray
        ``2 pi / T`` of each cycle [rad/s].
    energy_lost : (n_cycles,) ndarray
        Energy dissipated over each cycle, friction and dashpots [J].
    mode_frequency : (n_cycles,) ndarray
        The mode's frequency at each cycle's amplitude [rad/s].
    mode_energy : (n_cycles,) ndarray
        The mode's energy lost per cycle at that amplitude, ``xi oint x'^T M x' dt`` [J].
    frequency_error : float
        ``max |frequency - mode_frequency| / mode_frequency`` over the cycles.
    energy_error : float
        ``max |energy_lost - mode_energy| / mode_energy`` over the cycles (NaN where the mode
        loses no energy).
    message : str
        What was compared.
    """

    point: int
    peak_times: np.ndarray
    amplitude: np.ndarray
    frequency: np.ndarray
    energy_lost: np.ndarray
    mode_frequency: np.ndarray
    mode_energy: np.ndarray
    frequency_error: float
    energy_error: float
    message: str = ""

    @property
    def success(self) -> bool:
        """Whether cycles were compared (the result contract; not a verdict on the errors)."""
        return bool(self.amplitude.size) and bool(np.isfinite(self.frequency_error))

    @property
    def status(self) -> str:
        """``'compared'`` or ``'failed'``."""
        return "compared" if self.success else "failed"


@dataclass
class ModeOrbit:
    """The EPMC orbit at one amplitude, solved exactly in time (:func:`frictionjoint.solvers.marcher.autonomous.mode_orbit`).

    Attributes
    ----------
    amplitude : float
        First-harmonic amplitude at the DOF [m].
    frequency : float
        ``omega = 2 pi / T`` [rad/s] (NaN unless converged).
    damping_ratio : float
        ``zeta = xi / (2 omega)`` (NaN unless converged).
    negative_damping : float
        ``xi`` [1/s].
    harmonics : (H + 1, n_dof) complex ndarray
        The orbit's exact harmonics, ``x(t) = Re(sum_h harmonics[h] e^{i h omega t})`` [m], shifted
        in time so that the first harmonic at the DOF is real and positive (as the harmonic
        balance's).
    friction_per_cycle : float
        Energy friction dissipates over the period [J].
    state : (2 n_dof + n_sliders,) ndarray
        ``[x, v, w]`` at the section.
    residual : float
        Scaled residual of the last iterate (periodicity, phase, amplitude).
    iterations : int
        Newton iterations.
    converged : bool
        The residual is within the tolerance.
    message : str
        What happened.
    """

    amplitude: float
    frequency: float
    damping_ratio: float
    negative_damping: float
    harmonics: np.ndarray
    friction_per_cycle: float
    state: np.ndarray
    residual: float
    iterations: int
    converged: bool
    message: str = ""

    @property
    def success(self) -> bool:
        """Newton converged (the result contract)."""
        return bool(self.converged)

    @property
    def status(self) -> str:
        """``'periodic'`` or ``'not converged'``."""
        return "periodic" if self.converged else "not converged"


@dataclass
class NonlinearMode:
    """A nonlinear mode of a :class:`~frictionjoint.system.FrictionSystem` by the extended periodic
    motion concept (:func:`~frictionjoint.solvers.frequency_domain.nonlinear_mode.nonlinear_mode`):
    the free periodic motion with a negative mass-proportional damping ``-xi M x'`` at each amplitude.

    Attributes
    ----------
    amplitude : (n,) ndarray
        First-harmonic amplitude at ``dof`` [m] (``x_dof = amplitude cos(omega t) + ...``).
    frequency : (n,) ndarray
        Angular frequency [rad/s] (NaN where Newton did not converge).
    damping_ratio : (n,) ndarray
        ``zeta = xi / (2 omega)`` (NaN where Newton did not converge).
    negative_damping : (n,) ndarray
        ``xi`` [1/s] (NaN where Newton did not converge).
    harmonics : (n, H + 1, n_dof) complex ndarray
        Mode shape per amplitude: ``x(t) = Re(sum_h harmonics[:, h] e^{i h omega t})`` [m] (Newton's
        last iterate where it did not converge).
    converged : (n,) bool ndarray
        Newton converged at the amplitude.
    dissipated_per_cycle : (n,) ndarray
        Energy the negative damping puts in per period, equal to what friction and the dashpots
        take out [J].
    friction_per_cycle, viscous_per_cycle : (n,) ndarray
        Its parts: the joints' friction and the structure's dashpots [J].
    stuck : (n,) bool ndarray
        Every slider sticks over the whole period (the stuck linear mode).
    slider_positions : (n, n_sliders) ndarray
        The sliders' positions at ``t = 0`` [m] (the start of a free decay).
    iterations : (n,) int ndarray
        Newton iterations per amplitude (intermediate amplitudes included).
    mode : int
        The stuck system's mode followed.
    dof : int
        The DOF of the amplitude; ``dof_name`` its name.
    n_harmonics : int
        ``H``.
    stuck_frequency, stuck_damping_ratio : float
        The mode of the stuck linear limit (every slider stuck) [rad/s], [-].
    slipping_frequency, slipping_damping_ratio : float
        The most similar mode (mass-weighted MAC) of the free-slip limit (sliders carry no
        force) [rad/s], [-]; NaN where it is a rigid-body mode.
    message : str
        What happened.
    frequency_error, energy_error : (n,) ndarray or None
        With ``check``: per checked point, the largest relative difference of the exact free
        decay's cycles from the mode (:class:`DecayCheck`), NaN elsewhere.
    decays : tuple of DecayCheck
        With ``check``: the comparisons.
    exact_frequency, exact_damping_ratio : (n,) ndarray or None
        With ``exact``: per picked point, the EPMC orbit solved exactly in time (no truncation)
        [rad/s], [-]; NaN elsewhere and where it did not converge. ``frequency / exact_frequency -
        1`` and ``damping_ratio / exact_damping_ratio - 1`` are the harmonic balance's truncation
        errors.
    orbits : tuple of ModeOrbit
        With ``exact``: the exact orbits.
    """

    amplitude: np.ndarray
    frequency: np.ndarray
    damping_ratio: np.ndarray
    negative_damping: np.ndarray
    harmonics: np.ndarray
    converged: np.ndarray
    dissipated_per_cycle: np.ndarray
    friction_per_cycle: np.ndarray
    viscous_per_cycle: np.ndarray
    stuck: np.ndarray
    slider_positions: np.ndarray
    iterations: np.ndarray
    mode: int
    dof: int
    dof_name: str
    n_harmonics: int
    stuck_frequency: float = float("nan")
    stuck_damping_ratio: float = float("nan")
    slipping_frequency: float = float("nan")
    slipping_damping_ratio: float = float("nan")
    message: str = ""
    frequency_error: Optional[np.ndarray] = None
    energy_error: Optional[np.ndarray] = None
    decays: tuple = field(default_factory=tuple)
    exact_frequency: Optional[np.ndarray] = None
    exact_damping_ratio: Optional[np.ndarray] = None
    orbits: tuple = field(default_factory=tuple)

    @property
    def success(self) -> bool:
        """Every amplitude converged (the result contract)."""
        return bool(self.converged.size) and bool(np.all(self.converged))

    @property
    def status(self) -> str:
        """``'ok'``, ``'partial'`` or ``'failed'``."""
        if self.success:
            return "ok"
        return "partial" if np.any(self.converged) else "failed"

    def __repr__(self) -> str:
        """A table: the mode's points, then the checked ones only (their free decays' and exact
        orbits' differences), not every field's array (a NaN wherever a point was not checked)."""
        lines = [f"NonlinearMode(mode {self.mode} at {self.dof_name}, H = {self.n_harmonics}, {self.status}: {self.message}",
                 f"  stuck limit {self.stuck_frequency:.6g} rad/s (zeta {self.stuck_damping_ratio:.4g}), free-slip "
                 f"limit {self.slipping_frequency:.6g} rad/s (zeta {self.slipping_damping_ratio:.4g})",
                 f"  {'amplitude [m]':>14} {'omega [rad/s]':>14} {'zeta':>12} {'stuck':>6} {'converged':>9}"]
        rows = range(self.amplitude.size)
        shown = list(rows) if len(rows) <= MAX_ROWS else list(rows[:MAX_ROWS // 2]) + [-1] + list(rows[-MAX_ROWS // 2:])
        for k in shown:
            if k < 0:
                lines.append(f"  ... {self.amplitude.size - MAX_ROWS} more ...")
                continue
            lines.append(f"  {self.amplitude[k]:14.6g} {self.frequency[k]:14.8g} {self.damping_ratio[k]:12.6g} "
                         f"{'yes' if self.stuck[k] else 'no':>6} {'yes' if self.converged[k] else 'no':>9}")
        for title, names, columns in (
                ("checked against the exact free decay", ("frequency error", "energy error"),
                 (self.frequency_error, self.energy_error)),
                ("the EPMC orbit solved exactly in time", ("omega [rad/s]", "zeta"),
                 (self.exact_frequency, self.exact_damping_ratio))):
            picked = [] if columns[0] is None else np.flatnonzero(np.isfinite(columns[0]))
            if len(picked):
                lines.append(f"  {title} ({len(picked)} points):")
                lines.append(f"  {'amplitude [m]':>14}" + "".join(f" {n:>16}" for n in names))
                lines += [f"  {self.amplitude[k]:14.6g}" + "".join(f" {c[k]:16.8g}" for c in columns) for k in picked]
        return "\n".join(lines) + ")"

    def plot(self, ax=None, path=None):
        """Frequency and damping ratio against amplitude, the stuck and free-slip linear limits
        drawn (:func:`plot_nonlinear_mode`).

        Parameters
        ----------
        ax : (2,) sequence of matplotlib Axes, optional
            Axes for the frequency and the damping ratio (a new figure if omitted).
        path : str or os.PathLike, optional
            Write the figure there.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting import plot_target

        ax, path = plot_target(ax, path)
        return plot_nonlinear_mode(self, ax=ax, path=path)


def plot_nonlinear_mode(nm: NonlinearMode, ax=None, path=None):
    """Frequency and damping ratio of a :class:`NonlinearMode` against amplitude (log), converged
    points joined, the stuck and free-slip limits as dashed lines, checked points' free decays as
    crosses. Draws with the figure's own methods: matplotlib is imported by
    :func:`frictionjoint.plotting.new_figure` only.

    Parameters
    ----------
    nm : NonlinearMode
    ax : (2,) sequence of matplotlib Axes, optional
    path : str or os.PathLike, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..plotting import new_figure

    if ax is None:
        fig = new_figure((8.0, 6.5))
        ax_w, ax_z = fig.subplots(2, 1, sharex=True)
    else:
        ax_w, ax_z = ax
        fig = ax_w.figure
    ok = nm.converged
    ax_w.plot(nm.amplitude[ok], nm.frequency[ok], "o-", ms=3, color="C0", label=f"nonlinear mode (H = {nm.n_harmonics})")
    ax_z.plot(nm.amplitude[ok], nm.damping_ratio[ok], "o-", ms=3, color="C0", label="nonlinear mode")
    for value, axis, name, colour in ((nm.stuck_frequency, ax_w, "stuck", "C2"), (nm.slipping_frequency, ax_w, "free slip", "C3"),
                                      (nm.stuck_damping_ratio, ax_z, "stuck", "C2"),
                                      (nm.slipping_damping_ratio, ax_z, "free slip", "C3")):
        if np.isfinite(value):
            axis.axhline(value, ls="--", lw=1, color=colour, label=f"{name} limit")
    order = np.argsort(nm.amplitude[ok])
    for dc in nm.decays:  # the decay's damping ratio: the mode's, times its energy lost over the mode's
        ax_w.plot(dc.amplitude, dc.frequency, "x", color="k", ms=5)
        zeta = np.interp(dc.amplitude, nm.amplitude[ok][order], nm.damping_ratio[ok][order])
        ax_z.plot(dc.amplitude, dc.energy_lost / dc.mode_energy * zeta, "x", color="k", ms=5)
    if nm.decays:
        ax_w.plot([], [], "x", color="k", label="exact free decay, per cycle")
    ax_z.set_xscale("log")
    ax_z.set_xlabel(f"first-harmonic amplitude at {nm.dof_name} [m]")
    ax_w.set_ylabel("frequency [rad/s]")
    ax_z.set_ylabel("damping ratio [-]")
    for axis in (ax_w, ax_z):
        axis.grid(True, which="both", alpha=0.3)
        axis.legend(fontsize="small")
    if path is not None:
        fig.savefig(path, dpi=130)
    return fig
