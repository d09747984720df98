"""Side by side with pyHarm: harmonic balance of two Jenkins friction problems, at equal H.

What is compared
----------------
Two problems (SI units, x the displacement of a mass):

1. Jenkins SDOF: m = 1, k = 1, c = 0.02 (zeta = 1 %), a Jenkins element to ground (kt = 5,
   Fs = 0.1), force 0.2 cos(w t); 20 frequencies from 0.5 to 3.0 rad/s; observed DOF: the mass.
2. Two-DOF chain: m1 = 1, m2 = 0.5, K = [[3, -1], [-1, 1]] (k1 = 2 to ground, k2 = 1 between the
   masses), C = 0.02 I, a Jenkins element from ground to mass 2 (kt = 2, Fs = 0.3), force
   0.8 cos(w t) on mass 1; 20 frequencies from 0.5 to 2.5 rad/s; observed DOF: mass 2.

For H = 7 and H = 15 (harmonics 0..H in both codes) each code's first-harmonic amplitude of the
observed DOF is compared with frictionjoint's exact time-domain steady state
(``fj.periodic_response``: event-driven marching and shooting, no harmonic truncation): max and
median relative error over the 20 frequencies, and the time per frequency point (wall time of
the frequency loop / number of points, after one warm-up solve, the fastest of ``--repeat`` = 3
identical loops, in each code's own process: frictionjoint in the main process, pyHarm in the
worker).

* frictionjoint: ``fj.harmonic_balance(system, n_harmonics=H, guess=previous.harmonics)`` at each
  listed frequency (exact hysteresis, no time sampling; Newton tolerance ``tol = 1e-10``, its
  default; the guess is the previous frequency's balance when that one converged).
* pyHarm, fixed frequency (the main rows): one ``FRF_NonLinear`` analysis per listed frequency
  made with pyHarm's factory ``generateNonLinearAnalysis('frf', ...)`` on one ``System`` built by
  ``pyHarm.Maestro``, with ``puls_start = w`` and the stopper ``'solnumber'``
  (``max_solutions = 1``), so ``Solve(x0)`` solves only its first point, at fixed ``w`` (its
  corrector there is ``'nocontinuation'``), from ``x0`` = the previous frequency's solution (the
  first frequency: ``x0 = None``, pyHarm's linear solution with the Jacobian at zero, i.e. the
  Jenkins stuck).  The time per point includes building the analysis object (reported apart).
* pyHarm, continuation (an extra row): one ``FRF_NonLinear`` over the whole range with pyHarm's
  default predictor/corrector (tangent, arc length, ``'acceptance'`` step rule) but
  ``ds0 = ds_max = 0.05`` (``--continuation-ds``): its default ``ds0 = ds_max = 1`` steps over
  the resonance (4 points from 0.5 to 3.4 rad/s on problem 1).  The amplitudes are interpolated
  linearly in omega onto the listed frequencies (the first crossing along the branch), so the
  row's error includes the interpolation error; its time is the whole continuation
  (``Maestro.operate()``, the Maestro build excluded) / 20 listed frequencies.

How pyHarm is configured (input dictionary for ``pyHarm.Maestro``)
-------------------------------------------------------------------
* ``system``: ``{'type': 'Base', 'nh': H, 'nti': NTI}``.  ``nh = H`` is harmonics 0..H.  ``nti``
  is the number of time samples of the alternating frequency-time (AFT) procedure; pyHarm's
  default is 128 (``ABCSystem.default``), the ``pyharm_cli`` templates propose 1024: both are
  run (``--nti``).  ``adim`` left at its default (off).
* ``substructures``: one ``{'type': 'substructure', 'ndofs': 1, 'matrix': {'M', 'K', 'C'}}``
  (one node per mass, 1 DOF per node; node i is mass i).
* ``connectors``: ``{'type': 'Jenkins', 'connect': {sub: [node]}, 'dirs': [0], 'k': kt,
  'mu': Fs, 'N0': 1.0}`` (one entry in ``connect``: to ground; slip force ``mu * N0``;
  Jacobian ``'analytical'``, its default) and ``{'type': 'CosinusForcing', 'connect': {sub:
  [node]}, 'dirs': [0], 'amp': P}`` (a cosine on harmonic 1).
* analysis ``{'study': 'frf', ...}``: solver ``'scipyroot'`` (pyHarm's default:
  ``scipy.optimize.root``, method ``'hybr'`` with pyHarm's analytical Jacobian, scipy's default
  ``xtol = 1.49e-8``, relative change of the iterate; pyHarm's own ``residual_tolerance = 1e-4``
  only applies when the status is not 1), reductor ``'noreductor'``, ``verbose = False``.
* pyHarm's unknowns per DOF: ``[a0, a1, b1, ..., aH, bH]`` with ``x(t) = a0 + sum a_h cos(h w t) +
  b_h sin(h w t)``; the first-harmonic amplitude is ``hypot(a1, b1)``.

pyHarm's Jenkins element (``Elements/NodeToNodeElements/Jenkins.py``) is not regularised: a
stuck spring of stiffness ``k`` with the slider moved so the force is ``mu N0`` when the
predicted force reaches it, evaluated at the ``nti`` time samples only (a slip onset is caught at
the first sample past it), over three periods from the slider at 0 (the last period is kept).
That sampling is the difference between the two balances at equal H: here 1.5e-3 to 1.7e-3 of
the amplitude at ``nti = 128``, 1e-5 to 5e-5 at 1024 (column 'vs fj HBM' of the results).  Its ``FirstSolution`` is always flagged accepted, so this script
checks convergence itself: hybr's status 1, or a residual norm <= 1e-9 P (hybr may end with
status 5, 'not making good progress', on a solution whose residual is ~1e-17).

Install the peer
----------------
pyHarm is never a runtime (nor test) dependency of frictionjoint, and this script's main mode does
not import it: it runs in its own environment, e.g.::

    python -m venv /tmp/phenv && /tmp/phenv/bin/pip install pyHarm-os

(pyHarm 1.2.2 needs Python >= 3.11 and brings jax, numba, pandas, ...).  Its first run compiles
its numba kernels (about 40 s; cached afterwards).

Usage::

    python benchmarks/pyharm_side_by_side.py [--python /tmp/phenv/bin/python] [--nti 128,1024]
    python benchmarks/pyharm_side_by_side.py --worker PROBLEM H [--nti N] [--mode fixed|continuation]

The main mode (in frictionjoint's environment) computes the exact references and frictionjoint's
balance, starts the worker mode with pyHarm's python for each row (the worker prints one JSON
line and never imports frictionjoint), prints the tables and writes
``benchmarks/results_pyharm.txt``.  ``--python`` defaults to ``$PYHARM_PYTHON``, else
``/tmp/phenv/bin/python``.  If pyHarm cannot be run, the reason is printed and the frictionjoint
rows still are.  pyHarm's processes run in a scratch directory: importing pyHarm writes
``.pyHarm/context.json`` (its kernel state) in the working directory.
"""
from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time

