"""A stepped run of the Coulomb oscillator: the state a co-simulation step needs.

:class:`OscillatorRun` is what an FMU instance of the oscillator is: parameters, the exact
single-DOF kernel and its state, a held external force, and the cumulative outputs (dissipated energy, event
count). ``advance(t)`` marches exactly to ``t`` (events located inside, whatever the step).
The FMU slave (:mod:`frictionjoint.fmi.slaves`) maps FMI variables onto it, and the direct
sweep drives the same object without the FMU layer.
"""
from __future__ import annotations

import cmath
import math

import numpy as np

from .errors import ConvergenceError, ParameterError, check_positive, check_real
from .oscillator import CoulombOscillator
from .solvers.sdof.kernel import EventBudgetError, SdofCoulomb
from .solvers.sdof.steady import exp_integral, sdof_orbit, sdof_piece_fourier

__all__ = ["OscillatorRun", "OSCILLATOR_PARAMETERS", "OSCILLATOR_OUTPUTS", "run_parameters"]

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
    "start_on_orbit": (False, "start on the periodic steady state (x0, v0 are then only the initial guess "
                              "of its shooting): no transient to march; outputs orbit_found, monodromy_*"),
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
    "orbit_found": (bool, "true when start_on_orbit found the periodic steady state (the run starts on it)"),
    "monodromy_xx": (float, "d x(ts + T) / d x(ts), Jacobian of the period map at the orbit's section time ts (start_on_orbit; else 0)"),
    "monodromy_xv": (float, "d x(ts + T) / d v(ts) [s] (start_on_orbit; else 0)"),
    "monodromy_vx": (float, "d v(ts + T) / d x(ts) [1/s] (start_on_orbit; else 0)"),
    "monodromy_vv": (float, "d v(ts + T) / d v(ts) (start_on_orbit; else 0)"),
}
#: the quantities integrated piece by piece with ``harmonics`` on (the rows of the integrals, in order)
_INTEGRALS = ("x", "v", "friction_force")


def run_parameters(table: dict, parameters: dict) -> dict:
    """A stepped run's parameters: ``parameters`` over the defaults of ``table`` (name -> (default,
    description), e.g. :data:`OSCILLATOR_PARAMETERS`); a name not in ``table`` is a
    :class:`ParameterError` that lists the allowed ones."""
    unknown = set(parameters) - set(table)
    if unknown:
        raise ParameterError(f"unknown parameter(s) {sorted(unknown)}; allowed: {sorted(table)}")
    p = {k: v[0] for k, v in table.items()}
    p.update(parameters)
    return p


