"""FMI 3.0 co-simulation binding of the slaves (pythonfmu3), with early return at stick/slip events.

An FMI 3 slave here is a thin binding: it owns one FMI 2 slave of :mod:`.slaves` (its declarations,
validation, physics, FMU state, refusals) and maps the FMI 3 calls onto it; nothing of the model is
written twice. What FMI 3 adds:

- **Early return.** Where the host allows it (``earlyReturnAllowed`` of ``fmi3InstantiateCoSimulation``),
  ``do_step`` stops just after the first stick/slip event inside the step and returns ``earlyReturn =
  true`` with ``lastSuccessfulTime`` the event's instant; the state there is the event's, after its
  rules. The oscillator stops at each event of its exact march
  (:meth:`~frictionjoint.stepping.OscillatorRun.advance` with ``stop_at_event``): the instants are the
  library's; so does a whole friction system (:meth:`~frictionjoint.fmi.system_slave.SystemRun.advance`
  with ``stop_at_event``: the event-driven marcher's ``max_events``). A displacement-driven joint holds
  its inputs over a step, ``u`` and its rate ``velocity``, so ``u`` moves as ``u + velocity tau`` inside
  it: it stops where the nearest slider that sticks reaches its slip force
  (``_DrivenSlave._stop_at_slip``) and stands there (``u`` is then that point); a slipping slider sticks only where the velocity reverses, at a step's start.
  Without the host's permission a step is whole, as the FMI 2 FMU's (the same numbers).
- **Event mode.** Where the host uses it (``eventModeUsed``), an early return also asks for event
  handling (``eventHandlingNeeded``); the event was handled inside ``do_step``, so
  ``update_discrete_states`` has nothing left to do.
- ``time``, the independent variable FMI 3 requires (value reference 0; the slave's variables follow
  in the FMI 2 FMU's order, each one value reference further).

pythonfmu3 0.3.4's binary passes neither flag to the slave and drops ``earlyReturn`` and
``lastSuccessfulTime`` from ``do_step``'s result: early return needs its wrapper with
``fmi3_wrapper/early_return.patch``, which sets the attributes ``early_return_allowed`` and
``event_mode_used`` on the slave (:mod:`frictionjoint.fmi.build` puts the patched x86_64-linux binary
into the FMU). Under the stock binary the attributes keep their class defaults (False): whole steps.
Both binaries release the slave class, instance and log queue after a Python exception, which the
destructor releases again; the wrapper-called methods lend those references
(:func:`~frictionjoint.fmi.wrapper._lending_references`), as the FMI 2 slaves do.
"""
from __future__ import annotations

import functools
from collections import OrderedDict
from types import SimpleNamespace
from typing import NamedTuple

from pythonfmu3 import (Boolean, Fmi3Causality, Fmi3Initial, Fmi3Slave, Fmi3Status, Fmi3Variability, Float64,
                        Int32)
from pythonfmu3.modelexchange import ModelExchange

from . import model_exchange, slaves, system_slave
from .wrapper import _lending_references

__all__ = ["CoulombOscillatorSlave3", "JenkinsJointSlave3", "IwanJointSlave3", "MicroslipJointSlave3",
           "SystemSlave3", "StepResult", "CoulombOscillatorSlaveME3", "JenkinsJointSlaveME3", "IwanJointSlaveME3",
           "MicroslipJointSlaveME3", "LinearStructureSlaveME3", "SystemSlaveME3"]

_TYPES = {float: Float64, int: Int32, bool: Boolean}
#: the methods pythonfmu3's wrapper calls on the instance (their exceptions lend references)
WRAPPER_CALLS3 = ("setup_experiment", "enter_initialization_mode", "exit_initialization_mode", "do_step",
                  "terminate", "update_discrete_states", "get_float64", "get_int32", "get_boolean",
                  "set_float64", "set_int32", "set_boolean", "_get_fmu_state", "_set_fmu_state",
                  # Model Exchange (_SlaveME3)
                  "get_continuous_states", "set_continuous_states", "get_continuous_state_derivatives",
                  "get_event_indicators", "get_nominals_of_continuous_states", "set_time",
                  "get_number_of_continuous_states", "get_number_of_event_indicators")
