"""Steady states of multi-DOF chains with Jenkins joints: run time, periods marched, per-event cost.

The chain: ``n`` unit masses, fixed-free, unit springs (``LinearStructure.chain``), 2 % of critical
damping in the first mode (mass-proportional), force 0.01 N at the free end at ``0.9 w1``, and
``j`` Jenkins joints to the ground on the outer half (stiffness ``0.5 w1^2``, slip force 0.3 x the
spring force of the stuck linear response, so that they stick and slip every period).

Baseline, in the same process: the algorithm before the fast paths, reproduced by switches of the
same code -- the period map's Jacobian by finite differences (``jacobian='fd'``), the NumPy event
search (``Marcher.jit = False``), eigenpairs always refined, and stuck-only systems marched.
The two runs must find the same orbit (``amp diff``: largest relative difference of the per-DOF
amplitudes). The marcher's cost per event is timed over 10 periods on the orbit, compiled
(consistency test, piece coefficients and states, event search with skipped stretches) and in
NumPy (the same algorithm with a fixed sampling grid), with their ratio. Usage::

    python benchmarks/chains.py [--quick]
"""
from __future__ import annotations

import argparse
import math
import os
import platform
import time
from contextlib import contextmanager

import numpy as np

import frictionjoint as fj
from frictionjoint.solvers.marcher import piece_kernels, propagator, steady
from frictionjoint.solvers.marcher.events import EventLog, Marcher
from frictionjoint.solvers.marcher.steady import periodic_response


def chain(n: int, joints: int, slip_ratio: float = 0.3) -> fj.FrictionSystem:
    """The benchmark chain (see the module docstring); ``slip_ratio`` large: joints stay stuck."""
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    structure = fj.LinearStructure.chain(n, damping=0.02 * w1)
    dofs = sorted({int(d) for d in np.linspace(n - 1, n // 2, joints).round()})
    kt = 0.5 * w1 ** 2
    exc = [fj.HarmonicForce(n - 1, 0.01)]
    k = structure.stiffness + kt * sum(np.outer(np.eye(n)[d], np.eye(n)[d]) for d in dofs)
    w = 0.9 * w1
    x = np.linalg.solve(k - w * w * structure.mass + 1j * w * structure.damping, 0.01 * np.eye(n)[n - 1])
    slip = slip_ratio * kt * float(np.max(np.abs(x[dofs])))
    return fj.FrictionSystem(structure, [fj.Jenkins(kt, slip, dof=d) for d in dofs], omega=w, excitation=exc)


@contextmanager
def baseline():
    """The algorithm before the fast paths (see the module docstring)."""
    saved = propagator.REFINE_RATIO, steady._stuck_orbit, Marcher.__init__
    init = Marcher.__init__

    def numpy_marcher(self, system):
        init(self, system)
        self.jit = False
    propagator.REFINE_RATIO = 0.0
    steady._stuck_orbit = lambda *args, **kwargs: None
    Marcher.__init__ = numpy_marcher
    try:
        with numpy_pieces():
            yield
    finally:
        propagator.REFINE_RATIO, steady._stuck_orbit, Marcher.__init__ = saved


@contextmanager
def numpy_pieces():
    """Plain modal pieces' coefficients in NumPy (``piece_kernels`` off), as before the fast paths."""
    saved = piece_kernels.ENABLED
    piece_kernels.ENABLED = False
    try:
        yield
    finally:
        piece_kernels.ENABLED = saved


def best(fn, repeat):
    out, t_best = None, math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        t_best = min(t_best, time.perf_counter() - t0)
    return t_best, out


def per_event(system, res, jit: bool, periods: int = 10) -> float:
    """Marcher cost per event [s] over ``periods`` periods on the orbit (configurations cached)."""
    m = Marcher(system)
    m.jit = jit
    if not jit:
        with numpy_pieces():
            return _per_event(m, system, res, periods)
    return _per_event(m, system, res, periods)


def _per_event(m, system, res, periods):
    t_s = res.section_time
    period = 2 * math.pi / system.omega
    n = system.n_dof

    def run():
        st = m.initial_state(res.state[:n], res.state[n:2 * n], None if system.n_sliders == 0 else
                             _w(system, res.state), t0=t_s)
        log = EventLog()
        m.march(st, t_s + periods * period, log)
        return len(log)
    run()
    t, events = best(run, 3)
    return t / max(events, 1)


def _w(system, z):
    n = system.n_dof
    s = system.slider_direction @ z[:n]
    w = s.copy()
    w[~system.rigid] = z[2 * n:]
    return w


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="n = 2, 5, 20 only")
    args = ap.parse_args(argv)
    print(f"# {platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python "
          f"{platform.python_version()}; times: best of 3 (new), 1 run (baseline)")
    print(f"{'n':>3} {'joints':>6} {'new [ms]':>9} {'periods':>8} {'base [ms]':>10} {'periods':>8} "
          f"{'ratio':>7} {'amp diff':>9} {'ev/period':>9} {'ms/event jit':>12} {'numpy':>7} {'ratio':>6}")
    sizes = (2, 5, 20) if args.quick else (2, 5, 10, 20, 50)
    done = set()
    for n in sizes:
        for joints, ratio in ((1, 0.3), (2, 0.3), (5, 0.3), (2, 1e3)):
            system = chain(n, joints, ratio)
            key = (n, system.n_sliders, ratio)
            if key in done:
                continue  # fewer distinct joint positions than asked for
            done.add(key)
            t_new, res = best(lambda: periodic_response(system), 3)
            label = f"{system.n_sliders}" + (" stuck" if ratio > 1 else "")
            if n <= 20:
                with baseline():
                    t_old, old = best(lambda: periodic_response(system, jacobian="fd"), 1)
                diff = float(np.max(np.abs(res.amplitude / old.amplitude - 1)))
                base = f"{t_old * 1e3:10.1f} {old.periods:8.1f} {t_old / t_new:7.1f} {diff:9.1e}"
            else:
                base = f"{'-':>10} {'-':>8} {'-':>7} {'-':>9}"  # baseline > 1 min per case
            events = len(res.events)
            if events:
                fast, slow = per_event(system, res, True), per_event(system, res, False)
                cost = f"{fast * 1e3:12.3f} {slow * 1e3:7.3f} {slow / fast:6.1f}"
            else:
                cost = f"{'-':>12} {'-':>7} {'-':>6}"
            print(f"{n:3d} {label:>6} {t_new * 1e3:9.1f} {res.periods:8.1f} {base} {events:9d} {cost}",
                  flush=True)


if __name__ == "__main__":
    main()
