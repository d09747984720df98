"""What a DOF's name means in words, for tables and plot titles: the blade models' naming
(:attr:`~frictionjoint.structures.BeamBlade.dof_names`, :func:`~frictionjoint.structures.dof_name`)
read back. Results and plots both print it, so it sits at the bottom with the results."""
from __future__ import annotations

import re

__all__ = ["dof_meaning"]


def dof_meaning(name: str) -> str:
    """What a blade DOF's name means, in words (``""`` if it is not a blade's): the beam's
    ``u<i>``, ``w<i>``, ``t<i>`` (:attr:`~frictionjoint.structures.BeamBlade.dof_names`) and the
    solid's or an FE model's ``n<node>_u<d>`` (:func:`~frictionjoint.structures.dof_name`).

    Parameters
    ----------
    name : str
        A DOF's name (anything else means nothing: ``""``).

    Returns
    -------
    str
    """
    if not isinstance(name, str):
        return ""
    beam = re.fullmatch(r"([uwt])(\d+)", name)
    if beam:
        what = {"u": "axial displacement", "w": "transverse (bending) displacement", "t": "slope dw/ds"}[beam[1]]
        return f"the {what} at beam node {beam[2]} (node 0 at the root; the tip is the last node)"
    solid = re.fullmatch(r"n(\d+)_u([123])", name)
    if solid:
        return f"the {'xyz'[int(solid[2]) - 1]} displacement of node {solid[1]}"
    return ""
