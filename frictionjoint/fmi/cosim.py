"""A system of FMUs and a fixed-step co-simulation master for it.

:class:`FMUSystem` names the components (FMU files), their parameter values and the connections
between their ports. The same system runs through this module's master
(:meth:`FMUSystem.simulate`, fmpy, every component in this process) and is written as an SSP file
(:meth:`FMUSystem.to_ssp`, :mod:`frictionjoint.fmi.ssp`) for native hosts such as Ecos
(:mod:`frictionjoint.fmi.ecos`).

The master: communication points ``t0 + n h`` (never accumulated); at ``t0`` and after every
step, the connections are transferred **in the order given** (read the source, set the target at
once), then every component steps over ``[t_n, t_n + h]`` with its inputs held. A joint FMU's
outputs depend directly on its input displacement, so listing ``structure.x -> joint.u`` before
``joint.force -> structure`` gives the structure the joint force at the current displacement.

Coupling a joint to a structure (:func:`joint_connections`): *explicit* transfers the joint
force only, held over the step; it is unstable for a stiff stuck joint (a spring integrated by
zero-order hold). *Semi-implicit* also transfers the joint's ``tangent_stiffness`` and the
``displacement`` at which the force was evaluated, and the structure applies
``-(force + tangent_stiffness (x - displacement))`` over the step
(:class:`~frictionjoint.solvers.marcher.held.HeldPortStructure`): exact while the joint sticks, first
order in ``h`` through stick/slip changes, and stable whatever the joint stiffness.

Events located across FMUs (``locate_events``): between joint events the semi-implicit step is
exact whatever its length (a stuck Jenkins joint is a spring the structure integrates exactly, a
slipping one a constant force), so all the coupling error comes from status changes inside a step.
The joint FMUs report event indicators relative to their status at the step's start, positive
while it holds (:data:`EVENT_INDICATORS`: ``slip_margin``, the distance of the stuck sliders from
their slip force, and ``slip_velocity``, the slipping sliders' velocity in their slip direction;
the joint needs its ``velocity`` input for them, ``joint_connections(..., events=True)``). The
master saves every component's state at the step's start, steps, and where an indicator ends
negative, or dips below zero inside the step by the cubic Hermite interpolant of its values and
rate (``slip_margin_rate``) or of its integral (``slip_distance``, whose rate is the slip velocity),
finds the event time by root finding on the indicators at exact step ends (restore, step to
``t + tau`` with the same held inputs; Illinois, to the rounding of ``t``), steps to the end of the
bracket where the status has changed, transfers the connections there (twice with Jacobi transfer,
so that the structure gets the joint's new force law) and continues to ``t + h``. Recorded points
stay ``t0 + n h``. An event that comes and goes inside one step unseen by the interpolant is missed:
the README's chain is exact from T/20 on and loses 2 of its 31 events at T/10.
"""
from __future__ import annotations

import math
import sys
import threading
import weakref
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

import numpy as np

from ..errors import FMUError, ParameterError, check_positive, check_real
from ..memory import available_memory
from ..results import CoSimulationResult
from ..threads import owns_blas_threads
from .ports import checked_components, checked_connections, checked_parameters, split_port
from .ssp import write_ssp

__all__ = ["FMUSystem", "joint_connections", "EVENT_INDICATORS"]

#: outputs of a component that take part in event location (positive while the status at the step's
#: start holds, negative once it has changed), each with the outputs of its rate of change and of its
#: integral since the step's start (or None), from which the master sees an event come and go in a step
EVENT_INDICATORS = {"slip_margin": ("slip_margin_rate", None), "slip_velocity": (None, "slip_distance")}
#: the most events located in one communication step
MAX_EVENTS_PER_STEP = 100
#: seconds a run (:meth:`FMUSystem.simulate`) goes before its progress bar appears when
#: ``progress`` is left at None (a run of the README's chain takes 0.05-0.3 s: no bar; 10**6
#: steps take minutes: a bar with its estimate of the time left)
PROGRESS_DELAY = 2.0


