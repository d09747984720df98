"""How the cost grows with the chain's size (issue 26): time-domain steady states, harmonic balance
and a DOP853 baseline of the same linear chain, as ratios measured in the same process.

The chains are ``benchmarks/chains.py``'s (``chain(n, joints)``: ``n`` unit masses, Jenkins joints
to the ground spread over the outer half, the tip force near the first mode), the family
``n / joints = 5`` from 20 to 400 DOF. Per size, in a worker process of its own (spawned; nothing
is set in the environment, BLAS threads are the library's and NumPy's defaults):

- ``DOP853``: ``scipy.integrate.solve_ivp(method="DOP853")`` over 20 excitation periods from rest
  of the same chain made linear with every joint stuck (the structure's stiffness plus each joint's
  ``tangential_stiffness`` on its DOF, the structure's damping, the tip force), a plain
  ``A @ z`` right-hand side, at ``rtol = 1e-6, atol = 1e-9`` -- the baseline of every ratio -- and,
  for reference only, at ``rtol = 1e-10, atol = 1e-12`` (``tight``) and with one BLAS thread
  (``1 thread``, threadpoolctl: the library's own setting; NumPy's default threads make ``A @ z``
  of 800 states several times slower on a busy 2-core machine);
- ``cold``: ``fj.periodic_response(system)`` on a freshly built system (its first call; the compiled
  kernels were loaded before, on a 6-DOF chain, and that first call of the process is shown apart
  as ``jit``), ``warm``: a second call on the same system object;
- ``HBM7``, ``HBM15``: ``fj.harmonic_balance(system, n_harmonics=7)`` and ``15``, one point each,
  each on a freshly built system.

``--family`` chooses the chains (issue 40): ``chain`` (the default, ``chains.chain``: mass-proportional
damping, soft joints ``0.5 w1^2``, one slip force for all joints; today's results stay comparable)
or ``DAMPING:JOINT_STIFFNESS`` (``chains.damped_chain``: ``DAMPING`` one of ``mass``, ``stiffness``,
``rayleigh``, ``modal``, ``dashpot``, 1 % of critical in the free chain's mode 1; ``JOINT_STIFFNESS``
the joints' stiffness as a multiple of the chain's springs, or ``soft`` for ``0.5 w1^2``; each
joint's slip force 0.3 x its own stuck force), several separated by commas, or ``all``
(:data:`ALL_FAMILIES`): one table per family, each with its growth exponents. The ratios'
denominator (``--baseline``) is the loose DOP853 run for ``chain`` (issue 26's) and the tight one
(``rtol = 1e-10, atol = 1e-12``, issue 40's) for the damping families unless chosen; the header
says which. The chosen baseline is measured before the steady states, so that a size past its
limit keeps its ratios where it can. ``start``: where ``periodic_response``'s ``'auto'`` started
(``balance``: the harmonic-balance orbit, ``rest``); a size large enough for the balance start that
reads ``rest`` had its balance orbit discarded (not unique or not converged), which the note under
the row says, as it says ``NOT UNIQUE`` orbits. ``cold GB``: the worker's peak resident memory
during the cold steady state alone (Linux: the peak is reset before it).

Each size has ``--limit`` seconds and ``--memory`` GB resident (default half the machine's: the
cold steady state of (400, 80) grew to 24 GB and was killed by the kernel); a column that has not
finished by then reads ``> limit`` (``> memory``) and the next size starts; ``GB`` is the worker's
peak resident memory as last seen. Under the table: the growth exponent of each column, the
least-squares slope of ``log(time)`` against ``log(n)`` over the sizes that finished, and the same
between the two largest (where fixed costs weigh less). ``--check`` asserts the targets
for the sizes run: for ``chain`` issue 26's, against the loose DOP853: cold ``periodic_response``
at (100, 20) and (200, 40) at most 0.5 x, ``harmonic_balance`` at ``H = 7`` at (200, 40) at most
0.05 x; for every damping family issue 40's, against the tight DOP853 (:data:`FAMILY_TARGETS`):
cold at most 0.12 x at (20, 2) and 0.36 x at (20, 5) (issue 12's targets, which were absolute: 20
times faster than the 1.4 s and 3.6 s of then, restated by issue 40 as ratios to the tight run),
0.3 x at (100, 20), 0.5 x at (200, 40), 1 x at (400, 80) with at most 4 GB (``cold GB``) there,
``H = 7`` at most 0.05 x at (200, 40), and a unique orbit everywhere. ``--amplitudes FILE``
keeps the steady states' amplitudes: written when the file does not exist, otherwise compared
(column ``amp diff``, the largest difference of a DOF's amplitude relative to the largest
amplitude, the norm the steady state's tolerance is on; ``--check`` asserts it is at most 1e-10),
so that a faster marcher can show it finds the same orbits. The orbits of the code before issue
26's second session carried the rounding of its closed-form pieces, which grew like ``eps cond(K)``
with the chain (a period's march split at a time that is no event moved its end by 6.9e-12 of the
motion at n = 200, about 14 times that on the orbit of a map that contracts by 0.93 per period);
today's pieces move it by 1.7e-14, and against that code the amplitudes differ by up to 4.5e-11
at (200, 40). Usage::

    python benchmarks/scaling.py [--quick] [--sizes n:j,...] [--limit SECONDS] [--memory GB] [--out FILE]
                                 [--check] [--amplitudes FILE] [--family chain|DAMPING:STIFFNESS,...|all]
                                 [--baseline auto|loose|tight]
"""
from __future__ import annotations

