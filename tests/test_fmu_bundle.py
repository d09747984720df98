"""FMUs of this package in one process, one after another: each FMU carries the library as the
package ``_frictionjoint_bundle`` in its resources, and Python keeps the first one imported; an
importer (fmpy, this master) deletes an FMU's extracted folder when it frees it. An FMU loaded
later must not look for modules in the folder of one already freed (found by the co-simulation
benchmark: the three-FMU chain run through this master, then the system FMU, gave
``ModuleNotFoundError: No module named '_frictionjoint_bundle.fmi.system_slave'``)."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

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
    proc = subprocess.run([sys.executable, "-c", SCRIPT, str(fmus["JenkinsJoint"]), str(system)],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert out["jenkins"] == 0.0  # the joint ran (u held at 0: no force, exactly)
    assert abs(out["system"]) > 1e-3  # the chain ran: 1 N on unit masses moves it by ~0.1 m in 0.5 s