def joint_connections(structure: str, joint: str, dof: str, coupling: str = "semi-implicit",
                      events: bool = True) -> list:
    """Connections between a ``LinearStructure`` FMU component and a displacement-driven joint FMU
    component (JenkinsJoint, IwanJoint, MicroslipJoint) acting at the structure's port ``dof``.

    Parameters
    ----------
    structure, joint : str
        Component names.
    dof : str
        The structure's port DOF.
    coupling : {"semi-implicit", "explicit"}
        See the module docstring.
    events : bool
        Also connect the structure's velocity ``v_<dof>`` to the joint's ``velocity``, which the
        joint needs to report its status and event indicators for a master that locates events
        (:meth:`FMUSystem.simulate`, ``locate_events``, which then locates them by default).
        False: the fixed-step coupling of a host that does not (the joint's tangent stiffness at a
        reversal then follows its last move, as without the velocity).

    Returns
    -------
    list of (str, str)
        ``("component.output", "component.input")`` pairs, in transfer order.
    """
    if coupling not in ("semi-implicit", "explicit"):
        raise ParameterError(f"coupling must be 'semi-implicit' or 'explicit', got {coupling!r}")
    pairs = [(f"{structure}.x_{dof}", f"{joint}.u"),
             (f"{joint}.force", f"{structure}.joint_force_{dof}"),
             (f"{joint}.displacement", f"{structure}.joint_displacement_{dof}")]
    if coupling == "semi-implicit":
        pairs.append((f"{joint}.tangent_stiffness", f"{structure}.joint_stiffness_{dof}"))
    if events:
        pairs.insert(1, (f"{structure}.v_{dof}", f"{joint}.velocity"))
    return pairs