import argparse
import math
import multiprocessing
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import scipy
from scipy.integrate import solve_ivp
from threadpoolctl import threadpool_limits

if __package__ in (None, ""):  # run as a script: the repository is not on the path, benchmarks/ is
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import frictionjoint as fj  # noqa: E402
from benchmarks.chains import DAMPINGS, chain, damped_chain  # noqa: E402
from frictionjoint.solvers.steady_state import BALANCE_START_SIZE  # noqa: E402

SIZES = ((20, 5), (50, 10), (100, 20), (200, 40), (400, 80))
QUICK = ((20, 5), (50, 10))
PERIODS = 20                        # the baseline's excitation periods from rest
TOLERANCES = (1e-6, 1e-9)           # the baseline's rtol, atol
TIGHT = (1e-10, 1e-12)              # the reference column's
# issue 26, for ``chain``: (n, joints, column, largest ratio to the baseline column's time)
TARGETS = ((100, 20, "cold", 0.5, "dop853"), (200, 40, "cold", 0.5, "dop853"), (200, 40, "hbm7", 0.05, "dop853"))
# issue 40, for every damping family, against the tight run ((20, 2) and (20, 5): issue 12's)
FAMILY_TARGETS = ((20, 2, "cold", 0.12, "tight"), (20, 5, "cold", 0.36, "tight"), (100, 20, "cold", 0.3, "tight"),
                  (200, 40, "cold", 0.5, "tight"), (400, 80, "cold", 1.0, "tight"), (200, 40, "hbm7", 0.05, "tight"))
FAMILY_MEMORY = ((400, 80, 4.0),)   # issue 40: (n, joints, GB resident of the cold steady state)
DEFAULT_FAMILY = "chain"
# --family all: today's chain, each damping form with joints as stiff as the structure, and the
# joints' stiffness from soft to 10 x the springs under stiffness-proportional damping
ALL_FAMILIES = ("chain",) + tuple(f"{d}:1" for d in DAMPINGS) + ("stiffness:soft", "stiffness:10")
BASELINES = {"loose": "dop853", "tight": "tight"}   # --baseline: the column that divides
SAME_ORBIT = 1e-10                  # amplitudes against a kept reference, relative to the largest
ENVIRONMENT = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
               "FRICTIONJOINT_BLAS_THREADS", "NUMBA_NUM_THREADS")


