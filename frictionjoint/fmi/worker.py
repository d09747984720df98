"""An FMU instance in a worker process: the same calls as :class:`~frictionjoint.fmi.master.FMUInstance`.

Why a separate process: pythonfmu FMUs (0.7) cannot be instantiated twice in one process
(NTNU-IHB/PythonFMU #213, #228), and after many ``fmi2Reset`` calls the host's cyclic garbage
collector can meet a Python object that pythonfmu's C++ wrapper has left inconsistent and
crash the host (segmentation fault while "Garbage-collecting"; seen in about half of the runs
of 2-6 consecutive 12-point sweeps in one process, never with the collector disabled). A
worker owns one instance, runs with the cyclic collector off (the leaked cycles are freed
when it exits, with ``os._exit``, skipping the final collection) and dies with its sweep, so
the caller's process never loads the FMU's binary and may sweep as often as it likes.

Protocol: length-prefixed pickles over the worker's stdin/stdout; the worker's stderr is the
caller's. Start with ``python -m frictionjoint.fmi.worker FMU_PATH``.
"""
from __future__ import annotations

import os
import pickle
import struct
import subprocess
import sys

__all__ = ["FMUWorker", "FMUWorkerError"]

_HEADER = struct.Struct("!Q")


class FMUWorkerError(RuntimeError):
    """An FMU call failed in the worker (the FMU's log messages are in the text)."""


def _send(stream, obj) -> None:
    data = pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)
    stream.write(_HEADER.pack(len(data)) + data)
    stream.flush()


def _recv(stream):
    head = stream.read(_HEADER.size)
    if len(head) < _HEADER.size:
        raise EOFError
    (size,) = _HEADER.unpack(head)
    data = stream.read(size)
    if len(data) < size:
        raise EOFError
    return pickle.loads(data)


class FMUWorker:
    """One FMU instance in its own process (see the module docstring).

    Parameters
    ----------
    path : path
        The ``.fmu`` file.

    Attributes
    ----------
    vr : dict
        Variable name -> value reference.
    messages : list of str
        The FMU's log messages of the last call that failed.
    """

    def __init__(self, path):
        env = dict(os.environ)
        # the worker must import this very package (also from a source checkout)
        root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
        env["PYTHONPATH"] = root + (os.pathsep + env["PYTHONPATH"] if env.get("PYTHONPATH") else "")
        self._proc = subprocess.Popen([sys.executable, "-m", "frictionjoint.fmi.worker", str(path)],
                                      stdin=subprocess.PIPE, stdout=subprocess.PIPE, env=env)
        self.messages: list[str] = []
        self.time = 0.0
        try:
            self.vr, self.types = self._reply()
        except FMUWorkerError:
            self._shutdown()
            raise

    def _reply(self):
        try:
            ok, result = _recv(self._proc.stdout)
        except (EOFError, OSError):
            code = self._proc.wait()
            raise FMUWorkerError(f"the FMU worker process ended unexpectedly (exit status {code})") from None
        if not ok:
            text, self.messages = result
            raise FMUWorkerError(text)
        return result

    def _call(self, name, *args):
        try:
            _send(self._proc.stdin, (name, args))
        except (BrokenPipeError, OSError):
            code = self._proc.wait()
            raise FMUWorkerError(f"the FMU worker process ended unexpectedly (exit status {code})") from None
        return self._reply()

    def initialize(self, parameters: dict | None = None, start_time: float = 0.0) -> None:
        """(Re)initialise with parameter values at ``start_time`` [s]."""
        self.time = self._call("initialize", parameters, start_time)

    def set(self, values: dict) -> None:
        """Set variables by name."""
        self._call("set", values)

    def get(self, names) -> list:
        """Values of variables by name."""
        return self._call("get", list(names))

    def step_to(self, t_end: float) -> None:
        """One communication step to ``t_end`` [s]."""
        self.time = self._call("step_to", t_end)

    def get_state(self):
        """Serialised FMU state and the time."""
        return self._call("get_state")

    def set_state(self, saved) -> None:
        """Restore a state from :meth:`get_state`."""
        self.time = self._call("set_state", saved)

    def close(self) -> None:
        """Terminate and free the instance; end the worker."""
        if self._proc.poll() is None:
            try:
                self._call("close")
            except FMUWorkerError:
                pass
        self._shutdown()

    def _shutdown(self) -> None:
        for stream in (self._proc.stdin, self._proc.stdout):
            try:
                stream.close()
            except OSError:
                pass
        try:
            self._proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self._proc.kill()
            self._proc.wait()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _serve(path: str) -> None:
    """The worker's loop: one FMUInstance, commands from stdin, replies on stdout."""
    import gc

    gc.disable()  # see the module docstring
    stdin, stdout = sys.stdin.buffer, sys.stdout.buffer
    sys.stdout = sys.stderr  # stray prints must not corrupt the protocol
    from .master import FMUInstance

    try:
        inst = FMUInstance(path)
    except Exception as exc:  # noqa: BLE001 -- reported to the caller
        _send(stdout, (False, (f"cannot instantiate {path}: {exc}", [])))
        return
    _send(stdout, (True, (inst.vr, inst.types)))
    while True:
        try:
            name, args = _recv(stdin)
        except EOFError:
            break
        try:
            if name == "close":
                inst.close()
                _send(stdout, (True, None))
                break
            result = getattr(inst, name)(*args)
            if name in ("initialize", "step_to", "set_state"):
                result = inst.time
            _send(stdout, (True, result))
        except Exception as exc:  # noqa: BLE001 -- reported to the caller with the FMU's log
            messages = list(inst.messages)
            detail = "; ".join(m for m in messages if m) or "no message logged"
            _send(stdout, (False, (f"{name} failed: {exc} (FMU log: {detail})", messages)))
        inst.messages.clear()


if __name__ == "__main__":
    _serve(sys.argv[1])
    sys.stdout.flush()
    os._exit(0)
