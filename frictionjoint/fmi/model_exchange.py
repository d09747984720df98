"""Model Exchange form of the slaves: continuous states, their derivatives, event indicators and
the stick/slip rules applied in event mode.

In Model Exchange the host integrates the FMU's continuous states with its own ODE solver and
locates the state events from the FMU's event indicators (FMI's own event handling: a friction
element in Dymola, OpenModelica, Simulink or fmpy's CVode). Between events the FMU's discrete state
is frozen: a joint's force law (which sliders stick, where their springs are anchored, in which
direction the slipping ones slip) does not change while the solver evaluates it, even at a trial
point past an event; in event mode (:meth:`MEModel.me_update`) the rules are applied at the instant
the host located. The classes here are the FMI 2 slaves' declarations and validation
(:mod:`.slaves`, :mod:`.system_slave`) with this form in place of ``do_step``; the FMI 3 binding
is :mod:`.slaves3` (``*SlaveME3``).

- :class:`SpringSliders`: Jenkins sliders (a spring in series with a Coulomb slider) in this form,
  each driven by its own displacement ``u``, grouped by joint. Indicators per group: the smallest
  ``slip_force - |spring force|`` of the sliders that stick (stick -> slip where it falls through
  zero) and the velocity in the slip direction of those that slip (slip -> stick where it falls
  through zero).
- :class:`JenkinsJointME`, :class:`IwanJointME`, :class:`MicroslipJointME`: the displacement-driven
  joints; inputs ``u`` and ``velocity``, no continuous state, the sliders as discrete state.
- :class:`LinearStructureME`: the structure's ``x``, ``v`` as continuous states under its harmonic
  force and the joints' forces at its ports.
- :class:`CoulombOscillatorME`: the single-DOF Coulomb oscillator (a rigid slider: stuck, the mass
  stands; Hong and Liu's rules at each stop).
- :class:`SystemME`: a whole friction system (its definition's structure and Jenkins-type joints).

The rules at an event take a slider that sticks as having reached its limit when its margin is
within :data:`LIMIT_ROUNDING` rounding units of its spring force's terms: the host locates the
instant only to the rounding of ``t``, so the margin there is zero to that rounding, of either sign.
"""
from __future__ import annotations

import math

import numpy as np
from scipy.linalg import cho_factor, cho_solve

# imported here, not inside methods: see frictionjoint.fmi.slaves
from ..errors import ParameterError, check_nonnegative, check_positive, check_real
from ..stepping import OSCILLATOR_PARAMETERS
from . import slaves, system_slave

__all__ = ["SpringSliders", "MEModel", "JenkinsJointME", "IwanJointME", "MicroslipJointME", "LinearStructureME",
           "CoulombOscillatorME", "SystemME", "LIMIT_ROUNDING"]

#: rounding units of ``slip_force + stiffness (|u| + |w|)`` within which a sticking slider's margin
#: counts as zero at an event (its spring force ``stiffness (u - w)`` rounds by a few of them)
LIMIT_ROUNDING = 16.0
_EPS = float(np.finfo(float).eps)
#: an indicator with nothing to watch (no slider sticks, or none slips): a constant that never crosses
_IDLE = 1.0


