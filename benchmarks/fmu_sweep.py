"""Cost of the FMU layer: the same computation through an FMU (fmpy) and directly on the library,
in the same process, for the Coulomb oscillator, the blade on its dovetail, a linear structure and a
whole friction system.

Coulomb oscillator (m = k = P0 = 1, F/P0 = 0.5, r = 0.6 ... 2.2 up, 100 points), three ways:

- ``sweep(fmu)``: frictionjoint.sweep.sweep through CoulombOscillator.fmu (fmpy master): the FMU
  starts on the periodic orbit (parameter ``start_on_orbit``: the kernel's shooting with its exact
  Jacobian, the previous point's orbit as the guess), one communication step of a period checks
  it returns to its start and gives the exact Fourier integrals and peak;
- ``sweep('CoulombOscillator')``: the same algorithm on the library's stepping object
  (no FMU layer);
- ``oscillator_sweep``: the library's own sweep (``CoulombOscillator.steady_state`` per point):
  the baseline of the ratio (target <= 1.5x).

Errors against Den Hartog at the stop-free points: amplitude, first-harmonic phase of x, and of
the friction force (a square wave F sgn(v): phase = Den Hartog's peak phase - pi/2).

Blade (models/ti64_compressor_blade.toml on its dovetail, centrifugal force 46 N, 13 frequencies
1600 ... 2200 rad/s up): ``sweep(BladeDovetail.fmu)`` (per point a reset that starts on the orbit,
from the previous point's, and one period) against ``sweep('ti64_compressor_blade')``, the
library's sweep (the baseline, target <= 1.5x); the largest differences of their first harmonics
and of the harmonics' amplitudes.

Solid blade on contact-patch flanks (models/ti64_solid_blade.toml, 42 reduced DOFs, 9 nodes per
flank, 50 N at the tip, 6 frequencies 1850 ... 1960 rad/s up: stuck, then partial slip): its blade
FMU (``build_fmus(blades=["ti64_solid_blade"])``, ``Ti64SolidBlade.fmu``) swept as the beam's against
``sweep('ti64_solid_blade')`` (the baseline; it reduces the blade at each call, ~0.5 s, where the FMU
reuses its process's reduction), and, where the FMU ran the installed library, against the library's
sweep of the FMU's own reduced assembly: the differences of the first harmonics and amplitudes
(two reductions of one definition differ by ARPACK's start vector: see tests/test_blade_fmu.py).
Measured (2 shared cores at load 5-10, best of 2, two runs): FMU 17.0 and 17.6 s, library 16.7 and
17.3 s: 1.02x (2.9 s per point); against the definition's sweep 2.8e-9 and 9.3e-9 (harmonics), 1.3e-9
and 1.8e-9 (amplitudes); against the same reduced model 2.2e-11 and 4.8e-11, 6.0e-11 and 3.6e-11.

Linear structure (models/two_dof_chain.toml as ``LinearStructure`` FMU, ``--structure``): a run of
200 communication steps of T/50 with the joint inputs held at 0 (load, initialise, step, read
x1 and x2 at each step, free) against the library's
:class:`~frictionjoint.solvers.marcher.held.HeldPortStructure` stepped the same (the baseline);
the largest difference of the displacements.

Friction system (models/two_dof_chain_system.toml as one FMU, ``--system``: the chain with its two
Jenkins joints, 1 N cos(1.2 t) on DOF 2, from rest): 200 communication steps of T/50 (load,
initialise, step, read x1 and x2 at each step, free) against ``fj.simulate`` of the file's
FrictionSystem on the same times (the baseline) and against the FMU's own run object
(:class:`~frictionjoint.fmi.system_slave.SystemRun`) stepped the same without FMI; the largest
difference of the displacements.

Each FMU sweep or run includes loading and freeing its FMU (a sweep's one instance). Each method
is timed best-of-N, interleaved. Usage:

    python benchmarks/fmu_sweep.py [--repeat N] [--out DIR] [--solid-only]
"""
from __future__ import annotations

