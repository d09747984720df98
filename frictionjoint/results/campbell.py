"""Campbell diagrams: a blade's frequencies on its friction root against rotor speed, the
engine-order lines and their crossings (:class:`CampbellDiagram`)."""
from __future__ import annotations

import csv
import math
import os
from dataclasses import dataclass
from typing import Optional

import numpy as np

__all__ = ["CampbellDiagram", "CROSSING_DTYPE", "crossing_table"]

#: the columns of :attr:`CampbellDiagram.crossings`: which curve (``'stuck'``, ``'slipping'``,
#: ``'nonlinear'``), the engine order, the mode (0 the lowest), the rotor speed [rad/s] and the
#: mode's frequency there [rad/s]
CROSSING_DTYPE = np.dtype([("limit", "U9"), ("engine_order", float), ("mode", int), ("speed", float),
                           ("frequency", float)])

_RPM = 30.0 / math.pi  # rad/s -> rev/min
_HZ = 0.5 / math.pi  # rad/s -> Hz


def crossing_table(rows) -> np.ndarray:
    """The crossings as a structured array of :data:`CROSSING_DTYPE`, sorted by speed.

    Parameters
    ----------
    rows : iterable of tuple
        ``(limit, engine_order, mode, speed, frequency)`` each.

    Returns
    -------
    (n,) structured ndarray
    """
    table = np.array([tuple(r) for r in rows], dtype=CROSSING_DTYPE)
    return table[np.argsort(table["speed"], kind="stable")]


