"""A stepped run of a blade on its dovetail root: the state a co-simulation step needs.

:class:`BladeRun` is what an instance of ``BladeDovetail.fmu`` is: a blade model definition
(:mod:`.models`) assembled with its root (:meth:`BladeAssembly.from_model`) under the run's
parameters, the exact event-driven marcher on it, a held tip force, and the cumulative outputs
(friction energy, events, the first-harmonic integrals of the tip displacement). ``advance(t)``
marches exactly to ``t`` (events located inside, whatever the step). The FMU slave
(:mod:`frictionjoint.fmi.slaves`) maps FMI variables onto it.

With ``start_on_orbit`` the run starts on the periodic steady state (the library's shooting,
:func:`~frictionjoint.solvers.marcher.steady.periodic_response`, exact Jacobian), so that one period marched
from the start gives the steady first harmonic: a sweep through the FMU
(:func:`frictionjoint.sweep.sweep` of ``BladeDovetail.fmu``) and the library's sweep of the same
definition (:meth:`BladeAssembly.frequency_response`) answer the same. As that sweep, a run may start
its shooting from the previous point's orbit (``orbit_guess``; the FMU keeps it between its
initialisations with ``start_from_last_orbit``), from rest where that does not converge.

What a run builds that depends on the definition, ``n_modes`` and ``rotor_speed`` only (the blade's
finite elements and their Craig-Bampton reduction) is built once per process (:func:`_reduced`):
an FMU's instance is constructed anew at every reset, and a sweep resets once per frequency.
"""
from __future__ import annotations

import math
from collections import OrderedDict

import numpy as np

from ..threads import owns_blas_threads
from ..elements.dovetail import FLANK_OUTPUTS
from ..errors import ParameterError, check_bool, check_positive, check_real
from ..solvers.marcher.eventlog import MarchState
from ..solvers.marcher.events import EventLog, Marcher
from ..solvers.marcher.response import displacement_fourier, piece_slip
from ..solvers.steady_state import periodic_response
from ..stepping import run_parameters
from .assembly import BladeAssembly

__all__ = ["BladeRun", "blade_parameters", "BLADE_OUTPUTS"]

#: output name -> (type, description with unit)
BLADE_OUTPUTS = {
    "tip_displacement": (float, "tip displacement of the blade along the excitation [m]"),
    "tip_velocity": (float, "tip velocity [m/s]"),
    "root_tangential": (float, "tangential root displacement X from the static state [m]"),
    "root_radial": (float, "radial root displacement Y from the static state, outward [m]"),
    "root_rocking": (float, "root rocking theta (the blade's slope at the root) [rad]; 0 without rocking"),
    **FLANK_OUTPUTS,
    "lifted_right": (bool, "true while the right flank is lifted off (normal_load_variation)"),
    "lifted_left": (bool, "true while the left flank is lifted off (normal_load_variation)"),
    "dissipated_energy": (float, "energy dissipated by friction since the start [J]"),
    "event_count": (int, "number of stick/slip/lift-off events since the start"),
    "tip_cos_integral": (float, "integral of tip_displacement cos(omega t) dt since the start, exact [m s]"),
    "tip_sin_integral": (float, "integral of tip_displacement sin(omega t) dt since the start, exact [m s]"),
    "orbit_found": (bool, "true when start_on_orbit found the periodic steady state (the run starts on it)"),
}


def blade_parameters(model) -> dict:
    """The run's parameters with their defaults from the definition ``model``
    (:class:`~frictionjoint.structures.BladeModel`): name -> (default, description with unit)."""
    root = model.root
    return {
        "omega": (2000.0, "excitation angular frequency [rad/s], > 0"),
        "rotor_speed": (float(model.blade_parameters.get("rotor_speed", 0.0)),
                        "rotor speed [rad/s], > 0: centrifugal stiffening of the blade and, unless "
                        "centrifugal_force > 0, the root's load"),
        "centrifugal_force": (0.0, "root load Fc [N], >= 0; 0: the blade's centrifugal force at rotor_speed"),
        "friction_coefficient": (float(root.get("friction_coefficient", 0.3)), "flank friction coefficient mu, > 0"),
        "flank_angle": (float(root.get("flank_angle", math.radians(30.0))),
                        "angle between the flank normal and the radial axis [rad], in [0, pi/2)"),
        "normal_load_variation": (False, "the flanks' slip limits follow their normal loads, with lift-off; "
                                         "false: slip limits from the static normal load"),
        "n_modes": (5, "fixed-interface modes of the Craig-Bampton blade, >= 0"),
        "tip_force_amplitude": (float(model.excitation.get("tip_force_amplitude", 1.0)),
                                "amplitude of the tip force tip_force_amplitude cos(omega t) [N]"),
        "start_on_orbit": (False, "start on the periodic steady state (shooting at initialisation): no "
                                  "transient to march; output orbit_found"),
        "start_from_last_orbit": (False, "with start_on_orbit: the shooting starts from the orbit this instance "
                                         "found at its last initialisation with the same other parameters (a "
                                         "stepped sweep's continuation), from rest where there is none or it does "
                                         "not converge from there; false: from rest"),
    }


