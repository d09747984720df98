"""Solid-blade root study: a 3D blade on a dovetail whose flanks are contact patches, its forced
response around the first flapwise resonance and the stick/slip pattern over each flank.

The blade of ``models/ti64_solid_blade.toml``: Ti-6Al-4V, 150 x 30 x 3 mm, twisted 20 degrees,
27-node hexahedra (30 x 4 x 1), spinning at 1000 rad/s. The root face's two long edges sit on the
slot's flanks (30 degrees), 9 nodes each: every node a Jenkins slider along the flank in series
with its share of the flank's tangential stiffness and a normal spring, its static normal and
friction load from the spun-up contact solution of the blade under its centrifugal body forces
(19.4 kN). The blade is reduced by Craig-Bampton (sparse) to the 36 flank DOFs, 5 modes and the
excitation's residual vector: 42 DOFs. 50 N acts flapwise at the centre of the tip face.

The script

1. prints the static contact state (each node's normal and friction load; the run-up slips),
2. computes the tip's first harmonic at POINTS frequencies around the first flapwise resonance,
   each an exact periodic steady state (event-driven march and shooting, every node's events
   located on the closed-form pieces), with the root's two linear limits (every node stuck,
   every node slipping freely),
3. takes the stick/slip pattern of the flanks over one cycle at the first frequency where the
   flanks slip and at the peak (:func:`frictionjoint.solvers.marcher.slip_pattern.slip_pattern`:
   each node's status between its events), with the normal loads frozen at their static values
   and, at the peak, following the motion (``normal_load_variation``),
4. writes two figures: ``PREFIX_response.png`` (the forced response and its limits) and
   ``PREFIX_slip.png`` (the patterns: nodes along the chord against the time in the cycle, stuck,
   slipping or open, with the tip's motion over the same cycle and the nodes' static normal load
   per unit length of chord).

Usage::

    python examples/solid_blade_root.py [PREFIX] [POINTS]

PREFIX defaults to ``solid_blade_root``; POINTS (or the environment variable
``FRICTIONJOINT_EXAMPLE_POINTS``) is the number of frequencies from 1860 to 1980 rad/s, default 7.
"""
import os
import sys
import time

import numpy as np

from frictionjoint.linear_limits import limit_structures
from frictionjoint.plotting import new_figure, plot_slip_pattern
from frictionjoint.results.slip_pattern import OPEN, SLIPPING
from frictionjoint.solvers.marcher.slip_pattern import slip_pattern
from frictionjoint.structures import BladeAssembly, load_blade_model
from frictionjoint.structures.solid_root import flank_edges

BAND = (1800.0, 2000.0)  # [rad/s]: the free-slip (1819) and stuck (1976) limits' first flapwise mode
SWEPT = (1860.0, 1980.0)  # [rad/s]: the exact steady states, stuck below about 1900 rad/s
GRAZE = 1e-3  # slips shorter than this fraction of the cycle leave a node "stuck" in the regime's word


def sweep(asm, omegas):
    """Exact steady states at ``omegas`` in order, each started from the previous orbit (as
    frictionjoint's sweeps do), and the tip's first harmonic of each."""
    states, tip, z = [], [], None
    n = asm.structure.n_dof
    for w in omegas:
        guess = {} if z is None else dict(x0=z[:n], v0=z[n:2 * n], w0=z[2 * n:])
        r = asm.steady_state(float(w), **guess)
        if not r.converged and guess:
            r = asm.steady_state(float(w))  # from rest, the other guess
        z = r.initial_state if r.converged else None
        states.append(r)
        tip.append(asm.first_harmonic(r, asm.tip) if r.converged else np.nan)
    return states, np.array(tip)


def regime(pattern, flanks):
    """``'stuck'``, ``'partial slip'`` (some nodes slip, each flank always holds some stuck) or
    ``'gross slip'`` (for part of the cycle every closed node of a flank slips). Slips shorter than
    GRAZE of the cycle (a node grazing its limit on a stuck orbit) do not count."""
    if not np.any(pattern.fraction(SLIPPING) > GRAZE):
        return "stuck"
    slipping, closed = pattern.pattern == SLIPPING, pattern.pattern != OPEN
    for rows in flanks:
        whole = np.all(slipping[rows] | ~closed[rows], axis=0) & np.any(closed[rows], axis=0)
        if whole @ np.diff(pattern.times) > GRAZE * pattern.period:
            return "gross slip"
    return "partial slip"


