import os
import sys

# the independent brute-force reference (tests/bruteforce.py) is imported as a plain module
sys.path.insert(0, os.path.dirname(__file__))

import pytest


@pytest.fixture(scope="session")
def fmus(tmp_path_factory):
    """The FMUs, built once per test session: name -> path."""
    from frictionjoint.fmi.build import build_fmus

    out = tmp_path_factory.mktemp("fmus")
    return {p.stem: p for p in build_fmus(out)}
