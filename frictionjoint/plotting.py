"""Plots of results: the only module that imports matplotlib, and only inside its functions.

Figures are built with the object-oriented API on the Agg canvas (no pyplot, no global
backend switch), so plotting works on machines without a display and never disturbs an
interactive session's own backend; pass ``ax`` to draw into an existing figure instead.
"""
from __future__ import annotations

import os

import numpy as np

from .results.dof_names import dof_meaning

__all__ = ["plot_frequency_response", "plot_regime_map", "plot_time_response", "plot_work_precision",
           "new_figure", "plot_target", "plot_study_curve", "plot_study_contour", "plot_study_monte_carlo",
           "plot_slip_pattern", "plot_ahn_diagram", "safe_region"]

_DPI = 130


def new_figure(figsize=(8.0, 6.0)):
    """A matplotlib Figure on an Agg canvas (no pyplot state).

    Parameters
    ----------
    figsize : (2,) tuple of float
        Width and height [inch].

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def _axes(ax, figsize):
    """``(fig, ax)``: the given axes and their figure, or a new figure's single axes."""
    if ax is None:
        fig = new_figure(figsize)
        return fig, fig.subplots()
    return ax.figure, ax


def plot_target(ax, path):
    """``(ax, path)`` of a result's ``plot(ax=None, path=None)``: a path passed as the first
    argument (the results' former ``plot(path)``) is taken as ``path``.

    Parameters
    ----------
    ax : matplotlib Axes, tuple of Axes, str, os.PathLike or None
        What was passed as ``ax``.
    path : str, os.PathLike or None
        What was passed as ``path``.

    Returns
    -------
    (ax, path) : tuple
    """
    if isinstance(ax, (str, os.PathLike)):
        if path is not None:
            raise TypeError(f"plot(ax=None, path=None): ax is a path ({ax!r}) and path is given too")
        return None, ax
    return ax, path


def _save(fig, path):
    if path is not None:
        fig.savefig(path, dpi=_DPI)


def _runs(mask):
    """``(start, stop)`` index pairs of the runs of True in a 1-D bool array."""
    runs, start = [], None
    for i, m in enumerate(mask):
        if m and start is None:
            start = i
        elif not m and start is not None:
            runs.append((start, i - 1))
            start = None
    if start is not None:
        runs.append((start, len(mask) - 1))
    return runs


# --------------------------------------------------------------------------- forced response


_BRANCH_STYLE = {
    "up": dict(marker="o", mfc="none", color="C0", ms=5, lw=0.8, label="stepped sine, up"),
    "down": dict(marker="x", color="C1", ms=5, lw=0.8, ls="--", label="stepped sine, down"),
}
_REGIME_STYLE = {
    "stops": dict(marker="s", color="C3", ms=7, mfc="C3", alpha=0.55, ls="none",
                  label="motion with stops (simulation only)"),
    "stuck": dict(marker="D", color="0.4", ms=6, ls="none", label="permanent stick"),
}


def plot_frequency_response(fr, path=None, phase: bool = True, ax=None):
    """Amplitude (and phase) of a forced-response sweep against frequency.

    Up and down branches as markers, the analytic (Den Hartog) curve as a dense line where it
    is the motion, grey bands where it is not, points with stops highlighted, and vertical
    lines where the response grows without bound or did not converge.

    Outputs other than ``x`` recorded by the sweep (``fr.harmonics``, e.g. ``outputs=("x",
    "friction_force")``, the command line's ``--output``) get a panel each below, their
    first-harmonic amplitude.

    Parameters
    ----------
    fr : FrequencyResponse
        Result of :func:`frictionjoint.sweep.oscillator_sweep` (or any sweep of that type).
    path : str or os.PathLike, optional
        Write the figure there (format from the extension).
    phase : bool
        Add a phase panel [deg] below the amplitude.
    ax : matplotlib Axes or (Axes, Axes), optional
        Draw into these axes instead of a new figure: a pair, the amplitude and the phase axes
        (with ``phase``); one Axes, the amplitude only (the other outputs' panels need a new
        figure).

    Returns
    -------
    matplotlib.figure.Figure
    """
    ratio = fr.frequency_ratio
    xvals = ratio if ratio is not None else fr.omega
    extra = [name for name in fr.harmonics if name != "x"]  # the other outputs recorded (--output)
    ax_o = []
    if ax is not None:  # a pair: amplitude and phase; one Axes: the amplitude only
        ax_a, ax_p = (tuple(ax) if phase and np.ndim(ax) == 1 and len(ax) == 2 else (ax, None))
        fig = ax_a.figure
    else:
        rows = [1.6] + ([1.0] if phase else []) + [1.0] * len(extra)
        fig = new_figure((8.0, (7.0 if phase else 4.8) + 2.4 * len(extra)))
        grid = np.atleast_1d(fig.subplots(len(rows), 1, sharex=True, height_ratios=rows))
        ax_a, ax_p = grid[0], (grid[1] if phase else None)
        ax_o = list(grid[1 + phase:])
    axes = [ax_a] + ([ax_p] if ax_p is not None else []) + ax_o
    ok = fr.converged & np.isfinite(fr.amplitude)
    handles, amp_ref = _draw_analytic(fr, ax_a, ax_p, axes)
    handles += _draw_points(fr, xvals, ok, ax_a, ax_p, axes)
    _draw_outputs(fr, xvals, ok, extra, ax_o)
    _decorate_frequency_axes(fr, xvals, ok, amp_ref, ax_a, ax_p, axes)
    ax_a.legend(handles=handles, loc="upper right", fontsize=8, framealpha=0.9)
    _save(fig, path)
    return fig


