"""Events located across FMUs by the library's master (``FMUSystem.simulate(locate_events=...)``).

The case of tests/test_cosim.py and the README (models/two_dof_chain.toml as LinearStructure.fmu,
two JenkinsJoint.fmu with kt = 100 N/m, Fs = 0.8 N, 1 N cos(1.2 t) on DOF 2, from rest, four
periods; 31 stick/slip events of joint 2 in the exact solution, joint 1 never slips), connected
with ``joint_connections(..., events=True)``: against the library's exact event-driven solution
(FrictionSystem + simulate) at the communication points, sequential and Jacobi transfer.
"""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.fmi.cosim import FMUSystem, _hermite_dip, _illinois, joint_connections

MODEL = "models/two_dof_chain.toml"
OMEGA = 1.2
T = 2 * math.pi / OMEGA
PERIODS = 4
DIVISIONS = (20, 50, 100)  # communication steps T/20, T/50, T/100
EXACT_EVENTS = 31  # stick/slip events of the exact solution over the four periods
TOL = 1e-9  # error of the located co-simulation, relative to each DOF's amplitude


@pytest.fixture(scope="module")
def chain(tmp_path_factory, fmus):
    from pathlib import Path

    from frictionjoint.fmi.build import build_fmus
    from frictionjoint.structure_file import load_structure_definition

    root = Path(__file__).resolve().parents[1]
    (structure,) = build_fmus(tmp_path_factory.mktemp("structure"), structures=[root / MODEL])
    definition = load_structure_definition(root / MODEL)
    joints = [fj.Jenkins(100.0, 0.8, dof="x1"), fj.Jenkins(100.0, 0.8, dof="x2")]  # JenkinsJoint.fmu defaults
    exact = fj.FrictionSystem(definition.structure, joints, omega=OMEGA, excitation=[fj.HarmonicForce("x2", 1.0)])
    return {"chain": structure, "joint": fmus["JenkinsJoint"], "exact": exact}


def system(chain, events=True):
    return FMUSystem({"chain": chain["chain"], "j1": chain["joint"], "j2": chain["joint"]},
                     joint_connections("chain", "j1", "x1", events=events)
                     + joint_connections("chain", "j2", "x2", events=events))


def error(result, exact, division):
    """Max error over the communication points of the worse DOF, relative to its amplitude."""
    t = T / division * np.arange(division * PERIODS + 1)
    ref = fj.simulate(exact, t[-1], t_eval=t, record=("x",))
    x = np.vstack([result["chain.x_x1"], result["chain.x_x2"]])
    return float((np.max(np.abs(x - ref.x), axis=1) / np.max(np.abs(ref.x), axis=1)).max())


@pytest.mark.parametrize("transfer", ["sequential", "jacobi"])
def test_located_events_give_the_exact_solution_at_every_step(chain, transfer):
    s = system(chain)
    for d in DIVISIONS:
        r = s.simulate(PERIODS * T, T / d, ["chain.x_x1", "chain.x_x2", "j1.status", "j2.status"],
                       transfer=transfer)
        assert np.allclose(r.t, T / d * np.arange(d * PERIODS + 1), rtol=0, atol=1e-13)
        # measured 2.7e-14 to 3.7e-14 (sequential and Jacobi; without locating: 1.6 to 5.9 at T/20)
        assert error(r, chain["exact"], d) <= TOL, (d, transfer)
        assert f"{EXACT_EVENTS} events located" in r.host
        assert np.all(r["j1.status"] == 0) and np.any(r["j2.status"] != 0)


def test_locate_events_defaults_to_where_it_can_and_false_is_the_fixed_step_master(chain):
    # joint_connections connects the velocity by default, so that the default master locates
    assert ("chain.v_x1", "j1.velocity") in joint_connections("chain", "j1", "x1")
    assert all("velocity" not in t for _, t in joint_connections("chain", "j1", "x1", events=False))
    located = system(chain).simulate(PERIODS * T, T / 50, ["chain.x_x1", "chain.x_x2"])
    assert "events located" in located.host and error(located, chain["exact"], 50) <= TOL
    fixed = system(chain).simulate(PERIODS * T, T / 50, ["chain.x_x2", "chain.x_x1"], locate_events=False)
    assert "events" not in fixed.host and error(fixed, chain["exact"], 50) > 1e-2  # measured 0.2
    # without the joints' velocity connected the master cannot tell a reversal: not located
    plain = system(chain, events=False).simulate(PERIODS * T, T / 50, ["chain.x_x2", "chain.x_x1"])
    assert "events" not in plain.host and error(plain, chain["exact"], 50) > 1e-2  # measured 0.2


