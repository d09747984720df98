"""A whole friction system as one FMI 3.0 FMU with early return (issue 28, parts 2 and 3): the README's
two-DOF chain (models/two_dof_chain_system.toml) built by ``build-fmus --system FILE --fmi-version 3``,
validated, run by fmpy's FMU3Slave in a host loop and by simulate_fmu with early return: every event of
fj.simulate's event log of the same FrictionSystem is an early return at its instant, and the outputs on
the grid are fj.simulate's; without the host's permission whole steps with the FMI 2 system FMU's numbers;
FMU state. The marcher's stop after an event (Marcher.march(max_events=), SystemRun.advance(stop_at_event=))
without FMI."""
import math
import zipfile
from pathlib import Path

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.fmi.system_slave import SystemRun
from frictionjoint.solvers.marcher.events import EventLog, Marcher
from frictionjoint.system_file import load_system_definition
from test_fmi3 import _instance, host_loop  # (tests/ is on the path: tests/conftest.py)

ROOT = Path(__file__).resolve().parents[1]
CHAIN = ROOT / "models" / "two_dof_chain_system.toml"
OMEGA = 1.2
T = 2 * math.pi / OMEGA
PERIODS = 4
EVENT_TOL = 1e-12  # event instants [s]
TOL = 1e-10  # outputs on the grid, relative to each quantity's largest value
OUTPUTS = ["x_x1", "x_x2", "v_x1", "v_x2", "force_j1", "force_j2"]


def reference(divisions):
    """fj.simulate of the file's FrictionSystem from rest over PERIODS periods: its event instants after
    the start and its x, v, joint forces (rows as OUTPUTS) on the grid t0 + n T/divisions, n >= 1."""
    t = T / divisions * np.arange(PERIODS * divisions + 1)
    ref = fj.simulate(load_system_definition(CHAIN).system(), t[-1], t_eval=t,
                      record=("x", "v", "friction_force"))
    events = [e[0] for e in ref.events if e[0] > 0.0]
    return events, np.vstack([ref.x, ref.v, ref.friction_force])[:, 1:], len(ref.events)


def grid_error(values, rows):
    """Largest deviation of ``values`` ((n_t, 6), OUTPUTS' order) from ``rows`` ((6, n_t)), relative to
    the largest |x|, |v|, |force|."""
    got = np.asarray(values).T
    return max(float(np.max(np.abs(got[i:i + 2] - rows[i:i + 2])) / np.max(np.abs(rows[i:i + 2])))
               for i in (0, 2, 4))


@pytest.fixture(scope="module")
def chain(tmp_path_factory):
    """name -> (model description, extracted folder, path): the chain as FMI 3 ("fmi3", built by the
    command) and as FMI 2 ("fmi2")."""
    from fmpy import extract, read_model_description

    from frictionjoint.cli import main
    from frictionjoint.fmi.build import build_fmus

    out = tmp_path_factory.mktemp("fmi3_system")
    assert main(["build-fmus", "--system", str(CHAIN), "--fmi-version", "3", "--out", str(out)]) == 0
    assert [p.name for p in out.glob("*.fmu")] == ["TwoDofChainSystemFmi3.fmu"]
    paths = {"fmi3": out / "TwoDofChainSystemFmi3.fmu", "fmi2": build_fmus(out / "fmi2", systems=[CHAIN])[0]}
    return {n: (read_model_description(str(p)), extract(str(p)), p) for n, p in paths.items()}


def run(entry, divisions, allowed=True, event_mode=False):
    """tests/test_fmi3.py's FMI 3 host on fmpy's FMU3Slave over PERIODS periods at T/divisions: (early-return
    instants, [OUTPUTS] on the grid, event_count at the end)."""
    events, grid, count = host_loop(entry, {}, PERIODS * T, T / divisions, allowed, event_mode, OUTPUTS)
    return events, [list(g[1:]) for g in grid], count


@pytest.mark.parametrize("event_mode", [False, True])
@pytest.mark.parametrize("divisions", [20, 50])
@pytest.mark.fmu
@pytest.mark.slow
def test_every_event_is_an_early_return_at_its_instant(chain, divisions, event_mode):
    events, grid, count = run(chain["fmi3"], divisions, event_mode=event_mode)
    ref_events, rows, ref_count = reference(divisions)
    assert len(events) == len(ref_events) > 20
    assert max(abs(a - b) for a, b in zip(events, ref_events)) <= EVENT_TOL
    assert count == ref_count
    assert grid_error(grid, rows) <= TOL


@pytest.mark.fmu
@pytest.mark.slow
def test_the_fmu_builds_validates_and_declares_early_return(chain):
    from frictionjoint.fmi.build import build_fmus, validate

    md, _, path = chain["fmi3"]
    assert validate(path) == [] and md.fmiVersion == "3.0"
    cs = md.coSimulation
    assert cs.modelIdentifier == "FrictionSystemFmi3"
    assert cs.mightReturnEarlyFromDoStep and cs.hasEventMode and cs.canGetAndSetFMUstate and cs.canSerializeFMUstate
    with zipfile.ZipFile(path) as z:
        assert [n for n in z.namelist() if n.startswith("binaries/")] == ["binaries/x86_64-linux/FrictionSystemFmi3.so"]
        assert "resources/system.json" in z.namelist()
    # the FMI 2 FMU's variables, in its order, after time
    names = [v.name for v in md.modelVariables]
    assert names == ["time"] + [v.name for v in chain["fmi2"][0].modelVariables]
    with pytest.raises(ValueError, match="structures"):
        build_fmus(path.parent, structures=[ROOT / "models" / "two_dof_chain.toml"], fmi_version=3)