def parse_family(family: str) -> tuple[str, float | str] | None:
    """``--family``'s one family: None for ``chain``, else ``(damping, joint_stiffness)`` of
    ``chains.damped_chain``; ValueError with the allowed forms."""
    if family == "chain":
        return None
    damping, _, stiffness = family.partition(":")
    if damping not in DAMPINGS or not stiffness:
        raise ValueError(f"a family is 'chain' or DAMPING:JOINT_STIFFNESS with DAMPING one of {DAMPINGS}, "
                         f"got {family!r}")
    if stiffness == "soft":
        return damping, "soft"
    try:
        value = float(stiffness)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"a family's joint stiffness is a multiple > 0 of the springs or 'soft', got {family!r}")
    return damping, value


def build(family: str, n: int, joints: int) -> fj.FrictionSystem:
    """The system of ``family`` (see :func:`parse_family`) at size ``(n, joints)``."""
    parsed = parse_family(family)
    return chain(n, joints) if parsed is None else damped_chain(n, joints, *parsed)


def describe(family: str) -> str:
    """The family in words, for the table's header."""
    parsed = parse_family(family)
    if parsed is None:
        return ("chains.chain(n, joints): mass-proportional damping 1 % in mode 1, joints 0.5 w1^2, "
                "one slip force for all (0.3 x the largest stuck joint force)")
    damping, stiffness = parsed
    mode1 = "1 % of critical in the free chain's mode 1"
    forms = {"mass": f"C = alpha M, {mode1}", "stiffness": f"C = beta K, {mode1}",
             "rayleigh": "C = alpha M + beta K, 1 % of critical in the free chain's mode 1 and mode round(n/10) "
                         "(at least 2)",
             "modal": "C = M Phi diag(2 zeta w_i) Phi^T M, 1 % of critical in every mode of the free chain",
             "dashpot": f"C = alpha M, {mode1}, plus a dashpot 2 w1 from the tip to the ground (about 2/n more "
                        "in mode 1)"}
    joints = "0.5 w1^2" if stiffness == "soft" else f"{stiffness:g} x the chain's springs"
    return (f"chains.damped_chain(n, joints, {damping!r}, {stiffness!r}): {forms[damping]}; joints {joints}; "
            "each joint's slip force 0.3 x its own stuck force")


def baseline_key(family: str, baseline: str = "auto") -> str:
    """The column that divides the ratios: ``'dop853'`` (loose) or ``'tight'``; ``'auto'``: loose for
    ``chain`` (issue 26's), tight for the damping families (issue 40's)."""
    if baseline == "auto":
        return "dop853" if family == "chain" else "tight"
    return BASELINES[baseline]


def linear_stuck(system: fj.FrictionSystem):
    """State matrix ``A`` (2n, 2n) and the harmonic force's state vectors ``(g_cos, g_sin)`` of
    ``system`` with every slider stuck: ``z' = A z + g_cos cos(w t) + g_sin sin(w t)``, ``z = [x, v]``."""
    n = system.n_dof
    d = system.slider_direction
    k = system.stiffness + d.T @ (system.slider_stiffness[:, None] * d)
    m_inv = np.linalg.inv(system.mass)
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = -m_inv @ k
    a[n:, n:] = -m_inv @ system.damping
    g_cos, g_sin = np.zeros(2 * n), np.zeros(2 * n)
    g_cos[n:], g_sin[n:] = m_inv @ system.force_cos, m_inv @ system.force_sin
    return a, g_cos, g_sin


def dop853(system: fj.FrictionSystem, rtol: float, atol: float, periods: int = PERIODS):
    """Time [s] of DOP853 over ``periods`` excitation periods of the stuck linear chain from rest,
    and the final state (the matrices are built before the clock starts)."""
    a, g_cos, g_sin = linear_stuck(system)
    w = system.omega

    def rhs(t, z):
        return a @ z + g_cos * math.cos(w * t) + g_sin * math.sin(w * t)

    t_end = periods * 2 * math.pi / w
    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, t_end), np.zeros(2 * system.n_dof), method="DOP853", rtol=rtol, atol=atol,
                    t_eval=[t_end])  # only the end is kept: the steps of 800 states would fill the memory
    elapsed = time.perf_counter() - t0
    if not sol.success:
        raise RuntimeError(f"DOP853 failed: {sol.message}")
    return elapsed, sol.y[:, -1]


