"""pythonfmu slaves: thin maps from FMI variables onto library objects.

Each FMU script in ``fmus/`` only names one of these classes. The physics is the library's:
:class:`~frictionjoint.oscillator.CoulombOscillator` marched exactly inside ``do_step`` (events
located inside the step, so outputs at a communication point do not depend on the communication
step), and :class:`~frictionjoint.elements.driven.DrivenSliders` for displacement-driven joints.
Inputs are held over a step (zero-order hold). The whole internal state is deep-copied for FMU
state get/set and pickled for serialisation.

Statuses under pythonfmu 0.7.0's wrapper (``PySlaveInstance.cpp``, ``fmi2.cpp``): a Python exception
in any call becomes ``fmi2Fatal`` (``handle_py_exception`` throws ``fatal_error``), and ``do_step``
returning False becomes ``fmi2Discard`` (lastSuccessfulTime = the step's start, the state
unchanged). A slave cannot return ``fmi2Error``. So a step the slave refuses (a negative or
non-finite step, a step after ``fmi2Terminate``, an invalid input, a step beyond the march's
budget) logs the reason at status error and returns False: ``fmi2Discard``, the instance stays
usable. An invalid parameter raises at ``fmi2ExitInitializationMode`` (``fmi2Fatal`` with the
message; :class:`~frictionjoint.fmi.wrapper.BalancedSlave` keeps the instance alive for a reset).
The wrapper forwards log messages to the host only with debug logging on (``loggingOn`` or
``fmi2SetDebugLogging``).

A step answers in bounded time: the runs (:class:`CoulombOscillatorSlave`,
:class:`BladeDovetailSlave`) march at most :attr:`_RunSlave.max_cycles` cycles of the excitation
and of the structure per step, event by event; beyond, the oscillator skips whole periods once its
motion has returned to its orbit (to the periodic tolerance, 1e-9 of the orbit, judged with the exact
monodromy; the state a whole number of periods later is then the same) and the blade refuses. A
march that gives up (its own event budget, a ConvergenceError) is a refused step from the step's
start. The driven joints' steps cost one update whatever their length; the linear structure's
step spans at most :attr:`LinearStructureSlave.max_cycles`.
"""
from __future__ import annotations

import copy
import json
import math
import operator
import os
import pickle
from collections import OrderedDict
from typing import NamedTuple, Optional

import numpy as np
from pythonfmu import Boolean, Fmi2Causality, Fmi2Initial, Fmi2Variability, Integer, Real
from pythonfmu.enums import Fmi2Status

# Everything the slaves use is imported here, not inside methods: every FMU in a process shares
# the bundle of the first one loaded, and a host may delete that FMU's unpacked folder while the
# others run (fmpy users, FMUInstance.close): a late import would then fail.
from ..contact import HalfPlaneContact, MindlinContact, RoundedFlatPunch
from ..elements.dovetail import FLANK_OUTPUTS, RESOLUTION, DovetailRoot
from ..elements.driven import DrivenSliders
from ..elements.iwan import MAX_SLIDERS, Iwan, check_n_sliders
from ..errors import ConvergenceError, ParameterError, check_positive
from ..solvers.marcher.held import HeldPortStructure
from ..stepping import OSCILLATOR_OUTPUTS, OSCILLATOR_PARAMETERS, OscillatorRun
from ..structure_file import StructureDefinition
from ..structures.blade_run import BladeRun, blade_outputs, blade_parameters
from ..structures.models import load_blade_model
from .wrapper import BalancedSlave

__all__ = ["CoulombOscillatorSlave", "JenkinsJointSlave", "IwanJointSlave", "MicroslipJointSlave",
           "DovetailRootSlave", "LinearStructureSlave", "BladeDovetailSlave", "STRUCTURE_RESOURCE",
           "BLADE_RESOURCE", "SOLID_BLADE_DESCRIPTION"]

#: file name of the structure definition in LinearStructure.fmu's resources
STRUCTURE_RESOURCE = "structure.json"
#: file name of the blade model definition in BladeDovetail.fmu's resources (and in every blade FMU's)
BLADE_RESOURCE = "blade_model.toml"
#: the model description's ``description`` of a blade FMU carrying a solid blade definition
#: (``[blade] kind = "solid"``; :func:`~frictionjoint.fmi.build.build_fmus` ``blades=``)
SOLID_BLADE_DESCRIPTION = ("Solid blade (27-node hexahedra, Craig-Bampton to its flank nodes, rotating) on a "
                           "dovetail root whose flanks are contact patches (a Jenkins slider and a normal spring per "
                           "node, static node loads from the spun-up contact solution), harmonic tip force; exact "
                           "event-driven stick/slip of every node (and lift-off with normal_load_variation) located "
                           "inside do_step")

_TYPES = {float: Real, int: Integer, bool: Boolean}
#: the range of an FMI 2.0 Integer (fmi2Integer is a C int)
_FMI_INTEGER_MAX = 2 ** 31 - 1


def _copy_state(value):
    """A copy of a slave's snapshot that shares nothing mutable with it: dicts, lists and tuples
    copied item by item, NumPy arrays copied, immutable scalars as they are, anything else by
    ``copy.deepcopy``. (A master saves and restores the FMU state at every step: deepcopy's memo
    and dispatch were a third of a Jenkins joint's get-state call.)"""
    if value is None or isinstance(value, (float, int, bool, str, np.generic)):
        return value
    if isinstance(value, np.ndarray):
        return value.copy()
    if type(value) is dict:
        return {k: _copy_state(v) for k, v in value.items()}
    if type(value) in (list, tuple):
        return type(value)(_copy_state(v) for v in value)
    return copy.deepcopy(value)


class _Declaration(NamedTuple):
    """One FMU variable as a slave declares it; ``method``/``args``: how an output is read
    (``getattr(slave, method)(*args)``), None for a parameter or input (the attribute ``name``)."""

    name: str
    kind: type
    causality: Fmi2Causality
    variability: Fmi2Variability
    description: str
    start: object = None
    method: Optional[str] = None
    args: tuple = ()
    #: a Model Exchange FMU's derivative variable: the name of the continuous state it derives
    derivative: Optional[str] = None

    def start_args(self, exact) -> dict:
        """Keyword arguments of its variable: a parameter carries ``initial`` = ``exact`` (the binding's
        Initial.exact) and a start, an input a start only, an output neither."""
        if self.causality in (Fmi2Causality.output, Fmi2Causality.local):
            return {}
        return dict(initial=exact, start=self.start) if self.causality is Fmi2Causality.parameter else dict(
            start=self.start)


#: (slave class, declarations) -> pythonfmu variables, built once (see _Slave.vars)
_VARIABLES: dict = {}


