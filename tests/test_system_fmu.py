"""A whole friction system as one FMU (frictionjoint.system_file, frictionjoint.fmi.system_slave):
the README's two-DOF chain with its two Jenkins joints (models/two_dof_chain_system.toml) as one
FMU, run by fmpy.simulate_fmu (in a subprocess) and by Ecos, against frictionjoint.simulate of the
same FrictionSystem at every communication point; the run without FMI; the file's errors."""
import json
import math
import platform
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.fmi.system_slave import SystemRun
from frictionjoint.system_file import SystemDefinition, load_system_definition

ROOT = Path(__file__).resolve().parents[1]
CHAIN = ROOT / "models" / "two_dof_chain_system.toml"
OMEGA = 1.2
T = 2 * math.pi / OMEGA
PERIODS = 4
DIVISIONS = (20, 50, 100)
TOL = 1e-10  # every communication point, relative to the largest |x| (|v|, |force|) of the motion
OUTPUTS = ["x_x1", "x_x2", "v_x1", "v_x2", "force_j1", "force_j2", "dissipated_energy"]


def chain_system():
    """The chain as the README and benchmarks/cosim_coupling.py write it in the library."""
    structure = fj.LinearStructure([[1.0, 0.0], [0.0, 1.0]], [[2.0, -1.0], [-1.0, 1.0]],
                                   [[0.04, -0.02], [-0.02, 0.02]], dof_names=["x1", "x2"])
    return fj.FrictionSystem(structure, [fj.Jenkins(100.0, 0.8, dof="x1"), fj.Jenkins(100.0, 0.8, dof="x2")],
                             omega=OMEGA, excitation=[fj.HarmonicForce("x2", 1.0)])


def errors(t, values):
    """Largest deviation of the outputs ``values`` (name -> (n_t,)) from fj.simulate at ``t``,
    relative to each quantity's largest value; and the dissipated energy's, relative to its end."""
    ref = fj.simulate(chain_system(), t[-1], t_eval=t, record=("x", "v", "friction_force", "energy"))
    out = {}
    for key, rows in (("x", ref.x), ("v", ref.v), ("force", ref.friction_force)):
        names = [n for n in OUTPUTS if n.startswith(key + "_")]
        got = np.vstack([values[n] for n in names])
        out[key] = float(np.max(np.abs(got - rows)) / np.max(np.abs(rows)))
    diss = ref.dissipated_friction
    out["energy"] = float(np.max(np.abs(np.asarray(values["dissipated_energy"]) - diss)) / diss[-1])
    return out


@pytest.fixture(scope="module")
def chain_fmu(tmp_path_factory):
    """The chain's FMU, built by ``frictionjoint build-fmus --system`` (this process) and valid."""
    from frictionjoint.cli import main
    from frictionjoint.fmi.build import validate

    out = tmp_path_factory.mktemp("system_fmu")
    assert main(["build-fmus", "--system", str(CHAIN), "--out", str(out)]) == 0
    assert [p.name for p in out.iterdir()] == ["TwoDofChainSystem.fmu"]
    path = out / "TwoDofChainSystem.fmu"
    assert validate(path) == []
    return path


def test_cli_names_the_key_of_a_bad_file(tmp_path, capsys):
    from frictionjoint.cli import main

    (tmp_path / "bad.toml").write_text('structure = "%s"\n[excitation]\nomega = -1.0\n'
                                       % (ROOT / "models" / "two_dof_chain.toml"))
    with pytest.raises(SystemExit) as exc:
        main(["build-fmus", "--system", str(tmp_path / "bad.toml"), "--out", str(tmp_path)])
    assert exc.value.code == 2
    assert "excitation.omega" in capsys.readouterr().err


