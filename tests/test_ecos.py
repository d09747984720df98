"""The FMUs in Ecos, a native C++ co-simulation host (ecospy), through SSP files.

Ecos's library runs in its own process (frictionjoint.fmi.ecos.run_ecos, full precision); the
``ecos`` executable runs with the environment of ``frictionjoint host-env``. Ecos's binaries need
``libtbb.so.12``: PyPI's ``tbb`` wheel (test extra) ships it, so these tests run on a machine
with no system package (frictionjoint.fmi.ecos.load_ecospy); they are skipped only on platforms
for which the test extra installs no ecospy (it has wheels for Linux x86_64 only).
"""
import math
import os
import platform
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from frictionjoint.fmi.cosim import FMUSystem, joint_connections

if not (sys.platform == "linux" and platform.machine() == "x86_64"):
    pytest.skip("ecospy (Ecos) has wheels for Linux x86_64 only", allow_module_level=True)


@pytest.fixture(scope="module", autouse=True)
def ecospy():
    """Ecos, loaded as the package loads it: a failure here is an error of every test, with the
    reason (never a skip: the test extra installs everything Ecos needs)."""
    from frictionjoint.fmi.ecos import load_ecospy

    return load_ecospy()


def bare_environment():
    """This environment without the variables host-env sets: what a new shell has."""
    return {k: v for k, v in os.environ.items() if k not in ("LD_LIBRARY_PATH", "LD_PRELOAD", "PYTHONPATH", "ECOS")}


def system_has_libtbb():
    out = subprocess.run(["ldconfig", "-p"], capture_output=True, text=True).stdout if os.path.exists("/sbin/ldconfig") else ""
    return "libtbb.so.12" in out


@pytest.mark.slow  # a fresh Python importing the package: about 2 s
def test_ecospy_loads_in_a_fresh_process_with_the_tbb_wheel():
    """A fresh Python, no LD_LIBRARY_PATH: load_ecospy gives a working Ecos library, and the
    libtbb.so.12 mapped in the process is the tbb wheel's where the system has none (a bare
    ``import ecospy`` there is an OSError: libtbb.so.12: cannot open shared object file)."""
    from frictionjoint.fmi.ecos import tbb_library

    code = ("from frictionjoint.fmi.ecos import load_ecospy\n"
            "print(load_ecospy().EcosLib.version())\n"
            "print(sorted({l.split()[-1] for l in open('/proc/self/maps') if 'libtbb.so' in l}))\n")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=bare_environment(), timeout=120)
    assert p.returncode == 0, p.stderr
    version, mapped = p.stdout.strip().splitlines()
    assert version.startswith("v0.")
    wheel = tbb_library()
    assert wheel is not None, "the test extra installs PyPI's tbb wheel"
    if not system_has_libtbb():
        assert mapped == repr([str(wheel.resolve())])


@pytest.mark.slow  # a fresh Python importing the package: about 2 s
def test_host_env_runs_the_ecos_executable_from_a_new_shell():
    """``( eval "$(frictionjoint host-env)"; "$ECOS" ... )`` in a shell with none of its variables
    (the printed form, in a subshell): ``$ECOS`` starts (without LD_LIBRARY_PATH to the tbb wheel it
    stops at the loader where the system has no libtbb12: status 127)."""
    script = f'set -e; (eval "$({sys.executable} -m frictionjoint host-env)"; "$ECOS" --version)'
    p = subprocess.run(["bash", "-c", script], capture_output=True, text=True, env=bare_environment(), timeout=120)
    assert p.returncode == 0, p.stderr
    assert p.stdout.strip().startswith("v0.")


@pytest.mark.slow  # a fresh Python importing the package: about 2 s
def test_host_env_runs_a_command_with_the_environment_and_leaves_the_shell_alone():
    """Issue 39: ``eval "$(frictionjoint host-env)"`` left LD_PRELOAD=libpython in the user's shell
    for every later command. ``frictionjoint host-env ecos ...`` runs the wheel's ecos with the
    environment in its own process: the shell that ran it has no LD_PRELOAD afterwards, the
    command's status is passed on, and a command that does not exist is status 127 with the
    reason."""
    from frictionjoint.fmi.ecos import host_environment

    fj = f"{sys.executable} -m frictionjoint host-env"
    script = (f'set -e; {fj} ecos --version; echo "after: [${{LD_PRELOAD:-}}]"; '
              f'{fj} -- sh -c \'echo "inside: [$LD_PRELOAD]"; exit 3\' || echo "status $?"; '
              f'{fj} no-such-command-here || echo "status $?"')
    p = subprocess.run(["bash", "-c", script], capture_output=True, text=True, env=bare_environment(), timeout=120)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.strip().splitlines()
    assert lines[0].startswith("v0.")
    assert lines[1:] == ["after: []", f"inside: [{host_environment()['LD_PRELOAD']}]", "status 3", "status 127"]
    assert "cannot run 'no-such-command-here'" in p.stderr


