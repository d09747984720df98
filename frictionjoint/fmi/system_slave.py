"""A whole friction system as one FMU: the run an instance is, and the pythonfmu slave.

The FMU carries a system definition (:mod:`frictionjoint.system_file`) in its resources.
:class:`SystemRun` is what an instance is: the definition's
:class:`~frictionjoint.system.FrictionSystem` (with the FMU's parameter values), the library's exact
event-driven :class:`~frictionjoint.solvers.marcher.events.Marcher` on it, the external force
inputs held over a step (the marcher's held force) and the cumulative outputs (friction energy,
events). ``advance(t)`` marches exactly to ``t``: the events are located inside the step, so the
outputs at a communication point are those of :func:`frictionjoint.simulate` of the same system
whatever the communication step (to rounding: a step's end splits a closed-form piece).
:class:`SystemSlave` maps FMI variables onto it, as :class:`~frictionjoint.fmi.slaves.BladeDovetailSlave`
does onto its run (the step, its refusals and the FMU state are :class:`~frictionjoint.fmi.slaves._RunSlave`'s).
"""
from __future__ import annotations

import json
import math
import os

import numpy as np

# imported here, not inside methods: see frictionjoint.fmi.slaves
from ..errors import ParameterError, check_real
from ..solvers.marcher.eventlog import MarchState
from ..solvers.marcher.events import EventLog, Marcher
from ..solvers.marcher.response import piece_slip
from ..system_file import SystemDefinition
from ..threads import owns_blas_threads
from .slaves import _RunSlave

__all__ = ["SystemRun", "SystemSlave", "SYSTEM_RESOURCE"]

#: file name of the system definition in a system FMU's resources
SYSTEM_RESOURCE = "system.json"


def system_outputs(definition: SystemDefinition) -> dict:
    """The FMU's outputs of ``definition``: name -> (type, description with unit)."""
    out = {}
    for dof in definition.displacement:
        out[f"x_{dof}"] = (float, f"displacement of {dof} [m]")
    for dof in definition.velocity:
        out[f"v_{dof}"] = (float, f"velocity of {dof} [m/s]")
    for name in definition.joint_force:
        out[f"force_{name}"] = (float, f"force of joint {name} along its DOF or direction, restoring convention "
                                       "(a dovetail: its two flanks' friction forces summed) [N]")
    out["dissipated_energy"] = (float, "energy dissipated by friction since the start [J]")
    out["event_count"] = (int, "number of stick/slip events since the start")
    return out