def test_the_file_is_the_library_system(tmp_path):
    d = load_system_definition(CHAIN)
    s, ref = d.system(), chain_system()
    for attr in ("mass", "stiffness", "damping", "slider_stiffness", "slip_force", "slider_direction"):
        np.testing.assert_array_equal(getattr(s, attr), getattr(ref, attr))
    assert s.omega == ref.omega
    np.testing.assert_array_equal(s.harmonic_force(np.array([0.3, 1.7])), ref.harmonic_force(np.array([0.3, 1.7])))
    assert d.inputs == ("x1", "x2") and d.joint_force == ("j1", "j2")
    # the normalised form (the FMU's resource) gives the same definition
    again = SystemDefinition.from_dict(json.loads(json.dumps(d.to_dict())))
    assert again.to_dict() == d.to_dict()
    assert load_system_definition(d.to_json(tmp_path / "chain.json")).to_dict() == d.to_dict()


def test_run_matches_simulate_and_holds_inputs():
    """The run without FMI at T/20: within TOL of fj.simulate; a held force is the library's
    ExternalForce over the same steps."""
    d = load_system_definition(CHAIN)
    h = T / 20
    t = h * np.arange(20 * PERIODS + 1)
    run = SystemRun(d, {})
    values = {n: [] for n in OUTPUTS}
    for tk in t:
        run.advance(tk)
        for n in OUTPUTS:
            values[n].append(run.output(n))
    err = errors(t, values)
    assert max(err.values()) <= TOL, err
    # an external force on x1, held over each step: 0.3 N on the first 10 steps, -0.2 N on the next 10
    run = SystemRun(d, {}, forces=(0.0, 0.0))
    x = []
    for k in range(20):
        run.hold((0.3 if k < 10 else -0.2, 0.0))
        run.advance((k + 1) * h)
        x.append(run.state.x.copy())
    ext = fj.ExternalForce("x1", h * np.array([0.0, 10.0, 20.0]), [0.3, -0.2])
    sysm = fj.FrictionSystem(chain_system().structure, chain_system().elements, omega=OMEGA,
                             excitation=[fj.HarmonicForce("x2", 1.0), ext])
    ref = fj.simulate(sysm, 20 * h, t_eval=h * np.arange(1, 21), record=("x",))
    assert np.max(np.abs(np.array(x).T - ref.x)) <= TOL * np.max(np.abs(ref.x))


def test_joints_far_stiffer_than_the_structure_run_as_frictionjoint_simulate_runs_them():
    """Issue 39: Jenkins springs 1e12 times stiffer than the chain chatter at their stuck mode's rate
    (about sqrt(kt) events a period) and the FMU's march stopped as chattering; the FMU marches them
    as rigid sliders, their exact limit, as fj.simulate does (FrictionSystem.rigid_limit): the same
    motion within TOL (the same closed-form pieces: measured 8.3e-15)."""
    d = load_system_definition(CHAIN)
    stiff = {"j1_tangential_stiffness": 1e12, "j2_tangential_stiffness": 1e12}
    h = T / 20
    t = h * np.arange(20 * 2 + 1)
    run = SystemRun(d, stiff)
    x = []
    for tk in t:
        run.advance(tk)
        x.append([run.output("x_x1"), run.output("x_x2")])
    structure = chain_system().structure
    ref = fj.simulate(fj.FrictionSystem(structure, [fj.Jenkins(1e12, 0.8, dof="x1"), fj.Jenkins(1e12, 0.8, dof="x2")],
                                        omega=OMEGA, excitation=[fj.HarmonicForce("x2", 1.0)]),
                      t[-1], t_eval=t, record=("x",))
    assert "marched as rigid" in ref.message
    assert np.max(np.abs(np.array(x).T - ref.x)) <= TOL * np.max(np.abs(ref.x))


