"""A system of Model Exchange FMUs (FMI 2.0 or 3.0) integrated together, with state events located from the
FMUs' event indicators: this library's Model Exchange master.

:class:`ModelExchangeSystem` loads each component (fmpy's ``FMU2Model`` or ``FMU3Model``), stacks their continuous
states into one vector and integrates it with one of SciPy's explicit Runge-Kutta steppers
(:class:`scipy.integrate.DOP853` by default) at the tolerances given. At every evaluation it sets
each component's time and states, transfers the connections in the order of the model
descriptions' output dependencies (an output that depends on no input first: a structure's ``x``
and ``v`` before a joint's force) and reads the derivatives. After every accepted step it reads
the event indicators: where one has changed sign since the last event (an indicator that is
exactly zero has no sign yet), the earliest such instant inside the step is found on the step's
dense output (:func:`scipy.optimize.brentq` to the rounding of ``t``, then the first representable
time past which the sign has changed), the components enter event mode there
(``updateDiscreteStates`` until none needs more), the states are read back (an FMU may reset
them: the oscillator's velocity at a stop) and the integration restarts from that instant. This
is what a Model Exchange host (Dymola, OpenModelica, fmpy's CVode loop) does; the outputs are
recorded at the communication points ``t0 + n h`` from the dense output.

The error against the exact solution of the same model is the integrator's: ``docs/cosimulation.md``
(Model Exchange) gives it against ``rtol`` for the README's chain.
"""
from __future__ import annotations

import ctypes
import math
import shutil
import tempfile
from dataclasses import dataclass, field
from typing import Sequence

import numpy as np

from ..errors import FMUError, ParameterError, check_positive, check_real
from ..results import CoSimulationResult
from ..threads import owns_blas_threads
from .ports import checked_components, checked_connections, checked_parameters, split_port

__all__ = ["ModelExchangeSystem", "METHODS", "AMPLITUDE_FLOOR", "MAX_EVENTS"]

#: SciPy steppers this master takes (the explicit ones have a dense output of their order)
METHODS = ("DOP853", "RK45", "Radau", "BDF", "LSODA")
_DOUBLE_P = ctypes.POINTER(ctypes.c_double)
#: the default absolute tolerance of a state is ``rtol`` times the largest magnitude it has had, and at
#: least this fraction of its nominal value (a run from rest has no amplitude yet)
AMPLITUDE_FLOOR = 1e-3
#: the most events one run locates (a chattering indicator is refused instead of looping)
MAX_EVENTS = 1_000_000