import argparse
import math
import os
import platform
import tempfile
import time
from pathlib import Path

import numpy as np

from frictionjoint.analytic import den_hartog
from frictionjoint.fmi.build import build_fmus
from frictionjoint.sweep import oscillator_sweep, sweep

PARAMS = dict(mass=1.0, stiffness=1.0, slip_force=0.5, force_amplitude=1.0)
OMEGAS = np.linspace(0.6, 2.2, 100)
BLADE = "ti64_compressor_blade"
BLADE_PARAMS = {"centrifugal_force": 46.0}
BLADE_OMEGAS = np.linspace(1600.0, 2200.0, 13)
STRUCTURE = Path(__file__).resolve().parents[1] / "models" / "two_dof_chain.toml"
STRUCTURE_STEPS = 200  # of T/50: four periods
SYSTEM = Path(__file__).resolve().parents[1] / "models" / "two_dof_chain_system.toml"
SOLID = "ti64_solid_blade"
SOLID_OMEGAS = np.linspace(1850.0, 1960.0, 6)


def _best(runs: dict, repeat: int) -> tuple[dict, dict]:
    """Best time [s] and last result of each callable in ``runs``, run ``repeat`` times interleaved."""
    best = {name: float("inf") for name in runs}
    results = {}
    for _ in range(repeat):
        for name, fn in runs.items():
            t0 = time.perf_counter()
            results[name] = fn()
            best[name] = min(best[name], time.perf_counter() - t0)
    return best, results


def _fmu_run(fmu: str, h: float, outputs: list) -> np.ndarray:
    """Load the FMU, initialise it, take STRUCTURE_STEPS steps of ``h`` reading ``outputs`` after
    each, free it: the (steps, outputs) values."""
    from frictionjoint.fmi.master import FMUInstance

    inst = FMUInstance(fmu)
    try:
        inst.initialize()
        xs = []
        for n in range(1, STRUCTURE_STEPS + 1):
            inst.step_to(n * h)
            xs.append(inst.get(outputs))
        return np.array(xs)
    finally:
        inst.close()


def structure_runs(fmu: str):
    """The structure's run through its FMU and through the library (see the module docstring):
    ``name -> callable`` returning the (steps, 2) displacements."""
    from frictionjoint.solvers.marcher.held import HeldPortStructure
    from frictionjoint.structure_file import load_structure_definition

    d = load_structure_definition(STRUCTURE)
    h = 2 * math.pi / d.omega / 50
    dofs = [d.structure.dof_index(n) for n in d.outputs]

    def in_library():
        body = HeldPortStructure(d.structure, d.ports, d.force_vector(), omega=d.omega, t0=0.0)
        zero = [0.0] * len(d.ports)
        xs = []
        for n in range(1, STRUCTURE_STEPS + 1):
            body.t = (n - 1) * h
            body.advance(n * h - body.t, zero, zero, zero)
            xs.append(body.x[dofs].copy())
        return np.array(xs)

    return {"run(fmu)": lambda: _fmu_run(fmu, h, [f"x_{name}" for name in d.outputs]),
            "HeldPortStructure": in_library}


