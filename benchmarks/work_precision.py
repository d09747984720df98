"""Run time against error for the Coulomb oscillator: the exact marchers (the general n-DOF marcher
and the dedicated single-DOF kernel), steady_state, the FMU sweep, the describing function and the
scipy baselines (tanh-regularised RK45/LSODA/Radau, event-driven DOP853), all in this process. The
task, the protocol and the fairness rules are in the docstring of benchmarks/harness.py; this
script only runs it (as `frictionjoint bench` does).

Prints the table and the headline ratios (the fastest exact row against the scipy baselines at
matched accuracy and at error <= 1e-10), writes benchmarks/results/work_precision.csv (with the
machine described in its header) and benchmarks/results/work_precision.png. Usage:

    python benchmarks/work_precision.py [--quick] [--repeat N] [--out DIR]
"""
from __future__ import annotations

import argparse
import os
import sys

from frictionjoint.cli import main as cli_main

RESULTS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "results")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the short version (< 30 s)")
    ap.add_argument("--repeat", type=int, default=None, help="best of N runs (default 5, quick 2)")
    ap.add_argument("--out", default=RESULTS, help=f"output folder (default {RESULTS})")
    args = ap.parse_args(argv)
    bench = ["bench", "--out", args.out] + (["--quick"] if args.quick else [])
    if args.repeat is not None:
        bench += ["--repeat", str(args.repeat)]
    return cli_main(bench)


if __name__ == "__main__":
    sys.exit(main())
