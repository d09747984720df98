"""FMUs of this package in one process, one after another: each FMU carries the library as the
package ``_frictionjoint_bundle`` in its resources, and Python keeps the first one imported; an
importer (fmpy, this master) deletes an FMU's extracted folder when it frees it. An FMU loaded
later must not look for modules in the folder of one already freed (found by the co-simulation
benchmark: the three-FMU chain run through this master, then the system FMU, gave
``ModuleNotFoundError: No module named '_frictionjoint_bundle.fmi.system_slave'``).

An FMU runs the installed ``frictionjoint`` instead where that is its very library (the same
identity: frictionjoint.fmi.bundle_loader), its bundle otherwise."""
import json
import os
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

from frictionjoint.fmi.bundle_loader import ARCHIVE, BUNDLE, FORCE_BUNDLE, IDENTITY, identity

ROOT = Path(__file__).resolve().parents[1]

SCRIPT = r"""
import json, sys
from fmpy import simulate_fmu
jenkins, system = sys.argv[1], sys.argv[2]
# a JenkinsJoint FMU first: fmpy extracts it, imports the bundle from there, and removes the folder
a = simulate_fmu(jenkins, stop_time=0.1, output_interval=0.05, output=["force"])
# then the system FMU, whose slave module the first FMU's bundle never imported
b = simulate_fmu(system, stop_time=0.5, output_interval=0.1, output=["x_x2"])
print(json.dumps({"jenkins": float(a["force"][-1]), "system": float(b["x_x2"][-1])}))
"""


@pytest.mark.slow
def test_an_fmu_after_another_was_freed(fmus, tmp_path):
    from frictionjoint.cli import main

    assert main(["build-fmus", "--system", str(ROOT / "models" / "two_dof_chain_system.toml"),
                 "--out", str(tmp_path)]) == 0
    system = next(tmp_path.glob("*.fmu"))
    # the bundles themselves (the installed library is this FMUs' own: they would run that)
    proc = subprocess.run([sys.executable, "-c", SCRIPT, str(fmus["JenkinsJoint"]), str(system)],
                          capture_output=True, text=True, timeout=300, env=dict(os.environ, **{FORCE_BUNDLE: "1"}))
    assert proc.returncode == 0, proc.stderr[-3000:]
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert out["jenkins"] == 0.0  # the joint ran (u held at 0: no force, exactly)
    assert abs(out["system"]) > 1e-3  # the chain ran: 1 N on unit masses moves it by ~0.1 m in 0.5 s


CHOICE = r"""
import json, sys
from frictionjoint.fmi.master import FMUInstance
inst = FMUInstance(sys.argv[1])
inst.initialize(dict(slip_force=0.3, force_amplitude=1.0, omega=0.8, x0=0.1, v0=-0.2))
inst.step_to(20.0)
x = inst.get(["x", "v", "dissipated_energy"])
inst.close()
print(json.dumps({"bundle": "_frictionjoint_bundle" in sys.modules, "out": x}))
"""


def _run_choice(path, **env):
    proc = subprocess.run([sys.executable, "-c", CHOICE, str(path)], capture_output=True, text=True, timeout=300,
                          env=dict(os.environ, **env))
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


@pytest.mark.slow
def test_an_fmu_runs_the_installed_library_only_where_it_is_its_own(fmus, tmp_path):
    """Built from this library, an FMU runs it (its compiled kernels: the bundle is not imported);
    with FRICTIONJOINT_FMU_BUNDLED=1, or when its bundle is another library (here: the same files
    with another identity written), it runs its bundle. The numbers agree to rounding (the
    NumPy paths of the kernels; measured equal)."""
    env = {k: v for k, v in os.environ.items() if k != FORCE_BUNDLE}
    own = _run_choice(fmus["CoulombOscillator"], **env)
    assert not own["bundle"]
    forced = _run_choice(fmus["CoulombOscillator"], **{FORCE_BUNDLE: "1"})
    assert forced["bundle"]
    other = tmp_path / "CoulombOscillator.fmu"
    with zipfile.ZipFile(fmus["CoulombOscillator"]) as z:
        items = {name: z.read(name) for name in z.namelist()}
    inner = tmp_path / ARCHIVE
    inner.write_bytes(items[f"resources/{ARCHIVE}"])
    with zipfile.ZipFile(inner) as z:
        bundle = {name: z.read(name) for name in z.namelist()}
    bundle[f"{BUNDLE}/{IDENTITY}"] = json.dumps({"version": "0.0.0", "sha256": "0" * 64}).encode()
    with zipfile.ZipFile(inner, "w") as z:
        for name, data in bundle.items():
            z.writestr(name, data)
    items[f"resources/{ARCHIVE}"] = inner.read_bytes()
    with zipfile.ZipFile(other, "w") as z:
        for name, data in items.items():
            z.writestr(name, data)
    changed = _run_choice(other, **env)
    assert changed["bundle"]
    scale = max(abs(v) for v in own["out"])
    for run in (forced, changed):
        assert max(abs(a - b) for a, b in zip(run["out"], own["out"])) <= 1e-12 * scale


def test_identity_is_that_of_the_files_the_bundle_carries(tmp_path):
    """The identity of the installed library is that of a copy without what the bundle leaves out
    (bytecode, the command line); one byte changed in one file changes it."""
    import frictionjoint

    src = Path(frictionjoint.__file__).parent
    copy = tmp_path / "copy"
    shutil.copytree(src, copy, ignore=shutil.ignore_patterns("__pycache__", "*.pyc", "cli.py", "__main__.py"))
    (copy / "__pycache__").mkdir(exist_ok=True)
    (copy / "__pycache__" / "x.pyc").write_bytes(b"bytecode")
    ident = identity(str(copy))
    assert ident == identity(str(src))
    assert ident["version"] == frictionjoint.__version__
    target = copy / "errors.py"
    data = target.read_bytes()
    target.write_bytes(data[:-1] + bytes([data[-1] ^ 1]))
    assert identity(str(copy))["sha256"] != ident["sha256"]


def test_a_library_edited_after_this_process_started_is_not_taken_for_the_bundle(tmp_path):
    """The modules a process has imported may be older than the files the identity reads: files
    modified after the process started (Linux) make the FMU take its bundle."""
    from frictionjoint.fmi import bundle_loader

    if bundle_loader._process_start() is None:
        pytest.skip("the process start time is not known here (no /proc)")
    (tmp_path / "a.py").write_text("x = 1\n")
    assert bundle_loader._edited_since_start(str(tmp_path))
    old = bundle_loader._process_start() - 3600.0
    os.utime(tmp_path / "a.py", (old, old))
    assert not bundle_loader._edited_since_start(str(tmp_path))