@dataclass
class ModelExchangeSystem:
    """Model Exchange FMUs (FMI 2.0 or 3.0), their parameter values and the connections between them.

    Parameters
    ----------
    components : dict
        Component name -> ``.fmu`` path of an FMI 2.0 or 3.0 FMU with a ``ModelExchange`` interface
        (``frictionjoint build-fmus --interface me``). Several components may use the same FMU.
    connections : sequence of (str, str)
        ``("source.output", "target.input")`` pairs; transferred in the order of the outputs'
        dependencies (an algebraic loop is refused).
    parameters : dict, optional
        Component name -> {parameter name: value}.
    """

    components: dict
    connections: Sequence = ()
    parameters: dict = field(default_factory=dict)

    def __post_init__(self):
        from fmpy import read_model_description

        components = checked_components(self.components)
        self._md = {}
        for name, path in components.items():
            md = read_model_description(str(path))
            if md.modelExchange is None or not str(md.fmiVersion).startswith(("2.", "3.")):
                raise ParameterError(f"components[{name!r}]: {path.name} is not an FMI 2.0 or 3.0 Model Exchange "
                                     "FMU (build one with build-fmus --interface me)")
            if md.modelExchange.needsCompletedIntegratorStep:
                raise ParameterError(f"components[{name!r}]: {path.name} needs completedIntegratorStep after every "
                                     "step, which this master does not call")
            self._md[name] = md
        self.components = components
        self._vars = {c: {v.name: v for v in md.modelVariables} for c, md in self._md.items()}
        pairs = checked_connections(self.connections, self._vars)
        self.connections = [(f"{s[0]}.{s[1]}", f"{t[0]}.{t[1]}") for s, t in pairs]
        self._order = self._sorted(pairs)
        self.parameters = checked_parameters(self.parameters, self._vars, ("parameter", "input"))

    def _sorted(self, pairs) -> list:
        """The connections in an order in which each source output is read after every connection
        into the inputs it depends on (the model descriptions' ``dependencies``; none declared:
        all of the component's inputs)."""
        deps = {}
        for comp, md in self._md.items():
            inputs = [v for v in md.modelVariables if v.causality == "input"]
            for out in md.outputs:
                d = out.dependencies
                deps[(comp, out.variable.name)] = [(comp, v.name) for v in (inputs if d is None else d)]
        feeding = {t: s for s, t in pairs}
        order, state = [], {}

        def visit(pair, path):
            key = pair[1]
            if state.get(key) == "done":
                return
            if state.get(key) == "visiting":
                raise ParameterError(f"the connections form an algebraic loop through {' -> '.join(map('.'.join, path))}: "
                                     "a Model Exchange system needs an output without direct feedthrough in it")
            state[key] = "visiting"
            for needed in deps.get(pair[0], []):
                if needed in feeding:
                    visit((feeding[needed], needed), path + [needed])
            state[key] = "done"
            order.append(pair)

        for pair in pairs:
            visit(pair, [pair[1]])
        return order

    # -- a run ------------------------------------------------------------------------------------
    @owns_blas_threads
    def simulate(self, stop_time: float, step: float, outputs: Sequence[str], start_time: float = 0.0,
                 rtol: float = 1e-10, atol: float | None = None, method: str = "DOP853") -> CoSimulationResult:
        """Integrate the system from ``start_time`` to ``stop_time``, recording ``outputs`` every ``step``.

        Parameters
        ----------
        stop_time, step, start_time : float
            The run's end, the recording interval ``h`` and its start ``t0`` [s]; the outputs are
            recorded at ``t0 + n h <= stop_time`` (``step`` does not limit the integrator's steps).
        outputs : sequence of str
            ``"component.variable"`` names to record.
        rtol : float
            Relative tolerance of the integrator, in [1e-13, 1e-2].
        atol : float, optional
            Absolute tolerance of every state. By default each state's is ``rtol`` times the largest
            magnitude it has had (the integration restarts with the new tolerance at every event and
            where a state's magnitude has doubled), at least :data:`AMPLITUDE_FLOOR` times its
            nominal value (the FMUs'): so that ``rtol`` is relative to each state's amplitude, also
            where it passes through zero and for a DOF that moves a hundredth of another.
        method : str
            One of :data:`METHODS` (:func:`scipy.integrate.solve_ivp`'s steppers).

        Returns
        -------
        CoSimulationResult
            Its ``host`` names the method and the number of events located.
        """
        import scipy.integrate

        if method not in METHODS:
            raise ParameterError(f"method must be one of {METHODS}, got {method!r}")
        rtol = check_real("rtol", rtol)
        if not 1e-13 <= rtol <= 1e-2:
            raise ParameterError(f"rtol must be in [1e-13, 1e-2], got {rtol!r}")
        h = check_positive("step", step)
        t0, t_end = check_real("start_time", start_time), check_real("stop_time", stop_time)
        if not t_end > t0:
            raise ParameterError(f"stop_time must be > start_time = {t0!r}, got {t_end!r}")
        n_points = int(math.floor((t_end - t0) / h * (1 + 4 * np.finfo(float).eps))) + 1
        if n_points > 10_000_000 or t0 + h == t0:
            raise ParameterError(f"step {h!r} s gives {n_points} points from {t0!r} to {t_end!r} s; at most 1e7 "
                                 "and above the rounding of the times")
        from fmpy.fmi1 import FMICallException

        reads = [self._port(name) for name in outputs]
        times = t0 + h * np.arange(n_points)
        messages = []
        run = None
        try:
            run = _Run(self, t0, messages)
            record = run.integrate(getattr(scipy.integrate, method), times, reads, rtol, atol)
        except FMICallException as exc:  # the FMU's reason is in its log
            raise FMUError(f"{exc}: " + " | ".join(messages[-5:] or ["(no message)"])) from None
        finally:
            if run is not None:
                run.close()
        return CoSimulationResult(t=times, values=dict(zip(outputs, record.T)), step=h,
                                  host=f"frictionjoint Model Exchange master ({method}, rtol={rtol:g}), "
                                       f"{run.events} events located")

    def _port(self, name: str):
        comp, var = split_port(name)
        v = self._vars.get(comp, {}).get(var)
        if v is None:
            raise ParameterError(f"no variable {name!r}")
        return comp, v


