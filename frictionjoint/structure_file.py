"""Structure definition files: a linear structure, its ports and its harmonic excitation as data.

A definition is a TOML or JSON file (SI units)::

    name = "TwoDofChain"                 # optional: the FMU's file name
    source = "..."                       # optional: where the numbers come from
    dofs = ["x1", "x2"]
    mass = [[1.0, 0.0], [0.0, 1.0]]      # [kg]
    stiffness = [[2.0, -1.0], [-1.0, 1.0]]   # [N/m]
    damping = [[0.02, -0.01], [-0.01, 0.01]] # [N s/m], optional
    ports = ["x1", "x2"]                 # DOFs where joints act
    outputs = ["x1", "x2"]               # DOFs whose x, v are FMU outputs (the ports are always)
    indefinite_stiffness = false         # optional: true for a rotating structure's spin softening

    [excitation]                         # optional
    omega = 1.2                          # [rad/s]
    force_amplitude = { x2 = 1.0 }       # [N], force amplitude * cos(omega t) per DOF

:func:`load_structure_definition` reads one; :meth:`StructureDefinition.to_json` writes the
normalised form that ``LinearStructure.fmu`` carries in its resources.
"""
from __future__ import annotations

import json
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .errors import ParameterError, check_positive, check_real
from .structure import LinearStructure

__all__ = ["StructureDefinition", "load_structure_definition"]

_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*\Z")


@dataclass(frozen=True)
class StructureDefinition:
    """A linear structure with its ports and harmonic excitation (see the module docstring).

    Attributes
    ----------
    structure : LinearStructure
    ports : tuple of str
        DOFs where joints act.
    outputs : tuple of str
        DOFs whose displacement and velocity are reported (the ports first).
    force_amplitude : dict
        DOF name -> amplitude of ``cos(omega t)`` [N].
    omega : float
        Excitation angular frequency [rad/s].
    name : str
    source : str
    """

    structure: LinearStructure
    ports: tuple = ()
    outputs: tuple = ()
    force_amplitude: dict = field(default_factory=dict)
    omega: float = 1.0
    name: str = "LinearStructure"
    source: str = ""

    def __post_init__(self):
        s = self.structure
        if not isinstance(s, LinearStructure):
            raise ParameterError(f"structure must be a LinearStructure, got {type(s).__name__}")
        for dof in s.dof_names:
            if not _NAME.match(dof):
                raise ParameterError(f"dofs must be identifiers (letters, digits, _), got {dof!r}")
        ports = tuple(s.dof_names[s.dof_index(p)] for p in self.ports)
        if len(set(ports)) != len(ports):
            raise ParameterError(f"ports must be distinct DOFs, got {list(self.ports)!r}")
        outputs = ports + tuple(d for d in (s.dof_names[s.dof_index(o)] for o in self.outputs) if d not in ports)
        amplitude = {s.dof_names[s.dof_index(k)]: check_real(f"force_amplitude[{k!r}]", v)
                     for k, v in dict(self.force_amplitude).items()}
        if not _NAME.match(self.name):
            raise ParameterError(f"name must be an identifier (letters, digits, _), got {self.name!r}")
        object.__setattr__(self, "ports", ports)
        object.__setattr__(self, "outputs", outputs)
        object.__setattr__(self, "force_amplitude", amplitude)
        object.__setattr__(self, "omega", check_positive("omega", self.omega))

    def force_vector(self) -> np.ndarray:
        """The force amplitudes as an (n_dof,) vector [N]."""
        f = np.zeros(self.structure.n_dof)
        for dof, value in self.force_amplitude.items():
            f[self.structure.dof_index(dof)] = value
        return f

    def to_dict(self) -> dict:
        """The definition as plain data (the file format above)."""
        s = self.structure
        return {"name": self.name, "source": self.source, "dofs": list(s.dof_names),
                "mass": s.mass.tolist(), "stiffness": s.stiffness.tolist(), "damping": s.damping.tolist(),
                "ports": list(self.ports), "outputs": list(self.outputs),
                "indefinite_stiffness": bool(s.indefinite_stiffness),
                "excitation": {"omega": self.omega, "force_amplitude": dict(self.force_amplitude)}}

    def to_json(self, path) -> Path:
        """Write the definition as JSON (full double precision) and return the path."""
        path = Path(path)
        path.write_text(json.dumps(self.to_dict(), indent=1))
        return path

    @classmethod
    def from_dict(cls, data: dict) -> "StructureDefinition":
        """A definition from plain data (the file format above)."""
        data = dict(data)
        known = {"name", "source", "dofs", "mass", "stiffness", "damping", "ports", "outputs", "excitation",
                 "indefinite_stiffness"}
        unknown = set(data) - known
        if unknown:
            raise ParameterError(f"unknown keys {sorted(unknown)} in a structure definition; allowed: {sorted(known)}")
        for key in ("dofs", "mass", "stiffness"):
            if key not in data:
                raise ParameterError(f"a structure definition needs {key!r}")
        excitation = dict(data.get("excitation", {}))
        unknown = set(excitation) - {"omega", "force_amplitude"}
        if unknown:
            raise ParameterError(f"unknown keys {sorted(unknown)} in [excitation]; allowed: omega, force_amplitude")
        indefinite = data.get("indefinite_stiffness", False)
        if not isinstance(indefinite, bool):
            raise ParameterError(f"indefinite_stiffness must be true or false, got {indefinite!r}")
        structure = LinearStructure(data["mass"], data["stiffness"], data.get("damping"), dof_names=data["dofs"],
                                    indefinite_stiffness=indefinite)
        return cls(structure, tuple(data.get("ports", ())), tuple(data.get("outputs", ())),
                   dict(excitation.get("force_amplitude", {})), excitation.get("omega", 1.0),
                   data.get("name", "LinearStructure"), str(data.get("source", "")))


def load_structure_definition(path) -> StructureDefinition:
    """Read a structure definition from a ``.toml`` or ``.json`` file.

    Parameters
    ----------
    path : path
        The file (see the module docstring for the format).

    Returns
    -------
    StructureDefinition
    """
    path = Path(path)
    if not path.is_file():
        raise ParameterError(f"structure definition file {str(path)!r} not found")
    suffix = path.suffix.lower()
    if suffix == ".toml":
        try:
            import tomllib
        except ImportError:  # Python 3.10
            import tomli as tomllib
        data = tomllib.loads(path.read_text())
    elif suffix == ".json":
        data = json.loads(path.read_text())
    else:
        raise ParameterError(f"structure definition file must end in .toml or .json, got {str(path)!r}")
    return StructureDefinition.from_dict(data)
