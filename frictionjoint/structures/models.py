"""Blade model definitions: a blade, its rotor, its root and its excitation as data (TOML) with
their source; the definitions of the repository live in its top-level ``models/`` folder.

A definition (SI units)::

    name = "Ti64CompressorBlade"
    source = "where the numbers come from"
    [blade]            # BeamBlade's arguments: length, width, thickness, youngs_modulus,
                       # density, and optionally n_elements, bending, rayleigh = [alpha, beta];
                       # or, with kind = "solid", SolidBlade's: length, width, thickness,
                       # youngs_modulus, poisson_ratio, density, and optionally twist, taper,
                       # n_elements (an int or [span, chord, thickness]), rayleigh
    [rotor]            # optional: speed [rad/s], hub_radius [m]
    [root]             # optional: the root joint's parameters (e.g. a dovetail's)
    [excitation]       # optional: e.g. tip_force_amplitude [N]; a solid blade's tip_point
                       # ("centre", "leading_edge", "trailing_edge": where on the tip face)

A beam blade's root is a point-contact :class:`~frictionjoint.elements.DovetailRoot`; a solid
blade's is its root face's edges on the flanks as contact patches
(:mod:`~frictionjoint.structures.solid_root`), with the same ``[root]`` parameters (per flank).

:func:`load_blade_model` reads one.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

from ..errors import ParameterError
from .beam import BeamBlade
from .solid import SolidBlade

__all__ = ["BladeModel", "load_blade_model", "blade_model_names", "MODELS_DIR", "BLADE_KINDS"]

#: the repository's model definitions (a source checkout: next to the package)
MODELS_DIR = Path(__file__).resolve().parents[2] / "models"

_BLADE_KEYS = ("length", "width", "thickness", "youngs_modulus", "density", "n_elements", "bending", "rayleigh")
_SOLID_KEYS = ("length", "width", "thickness", "youngs_modulus", "poisson_ratio", "density", "twist", "taper",
               "n_elements", "rayleigh")
#: the blade kinds of a definition's [blade] ``kind``, and their classes
BLADE_KINDS = {"beam": BeamBlade, "solid": SolidBlade}
_SECTIONS = ("name", "source", "blade", "rotor", "root", "excitation")


@dataclass(frozen=True)
class BladeModel:
    """A blade model definition (see the module docstring).

    Attributes
    ----------
    name, source : str
        Its name and where its numbers come from.
    blade_parameters : dict
        :class:`~frictionjoint.structures.BeamBlade`'s (or SolidBlade's) arguments, the rotor's included.
    root, excitation : dict
        The root joint's and the excitation's parameters, as written.
    path : Path
        The file.
    """

    name: str
    source: str
    blade_parameters: dict = field(default_factory=dict)
    root: dict = field(default_factory=dict)
    excitation: dict = field(default_factory=dict)
    path: Path | None = None
    kind: str = "beam"

    def blade(self, **overrides) -> BeamBlade | SolidBlade:
        """The :class:`~frictionjoint.structures.BeamBlade` (or, ``kind = "solid"``,
        :class:`~frictionjoint.structures.SolidBlade`) of the definition, with ``overrides`` of its
        arguments (e.g. ``rotor_speed=0.0``).

        Parameters
        ----------
        **overrides
            The blade's arguments that replace the definition's.

        Returns
        -------
        BeamBlade or SolidBlade
        """
        return BLADE_KINDS[self.kind](**dict(self.blade_parameters, **overrides))


def _tomllib():
    try:
        import tomllib
    except ModuleNotFoundError:  # Python < 3.11
        import tomli as tomllib
    return tomllib


def read_definition_file(path: str | os.PathLike, what: str) -> dict:
    """The top-level table of a definition file: JSON if its suffix is ``.json``, else TOML.

    Every way the file can fail to be one (not UTF-8 text, e.g. binary garbage; a syntax error;
    a top level that is not a table) is a one-line :class:`~frictionjoint.errors.ParameterError`
    that names the file and the reason.

    Parameters
    ----------
    path : path
        The file (it exists).
    what : str
        What the file is, for the messages (``"system definition"``).

    Returns
    -------
    dict
    """
    import json

    path = Path(path)
    kind = "JSON" if path.suffix.lower() == ".json" else "TOML"
    try:
        data = path.read_bytes()
        text = data.decode("utf-8-sig")  # a byte-order mark (a Windows editor's) is not the text
    except UnicodeDecodeError as exc:
        raise ParameterError(f"{path}: not a {what} file: byte {data[exc.start]:#04x} at offset {exc.start} is not "
                             f"UTF-8 text") from None
    except OSError as exc:
        raise ParameterError(f"{path}: cannot read the {what} file ({exc.strerror})") from None
    tomllib = _tomllib()
    try:
        table = json.loads(text) if kind == "JSON" else tomllib.loads(text)
    except (json.JSONDecodeError, tomllib.TOMLDecodeError) as exc:
        raise ParameterError(f"{path}: the {what} file is not valid {kind}: {' '.join(str(exc).split())}") from None
    if not isinstance(table, dict):
        raise ParameterError(f"{path}: a {what} file holds a table, got {type(table).__name__}")
    return table


def load_blade_model(name_or_path: str | os.PathLike) -> BladeModel:
    """Read a blade model definition: a ``.toml`` path, or the name of a file in
    :data:`MODELS_DIR` (with or without ``.toml``).

    Parameters
    ----------
    name_or_path : str or os.PathLike
        E.g. ``"ti64_compressor_blade"`` or ``"models/ti64_compressor_blade.toml"``.

    Returns
    -------
    BladeModel
    """
    path = Path(name_or_path)
    if not path.is_file():
        stem = path.name if path.suffix == ".toml" else f"{path.name}.toml"
        path = MODELS_DIR / stem
    if not path.is_file():
        raise ParameterError(f"name_or_path: blade model {str(name_or_path)!r} not found; give a .toml file or one "
                             f"of the blade models of {MODELS_DIR}: {blade_model_names()}")
    data = read_definition_file(path, "blade model")
    unknown = set(data) - set(_SECTIONS)
    if unknown:
        raise ParameterError(f"{path.name}: unknown keys {sorted(unknown)} (allowed: {list(_SECTIONS)})")
    blade = dict(data.get("blade", {}))
    kind = blade.pop("kind", "beam")
    if kind not in BLADE_KINDS:
        raise ParameterError(f"{path.name}: [blade] kind must be one of {list(BLADE_KINDS)}, got {kind!r}")
    keys = _SOLID_KEYS if kind == "solid" else _BLADE_KEYS
    bad = set(blade) - set(keys)
    if bad or not blade:
        raise ParameterError(f"{path.name}: [blade] must hold {BLADE_KINDS[kind].__name__}'s arguments {list(keys)}, "
                             f"got {sorted(blade)}")
    if isinstance(blade.get("n_elements"), list):
        blade["n_elements"] = tuple(blade["n_elements"])
    rotor = dict(data.get("rotor", {}))
    if set(rotor) - {"speed", "hub_radius"}:
        raise ParameterError(f"{path.name}: [rotor] takes speed and hub_radius, got {sorted(rotor)}")
    if "speed" in rotor:
        blade["rotor_speed"] = rotor["speed"]
    if "hub_radius" in rotor:
        blade["hub_radius"] = rotor["hub_radius"]
    if "rayleigh" in blade:
        blade["rayleigh"] = tuple(blade["rayleigh"])
    model = BladeModel(str(data.get("name", path.stem)), str(data.get("source", "")), blade,
                       dict(data.get("root", {})), dict(data.get("excitation", {})), path, kind)
    if kind == "beam":
        model.blade()  # every value checked now, with the parameter's name in the error (a solid blade's
        # assembly takes a second: from_model checks it)
    return model


def blade_model_names() -> list[str]:
    """The names of the blade model definitions in :data:`MODELS_DIR` (its ``.toml`` files with a
    ``[blade]`` table; structure definitions such as ``two_dof_chain`` are not blade models).

    Returns
    -------
    list of str
        Sorted; empty outside a source checkout.
    """
    tomllib = _tomllib()
    names = []
    for path in sorted(MODELS_DIR.glob("*.toml")) if MODELS_DIR.is_dir() else []:
        try:
            if "blade" in tomllib.loads(path.read_text(encoding="utf-8")):
                names.append(path.stem)
        except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):  # not a definition: not listed
            continue
    return names
