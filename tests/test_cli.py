"""Tests of the ``frictionjoint`` command (frictionjoint.cli, ``python -m frictionjoint``).

The real command runs in a subprocess with this interpreter; argument errors are also checked
in-process through ``main(argv)``.
"""
import subprocess
import sys
from pathlib import Path

import pytest

from frictionjoint.cli import main

PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
TIMEOUT = 120  # seconds per subprocess


def run(*args, cwd=None):
    return subprocess.run([sys.executable, "-m", "frictionjoint", *args], capture_output=True,
                          text=True, timeout=TIMEOUT, cwd=cwd)


@pytest.mark.slow  # about 2-3 s: a CLI run in a subprocess
def test_demo_writes_table_png_and_csv(tmp_path):
    png, table = tmp_path / "fr.png", tmp_path / "fr.csv"
    proc = run("demo", "--points", "4", "--out", str(png), "--csv", str(table))
    assert proc.returncode == 0, proc.stderr
    out = proc.stdout
    assert "Den Hartog [m]" in out and "rel. error" in out and "stops/cycle" in out
    # r = 0.5 at F/P0 = 0.5 has stops: the regime word stands in the error column
    rows = [ln.split() for ln in out.splitlines() if ln.startswith(("up ", "down "))]
    assert len(rows) == 8
    assert rows[0][:3] == ["up", "0.5", "0.5000"] and rows[0][-2:] == ["stops", "2"]
    assert all(float(row[-2]) <= 1e-9 for row in rows if row[-2] != "stops")
    assert f"wrote {png}" in out
    assert png.read_bytes()[:8] == PNG_MAGIC
    assert table.read_text().count("\n") > 8
    assert "sweep" in proc.stderr  # the progress bar goes to stderr


@pytest.mark.slow  # about 2-3 s: a CLI run in a subprocess
def test_demo_default_output_name(tmp_path):
    proc = run("demo", "--points", "2", "--ratio", "1.5:2.0", "--slip-force", "0.3",
               "--direction", "up", "--no-progress", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "forced_response.png").read_bytes()[:8] == PNG_MAGIC
    assert proc.stderr == ""


@pytest.mark.slow  # about 2-3 s: a CLI run in a subprocess
def test_map_writes_png(tmp_path):
    png, table = tmp_path / "map.png", tmp_path / "map.csv"
    proc = run("map", "--out", str(png), "--friction", "0.3:1.2:2", "--ratio", "0.45:1.5:2",
               "--jobs", "1", "--table", "--csv", str(table), "--no-progress")
    assert proc.returncode == 0, proc.stderr
    assert png.read_bytes()[:8] == PNG_MAGIC
    assert "points per category" in proc.stdout
    assert "S permanent stick" in proc.stdout  # the text map
    assert len(table.read_text().splitlines()) == 1 + 4


def test_bad_arguments_exit_nonzero_in_a_subprocess(tmp_path):
    proc = run("demo", "--points", "zero", cwd=tmp_path)
    assert proc.returncode != 0
    assert "--points" in proc.stderr and "integer" in proc.stderr
    assert not (tmp_path / "forced_response.png").exists()


