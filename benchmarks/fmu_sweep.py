"""Cost of the FMU layer: the same stepped-sine sweep through CoulombOscillator.fmu (fmpy) and
directly on the library model, in the same process, with the error against Den Hartog.

Three ways to sweep the Coulomb oscillator (m = k = P0 = 1, F/P0 = 0.5, r = 0.6 ... 2.2 up,
12 points):

- ``sweep(fmu)``: frictionjoint.sweep.sweep through the FMU (fmpy master, shooting with
  re-initialisation, FMU state save/restore for the exact peaks);
- ``sweep('CoulombOscillator')``: the same algorithm on the library's stepping object
  (no FMU layer) -- the baseline of the ratio the FMU issue asks for (target < 2x);
- ``oscillator_sweep``: the library's own steady-state solver (shooting on the closed-form
  period map), for reference.

Each is timed best-of-N, interleaved. Usage:

    python benchmarks/fmu_sweep.py [--repeat N] [--out DIR]
"""
from __future__ import annotations

import argparse
import os
import platform
import tempfile
import time

import numpy as np

from frictionjoint.fmi.build import build_fmus
from frictionjoint.sweep import oscillator_sweep, sweep

PARAMS = dict(mass=1.0, stiffness=1.0, slip_force=0.5, force_amplitude=1.0)
OMEGAS = np.linspace(0.6, 2.2, 12)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="best of N runs (default 3)")
    ap.add_argument("--out", default=None, help="folder for the built FMU (default: a temporary one)")
    args = ap.parse_args(argv)
    out = args.out or tempfile.mkdtemp(prefix="fj-bench-")
    fmu = str(build_fmus(out, names=["CoulombOscillator"])[0])
    runs = {
        "sweep(fmu)": lambda: sweep(fmu, OMEGAS, PARAMS),
        "sweep('CoulombOscillator')": lambda: sweep("CoulombOscillator", OMEGAS, PARAMS),
        "oscillator_sweep": lambda: oscillator_sweep(PARAMS["mass"], PARAMS["stiffness"], PARAMS["slip_force"],
                                                     PARAMS["force_amplitude"], OMEGAS),
    }
    best = {name: float("inf") for name in runs}
    results = {}
    for _ in range(args.repeat):
        for name, fn in runs.items():
            t0 = time.perf_counter()
            results[name] = fn()
            best[name] = min(best[name], time.perf_counter() - t0)
    base = best["sweep('CoulombOscillator')"]
    fr_fmu, fr_lib = results["sweep(fmu)"], results["sweep('CoulombOscillator')"]
    print(f"# {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, best of {args.repeat}")
    print(f"# {len(OMEGAS)} points, F/P0 = 0.5, r = {OMEGAS[0]:g} ... {OMEGAS[-1]:g}")
    print(f"{'method':>28} {'time [s]':>9} {'per point [ms]':>15} {'max amp. error':>15} {'periods':>8} {'ratio':>7}")
    for name, fr in results.items():
        amp_err, _ = fr.max_error()
        print(f"{name:>28} {best[name]:9.3f} {1e3 * best[name] / len(OMEGAS):15.1f} {amp_err:15.2e} "
              f"{fr.periods.sum():8.0f} {best[name] / base:7.2f}")
    same = np.max(np.abs(fr_fmu.amplitude - fr_lib.amplitude) / fr_lib.amplitude)
    print(f"FMU layer: {best['sweep(fmu)'] / base:.2f}x the direct sweep (target < 2x); "
          f"largest amplitude difference FMU vs direct {same:.1e}")


if __name__ == "__main__":
    main()
