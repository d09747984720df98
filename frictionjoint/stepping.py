"""A stepped run of the Coulomb oscillator: the state a co-simulation step needs.

:class:`OscillatorRun` is what an FMU instance of the oscillator is: parameters, the exact marcher
and its state, a held external force, and the cumulative outputs (dissipated energy, event
count). ``advance(t)`` marches exactly to ``t`` (events located inside, whatever the step).
The FMU slave (:mod:`frictionjoint.fmi.slaves`) maps FMI variables onto it, and the direct
sweep drives the same object without the FMU layer.
"""
from __future__ import annotations

import math

import numpy as np

from .errors import ParameterError
from .oscillator import CoulombOscillator
from .solvers.events import EventLog, MarchState
from .solvers.propagator import Observables
from .solvers.response import piece_fourier, piece_peaks

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
    "harmonics": (False, "integrate the Fourier integrals and the peak of |x| (outputs *_integral, "
                         "peak_x) exactly, piece by piece, from the start"),
}
#: parameters of the oscillator itself (not of the run)
_MODEL = ("mass", "stiffness", "damping", "slip_force", "force_amplitude", "omega", "base_amplitude")
#: output name -> (type, description with unit)
OSCILLATOR_OUTPUTS = {
    "x": (float, "displacement of the mass [m]"),
    "v": (float, "velocity of the mass [m/s]"),
    "friction_force": (float, "friction force on the mass, restoring convention [N]"),
    "stuck": (bool, "true while the mass sticks"),
    "dissipated_energy": (float, "energy dissipated by friction since the start [J]"),
    "event_count": (int, "number of stick/slip events since the start"),
    "stop_count": (int, "number of stops of finite duration (slip -> stick) since the start"),
    "peak_x": (float, "max |x| since the start, exact (harmonics on; else 0) [m]"),
    "x_cos_integral": (float, "integral of x(t) cos(omega t) dt since the start, exact (harmonics on) [m s]"),
    "x_sin_integral": (float, "integral of x(t) sin(omega t) dt since the start, exact (harmonics on) [m s]"),
    "v_cos_integral": (float, "integral of v(t) cos(omega t) dt since the start, exact (harmonics on) [m]"),
    "v_sin_integral": (float, "integral of v(t) sin(omega t) dt since the start, exact (harmonics on) [m]"),
    "friction_force_cos_integral": (float, "integral of the friction force times cos(omega t) dt since the "
                                           "start, exact (harmonics on) [N s]"),
    "friction_force_sin_integral": (float, "integral of the friction force times sin(omega t) dt since the "
                                           "start, exact (harmonics on) [N s]"),
}
#: the quantities integrated piece by piece with ``harmonics`` on (the rows of the integrals, in order)
_INTEGRALS = ("x", "v", "friction_force")


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
        self.osc = CoulombOscillator(**{k: p[k] for k in _MODEL})
        self._marcher = self.osc._marcher
        self.force = 0.0
        self.hold(force)
        self.log = EventLog()
        self.state = self._marcher.initial_state(p["x0"], p["v0"], t0=start_time, log=self.log)
        self.dissipated_energy = 0.0
        self.harmonics = bool(p["harmonics"])
        self.integrals = np.zeros((len(_INTEGRALS), 2))  # [cos, sin] per integrand
        self.peak_x = np.abs(self.state.x).copy() if self.harmonics else np.zeros(1)

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

        m = self._marcher
        w = self.osc.omega

        def integrands(itv):
            # rows x, v (of the oscillator's DOF) and its slider's friction force
            force = m.force_observables(itv)
            n = m.system.n_dof
            zero = np.zeros(n)
            unit = np.eye(n)[0]
            return itv.reduce(Observables([unit, zero, force.ax[0]], [zero, unit, force.av[0]],
                                          [zero, zero, force.af[0]], [0.0, 0.0, force.a0[0]]))

        def on_piece(itv, tau):
            if itv.status.size and itv.status[0] != 0:
                x1, _ = itv.state(tau)
                self.dissipated_energy += fs * abs(float(x1[0, 0]) - float(itv.x0[0]))
            if self.harmonics and tau > 0:
                piece_peaks(itv, tau, self.peak_x)
                c, s_ = piece_fourier(itv, tau, w, integrands(itv))
                self.integrals[:, 0] += c
                self.integrals[:, 1] += s_

        m.march(self.state, t_end, self.log, on_interval=on_piece)

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
        if name == "stop_count":
            return self.log.count("stick")
        if name == "peak_x":
            return float(self.peak_x[0])
        if name.endswith("_integral"):
            kind, _, which = name[:-len("_integral")].rpartition("_")
            return float(self.integrals[_INTEGRALS.index(kind), 0 if which == "cos" else 1])
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
                "integrals": self.integrals.copy(), "peak_x": self.peak_x.copy(),
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
        self.integrals, self.peak_x = snap["integrals"].copy(), snap["peak_x"].copy()
        self._marcher.v_scale = snap["v_scale"]
        self.hold(snap["force"])