#: (binding class, FMI 2 declarations) -> pythonfmu3 variables, built once (see _Slave3.vars)
_VARIABLES3: dict = {}


class StepResult(NamedTuple):
    """What ``do_step`` returns to the (patched) wrapper."""

    status: Fmi3Status = Fmi3Status.ok
    eventHandlingNeeded: bool = False
    terminateSimulation: bool = False
    earlyReturn: bool = False
    lastSuccessfulTime: float = 0.0


def _lend(cls):
    """Wrap the wrapper-called methods that ``cls`` itself defines (:data:`WRAPPER_CALLS3`; inherited
    ones are wrapped where they are defined) so that their exceptions lend the references
    pythonfmu3's wrapper then releases (:func:`~frictionjoint.fmi.wrapper._lending_references`)."""
    for name in WRAPPER_CALLS3:
        method = cls.__dict__.get(name)
        if method is not None and not getattr(method, "_lends_references", False):
            setattr(cls, name, _lending_references(method))
    return cls


@_lend
class _Slave3(Fmi3Slave):
    """FMI 3 binding of the FMI 2 slave class :attr:`_binds` (see the module docstring)."""

    #: the :mod:`.slaves` class whose instance does the work
    _binds = slaves._Slave
    #: the host's flags, set on the instance by the patched wrapper (absent under the stock binary)
    early_return_allowed = False
    event_mode_used = False

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        _lend(cls)

    def __init__(self, **kwargs):
        self._inner = None
        super().__init__(**kwargs)
        inner = self._binds(**kwargs)
        inner.log = self._log2  # its refusals reach this FMU's log queue
        self._inner = inner
        self.author = self._binds.author  # (pythonfmu's base sets the instance's to None)
        self.description = self._binds.description + "; FMI 3: early return at each stick/slip event"
        self.time = 0.0

    def _log2(self, msg, status=Fmi3Status.ok, category=None):
        self.log(msg, Fmi3Status(int(status)), category)

    def to_xml(self, model_options=None):
        """pythonfmu3's model description with each output's ``dependencies``: the value references
        of the inputs it depends on directly (the bound slave's :meth:`~.slaves._Slave.dependencies`;
        empty: none)."""
        root = super().to_xml(model_options or {})
        declared = self._inner._declared
        vr = {d.name: i for i, d in enumerate(declared, start=1)}
        deps = self._inner.dependencies()
        for output in root.iterfind("ModelStructure/Output"):
            name = declared[int(output.get("valueReference")) - 1].name
            output.set("dependencies", " ".join(str(vr[i]) for i in deps[name]))
        return root

    @property
    def vars(self):
        """pythonfmu3's ``value reference -> variable`` map: ``time``, then the bound slave's
        declarations; built once per class and declaration list."""
        declared = tuple(self._inner._declared)
        key = (type(self), declared)
        table = _VARIABLES3.get(key)
        if table is None:
            table = OrderedDict()
            var = Float64("time", causality=Fmi3Causality.independent, variability=Fmi3Variability.continuous,
                          description="simulation time [s]")
            var.value_reference, table[0] = 0, var
            index = {d.name: vr for vr, d in enumerate(declared, start=1)}
            for vr, d in enumerate(declared, start=1):
                extra = {} if d.derivative is None else {"derivative": index[d.derivative]}
                var = _TYPES[d.kind](d.name, causality=Fmi3Causality[d.causality.name],
                                     variability=Fmi3Variability[d.variability.name], description=d.description,
                                     **d.start_args(Fmi3Initial.exact), **extra)
                var.value_reference, table[vr] = vr, var
            _VARIABLES3[key] = table
        return table

    # Fmi3SlaveBase.__init__ assigns an empty map, as Fmi2Slave's does: the FMI 2 slave's setter
    vars = vars.setter(slaves._Slave.vars.fset)

    # -- values: value reference 0 is time, vr n the bound slave's n - 1 -----------------------------
    def get_float64(self, vrs):
        return [self.time if vr == 0 else self._inner._get_values([vr - 1], float)[0] for vr in vrs]

    def get_int32(self, vrs):
        return self._inner._get_values([vr - 1 for vr in vrs], int)

    def get_boolean(self, vrs):
        return self._inner._get_values([vr - 1 for vr in vrs], bool)

    def set_float64(self, vrs, values):
        self._inner._set_values([vr - 1 for vr in vrs], values, float)

    def set_int32(self, vrs, values):
        self._inner._set_values([vr - 1 for vr in vrs], values, int)

    def set_boolean(self, vrs, values):
        self._inner._set_values([vr - 1 for vr in vrs], values, bool)

    # -- FMI calls: the bound slave's, without its FMI 2 wrapper's reference lending ----------------
    def _plain(self, name):
        method = getattr(type(self._inner), name)
        return functools.partial(getattr(method, "__wrapped__", method), self._inner)

    def setup_experiment(self, start_time):
        self.time = float(start_time)
        self._plain("setup_experiment")(start_time)

    def enter_initialization_mode(self):
        self._plain("enter_initialization_mode")()

    def exit_initialization_mode(self):
        self._plain("exit_initialization_mode")()

    def terminate(self):
        self._plain("terminate")()

    def do_step(self, current_time, step_size):
        inner = self._inner
        inner.stop_at_event = bool(self.early_return_allowed)
        if not self._plain("do_step")(current_time, step_size):  # refused (logged): the state is the start's
            return StepResult(Fmi3Status.discard, lastSuccessfulTime=current_time)
        if inner.early_stop is None:
            self.time = current_time + step_size
            return StepResult(lastSuccessfulTime=self.time)
        self.time = inner.early_stop
        return StepResult(earlyReturn=True, eventHandlingNeeded=bool(self.event_mode_used),
                          lastSuccessfulTime=self.time)

    def update_discrete_states(self):
        # the event's rules were applied inside do_step: nothing is left for event mode
        return SimpleNamespace(discreteStatesNeedUpdate=False, terminateSimulation=False,
                               nominalContinuousStatesChanged=False, valuesOfContinuousStatesChanged=False,
                               nextEventTimeDefined=False, nextEventTime=0.0)

    def _get_fmu_state(self):
        state = self._plain("_get_fmu_state")()
        state["__time__"] = self.time
        return state

    def _set_fmu_state(self, state):
        self._plain("_set_fmu_state")(state)
        self.time = state.get("__time__", self.time)

    # called on the class by the wrapper: the FMI 2 slaves' (bad bytes -> a state _set_fmu_state rejects)
    _fmu_state_to_bytes = staticmethod(slaves._Slave._fmu_state_to_bytes)
    _fmu_state_from_bytes = staticmethod(slaves._Slave._fmu_state_from_bytes)


