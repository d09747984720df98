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

import argparse
import hashlib
import importlib.metadata
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
PATCH = HERE / "early_return.patch"
BINARY = HERE / "binaries" / "x86_64-linux" / "libpythonfmu-export.so"
#: the pythonfmu3 release whose sources the patch is for
PYTHONFMU3 = "0.3.4"
#: Zig's target: x86_64 Linux, glibc 2.17 (manylinux2014) or newer
TARGET = "x86_64-linux-gnu.2.17"


def apply_patch(patch: Path, root: Path) -> None:
    """Apply the unified diff ``patch`` (paths ``a/...``/``b/...``, as ``patch -p1``) under ``root``: each
    hunk's old lines must follow the previous hunk's in its file."""
    path, hunks = None, {}
    lines = patch.read_text().splitlines(keepends=True)
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("+++ "):
            path = root / line[4:].strip().split("/", 1)[1]
            hunks.setdefault(path, [])
        elif line.startswith("@@") and path is not None:
            old, new = [], []
            i += 1
            while i < len(lines) and lines[i][:1] in (" ", "-", "+", "\n"):
                body = lines[i][1:] if lines[i] != "\n" else "\n"
                if lines[i][:1] != "+":
                    old.append(body)
                if lines[i][:1] != "-":
                    new.append(body)
                i += 1
            hunks[path].append(("".join(old), "".join(new)))
            continue
        i += 1
    for target, edits in hunks.items():
        text, pos = target.read_text(), 0
        for old, new in edits:  # in order, each after the previous one (as patch does)
            at = text.find(old, pos)
            if at < 0:
                raise RuntimeError(f"{patch.name}: a hunk does not match {target.name} (not pythonfmu3 "
                                   f"{PYTHONFMU3}'s sources?)")
            text, pos = text[:at] + new + text[at + len(old):], at + len(new)
        target.write_text(text)


def _compiler(tmp: Path, name: str) -> Path:
    """A compiler script CMake can call: Zig's ``cc``/``c++`` for :data:`TARGET`."""
    script = tmp / f"zig-{name}"
    script.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m ziglang {name} -target {TARGET} "$@"\n')
    script.chmod(0o755)
    return script


def build(out: Path = BINARY) -> Path:
    """Copy, patch, configure and build the wrapper; write the stripped binary to ``out``."""
    version = importlib.metadata.version("pythonfmu3")
    if version != PYTHONFMU3:
        raise RuntimeError(f"pythonfmu3 {PYTHONFMU3} is needed (the patch is for its sources), found {version}")
    import pythonfmu3

    sources = Path(pythonfmu3.__file__).parent / "pythonfmu-export"
    with tempfile.TemporaryDirectory(prefix="fj_fmi3_wrapper_") as tmpd:
        tmp = Path(tmpd)
        tree = tmp / "pythonfmu-export"
        shutil.copytree(sources, tree, ignore=shutil.ignore_patterns("build"))
        apply_patch(PATCH, tree / "src")
        build_dir = tree / "build"
        env = dict(os.environ, CC=str(_compiler(tmp, "cc")), CXX=str(_compiler(tmp, "c++")))
        cmake = [str(Path(sys.executable).with_name("cmake"))]  # the cmake wheel's, next to this Python
        if not Path(cmake[0]).is_file():
            cmake = [shutil.which("cmake") or "cmake"]
        subprocess.run([*cmake, "-S", str(tree), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
                        f"-DPython3_EXECUTABLE={sys.executable}", "-DCMAKE_SHARED_LINKER_FLAGS=-s"],
                       check=True, env=env)
        subprocess.run([*cmake, "--build", str(build_dir), "--parallel", "2"], check=True, env=env)
        built = tmp / "resources" / "binaries" / "x86_64-linux" / "libpythonfmu-export.so"  # (CMake's ../resources)
        out.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(built, out)
    digest = hashlib.sha256(out.read_bytes()).hexdigest()
    print(f"{out}: {out.stat().st_size} bytes, sha256 {digest}")
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BINARY, help="where to write the binary")
    build(parser.parse_args(argv).out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
