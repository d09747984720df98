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

__all__ = ["Attachment", "Contact", "Slider", "MasingCycles"]


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
    contacts : list of Contact
        Unilateral normal contacts whose load sets the slip limits of some sliders (normal-load
        variation); empty: the slip limits are constant.
    slider_contact : (k,) int sequence or None
        Index into ``contacts`` of each slider's contact, -1 for a constant slip limit (None: all
        constant).
    """

    directions: object
    sliders: list
    preload: object
    stiffness: object
    force: object
    damping: object = None
    contacts: tuple = ()
    slider_contact: object = None


@dataclass(frozen=True)
class Contact:
    """A unilateral normal contact (spring and dashpot) whose normal load sets the slip limit of
    the sliders attached to it: ``N = preload - stiffness * normal . x`` while ``N > 0`` (closed),
    no force once it reaches 0 (lift-off); a slider on it slips at ``friction_coefficient * N``.

    The contact's closed-state spring ``stiffness normal normal^T``, dashpot ``damping normal
    normal^T`` and constant force ``preload normal`` are part of the :class:`Attachment`'s
    ``stiffness``, ``damping`` and ``force`` (the structure's coordinates are measured from the
    static state, where ``N = preload``); the marcher removes them while the contact is open.

    Parameters
    ----------
    normal : (n_dof,) ndarray
        Normal direction over the structure DOFs (the contact force on the structure is ``N normal``).
    stiffness : float
        Normal stiffness ``kn`` [N/m], > 0.
    damping : float
        Normal dashpot [N s/m], >= 0, acting only while the contact is closed.
    preload : float
        Normal load ``N0`` [N], > 0, at ``x = 0``.
    friction_coefficient : float
        ``mu`` [-] of the sliders on the contact, > 0.
    """

    normal: object
    stiffness: float
    damping: float
    preload: float
    friction_coefficient: float
