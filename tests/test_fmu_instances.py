"""Many instances of every FMU in one fmpy process with the cyclic GC on (tests/fmu_instances_check.py).

pythonfmu 0.7.0's native wrapper over-releases the FMU script module's ``__dict__`` at every
instantiation and the slave class, instance and log queue after every Python error; the slaves
balance both (frictionjoint.fmi.slaves). Each check runs in its own process so that a crash is
a failed test, not a dead test run.
"""
import json
import subprocess
import sys
from pathlib import Path

import pytest
from fmu_instances_check import BAD  # tests/ is on sys.path (conftest.py)

from frictionjoint.fmi.build import FMUS

HERE = Path(__file__).parent


def run_instances(path, n_instances, n_rounds):
    proc = subprocess.run([sys.executable, str(HERE / "fmu_instances_check.py"), str(path), str(n_instances),
                           str(n_rounds)], capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, f"exit status {proc.returncode}: {proc.stderr[-3000:]}"
    return json.loads(proc.stdout.strip().splitlines()[-1])


# 2 x 25 and 10 x 5 rounds: 50 instantiations each (plus one rejected instance per round and the lone runs)
@pytest.mark.parametrize("n_instances,n_rounds", [(2, 25), (10, 5)])
@pytest.mark.parametrize("name", sorted(FMUS))
def test_many_instances_bit_identical_to_a_lone_one(fmus, name, n_instances, n_rounds):
    res = run_instances(fmus[name], n_instances, n_rounds)
    assert res["instantiations"] == n_instances + n_rounds * (n_instances + 1)
    assert res["differ"] == [[]] * n_rounds  # every instance of every round, bit for bit
    assert res["records"] > 20
    # a bad parameter is an FMI error naming the parameter, in every round, and never a crash
    assert res["rejected"] == [BAD[name][0]] * n_rounds
    # nothing over-released (and nothing leaked per instance) by the end
    before, after = res["references"]
    assert before == after
    assert res["sys_path"] == 1


def test_model_description_allows_many_instances(fmus):
    from fmpy import read_model_description

    for path in fmus.values():
        assert read_model_description(str(path)).coSimulation.canBeInstantiatedOnlyOncePerProcess is False
