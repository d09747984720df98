"""Rebuild ``binaries/x86_64-linux/libpythonfmu-export.so``: pythonfmu 0.7.0's wrapper with ``fix.patch``.

Pip-only tools, no system compiler or package::

    python -m venv /tmp/fmi2-build && /tmp/fmi2-build/bin/pip install ziglang==0.17.1 cmake==4.4.5
    /tmp/fmi2-build/bin/python frictionjoint/fmi/fmi2_wrapper/build_wrapper.py

It copies the vendored C++ sources (``pythonfmu-export/``, pythonfmu 0.7.0's), applies the patch, and
configures and builds them with CMake and Zig's clang for glibc 2.17 (:mod:`frictionjoint.fmi.native_build`:
it loads on every manylinux2014 machine). As pythonfmu's own binary, it does not link libpython (its
Python symbols come from the process) and uses the stable ABI (``Py_LIMITED_API``, any CPython 3). The
headers are the running Python's. The result is written over the shipped binary (or to ``--out``); its
size and SHA-256 are printed.
"""
from __future__ import annotations

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
try:
    from ..native_build import build_main, patched_build
except ImportError:  # run as a script (a build venv without frictionjoint's dependencies)
    sys.path.insert(0, str(HERE.parent))
    from native_build import build_main, patched_build

PATCH = HERE / "fix.patch"
SOURCES = HERE / "pythonfmu-export"
BINARY = HERE / "binaries" / "x86_64-linux" / "libpythonfmu-export.so"


def build(out: Path = BINARY) -> Path:
    """Copy, patch, configure and build the wrapper; write the stripped binary to ``out``."""
    return patched_build(SOURCES, PATCH, "resources/binaries/linux64/libpythonfmu-export.so", out)


def main(argv=None) -> int:
    return build_main(build, BINARY, __doc__, argv)


if __name__ == "__main__":
    sys.exit(main())
