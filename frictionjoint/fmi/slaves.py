"""pythonfmu slaves: thin maps from FMI variables onto library objects.

Each FMU script in ``fmus/`` only names one of these classes. The physics is the library's:
:class:`~frictionjoint.oscillator.CoulombOscillator` marched exactly inside ``do_step`` (events
located inside the step, so outputs at a communication point do not depend on the communication
step), and :class:`~frictionjoint.elements.driven.DrivenSliders` for displacement-driven joints.
Inputs are held over a step (zero-order hold). The whole internal state is deep-copied for FMU
state get/set and pickled for serialisation.
"""
from __future__ import annotations

import copy
import functools
import math
import pickle

from pythonfmu import Boolean, Fmi2Causality, Fmi2Initial, Fmi2Slave, Fmi2Variability, Integer, Real
from pythonfmu.enums import Fmi2Status

from ..elements.driven import DrivenSliders
from ..elements.iwan import Iwan
from ..errors import ParameterError, check_positive
from ..stepping import OSCILLATOR_OUTPUTS, OSCILLATOR_PARAMETERS, OscillatorRun

__all__ = ["CoulombOscillatorSlave", "JenkinsJointSlave", "IwanJointSlave"]

_TYPES = {float: Real, int: Integer, bool: Boolean}


class _Slave(Fmi2Slave):
    """Common declarations, validation at initialisation, pickled state."""

    author = "frictionjoint developers"
    description = ""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.start_time = 0.0
        self._ready = False

    # -- declarations ------------------------------------------------------
    def _parameter(self, name, start, description, kind=float):
        setattr(self, name, kind(start))
        self.register_variable(_TYPES[kind](
            name, causality=Fmi2Causality.parameter, variability=Fmi2Variability.fixed,
            initial=Fmi2Initial.exact, description=description, start=kind(start)))

    def _input(self, name, start, description):
        setattr(self, name, float(start))
        self.register_variable(Real(name, causality=Fmi2Causality.input,
                                    variability=Fmi2Variability.continuous, description=description,
                                    start=float(start)))

    def _output(self, name, description, kind=float, getter=None):
        variability = Fmi2Variability.continuous if kind is float else Fmi2Variability.discrete
        self.register_variable(_TYPES[kind](name, causality=Fmi2Causality.output, variability=variability,
                                            description=description, getter=getter))

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

    def _get_fmu_state(self):
        return {"__frictionjoint__": copy.deepcopy(self._snapshot())}

    def _set_fmu_state(self, state):
        self._restore(copy.deepcopy(state["__frictionjoint__"]))

    @staticmethod
    def _fmu_state_to_bytes(state) -> bytes:
        return pickle.dumps(state)

    @staticmethod
    def _fmu_state_from_bytes(state: bytes):
        return pickle.loads(state)


class CoulombOscillatorSlave(_Slave):
    """Single-DOF mass on a Coulomb friction surface with a spring to a moving base."""

    description = ("Mass on a Coulomb friction surface (exact stick/slip, Hong & Liu stop rules), spring to a "
                   "harmonically moving base; events located exactly inside do_step")

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        for name, (default, text) in OSCILLATOR_PARAMETERS.items():
            self._parameter(name, default, text)
        self._input("force", 0.0, "external force on the mass, added to the harmonic one, held over a step [N]")
        for name, (kind, text) in OSCILLATOR_OUTPUTS.items():
            self._output(name, text, kind=kind, getter=functools.partial(self._out, name))
        self._run = None

    def _initialise(self):
        params = {k: getattr(self, k) for k in OSCILLATOR_PARAMETERS}
        self._run = OscillatorRun(params, start_time=self.start_time, force=self.force)

    def _out(self, name):
        if self._run is None:
            return {"x": self.x0, "v": self.v0}.get(name, OSCILLATOR_OUTPUTS[name][0]())
        return self._run.output(name)

    def do_step(self, current_time, step_size):
        try:
            self._run.hold(self.force)
        except ParameterError as exc:
            self.log(f"invalid input: {exc}", status=Fmi2Status.error)
            return False
        self._run.advance(current_time + step_size)
        return True

    def _snapshot(self):
        return None if self._run is None else self._run.snapshot()

    def _restore(self, snap):
        if snap is not None:
            self._run.restore(snap)
            self.force = snap["force"]