def system_runs(fmu: str):
    """The friction system's run through its FMU, through its run object and through fj.simulate
    (see the module docstring): ``name -> callable`` returning the (steps, 2) displacements."""
    import frictionjoint as fj
    from frictionjoint.fmi.system_slave import SystemRun
    from frictionjoint.system_file import load_system_definition

    d = load_system_definition(SYSTEM)
    h = 2 * math.pi / d.omega / 50
    t = h * np.arange(1, STRUCTURE_STEPS + 1)
    rows = [d.structure.dof_index(n) for n in d.displacement]
    system = d.system()

    def run_object():
        run = SystemRun(d, {})
        xs = []
        for tk in t:
            run.advance(tk)
            xs.append(run.state.x[rows].copy())
        return np.array(xs)

    def simulate():
        return fj.simulate(system, t[-1], t_eval=t, record=("x",)).x[rows].T

    return {"run(fmu)": lambda: _fmu_run(fmu, h, [f"x_{name}" for name in d.displacement]),
            "SystemRun": run_object, "fj.simulate": simulate}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="best of N runs (default 3)")
    ap.add_argument("--out", default=None, help="folder for the built FMUs (default: a temporary one)")
    ap.add_argument("--solid-only", action="store_true", help="only the solid blade's rows")
    args = ap.parse_args(argv)
    out = args.out or tempfile.mkdtemp(prefix="fj-bench-")
    solid_fmu = str(build_fmus(out, blades=[SOLID])[0])
    if args.solid_only:
        solid_rows(solid_fmu, args.repeat)
        return
    from frictionjoint.structure_file import load_structure_definition

    built = {p.stem: str(p) for p in build_fmus(out, names=["CoulombOscillator", "BladeDovetail"])}
    structure_fmu = str(build_fmus(out, structures=[load_structure_definition(STRUCTURE)])[0])
    system_fmu = str(build_fmus(out, systems=[SYSTEM])[0])
    fmu = built["CoulombOscillator"]
    runs = {
        "sweep(fmu)": lambda: sweep(fmu, OMEGAS, PARAMS, outputs=("x", "friction_force")),
        "sweep('CoulombOscillator')": lambda: sweep("CoulombOscillator", OMEGAS, PARAMS,
                                                    outputs=("x", "friction_force")),
        "oscillator_sweep": lambda: oscillator_sweep(PARAMS["mass"], PARAMS["stiffness"], PARAMS["slip_force"],
                                                     PARAMS["force_amplitude"], OMEGAS),
    }
    best, results = _best(runs, args.repeat)
    base = best["oscillator_sweep"]
    fr_fmu, fr_lib = results["sweep(fmu)"], results["sweep('CoulombOscillator')"]
    print(f"# {platform.processor() or platform.machine()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, best of {args.repeat}")
    print(f"# Coulomb oscillator: {len(OMEGAS)} points, F/P0 = 0.5, r = {OMEGAS[0]:g} ... {OMEGAS[-1]:g}")
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

    blade_fmu = built["BladeDovetail"]
    runs = {"sweep(BladeDovetail.fmu)": lambda: sweep(blade_fmu, BLADE_OMEGAS, BLADE_PARAMS),
            f"sweep('{BLADE}')": lambda: sweep(BLADE, BLADE_OMEGAS, BLADE_PARAMS)}
    sweep(BLADE, BLADE_OMEGAS[:2], BLADE_PARAMS)  # the compiled kernels loaded before the timing
    best, results = _best(runs, args.repeat)
    a, b = results["sweep(BladeDovetail.fmu)"], results[f"sweep('{BLADE}')"]
    base = best[f"sweep('{BLADE}')"]
    print(f"# blade {BLADE}: {len(BLADE_OMEGAS)} points, centrifugal force {BLADE_PARAMS['centrifugal_force']:g} N, "
          f"omega = {BLADE_OMEGAS[0]:g} ... {BLADE_OMEGAS[-1]:g} rad/s")
    print(f"{'method':>28} {'time [s]':>9} {'per point [ms]':>15} {'converged':>10} {'ratio':>7}")
    for name, fr in results.items():
        print(f"{name:>28} {best[name]:9.3f} {1e3 * best[name] / len(BLADE_OMEGAS):15.1f} "
              f"{int(fr.converged.sum()):>10d} {best[name] / base:7.2f}")
    harm = np.max(np.abs(a.response - b.response) / np.abs(b.response))
    amp = np.max(np.abs(np.abs(a.response) - np.abs(b.response)) / np.abs(b.response))
    print(f"blade FMU sweep: {best['sweep(BladeDovetail.fmu)'] / base:.2f}x the library's sweep per point "
          f"(target <= 1.5x); largest difference FMU vs library: first harmonic {harm:.1e}, "
          f"its amplitude {amp:.1e} (target <= 1e-12), relative")

    best, results, diff = _stepped_runs(structure_runs(structure_fmu), "HeldPortStructure", args.repeat,
                                        f"# linear structure {STRUCTURE.name} (--structure): {STRUCTURE_STEPS} "
                                        "steps of T/50, joint inputs 0")
    print(f"structure FMU run: {best['run(fmu)'] / best['HeldPortStructure']:.2f}x the library's; largest "
          f"displacement difference {diff:.1e} of the largest displacement")
    best, results, diff = _stepped_runs(system_runs(system_fmu), "fj.simulate", args.repeat,
                                        f"# friction system {SYSTEM.name} (--system): {STRUCTURE_STEPS} steps of "
                                        "T/50 from rest")
    print(f"system FMU run: {best['run(fmu)'] / best['fj.simulate']:.2f}x fj.simulate on the same times, "
          f"{best['run(fmu)'] / best['SystemRun']:.2f}x its run object stepped the same; largest displacement "
          f"difference {diff:.1e} of the largest displacement")
    solid_rows(solid_fmu, args.repeat)