@dataclass(frozen=True)
class FMUSystem:
    """Components (FMU files), their parameter values and the connections between them.

    Parameters
    ----------
    components : dict
        Component name -> ``.fmu`` path. Several components may use the same FMU.
    connections : sequence of (str, str)
        ``("source.output", "target.input")`` pairs, transferred in this order.
    parameters : dict, optional
        Component name -> {parameter name: value}.

    Notes
    -----
    The components are loaded (extracted, instantiated) at the first :meth:`simulate` and kept for
    the next ones, which reset and re-initialise them: loading costs some 0.1 s per FMU (the
    pythonfmu slaves import their bundled library), a run of the README's chain 0.05-0.3 s. They
    are freed by :meth:`close` (or ``with FMUSystem(...) as system:``), when the system is garbage
    collected, at the process's exit, and after a run that failed. A run started while another
    is under way on the same system (another thread) loads its own instances.
    """

    components: dict
    connections: Sequence = ()
    parameters: dict = field(default_factory=dict)

    def __post_init__(self):
        from fmpy import read_model_description

        components = checked_components(self.components)
        variables, restorable, versions = {}, set(), {}
        for name, path in components.items():
            md = read_model_description(str(path))
            variables[name] = {v.name: v for v in md.modelVariables}
            if md.coSimulation is not None and md.coSimulation.canGetAndSetFMUstate:
                restorable.add(name)
            if not str(md.fmiVersion).startswith("2."):
                versions[name] = md.fmiVersion
        connections = [(f"{sc}.{sv}", f"{tc}.{tv}") for (sc, sv), (tc, tv) in
                       checked_connections(self.connections, variables)]
        parameters = checked_parameters(self.parameters, variables)
        object.__setattr__(self, "components", components)
        object.__setattr__(self, "connections", tuple(connections))
        object.__setattr__(self, "parameters", parameters)
        object.__setattr__(self, "_variables", variables)
        object.__setattr__(self, "_restorable", frozenset(restorable))  # can get and set their FMU state
        object.__setattr__(self, "_not_fmi2", versions)  # component -> its FMI version, where not 2.0
        pool = {}
        object.__setattr__(self, "_pool", pool)
        object.__setattr__(self, "_lock", threading.Lock())
        object.__setattr__(self, "_finalizer", weakref.finalize(self, _free_instances, pool))

    def __getstate__(self):  # (the loaded instances stay with this process's object)
        return {"components": self.components, "connections": self.connections, "parameters": self.parameters}

    def __setstate__(self, state):
        self.__init__(**state)

    def close(self) -> None:
        """Free the components loaded by :meth:`simulate` (the next run loads them again)."""
        with self._lock:
            _free_instances(self._pool)

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _instances(self) -> tuple:
        """``(instances, pooled)``: the kept instances (loading them at the first run) while no other
        run holds them, else fresh ones the caller frees."""
        from .master import FMUInstance

        pooled = self._lock.acquire(blocking=False)
        insts = self._pool if pooled else {}
        try:
            for name, path in self.components.items():
                if name not in insts:
                    insts[name] = FMUInstance(path, name=name)
        except BaseException:
            _free_instances(insts)
            if pooled:
                self._lock.release()
            raise
        return insts, pooled

    def variable(self, port: str):
        """The model variable (fmpy) of ``"component.variable"``."""
        comp, var = split_port(port)
        try:
            return self._variables[comp][var]
        except KeyError:
            raise ParameterError(f"no variable {port!r} in the system") from None

    @owns_blas_threads
    def simulate(self, stop_time: float, step: float, outputs: Sequence[str], start_time: float = 0.0,
                 transfer: str = "sequential", progress: bool | None = None,
                 locate_events: bool | None = None) -> CoSimulationResult:
        """Run the system with this module's fixed-step master (see the module docstring).

        Parameters
        ----------
        stop_time : float
            End time [s]; the last communication point is the last ``t0 + n h <= stop_time``
            (within rounding).
        step : float
            Communication step ``h`` [s], > 0 and above the rounding of the times (``t0 + h`` must
            differ from ``t0``, and ``stop_time`` from ``stop_time + h``). The recorded grid,
            ``(n + 1) * (len(outputs) + 1)`` floats for ``n`` steps, must fit in the memory
            available (:func:`frictionjoint.memory.available_memory`): a run that cannot is refused before any FMU is
            loaded, with the estimate.
        outputs : sequence of str
            ``"component.variable"`` names to record at every communication point.
        start_time : float
            Start time ``t0`` [s].
        transfer : {"sequential", "jacobi"}
            ``"sequential"``: each connection is read and set in turn (see the module docstring);
            ``"jacobi"``: all sources are read, then all targets set, as Ecos does (a joint's force
            then lags its displacement by one step; the semi-implicit coupling stays exact while
            the joint sticks).
        progress : bool, optional
            Show a progress bar (tqdm, on stderr, with the estimated time left). None (default):
            shown once the run has lasted :data:`PROGRESS_DELAY` seconds.
        locate_events : bool, optional
            Cut each communication step at the events of the components that report event
            indicators (see the module docstring). Default: where every component can get and set
            its FMU state and every such component's ``velocity`` input is connected. True where
            that is not so raises :class:`ParameterError`.

        Returns
        -------
        CoSimulationResult

        Notes
        -----
        The components run in this process with the library's BLAS threads
        (:func:`~frictionjoint.threads.blas_threads`, 1 by default): their matrices are small, and
        OpenBLAS's threads made a structure FMU's 8 x 8 matrix exponential take 15 ms instead of
        15 us on two busy cores.
        """
        if transfer not in ("sequential", "jacobi"):
            raise ParameterError(f"transfer must be 'sequential' or 'jacobi', got {transfer!r}")
        if self._not_fmi2:
            comp, version = next(iter(self._not_fmi2.items()))
            raise ParameterError(f"component {comp!r} is an FMI {version} FMU: this master runs FMI 2.0 "
                                 "co-simulation FMUs (an FMI 3 FMU runs in an FMI 3 host, e.g. fmpy's "
                                 "simulate_fmu; to_ssp writes it for an SSP host)")
        if progress is not None and not isinstance(progress, (bool, np.bool_)):
            raise ParameterError(f"progress must be True, False or None, got {progress!r}")
        h = check_positive("step", step)
        t0 = check_real("start_time", start_time)
        outputs = list(outputs)
        for name in outputs:
            self.variable(name)
        n_steps = _step_count(t0, check_real("stop_time", stop_time), h, len(outputs))
        indicators = self._event_indicators(locate_events)
        insts, pooled = self._instances()
        locator, done = None, False
        try:
            for name, inst in insts.items():
                inst.initialize(self.parameters.get(name), start_time=t0)
            locator = _EventLocator(self, insts, transfer, indicators) if indicators else None
            record = self._march(insts, t0, h, n_steps, outputs, transfer, locator, progress)
            done = True
        finally:
            if not (done and pooled):  # (a failed run may leave an instance in its error state)
                _free_instances(insts)
            if pooled:
                self._lock.release()
        host = "frictionjoint master (fmpy)"
        if locator is not None:
            host += f", {locator.count} events located"
        return CoSimulationResult(t=t0 + h * np.arange(n_steps + 1), values=dict(zip(outputs, record.T)),
                                  step=h, host=host)

    def _march(self, insts, t0, h, n_steps, outputs, transfer, locator, progress) -> np.ndarray:
        """The initialised components over ``n_steps`` steps: the outputs at every communication
        point, (n_steps + 1, n_outputs)."""
        record = np.empty((n_steps + 1, len(outputs)))
        move, read = self._transfer(insts, transfer), self._read(insts, outputs)
        move()
        record[0] = read()
        from tqdm import tqdm

        steps = tqdm(range(1, n_steps + 1), desc="co-simulation", unit="step", file=sys.stderr,
                     disable=progress is False, delay=PROGRESS_DELAY if progress is None else 0.0,
                     leave=False)
        for n in steps:
            if locator is None:
                for inst in insts.values():
                    inst.step(h)
                move()
            else:
                locator.step(t0 + (n - 1) * h, t0 + n * h)
            record[n] = read()
        return record

    def _event_indicators(self, locate_events) -> list:
        """``[(component, indicator names, [(rate, integral) output names or None]), ...]`` when
        events are located, [] when not (see :meth:`simulate`)."""
        if locate_events is not None and not isinstance(locate_events, (bool, np.bool_)):
            raise ParameterError(f"locate_events must be True, False or None, got {locate_events!r}")
        if locate_events is False:
            return []
        targets = {t for _, t in self.connections}
        found, why = [], None
        for comp in self.components:
            variables = self._variables[comp]
            names = [n for n in EVENT_INDICATORS if n in variables and variables[n].causality == "output"]
            if comp not in self._restorable:
                why = why or f"component {comp!r} cannot get and set its FMU state"
            if not names:
                continue
            if "velocity" in variables and f"{comp}.velocity" not in targets:
                why = why or f"the input {comp}.velocity is not connected (joint_connections(..., events=True))"
            rates = [tuple(m if m in variables else None for m in EVENT_INDICATORS[n]) for n in names]
            found.append((comp, names, rates))
        if locate_events and (why or not found):
            raise ParameterError(f"locate_events=True: {why or 'no component reports event indicators'}")
        return [] if why else found

    def _transfer(self, insts, transfer: str) -> "_Transfer":
        """The connections' transfer over the instances ``insts`` (:class:`_Transfer`): call it."""
        return _Transfer(self.connections, insts, transfer)

    @staticmethod
    def _read(insts, outputs):
        """A function of no arguments giving the values of ``outputs`` (one FMI call per component)."""
        by_comp = {}
        for pos, (c, v) in enumerate(map(split_port, outputs)):
            by_comp.setdefault(c, []).append((pos, v))
        readers = [(insts[c].reader([v for _, v in items]), [pos for pos, _ in items])
                   for c, items in by_comp.items()]

        def read():
            out = [0.0] * len(outputs)
            for reader, positions in readers:
                for pos, value in zip(positions, reader()):
                    out[pos] = float(value)
            return out

        return read

    def to_ssp(self, path, name: str = "system", start_time: float = 0.0, stop_time: float | None = None,
               step: float | None = None) -> Path:
        """Write the system as an SSP archive (:func:`frictionjoint.fmi.ssp.write_ssp`), with the
        default experiment ``start_time`` to ``stop_time`` [s] and a fixed-step host's communication
        ``step`` [s] where given."""
        return write_ssp(self, path, name=name, start_time=start_time, stop_time=stop_time, step=step)


