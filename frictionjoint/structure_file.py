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

The matrices may instead come from the files an FE code exports: an ``[fe]`` table in place of
``dofs``, ``mass``, ``stiffness`` and ``damping`` (read by
:func:`frictionjoint.structures.fe_import.read_fe_model`; DOF names ``n<node>_u<d>`` for the
translations and ``n<node>_r<d>`` for the rotations, e.g. ``n131_u3``)::

    ports = ["n101_u1"]
    [fe]
    format = "matrix_market"             # optional: from the files' suffixes; or harwell_boeing,
                                         # nastran_dmig, nastran_op4, abaqus_matrix_input
    mass = "blade_M.mtx"                 # [kg]; ["blade.pch", "MAAX"] names a matrix of a file
    stiffness = "blade_K.mtx"            # [N/m]
    damping = "blade_C.mtx"              # [N s/m], optional
    rayleigh = [0.0, 2e-6]               # optional, instead of damping: C = alpha M + beta K [1/s, s]
    dofs = "blade.dofs.csv"              # the DOF table (node,direction); not for DMIG and Abaqus
                                         # files, which carry theirs
    node_sets = "blade.sets.csv"         # optional (set,node); or a table { tip = [131] }

Relative paths are from the definition file's folder. The structure is made dense
(:meth:`~frictionjoint.structures.fe_import.FEModel.to_structure`, at most 2,000 DOFs): a larger
model is reduced first.

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
    def from_dict(cls, data: dict, folder=None) -> "StructureDefinition":
        """A definition from plain data (the file format above).

        Parameters
        ----------
        data : dict
            The definition.
        folder : path, optional
            Where the relative paths of an ``[fe]`` table start (the current folder if omitted).

        Returns
        -------
        StructureDefinition
        """
        data = dict(data)
        known = {"name", "source", "dofs", "mass", "stiffness", "damping", "ports", "outputs", "excitation",
                 "indefinite_stiffness", "fe"}
        unknown = set(data) - known
        if unknown:
            raise ParameterError(f"unknown keys {sorted(unknown)} in a structure definition; allowed: {sorted(known)}")
        if "fe" in data:
            clash = sorted({"dofs", "mass", "stiffness", "damping"} & set(data))
            if clash:
                raise ParameterError(f"a structure definition with [fe] takes its matrices from the files; remove {clash}")
            data.update(_fe_matrices(data["fe"], Path(folder) if folder is not None else Path(".")))
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
    if path.suffix.lower() not in (".toml", ".json"):
        raise ParameterError(f"structure definition file must end in .toml or .json, got {str(path)!r}")
    from .structures.models import read_definition_file

    data = read_definition_file(path, "structure definition")
    return StructureDefinition.from_dict(data, folder=path.parent)


def _fe_matrices(fe, folder: Path) -> dict:
    """``dofs``, ``mass``, ``stiffness``, ``damping`` of an ``[fe]`` table (module docstring)."""
    from .structures.fe_import import read_fe_model

    if not isinstance(fe, dict):
        raise ParameterError(f"[fe] must be a table, got {fe!r}")
    known = {"format", "mass", "stiffness", "damping", "rayleigh", "dofs", "node_sets"}
    unknown = set(fe) - known
    if unknown:
        raise ParameterError(f"unknown keys {sorted(unknown)} in [fe]; allowed: {sorted(known)}")
    for key in ("mass", "stiffness"):
        if key not in fe:
            raise ParameterError(f"[fe] needs {key!r}")
    if "damping" in fe and "rayleigh" in fe:
        raise ParameterError("[fe] takes damping or rayleigh, not both")

    def place(value):  # a path, or [path, matrix name]
        if isinstance(value, str):
            return folder / value
        if isinstance(value, list) and len(value) == 2 and all(isinstance(v, str) for v in value):
            return (folder / value[0], value[1])
        raise ParameterError(f"[fe] matrices are a path or [path, matrix name], got {value!r}")

    sets = fe.get("node_sets")
    model = read_fe_model(place(fe["mass"]), place(fe["stiffness"]),
                          place(fe["damping"]) if "damping" in fe else None,
                          dofs=folder / fe["dofs"] if isinstance(fe.get("dofs"), str) else fe.get("dofs"),
                          node_sets=folder / sets if isinstance(sets, str) else sets, format=fe.get("format"))
    structure = model.to_structure()
    damping = structure.damping
    if "rayleigh" in fe:
        r = fe["rayleigh"]
        if not (isinstance(r, list) and len(r) == 2):
            raise ParameterError(f"[fe] rayleigh must be [alpha, beta], got {r!r}")
        alpha, beta = (check_real(f"[fe] rayleigh[{i}]", v) for i, v in enumerate(r))
        damping = alpha * structure.mass + beta * structure.stiffness
    return {"dofs": list(structure.dof_names), "mass": structure.mass, "stiffness": structure.stiffness,
            "damping": damping}
