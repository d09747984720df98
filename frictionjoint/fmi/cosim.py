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
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

import numpy as np

from ..errors import ParameterError, check_positive, check_real
from ..results import CoSimulationResult
from .ports import split_port
from .ssp import write_ssp

__all__ = ["FMUSystem", "joint_connections"]


def joint_connections(structure: str, joint: str, dof: str, coupling: str = "semi-implicit") -> list:
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
    """

    components: dict
    connections: Sequence = ()
    parameters: dict = field(default_factory=dict)

    def __post_init__(self):
        from fmpy import read_model_description

        components = {str(k): Path(v) for k, v in dict(self.components).items()}
        if not components:
            raise ParameterError("components must name at least one FMU")
        variables = {}
        for name, path in components.items():
            if "." in name or not name:
                raise ParameterError(f"component names must be non-empty and without '.', got {name!r}")
            if not path.is_file():
                raise ParameterError(f"components[{name!r}]: FMU {str(path)!r} not found")
            md = read_model_description(str(path))
            variables[name] = {v.name: v for v in md.modelVariables}
        connections = []
        for pair in self.connections:
            if len(pair) != 2:
                raise ParameterError(f"connections are (source, target) pairs, got {pair!r}")
            (sc, sv), (tc, tv) = split_port(pair[0]), split_port(pair[1])
            for comp, var, causality in ((sc, sv, "output"), (tc, tv, "input")):
                if comp not in variables:
                    raise ParameterError(f"connection {pair!r}: no component {comp!r}")
                v = variables[comp].get(var)
                if v is None or v.causality != causality:
                    raise ParameterError(f"connection {pair!r}: {comp} has no {causality} {var!r}")
            connections.append((f"{sc}.{sv}", f"{tc}.{tv}"))
        targets = [t for _, t in connections]
        if len(set(targets)) != len(targets):
            raise ParameterError("an input may be the target of one connection only")
        parameters = {}
        for comp, values in dict(self.parameters).items():
            if comp not in variables:
                raise ParameterError(f"parameters: no component {comp!r}")
            for var in values:
                v = variables[comp].get(var)
                if v is None or v.causality != "parameter":
                    raise ParameterError(f"parameters[{comp!r}]: {comp} has no parameter {var!r}")
            parameters[comp] = dict(values)
        object.__setattr__(self, "components", components)
        object.__setattr__(self, "connections", tuple(connections))
        object.__setattr__(self, "parameters", parameters)
        object.__setattr__(self, "_variables", variables)

    def variable(self, port: str):
        """The model variable (fmpy) of ``"component.variable"``."""
        comp, var = split_port(port)
        try:
            return self._variables[comp][var]
        except KeyError:
            raise ParameterError(f"no variable {port!r} in the system") from None

    def simulate(self, stop_time: float, step: float, outputs: Sequence[str], start_time: float = 0.0,
                 transfer: str = "sequential", progress: bool = False) -> CoSimulationResult:
        """Run the system with this module's fixed-step master (see the module docstring).

        Parameters
        ----------
        stop_time : float
            End time [s]; the last communication point is the last ``t0 + n h <= stop_time``
            (within rounding).
        step : float
            Communication step ``h`` [s], > 0.
        outputs : sequence of str
            ``"component.variable"`` names to record at every communication point.
        start_time : float
            Start time ``t0`` [s].
        transfer : {"sequential", "jacobi"}
            ``"sequential"``: each connection is read and set in turn (see the module docstring);
            ``"jacobi"``: all sources are read, then all targets set, as Ecos does (a joint's force
            then lags its displacement by one step; the semi-implicit coupling stays exact while
            the joint sticks).
        progress : bool
            Show a progress bar.

        Returns
        -------
        CoSimulationResult
        """
        from .master import FMUInstance

        if transfer not in ("sequential", "jacobi"):
            raise ParameterError(f"transfer must be 'sequential' or 'jacobi', got {transfer!r}")
        h = check_positive("step", step)
        t0 = check_real("start_time", start_time)
        n_steps = _step_count(t0, check_real("stop_time", stop_time), h)
        outputs = list(outputs)
        for name in outputs:
            self.variable(name)
        insts = {}
        try:
            for name, path in self.components.items():
                insts[name] = FMUInstance(path, name=name)
            for name, inst in insts.items():
                inst.initialize(self.parameters.get(name), start_time=t0)
            record = np.empty((n_steps + 1, len(outputs)))
            self._transfer(insts, transfer)
            record[0] = self._read(insts, outputs)
            steps = range(1, n_steps + 1)
            if progress:
                from tqdm import tqdm

                steps = tqdm(steps, desc="co-simulation", unit="step")
            for n in steps:
                for inst in insts.values():
                    inst.step(h)
                self._transfer(insts, transfer)
                record[n] = self._read(insts, outputs)
        finally:
            for inst in insts.values():
                inst.close()
        return CoSimulationResult(t=t0 + h * np.arange(n_steps + 1), values=dict(zip(outputs, record.T)),
                                  step=h, host="frictionjoint master (fmpy)")

    def _transfer(self, insts, transfer: str) -> None:
        pairs = [(split_port(s), split_port(t)) for s, t in self.connections]
        if transfer == "jacobi":
            values = [insts[sc].get([sv])[0] for (sc, sv), _ in pairs]
            for ((_, _), (tc, tv)), value in zip(pairs, values):
                insts[tc].set({tv: value})
            return
        for (sc, sv), (tc, tv) in pairs:
            insts[tc].set({tv: insts[sc].get([sv])[0]})

    @staticmethod
    def _read(insts, outputs) -> list:
        return [float(insts[c].get([v])[0]) for c, v in map(split_port, outputs)]

    def to_ssp(self, path, name: str = "system") -> Path:
        """Write the system as an SSP archive (:func:`frictionjoint.fmi.ssp.write_ssp`)."""
        return write_ssp(self, path, name=name)


def _step_count(t0: float, stop: float, h: float) -> int:
    n = int(np.floor((stop - t0) / h * (1 + 1e-12) + 1e-9))
    if n < 1:
        raise ParameterError(f"stop_time must be at least one step ({h!r} s) after start_time, got {stop!r}")
    return n
