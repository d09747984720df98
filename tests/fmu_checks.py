"""Checks that run a real FMU through fmpy, one per process (pythonfmu FMUs cannot be
instantiated twice in one process: NTNU-IHB/PythonFMU #213, #228). Usage:

    python tests/fmu_checks.py CHECK FMU_PATH   -> prints one JSON object
"""
import json
import math
import sys

import numpy as np

from frictionjoint.fmi.master import FMUInstance


def step_independence(path):
    """x at common times with steps T/7 and T/200, stop-free and stop cases."""
    out = {}
    with FMUInstance(path) as inst:
        for f, r in [(0.3, 1.5), (0.5, 0.45)]:
            period = 2 * math.pi / r
            xs = {}
            for n in (7, 200):
                inst.initialize(dict(slip_force=f, force_amplitude=1.0, omega=r, x0=0.1, v0=-0.2))
                vals = []
                for k in range(8 * n):
                    inst.step(period / n)
                    if (k + 1) % n == 0:
                        vals.append(inst.get(["x", "v", "dissipated_energy", "event_count"]))
                xs[n] = np.array(vals, dtype=float)
            amp = np.max(np.abs(xs[200][:, 0]))
            out[f"{f},{r}"] = {"x_err": float(np.max(np.abs(xs[7][:, 0] - xs[200][:, 0])) / amp),
                               "diss_err": float(np.max(np.abs(xs[7][:, 2] - xs[200][:, 2]))),
                               "events": [int(xs[7][-1, 3]), int(xs[200][-1, 3])],
                               "x_end": float(xs[200][-1, 0]), "v_end": float(xs[200][-1, 1]),
                               "diss_end": float(xs[200][-1, 2])}
        out["messages"] = inst.messages
    return out


def state_roundtrip(path):
    with FMUInstance(path) as inst:
        inst.initialize(dict(slip_force=0.5, force_amplitude=1.0, omega=0.45))
        inst.step_to(3.0)
        saved = inst.get_state()
        inst.set({"force": 0.2})
        inst.step_to(9.0)
        a = inst.get(["x", "v", "friction_force", "stuck", "dissipated_energy", "event_count"])
        inst.step_to(11.0)
        inst.set_state(saved)
        inst.set({"force": 0.2})
        inst.step_to(9.0)
        b = inst.get(["x", "v", "friction_force", "stuck", "dissipated_energy", "event_count"])
    return {"a": a, "b": b}


def bad_parameter(path, name="mass", value="-1.0"):
    value = json.loads(value)
    with FMUInstance(path) as inst:
        try:
            inst.initialize({name: value})
            raised = None
        except Exception as exc:  # fmpy's FMICallException
            raised = str(exc)
        return {"raised": raised, "messages": inst.messages}


def jenkins_loop(path):
    """Force along u = u0 cos(theta) sampled at 400 points per cycle, 3 cycles."""
    with FMUInstance(path) as inst:
        inst.initialize(dict(stiffness=50.0, slip_force=2.0))
        th = np.linspace(0, 6 * np.pi, 1201)
        u = 0.1 * np.cos(th)
        rows = []
        for k, uk in enumerate(u):
            inst.set({"u": float(uk)})
            rows.append(inst.get(["force", "tangent_stiffness", "slipping", "dissipated_energy"]))
            inst.step(0.01)
        saved = inst.get_state()
        inst.set({"u": 0.05})
        inst.step(0.01)
        f1 = inst.get(["force"])[0]
        inst.set_state(saved)
        inst.set({"u": 0.05})
        inst.step(0.01)
        f2 = inst.get(["force"])[0]
    return {"u": u.tolist(), "rows": rows, "restore": [f1, f2]}


def iwan_loop(path):
    with FMUInstance(path) as inst:
        inst.initialize(dict(stiffness=100.0, slip_force=1.0, chi=-0.4, beta=0.2, n_sliders=12))
        th = np.linspace(0, 4 * np.pi, 401)
        u = 0.012 * np.sin(th)
        rows = []
        for uk in u:
            inst.set({"u": float(uk)})
            inst.step(0.01)
            rows.append(inst.get(["force", "dissipated_energy", "tangent_stiffness"]))
    return {"u": u.tolist(), "rows": rows}


