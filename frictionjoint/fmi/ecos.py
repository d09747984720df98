"""Run an SSP system in Ecos, a native C++ co-simulation host (``pip install 'frictionjoint[ecos]'``).

Ecos loads the FMUs' shared libraries itself; the Python inside these FMUs then runs in the
host's process. Two ways are offered:

- :func:`run_ecos`: Ecos's library (``libecosc``, through ecospy) in a separate process of this
  Python, recording outputs in full double precision at every communication point (the ``ecos``
  command line writes CSV files with six decimals only).
- :func:`ecos_cli`: the ``ecos`` executable itself, with the environment a non-Python host
  needs (:func:`host_environment`: libpython preloaded, this environment's packages on
  ``PYTHONPATH``, the ``tbb`` wheel's folder on ``LD_LIBRARY_PATH``). FMU log messages reach
  its log only with ``--debugLogging`` and ``-l debug`` (pythonfmu forwards no message, errors
  included, unless debug logging is on).

Ecos's binaries need ``libtbb.so.12``; PyPI's ``tbb`` wheel (in the ``ecos`` and ``test`` extras)
ships it, outside the loader's search path: :func:`load_ecospy` loads it before ecospy, and
:func:`host_environment` puts its folder on ``LD_LIBRARY_PATH``. No system package is needed.

Ecos's master (``fixed_step_algorithm``) is Jacobi: every component steps over
``[t_n, t_n + h]`` with the inputs of ``t_n``, then all connections are transferred; its time is
accumulated (``t += h``), and it does not stop on an FMU's error status.
"""
from __future__ import annotations

import ctypes
import importlib.util
import json
import os
import shutil
import site
import stat
import subprocess
import sys
import sysconfig
from pathlib import Path
from typing import Optional, Sequence

import numpy as np

from ..errors import FMUError, ParameterError, check_positive, check_real
from ..results import CoSimulationResult

__all__ = ["TBB_LIBRARY", "tbb_library", "load_ecospy", "host_environment", "ecos_executable",
           "ecos_environment", "run_ecos", "ecos_cli"]


#: the TBB library Ecos's binaries (libecosc.so, ecos) are linked against
TBB_LIBRARY = "libtbb.so.12"

_REMEDY = "pip install 'frictionjoint[ecos]' (ecospy and tbb, PyPI's TBB wheel, which ships " + TBB_LIBRARY + ")"


def tbb_library() -> Optional[Path]:
    """The ``libtbb.so.12`` of PyPI's ``tbb`` wheel in this environment, or None without it.

    The wheel installs its libraries as data files in ``<prefix>/lib`` (``.venv/lib``,
    ``~/.local/lib``), where neither the dynamic loader nor ecospy looks; Ecos's binaries need
    this one (Debian's ``libtbb12`` is the system's alternative).
    """
    from importlib.metadata import PackageNotFoundError, distribution

    try:
        files = distribution("tbb").files or ()
    except PackageNotFoundError:
        return None
    for f in files:
        if f.name == TBB_LIBRARY:
            path = Path(os.path.normpath(f.locate()))
            if path.is_file():
                return path
    return None


def load_ecospy():
    """Import ecospy, with the ``tbb`` wheel's ``libtbb.so.12`` loaded first.

    ecospy loads its ``libecosc.so`` with ctypes at import, and that library needs
    ``libtbb.so.12``, which the loader finds only in system folders. Loading the wheel's copy
    first (``RTLD_GLOBAL``) satisfies that dependency by its soname, so Ecos runs with no system
    package.

    Returns
    -------
    module
        ``ecospy``.

    Raises
    ------
    FMUError
        ecospy is not installed, or its library cannot load (the loader's reason and the remedy).
    """
    if "ecospy" in sys.modules:
        return sys.modules["ecospy"]
    if importlib.util.find_spec("ecospy") is None:
        raise FMUError(f"Ecos is not installed in this Python ({sys.executable}): {_REMEDY}")
    tbb = tbb_library()
    if tbb is not None:
        try:
            ctypes.CDLL(str(tbb), mode=ctypes.RTLD_GLOBAL)
        except OSError as exc:
            raise FMUError(f"the tbb wheel's {tbb} cannot load here: {exc}") from exc
    try:
        import ecospy
    except OSError as exc:  # ctypes.CDLL of libecosc.so: a library it needs is missing
        raise FMUError(f"the Ecos library (ecospy's libecosc.so) cannot load: {exc}; {_REMEDY}") from exc
    return ecospy