class SpringSliders:
    """Jenkins sliders in Model Exchange form, each driven by its own displacement.

    Parameters
    ----------
    stiffness, slip_force : (n,) array_like
        Spring stiffness [N/m] and slip force [N] of each slider, both finite and > 0.
    group : (n,) array_like of int, optional
        The joint each slider belongs to (0 ... n_groups - 1); one joint by default. The sliders of
        a joint share its displacement, so those that slip slip in one direction.
    w0 : (n,) array_like, optional
        Initial anchors [m]: a stuck slider's force is ``stiffness (u - w)``; 0 by default.

    Attributes
    ----------
    w : (n,) ndarray
        Anchors [m]: of a stuck slider its spring's, of a slipping one the slider's position where its
        slip began (it is at ``u - direction slip_force / stiffness`` while it slips).
    direction : (n,) int ndarray
        0 where the slider sticks, +1 or -1 where it slips in that direction.
    dissipated : float
        Energy dissipated by the slips that have ended [J].
    """

    def __init__(self, stiffness, slip_force, group=None, w0=None):
        self.stiffness = np.atleast_1d(np.asarray(stiffness, dtype=float))
        self.slip_force = np.atleast_1d(np.asarray(slip_force, dtype=float))
        n = self.stiffness.size
        self.group = np.zeros(n, dtype=np.intp) if group is None else np.asarray(group, dtype=np.intp)
        self.n_groups = int(self.group.max()) + 1 if n else 0
        self.reach = self.slip_force / self.stiffness
        self.w = np.zeros(n) if w0 is None else np.array(w0, dtype=float)
        self.direction = np.zeros(n, dtype=np.int8)
        self.dissipated = 0.0

    def forces(self, u) -> np.ndarray:
        """Each slider's force [N] at the displacements ``u`` (restoring convention), under the frozen law."""
        return np.where(self.direction == 0, self.stiffness * (u - self.w), self.direction * self.slip_force)

    def group_sum(self, values) -> np.ndarray:
        """Per joint: the sum of the per-slider ``values``."""
        return np.bincount(self.group, weights=values, minlength=self.n_groups)

    def tangent_stiffness(self) -> np.ndarray:
        """Per joint: the stiffness of its sliders that stick [N/m]."""
        return self.group_sum(np.where(self.direction == 0, self.stiffness, 0.0))

    def indicators(self, u, udot) -> np.ndarray:
        """``(2, n_groups)``: per joint the smallest margin ``slip_force - |spring force|`` of its sliders
        that stick [N] and the velocity in the slip direction of those that slip [m/s] (:data:`_IDLE`
        where it has none)."""
        out = np.full((2, self.n_groups), _IDLE)
        stuck = self.direction == 0
        if stuck.any():
            margin = self.slip_force[stuck] - np.abs(self.stiffness[stuck] * (u - self.w)[stuck])
            lowest = np.full(self.n_groups, np.inf)
            np.minimum.at(lowest, self.group[stuck], margin)
            out[0] = np.where(np.isfinite(lowest), lowest, _IDLE)
        if not stuck.all():
            slip = ~stuck
            out[1, self.group[slip]] = (self.direction * np.broadcast_to(udot, self.w.shape))[slip]
        return out

    def dissipated_energy(self, u) -> float:
        """Energy dissipated since the start [J] at the displacements ``u``: the ended slips' and the
        current slips' ``slip_force`` times the distance slid."""
        slip = self.direction != 0
        if not slip.any():
            return float(self.dissipated)
        d = self.direction[slip]
        slid = d * ((np.broadcast_to(u, self.w.shape)[slip] - d * self.reach[slip]) - self.w[slip])
        return float(self.dissipated + np.dot(self.slip_force[slip], slid))

    def update(self, u, udot) -> bool:
        """Apply the stick/slip rules at the displacements ``u`` and velocities ``udot`` (event mode):
        a slipping slider whose velocity in its slip direction is <= 0 sticks, anchored at its limit;
        a sticking one at its limit (see :data:`LIMIT_ROUNDING`) and moving outward slips; one beyond
        its limit but not moving outward is put back onto it. Returns whether a slider changed its
        state (sticks or slips)."""
        u = np.broadcast_to(np.asarray(u, dtype=float), self.w.shape)
        udot = np.broadcast_to(np.asarray(udot, dtype=float), self.w.shape)
        d = self.direction.astype(float)
        stops = (d != 0) & (d * udot <= 0.0)
        if stops.any():
            anchor = self._anchor(u, d, stops)
            self.dissipated += float(np.dot(self.slip_force[stops], d[stops] * (anchor - self.w[stops])))
            self.w[stops] = anchor
            self.direction[stops] = 0
        stuck = (self.direction == 0) & ~stops
        spring = self.stiffness * (u - self.w)
        side = np.sign(u - self.w)
        tol = LIMIT_ROUNDING * _EPS * (self.slip_force + self.stiffness * (np.abs(u) + np.abs(self.w)))
        at_limit = stuck & (self.slip_force - np.abs(spring) <= tol)
        starts = at_limit & (side * udot > 0.0)
        if starts.any():  # (the anchor stays: the slider slides from where its spring held it)
            self.direction[starts] = side[starts].astype(np.int8)
        beyond = at_limit & ~starts & (np.abs(spring) > self.slip_force)
        if beyond.any():  # slid to its limit (the play operator; a velocity not connected reads 0)
            anchor = self._anchor(u, side, beyond)
            self.dissipated += float(np.dot(self.slip_force[beyond], np.abs(anchor - self.w[beyond])))
            self.w[beyond] = anchor
        return bool(stops.any() or starts.any())

    def _anchor(self, u, side, which) -> np.ndarray:
        """The anchors of the sliders ``which`` that stick at their limit on ``side`` of ``u``: ``u -
        side reach``, moved by rounding units towards ``u`` until the spring force rounds to at most
        the slip force (so that the margin indicator starts at >= 0, not at -1e-16, which a host
        would take for a zero crossing as it rises)."""
        u, side = u[which], side[which]
        k, f = self.stiffness[which], self.slip_force[which]
        w = u - side * self.reach[which]
        step = np.spacing(np.maximum(np.abs(u), np.abs(w)))  # (one of w's ulps may not move u - w)
        for _ in range(64):
            over = np.abs(k * (u - w)) > f
            if not over.any():
                break
            w[over] += side[over] * step[over]
            step[over] *= 2.0
        return w

    def snapshot(self) -> dict:
        return {"w": self.w.copy(), "direction": self.direction.copy(), "dissipated": self.dissipated}

    def restore(self, snap: dict) -> None:
        self.w, self.direction = snap["w"].copy(), snap["direction"].copy()
        self.dissipated = snap["dissipated"]