class _DrivenSlave(_Slave):
    """Displacement-driven joint: input ``u``, outputs force, tangent stiffness, slip state."""

    def _declare_io(self):
        self._input("u", 0.0, "relative displacement across the joint, held over a step [m]")
        self._output("force", "joint force, restoring convention [N]", getter=lambda: self._get("force"))
        self._output("tangent_stiffness", "stiffness of the sliders that stick (0 while all slip) [N/m]",
                     getter=lambda: self._get("tangent_stiffness"))
        self._output("slipping", "true while the joint slips", kind=bool, getter=lambda: self._get("slipping"))
        self._output("dissipated_energy", "energy dissipated since the start [J]",
                     getter=lambda: self._get("dissipated_energy"))

    def _get(self, name):
        if not self._ready:
            return False if name == "slipping" else 0.0
        sl = self._sliders
        u = self.u
        if not math.isfinite(u):
            return False if name == "slipping" else 0.0
        if name == "force":
            return sl.force_at(u)
        if name == "tangent_stiffness":
            return sl.tangent_stiffness_at(u)
        probe = sl.copy()
        probe.update(u)
        if name == "slipping":
            return bool(probe.slipping.all())
        return probe.dissipated_energy

    def _initialise(self):
        k, f = self._slider_table()
        self._sliders = DrivenSliders(k, f, u0=self.u)

    def do_step(self, current_time, step_size):
        if not math.isfinite(self.u):
            self.log(f"input u must be finite, got {self.u!r}", status=Fmi2Status.error)
            return False
        self._sliders.update(self.u)
        return True

    def _snapshot(self):
        if not self._ready:
            return None
        sl = self._sliders
        return {"u_state": sl.u, "w": sl.w, "slipping": sl.slipping, "diss": sl.dissipated_energy, "u": self.u}

    def _restore(self, snap):
        if snap is None:
            return
        sl = self._sliders
        sl.u, sl.w, sl.slipping, sl.dissipated_energy = snap["u_state"], snap["w"], snap["slipping"], snap["diss"]
        self.u = snap["u"]


class JenkinsJointSlave(_DrivenSlave):
    """Jenkins element (spring in series with a Coulomb slider) driven by a displacement."""

    description = "Jenkins joint: spring in series with a Coulomb slider, displacement-driven, exact play operator"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._parameter("stiffness", 1.0, "tangential stiffness of the spring [N/m], > 0")
        self._parameter("slip_force", 1.0, "slip force of the slider [N], > 0")
        self._declare_io()

    def _slider_table(self):
        return [check_positive("stiffness", self.stiffness)], [check_positive("slip_force", self.slip_force)]


class IwanJointSlave(_DrivenSlave):
    """Segalman 4-parameter Iwan joint (parallel Jenkins sliders) driven by a displacement."""

    description = "Iwan joint, Segalman 4-parameter form with n_sliders discrete Jenkins sliders, displacement-driven"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self._parameter("stiffness", 1.0, "initial tangential stiffness K_T [N/m], > 0")
        self._parameter("slip_force", 1.0, "macroslip force F_S [N], > 0")
        self._parameter("chi", -0.5, "power-law exponent chi, -1 < chi <= 0")
        self._parameter("beta", 0.1, "strength of the macroslip delta relative to the power law, >= 0")
        self._parameter("n_sliders", 20, "number of sliders of the power-law part, >= 1", kind=int)
        self._declare_io()

    def _slider_table(self):
        iw = Iwan.segalman(self.slip_force, self.stiffness, self.chi, self.beta, int(self.n_sliders), dof=0)
        k, f = zip(*iw.sliders_table)
        return list(k), list(f)
