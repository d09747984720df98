"""Examples and documentation run as tests: examples/forced_response.py, the Python examples of the
user guide (docs/*.md) and of the README (copies of the guide's), the README's two set-up commands
and their agreement with .ci/run."""
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOCS = ROOT / "docs"
PNG_MAGIC = b"\x89PNG\r\n\x1a\n"
TIMEOUT = 120  # seconds per subprocess


def code_blocks(text):
    """``(language, body)`` of every fenced code block, in order."""
    return [(m.group(1), m.group(2)) for m in re.finditer(r"^```(\w*)\n(.*?)^```", text, re.S | re.M)]


#: the Python examples of the guide, each executed by a test below: page -> a line only it holds
GUIDE_EXAMPLES = {
    "getting-started.md": "osc = fj.CoulombOscillator(",
    "cosimulation.md": "system = FMUSystem(",
    "blades.md": "from frictionjoint.structures import BeamBlade",
    "harmonic-balance.md": "hb = fj.harmonic_balance(",
    "studies.md": "study = Study(",
    "nonlinear-modes.md": "nm = fj.nonlinear_mode(",
    "campbell.md": "cd = fj.campbell(",
    "solid-blades.md": "pattern = slip_pattern(",
    "fmus.md": "system = ModelExchangeSystem(",
}


def guide_example(page):
    """The Python example of a guide page (the one block holding its marker), and its origin."""
    path = DOCS / page
    blocks = [body for lang, body in code_blocks(path.read_text()) if lang == "python"]
    found = [b for b in blocks if GUIDE_EXAMPLES[page] in b]
    assert len(found) == 1, f"{page}: {len(found)} Python blocks hold {GUIDE_EXAMPLES[page]!r}"
    return found[0], f"{path}:python-example"


def test_every_python_example_is_executed():
    """Each Python block of the guide is one of GUIDE_EXAMPLES (so a test runs it), and each Python
    block of the README is a copy of one of them."""
    guide = {}
    for path in sorted(DOCS.rglob("*.md")):
        if "_build" in path.parts:
            continue
        for lang, body in code_blocks(path.read_text()):
            if lang == "python":
                page = path.relative_to(DOCS).as_posix()
                assert page in GUIDE_EXAMPLES and GUIDE_EXAMPLES[page] in body, \
                    f"{page}: a Python block no test runs (add it to GUIDE_EXAMPLES and a test)"
                guide.setdefault(page, []).append(body)
    assert {p: len(b) for p, b in guide.items()} == {p: 1 for p in GUIDE_EXAMPLES}
    executed = {bodies[0] for bodies in guide.values()}
    readme = [body for lang, body in code_blocks(README.read_text()) if lang == "python"]
    assert readme, "the README shows the scripted co-simulation example"
    for body in readme:
        assert body in executed, "a README Python block that is not a copy of the guide's example"


@pytest.mark.slow  # about 2-3 s: the example script in a subprocess
def test_forced_response_example(tmp_path):
    out = tmp_path / "fr.png"
    env = dict(os.environ, FRICTIONJOINT_EXAMPLE_POINTS="3")
    proc = subprocess.run([sys.executable, str(ROOT / "examples" / "forced_response.py"), str(out)],
                          capture_output=True, text=True, timeout=TIMEOUT, cwd=tmp_path, env=env)
    assert proc.returncode == 0, proc.stderr
    assert out.read_bytes()[:8] == PNG_MAGIC
    assert "Den Hartog" in proc.stdout and f"wrote {out}" in proc.stdout
    rows = [ln for ln in proc.stdout.splitlines() if ln.startswith(("up ", "down "))]
    assert len(rows) == 6  # three points up, three down