def solid_rows(fmu: str, repeat: int) -> None:
    """The solid blade's FMU sweep against the library's (module docstring): its table and line."""
    from frictionjoint.structures import blade_run

    runs = {f"sweep({Path(fmu).name})": lambda: sweep(fmu, SOLID_OMEGAS),
            f"sweep('{SOLID}')": lambda: sweep(SOLID, SOLID_OMEGAS)}
    sweep(SOLID, SOLID_OMEGAS[:1])  # the compiled kernels loaded before the timing
    blade_run._REDUCED.clear()
    best, results = _best(runs, repeat)
    (fmu_name, a), (lib_name, b) = results.items()
    base = best[lib_name]
    print(f"# solid blade {SOLID}: {len(SOLID_OMEGAS)} points, omega = {SOLID_OMEGAS[0]:g} ... "
          f"{SOLID_OMEGAS[-1]:g} rad/s")
    print(f"{'method':>28} {'time [s]':>9} {'per point [ms]':>15} {'converged':>10} {'ratio':>7}")
    for name, fr in results.items():
        print(f"{name:>28} {best[name]:9.3f} {1e3 * best[name] / len(SOLID_OMEGAS):15.1f} "
              f"{int(fr.converged.sum()):>10d} {best[name] / base:7.2f}")
    line = (f"solid blade FMU sweep: {best[fmu_name] / base:.2f}x the library's sweep per point; largest difference "
            f"FMU vs library: first harmonic {_rel(a.response, b.response):.1e}, its amplitude "
            f"{_rel(np.abs(a.response), np.abs(b.response)):.1e}")
    if blade_run._REDUCED:  # the FMU ran the installed library: its reduction is the library's to sweep
        c = sweep(next(iter(blade_run._REDUCED.values())), SOLID_OMEGAS)
        line += (f"; vs the library on the FMU's reduced model {_rel(a.response, c.response):.1e} and "
                 f"{_rel(np.abs(a.response), np.abs(c.response)):.1e}")
    print(line + ", relative")


def _rel(a, b) -> float:
    return float(np.max(np.abs(a - b) / np.abs(b)))


def _stepped_runs(runs: dict, baseline: str, repeat: int, title: str):
    """Time ``runs`` (best of ``repeat``), print their table under ``title``: (best, results, the
    largest difference of the FMU's run from the baseline's, relative to its largest value)."""
    best, results = _best(runs, repeat)
    base = best[baseline]
    xs = results[baseline]
    diff = np.max(np.abs(results["run(fmu)"] - xs)) / np.max(np.abs(xs))
    print(title)
    print(f"{'method':>28} {'time [s]':>9} {'per step [ms]':>15} {'ratio':>7}")
    for name in runs:
        print(f"{name:>28} {best[name]:9.3f} {1e3 * best[name] / STRUCTURE_STEPS:15.3f} {best[name] / base:7.2f}")
    return best, results, diff


def _wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


if __name__ == "__main__":
    main()