@dataclass(eq=False)
class CampbellDiagram:
    """A blade model's frequencies on its friction root against rotor speed, in the root's two
    linear limits, with the engine-order lines ``omega = EO Omega`` and their crossings
    (:func:`frictionjoint.campbell.campbell`).

    Attributes
    ----------
    model : str
        The blade model's name.
    speed : (n,) ndarray
        Rotor speeds ``Omega`` [rad/s], increasing.
    engine_orders : (m,) ndarray
        The engine orders ``EO`` [-].
    stuck_frequency, slipping_frequency : (n, n_modes) ndarray
        Undamped natural frequencies [rad/s] of the lowest ``n_modes`` modes with every slider of
        the root stuck, and with every slider slipping (free slip), ascending per speed; 0 for a
        mechanism (``omega^2 <= 0``).
    crossings : (k,) structured ndarray
        One row per crossing of a mode's curve with an engine-order line (:data:`CROSSING_DTYPE`:
        ``limit``, ``engine_order``, ``mode``, ``speed`` [rad/s], ``frequency`` [rad/s]), sorted
        by speed; located by root finding between the speed samples.
    amplitude : float, optional
        With a nonlinear band: the first-harmonic amplitude at ``dof`` [m] of the nonlinear modes.
    dof : str, optional
        The DOF of ``amplitude`` (None with a nonlinear band: each stuck mode's largest DOF).
    n_harmonics : int, optional
        Harmonics of the nonlinear modes.
    nonlinear_frequency, nonlinear_damping_ratio : (n, n_modes) ndarray, optional
        The nonlinear mode (EPMC) that starts from each stuck mode, at ``amplitude``: its frequency
        [rad/s] and damping ratio [-]; NaN where it did not converge.
    nonlinear_converged : (n, n_modes) bool ndarray, optional
        Where it converged.
    design_speed : float, optional
        The model's own rotor speed [rad/s] (its ``[rotor] speed``), marked on the plot.
    message : str
        What was computed, and how accurately the crossings are located.
    """

    model: str
    speed: np.ndarray
    engine_orders: np.ndarray
    stuck_frequency: np.ndarray
    slipping_frequency: np.ndarray
    crossings: np.ndarray
    amplitude: Optional[float] = None
    dof: Optional[str] = None
    n_harmonics: Optional[int] = None
    nonlinear_frequency: Optional[np.ndarray] = None
    nonlinear_damping_ratio: Optional[np.ndarray] = None
    nonlinear_converged: Optional[np.ndarray] = None
    design_speed: Optional[float] = None
    message: str = ""

    @property
    def n_modes(self) -> int:
        """Modes per limit."""
        return int(self.stuck_frequency.shape[1])

    @property
    def success(self) -> bool:
        """Every frequency is finite and, with a nonlinear band, every nonlinear mode converged
        (the result contract)."""
        ok = bool(np.all(np.isfinite(self.stuck_frequency)) and np.all(np.isfinite(self.slipping_frequency)))
        return ok and (self.nonlinear_converged is None or bool(np.all(self.nonlinear_converged)))

    @property
    def status(self) -> str:
        """``'ok'``, or ``'partial'`` where some nonlinear modes did not converge."""
        return "ok" if self.success else "partial"

    def table(self, markdown: bool = False) -> str:
        """The crossings as text: curve, engine order, mode, speed [rad/s] and [rpm], frequency
        [rad/s] and [Hz].

        Parameters
        ----------
        markdown : bool
            A Markdown table (for a README) instead of aligned columns.

        Returns
        -------
        str
        """
        head = ("curve", "EO", "mode", "speed [rad/s]", "speed [rpm]", "frequency [rad/s]", "frequency [Hz]")
        rows = [(str(r["limit"]), f"{r['engine_order']:g}", str(int(r["mode"])), f"{r['speed']:.6g}",
                 f"{r['speed'] * _RPM:.6g}", f"{r['frequency']:.6g}", f"{r['frequency'] * _HZ:.6g}")
                for r in self.crossings]
        if markdown:
            lines = ["| " + " | ".join(head) + " |", "|" + "|".join(["---"] * 3 + ["---:"] * 4) + "|"]
            lines += ["| " + " | ".join(r) + " |" for r in rows]
        else:
            widths = [max([len(h)] + [len(r[j]) for r in rows]) for j, h in enumerate(head)]
            lines = ["  ".join(h.rjust(w) for h, w in zip(head, widths))]
            lines += ["  ".join(c.rjust(w) for c, w in zip(r, widths)) for r in rows]
        if not rows:
            lines.append("no crossing in the speed range")
        return "\n".join(lines)

    def to_csv(self, path: str | os.PathLike, curves: bool = False) -> None:
        """Write the crossings (one row each, SI units), or with ``curves`` one row per speed with
        every mode's stuck, slipping (and nonlinear) frequency; ``# key = value`` lines first
        (model, engine orders, amplitude). Floats round-trip exactly.

        Parameters
        ----------
        path : str or os.PathLike
            Output file.
        curves : bool
            The curves instead of the crossings.
        """
        with open(path, "w", newline="", encoding="utf-8") as fh:
            for key in ("model", "amplitude", "dof", "n_harmonics", "design_speed"):
                fh.write(f"# {key} = {getattr(self, key)!r}\n")
            fh.write(f"# engine_orders = {[float(e) for e in self.engine_orders]!r}\n")
            w = csv.writer(fh)
            if not curves:
                w.writerow(CROSSING_DTYPE.names)
                for r in self.crossings:
                    w.writerow([str(r["limit"]), repr(float(r["engine_order"])), int(r["mode"]),
                                repr(float(r["speed"])), repr(float(r["frequency"]))])
                return
            blocks = {"stuck": self.stuck_frequency, "slipping": self.slipping_frequency}
            if self.nonlinear_frequency is not None:
                blocks.update(nonlinear=self.nonlinear_frequency, nonlinear_damping_ratio=self.nonlinear_damping_ratio)
            w.writerow(["speed"] + [f"{name}_{k}" for name in blocks for k in range(self.n_modes)])
            for i, s in enumerate(self.speed):
                w.writerow([repr(float(s))] + [repr(float(b[i, k])) for b in blocks.values() for k in range(self.n_modes)])

    def plot(self, ax=None, path=None):
        """Frequency against rotor speed (:func:`plot_campbell`): each mode in both limits with
        the band between them, the nonlinear modes at the amplitude, the engine-order lines and
        the crossings; with the nonlinear modes, their damping ratios below.

        Parameters
        ----------
        ax : matplotlib Axes or (2,) sequence of Axes, optional
            Axes for the frequencies (and, given two, the damping ratios); a new figure if omitted.
        path : str or os.PathLike, optional
            Write the figure there.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from ..plotting import plot_target

        ax, path = plot_target(ax, path)
        return plot_campbell(self, ax=ax, path=path)


_MARKERS = {"stuck": dict(marker="o", mfc="none", color="C0"), "slipping": dict(marker="s", mfc="none", color="C3"),
            "nonlinear": dict(marker="D", mfc="C1", color="C1")}


def plot_campbell(cd: CampbellDiagram, ax=None, path=None):
    """The Campbell diagram of a :class:`CampbellDiagram`: frequency [rad/s] against rotor speed
    [rad/s], each mode stuck (solid) and free-slip (dashed) with the band between them shaded,
    the nonlinear modes at the amplitude (dots), the engine-order lines (grey, labelled) and the
    crossings marked; with the nonlinear modes, their damping ratios against speed in a panel below
    (log scale). Draws with the figure's own methods: matplotlib is imported by
    :func:`frictionjoint.plotting.new_figure` only. Each mode is labelled at its stuck curve's end
    (0 the lowest) and each engine-order line at its end; the model's design speed is dotted.

    Parameters
    ----------
    cd : CampbellDiagram
    ax : matplotlib Axes or (2,) sequence of Axes, optional
        The frequencies' axes, or those and the damping ratios' (a new figure if omitted).
    path : str or os.PathLike, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    from ..plotting import new_figure

    band = cd.nonlinear_damping_ratio is not None
    ax_z = None
    if ax is None and band:
        fig = new_figure((8.0, 8.0))
        ax, ax_z = fig.subplots(2, 1, sharex=True, height_ratios=(3.0, 1.2))
    elif ax is None:
        fig = new_figure((8.0, 6.0))
        ax = fig.subplots()
    elif isinstance(ax, (list, tuple)):
        ax, ax_z = ax
    fig = ax.figure
    s = cd.speed
    where = f" at {cd.dof}" if cd.dof else ""
    for k in range(cd.n_modes):
        first = k == 0
        ax.fill_between(s, cd.slipping_frequency[:, k], cd.stuck_frequency[:, k], color="C0", alpha=0.12, lw=0,
                        label="between the limits" if first else None)
        ax.plot(s, cd.stuck_frequency[:, k], "-", color="C0", lw=1.4, label="stuck root" if first else None)
        ax.annotate(f"mode {k}", (s[-1], cd.stuck_frequency[-1, k]), textcoords="offset points", xytext=(-4, 5),
                    ha="right", va="bottom", fontsize="small", color="C0")
        ax.plot(s, cd.slipping_frequency[:, k], "--", color="C3", lw=1.2, label="free slip" if first else None)
        if cd.nonlinear_frequency is not None:
            ax.plot(s, cd.nonlinear_frequency[:, k], ".-", color="C1", lw=1.0, ms=4,
                    label=f"nonlinear mode at {cd.amplitude:.3g} m{where}, H = {cd.n_harmonics}" if first else None)
    top = 1.08 * float(np.nanmax(cd.stuck_frequency))
    for eo in cd.engine_orders:
        end = min(s[-1], top / eo)
        ax.plot([0.0, end], [0.0, eo * end], "-", color="0.55", lw=0.8, zorder=1)
        ax.annotate(f"{eo:g}", (end, eo * end), textcoords="offset points", xytext=(2, 2), fontsize="small",
                    color="0.35")
    ax.plot([], [], "-", color="0.55", lw=0.8, label="engine orders")
    if cd.design_speed is not None:
        ax.axvline(cd.design_speed, ls=":", color="k", lw=1.0, label=f"design speed {cd.design_speed:g} rad/s")
    for limit, style in _MARKERS.items():
        rows = cd.crossings[cd.crossings["limit"] == limit]
        if rows.size:
            ax.plot(rows["speed"], rows["frequency"], ls="none", ms=6, label=f"crossings ({limit})", **style)
    ax.set_xlim(0.0, 1.02 * s[-1])
    ax.set_ylim(0.0, top)
    if ax_z is not None and band:
        _draw_damping(cd, ax_z)
    (ax if ax_z is None else ax_z).set_xlabel("rotor speed [rad/s]")
    ax.set_ylabel("frequency [rad/s]")
    ax.set_title(f"Campbell diagram: {cd.model}")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small", loc="upper left")
    if path is not None:
        fig.savefig(path, dpi=130)
    return fig


def _draw_damping(cd: CampbellDiagram, ax) -> None:
    """The nonlinear modes' damping ratios against speed, one line per mode, log scale."""
    for k in range(cd.n_modes):
        ax.plot(cd.speed, cd.nonlinear_damping_ratio[:, k], ".-", lw=1.0, ms=3, color=f"C{k + 4}", label=f"mode {k}")
    if cd.design_speed is not None:
        ax.axvline(cd.design_speed, ls=":", color="k", lw=1.0)
    ax.set_yscale("log")
    ax.set_ylabel("damping ratio [-]")
    ax.set_title(f"nonlinear modes at {cd.amplitude:.3g} m{f' at {cd.dof}' if cd.dof else ''}", fontsize="medium")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small", loc="upper right")