def host_environment() -> dict:
    """The environment variables a non-Python host needs to run these FMUs with this Python.

    Returns
    -------
    dict
        ``LD_PRELOAD``: this interpreter's shared libpython (pythonfmu's binary leaves the Python
        symbols to the process); ``PYTHONPATH``: this environment's site-packages (numpy, scipy);
        with the ``tbb`` wheel installed, ``LD_LIBRARY_PATH``: its folder first (the ``ecos``
        executable needs its ``libtbb.so.12``), then the current ``LD_LIBRARY_PATH``.

    Raises
    ------
    FMUError
        This Python has no shared libpython.
    """
    libdir, library = sysconfig.get_config_var("LIBDIR"), sysconfig.get_config_var("LDLIBRARY")
    lib = Path(libdir or "", library or "")
    if not library or not lib.is_file() or not lib.suffix.startswith(".so"):
        raise FMUError(f"this Python ({sys.executable}) has no shared libpython ({lib}): a non-Python host "
                       "cannot load the FMUs' Python; use a Python built with --enable-shared")
    paths = [p for p in site.getsitepackages() if os.path.isdir(p)]
    env = {"LD_PRELOAD": str(lib), "PYTHONPATH": os.pathsep.join(paths)}
    tbb = tbb_library()
    if tbb is not None:
        current = [p for p in os.environ.get("LD_LIBRARY_PATH", "").split(os.pathsep) if p]
        env["LD_LIBRARY_PATH"] = os.pathsep.join([str(tbb.parent)] + [p for p in current if p != str(tbb.parent)])
    return env


def ecos_executable() -> Path:
    """The ``ecos`` command-line executable shipped in the ecospy wheel.

    The wheel installs it without the execute permission; in that case a copy with the permission
    is made once in ``~/.cache/frictionjoint/ecos-<version>/`` (next to ``proxyfmu``, which ecos
    starts for ``proxyfmu://`` components). It runs with :func:`host_environment`.

    Raises
    ------
    FMUError
        ecospy is not installed, has no executable for this platform, or the copy cannot be made.
    """
    spec = importlib.util.find_spec("ecospy")  # its folder, without loading its library
    if spec is None or not spec.submodule_search_locations:
        raise FMUError(f"Ecos is not installed in this Python ({sys.executable}): {_REMEDY}")
    binaries = Path(list(spec.submodule_search_locations)[0]) / "binaries"
    exe = binaries / "ecos"
    if not exe.is_file():
        raise FMUError(f"the ecospy wheel has no ecos executable for this platform ({binaries})")
    if os.access(exe, os.X_OK):
        return exe
    from importlib.metadata import version

    cache = Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "frictionjoint" / f"ecos-{version('ecospy')}"
    try:
        cache.mkdir(parents=True, exist_ok=True)
        for name in ("ecos", "proxyfmu"):
            src, dst = binaries / name, cache / name
            if src.is_file() and (not dst.is_file() or dst.stat().st_size != src.stat().st_size):
                tmp = dst.with_name(f".{name}.{os.getpid()}")  # complete before it is visible
                shutil.copyfile(src, tmp)
                tmp.chmod(tmp.stat().st_mode | stat.S_IXUSR | stat.S_IXGRP | stat.S_IXOTH)
                os.replace(tmp, dst)
    except OSError as exc:
        raise FMUError(f"cannot make an executable copy of {exe} in {cache} ({exc}); set XDG_CACHE_HOME to a "
                       "writable folder") from exc
    return cache / "ecos"