def _timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def measure(n: int, joints: int, send, family: str = DEFAULT_FAMILY, base: str = "dop853") -> None:
    """One size's row, column by column: ``send((key, value))`` as each is known (a worker's pipe);
    ``base``, the ratios' column, is measured before the steady states."""
    small = build(family, 6, 2)
    t_jit, _ = _timed(lambda: (fj.periodic_response(small), fj.harmonic_balance(build(family, 6, 2), n_harmonics=3)))
    send(("jit", t_jit))
    for h in (7, 15):  # the short columns first: a size past its limit loses the fewest
        fresh = build(family, n, joints)
        t_h, res = _timed(lambda: fj.harmonic_balance(fresh, n_harmonics=h))
        send((f"hbm{h}", t_h))
        send((f"hbm{h}_converged", bool(res.converged)))
    dop = {"dop853": TOLERANCES, "tight": TIGHT}
    send((base, dop853(build(family, n, joints), *dop[base])[0]))
    system = build(family, n, joints)
    send(("sliders", system.n_sliders))
    send(("rss", _peak_reset()))  # the worker's peak so far, then the cold steady state's own
    t_cold, cold = _timed(lambda: fj.periodic_response(system))
    send(("cold", t_cold))
    send(("cold_gb", _peak_reset()))
    send(("status", cold.status))
    send(("unique", bool(cold.unique)))
    send(("start", "balance" if "started from the harmonic-balance orbit" in cold.message else "rest"))
    send(("periods", float(cold.periods)))
    send(("events", len(cold.events)))
    send(("amplitude", np.asarray(cold.amplitude, dtype=float)))
    t_warm, warm = _timed(lambda: fj.periodic_response(system))
    send(("warm", t_warm))
    send(("warm_same", bool(np.array_equal(warm.amplitude, cold.amplitude))))
    with threadpool_limits(1):  # the library's own BLAS setting (frictionjoint.threads)
        send(("dop853_1", dop853(build(family, n, joints), *TOLERANCES)[0]))
    for key in dop.keys() - {base}:
        send((key, dop853(build(family, n, joints), *dop[key])[0]))


def _peak_reset() -> float:
    """This process's peak resident memory [GB] so far, and the peak reset to the present (Linux:
    ``/proc/self/clear_refs``; elsewhere the peak stays and NaN if unknown)."""
    peak = _rss(os.getpid())[1] or math.nan
    try:
        Path("/proc/self/clear_refs").write_text("5")
    except OSError:
        pass
    return peak


def _worker(n, joints, conn, family=DEFAULT_FAMILY, base="dop853"):
    try:
        measure(n, joints, conn.send, family, base)
    except Exception as exc:  # reported in the row, the next size goes on
        conn.send(("error", f"{type(exc).__name__}: {exc}"))
    finally:
        conn.close()


def _rss(pid: int) -> tuple[float, float]:
    """Resident and peak resident memory [GB] of process ``pid`` (Linux ``/proc``; 0 elsewhere)."""
    try:
        text = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return 0.0, 0.0
    kb = {ln.split(":")[0]: float(ln.split()[1]) for ln in text.splitlines() if ln.startswith(("VmRSS", "VmHWM"))}
    return kb.get("VmRSS", 0.0) / 1e6, kb.get("VmHWM", 0.0) / 1e6