@pytest.mark.parametrize("argv, words", [
    ([], "required"),
    (["bogus"], "invalid choice"),
    (["sweep", "CoulombOscillator"], "--omega"),
    (["sweep", "CoulombOscillator", "--omega", "0:2:3"], "--omega"),
    (["sweep", "CoulombOscillator", "--omega", "1:2:3", "--set", "mass"], "NAME=VALUE"),
    (["sweep", "CoulombOscillator", "--omega", "1:2:3", "--set", "mass=inf"], "--set"),
    (["sweep", "CoulombOscillator", "--omega", "1:2:3", "--set", "mass=-1"], "mass must be > 0"),
    (["sweep", "CoulombOscillator", "--omega", "1:2:3", "--set", "force_amplitude=0"],
     "force_amplitude + stiffness * base_amplitude"),
    (["sweep", "CoulombOscillator", "--omega", "1:2:3", "--set", "mass=1", "--set", "mass=2"], "twice"),
    (["sweep", "CoulombOscillator", "--omega", "1:2:3", "--set", "omega=2"], "parameters must be among"),
    (["sweep", "CoulombOscillator", "--omega", "1:2:3", "--set", "force_amplitude=1", "--output", "y"], "outputs must be among"),
    (["sweep", "CoulombOscillator", "--omega", "1:2:3", "--compare", "exact"], "--compare"),
    (["sweep", "CoulombOscillator", "--omega", "1:2:3", "--samples", "8"], "--samples"),
    (["sweep", "CoulombOscillator", "--omega", "1:2:3", "--plot", "/nonexistent-dir/x.png"], "--plot"),
    (["sweep", "nothing.fmu", "--omega", "1:2:3"], "existing .fmu file"),
    # issue 25, section 7: a range with a negative START reaches the range's own check (argparse took
    # '-1:2.5:10' for an option: "expected one argument"), with the Python API's message
    (["sweep", "CoulombOscillator", "--omega", "-1:2.5:10"], "START must be a finite angular frequency > 0"),
    (["sweep", "CoulombOscillator", "--omega=-1:2.5:10"], "START must be a finite angular frequency > 0"),
    (["sweep", "CoulombOscillator", "--omega", "-.5:2.5:10"], "START must be a finite angular frequency > 0"),
    (["sweep", "CoulombOscillator", "--omega", "1:2.5:10.5"], "whole number N"),
    (["map", "--ratio", "-0.5:1.5:3"], "START and STOP must be finite"),
    (["demo", "--ratio", "-1:2"], "START and STOP must be finite"),
    # a missing .fmu or a misspelt model: "not found", and the blade models of models/ listed
    (["sweep", "nothing.fmu", "--omega", "1:2:3"], "'nothing.fmu' not found"),
    (["sweep", "CoulombOscilator", "--omega", "1:2:3"], "'CoulombOscilator' not found"),
    (["sweep", "CoulombOscilator", "--omega", "1:2:3"], "(ti64_compressor_blade, ti64_solid_blade)"),
    (["sweep", "two_dof_chain", "--omega", "1:2:3"], "two_dof_chain.toml in"),  # a structure, not a blade
    (["sweep", "ti64_compressor_blade", "--omega", "1:2:3", "--set", "normal_load_variation=maybe"], "true/false"),
    (["demo", "--bogus"], "unrecognized arguments"),
    (["demo", "--poin", "5"], "unrecognized arguments"),  # no silent abbreviations
    (["demo", "--points", "0"], "--points"),
    (["demo", "--points", "2.5"], "--points"),
    (["demo", "--slip-force", "-1"], "--slip-force"),
    (["demo", "--mass", "nan"], "--mass"),
    (["demo", "--ratio", "2.5:0.5"], "--ratio"),
    (["demo", "--ratio", "0:2"], "--ratio"),
    (["demo", "--ratio", "0.5:2:10"], "--ratio"),
    (["demo", "--direction", "sideways"], "--direction"),
    (["demo", "--out", "/nonexistent-dir/x.png"], "does not exist"),
    (["map", "--friction", "0:1"], "--friction"),
    (["map", "--friction", "-0.1:1:3"], "--friction"),
    (["map", "--ratio", "0.5:1.5:0"], "--ratio"),
    (["map", "--ratio", "0.5:1.5:x"], "--ratio"),
    (["map", "--jobs", "0"], "--jobs"),
])
def test_bad_arguments_give_a_clear_error(argv, words, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert words in err
    assert "usage:" in err


def test_set_for_a_blade_lists_only_what_set_takes(capsys):
    """The --set error for a blade model lists the names --set can set (numbers and the switch of
    the root, the tip force), not the root's DOF names or contact law, which a number cannot be."""
    from frictionjoint.sweep import BLADE_SETTINGS

    with pytest.raises(SystemExit) as exc:
        main(["sweep", "ti64_compressor_blade", "--omega", "1900:2100:3", "--set", "flank=1"])
    err = capsys.readouterr().err
    assert exc.value.code == 2 and "['flank']" in err
    assert all(name in err for name in BLADE_SETTINGS)
    assert not any(name in err for name in ("radial_dof", "tangential_dof", "rocking_dof", "flank_contact",
                                            "n_sliders"))


def test_range_values_are_attached_to_their_option_only():
    """Only a range option's value that starts with '-' and a digit or a point is attached; other
    words and everything after '--' stay as they are."""
    from frictionjoint.cli import _attach_range_values

    assert _attach_range_values(["sweep", "M", "--omega", "-1:2:3"]) == ["sweep", "M", "--omega=-1:2:3"]
    assert _attach_range_values(["map", "--ratio", "-.5:1:3", "--friction", "-1:1:2"]) == [
        "map", "--ratio=-.5:1:3", "--friction=-1:1:2"]
    assert _attach_range_values(["sweep", "M", "--omega", "--csv"]) == ["sweep", "M", "--omega", "--csv"]
    assert _attach_range_values(["demo", "--mass", "-1"]) == ["demo", "--mass", "-1"]
    assert _attach_range_values(["x", "--", "--omega", "-1:2:3"]) == ["x", "--", "--omega", "-1:2:3"]


@pytest.mark.slow  # about 3 s: two steady states of the blade on its root
def test_sweep_blade_model_switch_from_the_command_line(tmp_path, capsys):
    """``--set normal_load_variation=true`` (and True, 1) switches the library blade's normal-load
    variation on: the same orbit as the Python call with True (the same computation in this process:
    equal bit for bit), not the frozen-load orbit (about 10 % lower at 259 N: README, normal-load
    variation, to the CSV's digits). '=true' was "expected a number"."""
    import numpy as np

    import frictionjoint as fj
    from frictionjoint.results import OutputSweep

    on = fj.sweep("ti64_compressor_blade", np.array([2025.0]), {"centrifugal_force": 259.0,
                                                              "normal_load_variation": True})
    off = fj.sweep("ti64_compressor_blade", np.array([2025.0]), {"centrifugal_force": 259.0})
    assert abs(on.response[0]) > 1.05 * abs(off.response[0])
    for word in ("true", "True", "1"):
        table = tmp_path / f"{word}.csv"
        assert main(["sweep", "ti64_compressor_blade", "--set", "centrifugal_force=259", "--set",
                     f"normal_load_variation={word}", "--omega", "2025:2025:1", "--csv", str(table),
                     "--no-progress"]) == 0
        # the same computation; the CSV's decimal digits leave a last-bit difference at most
        assert abs(OutputSweep.from_csv(table).response[0] - on.response[0]) <= 1e-14 * abs(on.response[0]), word
    capsys.readouterr()


def test_sweep_blade_fmu_switch_from_the_command_line_and_python(fmus, tmp_path, capsys):
    """BladeDovetail.fmu's Boolean normal_load_variation from ``--set ...=true`` and from Python
    ('yes', 1): the library's orbit with the switch on (to 1e-8, as the blade FMU's sweep against
    the library's); a value that is no switch (0.5) and a fractional Integer are refused (they were
    bool(0.5) = True and int(5.5) = 5, silently)."""
    import numpy as np

    import frictionjoint as fj
    from frictionjoint.errors import ParameterError
    from frictionjoint.results import OutputSweep

    fmu = str(fmus["BladeDovetail"])
    lib = fj.sweep("ti64_compressor_blade", np.array([2025.0]), {"centrifugal_force": 259.0,
                                                               "normal_load_variation": True})
    table = tmp_path / "fmu.csv"
    assert main(["sweep", fmu, "--set", "centrifugal_force=259", "--set", "normal_load_variation=true",
                 "--omega", "2025:2025:1", "--csv", str(table), "--no-progress"]) == 0
    fr = OutputSweep.from_csv(table)
    assert abs(fr.response[0] - lib.response[0]) <= 1e-8 * abs(lib.response[0])
    py = fj.sweep(fmu, "2025:2025:1", {"centrifugal_force": 259.0, "normal_load_variation": "yes"})
    assert abs(py.response[0] - fr.response[0]) <= 1e-14 * abs(fr.response[0])  # the same; fr through its CSV
    for value in (0.5, "maybe"):
        with pytest.raises(ParameterError, match="normal_load_variation must be True or False"):
            fj.sweep(fmu, "2025:2025:1", {"normal_load_variation": value})
    with pytest.raises(ParameterError, match="n_modes must be a whole number"):
        fj.sweep(fmu, "2025:2025:1", {"n_modes": 5.5})
    with pytest.raises(SystemExit) as exc:
        main(["sweep", fmu, "--set", "normal_load_variation=0.5", "--omega", "2025:2025:1", "--no-progress"])
    assert exc.value.code == 2 and "normal_load_variation must be True or False" in capsys.readouterr().err


def test_help_and_version(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out.startswith("frictionjoint ")
    for sub in ("demo", "map", "sweep"):
        with pytest.raises(SystemExit) as exc:
            main([sub, "--help"])
        assert exc.value.code == 0
        assert ("--plot" if sub == "sweep" else "--out") in capsys.readouterr().out


def test_console_script_is_installed():
    script = Path(sys.executable).with_name("frictionjoint")
    if not script.exists():
        pytest.skip("console script not installed next to this interpreter")
    proc = subprocess.run([str(script), "--version"], capture_output=True, text=True, timeout=TIMEOUT)
    assert proc.returncode == 0 and proc.stdout.startswith("frictionjoint ")


def _rows(text):
    return [ln.split() for ln in text.splitlines() if ln.startswith(("up ", "down "))]


@pytest.mark.slow  # about 2-3 s: a CLI run in a subprocess
def test_sweep_library_model_with_compare(tmp_path):
    """``sweep CoulombOscillator --compare analytic``: Den Hartog beside each point, r = 1 unbounded."""
    from frictionjoint.analytic import den_hartog_response as den_hartog
    from frictionjoint.sweep import FrequencyResponse

    png, table = tmp_path / "sw.png", tmp_path / "sw.csv"
    proc = run("sweep", "CoulombOscillator", "--set", "slip_force=0.5", "--set", "force_amplitude=2",
               "--set", "stiffness=4", "--omega", "1.6:2.4:3", "--compare", "analytic",
               "--csv", str(table), "--plot", str(png))
    assert proc.returncode == 0, proc.stderr
    rows = _rows(proc.stdout)
    assert [r[2] for r in rows] == ["0.8000", "1.0000", "1.2000"]  # omega_n = 2 rad/s
    assert rows[1][3] == "unbounded" and rows[1][5] == "unbounded"
    for row in (rows[0], rows[2]):
        ref = den_hartog(1.0, 4.0, 0.5, 2.0, float(row[1]))  # closed form, analytic.py
        assert float(row[4]) == pytest.approx(ref.amplitude, rel=1e-6)  # printed to 7 digits
        assert float(row[5]) <= 1e-9
    fr = FrequencyResponse.from_csv(table)
    for i in (0, 2):
        ref = den_hartog(1.0, 4.0, 0.5, 2.0, fr.omega[i])
        assert abs(fr.amplitude[i] - ref.amplitude) <= 1e-9 * ref.amplitude
        assert abs(fr.harmonics["x"]["peak"][i] - ref.amplitude) <= 1e-9 * ref.amplitude
    assert png.read_bytes()[:8] == PNG_MAGIC


def test_sweep_through_the_fmu_reports_requested_outputs(fmus, tmp_path):
    """The FMU sweep from the command line, without --compare: simulated columns only, per output."""
    from frictionjoint.analytic import den_hartog_response as den_hartog

    table = tmp_path / "sw.csv"
    proc = run("sweep", str(fmus["CoulombOscillator"]), "--set", "slip_force=0.3", "--set",
               "force_amplitude=1", "--omega", "0.8:1.5:2", "--direction", "both",
               "--output", "friction_force", "--output", "v", "--csv", str(table))
    assert proc.returncode == 0, proc.stderr
    assert "through fmpy" in proc.stdout and "Den Hartog" not in proc.stdout
    head = next(ln for ln in proc.stdout.splitlines() if ln.startswith("branch"))
    assert "friction_force peak" in head and "v peak" in head and "x peak" in head
    rows = _rows(proc.stdout)
    assert [(r[0], r[1]) for r in rows] == [("up", "0.8"), ("up", "1.5"), ("down", "1.5"), ("down", "0.8")]
    for row in rows:
        ref = den_hartog(1.0, 1.0, 0.3, 1.0, float(row[1]))
        assert float(row[3]) == pytest.approx(ref.amplitude, rel=1e-6)  # x peak
        assert float(row[6]) == pytest.approx(0.3, rel=1e-12)  # |friction force| = F while slipping
        assert row[-1] == "stop-free"
    text = table.read_text()
    assert "friction_force_peak" in text and "v_amplitude" in text


def test_sweep_rejects_an_fmu_without_oscillator_variables(fmus, capsys):
    with pytest.raises(SystemExit) as exc:  # in this process: the same parser as the subprocess's
        main(["sweep", str(fmus["JenkinsJoint"]), "--omega", "1:2:2", "--set", "force_amplitude=1"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "not an oscillator FMU" in err and "lacks the variables" in err


def test_host_env_prints_what_a_native_host_needs(capsys):
    """Every export, and ECOS, which starts with them (ecos --version) in a process that has only
    them: LD_LIBRARY_PATH holds the tbb wheel's libtbb.so.12 (without it, where the system has
    no libtbb12, ecos stops at the loader with status 127)."""
    import os
    import shlex

    from frictionjoint.fmi.ecos import TBB_LIBRARY

    assert main(["host-env"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert all(line.startswith("export ") for line in lines)
    exports = dict(shlex.split(line[len("export "):])[0].split("=", 1) for line in lines)
    assert os.path.isfile(exports["LD_PRELOAD"]) and "libpython" in exports["LD_PRELOAD"]
    for path in exports["PYTHONPATH"].split(os.pathsep):
        assert os.path.isdir(path)
    import numpy

    assert any(numpy.__file__.startswith(p) for p in exports["PYTHONPATH"].split(os.pathsep))
    assert os.path.isfile(os.path.join(exports["LD_LIBRARY_PATH"].split(os.pathsep)[0], TBB_LIBRARY))
    assert os.access(exports["ECOS"], os.X_OK)
    env = {k: v for k, v in os.environ.items() if k not in ("LD_LIBRARY_PATH", "LD_PRELOAD", "PYTHONPATH")}
    proc = subprocess.run([exports["ECOS"], "--version"], capture_output=True, text=True, timeout=60,
                          env=dict(env, **exports))
    assert proc.returncode == 0 and proc.stdout.startswith("v0."), proc.stderr


@pytest.mark.parametrize("broken", ["ecos does not start", "ecospy not installed"])
def test_host_env_where_ecos_cannot_run_prints_nothing_and_says_why(broken, tmp_path, monkeypatch, capsys):
    """All or nothing for ``eval "$(frictionjoint host-env)"``: stdout empty, the reason and the
    remedy on stderr, status 1, no traceback (it printed LD_PRELOAD and PYTHONPATH, then a
    traceback or a comment, status 0)."""
    import importlib.util

    import frictionjoint.fmi.ecos as ecos

    if broken == "ecos does not start":  # what the loader says without libtbb.so.12
        fake = tmp_path / "ecos"
        fake.write_text("#!/bin/sh\necho 'ecos: error while loading shared libraries: libtbb.so.12: cannot open "
                        "shared object file: No such file or directory' >&2\nexit 127\n")
        fake.chmod(0o755)
        monkeypatch.setattr(ecos, "ecos_executable", lambda: fake)
        reason = "libtbb.so.12"
    else:
        find_spec = importlib.util.find_spec
        monkeypatch.setattr(importlib.util, "find_spec",
                            lambda name, *a: None if name == "ecospy" else find_spec(name, *a))
        reason = "not installed"
    with pytest.raises(SystemExit) as exc:
        main(["host-env"])
    out, err = capsys.readouterr()
    assert exc.value.code == 1
    assert out == ""
    assert reason in err and "pip install 'frictionjoint[ecos]'" in err and "Traceback" not in err


def test_build_fmus_structure(tmp_path, capsys):
    model = Path(__file__).resolve().parents[1] / "models" / "two_dof_chain.toml"
    assert main(["build-fmus", "--out", str(tmp_path), "--structure", str(model)]) == 0
    assert capsys.readouterr().out.strip() == f"built and validated {tmp_path / 'TwoDofChain.fmu'}"
    with pytest.raises(SystemExit) as exc:
        main(["build-fmus", "--out", str(tmp_path), "--structure", str(tmp_path / "none.toml")])
    assert exc.value.code == 2
    assert "none.toml' not found" in capsys.readouterr().err


def test_build_fmus_blade(tmp_path, capsys):
    """--blade builds a blade FMU per definition (here the solid blade on contact patches), named
    after its name; an unknown model and FMI 3 are refused with the option named."""
    assert main(["build-fmus", "--out", str(tmp_path), "--blade", "ti64_solid_blade"]) == 0
    assert capsys.readouterr().out.strip() == f"built and validated {tmp_path / 'Ti64SolidBlade.fmu'}"
    for argv, words in ((["--blade", "no_such_blade"], "no_such_blade"),
                        (["--blade", "ti64_solid_blade", "--fmi-version", "3"], "--blade")):
        with pytest.raises(SystemExit) as exc:
            main(["build-fmus", "--out", str(tmp_path)] + argv)
        assert exc.value.code == 2
        assert words in capsys.readouterr().err


@pytest.mark.slow  # about 4 s: sweeping the blade on its root
def test_sweep_blade_model_with_its_linear_limits(tmp_path, capsys):
    """``sweep ti64_compressor_blade``: the tip's first harmonic with the root's linear limits; far
    from resonance the root sticks and the tip equals the stuck limit (the same linear solve, to
    rounding); the CSV round trip keeps every number; bad input names itself. In this process
    through main(argv) (the real command's subprocesses: the demo, map and compare tests above)."""
    from frictionjoint.results import OutputSweep

    png, table = tmp_path / "blade.png", tmp_path / "blade.csv"
    assert main(["sweep", "ti64_compressor_blade", "--set", "centrifugal_force=200", "--omega", "1800:2100:4",
                 "--csv", str(table), "--plot", str(png), "--no-progress"]) == 0
    assert "4 of 4 points converged" in capsys.readouterr().out
    fr = OutputSweep.from_csv(table)
    assert fr.output == "w30" and fr.stuck[0]
    assert abs(fr.response[0] - fr.limits["stuck"][0]) <= 1e-9 * abs(fr.limits["stuck"][0])
    assert png.read_bytes()[:8] == PNG_MAGIC
    with pytest.raises(SystemExit) as exc:
        main(["sweep", "ti64_compressor_blade", "--set", "flank=1", "--omega", "1800:2100:2"])
    assert exc.value.code == 2 and "flank" in capsys.readouterr().err


def test_sweep_blade_fmu_equals_the_library_sweep(fmus, tmp_path, capsys):
    """``sweep BladeDovetail.fmu``: the blade FMU through fmpy; its CSV equals the library's sweep
    of the definition (to 1e-8; tests/test_blade_fmu.py for more)."""
    import numpy as np

    import frictionjoint as fj
    from frictionjoint.results import OutputSweep

    table = tmp_path / "fmu.csv"
    proc = run("sweep", str(fmus["BladeDovetail"]), "--set", "centrifugal_force=46", "--omega", "1900:2000:2",
               "--csv", str(table), "--no-progress")
    assert proc.returncode == 0, proc.stderr
    assert "2 of 2 points converged" in proc.stdout
    fr = OutputSweep.from_csv(table)
    lib = fj.sweep("ti64_compressor_blade", fr.omega, {"centrifugal_force": 46.0})
    assert np.max(np.abs(fr.response - lib.response) / np.abs(lib.response)) <= 1e-8
    with pytest.raises(SystemExit) as exc:  # in this process: the same parser as the subprocess's
        main(["sweep", str(fmus["BladeDovetail"]), "--set", "flank=1", "--omega", "1800:2100:2"])
    assert exc.value.code == 2 and "flank" in capsys.readouterr().err


def test_sweep_blade_model_by_harmonic_balance(tmp_path, capsys):
    """``sweep MODEL --method hbm --harmonics H``: the harmonic-balance branch (continuation) in the
    same table and CSV, its stuck points on the stuck linear limit (the same linear solve); the
    oscillator has no --method hbm. In this process through main(argv)."""
    import numpy as np

    from frictionjoint.results import OutputSweep

    table = tmp_path / "hbm.csv"
    assert main(["sweep", "ti64_compressor_blade", "--set", "centrifugal_force=259", "--omega", "1950:2100:20",
                 "--method", "hbm", "--harmonics", "5", "--check", "--csv", str(table), "--no-progress"]) == 0
    stdout = capsys.readouterr().out
    assert "harmonic balance (H = 5)" in stdout and "points converged" in stdout
    assert "stable" in stdout.splitlines()[2] and "fold" in stdout.splitlines()[2]
    fr = OutputSweep.from_csv(table)
    assert fr.converged.all() and fr.omega[0] == 1950.0 and fr.omega[-1] >= 2100.0
    # every point checked against its exact orbit (the blade's forced resonance has no fold: all
    # stable); stuck points are exact, slipping ones carry the truncation (at H = 5 up to 64 % of
    # the complex first harmonic just after the root starts to slip, where the phase swings)
    assert fr.stable is not None and all(v is True for v in fr.stable) and not fr.fold.any()
    assert "trunc. err" in stdout and np.all(np.isfinite(fr.truncation_error))
    assert np.all(fr.truncation_error[fr.stuck] <= 1e-9) and np.all(fr.truncation_error[~fr.stuck] > 1e-6)
    assert fr.stuck.any() and not fr.stuck.all()
    s = fr.stuck
    assert np.max(np.abs(fr.response[s] - fr.limits["stuck"][s]) / np.abs(fr.limits["stuck"][s])) <= 1e-8
    for option in (["--method", "hbm"], ["--check"]):
        with pytest.raises(SystemExit) as exc:
            main(["sweep", "CoulombOscillator", "--omega", "0.5:2:3", *option])
        err = capsys.readouterr().err
        assert exc.value.code == 2 and "blade model" in err and option[0] in err
