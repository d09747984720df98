"""The two linear limits of a friction system: every slider stuck, every slider slipping.

A joint's nonlinear response lies between two linear systems of the same structure:

- **stuck**: every Jenkins slider sticks, its spring ``k d d^T`` adds to the stiffness (a stuck
  dovetail root: ``2 (kn sin^2 g + kt cos^2 g)`` tangentially);
- **slipping** (free slip): every slider slips and carries a constant force, so only the
  structure and the elements' linear springs remain (the dovetail's normal springs).

The slip forces are constant in the slipping limit and do not enter a frequency response. Rigid
Coulomb sliders have no finite stuck stiffness: a system with them has no stuck limit here.
Both limits come as python-control state-space models (state ``[x, v]``, inputs: forces on all
DOFs, outputs: all displacements), whose poles give the natural frequencies and damping ratios.
"""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from .errors import ParameterError, check_system
from .structure import LinearStructure
from .system import FrictionSystem

if TYPE_CHECKING:
    import control

__all__ = ["linear_limits", "limit_structures", "LIMITS"]

#: the names of the two limits
LIMITS = ("stuck", "slipping")


def limit_structures(system: FrictionSystem) -> dict[str, LinearStructure]:
    """The stuck and the slipping limit of ``system`` as linear structures.

    Parameters
    ----------
    system : FrictionSystem
        Structure and joint elements (the excitation is not used).

    Returns
    -------
    dict
        ``{"stuck": LinearStructure, "slipping": LinearStructure}``, the structure's DOF names.
    """
    check_system("system", system, FrictionSystem)
    if np.any(system.rigid):
        raise ParameterError("system must have no rigid Coulomb sliders (they have no finite stuck stiffness)")
    d, k = system.slider_direction, system.slider_stiffness
    k_stuck = system.stiffness + (d.T * k) @ d
    names = system.structure.dof_names
    indefinite = system.structure.indefinite_stiffness
    return {name: LinearStructure(system.mass, kk, system.damping, dof_names=names, indefinite_stiffness=indefinite)
            for name, kk in (("stuck", k_stuck), ("slipping", system.stiffness))}


def linear_limits(system: FrictionSystem) -> dict[str, "control.StateSpace"]:
    """The stuck and the slipping limit of ``system`` as python-control state-space models.

    Parameters
    ----------
    system : FrictionSystem
        Structure and joint elements.

    Returns
    -------
    dict
        ``{"stuck": StateSpace, "slipping": StateSpace}``: state ``[x, v]``, inputs the forces on
        the DOFs [N], outputs the displacements [m] (:meth:`LinearStructure.to_statespace`); e.g.
        ``control.damp(limits["stuck"])`` gives the natural frequencies and damping ratios,
        ``limits["stuck"].frequency_response(omegas)`` the receptances.
    """
    return {name: s.to_statespace() for name, s in limit_structures(system).items()}
