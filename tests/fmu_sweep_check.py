"""Sweep through CoulombOscillator.fmu and directly in the library (one process, one FMU instance).

    python tests/fmu_sweep_check.py FMU_PATH N_POINTS  -> JSON
"""
import json
import sys
import time

import numpy as np

from frictionjoint.sweep import sweep

path, n = sys.argv[1], int(sys.argv[2])
ws = np.linspace(0.5, 2.5, n)  # m = k = 1: omega = r
params = dict(slip_force=0.5, force_amplitude=1.0)
t0 = time.perf_counter()
lib = sweep("CoulombOscillator", ws, params, outputs=("x", "friction_force"))
t1 = time.perf_counter()
fmu = sweep(path, ws, params, outputs=("x", "friction_force"))
t2 = time.perf_counter()
print(json.dumps({
    "lib": {"amplitude": lib.amplitude.tolist(), "phase": lib.phase.tolist(),
            "ff": lib.harmonics["friction_force"]["amplitude"].tolist(), "converged": lib.converged.tolist()},
    "fmu": {"amplitude": fmu.amplitude.tolist(), "phase": fmu.phase.tolist(),
            "ff": fmu.harmonics["friction_force"]["amplitude"].tolist(), "converged": fmu.converged.tolist()},
    "amp_err": [None if e is np.ma.masked else float(e) for e in fmu.amplitude_error],
    "regime": fmu.analytic_regime.tolist(), "time": [t1 - t0, t2 - t1]}))