def _since(reading):
    """A step's start reading for the step: its integrals (since the last step's start) are 0."""
    g, r, q = reading
    return g, r, np.where(np.isfinite(q), 0.0, q)


def _free_instances(insts: dict) -> None:
    """Close and forget every instance of ``insts`` (all of them, whatever one raises)."""
    errors = []
    while insts:
        _, inst = insts.popitem()
        try:
            inst.close()
        except Exception as exc:  # noqa: BLE001 -- free the others first
            errors.append(exc)
    if errors:
        raise errors[0]


class _Transfer:
    """The connections' transfer (see :meth:`FMUSystem.simulate`), compiled once per run into FMI
    calls: ``"sequential"``, each source read after every earlier connection's target is set;
    ``"jacobi"``, every source read before any target is set. A component's outputs depend only on
    its own inputs and state, so the values a component is read (one call for all its sources) or
    set (one call) in one batch are those of one connection at a time: sets are kept until their
    component is read or the end, and each takes its values from the read that its connections
    saw."""

    def __init__(self, connections, insts, transfer: str):
        pairs = [(split_port(s), split_port(t)) for s, t in connections]
        sources = {}
        for (sc, sv), _ in pairs:
            sources.setdefault(sc, []).append(sv)
        ops, pending, read = [], {}, {}  # read: component -> its latest read's slot (the reads' count then)

        def flush(comp):
            items = pending.pop(comp, None)
            if items:
                ops.append((None, insts[comp].writer([v for v, _ in items]), [src for _, src in items]))
                read.pop(comp, None)

        for (sc, sv), (tc, tv) in pairs:
            if transfer == "sequential":
                flush(sc)
            if sc not in read:
                read[sc] = sum(op[0] is not None for op in ops)
                ops.append((insts[sc].reader(sources[sc]), None, None))
            pending.setdefault(tc, []).append((tv, (read[sc], sources[sc].index(sv))))
        for comp in list(pending):
            flush(comp)
        self._ops = ops

    def __call__(self) -> None:
        slots = []
        for reader, writer, refs in self._ops:
            if reader is not None:
                slots.append(reader())
            else:
                writer([slots[k][i] for k, i in refs])