import numpy as np

PROBLEMS = {
    1: dict(name="Jenkins SDOF (m = k = 1, zeta = 1 %, kt = 5, Fs = 0.1, P = 0.2)",
            mass=[[1.0]], stiffness=[[1.0]], damping=[[0.02]],
            jenkins_dof=0, kt=5.0, slip_force=0.1, force_dof=0, force=0.2,
            omega_range=(0.5, 3.0), n_points=20, observe=0),
    2: dict(name="two-DOF chain (m = 1, 0.5; K = [[3, -1], [-1, 1]]; C = 0.02 I; Jenkins kt = 2, Fs = 0.3 "
                 "on mass 2; 0.8 cos(w t) on mass 1)",
            mass=[[1.0, 0.0], [0.0, 0.5]], stiffness=[[3.0, -1.0], [-1.0, 1.0]],
            damping=[[0.02, 0.0], [0.0, 0.02]],
            jenkins_dof=1, kt=2.0, slip_force=0.3, force_dof=0, force=0.8,
            omega_range=(0.5, 2.5), n_points=20, observe=1),
}
H_LIST = (7, 15)
HERE = os.path.dirname(os.path.abspath(__file__))
RESULTS = os.path.join(HERE, "results_pyharm.txt")


def omegas_of(prob: dict) -> np.ndarray:
    lo, hi = prob["omega_range"]
    return np.linspace(lo, hi, prob["n_points"])