@pytest.mark.slow  # a fresh Python importing the package: about 2 s
def test_a_failed_run_says_so_when_its_values_are_read(tmp_path):
    """A file that is not an SSP: the result is a failure, and reading an output raises an error
    saying the run failed and why (a KeyError subclass), not a bare KeyError('osc.x')."""
    from frictionjoint.fmi.ecos import run_ecos
    from frictionjoint.results.response import OutputNotRecordedError

    bad = tmp_path / "bad.ssp"
    bad.write_text("not an SSP archive")
    r = run_ecos(bad, 1.0, 0.1, ["osc.x"], timeout=120)
    assert not r.success and r.status == "failed"
    for read in (lambda: r.values["osc.x"], lambda: r["osc.x"]):
        with pytest.raises(OutputNotRecordedError) as exc:
            read()
        assert isinstance(exc.value, KeyError)
        assert "failed" in str(exc.value) and r.message in str(exc.value)


def test_a_relative_ssp_path_is_from_the_callers_folder(fmus, tmp_path, monkeypatch):
    """``run_ecos("osc.ssp", ...)`` and ``ecos_cli("osc.ssp", ...)`` from the folder holding it:
    Ecos runs in another folder (a temporary one, the CSV's), where the relative path named
    nothing (the run failed: Ecos could not initialise)."""
    from frictionjoint.fmi.ecos import ecos_cli, run_ecos

    s = FMUSystem({"osc": fmus["CoulombOscillator"]}, [], {"osc": dict(slip_force=0.3, omega=1.5)})
    s.to_ssp(tmp_path / "osc.ssp")
    monkeypatch.chdir(tmp_path)
    r = run_ecos("osc.ssp", 1.0, 0.1, ["osc.x"], timeout=120)
    assert r.success, r.message
    assert np.max(np.abs(r["osc.x"] - s.simulate(1.0, 0.1, ["osc.x"])["osc.x"])) <= 1e-12  # same motion
    p = ecos_cli("osc.ssp", 1.0, 0.1, "out", debug=False, timeout=120)
    assert p.returncode == 0, p.stdout + p.stderr
    assert len((tmp_path / "out" / "osc.csv").read_text().strip().splitlines()) == 12  # header, t = 0, ten steps


def relative(a, b):
    return np.max(np.abs(np.asarray(a) - np.asarray(b))) / max(np.max(np.abs(b)), 1e-300)


def test_coulomb_oscillator_in_ecos_equals_fmpy(fmus):
    """SSP sets the parameters; Ecos's values equal fmpy's at the common communication points
    (Ecos accumulates its time: the points differ by rounding, 1e-14 s)."""
    from frictionjoint.fmi.ecos import run_ecos

    params = {"osc": dict(mass=1.0, stiffness=1.0, force_amplitude=1.0, slip_force=0.3, omega=1.5, x0=0.1)}
    s = FMUSystem({"osc": fmus["CoulombOscillator"]}, [], params)
    period = 2 * math.pi / 1.5
    outs = ["osc.x", "osc.v", "osc.dissipated_energy", "osc.friction_force"]
    e = run_ecos(s, 8 * period, period / 20, outs)
    assert e.success, e.message
    f = s.simulate(8 * period, period / 20, outs)
    assert np.max(np.abs(e.t - f.t)) < 1e-13
    for k in outs:
        assert relative(e[k], f[k]) <= 1e-12, k  # measured 7.5e-14 (x), 8.8e-14 (v), 4.4e-15 (energy)
    assert e["osc.dissipated_energy"][-1] > 0.1  # friction did work: events inside the steps


def test_every_fmu_and_two_instances_in_ecos_equal_this_master(fmus):
    """One SSP with every FMU: two CoulombOscillator instances, one driving the displacement of
    each joint FMU (JenkinsJoint, IwanJoint, MicroslipJoint, DovetailRoot); Ecos's values equal
    this library's master with Ecos's (Jacobi) transfer."""
    from frictionjoint.fmi.ecos import run_ecos

    comps = {"osc": fmus["CoulombOscillator"], "osc2": fmus["CoulombOscillator"], "jenkins": fmus["JenkinsJoint"],
             "iwan": fmus["IwanJoint"], "micro": fmus["MicroslipJoint"], "dove": fmus["DovetailRoot"]}
    params = {"osc": dict(force_amplitude=1e-4, slip_force=0.0, omega=1.5),
              "osc2": dict(force_amplitude=2.0, slip_force=0.5, omega=0.8),
              "jenkins": dict(stiffness=1e4, slip_force=0.3)}
    conns = [("osc.x", "jenkins.u"), ("osc.x", "iwan.u"), ("osc.x", "micro.u"), ("osc.x", "dove.u_tangential"),
             ("osc2.x", "osc.force")]
    s = FMUSystem(comps, conns, params)
    outs = ["osc.x", "osc2.x", "jenkins.force", "iwan.force", "micro.force", "dove.root_force_tangential",
            "dove.friction_force_left", "micro.dissipated_energy", "dove.dissipated_energy"]
    period = 2 * math.pi / 1.5
    e = run_ecos(s, 3 * period, period / 25, outs)
    assert e.success, e.message
    f = s.simulate(3 * period, period / 25, outs, transfer="jacobi")
    for k in outs:
        assert relative(e[k], f[k]) <= 1e-9, k  # measured <= 2.9e-13 (IwanJoint force), others <= 1.3e-14
    assert e["micro.dissipated_energy"][-1] > 0 and e["dove.dissipated_energy"][-1] > 0  # they slipped