def _instantiate(md, folder, name, log):
    """An fmpy Model Exchange instance of the FMU unpacked in ``folder`` (FMI 2.0 or 3.0), its log
    messages passed to ``log``."""
    if md.fmiVersion.startswith("2."):
        from ctypes import byref

        from fmpy import calloc, free
        from fmpy.fmi2 import (FMU2Model, fmi2CallbackAllocateMemoryTYPE, fmi2CallbackFreeMemoryTYPE,
                               fmi2CallbackFunctions, fmi2CallbackLoggerTYPE)
        from fmpy.logging import addLoggerProxy

        callbacks = fmi2CallbackFunctions()
        callbacks.logger = fmi2CallbackLoggerTYPE(lambda env, inst, status, category, message: log(message))
        callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        addLoggerProxy(byref(callbacks))  # (the variadic logger's message formatted)
        fmu = FMU2Model(guid=md.guid, unzipDirectory=folder, modelIdentifier=md.modelExchange.modelIdentifier,
                        instanceName=name)
        fmu.instantiate(callbacks=callbacks)
        fmu._frictionjoint_callbacks = callbacks  # (kept alive with the instance)
        return fmu
    from fmpy.fmi3 import FMU3Model

    fmu = FMU3Model(guid=md.instantiationToken, unzipDirectory=folder,
                    modelIdentifier=md.modelExchange.modelIdentifier, instanceName=name)
    fmu.instantiate(logMessage=lambda env, status, category, message: log(message))
    return fmu


