"""The whole-system FMU as FMI 3.0 with early return, under an FMI 3 importer, against the exact answer.

The README's chain as one FMU (models/two_dof_chain_system.toml: models/two_dof_chain.toml with a
Jenkins joint at each mass, kt = 100 N/m, Fs = 0.8 N, 1 N cos(1.2 t) on DOF 2), built as FMI 3.0
(``build_fmus(systems=..., fmi_version=3)``: early return just after each stick/slip event), from rest
over four periods, communication steps T/20 to T/400, run by fmpy 0.3 as the FMI 3 host:

- "host loop": a host on fmpy's FMU3Slave that steps to the grid ``n T/d`` and continues from each
  early return (the FMU loaded once; each run resets the instance, initialises it and steps; best
  of 3 after a first run, "first": the first run with the FMU's loading and the first import of its
  bundled library); "host loop, no early return" the same without the host's permission (whole
  steps: the events are located inside them all the same);
- "simulate_fmu": ``fmpy.simulate_fmu(early_return_allowed=True)`` as it does it (extract,
  instantiate, run, free, every call), timed inside a fresh process without its start ("first", as
  benchmarks/cosim_coupling.py times its simulate_fmu rows) and the best of 3 more calls in that
  process ("time").

Error: the largest deviation over the communication points of each DOF's displacement from
fj.simulate of the file's FrictionSystem at the same times, relative to that DOF's amplitude, the
worse DOF; "early": the early returns of a run (fj.simulate's events after the start: 31); "exact":
fj.simulate on the same times, after a first call, best of 5; "cost": time / exact. Usage::

    python benchmarks/fmi3_system.py [--out DIR]   # DIR: also write results_fmi3_system.txt there
"""
from __future__ import annotations

import argparse
import json
import math
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

if __package__ in (None, ""):  # run as a script: the repository is not on the path, benchmarks/ is
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.cosim_coupling import exact  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CHAIN = ROOT / "models" / "two_dof_chain_system.toml"
OMEGA, PERIODS, DIVISIONS = 1.2, 4, (20, 50, 100, 200, 400)
T = 2 * math.pi / OMEGA
OUT = ["x_x1", "x_x2"]
REPEAT = 3


def host_loop(slave, vr: dict, d: int, allowed: bool, first: bool) -> tuple:
    """One run of the FMU3Slave ``slave`` (reset unless ``first``) stepped to ``n T/d``, continuing from
    early returns: (grid times, {output: values}, early returns)."""
    if not first:
        slave.reset()
    slave.enterInitializationMode(startTime=0.0)
    slave.exitInitializationMode()
    h = T / d
    refs = [vr[o] for o in OUT]
    t, n, early, rows = 0.0, 0, 0, []
    while n < PERIODS * d:
        target = (n + 1) * h
        returned, last = slave.doStep(t, target - t)[2:]
        if returned and allowed:
            t, early = last, early + 1
            continue
        t, n = target, n + 1
        rows.append(slave.getFloat64(refs))
    slave.terminate()
    values = np.array(rows).T
    return h * np.arange(1, PERIODS * d + 1), dict(zip(OUT, values)), early


def host_loop_rows(path: Path, allowed: bool):
    """``run(d) -> (t, values, early returns, time, first)`` of the host loop, the FMU loaded once."""
    from fmpy import extract, instantiate_fmu, read_model_description

    md = read_model_description(str(path))
    folder = extract(str(path))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    state = {"slave": None}

    def run(d):
        t0 = time.perf_counter()
        if state["slave"] is None:
            state["slave"] = instantiate_fmu(folder, md, fmi_type="CoSimulation", early_return_allowed=allowed)
            result = host_loop(state["slave"], vr, d, allowed, first=True)
        else:
            result = host_loop(state["slave"], vr, d, allowed, first=False)
        first = time.perf_counter() - t0
        best = math.inf
        for _ in range(REPEAT):
            t0 = time.perf_counter()
            host_loop(state["slave"], vr, d, allowed, first=False)
            best = min(best, time.perf_counter() - t0)
        return (*result, best, first)
    return run