class MEModel:
    """What a Model Exchange slave adds to a slave of :mod:`.slaves`: its continuous states (declared
    outputs or locals, in :attr:`me_states`), a local ``der(<state>)`` per state, its event
    indicators (declared variables, in :attr:`me_indicators`), the time the host sets, and the rules
    of event mode (:meth:`me_update`)."""

    #: the time the host set [s]
    me_time = 0.0

    def _me_declare(self, states, indicators) -> None:
        """Declare ``der(<state>)`` for each state name of ``states`` (each already declared, or
        declared here as a local read by ``_me_value``) and the locals ``indicators`` (name ->
        description)."""
        known = {d.name for d in self._declared}
        self.me_states = tuple(states)
        for i, (name, text) in enumerate(states.items()):
            if name not in known:
                self._local(name, text, "_me_value", ("state", i))
        for i, (name, text) in enumerate(states.items()):
            self._local(f"der({name})", f"time derivative of {name}", "_me_value", ("derivative", i),
                        derivative=name)
        self.me_indicators = tuple(indicators)
        for i, (name, text) in enumerate(indicators.items()):
            self._local(name, text, "_me_value", ("indicator", i))

    def _me_value(self, kind, i):
        if not self._ready:
            return 0.0
        if kind == "state":
            return float(self.me_get_states()[i])
        if kind == "derivative":
            return float(self.me_derivatives()[i])
        return float(self.me_event_indicators()[i])

    # -- the interface of a binding (all values as lists of float) ------------------------------
    def me_get_states(self) -> np.ndarray:
        return np.empty(0)

    def me_set_states(self, values) -> None:
        if len(values):
            raise ParameterError(f"{type(self).__name__} has no continuous state, got {len(values)} values")

    def me_derivatives(self) -> np.ndarray:
        return np.empty(0)

    def me_event_indicators(self) -> np.ndarray:
        return np.empty(0)

    def me_nominals(self) -> np.ndarray:
        """Each continuous state's nominal magnitude (FMI: the scale of the host's absolute tolerance)."""
        return np.ones(len(self.me_states))

    def me_update(self) -> bool:
        """Apply the rules at the current time, states and inputs (event mode); returns whether the
        continuous states' values were changed (a velocity set to zero at a stop)."""
        return False

    def me_set_time(self, t) -> None:
        self.me_time = check_real("time", t)

    def setup_experiment(self, start_time, stop_time=None, tolerance=None):
        super().setup_experiment(start_time, stop_time, tolerance)
        self.me_time = float(start_time)

    def do_step(self, current_time, step_size):  # a Model Exchange FMU has no step
        return self._refuse("a Model Exchange FMU is not stepped: its host integrates its states")

    # -- FMI 2.0: what the fixed wrapper calls (fmi2_wrapper/fix.patch, 6) -------------------------------
    def set_time(self, time):
        self.me_set_time(time)

    def set_continuous_states(self, values):
        self.me_set_states(list(values))

    def get_continuous_states(self):
        if not self._ready:
            return [0.0] * len(self.me_states)
        return [float(v) for v in self.me_get_states()]

    def get_derivatives(self):
        return [float(v) for v in self.me_derivatives()]

    def get_event_indicators(self):
        return [float(v) for v in self.me_event_indicators()]

    def get_nominals_of_continuous_states(self):
        return [float(v) for v in self.me_nominals()]

    def new_discrete_states(self):
        """``(newDiscreteStatesNeeded, terminateSimulation, nominalsOfContinuousStatesChanged,
        valuesOfContinuousStatesChanged, nextEventTimeDefined, nextEventTime)``: the rules applied once
        (they leave nothing for a second pass)."""
        return False, False, False, bool(self.me_update()), False, 0.0

    def to_xml(self, model_options=None):
        """pythonfmu's FMI 2.0 model description made Model Exchange: a ``ModelExchange`` element
        (:func:`~frictionjoint.fmi.build.postprocess` moves the builder's capability flags there and drops
        ``CoSimulation``),
        ``numberOfEventIndicators``, each ``der(<state>)``'s ``derivative`` and the ``Derivatives``
        of the model structure (:func:`~frictionjoint.fmi.build.postprocess` adds them and the states to
        the initial unknowns)."""
        import xml.etree.ElementTree as ET

        root = super().to_xml(model_options)
        cs = root.find("CoSimulation")  # (pythonfmu's builder sets its flags there; postprocess moves them)
        me = ET.Element("ModelExchange", modelIdentifier=cs.get("modelIdentifier"),
                        completedIntegratorStepNotNeeded="true")
        root.insert(list(root).index(cs), me)
        root.set("numberOfEventIndicators", str(len(self.me_indicators)))
        index = {d.name: i for i, d in enumerate(self._declared, start=1)}
        variables = root.find("ModelVariables").findall("ScalarVariable")
        derivatives = ET.Element("Derivatives")
        for i, d in enumerate(self._declared, start=1):
            if d.derivative is not None:
                variables[i - 1].find("Real").set("derivative", str(index[d.derivative]))
                ET.SubElement(derivatives, "Unknown", index=str(i))
        structure = root.find("ModelStructure")
        outputs = structure.find("Outputs")
        if len(derivatives):
            structure.insert(0 if outputs is None else list(structure).index(outputs) + 1, derivatives)
        return root


