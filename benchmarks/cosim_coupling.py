"""Co-simulation of a system of FMUs against the exact answer of the same model.

The case of the README (models/two_dof_chain.toml as LinearStructure.fmu, two JenkinsJoint.fmu
instances with their defaults kt = 100 N/m, Fs = 0.8 N, 1 N cos(1.2 t) on DOF 2, from rest, four
periods) through:

- this library's master (fmpy, all FMUs in this process), sequential transfer
  (``structure.x -> joint.u`` before ``joint.force -> structure``) and Jacobi transfer;
- Ecos (its library, in its own process; Jacobi, as its command line);
- libcosim (libcosimpy, in its own process; Jacobi: its fixed-step algorithm steps every FMU, then
  transfers every connection);

with semi-implicit coupling (the joints' tangent stiffness and evaluation point passed to the
structure) and explicit coupling (force held), the joints' velocity not connected
(``joint_connections(..., events=False)``; the rows with it connected are rerun by
tests/test_cosim.py::test_the_guide_table_rows); this master with the events located across the
FMUs (``locate_events=True``, the joints' velocity connected: ``joint_connections(...,
events=True)``), both transfers; and the whole system as one FMU (models/two_dof_chain_system.toml,
``build_fmus(systems=...)``: its events located inside each doStep) under fmpy's simulate_fmu (its
own process), Ecos and libcosim. Steps T/20 to T/400; libcosim's are T/d rounded to whole
nanoseconds (its clock), and its runs are compared at its own times, Ecos's at Ecos's.

Error: the largest deviation over all communication points of each DOF from the library's exact
event-driven solution (FrictionSystem + simulate) at the same times, relative to that DOF's
amplitude; the table gives the worse DOF and the observed order between neighbouring steps. Cost:
the wall time of a run ("time"; this master: with its FMUs loaded by a first run, which an
FMUSystem keeps, best of three; the other hosts load the FMUs in every run: Ecos with its
process's start, most of its 1.4 s at T/20; fmpy's simulate_fmu and libcosim timed inside their
process, without its start), the first run's ("first": this master loading its FMUs), the exact
solution's (fj.simulate on the same times, after a first call, best of 5) and the ratio of the
run's to the exact solution's ("cost").
Usage:

    python benchmarks/cosim_coupling.py [--out DIR]
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

ROOT = Path(__file__).resolve().parents[1]
OMEGA, PERIODS, DIVISIONS = 1.2, 4, (20, 50, 100, 200, 400)
T = 2 * math.pi / OMEGA
OUT = ["chain.x_x1", "chain.x_x2"]


def exact_system():
    """The chain with its two Jenkins joints in the library (the exact solution's system)."""
    import frictionjoint as fj
    from frictionjoint.structure_file import load_structure_definition

    definition = load_structure_definition(ROOT / "models" / "two_dof_chain.toml")
    return fj.FrictionSystem(definition.structure, [fj.Jenkins(100.0, 0.8, dof="x1"), fj.Jenkins(100.0, 0.8, dof="x2")],
                             omega=OMEGA, excitation=[fj.HarmonicForce("x2", 1.0)])


def own_process(host: str, comps: dict, connections: list, d: int) -> dict:
    """One run of ``host`` ("fmpy": simulate_fmu of the single component; "libcosim") in a fresh
    Python (this script, ``--run``): ``{"t", "values", "time"}``. A fresh process, so that each
    host's time is its own (the FMUs' import of their bundled library included); it was also needed
    before the FMUs' loader (``frictionjoint.fmi.bundle_loader``), when a process that had freed one
    FMU could not import another's modules."""
    job = dict(host=host, components={k: str(v) for k, v in comps.items()}, connections=connections, d=d)
    proc = subprocess.run([sys.executable, __file__, "--run", json.dumps(job)], capture_output=True, text=True,
                          timeout=600)
    if proc.returncode != 0:
        raise RuntimeError(proc.stderr.strip().splitlines()[-1] if proc.stderr.strip() else str(proc.returncode))
    return json.loads(proc.stdout.strip().splitlines()[-1])


def run_job(job: dict) -> dict:
    """The ``--run`` side of :func:`own_process`."""
    n = job["d"] * PERIODS
    if job["host"] == "fmpy":
        from fmpy import simulate_fmu

        (path,) = job["components"].values()
        t0 = time.perf_counter()
        r = simulate_fmu(path, stop_time=PERIODS * T, output_interval=T / job["d"], output=[o[6:] for o in OUT])
        elapsed = time.perf_counter() - t0
        return dict(t=r["time"].tolist(), values={o: r[o[6:]].tolist() for o in OUT}, time=elapsed)
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.WARNING)
    step_ns = round(T / job["d"] * 1e9)
    t0 = time.perf_counter()
    ex = CosimExecution.from_step_size(step_ns)
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    idx, vr = {}, {}
    for name, path in job["components"].items():
        idx[name] = ex.add_local_slave(CosimLocalSlave(fmu_path=path, instance_name=name))
        vr[name] = {v.name.decode(): v.reference for v in ex.slave_variables(idx[name])}
    for source, target in job["connections"]:
        (a, out), (b, inp) = source.split(".", 1), target.split(".", 1)
        if ex.connect_real_variables(idx[a], vr[a][out], idx[b], vr[b][inp]) != 0:
            raise RuntimeError(f"libcosim did not connect {source} -> {target}")
    ports = [o.split(".", 1) for o in OUT]
    rows = []
    for _ in range(n):
        if not ex.step():
            raise RuntimeError(f"libcosim step failed at {ex.status().current_time} ns")
        rows.append([obs.last_real_values(idx[c], [vr[c][v]])[0] for c, v in ports])
    elapsed = time.perf_counter() - t0
    values = np.array(rows).T
    return dict(t=(step_ns * 1e-9 * np.arange(1, n + 1)).tolist(), values=dict(zip(OUT, values.tolist())),
                time=elapsed)