def test_locate_events_refuses_what_it_cannot_do(chain):
    s = system(chain, events=False)
    with pytest.raises(ParameterError, match=r"j1\.velocity is not connected"):
        s.simulate(1.0, 0.1, ["chain.x_x1"], locate_events=True)
    with pytest.raises(ParameterError, match="locate_events must be"):
        s.simulate(1.0, 0.1, ["chain.x_x1"], locate_events="yes")
    only_structure = FMUSystem({"chain": chain["chain"]})
    with pytest.raises(ParameterError, match="no component reports event indicators"):
        only_structure.simulate(1.0, 0.1, ["chain.x_x1"], locate_events=True)


def test_joint_event_outputs(chain):
    """JenkinsJoint.fmu (k = 100 N/m, Fs = 0.8 N: slip travel 8 mm): status, slip margin and its
    rate, slip velocity, and the tangent stiffness at a reversal once the velocity is known."""
    from frictionjoint.fmi.master import FMUInstance

    names = ["status", "slip_margin", "slip_margin_rate", "slip_velocity", "tangent_stiffness", "force"]
    inst = FMUInstance(chain["joint"], "j")
    try:
        inst.initialize()
        inst.set({"u": 0.005, "velocity": 1.0})
        assert inst.get(names) == pytest.approx([0, 0.3, -100.0, 0.0, 100.0, 0.5], abs=1e-14)
        inst.set({"u": 0.01})  # beyond the slip travel: slips, the margin of the stuck state < 0
        assert inst.get(names) == pytest.approx([1, -0.2, -100.0, 0.0, 0.0, 0.8], abs=1e-14)
        inst.step_between(0.0, 0.1)  # commits: slipping forwards
        assert inst.get(names)[:4] == pytest.approx([1, 0.0, 0.0, 1.0], abs=1e-14)
        inst.set({"velocity": -0.5})  # the reversal: it sticks, the slip velocity turns negative
        assert inst.get(names) == pytest.approx([0, 0.0, 0.0, -0.5, 100.0, 0.8], abs=1e-14)
        inst.set({"velocity": 0.0})  # not known: the play operator's last move (slipping), as before
        assert inst.get(["status", "tangent_stiffness"]) == [1, 0.0]
    finally:
        inst.close()


def test_illinois_brackets_a_root_to_rounding():
    calls = []

    def phi(s):
        calls.append(s)
        return math.cos(s) - 0.5  # root pi/3, positive before it

    hi = _illinois(phi, 0.5, 2.0)
    # a root to the last bits: libm's cos (1 ulp, platform-dependent) over |phi'| = 0.87 and the
    # bracket's ulps; 1e-14 (measured 2.2e-16, one ulp, where 1e-15 was 4.5 ulps)
    assert math.cos(hi) - 0.5 <= 0 and abs(hi - math.pi / 3) <= 1e-14
    assert len(calls) < 20


def test_hermite_dip_finds_a_minimum_below_zero_between_positive_ends():
    # g = (s - 0.5)^2 - 0.01 on [0, 1]: positive at both ends, lowest at 0.5
    g = lambda s: (s - 0.5) ** 2 - 0.01  # noqa: E731
    rate = lambda s: 2 * (s - 0.5)  # noqa: E731
    none = np.array([np.nan, np.nan])
    start = (np.array([g(0.0), 1.0]), np.array([rate(0.0), np.nan]), none)
    end = (np.array([g(1.0), 1.0]), np.array([rate(1.0), np.nan]), none)
    assert _hermite_dip(0.0, 1.0, start, end) == pytest.approx(0.5)
    start[0][0] += 0.02
    end[0][0] += 0.02
    assert _hermite_dip(0.0, 1.0, start, end) is None