def run_size(n: int, joints: int, limit: float, memory: float = math.inf, family: str = DEFAULT_FAMILY,
             baseline: str = "auto") -> dict:
    """``measure(n, joints)`` of ``family`` in a spawned worker for at most ``limit`` seconds and
    ``memory`` GB resident (the worker is ended beyond: (400, 80) took 24 GB and the whole machine's
    memory): what it finished, and its peak memory ``rss`` [GB] as last seen."""
    base = baseline_key(family, baseline)
    ctx = multiprocessing.get_context("spawn")
    receive, send = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_worker, args=(n, joints, send, family, base), daemon=True)
    proc.start()
    send.close()
    row = {"n": n, "joints": joints, "family": family, "baseline": base}
    deadline = time.perf_counter() + limit  # from the spawn: the worker's imports count, they are small
    try:
        while (left := deadline - time.perf_counter()) > 0:
            if receive.poll(min(left, 0.2)):
                try:
                    key, value = receive.recv()
                except EOFError:  # the worker is done (or died: its columns stay empty)
                    break
                row[key] = max(row.get(key, 0.0), value) if key == "rss" else value
            rss, peak = _rss(proc.pid)
            row["rss"] = max(row.get("rss", 0.0), peak)
            if rss > memory:
                row["memory"] = True
                break
        else:
            row["limit"] = True
    finally:
        proc.join(max(0.0, min(10.0, deadline - time.perf_counter())))  # done: it is exiting
        if proc.is_alive():
            proc.terminate()
            proc.join()
        receive.close()
    if proc.exitcode not in (0, None) and not ({"error", "limit", "memory"} & row.keys()):
        row["error"] = f"worker exit code {proc.exitcode}"
    return row


def growth(rows: list[dict], key: str, last: int | None = None) -> tuple[float, int]:
    """Least-squares slope of log(time) against log(n) over the rows where ``key`` finished (the
    ``last`` largest of them only, if given), and their count (NaN below two sizes)."""
    pts = sorted((r["n"], r[key]) for r in rows if isinstance(r.get(key), float))[-(last or 0):]
    if len(pts) < 2:
        return math.nan, len(pts)
    x, y = np.log([p[0] for p in pts]), np.log([p[1] for p in pts])
    return float(np.polyfit(x, y, 1)[0]), len(pts)


def _commit() -> str:
    root = Path(__file__).resolve().parents[1]
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=root, capture_output=True, text=True,
                              timeout=10).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "frictionjoint"], cwd=root,
                               capture_output=True, text=True, timeout=10).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return (head or "unknown") + (" with uncommitted changes in frictionjoint/" if dirty else "")


def _half_memory() -> float:
    try:
        return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2e9
    except (ValueError, OSError, AttributeError):
        return 8.0


def _load() -> str:
    try:
        return " ".join(f"{v:.1f}" for v in os.getloadavg())
    except OSError:
        return "unknown"


def header(args) -> list[str]:
    """The lines above every table: the machine, the software, the environment, the columns."""
    env = [f"{k}={os.environ[k]}" for k in ENVIRONMENT if k in os.environ]
    return [
        f"# benchmarks/scaling.py{' --quick' if args.quick else ''}: {platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} cores, Python {platform.python_version()}, NumPy {np.__version__}, SciPy "
        f"{scipy.__version__}, frictionjoint at {_commit()}, {time.strftime('%Y-%m-%d %H:%M')}",
        f"# environment: {', '.join(env) if env else 'no thread settings (library and NumPy defaults)'}; "
        f"one spawned worker per size, limit {args.limit:g} s and {args.memory:.3g} GB resident (GB: the "
        f"worker's peak, cold GB: the cold steady state's); load average {_load()} at the start",
        f"# DOP853: {PERIODS} periods from rest of the stuck linear chain, rtol={TOLERANCES[0]:g}, "
        f"atol={TOLERANCES[1]:g}; tight: rtol={TIGHT[0]:g}, atol={TIGHT[1]:g}; 1 thread: DOP853 with one BLAS "
        "thread (threadpoolctl), as the library runs",
        "# cold: periodic_response, first call on a new system (compiled kernels loaded before: jit, the "
        "process's first call on the family's 6-DOF chain); warm: second call on the same system; HBM7/15: "
        "harmonic_balance, one point, new system; start: where 'auto' started; times in s, (x) the ratio to "
        "the family's baseline",
    ]


def family_header(family: str, base: str) -> list[str]:
    """A family's table's first lines: the chains, and the run that divides the ratios."""
    tol = TOLERANCES if base == "dop853" else TIGHT
    name = "DOP853" if base == "dop853" else "tight"
    return [f"## family {family}: {describe(family)}",
            f"## baseline (the ratios' denominator): the {name} column, DOP853 over {PERIODS} periods from rest "
            f"of the stuck linear chain at rtol={tol[0]:g}, atol={tol[1]:g}"]