def ecos_environment(timeout: float = 60.0) -> dict:
    """:func:`host_environment` and ``ECOS``, the ``ecos`` executable, checked to start with it.

    Everything is computed and ``ecos --version`` run before anything is returned, so that a
    caller prints all of it or nothing (``eval "$(frictionjoint host-env)"``).

    Parameters
    ----------
    timeout : float
        Seconds ``ecos --version`` may take [s].

    Returns
    -------
    dict
        ``LD_PRELOAD``, ``PYTHONPATH``, ``LD_LIBRARY_PATH`` (with the tbb wheel) and ``ECOS``.

    Raises
    ------
    FMUError
        Ecos cannot run here: why, and what to do.
    """
    env = host_environment()
    exe = ecos_executable()
    try:
        proc = subprocess.run([str(exe), "--version"], capture_output=True, text=True, timeout=timeout,
                              env=dict(os.environ, **env))
    except (OSError, subprocess.TimeoutExpired) as exc:
        raise FMUError(f"{exe} does not run here: {exc}") from exc
    if proc.returncode != 0:
        reason = (proc.stderr or proc.stdout).strip().splitlines()
        raise FMUError(f"{exe} does not run here (status {proc.returncode}: {reason[-1] if reason else 'no message'}); "
                       f"{_REMEDY}")
    return dict(env, ECOS=str(exe))


def _ssp_path(system_or_ssp, workdir: Path) -> Path:
    from .cosim import FMUSystem

    if isinstance(system_or_ssp, FMUSystem):
        return system_or_ssp.to_ssp(workdir / "system.ssp")
    path = Path(system_or_ssp)
    if not path.exists():
        raise ParameterError(f"ssp: {str(path)!r} not found (from {os.getcwd()})")
    return path.resolve()  # Ecos runs in another working folder


def run_ecos(system_or_ssp, stop_time: float, step: float, outputs: Sequence[str], start_time: float = 0.0,
             timeout: float = 600.0) -> CoSimulationResult:
    """Run a system in Ecos (its library, in a separate process) and record Real outputs.

    Parameters
    ----------
    system_or_ssp : FMUSystem or path
        The system (written to a temporary SSP) or an ``.ssp`` archive / folder (a relative path
        is from the current working folder); its parameter set ``initialValues`` is applied.
    stop_time, step, start_time : float
        As :meth:`FMUSystem.simulate` [s]: ``round((stop_time - start_time) / step)`` steps.
    outputs : sequence of str
        ``"component.variable"`` names of Real outputs.
    timeout : float
        Seconds before the run is abandoned.

    Returns
    -------
    CoSimulationResult
        ``t`` is Ecos's own (accumulated) time. ``success`` is False, with the reason in
        ``message``, when the Ecos process failed (then ``values[name]`` raises that reason).
    """
    import tempfile

    from .cosim import _step_count

    h = check_positive("step", step)
    t0 = check_real("start_time", start_time)
    stop = check_real("stop_time", stop_time)
    # refused before Ecos starts where the points are not distinct or the rows cannot fit: each
    # value passes as a Python float in a list, JSON text and a float64, ~100 bytes in all
    _step_count(t0, stop, h, len(outputs), bytes_per_value=100.0)
    n = int(round((stop - t0) / h))
    if n < 1:
        raise ParameterError(f"stop_time must be at least one step ({h!r} s) after start_time, got {stop_time!r}")
    with tempfile.TemporaryDirectory(prefix="frictionjoint_ecos_") as tmpd:
        ssp = _ssp_path(system_or_ssp, Path(tmpd))
        cmd = [sys.executable, "-m", "frictionjoint.fmi.ecos", str(ssp), repr(h), str(n), repr(t0), *outputs]
        env = dict(os.environ)
        root = str(Path(__file__).resolve().parents[2])  # this package, also from a source checkout
        env["PYTHONPATH"] = root + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, cwd=tmpd)
    lines = proc.stdout.strip().splitlines()
    if proc.returncode != 0 or not lines:
        return CoSimulationResult(t=np.zeros(0), values={}, step=h, host="Ecos", success=False,
                                  message=f"Ecos process ended with status {proc.returncode}: {proc.stderr[-2000:]}")
    data = json.loads(lines[-1])
    if not data["ok"]:
        return CoSimulationResult(t=np.zeros(0), values={}, step=h, host="Ecos", success=False,
                                  message=data["message"])
    rows = np.array(data["rows"], dtype=float).reshape(n + 1, len(outputs) + 1)
    return CoSimulationResult(t=rows[:, 0], values={k: rows[:, i + 1] for i, k in enumerate(outputs)}, step=h,
                              host=f"Ecos {data['version']} (libecosc)")