def test_hermite_dip_of_an_indicator_seen_through_its_integral():
    # a slip velocity g = (s - 0.5)^2 - 0.01 on [0, 2] (its integral from 0 given at the end, no
    # rate): positive at both ends, negative around 0.5 -- a reversal and a return to slip
    g = lambda s: (s - 0.5) ** 2 - 0.01  # noqa: E731
    integral = lambda s: ((s - 0.5) ** 3 + 0.125) / 3 - 0.01 * s  # noqa: E731
    none = np.array([np.nan])
    start = (np.array([g(0.0)]), none, none)
    end = (np.array([g(2.0)]), none, np.array([integral(2.0)]))
    s = _hermite_dip(0.0, 2.0, start, end)
    assert s is not None and g(s) < 0
    end = (np.array([g(2.0)]), none, np.array([integral(2.0) + 1.0]))  # it went further: no dip
    assert _hermite_dip(0.0, 2.0, start, end) is None


@pytest.mark.parametrize("transfer", ["sequential", "jacobi"])
def test_located_events_of_iwan_joints_slider_by_slider(chain, fmus, transfer):
    """The same chain with an IwanJoint.fmu of 8 sliders (Segalman, the FMU's defaults) at each
    mass: the sliders slip one by one and stick together (145 slider events in two periods of the
    exact solution, 65 distinct instants), each one a change of the structure's force law."""
    n = 8
    joints = [fj.Iwan.segalman(0.8, 100.0, -0.5, 0.1, n, dof=dof) for dof in ("x1", "x2")]
    exact = fj.FrictionSystem(chain["exact"].structure, joints, omega=OMEGA,
                              excitation=[fj.HarmonicForce("x2", 1.0)])
    s = FMUSystem({"chain": chain["chain"], "j1": fmus["IwanJoint"], "j2": fmus["IwanJoint"]},
                  joint_connections("chain", "j1", "x1", events=True)
                  + joint_connections("chain", "j2", "x2", events=True),
                  parameters={"j1": {"n_sliders": n}, "j2": {"n_sliders": n}})
    for d in (20, 50):
        r = s.simulate(2 * T, T / d, ["chain.x_x1", "chain.x_x2"], transfer=transfer)
        t = T / d * np.arange(2 * d + 1)
        ref = fj.simulate(exact, t[-1], t_eval=t, record=("x",))
        x = np.vstack([r["chain.x_x1"], r["chain.x_x2"]])
        err = float((np.max(np.abs(x - ref.x), axis=1) / np.max(np.abs(ref.x), axis=1)).max())
        assert err <= TOL, (d, err)  # measured 1.1e-14 to 1.3e-14
        assert "65 events located" in r.host


class _Indicator:
    """A stand-in component whose one event indicator is g(t) = 0.05 + 0.05 cosh(20 (t - 0.5)) /
    cosh(10): positive throughout [0, 1], with g(0) = g(1) = 0.1 and slopes -+0.9999 there, so the
    cubic Hermite interpolant of its end values and rates dips to -0.15 at t = 0.5."""

    def __init__(self):
        self.t = 0.0

    @staticmethod
    def g(t):
        return 0.05 + 0.05 * math.cosh(20 * (t - 0.5)) / math.cosh(10.0)

    @staticmethod
    def rate(t):
        return math.sinh(20 * (t - 0.5)) / math.cosh(10.0)

    def save(self):
        return self.t

    def restore(self, saved):
        self.t = saved

    def free(self, saved):
        pass

    def step_between(self, t, s):
        self.t = s

    def reader(self, names):
        return lambda: [self.g(self.t), self.rate(self.t)]


def test_a_probe_that_finds_no_event_leaves_the_components_at_the_step_end():
    """The interpolant predicts a dip, the probe there finds the indicator positive: no event, and
    every component is back at the step's end (it was left at the probe's time)."""
    from types import SimpleNamespace

    from frictionjoint.fmi.cosim import _EventLocator

    comp = _Indicator()
    system = SimpleNamespace(_transfer=lambda insts, transfer: (lambda: None))
    locator = _EventLocator(system, {"c": comp}, "sequential", [("c", ["slip_margin"], [("slip_margin_rate", None)])])
    assert _hermite_dip(0.0, 1.0, (np.array([0.1]), np.array([-0.9999]), np.array([np.nan])),
                        (np.array([0.1]), np.array([0.9999]), np.array([np.nan]))) == pytest.approx(0.5)
    locator.step(0.0, 1.0)
    assert locator.count == 0 and comp.t == 1.0