def _time(row, key, base=None):
    v = row.get(key)
    if isinstance(v, float):
        ratio = f" ({v / base:.3f})" if isinstance(base, float) and base > 0 else ""
        return f"{v:.3g}{ratio}"
    if row.get("limit") or row.get("memory"):
        return "> limit" if row.get("limit") else "> memory"
    return "error" if "error" in row else "-"


WIDTHS = (4, 6, 6, 8, 8, 8, 15, 15, 15, 15, 7, 9, 10, 8, 9, 7, 7)
NAMES = ("n", "joints", "jit", "DOP853", "1 thread", "tight", "cold", "warm", "HBM7", "HBM15", "periods",
         "ev/period", "status", "start", "amp diff", "GB", "cold GB")


def _line(cells) -> str:
    return " ".join(f"{c:>{w}}" for c, w in zip(cells, WIDTHS))


def _gb(row, key) -> str:
    v = row.get(key)
    return f"{v:.2f}" if isinstance(v, float) and v > 0 else "-"


def row_lines(r: dict, reference: dict | None) -> list[str]:
    """A size's line of the table, and a note under it when something went wrong."""
    base = r.get(r.get("baseline", "dop853"))
    periods = f"{r['periods']:.2f}" if "periods" in r else "-"
    events = str(r["events"]) if "events" in r else "-"
    lines = [_line((str(r["n"]), str(r.get("sliders", r["joints"])), _time(r, "jit"), _time(r, "dop853"),
                    _time(r, "dop853_1"), _time(r, "tight"), _time(r, "cold", base), _time(r, "warm", base),
                    _time(r, "hbm7", base), _time(r, "hbm15", base), periods, events, r.get("status", "-"),
                    r.get("start", "-"), _amp_diff(r, reference), _gb(r, "rss"), _gb(r, "cold_gb")))]
    notes = [f"HBM{h} not converged" for h in (7, 15) if r.get(f"hbm{h}_converged") is False]
    if r.get("unique") is False:
        notes.append("NOT UNIQUE: the orbit found is one of a family")
    if r.get("start") == "rest" and 2 * r["n"] + r.get("sliders", r["joints"]) > BALANCE_START_SIZE:
        notes.append("'auto' discarded the harmonic-balance start (not unique, not converged or stuck): from rest")
    if r.get("warm_same") is False:
        notes.append("warm amplitudes differ from cold")
    if "error" in r:
        notes.append(r["error"])
    if r.get("memory"):
        notes.append(f"the worker passed the memory limit ({r['rss']:.1f} GB resident at its peak)")
    if notes:
        lines.append(f"{'':>12}note: " + "; ".join(notes))
    return lines


def exponents(rows: list[dict]) -> list[str]:
    """The growth exponents' lines, under the table."""
    lines = []
    for last, title in ((None, "least squares of log time on log n over the sizes that finished"),
                        (2, "between the two largest sizes that finished (fixed costs weigh less)")):
        exps = []
        for key, name in (("cold", "cold"), ("warm", "warm"), ("hbm7", "HBM7"), ("hbm15", "HBM15"),
                          ("dop853", "DOP853"), ("dop853_1", "DOP853 1 thread"), ("tight", "DOP853 tight")):
            p, count = growth(rows, key, last)
            exps.append(f"{name} {p:.2f}" if count >= 2 else f"{name} -")
        lines += [f"growth exponents ({title}):", "  " + ", ".join(exps)]
    return lines


def amplitude_key(row: dict) -> str:
    """The row's name in ``--amplitudes``' file: ``n_joints`` for ``chain`` (the files kept before the
    families), ``family_n_joints`` with ``:`` as ``-`` for the others."""
    family = row.get("family", DEFAULT_FAMILY)
    prefix = "" if family == DEFAULT_FAMILY else family.replace(":", "-") + "_"
    return f"{prefix}{row['n']}_{row['joints']}"


