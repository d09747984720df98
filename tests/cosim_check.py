"""Run CoulombOscillator.fmu in libcosimpy (Open Simulation Platform's libcosim), the second,
independent FMI importer; one run per process (pythonfmu FMUs cannot be instantiated twice in one
process). Usage:

    python tests/cosim_check.py FMU_PATH SLIP_FORCE OMEGA STEP_NS N_STEPS  -> prints one JSON object

libcosim counts time in integer nanoseconds: communication points are k * STEP_NS * 1e-9 s.
"""
import json
import sys

from libcosimpy.CosimEnums import CosimVariableType  # noqa: F401  (import check of the package)
from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
from libcosimpy.CosimObserver import CosimObserver
from libcosimpy.CosimSlave import CosimLocalSlave

OUTPUTS = ("x", "v", "dissipated_energy")


def main(path, slip_force, omega, step_ns, n_steps):
    log_output_level(CosimLogLevel.WARNING)
    ex = CosimExecution.from_step_size(step_ns)
    idx = ex.add_local_slave(CosimLocalSlave(fmu_path=path, instance_name="oscillator"))
    vr = {v.name.decode(): v.reference for v in ex.slave_variables(idx)}
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    for name, value in dict(slip_force=slip_force, force_amplitude=1.0, omega=omega, x0=0.1, v0=-0.2).items():
        assert ex.real_initial_value(idx, vr[name], value)
    rows, times = [], []
    for _ in range(n_steps):
        assert ex.step()
        rows.append(obs.last_real_values(idx, [vr[n] for n in OUTPUTS])
                    + obs.last_integer_values(idx, [vr["event_count"]]))
        times.append(ex.status().current_time)
    return {"time_ns": times, "rows": rows}


if __name__ == "__main__":
    # pythonfmu's wrapper can leave the heap inconsistent for the host's cyclic garbage collector
    # and for interpreter teardown ("corrupted double-linked list" at exit, seen once in ~10 runs):
    # no cyclic GC, and leave with os._exit once the result is out (as frictionjoint.fmi.worker)
    import gc
    import os

    gc.disable()
    path, f, w, step, n = sys.argv[1:]
    print(json.dumps(main(path, float(f), float(w), int(step), int(n))), flush=True)
    os._exit(0)