# ----------------------------------------------------------------------------------------------
# worker mode: pyHarm only (never imports frictionjoint)
# ----------------------------------------------------------------------------------------------

def _pyharm_input(prob: dict, hh: int, nti: int, analysis: dict | None = None) -> dict:
    """pyHarm's input dictionary for ``prob`` (module docstring)."""
    data = {
        "system": {"type": "Base", "nh": int(hh), "nti": int(nti)},
        "substructures": {
            "chain": {"type": "substructure", "ndofs": 1,
                      "matrix": {"M": np.array(prob["mass"], float), "K": np.array(prob["stiffness"], float),
                                 "C": np.array(prob["damping"], float)}},
        },
        "connectors": {
            "jenkins": {"type": "Jenkins", "connect": {"chain": [prob["jenkins_dof"]]}, "dirs": [0],
                        "k": prob["kt"], "mu": prob["slip_force"], "N0": 1.0},
            "forcing": {"type": "CosinusForcing", "connect": {"chain": [prob["force_dof"]]}, "dirs": [0],
                        "amp": prob["force"]},
        },
    }
    if analysis is not None:
        data["analysis"] = analysis
    return data


def _first_harmonic_index(edf, dof: int) -> tuple[int, int]:
    """Indices of ``a1`` and ``b1`` of node ``dof`` in pyHarm's explicit DOF table."""
    sel = edf[(edf["sub"] == "chain") & (edf["node_num"] == dof) & (edf["harm"] == 1)]
    ia = int(sel[sel["cs"] == "c"].index[0])
    ib = int(sel[sel["cs"] == "s"].index[0])
    return ia, ib