def trajectory(path, slip_force, omega, step_ns, n_steps):
    """x, v, dissipated energy, event count at t_k = k * step_ns * 1e-9 s through fmpy (the
    communication points libcosim uses), started like tests/cosim_check.py."""
    with FMUInstance(path) as inst:
        inst.initialize(dict(slip_force=float(slip_force), force_amplitude=1.0, omega=float(omega), x0=0.1, v0=-0.2))
        rows = []
        for k in range(1, int(n_steps) + 1):
            inst.step_to(k * int(step_ns) * 1e-9)
            rows.append(inst.get(["x", "v", "dissipated_energy", "event_count"]))
        return {"rows": rows, "messages": inst.messages}


def _mass_step(x, v, t, h, m, k_eff, g0, P, w):
    """The master's own subsystem: m x'' + k_eff x = g0 + P cos(w t) over [t, t + h], exactly."""
    X = P / (k_eff - m * w * w)
    om = math.sqrt(k_eff / m)
    xp0, vp0 = g0 / k_eff + X * math.cos(w * t), -X * w * math.sin(w * t)
    c, s = math.cos(om * h), math.sin(om * h)
    dx, dv = x - xp0, v - vp0
    t1 = t + h
    return (g0 / k_eff + X * math.cos(w * t1) + dx * c + dv / om * s,
            -X * w * math.sin(w * t1) - dx * om * s + dv * c)


def jenkins_coupling(path):
    """JenkinsJoint.fmu coupled to a mass-spring m x'' + k x + f_joint(x) = P cos(w t) by a master
    loop with communication step h, explicitly (joint force held over the step) and
    semi-implicitly (joint force linearised with the FMU's tangent_stiffness over the step)."""
    m, k, kt, P, w = 1.0, 1.0, 1e4, 1.0, 0.8
    period = 2 * math.pi / w
    out = {}
    with FMUInstance(path) as inst:
        for slip_force in (1e12, 0.5):
            for n in (100, 400, 1600):
                h = period / n
                for scheme in ("explicit", "semi-implicit"):
                    inst.initialize(dict(stiffness=kt, slip_force=slip_force))
                    x = v = 0.0
                    xs = []
                    for i in range(10 * n):
                        inst.set({"u": x})
                        f, K = inst.get(["force", "tangent_stiffness"])
                        K = K if scheme == "semi-implicit" else 0.0
                        x, v = _mass_step(x, v, i * h, h, m, k + K, -f + K * x, P, w)
                        inst.step(h)
                        xs.append(x)
                        if not (math.isfinite(x) and abs(x) < 1e30):
                            break
                    inst.set({"u": x})
                    diss = inst.get(["dissipated_energy"])[0]
                    out[f"{slip_force:g},{n},{scheme}"] = {"x": xs, "h": h, "dissipated_energy": diss}
        out["messages"] = inst.messages
    return out


DOVETAIL_OUT = ("root_force_tangential", "root_force_radial", "normal_force_right", "normal_force_left",
                "friction_force_right", "friction_force_left", "slipping_right", "slipping_left",
                "stiffness_tt", "stiffness_tr", "stiffness_rt", "stiffness_rr", "dissipated_energy")


def dovetail_corners(n_corners=40, seed=3, lift=1):
    """Corners of a random piecewise-linear root path (X, Y) [m] that opens the flanks at times."""
    rng = np.random.default_rng(int(seed))
    c = rng.normal(scale=2e-6, size=(int(n_corners), 2))
    if int(lift):
        c[10:13, 1] = -1e-4  # radial pull-in far enough to lift both flanks off
    c[0] = 0.0
    return c