def _amp_diff(row, reference):
    key = amplitude_key(row)
    if reference is None or key not in reference or "amplitude" not in row:
        return "-"
    ref = reference[key]
    if ref.shape != row["amplitude"].shape:
        return "shape"
    return f"{float(np.max(np.abs(row['amplitude'] - ref)) / np.max(np.abs(ref))):.1e}"


def targets(family: str) -> tuple:
    """``(n, joints, column, bound, baseline column)`` of the issue ``family`` answers to."""
    return TARGETS if family == DEFAULT_FAMILY else FAMILY_TARGETS


def _ratio_failures(rows: list[dict]) -> list[str]:
    failures = []
    for family in dict.fromkeys(r.get("family", DEFAULT_FAMILY) for r in rows):
        mine = [r for r in rows if r.get("family", DEFAULT_FAMILY) == family]
        tag = "" if family == DEFAULT_FAMILY else f"{family} "
        for n, joints, key, bound, base_key in targets(family):
            row = next((r for r in mine if (r["n"], r["joints"]) == (n, joints)), None)
            if row is None:
                continue
            t, base = row.get(key), row.get(base_key)
            name = "DOP853" if base_key == "dop853" else "tight DOP853"
            if not (isinstance(t, float) and isinstance(base, float)):
                failures.append(f"{tag}({n}, {joints}) {key}: not measured within the limit")
            elif t > bound * base:
                failures.append(f"{tag}({n}, {joints}) {key}: {t:.3g} s = {t / base:.3f} x {name} ({base:.3g} s), "
                                f"more than {bound:g} x")
        for n, joints, gb in FAMILY_MEMORY if family != DEFAULT_FAMILY else ():
            row = next((r for r in mine if (r["n"], r["joints"]) == (n, joints)), None)
            if row is not None and not row.get("cold_gb", math.inf) <= gb:
                failures.append(f"{tag}({n}, {joints}) memory: cold steady state {row.get('cold_gb', math.nan):.2f} "
                                f"GB resident, more than {gb:g} GB")
    return failures


def check(rows: list[dict], reference: dict | None) -> list[str]:
    """The targets of each row's family for the sizes run (issue 26's for ``chain``, issue 40's for
    the damping families): the failures, in words (empty: all met)."""
    failures = _ratio_failures(rows)
    for row in rows:
        family = row.get("family", DEFAULT_FAMILY)
        tag = "" if family == DEFAULT_FAMILY else f"{family} "
        if row.get("status", "periodic") != "periodic":
            failures.append(f"{tag}({row['n']}, {row['joints']}): periodic_response status {row['status']!r}")
        if family != DEFAULT_FAMILY and row.get("unique") is False:
            failures.append(f"{tag}({row['n']}, {row['joints']}): the orbit is not unique (slip forces per joint "
                            "should make it so)")
        diff = _amp_diff(row, reference)
        if diff != "-" and (diff == "shape" or not float(diff) <= SAME_ORBIT):
            failures.append(f"{tag}({row['n']}, {row['joints']}): amplitudes differ from the reference by {diff} "
                            f"(at most {SAME_ORBIT:g})")
    return failures


def _met(rows: list[dict]) -> str:
    """The check's verdict when nothing failed: which targets the sizes run were held to."""
    met = []
    for family in dict.fromkeys(r.get("family", DEFAULT_FAMILY) for r in rows):
        ran = {(r["n"], r["joints"]) for r in rows if r.get("family", DEFAULT_FAMILY) == family}
        tag = "" if family == DEFAULT_FAMILY else f"{family} "
        met += [f"{tag}({n}, {j}) {key} <= {bound:g} x {'DOP853' if b == 'dop853' else 'tight DOP853'}"
                for n, j, key, bound, b in targets(family) if (n, j) in ran]
        if family != DEFAULT_FAMILY:
            met += [f"{tag}({n}, {j}) cold <= {gb:g} GB" for n, j, gb in FAMILY_MEMORY if (n, j) in ran]
    return (f"check: met: {', '.join(met)}" if met else
            "check: none of the targets' sizes was run; statuses and amplitudes only")