#: (definition, n_modes, rotor_speed) -> the definition's assembly (:meth:`BladeAssembly.from_model`),
#: the most recently used :data:`_REDUCED_SIZE` (see :func:`_reduced`)
_REDUCED: OrderedDict = OrderedDict()
_REDUCED_SIZE = 8


def _reduced(model, n_modes: int, rotor_speed: float) -> BladeAssembly:
    """``BladeAssembly.from_model(model, n_modes, rotor_speed=rotor_speed)``, built once per process
    for each definition (its contents, wherever it was read from), ``n_modes`` and ``rotor_speed``:
    the blade's finite elements and their reduction (~8 ms of the default blade; a run does not
    change the assembly, :meth:`BladeAssembly.with_root` makes a new one)."""
    # the definition's contents as written (repr of floats is exact: equal keys, equal numbers)
    key = (repr((model.blade_parameters, model.root, model.excitation)), int(n_modes), float(rotor_speed))
    asm = _REDUCED.get(key)
    if asm is None:
        asm = _REDUCED[key] = BladeAssembly.from_model(model, n_modes=int(n_modes), rotor_speed=rotor_speed)
        while len(_REDUCED) > _REDUCED_SIZE:
            _REDUCED.popitem(last=False)
    else:
        _REDUCED.move_to_end(key)
    return asm