# -- displacement-driven joints -------------------------------------------------------------------
class _DrivenME(MEModel, slaves._DrivenSlave):
    """A displacement-driven joint (its sliders' table from the FMI 2 slave) in Model Exchange form."""

    def _declare_io(self):
        self._input("u", 0.0, "relative displacement across the joint [m]")
        self._input("velocity", 0.0, "rate of change of u [m/s] (decides the slip direction at an event)")
        self._output("force", "joint force, restoring convention [N]", method="_me_output", args=("force",))
        self._output("tangent_stiffness", "stiffness of the sliders that stick (0 while all slip) [N/m]",
                     method="_me_output", args=("tangent_stiffness",))
        self._output("slipping", "true while every slider slips", kind=bool, method="_me_output",
                     args=("slipping",))
        self._output("dissipated_energy", "energy dissipated since the start [J]", method="_me_output",
                     args=("dissipated_energy",))
        self._output("status", "signed number of slipping sliders (sign: slip direction; 0: all stick)",
                     kind=int, method="_me_output", args=("status",))
        self._me_declare({}, {
            "slip_margin": "event indicator: smallest slip_force - |spring force| of the sliders that stick [N] "
                           "(through zero: one slips; 1 while none sticks)",
            "slip_velocity": "event indicator: velocity in the slip direction of the sliders that slip [m/s] "
                             "(through zero: they stick; 1 while none slips)"})

    def _initialise(self):
        k, f = self._slider_table()
        self._sliders = slaves.DrivenSliders(k, f)  # (its reach names the bound of u in _check_u)
        self._u_max = float(min(np.asarray(f) / np.asarray(k))) * slaves.RESOLUTION / _EPS
        u0 = self._check_u()
        self._me = SpringSliders(k, f, w0=np.full(len(k), u0))

    def _me_inputs(self):
        u = self._check_u()
        if not math.isfinite(self.velocity):
            raise ParameterError(f"input velocity must be finite, got {self.velocity!r}")
        return u, float(self.velocity)

    def _me_output(self, name):
        if not self._ready:
            return False if name == "slipping" else (0 if name == "status" else 0.0)
        u, _ = self._me_inputs()
        me = self._me
        if name == "force":
            return float(me.forces(u).sum())
        if name == "tangent_stiffness":
            return float(me.tangent_stiffness()[0])
        if name == "slipping":
            return bool(np.all(me.direction != 0))
        if name == "status":
            d = me.direction
            return int(np.sign(d.sum()) * np.count_nonzero(d))
        return me.dissipated_energy(u)

    def me_event_indicators(self):
        if not self._ready:
            return np.full(2, _IDLE)
        return self._me.indicators(*self._me_inputs())[:, 0]

    def me_update(self):
        if self._ready:
            self._me.update(*self._me_inputs())
        return False

    def _snapshot(self):
        return None if not self._ready else {"me": self._me.snapshot(), "u": self.u, "velocity": self.velocity}

    def _restore(self, snap):
        if snap is not None:
            self._me.restore(snap["me"])
            self.u, self.velocity = snap["u"], snap["velocity"]


