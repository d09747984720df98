"""Port names of a system of FMUs, ``"component.variable"``: read by the master
(:mod:`frictionjoint.fmi.cosim`) and by the SSP writer (:mod:`frictionjoint.fmi.ssp`), below both."""
from __future__ import annotations

from ..errors import ParameterError

__all__ = ["split_port"]


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