def _draw_analytic(fr, ax_a, ax_p, axes):
    """The analytic curve (dense, gaps where it is not the motion, grey bands there); returns
    ``(legend handles, its finite positive amplitudes)``."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    handles, amp_ref = [], np.empty(0)
    dense = np.empty(0)
    if len(fr):
        lo, hi = float(fr.omega.min()), float(fr.omega.max())
        dense = np.linspace(lo, hi, 600)
        wn = fr.natural_frequency
        if wn is not None and lo < wn < hi:  # resolve the resonance itself
            dense = np.unique(np.concatenate([dense, [wn]]))
    curve = fr.analytic_curve(dense) if dense.size else None
    if curve is None:
        return handles, amp_ref
    d_amp, d_ph = curve
    amp_line = np.ma.filled(d_amp.astype(float), np.nan)
    amp_ref = amp_line[np.isfinite(amp_line) & (amp_line > 0)]
    ph_line = np.ma.filled(d_ph.astype(float), np.nan)
    scale = fr.natural_frequency if fr.frequency_ratio is not None else 1.0
    xd = dense / scale
    if np.isfinite(amp_line).any():  # a closed form that is nowhere the motion is not drawn, nor listed
        ax_a.plot(xd, amp_line, color="k", lw=1.4, zorder=2)
        if ax_p is not None:
            ax_p.plot(xd, np.degrees(ph_line), color="k", lw=1.4, zorder=2)
        handles.append(Line2D([], [], color="k", lw=1.4, label=f"{fr.analytic_name} (closed form)"))
    banded = False
    for a, b in _runs(np.ma.getmaskarray(d_amp)):
        if a == b and 0 < a < len(xd) - 1:
            # one dense sample, the closed form valid on both sides (the resonance itself, where
            # the amplitude is unbounded, or an isolated r = 1/(2n)): a point, not a band (its
            # band would be two samples wide, hidden under the resonance's line)
            continue
        x0 = xd[max(a - 1, 0)] if a > 0 else xd[a]
        x1 = xd[min(b + 1, len(xd) - 1)]
        for ax in axes:
            ax.axvspan(x0, x1, color="0.88", zorder=0, lw=0)
        banded = True
    if banded:
        handles.append(Patch(color="0.88", label=f"{fr.analytic_name} not valid (stops / resonance)"))
    return handles, amp_ref


def _draw_points(fr, xvals, ok, ax_a, ax_p, axes):
    """The simulated points: branches as lines with markers (broken where no orbit was found),
    points with stops or permanent stick highlighted, vertical lines at unbounded or
    unconverged points; returns the legend handles."""
    from matplotlib.lines import Line2D

    handles = []
    for branch in ("up", "down"):
        sel = fr.branch == branch
        if not (sel & ok).any():
            continue
        style = dict(_BRANCH_STYLE[branch])
        label = style.pop("label")
        order = np.argsort(xvals[sel], kind="stable")
        xb = xvals[sel][order]
        good = ok[sel][order]
        ax_a.plot(xb, np.where(good, fr.amplitude[sel][order], np.nan), zorder=3, **style)
        if ax_p is not None:
            ax_p.plot(xb, np.where(good, np.degrees(fr.phase[sel][order]), np.nan), zorder=3, **style)
        handles.append(Line2D([], [], label=label, **style))
    for regime, style in _REGIME_STYLE.items():
        sel = (fr.regime == regime) & ok
        if not sel.any():
            continue
        style = dict(style)
        label = style.pop("label")
        ax_a.plot(xvals[sel], fr.amplitude[sel], zorder=4, **style)
        if ax_p is not None:
            ax_p.plot(xvals[sel], np.degrees(fr.phase[sel]), zorder=4, **style)
        handles.append(Line2D([], [], label=label, **style))
    family = ok & ~np.asarray(fr.unique, bool) & (fr.regime != "stuck")  # the tables' '*' (a stuck mass's
    if family.any():  # rest positions always form a family: the regime says so)
        style = dict(marker="o", ms=11, mfc="none", mec="C2", mew=1.5, ls="none")
        ax_a.plot(xvals[family], fr.amplitude[family], zorder=5, **style)
        if ax_p is not None:
            ax_p.plot(xvals[family], np.degrees(fr.phase[family]), zorder=5, **style)
        handles.append(Line2D([], [], label="not unique: one member of a family of orbits", **style))
    for regime, color, label in (("unbounded", "C3", "unbounded growth (resonance)"),
                                 ("not converged", "m", "no periodic orbit found")):
        sel = fr.regime == regime
        if not sel.any():
            continue
        for xv in np.unique(xvals[sel]):
            for ax in axes:
                ax.axvline(xv, color=color, ls=":", lw=1.5, zorder=1)
        handles.append(Line2D([], [], color=color, ls=":", lw=1.5, label=label))
    return handles


#: units of the oscillator's outputs that have a first harmonic (frictionjoint.stepping.OSCILLATOR_OUTPUTS;
#: not imported here: stepping imports the results, which import this module)
_OUTPUT_UNITS = {"x": "m", "v": "m/s", "friction_force": "N", "dissipated_energy": "J"}


def _draw_outputs(fr, xvals, ok, names, axes):
    """One panel per other recorded output (``fr.harmonics``): its first-harmonic amplitude per
    branch, as the amplitude panel's markers."""
    for name, ax in zip(names, axes):
        h1 = np.asarray(fr.harmonics[name]["amplitude"], dtype=float)
        for branch in ("up", "down"):
            sel = (fr.branch == branch) & ok
            if not sel.any():
                continue
            style = {k: v for k, v in _BRANCH_STYLE[branch].items() if k != "label"}
            order = np.argsort(xvals[sel], kind="stable")
            ax.plot(xvals[sel][order], h1[sel][order], zorder=3, **style)
        unit = _OUTPUT_UNITS.get(name)
        ax.set_ylabel(f"{name}, first harmonic" + (f" [{unit}]" if unit else ""))
        ax.grid(True, alpha=0.3)


