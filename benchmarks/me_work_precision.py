"""Work-precision of the Model Exchange FMUs against the exact answer of the same model.

The case of the README (models/two_dof_chain.toml, a Jenkins joint kt = 100 N/m, Fs = 0.8 N from each
mass to the ground, 1 N cos(1.2 t) on DOF 2, from rest, four periods, outputs every T/50) through:

- this library's Model Exchange master (:class:`frictionjoint.fmi.me_master.ModelExchangeSystem`)
  on three ME FMUs (``TwoDofChainME.fmu``, two ``JenkinsJointME.fmu``), DOP853 and Radau;
- fmpy's ``simulate_fmu`` (its Model Exchange loop: CVode BDF, absolute tolerance rtol x the FMU's
  nominals) on the ME system FMU (``TwoDofChainSystemME.fmu``);

all FMI 2.0 (the FMI 3.0 FMUs, ``--fmi-version 3``, give the same numbers: tests/test_model_exchange.py);

at relative tolerances 1e-4 ... 1e-12. Error: the largest deviation over the recorded times of each
DOF from ``fj.simulate`` (exact, event-driven) at the same times, relative to that DOF's amplitude,
the worse DOF ("err") and relative to the largest amplitude ("err_sys"; DOF 1 moves 1.1 % of DOF 2).
Time: wall time of a run (each run loads its FMUs: 0.1-0.3 s of it), best of two, and its ratio to
the exact solution's (best of 5). Beside it, the co-simulation of the same FMUs' CS versions with
events located (docs/cosimulation.md): 2.5e-14 to 3.8e-14 at 24-44x the exact solution's time.

Usage:

    python benchmarks/me_work_precision.py [--out DIR]

writes ``results_me_work_precision.txt`` and ``docs/me_work_precision.png``.
"""
from __future__ import annotations

import argparse
import math
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OMEGA = 1.2
T = 2 * math.pi / OMEGA
PERIODS = 4
DIVISION = 50
RTOLS = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)


def main(out_dir: Path) -> None:
    import frictionjoint as fj
    from fmpy import simulate_fmu
    from frictionjoint.fmi.build import build_fmus
    from frictionjoint.fmi.me_master import ModelExchangeSystem
    from frictionjoint.system_file import load_system_definition

    with tempfile.TemporaryDirectory() as tmp:
        built = build_fmus(tmp, names=["JenkinsJoint"], structures=[ROOT / "models" / "two_dof_chain.toml"],
                           systems=[ROOT / "models" / "two_dof_chain_system.toml"], interface="model-exchange")
        fmus = {p.stem: p for p in built}
        system = load_system_definition(ROOT / "models" / "two_dof_chain_system.toml").system({})
        t = T / DIVISION * np.arange(DIVISION * PERIODS + 1)
        ref = fj.simulate(system, t[-1], t_eval=t, record=("x",))
        exact_time = math.inf
        for _ in range(5):
            t0 = time.perf_counter()
            fj.simulate(system, t[-1], t_eval=t, record=("x",))
            exact_time = min(exact_time, time.perf_counter() - t0)
        connections = []
        for j, dof in (("j1", "x1"), ("j2", "x2")):
            connections += [(f"chain.x_{dof}", f"{j}.u"), (f"chain.v_{dof}", f"{j}.velocity"),
                            (f"{j}.force", f"chain.joint_force_{dof}")]
        chain = ModelExchangeSystem({"chain": fmus["TwoDofChainME"], "j1": fmus["JenkinsJointME"],
                                     "j2": fmus["JenkinsJointME"]}, connections)

        def errors(x):
            dev = np.abs(np.asarray(x) - ref.x)
            return (float(np.max(np.max(dev, axis=1) / np.max(np.abs(ref.x), axis=1))),
                    float(np.max(dev) / np.max(np.abs(ref.x))))

        def master(method, rtol):
            r = chain.simulate(PERIODS * T, T / DIVISION, ["chain.x_x1", "chain.x_x2"], rtol=rtol, method=method)
            return np.vstack([r["chain.x_x1"], r["chain.x_x2"]])

        def fmpy_cvode(rtol):
            r = simulate_fmu(str(fmus["TwoDofChainSystemME"]), stop_time=PERIODS * T, output_interval=T / DIVISION,
                             relative_tolerance=rtol, output=["x_x1", "x_x2"], record_events=False)
            return np.vstack([r["x_x1"], r["x_x2"]])

        rows = []
        for label, run, rtols in (("master DOP853, 3 ME FMUs", lambda r: master("DOP853", r), RTOLS),
                                  ("master Radau, 3 ME FMUs", lambda r: master("Radau", r), RTOLS[:-1]),
                                  ("fmpy CVode, ME system FMU", fmpy_cvode, RTOLS)):
            for rtol in rtols:
                best = math.inf
                for _ in range(2):
                    t0 = time.perf_counter()
                    x = run(rtol)
                    best = min(best, time.perf_counter() - t0)
                err, err_sys = errors(x)
                rows.append((label, rtol, err, err_sys, best, best / exact_time))
                print(f"{label:28s} rtol {rtol:7.0e}  err {err:9.2e}  err_sys {err_sys:9.2e}  "
                      f"{best:7.3f} s  {best / exact_time:8.0f} x exact", flush=True)

    lines = [f"# {__doc__.splitlines()[0]}",
             f"# Python {platform.python_version()}, {platform.machine()}, exact solution {exact_time * 1e3:.2f} ms",
             f"{'run':28s} {'rtol':>7s} {'err':>9s} {'err_sys':>9s} {'time_s':>8s} {'x_exact':>8s}"]
    lines += [f"{lab:28s} {rtol:7.0e} {e:9.2e} {es:9.2e} {tm:8.3f} {ratio:8.0f}" for lab, rtol, e, es, tm, ratio in rows]
    (out_dir / "results_me_work_precision.txt").write_text("\n".join(lines) + "\n")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for label in dict.fromkeys(r[0] for r in rows):
        sel = [r for r in rows if r[0] == label]
        ax.loglog([r[5] for r in sel], [r[2] for r in sel], "o-", label=label)
        for r in sel:
            ax.annotate(f"{r[1]:.0e}", (r[5], r[2]), textcoords="offset points", xytext=(4, 2), fontsize=7)
    ax.axhspan(2.5e-14, 3.8e-14, color="0.8", label="CS FMUs, events located (24-44x)")
    ax.set_xlabel("run time / exact solution's time")
    ax.set_ylabel("error, worse DOF, relative to its amplitude")
    ax.set_title("README chain, Model Exchange FMUs (labels: rtol)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(ROOT / "docs" / "me_work_precision.png", dpi=110)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=str(Path(__file__).resolve().parent), help="results folder")
    main(Path(parser.parse_args().out))
    sys.exit(0)