def parse_args(argv=None) -> argparse.Namespace:
    """The command line, checked; ``sizes`` and ``families`` parsed."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="n = 20 and 50 only")
    parser.add_argument("--sizes", type=str, default=None,
                        help="sizes as n:joints,n:joints (default the n / joints = 5 family to 400)")
    parser.add_argument("--limit", type=float, default=600.0, help="seconds per size (default 600)")
    parser.add_argument("--memory", type=float, default=_half_memory(),
                        help="GB resident per size (default half of this machine's memory)")
    parser.add_argument("--out", type=Path, default=None, help="also write the table to this file")
    parser.add_argument("--check", action="store_true", help="exit 1 unless the families' targets are met")
    parser.add_argument("--amplitudes", type=Path, default=None,
                        help=".npz of the steady states' amplitudes: written if absent, else compared")
    parser.add_argument("--family", type=str, default=DEFAULT_FAMILY,
                        help="chain (default, chains.chain), DAMPING:JOINT_STIFFNESS with DAMPING one of "
                             f"{', '.join(DAMPINGS)} and JOINT_STIFFNESS a multiple of the springs or soft "
                             f"(0.5 w1^2), several separated by commas, or all ({', '.join(ALL_FAMILIES)})")
    parser.add_argument("--baseline", choices=("auto",) + tuple(BASELINES), default="auto",
                        help="the ratios' DOP853 run: auto (loose for chain, tight for the damping families), "
                             "loose or tight")
    args = parser.parse_args(argv)
    if args.limit <= 0:
        parser.error(f"--limit must be > 0 seconds, got {args.limit}")
    if args.memory <= 0:
        parser.error(f"--memory must be > 0 GB, got {args.memory}")
    if args.sizes:
        try:
            args.sizes = tuple(tuple(int(v) for v in s.split(":")) for s in args.sizes.split(","))
        except ValueError:
            parser.error(f"--sizes must read n:joints,n:joints, got {args.sizes!r}")
        if any(len(s) != 2 or s[0] < 2 or s[1] < 1 for s in args.sizes):
            parser.error(f"--sizes: each size is n:joints with n >= 2 and joints >= 1, got {args.sizes!r}")
    else:
        args.sizes = QUICK if args.quick else SIZES
    args.families = ALL_FAMILIES if args.family == "all" else tuple(dict.fromkeys(args.family.split(",")))
    for family in args.families:
        try:
            parse_family(family)
        except ValueError as exc:
            parser.error(f"--family: {exc}")
    return args


def main(argv=None) -> int:
    args = parse_args(argv)
    reference = None
    if args.amplitudes is not None and args.amplitudes.exists():
        with np.load(args.amplitudes) as f:
            reference = {k: f[k] for k in f.files}
    lines = header(args)
    print("\n".join(lines), flush=True)
    rows = []
    for family in args.families:
        block = family_header(family, baseline_key(family, args.baseline)) + [_line(NAMES)]
        print("\n".join(block), flush=True)
        mine = []
        for n, joints in args.sizes:
            mine.append(run_size(n, joints, args.limit, args.memory, family, args.baseline))
            block += row_lines(mine[-1], reference)
            print("\n".join(row_lines(mine[-1], reference)), flush=True)  # the row as soon as it is known
        block += exponents(mine)
        print("\n".join(exponents(mine)), flush=True)
        lines += block
        rows += mine
    lines.append(f"load average {_load()} at the end")
    print(lines[-1])
    if args.amplitudes is not None and reference is None:
        np.savez(args.amplitudes, **{amplitude_key(r): r["amplitude"] for r in rows if "amplitude" in r})
        print(f"amplitudes written to {args.amplitudes}")
    if args.out is not None:
        args.out.write_text("\n".join(lines) + "\n")
        print(f"wrote {args.out}")
    if args.check:
        failures = check(rows, reference)
        for f in failures:
            print(f"check failed: {f}", file=sys.stderr)
        if failures:
            return 1
        print(_met(rows))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