class _Run:
    """One run: the loaded instances, the state layout, the evaluations and the event loop."""

    def __init__(self, system: ModelExchangeSystem, t0: float, messages: list):
        from fmpy import extract

        self.system, self.events = system, 0
        self._dirs, self.inst, self._v2 = [], {}, set()

        def log(text):  # the FMUs' messages, for the error a failed call raises
            messages.append(text.decode(errors="replace") if isinstance(text, bytes) else str(text))
            del messages[:-20]
        try:
            for comp, path in system.components.items():
                md = system._md[comp]
                folder = extract(str(path), unzipdir=tempfile.mkdtemp(prefix="frictionjoint_me_"))
                self._dirs.append(folder)
                self.inst[comp] = fmu = _instantiate(md, folder, comp, log)
                if md.fmiVersion.startswith("2."):
                    self._v2.add(comp)
                    fmu.setupExperiment(startTime=t0)
                for pname, value in system.parameters.get(comp, {}).items():
                    self._set(comp, system._vars[comp][pname], value)
                if comp in self._v2:
                    fmu.enterInitializationMode()
                else:
                    fmu.enterInitializationMode(startTime=t0)
            self.sizes = {c: self.system._md[c].numberOfContinuousStates for c in self.inst}
            self.n_ind = {c: self.system._md[c].numberOfEventIndicators for c in self.inst}
            self._transfer()  # each input from the initial outputs it is connected to
            for comp, fmu in self.inst.items():
                fmu.exitInitializationMode()
            self.t = t0
            self._event_mode(t0, initial=True)
        except Exception:
            self.close()
            raise

    # -- values ------------------------------------------------------------------------------------
    def _set(self, comp, var, value):
        fmu, v2 = self.inst[comp], comp in self._v2
        if var.type in ("Float64", "Real"):
            (fmu.setReal if v2 else fmu.setFloat64)([var.valueReference], [float(value)])
        elif var.type == "Boolean":
            fmu.setBoolean([var.valueReference], [bool(value)])
        else:
            if float(value) != int(value):
                raise ParameterError(f"{comp}.{var.name} is an integer, got {value!r}")
            (fmu.setInteger if v2 else fmu.setInt32)([var.valueReference], [int(value)])

    def _get(self, comp, var) -> float:
        fmu, v2 = self.inst[comp], comp in self._v2
        if var.type in ("Float64", "Real"):
            getter = fmu.getReal if v2 else fmu.getFloat64
        elif var.type == "Boolean":
            getter = fmu.getBoolean
        else:
            getter = fmu.getInteger if v2 else fmu.getInt32
        return float(getter([var.valueReference])[0])

    def _vector(self, which: str, sizes: dict) -> np.ndarray:
        """Every component's ``get<which>`` (continuous states, their derivatives or nominals, event
        indicators: ``sizes`` per component) stacked."""
        out = np.empty(sum(sizes.values()))
        i = 0
        for comp, n in sizes.items():
            if n:
                part = np.empty(n)
                name = "Derivatives" if which == "ContinuousStateDerivatives" and comp in self._v2 else which
                getattr(self.inst[comp], "get" + name)(part.ctypes.data_as(_DOUBLE_P), n)
                out[i:i + n] = part
            i += n
        return out

    def _states(self) -> np.ndarray:
        return self._vector("ContinuousStates", self.sizes)

    def _sync(self, t, y) -> None:
        """Set every component's time and states to ``(t, y)`` (Continuous-Time Mode) and transfer
        the connections."""
        i = 0
        for comp, n in self.sizes.items():
            fmu = self.inst[comp]
            fmu.setTime(float(t))
            if n:
                part = np.ascontiguousarray(y[i:i + n], dtype=float)
                fmu.setContinuousStates(part.ctypes.data_as(_DOUBLE_P), n)
            i += n
        self._transfer()

    def _transfer(self) -> None:
        """Every connection, in the order of the dependencies (each input from its source output)."""
        vars_ = self.system._vars
        for (sc, sv), (tc, tv) in self.system._order:
            self._set(tc, vars_[tc][tv], self._get(sc, vars_[sc][sv]))

    def derivatives(self, t, y) -> np.ndarray:
        self._sync(t, y)
        return self._vector("ContinuousStateDerivatives", self.sizes)

    def indicators(self, t, y) -> np.ndarray:
        self._sync(t, y)
        return self._vector("EventIndicators", self.n_ind)

    # -- events ---------------------------------------------------------------------------------------
    def _event_mode(self, t, initial=False) -> None:
        """Event Mode at ``t`` (after initialisation: its event iteration): every component updates
        its discrete states, the connections are transferred (inputs only: states are not set in
        Event Mode), and again while one needs more or has changed its states; then Continuous-Time
        Mode and the states read back. A time event (``nextEventTimeDefined``) is refused."""
        if not initial:
            for fmu in self.inst.values():
                fmu.enterEventMode()
        for _ in range(100):
            again = False
            for comp, fmu in self.inst.items():
                need, terminate, _, changed, timed, _ = (fmu.newDiscreteStates() if comp in self._v2
                                                         else fmu.updateDiscreteStates())
                if terminate:
                    raise FMUError(f"component {comp!r} asked to terminate the simulation at t = {t!r} s")
                if timed:
                    raise FMUError(f"component {comp!r} schedules a time event: this master locates state "
                                   "events only")
                again |= bool(need) or bool(changed)
            self._transfer()
            if not again:
                break
        else:
            raise FMUError(f"the discrete states did not settle at t = {t!r} s in 100 event iterations")
        for fmu in self.inst.values():
            fmu.enterContinuousTimeMode()
        self.y = self._states()
        self._sync(t, self.y)

    def integrate(self, stepper, times, reads, rtol, atol) -> np.ndarray:
        from scipy.optimize import brentq

        record = np.empty((times.size, len(reads)))
        t_end = float(times[-1])
        nominal = np.abs(self._vector("NominalsOfContinuousStates", self.sizes))
        if atol is not None:
            atol = check_positive("atol", atol)
        peak = np.zeros(self.y.size)
        k = 0
        k = self._record(record, times, k, self.t, lambda t: self.y, reads)
        sign = np.sign(self.indicators(self.t, self.y))
        while self.t < t_end:
            peak = np.maximum(peak, np.abs(self.y))
            scale = np.maximum(peak, AMPLITUDE_FLOOR * nominal)
            if self.y.size:
                solver = stepper(self.derivatives, self.t, self.y, t_end, rtol=rtol,
                                 atol=rtol * scale if atol is None else atol)
            else:  # no continuous state: the events come from the inputs' time dependence only
                solver = None
            t_old = self.t
            while True:
                if solver is None:
                    t_new, dense = t_end, (lambda t: self.y)
                else:
                    message = solver.step()
                    if solver.status == "failed":
                        raise FMUError(f"the integrator failed at t = {solver.t!r} s: {message}")
                    t_new, dense = solver.t, solver.dense_output()
                g = self.indicators(t_new, dense(t_new))
                crossed = np.flatnonzero((sign != 0) & (np.sign(g) != sign))
                if crossed.size:
                    t_ev = self._locate(brentq, dense, t_old, t_new, sign, crossed)
                    k = self._record(record, times, k, t_ev, dense, reads, inclusive=False)
                    self.t, self.y = t_ev, np.asarray(dense(t_ev), dtype=float)
                    self._sync(self.t, self.y)
                    self._event_mode(self.t)
                    self.events += 1
                    if self.events > MAX_EVENTS:
                        raise FMUError(f"more than {MAX_EVENTS} events by t = {self.t!r} s: the indicators chatter")
                    sign = np.sign(self.indicators(self.t, self.y))
                    break
                k = self._record(record, times, k, t_new, dense, reads)
                sign = np.where(sign == 0, np.sign(g), sign)
                t_old = t_new
                self.t, self.y = t_new, np.asarray(dense(t_new), dtype=float)
                if t_new >= t_end or (atol is None and np.any(np.abs(self.y) > 2 * scale)):
                    break  # (a state's amplitude has doubled: its tolerance with it)
        y_end = self.y
        k = self._record(record, times, k, t_end, lambda t: y_end, reads)  # (an event at t_end: the state after it)
        if k != times.size:
            raise FMUError(f"recorded {k} of {times.size} points: the run ended at t = {self.t!r} s")
        return record

    def _locate(self, brentq, dense, t_lo, t_hi, sign, crossed) -> float:
        """The earliest instant in ``(t_lo, t_hi]`` at which an indicator of ``crossed`` has left its
        sign: each one's root by Brent's method to the rounding of ``t``, then the first representable
        time at which its sign has changed (the event's rules need the state past it)."""
        def g(i, t):
            return self.indicators(t, dense(t))[i]

        first = t_hi
        for i in crossed:
            lo, hi = t_lo, first
            if np.sign(g(i, hi)) == sign[i]:
                continue
            if np.sign(g(i, lo)) != sign[i]:
                return lo
            root = brentq(lambda t: g(i, t) * sign[i], lo, hi, xtol=4 * np.finfo(float).eps * abs(hi), rtol=4 * np.finfo(float).eps)
            t = root
            for j in range(64):  # the first time past the root (in doubling rounding units) with the sign changed
                if np.sign(g(i, t)) != sign[i]:
                    break
                t = min(root + 2.0 ** j * np.finfo(float).eps * max(abs(root), np.finfo(float).tiny), hi)
            first = min(first, t)
        return first

    def _record(self, record, times, k, t_upto, dense, reads, inclusive=True) -> int:
        while k < times.size and (times[k] <= t_upto if inclusive else times[k] < t_upto):
            y = np.asarray(dense(times[k]), dtype=float)
            self._sync(times[k], y)
            record[k] = [self._get(c, v) for c, v in reads]
            k += 1
        return k

    def close(self) -> None:
        for fmu in self.inst.values():
            try:
                fmu.terminate()
            except Exception:  # noqa: BLE001 -- freeing after a failed run
                pass
            try:
                fmu.freeInstance()
            except Exception:  # noqa: BLE001
                pass
        self.inst = {}
        for folder in self._dirs:
            shutil.rmtree(folder, ignore_errors=True)
        self._dirs = []