def worker(problem: int, hh: int, nti: int, mode: str, ds: float, repeat: int = 3) -> dict:
    import logging
    import warnings

    warnings.filterwarnings("ignore")  # numba performance warnings on pyHarm's kernels
    logging.disable(logging.CRITICAL)  # pyHarm's banner and per-point log lines
    t_import = time.perf_counter()
    import pyHarm
    from pyHarm.Analysis.FactoryNonLinearStudy import generateNonLinearAnalysis
    t_import = time.perf_counter() - t_import

    prob = PROBLEMS[problem]
    omegas = omegas_of(prob)
    out = dict(problem=problem, H=hh, nti=nti, mode=mode, pyharm_version=getattr(pyHarm, "__version__", "?"),
               omegas=omegas.tolist(), import_seconds=t_import)

    if mode == "fixed":
        maestro = pyHarm.Maestro(_pyharm_input(prob, hh, nti))
        system = maestro.system
        ia, ib = _first_harmonic_index(system.expl_dofs, prob["observe"])
        setup = [0.0]

        def solve(w, x0):
            cfg = {"study": "frf", "puls_inf": 0.5 * w, "puls_sup": 2.0 * w, "puls_start": float(w),
                   "stopper": "solnumber", "stopper_options": {"max_solutions": 1}, "verbose": False}
            t = time.perf_counter()
            ana = generateNonLinearAnalysis("frf", cfg, system, logger=maestro.logger, key=f"w={w:.6g}")
            setup[0] += time.perf_counter() - t
            ana.Solve(x0)
            sol = ana.SolList[0]
            rn = float(np.linalg.norm(sol.R_solver))
            # hybr's status 1 (its xtol test), or a residual at rounding level: hybr may stop with
            # status 5 ('not making good progress') on an exact solution (residual ~1e-17)
            ok = bool((sol.status_solver == 1 or rn <= 1e-9 * abs(prob["force"])) and np.all(np.isfinite(sol.x))
                      and abs(sol.x[-1] - w) <= 1e-12 * w)
            return sol, ok, rn, int(sol.status_solver)

        t = time.perf_counter()
        solve(omegas[0], None)  # warm-up: numba kernels compiled or loaded from their cache
        out["warmup_seconds"] = time.perf_counter() - t
        best = None
        for _ in range(repeat):  # the fastest of `repeat` identical loops (both codes alike)
            setup[0] = 0.0
            amp, conv, res, status = [], [], [], []
            x0 = None
            t0 = time.perf_counter()
            for w in omegas:
                sol, ok, rn, st = solve(w, x0)
                amp.append(float(np.hypot(sol.x[ia], sol.x[ib])))
                conv.append(ok)
                res.append(rn)
                status.append(st)
                x0 = sol.x[:-1].copy() if ok else None
            dt = time.perf_counter() - t0
            if best is None or dt < best[0]:
                best = (dt, setup[0])
        dt, setup[0] = best
        out.update(amplitude=amp, converged=conv, residual_norm=res, solver_status=status, seconds=dt,
                   ms_per_point=dt / len(omegas) * 1e3, setup_ms_per_point=setup[0] / len(omegas) * 1e3,
                   description=(f"fixed frequency: FRF_NonLinear per listed omega (solnumber stopper, 1 solution, "
                                f"'nocontinuation' first point), scipyroot/hybr, x0 = previous solution; nti = {nti}"))
    elif mode == "continuation":
        lo, hi = prob["omega_range"]

        def run():
            ana = {"frf": {"study": "frf", "puls_inf": lo, "puls_sup": hi, "ds0": ds, "ds_max": ds,
                           "verbose": False}}
            t = time.perf_counter()
            maestro = pyHarm.Maestro(_pyharm_input(prob, hh, nti, ana))
            t_build = time.perf_counter() - t
            t = time.perf_counter()
            maestro.operate()
            return maestro, t_build, time.perf_counter() - t

        t = time.perf_counter()
        run()  # warm-up
        out["warmup_seconds"] = time.perf_counter() - t
        runs = [run() for _ in range(repeat)]
        dt = min(r[2] for r in runs)
        maestro, t_build = runs[-1][0], runs[-1][1]
        sols = [s for s in maestro.nls["frf"].SolList if s.flag_accepted]
        ia, ib = _first_harmonic_index(maestro.system.expl_dofs, prob["observe"])
        om = np.array([s.x[-1] for s in sols])
        a = np.array([np.hypot(s.x[ia], s.x[ib]) for s in sols])
        amp, conv = [], []
        for w in omegas:
            val = float("nan")
            for j in range(len(om) - 1):  # first crossing along the branch
                if (om[j] - w) * (om[j + 1] - w) <= 0 and om[j] != om[j + 1]:
                    s = (w - om[j]) / (om[j + 1] - om[j])
                    val = float(a[j] + s * (a[j + 1] - a[j]))
                    break
            amp.append(val)
            conv.append(bool(np.isfinite(val)))
        folds = int(np.sum(np.diff(np.sign(np.diff(om))) != 0)) if len(om) > 2 else 0
        out.update(amplitude=amp, converged=conv, seconds=dt, ms_per_point=dt / len(omegas) * 1e3,
                   build_seconds=t_build, n_continuation_points=len(sols),
                   n_solutions_tried=len(maestro.nls["frf"].SolList), omega_reached=float(om.max()),
                   omega_turns=folds,
                   description=(f"arc-length continuation (tangent predictor, arc_length corrector, acceptance "
                                f"step rule, ds0 = ds_max = {ds:g}), {len(sols)} points, amplitudes linearly "
                                f"interpolated in omega onto the listed frequencies; nti = {nti}"))
    else:
        raise SystemExit(f"unknown mode {mode!r}")
    return out