class _EventLocator:
    """The master's steps cut at events (see the module docstring): :meth:`step` advances every
    component from ``t`` to ``t_end`` and leaves the connections transferred at ``t_end``."""

    def __init__(self, system, insts, transfer, indicators):
        self.system, self.insts, self.transfer, self.indicators = system, insts, transfer, indicators
        self.count = 0
        self._move = system._transfer(insts, transfer)
        self._readers = [insts[comp].reader(names + [m for pair in extra for m in pair if m is not None])
                         for comp, names, extra in indicators]
        self._carry = None  # the indicators read at the end of the last step, where nothing was set since

    def _read(self):
        """Indicator values, rates and integrals (NaN: none) of every event component, flat."""
        g, r, q = [], [], []
        for (comp, names, extra), reader in zip(self.indicators, self._readers):
            values = reader()
            g += values[:len(names)]
            it = iter(values[len(names):])
            for rate, integral in extra:
                r.append(np.nan if rate is None else next(it))
                q.append(np.nan if integral is None else next(it))
        return np.array(g), np.array(r), np.array(q)

    def _advance(self, saved, t, s):
        """Every component from its state ``saved`` at ``t`` to ``s``, connections transferred."""
        for name, inst in self.insts.items():
            inst.restore(saved[name])
            inst.step_between(t, s)
        self._move()
        self._at = s

    def step(self, t: float, t_end: float) -> None:
        fresh = True  # t is not an event: the indicators read there hold for the step
        start = self._carry
        for _ in range(MAX_EVENTS_PER_STEP):
            if start is None:
                start = self._read()
            start = _since(start)
            saved = {name: inst.save() for name, inst in self.insts.items()}
            self._at = None
            try:
                for inst in self.insts.values():
                    inst.step_between(t, t_end)
                self._move()
                end = self._read()
                cut = self._event(saved, t, t_end, start if fresh else None, end)
                if cut is None:
                    if self._at is not None:  # a probe found no event: back to the step's end
                        self._advance(saved, t, t_end)
                    self._carry = end  # the next step's start (the same state as read there)
                    return
                if self._at != cut:  # (the root finder's last evaluation is mostly there)
                    self._advance(saved, t, cut)
                if self.transfer == "jacobi":  # the structure gets the joint's outputs at its new input
                    self._move()
            finally:
                for name, inst in self.insts.items():
                    inst.free(saved[name])
            self.count += 1
            self._carry = start = None
            if cut >= t_end:
                return
            t, fresh = cut, False
        raise FMUError(f"more than {MAX_EVENTS_PER_STEP} events in the communication step ending at "
                       f"t = {t_end!r} s")

    def _event(self, saved, t, t_end, start, end):
        """The end of the bracket (where the status has changed) of the first event in
        ``(t, t_end]``, or None: none found."""
        g1 = end[0]
        negative = np.flatnonzero(g1 < 0)
        readings = {t_end: end}  # time -> the indicators read there (integrals since t)
        if start is not None:
            readings[t] = start
        hi, f_hi = t_end, g1
        if negative.size == 0:
            if start is None:
                return None
            s = _hermite_dip(t, t_end, start, end)
            if s is None:
                return None
            self._advance(saved, t, s)
            readings[s] = reading = self._read()
            negative = np.flatnonzero(reading[0] < 0)
            if negative.size == 0:
                return None
            hi, f_hi = s, reading[0]
        indices = set(negative.tolist())

        def phi(s):
            self._advance(saved, t, s)
            readings[s] = reading = self._read()
            return float(reading[0][negative].min())

        def predict(lo, hi, s1, s2):  # a zero inside the bracket of the interpolants through the latest two
            if s1 in readings and s2 in readings and s1 != s2:
                (a, ra), (b, rb) = sorted([(s1, readings[s1]), (s2, readings[s2])], key=lambda p: p[0])
                return _hermite_root(a, b, ra, rb, indices, within=(lo, hi), near=s2)
            return None

        lo = t
        if start is None or not np.all(start[0][negative] > 0):
            lo = self._lower_end(phi, t, hi)
            if lo is None:
                return None
        return _illinois(phi, lo, hi, None if lo > t else float(start[0][negative].min()),
                         float(f_hi[negative].min()), predict)

    @staticmethod
    def _lower_end(phi, t, hi):
        """A time in ``(t, hi)`` where ``phi >= 0`` (halving towards ``t``), or None."""
        s = hi
        for _ in range(60):
            s = t + 0.5 * (s - t)
            if s <= t:
                return None
            if phi(s) >= 0:
                return s
        return None


