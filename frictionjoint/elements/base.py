"""Common pieces of joint elements.

A joint element acts along the relative coordinate ``s = d . x`` of the structure (``d`` a
direction vector over the DOFs) and exerts the force ``-T d`` on it, ``T`` being the element
force in the *restoring* convention (positive when it resists positive ``s``). Every element is
expanded into *sliders* for the marcher: a rigid Coulomb slider (``stiffness = inf``) or a
Jenkins slider (spring ``stiffness`` in series with a Coulomb slider of strength ``slip_force``).
"""
from __future__ import annotations

from dataclasses import dataclass
import math

__all__ = ["Attachment", "Slider"]


@dataclass(frozen=True)
class Slider:
    """One Coulomb slider, rigid (``stiffness == inf``) or behind a spring (Jenkins).

    Parameters
    ----------
    slip_force : float
        Slip force [N], > 0.
    stiffness : float
        Tangential stiffness [N/m] in series with the slider; ``math.inf`` for a rigid slider.
    """

    slip_force: float
    stiffness: float = math.inf

    @property
    def rigid(self) -> bool:
        """True for a rigid Coulomb slider (no spring in series)."""
        return math.isinf(self.stiffness)


@dataclass(frozen=True)
class Attachment:
    """What an element acting along several directions adds to a structure (see
    :meth:`~frictionjoint.elements.dovetail.DovetailRoot.attach`).

    Attributes
    ----------
    directions : (k, n_dof) ndarray
        Direction vector of each slider over the structure DOFs.
    sliders : list of Slider
        The ``k`` sliders.
    preload : (k,) ndarray
        Spring force [N] of each Jenkins slider in the state ``x = 0``.
    stiffness : (n_dof, n_dof) ndarray
        Linear stiffness [N/m] the element adds (e.g. normal contact springs).
    force : (n_dof,) ndarray
        Constant force [N] on the structure (e.g. the load that makes ``x = 0`` a static state).
    """

    directions: object
    sliders: list
    preload: object
    stiffness: object
    force: object