# ----------------------------------------------------------------------------------------------
# main mode: frictionjoint
# ----------------------------------------------------------------------------------------------

def fj_rows(problem: int, h_list, repeat: int = 3) -> tuple[np.ndarray, dict, list[str]]:
    import frictionjoint as fj

    prob = PROBLEMS[problem]
    omegas = omegas_of(prob)
    st = fj.LinearStructure(prob["mass"], prob["stiffness"], prob["damping"])

    def system(w):
        return fj.FrictionSystem(st, [fj.Jenkins(prob["kt"], prob["slip_force"], dof=prob["jenkins_dof"])],
                                 omega=float(w), excitation=[fj.HarmonicForce(prob["force_dof"], prob["force"])])

    notes = []
    t = time.perf_counter()
    exact = [fj.periodic_response(system(w), peaks=False) for w in omegas]
    t_exact = time.perf_counter() - t
    bad = [float(w) for w, e in zip(omegas, exact) if not e.converged]
    if bad:
        notes.append(f"exact time domain NOT converged at omega = {bad}")
    ref = np.array([e.harmonic_amplitude[prob["observe"]] for e in exact])
    notes.append(f"exact time-domain references: {len(omegas)} points in {t_exact:.2f} s "
                 f"({t_exact / len(omegas) * 1e3:.1f} ms per point)")
    rows = {}
    for hh in h_list:
        fj.harmonic_balance(system(omegas[0]), n_harmonics=hh)  # warm-up
        dt = None
        for _ in range(repeat):  # the fastest of `repeat` identical loops (both codes alike)
            guess = None
            amp, conv = [], []
            t0 = time.perf_counter()
            for w in omegas:
                hb = fj.harmonic_balance(system(w), n_harmonics=hh, guess=guess)
                guess = hb.harmonics if hb.converged else None
                amp.append(float(abs(hb.harmonics[1, prob["observe"]])))
                conv.append(bool(hb.converged))
            t1 = time.perf_counter() - t0
            dt = t1 if dt is None else min(dt, t1)
        rows[hh] = dict(amplitude=amp, converged=conv, ms_per_point=dt / len(omegas) * 1e3)
    return ref, rows, notes


def errors(amp, ref) -> tuple[float, float]:
    e = np.abs(np.asarray(amp, float) - ref) / ref
    if not np.all(np.isfinite(e)):
        return float("nan"), float("nan")
    return float(e.max()), float(np.median(e))


def run_worker(python: str, problem: int, hh: int, nti: int, mode: str, ds: float, timeout: float,
               repeat: int = 3, cwd: str | None = None):
    """Run the worker with pyHarm's python (in ``cwd``: importing pyHarm writes
    ``.pyHarm/context.json`` in the working directory); (result dict, None) or (None, reason)."""
    cmd = [python, os.path.abspath(__file__), "--worker", str(problem), str(hh), "--nti", str(nti),
           "--mode", mode, "--continuation-ds", repr(ds), "--repeat", str(repeat)]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, cwd=cwd)
    except FileNotFoundError:
        return None, f"pyHarm python not found: {python}"
    except subprocess.TimeoutExpired:
        return None, f"pyHarm worker timed out after {timeout:.0f} s: {' '.join(cmd)}"
    lines = [ln for ln in proc.stdout.splitlines() if ln.startswith("{")]
    if proc.returncode != 0 or not lines:
        tail = (proc.stderr.strip().splitlines() or ["(no stderr)"])[-1]
        return None, f"pyHarm worker failed (exit {proc.returncode}): {tail}"
    try:
        return json.loads(lines[-1]), None
    except json.JSONDecodeError as exc:
        return None, f"pyHarm worker printed no valid JSON ({exc})"


