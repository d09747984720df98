"""System definition files: a whole friction system (structure, joints, excitation, outputs) as data.

A definition is a TOML or JSON file (SI units); ``frictionjoint build-fmus --system FILE`` makes
one FMU of it, which marches the system with the library's exact event-driven marcher inside each
communication step (:mod:`frictionjoint.fmi.system_slave`)::

    name = "TwoDofChainSystem"           # optional: the FMU's file name (default: the file's stem)
    source = "..."                       # optional: where the numbers come from
    structure = "two_dof_chain.toml"     # a structure definition file (relative to this file), or a
                                         # [structure] table with its keys (dofs, mass, stiffness, ...)

    [[joints]]                           # each joint: a name, a type, where it acts, its parameters
    name = "j1"
    type = "jenkins"
    dof = "x1"                           # or direction = { x1 = 1.0, x2 = -1.0 }: s = x1 - x2
    tangential_stiffness = 100.0         # [N/m]
    slip_force = 0.8                     # [N]

    # types and their parameters: jenkins: tangential_stiffness [N/m], slip_force [N];
    # coulomb: slip_force [N]; iwan (Segalman): slip_force [N], stiffness [N/m], chi, beta and
    # n_sliders (an integer, default 50). A joint on ``dof`` ties it to the ground; one along
    # ``direction`` (DOF name = coefficient) acts on s = sum of coefficient * x, e.g. between two DOFs.
    # dovetail (flat flanks, frictionjoint.DovetailRoot): tangential_dof and/or radial_dof (the
    # root's DOFs) instead of dof; centrifugal_force [N], flank_angle [rad], friction_coefficient,
    # normal_stiffness, tangential_stiffness [N/m], normal_damping [N s/m] (default 0) and
    # normal_load_variation (true/false, default false); a root that rocks on its flanks also
    # rocking_dof (the root's rotation [rad]) and flank_half_width (each flank's contact point from
    # the root's centre line [m], > 0).

    [excitation]                         # optional; default: the structure definition's
    omega = 1.2                          # [rad/s]
    force_amplitude = { x2 = 1.0 }       # [N], amplitude * cos(omega t) per DOF
    inputs = ["x1"]                      # DOFs with an external force input, held over a step [N]

    [outputs]                            # optional; default: the structure definition's outputs
    displacement = ["x1", "x2"]          # DOFs whose x is an output (x_<dof>) [m]
    velocity = ["x1", "x2"]              # DOFs whose v is an output (v_<dof>) [m/s]
    joint_force = ["j1", "j2"]           # joints whose force is an output (force_<joint>), default all

The dissipated energy and the event count are always outputs. :func:`load_system_definition`
reads a file; :meth:`SystemDefinition.to_json` writes the normalised form (the structure's
matrices inline) that the FMU carries in its resources; :meth:`SystemDefinition.system` is the
:class:`~frictionjoint.system.FrictionSystem` the FMU marches (with its parameters' values).
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

from .elements import CoulombSlider, DovetailRoot, Iwan, Jenkins
from .errors import ParameterError, check_bool, check_count, check_positive, check_real
from .excitation import HarmonicForce
from .structure import LinearStructure
from .structure_file import _NAME, StructureDefinition, load_structure_definition
from .system import FrictionSystem

__all__ = ["SystemDefinition", "load_system_definition", "JOINT_TYPES"]

#: joint type -> its real parameters (name -> description with unit), each an FMU parameter
#: ``<joint>_<name>``
JOINT_TYPES = {
    "jenkins": {"tangential_stiffness": "stiffness of the spring in series with the slider [N/m], > 0",
                "slip_force": "slip force [N], >= 0"},
    "coulomb": {"slip_force": "friction force limit [N], >= 0"},
    "iwan": {"slip_force": "macro-slip force F_S of the Segalman Iwan element [N], > 0",
             "stiffness": "tangent stiffness K_T of the Segalman Iwan element [N/m], > 0",
             "chi": "exponent chi of the Segalman slip density, in (-1, 0]",
             "beta": "weight beta of the Segalman delta at macro-slip, >= 0"},
    "dovetail": {"centrifugal_force": "root load Fc [N], > 0",
                 "flank_angle": "angle between the flank normal and the radial axis [rad], in [0, pi/2)",
                 "friction_coefficient": "flank friction coefficient mu, > 0",
                 "normal_stiffness": "normal contact stiffness of one flank [N/m], > 0",
                 "tangential_stiffness": "tangential stiffness of one flank [N/m], > 0",
                 "normal_damping": "viscous damping of each flank's normal contact [N s/m], >= 0"},
}
#: real parameters that may be left out: type -> name -> default
_DEFAULTS = {"dovetail": {"normal_damping": 0.0}}
#: options that are no FMU parameter: type -> name -> (default, check)
_OPTIONS = {"iwan": {"n_sliders": (50, check_count)},
            "dovetail": {"normal_load_variation": (False, check_bool),
                         "flank_half_width": (None, lambda name, v: None if v is None else check_positive(name, v))}}
#: where a joint acts: type -> its keys (the others: exactly one of dof and direction)
_ATTACH = {"dovetail": ("tangential_dof", "radial_dof", "rocking_dof")}
#: attachment keys that do not attach alone: type -> keys
_SECONDARY = {"dovetail": ("rocking_dof",)}
_ATTACH_DEFAULT = ("dof", "direction")


def _element(kind: str, attach: dict, values: dict, options: dict):
    """The library element of a joint of type ``kind`` attached by ``attach`` (``dof=``,
    ``direction=`` or the root DOFs) with its parameter ``values`` and ``options``."""
    if kind == "jenkins":
        return Jenkins(values["tangential_stiffness"], values["slip_force"], **attach)
    if kind == "coulomb":
        return CoulombSlider(values["slip_force"], **attach)
    if kind == "iwan":
        return Iwan.segalman(values["slip_force"], values["stiffness"], values["chi"], values["beta"],
                             n_sliders=options["n_sliders"], **attach)
    return DovetailRoot(**values, **attach, normal_load_variation=options["normal_load_variation"],
                        flank_half_width=options["flank_half_width"])


def _dof_names(structure: LinearStructure, key: str, names) -> tuple:
    """The DOFs ``names`` (names or indices) of ``structure`` by name, distinct; errors name ``key``."""
    try:
        out = tuple(structure.dof_names[structure.dof_index(d)] for d in names)
    except ParameterError as exc:
        raise ParameterError(f"{key}: {exc}") from None
    if len(set(out)) != len(out):
        raise ParameterError(f"{key} must be distinct DOFs, got {list(names)!r}")
    return out


def _attachment(kind: str, data: dict, where: str) -> dict:
    """Where the joint of table ``data`` acts: its keys of :data:`_ATTACH` (DOF names; a direction
    as a table DOF name -> coefficient)."""
    if kind in _ATTACH:
        attach = {k: str(data[k]) for k in _ATTACH[kind] if k in data}
        primary = [k for k in _ATTACH[kind] if k not in _SECONDARY.get(kind, ())]
        if not any(k in attach for k in primary):
            raise ParameterError(f"{where} ({kind}) needs {' or '.join(map(repr, primary))} (DOF names)")
        return attach
    if ("dof" in data) == ("direction" in data):
        raise ParameterError(f"{where} ({kind}) needs one of 'dof' (a DOF name) and 'direction' (a table "
                             "DOF name = coefficient)")
    if "dof" in data:
        return {"dof": str(data["dof"])}
    direction = data["direction"]
    if not isinstance(direction, dict) or not direction:
        raise ParameterError(f"{where}.direction must be a table DOF name = coefficient, got {direction!r}")
    return {"direction": {str(k): check_real(f"{where}.direction[{k!r}]", v) for k, v in direction.items()}}


@dataclass(frozen=True)
class Joint:
    """One joint of a system definition: ``name``, ``type`` (a key of :data:`JOINT_TYPES`), where
    it acts (``attach``: its ``dof``, tied to the ground, or the ``direction`` it acts along, DOF
    name -> coefficient; a dovetail's ``tangential_dof`` and ``radial_dof``), its real parameters
    ``values`` and its ``options`` (an Iwan joint's ``n_sliders``, a dovetail's
    ``normal_load_variation``)."""

    name: str
    type: str
    attach: dict
    values: dict
    options: dict = field(default_factory=dict)

    @classmethod
    def from_dict(cls, data: dict, index: int) -> "Joint":
        """A joint from its table ``data`` (the ``index``-th of ``[[joints]]``, for messages)."""
        where = f"joints[{index}]"
        if not isinstance(data, dict):
            raise ParameterError(f"{where} must be a table, got {data!r}")
        kind = data.get("type")
        if kind not in JOINT_TYPES:
            raise ParameterError(f"{where}.type must be one of {sorted(JOINT_TYPES)}, got {kind!r}")
        options = _OPTIONS.get(kind, {})
        defaults = _DEFAULTS.get(kind, {})
        allowed = {"name", "type", *_ATTACH.get(kind, _ATTACH_DEFAULT), *JOINT_TYPES[kind], *options}
        unknown = set(data) - allowed
        if unknown:
            raise ParameterError(f"unknown keys {sorted(unknown)} in {where} ({kind}); allowed: {sorted(allowed)}")
        for key in ("name", *(k for k in JOINT_TYPES[kind] if k not in defaults)):
            if key not in data:
                raise ParameterError(f"{where} ({kind}) needs {key!r}")
        name = data["name"]
        if not isinstance(name, str) or not _NAME.match(name):
            raise ParameterError(f"{where}.name must be an identifier (letters, digits, _), got {name!r}")
        values = {k: check_real(f"{where}.{k}", data.get(k, defaults.get(k))) for k in JOINT_TYPES[kind]}
        chosen = {k: check(f"{where}.{k}", data.get(k, default)) for k, (default, check) in options.items()}
        return cls(name, kind, _attachment(kind, data, where), values, chosen)

    def to_dict(self) -> dict:
        """The joint's table (the file format)."""
        attach = {k: dict(v) if isinstance(v, dict) else v for k, v in self.attach.items()}
        return {"name": self.name, "type": self.type, **attach, **self.values,
                **{k: v for k, v in self.options.items() if v is not None}}

    def on(self, structure: LinearStructure) -> "Joint":
        """The joint with its DOFs checked on ``structure`` and given by name."""
        attach = {}
        for key, value in self.attach.items():
            where = f"joint {self.name!r} {key}"
            if isinstance(value, dict):
                attach[key] = dict(zip(_dof_names(structure, where, list(value)), value.values()))
            else:
                attach[key] = _dof_names(structure, where, [value])[0]
        return Joint(self.name, self.type, attach, self.values, self.options)

    @property
    def where(self) -> str:
        """Where the joint acts, in words."""
        if "direction" in self.attach:
            return "along " + " ".join(f"{c:+g} {d}" for d, c in self.attach["direction"].items())
        if "dof" in self.attach:
            return f"at {self.attach['dof']}"
        return "at " + ", ".join(f"{k[:-4]} {v}" for k, v in self.attach.items())

    def element(self, structure: LinearStructure, values: dict | None = None):
        """The library element on ``structure``, with ``values`` (parameter name -> value) over the
        joint's own; an invalid value is a :class:`ParameterError` naming the joint and its FMU
        parameter ``<joint>_<name>`` (the element's message starts with the name)."""
        attach = dict(self.attach)
        if "direction" in attach:
            vector = [0.0] * structure.n_dof
            for dof, c in attach["direction"].items():
                vector[structure.dof_index(dof)] = c
            attach["direction"] = vector
        try:
            return _element(self.type, attach, {**self.values, **(values or {})}, self.options)
        except ParameterError as exc:
            message = str(exc)
            if message.split(" ", 1)[0] in self.values:  # the FMU parameter's name
                message = f"{self.name}_{message}"
            raise ParameterError(f"joint {self.name!r}: {message}") from None


@dataclass(frozen=True)
class SystemDefinition:
    """A friction system as data (see the module docstring).

    Attributes
    ----------
    structure : LinearStructure
    joints : tuple of Joint
    omega : float
        Excitation angular frequency [rad/s].
    force_amplitude : dict
        DOF name -> amplitude of ``cos(omega t)`` [N].
    inputs : tuple of str
        DOFs with an external force input, held over a communication step.
    displacement, velocity : tuple of str
        DOFs whose displacement [m] / velocity [m/s] are outputs.
    joint_force : tuple of str
        Joints whose force [N] (restoring convention) is an output.
    name, source : str
    """

    structure: LinearStructure
    joints: tuple = ()
    omega: float = 1.0
    force_amplitude: dict = field(default_factory=dict)
    inputs: tuple = ()
    displacement: tuple = ()
    velocity: tuple = ()
    joint_force: tuple = ()
    name: str = "FrictionSystem"
    source: str = ""

    def __post_init__(self):
        s = self.structure
        if not isinstance(s, LinearStructure):
            raise ParameterError(f"structure must be a LinearStructure, got {type(s).__name__}")
        if not isinstance(self.name, str) or not _NAME.match(self.name):
            raise ParameterError(f"name must be an identifier (letters, digits, _), got {self.name!r}")
        joints = tuple(self.joints)
        names = [j.name for j in joints]
        if len(set(names)) != len(names):
            raise ParameterError(f"joints' names must be distinct, got {names!r}")
        joints = tuple(j.on(s) for j in joints)
        unknown = [j for j in self.joint_force if j not in names]
        if unknown:
            raise ParameterError(f"outputs.joint_force: no joints {unknown!r}; the joints are {names!r}")
        amplitude = {_dof_names(s, "excitation.force_amplitude", [k])[0]:
                     check_real(f"excitation.force_amplitude[{k!r}]", v) for k, v in dict(self.force_amplitude).items()}
        object.__setattr__(self, "joints", joints)
        object.__setattr__(self, "force_amplitude", amplitude)
        object.__setattr__(self, "omega", check_positive("excitation.omega", self.omega))
        object.__setattr__(self, "inputs", _dof_names(s, "excitation.inputs", self.inputs))
        object.__setattr__(self, "displacement", _dof_names(s, "outputs.displacement", self.displacement))
        object.__setattr__(self, "velocity", _dof_names(s, "outputs.velocity", self.velocity))
        object.__setattr__(self, "joint_force", tuple(dict.fromkeys(self.joint_force)))
        self.system()  # every joint's element is valid with its values

    def parameters(self) -> dict:
        """The FMU's real parameters: name -> (default, description with unit): ``omega``,
        ``force_amplitude_<dof>`` and ``<joint>_<parameter>`` (:data:`JOINT_TYPES`)."""
        out = {"omega": (self.omega, "excitation angular frequency [rad/s], > 0")}
        for dof, value in self.force_amplitude.items():
            out[f"force_amplitude_{dof}"] = (value, f"amplitude of the force on {dof}, times cos(omega t) [N]")
        for j in self.joints:
            for key, text in JOINT_TYPES[j.type].items():
                out[f"{j.name}_{key}"] = (j.values[key], f"{j.type} joint {j.name} {j.where}: {text}")
        return out

    def system(self, values: dict | None = None) -> FrictionSystem:
        """The :class:`~frictionjoint.system.FrictionSystem`, with ``values`` (names of
        :meth:`parameters` -> value) over the definition's."""
        values = dict(values or {})
        unknown = set(values) - set(self.parameters()) if values else set()
        if unknown:
            raise ParameterError(f"unknown parameter(s) {sorted(unknown)}; allowed: {sorted(self.parameters())}")
        elements = [j.element(self.structure, {k: values[f"{j.name}_{k}"] for k in j.values
                                               if f"{j.name}_{k}" in values}) for j in self.joints]
        forces = [HarmonicForce(dof, check_real(f"force_amplitude_{dof}", values.get(f"force_amplitude_{dof}", a)))
                  for dof, a in self.force_amplitude.items()]
        return FrictionSystem(self.structure, elements, omega=values.get("omega", self.omega), excitation=forces)

    def to_dict(self) -> dict:
        """The definition as plain data (the file format, the structure's matrices inline)."""
        s = self.structure
        return {"name": self.name, "source": self.source,
                "structure": {"dofs": list(s.dof_names), "mass": s.mass.tolist(), "stiffness": s.stiffness.tolist(),
                              "damping": s.damping.tolist(), "indefinite_stiffness": bool(s.indefinite_stiffness)},
                "joints": [j.to_dict() for j in self.joints],
                "excitation": {"omega": self.omega, "force_amplitude": dict(self.force_amplitude),
                               "inputs": list(self.inputs)},
                "outputs": {"displacement": list(self.displacement), "velocity": list(self.velocity),
                            "joint_force": list(self.joint_force)}}

    def to_json(self, path) -> Path:
        """Write the definition as JSON (full double precision) and return the path."""
        path = Path(path)
        path.write_text(json.dumps(self.to_dict(), indent=1))
        return path

    @classmethod
    def from_dict(cls, data: dict, folder=None, default_name: str = "FrictionSystem") -> "SystemDefinition":
        """A definition from plain data (the file format); a structure given as a file name is read
        from ``folder`` (the definition file's folder)."""
        data = dict(data)
        known = {"name", "source", "structure", "joints", "excitation", "outputs"}
        unknown = set(data) - known
        if unknown:
            raise ParameterError(f"unknown keys {sorted(unknown)} in a system definition; allowed: {sorted(known)}")
        if "structure" not in data:
            raise ParameterError("a system definition needs 'structure' (a structure definition file or table)")
        base = _structure(data["structure"], folder)
        joints = data.get("joints", [])
        if not isinstance(joints, list):
            raise ParameterError(f"joints must be an array of tables ([[joints]]), got {joints!r}")
        joints = tuple(Joint.from_dict(j, i) for i, j in enumerate(joints))
        excitation = _table(data, "excitation", {"omega", "force_amplitude", "inputs"})
        outputs = _table(data, "outputs", {"displacement", "velocity", "joint_force"})
        if "excitation" not in data:
            excitation = {"omega": base.omega, "force_amplitude": base.force_amplitude}
        dofs = list(base.outputs) or list(base.structure.dof_names)
        return cls(base.structure, joints, excitation.get("omega", 1.0), dict(excitation.get("force_amplitude", {})),
                   tuple(excitation.get("inputs", ())), tuple(outputs.get("displacement", dofs)),
                   tuple(outputs.get("velocity", dofs)), tuple(outputs.get("joint_force", [j.name for j in joints])),
                   data.get("name", default_name), str(data.get("source", "")))


def _table(data: dict, key: str, allowed: set) -> dict:
    """The table ``data[key]`` (empty if absent), its keys checked against ``allowed``."""
    table = data.get(key, {})
    if not isinstance(table, dict):
        raise ParameterError(f"{key} must be a table, got {table!r}")
    unknown = set(table) - allowed
    if unknown:
        raise ParameterError(f"unknown keys {sorted(unknown)} in [{key}]; allowed: {sorted(allowed)}")
    for k, v in table.items():
        if k == "force_amplitude" and not isinstance(v, dict):
            raise ParameterError(f"{key}.{k} must be a table (DOF name = amplitude [N]), got {v!r}")
        if k not in ("omega", "force_amplitude") and not isinstance(v, list):
            raise ParameterError(f"{key}.{k} must be an array of names, got {v!r}")
    return table


def _structure(value, folder) -> StructureDefinition:
    """The structure of a system definition: a structure definition file's (relative to
    ``folder``) or an inline table's."""
    if isinstance(value, str):
        path = Path(value)
        if not path.is_absolute() and folder is not None:
            path = Path(folder) / path
        try:
            return load_structure_definition(path)
        except ParameterError as exc:
            raise ParameterError(f"structure ({value!r}): {exc}") from None
    if not isinstance(value, dict):
        raise ParameterError(f"structure must be a file name or a table, got {value!r}")
    try:
        return StructureDefinition.from_dict({"name": "Structure", **value}, folder=folder)
    except ParameterError as exc:
        raise ParameterError(f"[structure]: {exc}") from None


def load_system_definition(path) -> SystemDefinition:
    """Read a system definition (the module docstring's format) from a ``.toml`` or ``.json`` file.

    Parameters
    ----------
    path : path
        The file; a structure file it names is read relative to its folder.

    Returns
    -------
    SystemDefinition
        Named after the file's stem unless it gives a ``name``.
    """
    from .structures.models import read_definition_file

    path = Path(path)
    if not path.is_file():
        raise ParameterError(f"system definition file {str(path)!r} not found")
    if path.suffix.lower() not in (".toml", ".json"):
        raise ParameterError(f"system definition file must end in .toml or .json, got {str(path)!r}")
    data = read_definition_file(path, "system definition")
    return SystemDefinition.from_dict(data, folder=path.parent, default_name=path.stem)