class SystemRun:
    """A system definition's friction system from a start time, from rest, stepped exactly with
    held external forces.

    Parameters
    ----------
    definition : SystemDefinition
    parameters : dict
        Values of :meth:`SystemDefinition.parameters` (the definition's for the missing ones).
    start_time : float
        Start time [s]; the excitation is ``cos(omega t)`` in absolute time.
    forces : sequence of float
        External force on each of the definition's ``inputs`` [N], held until :meth:`hold`.
    """

    def __init__(self, definition: SystemDefinition, parameters: dict, start_time: float = 0.0,
                 forces=()):
        self.definition = definition
        # Jenkins springs stiff enough for their rigid limit to be exact are marched rigid, as
        # frictionjoint.simulate marches them (FrictionSystem.rigid_limit)
        self.system = definition.system(parameters).rigid_limit()[0]
        self.marcher = Marcher(self.system)
        st = self.system.structure
        self._input_rows = [st.dof_index(d) for d in definition.inputs]
        self._joint_index = {j.name: i for i, j in enumerate(definition.joints)}
        self.t = check_real("start_time", start_time)
        self.held_forces = (0.0,) * len(self._input_rows)
        self.hold(forces if len(forces) else self.held_forces)
        n = self.system.n_dof
        self.log = EventLog()  # with the events of the start's settling, as frictionjoint.simulate's
        self.state = self.marcher.initial_state(np.zeros(n), np.zeros(n), None, t0=self.t, log=self.log)
        self.itv = None
        self.dissipated_energy = 0.0

    def hold(self, forces) -> None:
        """Hold the external forces (one per input DOF) [N] from now on (finite); the same forces
        again change nothing."""
        f = tuple(check_real(f"force_{d}", v) for d, v in zip(self.definition.inputs, forces))
        if len(f) != len(self._input_rows):
            raise ParameterError(f"forces must give one value per input DOF {list(self.definition.inputs)}, "
                                 f"got {list(forces)!r}")
        if f == self.held_forces:
            return
        self.held_forces = f
        vector = np.zeros(self.system.n_dof)
        vector[self._input_rows] = f
        self.marcher.set_held_force(vector if any(f) else None)
        self.itv = None  # holding forces may have jumped: settle again

    def _on_interval(self, itv, tau_end) -> None:
        if tau_end > 0:
            x1 = itv.state(tau_end)[0][:, 0]
            self.dissipated_energy += piece_slip(self.system, itv, tau_end, x1 - itv.x0)[1]

    def _march(self, t_end: float, max_events=None) -> None:
        """March exactly to ``t_end`` (after the current time), accumulating the outputs; with
        ``max_events``, stop just after that many events (:meth:`Marcher.march`)."""
        self.itv = self.marcher.march(self.state, t_end, self.log, on_interval=self._on_interval, itv=self.itv,
                                      max_events=max_events)
        self.t = self.state.t if self.state.t < t_end else t_end

    @owns_blas_threads
    def advance(self, t: float, stop_at_event: bool = False) -> bool:
        """March exactly to time ``t`` [s] (>= the current time; events inside). With
        ``stop_at_event``, stop just after the first event before ``t`` (its rules applied; FMI 3
        early return). Returns whether it stopped there (:attr:`t` < ``t``); marching on from there
        to ``t`` gives the state of the march without the stop, bit for bit."""
        t = check_real("t", t)
        if t < self.t:
            raise ParameterError(f"t must be >= the current time {self.t!r}, got {t!r}")
        if t > self.t:
            self._march(t, 1 if stop_at_event else None)
        return self.t < t

    def joint_forces(self) -> np.ndarray:
        """Each joint's force at the current time [N], restoring convention (the sum of its
        sliders' forces; 0 for a joint with no slider)."""
        if self.itv is None:
            self.itv = self.marcher.settle(self.state, self.log)
        itv = self.itv
        red = itv.reduce(self.marcher.force_observables(itv))
        sliders = itv.evaluate(red, np.zeros(1))[0][:, 0]
        return np.bincount(self.system.slider_owner, weights=sliders, minlength=len(self.definition.joints))

    def output(self, name: str):
        """The output ``name`` of :func:`system_outputs` at the current time."""
        st = self.system.structure
        if name == "dissipated_energy":
            return float(self.dissipated_energy)
        if name == "event_count":
            return len(self.log)
        if name.startswith("x_") or name.startswith("v_"):
            return float((self.state.x if name[0] == "x" else self.state.v)[st.dof_index(name[2:])])
        if name.startswith("force_") and name[6:] in self._joint_index:
            return float(self.joint_forces()[self._joint_index[name[6:]]])
        raise ParameterError(f"unknown output {name!r}; allowed: {sorted(system_outputs(self.definition))}")

    def snapshot(self) -> dict:
        """The run's complete state (copied), for :meth:`restore`."""
        st = self.state
        return {"t": self.t, "x": st.x.copy(), "v": st.v.copy(), "w": st.w.copy(), "status": st.status.copy(),
                "v_scale": st.v_scale, "diss": self.dissipated_energy, "events": len(self.log),
                "held_forces": self.held_forces}

    def restore(self, snap: dict) -> None:
        """Back to a state from :meth:`snapshot` (its events beyond it forgotten)."""
        self.state = MarchState(snap["t"], snap["x"].copy(), snap["v"].copy(), snap["w"].copy(),
                                snap["status"].copy(), snap["v_scale"])
        self.t = snap["t"]
        self.dissipated_energy = snap["diss"]
        for lst in (self.log.time, self.log.element, self.log.slider, self.log.kind):
            del lst[snap["events"]:]
        self.hold(snap["held_forces"])
        self.itv = None  # the piece of another state: settle again


class SystemSlave(_RunSlave):
    """A system definition (in the FMU's resources) marched exactly inside ``do_step``
    (:class:`SystemRun`): parameters ``omega``, ``force_amplitude_<dof>``, ``<joint>_<parameter>``;
    inputs ``force_<dof>`` (held over a step); outputs of :func:`system_outputs`."""

    description = ("Linear structure with friction joints (Jenkins, Coulomb, Iwan, dovetail) under harmonic and "
                   "held external forces; exact event-driven stick/slip located inside do_step")
    #: the held inputs, as one tuple (the property below): _RunSlave holds and restores it
    _held = "held_forces"
    # the README's chain: about 1.1 ms per period (8 events, 1.5 cycles of the excitation and the
    # structure's lowest frequency): 5000 cycles take about 4 s
    max_cycles = 5000.0

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        with open(os.path.join(kwargs["resources"], SYSTEM_RESOURCE)) as f:
            self._definition = d = SystemDefinition.from_dict(json.load(f))
        for name, (default, text) in d.parameters().items():
            self._parameter(name, default, text)
        for dof in d.inputs:
            self._input(f"force_{dof}", 0.0, f"external force on {dof}, added to the harmonic one, held over "
                        "a step [N]")
        for name, (kind, text) in system_outputs(d).items():
            self._output(name, text, kind=kind)
        self._run = None

    @property
    def held_forces(self) -> tuple:
        """The inputs ``force_<dof>`` [N], in the definition's order."""
        return tuple(getattr(self, f"force_{dof}") for dof in self._definition.inputs)

    @held_forces.setter
    def held_forces(self, values) -> None:
        for dof, value in zip(self._definition.inputs, values):
            setattr(self, f"force_{dof}", float(value))

    def _initialise(self):
        params = {k: getattr(self, k) for k in self._definition.parameters()}
        self._run = SystemRun(self._definition, params, start_time=self.start_time, forces=self.held_forces)
        freqs = self._run.system.structure.natural_frequencies()
        positive = freqs[freqs > 0]
        self._natural = float(positive[0]) if positive.size else 0.0

    def _cycle_rate(self):
        return (self._run.system.omega + self._natural) / (2 * math.pi)

    def _idle(self, name):
        return 0 if name == "event_count" else 0.0
