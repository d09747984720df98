"""A small fmpy master for one FMI 2.0 co-simulation FMU instance (reused across runs).

Every call into the FMU goes through fmpy, which turns a bad status into an exception; log
messages of the FMU (Python errors included: logging is on) are collected in :attr:`messages`.
pythonfmu FMUs cannot be instantiated twice in one process (NTNU-IHB/PythonFMU #213, #228):
reuse one :class:`FMUInstance` (``initialize`` may be called again: it resets the FMU).
"""
from __future__ import annotations

import shutil
from pathlib import Path

__all__ = ["FMUInstance"]


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
        self._initialized = False
        self.time = 0.0

    # ---------------------------------------------------------------- set-up
    def initialize(self, parameters: dict | None = None, start_time: float = 0.0) -> None:
        """(Re)initialise with parameter values at ``start_time`` [s]."""
        if self._initialized:
            self._fmu.reset()
        self._fmu.setupExperiment(startTime=start_time)
        self._fmu.enterInitializationMode()
        if parameters:
            self.set(parameters)
        self._fmu.exitInitializationMode()
        self._initialized = True
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
        """Terminate and free the instance; remove the extracted files."""
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