def test_two_jenkins_chain_in_ecos_converges_to_the_exact_solution(fmus, tmp_path):
    """The co-simulation case through SSP in Ecos, semi-implicit coupling, against the library's
    exact MDOF solution (see test_cosim.py)."""
    from pathlib import Path

    from frictionjoint.fmi.build import build_fmus
    from frictionjoint.fmi.ecos import run_ecos
    from test_cosim import DIVISIONS, PERIODS, T, errors, exact, observed_order

    from frictionjoint.structure_file import load_structure_definition

    model = Path(__file__).resolve().parents[1] / "models" / "two_dof_chain.toml"
    (chain,) = build_fmus(tmp_path, structures=[model])
    definition = load_structure_definition(model)
    comps = {"chain": chain, "j1": fmus["JenkinsJoint"], "j2": fmus["JenkinsJoint"]}
    s = FMUSystem(comps, joint_connections("chain", "j1", "x1", events=False)
                  + joint_connections("chain", "j2", "x2", events=False))
    errs = []
    for d in DIVISIONS:
        r = run_ecos(s, PERIODS * T, T / d, ["chain.x_x1", "chain.x_x2"])
        assert r.success, r.message
        errs.append(errors(r, exact(definition, d)).max())
    # measured: 1.35, 0.28, 0.093, 0.021 (Jacobi: the joint force lags a step)
    assert errs[-1] < 0.05 and observed_order(errs) > 1.5


@pytest.mark.parametrize("parallel", [True, False])
def test_ecos_executable_logs_a_bad_parameter_and_does_not_crash(fmus, tmp_path, parallel):
    """``ecos simulate`` with the host environment, two instances of one FMU: the FMU's error
    names the parameter in Ecos's log (debug logging on), Ecos steps on (it ignores error
    statuses), the FMU answers each step with an error instead of crashing, the other instance
    runs, and the process ends normally (pythonfmu's exit-time double release and SciPy's
    _uarray release after Py_Finalize used to corrupt the heap at exit: status 139/134 in 6-8
    of 8 runs; fixed in the FMI 2 wrapper's C++ source, frictionjoint/fmi/fmi2_wrapper/fix.patch item
    8, and balanced from Python under pythonfmu's binary, frictionjoint.fmi.wrapper._finalize_before_exit:
    with neither, Ecos unloads and reloads the library and NumPy refuses to load twice)."""
    from frictionjoint.fmi.ecos import ecos_cli

    s = FMUSystem({"osc": fmus["CoulombOscillator"], "osc2": fmus["CoulombOscillator"]}, [],
                  {"osc": dict(mass=-1.0)})
    for _ in range(3):
        p = ecos_cli(s, 1.0, 0.1, tmp_path, parallel=parallel)
        log = p.stdout + p.stderr
        assert "mass must be > 0" in log
        assert "not initialised" in log
        assert p.returncode == 0, log[-3000:]
    rows = (tmp_path / "system.csv").read_text().strip().splitlines()
    assert len(rows) == 12  # header, t = 0 and ten steps


def test_ecos_runs_that_cannot_be_done_are_refused_before_ecos_starts(tmp_path, monkeypatch):
    """Issue 39: as FMUSystem.simulate, run_ecos and ecos_cli refuse points that are not distinct
    in floating point and (run_ecos) rows that cannot fit, naming the parameter, before Ecos starts
    (the SSP need not even exist: nothing is read)."""
    from frictionjoint.errors import ParameterError
    from frictionjoint.fmi import cosim
    from frictionjoint.fmi.ecos import ecos_cli, run_ecos

    for call in (lambda: run_ecos("missing.ssp", 1e9, 1e-9, ["osc.x"]),
                 lambda: ecos_cli("missing.ssp", 1.0, 1e-300, tmp_path / "w")):
        with pytest.raises(ParameterError, match="step must be above the rounding of the times"):
            call()
    monkeypatch.setattr(cosim, "available_memory", lambda: 2 ** 30)  # 1 GiB: 1e8 rows of 2 values, ~100 B each
    with pytest.raises(ParameterError, match=r"1e\+08 communication steps.*18.6 GiB"):
        run_ecos("missing.ssp", 1e8, 1.0, ["osc.x"])
    assert not (tmp_path / "w").exists()