def hosts(fmus: dict) -> list:
    """(host, coupling, run) rows of the table; ``run(d) -> (t, {output: values}, seconds)``."""
    from frictionjoint.errors import FMUError
    from frictionjoint.fmi.cosim import FMUSystem, joint_connections
    from frictionjoint.fmi.ecos import load_ecospy, run_ecos

    def three(coupling, events=False):
        return FMUSystem({"chain": fmus["TwoDofChain"], "j1": fmus["JenkinsJoint"], "j2": fmus["JenkinsJoint"]},
                         joint_connections("chain", "j1", "x1", coupling, events=events)
                         + joint_connections("chain", "j2", "x2", coupling, events=events))

    def timed(call, system=None):
        """``run(d)`` of a call in this process; with the FMUSystem ``system`` (which keeps its
        FMUs loaded between runs): its first run loads them, the time is the best of three more."""
        def run(d):
            if system is not None:
                system.close()
            t0 = time.perf_counter()
            r = call(d)
            first = time.perf_counter() - t0
            if not r.success:
                raise RuntimeError(r.message)
            best = first
            for _ in range(3 if system is not None else 0):
                t0 = time.perf_counter()
                call(d)
                best = min(best, time.perf_counter() - t0)
            return r.t, {o: r[o] for o in OUT}, best, first
        return run

    def elsewhere(host, comps, connections):
        def run(d):
            r = own_process(host, comps, connections, d)
            return np.asarray(r["t"]), {o: np.asarray(v) for o, v in r["values"].items()}, r["time"], r["time"]
        return run

    try:
        load_ecospy()
        ecos = True
    except FMUError as exc:
        print(f"no Ecos rows: {exc}")
        ecos = False
    system = FMUSystem({"chain": fmus["TwoDofChainSystem"]})
    rows = []
    for coupling in ("semi-implicit", "explicit"):
        s = three(coupling)
        rows += [("master, sequential", coupling, timed(lambda d, s=s: s.simulate(PERIODS * T, T / d, OUT), s)),
                 ("master, Jacobi", coupling, timed(lambda d, s=s: s.simulate(PERIODS * T, T / d, OUT,
                                                                                transfer="jacobi"), s))]
        if ecos:
            rows.append(("Ecos (Jacobi)", coupling, timed(lambda d, s=s: run_ecos(s, PERIODS * T, T / d, OUT))))
        rows.append(("libcosim (Jacobi)", coupling, elsewhere("libcosim", s.components, list(s.connections))))
    s = three("semi-implicit", events=True)
    for transfer in ("sequential", "jacobi"):
        rows.append((f"master, {transfer.replace('j', 'J')}", "event-located", timed(
            lambda d, s=s, tr=transfer: s.simulate(PERIODS * T, T / d, OUT, transfer=tr, locate_events=True), s)))
    rows.append(("fmpy (simulate_fmu)", "one FMU", elsewhere("fmpy", system.components, [])))
    if ecos:
        rows.append(("Ecos", "one FMU", timed(lambda d: run_ecos(system, PERIODS * T, T / d, OUT))))
    rows.append(("libcosim", "one FMU", elsewhere("libcosim", system.components, [])))
    return rows


