"""The FMUs under a careless host (issue 25, section 5 and section 6's FMU bullet): huge,
negative and post-terminate steps, an absurd number of Iwan sliders, and every Real parameter
and input at +-1e300 and +-1e308. Each FMU runs in a subprocess (tests/stress/fmu_stress_checks.py:
pythonfmu FMUs cannot be instantiated twice in one process).

The FMUs' wrapper (pythonfmu 0.7.0's with frictionjoint's fixes, frictionjoint/fmi/fmi2_wrapper) turns
an exception into fmi2Error with its message and ``do_step`` returning False into fmi2Discard (pythonfmu's
own turned an exception into fmi2Fatal). So "refused" below is a bad status (>= fmi2Discard) with the
reason in the log, never fmi2OK.
"""
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from frictionjoint.analytic import den_hartog
from frictionjoint.elements.iwan import MAX_SLIDERS

CHECKS = Path(__file__).parent / "stress" / "fmu_stress_checks.py"
ROOT = Path(__file__).parent.parent
OK, DISCARD, ERROR = 0, 2, 3
SECONDS = 10.0  # "bounded time": a step of any length answers within this on a loaded 2-core machine


def run(check, path, cases, timeout=300):
    proc = subprocess.run([sys.executable, str(CHECKS), check, str(path), json.dumps(cases)],
                          capture_output=True, text=True, timeout=timeout)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])["cases"]


@pytest.fixture(scope="module")
def linear_structure(tmp_path_factory):
    """LinearStructure.fmu of the co-simulation case (models/two_dof_chain.toml)."""
    from frictionjoint.fmi.build import build_fmus

    (path,) = build_fmus(tmp_path_factory.mktemp("structure"), structures=[ROOT / "models" / "two_dof_chain.toml"])
    return path


def test_huge_step_on_the_orbit_is_den_hartog_state(fmus):
    # The README's case (m = k = P0 = 1, F = 0.5, omega = 1.5: r = 1.5, f = 0.5, stop-free) from
    # rest, one step of 1e8 s (2.4e7 periods; marched event by event it took ~14 min, beyond the
    # subprocess's timeout, before the FMU skipped whole periods). Reference: Den Hartog's closed
    # form (1931), x(t) = (P0/k) xbar(omega t), v = (P0/k) wn dxbar/dtau, and 4 F X per cycle.
    (case,) = run("careless_host", fmus["CoulombOscillator"],
                  [{"steps": [1e8], "read": ["x", "v", "dissipated_energy", "event_count"]}])
    (step,) = case["steps"]
    assert step["status"] == OK and step["seconds"] < SECONDS, case
    x, v, energy, events = case["values"]
    dh = den_hartog(1.5, 0.5)
    phase = 1.5 * 1e8  # exact in binary floating point
    # the phase omega t at t = 1e8 is resolved to ulp(1.5e8) = 3e-8 rad: a few of them here
    assert abs(x - dh.waveform(phase)) <= 1e-7
    assert abs(v - dh.waveform(phase, 1)) <= 1e-7
    periods = 1e8 / (2 * math.pi / 1.5)
    per_cycle = 4 * 0.5 * dh.amplitude  # 4 F X (Den Hartog), plus a bounded transient from rest
    assert abs(energy - periods * per_cycle) <= 1e-6 * periods * per_cycle
    assert abs(events - 2 * periods) <= 10  # two stops of zero duration per period (stop-free)


def test_huge_step_answers_in_bounded_time_with_the_state_or_a_reason(fmus):
    # 1e12 s: the damped linear oscillator (slip_force = 0) converges to its steady state
    # Re(P0 e^{i w t} / (k - m w^2 + i c w)) (exact, textbook), skipped to; the README's case
    # would count 4.8e11 events, beyond the FMI Integer event_count: refused, with the reason.
    cases = run("careless_host", fmus["CoulombOscillator"],
                [{"params": {"slip_force": 0.0, "damping": 0.1}, "steps": [1e12], "read": ["x", "v"]},
                 {"steps": [1e12], "read": ["x", "v"]},
                 {"params": {"start_on_orbit": True}, "steps": [1e12], "read": ["x", "v"]}])
    linear, default, on_orbit = cases
    assert linear["steps"][0]["status"] == OK and linear["steps"][0]["seconds"] < SECONDS, linear
    amp = 1.0 / complex(1.0 - 1.5 ** 2, 0.1 * 1.5)
    phase = 1.5e12  # = 1.5 * 1e12 exactly; resolved to ulp(1.5e12) = 2.4e-4 rad
    ref = amp * complex(math.cos(phase), math.sin(phase))
    x, v = linear["values"]
    assert abs(x - ref.real) <= 1e-3 * abs(amp)
    assert abs(v - (1j * 1.5 * ref).real) <= 1.5e-3 * abs(amp)
    for case in (default, on_orbit):
        (step,) = case["steps"]
        assert step["status"] >= DISCARD and step["seconds"] < SECONDS, case
        assert case["t"] == 0.0 and case["values"] == [0.0, 0.0] if case is default else True
        assert any("event_count" in m and "shorter steps" in m for m in case["messages"]), case


