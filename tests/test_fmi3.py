"""FMI 3.0 co-simulation FMUs with early return (issue 28, part 2): build and validation, fmpy's FMU3Slave
as the host, event instants against the library's event log, whole steps where the host does not allow
early return (the FMI 2 FMU's numbers), FMU state, an FMI 2 and an FMI 3 FMU in one process, a slave's
exception as an error status."""
import json
import math
import subprocess
import sys
import zipfile

import numpy as np
import pytest
from fmpy import extract, instantiate_fmu, read_model_description, simulate_fmu

import frictionjoint as fj
from frictionjoint.fmi.build import FMUS, FMUS3, build_fmus, validate

# they build and run FMUs: fmu and slow, as the users of the fmus fixture (tests/conftest.py)
pytestmark = [pytest.mark.fmu, pytest.mark.slow]

#: README's oscillator (m = k = 1, P0 = 1 N): pure slip (no stops), stick-slip, long sticks
CASES = {
    "slip": dict(slip_force=0.5, force_amplitude=1.0, omega=1.5),
    "stick-slip": dict(slip_force=0.5, force_amplitude=1.0, omega=0.5),
    "long sticks": dict(slip_force=0.7, force_amplitude=1.0, omega=0.3),
}
PERIODS = 2
EVENT_TOL = 1e-12  # event instants [s] and outputs on the grid, against the library


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """name -> (model description, extracted folder, path): the FMI 3 FMUs with early return, the stock
    CoulombOscillator FMI 3 FMU ("stock") and the FMI 2 oscillator and Jenkins joint ("fmi2 ...")."""
    out = tmp_path_factory.mktemp("fmi3")
    paths = {n: p for n, p in zip(FMUS3, build_fmus(out, fmi_version=3))}
    paths["stock"] = build_fmus(out / "stock", names=["CoulombOscillator"], fmi_version=3, early_return=False)[0]
    for name, p in zip(("CoulombOscillator", "JenkinsJoint"), build_fmus(out / "fmi2", names=["CoulombOscillator",
                                                                                              "JenkinsJoint"])):
        paths["fmi2 " + name] = p
    return {n: (read_model_description(str(p)), extract(str(p)), p) for n, p in paths.items()}


def _instance(entry, allowed=True, event_mode=False):
    md, folder, _ = entry
    s = instantiate_fmu(folder, md, fmi_type="CoSimulation", early_return_allowed=allowed,
                        event_mode_used=event_mode)
    return s, {v.name: v.valueReference for v in md.modelVariables}


def host_loop(entry, params, t_end, h, allowed=True, event_mode=False, outputs=("x", "v")):
    """An FMI 3 host on fmpy's FMU3Slave: steps to the grid t0 + n h, continues from an early return;
    returns (early-return instants, [(t, outputs...)] on the grid, event_count)."""
    s, vr = _instance(entry, allowed, event_mode)
    s.setFloat64([vr[k] for k in params], list(params.values()))
    s.enterInitializationMode(startTime=0.0, stopTime=t_end)
    s.exitInitializationMode()
    if event_mode:
        s.updateDiscreteStates()
        s.enterStepMode()
    t, n, events, grid = 0.0, 0, [], []
    n_steps = int(round(t_end / h))
    while n < n_steps:
        target = (n + 1) * h
        handling, _, early, last = s.doStep(t, target - t)
        if early:
            assert t < last < target
            events.append(last)
            t = last
            if event_mode:
                assert handling
                s.enterEventMode()
                s.updateDiscreteStates()
                s.enterStepMode()
        else:
            t, n = target, n + 1
            grid.append((t, *s.getFloat64([vr[k] for k in outputs])))
    count = s.getInt32([vr["event_count"]])[0]
    s.terminate()
    s.freeInstance()
    return events, grid, count


def fmi2_loop(entry, params, t_end, h, outputs=("x", "v")):
    """The FMI 2 FMU stepped on the same grid."""
    md, folder, _ = entry
    s = instantiate_fmu(folder, md, fmi_type="CoSimulation")
    vr = {v.name: v.valueReference for v in md.modelVariables}
    s.setReal([vr[k] for k in params], list(params.values()))
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    grid = []
    for n in range(int(round(t_end / h))):
        s.doStep(n * h, (n + 1) * h - n * h)
        grid.append(((n + 1) * h, *s.getReal([vr[k] for k in outputs])))
    s.terminate()
    s.freeInstance()
    return grid


