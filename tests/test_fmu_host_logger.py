"""An FMI 2 FMU's error in a host that builds a string from the log category (issue 41, section 1):
OpenModelica's OMSimulator aborted (exit 134, ``basic_string: construction from null``) because
pythonfmu 0.7.0's wrapper called the host's logger with a NULL category. The FMUs carry the wrapper
with frictionjoint's fixes (frictionjoint/fmi/fmi2_wrapper/fix.patch); a host whose logger aborts on a
NULL category (tests/stress/strict_logger_host.py, through fmpy, debug logging off, in a subprocess)
gets fmi2Error with the message and the standard's category, frees the instance and runs another.
pythonfmu's stock binary, put back into the same FMU, aborts that host."""
import json
import shutil
import signal
import subprocess
import sys
import zipfile
from pathlib import Path

import pytest

HOST = Path(__file__).parent / "stress" / "strict_logger_host.py"
ERROR = 3  # fmi2Error


def host(path, name, value, logging="off"):
    proc = subprocess.run([sys.executable, str(HOST), str(path), name, repr(value), logging], capture_output=True,
                          text=True, timeout=300)
    return proc.returncode, json.loads(proc.stdout.strip().splitlines()[-1]) if proc.stdout.strip() else None


@pytest.mark.parametrize("fmu, name, value, text", [
    ("CoulombOscillator", "mass", -1.0, "mass must be > 0"),
    ("JenkinsJoint", "u", 1e308, "input u must be finite"),
])
def test_an_error_reaches_a_strict_host_which_survives(fmus, fmu, name, value, text):
    rc, out = host(fmus[fmu], name, value)
    assert rc == 0 and out["survived"], (rc, out)
    assert out["calls"]["initialize"] == ERROR, out
    assert any(status == ERROR and category == "logStatusError" and text in message
               for status, category, message in out["messages"]), out


def test_the_stock_wrapper_aborts_the_same_host(fmus, tmp_path):
    """The same FMU with pythonfmu 0.7.0's own binary and debug logging on (without, that binary does
    not log the error at all): its error is logged with a NULL category and the host aborts
    (SIGABRT), as OMSimulator did. The fixed wrapper, debug logging on or off, does not."""
    import pythonfmu

    stock = Path(pythonfmu.__file__).parent / "resources" / "binaries" / "linux64" / "libpythonfmu-export.so"
    if not (sys.platform.startswith("linux") and stock.is_file()):
        pytest.skip("pythonfmu's linux64 binary is the comparison")
    path = tmp_path / "CoulombOscillator.fmu"
    with zipfile.ZipFile(fmus["CoulombOscillator"]) as src, zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as dst:
        for item in src.infolist():
            data = stock.read_bytes() if item.filename == "binaries/linux64/CoulombOscillator.so" else src.read(item)
            dst.writestr(item, data)
    rc, out = host(fmus["CoulombOscillator"], "mass", -1.0, "on")
    assert rc == 0 and out["survived"], (rc, out)
    rc, out = host(path, "mass", -1.0, "on")
    # (the slave's own message, with its category, came first; the wrapper's own had none)
    assert rc == -signal.SIGABRT and out["aborted"] == "NULL category", (rc, out)


def test_the_fmus_carry_the_fixed_wrapper_which_loads_on_manylinux2014(fmus):
    """Every FMI 2 FMU's x86_64-linux binary is the fixed wrapper (FMI2_BINARIES), and that binary
    asks for glibc symbols of 2.17 or older only, links no libstdc++ (libc++ is linked in) and no
    libpython (the process provides Python: any CPython 3, stable ABI), as manylinux2014 allows."""
    import re

    from frictionjoint.fmi.build import FMI2_BINARIES

    fixed = FMI2_BINARIES["linux64"].read_bytes()
    for name, path in fmus.items():
        with zipfile.ZipFile(path) as z:
            (binary,) = [n for n in z.namelist() if n.startswith("binaries/linux64/")]
            assert z.read(binary) == fixed, name
    versions = {tuple(int(p) for p in v.split(b".")) for v in re.findall(rb"GLIBC_([0-9]+(?:\.[0-9]+)+)", fixed)}
    assert versions and max(versions) <= (2, 17), sorted(versions)
    assert b"libstdc++.so" not in fixed and not re.search(rb"libpython3\.[0-9]+\.so", fixed)