def test_huge_step_of_every_other_fmu_returns_in_bounded_time(fmus, linear_structure):
    # each answers a 1e12 s step in bounded time: a held-input joint in one update (its result is
    # the exact play operator at the held input, as at any step length), the blade and the linear
    # structure refuse with the reason (before: the blade marched ~2e15 events, the structure
    # returned NaN or a rounding-dominated state)
    expect = {"JenkinsJoint": OK, "IwanJoint": OK, "MicroslipJoint": OK, "DovetailRoot": OK,
              "BladeDovetail": DISCARD, linear_structure.stem: DISCARD}
    paths = {**fmus, linear_structure.stem: linear_structure}
    for name, status in expect.items():
        (case,) = run("careless_host", paths[name], [{"steps": [1e12]}])
        (step,) = case["steps"]
        assert step["status"] == status and step["seconds"] < SECONDS, (name, case)
        if status != OK:
            assert any("shorter steps" in m for m in case["messages"]), (name, case)


@pytest.mark.parametrize("name", ["CoulombOscillator", "JenkinsJoint", "BladeDovetail"])
def test_negative_step_and_step_after_terminate_are_refused(fmus, name):
    # before: both returned fmi2OK and did nothing
    cases = run("careless_host", fmus[name], [{"steps": [1e-3, -1e-3]}, {"steps": [1e-3, 1e-3], "terminate": 1}])
    negative, terminated = cases
    assert [s["status"] for s in negative["steps"]] == [OK, DISCARD], negative
    assert any("communicationStepSize must be >= 0" in m for m in negative["messages"]), negative
    assert [s.get("status", s.get("terminate")) for s in terminated["steps"]] == [OK, OK, DISCARD], terminated
    assert any("after terminate" in m for m in terminated["messages"]), terminated


@pytest.mark.parametrize("name, extra", [("IwanJoint", {}), ("MicroslipJoint", {}),
                                         ("DovetailRoot", {"flank_profile": 1})])
