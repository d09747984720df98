"""Steady states of the Craig-Bampton blade on its dovetail root: time per frequency point and error.

The blade of ``models/ti64_compressor_blade.toml`` (Craig-Bampton with 3 or 5 fixed-interface modes
and the tip's residual vector) on its rocking dovetail root, 1 N at the tip, swept over 200
frequencies from 1600 to 2200 rad/s (both linear limits' first mode) at three root loads: the damper
optimum (46 N, the flanks slip every cycle), a tenth of the blade's centrifugal load (1.9 kN, slip
near the peak only) and the full load (19.4 kN, stuck: orbits in closed form).

Error: the tip's first-harmonic amplitude against a converged reference of the same root model, the
blade with 15 modes and the shooting tolerance 100 times tighter (``tol=1e-14``), at every tenth
point (20 points); that is the error of the reduction plus the solver. The steady states are the
sweep's (first harmonics, no displacement peaks located: ``peaks=False``). Baseline, in the same
process: the same steady states with the NumPy event search and piece kernels (the compiled kernels
switched off), at every tenth point. Usage::

    python benchmarks/blade_sweep.py [--quick]
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

if __package__ in (None, ""):  # run as a script: the repository is not on the path, benchmarks/ is
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.harness import script_header, write_results  # noqa: E402
from frictionjoint.solvers.marcher import piece_kernels, search  # noqa: E402
from frictionjoint.structures import BladeAssembly, load_blade_model  # noqa: E402

LOADS = (("optimum", 46.09), ("tenth", None), ("full", None))


def assemblies(n_modes: int) -> dict:
    asm = BladeAssembly.from_model(load_blade_model("ti64_compressor_blade"), n_modes=n_modes)
    fc = asm.joints[0].centrifugal_force
    values = {"optimum": 46.09, "tenth": 0.1 * fc, "full": fc}
    return {name: asm.with_root(centrifugal_force=values[name]) for name, _ in LOADS}


def tip_amplitudes(asm, omegas, **kwargs) -> np.ndarray:
    out = []
    for w in omegas:
        r = asm.steady_state(float(w), peaks=False, **kwargs)  # the first harmonics, as the sweep
        out.append(abs(asm.first_harmonic(r, asm.tip)) if r.converged else np.nan)
    return np.array(out)


def numpy_kernels(on: bool) -> None:
    search.ENABLED = piece_kernels.ENABLED = not on


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="40 points, no 3-mode blade")
    args = parser.parse_args(argv)
    n_points = 40 if args.quick else 200
    omegas = np.linspace(1600.0, 2200.0, n_points)
    check = omegas[::10]
    reference = assemblies(15)
    lines = [script_header("blade_sweep.py", args.quick),
             f"# {n_points}-point sweep 1600-2200 rad/s, 1 N at the tip; error of the tip amplitude against "
             f"15 modes and tol 1e-14 at {check.size} points; baseline: NumPy kernels at the same points",
             f"{'modes':>5} {'load':>8} {'ms/pt mean':>10} {'median':>7} {'max':>7} {'conv':>8} {'slip pts':>8} "
             f"{'max rel err':>11} {'NumPy/compiled':>14}"]
    print("\n".join(lines), flush=True)
    for n_modes in ((5,) if args.quick else (3, 5)):
        for name, asm in assemblies(n_modes).items():
            asm.steady_state(1900.0)  # load the compiled kernels from the cache
            times = []
            sw = None
            t_all = time.perf_counter()
            sw = asm.frequency_response(omegas, progress=True)
            t_all = time.perf_counter() - t_all
            # per-point times: a second pass point by point (continuation as in the sweep)
            z = None
            from frictionjoint.solvers.marcher.steady import periodic_response
            for w in omegas:
                system = asm.system(float(w))
                n = system.n_dof
                t0 = time.perf_counter()
                r = (periodic_response(system, peaks=False) if z is None else
                     periodic_response(system, z[:n], z[n:2 * n], z[2 * n:], peaks=False))
                times.append(time.perf_counter() - t0)
                z = r.initial_state if r.converged else None
            times = np.array(times) * 1e3
            ref = tip_amplitudes(reference[name], check, tol=1e-14)
            got = sw.amplitude[::10]
            err = float(np.nanmax(np.abs(got - ref) / ref))
            t_c = time.perf_counter()
            tip_amplitudes(asm, check)
            t_c = time.perf_counter() - t_c
            numpy_kernels(True)
            try:
                t_n = time.perf_counter()
                tip_amplitudes(asm, check)
                t_n = time.perf_counter() - t_n
            finally:
                numpy_kernels(False)
            row = (f"{n_modes:5d} {name:>8} {1e3 * t_all / n_points:10.1f} {np.median(times):7.1f} "
                   f"{times.max():7.1f} {int(sw.converged.sum()):4d}/{n_points:<3d} "
                   f"{int((~sw.stuck & sw.converged).sum()):8d} {err:11.2e} {t_n / t_c:14.1f}")
            print(row, flush=True)
            lines.append(row)
    write_results("results_blade.txt", lines, args.quick)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
