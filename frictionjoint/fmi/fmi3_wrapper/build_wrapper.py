"""Rebuild ``binaries/x86_64-linux/libpythonfmu-export.so``: pythonfmu3's wrapper with ``early_return.patch``.

Pip-only tools, no system compiler or package::

    python -m venv /tmp/fmi3-build && /tmp/fmi3-build/bin/pip install pythonfmu3==0.3.4 ziglang==0.17.1 cmake==4.4.5
    /tmp/fmi3-build/bin/python frictionjoint/fmi/fmi3_wrapper/build_wrapper.py

It copies the C++ sources that the installed pythonfmu3 (0.3.4 exactly: the patch is for its sources)
ships in ``pythonfmu3/pythonfmu-export``, applies the patch, configures them with CMake with Zig's clang
(``python -m ziglang cc``) for ``x86_64-linux-gnu.2.17`` -- glibc 2.17 symbols only, libc++ linked in,
so that it loads on every manylinux2014 machine -- builds the release and strips it. As pythonfmu3's own
binary, it does not link libpython (its Python symbols come from the process: a Python host, or a
native host that loads libpython globally first) and uses the stable ABI (``Py_LIMITED_API``, any
CPython 3). The headers are the running Python's. The result is written over the shipped binary (or to
``--out``); its size and SHA-256 are printed.
"""
from __future__ import annotations

import importlib.metadata
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
try:
    from ..native_build import TARGET, apply_patch, build_main, patched_build  # noqa: F401 (apply_patch: build.postprocess3's)
except ImportError:  # run as a script (a build venv without frictionjoint's dependencies)
    sys.path.insert(0, str(HERE.parent))
    from native_build import TARGET, apply_patch, build_main, patched_build  # noqa: F401

PATCH = HERE / "early_return.patch"
BINARY = HERE / "binaries" / "x86_64-linux" / "libpythonfmu-export.so"
#: the pythonfmu3 release whose sources the patch is for
PYTHONFMU3 = "0.3.4"


def build(out: Path = BINARY) -> Path:
    """Copy, patch, configure and build the wrapper; write the stripped binary to ``out``."""
    version = importlib.metadata.version("pythonfmu3")
    if version != PYTHONFMU3:
        raise RuntimeError(f"pythonfmu3 {PYTHONFMU3} is needed (the patch is for its sources), found {version}")
    import pythonfmu3

    sources = Path(pythonfmu3.__file__).parent / "pythonfmu-export"
    return patched_build(sources, PATCH, "resources/binaries/x86_64-linux/libpythonfmu-export.so", out)


def main(argv=None) -> int:
    return build_main(build, BINARY, __doc__, argv)


if __name__ == "__main__":
    sys.exit(main())
