"""A small fmpy master for one FMI 2.0 co-simulation FMU instance (reused across runs).

Every call into the FMU goes through fmpy, which turns a bad status into an exception; log
messages of the FMU (Python errors included: logging is on) are collected in :attr:`messages`.
pythonfmu FMUs cannot be instantiated twice in one process (NTNU-IHB/PythonFMU #213, #228):
reuse one :class:`FMUInstance` (``initialize`` may be called again: it resets the FMU), e.g.
through :meth:`FMUInstance.shared`, which keeps one live instance per model for the process.
"""
from __future__ import annotations

import atexit
import shutil
from pathlib import Path

__all__ = ["FMUInstance"]

#: guid -> live instance handed out by FMUInstance.shared (closed at exit)
_SHARED: dict = {}
#: guids of pythonfmu models instantiated in this process (they cannot be instantiated again)
_PYTHONFMU_GUIDS: set = set()


@atexit.register
def _close_shared() -> None:
    for inst in list(_SHARED.values()):
        inst._free()
    _SHARED.clear()


class FMUInstance:
    """One instantiated co-simulation FMU.

    Parameters
    ----------
    path : path
        The ``.fmu`` file.
    """

    def __init__(self, path):
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave, fmi2CallbackLoggerTYPE, fmi2CallbackFunctions
        from fmpy import fmi2

        self.path = Path(path)
        self.model = read_model_description(str(self.path))
        self._pythonfmu = (self.model.generationTool or "").startswith("PythonFMU")
        if self._pythonfmu and self.model.guid in _PYTHONFMU_GUIDS:
            raise RuntimeError(
                f"{self.path.name} (pythonfmu) was already instantiated in this process and cannot be "
                "instantiated again (NTNU-IHB/PythonFMU #213, #228): reuse one instance, e.g. "
                "FMUInstance.shared(path), or run each instance in its own process")
        self.vr = {v.name: v.valueReference for v in self.model.modelVariables}
        self.types = {v.name: v.type for v in self.model.modelVariables}
        self.messages: list[str] = []
        self._dir = extract(str(self.path))
        self._fmu = FMU2Slave(guid=self.model.guid, unzipDirectory=self._dir,
                              modelIdentifier=self.model.coSimulation.modelIdentifier, instanceName="fj")

        def log(component, instance, status, category, message):
            text = [b.decode(errors="replace") if b else "" for b in (category, message)]
            self.messages.append(f"[{status}] {text[0]}: {text[1]}")

        self._logger = fmi2CallbackLoggerTYPE(log)
        cb = fmi2CallbackFunctions()
        cb.logger = self._logger
        cb.allocateMemory = fmi2.defaultCallbacks.allocateMemory
        cb.freeMemory = fmi2.defaultCallbacks.freeMemory
        self._callbacks = cb
        self._fmu.instantiate(loggingOn=True, callbacks=cb)
        if self._pythonfmu:
            _PYTHONFMU_GUIDS.add(self.model.guid)
        self._initialized = self._used = False
        self._freed = False
        self._shared = False
        self.time = 0.0

    @classmethod
    def shared(cls, path) -> "FMUInstance":
        """The process's live instance of the model in ``path`` (created on first use).

        Instances are keyed by the model's guid; :meth:`close` on a shared instance only
        terminates the run, and the instance is freed at interpreter exit. Messages collected
        so far are cleared.
        """
        from fmpy import read_model_description

        guid = read_model_description(str(path)).guid
        inst = _SHARED.get(guid)
        if inst is None:
            inst = _SHARED[guid] = cls(path)
            inst._shared = True
        inst.messages.clear()
        return inst

    # ---------------------------------------------------------------- set-up
    def initialize(self, parameters: dict | None = None, start_time: float = 0.0) -> None:
        """(Re)initialise with parameter values at ``start_time`` [s]."""
        if self._used:  # initialised (and possibly terminated) before: back to 'instantiated'
            self._fmu.reset()
        self._used = True  # also after a failed initialisation (the FMU is then in error state)
        self._initialized = False
        self._fmu.setupExperiment(startTime=start_time)
        self._fmu.enterInitializationMode()
        if parameters:
            self.set(parameters)
        self._fmu.exitInitializationMode()
        self._initialized = self._used = True
        self.time = float(start_time)
        self._t0 = float(start_time)
        self._n = 0
        self._h = None

    def set(self, values: dict) -> None:
        """Set variables by name (Real, Integer or Boolean)."""
        for name, value in values.items():
            if name not in self.vr:
                raise KeyError(f"{self.path.name} has no variable {name!r}")
            t = self.types[name]
            if t == "Real":
                self._fmu.setReal([self.vr[name]], [float(value)])
            elif t == "Integer":
                self._fmu.setInteger([self.vr[name]], [int(value)])
            elif t == "Boolean":
                self._fmu.setBoolean([self.vr[name]], [bool(value)])
            else:
                raise TypeError(f"unsupported type {t} of {name}")

    def get(self, names) -> list:
        """Values of variables by name."""
        out = []
        for name in names:
            t = self.types[name]
            vr = [self.vr[name]]
            if t == "Real":
                out.append(self._fmu.getReal(vr)[0])
            elif t == "Integer":
                out.append(self._fmu.getInteger(vr)[0])
            else:
                out.append(bool(self._fmu.getBoolean(vr)[0]))
        return out

    # ---------------------------------------------------------------- stepping
    def step(self, h: float) -> None:
        """One communication step of length ``h`` [s] (points ``t0 + n h``, never ``t += h``)."""
        if self._h != h:
            self._t0, self._n, self._h = self.time, 0, h
        t = self._t0 + self._n * h
        self._fmu.doStep(currentCommunicationPoint=t, communicationStepSize=h)
        self._n += 1
        self.time = self._t0 + self._n * h

    def step_to(self, t_end: float) -> None:
        """One communication step to ``t_end`` [s] (events are handled inside the step)."""
        if t_end > self.time:
            self._fmu.doStep(currentCommunicationPoint=self.time, communicationStepSize=t_end - self.time)
            self.time = float(t_end)
            self._h = None

    # ---------------------------------------------------------------- state
    def get_state(self):
        """Serialised FMU state (bytes) and the master's time."""
        st = self._fmu.getFMUstate()
        data = self._fmu.serializeFMUstate(st)
        self._fmu.freeFMUstate(st)
        return bytes(data), self.time

    def set_state(self, saved) -> None:
        """Restore a state from :meth:`get_state`."""
        data, t = saved
        st = self._fmu.deSerializeFMUstate(data)
        self._fmu.setFMUstate(st)
        self._fmu.freeFMUstate(st)
        self.time = t
        self._h = None

    def close(self) -> None:
        """Terminate the run; free the instance and remove the extracted files (a shared
        instance stays alive for reuse until interpreter exit)."""
        if self._shared:
            if self._initialized:
                self._fmu.terminate()
                self._initialized = False
            return
        self._free()

    def _free(self) -> None:
        if self._freed:
            return
        self._freed = True
        try:
            if self._initialized:
                self._fmu.terminate()
            self._fmu.freeInstance()
        finally:
            shutil.rmtree(self._dir, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