def ecos_cli(system_or_ssp, stop_time: float, step: float, workdir, debug: bool = True, parallel: bool = True,
             timeout: float = 600.0) -> subprocess.CompletedProcess:
    """Run a system with the ``ecos simulate`` command in ``workdir`` (it writes its CSV there).

    Parameters
    ----------
    system_or_ssp : FMUSystem or path
        A relative path is from the current working folder.
    stop_time, step : float
        [s]; ecos steps while ``t + h <= stop_time`` with accumulated ``t``, so half a step is
        added to ``stop_time``.
    workdir : path
        Working folder (created).
    debug : bool
        ``--debugLogging -l debug``: the FMUs' log messages (errors included) in the output.
    parallel : bool
        False: ``--noParallel`` (components stepped one after the other in one thread).

    Returns
    -------
    subprocess.CompletedProcess
        With ``stdout`` and ``stderr`` as text.
    """
    from .cosim import _step_count

    h = check_positive("step", step)
    _step_count(0.0, check_real("stop_time", stop_time), h, bytes_per_value=0.0)  # distinct points, >= 1 step
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    ssp = _ssp_path(system_or_ssp, workdir)
    cmd = [str(ecos_executable()), "simulate", "--path", str(ssp), "--stepSize", repr(h),
           "--stopTime", repr(check_real("stop_time", stop_time) + h / 2), "--parameterSet", "initialValues"]
    cmd += ["--debugLogging", "-l", "debug"] if debug else ["-l", "warn"]
    if not parallel:
        cmd.append("--noParallel")
    env = dict(os.environ, **host_environment())
    return subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, cwd=workdir)


def _main(argv) -> None:
    """``python -m frictionjoint.fmi.ecos SSP STEP N_STEPS T0 OUTPUT...``: one JSON line."""
    ssp, h, n, t0, outputs = argv[0], float(argv[1]), int(argv[2]), float(argv[3]), argv[4:]
    try:
        ecospy = load_ecospy()
    except FMUError as exc:
        print(json.dumps({"ok": False, "message": str(exc)}))
        return
    EcosLib, EcosSimulation = ecospy.EcosLib, ecospy.EcosSimulation
    EcosLib.set_log_level("warn")
    names = [o.replace(".", "::", 1) for o in outputs]
    try:
        sim = EcosSimulation(ssp_path=ssp, step_size=h)
    except Exception as exc:  # noqa: BLE001 -- ecospy raises a bare Exception with Ecos's last error
        print(json.dumps({"ok": False, "message": f"Ecos could not load {ssp}: {exc}"}))
        return
    if not sim.init(t0, "initialValues"):
        print(json.dumps({"ok": False, "message": f"Ecos could not initialise: {EcosLib.get_last_error()}"}))
        return
    rows = []
    for k in range(n + 1):
        if k:
            sim.step()
        rows.append([sim.get_time(), *(sim.get_real(v) for v in names)])
    sim.terminate()
    sim.free()
    print(json.dumps({"ok": True, "rows": rows, "version": str(EcosLib.version())}), flush=True)


if __name__ == "__main__":
    _main(sys.argv[1:])