def main(argv):
    prefix = argv[1] if len(argv) > 1 else "solid_blade_root"
    n = int(argv[2]) if len(argv) > 2 else int(os.environ.get("FRICTIONJOINT_EXAMPLE_POINTS", "7"))
    start = time.perf_counter()
    model = load_blade_model("ti64_solid_blade")
    asm = BladeAssembly.from_model(model, n_modes=5)
    root = asm.joints[0]
    blade = model.blade()  # for the nodes' coordinates
    chord = [1e3 * blade.nodes[edge, 1] for edge in flank_edges(blade)]  # [mm], right and left flank
    flanks = [np.flatnonzero(root.flank == k) for k in (0, 1)]
    print(f"{model.name}: {blade.n_dof} DOFs reduced to {asm.structure.n_dof} (Craig-Bampton, 5 modes), {root!r}; "
          f"tip force {asm.loads[asm.tip]:g} N on {asm.tip}")

    st = root.static_state(asm.structure)
    weights = root.normal_stiffness / np.bincount(root.flank, root.normal_stiffness)[root.flank]
    line_load = st.normal_force / (weights * blade.width)  # [N/m]: N0_i over the node's share of the chord
    print(f"static contact state ({st.regime} during run-up): flank normal loads {st.flank_normal_force.round(1)} N, "
          f"friction {st.flank_friction_force.round(1)} N")
    print(f"{'node':>4} {'chord [mm]':>10} {'N0 [N]':>9} {'T0 [N]':>8} {'N0/(w b) [N/mm]':>16}  (right flank)")
    for i, k in enumerate(flanks[0]):
        print(f"{i:4d} {chord[0][i]:10.3f} {st.normal_force[k]:9.2f} {st.friction_force[k]:8.2f} "
              f"{1e-3 * line_load[k]:16.2f}")

    omegas = np.linspace(*SWEPT, n)
    states, tip = sweep(asm, omegas)
    patterns = [slip_pattern(r, asm.system(r.omega)) if r.converged else None for r in states]
    regimes = [regime(p, flanks) if p is not None else "no orbit" for p in patterns]
    fine = np.linspace(*BAND, 801)
    tip_row = asm.structure.transformation[list(asm.structure.full_dof_names).index(asm.tip)]  # x_tip = row . x_r
    limit_structure = limit_structures(asm.system(fine[0]))  # every node stuck; every node slipping freely
    limits, lim_at = ({name: s.harmonic_response(ws, asm.loads[asm.tip] * tip_row) @ tip_row
                       for name, s in limit_structure.items()} for ws in (fine, omegas))
    print(f"\n{'omega [rad/s]':>13} {'tip [mm]':>9} {'stuck limit':>11} {'free slip':>10}  regime (frozen N0)")
    for w, x, a, b, reg in zip(omegas, tip, lim_at["stuck"], lim_at["slipping"], regimes):
        print(f"{w:13.1f} {1e3 * abs(x):9.4f} {1e3 * abs(a):11.4f} {1e3 * abs(b):10.4f}  {reg}")
    for name, v in limits.items():
        k = int(np.argmax(np.abs(v)))
        print(f"linear limit '{name}': peak {1e3 * abs(v[k]):.4g} mm at {fine[k]:.5g} rad/s")
    k_peak = int(np.nanargmax(np.abs(tip)))
    slipping = [k for k, reg in enumerate(regimes) if reg not in ("stuck", "no orbit")]
    k_onset = slipping[0] if slipping else k_peak
    print(f"peak of the sweep: {1e3 * abs(tip[k_peak]):.4g} mm at {omegas[k_peak]:g} rad/s ({regimes[k_peak]})")

    # up to the peak again with each node's slip limit following its normal load (lift-off
    # allowed), from the last stuck frequency (a linear orbit) as the sweep climbs
    varying = asm.with_root(normal_load_variation=True)
    first = max([k for k in range(k_peak) if regimes[k] == "stuck"], default=k_peak)
    var_states, var_tip = sweep(varying, omegas[first:k_peak + 1])
    m = asm.structure.n_dof
    r_var, x_var = var_states[-1], var_tip[-1]
    p_var = slip_pattern(r_var, varying.system(r_var.omega)) if r_var.converged else None
    if r_var.converged:  # each node's normal load over the cycle, from the orbit marched once more
        system, z, period = varying.system(r_var.omega), r_var.initial_state, 2 * np.pi / r_var.omega
        x = varying.simulate(r_var.omega, period, x0=z[:m], v0=z[m:2 * m], w0=z[2 * m:],
                             t_eval=np.linspace(0.0, period, 401), record=("x",)).x
        ratio = system.normal_loads(x) / system.contact_preload[:, None]
        print(f"normal loads varying, {r_var.omega:g} rad/s: each node's between {ratio.min(axis=1).min():.2f}-"
              f"{ratio.min(axis=1).max():.2f} and {ratio.max(axis=1).min():.2f}-{ratio.max(axis=1).max():.2f} "
              "times its static load over the cycle")
    print(f"varying normal loads at {omegas[k_peak]:g} rad/s: {r_var.message}; tip {1e3 * abs(x_var):.4g} mm, "
          f"{regime(p_var, flanks) if p_var is not None else 'no orbit'}")

    cases = [(f"frozen N0, {omegas[k]:g} rad/s ({regimes[k]}{', peak' if k == k_peak else ''})", patterns[k], tip[k])
             for k in sorted({k_onset, k_peak})]
    if p_var is not None:
        cases.append((f"varying N, {omegas[k_peak]:g} rad/s", p_var, x_var))
    for label, p, _ in cases:
        frac = p.fraction(SLIPPING)
        print(f"{label}: {p.message}; slipping fraction of the cycle per node, right flank "
              f"{np.array2string(frac[flanks[0]], precision=3)}, left {np.array2string(frac[flanks[1]], precision=3)}"
              + (f"; open {p.fraction(OPEN).max():.3f} at most" if (p.pattern == OPEN).any() else ""))

    draw_response(f"{prefix}_response.png", omegas, tip, regimes, fine, limits, omegas[first:k_peak + 1], var_tip,
                  model.name)
    draw_patterns(f"{prefix}_slip.png", cases, flanks, chord, line_load, asm.loads[asm.tip])
    print(f"wrote {prefix}_response.png and {prefix}_slip.png ({time.perf_counter() - start:.0f} s, "
          f"{time.process_time():.0f} s of CPU)")
    return 0