def library(params, t_end, grid_t=()):
    """The library's event instants in (0, t_end) and its (x, v) at ``grid_t``."""
    osc = fj.CoulombOscillator(mass=1.0, stiffness=1.0, **params)
    events = [t for t, _, _, _ in osc.simulate(t_end, 0.0, 0.0).events if 0.0 < t < t_end]
    tr = osc.simulate(t_end, 0.0, 0.0, t_eval=np.concatenate([[0.0], grid_t])) if len(grid_t) else None
    return events, tr


def test_fmi3_fmus_build_validate_and_declare_what_they_do(built):
    assert set(FMUS3) <= set(FMUS)  # FMI 3 versions of FMI 2 models, under names of their own
    stems = [s[:-3] for s in FMUS3.values()]
    assert len(set(stems) | {s[:-3] for s in FMUS.values()}) == len(stems) + len(FMUS)
    for name in FMUS3:
        md, _, path = built[name]
        assert path.name == f"{name}Fmi3.fmu" and md.fmiVersion == "3.0"
        assert validate(path) == []
        cs = md.coSimulation
        assert cs.modelIdentifier == f"{name}Fmi3"
        assert cs.mightReturnEarlyFromDoStep and cs.hasEventMode and cs.canGetAndSetFMUstate
        assert cs.canSerializeFMUstate and cs.canHandleVariableCommunicationStepSize and not cs.needsExecutionTool
        with zipfile.ZipFile(path) as z:  # the patched binary alone (no platform with a stock one)
            assert [n for n in z.namelist() if n.startswith("binaries/")] == [f"binaries/x86_64-linux/{name}Fmi3.so"]
            assert "lastSuccessfulTime = *earlyReturn" in z.read("sources/src/cppfmu/fmi_functions.cpp").decode()
    md, _, path = built["stock"]
    assert validate(path) == []
    assert not md.coSimulation.mightReturnEarlyFromDoStep and not md.coSimulation.hasEventMode
    with zipfile.ZipFile(path) as z:
        assert "binaries/x86_64-windows/CoulombOscillatorFmi3.dll" in z.namelist()
    with pytest.raises(ValueError, match="fmi_version"):
        build_fmus(path.parent, names=["BladeDovetail"], fmi_version=3)


@pytest.mark.parametrize("case", list(CASES))
def test_early_return_at_the_library_events(built, case):
    """Every event of the exact solution is an early return at its instant (1e-12 s), with and without
    event mode, at two communication steps; on the grid the outputs are the library's."""
    p = CASES[case]
    period = 2 * math.pi / p["omega"]
    t_end = PERIODS * period
    for divisions in (20, 7):
        h = t_end / (PERIODS * divisions)
        grid_t = np.minimum((np.arange(PERIODS * divisions) + 1) * h, t_end)  # (the last one rounds above)
        ref, tr = library(p, t_end, grid_t)
        for event_mode in (False, True):
            events, grid, count = host_loop(built["CoulombOscillator"], p, t_end, h, event_mode=event_mode)
            assert len(events) == len(ref) > 0
            assert max(abs(a - b) for a, b in zip(events, ref)) <= EVENT_TOL
            assert count == len(ref) + 1  # and the settle at t = 0
            x = np.array([g[1] for g in grid])
            v = np.array([g[2] for g in grid])
            assert np.max(np.abs(x - tr.x[1:])) <= EVENT_TOL
            assert np.max(np.abs(v - tr.v[1:])) <= EVENT_TOL


@pytest.mark.parametrize("event_mode", [False, True])
def test_fmpy_simulate_fmu_with_early_return(built, event_mode):
    p = CASES["stick-slip"]
    period = 2 * math.pi / p["omega"]
    t_end = PERIODS * period
    res = simulate_fmu(str(built["CoulombOscillator"][2]), stop_time=t_end, output_interval=period / 20,
                       start_values=p, early_return_allowed=True, use_event_mode=event_mode, output=["x"])
    grid = np.arange(PERIODS * 20 + 1) * period / 20
    off_grid = sorted({float(t) for t in res["time"] if np.min(np.abs(grid - t)) > 1e-9 * period})
    ref, _ = library(p, t_end)
    assert len(off_grid) == len(ref) > 0
    assert max(abs(a - b) for a, b in zip(off_grid, ref)) <= EVENT_TOL


def test_whole_steps_where_the_host_does_not_allow_early_return(built):
    """No early return unless allowed, nor from pythonfmu3's stock binary: the FMI 2 FMU's numbers."""
    p = CASES["stick-slip"]
    period = 2 * math.pi / p["omega"]
    h = period / 20
    fmi2 = fmi2_loop(built["fmi2 CoulombOscillator"], p, PERIODS * period, h)
    for name, allowed in (("CoulombOscillator", False), ("stock", True), ("stock", False)):
        events, grid, _ = host_loop(built[name], p, PERIODS * period, h, allowed=allowed)
        assert events == []
        assert grid == fmi2  # bit for bit


