"""Steady states of multi-DOF chains with Jenkins joints: run time, periods marched, per-event cost.

The chain: ``n`` unit masses, fixed-free, unit springs (``LinearStructure.chain``), a dashpot
``0.02 w1`` to the ground at each mass (mass-proportional: 1 % of critical damping in the first
mode), force 0.01 N at the free end at ``0.9 w1``, and ``j`` Jenkins joints to the ground on the
outer half (stiffness ``0.5 w1^2``, slip force 0.3 x the largest joint spring force of the stuck
linear response, the same for every joint).

The damping families of issue 40 (:func:`damped_chain`): the same chain and force with the damping
users have -- mass- or stiffness-proportional, Rayleigh, modal, or mass-proportional with a
discrete dashpot -- and joints from ``0.5 w1^2`` to 10 x the chain's springs, each joint's slip
force 0.3 x its own stuck force, so that every joint sticks and slips every period.

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
import scipy.linalg

import frictionjoint as fj
from frictionjoint.solvers.marcher import piece_kernels, propagator, steady
from frictionjoint.solvers.marcher.events import EventLog, Marcher
from frictionjoint.solvers.marcher.steady import periodic_response


def chain(n: int, joints: int, slip_ratio: float = 0.3) -> fj.FrictionSystem:
    """The benchmark chain (see the module docstring); ``slip_ratio`` large: joints stay stuck."""
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    structure = fj.LinearStructure.chain(n, damping=0.02 * w1)
    dofs = joint_dofs(n, joints)
    kt = 0.5 * w1 ** 2
    exc = [fj.HarmonicForce(n - 1, 0.01)]
    k = structure.stiffness + kt * sum(np.outer(np.eye(n)[d], np.eye(n)[d]) for d in dofs)
    w = 0.9 * w1
    x = np.linalg.solve(k - w * w * structure.mass + 1j * w * structure.damping, 0.01 * np.eye(n)[n - 1])
    slip = slip_ratio * kt * float(np.max(np.abs(x[dofs])))
    return fj.FrictionSystem(structure, [fj.Jenkins(kt, slip, dof=d) for d in dofs], omega=w, excitation=exc)


#: damping forms of :func:`damped_chain`
DAMPINGS = ("mass", "stiffness", "rayleigh", "modal", "dashpot")
ZETA = 0.01  # the damping ratio the forms are set to (of critical, in the free chain's modes)


def joint_dofs(n: int, joints: int) -> list[int]:
    """The joints' DOFs: ``joints`` spread evenly over the outer half (fewer if they coincide)."""
    return sorted({int(d) for d in np.linspace(n - 1, n // 2, joints).round()})


def free_modes(n: int) -> tuple[np.ndarray, np.ndarray]:
    """Circular frequencies (n,) [rad/s], ascending, and mass-normalised mode shapes (n, n) of the
    free chain (``LinearStructure.chain(n)``, no joint)."""
    base = fj.LinearStructure.chain(n)
    lam, phi = scipy.linalg.eigh(base.stiffness, base.mass)
    return np.sqrt(lam), phi


def rayleigh_mode(n: int) -> int:
    """The higher mode (1-based) of the Rayleigh family's second 1 % point: the mode near ``n / 10``,
    at least mode 2 (at most mode ``n``)."""
    return min(max(round(n / 10), 2), n)


def damping_matrix(n: int, damping: str) -> np.ndarray:
    """The damping matrix (n, n) [N s/m] of :func:`damped_chain`'s form ``damping`` for the free
    chain of ``n`` unit masses (``w``: its circular frequencies, ``Phi``: its mass-normalised modes):

    - ``'mass'``: ``alpha M``, ``ZETA`` of critical in mode 1 (``alpha = 2 ZETA w1``);
    - ``'stiffness'``: ``beta K``, ``ZETA`` in mode 1 (``beta = 2 ZETA / w1``);
    - ``'rayleigh'``: ``alpha M + beta K`` with ``ZETA`` in mode 1 and in mode :func:`rayleigh_mode`
      (between them less, above more);
    - ``'modal'``: ``M Phi diag(2 ZETA w_i) Phi^T M``, ``ZETA`` in every mode;
    - ``'dashpot'``: ``'mass'`` plus one dashpot ``2 w1`` [N s/m] from the tip (DOF ``n - 1``, a joint's
      DOF) to the ground: the critical damping of mode 1 in mass-normalised coordinates, which adds
      about ``2 / n`` of critical to mode 1 (``Phi_tip^2``) and couples the modes.
    """
    if damping not in DAMPINGS:
        raise ValueError(f"damping must be one of {DAMPINGS}, got {damping!r}")
    w, phi = free_modes(n)
    base = fj.LinearStructure.chain(n)
    m, k = base.mass, base.stiffness
    if damping in ("mass", "dashpot"):
        c = 2 * ZETA * w[0] * m
        if damping == "dashpot":
            c[n - 1, n - 1] += 2 * w[0]
        return c
    if damping == "stiffness":
        return (2 * ZETA / w[0]) * k
    if damping == "rayleigh":
        w1, w2 = w[0], w[rayleigh_mode(n) - 1]
        return (2 * ZETA * w1 * w2 / (w1 + w2)) * m + (2 * ZETA / (w1 + w2)) * k
    c = m @ phi @ np.diag(2 * ZETA * w) @ phi.T @ m
    return 0.5 * (c + c.T)


def damped_chain(n: int, joints: int, damping: str = "stiffness", joint_stiffness: float | str = 1.0,
                 slip_ratio: float = 0.3) -> fj.FrictionSystem:
    """A chain of issue 40's damping families (see the module docstring).

    Parameters
    ----------
    n : int
        Unit masses [kg], fixed-free, unit springs [N/m].
    joints : int
        Jenkins joints to the ground, spread over the outer half (:func:`joint_dofs`).
    damping : {'mass', 'stiffness', 'rayleigh', 'modal', 'dashpot'}
        The damping form (:func:`damping_matrix`), 1 % of critical in the free chain's mode 1.
    joint_stiffness : float or 'soft'
        Each joint's stiffness as a multiple of the chain's springs (1: as stiff as the structure);
        ``'soft'``: ``0.5 w1^2`` as in :func:`chain`.
    slip_ratio : float
        Each joint's slip force over its own spring force in the stuck linear response at the
        forcing frequency (below 1: every joint sticks and slips every period).

    Returns
    -------
    FrictionSystem
        Force 0.01 N at the tip at ``0.9 w1`` of the free chain.
    """
    w1 = free_modes(n)[0][0]
    base = fj.LinearStructure.chain(n)
    structure = fj.LinearStructure(base.mass, base.stiffness, damping_matrix(n, damping))
    kt = 0.5 * w1 ** 2 if joint_stiffness == "soft" else float(joint_stiffness)
    if not kt > 0:
        raise ValueError(f"joint_stiffness must be > 0 or 'soft', got {joint_stiffness!r}")
    dofs = joint_dofs(n, joints)
    k = structure.stiffness + kt * sum(np.outer(np.eye(n)[d], np.eye(n)[d]) for d in dofs)
    w = 0.9 * w1
    x = np.linalg.solve(k - w * w * structure.mass + 1j * w * structure.damping, 0.01 * np.eye(n)[n - 1])
    joints_ = [fj.Jenkins(kt, slip_ratio * kt * float(abs(x[d])), dof=d) for d in dofs]
    return fj.FrictionSystem(structure, joints_, omega=w, excitation=[fj.HarmonicForce(n - 1, 0.01)])


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
