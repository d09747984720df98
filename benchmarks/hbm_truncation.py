"""Harmonic balance against the exact time domain: truncation error against H, and run time.

1. The Jenkins SDOF of issue 14 (m = k = 1, zeta = 1 %, kt = 5, Fs = 0.1; P = 0.05, 0.2, 1.0; 40
   frequencies from 0.5 to 3 rad/s): the first-harmonic amplitude and the peak amplitude of the
   harmonic balance (exact hysteresis, H = 1, 3, 7, 15, 31) against the exact steady state of the
   same system (the event-driven marcher's shooting), max and median relative error over the
   frequencies, and the observed rate (slope of log error against log H, from H = 3 to 31; the
   points where the slider stays stuck are exact at any H and carry no rate).
2. Time: a pseudo-arclength continuation of the SDOF (P = 0.2) at H = 15 over 0.5-3 rad/s, and of
   the Craig-Bampton blade on its dovetail (259 N at the root, 1 N at the tip) at H = 7 over
   1600-2200 rad/s; milliseconds per point, in this process.
3. The blade with normal-load variation and lift-off on its flanks: continuation time at H = 7
   and the peak's error against the exact time domain for H = 3, 7, 11, 15 at three root loads.
4. A root block whose flanks lift off once per period: truncation error against H.

Usage::

    python benchmarks/hbm_truncation.py [--quick]
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

if __package__ in (None, ""):  # run as a script: the repository is not on the path, benchmarks/ is
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import frictionjoint as fj  # noqa: E402
from benchmarks.harness import script_header, write_results  # noqa: E402
from frictionjoint.structures import BladeAssembly, load_blade_model  # noqa: E402

H_LIST = (1, 3, 7, 15, 31)
FORCES = (0.05, 0.2, 1.0)


def sdof(omega: float, p: float) -> fj.FrictionSystem:
    st = fj.LinearStructure([[1.0]], [[1.0]], [[0.02]])
    return fj.FrictionSystem(st, [fj.Jenkins(5.0, 0.1, dof=0)], omega=omega, excitation=[fj.HarmonicForce(0, p)])


def root_block(omega: float = 3000.0, fx: float = 200.0, fy: float = 400.0, normal_damping: float = 40.0):
    """A 0.2 kg root block on its two flanks (40 deg, mu = 0.3, kn = 1e6 N/m, kt = 8e5 N/m, 1 kN
    centrifugal load, normal-load variation), shaken by ``fx`` along and ``fy`` (phase 0.7) across
    the root: at 3000 rad/s each flank slips, lifts off and closes again once per period. Returns
    ``(system, root)``."""
    st = fj.LinearStructure(np.diag([0.2, 0.2]), np.zeros((2, 2)), np.diag([2.0, 2.0]), dof_names=["X", "Y"])
    root = fj.DovetailRoot(1000.0, flank_angle=math.radians(40.0), friction_coefficient=0.3, normal_stiffness=1e6,
                           tangential_stiffness=8e5, tangential_dof="X", radial_dof="Y",
                           normal_load_variation=True, normal_damping=normal_damping)
    exc = [fj.HarmonicForce("X", fx), fj.HarmonicForce("Y", fy, phase=0.7)]
    return fj.FrictionSystem(st, [root], omega=omega, excitation=exc), root


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="10 frequencies, H up to 15")
    args = parser.parse_args(argv)
    n_w = 10 if args.quick else 40
    h_list = H_LIST[:-1] if args.quick else H_LIST
    omegas = np.linspace(0.5, 3.0, n_w)
    lines = [script_header("hbm_truncation.py", args.quick),
             f"# Jenkins SDOF m = k = 1, zeta = 1 %, kt = 5, Fs = 0.1; {n_w} frequencies 0.5-3 rad/s; error of the "
             "harmonic balance against the exact time-domain steady state (relative, max / median over the "
             "frequencies); rate: slope of log(error) against log H from H = 3 (stuck points are exact)",
             f"{'P [N]':>6} {'H':>3} {'X1 max':>9} {'X1 median':>9} {'peak max':>9} {'peak median':>11} {'ms/pt':>6}"]
    print("\n".join(lines), flush=True)

    def emit(row):
        print(row, flush=True)
        lines.append(row)

    def branch(label, system, omega_range, hh):
        """One timed 200-point continuation: its row."""
        t0 = time.perf_counter()
        sw = fj.hbm_sweep(system, omega_range, n_harmonics=hh, n_points=200)
        dt = time.perf_counter() - t0
        emit(f"continuation, {label}, H = {hh}: {sw.omega.size} points in {dt:.2f} s "
             f"({dt / sw.omega.size * 1e3:.1f} ms per point; {sw.message})")

    for p in FORCES:
        exact = [fj.periodic_response(sdof(w, p)) for w in omegas]
        x1 = np.array([r.harmonic_amplitude[0] * np.exp(-1j * r.phase[0]) for r in exact])
        peak = np.array([r.amplitude[0] for r in exact])
        medians, maxima = [], []
        for hh in h_list:
            guess = None
            e1, ep = [], []
            t0 = time.perf_counter()
            for k, w in enumerate(omegas):
                hb = fj.harmonic_balance(sdof(w, p), n_harmonics=hh, guess=guess)
                guess = hb.harmonics if hb.converged else None
                e1.append(abs(hb.harmonics[1, 0] - x1[k]) / abs(x1[k]))
                ep.append(abs(hb.amplitude[0] - peak[k]) / peak[k])
            dt = (time.perf_counter() - t0) / n_w * 1e3
            medians.append(float(np.median(e1)))
            maxima.append(float(max(e1)))
            emit(f"{p:6.2f} {hh:3d} {max(e1):9.2e} {np.median(e1):9.2e} {max(ep):9.2e} {np.median(ep):11.2e} "
                 f"{dt:6.1f}")
        hs = np.array(h_list[1:], float)

        def rate(errors):
            e = np.array(errors[1:])
            ok = e > 1e-13  # stuck points are exact at any H: no rate
            return float(np.polyfit(np.log(hs[ok]), np.log(e[ok]), 1)[0]) if ok.sum() >= 2 else math.nan
        emit(f"{p:6.2f} observed rate of the first-harmonic error: max H^{rate(maxima):.2f}, "
             f"median H^{rate(medians):.2f}")
    # continuation timings
    sys0 = sdof(1.0, 0.2)
    fj.hbm_sweep(sys0, (0.5, 3.0), n_harmonics=3, n_points=10)  # compile and warm up
    branch("Jenkins SDOF P = 0.2", sys0, (0.5, 3.0), 15)
    asm = BladeAssembly.from_model(load_blade_model("ti64_compressor_blade")).with_root(centrifugal_force=259.0)
    branch("blade on its dovetail (259 N)", asm.system(1600.0), (1600.0, 2200.0), 7)
    # the blade with normal-load variation and lift-off on the flanks
    asm_v = asm.with_root(normal_load_variation=True)
    branch("blade on its dovetail (259 N), normal-load variation", asm_v.system(1600.0), (1600.0, 2200.0), 7)
    emit("# blade peak tip amplitude (first harmonic, 1 N at the tip), normal-load variation: the branch's maximum "
         "(1950-2100 rad/s) against the exact time-domain peak (BladeAssembly.peak)")
    for fc in ((259.0,) if args.quick else (259.0, 615.0, 1458.0)):
        a = asm_v.with_root(centrifugal_force=fc)
        _, a_ex = a.peak(1950.0, 2100.0, a.tip, n_grid=15)
        errs = []
        for hh in (3, 7, 11, 15):
            sw = fj.hbm_sweep(a.system(1950.0), (1950.0, 2100.0), n_harmonics=hh, n_points=60)
            errs.append(f"H = {hh}: {np.abs(sw.harmonics[:, 1] @ a._row(a.tip)).max() / a_ex - 1:+.2e}")
        emit(f"{fc:7.0f} N: exact {a_ex:.6e} m; " + ", ".join(errs))
    # a root block whose flanks lift off once per period (tests/test_hbm_contacts.py)
    block, _ = root_block()
    emit("# root block on two flanks, 3000 rad/s, each flank lifts off once per period: error against its exact orbit")
    for hh in h_list:
        t0 = time.perf_counter()
        hb = fj.harmonic_balance(block, n_harmonics=hh)
        dt = (time.perf_counter() - t0) * 1e3
        hb = fj.harmonic_balance(block, n_harmonics=hh, check=True)
        emit(f"H = {hh:2d}: first harmonic {hb.truncation_error:.2e}, peak {hb.amplitude_error:.2e}, dissipation "
             f"{abs(hb.dissipated_per_cycle / hb.exact.dissipated_per_cycle - 1):.2e}, {dt:.1f} ms")
    write_results("results_hbm.txt", lines, args.quick)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