def _three_steps(s, vr, params):
    """Initialise and take three 1 s steps (whole, or to an event); returns the time reached."""
    s.setFloat64([vr[k] for k in params], list(params.values()))
    s.enterInitializationMode(startTime=0.0)
    s.exitInitializationMode()
    t = 0.0
    for _ in range(3):
        t = s.doStep(t, 1.0)[3]
    return t


def test_fmu_state_rollback_and_serialisation(built):
    p = CASES["stick-slip"]
    s, vr = _instance(built["CoulombOscillator"])
    t = _three_steps(s, vr, p)
    state = s.getFMUState()
    blob = s.serializeFMUState(state)
    first = s.doStep(t, 5.0)  # an early return inside
    after = s.getFloat64([vr["time"], vr["x"], vr["v"]])
    assert first[2]
    for restore in (lambda: s.setFMUState(state), lambda: s.setFMUState(s.deserializeFMUState(blob))):
        restore()
        assert s.getFloat64([vr["time"]]) == [t]
        assert s.doStep(t, 5.0) == first
        assert s.getFloat64([vr["time"], vr["x"], vr["v"]]) == after
    s.freeFMUState(state)
    s.terminate()
    s.reset()  # a new run of the same instance: the host's flags still hold (the wrapper sets them again)
    assert s.doStep(_three_steps(s, vr, p), 5.0) == first
    s.terminate()
    s.freeInstance()


def _triangle(amplitude, period):
    """u(t) and the slope of the segment that starts at t: a triangle wave from 0 (vertices at odd
    quarter periods)."""
    def u(t):
        ph = (t / period) % 1.0
        return amplitude * (4 * ph if ph < 0.25 else 2 - 4 * ph if ph < 0.75 else 4 * ph - 4)

    def slope(t):
        ph = round((t / period) % 1.0, 12)
        return 4 * amplitude / period * (1.0 if (ph < 0.25 or ph >= 0.75) else -1.0)
    return u, slope


def joint_loop(entry, params, u, slope, t_end, h, allowed=True, fmi2=False):
    """A host driving a joint with u(t) and its rate, set at every step's start (the joint holds both
    over the step: u moves as u + velocity tau); returns (early-return instants, force on the grid)."""
    md, folder, _ = entry
    s = instantiate_fmu(folder, md, fmi_type="CoSimulation", **({} if fmi2 else dict(early_return_allowed=allowed)))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    set_, get = (s.setReal, s.getReal) if fmi2 else (s.setFloat64, s.getFloat64)
    set_([vr[k] for k in params], list(params.values()))
    if fmi2:
        s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    t, n, events, forces = 0.0, 0, [], []
    while n < int(round(t_end / h)):
        target = (n + 1) * h
        set_([vr["u"], vr["velocity"]], [u(t), slope(t)])
        result = s.doStep(t, target - t)
        if not fmi2 and result[2]:
            events.append(result[3])
            t = result[3]
            continue
        t, n = target, n + 1
        set_([vr["u"], vr["velocity"]], [u(t), slope(t)])
        forces.append(get([vr["force"]])[0])
    s.terminate()
    s.freeInstance()
    return events, forces


def test_joint_returns_early_where_a_slider_reaches_its_slip_force(built):
    """Jenkins joint (k = 100 N/m, slip force 0.8 N: travel 8 mm) under a triangle wave of 50 mm and 1 s
    whose vertices are on the grid (T/8): it slips 8 mm after the start and 16 mm after each reversal;
    the force on the grid is the FMI 2 joint's; no early return unless allowed. An Iwan joint returns at
    each slider's slip."""
    amplitude, period, t_end, h = 0.05, 1.0, 2.0, 1.0 / 8
    u, slope = _triangle(amplitude, period)
    rate = 4 * amplitude / period
    reach = 0.8 / 100
    exact = [reach / rate] + [(2 * k + 1) * period / 4 + 2 * reach / rate for k in range(4)]
    params = dict(stiffness=100.0, slip_force=0.8)
    events, forces = joint_loop(built["JenkinsJoint"], params, u, slope, t_end, h)
    assert len(events) == len(exact)
    assert max(abs(a - b) for a, b in zip(events, exact)) <= EVENT_TOL
    _, forces2 = joint_loop(built["fmi2 JenkinsJoint"], params, u, slope, t_end, h, fmi2=True)
    assert max(abs(a - b) for a, b in zip(forces, forces2)) <= EVENT_TOL
    assert joint_loop(built["JenkinsJoint"], params, u, slope, t_end, h, allowed=False) == ([], forces2)
    # the Iwan joint's defaults (Segalman, 20 sliders and the macroslip one): on the first quarter (u from 0
    # to 50 mm) each slider slips once, where u reaches its travel slip_force / stiffness
    iwan = fj.Iwan.segalman(0.8, 100.0, -0.5, 0.1, 20, dof=0)
    k, f = map(np.array, zip(*iwan.sliders_table))
    events, _ = joint_loop(built["IwanJoint"], {}, u, slope, period / 4, h)
    exact = np.sort(f / k) / rate
    assert len(events) == len(exact) == 21
    assert np.max(np.abs(np.array(events) - exact)) <= EVENT_TOL