def _decorate_frequency_axes(fr, xvals, ok, amp_ref, ax_a, ax_p, axes):
    """Scales, limits, labels, grids and the title of a frequency-response figure."""
    amp_ok = fr.amplitude[ok & (fr.amplitude > 0)]
    if amp_ok.size:
        ax_a.set_yscale("log")
        top, bottom = float(amp_ok.max()), float(amp_ok.min())
        if amp_ref.size:  # show the analytic curve too, but not its resonance peak to infinity
            top = max(top, float(np.quantile(amp_ref, 0.97)))
            bottom = min(bottom, float(amp_ref.min()))
        ax_a.set_ylim(bottom / 1.5, top * 1.5)
    ax_a.set_ylabel("amplitude max |x| [m]")
    ax_a.grid(True, which="major", alpha=0.35)
    ax_a.grid(True, which="minor", alpha=0.12)
    if ax_p is not None:
        ax_p.set_ylabel("phase lag of x [deg]")
        ax_p.set_ylim(-5, 185)
        ax_p.set_yticks([0, 45, 90, 135, 180])
        ax_p.grid(True, alpha=0.3)
    axes[-1].set_xlabel(r"frequency ratio $r = \omega/\omega_n$" if fr.frequency_ratio is not None
                        else r"excitation frequency $\omega$ [rad/s]")
    if len(xvals):
        lo, hi = float(np.min(xvals)), float(np.max(xvals))
        pad = 0.015 * (hi - lo) if hi > lo else 0.05 * abs(lo)
        axes[-1].set_xlim(lo - pad, hi + pad)
    p = fr.parameters
    title = "Forced response"
    if {"slip_force", "force_amplitude", "base_amplitude", "stiffness"} <= set(p):
        p0 = p["force_amplitude"] + p["stiffness"] * p["base_amplitude"]
        title = (f"Coulomb oscillator, F/P$_0$ = {p['slip_force'] / abs(p0):.3g}"
                 f" (m = {p.get('mass', float('nan')):g} kg, k = {p['stiffness']:g} N/m"
                 + (f", c = {p['damping']:g} N s/m" if p.get("damping") else "") + ")")
    ax_a.set_title(title)


# --------------------------------------------------------------------------- regime map


_FIXED = {
    "stuck": ("permanent stick", "0.55"),
    "unbounded": ("unbounded (resonance)", "black"),
    "not converged": ("not converged", "#ff00ff"),
}
_EVEN = ["#fff7bc", "#a6cee3", "#1f78b4", "#08306b", "#6a3d9a", "#3f007d"]
_ODD = ["#e31a1c", "#ff7f00", "#fb9a99", "#b15928"]