def exact(system, t):
    """fj.simulate on the times ``t``: (x, best of 5 wall times after a first call)."""
    import frictionjoint as fj

    ref = fj.simulate(system, t[-1], t_eval=t, record=("x",))
    best = math.inf
    for _ in range(5):
        t0 = time.perf_counter()
        fj.simulate(system, t[-1], t_eval=t, record=("x",))
        best = min(best, time.perf_counter() - t0)
    return ref.x, best


def main(out_dir: str) -> None:
    from frictionjoint.fmi.build import build_fmus
    from frictionjoint.structure_file import load_structure_definition

    lines = [f"# {platform.node()} {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
             f"Python {platform.python_version()}",
             f"{'host':20s} {'coupling':14s} {'step':>6s} {'error':>9s} {'order':>6s} {'time [s]':>8s} "
             f"{'first [s]':>9s} {'exact [s]':>9s} {'cost':>7s}"]
    system = exact_system()
    with tempfile.TemporaryDirectory() as tmp:
        fmus = {p.stem: p for p in build_fmus(tmp, names=["JenkinsJoint"])}
        fmus.update({p.stem: p for p in build_fmus(tmp, structures=[load_structure_definition(
            ROOT / "models" / "two_dof_chain.toml")])})
        fmus.update({p.stem: p for p in build_fmus(tmp, systems=[ROOT / "models" / "two_dof_chain_system.toml"])})
        for name, coupling, run in hosts(fmus):
            previous = None
            for d in DIVISIONS:
                head = f"{name:20s} {coupling:14s} {'T/' + str(d):>6s}"
                try:
                    t, values, seconds, first = run(d)
                except Exception as exc:  # a row that does not run says why
                    lines.append(f"{head} did not run: {type(exc).__name__}: {str(exc)[:200]}")
                    print(lines[-1], flush=True)
                    previous = None
                    continue
                t = np.asarray(t, dtype=float)
                ref, ref_time = exact(system, t)
                x = np.vstack([values[o] for o in OUT])
                err = float((np.max(np.abs(x - ref), axis=1) / np.max(np.abs(ref), axis=1)).max())
                order = "" if previous is None or not err > 0 else f"{math.log2(previous / err):6.2f}"
                previous = err
                lines.append(f"{head} {err:9.2e} {order:>6s} {seconds:8.3f} {first:9.3f} {ref_time:9.4f} "
                             f"{seconds / ref_time:7.0f}")
                print(lines[-1], flush=True)
    os.makedirs(out_dir, exist_ok=True)
    Path(out_dir, "results_cosim_coupling.txt").write_text("\n".join(lines) + "\n")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(Path(__file__).parent), help="folder for results_cosim_coupling.txt")
    ap.add_argument("--run", help=argparse.SUPPRESS)  # one run in this process (own_process)
    args = ap.parse_args()
    if args.run:
        print(json.dumps(run_job(json.loads(args.run))), flush=True)
    else:
        main(args.out)
