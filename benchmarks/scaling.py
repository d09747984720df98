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

Each size has ``--limit`` seconds and ``--memory`` GB resident (default half the machine's: the
cold steady state of (400, 80) grew to 24 GB and was killed by the kernel); a column that has not
finished by then reads ``> limit`` (``> memory``) and the next size starts; ``GB`` is the worker's
peak resident memory as last seen. Under the table: the growth exponent of each column, the
least-squares slope of ``log(time)`` against ``log(n)`` over the sizes that finished, and the same
between the two largest (where fixed costs weigh less). ``--check`` asserts issue 26's
ratios for the sizes run: cold ``periodic_response`` at (100, 20) and (200, 40) at most 0.5 x the
baseline, ``harmonic_balance`` at ``H = 7`` at (200, 40) at most 0.05 x. ``--amplitudes FILE``
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
                                 [--check] [--amplitudes FILE]
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
from benchmarks.chains import chain  # noqa: E402

SIZES = ((20, 5), (50, 10), (100, 20), (200, 40), (400, 80))
QUICK = ((20, 5), (50, 10))
PERIODS = 20                        # the baseline's excitation periods from rest
TOLERANCES = (1e-6, 1e-9)           # the baseline's rtol, atol
TIGHT = (1e-10, 1e-12)              # the reference column's
# issue 26: (n, joints, column, largest ratio to the baseline)
TARGETS = ((100, 20, "cold", 0.5), (200, 40, "cold", 0.5), (200, 40, "hbm7", 0.05))
SAME_ORBIT = 1e-10                  # amplitudes against a kept reference, relative to the largest
ENVIRONMENT = ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
               "FRICTIONJOINT_BLAS_THREADS", "NUMBA_NUM_THREADS")


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


def measure(n: int, joints: int, send) -> None:
    """One size's row, column by column: ``send((key, value))`` as each is known (a worker's pipe)."""
    t_jit, _ = _timed(lambda: (fj.periodic_response(chain(6, 2)), fj.harmonic_balance(chain(6, 2), n_harmonics=3)))
    send(("jit", t_jit))
    for h in (7, 15):  # the short columns first: a size past its limit loses the fewest
        fresh = chain(n, joints)
        t_h, res = _timed(lambda: fj.harmonic_balance(fresh, n_harmonics=h))
        send((f"hbm{h}", t_h))
        send((f"hbm{h}_converged", bool(res.converged)))
    send(("dop853", dop853(chain(n, joints), *TOLERANCES)[0]))
    system = chain(n, joints)
    send(("sliders", system.n_sliders))
    t_cold, cold = _timed(lambda: fj.periodic_response(system))
    send(("cold", t_cold))
    send(("status", cold.status))
    send(("periods", float(cold.periods)))
    send(("events", len(cold.events)))
    send(("amplitude", np.asarray(cold.amplitude, dtype=float)))
    t_warm, warm = _timed(lambda: fj.periodic_response(system))
    send(("warm", t_warm))
    send(("warm_same", bool(np.array_equal(warm.amplitude, cold.amplitude))))
    with threadpool_limits(1):  # the library's own BLAS setting (frictionjoint.threads)
        send(("dop853_1", dop853(chain(n, joints), *TOLERANCES)[0]))
    send(("tight", dop853(chain(n, joints), *TIGHT)[0]))


def _worker(n, joints, conn):
    try:
        measure(n, joints, conn.send)
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


