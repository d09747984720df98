"""Building pythonfmu's and pythonfmu3's C++ wrappers with patches, with pip-only tools: Zig's clang
(``python -m ziglang cc``, the ``ziglang`` wheel) for ``x86_64-linux-gnu.2.17`` -- glibc 2.17 symbols
only, libc++ linked in, so that the binary loads on every manylinux2014 machine -- and the ``cmake``
wheel. Used by :mod:`.fmi3_wrapper.build_wrapper` and :mod:`.fmi2_wrapper.build_wrapper`."""
from __future__ import annotations

import argparse
import hashlib
import os
import shutil
import subprocess
import sys
import sysconfig
import tempfile
from pathlib import Path

__all__ = ["TARGET", "apply_patch", "build_main", "patched_build"]

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
                raise RuntimeError(f"{patch.name}: a hunk does not match {target.name} (not the sources "
                                   "the patch is for?)")
            text, pos = text[:at] + new + text[at + len(old):], at + len(new)
        target.write_text(text)


def _compiler(tmp: Path, name: str) -> Path:
    """A compiler script CMake can call: Zig's ``cc``/``c++`` for :data:`TARGET`."""
    script = tmp / f"zig-{name}"
    script.write_text(f'#!/bin/sh\nexec "{sys.executable}" -m ziglang {name} -target {TARGET} "$@"\n')
    script.chmod(0o755)
    return script


def patched_build(sources: Path, patch: Path, library: str, out: Path) -> Path:
    """Copy the CMake project ``sources`` (a pythonfmu-export tree) to a temporary folder, apply
    ``patch`` to its ``src``, configure and build it (release, stripped) with Zig's compilers, and copy
    the library CMake writes at ``library`` (relative to the copy's parent: pythonfmu's CMake writes
    to ``../resources``) to ``out``; prints its size and SHA-256."""
    with tempfile.TemporaryDirectory(prefix="fj_wrapper_") as tmpd:
        tmp = Path(tmpd)
        tree = tmp / "pythonfmu-export"
        shutil.copytree(sources, tree, ignore=shutil.ignore_patterns("build"))
        apply_patch(patch, tree / "src")
        build_dir = tree / "build"
        env = dict(os.environ, CC=str(_compiler(tmp, "cc")), CXX=str(_compiler(tmp, "c++")))
        cmake = [str(Path(sys.executable).with_name("cmake"))]  # the cmake wheel's, next to this Python
        if not Path(cmake[0]).is_file():
            cmake = [shutil.which("cmake") or "cmake"]
        subprocess.run([*cmake, "-S", str(tree), "-B", str(build_dir), "-DCMAKE_BUILD_TYPE=Release",
                        f"-DPython3_EXECUTABLE={sys.executable}",
                        # the headers given: a FindPython of the stable ABI alone does not ask the interpreter
                        f"-DPython3_INCLUDE_DIR={sysconfig.get_paths()['include']}",
                        "-DCMAKE_SHARED_LINKER_FLAGS=-s"],
                       check=True, env=env)
        subprocess.run([*cmake, "--build", str(build_dir), "--parallel", "2"], check=True, env=env)
        out.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(tmp / library, out)
    digest = hashlib.sha256(out.read_bytes()).hexdigest()
    print(f"{out}: {out.stat().st_size} bytes, sha256 {digest}")
    return out


def build_main(build, binary: Path, doc: str, argv=None) -> int:
    """A build script's command line: ``--out`` (default ``binary``), then ``build(out)``."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--out", type=Path, default=binary, help="where to write the binary")
    build(parser.parse_args(argv).out)
    return 0