class JenkinsJointME(_DrivenME, slaves.JenkinsJointSlave):
    """Jenkins joint, Model Exchange: inputs ``u``, ``velocity``; the slider as discrete state."""

    description = ("Jenkins joint (spring in series with a Coulomb slider), displacement-driven, Model Exchange: "
                   "event indicators for stick -> slip and slip -> stick")


class IwanJointME(_DrivenME, slaves.IwanJointSlave):
    """Iwan joint (Segalman), Model Exchange."""

    description = ("Iwan joint, Segalman 4-parameter form with n_sliders Jenkins sliders, displacement-driven, "
                   "Model Exchange: event indicators for stick -> slip and slip -> stick")


class MicroslipJointME(_DrivenME, slaves.MicroslipJointSlave):
    """Microslip joint (Cattaneo-Mindlin Iwan), Model Exchange."""

    description = ("Microslip joint: Iwan element built from Cattaneo-Mindlin contact theory, displacement-driven, "
                   "Model Exchange: event indicators for stick -> slip and slip -> stick")


# -- linear structure --------------------------------------------------------------------------------
class _LinearME(MEModel):
    """``M a = f(t) - C v - K x - loads``: the states ``x``, ``v`` of every DOF and their derivatives."""

    def _linear(self, structure, mass, damping, stiffness) -> None:
        self._names = structure.dof_names
        self._mass = cho_factor(np.asarray(mass, dtype=float))
        self._c, self._k = np.asarray(damping, dtype=float), np.asarray(stiffness, dtype=float)
        n = len(self._names)
        self._x, self._v = np.zeros(n), np.zeros(n)

    def _state_names(self, structure) -> dict:
        names = {f"x_{d}": f"displacement of {d} [m]" for d in structure.dof_names}
        names.update({f"v_{d}": f"velocity of {d} [m/s]" for d in structure.dof_names})
        return names

    def me_get_states(self):
        return np.concatenate([self._x, self._v])

    def me_set_states(self, values):
        values = np.asarray(values, dtype=float)
        n = self._x.size
        if values.shape != (2 * n,) or not np.all(np.isfinite(values)):
            raise ParameterError(f"continuous states must be {2 * n} finite values, got {values!r}")
        self._x, self._v = values[:n].copy(), values[n:].copy()

    def _load(self) -> np.ndarray:
        raise NotImplementedError

    def _static_nominals(self, stiffness, force, omega) -> None:
        """Nominals: each DOF's static deflection under the harmonic force's amplitudes with the
        stiffness ``stiffness`` (|K^-1 f|, at least 1e-3 of the largest; 1 where there is no force) and
        ``omega`` times it for the velocities."""
        try:
            x = np.abs(np.linalg.solve(stiffness, force))
        except np.linalg.LinAlgError:  # a free body: no static scale
            x = np.zeros(len(force))
        top = float(x.max()) if x.size and np.all(np.isfinite(x)) else 0.0
        x = np.maximum(x, 1e-3 * top) if top > 0 else np.ones(len(force))
        self._nominal = np.concatenate([x, omega * x if omega > 0 else x])

    def me_nominals(self):
        return self._nominal if self._ready else np.ones(len(self.me_states))

    def me_derivatives(self):
        f = self._load() - self._c @ self._v - self._k @ self._x
        return np.concatenate([self._v, cho_solve(self._mass, f)])


