"""One FMI 2.0 co-simulation FMU instance driven through fmpy.

Every call into the FMU goes through :meth:`FMUInstance._call`, which turns a bad status into
:class:`~frictionjoint.errors.FMUError` carrying the FMU's log (logging is on, so Python errors
inside a pythonfmu FMU reach the message). Any number of instances of any FMU may live in one
process: the slaves balance the reference-counting defects of pythonfmu's native wrapper
(:mod:`frictionjoint.fmi.slaves`).
"""
from __future__ import annotations

import math
import shutil
from pathlib import Path

from ..errors import FMUError, check_bool, check_real, check_whole

__all__ = ["FMUInstance"]


class FMUInstance:
    """One instantiated co-simulation FMU.

    Parameters
    ----------
    path : path
        The ``.fmu`` file.
    name : str
        Instance name (FMI ``instanceName``).
    """

    def __init__(self, path, name: str = "fj"):
        from fmpy import extract, fmi2, read_model_description
        from fmpy.fmi2 import FMU2Slave

        self.path = Path(path)
        self.name = name
        try:
            self.model = read_model_description(str(self.path))
        except Exception as exc:  # noqa: BLE001 -- fmpy raises plain exceptions
            raise FMUError(f"cannot read the FMU {self.path}: {exc}") from exc
        self.vr = {v.name: v.valueReference for v in self.model.modelVariables}
        self.types = {v.name: v.type for v in self.model.modelVariables}
        self.messages: list[str] = []
        self._dir = extract(str(self.path))
        self._fmu = FMU2Slave(guid=self.model.guid, unzipDirectory=self._dir,
                              modelIdentifier=self.model.coSimulation.modelIdentifier, instanceName=name)

        def log(component, instance, status, category, message):
            text = [b.decode(errors="replace") if b else "" for b in (category, message)]
            self.messages.append(f"[{status}] {text[0]}: {text[1]}")

        self._logger = fmi2.fmi2CallbackLoggerTYPE(log)  # kept alive as long as the instance
        cb = fmi2.fmi2CallbackFunctions()
        cb.logger = self._logger
        cb.allocateMemory = fmi2.defaultCallbacks.allocateMemory
        cb.freeMemory = fmi2.defaultCallbacks.freeMemory
        self._callbacks = cb
        self._initialized = self._used = self._freed = False
        try:
            self._call("instantiate", loggingOn=True, callbacks=cb)
        except FMUError:
            self._freed = True
            shutil.rmtree(self._dir, ignore_errors=True)
            raise
        self.time = 0.0

    def _call(self, name: str, *args, **kwargs):
        """``self._fmu.<name>(...)``; a bad status raises :class:`FMUError` with the FMU's log."""
        try:
            return getattr(self._fmu, name)(*args, **kwargs)
        except Exception as exc:  # noqa: BLE001 -- fmpy raises plain exceptions for bad statuses
            detail = "; ".join(m for m in self.messages if m) or "no message logged"
            raise FMUError(f"{self.path.name} ({self.name}): {name} failed: {exc} (FMU log: {detail})") from exc

    # ---------------------------------------------------------------- set-up
    def initialize(self, parameters: dict | None = None, start_time: float = 0.0) -> None:
        """(Re)initialise with parameter values at ``start_time`` [s]."""
        self.messages.clear()
        if self._used:  # initialised (and possibly terminated) before: back to 'instantiated'
            self._call("reset")
        self._used = True  # also after a failed initialisation (the FMU is then in error state)
        self._initialized = False
        self._call("setupExperiment", startTime=start_time)
        self._call("enterInitializationMode")
        if parameters:
            self.set(parameters)
        self._call("exitInitializationMode")
        self._initialized = self._used = True
        self.time = float(start_time)
        self._t0 = float(start_time)
        self._n = 0
        self._h = None

    _SETTERS = {"Real": ("setReal", check_real), "Integer": ("setInteger", check_whole),
                "Boolean": ("setBoolean", check_bool)}
    _GETTERS = {"Real": ("getReal", float), "Integer": ("getInteger", int), "Boolean": ("getBoolean", bool)}

    def _by_type(self, names) -> dict:
        """``type -> [(position, name), ...]`` of variables (one FMI call per type, not per name)."""
        groups = {}
        for pos, name in enumerate(names):
            if name not in self.vr:
                raise KeyError(f"{self.path.name} has no variable {name!r}")
            t = self.types[name]
            if t not in self._SETTERS:
                raise TypeError(f"unsupported type {t} of {name}")
            groups.setdefault(t, []).append((pos, name))
        return groups

    def set(self, values: dict) -> None:
        """Set variables by name (Real, Integer or Boolean)."""
        names = list(values)
        for t, items in self._by_type(names).items():
            fun, conv = self._SETTERS[t]
            self._call(fun, [self.vr[n] for _, n in items], [conv(n, values[n]) for _, n in items])

    def convert(self, name: str, value):
        """``value`` as variable ``name``'s type: a Boolean from any way of writing a switch
        (:func:`~frictionjoint.errors.check_bool`), an Integer from a whole number, a Real from a
        finite real number -- never a silent ``bool(0.5)`` or ``int(5.5)``.

        Raises
        ------
        ParameterError
            Naming ``name`` when ``value`` is not of its type.
        """
        (t, items), = self._by_type([name]).items()
        return self._SETTERS[t][1](name, value)

    def get(self, names) -> list:
        """Values of variables by name."""
        names = list(names)
        out = [None] * len(names)
        for t, items in self._by_type(names).items():
            fun, conv = self._GETTERS[t]
            vals = self._call(fun, [self.vr[n] for _, n in items])
            for (pos, _), val in zip(items, vals):
                out[pos] = conv(val)
        return out

    def reader(self, names):
        """A function of no arguments returning the values of ``names`` (as :meth:`get`), for a
        master that reads the same variables many times: where all are Real, one FMI call into
        value-reference and value arrays made once."""
        names = list(names)
        groups = self._by_type(names)
        if list(groups) != ["Real"]:
            return lambda: self.get(names)
        from fmpy.fmi2 import fmi2Real, fmi2ValueReference

        n = len(names)
        vrs = (fmi2ValueReference * n)(*[self.vr[name] for name in names])
        values = (fmi2Real * n)()
        fmu = self._fmu

        def read():
            try:
                fmu.fmi2GetReal(fmu.component, vrs, n, values)
            except Exception:  # noqa: BLE001 -- the call again, through _call, for its message
                return self.get(names)
            return values[:]

        return read

    def writer(self, names):
        """A function setting ``names`` to a sequence of values (as :meth:`set`), for a master that
        sets the same variables many times: where all are Real, one FMI call from arrays made
        once (a value that is not a finite real number goes through :meth:`set`'s check)."""
        names = list(names)
        groups = self._by_type(names)
        if list(groups) != ["Real"]:
            return lambda values: self.set(dict(zip(names, values)))
        from fmpy.fmi2 import fmi2Real, fmi2ValueReference

        n = len(names)
        vrs = (fmi2ValueReference * n)(*[self.vr[name] for name in names])
        array = fmi2Real * n
        fmu = self._fmu

        def write(values):
            if not all(isinstance(v, float) and math.isfinite(v) for v in values):
                return self.set(dict(zip(names, values)))
            try:
                fmu.fmi2SetReal(fmu.component, vrs, n, array(*values))
            except Exception:  # noqa: BLE001 -- the call again, through _call, for its message
                self.set(dict(zip(names, values)))

        return write

    # ---------------------------------------------------------------- stepping
    def step(self, h: float) -> None:
        """One communication step of length ``h`` [s] (points ``t0 + n h``, never ``t += h``)."""
        if self._h != h:
            self._t0, self._n, self._h = self.time, 0, h
        t = self._t0 + self._n * h
        self._call("doStep", currentCommunicationPoint=t, communicationStepSize=h)
        self._n += 1
        self.time = self._t0 + self._n * h

    def step_to(self, t_end: float) -> None:
        """One communication step to ``t_end`` [s] (events are handled inside the step)."""
        if t_end > self.time:
            self._call("doStep", currentCommunicationPoint=self.time, communicationStepSize=t_end - self.time)
            self.time = float(t_end)
            self._h = None

    def step_between(self, t_start: float, t_end: float) -> None:
        """One communication step from ``t_start`` to ``t_end`` [s] (a master that cuts its steps at
        events: the FMU's time is the master's, whatever it was)."""
        self._call("doStep", currentCommunicationPoint=t_start, communicationStepSize=t_end - t_start)
        self.time = float(t_end)
        self._h = None

    # ---------------------------------------------------------------- state
    @property
    def can_save_state(self) -> bool:
        """Whether the FMU can get and set its state (``canGetAndSetFMUstate``)."""
        return bool(self.model.coSimulation.canGetAndSetFMUstate)

    def save(self):
        """The FMU's state in memory (an ``fmi2FMUstate``, not serialised; free it with
        :meth:`free`) and the master's time."""
        return self._call("getFMUstate"), self.time

    def restore(self, saved) -> None:
        """Restore a state from :meth:`save` (it stays valid: restore it again or :meth:`free` it)."""
        st, t = saved
        self._call("setFMUstate", st)
        self.time = t
        self._h = None

    def free(self, saved) -> None:
        """Release a state from :meth:`save`."""
        self._call("freeFMUstate", saved[0])

    def get_state(self):
        """Serialised FMU state (bytes) and the master's time."""
        st = self._call("getFMUstate")
        data = self._call("serializeFMUstate", st)
        self._call("freeFMUstate", st)
        return bytes(data), self.time

    def set_state(self, saved) -> None:
        """Restore a state from :meth:`get_state`."""
        data, t = saved
        st = self._call("deSerializeFMUstate", data)
        try:
            self._call("setFMUstate", st)
        finally:
            self._call("freeFMUstate", st)
        self.time = t
        self._h = None

    def close(self) -> None:
        """Terminate the run, free the instance and remove the extracted files."""
        if self._freed:
            return
        self._freed = True
        try:
            if self._initialized:
                self._call("terminate")
        finally:
            self._fmu.freeInstance()
            shutil.rmtree(self._dir, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

