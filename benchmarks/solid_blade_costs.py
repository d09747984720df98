#!/usr/bin/env python
"""The cost of each step of a root study on an engineer's own FE model, on this machine, in one
process (the README's "Bringing your own FE model"; results in benchmarks/results_solid_blade_costs.txt).

Steps, each timed (wall and CPU seconds, the machine's one-minute load average before and after,
the process's peak memory so far):

1. read a 50,100-DOF export in every format (``tests/data/fe_import/make_files.py``'s lattice of
   167 x 10 x 10 nodes; its ``time_reads`` table, written first into FOLDER if it is not there);
2. a 50,000-DOF solid blade: :class:`~frictionjoint.structures.SolidBlade` of
   ``models/ti64_solid_blade.toml`` with 160 x 8 x 1 hexahedra (49,113 DOFs; assembly with the
   centrifugal static solution and the geometric stiffness);
3. its root on contact patches, reduced by sparse Craig-Bampton
   (:func:`~frictionjoint.structures.solid_root.solid_blade_on_patches`: 17 nodes per flank, 5
   modes and the tip's residual vector);
4. the static contact solution (:meth:`PatchDovetailRoot.static_state
   <frictionjoint.elements.PatchDovetailRoot.static_state>`) on that reduced blade;
5. on ``ti64_solid_blade`` itself (30 x 4 x 1, 42 reduced DOFs): the assembly
   (``BladeAssembly.from_model``), one exact steady state in partial slip (1920 rad/s, from rest),
   one harmonic-balance point at H = 15 there (and its check against the exact orbit), and a
   13-point sweep (``fj.sweep("ti64_solid_blade", "1850:1970:13")``, what ``frictionjoint sweep``
   runs).

Measured (benchmarks/results_solid_blade_costs.txt: two runs, the machine's load 4-5 and 9-12; CPU
seconds, wall at load 4-5 in brackets): reading 50,100 DOFs 2.0 (Matrix Market) to 13 s (OP4) wall
per format; SolidBlade 160 x 8 x 1 (49,113 DOFs) 2.3 s (5.8 s); Craig-Bampton to its 2 x 17 flank
nodes (74 DOFs) 8.7 s (22 s), peak memory 1.2 GB; the static contact solution 2 ms;
ti64_solid_blade's assembly 0.6 s (1.6 s), one exact steady state at 1920 rad/s from rest 5.9 s
(14 s), a harmonic-balance point at H = 15 0.18 s (0.44 s; its check against the exact orbit 2.3 s,
truncation error 1.5e-2 there: tests/test_solid_blade_model.py), the 13-point sweep 16 s (40 s).

Usage::

    python benchmarks/solid_blade_costs.py [FOLDER]     # FOLDER for the export, default /tmp/solid_blade_costs_export
    python benchmarks/solid_blade_costs.py --quick      # steps 5 only
"""
from __future__ import annotations

import importlib.util
import os
import resource
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if __package__ in (None, ""):  # run as a script: the repository is not on the path
    sys.path.insert(0, str(ROOT))

import frictionjoint as fj  # noqa: E402
from frictionjoint.structures import BladeAssembly, load_blade_model  # noqa: E402
from frictionjoint.structures.solid_root import solid_blade_on_patches  # noqa: E402

ROWS = []


def step(name, call):
    """Run ``call()``, print and keep its wall and CPU time, the load before and after and the
    peak memory; return its result."""
    load0 = os.getloadavg()[0]
    wall0, cpu0 = time.perf_counter(), time.process_time()
    out = call()
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    load1 = os.getloadavg()[0]
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2 ** 20  # [GB] (ru_maxrss in kB)
    ROWS.append((name, wall, cpu, load0, load1, peak))
    print(f"{name:58s} {wall:9.3f} s wall {cpu:8.3f} s CPU  load {load0:4.1f} -> {load1:4.1f}  peak {peak:.2f} GB",
          flush=True)
    return out


def read_exports(folder: Path):
    spec = importlib.util.spec_from_file_location("make_files", ROOT / "tests" / "data" / "fe_import" / "make_files.py")
    make_files = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(make_files)
    if not (folder / "lattice_K.mtx").exists():
        print(f"writing the 50,100-DOF export into {folder} (every format; a few minutes)", flush=True)
        make_files.write_all(folder, 167, 10, 10)
    step("read the 50,100-DOF export, every format (table above)", lambda: make_files.time_reads(folder))


def big_blade(model):
    blade = step("SolidBlade 160 x 8 x 1, rotating (assembly)",
                 lambda: model.blade(n_elements=(160, 8, 1)))
    print(f"  {blade.n_dof} DOFs, nnz(K) {blade.stiffness.nnz}")
    reduced, root, tip = step("sparse Craig-Bampton to the flank nodes, 5 modes + residual",
                              lambda: solid_blade_on_patches(blade, model.root, 5,
                                                             model.excitation.get("tip_point", "centre")))
    print(f"  {root!r}: {reduced.n_dof} DOFs")
    st = step("static contact solution on the reduced blade", lambda: root.static_state(reduced))
    print(f"  {st.regime}; flank normal loads {st.flank_normal_force.round(1)} N")


def small_model(model):
    asm = step("ti64_solid_blade: BladeAssembly.from_model (30 x 4 x 1)", lambda: BladeAssembly.from_model(model))
    st = step("static contact solution (42 DOFs)", lambda: asm.joints[0].static_state(asm.structure))
    print(f"  {st.regime}")
    w = 1920.0
    r = step(f"one exact steady state, {w:g} rad/s, from rest", lambda: asm.steady_state(w))
    print(f"  {r.message}; tip {abs(asm.first_harmonic(r, asm.tip)):.5e} m, {len(r.events)} events per period")
    system = asm.system(w)
    hb = step("one harmonic-balance point, H = 15", lambda: fj.harmonic_balance(system, w, n_harmonics=15))
    tip_row = asm.structure.transformation[list(asm.structure.full_dof_names).index(asm.tip)]
    print(f"  {hb.message}; tip {abs(tip_row @ hb.harmonics[1]):.5e} m")
    hbc = step("the same with check=True (the exact orbit from it)",
               lambda: fj.harmonic_balance(system, w, n_harmonics=15, check=True))
    print(f"  truncation error {hbc.truncation_error:.2e}, stable {hbc.stable}")
    sw = step("13-point sweep, fj.sweep('ti64_solid_blade', '1850:1970:13')",
              lambda: fj.sweep("ti64_solid_blade", "1850:1970:13"))
    print(f"  {sw.message}; peak {np.nanmax(np.abs(sw.response)):.5e} m")


def main(argv):
    quick = "--quick" in argv
    args = [a for a in argv[1:] if not a.startswith("--")]
    folder = Path(args[0]) if args else Path("/tmp/solid_blade_costs_export")
    print(f"{os.cpu_count()} cores; load average {os.getloadavg()}", flush=True)
    model = load_blade_model("ti64_solid_blade")
    if not quick:
        read_exports(folder)
        big_blade(model)
    small_model(model)
    print(f"\n{'step':58s} {'wall [s]':>9s} {'CPU [s]':>8s} {'load':>11s} {'peak [GB]':>9s}")
    for name, wall, cpu, l0, l1, peak in ROWS:
        print(f"{name:58s} {wall:9.3f} {cpu:8.3f} {l0:5.1f}-{l1:<5.1f} {peak:9.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
