"""Jenkins element: a spring in series with a Coulomb slider."""
from __future__ import annotations

from dataclasses import dataclass

from ..errors import check_nonnegative, check_positive
from .base import Slider

__all__ = ["Jenkins"]


@dataclass(frozen=True)
class Jenkins:
    """Spring ``tangential_stiffness`` in series with a massless slider of strength ``slip_force``.

    Stuck: force ``T = tangential_stiffness * (s - w)`` with the slider position ``w`` fixed;
    slipping: ``|T| = slip_force`` and ``w`` follows ``s``. The slider sticks when ``s'`` changes
    sign and slips when ``|T|`` reaches ``slip_force``.

    Parameters
    ----------
    tangential_stiffness : float
        Spring stiffness [N/m], > 0.
    slip_force : float
        Slip force [N], >= 0 (0: the element exerts no force).
    dof : str or int, optional
        DOF the element connects to the ground.
    direction : (n_dof,) array_like, optional
        Direction vector instead of ``dof``: the element acts on ``s = direction . x``.
    """

    tangential_stiffness: float
    slip_force: float
    dof: object = None
    direction: object = None

    def __post_init__(self):
        object.__setattr__(self, "tangential_stiffness",
                           check_positive("tangential_stiffness", self.tangential_stiffness))
        object.__setattr__(self, "slip_force", check_nonnegative("slip_force", self.slip_force))

    def sliders(self) -> list[Slider]:
        """The sliders the marcher handles (none when ``slip_force == 0``)."""
        if self.slip_force == 0:
            return []
        return [Slider(self.slip_force, self.tangential_stiffness)]