def _hermite_pieces(t, t_end, start, end):
    """Per indicator with a rate or an integral: ``(i, a, b, c, p0, deriv)``, the cubic Hermite
    interpolant ``p(x) = a x^3 + b x^2 + c x + p0`` over the step (``x = (s - t) / (t_end - t)``) of
    its values and rates, or (``deriv``) of its integral (since the step's start; zero where not
    given) and its values, at ``t`` and
    ``t_end`` (``start``, ``end``: values, rates, integrals as :meth:`_EventLocator._read` gives them);
    the indicator is ``p(x)``, or ``p'(x) / (t_end - t)``."""
    (g0, r0, q0), (g1, r1, q1) = start, end
    length = t_end - t
    for i in range(len(g0)):
        if np.isfinite(r0[i]) and np.isfinite(r1[i]):
            p0, p1, m0, m1, deriv = g0[i], g1[i], r0[i] * length, r1[i] * length, False
        elif np.isfinite(q1[i]):
            p0 = q0[i] if np.isfinite(q0[i]) else 0.0
            p1, m0, m1, deriv = q1[i], g0[i] * length, g1[i] * length, True
            if np.finfo(float).eps * max(abs(p0), abs(p1)) > 1e-6 * (abs(m0) + abs(m1)):
                # the integral's increase is lost in its rounding (a short interval late in a
                # step): the indicator's values alone, linearly
                yield i, 0.0, 0.5 * (m1 - m0), m0, p0, True
                continue
        else:
            continue
        yield i, 2 * p0 + m0 - 2 * p1 + m1, -3 * p0 - 2 * m0 + 3 * p1 - m1, m0, p0, deriv