class LinearStructureME(_LinearME, slaves.LinearStructureSlave):
    """A linear structure (definition in the FMU's resources), Model Exchange: states ``x``, ``v`` of
    every DOF, joint loads ``-(joint_force + joint_stiffness (x - joint_displacement))`` at the ports."""

    description = ("Linear structure M x'' + C x' + K x = f, Model Exchange: states x, v of every DOF, harmonic "
                   "force and joint loads -(joint_force + joint_stiffness (x - joint_displacement)) at each port DOF")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._me_declare(self._state_names(self._definition.structure), {})

    def _initialise(self):
        d = self._definition
        self._force = d.force_vector()
        for dof in d.force_amplitude:
            self._force[d.structure.dof_index(dof)] = getattr(self, f"force_amplitude_{dof}")
        self._omega = check_positive("omega", self.omega)
        st = d.structure
        self._linear(st, st.mass, st.damping, st.stiffness)
        self._ports = np.array([st.dof_index(dof) for dof in d.ports], dtype=np.intp)
        self._static_nominals(st.stiffness, self._force, self._omega)

    def _state(self, which, dof):
        if not self._ready:
            return 0.0
        return float((self._x, self._v)[which][self._definition.structure.dof_index(dof)])

    def _load(self):
        f = self._force * math.cos(self._omega * self.me_time)
        stiffness = np.array(self._port_inputs("stiffness"), dtype=float)
        load = (np.array(self._port_inputs("force"), dtype=float)
                + stiffness * (self._x[self._ports] - np.array(self._port_inputs("displacement"), dtype=float)))
        if not np.all(np.isfinite(load)):
            raise ParameterError(f"joint inputs must be finite, got a port load {load!r}")
        np.subtract.at(f, self._ports, load)
        return f

    def _snapshot(self):
        return None if not self._ready else {"x": self._x.copy(), "v": self._v.copy(), "t": self.me_time}

    def _restore(self, snap):
        if snap is not None:
            self._x, self._v, self.me_time = snap["x"].copy(), snap["v"].copy(), snap["t"]


# -- Coulomb oscillator -------------------------------------------------------------------------------
#: the Model Exchange oscillator's parameters (its model and start; no run options)
_OSCILLATOR_ME = ("mass", "stiffness", "damping", "slip_force", "force_amplitude", "omega", "base_amplitude",
                  "x0", "v0")


