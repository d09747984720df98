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

__all__ = ["Slider"]


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
