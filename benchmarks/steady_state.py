"""Run time against error of CoulombOscillator.steady_state, with a baseline in the same process.

Baselines: the event-driven scipy solve_ivp brute force of benchmarks/bruteforce.py (DOP853, rtol 1e-12,
marched period by period to a fixed point), i.e. what a careful user would write; and what most
users write first, tanh-regularised friction in LSODA (eps = 1e-4 wn P0/k, rtol 1e-9, 60 periods,
peak of the last; benchmarks/harness.py regularised_amplitude). Errors are relative to Den
Hartog's closed form (frictionjoint.analytic). Usage:

    python benchmarks/steady_state.py [--repeat N]
"""
from __future__ import annotations

import argparse
import os
import platform
import time

import bruteforce as bf  # benchmarks/bruteforce.py, beside this script
from harness import Case, make_problem, regularised_amplitude

import frictionjoint as fj
from frictionjoint.analytic import den_hartog


def best_time(fn, repeat):
    best = float("inf")
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)
    print(f"# {platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}")
    print(f"{'case':>14} {'method':>22} {'rel. error':>11} {'time [ms]':>10} {'periods':>8} {'ratio':>8}")
    for r, f in [(0.8, 0.3), (1.5, 0.3), (0.9, 0.1)]:
        ref = den_hartog(r, f).amplitude
        osc = fj.CoulombOscillator(slip_force=f, force_amplitude=1.0, omega=r)
        t_fj, ss = best_time(osc.steady_state, args.repeat)
        t_bf, bs = best_time(lambda: bf.coulomb_steady_state(1.0, 1.0, 0.0, f, 1.0, 0.0, r), max(1, args.repeat // 2))
        case = f"r={r} f={f}"
        print(f"{case:>14} {'steady_state (exact)':>22} {abs(ss.amplitude / ref - 1):11.2e} {t_fj * 1e3:10.1f} "
              f"{ss.periods:8.1f} {1.0:8.2f}")
        print(f"{case:>14} {'solve_ivp events':>22} {abs(bs.amplitude / ref - 1):11.2e} {t_bf * 1e3:10.1f} "
              f"{bs.periods:8d} {t_bf / t_fj:8.2f}")
        problem = make_problem(Case(r, f))
        t_reg, a_reg = best_time(lambda: regularised_amplitude(problem, "LSODA", 1e-4, 1e-9, periods=60,
                                                                       max_evaluations=10 ** 8),
                                 max(1, args.repeat // 2))
        print(f"{case:>14} {'tanh LSODA (1e-4)':>22} {abs(a_reg / ref - 1):11.2e} {t_reg * 1e3:10.1f} "
              f"{60:8d} {t_reg / t_fj:8.2f}", flush=True)


if __name__ == "__main__":
    main()