def _hermite_dip(t, t_end, start, end):
    """Where an indicator dips below zero inside the step by its interpolant
    (:func:`_hermite_pieces`): the lowest such point, or None."""
    length = t_end - t
    best = None
    for _, a, b, c, p0, deriv in _hermite_pieces(t, t_end, start, end):
        if deriv:  # the lowest point of the parabola p'
            xs = [-b / (3 * a)] if a > 0 else []
        else:  # the stationary points of the cubic
            xs = _real_roots([3 * a, 2 * b, c], 0.0, 1.0)
        for x in xs:
            value = ((3 * a * x + 2 * b) * x + c) / length if deriv else ((a * x + b) * x + c) * x + p0
            if 0 < x < 1 and value < 0 and (best is None or value < best[0]):
                best = (value, t + x * length)
    return None if best is None else best[1]


def _hermite_root(t, t_end, start, end, indices, within=None, near=None):
    """The first zero inside the step of the interpolants (:func:`_hermite_pieces`) of the
    indicators ``indices``: a first estimate of the event time, or None. With ``within``
    ``(lo, hi)``: the zero in that interval (which the interpolant may extrapolate to) nearest
    to ``near``."""
    lo, hi = (t, t_end) if within is None else within
    length = t_end - t
    best = None
    for i, a, b, c, p0, deriv in _hermite_pieces(t, t_end, start, end):
        if i not in indices:
            continue
        coefficients = [3 * a, 2 * b, c] if deriv else [a, b, c, p0]
        if not any(coefficients[:-1]):
            continue
        for x in _real_roots(coefficients, (lo - t) / length - 1.0, (hi - t) / length + 1.0):
            s = t + x * length
            if not lo < s < hi:
                continue
            key = s if near is None else abs(s - near)
            if best is None or key < best[0]:
                best = (key, s)
    return None if best is None else best[1]


def _real_roots(coefficients, x_lo, x_hi) -> list:
    """The real roots in ``(x_lo, x_hi)`` of the polynomial of degree <= 3 with ``coefficients``
    (highest power first), ascending: the quadratic formula in its stable form, and a cubic's
    roots one per monotone piece between its stationary points by Newton's method kept inside a
    bracket that halves where Newton does not. (``np.roots`` forms and solves the companion
    matrix's eigenvalue problem: 80 us a call, a dozen times a step's scalar work here.)"""
    c = [float(v) for v in coefficients]
    while c and c[0] == 0.0:
        c.pop(0)
    if len(c) <= 1:
        return []
    if len(c) == 2:
        roots = [-c[1] / c[0]]
    elif len(c) == 3:
        a, b, k = c
        disc = b * b - 4 * a * k
        if disc < 0:
            return []
        q = -0.5 * (b + math.copysign(math.sqrt(disc), b))
        roots = [q / a] + ([k / q] if q != 0 else [])
    else:
        a, b, k, d = c

        def p(x):
            return ((a * x + b) * x + k) * x + d

        cuts = [x_lo] + [x for x in _real_roots([3 * a, 2 * b, k], x_lo, x_hi)] + [x_hi]
        roots = []
        for u, w in zip(cuts[:-1], cuts[1:]):
            pu, pw = p(u), p(w)
            if pu == 0.0:
                roots.append(u)
            if pu * pw >= 0:
                continue
            x = 0.5 * (u + w)
            for _ in range(100):
                px = p(x)
                if px == 0.0:
                    break
                if (px < 0) == (pu < 0):
                    u = x
                else:
                    w = x
                slope = (3 * a * x + 2 * b) * x + k
                step = px / slope if slope != 0 else math.inf
                x_new = x - step
                if not u < x_new < w:
                    x_new = 0.5 * (u + w)
                if x_new == x or w - u <= 2 * np.finfo(float).eps * max(abs(u), abs(w)):
                    x = x_new
                    break
                x = x_new
            roots.append(x)
    return sorted(x for x in roots if x_lo < x < x_hi)