class CoulombOscillatorSlave3(_Slave3):
    """FMI 3 Coulomb oscillator (:class:`~frictionjoint.fmi.slaves.CoulombOscillatorSlave`)."""

    _binds = slaves.CoulombOscillatorSlave


class JenkinsJointSlave3(_Slave3):
    """FMI 3 Jenkins joint (:class:`~frictionjoint.fmi.slaves.JenkinsJointSlave`)."""

    _binds = slaves.JenkinsJointSlave


class IwanJointSlave3(_Slave3):
    """FMI 3 Iwan joint (:class:`~frictionjoint.fmi.slaves.IwanJointSlave`)."""

    _binds = slaves.IwanJointSlave


class MicroslipJointSlave3(_Slave3):
    """FMI 3 microslip joint (:class:`~frictionjoint.fmi.slaves.MicroslipJointSlave`)."""

    _binds = slaves.MicroslipJointSlave


class SystemSlave3(_Slave3):
    """FMI 3 friction system (:class:`~frictionjoint.fmi.system_slave.SystemSlave`: the system definition
    in the FMU's resources, its events exact inside ``do_step``; early return just after each)."""

    _binds = system_slave.SystemSlave


@_lend
class _SlaveME3(_Slave3, ModelExchange):
    """FMI 3 Model Exchange binding of a :mod:`.model_exchange` model (:attr:`_binds`; the FMI 2 FMUs are
    the model classes themselves, on the fixed FMI 2 wrapper): the host sets
    the time and the continuous states, reads their derivatives and the event indicators and, at an
    event it located, calls ``update_discrete_states`` (the model's rules there). The model
    description declares the ``ModelExchange`` interface only (:func:`~frictionjoint.fmi.build.postprocess3`
    drops the ``CoSimulation`` element pythonfmu3 writes for its base class)."""

    _binds = model_exchange.MEModel

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        inner = self._inner
        self.description = self._binds.description
        vr = {d.name: i for i, d in enumerate(inner._declared, start=1)}
        self.event_indicators = [vr[name] for name in inner.me_indicators]

    def set_time(self, time):
        self.time = float(time)
        self._inner.me_set_time(time)

    def get_number_of_continuous_states(self):
        return len(self._inner.me_states)

    def get_number_of_event_indicators(self):
        return len(self._inner.me_indicators)

    def get_continuous_states(self):
        return [float(v) for v in self._inner.me_get_states()] if self._inner._ready else [
            0.0] * len(self._inner.me_states)

    def set_continuous_states(self, values):
        self._inner.me_set_states(list(values))

    def get_continuous_state_derivatives(self):
        return [float(v) for v in self._inner.me_derivatives()]

    def get_event_indicators(self):
        return [float(v) for v in self._inner.me_event_indicators()]

    def get_nominals_of_continuous_states(self, size):
        return [float(v) for v in self._inner.me_nominals()][:size]

    def update_discrete_states(self):
        changed = self._inner.me_update()
        return SimpleNamespace(discreteStatesNeedUpdate=False, terminateSimulation=False,
                               nominalContinuousStatesChanged=False, valuesOfContinuousStatesChanged=bool(changed),
                               nextEventTimeDefined=False, nextEventTime=0.0)

    def do_step(self, current_time, step_size):
        return StepResult(Fmi3Status.error, lastSuccessfulTime=current_time)