ONE_PROCESS = r"""
import json, sys
from fmpy import simulate_fmu, extract, instantiate_fmu, read_model_description
from fmpy.fmi1 import FMICallException
fmi2, fmi3 = sys.argv[1], sys.argv[2]
a = simulate_fmu(fmi2, stop_time=10.0, output_interval=0.5, output=["x"])
b = simulate_fmu(fmi3, stop_time=10.0, output_interval=0.5, output=["x"], early_return_allowed=True)
md = read_model_description(fmi3)
folder = extract(fmi3)
vr = {v.name: v.valueReference for v in md.modelVariables}
errors = []
for slip_force in (-1.0, 0.5):  # a bad parameter raises in the slave: an error status, the process lives
    s = instantiate_fmu(folder, md, fmi_type="CoSimulation", early_return_allowed=True)
    s.setFloat64([vr["slip_force"]], [slip_force])
    s.enterInitializationMode(startTime=0.0)
    try:
        s.exitInitializationMode()
        errors.append(s.doStep(0.0, 10.0)[2])
    except FMICallException as exc:
        errors.append(str(exc))
    s.freeInstance()
import gc; gc.collect()
print(json.dumps({"fmi2": float(a["x"][-1]), "fmi3": float(b["x"][-1]), "errors": errors}))
"""


@pytest.mark.parametrize("fmi3", ["CoulombOscillator", "stock"])
def test_fmi2_and_fmi3_fmus_in_one_process_and_an_exception(built, fmi3):
    """In a fresh process: both FMUs run, a slave's exception is an error status (fatal) and the next
    instance runs, and the process exits normally (the patched binary released its interpreter holder
    twice at exit before patch item 4: SIGSEGV)."""
    proc = subprocess.run([sys.executable, "-c", ONE_PROCESS, str(built["fmi2 CoulombOscillator"][2]),
                           str(built[fmi3][2])], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr[-3000:]
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert abs(out["fmi2"] - out["fmi3"]) <= EVENT_TOL
    assert "fmi3ExitInitializationMode" in out["errors"][0] and out["errors"][1] is (fmi3 != "stock")


def test_build_fmus_command_fmi3(tmp_path):
    from frictionjoint.cli import main

    assert main(["build-fmus", "--fmi-version", "3", "--only", "JenkinsJoint", "--out", str(tmp_path)]) == 0
    assert [p.name for p in tmp_path.glob("*.fmu")] == ["JenkinsJointFmi3.fmu"]
    for bad in (["--only", "BladeDovetail"], ["--structure", "models/two_dof_chain.toml"]):
        with pytest.raises(SystemExit) as exc:
            main(["build-fmus", "--fmi-version", "3", "--out", str(tmp_path), *bad])
        assert exc.value.code == 2


def test_fmi3_component_in_an_ssp_and_refused_by_the_fmi2_master(built, tmp_path):
    """An FMU system with an FMI 3 joint: written as SSP (its Float64 ports as SSP 1.0 Real
    connectors), and this library's FMI 2 master refuses it by name instead of failing inside fmpy."""
    from frictionjoint.errors import ParameterError
    from frictionjoint.fmi.cosim import FMUSystem

    s = FMUSystem({"osc": built["fmi2 CoulombOscillator"][2], "j": built["JenkinsJoint"][2]},
                  [("osc.x", "j.u")], parameters={"j": {"slip_force": 0.5}})
    ssp = s.to_ssp(tmp_path / "mixed.ssp")
    with zipfile.ZipFile(ssp) as z:
        ssd = z.read("SystemStructure.ssd").decode()
    assert 'name="u"' in ssd and "ssc:Real" in ssd and "Float64" not in ssd
    with pytest.raises(ParameterError, match="component 'j' is an FMI 3.0 FMU"):
        s.simulate(1.0, 0.1, ["osc.x"])
