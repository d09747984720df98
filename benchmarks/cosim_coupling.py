"""Co-simulation of a system of FMUs against the exact answer of the same model.

The case of the README (models/two_dof_chain.toml as LinearStructure.fmu, two JenkinsJoint.fmu
instances with their defaults kt = 100 N/m, Fs = 0.8 N, 1 N cos(1.2 t) on DOF 2, from rest, four
periods) through:

- this library's master (fmpy, all FMUs in this process), sequential transfer
  (``structure.x -> joint.u`` before ``joint.force -> structure``) and Jacobi transfer;
- Ecos (its library, in its own process; Jacobi, as its command line);

with semi-implicit coupling (the joints' tangent stiffness and evaluation point passed to the
structure) and explicit coupling (force held); and this master with the events located across the
FMUs (``locate_events=True``, the joints' velocity connected: ``joint_connections(...,
events=True)``), both transfers, from T/20. Error: the largest deviation over all
communication points of each DOF from the library's exact event-driven solution
(FrictionSystem + simulate), relative to that DOF's amplitude; the table gives the worse DOF, the
observed order between neighbouring steps and the wall time of the run. Usage:

    python benchmarks/cosim_coupling.py [--out DIR]
"""
from __future__ import annotations

import argparse
import math
import os
import platform
import tempfile
import time
from pathlib import Path

import numpy as np

import frictionjoint as fj
from frictionjoint.fmi.build import build_fmus
from frictionjoint.fmi.cosim import FMUSystem, joint_connections
from frictionjoint.structure_file import load_structure_definition

ROOT = Path(__file__).resolve().parents[1]
OMEGA, PERIODS, DIVISIONS = 1.2, 4, (50, 100, 200, 400)
LOCATED_DIVISIONS = (20, 50, 100, 200, 400)
T = 2 * math.pi / OMEGA


def main(out_dir: str) -> None:
    definition = load_structure_definition(ROOT / "models" / "two_dof_chain.toml")
    with tempfile.TemporaryDirectory() as tmp:
        paths = {p.stem: p for p in build_fmus(tmp, names=["JenkinsJoint"])}
        paths.update({p.stem: p for p in build_fmus(tmp, structures=[definition])})
        comps = {"chain": paths["TwoDofChain"], "j1": paths["JenkinsJoint"], "j2": paths["JenkinsJoint"]}
        exact_system = fj.FrictionSystem(definition.structure, [fj.Jenkins(100.0, 0.8, dof="x1"),
                                                                fj.Jenkins(100.0, 0.8, dof="x2")],
                                         omega=OMEGA, excitation=[fj.HarmonicForce("x2", 1.0)])
        hosts = [("master, sequential", lambda s, h: s.simulate(PERIODS * T, h, OUT)),
                 ("master, Jacobi", lambda s, h: s.simulate(PERIODS * T, h, OUT, transfer="jacobi"))]
        from frictionjoint.errors import FMUError
        from frictionjoint.fmi.ecos import load_ecospy, run_ecos

        try:
            load_ecospy()
            hosts.append(("Ecos (Jacobi)", lambda s, h: run_ecos(s, PERIODS * T, h, OUT)))
        except FMUError as exc:
            print(f"no Ecos rows: {exc}")
        lines = [f"# {platform.node()} {platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
                 f"Python {platform.python_version()}",
                 f"{'host':20s} {'coupling':14s} {'step':>6s} {'error':>9s} {'order':>6s} {'time [s]':>8s} "
                 f"{'exact [s]':>9s}"]
        located = [("master, sequential", lambda s, h: s.simulate(PERIODS * T, h, OUT, locate_events=True)),
                   ("master, Jacobi", lambda s, h: s.simulate(PERIODS * T, h, OUT, transfer="jacobi",
                                                              locate_events=True))]
        for coupling, runs, divisions in (("semi-implicit", hosts, DIVISIONS), ("explicit", hosts, DIVISIONS),
                                          ("event-located", located, LOCATED_DIVISIONS)):
            base, events = ("semi-implicit", True) if coupling == "event-located" else (coupling, False)
            s = FMUSystem(comps, joint_connections("chain", "j1", "x1", base, events=events)
                          + joint_connections("chain", "j2", "x2", base, events=events))
            for name, run in runs:
                previous = None
                for d in divisions:
                    t = T / d * np.arange(d * PERIODS + 1)
                    t0 = time.perf_counter()
                    ref = fj.simulate(exact_system, t[-1], t_eval=t, record=("x",))
                    t1 = time.perf_counter()
                    r = run(s, T / d)
                    t2 = time.perf_counter()
                    x = np.vstack([r["chain.x_x1"], r["chain.x_x2"]])
                    err = float((np.max(np.abs(x - ref.x), axis=1) / np.max(np.abs(ref.x), axis=1)).max())
                    order = "" if previous is None else f"{math.log2(previous / err):6.2f}"
                    previous = err
                    lines.append(f"{name:20s} {coupling:14s} {'T/' + str(d):>6s} {err:9.2e} {order:>6s} "
                                 f"{t2 - t1:8.2f} {t1 - t0:9.2f}")
                    print(lines[-1], flush=True)
    os.makedirs(out_dir, exist_ok=True)
    Path(out_dir, "results_cosim_coupling.txt").write_text("\n".join(lines) + "\n")


OUT = ["chain.x_x1", "chain.x_x2"]

if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(Path(__file__).parent), help="folder for results_cosim_coupling.txt")
    main(ap.parse_args().out)