def test_too_many_sliders_are_refused_at_once(fmus, name, extra):
    # n_sliders = 1e7 took 43 s to initialise the IwanJoint, 1e8 did not finish
    proc = subprocess.run([sys.executable, str(CHECKS), "bad_parameters", str(fmus[name]),
                           json.dumps([{**extra, "n_sliders": 10 ** 8}, {**extra, "n_sliders": 0}])],
                          capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr[-3000:]
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    for case in res["cases"]:
        assert case["raised"] is not None
        assert any(f"n_sliders must be an integer in [1, {MAX_SLIDERS}]" in m for m in case["messages"]), case
    assert res["defaults_ok"] is True


def test_jenkins_and_dovetail_at_huge_displacements_refuse_instead_of_wrong_values(fmus):
    # JenkinsJoint stiffness 1e308 at u = 1e308 returned force 0.0 while slipping at 0.8 N; the
    # DovetailRoot at u_radial = 1e300 returned -inf, both with fmi2OK
    (jen,) = run("extreme_values", fmus["JenkinsJoint"], [{"params": {"stiffness": 1e308}, "inputs": {"u": 1e308}}])
    (dov,) = run("extreme_values", fmus["DovetailRoot"], [{"inputs": {"u_radial": 1e300}}])
    for case, text in ((jen, "input u must be finite with |u| <="), (dov, "moves a flank by")):
        assert case["init"] is None, case
        assert [r["error"] for r in case["reads"]] == [ERROR, ERROR] and case["step"] == DISCARD, case
        assert any(text in m for m in case["messages"]), case


def _extreme_cases(path):
    """One case per Real parameter or input and value in (+-1e300, +-1e308), the rest default."""
    from fmpy import read_model_description

    md = read_model_description(str(path))
    cases = []
    for v in md.modelVariables:
        if v.type == "Real" and v.causality in ("parameter", "input"):
            for value in (1e300, -1e300, 1e308, -1e308):
                key = "params" if v.causality == "parameter" else "inputs"
                cases.append({key: {v.name: value}, "h": 1e-3, "what": f"{v.name}={value:g}"})
    return cases


#: a driven joint's force once all its sliders slip (a move from u = 0 beyond every slider's
#: travel): its total slip force at the defaults (Jenkins and Segalman Iwan: slip_force = 0.8 N,
#: reproduced exactly by the discrete table; Mindlin: friction_coefficient * normal_load = 30 N)
MACROSLIP = {"JenkinsJoint": 0.8, "IwanJoint": 0.8, "MicroslipJoint": 30.0}


@pytest.mark.parametrize("name", ["CoulombOscillator", "JenkinsJoint", "IwanJoint", "MicroslipJoint",
                                  "DovetailRoot", "BladeDovetail", "structure"])
def test_extreme_values_never_give_non_finite_outputs_with_status_ok(fmus, linear_structure, name):
    # every Real parameter and input at +-1e300 and +-1e308 in turn: either the initialisation
    # fails with the reason, or every read and step is finite with fmi2OK or a bad status (a
    # step refused with the reason: fmi2Discard; a read: fmi2Error with the message); a driven
    # joint's force read at a huge u is its macroslip force or an error (before: 0 N, the
    # sliders' absolute positions rounded to u; DovetailRoot and MicroslipJoint: inf)
    path = linear_structure if name == "structure" else fmus[name]
    cases = _extreme_cases(path)
    for case, res in zip(cases, run("extreme_values", path, cases, timeout=600)):
        if res["init"] is not None:
            assert res["messages"] or "set:" in res["init"], (case["what"], res)
            continue
        for read in res["reads"]:
            if read["error"] is None:
                bad = {k: v for k, v in read["values"].items() if not np.isfinite(v)}
                assert not bad, (case["what"], bad, res["messages"])
                u = case.get("inputs", {}).get("u")
                if name in MACROSLIP and u is not None:
                    force = read["values"]["force"]
                    assert force == pytest.approx(math.copysign(MACROSLIP[name], u), rel=1e-9), (case["what"], res)
            else:
                assert read["error"] >= DISCARD and res["messages"], (case["what"], res)
        if res["step"] != OK:
            assert res["messages"], (case["what"], res)


def test_iwan_element_states_its_slider_bound():
    # the element itself (not only the FMUs): 1e7 sliders took 43 s to build, 1e8 never finished
    import time

    from frictionjoint.elements.iwan import Iwan
    from frictionjoint.errors import ParameterError

    start = time.perf_counter()
    for n in (MAX_SLIDERS + 1, 10 ** 7, 10 ** 8, 0):
        with pytest.raises(ParameterError, match=rf"n_sliders must be an integer in \[1, {MAX_SLIDERS}\]"):
            Iwan.segalman(0.8, 100.0, -0.5, 0.1, n)
    assert time.perf_counter() - start < 1.0
    iw = Iwan.segalman(0.8, 100.0, -0.5, 0.1, MAX_SLIDERS)  # the bound itself: MAX_SLIDERS + the delta
    assert len(iw.sliders_table) == MAX_SLIDERS + 1
    assert iw.slip_force == pytest.approx(0.8, rel=1e-12)  # Segalman's table reproduces F_S exactly


def test_driven_dovetail_refuses_what_it_cannot_resolve():
    # u_radial = 1e300 gave root forces of -inf; the state is kept when a move is refused
    from frictionjoint.elements.dovetail import DovetailRoot
    from frictionjoint.errors import ParameterError

    root = DovetailRoot(1e4, flank_angle=math.radians(30.0), friction_coefficient=0.3, normal_stiffness=2e8,
                        tangential_stiffness=1e8, tangential_dof=0, radial_dof=1)
    for vary in (True, False):
        d = root.driven(normal_load_variation=vary)
        d.update([1e-5, 1e-6])
        before = d.root_force.copy()
        for u in ([0.0, 1e300], [1e300, 0.0], [-1e308, 1e308]):
            with pytest.raises(ParameterError, match="moves a flank by"):
                d.update(u)
            np.testing.assert_array_equal(d.root_force, before)
            np.testing.assert_array_equal(d.u, [1e-5, 1e-6])


def test_dovetail_root_whose_slip_limit_overflows_is_refused():
    # friction_coefficient = 1e308: mu N0 = inf, BladeDovetail.fmu read friction_force = -inf
    from frictionjoint.elements.dovetail import DovetailRoot
    from frictionjoint.errors import ParameterError

    args = dict(flank_angle=math.radians(30.0), normal_stiffness=2e8, tangential_stiffness=1e8,
                tangential_dof=0, radial_dof=1)
    with pytest.raises(ParameterError, match="friction_coefficient = 1e\\+308"):
        DovetailRoot(1e4, friction_coefficient=1e308, **args)
    assert DovetailRoot(1e4, friction_coefficient=1e300, **args).static.normal_force > 0  # mu N0 = 5e303: finite