@pytest.mark.fmu
@pytest.mark.slow
def test_fmpy_simulate_fmu_with_early_return(chain):
    """simulate_fmu(early_return_allowed=True) at T/20: its rows off the grid are the events' instants,
    and its rows on the grid fj.simulate's."""
    from fmpy import simulate_fmu

    res = simulate_fmu(str(chain["fmi3"][2]), stop_time=PERIODS * T, output_interval=T / 20,
                       early_return_allowed=True, output=OUTPUTS)
    ref_events, rows, _ = reference(20)
    grid = T / 20 * np.arange(PERIODS * 20 + 1)
    t = np.asarray(res["time"])
    on = np.array([np.min(np.abs(grid - tk)) <= 1e-9 * T for tk in t])
    off_grid = sorted({float(tk) for tk in t[~on]})
    assert len(off_grid) == len(ref_events)
    assert max(abs(a - b) for a, b in zip(off_grid, ref_events)) <= EVENT_TOL
    # the last row on each grid point (an event's rows come before)
    values = np.array([[res[k][np.flatnonzero(on & (np.abs(t - tg) <= 1e-9 * T))[-1]] for k in OUTPUTS]
                       for tg in grid[1:]])
    assert grid_error(values, rows) <= TOL


@pytest.mark.fmu
@pytest.mark.slow
def test_whole_steps_without_permission_are_the_fmi2_fmus(chain):
    """No early return where the host does not allow it: whole steps, with the FMI 2 system FMU's
    numbers bit for bit."""
    from fmpy import instantiate_fmu

    events, grid, _ = run(chain["fmi3"], 20, allowed=False)
    assert events == []
    md, folder, _ = chain["fmi2"]
    s = instantiate_fmu(folder, md, fmi_type="CoSimulation")
    vr = {v.name: v.valueReference for v in md.modelVariables}
    s.setupExperiment(startTime=0.0)
    s.enterInitializationMode()
    s.exitInitializationMode()
    h = T / 20
    fmi2 = []
    for n in range(PERIODS * 20):
        s.doStep(n * h, (n + 1) * h - n * h)
        fmi2.append(s.getReal([vr[k] for k in OUTPUTS]))
    s.terminate()
    s.freeInstance()
    assert grid == fmi2


@pytest.mark.fmu
@pytest.mark.slow
def test_fmu_state_rollback_and_serialisation(chain):
    """A state taken after a few steps, restored (and deserialised): the next step returns early at the
    same event with the same outputs."""
    s, vr = _instance(chain["fmi3"])
    s.setFloat64([vr["force_x1"]], [0.2])  # a held input too
    s.enterInitializationMode(startTime=0.0)
    s.exitInitializationMode()
    t = 0.0
    for _ in range(3):
        t = s.doStep(t, 1.0)[3]
    state = s.getFMUState()
    blob = s.serializeFMUState(state)
    first = s.doStep(t, 5.0)
    refs = [vr[k] for k in ["time", *OUTPUTS, "dissipated_energy"]]
    after = s.getFloat64(refs), s.getInt32([vr["event_count"]])
    assert first[2]
    s.setFloat64([vr["force_x1"]], [0.0])  # the state restores the held input
    for restore in (lambda: s.setFMUState(state), lambda: s.setFMUState(s.deserializeFMUState(blob))):
        restore()
        assert s.getFloat64([vr["time"], vr["force_x1"]]) == [t, 0.2]
        assert s.doStep(t, 5.0) == first
        assert (s.getFloat64(refs), s.getInt32([vr["event_count"]])) == after
    s.freeFMUState(state)
    s.terminate()
    s.freeInstance()


def test_stopping_at_each_event_is_the_march_without_stops():
    """SystemRun.advance(stop_at_event=True) until each grid point: it stops at each event of the march
    (fj.simulate's instants) and its states on the grid are those of the march without stops, bit for
    bit; Marcher.march(max_events=) refuses a count that is not an integer >= 1."""
    d = load_system_definition(CHAIN)
    stopping, whole = SystemRun(d, {}), SystemRun(d, {})
    h = T / 20
    stops = []
    for n in range(1, 2 * 20 + 1):
        while stopping.advance(n * h, stop_at_event=True):
            stops.append(stopping.t)
        assert not whole.advance(n * h)
        for a, b in zip(stopping.snapshot().values(), whole.snapshot().values()):
            np.testing.assert_array_equal(a, b)
    ref = fj.simulate(d.system(), 2 * 20 * h, record=("x",))
    assert len(stops) == len([e for e in ref.events if e[0] > 0]) > 10
    assert max(abs(a - e[0]) for a, e in zip(stops, [e for e in ref.events if e[0] > 0])) <= EVENT_TOL
    assert stopping.log.time == whole.log.time and stopping.log.kind == whole.log.kind
    marcher = Marcher(d.system())
    state = marcher.initial_state(np.zeros(2), np.zeros(2))
    for bad in (0, 1.0, True, -2):
        with pytest.raises(ParameterError, match="max_events"):
            marcher.march(state, 1.0, EventLog(), max_events=bad)