class _Slave(BalancedSlave):
    """Common declarations, validation at initialisation, pickled state (the defects of
    pythonfmu's native wrapper are balanced by :class:`~frictionjoint.fmi.wrapper.BalancedSlave`).

    pythonfmu's wrapper constructs the slave anew at every ``fmi2Reset`` (``PySlaveInstance.cpp``,
    ``Reset`` -> ``initialize``), so a host that resets per run (a sweep: one reset per frequency)
    pays the construction each time. pythonfmu's own declarations (``register_variable``: one
    variable object and two closures over the instance per variable) cost ~5 us per variable
    and make every instance a reference cycle; here a slave only records its declarations
    (:class:`_Declaration`) and sets their start values, the pythonfmu variables (for the model
    description) are built once per class and declaration list, and ``get_*``/``set_*`` read and
    write the attributes through the declarations.
    """

    author = "frictionjoint developers"
    description = ""
    #: the inputs every output depends on directly (its value changes when one is set, without a
    #: step): the model description's ``dependencies`` of each output (:meth:`dependencies`), which
    #: lets a host order the FMUs of a system (an output that depends on no input breaks a loop)
    direct_inputs: tuple = ()
    #: stop a step just after its first event (the FMI 3 binding, :mod:`.slaves3`, sets it where the host
    #: allows early return); :attr:`early_stop` is then the time it stopped at, None after a whole step
    stop_at_event = False

    def __init__(self, **kwargs):
        self._declared = []
        super().__init__(**kwargs)
        self.start_time = 0.0
        self._ready = False
        self._terminated = False
        self.early_stop = None

    # -- declarations ------------------------------------------------------
    def _parameter(self, name, start, description, kind=float):
        setattr(self, name, kind(start))
        self._declared.append(_Declaration(name, kind, Fmi2Causality.parameter, Fmi2Variability.fixed,
                                           description, kind(start)))

    def _input(self, name, start, description):
        setattr(self, name, float(start))
        self._declared.append(_Declaration(name, float, Fmi2Causality.input, Fmi2Variability.continuous,
                                           description, float(start)))

    def _output(self, name, description, kind=float, method="_out", args=None):
        """An output read as ``self.<method>(*args)`` (``args`` defaults to ``(name,)``)."""
        variability = Fmi2Variability.continuous if kind is float else Fmi2Variability.discrete
        self._declared.append(_Declaration(name, kind, Fmi2Causality.output, variability, description,
                                           method=method, args=(name,) if args is None else tuple(args)))

    def _local(self, name, description, method, args=(), derivative=None):
        """A local variable read as ``self.<method>(*args)`` (a Model Exchange FMU's state not among its
        outputs, a state's derivative, an event indicator; :mod:`.model_exchange`)."""
        self._declared.append(_Declaration(name, float, Fmi2Causality.local, Fmi2Variability.continuous,
                                           description, method=method, args=tuple(args), derivative=derivative))

    def dependencies(self) -> dict:
        """Output name -> the names of the inputs it depends on directly (:attr:`direct_inputs`)."""
        inputs = [d.name for d in self._declared if d.causality is Fmi2Causality.input]
        missing = set(self.direct_inputs) - set(inputs)
        if missing:
            raise ValueError(f"{type(self).__name__}.direct_inputs names no input: {sorted(missing)}")
        return {d.name: tuple(self.direct_inputs) for d in self._declared if d.causality is Fmi2Causality.output}

    def to_xml(self, model_options=None):
        """pythonfmu's model description with each output's ``dependencies`` (the indices of the
        inputs it depends on directly, :meth:`dependencies`; empty: none)."""
        root = super().to_xml(model_options or {})
        index = {d.name: i + 1 for i, d in enumerate(self._declared)}
        deps = self.dependencies()
        for unknown in root.iterfind("ModelStructure/Outputs/Unknown"):
            name = self._declared[int(unknown.get("index")) - 1].name
            unknown.set("dependencies", " ".join(str(index[i]) for i in deps[name]))
        return root

    @property
    def vars(self):
        """pythonfmu's ``value reference -> variable`` map (read when the model description is
        written), built once per class and declaration list."""
        key = (type(self), tuple(self._declared))
        table = _VARIABLES.get(key)
        if table is None:
            table = OrderedDict()
            for vr, d in enumerate(self._declared):
                var = _TYPES[d.kind](d.name, causality=d.causality, variability=d.variability,
                                     description=d.description, **d.start_args(Fmi2Initial.exact))
                var.value_reference = vr
                table[vr] = var
            _VARIABLES[key] = table
        return table

    @vars.setter
    def vars(self, value):
        # Fmi2Slave.__init__ assigns an empty map: the declarations are the variables
        if value:
            raise AttributeError("a frictionjoint slave declares its variables with _parameter/_input/_output")

    def _declaration(self, vr, kind):
        try:
            i = operator.index(vr)
        except TypeError:
            i = -1
        if not 0 <= i < len(self._declared):  # (no negative indexing from the end)
            raise KeyError(f"no variable with valueReference={vr!r}")
        d = self._declared[i]
        if d.kind is not kind:
            raise TypeError(f"Variable with valueReference={vr} is not of type {_TYPES[kind].__name__}!")
        return d

    def _get_values(self, vrs, kind):
        out = []
        for vr in vrs:
            d = self._declaration(vr, kind)
            value = kind(getattr(self, d.name) if d.method is None else getattr(self, d.method)(*d.args))
            # never a value the host would take for an answer: inf/NaN, or a count that the C int of
            # fmi2Integer would wrap (an exception: fmi2Fatal with this message)
            if kind is float and not math.isfinite(value) and d.method is not None:
                raise ParameterError(f"output {d.name} is not finite ({value!r}): the inputs or parameters "
                                     "are beyond what the model resolves in floating point")
            if kind is int and not -_FMI_INTEGER_MAX - 1 <= value <= _FMI_INTEGER_MAX:
                raise ParameterError(f"{d.name} = {value} is beyond the range of an FMI Integer "
                                     f"[{-_FMI_INTEGER_MAX - 1}, {_FMI_INTEGER_MAX}]")
            out.append(value)
        return out

    def _set_values(self, vrs, values, kind):
        for vr, value in zip(vrs, values):
            d = self._declaration(vr, kind)
            if d.method is not None:
                raise TypeError(f"Variable {d.name} (valueReference={vr}) is an output: it cannot be set")
            setattr(self, d.name, value)

    def get_real(self, vrs):
        return self._get_values(vrs, float)

    def get_integer(self, vrs):
        return self._get_values(vrs, int)

    def get_boolean(self, vrs):
        return self._get_values(vrs, bool)

    def set_real(self, vrs, values):
        self._set_values(vrs, values, float)

    def set_integer(self, vrs, values):
        self._set_values(vrs, values, int)

    def set_boolean(self, vrs, values):
        self._set_values(vrs, values, bool)

    # -- FMI calls ---------------------------------------------------------
    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        self.start_time = float(start_time)

    def exit_initialization_mode(self):
        try:
            self._initialise()
        except ParameterError as exc:
            self.log(f"invalid parameter: {exc}", status=Fmi2Status.error)
            raise
        self._ready = True

    def terminate(self):
        self._terminated = True

    def _refuse(self, message: str) -> bool:
        """Log ``message`` at status error and refuse the step (``fmi2Discard``: pythonfmu's only
        non-fatal bad status for a step; the state is that of the step's start)."""
        self.log(message, status=Fmi2Status.error)
        return False

    def do_step(self, current_time, step_size):
        if self._terminated:
            return self._refuse("do_step after terminate: the instance has ended its run (fmi2Reset "
                                "starts a new one)")
        if not (math.isfinite(current_time) and math.isfinite(step_size)):
            return self._refuse(f"do_step needs a finite currentCommunicationPoint and "
                                f"communicationStepSize, got {current_time!r}, {step_size!r}")
        if step_size < 0:
            return self._refuse(f"communicationStepSize must be >= 0 s, got {step_size!r}")
        # a host that ignores the error status of exitInitializationMode (Ecos does) steps on: an
        # error status (fmi2Discard) with the reason, not an exception on an unbuilt model
        if not self._ready:
            return self._refuse("do_step on an instance that was not initialised (see the error of "
                                "exitInitializationMode)")
        self.early_stop = None
        return self._do_step(current_time, step_size)

    def _get_fmu_state(self):
        return {"__frictionjoint__": _copy_state(self._snapshot())}

    def _set_fmu_state(self, state):
        if "__frictionjoint__" not in state:
            message = state.get("__invalid__", "not an FMU state of this model")
            self.log(message, status=Fmi2Status.error)
            raise ParameterError(message)
        self._restore(_copy_state(state["__frictionjoint__"]))

    # The wrapper calls these two on the class: an exception there would release the instance
    # with nothing to lend it (see frictionjoint.fmi.wrapper), so bad bytes become a state that
    # _set_fmu_state rejects.
    @staticmethod
    def _fmu_state_to_bytes(state) -> bytes:
        return pickle.dumps(state)

    @staticmethod
    def _fmu_state_from_bytes(state: bytes):
        try:
            return pickle.loads(state)
        except Exception as exc:  # noqa: BLE001 -- reported by _set_fmu_state
            return {"__invalid__": f"cannot deserialise the FMU state: {exc!r}"}