def test_forced_response_example_points_argument(tmp_path, monkeypatch, capsys):
    """The script's arguments (a relative PNG path, the number of points), which win over the
    environment variable: run as ``__main__`` in this process (runpy; the script in a subprocess of
    its own is the test above), 6.5 s -> 1 s on a loaded machine."""
    import runpy

    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("FRICTIONJOINT_EXAMPLE_POINTS", "60")
    monkeypatch.setattr(sys, "argv", [str(ROOT / "examples" / "forced_response.py"), "plot.png", "2"])
    runpy.run_path(sys.argv[0], run_name="__main__")
    assert (tmp_path / "plot.png").read_bytes()[:8] == PNG_MAGIC
    rows = [ln for ln in capsys.readouterr().out.splitlines() if ln.startswith(("up ", "down "))]
    assert len(rows) == 4  # two points up, two down


def test_readme_opens_with_the_two_commands():
    text = README.read_text()
    title, rest = text.split("\n", 1)
    assert title.startswith("# ")
    # title, a one-sentence description, then two code blocks with one command each
    match = re.match(r"\s*([^\n`]+)\n\s*```bash\n([^\n]+)\n```\s*```bash\n([^\n]+)\n```\n", rest)
    assert match, "README must open with a sentence and exactly two one-line code blocks"
    description, main_job, tests = match.groups()
    assert description.endswith(".") and description.count(". ") == 0
    assert main_job.startswith("python3 -m venv .venv && .venv/bin/pip install -e . && ")
    # the main job: build the FMUs, sweep CoulombOscillator.fmu through fmpy, compare, plot
    assert "frictionjoint build-fmus" in main_job and "frictionjoint sweep " in main_job
    assert "CoulombOscillator.fmu" in main_job and "--compare analytic" in main_job
    assert "--plot " in main_job
    assert tests.startswith("python3 -m venv .venv && .venv/bin/pip install -e '.[test]' && ")
    assert tests.endswith("pytest -q -n auto")  # pytest-xdist: every core (the tests are single-threaded)
    assert "<!-- numbers filled in by the core developer -->" in text or "## Accuracy" in text
    # what a newcomer needs in the first five minutes; the rest is in the guide (issue 27)
    assert len(text.splitlines()) <= 250
    for link in re.findall(r"\]\((docs/[^)#]+)", text):
        assert (ROOT / link).is_file(), f"README links to a missing page {link}"


@pytest.mark.slow
def test_library_example_runs(tmp_path, monkeypatch):
    """The library example of docs/getting-started.md."""
    block, origin = guide_example("getting-started.md")
    monkeypatch.chdir(tmp_path)
    exec(compile(block, origin, "exec"), {"__name__": "guide"})
    assert (tmp_path / "sweep.png").read_bytes()[:8] == PNG_MAGIC


def test_harmonic_balance_example_runs(tmp_path, monkeypatch):
    block, origin = guide_example("harmonic-balance.md")
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "guide"}
    exec(compile(block, origin, "exec"), namespace)
    hb, sw = namespace["hb"], namespace["sw"]
    assert hb.converged and hb.truncation_error <= 1e-3 and hb.stable is True
    assert sw.success and (tmp_path / "hbm_branch.png").read_bytes()[:8] == PNG_MAGIC


def test_system_of_fmus_example_runs(tmp_path, monkeypatch, fmus):
    """The FMUSystem example of docs/cosimulation.md (and the README), with the FMUs its shell
    commands build in build/."""
    from frictionjoint.fmi.build import build_fmus

    block, origin = guide_example("cosimulation.md")
    build = tmp_path / "build"
    build.mkdir()
    for path in fmus.values():
        shutil.copy(path, build / path.name)
    build_fmus(build, structures=[ROOT / "models" / "two_dof_chain.toml"])
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "readme"}
    exec(compile(block, origin, "exec"), namespace)
    result = namespace["result"]
    assert result.t[-1] == pytest.approx(20.9, abs=0.0524) and abs(result["j2.force"]).max() <= 0.8 + 1e-12
    assert (tmp_path / "chain.ssp").is_file()


