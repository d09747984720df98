"""Rigid Coulomb slider (Hong & Liu's stop rules are applied by the marcher)."""
from __future__ import annotations

from dataclasses import dataclass
import math

from ..errors import check_nonnegative
from .base import Slider

__all__ = ["CoulombSlider"]


@dataclass(frozen=True)
class CoulombSlider:
    """Rigid Coulomb friction on a DOF (or along a direction) that has inertia.

    While slipping the element force is ``slip_force * sign(s')``; at ``s' = 0`` the slider
    sticks if the force needed to hold it is within ``slip_force`` (a stop of finite duration),
    otherwise it slips on, reversed (normal stop) or in the same direction (abnormal stop);
    a stuck slider starts to slide when the holding force reaches ``slip_force``
    (Hong & Liu 2000; seed ``frictional_damping_sliding_regime``).

    Parameters
    ----------
    slip_force : float
        Friction force limit [N], >= 0.
    dof : str or int, optional
        DOF the slider acts on.
    direction : (n_dof,) array_like, optional
        Direction vector instead of ``dof``: the slider acts on ``s = direction . x``.
    """

    slip_force: float
    dof: object = None
    direction: object = None

    def __post_init__(self):
        object.__setattr__(self, "slip_force", check_nonnegative("slip_force", self.slip_force))

    def sliders(self) -> list[Slider]:
        """The sliders the marcher handles (none when ``slip_force == 0``)."""
        return [Slider(self.slip_force, math.inf)] if self.slip_force > 0 else []