class _RunSlave(_Slave):
    """A slave that is a run stepped in the library (:class:`~frictionjoint.stepping.OscillatorRun`,
    :class:`~frictionjoint.structures.blade_run.BladeRun`): one input held over each step
    (:attr:`_held`, the run's ``hold``), ``advance`` to the end of the step, outputs read from the
    run, its snapshot for FMU state (holding the input under the same name)."""

    #: the input the run holds over a step
    _held = ""
    #: the most cycles (:meth:`_cycle_rate` times the step) one step marches event by event: a few
    #: seconds of work at the densest events measured (see the subclasses)
    max_cycles = 0.0

    def _declare_run(self, parameters: dict, held_description: str, outputs: dict) -> None:
        """Declares the run's variables in the FMU's order: its parameters (name -> (default,
        description)), the held input :attr:`_held` (0 until set) and its outputs (name -> (kind,
        description)); no run until initialisation."""
        for name, (default, text) in parameters.items():
            self._parameter(name, default, text, kind=type(default))
        self._input(self._held, 0.0, held_description)
        for name, (kind, text) in outputs.items():
            self._output(name, text, kind=kind)
        self._run = None

    def _idle(self, name):
        """An output before initialisation."""
        raise NotImplementedError

    def _cycle_rate(self) -> float:
        """Cycles per second [1/s] of the excitation and of the structure's natural frequency:
        a bound on the rate of events of a march, up to a small factor."""
        raise NotImplementedError

    def _out(self, name):
        return self._idle(name) if self._run is None else self._run.output(name)

    def _do_step(self, current_time, step_size):
        try:
            self._run.hold(getattr(self, self._held))
        except ParameterError as exc:
            return self._refuse(f"invalid input: {exc}")
        t_end = current_time + step_size
        run = self._run
        start = run.snapshot()
        try:
            if self.stop_at_event and run.advance(t_end, stop_at_event=True):  # at most one event's work
                self.early_stop = run.t
                return True
            if t_end > run.t and (t_end - run.t) * self._cycle_rate() > self.max_cycles:
                return self._long_step(t_end)
            run.advance(t_end)
        except (ConvergenceError, ParameterError) as exc:  # the march's refusal (e.g. its event budget)
            run.restore(start)
            return self._refuse(f"the step to t = {t_end!r} s is refused, the state is the step's start: {exc}")
        return True

    def _too_long(self, t_end) -> str:
        """Why a step to ``t_end`` is not marched event by event."""
        rate = self._cycle_rate()
        return (f"a step to t = {t_end!r} s spans {(t_end - self._run.t) * rate:.3g} cycles of the excitation "
                f"and of the structure ({rate:.3g} per s); one step marches at most {self.max_cycles:.3g} "
                "event by event, to answer in bounded time: take shorter steps")

    def _long_step(self, t_end) -> bool:
        """A step beyond :attr:`max_cycles`: refused (the oscillator skips periods instead)."""
        return self._refuse(self._too_long(t_end))

    def _snapshot(self):
        return None if self._run is None else self._run.snapshot()

    def _restore(self, snap):
        if snap is not None:
            self._run.restore(snap)
            setattr(self, self._held, snap[self._held])