def main_mode(args) -> int:
    import frictionjoint as fj

    python = args.python
    nti_list = [int(s) for s in args.nti.split(",") if s.strip()]
    args.repeat = max(1, args.repeat)
    t_start = time.perf_counter()
    lines = [f"# benchmarks/pyharm_side_by_side.py: {platform.machine()}, {os.cpu_count()} cores, "
             f"{time.strftime('%Y-%m-%d')}; frictionjoint {getattr(fj, '__version__', '?')}, pyHarm peer: {python}",
             "# first-harmonic amplitude of the observed DOF against frictionjoint's exact time-domain steady state "
             "(relative error, max / median over the frequencies); ms/pt: wall time of the frequency loop / points, "
             f"after a warm-up solve, fastest of {args.repeat} loops, each code in its own process; conv: points "
             "converged (pyHarm: hybr status 1 or residual <= 1e-9 P; continuation: listed omega reached by the "
             "branch); vs fj HBM: max |X1 pyHarm - X1 frictionjoint HBM| / X1 exact at the same H (the "
             "difference of the two balances: pyHarm's AFT sampling, its solver's tolerance, interpolation)"]
    print("\n".join(lines), flush=True)

    # does pyHarm run at all?  (every pyHarm process runs in a scratch directory: importing pyHarm
    # writes its kernel state, .pyHarm/context.json, in the working directory)
    scratch = tempfile.TemporaryDirectory(prefix="pyharm_side_by_side_")
    probe_reason = None
    try:
        pr = subprocess.run([python, "-c", "import pyHarm, sys; sys.stdout.write(pyHarm.__version__)"],
                            capture_output=True, text=True, timeout=600, cwd=scratch.name)
        if pr.returncode != 0:
            probe_reason = "pyHarm cannot be imported: " + ((pr.stderr.strip().splitlines() or ["?"])[-1])
        else:
            lines.append(f"# pyHarm {pr.stdout.strip()}")
            print(lines[-1], flush=True)
    except (FileNotFoundError, PermissionError):
        probe_reason = f"pyHarm python not found: {python}"
    except subprocess.TimeoutExpired:
        probe_reason = "importing pyHarm timed out"
    if probe_reason:
        lines.append(f"# pyHarm rows skipped: {probe_reason}")
        print(lines[-1], flush=True)

    for problem, prob in PROBLEMS.items():
        omegas = omegas_of(prob)
        head = (f"\n## Problem {problem}: {prob['name']}; {len(omegas)} frequencies "
                f"{omegas[0]:g}-{omegas[-1]:g} rad/s; observed: mass {prob['observe'] + 1}")
        print(head, flush=True)
        lines.append(head)
        ref, fj_res, notes = fj_rows(problem, H_LIST, args.repeat)
        for n in notes:
            lines.append("# " + n)
            print(lines[-1], flush=True)
        for hh in H_LIST:
            sub = [f"H = {hh}",
                   f"{'code':<62} {'ms/pt':>7} {'conv':>6} {'X1 err max':>10} {'X1 err med':>10} {'vs fj HBM':>9}"]
            r = fj_res[hh]
            fj_amp = np.array(r["amplitude"])
            emax, emed = errors(r["amplitude"], ref)
            sub.append(f"{'frictionjoint HBM (exact hysteresis), fixed omega, guess prev.':<62} "
                       f"{r['ms_per_point']:7.2f} {sum(r['converged']):>3}/{len(omegas):<2} {emax:10.2e} {emed:10.2e} "
                       f"{'':>9}")
            extra = []
            if probe_reason is None:
                jobs = [("fixed", n) for n in nti_list]
                if args.continuation_ds > 0:
                    jobs.append(("continuation", nti_list[0] if nti_list else 128))
                for mode, nti in jobs:
                    res, reason = run_worker(python, problem, hh, nti, mode, args.continuation_ds, args.timeout,
                                         args.repeat, cwd=scratch.name)
                    label = (f"pyHarm HBM, AFT nti = {nti}, fixed omega, x0 prev." if mode == "fixed" else
                             f"pyHarm arc-length ds = {args.continuation_ds:g}, nti = {nti}, interp.")
                    if res is None:
                        sub.append(f"{label:<62} {'--':>7} {'--':>6} {'--':>10} {'--':>10} {'--':>9}")
                        extra.append(f"  {label}: {reason}")
                        continue
                    emax, emed = errors(res["amplitude"], ref)
                    ok = [c for c in res["converged"]]
                    if not all(ok):
                        conv_amp = [a if c else np.nan for a, c in zip(res["amplitude"], ok)]
                        e = np.abs(np.array(conv_amp, float) - ref) / ref
                        e = e[np.isfinite(e)]
                        if e.size:
                            emax, emed = float(e.max()), float(np.median(e))
                        extra.append(f"  {label}: errors over the {e.size} converged points only")
                    d = np.abs(np.array(res["amplitude"], float) - fj_amp) / ref
                    d = d[np.isfinite(d) & np.array(ok)]
                    dmax = float(d.max()) if d.size else float("nan")
                    sub.append(f"{label:<62} {res['ms_per_point']:7.2f} {sum(ok):>3}/{len(omegas):<2} "
                               f"{emax:10.2e} {emed:10.2e} {dmax:9.2e}")
                    if mode == "fixed":
                        extra.append(f"  {label}: of which {res['setup_ms_per_point']:.2f} ms/pt building the "
                                     f"FRF_NonLinear object; warm-up {res['warmup_seconds']:.1f} s; max residual norm "
                                     f"{max(res['residual_norm']):.1e}; hybr status != 1 at "
                                     f"{sum(st != 1 for st in res['solver_status'])} points")
                    else:
                        extra.append(f"  {label}: {res['n_continuation_points']} continuation points "
                                     f"({res['seconds'] / max(res['n_continuation_points'], 1) * 1e3:.2f} ms each), "
                                     f"reached omega = {res['omega_reached']:.4g}, {res['omega_turns']} turns in omega")
            sub += extra
            print("\n".join(sub), flush=True)
            lines += sub
    scratch.cleanup()
    total = time.perf_counter() - t_start
    lines.append(f"\n# total run time {total:.1f} s")
    print(lines[-1])
    with open(RESULTS, "w") as fh:
        fh.write("\n".join(lines) + "\n")
    print(f"written to {os.path.relpath(RESULTS, os.getcwd())}")
    return 0


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--worker", nargs=2, type=int, metavar=("PROBLEM", "H"),
                        help="pyHarm worker mode (run with pyHarm's python): print one JSON line")
    parser.add_argument("--python", default=os.environ.get("PYHARM_PYTHON", "/tmp/phenv/bin/python"),
                        help="python of the environment where pyHarm-os is installed")
    parser.add_argument("--nti", default="128,1024",
                        help="pyHarm AFT time samples (main mode: comma-separated list; worker: one value)")
    parser.add_argument("--mode", default="fixed", choices=("fixed", "continuation"), help="worker mode")
    parser.add_argument("--continuation-ds", type=float, default=0.05,
                        help="pyHarm continuation step ds0 = ds_max (0: no continuation row)")
    parser.add_argument("--repeat", type=int, default=3,
                        help="time the frequency loop this many times and keep the fastest (both codes)")
    parser.add_argument("--timeout", type=float, default=1800.0, help="seconds per pyHarm worker")
    args = parser.parse_args(argv)
    if args.worker:
        problem, hh = args.worker
        if problem not in PROBLEMS:
            parser.error(f"PROBLEM must be one of {sorted(PROBLEMS)}")
        out = worker(problem, hh, int(args.nti.split(",")[0]), args.mode, args.continuation_ds, max(1, args.repeat))
        sys.stdout.write(json.dumps(out) + "\n")
        return 0
    return main_mode(args)


if __name__ == "__main__":
    sys.exit(main())
