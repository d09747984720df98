"""Blade root study: the friction-damper curve of a compressor blade on its dovetail root.

The blade of ``models/ti64_compressor_blade.toml`` (Ti-6Al-4V, 150 mm, Craig-Bampton with 5 modes and
the tip's residual vector) sits on a dovetail root that rocks on two flat flanks; 1 N at the tip
excites its first bending mode. The root's centrifugal load sets the flanks' normal load:

- high load: the flanks stick, the blade rings at the stuck-root frequency (2035 rad/s) with only its
  material and contact damping;
- low load: the flanks slip freely, the root rolls on them and the blade rings at the free-slip
  frequency (1707 rad/s);
- in between, friction at the flanks damps the resonance: the peak tip amplitude has a minimum,
  the damper optimum.

The script computes the damper curve (peak tip amplitude against the centrifugal load, and against
the friction coefficient at a tenth of the load), marks the optimum, and draws the tip's frequency
response at three loads with the root's two linear limits beside it. Every point is an exact
periodic steady state (event-driven marching and shooting; no time step). The damper curves are
design studies (frictionjoint.study): their points run on the machine's cores.

Usage::

    python examples/blade_root_study.py [PNG] [POINTS]

writes the figure to PNG (default ``blade_root_study.png``); POINTS (or the environment variable
``FRICTIONJOINT_EXAMPLE_POINTS``) sets the number of loads and friction coefficients (default 9).
"""
import os
import sys
import tempfile
from pathlib import Path

import numpy as np

from frictionjoint.plotting import new_figure
from frictionjoint.structures import BladeAssembly, load_blade_model
from frictionjoint.study import Study, Values, run_study

BAND = (1600.0, 2200.0)  # [rad/s]: both linear limits' first bending mode


def damper_curve(asm, name, values, folder, fixed=None):
    """Peak tip amplitude for each value of a root parameter: a study (frictionjoint.study) on the
    machine's cores, each peak refined between 31 frequencies; prints the table."""
    study = Study(model=asm, omega=f"{BAND[0]:g}:{BAND[1]:g}:31",  # START:STOP:N [rad/s]
                  vary={name: Values(tuple(float(v) for v in values))}, fixed=dict(fixed or {}))
    table = run_study(study, Path(folder) / f"{name}.csv", restart=True)
    rows = np.c_[table[name], table["peak_amplitude"], table["peak_omega"]]
    print(f"\n{name:>22} {'peak tip [m]':>13} {'at omega [rad/s]':>17}")
    for v, amp, w in rows:
        print(f"{v:22.6g} {amp:13.5e} {w:17.6g}")
    k = int(np.nanargmin(rows[:, 1]))
    print(f"optimum: {name} = {rows[k, 0]:.6g}, peak tip amplitude {rows[k, 1]:.5e} m "
          f"({np.nanmax(rows[:, 1]) / rows[k, 1]:.1f}x below the worst; {table.message})")
    return rows, k


def main(argv):
    out = argv[1] if len(argv) > 1 else "blade_root_study.png"
    n = int(argv[2]) if len(argv) > 2 else int(os.environ.get("FRICTIONJOINT_EXAMPLE_POINTS", "9"))
    model = load_blade_model("ti64_compressor_blade")
    asm = BladeAssembly.from_model(model)
    root = asm.joints[0]
    fc0, mu0 = root.centrifugal_force, root.friction_coefficient
    print(f"{model.name}: {asm.structure.n_dof} DOFs (Craig-Bampton), root {root!r}")

    with tempfile.TemporaryDirectory() as folder:
        loads, k_load = damper_curve(asm, "centrifugal_force", fc0 * np.logspace(-3, 0, n), folder)
        mus, k_mu = damper_curve(asm, "friction_coefficient", mu0 * np.logspace(-2, 0, n), folder,
                                 fixed={"centrifugal_force": 0.1 * fc0})

    fig = new_figure((12.0, 9.0))
    ax_fc, ax_mu, ax_frf = fig.subplot_mosaic([["fc", "mu"], ["frf", "frf"]]).values()
    for ax, rows, k, label in ((ax_fc, loads, k_load, "centrifugal load Fc [N]"),
                               (ax_mu, mus, k_mu, f"friction coefficient (Fc = {0.1 * fc0:.4g} N)")):
        ax.loglog(rows[:, 0], rows[:, 1], "o-", color="C0")
        ax.loglog(rows[k, 0], rows[k, 1], "*", ms=16, color="C3", label=f"optimum {rows[k, 0]:.3g}")
        ax.set_xlabel(label)
        ax.set_ylabel("peak tip amplitude [m] (1 N at the tip)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    omegas = np.linspace(*BAND, 121)
    for fc, colour in ((fc0 * 1e-3, "C2"), (loads[k_load, 0], "C3"), (fc0, "C0")):
        fr = asm.with_root(centrifugal_force=float(fc)).frequency_response(omegas)
        ok = fr.converged
        ax_frf.semilogy(fr.omega[ok], fr.amplitude[ok], "-", color=colour, label=f"Fc = {fc:.4g} N")
        print(f"FRF at Fc = {fc:.4g} N: {fr.message}; peak {fr.peak()[1]:.5e} m at {fr.peak()[0]:.6g} rad/s")
    for name, style in (("stuck", "--"), ("slipping", ":")):
        ax_frf.semilogy(fr.omega, np.abs(fr.limits[name]), style, color="0.3", label=f"linear limit: {name}")
    ax_frf.set_xlabel("omega [rad/s]")
    ax_frf.set_ylabel("tip first-harmonic amplitude [m]")
    ax_frf.grid(True, which="both", alpha=0.3)
    ax_frf.legend(fontsize="small")
    fig.savefig(out, dpi=110)
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