def dovetail_path(path, substeps, profile=0, vary=1):
    """Drive DovetailRoot.fmu along the corners, each straight leg in ``substeps`` equal steps;
    rows at the corners only (the communication points common to every ``substeps``)."""
    corners = dovetail_corners()
    rows = []
    with FMUInstance(path) as inst:
        inst.initialize(dict(centrifugal_force=2e3, flank_profile=int(profile),
                             normal_load_variation=bool(int(vary))))
        for a, b in zip(corners[:-1], corners[1:]):
            for lam in np.arange(1, int(substeps) + 1) / int(substeps):
                u = a + lam * (b - a)
                inst.set({"u_tangential": float(u[0]), "u_radial": float(u[1])})
                inst.step(1e-3 / int(substeps))
            rows.append(inst.get(list(DOVETAIL_OUT)))
    return {"corners": corners.tolist(), "rows": rows}


MICROSLIP_PARAMETERS = dict(normal_load=100.0, friction_coefficient=0.3, radius=0.01, youngs_modulus=210e9,
                           poisson_ratio=0.3, n_sliders=16)
MICROSLIP_AMPLITUDES = [0.2e-6, 0.5e-6, 1.0e-6, 1.0e-6]


def microslip_loop(path, substeps):
    """MicroslipJoint.fmu along u = +-A triangles (4 cycles), each leg in ``substeps`` steps."""
    amps = MICROSLIP_AMPLITUDES
    rows = []
    with FMUInstance(path) as inst:
        inst.initialize(MICROSLIP_PARAMETERS)
        u_prev = 0.0
        for a in amps:
            for target in (a, -a, a):
                for lam in np.arange(1, int(substeps) + 1) / int(substeps):
                    inst.set({"u": float(u_prev + lam * (target - u_prev))})
                    inst.step(1e-3 / int(substeps))
                u_prev = target
                rows.append(inst.get(["force", "tangent_stiffness", "dissipated_energy"]))
    return {"amplitudes": amps, "rows": rows}


#: BladeDovetail.fmu's case for the checks: the damper optimum's root load, a tip force that slips
#: the flanks every cycle, near the first resonance (tests/test_blade_fmu.py)
BLADE_PARAMETERS = dict(centrifugal_force=46.0, omega=2000.0, tip_force_amplitude=1.0)
BLADE_OUT = ("tip_displacement", "tip_velocity", "root_tangential", "root_radial", "root_rocking",
             "normal_force_right", "normal_force_left", "friction_force_right", "friction_force_left",
             "dissipated_energy", "tip_cos_integral", "tip_sin_integral")


def blade_steps(path, step, n_steps, vary=0):
    """BladeDovetail.fmu from its static state, ``n_steps`` communication steps of ``step`` [s]
    (points ``k * step``); rows of :data:`BLADE_OUT` (and the event count, the slip and lift-off
    flags) after each step."""
    step, n_steps = float(step), int(n_steps)
    rows = []
    with FMUInstance(path) as inst:
        inst.initialize(dict(BLADE_PARAMETERS, normal_load_variation=bool(int(vary))))
        for _ in range(n_steps):
            inst.step(step)
            rows.append(inst.get(list(BLADE_OUT)) + [float(v) for v in inst.get(
                ["event_count", "slipping_right", "slipping_left", "lifted_right", "lifted_left"])])
        messages = inst.messages
    return {"rows": rows, "messages": messages}


def fmpy_simulate(path, cases):
    """fmpy's ``simulate_fmu`` (FMI 2 co-simulation, one second at 0.1 s, debug logging on) once per
    case of ``cases`` (JSON: a list of {parameter: value}): per case, whether it raised, the rows it
    returned and the FMU's log messages."""
    from fmpy import simulate_fmu

    out = []
    for values in json.loads(cases):
        messages = []

        def log(component, instance, status, category, message):
            messages.append(message.decode(errors="replace") if message else "")

        try:
            rows = len(simulate_fmu(str(path), stop_time=1.0, output_interval=0.1, start_values=values,
                                    debug_logging=True, logger=log))
            raised = None
        except Exception as exc:  # fmpy's FMICallException
            rows, raised = 0, str(exc)
        out.append({"raised": raised, "rows": rows, "messages": messages})
    return out


if __name__ == "__main__":
    print(json.dumps(globals()[sys.argv[1]](*sys.argv[2:])), flush=True)