def _stop_colour(n: int) -> str:
    if n % 2 == 0:
        return _EVEN[min(n // 2, len(_EVEN) - 1)]
    return _ODD[min(n // 2, len(_ODD) - 1)]


def _edges(centres):
    c = np.asarray(centres, dtype=float)
    if c.size == 1:
        return np.array([c[0] - 0.5 * max(abs(c[0]), 1e-3) * 0.1, c[0] + 0.5 * max(abs(c[0]), 1e-3) * 0.1])
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


def plot_regime_map(rm, path=None, ax=None):
    """Categorical map of stops per cycle over (frequency ratio, friction ratio).

    Each cell is coloured by its category (0, 1, 2, ... stops per cycle; permanent stick;
    unbounded; not converged) with a legend; a dot marks non-unique orbits; the dashed line is
    Den Hartog's stop boundary ``X̄ r^2 = f`` (sufficient for stop-free motion only for
    ``r >= 1/2``).

    Parameters
    ----------
    rm : RegimeMap
        Result of :func:`frictionjoint.regime.regime_map`.
    path : str or os.PathLike, optional
        Write the figure there.
    ax : matplotlib Axes, optional
        Draw into these axes.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from .analytic import den_hartog_boundary

    fig, ax = _axes(ax, (9.0, 6.0))
    stops = sorted({int(n) for n, reg in zip(rm.stops_per_cycle.ravel(), rm.regime.ravel())
                    if reg in ("stop-free", "stops")})
    cats = [(f"{n} stop" + ("" if n == 1 else "s") + (" (continuous)" if n == 0 else ""),
             _stop_colour(n), ("n", n)) for n in stops]
    cats += [(label, colour, ("r", reg)) for reg, (label, colour) in _FIXED.items()
             if np.any(rm.regime == reg)]
    index = np.zeros(rm.shape, dtype=int)
    for k, (_, _, key) in enumerate(cats):
        if key[0] == "n":
            sel = np.isin(rm.regime, ("stop-free", "stops")) & (rm.stops_per_cycle == key[1])
        else:
            sel = rm.regime == key[1]
        index[sel] = k
    cmap = ListedColormap([c for _, c, _ in cats] or ["white"])
    norm = BoundaryNorm(np.arange(len(cats) + 1) - 0.5, cmap.N)
    ax.pcolormesh(_edges(rm.frequency_ratios), _edges(rm.friction_ratios), index, cmap=cmap,
                  norm=norm, shading="flat", edgecolors="face", linewidth=0)
    handles = [Patch(facecolor=c, edgecolor="0.3", lw=0.5, label=label) for label, c, _ in cats]
    nonu = ~rm.unique & (rm.regime != "stuck")  # rest positions of a stuck mass always form a family
    if nonu.any():
        jj, ii = np.meshgrid(rm.frequency_ratios, rm.friction_ratios)
        ax.plot(jj[nonu], ii[nonu], ".", color="white", mec="k", mew=0.5, ms=5)
        handles.append(Line2D([], [], marker=".", ls="none", color="white", mec="k", mew=0.5,
                              ms=8, label="not unique (family of orbits)"))
    r_lo, r_hi = float(rm.frequency_ratios.min()), float(rm.frequency_ratios.max())
    rd = np.linspace(r_lo, r_hi, 800)
    fb = np.array([den_hartog_boundary(float(r)) for r in rd])
    ax.plot(rd, fb, color="white", lw=2.6, zorder=3)
    ax.plot(rd, fb, color="k", lw=1.2, ls="--", zorder=4)
    handles.append(Line2D([], [], color="k", lw=1.2, ls="--",
                          label=r"Den Hartog boundary $\bar X r^2 = F/P_0$"))
    ex, ey = _edges(rm.frequency_ratios), _edges(rm.friction_ratios)
    ax.set_xlim(ex[0], ex[-1])
    ax.set_ylim(ey[0], ey[-1])
    ax.set_xlabel(r"frequency ratio $r = \omega/\omega_n$")
    ax.set_ylabel(r"friction ratio $F/P_0$")
    ax.set_title("Stops per cycle of the Coulomb oscillator (Hong & Liu map), exact steady states")
    ax.legend(handles=handles, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8,
              frameon=False)
    _save(fig, path)
    return fig


# --------------------------------------------------------------------------- time response


def plot_time_response(tr, ax=None, path=None, **kwargs):
    """Displacement against time; the friction force on a second axis when it was recorded.

    Stops of finite duration (``'stick'`` events) are marked on the time axis.

    Parameters
    ----------
    tr : TimeResponse
        Result of ``simulate``.
    ax : matplotlib Axes, optional
        Draw into these axes (a new figure if omitted).
    path : str or os.PathLike, optional
        Write the figure there.
    **kwargs
        Passed to ``Axes.plot`` for the displacement lines.

    Returns
    -------
    matplotlib.axes.Axes
        The axes of the displacement.
    """
    fig, ax = _axes(ax, (8.0, 4.0))
    t = np.asarray(tr.t)
    if tr.x is not None:
        x = np.atleast_2d(tr.x)
        for i, row in enumerate(x):
            ax.plot(t, row, label=("x" if x.shape[0] == 1 else f"x[{i}]"), **kwargs)
        ax.set_ylabel("displacement [m]")
    if tr.friction_force is not None:
        f = np.atleast_2d(tr.friction_force)
        ax2 = ax.twinx()
        for i, row in enumerate(f):
            ax2.plot(t, row, color=f"C{(i + 3) % 10}", lw=0.9, alpha=0.8,
                     label=("friction force" if f.shape[0] == 1 else f"friction force [{i}]"))
        ax2.set_ylabel("friction force [N]")
        lines = ax.get_lines() + ax2.get_lines()
        ax.legend(lines, [ln.get_label() for ln in lines], loc="upper right", fontsize=8)
    elif tr.x is not None:
        ax.legend(loc="upper right", fontsize=8)
    events = getattr(tr, "events", None)
    if events is not None and len(events):
        stick = [tt for tt, _, _, kind in events if kind == "stick" and t[0] <= tt <= t[-1]]
        if stick:
            ax.plot(stick, np.zeros(len(stick)), "|", color="k", ms=8, transform=ax.get_xaxis_transform(),
                    label="_stop")
    ax.set_xlabel("time [s]")
    ax.grid(True, alpha=0.3)
    _save(fig, path)
    return ax


# --------------------------------------------------------------------------- work precision


_METHOD_STYLE = {
    "exact marcher": dict(marker="*", color="C3", ms=13, zorder=5),
    "exact SDOF kernel": dict(marker="*", color="C6", ms=13, zorder=6),
    "steady_state": dict(marker="s", color="C0", ms=6, mfc="none"),
    "FMU sweep": dict(marker="D", color="C4", ms=6, mfc="none"),
    "describing function": dict(marker="X", color="k", ms=8),
    "tanh RK45": dict(marker="o", color="C1", ms=4, alpha=0.75),
    "tanh LSODA": dict(marker="^", color="C2", ms=4, alpha=0.75),
    "tanh Radau": dict(marker="v", color="C8", ms=4, alpha=0.75),
    "events DOP853": dict(marker="P", color="C9", ms=7),
}


def plot_work_precision(wp, path=None, floor: float = 1e-17, ax=None):
    """Work-precision diagram: relative error against wall time, log-log, one panel per case.

    Parameters
    ----------
    wp : WorkPrecision (benchmarks/harness.py)
        Result of ``run_benchmark`` of the benchmark harness (``benchmarks/harness.py``).
    path : str or os.PathLike, optional
        Write the figure there.
    floor : float
        Errors below this (exact zeros) are drawn at it [-].
    ax : sequence of matplotlib Axes, optional
        One axes per case, instead of a new figure.

    Returns
    -------
    matplotlib.figure.Figure
    """
    cases = list(wp.problems)
    if ax is not None:
        axes = np.atleast_1d(np.asarray(ax, dtype=object))
        if axes.size != len(cases):
            raise ValueError(f"ax must hold one Axes per case ({len(cases)}), got {axes.size}")
        fig = axes[0].figure
    else:
        fig = new_figure((4.6 * len(cases), 4.8))
        axes = np.atleast_1d(fig.subplots(1, len(cases), sharey=True))
    handles = {}
    for ax, case in zip(axes, cases):
        rows = [r for r in wp.case_rows(case) if r.ok]
        for method in dict.fromkeys(r.method for r in rows):
            sel = [r for r in rows if r.method == method]
            style = dict(_METHOD_STYLE.get(method, dict(marker="o")), ls="none", label=method)
            (line,) = ax.plot([r.time for r in sel], [max(r.error, floor) for r in sel], **style)
            handles.setdefault(method, line)
        ax.axhline(1e-10, color="0.5", lw=0.8, ls="--")
        ax.text(0.02, 1e-10, " 1e-10", transform=ax.get_yaxis_transform(), va="bottom", fontsize=7,
                color="0.4")
        ax.set_xscale("log")
        ax.set_yscale("log")
        prob = wp.problems[case]
        motion = "stop-free" if prob.regime == "stop-free" else "with stops"
        ax.set_title(f"{case.label} ({motion})\nreference: {prob.reference_name.split(' (')[0]}", fontsize=9)
        ax.set_xlabel("wall time [s] (best of repeats)")
        ax.grid(True, which="major", alpha=0.3)
    axes[0].set_ylabel(f"relative amplitude error (0 drawn at {floor:.0e})")
    fig.legend(list(handles.values()), list(handles), loc="outside lower center", ncol=len(handles),
               fontsize=8, frameon=False)
    fig.suptitle("Coulomb oscillator, amplitude of the periodic steady state: error against run time",
                 fontsize=10)
    _save(fig, path)
    return fig


def plot_output_sweep(sw, ax=None, path=None, label: str | None = None):
    """Amplitude of an :class:`~frictionjoint.results.OutputSweep` against frequency (log scale):
    the nonlinear points (stuck and slipping marked differently, unstable ones crossed, unconverged
    points left out) and the two linear limits as lines.

    Parameters
    ----------
    sw : OutputSweep
    ax : matplotlib Axes, optional
        Draw into these axes (a new figure if omitted).
    path : str or os.PathLike, optional
        Write the figure there.
    label : str, optional
        Legend label of the nonlinear curve (default: the output's name).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _axes(ax, (8.0, 5.0))
    styles = {"stuck": dict(color="0.35", ls="--"), "slipping": dict(color="0.35", ls=":")}
    for name, x in sw.limits.items():
        ax.plot(sw.omega, np.abs(x), lw=1.0, label=f"linear limit: {name}", **styles.get(name, {}))
    ok = np.asarray(sw.converged, bool)
    ax.plot(sw.omega[ok], sw.amplitude[ok], "-", lw=1.5, color="C0", label=label or f"nonlinear, {sw.output}")
    slip = ok & ~np.asarray(sw.stuck, bool)
    ax.plot(sw.omega[slip], sw.amplitude[slip], ".", ms=4, color="C3", label="root slips")
    if getattr(sw, "stable", None) is not None:  # orbits the Floquet multipliers find unstable
        bad = ok & np.array([v is False for v in sw.stable])
        if bad.any():
            ax.plot(sw.omega[bad], sw.amplitude[bad], "x", ms=5, color="k", label="unstable")
    ax.set_yscale("log")
    ax.set_xlabel("omega [rad/s]")
    ax.set_ylabel(f"first-harmonic amplitude of {sw.output} [m]")
    how = "harmonic balance" if getattr(sw, "fold", None) is not None else "stepped sine"
    meaning = dof_meaning(sw.output)
    ax.set_title(f"Forced response ({how}) of {sw.output}" + (f":\n{meaning}" if meaning else ""), fontsize=10)
    ax.legend(fontsize="small")
    ax.grid(True, which="both", alpha=0.3)
    _save(fig, path)
    return fig


def plot_hbm_sweep(sw, output=0, ax=None, path=None):
    """First-harmonic amplitude of a harmonic-balance branch
    (:class:`~frictionjoint.results.HarmonicBalanceSweep`) against frequency, in branch order:
    stable parts solid, unstable parts dashed, parts of unknown stability dotted; folds marked.

    Parameters
    ----------
    sw : HarmonicBalanceSweep
    output : int or (n_dof,) array_like
        A DOF index, or the coefficients of an output linear in the DOFs (e.g. a blade's tip).
    ax : matplotlib Axes, optional
        Draw into these axes (a new figure if omitted).
    path : str or os.PathLike, optional
        Write the figure there.

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _axes(ax, (8.0, 5.0))
    h1 = sw.harmonics[:, 1]
    amp = np.abs(h1[:, int(output)] if np.ndim(output) == 0 else h1 @ np.asarray(output, dtype=float))
    kinds = np.array(["unknown" if sw.stable is None or sw.stable[k] is None else
                      ("stable" if sw.stable[k] else "unstable") for k in range(sw.omega.size)])
    styles = {"stable": dict(ls="-", color="C0"), "unstable": dict(ls="--", color="C3"),
              "unknown": dict(ls=":", color="C0")}
    start = 0
    labelled = set()
    for k in range(1, sw.omega.size + 1):  # one line per run of one stability kind
        if k == sw.omega.size or kinds[k] != kinds[start]:
            kind = kinds[start]
            stop = min(k + 1, sw.omega.size)
            ax.plot(sw.omega[start:stop], amp[start:stop], lw=1.5,
                    label=None if kind in labelled else f"H = {sw.n_harmonics}, {kind}", **styles[kind])
            labelled.add(kind)
            start = k
    folds = np.flatnonzero(sw.fold)
    if folds.size:
        ax.plot(sw.omega[folds], amp[folds], "o", ms=5, mfc="none", color="k", label="fold")
    ax.set_yscale("log")
    ax.set_xlabel("omega [rad/s]")
    ax.set_ylabel("first-harmonic amplitude [m]")
    ax.legend(fontsize="small")
    ax.grid(True, which="both", alpha=0.3)
    _save(fig, path)
    return fig


_QUANTITY_LABELS = {"peak_amplitude": "peak amplitude [m]", "peak_omega": "peak frequency [rad/s]",
                    "damping_ratio": "equivalent damping ratio [-]",
                    "dissipated_at_peak": "energy dissipated per cycle at the peak [J]"}


def plot_study_curve(table, x: str, quantity: str = "peak_amplitude", ax=None, path=None):
    """A quantity of a study (:class:`~frictionjoint.results.StudyTable`) against one varied
    parameter, its minimum marked: for ``centrifugal_force`` and ``peak_amplitude`` the friction
    damper curve (the root load that minimises the peak). Points with some frequencies without a
    periodic orbit are drawn hollow (their peak may be missed); failed ones are marked on the
    axis.

    Parameters
    ----------
    table : StudyTable
    x : str
        The varied parameter.
    quantity : str
        A quantity column.
    ax : matplotlib Axes, optional
    path : str or os.PathLike, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _axes(ax, (7.0, 4.5))
    xv, yv, ok = np.asarray(table[x], float), np.asarray(table[quantity], float), table.ok
    order = np.argsort(xv)
    good = ok[order] & np.isfinite(yv[order])
    ax.plot(xv[order][good], yv[order][good], "o-", color="C0", ms=4, label=quantity)
    if good.any():
        k = order[good][int(np.argmin(yv[order][good]))]
        ax.plot([xv[k]], [yv[k]], "*", ms=14, color="C3", label=f"minimum {yv[k]:.4g} at {x} = {xv[k]:.4g}")
    part = table.partial & np.isfinite(yv)
    if part.any():
        ax.plot(xv[part], yv[part], "o", mfc="none", color="C1", label="some frequencies without an orbit")
    bad = ~ok & ~part
    if bad.any():
        ax.plot(xv[bad], np.full(int(bad.sum()), np.nanmin(yv) if good.any() else 0.0), "x", color="k",
                label="failed / no periodic orbit")
    if np.all(xv[np.isfinite(xv)] > 0) and np.nanmax(xv) / np.nanmin(xv) > 20:
        ax.set_xscale("log")
    ax.set_xlabel(x)
    ax.set_ylabel(_QUANTITY_LABELS.get(quantity, quantity))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize="small")
    _save(fig, path)
    return fig


def plot_study_contour(table, x: str, y: str, quantity: str = "peak_amplitude", ax=None, path=None):
    """A quantity of a study over two varied grid parameters (filled contour of the grid, points
    without a peak blank, the minimum marked).

    Parameters
    ----------
    table : StudyTable
    x, y : str
        The two grid parameters.
    quantity : str
    ax : matplotlib Axes, optional
    path : str or os.PathLike, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig, ax = _axes(ax, (7.0, 5.0))
    xv, yv = np.asarray(table[x], float), np.asarray(table[y], float)
    zv = np.where(table.ok, np.asarray(table[quantity], float), np.nan)
    xs, ys = np.unique(xv), np.unique(yv)
    grid = np.full((ys.size, xs.size), np.nan)
    grid[np.searchsorted(ys, yv), np.searchsorted(xs, xv)] = zv
    cs = ax.contourf(xs, ys, grid, levels=20, cmap="viridis")
    fig.colorbar(cs, ax=ax, label=_QUANTITY_LABELS.get(quantity, quantity))
    ax.plot(xv, yv, ".", color="w", ms=2)
    if np.isfinite(zv).any():
        k = int(np.nanargmin(zv))
        ax.plot([xv[k]], [yv[k]], "*", ms=14, color="C3", label=f"minimum {zv[k]:.4g}")
        ax.legend(fontsize="small")
    ax.set_xlabel(x)
    ax.set_ylabel(y)
    _save(fig, path)
    return fig


def plot_study_monte_carlo(table, quantity: str = "peak_amplitude", path=None):
    """A Monte Carlo study: the quantity against each random parameter (scatter) and its histogram
    with the 5th, 50th and 95th percentiles marked.

    Parameters
    ----------
    table : StudyTable
    quantity : str
    path : str or os.PathLike, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    names = list(table.random) or list(table.varied)
    fig = new_figure((4.0 * (len(names) + 1), 4.0))
    fig.set_layout_engine("constrained")
    axes = fig.subplots(1, len(names) + 1, squeeze=False)[0]
    zv = np.asarray(table[quantity], float)
    ok = table.ok & np.isfinite(zv)
    for ax, name in zip(axes, names):
        ax.plot(np.asarray(table[name], float)[ok], zv[ok], ".", ms=4, color="C0")
        ax.set_xlabel(name)
        ax.set_ylabel(_QUANTITY_LABELS.get(quantity, quantity))
        ax.grid(True, alpha=0.3)
    ax = axes[-1]
    ax.hist(zv[ok], bins=max(5, int(np.sqrt(ok.sum()))), color="C0", alpha=0.7)
    # the percentiles named in a legend, not beside their lines: close percentiles' labels overlapped
    styles = {5.0: ":", 50.0: "-", 95.0: "--"}
    for q, v in table.percentiles(quantity).items():
        ax.axvline(v, color="C3", ls=styles.get(float(q), "-."), lw=1.2, label=f"P{q:g} = {v:.4g}")
    ax.legend(fontsize="small", framealpha=0.9)
    ax.set_xlabel(_QUANTITY_LABELS.get(quantity, quantity))
    ax.set_ylabel("points")
    ax.set_title(f"{int(ok.sum())} of {len(table)} points", fontsize="small")
    _save(fig, path)
    return fig


# --------------------------------------------------------------------------- contact patches


#: words and colours of a slider's status, by SlipPattern's codes (frictionjoint.results.slip_pattern:
#: 0 stuck, 1 slipping, 2 open; not imported here: the results import this module)
_SLIP_NAMES = ("stuck", "slipping", "open")
_SLIP_COLOURS = ("#c6dbef", "#d62728", "#252525")


def plot_slip_pattern(pattern, sliders=None, positions=None, static_load=None, ax=None, path=None,
                      position_label: str = "position along the patch", load_label: str = "static normal load [N]",
                      title: str | None = None):
    """The stick/slip pattern of a contact patch over one cycle: its nodes (along the patch) against
    the time in the cycle, each piece coloured stuck, slipping or open, exact between the events;
    beside it, the nodes' static normal load.

    Parameters
    ----------
    pattern : SlipPattern
        Result of :func:`frictionjoint.solvers.marcher.slip_pattern.slip_pattern`.
    sliders : (n,) sequence of int, optional
        The rows to draw (e.g. one flank's nodes), in the order of ``positions``; default all.
    positions : (n,) array_like, optional
        Each row's position along the patch (the y axis; e.g. its chord coordinate [mm]); default
        its index.
    static_load : (n,) array_like, optional
        A static quantity per node drawn beside the pattern (e.g. the normal load per unit length).
    ax : matplotlib Axes or (2,) sequence of Axes, optional
        The pattern's axes, or the pattern's and the static load's; a new figure if omitted.
    path : str or os.PathLike, optional
        Write the figure there.
    position_label, load_label : str
        Labels of the y axis and of the static load's axis.
    title : str, optional
        The pattern's title (default: the frequency).

    Returns
    -------
    matplotlib.axes.Axes
        The pattern's axes.
    """
    from matplotlib.colors import BoundaryNorm, ListedColormap
    from matplotlib.patches import Patch

    rows = np.arange(pattern.n_sliders) if sliders is None else np.asarray(sliders, dtype=int)
    y = np.arange(rows.size, dtype=float) if positions is None else np.asarray(positions, dtype=float)
    if y.shape != rows.shape:
        raise ValueError(f"positions has {y.size} entries for {rows.size} sliders")
    if ax is None:
        fig = new_figure((9.0, 3.2) if static_load is not None else (7.5, 3.2))
        axes = fig.subplots(1, 2, sharey=True, width_ratios=(4, 1)) if static_load is not None else [fig.subplots()]
    else:
        axes = list(ax) if isinstance(ax, (list, tuple, np.ndarray)) else [ax]
        fig = axes[0].figure
    ax_map = axes[0]
    order = np.argsort(y)
    cmap = ListedColormap(_SLIP_COLOURS)
    ax_map.pcolormesh(pattern.times / pattern.period, _edges(y[order]), pattern.pattern[rows[order]], cmap=cmap,
                      norm=BoundaryNorm([-0.5, 0.5, 1.5, 2.5], cmap.N), shading="flat")
    ax_map.set_xlim(0.0, 1.0)
    ax_map.set_xlabel("time in the cycle t / T (force cos(omega t))")
    ax_map.set_ylabel(position_label)
    ax_map.set_title(title if title is not None else f"omega = {pattern.omega:g} rad/s", fontsize="medium",
                     loc="left")
    shown = sorted(set(np.unique(pattern.pattern[rows]).tolist()) | {0, 1})
    ax_map.legend(handles=[Patch(facecolor=_SLIP_COLOURS[s], edgecolor="0.3", lw=0.5, label=_SLIP_NAMES[s])
                           for s in shown], loc="lower right", bbox_to_anchor=(1.0, 1.0), ncol=len(shown),
                  fontsize="small", frameon=False, borderaxespad=0.2, handlelength=1.2)
    if static_load is not None and len(axes) > 1:
        load = np.asarray(static_load, dtype=float)
        axes[1].plot(load[order], y[order], "o-", color="C0", ms=4)
        axes[1].set_xlabel(load_label)
        axes[1].grid(True, alpha=0.3)
    _save(fig, path)
    return ax_map


def _clip(polygon: np.ndarray, row: np.ndarray, bound: float) -> np.ndarray:
    """The part of a convex polygon ``(k, 2)`` with ``row @ p <= bound`` (Sutherland-Hodgman)."""
    out = []
    for a, b in zip(polygon, np.roll(polygon, -1, axis=0)):
        fa, fb = row @ a - bound, row @ b - bound
        if fa <= 0:
            out.append(a)
        if fa * fb < 0:
            out.append(a + (b - a) * fa / (fa - fb))
    return np.array(out).reshape(-1, 2)


def safe_region(rows: np.ndarray, bound: np.ndarray, box: np.ndarray) -> np.ndarray:
    """The polygon ``(k, 2)`` of the points of ``box`` (``(4, 2)``, a convex quadrilateral) with
    ``rows @ p <= bound``: the safe shakedown region of a two-node Ahn diagram within the box (empty
    ``(0, 2)`` if none).

    Parameters
    ----------
    rows : (m, 2) ndarray
    bound : (m,) ndarray
    box : (4, 2) ndarray

    Returns
    -------
    (k, 2) ndarray
    """
    poly = np.asarray(box, dtype=float)
    for row, b in zip(rows, bound):
        if poly.size == 0:
            break
        poly = _clip(poly, np.asarray(row, dtype=float), float(b))
    return poly


def plot_ahn_diagram(rows, bound, trajectories=(), path=None, ax=None):
    """Ahn's diagram of a two-node frictional system (seed Sec. 3.1, Fig. 3-5): the four extreme
    friction constraints as lines in the slip plane ``(w1, w2)``, the safe shakedown region they
    leave (shaded) and each trajectory of the slips, cycle by cycle.

    Parameters
    ----------
    rows, bound : ndarray
        :func:`frictionjoint.shakedown.extreme_constraints` of the system and load: ``(4, 2)``, ``(4,)``.
    trajectories : sequence of (k, 2) array_like
        Slips [m] to draw as lines, each from its first point (e.g. the ``slip_at_samples`` of
        consecutive :class:`~frictionjoint.results.CycleResult` stacked).
    path : str or os.PathLike, optional
        Write the figure there.
    ax : matplotlib Axes, optional
        Draw into these axes.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.patches import Polygon

    rows, bound = np.asarray(rows, dtype=float), np.asarray(bound, dtype=float)
    if rows.shape != (4, 2) or bound.shape != (4,):
        raise ValueError(f"an Ahn diagram has two nodes: rows (4, 2) and bound (4,), got {rows.shape}, {bound.shape}")
    fig, ax = _axes(ax, (6.5, 6.0))
    paths = [np.asarray(t, dtype=float).reshape(-1, 2) for t in trajectories]
    corners = []
    for i in range(4):  # the pairwise intersections span the picture
        for j in range(i + 1, 4):
            a = rows[[i, j]]
            if abs(np.linalg.det(a)) > 1e-12 * np.abs(a).max() ** 2:
                corners.append(np.linalg.solve(a, bound[[i, j]]))
    # framed on the safe region (within the constraints' intersections) and the trajectories
    span = np.vstack(corners) if corners else np.zeros((1, 2))
    far = np.abs(span).max() * 10 + 1.0
    region = safe_region(rows, bound, np.array([[-far, -far], [far, -far], [far, far], [-far, far]]))
    points = np.vstack([region] + paths) if len(region) or paths else span
    lo, hi = points.min(axis=0), points.max(axis=0)
    pad = 0.6 * np.maximum(hi - lo, 1e-9 * (np.abs(points).max() + 1e-300))
    lo, hi = lo - pad, hi + pad
    box = np.array([[lo[0], lo[1]], [hi[0], lo[1]], [hi[0], hi[1]], [lo[0], hi[1]]])
    region = safe_region(rows, bound, box)
    if len(region) >= 3:
        ax.add_patch(Polygon(region, closed=True, facecolor="0.85", edgecolor="none", label="safe shakedown region"))
    names = ("node 1 at +f N", "node 2 at +f N", "node 1 at -f N", "node 2 at -f N")
    x = np.linspace(lo[0], hi[0], 2)
    for (r1, r2), b, name, style in zip(rows, bound, names, ("-", "-", "--", "--")):
        if abs(r2) > 1e-12 * max(abs(r1), abs(r2)):
            ax.plot(x, (b - r1 * x) / r2, style, lw=1.2, label=name)
        else:
            ax.axvline(b / r1, ls=style, lw=1.2, label=name)
    for k, t in enumerate(paths):
        ax.plot(t[:, 0], t[:, 1], ".-", ms=2, lw=0.8, label=f"slips from ({t[0, 0]:.3g}, {t[0, 1]:.3g})")
        ax.plot(t[-1, 0], t[-1, 1], "ko", ms=4)
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_xlabel("slip w1 [m]")
    ax.set_ylabel("slip w2 [m]")
    ax.set_title("Ahn's diagram: extreme friction constraints and slips cycle by cycle")
    ax.legend(fontsize=7, loc="best")
    _save(fig, path)
    return fig
