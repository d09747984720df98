"""Run CoulombOscillator.fmu in libcosimpy (Open Simulation Platform's libcosim), the second,
independent FMI importer. Usage:

    python tests/cosim_check.py FMU_PATH SLIP_FORCE OMEGA STEP_NS N_STEPS  -> prints one JSON object
    python tests/cosim_check.py two FMU_PATH STEP_NS N_STEPS SLIP_FORCE,OMEGA SLIP_FORCE,OMEGA
                         -> two instances of the FMU in one execution, rows of each
    python tests/cosim_check.py dovetail|microslip FMU_PATH SUBSTEPS       -> DovetailRoot.fmu or
                         MicroslipJoint.fmu driven along tests/fmu_checks.py's paths
    python tests/cosim_check.py blade FMU_PATH STEP_NS N_STEPS [VARY]    -> BladeDovetail.fmu from rest

libcosim counts time in integer nanoseconds: communication points are k * STEP_NS * 1e-9 s.
"""
import json
import sys

from libcosimpy.CosimEnums import CosimVariableType  # noqa: F401  (import check of the package)
from libcosimpy.CosimExecution import CosimExecution
from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
from libcosimpy.CosimManipulator import CosimManipulator
from libcosimpy.CosimObserver import CosimObserver
from libcosimpy.CosimSlave import CosimLocalSlave

OUTPUTS = ("x", "v", "dissipated_energy")


def _execution(path, step_ns, instance_name, parameters):
    """One FMU in a libcosim execution with a last-value observer and an override manipulator
    (for inputs), its parameters set: ``(execution, index, references, observer, manipulator)``."""
    log_output_level(CosimLogLevel.WARNING)
    ex = CosimExecution.from_step_size(int(step_ns))
    idx = ex.add_local_slave(CosimLocalSlave(fmu_path=path, instance_name=instance_name))
    vr = {v.name.decode(): v.reference for v in ex.slave_variables(idx)}
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    man = CosimManipulator.create_override()
    ex.add_manipulator(man)
    for name, value in parameters.items():
        if isinstance(value, int):
            assert ex.integer_initial_value(idx, vr[name], value)
        else:
            assert ex.real_initial_value(idx, vr[name], value)
    return ex, idx, vr, obs, man


def main(path, slip_force, omega, step_ns, n_steps):
    ex, idx, vr, obs, _ = _execution(path, step_ns, "oscillator", dict(
        slip_force=slip_force, force_amplitude=1.0, omega=omega, x0=0.1, v0=-0.2))
    rows, times = [], []
    for _ in range(n_steps):
        assert ex.step()
        rows.append(obs.last_real_values(idx, [vr[n] for n in OUTPUTS])
                    + obs.last_integer_values(idx, [vr["event_count"]]))
        times.append(ex.status().current_time)
    return {"time_ns": times, "rows": rows}


def two(path, step_ns, n_steps, case_a, case_b):
    """Two instances of one FMU in one libcosim execution, with different parameters."""
    log_output_level(CosimLogLevel.WARNING)
    ex = CosimExecution.from_step_size(int(step_ns))
    obs = CosimObserver.create_last_value()
    ex.add_observer(obs)
    slaves = []
    for name, case in (("a", case_a), ("b", case_b)):
        idx = ex.add_local_slave(CosimLocalSlave(fmu_path=path, instance_name=name))
        vr = {v.name.decode(): v.reference for v in ex.slave_variables(idx)}
        f, w = map(float, case.split(","))
        for pname, value in dict(slip_force=f, force_amplitude=1.0, omega=w, x0=0.1, v0=-0.2).items():
            assert ex.real_initial_value(idx, vr[pname], value)
        slaves.append((idx, vr))
    rows = {"a": [], "b": []}
    for _ in range(int(n_steps)):
        assert ex.step()
        for name, (idx, vr) in zip(rows, slaves):
            rows[name].append(obs.last_real_values(idx, [vr[n] for n in OUTPUTS])
                              + obs.last_integer_values(idx, [vr["event_count"]]))
    return rows


def dovetail(path, substeps):
    """DovetailRoot.fmu with its inputs set by libcosim's override manipulator before each step,
    along the same corners as ``fmu_checks.dovetail_path`` (rows at the corners)."""
    import numpy as np

    from fmu_checks import DOVETAIL_OUT, dovetail_corners

    ex, idx, vr, obs, man = _execution(path, 1e6 / substeps, "root",  # 1 ms per leg
                                       dict(centrifugal_force=2e3))
    corners = dovetail_corners()
    reals = [n for n in DOVETAIL_OUT if not n.startswith("slipping")]
    rows = []
    for a, b in zip(corners[:-1], corners[1:]):
        for lam in np.arange(1, substeps + 1) / substeps:
            u = a + lam * (b - a)
            man.slave_real_values(idx, [vr["u_tangential"], vr["u_radial"]], [float(u[0]), float(u[1])])
            assert ex.step()
        rows.append(dict(zip(reals, obs.last_real_values(idx, [vr[n] for n in reals]))))
    return {"rows": rows}


def blade(path, step_ns, n_steps, vary=0):
    """BladeDovetail.fmu in libcosim, from its static state, with ``fmu_checks.BLADE_PARAMETERS``
    (rows of ``fmu_checks.BLADE_OUT`` after each step)."""
    from fmu_checks import BLADE_OUT, BLADE_PARAMETERS

    ex, idx, vr, obs, _ = _execution(path, int(step_ns), "blade", BLADE_PARAMETERS)
    assert ex.boolean_initial_value(idx, vr["normal_load_variation"], bool(int(vary)))
    rows = []
    for _ in range(int(n_steps)):
        assert ex.step()
        rows.append(obs.last_real_values(idx, [vr[n] for n in BLADE_OUT]))
    return {"rows": rows}


def microslip(path, substeps):
    """MicroslipJoint.fmu along ``fmu_checks.microslip_loop``'s triangles, inputs set by libcosim's
    override manipulator (rows at the turning points)."""
    import numpy as np

    from fmu_checks import MICROSLIP_AMPLITUDES, MICROSLIP_PARAMETERS

    ex, idx, vr, obs, man = _execution(path, 1e6 / substeps, "joint", MICROSLIP_PARAMETERS)
    rows, u_prev = [], 0.0
    for a in MICROSLIP_AMPLITUDES:
        for target in (a, -a, a):
            for lam in np.arange(1, substeps + 1) / substeps:
                man.slave_real_values(idx, [vr["u"]], [float(u_prev + lam * (target - u_prev))])
                assert ex.step()
            u_prev = target
            rows.append(obs.last_real_values(idx, [vr[n] for n in ("force", "tangent_stiffness",
                                                                   "dissipated_energy")]))
    return {"rows": rows}


if __name__ == "__main__":
    if sys.argv[1] == "two":
        print(json.dumps(two(*sys.argv[2:])), flush=True)
    elif sys.argv[1] == "blade":
        print(json.dumps(blade(*sys.argv[2:])), flush=True)
    elif sys.argv[1] in ("dovetail", "microslip"):
        print(json.dumps(globals()[sys.argv[1]](sys.argv[2], int(sys.argv[3]))), flush=True)
    else:
        path, f, w, step, n = sys.argv[1:]
        print(json.dumps(main(path, float(f), float(w), int(step), int(n))), flush=True)