def draw_response(path, omegas, tip, regimes, fine, limits, var_omegas, var_tip, name):
    fig = new_figure((8.0, 5.0))
    ax = fig.subplots()
    for lim, style, label in (("stuck", "--", "linear limit: every node stuck"),
                              ("slipping", ":", "linear limit: every node slipping")):
        ax.plot(fine, 1e3 * np.abs(limits[lim]), style, color="0.35", label=label)
    ax.plot(var_omegas, 1e3 * np.abs(var_tip), "s-", ms=9, mfc="none", color="C2", lw=1.0,
            label="exact steady state, normal loads varying")
    ax.plot(omegas, 1e3 * np.abs(tip), "-", color="C0", lw=1.0)
    for reg, colour in (("stuck", "C0"), ("partial slip", "C1"), ("gross slip", "C3")):
        sel = np.array([r == reg for r in regimes])
        if sel.any():
            ax.plot(omegas[sel], 1e3 * np.abs(tip[sel]), "o", color=colour, label=f"exact steady state: {reg}")
    ax.set_ylim(0.0, 1e3 * 2.0 * np.nanmax(np.abs(tip)))
    ax.set_xlabel("omega [rad/s]")
    ax.set_ylabel("tip first harmonic, flapwise [mm]")
    ax.set_title(f"{name}: 50 N at the tip's centre, root on 2 x 9 contact nodes", fontsize="medium")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize="small", loc="upper left")
    fig.savefig(path, dpi=110)


def draw_patterns(path, cases, flanks, chord, line_load, force_amplitude):
    fig = new_figure((4.2 * len(cases) + 2.2, 8.0))
    grid = fig.add_gridspec(3, len(cases) + 1, height_ratios=(1.0, 2.0, 2.0), width_ratios=[4] * len(cases) + [1.3])
    for c, (label, p, x) in enumerate(cases):
        top = fig.add_subplot(grid[0, c])
        phase = np.linspace(0.0, 1.0, 201)
        top.plot(phase, 1e3 * np.real(x * np.exp(2j * np.pi * phase)), color="C0", label="tip (first harmonic)")
        top.set_xlim(0.0, 1.0)
        top.set_ylabel("tip [mm]")
        top.set_title(label, fontsize="medium")
        twin = top.twinx()
        twin.plot(phase, force_amplitude * np.cos(2 * np.pi * phase), ":", color="0.4")
        twin.set_ylabel("tip force [N]", fontsize="small")
        top.grid(True, alpha=0.3)
        for row, (side, rows, y) in enumerate(zip(("right", "left"), flanks, chord), start=1):
            ax = fig.add_subplot(grid[row, c], sharex=top)
            axes = ax
            if c == len(cases) - 1:
                axes = (ax, fig.add_subplot(grid[row, -1], sharey=ax))
            plot_slip_pattern(p, sliders=rows, positions=y, ax=axes, title=f"{side} flank",
                              static_load=1e-3 * line_load[rows] if c == len(cases) - 1 else None,
                              position_label="chord y [mm] (leading edge +15)", load_label="static N0 [N/mm]")
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    sys.exit(main(sys.argv))