def run_size(n: int, joints: int, limit: float, memory: float = math.inf) -> dict:
    """``measure(n, joints)`` in a spawned worker for at most ``limit`` seconds and ``memory`` GB
    resident (the worker is ended beyond: (400, 80) took 24 GB and the whole machine's memory): what
    it finished, and its peak memory ``rss`` [GB] as last seen."""
    ctx = multiprocessing.get_context("spawn")
    receive, send = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_worker, args=(n, joints, send), daemon=True)
    proc.start()
    send.close()
    row = {"n": n, "joints": joints}
    deadline = time.perf_counter() + limit  # from the spawn: the worker's imports count, they are small
    try:
        while (left := deadline - time.perf_counter()) > 0:
            if receive.poll(min(left, 0.2)):
                try:
                    key, value = receive.recv()
                except EOFError:  # the worker is done (or died: its columns stay empty)
                    break
                row[key] = value
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
    env = [f"{k}={os.environ[k]}" for k in ENVIRONMENT if k in os.environ]
    return [
        f"# benchmarks/scaling.py{' --quick' if args.quick else ''}: {platform.processor() or platform.machine()}, "
        f"{os.cpu_count()} cores, Python {platform.python_version()}, NumPy {np.__version__}, SciPy "
        f"{scipy.__version__}, frictionjoint at {_commit()}, {time.strftime('%Y-%m-%d %H:%M')}",
        f"# environment: {', '.join(env) if env else 'no thread settings (library and NumPy defaults)'}; "
        f"one spawned worker per size, limit {args.limit:g} s and {args.memory:.3g} GB resident (GB: the "
        f"worker's peak); load average {_load()} at the start",
        f"# chains.chain(n, joints); baseline DOP853 (ratios' denominator): {PERIODS} periods from rest of the "
        f"stuck linear chain, rtol={TOLERANCES[0]:g}, atol={TOLERANCES[1]:g}; tight: rtol={TIGHT[0]:g}, "
        f"atol={TIGHT[1]:g}, and 1 thread: the baseline with one BLAS thread (threadpoolctl), as the library "
        "runs (both for reference only)",
        "# cold: periodic_response, first call on a new system (compiled kernels loaded before: jit, the "
        "process's first call on a 6-DOF chain); warm: second call on the same system; HBM7/15: "
        "harmonic_balance, one point, new system; times in s, (x) the ratio to DOP853",
    ]


def _time(row, key, base=None):
    v = row.get(key)
    if isinstance(v, float):
        ratio = f" ({v / base:.3f})" if isinstance(base, float) and base > 0 else ""
        return f"{v:.3g}{ratio}"
    if row.get("limit") or row.get("memory"):
        return "> limit" if row.get("limit") else "> memory"
    return "error" if "error" in row else "-"


WIDTHS = (4, 6, 6, 8, 8, 8, 15, 15, 15, 15, 7, 9, 10, 9, 7)
NAMES = ("n", "joints", "jit", "DOP853", "1 thread", "tight", "cold", "warm", "HBM7", "HBM15", "periods",
         "ev/period", "status", "amp diff", "GB")


def _line(cells) -> str:
    return " ".join(f"{c:>{w}}" for c, w in zip(cells, WIDTHS))


def row_lines(r: dict, reference: dict | None) -> list[str]:
    """A size's line of the table, and a note under it when something went wrong."""
    base = r.get("dop853")
    periods = f"{r['periods']:.2f}" if "periods" in r else "-"
    events = str(r["events"]) if "events" in r else "-"
    lines = [_line((str(r["n"]), str(r.get("sliders", r["joints"])), _time(r, "jit"), _time(r, "dop853"),
                    _time(r, "dop853_1"), _time(r, "tight"), _time(r, "cold", base), _time(r, "warm", base),
                    _time(r, "hbm7", base), _time(r, "hbm15", base), periods, events, r.get("status", "-"),
                    _amp_diff(r, reference), f"{r['rss']:.2f}" if r.get("rss") else "-"))]
    notes = [f"HBM{h} not converged" for h in (7, 15) if r.get(f"hbm{h}_converged") is False]
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


def _amp_diff(row, reference):
    key = f"{row['n']}_{row['joints']}"
    if reference is None or key not in reference or "amplitude" not in row:
        return "-"
    ref = reference[key]
    if ref.shape != row["amplitude"].shape:
        return "shape"
    return f"{float(np.max(np.abs(row['amplitude'] - ref)) / np.max(np.abs(ref))):.1e}"


