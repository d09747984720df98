"""What the FMUs tell a host about their structure (issue 41, section 2): every output declares the
inputs it depends on directly (``dependencies`` in the model description), so that a host that sorts
its FMUs by their data flow (OMSimulator) finds no algebraic loop in the README's chain; and an SSP
written by ``FMUSystem.to_ssp`` carries the run's default experiment and step."""
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy.ssp.ssd import read_ssd
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from frictionjoint.errors import ParameterError
from frictionjoint.fmi.build import build_fmus
from frictionjoint.fmi.cosim import FMUSystem, joint_connections

CHAIN = Path(__file__).resolve().parents[1] / "models" / "two_dof_chain.toml"


def _structure(fmu) -> tuple[dict, dict]:
    """``(causality of each variable by name, output name -> names it depends on or None)`` from the
    model description (FMI 2: indices; FMI 3: value references)."""
    with zipfile.ZipFile(fmu) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    if root.get("fmiVersion", "").startswith("2"):
        variables = root.find("ModelVariables").findall("ScalarVariable")
        key = {str(i + 1): v.get("name") for i, v in enumerate(variables)}
        unknowns, ref = root.iterfind("ModelStructure/Outputs/Unknown"), "index"
    else:
        variables = list(root.find("ModelVariables"))
        key = {v.get("valueReference"): v.get("name") for v in variables}
        unknowns, ref = root.iterfind("ModelStructure/Output"), "valueReference"
    causality = {v.get("name"): v.get("causality", "local") for v in variables}
    deps = {}
    for u in unknowns:
        d = u.get("dependencies")
        deps[key[u.get(ref)]] = None if d is None else [key[i] for i in d.split()]
    return causality, deps


@pytest.fixture(scope="module")
def fmi3(tmp_path_factory):
    return build_fmus(tmp_path_factory.mktemp("fmi3_deps"), fmi_version=3)


@pytest.fixture(scope="module")
def chain(tmp_path_factory):
    (fmu,) = build_fmus(tmp_path_factory.mktemp("chain_deps"), structures=[CHAIN])
    return fmu


def test_every_output_declares_its_dependencies(fmus, fmi3, chain):
    """Every output of every FMU (FMI 2, FMI 3, a structure's) says which inputs it depends on
    directly, and names inputs only (absent, FMI says it depends on every input)."""
    for fmu in [*fmus.values(), *fmi3, chain]:
        causality, deps = _structure(fmu)
        outputs = [n for n, c in causality.items() if c == "output"]
        assert sorted(deps) == sorted(outputs), fmu.name
        for name, on in deps.items():
            assert on is not None, f"{fmu.name}: output {name} declares no dependencies"
            assert all(causality[i] == "input" for i in on), (fmu.name, name, on)


def test_state_outputs_depend_on_no_input_and_joints_on_theirs(fmus, chain):
    """A structure's displacements and velocities and the oscillator's outputs are its state at the
    communication point (the inputs act over the next step): no input; a displacement-driven joint's
    outputs are evaluated at its inputs as set: ``u`` and ``velocity``."""
    _, structure = _structure(chain)
    assert structure and all(on == [] for on in structure.values())
    _, oscillator = _structure(fmus["CoulombOscillator"])
    assert all(on == [] for on in oscillator.values())
    _, joint = _structure(fmus["JenkinsJoint"])
    assert all(sorted(on) == ["u", "velocity"] for on in joint.values())


def _largest_loop(system: FMUSystem, declared: bool) -> int:
    """The size of the largest strongly connected set of variables in the data flow of ``system``
    (connections, and inside each FMU its inputs to the outputs that depend on them; ``declared``
    False: every output on every input, as a host reads a model description without dependencies):
    1 where a host can order every variable (no algebraic loop)."""
    nodes, edges = {}, []

    def node(name):
        return nodes.setdefault(name, len(nodes))
    for source, target in system.connections:
        edges.append((node(source), node(target)))
    for comp, fmu in system.components.items():
        causality, deps = _structure(fmu)
        inputs = [n for n, c in causality.items() if c == "input"]
        for out, on in deps.items():
            for i in (on if declared else inputs):
                edges.append((node(f"{comp}.{i}"), node(f"{comp}.{out}")))
    a, b = np.array(edges).T
    graph = coo_matrix((np.ones(a.size), (a, b)), shape=(len(nodes), len(nodes)))
    _, labels = connected_components(graph, directed=True, connection="strong")
    return int(np.bincount(labels).max())


def test_the_readme_chain_has_no_algebraic_loop(fmus, chain):
    """The README's chain (a structure and two Jenkins joints, semi-implicit coupling with velocities):
    without the declarations every connected variable (20: the structure's 6 joint inputs and 4
    port outputs, each joint's 2 inputs and 3 outputs) is in one loop, which a host such as
    OMSimulator solves at every step; with them, none (the structure's outputs are its state)."""
    system = FMUSystem({"chain": chain, "j1": fmus["JenkinsJoint"], "j2": fmus["JenkinsJoint"]},
                       joint_connections("chain", "j1", "x1") + joint_connections("chain", "j2", "x2"))
    assert _largest_loop(system, declared=False) == 20
    assert _largest_loop(system, declared=True) == 1


def test_the_ssp_carries_the_default_experiment_and_step(fmus, chain, tmp_path):
    """``to_ssp`` writes SSP 1.0's ``DefaultExperiment`` (start, stop) and the step where
    OMSimulator reads it (its fixed-step master in the system's annotation); the SSD validates
    against SSP 1.0's schema (fmpy's ``read_ssd``). Bad times are refused by name."""
    system = FMUSystem({"chain": chain, "j1": fmus["JenkinsJoint"]}, joint_connections("chain", "j1", "x1"))
    ssd = "{http://ssp-standard.org/SSP1/SystemStructureDescription}"
    oms = "{https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd}"

    def written(path):
        read_ssd(str(path), validate=True)  # raises where the SSD does not validate
        with zipfile.ZipFile(path) as z:
            root = ET.fromstring(z.read("SystemStructure.ssd"))
        return root.find(f"{ssd}DefaultExperiment").attrib, root.find(f".//{oms}FixedStepMaster")
    experiment, master = written(system.to_ssp(tmp_path / "chain.ssp", stop_time=20.9, step=0.0524))
    assert float(experiment["startTime"]) == 0.0 and float(experiment["stopTime"]) == 20.9
    assert float(master.get("stepSize")) == 0.0524 and master.get("description") == "oms-ma"
    experiment, master = written(system.to_ssp(tmp_path / "plain.ssp"))  # start time only
    assert experiment == {"startTime": "0.0"} and master is None
    for kwargs, name in ((dict(stop_time=-1.0), "stop_time"), (dict(step=0.0), "step"),
                         (dict(start_time=float("nan")), "start_time")):
        with pytest.raises(ParameterError, match=name):
            system.to_ssp(tmp_path / "bad.ssp", **kwargs)