def test_model_exchange_example_runs(tmp_path, monkeypatch):
    """The Model Exchange example of docs/fmus.md, with the FMUs its shell commands build in build/:
    fmpy's loop and this library's master both locate the exact solution's 31 events (the chain of
    tests/test_model_exchange.py, 20.9 s: four periods of omega = 1.2 rad/s but the last 0.04 s)."""
    from frictionjoint.fmi.build import build_fmus

    block, origin = guide_example("fmus.md")
    build_fmus(tmp_path / "build", names=["JenkinsJoint"], structures=[ROOT / "models" / "two_dof_chain.toml"],
               systems=[ROOT / "models" / "two_dof_chain_system.toml"], interface="model-exchange")
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "guide"}
    exec(compile(block, origin, "exec"), namespace)
    r, result = namespace["r"], namespace["result"]
    assert r["event_count"][-1] == 31 and result.host.endswith("31 events located")
    assert abs(result["j2.force"]).max() <= 0.8 * (1 + 1e-12)


def test_ci_runs_the_readme_test_command():
    bash = shutil.which("bash")
    if bash is None:
        pytest.skip("bash not available")
    script = ROOT / ".ci" / "run"
    text = script.read_text()
    assert text.startswith("#!/usr/bin/env bash") and "set -euo pipefail" in text
    assert "status -eq 5" in text  # 'no tests collected' is a failure
    proc = subprocess.run([bash, str(script), "--dry-run"], capture_output=True, text=True,
                          timeout=TIMEOUT)
    assert proc.returncode == 0, proc.stderr
    readme_tests = code_blocks(README.read_text())[1][1].strip()
    invocation = readme_tests.rsplit("&& .venv/bin/", 1)[1]
    assert proc.stdout.splitlines()[-1] == f"$VENV/bin/{invocation}"
    assert "python3 -m venv" in proc.stdout and "install -e '.[test]'" in proc.stdout
    bad = subprocess.run([bash, str(script), "--bogus"], capture_output=True, text=True,
                         timeout=TIMEOUT)
    assert bad.returncode != 0