@pytest.mark.slow  # a fresh Python with fmpy and the FMU's bundle: about 2 s
def test_fmpy_simulate_fmu_at_three_steps(chain_fmu):
    """fmpy.simulate_fmu (its own process: the FMU's bundle is not this process's package) at
    T/20, T/50, T/100: every communication point within TOL of fj.simulate."""
    code = ("import json, sys\nfrom fmpy import simulate_fmu\nout = {}\n"
            "for d in (%s):\n"
            "    r = simulate_fmu(sys.argv[1], stop_time=%r, output_interval=%r / d, output=%r)\n"
            "    out[d] = {n: r[n].tolist() for n in r.dtype.names}\n"
            "print(json.dumps(out))\n") % (", ".join(map(str, DIVISIONS)), PERIODS * T, T, OUTPUTS)
    proc = subprocess.run([sys.executable, "-c", code, str(chain_fmu)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr[-3000:]
    results = json.loads(proc.stdout.strip().splitlines()[-1])
    for d in DIVISIONS:
        r = results[str(d)]
        t = np.asarray(r["time"])
        assert t.size == d * PERIODS + 1 and abs(t[-1] - PERIODS * T) <= 1e-12 * PERIODS * T
        err = errors(t, r)
        assert max(err.values()) <= TOL, (d, err)


HELD = """
import json, sys
from frictionjoint.fmi.master import FMUInstance

h, out = float(sys.argv[2]), {}
with FMUInstance(sys.argv[1]) as inst:
    inst.initialize()
    rows = []
    for k in range(20):
        inst.set({"force_x1": 0.3 if k < 10 else -0.2})
        if k == 10:
            saved = inst.get_state()
        inst.step_between(k * h, (k + 1) * h)  # the same times in both runs
        rows.append(inst.get(["x_x1", "x_x2", "event_count"]))
    out["rows"] = rows
    inst.set_state(saved)  # serialised: the second half again, bit for bit
    again = []
    for k in range(10, 20):
        inst.set({"force_x1": -0.2})
        inst.step_between(k * h, (k + 1) * h)
        again.append(inst.get(["x_x1", "x_x2", "event_count"]))
    out["again"] = again
with FMUInstance(sys.argv[1]) as inst:
    try:
        inst.initialize({"j1_slip_force": -1.0})
        out["raised"] = None
    except Exception as exc:  # fmpy's FMICallException
        out["raised"] = str(exc)
    out["messages"] = inst.messages
with FMUInstance(sys.argv[1]) as inst:
    inst.initialize()
    try:
        inst.step_between(0.0, 1e6)
        out["long"] = None
    except Exception as exc:  # fmi2Discard
        out["long"] = str(exc)
    inst.step_between(0.0, h)  # the state is the step's start: the run goes on
    out["after_long"] = inst.get(["x_x2", "event_count"])
    out["long_messages"] = inst.messages
print(json.dumps(out))
"""


@pytest.mark.slow  # a fresh Python with fmpy and the FMU's bundle: about 2 s
def test_fmu_holds_inputs_restores_state_and_names_a_bad_parameter(chain_fmu):
    """Through the FMU (its own process): an external force on x1 held over each step is the
    library's ExternalForce; a serialised state restarts the run bit for bit; a negative slip
    force fails initialisation with a message naming the parameter; a step beyond the budget is
    refused (fmi2Discard) and the next step goes on from its start."""
    h = T / 20
    proc = subprocess.run([sys.executable, "-c", HELD, str(chain_fmu), repr(h)], capture_output=True, text=True,
                          timeout=120)
    assert proc.returncode == 0, proc.stderr[-3000:]
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    ext = fj.ExternalForce("x1", h * np.array([0.0, 10.0, 20.0]), [0.3, -0.2])
    ref_system = chain_system()
    sysm = fj.FrictionSystem(ref_system.structure, ref_system.elements, omega=OMEGA,
                             excitation=[fj.HarmonicForce("x2", 1.0), ext])
    ref = fj.simulate(sysm, 20 * h, t_eval=h * np.arange(1, 21), record=("x",))
    x = np.array(out["rows"])[:, :2].T
    assert np.max(np.abs(x - ref.x)) <= TOL * np.max(np.abs(ref.x))
    assert out["again"] == out["rows"][10:]
    assert out["rows"][-1][2] > 0  # events happened
    assert out["raised"] is not None
    assert any("j1_slip_force" in m and ">= 0" in m for m in out["messages"]), out["messages"]
    # a step beyond the budget (1e6 s: about 3e5 cycles) is refused with the reason, and the run
    # goes on from the step's start
    assert out["long"] is not None
    assert any("take shorter steps" in m for m in out["long_messages"]), out["long_messages"]
    ref = fj.simulate(chain_system(), h, t_eval=[h], record=("x",))
    assert abs(out["after_long"][0] - ref.x[1, 0]) <= TOL * np.max(np.abs(ref.x))


@pytest.mark.slow  # three Ecos processes: about 5 s
@pytest.mark.skipif(not (sys.platform == "linux" and platform.machine() == "x86_64"),
                    reason="ecospy (Ecos) has wheels for Linux x86_64 only")
def test_ecos_at_three_steps(chain_fmu):
    """Ecos (its library, in its own process, time accumulated) at T/20, T/50, T/100: every
    communication point within TOL of fj.simulate at Ecos's times."""
    from frictionjoint.fmi.cosim import FMUSystem
    from frictionjoint.fmi.ecos import run_ecos

    system = FMUSystem({"chain": chain_fmu})
    for d in DIVISIONS:
        r = run_ecos(system, PERIODS * T, T / d, [f"chain.{n}" for n in OUTPUTS])
        assert r.success, r.message
        t = np.asarray(r.t)
        assert t.size == d * PERIODS + 1
        err = errors(t, {n: r[f"chain.{n}"] for n in OUTPUTS})
        assert max(err.values()) <= TOL, (d, err)


@pytest.mark.parametrize("change, message", [
    (lambda data: data.pop("structure"), "'structure'"),
    (lambda data: data["joints"][0].pop("slip_force"), "'slip_force'"),
    (lambda data: data["joints"][1].update(type="masing"), "joints[1].type"),
    (lambda data: data["joints"][0].update(slip_force=-1.0), "slip_force"),
    (lambda data: data["joints"][0].update(dof="x3"), "joint 'j1' dof"),
    (lambda data: data["joints"][1].update(name="j1"), "distinct"),
    (lambda data: data["excitation"].update(inputs=["x9"]), "excitation.inputs"),
    (lambda data: data["excitation"].update(omega=0.0), "excitation.omega"),
    (lambda data: data["excitation"].update(force_amplitude=3.0), "excitation.force_amplitude"),
    (lambda data: data["excitation"].update(inputs="x1"), "excitation.inputs"),
    (lambda data: data["joints"][0].update(tangential_stiffness="stiff"), r"joints[0].tangential_stiffness"),
    (lambda data: data["joints"][0].update(name="j-1"), r"joints[0].name"),
    (lambda data: data["outputs"].update(joint_force=["j3"]), "outputs.joint_force"),
    (lambda data: data["outputs"].update(velocity=["x1", "y"]), "outputs.velocity"),
    (lambda data: data.update(colour="red"), "colour"),
    (lambda data: data["structure"].pop("mass"), "'mass'"),
])
def test_loading_errors_name_the_key(change, message):
    data = load_system_definition(CHAIN).to_dict()
    change(data)
    with pytest.raises(ParameterError, match=message.replace("[", r"\[").replace("(", r"\(")):
        SystemDefinition.from_dict(data)


def test_structure_file_relative_to_the_definition(tmp_path):
    (tmp_path / "s.toml").write_text('structure = "missing.toml"\n')
    with pytest.raises(ParameterError, match="structure .'missing.toml'.*not found"):
        load_system_definition(tmp_path / "s.toml")
    (tmp_path / "s.toml").write_text(f'structure = "{ROOT / "models" / "two_dof_chain.toml"}"\n'
                                     '[[joints]]\nname = "slider"\ntype = "coulomb"\ndof = "x2"\nslip_force = 0.1\n')
    d = load_system_definition(tmp_path / "s.toml")
    # the structure definition's excitation and outputs, every joint's force; named after the file
    assert d.name == "s" and d.omega == OMEGA and d.force_amplitude == {"x2": 1.0}
    assert d.displacement == ("x1", "x2") and d.joint_force == ("slider",) and d.inputs == ()
    assert set(d.parameters()) == {"omega", "force_amplitude_x2", "slider_slip_force"}


def test_run_with_coulomb_and_iwan_joints_matches_simulate():
    """A Coulomb slider (slipping from the start: 1 N on its DOF against 0.3 N) and a Segalman Iwan
    joint (8 sliders) on the chain, stepped at T/20 with SystemRun: x and each joint's force within
    TOL of fj.simulate of the file's system, the same events (those of the start included)."""
    data = load_system_definition(CHAIN).to_dict()
    data["joints"] = [{"name": "c", "type": "coulomb", "dof": "x2", "slip_force": 0.3},
                      {"name": "iw", "type": "iwan", "dof": "x1", "slip_force": 0.5, "stiffness": 50.0,
                       "chi": -0.5, "beta": 0.1, "n_sliders": 8}]
    data["outputs"]["joint_force"] = ["c", "iw"]
    d = SystemDefinition.from_dict(data)
    assert set(d.parameters()) >= {"c_slip_force", "iw_slip_force", "iw_stiffness", "iw_chi", "iw_beta"}
    t = T / 20 * np.arange(20 * 2 + 1)
    ref = fj.simulate(d.system(), t[-1], t_eval=t, record=("x", "friction_force", "energy"))
    run = SystemRun(d, {})
    x, f, e = [], [], []
    for tk in t:
        run.advance(tk)
        x.append([run.output("x_x1"), run.output("x_x2")])
        f.append([run.output("force_c"), run.output("force_iw")])
        e.append(run.output("dissipated_energy"))
    assert len(run.log) > 4  # the joints stick and slip
    assert run.log.time[0] == 0.0 and run.output("event_count") == len(ref.events)
    assert np.max(np.abs(np.array(x).T - ref.x)) <= TOL * np.max(np.abs(ref.x))
    assert np.max(np.abs(np.array(f).T - ref.friction_force)) <= TOL * np.max(np.abs(ref.friction_force))
    assert np.max(np.abs(np.array(e) - ref.dissipated_friction)) <= TOL * ref.dissipated_friction[-1]


def test_run_from_a_later_start_time():
    """From rest at t0 = 1.3 s (the excitation's phase is absolute): fj.simulate with t0."""
    d = load_system_definition(CHAIN)
    t = 1.3 + T / 20 * np.arange(21)
    ref = fj.simulate(d.system(), t[-1], t0=1.3, t_eval=t, record=("x",))
    run = SystemRun(d, {}, start_time=1.3)
    x = []
    for tk in t:
        run.advance(tk)
        x.append(run.state.x.copy())
    assert np.max(np.abs(np.array(x).T - ref.x)) <= TOL * np.max(np.abs(ref.x))
    with pytest.raises(ParameterError, match="t must be >= the current time"):
        run.advance(1.0)


def test_a_joint_between_two_dofs():
    """A Jenkins joint along x1 - x2 (direction), in the file and in the library: the same system,
    and the run within TOL of fj.simulate."""
    data = load_system_definition(CHAIN).to_dict()
    data["joints"][1] = {"name": "j12", "type": "jenkins", "direction": {"x1": 1.0, "x2": -1.0},
                         "tangential_stiffness": 20.0, "slip_force": 0.3}
    data["outputs"]["joint_force"] = ["j12"]
    d = SystemDefinition.from_dict(data)
    assert "along +1 x1 -1 x2" in d.parameters()["j12_slip_force"][1]
    s = d.system()
    np.testing.assert_array_equal(s.slider_direction, [[1.0, 0.0], [1.0, -1.0]])
    t = T / 20 * np.arange(20 * 2 + 1)
    ref = fj.simulate(s, t[-1], t_eval=t, record=("x", "friction_force"))
    run = SystemRun(d, {})
    x, f = [], []
    for tk in t:
        run.advance(tk)
        x.append([run.output("x_x1"), run.output("x_x2")])
        f.append(run.output("force_j12"))
    assert len(run.log) > 4
    assert np.max(np.abs(np.array(x).T - ref.x)) <= TOL * np.max(np.abs(ref.x))
    assert np.max(np.abs(np.array(f) - ref.friction_force[1])) <= TOL * np.max(np.abs(ref.friction_force[1]))
    for bad, message in (({"x1": 1.0, "x3": -1.0}, "joint 'j12' direction"), ({}, r"joints\[1\].direction")):
        data["joints"][1]["direction"] = bad
        with pytest.raises(ParameterError, match=message):
            SystemDefinition.from_dict(data)
    data["joints"][1]["dof"] = "x2"
    with pytest.raises(ParameterError, match="one of 'dof'"):
        SystemDefinition.from_dict(data)


@pytest.mark.parametrize("variation", [False, True])
def test_a_rocking_dovetail_root(variation):
    """A dovetail root that rocks on its flanks (rocking_dof, flank_half_width: the blade models'
    root) on a three-DOF root (tangential X, radial Y, rotation R): the file's joint is the
    library's DovetailRoot, and the run at T/20 is within TOL of fj.simulate."""
    data = {"structure": {"dofs": ["X", "Y", "R"], "mass": np.diag([1.0, 1.0, 2e-4]).tolist(),
                          "stiffness": [[100.0, 0.0, 1.0], [0.0, 100.0, 0.0], [1.0, 0.0, 5.0]],
                          "damping": (0.002 * np.array([[100.0, 0.0, 1.0], [0.0, 100.0, 0.0],
                                                        [1.0, 0.0, 5.0]])).tolist()},
            "joints": [{"name": "root", "type": "dovetail", "tangential_dof": "X", "radial_dof": "Y",
                        "rocking_dof": "R", "flank_half_width": 0.01,
                        "centrifugal_force": 10.0, "flank_angle": 0.5, "friction_coefficient": 0.3,
                        "normal_stiffness": 1000.0, "tangential_stiffness": 500.0,
                        "normal_load_variation": variation}],
            "excitation": {"omega": 8.0, "force_amplitude": {"X": 8.0}}}
    d = SystemDefinition.from_dict(data)
    assert SystemDefinition.from_dict(json.loads(json.dumps(d.to_dict()))).to_dict() == d.to_dict()
    assert "flank_half_width" in d.joints[0].to_dict() and "root_flank_half_width" not in d.parameters()
    period = 2 * math.pi / 8.0
    t = period / 20 * np.arange(20 * 2 + 1)
    root = fj.DovetailRoot(10.0, 0.5, 0.3, 1000.0, 500.0, tangential_dof="X", radial_dof="Y", rocking_dof="R",
                           flank_half_width=0.01, normal_load_variation=variation)
    system = fj.FrictionSystem(d.structure, [root], omega=8.0, excitation=[fj.HarmonicForce("X", 8.0)])
    ref = fj.simulate(system, t[-1], t_eval=t, record=("x", "energy"))
    np.testing.assert_array_equal(fj.simulate(d.system(), t[-1], t_eval=t, record=("x",)).x, ref.x)
    run = SystemRun(d, {})
    x, e = [], []
    for tk in t:
        run.advance(tk)
        x.append(run.state.x.copy())
        e.append(run.output("dissipated_energy"))
    assert len(run.log) > 10
    assert np.max(np.abs(np.array(x).T - ref.x), axis=1).max() <= TOL * np.max(np.abs(ref.x))
    assert np.max(np.abs(np.array(e) - ref.dissipated_friction)) <= TOL * ref.dissipated_friction[-1]
    data["joints"][0]["flank_half_width"] = -1.0
    with pytest.raises(ParameterError, match="flank_half_width"):
        SystemDefinition.from_dict(data)
    data["joints"][0].pop("flank_half_width")
    with pytest.raises(ParameterError, match="rocking_dof and flank_half_width go together"):
        SystemDefinition.from_dict(data)
    data["joints"][0].pop("tangential_dof"), data["joints"][0].pop("radial_dof")
    with pytest.raises(ParameterError, match=r"needs 'tangential_dof' or 'radial_dof'"):
        SystemDefinition.from_dict(data)


@pytest.mark.parametrize("variation", [False, True])
def test_a_dovetail_root(variation):
    """A flat-flank dovetail root on a two-DOF root (tangential X, radial Y), with and without
    normal-load variation (lift-off): the file's system is the library's, and the run at T/20 is
    within TOL of fj.simulate (x, the flanks' summed friction force, the friction energy)."""
    data = {"structure": {"dofs": ["X", "Y"], "mass": [[1.0, 0.0], [0.0, 1.0]],
                          "stiffness": [[100.0, 0.0], [0.0, 100.0]], "damping": [[0.2, 0.0], [0.0, 0.2]]},
            "joints": [{"name": "root", "type": "dovetail", "tangential_dof": "X", "radial_dof": "Y",
                        "centrifugal_force": 10.0, "flank_angle": 0.5, "friction_coefficient": 0.3,
                        "normal_stiffness": 1000.0, "tangential_stiffness": 500.0,
                        "normal_load_variation": variation}],
            "excitation": {"omega": 8.0, "force_amplitude": {"X": 8.0}}}
    d = SystemDefinition.from_dict(data)
    assert d.joints[0].to_dict()["normal_damping"] == 0.0
    assert SystemDefinition.from_dict(json.loads(json.dumps(d.to_dict()))).to_dict() == d.to_dict()
    assert "root_centrifugal_force" in d.parameters() and "root_normal_load_variation" not in d.parameters()
    period = 2 * math.pi / 8.0
    t = period / 20 * np.arange(20 * 2 + 1)
    ref = fj.simulate(d.system(), t[-1], t_eval=t, record=("x", "friction_force", "energy"))
    root = fj.DovetailRoot(10.0, 0.5, 0.3, 1000.0, 500.0, tangential_dof="X", radial_dof="Y",
                           normal_load_variation=variation)
    lib = fj.simulate(fj.FrictionSystem(d.structure, [root], omega=8.0, excitation=[fj.HarmonicForce("X", 8.0)]),
                      t[-1], t_eval=t, record=("x",))
    np.testing.assert_array_equal(lib.x, ref.x)
    run = SystemRun(d, {})
    x, f, e = [], [], []
    for tk in t:
        run.advance(tk)
        x.append(run.state.x.copy())
        f.append(run.output("force_root"))
        e.append(run.output("dissipated_energy"))
    assert len(run.log) > 10
    assert np.max(np.abs(np.array(x).T - ref.x)) <= TOL * np.max(np.abs(ref.x))
    assert np.max(np.abs(np.array(f) - ref.friction_force[0])) <= TOL * np.max(np.abs(ref.friction_force))
    assert np.max(np.abs(np.array(e) - ref.dissipated_friction)) <= TOL * ref.dissipated_friction[-1]
    data["joints"][0].pop("tangential_dof"), data["joints"][0].pop("radial_dof")
    with pytest.raises(ParameterError, match=r"joints\[0\] \(dovetail\) needs 'tangential_dof' or 'radial_dof'"):
        SystemDefinition.from_dict(data)
