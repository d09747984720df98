"""A stepped run of the Coulomb oscillator: the state a co-simulation step needs.

:class:`OscillatorRun` is what an FMU instance of the oscillator is: parameters, the exact marcher
and its state, a held external force, and the cumulative outputs (dissipated energy, event
count). ``advance(t)`` marches exactly to ``t`` (events located inside, whatever the step).
The FMU slave (:mod:`frictionjoint.fmi.slaves`) maps FMI variables onto it, and the direct
sweep drives the same object without the FMU layer.
"""
from __future__ import annotations

import math

from .errors import ParameterError
from .oscillator import CoulombOscillator
from .solvers.events import EventLog, MarchState

__all__ = ["OscillatorRun", "OSCILLATOR_PARAMETERS", "OSCILLATOR_OUTPUTS"]

#: parameter name -> (default, description with unit). The defaults are the README's case (m = k = 1,
#: P0 = 1 N, F/P0 = 0.5) at r = 1.5, a stop-free steady state (Den Hartog), so that the FMU dropped
#: into a host with its defaults does something meaningful.
OSCILLATOR_PARAMETERS = {
    "mass": (1.0, "mass m [kg], > 0"),
    "stiffness": (1.0, "spring k to the base [N/m], > 0"),
    "damping": (0.0, "viscous damper to the ground [N s/m], >= 0"),
    "slip_force": (0.5, "Coulomb friction force limit F [N], >= 0"),
    "force_amplitude": (1.0, "amplitude of the force force_amplitude*cos(omega t) on the mass [N]"),
    "omega": (1.5, "excitation angular frequency [rad/s], > 0"),
    "base_amplitude": (0.0, "amplitude of the base motion base_amplitude*cos(omega t) [m]"),
    "x0": (0.0, "displacement at the start time [m]"),
    "v0": (0.0, "velocity at the start time [m/s]"),
}
#: output name -> (type, description with unit)
OSCILLATOR_OUTPUTS = {
    "x": (float, "displacement of the mass [m]"),
    "v": (float, "velocity of the mass [m/s]"),
    "friction_force": (float, "friction force on the mass, restoring convention [N]"),
    "stuck": (bool, "true while the mass sticks"),
    "dissipated_energy": (float, "energy dissipated by friction since the start [J]"),
    "event_count": (int, "number of stick/slip events since the start"),
}


class OscillatorRun:
    """The Coulomb oscillator from a start time, stepped exactly with a held external force.

    Parameters
    ----------
    parameters : dict
        Values for :data:`OSCILLATOR_PARAMETERS` (defaults for the missing ones).
    start_time : float
        Start time [s]; the harmonic excitation is ``cos(omega t)`` in absolute time.
    force : float
        External force on the mass [N], held until changed by :meth:`hold`.
    """

    def __init__(self, parameters: dict, start_time: float = 0.0, force: float = 0.0):
        unknown = set(parameters) - set(OSCILLATOR_PARAMETERS)
        if unknown:
            raise ParameterError(f"unknown parameter(s) {sorted(unknown)}; allowed: {sorted(OSCILLATOR_PARAMETERS)}")
        p = {k: v[0] for k, v in OSCILLATOR_PARAMETERS.items()}
        p.update(parameters)
        self.parameters = p
        self.osc = CoulombOscillator(**{k: p[k] for k in p if k not in ("x0", "v0")})
        self._marcher = self.osc._marcher
        self.force = 0.0
        self.hold(force)
        self.log = EventLog()
        self.state = self._marcher.initial_state(p["x0"], p["v0"], t0=start_time, log=self.log)
        self.dissipated_energy = 0.0

    def hold(self, force: float) -> None:
        """Hold the external force ``force`` [N] from now on."""
        if not math.isfinite(force):
            raise ParameterError(f"force must be finite, got {force!r}")
        if force != self.force or self._marcher.held_force is None:
            self._marcher.set_held_force([force])
            self.force = float(force)

    @property
    def time(self) -> float:
        """Current time [s]."""
        return self.state.t

    def advance(self, t_end: float) -> None:
        """March exactly to ``t_end`` [s]; events inside are located exactly."""
        fs = self.osc.slip_force

        def dissipate(itv, tau):
            if itv.status.size and itv.status[0] != 0:
                x1, _ = itv.state(tau)
                self.dissipated_energy += fs * abs(float(x1[0, 0]) - float(itv.x0[0]))

        self._marcher.march(self.state, t_end, self.log, on_interval=dissipate)

    def output(self, name: str):
        """Value of an output of :data:`OSCILLATOR_OUTPUTS` at the current time."""
        st = self.state
        if name == "x":
            return float(st.x[0])
        if name == "v":
            return float(st.v[0])
        if name == "stuck":
            return bool(st.status.size and st.status[0] == 0)
        if name == "dissipated_energy":
            return self.dissipated_energy
        if name == "event_count":
            return len(self.log)
        if name == "friction_force":
            m = self._marcher
            itv = m.interval(st)
            val = itv.start_values(itv.reduce(m.force_observables(itv)))[0]
            return float(val[0]) if val.size else 0.0
        raise ParameterError(f"output must be one of {sorted(OSCILLATOR_OUTPUTS)}, got {name!r}")

    def snapshot(self) -> dict:
        """The complete state as plain data (floats, lists, numpy arrays)."""
        st, log = self.state, self.log
        return {"t": st.t, "x": st.x.copy(), "v": st.v.copy(), "w": st.w.copy(), "status": st.status.copy(),
                "diss": self.dissipated_energy, "force": self.force,
                # the marcher's velocity scale sets its event tolerances: part of the state, so
                # that a restored run continues bit for bit as the original did
                "v_scale": self._marcher.v_scale,
                "log": (list(log.time), list(log.element), list(log.slider), list(log.kind))}

    def restore(self, snap: dict) -> None:
        """Return to a :meth:`snapshot`."""
        self.state = MarchState(snap["t"], snap["x"], snap["v"], snap["w"], snap["status"])
        log = EventLog()
        log.time, log.element, log.slider, log.kind = (list(a) for a in snap["log"])
        self.log = log
        self.dissipated_energy = snap["diss"]
        self._marcher.v_scale = snap["v_scale"]
        self.hold(snap["force"])