class OscillatorRun:
    """The Coulomb oscillator from a start time, stepped exactly with a held external force.

    It runs on the closed-form single-DOF kernel (:class:`~frictionjoint.solvers.sdof.kernel.SdofCoulomb`):
    a held force ``F_h`` only moves the spring's rest position (``x = x~ + F_h / k``), so the kernel
    marches ``x~`` and the outputs shift it back. Every extreme of ``x`` is at a piece end (a slip
    piece ends where ``v = 0``), and the Fourier integrals are closed forms per piece
    (:func:`~frictionjoint.solvers.sdof.steady.sdof_piece_fourier`; ``int v e^{iwt}`` by parts).

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
        self.parameters = p = run_parameters(OSCILLATOR_PARAMETERS, parameters)
        self._osc = None
        base = check_real("base_amplitude", p["base_amplitude"])
        stiffness = check_positive("stiffness", p["stiffness"])
        # force and base motion act in phase on the mass: P0 = P + k Y (CoulombOscillator's model)
        self._kernel = SdofCoulomb(p["mass"], stiffness, p["slip_force"],
                                   check_real("force_amplitude", p["force_amplitude"]) + stiffness * base,
                                   p["omega"], p["damping"])
        self.t = check_real("start_time", start_time)
        self.x = check_real("x0", p["x0"])
        self.v = check_real("v0", p["v0"])
        self.force = 0.0
        self.hold(force)
        self.orbit_found, self.monodromy = False, np.zeros((2, 2))
        if p["start_on_orbit"]:
            self._start_on_orbit()
        self.v_scale = abs(self.v)
        self.event_count = self.stop_count = 0
        self.status = 1 if self.v > 0 else (-1 if self.v < 0 else self._settle(0))
        self.dissipated_energy = 0.0
        self.harmonics = bool(p["harmonics"])
        self.integrals = np.zeros((len(_INTEGRALS), 2))  # [cos, sin] per integrand
        self.peak_x = abs(self.x) if self.harmonics else 0.0
        self._resettle = False

    @property
    def osc(self) -> CoulombOscillator:
        """The oscillator as a library model (built on first use: the run itself needs only the
        kernel)."""
        if self._osc is None:
            self._osc = CoulombOscillator(**{k: self.parameters[k] for k in _MODEL})
        return self._osc

    def _start_on_orbit(self) -> None:
        """Replace ``(x, v)`` by the periodic steady state at the start time: shooting on the
        kernel's exact period map from ``(x0, v0)`` as the guess at ``t = 0``, nothing evaluated on
        the orbit but its state (the library's ``steady_state`` where the kernel cannot answer)."""
        shift = self._shift  # the orbit of the kernel coordinates x~ = x - F_h / k
        try:
            orbit = sdof_orbit(self._kernel, self.x - shift, self.v, tol=1e-12, max_newton=25, max_periods=2000)
        except EventBudgetError:
            return  # the march is refused for its event count: so would steady_state's be, from the same start
        if orbit is not None:
            pmap, outcome, jac, _ = orbit
            t_s, (x, v) = pmap.t_s, (float(a) for a in outcome.z)
        else:
            res = self.osc.steady_state(self.x - shift, self.v)
            if not res.converged:
                return
            t_s, x, v = res.section_time, float(res.state[0]), float(res.state[1])
            try:  # at the orbit's section (a slipping state, where the period map is smooth)
                jac = self.osc.monodromy(t_s, x, v)
            except ConvergenceError:
                jac = None
        # along the orbit from its section to the start time (less than a period: it is periodic)
        dt = (self.t - t_s) % (2 * math.pi / self._kernel.omega)
        if dt > 0.0:
            end = self._kernel.march(t_s, x, v, t_s + dt)
            x, v = end.x, end.v
        self.x, self.v = x + shift, v
        self.orbit_found = True
        if jac is not None:
            self.monodromy = np.array(jac, dtype=float)

    def _settle(self, status: int) -> int:
        """Stick/slip status at rest (``v = 0``) by the kernel's rules; counts a change."""
        if self._kernel.slip_force == 0.0:
            return 0
        new = self._kernel.settle(self.t, self.x - self._shift, status, self.v_scale)
        if new != status:
            self.event_count += 1
        return new

    @property
    def _shift(self) -> float:
        return self.force / self._kernel.stiffness

    def hold(self, force: float) -> None:
        """Hold the external force ``force`` [N] from now on."""
        if not math.isfinite(force):
            raise ParameterError(f"force must be finite, got {force!r}")
        if force != self.force:
            self.force = float(force)
            self._resettle = True  # a mass at rest may start or stop slipping under the new force

    @property
    def time(self) -> float:
        """Current time [s]."""
        return self.t

    def advance(self, t_end: float, stop_at_event: bool = False) -> bool:
        """March exactly to ``t_end`` [s]; events inside are located exactly. With ``stop_at_event``,
        stop just after the first event before ``t_end`` (its rules applied). Returns whether it stopped
        there (:attr:`t` < ``t_end``)."""
        k = self._kernel
        if self._resettle and self.v == 0.0:
            self.status = self._settle(self.status)
        self._resettle = False
        if t_end <= self.t:
            return False
        shift = self._shift
        fs = k.slip_force
        on_piece = self._on_piece if self.harmonics else self._on_piece_energy
        res = k.march(self.t, self.x - shift, self.v, t_end, status=self.status if fs > 0 else None,
                      on_piece=on_piece, v_scale=self.v_scale, max_events=1 if stop_at_event else None)
        self.t, self.x, self.v, self.status, self.v_scale = res.t, res.x + shift, res.v, res.status, res.v_scale
        self.event_count += res.n_events
        self.stop_count += res.events["stick"]
        return res.t < t_end

    def _on_piece_energy(self, ta, xa, va, s, tb, xb, vb):
        if s != 0 and self._kernel.slip_force > 0:
            self.dissipated_energy += self._kernel.slip_force * abs(xb - xa)

    def _on_piece(self, ta, xa, va, s, tb, xb, vb):
        """Energy, peak and Fourier integrals of one closed-form piece (kernel coordinates)."""
        self._on_piece_energy(ta, xa, va, s, tb, xb, vb)
        k = self._kernel
        shift = self._shift
        self.peak_x = max(self.peak_x, abs(xb + shift))
        if tb <= ta:
            return
        w = k.omega
        e = exp_integral(1j * w, ta, tb)
        fx = sdof_piece_fourier(k, s, ta, xa, va, tb, w) + shift * e
        # int v e^{iwt} = [x e^{iwt}] - i w int x e^{iwt}
        fv = (xb + shift) * cmath.exp(1j * w * tb) - (xa + shift) * cmath.exp(1j * w * ta) - 1j * w * fx
        if k.slip_force == 0.0:
            ff = 0j
        elif s != 0:
            ff = s * k.slip_force * e
        else:  # holding force P cos(wt) + F_h - k x = P cos(wt) - k x~ (v = 0, stuck)
            p0 = k.force_amplitude
            ff = (0.5 * p0 * (exp_integral(2j * w, ta, tb) + (tb - ta))
                  - k.stiffness * (fx - shift * e))
        for row, val in enumerate((fx, fv, ff)):
            self.integrals[row, 0] += val.real
            self.integrals[row, 1] += val.imag

    def output(self, name: str):
        """Value of an output of :data:`OSCILLATOR_OUTPUTS` at the current time."""
        if name == "x":
            return float(self.x)
        if name == "v":
            return float(self.v)
        if name == "stuck":
            return bool(self.status == 0 and self._kernel.slip_force > 0)
        if name == "dissipated_energy":
            return self.dissipated_energy
        if name == "event_count":
            return self.event_count
        if name == "stop_count":
            return self.stop_count
        if name == "peak_x":
            return float(self.peak_x)
        if name.endswith("_integral"):
            kind, _, which = name[:-len("_integral")].rpartition("_")
            return float(self.integrals[_INTEGRALS.index(kind), 0 if which == "cos" else 1])
        if name == "orbit_found":
            return self.orbit_found
        if name.startswith("monodromy_"):
            i, j = ("xv".index(c) for c in name[-2:])
            return float(self.monodromy[i, j])
        if name == "friction_force":
            k = self._kernel
            if k.slip_force == 0.0:
                return 0.0
            if self.status != 0:
                return float(self.status * k.slip_force)
            return float(k.force_amplitude * math.cos(k.omega * self.t) + self.force - k.stiffness * self.x)
        raise ParameterError(f"output must be one of {sorted(OSCILLATOR_OUTPUTS)}, got {name!r}")

    def snapshot(self) -> dict:
        """The complete state as plain data (floats and a numpy array): the march's velocity
        scale (its event tolerances) included, so that a restored run continues bit for bit."""
        return {"t": self.t, "x": self.x, "v": self.v, "status": self.status, "v_scale": self.v_scale,
                "diss": self.dissipated_energy, "force": self.force, "resettle": self._resettle,
                "integrals": self.integrals.copy(), "peak_x": self.peak_x,
                "events": (self.event_count, self.stop_count)}

    def restore(self, snap: dict) -> None:
        """Return to a :meth:`snapshot`."""
        self.t, self.x, self.v, self.status = snap["t"], snap["x"], snap["v"], snap["status"]
        self.v_scale, self.dissipated_energy, self.force = snap["v_scale"], snap["diss"], snap["force"]
        self._resettle = snap["resettle"]
        self.integrals, self.peak_x = snap["integrals"].copy(), snap["peak_x"]
        self.event_count, self.stop_count = snap["events"]