def simulate_fmu_rows(path: Path):
    """``run(d)`` of simulate_fmu in a fresh process (:func:`run_job`)."""
    def run(d):
        proc = subprocess.run([sys.executable, __file__, "--run", json.dumps(dict(path=str(path), d=d))],
                              capture_output=True, text=True, timeout=600)
        if proc.returncode != 0:
            raise RuntimeError(proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else str(proc.returncode))
        r = json.loads(proc.stdout.strip().splitlines()[-1])
        return np.asarray(r["t"]), {o: np.asarray(v) for o, v in r["values"].items()}, r["early"], r["time"], r["first"]
    return run


def run_job(job: dict) -> dict:
    """The ``--run`` side of :func:`simulate_fmu_rows`: the first call's time, the best of
    :data:`REPEAT` more, the grid rows (the last row at each ``n T/d``) and the rows between them
    (early returns)."""
    from fmpy import simulate_fmu

    def call():
        return simulate_fmu(job["path"], stop_time=PERIODS * T, output_interval=T / job["d"],
                            early_return_allowed=True, output=OUT)

    t0 = time.perf_counter()
    r = call()
    first = time.perf_counter() - t0
    best = math.inf
    for _ in range(REPEAT):
        t0 = time.perf_counter()
        call()
        best = min(best, time.perf_counter() - t0)
    h = T / job["d"]
    t = np.asarray(r["time"])
    n = np.rint(t / h)
    on = (np.abs(t - n * h) <= 1e-9 * T) & (n >= 1)
    last = [int(np.flatnonzero(on & (n == k))[-1]) for k in range(1, PERIODS * job["d"] + 1)]
    early = len({float(tk) for tk in t[~on] if tk > 0.0})
    return dict(t=t[last].tolist(), values={o: r[o][last].tolist() for o in OUT}, early=early, time=best,
                first=first)


def main(out_dir: str | None) -> None:
    from frictionjoint.fmi.build import build_fmus
    from frictionjoint.system_file import load_system_definition

    lines = [f"# {platform.node()} {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
             f"Python {platform.python_version()}; the chain as one FMI 3.0 FMU, four periods from rest",
             f"{'host (fmpy 0.3, FMI 3)':30s} {'step':>6s} {'error':>9s} {'early':>5s} {'time [s]':>8s} "
             f"{'first [s]':>9s} {'exact [s]':>9s} {'cost':>6s}"]
    print("\n".join(lines), flush=True)
    system = load_system_definition(CHAIN).system()
    with tempfile.TemporaryDirectory() as tmp:
        (path,) = build_fmus(tmp, systems=[CHAIN], fmi_version=3)
        rows = [("host loop, early return", host_loop_rows(path, True)),
                ("host loop, no early return", host_loop_rows(path, False)),
                ("simulate_fmu, early return", simulate_fmu_rows(path))]
        for name, run in rows:
            for d in DIVISIONS:
                t, values, early, seconds, first = run(d)
                ref, ref_time = exact(system, np.concatenate([[0.0], t]))
                x = np.vstack([values[o] for o in OUT])
                err = float((np.max(np.abs(x - ref[:, 1:]), axis=1) / np.max(np.abs(ref), axis=1)).max())
                lines.append(f"{name:30s} {'T/' + str(d):>6s} {err:9.2e} {early:5d} {seconds:8.4f} {first:9.4f} "
                             f"{ref_time:9.4f} {seconds / ref_time:6.1f}")
                print(lines[-1], flush=True)
    if out_dir is not None:
        os.makedirs(out_dir, exist_ok=True)
        Path(out_dir, "results_fmi3_system.txt").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=None, help="folder for results_fmi3_system.txt (none: print only)")
    ap.add_argument("--run", help=argparse.SUPPRESS)  # one simulate_fmu job in this process
    args = ap.parse_args()
    if args.run:
        print(json.dumps(run_job(json.loads(args.run))), flush=True)
    else:
        main(args.out)