class BladeRun:
    """A blade model definition on its dovetail root from a start time, stepped exactly with a
    held tip force.

    Parameters
    ----------
    model : BladeModel
        The definition (:func:`~frictionjoint.structures.load_blade_model`).
    parameters : dict
        Values for :func:`blade_parameters` (the definition's defaults for the missing ones).
    start_time : float
        Start time [s]; the excitation is ``cos(omega t)`` in absolute time.
    tip_force : float
        Extra force at the tip [N], held until changed by :meth:`hold`.
    orbit_guess : (2 n_dof + n,) ndarray, optional
        With ``start_on_orbit``: the state at ``t = 0`` of a nearby orbit (the previous sweep
        point's :attr:`orbit_state`) from which the shooting starts, from rest where it does not
        converge from there (as :func:`~frictionjoint.system_sweeps.system_sweep`); default: from
        rest.

    Attributes
    ----------
    orbit_state : ndarray or None
        With ``start_on_orbit``: the orbit's state at ``t = 0`` (its ``initial_state``), None if no
        orbit was found.
    """

    def __init__(self, model, parameters: dict, start_time: float = 0.0, tip_force: float = 0.0,
                 orbit_guess=None):
        self.parameters = p = run_parameters(blade_parameters(model), parameters)
        omega = check_positive("omega", p["omega"])
        speed = check_positive("rotor_speed", p["rotor_speed"])
        fc = check_real("centrifugal_force", p["centrifugal_force"])
        if fc < 0:
            raise ParameterError(f"centrifugal_force must be >= 0 N (0: from rotor_speed), got {fc!r}")
        n_modes = p["n_modes"]
        if isinstance(n_modes, bool) or not isinstance(n_modes, (int, np.integer)) or n_modes < 0:
            raise ParameterError(f"n_modes must be an integer >= 0, got {n_modes!r}")
        check_bool("start_from_last_orbit", p["start_from_last_orbit"])  # the FMU's: it keeps orbit_guess
        asm = _reduced(model, int(n_modes), speed)
        changes = dict(friction_coefficient=p["friction_coefficient"], flank_angle=p["flank_angle"],
                       normal_load_variation=check_bool("normal_load_variation",
                                                             p["normal_load_variation"]))
        if fc > 0:
            changes["centrifugal_force"] = fc
        asm = asm.with_root(**changes)
        tip = asm.tip
        asm = BladeAssembly(asm.structure, asm.joints, {tip: check_real("tip_force_amplitude",
                                                                        p["tip_force_amplitude"])})
        self.assembly = asm
        self.system = asm.system(omega)
        self.marcher = Marcher(self.system)
        self._tip_row = asm._row(tip)
        root = asm.joints[0]
        self._root = root
        self._root_map = root._root_map(self.system.structure)
        self.t = check_real("start_time", start_time)
        self.orbit_found = False
        self.orbit_state = None
        n = self.system.n_dof
        x0 = v0 = np.zeros(n)
        w0 = None
        if check_bool("start_on_orbit", p["start_on_orbit"]):
            orbit = None
            z = None if orbit_guess is None else np.asarray(orbit_guess, dtype=float)
            if z is not None and z.ndim == 1 and z.size >= 2 * n and np.all(np.isfinite(z)):
                # the guess as system_sweep gives it (the previous orbit's state at t = 0); rest is
                # the other guess (see there)
                orbit = periodic_response(self.system, z[:n], z[n:2 * n], z[2 * n:] if z.size > 2 * n else None,
                                          marcher=self.marcher, peaks=False)
            if orbit is None or not orbit.converged:
                orbit = periodic_response(self.system, marcher=self.marcher, peaks=False)  # its state only
            if orbit.converged and orbit.initial_state is not None:
                self.orbit_state = orbit.initial_state.copy()
                z = orbit.initial_state
                x0, v0 = z[:n], z[n:2 * n]
                w0 = self._slider_positions(x0, z[2 * n:])
                self.orbit_found = True
        self.tip_force = 0.0
        self.hold(tip_force)
        # the orbit's state is at t = 0 (its phase is absolute): march it to the start time
        self.state = self.marcher.initial_state(x0, v0, w0, t0=0.0 if self.orbit_found else self.t)
        self.itv = None
        self.log = EventLog()
        self.dissipated_energy = 0.0
        self.integrals = np.zeros(2)
        if self.orbit_found and self.t != 0.0:
            self._march(self.t, record=False)

    def _slider_positions(self, x, w_jen):
        w = self.system.slider_direction @ x
        w[~self.system.rigid] = w_jen
        return w

    def hold(self, tip_force: float) -> None:
        """Hold an extra tip force [N] from now on (finite); the same force again changes nothing."""
        f = check_real("tip_force", tip_force)
        if f == self.tip_force:
            return
        self.tip_force = f
        self.marcher.set_held_force(None if f == 0.0 else f * self._tip_row)
        self.itv = None  # holding forces may have jumped: settle again

    def _march(self, t_end: float, record: bool = True) -> None:
        w = self.system.omega

        def on_interval(itv, tau_end):
            if not record or tau_end <= 0:
                return
            ca, sa = displacement_fourier(itv, tau_end, w)
            self.integrals += (self._tip_row @ ca, self._tip_row @ sa)
            x0 = itv.x0
            x1 = itv.state(tau_end)[0][:, 0]
            self.dissipated_energy += piece_slip(self.system, itv, tau_end, x1 - x0)[1]

        self.itv = self.marcher.march(self.state, t_end, self.log if record else None,
                                      on_interval=on_interval, itv=self.itv)
        self.t = t_end

    @owns_blas_threads
    def advance(self, t: float) -> None:
        """March exactly to time ``t`` [s] (> the current time; events inside)."""
        t = check_real("t", t)
        if t < self.t:
            raise ParameterError(f"t must be >= the current time {self.t!r}, got {t!r}")
        if t > self.t:
            self._march(t)

    def output(self, name: str):
        """The output ``name`` of :data:`BLADE_OUTPUTS` at the current time."""
        st, sysm = self.state, self.system
        u = self._root_map @ st.x
        if name == "tip_displacement":
            return float(self._tip_row @ st.x)
        if name == "tip_velocity":
            return float(self._tip_row @ st.v)
        if name.startswith("root_"):
            k = ("tangential", "radial", "rocking").index(name[5:])
            return float(u[k]) if k < u.size else 0.0
        if name == "dissipated_energy":
            return float(self.dissipated_energy)
        if name == "event_count":
            return len(self.log)
        if name in ("tip_cos_integral", "tip_sin_integral"):
            return float(self.integrals[0 if "cos" in name else 1])
        if name == "orbit_found":
            return bool(self.orbit_found)
        side = 0 if name.endswith("right") else 1
        if name.startswith("normal_force"):
            n0 = self._root.static.normal_force
            load = n0 - self._root.normal_stiffness * float(self._root.normal_rows[side] @ u)
            return max(load, 0.0) if sysm.n_contacts else load
        if name.startswith("friction_force"):
            # the Jenkins spring force k (d.x - w), the static preload included (w is projected
            # on the status: slipping sig mu N, zero on an open contact)
            k = sysm.slider_stiffness[side]
            return float(k * (sysm.slider_direction[side] @ st.x - st.w[side]))
        if name.startswith("slipping"):
            return bool(st.status[side] in (1, -1))
        if name.startswith("lifted"):
            return bool(st.status[side] == 2)
        raise ParameterError(f"unknown output {name!r}; allowed: {sorted(BLADE_OUTPUTS)}")

    def snapshot(self) -> dict:
        """The run's complete state (copied), for :meth:`restore`."""
        st = self.state
        return {"t": self.t, "x": st.x.copy(), "v": st.v.copy(), "w": st.w.copy(), "status": st.status.copy(),
                "v_scale": st.v_scale, "diss": self.dissipated_energy, "integrals": self.integrals.copy(),
                "events": len(self.log), "tip_force": self.tip_force}

    def restore(self, snap: dict) -> None:
        """Back to a state from :meth:`snapshot` (its events beyond it forgotten)."""
        self.state = MarchState(snap["t"], snap["x"].copy(), snap["v"].copy(), snap["w"].copy(),
                                snap["status"].copy(), snap["v_scale"])
        self.t = snap["t"]
        self.dissipated_energy = snap["diss"]
        self.integrals = snap["integrals"].copy()
        for lst in (self.log.time, self.log.element, self.log.slider, self.log.kind):
            del lst[snap["events"]:]
        self.hold(snap["tip_force"])
        self.itv = None  # the piece of another state: settle again
