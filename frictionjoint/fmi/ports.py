"""Port names of a system of FMUs, ``"component.variable"``, and the checks of a system's components,
connections and parameters: read by the masters (:mod:`frictionjoint.fmi.cosim`,
:mod:`frictionjoint.fmi.me_master`) and by the SSP writer (:mod:`frictionjoint.fmi.ssp`), below them."""
from __future__ import annotations

from pathlib import Path

from ..errors import ParameterError

__all__ = ["split_port", "checked_components", "checked_connections", "checked_parameters"]


def split_port(name: str) -> tuple[str, str]:
    """``(component, variable)`` of the port ``"component.variable"``.

    Parameters
    ----------
    name : str
        The port, ``"component.variable"`` (the variable's name may contain dots).

    Returns
    -------
    (str, str)

    Raises
    ------
    ParameterError
        If ``name`` has no dot, or nothing before or after its first dot.
    """
    component, sep, variable = str(name).partition(".")
    if not sep or not component or not variable:
        raise ParameterError(f"ports are named 'component.variable', got {name!r}")
    return component, variable


def checked_components(components) -> dict:
    """``components`` (name -> ``.fmu`` path) as ``{str: Path}``: at least one, each name non-empty and
    without ``'.'``, each file there; else :class:`ParameterError` naming it."""
    checked = {str(k): Path(v) for k, v in dict(components).items()}
    if not checked:
        raise ParameterError("components must name at least one FMU")
    for name, path in checked.items():
        if "." in name or not name:
            raise ParameterError(f"component names must be non-empty and without '.', got {name!r}")
        if not path.is_file():
            raise ParameterError(f"components[{name!r}]: FMU {str(path)!r} not found")
    return checked


def checked_connections(connections, variables: dict) -> list:
    """``connections`` (``("source.output", "target.input")`` pairs) as ``((component, output),
    (component, input))`` pairs, each port a variable of that causality in ``variables`` (component ->
    {name: fmpy variable}) and each input the target of one connection only."""
    pairs = []
    for pair in connections:
        if len(pair) != 2:
            raise ParameterError(f"connections are (source, target) pairs, got {pair!r}")
        (sc, sv), (tc, tv) = split_port(pair[0]), split_port(pair[1])
        for comp, var, causality in ((sc, sv, "output"), (tc, tv, "input")):
            if comp not in variables:
                raise ParameterError(f"connection {pair!r}: no component {comp!r}")
            v = variables[comp].get(var)
            if v is None or v.causality != causality:
                raise ParameterError(f"connection {pair!r}: {comp} has no {causality} {var!r}")
        pairs.append(((sc, sv), (tc, tv)))
    targets = [t for _, t in pairs]
    if len(set(targets)) != len(targets):
        raise ParameterError("an input may be the target of one connection only")
    return pairs


def checked_parameters(parameters, variables: dict, causalities=("parameter",)) -> dict:
    """``parameters`` (component -> {name: value}) as a dict of dicts, each name a variable of one of
    ``causalities`` of a component in ``variables``."""
    checked = {}
    for comp, values in dict(parameters).items():
        if comp not in variables:
            raise ParameterError(f"parameters: no component {comp!r}")
        for var in values:
            v = variables[comp].get(var)
            if v is None or v.causality not in causalities:
                raise ParameterError(f"parameters[{comp!r}]: {comp} has no parameter {var!r}")
        checked[comp] = dict(values)
    return checked