class CoulombOscillatorSlaveME3(_SlaveME3):
    """FMI 3 Model Exchange Coulomb oscillator (:class:`~frictionjoint.fmi.model_exchange.CoulombOscillatorME`)."""

    _binds = model_exchange.CoulombOscillatorME


class JenkinsJointSlaveME3(_SlaveME3):
    """FMI 3 Model Exchange Jenkins joint (:class:`~frictionjoint.fmi.model_exchange.JenkinsJointME`)."""

    _binds = model_exchange.JenkinsJointME


class IwanJointSlaveME3(_SlaveME3):
    """FMI 3 Model Exchange Iwan joint (:class:`~frictionjoint.fmi.model_exchange.IwanJointME`)."""

    _binds = model_exchange.IwanJointME


class MicroslipJointSlaveME3(_SlaveME3):
    """FMI 3 Model Exchange microslip joint (:class:`~frictionjoint.fmi.model_exchange.MicroslipJointME`)."""

    _binds = model_exchange.MicroslipJointME


class LinearStructureSlaveME3(_SlaveME3):
    """FMI 3 Model Exchange linear structure (:class:`~frictionjoint.fmi.model_exchange.LinearStructureME`)."""

    _binds = model_exchange.LinearStructureME


class SystemSlaveME3(_SlaveME3):
    """FMI 3 Model Exchange friction system (:class:`~frictionjoint.fmi.model_exchange.SystemME`)."""

    _binds = model_exchange.SystemME
