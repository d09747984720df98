import os
import sys

# the helper scripts of tests/ (fmu_instances_check.py, ...) are imported as plain modules; the
# brute-force reference is benchmarks/bruteforce.py (pytest's pythonpath has the repository root)
sys.path.insert(0, os.path.dirname(__file__))

import pytest


@pytest.fixture(scope="session")
def fmus(tmp_path_factory):
    """The FMUs, built once per test session: name -> path."""
    from frictionjoint.fmi.build import build_fmus

    out = tmp_path_factory.mktemp("fmus")
    return {p.stem: p for p in build_fmus(out)}


def pytest_collection_modifyitems(config, items):
    """Markers by what a test needs: ``fmu`` for the users of the ``fmus`` fixture, ``stress`` for
    tests/stress; both are ``slow`` too, so that ``pytest -m "not slow"`` is the quick subset
    (``slow`` is set by hand on the other tests that take more than about 2 s)."""
    stress_dir = os.path.join(os.path.dirname(__file__), "stress")
    for item in items:
        if "fmus" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.fmu)
            item.add_marker(pytest.mark.slow)
        if str(item.fspath).startswith(stress_dir):
            item.add_marker(pytest.mark.stress)
            item.add_marker(pytest.mark.slow)