@pytest.mark.slow
def test_readme_main_job_runs_with_fewer_points(tmp_path):
    """The README's main command, verbatim after installation, but with 6 frequencies instead of
    60 (CI time): FMUs built, the FMU swept, Den Hartog beside every stop-free point, plot written."""
    import shlex

    text = README.read_text()
    main_job = code_blocks(text)[0][1].strip()
    steps = main_job.split(" && ")[2:]  # after 'python3 -m venv' and 'pip install -e .'
    assert len(steps) == 2
    for step in steps:
        argv = shlex.split(step)
        assert argv[0] == ".venv/bin/frictionjoint"
        argv = [sys.executable, "-m", "frictionjoint", *argv[1:]]
        if "sweep" in argv:
            i = argv.index("--omega")
            start, stop, n = argv[i + 1].split(":")
            assert int(n) >= 60
            argv[i + 1] = f"{start}:{stop}:6"
        proc = subprocess.run(argv, capture_output=True, text=True, timeout=TIMEOUT, cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr[-3000:]
    out = proc.stdout
    assert "through fmpy" in out and "Den Hartog [m]" in out
    errors = [ln.split()[5] for ln in out.splitlines() if ln.startswith(("up ", "down "))]
    assert len(errors) == 12
    numeric = [float(e) for e in errors if e[0].isdigit()]
    assert len(numeric) >= 8 and max(numeric) <= 1e-9
    png = argv[argv.index("--plot") + 1]
    assert (tmp_path / png).read_bytes()[:8] == PNG_MAGIC


def test_blade_example_runs():
    """The blade-models example of docs/blades.md (issue 13)."""
    block, origin = guide_example("blades.md")
    namespace = {"__name__": "guide"}
    exec(compile(block, origin, "exec"), namespace)
    assert namespace["reduced"].dof_names[-1] == "r_w30" and namespace["model"].name == "Ti64CompressorBlade"


@pytest.mark.slow
@pytest.mark.weekly  # 74 s on a loaded 2-core machine: two 3-point studies and three 121-point FRFs
def test_blade_root_study_example(tmp_path):
    """examples/blade_root_study.py, whole. Weekly (.ci/weekly): what it runs is covered on every commit
    by test_study_example_runs (a Study of the same blade definition on a local pool, the damper
    curve's minimum inside the loads), tests/test_study.py and tests/test_study_robust.py (Values,
    run_study's restart from its CSV), tests/test_dovetail.py's friction-damper optimum and
    tests/test_cli.py's blade sweep with its linear limits (BladeAssembly.frequency_response)."""
    out = tmp_path / "study.png"
    env = dict(os.environ, FRICTIONJOINT_EXAMPLE_POINTS="3")
    proc = subprocess.run([sys.executable, str(ROOT / "examples" / "blade_root_study.py"), str(out)],
                          capture_output=True, text=True, timeout=300, cwd=tmp_path, env=env)
    assert proc.returncode == 0, proc.stderr
    assert out.read_bytes()[:8] == PNG_MAGIC
    assert proc.stdout.count("optimum:") == 2 and "121 of 121 points converged" in proc.stdout


@pytest.mark.slow
def test_study_example_runs(tmp_path, monkeypatch):
    """The study example of docs/studies.md (5 root loads on 2 local processes) writes its table
    and plot, and the damper curve has its minimum inside the range of loads."""
    import numpy as np

    block, origin = guide_example("studies.md")
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__main__"}  # run as a script (its guard lets the pool's workers import it)
    exec(compile(block, origin, "exec"), namespace)
    table = namespace["table"]
    assert len(table) == 5 and table.success
    assert 0 < int(np.argmin(table["peak_amplitude"])) < 4
    assert (tmp_path / "damper.csv").exists() and (tmp_path / "damper.png").read_bytes()[:4] == b"\x89PNG"


@pytest.mark.slow  # about 5 s: a coarse solid blade reduced to its flanks, one steady state
def test_solid_blades_example_runs(tmp_path, monkeypatch):
    """The step-by-step example of docs/solid-blades.md: partial slip over the flanks at 2050 rad/s
    (the ends of each flank stick, the inner nodes slip), its picture written."""
    block, origin = guide_example("solid-blades.md")
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "guide"}
    exec(compile(block, origin, "exec"), namespace)
    fraction = namespace["pattern"].fraction()
    assert namespace["static"].regime == "slipping" and namespace["reduced"].n_dof == 26
    assert fraction.max() > 0.1 and fraction[[0, 4, 5, 9]].max() < 1e-3
    assert (tmp_path / "slip_pattern.png").read_bytes()[:8] == PNG_MAGIC


@pytest.mark.slow
@pytest.mark.weekly  # 89 s on a loaded 2-core machine: three frequencies far apart, two slipping, the varying loads
def test_solid_blade_root_example(tmp_path):
    """examples/solid_blade_root.py, whole. Weekly (.ci/weekly): what it runs is covered on every commit
    by test_solid_blades_example_runs (the solid blade reduced to its flanks, its static state, a
    partial-slip steady state and its slip pattern), tests/test_solid_blade_model.py (the definition's
    sweep, frozen and varying normal loads with lift-off), tests/test_solid_root.py (the static contact
    state), tests/test_slip_pattern.py and tests/test_blade_fmu.py's solid blade run."""
    env = dict(os.environ, FRICTIONJOINT_EXAMPLE_POINTS="3")
    proc = subprocess.run([sys.executable, str(ROOT / "examples" / "solid_blade_root.py"), str(tmp_path / "study")],
                          capture_output=True, text=True, timeout=600, cwd=tmp_path, env=env)
    assert proc.returncode == 0, proc.stderr
    for name in ("study_response.png", "study_slip.png"):
        assert (tmp_path / name).read_bytes()[:8] == PNG_MAGIC
    assert "slipping during run-up" in proc.stdout and "gross slip" in proc.stdout
    assert "varying normal loads at 1920 rad/s: periodic steady state found" in proc.stdout