class CoulombOscillatorME(MEModel, slaves._Slave):
    """The Coulomb oscillator ``m x'' + c x' + k (x - B cos wt) + friction = F cos wt + force`` with a
    rigid Coulomb slider to the ground, Model Exchange: states ``x``, ``v``; while it sticks the mass
    stands (both derivatives zero); Hong and Liu's rules at each stop (it sticks where the other forces
    stay within the slip force, else slips on in their direction)."""

    description = ("Mass on a Coulomb friction surface, spring to a harmonically moving base, Model Exchange: "
                   "states x, v; event indicator for stick -> slip and slip -> stop (Hong & Liu stop rules)")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        for name in _OSCILLATOR_ME:
            default, text = OSCILLATOR_PARAMETERS[name]
            self._parameter(name, default, text)
        self._input("force", 0.0, "external force on the mass, added to the harmonic one [N]")
        self._output("friction_force", "friction force on the mass, restoring convention [N]", method="_osc")
        self._output("stuck", "true while the mass sticks", kind=bool, method="_osc")
        self._output("dissipated_energy", "energy dissipated by friction since the start [J]", method="_osc")
        self._output("event_count", "number of stick/slip events since the start", kind=int, method="_osc")
        self._output("stop_count", "number of slip -> stick transitions since the start", kind=int, method="_osc")
        self._output("x", "displacement of the mass [m]", method="_me_value", args=("state", 0))
        self._output("v", "velocity of the mass [m/s]", method="_me_value", args=("state", 1))
        self._me_declare({"x": "", "v": ""}, {
            "stick_slip_indicator": "event indicator: while slipping the velocity in the slip direction [m/s]; "
                                    "while stuck slip_force - |the other forces on the mass| [N]"})

    def _initialise(self):
        self._m = check_positive("mass", self.mass)
        self._kk = check_positive("stiffness", self.stiffness)
        self._cc = check_nonnegative("damping", self.damping)
        self._fs = check_nonnegative("slip_force", self.slip_force)
        self._w = check_positive("omega", self.omega)
        self._fa = check_real("force_amplitude", self.force_amplitude)
        self._ba = check_real("base_amplitude", self.base_amplitude)
        self._xv = np.array([check_real("x0", self.x0), check_real("v0", self.v0)])
        self._mode = 0  # 0 stuck, +-1 slipping in that direction
        self._slide_from = self._xv[0]
        self._diss, self._events, self._stops = 0.0, 0, 0
        self._ready = True  # the rules below read the states
        if self._xv[1] != 0.0:
            self._mode = 1 if self._xv[1] > 0 else -1
        else:
            r = self._drive()
            if abs(r) > self._fs:  # from rest into slip: an event at the start, as the exact march logs it
                self._mode, self._events = (1 if r > 0 else -1), 1

    def _drive(self) -> float:
        """The forces on the mass other than friction and damping [N] (what friction holds while stuck)."""
        c = math.cos(self._w * self.me_time)
        return self._fa * c + self.force + self._kk * (self._ba * c - self._xv[0])

    def me_get_states(self):
        return self._xv.copy()

    def me_set_states(self, values):
        values = np.asarray(values, dtype=float)
        if values.shape != (2,) or not np.all(np.isfinite(values)):
            raise ParameterError(f"continuous states must be 2 finite values, got {values!r}")
        self._xv = values.copy()

    def me_derivatives(self):
        if self._mode == 0:
            return np.zeros(2)
        x, v = self._xv
        a = (self._drive() - self._cc * v - self._mode * self._fs) / self._m
        return np.array([v, a])

    def me_event_indicators(self):
        if not self._ready:
            return np.full(1, _IDLE)
        if self._mode == 0:
            return np.array([self._fs - abs(self._drive())])
        return np.array([self._mode * self._xv[1]])

    def me_update(self):
        r = self._drive()
        if self._mode != 0 and self._mode * self._xv[1] <= 0.0:  # a stop
            onward = 0 if abs(r) <= self._fs else (1 if r > 0 else -1)
            if onward == self._mode:  # a slip that starts at rest (t0, or just now): nothing has stopped
                return False
            self._diss += self._fs * abs(self._xv[0] - self._slide_from)
            self._xv[1] = 0.0
            self._events += 1
            if onward == 0:
                self._mode, self._stops = 0, self._stops + 1
            else:  # slips on, reversed, in the direction of the other forces (Hong & Liu)
                self._mode, self._slide_from = onward, self._xv[0]
            return True
        tol = LIMIT_ROUNDING * _EPS * (self._fs + abs(self._fa) + abs(self.force) + self._kk * (abs(self._ba)
                                                                                              + abs(self._xv[0])))
        if self._mode == 0 and self._fs - abs(r) <= tol and r != 0.0:
            self._mode, self._slide_from = (1 if r > 0 else -1), self._xv[0]
            self._events += 1
        return False

    def _osc(self, name):
        if not self._ready:
            return False if name == "stuck" else 0
        if name == "friction_force":
            return self._drive() if self._mode == 0 else self._mode * self._fs
        if name == "stuck":
            return self._mode == 0
        if name == "dissipated_energy":
            return self._diss + (self._fs * abs(self._xv[0] - self._slide_from) if self._mode else 0.0)
        return self._events if name == "event_count" else self._stops

    def me_nominals(self):
        """The static deflection of the spring under the larger of the force amplitude, the base's
        force and the slip force, and ``omega`` times it."""
        if not self._ready:
            return np.ones(2)
        x = max(abs(self._fa) + self._kk * abs(self._ba), self._fs) / self._kk
        x = x if x > 0 else 1.0
        return np.array([x, self._w * x])

    def _snapshot(self):
        if not self._ready:
            return None
        return {"xv": self._xv.copy(), "mode": self._mode, "from": self._slide_from, "diss": self._diss,
                "events": self._events, "stops": self._stops, "t": self.me_time, "force": self.force}

    def _restore(self, snap):
        if snap is not None:
            self._xv, self._mode, self._slide_from = snap["xv"].copy(), snap["mode"], snap["from"]
            self._diss, self._events, self._stops = snap["diss"], snap["events"], snap["stops"]
            self.me_time, self.force = snap["t"], snap["force"]