class CoulombOscillatorSlave(_RunSlave):
    """Single-DOF mass on a Coulomb friction surface with a spring to a moving base."""

    description = ("Mass on a Coulomb friction surface (exact stick/slip, Hong & Liu stop rules), spring to a "
                   "harmonically moving base; events located exactly inside do_step")
    _held = "force"
    # 35-50 us per period of the README's case (2 to 4 events): 1e5 cycles, 6e4 periods, take ~3 s
    max_cycles = 1e5
    #: relative distance from the periodic orbit below which the march skips whole periods
    periodic_tolerance = 1e-9

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._declare_run(OSCILLATOR_PARAMETERS,
                          "external force on the mass, added to the harmonic one, held over a step [N]",
                          OSCILLATOR_OUTPUTS)

    def _initialise(self):
        params = {k: getattr(self, k) for k in OSCILLATOR_PARAMETERS}
        self._run = OscillatorRun(params, start_time=self.start_time, force=self.force)

    def _idle(self, name):
        return {"x": self.x0, "v": self.v0}.get(name, OSCILLATOR_OUTPUTS[name][0]())

    def _cycle_rate(self):
        p = self._run.parameters
        return (p["omega"] + math.sqrt(p["stiffness"] / p["mass"])) / (2 * math.pi)

    def _long_step(self, t_end):
        """March period by period until the motion is periodic (:meth:`_periodic`), skip the whole
        periods up to ``t_end`` (the state after them is the same, the cumulative outputs grow by
        the last period's increments) and march the rest; refused when the motion is not periodic
        within the step's budget or the counts would leave the FMI Integer range."""
        run = self._run
        period = 2 * math.pi / run.parameters["omega"]
        budget = int(self.max_cycles // (period * self._cycle_rate())) - 2  # two left for the rest
        if budget < 1:
            return self._refuse(self._too_long(t_end) + " (a period alone exceeds the budget: no period can "
                                "be skipped)")
        start = run.snapshot()
        t0 = run.t
        k, chunk = 0, 1  # periods marched; periods marched unchecked before the next check (doubling)
        while True:
            # periodic over two periods in a row with the same increments: a period whose events
            # are attributed otherwise (one at the section, or missed) is not taken for the orbit's
            first = run.snapshot()
            k += 1
            run.advance(t0 + k * period)  # t0 + k T, not accumulated
            before = run.snapshot()
            if self._periodic(first, before) and k < budget:
                k += 1
                run.advance(t0 + k * period)
                after = run.snapshot()
                if self._periodic(before, after) and self._same_increments(first, before, after):
                    break
            if k >= budget:
                message = (self._too_long(t_end) + f"; the motion did not become periodic within {budget} "
                           "periods (whole periods are skipped once it is; start_on_orbit starts on the orbit)")
                run.restore(start)
                return self._refuse(message)
            chunk = min(chunk, budget - k)
            k += chunk
            run.advance(t0 + k * period)
            chunk *= 2
        m = math.floor((t_end - t0) / period)
        while m > k and t0 + m * period > t_end:
            m -= 1
        skip = m - k
        events = [a - b for a, b in zip(after["events"], before["events"])]
        # the counts at t_end: the skipped periods and at most two more marched
        if after["events"][0] + (skip + 2) * events[0] > _FMI_INTEGER_MAX:
            run.restore(start)
            return self._refuse(f"a step to t = {t_end!r} s would count about {(m + 2) * events[0]:.3g} events "
                                f"({events[0]} per period), beyond the range of the FMI Integer output "
                                f"event_count ({_FMI_INTEGER_MAX}): take shorter steps")
        if skip > 0:
            state = dict(after)
            state["t"] = t0 + m * period
            state["diss"] = after["diss"] + skip * (after["diss"] - before["diss"])
            state["integrals"] = after["integrals"] + skip * (after["integrals"] - before["integrals"])
            state["events"] = tuple(a + skip * d for a, d in zip(after["events"], events))
            run.restore(state)  # x, v, status, the velocity scale and peak_x: those of the period's end
        run.advance(t_end)
        return True

    def _same_increments(self, a, b, c) -> bool:
        """Whether the cumulative outputs grow alike over the periods ``a`` -> ``b`` and ``b`` -> ``c``
        (snapshots): the same event and stop counts, energy and integrals within
        :attr:`periodic_tolerance` of the period's increment."""
        if [y - x for x, y in zip(a["events"], b["events"])] != [y - x for x, y in zip(b["events"], c["events"])]:
            return False
        tol = self.periodic_tolerance
        d1, d2 = b["diss"] - a["diss"], c["diss"] - b["diss"]
        i1, i2 = b["integrals"] - a["integrals"], c["integrals"] - b["integrals"]
        return (abs(d2 - d1) <= tol * abs(d1) + 1e-300
                and bool(np.all(np.abs(i2 - i1) <= tol * np.max(np.abs(i1)) + 1e-300)))

    def _periodic(self, before, after) -> bool:
        """Whether the state ``after`` one period from ``before`` (run snapshots) is on an attracting
        periodic orbit: the same held force and slip status, and the same state bit for bit, or
        within :attr:`periodic_tolerance` (or the resolution of the phase ``omega t`` in floating
        point, if coarser) of the orbit, its distance estimated from the one-period return
        ``|z1 - z0| / (1 - rho)`` with ``rho`` the spectral radius of the exact monodromy."""
        if after["status"] != before["status"] or after["force"] != before["force"] or after["resettle"]:
            return False
        w = self._run.parameters["omega"]
        gap = max(abs(after["x"] - before["x"]), abs(after["v"] - before["v"]) / w)
        if gap == 0.0:
            return True
        scale = max(abs(after["x"]), abs(after["v"]) / w)
        tol = scale * (self.periodic_tolerance + 64 * math.ulp(w * after["t"]))
        if not gap <= tol:  # (NaN: not periodic)
            return False
        run = self._run
        try:
            jac = run.osc.monodromy(after["t"], after["x"] - after["force"] / run.parameters["stiffness"],
                                    after["v"])
        except (ConvergenceError, ParameterError):
            return False
        if jac is None:
            return False
        rho = float(max(abs(np.linalg.eigvals(jac))))
        return rho < 1.0 and gap <= tol * (1.0 - rho)


class _DrivenSlave(_Slave):
    """Displacement-driven joint: input ``u``, outputs force, tangent stiffness, slip state; with
    the input ``velocity`` (the rate of ``u``), the status and event indicators a master needs to
    locate the joint's stick/slip events (:mod:`frictionjoint.fmi.cosim`, ``locate_events``)."""

    #: every output is evaluated at the inputs as set (the slip state also at the velocity's sign)
    direct_inputs = ("u", "velocity")

    def _declare_io(self):
        self._input("u", 0.0, "relative displacement across the joint, held over a step [m]")
        self._output("force", "joint force, restoring convention [N]", method="_get")
        self._output("tangent_stiffness", "stiffness of the sliders that stick (0 while all slip) [N/m]",
                     method="_get")
        self._output("slipping", "true while the joint slips", kind=bool, method="_get")
        self._output("dissipated_energy", "energy dissipated since the start [J]",
                     method="_get")
        self._output("displacement", "the input u at which force and tangent_stiffness are evaluated [m] "
                     "(for a master that couples through the tangent stiffness)", method="_displacement", args=())
        # for a master that locates stick/slip events (frictionjoint.fmi.cosim, locate_events)
        self._input("velocity", 0.0, "rate of change of u [m/s]: a slider at its limit slips only while u moves "
                    "towards it (0: not known, the slip state of the last move of u)")
        self._output("status", "signed number of slipping sliders at u and velocity (sign: slip direction; "
                     "0: all stick)", kind=int, method="_event", args=("status",))
        self._output("slip_margin", "event indicator: smallest slip_force - |spring force| at u of the sliders "
                     "that stuck at the last step's start [N] (< 0: one has slipped since; 0 if none stuck)",
                     method="_event", args=("slip_margin",))
        self._output("slip_margin_rate", "rate of change of slip_margin at u and velocity [N/s]", method="_event",
                     args=("slip_margin_rate",))
        self._output("slip_velocity", "event indicator: velocity in the slip direction of the sliders that slipped "
                     "at the last step's start [m/s] (< 0: they stick again; 0 if none slipped)",
                     method="_event", args=("slip_velocity",))
        self._output("slip_distance", "u travelled since the last step's start in the slip direction of the "
                     "sliders that slipped then [m] (its rate is slip_velocity; 0 if none slipped)",
                     method="_event", args=("slip_distance",))

    def _displacement(self):
        return float(self.u)

    def _check_u(self) -> float:
        """The input ``u``, or a :class:`ParameterError` where the play operator cannot resolve it:
        the sliders' positions are absolute, so a displacement whose rounding reaches the smallest
        slider travel ``slip_force / stiffness`` would give a wrong force (``JenkinsJoint`` with
        stiffness 1e308 at u = 1e308: force 0 while slipping at 0.8 N)."""
        u = self.u
        if not abs(u) <= self._u_max:
            raise ParameterError(f"input u must be finite with |u| <= {self._u_max:.3g} m, got {u!r}: beyond, "
                                 f"its rounding exceeds {RESOLUTION:g} of the smallest slider travel "
                                 f"slip_force/stiffness ({min(self._sliders.reach):.3g} m)")
        return u

    def _get(self, name):
        if not self._ready:
            return False if name == "slipping" else 0.0
        sl = self._sliders
        u = self._check_u()  # an input the joint cannot take: fmi2Fatal with the message, not 0 with OK
        if name == "force":
            return sl.force_at(u)
        if name == "tangent_stiffness":
            if self.velocity != 0.0:
                return float(sl.stiffness[self._slips(u, self.velocity) == 0].sum())
            return sl.tangent_stiffness_at(u)
        if name == "slipping" and self.velocity != 0.0:
            return bool(np.all(self._slips(u, self.velocity) != 0))
        probe = sl.copy()
        probe.update(u)
        if name == "slipping":
            return bool(probe.slipping.all())
        return probe.dissipated_energy

    def _slips(self, u: float, velocity: float) -> np.ndarray:
        """Per slider: +1 or -1 where it slips at ``u`` (reached monotonically from the committed
        state) in that direction, 0 where it sticks. With ``velocity`` != 0 a slider at its limit
        slips only while ``u`` moves towards it (at a reversal it sticks, at the instant it reaches
        its limit moving outwards it slips); with 0, the play operator's last move decides."""
        sl = self._sliders
        w = np.clip(sl.w, u - sl.reach, u + sl.reach)
        if velocity != 0.0:
            # at its limit: moved there, or a spring force that slip_margin counts as reaching it
            # (the two tests round apart: one slider, one answer)
            direction = 1 if velocity > 0.0 else -1
            at_limit = (w == u - direction * sl.reach) | (direction * sl.stiffness * (u - sl.w) >= sl.slip_force)
            return np.where(at_limit, direction, 0)
        moved = sl.slipping if u == sl.u else w != sl.w
        return np.where(moved, np.sign(u - w), 0).astype(int)

    def _event(self, name):
        """The event outputs (see their descriptions), relative to the state committed at the last
        step's start (:attr:`_committed`: its slip directions)."""
        if not self._ready:
            return 0 if name == "status" else 0.0
        u, v = self._check_u(), float(self.velocity)
        if name == "status":
            slips = self._slips(u, v)
            return int(np.sign(slips.sum()) * np.count_nonzero(slips))
        committed = self._committed
        sl = self._sliders
        if name in ("slip_velocity", "slip_distance"):
            direction = np.sign(committed.sum())
            return float(direction * (v if name == "slip_velocity" else u - sl.u))
        stuck = committed == 0
        if not stuck.any():
            return 0.0
        spring = sl.stiffness[stuck] * (u - sl.w[stuck])
        margins = sl.slip_force[stuck] - np.abs(spring)
        i = int(np.argmin(margins))
        if name == "slip_margin":
            return float(margins[i])
        return float(-np.sign(spring[i]) * sl.stiffness[stuck][i] * v)

    def _initialise(self):
        k, f = self._slider_table()
        self._sliders = DrivenSliders(k, f)  # its reach bounds u (_check_u)
        self._u_max = float(min(self._sliders.reach)) * RESOLUTION / np.finfo(float).eps
        self._sliders = DrivenSliders(k, f, u0=self._check_u())
        self._committed = np.zeros(len(k), dtype=int)  # the sliders' slip directions at the step's start

    def _do_step(self, current_time, step_size):
        try:
            u = self._check_u()
        except ParameterError as exc:
            return self._refuse(str(exc))
        if not math.isfinite(self.velocity):
            return self._refuse(f"input velocity must be finite, got {self.velocity!r}")
        self._committed = self._slips(u, float(self.velocity))
        self._sliders.update(u)
        if self.stop_at_event and self.velocity != 0.0:
            self._stop_at_slip(current_time, step_size)
        return True

    def _stop_at_slip(self, current_time, step_size) -> None:
        """Early return (FMI 3, :attr:`stop_at_event`): under the held inputs ``u`` moves as ``u +
        velocity tau`` over the step, so the first event inside it is the instant the nearest slider that
        sticks now reaches its slip force (a slipping one sticks only where the velocity reverses, which
        the host sets at a step's start). If that falls inside the step, the joint stops there: ``u``
        becomes that slider's limit, the sliders move to it and :attr:`early_stop` is its time. A limit
        reached within 16 rounding units of the step's start counts as reached there (the slider slips in
        the step as the play operator moves it): a host whose u(t) at the last stop rounds a little short
        of the limit it was told would otherwise get a second stop an instant later."""
        stuck = self._committed == 0
        if not stuck.any():
            return
        sl, velocity = self._sliders, float(self.velocity)
        limits = sl.w[stuck] + (1.0 if velocity > 0.0 else -1.0) * sl.reach[stuck]
        t_stops = current_time + (limits - self.u) / velocity
        later = np.flatnonzero(t_stops - current_time > 16 * np.finfo(float).eps * np.abs(t_stops))
        if later.size == 0:
            return
        i = later[np.argmin(t_stops[later])]
        if t_stops[i] < current_time + step_size:
            self.u = float(limits[i])
            sl.update(self.u)
            self.early_stop = float(t_stops[i])

    def _snapshot(self):
        if not self._ready:
            return None
        sl = self._sliders
        return {"u_state": sl.u, "w": sl.w, "slipping": sl.slipping, "diss": sl.dissipated_energy, "u": self.u,
                "velocity": self.velocity, "committed": self._committed}

    def _restore(self, snap):
        if snap is None:
            return
        sl = self._sliders
        sl.u, sl.w, sl.slipping, sl.dissipated_energy = snap["u_state"], snap["w"], snap["slipping"], snap["diss"]
        self.u = snap["u"]
        self.velocity = snap.get("velocity", 0.0)
        self._committed = snap.get("committed", np.zeros(len(sl.w), dtype=int))


class JenkinsJointSlave(_DrivenSlave):
    """Jenkins element (spring in series with a Coulomb slider) driven by a displacement."""

    description = "Jenkins joint: spring in series with a Coulomb slider, displacement-driven, exact play operator"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        # defaults: the joints of the co-simulation case (models/two_dof_chain.toml, README)
        self._parameter("stiffness", 100.0, "tangential stiffness of the spring [N/m], > 0")
        self._parameter("slip_force", 0.8, "slip force of the slider [N], > 0")
        self._declare_io()

    def _slider_table(self):
        return [check_positive("stiffness", self.stiffness)], [check_positive("slip_force", self.slip_force)]


class IwanJointSlave(_DrivenSlave):
    """Segalman 4-parameter Iwan joint (parallel Jenkins sliders) driven by a displacement."""

    description = "Iwan joint, Segalman 4-parameter form with n_sliders discrete Jenkins sliders, displacement-driven"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        # defaults: a drop-in for the JenkinsJoint of the co-simulation case (same K_T and F_S)
        self._parameter("stiffness", 100.0, "initial tangential stiffness K_T [N/m], > 0")
        self._parameter("slip_force", 0.8, "macroslip force F_S [N], > 0")
        self._parameter("chi", -0.5, "power-law exponent chi, -1 < chi <= 0")
        self._parameter("beta", 0.1, "strength of the macroslip delta relative to the power law, >= 0")
        self._parameter("n_sliders", 20, f"number of sliders of the power-law part, in [1, {MAX_SLIDERS}]",
                        kind=int)
        self._declare_io()

    def _slider_table(self):
        iw = Iwan.segalman(self.slip_force, self.stiffness, self.chi, self.beta,
                           check_n_sliders("n_sliders", self.n_sliders), dof=0)
        k, f = zip(*iw.sliders_table)
        return list(k), list(f)


class MicroslipJointSlave(_DrivenSlave):
    """Microslip joint: the discrete Iwan element of a Cattaneo-Mindlin sphere-on-flat contact,
    driven by a displacement."""

    description = ("Microslip joint: Iwan element with n_sliders sliders built from Cattaneo-Mindlin "
                   "contact theory (sphere on flat, constant normal load), displacement-driven")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._parameter("normal_load", 100.0, "normal load P [N], > 0")
        self._parameter("friction_coefficient", 0.3, "friction coefficient f, > 0")
        self._parameter("radius", 0.01, "sphere radius R [m], > 0")
        self._parameter("youngs_modulus", 210e9, "Young's modulus E of both bodies [Pa], > 0")
        self._parameter("poisson_ratio", 0.3, "Poisson's ratio of both bodies, in (-1, 0.5)")
        self._parameter("n_sliders", 64, f"number of Iwan sliders, in [1, {MAX_SLIDERS}] (error ~0.8/n^2 of "
                        "the dissipation)", kind=int)
        self._declare_io()

    def _slider_table(self):
        c = MindlinContact(self.normal_load, self.friction_coefficient, self.radius, self.youngs_modulus,
                           self.poisson_ratio)
        k, f = zip(*c.to_iwan(check_n_sliders("n_sliders", self.n_sliders)).sliders_table)
        return list(k), list(f)


#: DovetailRoot.fmu outputs: name -> (kind, description)
DOVETAIL_OUTPUTS = {
    "root_force_tangential": (float, "tangential force of both flanks on the blade [N]"),
    "root_force_radial": (float, "radial force of both flanks on the blade [N] (-Fc in the static state)"),
    **FLANK_OUTPUTS,
    "stiffness_tt": (float, "tangent stiffness -dF_tangential/du_tangential [N/m]"),
    "stiffness_tr": (float, "tangent stiffness -dF_tangential/du_radial [N/m]"),
    "stiffness_rt": (float, "tangent stiffness -dF_radial/du_tangential [N/m]"),
    "stiffness_rr": (float, "tangent stiffness -dF_radial/du_radial [N/m]"),
    "dissipated_energy": (float, "energy dissipated since the start [J]"),
}


class DovetailRootSlave(_Slave):
    """Dovetail blade root (two inclined flanks under centrifugal load) driven by the root's
    tangential and radial displacement from the static state
    (:class:`~frictionjoint.elements.dovetail.DrivenDovetail`)."""

    #: every output is the root's response at the displacement as set
    direct_inputs = ("u_tangential", "u_radial")

    description = ("Dovetail blade root: two flanks inclined at flank_angle, loaded by the centrifugal "
                   "force, each a Jenkins (flat flank) or a microslip Iwan from contact theory (rounded "
                   "flank), driven by the root displacement; exact for inputs linear between steps")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._parameter("centrifugal_force", 1e4, "centrifugal force Fc on the blade [N], > 0")
        self._parameter("flank_angle", 0.5235987755982988, "angle between flank normal and radial axis [rad], "
                        "in [0, pi/2)")
        self._parameter("friction_coefficient", 0.3, "friction coefficient mu, > 0")
        self._parameter("normal_stiffness", 2e8, "normal contact stiffness of one flank [N/m], > 0")
        self._parameter("tangential_stiffness", 1e8, "tangential stiffness of one flat flank [N/m], > 0")
        self._parameter("normal_load_variation", True, "normal loads follow the root motion, with lift-off "
                        "(flat flanks only); false: slip limits from the static normal load", kind=bool)
        self._parameter("flank_profile", 0, "0: flat flank with sharp edges (Jenkins); 1: spherical contact "
                        "of radius flank_radius (Cattaneo-Mindlin Iwan); 2: flat with rounded edges (2D "
                        "half-plane, Ciavarella-Jaeger Iwan)", kind=int)
        self._parameter("flank_radius", 0.02, "flank_profile 1: sphere radius [m], > 0")
        self._parameter("flat_half_width", 2e-3, "flank_profile 2: half-width of the flat [m], > 0")
        self._parameter("corner_radius", 5e-3, "flank_profile 2: radius of the rounded edges [m], > 0")
        self._parameter("flank_length", 0.02, "flank_profile 2: contact length along the root [m], > 0")
        self._parameter("reference_depth", 0.01, "flank_profile 2: depth of the points whose relative "
                        "displacement is the flank slip (2D half-plane) [m], > contact half-width")
        self._parameter("youngs_modulus", 210e9, "flank_profile 1, 2: Young's modulus [Pa], > 0")
        self._parameter("poisson_ratio", 0.3, "flank_profile 1, 2: Poisson's ratio, in (-1, 0.5)")
        self._parameter("n_sliders", 32, f"flank_profile 1, 2: Iwan sliders per flank, in [1, {MAX_SLIDERS}]",
                        kind=int)
        self._input("u_tangential", 0.0, "tangential root displacement from the static state [m]")
        self._input("u_radial", 0.0, "radial root displacement from the static state, outward [m]")
        for name, (kind, text) in DOVETAIL_OUTPUTS.items():
            self._output(name, text, kind=kind)
        self._root = None

    def _initialise(self):
        args = dict(flank_angle=self.flank_angle, friction_coefficient=self.friction_coefficient,
                    normal_stiffness=self.normal_stiffness, tangential_dof=0, radial_dof=1)
        profile = int(self.flank_profile)
        if profile == 0:
            root = DovetailRoot(self.centrifugal_force, tangential_stiffness=self.tangential_stiffness, **args)
        elif profile in (1, 2):
            def contact(n):
                if profile == 1:
                    return MindlinContact(n, self.friction_coefficient, self.flank_radius, self.youngs_modulus,
                                          self.poisson_ratio)
                return HalfPlaneContact(RoundedFlatPunch(self.flat_half_width, self.corner_radius), n,
                                        self.friction_coefficient, self.youngs_modulus, self.poisson_ratio,
                                        self.reference_depth, length=self.flank_length)
            root = DovetailRoot(self.centrifugal_force, flank_contact=contact,
                                n_sliders=check_n_sliders("n_sliders", self.n_sliders), **args)
        else:
            raise ParameterError(f"flank_profile must be 0 (flat), 1 (sphere) or 2 (rounded flat), got {profile}")
        self._root = root.driven(normal_load_variation=bool(self.normal_load_variation) and profile == 0)
        self._root.update([self.u_tangential, self.u_radial])
        self._scratch = root.driven(normal_load_variation=self._root.vary)
        self._probed = None

    def _probe(self):
        """The flanks moved to the current input (direct feedthrough), computed once per input
        value between steps and shared by all outputs; the committed state is not changed."""
        u = (self.u_tangential, self.u_radial)
        if tuple(self._root.u) == u:
            return self._root
        if self._probed is None or self._probed[0] != u:
            self._scratch.set_state(self._root.state())
            self._scratch.update(u)
            self._probed = (u, self._scratch)
        return self._probed[1]

    def _out(self, name):
        if self._root is None:
            return DOVETAIL_OUTPUTS[name][0]()
        p = self._probe()  # an input the root cannot take: fmi2Fatal with the message, not 0 with OK
        if name.startswith("root_force"):
            return float(p.root_force[0 if name.endswith("tangential") else 1])
        side = 0 if name.endswith("right") else 1
        if name.startswith("normal_force"):
            return float(p.normal_force[side])
        if name.startswith("friction_force"):
            return float(p.friction_force[side])
        if name.startswith("slipping"):
            return bool(p.slipping[side])
        if name.startswith("stiffness"):
            k = p.tangent_stiffness()
            return float(k["tr".index(name[-2]), "tr".index(name[-1])])
        return float(p.dissipated_energy)

    def _do_step(self, current_time, step_size):
        try:
            self._root.update((self.u_tangential, self.u_radial))
        except ParameterError as exc:
            return self._refuse(f"invalid inputs u_tangential, u_radial: {exc}")
        self._probed = None
        return True

    def _snapshot(self):
        if self._root is None:
            return None
        return {"root": self._root.state(), "u": (self.u_tangential, self.u_radial)}

    def _restore(self, snap):
        if snap is not None:
            self._root.set_state(snap["root"])
            self._probed = None
            self.u_tangential, self.u_radial = snap["u"]


class LinearStructureSlave(_Slave):
    """A linear structure (M, C, K, named DOFs) from the definition in the FMU's resources,
    advanced exactly under harmonic force and joint loads held over a step
    (:class:`~frictionjoint.solvers.marcher.held.HeldPortStructure`)."""

    description = ("Linear structure M x'' + C x' + K x = f, advanced exactly (matrix exponential) under a "
                   "harmonic force and joint loads held over a communication step in linearly implicit form "
                   "-(joint_force + joint_stiffness (x - joint_displacement)) at each port DOF")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        with open(os.path.join(kwargs["resources"], STRUCTURE_RESOURCE)) as f:
            self._definition = d = StructureDefinition.from_dict(json.load(f))
        self._parameter("omega", d.omega, "excitation angular frequency [rad/s], > 0")
        for dof, value in d.force_amplitude.items():
            self._parameter(f"force_amplitude_{dof}", value, f"amplitude of the force on {dof}, times "
                            "cos(omega t) [N]")
        for dof in d.ports:
            self._input(f"joint_force_{dof}", 0.0, f"restoring force of the joint at {dof}, evaluated at "
                        f"joint_displacement_{dof} (the structure feels its negative), held over a step [N]")
            self._input(f"joint_stiffness_{dof}", 0.0, f"tangent stiffness of the joint at {dof} [N/m], >= 0; "
                        "0: the force is held (explicit coupling)")
            self._input(f"joint_displacement_{dof}", 0.0, f"displacement at which joint_force_{dof} was "
                        "evaluated [m]")
        for dof in d.outputs:
            self._output(f"x_{dof}", f"displacement of {dof} [m]", method="_state", args=(0, dof))
            self._output(f"v_{dof}", f"velocity of {dof} [m/s]", method="_state", args=(1, dof))
        self._body = None

    def _state(self, which, dof):
        if self._body is None:
            return 0.0
        i = self._definition.structure.dof_index(dof)
        return float((self._body.x, self._body.v)[which][i])

    def _initialise(self):
        d = self._definition
        f = d.force_vector()
        for dof in d.force_amplitude:
            f[d.structure.dof_index(dof)] = getattr(self, f"force_amplitude_{dof}")
        self._body = HeldPortStructure(d.structure, d.ports, f, omega=self.omega, t0=self.start_time)
        self._frequencies = {}

    def _port_inputs(self, kind):
        return [getattr(self, f"joint_{kind}_{dof}") for dof in self._definition.ports]

    #: the most cycles (the excitation's and the highest natural frequency's, joint stiffness
    #: included) one step may span: the rounding of the propagator expm(A h) grows like eps |A| h,
    #: below 1e-9 here (at 1e300 s it overflows to NaN)
    max_cycles = 1e6

    def _highest_frequency(self, stiffness) -> float:
        """Highest natural frequency [rad/s] with the joints' stiffness ``stiffness`` at the ports."""
        key = tuple(stiffness)
        if key not in self._frequencies:
            st = self._definition.structure
            k = st.stiffness.copy()
            ports = [st.dof_index(dof) for dof in self._definition.ports]
            k[ports, ports] += np.asarray(stiffness, dtype=float)
            lam = np.linalg.eigvals(np.linalg.solve(st.mass, k))
            if len(self._frequencies) >= 64:
                self._frequencies.clear()
            self._frequencies[key] = float(np.sqrt(np.max(np.abs(lam))))
        return self._frequencies[key]

    def _do_step(self, current_time, step_size):
        stiffness = self._port_inputs("stiffness")
        if not all(math.isfinite(k) and k >= 0 for k in stiffness):
            return self._refuse(f"invalid input: joint_stiffness must be finite and >= 0 N/m, got {stiffness!r}")
        rate = (self.omega + self._highest_frequency(stiffness)) / (2 * math.pi)
        if step_size * rate > self.max_cycles:
            return self._refuse(f"a step of {step_size!r} s spans {step_size * rate:.3g} cycles of the excitation "
                                f"and the highest natural frequency ({rate:.3g} per s); one step spans at most "
                                f"{self.max_cycles:.3g} (the propagator's rounding grows with it): take shorter steps")
        saved = self._snapshot()
        try:
            self._body.t = float(current_time)  # the host's time: the excitation phase is absolute
            self._body.advance(step_size, self._port_inputs("force"), stiffness,
                               self._port_inputs("displacement"))
        except ParameterError as exc:
            return self._refuse(f"invalid input: {exc}")
        if not (np.all(np.isfinite(self._body.x)) and np.all(np.isfinite(self._body.v))):
            self._restore(saved)
            return self._refuse("the step's state is not finite: the inputs or parameters are beyond what "
                                "the model resolves in floating point")
        return True

    def _snapshot(self):
        if self._body is None:
            return None
        b = self._body
        return {"x": b.x.copy(), "v": b.v.copy(), "t": b.t,
                "inputs": {k: self._port_inputs(k) for k in ("force", "stiffness", "displacement")}}

    def _restore(self, snap):
        if snap is None:
            return
        b = self._body
        b.x, b.v, b.t = snap["x"].copy(), snap["v"].copy(), snap["t"]
        for kind, values in snap["inputs"].items():
            for dof, value in zip(self._definition.ports, values):
                setattr(self, f"joint_{kind}_{dof}", value)


#: the blade model definitions read from FMU resources in this process: the file's bytes -> the
#: definition (one slave is constructed at every reset; the definition is built once)
_BLADE_MODELS: dict = {}


class BladeDovetailSlave(_RunSlave):
    """A blade model definition on its dovetail root (the definition in the FMU's resources),
    marched exactly inside ``do_step`` (:class:`~frictionjoint.structures.blade_run.BladeRun`).

    The definition is a beam blade on a point-contact dovetail (``BladeDovetail.fmu``) or a solid
    blade on contact-patch flanks (``build_fmus(blades=...)``): the outputs are the run's
    (:func:`~frictionjoint.structures.blade_run.blade_outputs`: the beam's, or the same names as
    flank aggregates and the patch's own), and a step of a solid blade marches at most
    :attr:`max_cycles_patch` cycles.

    What does not change between the resets of a sweep is built once: the definition (per file
    contents) and its reduced assembly (per process, :func:`~frictionjoint.structures.blade_run._reduced`).
    With ``start_from_last_orbit`` the shooting starts from the orbit this instance found at its
    last initialisation with the same other parameters (the sweep's continuation), kept through
    ``fmi2Reset`` (which constructs the slave anew) on the slave's class: pythonfmu's wrapper holds
    the class for the process (the first ``fmi2Instantiate``'s, for every instance of the FMU
    script), so the orbits are keyed by the instance's name and unpacked resources folder.
    """

    description = ("Blade (Craig-Bampton beam, rotating) on a dovetail root with two flat flanks under the "
                   "centrifugal load, harmonic tip force; exact event-driven stick/slip (and lift-off with "
                   "normal_load_variation) located inside do_step")
    _held = "tip_force"
    # about 2 ms per period of the default blade with slipping flanks (8 events), 2.6 cycles per
    # period: 5000 cycles take ~4 s
    max_cycles = 5000.0
    # the solid blade on patches (models/ti64_solid_blade.toml, 42 DOFs, 18 nodes): about 60 ms per
    # period on its partial-slip orbit at 1900 rad/s (32 events), 2 cycles per period; from rest up to
    # 0.9 s for the first period (its configurations built): 200 cycles take ~6 s on the orbit
    max_cycles_patch = 200.0

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        path = os.path.join(kwargs["resources"], BLADE_RESOURCE)
        with open(path, "rb") as f:
            data = f.read()
        self._model = _BLADE_MODELS.get(data)
        if self._model is None:
            if len(_BLADE_MODELS) >= 8:
                _BLADE_MODELS.clear()
            self._model = _BLADE_MODELS[data] = load_blade_model(path)
        self._outputs = blade_outputs(self._model)
        if self._model.kind == "solid":
            self.max_cycles = self.max_cycles_patch
        self._declare_run(blade_parameters(self._model),
                          "extra force at the tip, added to the harmonic one, held over a step [N]", self._outputs)

    def _initialise(self):
        params = {k: getattr(self, k) for k in blade_parameters(self._model)}
        # this instance's last orbit, for the same parameters but omega
        key = (self.instance_name, self.resources, repr(sorted((k, v) for k, v in params.items() if k != "omega")))
        memory = type(self).__dict__.get("_last_orbits")
        if memory is None:
            memory = {}
            setattr(type(self), "_last_orbits", memory)
        guess = memory.get(key) if params["start_from_last_orbit"] else None
        self._run = BladeRun(self._model, params, start_time=self.start_time, tip_force=self.tip_force,
                             orbit_guess=guess)
        if len(memory) >= 8:
            memory.clear()
        memory[key] = self._run.orbit_state
        freqs = self._run.system.structure.natural_frequencies()
        # the first elastic one: rigid-body modes of the free root are 0 to rounding (sqrt(eps) of
        # the largest: 0.08 rad/s on the solid blade)
        positive = freqs[freqs > 1e-6 * freqs.max()]
        self._natural = float(positive[0]) if positive.size else 0.0

    def _cycle_rate(self):
        return (self._run.parameters["omega"] + self._natural) / (2 * math.pi)

    def _idle(self, name):
        return self._outputs[name][0]()
