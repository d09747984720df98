"""Cost of the FMU layer: the same stepped-sine sweep through CoulombOscillator.fmu (fmpy) and
directly on the library model, in the same process, with the error against Den Hartog.

Three ways to sweep the Coulomb oscillator (m = k = P0 = 1, F/P0 = 0.5, r = 0.6 ... 2.2 up,
100 points):

- ``sweep(fmu)``: frictionjoint.sweep.sweep through the FMU (fmpy master): the FMU starts on
  the periodic orbit (parameter ``start_on_orbit``: the kernel's shooting with its exact
  Jacobian, the previous point's orbit as the guess), one communication step of a period checks
  it returns to its start and gives the exact Fourier integrals and peak;
- ``sweep('CoulombOscillator')``: the same algorithm on the library's stepping object
  (no FMU layer);
- ``oscillator_sweep``: the library's own sweep (``CoulombOscillator.steady_state`` per point):
  the baseline of the ratio (target <= 1.5x).

Errors against Den Hartog at the stop-free points: amplitude, first-harmonic phase of x, and of
the friction force (a square wave F sgn(v): phase = Den Hartog's peak phase - pi/2). Each method is
timed best-of-N, interleaved. Usage:

    python benchmarks/fmu_sweep.py [--repeat N] [--out DIR]
"""
from __future__ import annotations

import argparse
import math
import os
import platform
import tempfile
import time

import numpy as np

from frictionjoint.analytic import den_hartog
from frictionjoint.fmi.build import build_fmus
from frictionjoint.sweep import oscillator_sweep, sweep

PARAMS = dict(mass=1.0, stiffness=1.0, slip_force=0.5, force_amplitude=1.0)
OMEGAS = np.linspace(0.6, 2.2, 100)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="best of N runs (default 3)")
    ap.add_argument("--out", default=None, help="folder for the built FMU (default: a temporary one)")
    args = ap.parse_args(argv)
    out = args.out or tempfile.mkdtemp(prefix="fj-bench-")
    fmu = str(build_fmus(out, names=["CoulombOscillator"])[0])
    runs = {
        "sweep(fmu)": lambda: sweep(fmu, OMEGAS, PARAMS, outputs=("x", "friction_force")),
        "sweep('CoulombOscillator')": lambda: sweep("CoulombOscillator", OMEGAS, PARAMS,
                                                    outputs=("x", "friction_force")),
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
    base = best["oscillator_sweep"]
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
    direct = best["sweep('CoulombOscillator')"]
    print(f"FMU sweep: {best['sweep(fmu)'] / base:.2f}x oscillator_sweep (target <= 1.5x), "
          f"{best['sweep(fmu)'] / direct:.2f}x the same algorithm without the FMU "
          f"layer; largest amplitude difference FMU vs direct {same:.1e}")
    ph_x = ph_f = 0.0
    ff = fr_fmu.harmonics["friction_force"]
    for i, w in enumerate(OMEGAS):
        sol = den_hartog(w, PARAMS["slip_force"] / PARAMS["force_amplitude"])
        if not sol.applicable or fr_fmu.stops_per_cycle[i]:
            continue
        ph_x = max(ph_x, abs(_wrap(fr_fmu.phase[i] - sol.harmonic_phase)))
        ph_f = max(ph_f, abs(_wrap(ff["phase"][i] - (sol.peak_phase - math.pi / 2))))
    print(f"FMU first-harmonic phase error against Den Hartog (stop-free points): x {ph_x:.1e} rad, "
          f"friction force {ph_f:.1e} rad (target <= 1e-10)")


def _wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


if __name__ == "__main__":
    main()