# -- a whole friction system ----------------------------------------------------------------------------
class SystemME(_LinearME, system_slave.SystemSlave):
    """A friction system (definition in the FMU's resources), Model Exchange: states ``x``, ``v`` of
    every DOF; its joints' sliders (Jenkins-type: a finite spring, a constant slip force) as discrete
    state, two event indicators per joint (:class:`SpringSliders`)."""

    description = ("Linear structure with Jenkins-type friction joints (Jenkins, Iwan) under harmonic and "
                   "external forces, Model Exchange: states x, v of every DOF, two event indicators per joint")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        d = self._definition
        indicators = {}
        for j in d.joints:
            indicators[f"slip_margin_{j.name}"] = (f"event indicator: smallest slip_force - |spring force| of "
                                                   f"joint {j.name}'s sliders that stick [N]")
            indicators[f"slip_velocity_{j.name}"] = (f"event indicator: velocity in the slip direction of joint "
                                                     f"{j.name}'s sliders that slip [m/s]")
        self._me_declare(self._state_names(d.structure), indicators)

    def _initialise(self):
        params = {k: getattr(self, k) for k in self._definition.parameters()}
        system = self._definition.system(params)
        d = system.slider_direction
        one_direction = all(np.array_equal(d[i], d[np.flatnonzero(system.slider_owner == system.slider_owner[i])[0]])
                            for i in range(system.n_sliders))
        if system.rigid.any() or system.varying.any() or not one_direction or not np.all(system.slip_force > 0):
            raise ParameterError("a Model Exchange system FMU needs joints of Jenkins sliders along one direction "
                                 "each (finite stiffness, a constant slip force > 0: Jenkins, Iwan): a rigid slider, "
                                 "a varying normal load, a zero slip force or a dovetail's two flanks are marched "
                                 "exactly by the co-simulation FMU")
        self._system = system
        self._linear(system.structure, system.mass, system.damping, system.stiffness)
        self._d = system.slider_direction
        self._me = SpringSliders(system.slider_stiffness, system.slip_force, system.slider_owner,
                                 w0=-system.slider_preload / system.slider_stiffness)
        self._me.n_groups = len(self._definition.joints)
        stuck = system.stiffness + (self._d.T * system.slider_stiffness) @ self._d  # every slider stuck
        self._static_nominals(stuck, np.hypot(system.force_cos, system.force_sin), system.omega)
        st = system.structure
        self._input_rows = np.array([st.dof_index(dof) for dof in self._definition.inputs], dtype=np.intp)
        self._events = 0

    def _load(self):
        s = self._system
        f = s.harmonic_force(self.me_time) + s.external_force(self.me_time)
        held = np.array(self.held_forces, dtype=float)
        if not np.all(np.isfinite(held)):
            raise ParameterError(f"input forces must be finite, got {held!r}")
        np.add.at(f, self._input_rows, held)
        return f - self._d.T @ self._me.forces(self._d @ self._x)

    def me_event_indicators(self):
        if not self._ready:
            return np.full(len(self.me_indicators), _IDLE)
        return self._me.indicators(self._d @ self._x, self._d @ self._v).T.ravel()

    def me_update(self):
        if self._me.update(self._d @ self._x, self._d @ self._v):
            self._events += 1
        return False

    def _out(self, name):
        if not self._ready:
            return self._idle(name)
        st = self._system.structure
        if name == "dissipated_energy":
            return self._me.dissipated_energy(self._d @ self._x)
        if name == "event_count":
            return self._events
        if name[:2] in ("x_", "v_"):
            return float((self._x if name[0] == "x" else self._v)[st.dof_index(name[2:])])
        forces = self._me.group_sum(self._me.forces(self._d @ self._x))
        return float(forces[[j.name for j in self._definition.joints].index(name[6:])])

    def _snapshot(self):
        if not self._ready:
            return None
        return {"x": self._x.copy(), "v": self._v.copy(), "me": self._me.snapshot(), "t": self.me_time,
                "events": self._events, "held": self.held_forces}

    def _restore(self, snap):
        if snap is not None:
            self._x, self._v, self.me_time = snap["x"].copy(), snap["v"].copy(), snap["t"]
            self._me.restore(snap["me"])
            self._events, self.held_forces = snap["events"], snap["held"]
