"""Studies on more workers: speed-up on this machine and the per-point overhead of each executor,
as ratios measured in this process.

1. Speed-up: one study (the blade on its dovetail at 8 root loads, 12 frequencies each, peaks
   refined) serially, on the local process pool with 2 workers, and on a Dask LocalCluster with 2
   worker processes; wall time and the ratio to the serial run. The pool's and the cluster's start
   are inside their runs (the pool is started per study; the cluster is started before and its
   start is reported apart).
2. The machine's parallel capacity: one point alone, and the same point twice at once in two
   processes (on 2 shared cores two processes need not run at twice the throughput of one).
3. Overhead per point: studies of points that fail at once (a root load outside its range: the
   row is written with its error, no sweep), 100 and 300 points; the slope (time difference over
   200 points) is the per-point cost of each executor (task, transport, row, journal), without its
   start.

Usage::

    python benchmarks/study_scaling.py [--quick]
"""
from __future__ import annotations

import argparse
import multiprocessing
import os
import platform
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from frictionjoint.study import Grid, Study, Values, evaluate_point, run_study
from frictionjoint.study.execution import tasks


def _timed(study, table, **kw) -> float:
    t0 = time.perf_counter()
    run_study(study, table, restart=True, **kw)
    return time.perf_counter() - t0


def _list_schedule(cost, workers: int) -> float:
    """Makespan of the points in point order on ``workers`` idle workers, each taking the next
    point when it is free (what a pool and Dask do), without any overhead: the best a run can do."""
    free = [0.0] * workers
    for c in cost:
        k = int(np.argmin(free))
        free[k] += c
    return max(free)


def main(argv=None) -> int:
    from distributed import LocalCluster

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="4 loads, 6 frequencies")
    args = parser.parse_args(argv)
    n_loads, n_w = (4, 6) if args.quick else (8, 12)
    work = Study(model="ti64_compressor_blade", omega=f"1950:2100:{n_w}",
                 vary={"centrifugal_force": Grid(50.0, 1500.0, n_loads, "log")})

    def null(n):  # points that fail at once: the executor's own cost per point
        return Study(model="ti64_compressor_blade", omega="1950:2100:2",
                     vary={"centrifugal_force": Values(tuple(-1.0 - np.arange(n)))})

    lines = [f"# benchmarks/study_scaling.py{' --quick' if args.quick else ''}: {platform.machine()}, "
             f"{os.cpu_count()} cores, {time.strftime('%Y-%m-%d')}"]
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        stamps = [time.perf_counter()]  # serial: the rows come one after the other, their gaps are the points' costs
        t_serial = _timed(work, tmp / "s.csv", workers=1, on_row=lambda row: stamps.append(time.perf_counter()))
        cost = np.diff(stamps)
        bound = _list_schedule(cost, 2)
        t_pool = _timed(work, tmp / "p.csv", workers=2)
        t0 = time.perf_counter()
        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cl:
            t_start = time.perf_counter() - t0
            _timed(null(2), tmp / "warm.csv", scheduler=cl.scheduler_address)  # the workers import the library
            t_dask = _timed(work, tmp / "d.csv", scheduler=cl.scheduler_address)
            d_small = _timed(null(100), tmp / "d1.csv", scheduler=cl.scheduler_address)
            d_large = _timed(null(300), tmp / "d2.csv", scheduler=cl.scheduler_address)
        same = (tmp / "s.csv").read_bytes() == (tmp / "p.csv").read_bytes() == (tmp / "d.csv").read_bytes()
        s_small, s_large = _timed(null(100), tmp / "n1.csv", workers=1), _timed(null(300), tmp / "n2.csv", workers=1)
        p_small, p_large = _timed(null(100), tmp / "p1.csv", workers=2), _timed(null(300), tmp / "p2.csv", workers=2)
    # the machine's own parallel capacity: one point alone against the same point twice at once,
    # in two warm worker processes (2 shared cores need not give 2x)
    one = tasks(Study(model="ti64_compressor_blade", omega=f"1950:2100:{n_w}",
                      vary={"centrifugal_force": Values((259.0,))}))[0]
    with ProcessPoolExecutor(2, mp_context=multiprocessing.get_context("spawn")) as ex:
        list(ex.map(evaluate_point, [one, one]))
        t0 = time.perf_counter()
        list(ex.map(evaluate_point, [one]))
        t_one = time.perf_counter() - t0
        t0 = time.perf_counter()
        list(ex.map(evaluate_point, [one, one]))
        t_two = time.perf_counter() - t0
    n = n_loads
    lines += [
        f"machine: one point alone {t_one:.2f} s, two at once {t_two:.2f} s: {2 * t_one / t_two:.2f}x the throughput "
        "of one process (the most any run on 2 workers can gain)",
        f"study: blade on its dovetail, {n} root loads x {n_w} frequencies, peaks refined",
        f"  serial          {t_serial:7.2f} s  (points from {cost.min():.2f} to {cost.max():.2f} s)",
        f"  best possible on 2 workers (the points' costs scheduled in order, no overhead): {bound:.2f} s, "
        f"speed-up {t_serial / bound:.2f}x",
        f"  pool, 2 workers {t_pool:7.2f} s  speed-up {t_serial / t_pool:.2f}x, {bound / t_pool:.0%} of the best "
        "(the pool's start included)",
        f"  Dask, 2 workers {t_dask:7.2f} s  speed-up {t_serial / t_dask:.2f}x, {bound / t_dask:.0%} of the best "
        f"(cluster started before: {t_start:.1f} s)",
        f"  tables byte-identical: {same}",
        "overhead per point (slope over 200 points that fail at once), and the ratio to the pool's",
    ]
    per = {"serial": (s_large - s_small) / 200, "pool": (p_large - p_small) / 200, "Dask": (d_large - d_small) / 200}
    for name, v in per.items():
        lines.append(f"  {name:6s} {v * 1e3:7.2f} ms per point  ({v / per['pool']:.2f}x the pool's)")
    text = "\n".join(lines)
    print(text)
    if not args.quick:
        out = Path(__file__).with_name("results_study.txt")
        out.write_text(text + "\n")
        print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