def _illinois(phi, lo, hi, f_lo=None, f_hi=None, predict=None):
    """The upper end of a bracket ``[lo, hi]`` of the root of ``phi`` (``phi(lo) >= 0 > phi(hi)``;
    ``f_lo``, ``f_hi``: the values there if known) shrunk to the rounding of ``hi``.

    Each trial is ``predict(lo, hi, s1, s2)`` (an estimate of the root inside the bracket from what
    is known at the latest two points ``s1``, ``s2``: here the cubic Hermite interpolant of the
    indicators' values and rates, or of their integrals and values, through them) where it gives one,
    else the secant through the two latest points, else Illinois' regula falsi; a trial closer than
    the rounding tolerance to the latest point steps that tolerance across it, so that the bracket
    closes round the root."""
    f_lo = phi(lo) if f_lo is None else f_lo
    f_hi = phi(hi) if f_hi is None else f_hi
    latest = [(lo, f_lo), (hi, f_hi)]
    side = 0
    for k in range(200):
        tol = 4 * np.finfo(float).eps * max(abs(lo), abs(hi))
        if hi - lo <= tol:
            break
        (s1, f1), (s2, f2) = latest[-2:]
        s = predict(lo, hi, s1, s2) if predict is not None and k < 20 else None
        if s is None or not lo < s < hi:
            s = s2 - f2 * (s2 - s1) / (f2 - f1) if f2 != f1 and k < 40 else None
        if s is not None and abs(s - s2) < tol:
            s = s2 + np.copysign(tol, s - s2)
        if s is None or not lo < s < hi:
            s = hi - f_hi * (hi - lo) / (f_hi - f_lo) if f_hi != f_lo else 0.5 * (lo + hi)
            s = min(max(s, lo + 0.25 * tol), hi - 0.25 * tol)
            if not lo < s < hi:
                s = 0.5 * (lo + hi)
                if not lo < s < hi:
                    break
        f = phi(s)
        latest.append((s, f))
        if f >= 0:  # (0: the status has not changed yet -- a velocity of exactly 0 is no reversal)
            lo, f_lo = s, f
            if side == 1:
                f_hi *= 0.5
            side = 1
        else:
            hi, f_hi = s, f
            if side == -1:
                f_lo *= 0.5
            side = -1
    return hi


def _step_count(t0: float, stop: float, h: float, n_outputs: int = 0, bytes_per_value: float = 8.0) -> int:
    """The number of communication steps ``n`` from ``t0`` to ``stop`` (the last ``t0 + n h <=
    stop`` within rounding), refused before anything is allocated when the points are not distinct
    in floating point or the recorded grid, ``(n + 1) (n_outputs + 1)`` values of
    ``bytes_per_value`` bytes each, does not fit in the available memory."""
    rounding = 4 * np.finfo(float).eps * max(abs(t0), abs(stop))
    if h <= rounding:
        raise ParameterError(f"step must be above the rounding of the times ({rounding:.3g} s at start_time = "
                             f"{t0!r} s, stop_time = {stop!r} s), got {h!r}: the communication points would not "
                             "be distinct")
    span = (stop - t0) / h  # finite: h > eps |t|
    if span * (1 + 1e-12) + 1e-9 < 1:
        raise ParameterError(f"stop_time must be at least one step ({h!r} s) after start_time, got {stop!r}")
    grid = (span + 2) * (n_outputs + 1) * bytes_per_value  # the times and the outputs
    free = available_memory()
    if free is not None and grid > free:
        raise ParameterError(f"stop_time = {stop!r} s with step = {h!r} s is {span:.3g} communication steps, whose "
                             f"recorded times and {n_outputs} output(s) take {grid / 2 ** 30:.3g} GiB, beyond the "
                             f"{free / 2 ** 30:.3g} GiB of memory available: take a longer step or a shorter run")
    return int(np.floor(span * (1 + 1e-12) + 1e-9))
