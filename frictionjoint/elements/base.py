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

from ..errors import check_nonnegative

__all__ = ["Attachment", "Slider", "MasingCycles"]


class MasingCycles:
    """Force-controlled cycles of a Masing element from its displacement-controlled ones: an
    element with ``displacement(force)`` (the backbone inverted) and
    ``dissipation_per_displacement_cycle(amplitude)`` gets :meth:`dissipation_per_cycle`."""

    def dissipation_per_cycle(self, force_amplitude: float) -> float:
        """Energy [J] dissipated per cycle of the force between ``±Q*``, ``0 <= Q* < slip_force``.

        Parameters
        ----------
        force_amplitude : float
            Force amplitude ``Q*`` [N], ``0 <= Q* < slip_force``.

        Returns
        -------
        float
            Energy dissipated per cycle [J].
        """
        q = check_nonnegative("force_amplitude", force_amplitude)
        return self.dissipation_per_displacement_cycle(self.displacement(q))


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
    damping : (n_dof, n_dof) ndarray or None
        Linear viscous damping [N s/m] the element adds (e.g. contact dashpots); None: none.
    """

    directions: object
    sliders: list
    preload: object
    stiffness: object
    force: object
    damping: object = None