def check(rows: list[dict], reference: dict | None) -> list[str]:
    """Issue 26's targets for the sizes run: the failures, in words (empty: all met)."""
    failures = []
    for n, joints, key, bound in TARGETS:
        row = next((r for r in rows if (r["n"], r["joints"]) == (n, joints)), None)
        if row is None:
            continue
        t, base = row.get(key), row.get("dop853")
        if not (isinstance(t, float) and isinstance(base, float)):
            failures.append(f"({n}, {joints}) {key}: not measured within the limit")
        elif t > bound * base:
            failures.append(f"({n}, {joints}) {key}: {t:.3g} s = {t / base:.3f} x DOP853 ({base:.3g} s), "
                            f"more than {bound:g} x")
    for row in rows:
        if row.get("status", "periodic") != "periodic":
            failures.append(f"({row['n']}, {row['joints']}): periodic_response status {row['status']!r}")
        diff = _amp_diff(row, reference)
        if diff != "-" and (diff == "shape" or not float(diff) <= SAME_ORBIT):
            failures.append(f"({row['n']}, {row['joints']}): amplitudes differ from the reference by {diff} "
                            f"(at most {SAME_ORBIT:g})")
    return failures


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="n = 20 and 50 only")
    parser.add_argument("--sizes", type=str, default=None,
                        help="sizes as n:joints,n:joints (default the n / joints = 5 family to 400)")
    parser.add_argument("--limit", type=float, default=600.0, help="seconds per size (default 600)")
    parser.add_argument("--memory", type=float, default=_half_memory(),
                        help="GB resident per size (default half of this machine's memory)")
    parser.add_argument("--out", type=Path, default=None, help="also write the table to this file")
    parser.add_argument("--check", action="store_true", help="exit 1 unless issue 26's ratios are met")
    parser.add_argument("--amplitudes", type=Path, default=None,
                        help=".npz of the steady states' amplitudes: written if absent, else compared")
    args = parser.parse_args(argv)
    if args.limit <= 0:
        parser.error(f"--limit must be > 0 seconds, got {args.limit}")
    if args.memory <= 0:
        parser.error(f"--memory must be > 0 GB, got {args.memory}")
    if args.sizes:
        try:
            sizes = tuple(tuple(int(v) for v in s.split(":")) for s in args.sizes.split(","))
        except ValueError:
            parser.error(f"--sizes must read n:joints,n:joints, got {args.sizes!r}")
        if any(len(s) != 2 or s[0] < 2 or s[1] < 1 for s in sizes):
            parser.error(f"--sizes: each size is n:joints with n >= 2 and joints >= 1, got {args.sizes!r}")
    else:
        sizes = QUICK if args.quick else SIZES
    reference = None
    if args.amplitudes is not None and args.amplitudes.exists():
        with np.load(args.amplitudes) as f:
            reference = {k: f[k] for k in f.files}
    lines = header(args) + [_line(NAMES)]
    print("\n".join(lines), flush=True)
    rows = []
    for n, joints in sizes:
        rows.append(run_size(n, joints, args.limit, args.memory))
        lines += row_lines(rows[-1], reference)
        print("\n".join(row_lines(rows[-1], reference)), flush=True)  # the row as soon as it is known
    lines += exponents(rows) + [f"load average {_load()} at the end"]
    print("\n".join(lines[-5:]))
    if args.amplitudes is not None and reference is None:
        np.savez(args.amplitudes, **{f"{r['n']}_{r['joints']}": r["amplitude"] for r in rows if "amplitude" in r})
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
        ran = {(r["n"], r["joints"]) for r in rows}
        checked = [f"({n}, {j}) {key} <= {bound:g} x DOP853" for n, j, key, bound in TARGETS if (n, j) in ran]
        print(f"check: met: {', '.join(checked)}" if checked else
              "check: none of issue 26's sizes (100, 20), (200, 40) was run; statuses and amplitudes only")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
