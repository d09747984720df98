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

The root is the definition's: a :class:`~frictionjoint.elements.DovetailRoot` (two point contacts,
a beam blade) or, for a solid blade (``[blade] kind = "solid"``), a
:class:`~frictionjoint.structures.solid_root.SolidBladeRoot` whose flanks are contact patches of
many nodes. The flank outputs are the same names for both (:func:`blade_outputs`): for a patch,
each is its flank's aggregate -- the sum of its nodes' normal and friction forces, slipping while
any node slips, lifted while every node is -- and the patch adds what a point contact cannot
say: how many nodes slip or are lifted now, and the share of the flank's node time spent
slipping since the start (over one period of an orbit: the mean slipping share of the flank).
"""
from __future__ import annotations

import math
from collections import OrderedDict

import numpy as np

from ..threads import owns_blas_threads
from ..elements.dovetail import FLANK_OUTPUTS
from ..elements.patch import PatchDovetailRoot
from ..errors import ParameterError, check_bool, check_positive, check_real
from ..solvers.marcher.eventlog import MarchState
from ..solvers.marcher.events import EventLog, Marcher
from ..solvers.marcher.response import displacement_fourier, piece_slip
from ..solvers.steady_state import periodic_response
from ..stepping import run_parameters
from .assembly import BladeAssembly

__all__ = ["BladeRun", "blade_parameters", "blade_outputs", "BLADE_OUTPUTS", "PATCH_OUTPUTS"]

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

#: a root on contact patches (a solid blade's): its flank outputs as aggregates of the nodes, and the
#: outputs of the patch besides :data:`BLADE_OUTPUTS`'s: output name -> (type, description with unit)
PATCH_OUTPUTS = {
    "root_tangential": (float, "tangential root displacement X from the static state, the mean over the flank "
                               "nodes (each weighted by its share of its flank's stiffness) [m]"),
    "root_radial": (float, "radial root displacement Y from the static state, outward, the mean over the flank "
                           "nodes [m]"),
    "root_rocking": (float, "root rocking theta [rad]: the left flank's mean Y minus the right flank's, over the "
                            "blade's thickness (the slope of the root face's mid line)"),
    "normal_force_right": (float, "normal force of the right flank, the sum over its nodes [N]"),
    "normal_force_left": (float, "normal force of the left flank, the sum over its nodes [N]"),
    "friction_force_right": (float, "friction force of the right flank, the sum over its nodes, positive radially "
                                    "inward on the blade [N]"),
    "friction_force_left": (float, "friction force of the left flank, the sum over its nodes, positive radially "
                                   "inward on the blade [N]"),
    "slipping_right": (bool, "true while any node of the right flank slips"),
    "slipping_left": (bool, "true while any node of the left flank slips"),
    "lifted_right": (bool, "true while every node of the right flank is lifted off (normal_load_variation)"),
    "lifted_left": (bool, "true while every node of the left flank is lifted off (normal_load_variation)"),
    "slipping_nodes_right": (int, "number of nodes of the right flank slipping now"),
    "slipping_nodes_left": (int, "number of nodes of the left flank slipping now"),
    "lifted_nodes_right": (int, "number of nodes of the right flank lifted off now (normal_load_variation)"),
    "lifted_nodes_left": (int, "number of nodes of the left flank lifted off now (normal_load_variation)"),
    "slip_fraction_right": (float, "share of the right flank's node time spent slipping since the start [-], "
                                   "exact (over one period of an orbit: the mean share of the flank that slips)"),
    "slip_fraction_left": (float, "share of the left flank's node time spent slipping since the start [-], exact"),
}


def blade_outputs(model) -> dict:
    """The outputs of a run of the definition ``model``: :data:`BLADE_OUTPUTS` for a beam blade on
    its point-contact dovetail; for a solid blade on contact patches the same names (their
    descriptions the patch's, :data:`PATCH_OUTPUTS`) and the patch's own after them. Name ->
    (type, description with unit)."""
    if getattr(model, "kind", "beam") != "solid":
        return BLADE_OUTPUTS
    return {**{name: PATCH_OUTPUTS.get(name, value) for name, value in BLADE_OUTPUTS.items()}, **PATCH_OUTPUTS}


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
        patch = getattr(root, "patch_root", root)
        #: a root on contact patches: its nodes' outputs (None for a DovetailRoot)
        self._patch = (_PatchFlanks(patch, self.system, model.blade_parameters.get("thickness"))
                       if isinstance(patch, PatchDovetailRoot) else None)
        self._root_map = root._root_map(self.system.structure) if self._patch is None else self._patch.root_map
        #: each patch node's time spent slipping since the start [s] (empty for a DovetailRoot)
        self.slip_time = np.zeros(0 if self._patch is None else patch.n_nodes)
        self._t_start = self.t = check_real("start_time", start_time)
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
            if self.slip_time.size:
                self.slip_time[np.abs(itv.status[:self.slip_time.size]) == 1] += tau_end

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
        if self._patch is not None:
            return self._patch.output(name, side, st, self.slip_time, self.t - self._t_start)
        if name.startswith("normal_force"):
            n0 = self._root.static.normal_force
            load = n0 - self._root.normal_stiffness * float(self._root.normal_rows[side] @ u)
            return max(load, 0.0) if sysm.n_contacts else load
        if name.startswith("friction_force"):
            # the Jenkins spring force k (d.x - w), the static preload included (w is projected
            # on the status: slipping sig mu N, zero on an open contact)
            k = sysm.slider_stiffness[side]
            return float(k * (sysm.slider_direction[side] @ st.x - st.w[side]))
        if name in ("slipping_right", "slipping_left"):
            return bool(st.status[side] in (1, -1))
        if name in ("lifted_right", "lifted_left"):
            return bool(st.status[side] == 2)
        raise ParameterError(f"unknown output {name!r}; allowed: {sorted(BLADE_OUTPUTS)}")

    def snapshot(self) -> dict:
        """The run's complete state (copied), for :meth:`restore`."""
        st = self.state
        return {"t": self.t, "x": st.x.copy(), "v": st.v.copy(), "w": st.w.copy(), "status": st.status.copy(),
                "v_scale": st.v_scale, "diss": self.dissipated_energy, "integrals": self.integrals.copy(),
                "events": len(self.log), "tip_force": self.tip_force, "slip_time": self.slip_time.copy()}

    def restore(self, snap: dict) -> None:
        """Back to a state from :meth:`snapshot` (its events beyond it forgotten)."""
        self.state = MarchState(snap["t"], snap["x"].copy(), snap["v"].copy(), snap["w"].copy(),
                                snap["status"].copy(), snap["v_scale"])
        self.t = snap["t"]
        self.dissipated_energy = snap["diss"]
        self.integrals = snap["integrals"].copy()
        self.slip_time = snap["slip_time"].copy()
        for lst in (self.log.time, self.log.element, self.log.slider, self.log.kind):
            del lst[snap["events"]:]
        self.hold(snap["tip_force"])
        self.itv = None  # the piece of another state: settle again


class _PatchFlanks:
    """The flank outputs of a root on contact patches (:class:`~frictionjoint.elements.PatchDovetailRoot`,
    a :class:`~frictionjoint.structures.solid_root.SolidBladeRoot`'s) in a run's system, whose
    sliders and contacts are the root's nodes in order (right flank first): see :data:`PATCH_OUTPUTS`.

    Parameters
    ----------
    root : PatchDovetailRoot
    system : FrictionSystem
        The run's system, the root its only joint.
    thickness : float or None
        The distance [m] between the flanks' lines (a solid blade's thickness), the lever of
        ``root_rocking``; None: ``root_rocking`` is 0.
    """

    def __init__(self, root: PatchDovetailRoot, system, thickness) -> None:
        structure = system.structure
        if system.n_sliders != root.n_nodes:
            raise ParameterError(f"a blade run on patches needs the root as its only joint ({system.n_sliders} "
                                 f"sliders, {root.n_nodes} nodes)")
        index, normal, _ = root._node_rows(structure)
        self.normal_rows = root._rows(structure, index, normal)  # (n_nodes, n_dof): each node's normal
        self.normal_stiffness = root.normal_stiffness
        self.static_normal_force = root.static_state(structure).normal_force
        self.nodes = [np.flatnonzero(root.flank == side) for side in (0, 1)]
        # root coordinates: per flank the stiffness-weighted mean of its nodes' (X, Y), averaged
        # over the flanks; rocking from the flanks' mean Y across the thickness
        means = np.zeros((2, 2, structure.n_dof))  # flank, (X, Y), dofs
        for side, nodes in enumerate(self.nodes):
            w = root.normal_stiffness[nodes] / root.normal_stiffness[nodes].sum()
            for k in range(2):
                np.add.at(means[side, k], index[nodes, k], w)
        self.root_map = np.vstack([0.5 * (means[0] + means[1]),
                                   (means[1, 1] - means[0, 1])[None] / thickness if thickness
                                   else np.zeros((1, structure.n_dof))])
        self.system = system

    def output(self, name: str, side: int, state, slip_time: np.ndarray, elapsed: float):
        """The flank output ``name`` of the flank ``side`` (0 right, 1 left) in the march state
        ``state``; ``slip_time`` the nodes' slip times [s] over the ``elapsed`` time [s]."""
        sysm, nodes = self.system, self.nodes[side]
        status = state.status[nodes]
        if name.startswith("normal_force"):
            if sysm.n_contacts:  # each node's contact, lift-off included
                return float(sysm.normal_loads(state.x)[nodes].sum())
            return float(np.sum(self.static_normal_force[nodes]
                                - self.normal_stiffness[nodes] * (self.normal_rows[nodes] @ state.x)))
        if name.startswith("friction_force"):
            # the nodes' Jenkins spring forces k (d.x - w), their static preloads included
            k = sysm.slider_stiffness[nodes]
            return float(np.sum(k * (sysm.slider_direction[nodes] @ state.x - state.w[nodes])))
        if name.startswith("slipping_nodes"):
            return int(np.count_nonzero(np.abs(status) == 1))
        if name.startswith("lifted_nodes"):
            return int(np.count_nonzero(status == 2))
        if name.startswith("slipping"):
            return bool(np.any(np.abs(status) == 1))
        if name.startswith("lifted"):
            return bool(np.all(status == 2))
        if name.startswith("slip_fraction"):
            return float(slip_time[nodes].sum() / (nodes.size * elapsed)) if elapsed > 0 else 0.0
        raise ParameterError(f"unknown output {name!r}; allowed: {sorted(BLADE_OUTPUTS)} and {sorted(PATCH_OUTPUTS)}")
