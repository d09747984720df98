"""Iwan element: Jenkins sliders in parallel (discrete), with the Segalman 4-parameter form."""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterable

import numpy as np
from numpy.typing import ArrayLike

from ..errors import ParameterError, check_nonnegative, check_positive, check_real
from .base import MasingCycles, Slider

__all__ = ["Iwan", "segalman_density", "MAX_SLIDERS", "check_n_sliders", "check_backbone_force"]

#: The most sliders a discrete Iwan element holds. Building one costs about 10 us per slider (the
#: validated table: 1 s at this bound, 43 s at 1e7) and every update of a driven joint is O(n)
#: (about 10 ms at this bound);
#: the discretisation error of the Segalman and Mindlin tables falls as ``n**-2`` (1e-10 of the
#: dissipation here), far below anything physical: more sliders buy only time and memory.
MAX_SLIDERS = 100_000


def check_n_sliders(name: str, value) -> int:
    """``value`` as an int in ``[1, MAX_SLIDERS]`` or a :class:`ParameterError` naming ``name``."""
    if (isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer))
            or not 1 <= value <= MAX_SLIDERS):
        raise ParameterError(f"{name} must be an integer in [1, {MAX_SLIDERS}], got {value!r}")
    return int(value)


def check_backbone_force(force, slip_force: float) -> float:
    """``|force|`` [N] for the inverse of an Iwan backbone (discrete or continuous), where it is
    defined: ``|force| < slip_force``, the macroslip force; else a :class:`ParameterError` naming
    ``force`` and that range."""
    q = abs(float(force))
    if not (math.isfinite(q) and q < slip_force):
        raise ParameterError(f"force must be in (-{slip_force:g}, {slip_force:g}) N "
                             f"(below the macroslip force), got {force!r}")
    return q


def segalman_density(slip_force, stiffness, chi, beta):
    """Validated Segalman parameters and the density they define.

    Segalman (2005), "A four-parameter Iwan model for lap-type joints", J. Appl. Mech. 72:
    slider stiffness density ``rho(phi) = R phi**chi`` on ``0 < phi < phi_max`` plus
    ``S delta(phi - phi_max)``, with ``beta = S / (R phi_max**(chi+1)/(chi+1))`` the stiffness
    of the delta over that of the power-law part, so that the total stiffness is
    ``K_T = R phi_max**(chi+1)/(chi+1) + S`` and the macroslip force
    ``F_S = R phi_max**(chi+2)/(chi+2) + S phi_max``.

    Parameters
    ----------
    slip_force, stiffness, chi, beta : float
        F_S [N], K_T [N/m], chi and beta as in :meth:`Iwan.segalman` (validated here).

    Returns
    -------
    chi : float
    phi_max : float
        Largest slider slip displacement [m].
    r : float
        ``R`` [N/m^(chi+2)].
    s : float
        ``S`` [N/m].
    """
    fs = check_positive("slip_force", slip_force)
    kt = check_positive("stiffness", stiffness)
    chi = check_real("chi", chi)
    if not -1.0 < chi <= 0.0:
        raise ParameterError(f"chi must be in (-1, 0], got {chi!r}")
    beta = check_real("beta", beta)
    if beta < 0:
        raise ParameterError(f"beta must be >= 0, got {beta!r}")
    c = (chi + 1.0) / (chi + 2.0)
    phi_max = fs * (1.0 + beta) / (kt * (beta + c))
    r = fs * (chi + 1.0) / (phi_max ** (chi + 2.0) * (beta + c))
    s = fs * beta / (phi_max * (beta + c))
    return chi, phi_max, r, s


@dataclass(frozen=True)
class Iwan(MasingCycles):
    """Parallel Jenkins sliders on one DOF (or direction).

    Parameters
    ----------
    sliders : sequence of (stiffness, slip_force) pairs
        Each pair is one Jenkins slider: stiffness [N/m] > 0, slip force [N] > 0.
    dof : str or int, optional
        DOF the element connects to the ground.
    direction : (n_dof,) array_like, optional
        Direction vector instead of ``dof``.
    """

    sliders_table: tuple
    dof: object = None
    direction: object = None

    def __init__(self, sliders: Iterable[tuple[float, float]], dof: str | int | None = None,
                 direction: ArrayLike | None = None):
        table = []
        try:
            pairs = list(sliders)
        except TypeError:
            raise ParameterError("sliders must be a sequence of (stiffness, slip_force) pairs") from None
        if not pairs:
            raise ParameterError("sliders must hold at least one (stiffness, slip_force) pair")
        if len(pairs) > MAX_SLIDERS + 1:  # + 1: the Segalman delta beside MAX_SLIDERS power-law sliders
            raise ParameterError(f"sliders must hold at most {MAX_SLIDERS + 1} pairs, got {len(pairs)}")
        for i, pair in enumerate(pairs):
            if np.shape(pair) != (2,):
                raise ParameterError(f"sliders[{i}] must be a (stiffness, slip_force) pair, got {pair!r}")
            k = check_positive(f"sliders[{i}] stiffness", pair[0])
            f = check_positive(f"sliders[{i}] slip_force", pair[1])
            table.append((k, f))
        object.__setattr__(self, "sliders_table", tuple(table))
        object.__setattr__(self, "dof", dof)
        object.__setattr__(self, "direction", direction)

    @classmethod
    def segalman(cls, slip_force: float, stiffness: float, chi: float, beta: float, n_sliders: int = 50,
                 dof: str | int | None = None, direction: ArrayLike | None = None) -> Iwan:
        """Discrete Segalman 4-parameter Iwan element.

        Density of slider slip displacements (Segalman 2005, "A four-parameter Iwan model
        for lap-type joints", J. Appl. Mech. 72; see :func:`segalman_density`):
        ``rho(phi) = R phi**chi`` on ``0 < phi < phi_max`` plus ``S delta(phi - phi_max)``, with
        ``phi_max = F_S (1 + beta) / (K_T (beta + (chi+1)/(chi+2)))``,
        ``R = F_S (chi+1) / (phi_max**(chi+2) (beta + (chi+1)/(chi+2)))`` and
        ``S = F_S beta / (phi_max (beta + (chi+1)/(chi+2)))``. The continuous element with the
        same parameters is :meth:`frictionjoint.elements.masing.ContinuousIwan.segalman`; this
        one converges to it as ``O(n_sliders**-2)`` in dissipation per cycle.
        The power-law part is split into ``n_sliders`` equal intervals of ``phi``; each slider
        carries that interval's exact stiffness and strength, so the total stiffness ``K_T`` and
        the total slip force ``F_S`` are reproduced exactly.

        Parameters
        ----------
        slip_force : float
            Macroslip force F_S [N], > 0.
        stiffness : float
            Initial tangential stiffness K_T [N/m], > 0.
        chi : float
            Power-law exponent, -1 < chi <= 0 (typical -0.5 ... -0.1).
        beta : float
            Stiffness of the delta at ``phi_max`` relative to the power-law part, >= 0.
        n_sliders : int
            Number of sliders for the power-law part, in ``[1, MAX_SLIDERS]``.
        dof : str or int, optional
            DOF the element connects to the ground.
        direction : (n_dof,) array_like, optional
            Direction vector instead of ``dof``.

        Returns
        -------
        Iwan
            ``n_sliders`` sliders, plus one for the delta at ``phi_max`` when ``beta > 0``.
        """
        chi, phi_max, r, s = segalman_density(slip_force, stiffness, chi, beta)
        edges = np.linspace(0.0, phi_max, check_n_sliders("n_sliders", n_sliders) + 1)
        k = r * np.diff(edges ** (chi + 1.0)) / (chi + 1.0)
        f = r * np.diff(edges ** (chi + 2.0)) / (chi + 2.0)
        table = list(zip(k, f))
        if s > 0:
            table.append((s, s * phi_max))
        return cls(table, dof=dof, direction=direction)

    @property
    def stiffness(self) -> float:
        """Initial (all stuck) stiffness [N/m]."""
        return float(sum(k for k, _ in self.sliders_table))

    @property
    def slip_force(self) -> float:
        """Macroslip force [N] (all sliders slipping)."""
        return float(sum(f for _, f in self.sliders_table))

    def _table(self):
        k = np.array([p[0] for p in self.sliders_table])
        f = np.array([p[1] for p in self.sliders_table])
        return k, f, f / k

    def backbone(self, u: ArrayLike) -> float | np.ndarray:
        """Force [N] on monotonic loading from the unstressed state to displacement ``u`` [m] (odd).

        ``F(u) = sum_i min(k_i |u|, f_i) sgn(u)``: piecewise linear.

        Parameters
        ----------
        u : float or array_like
            Displacement [m], finite.

        Returns
        -------
        float or ndarray
            Backbone force [N], a float for a scalar ``u``, else an array of the shape of ``u``.
        """
        k, f, _ = self._table()
        u = np.asarray(u, dtype=float)
        if not np.all(np.isfinite(u)):
            raise ParameterError("u must be finite")
        out = np.sign(u) * np.minimum(np.multiply.outer(np.abs(u), k), f).sum(axis=-1)
        return float(out) if out.ndim == 0 else out

    def displacement(self, force: float) -> float:
        """Displacement [m] where the backbone reaches ``force`` [N], ``|force| < slip_force`` (exact).

        Parameters
        ----------
        force : float
            Backbone force [N], ``|force| < slip_force``.

        Returns
        -------
        float
            Displacement [m] on the backbone, with the sign of ``force``.
        """
        q = check_backbone_force(force, self.slip_force)
        k, f, phi = self._table()
        order = np.argsort(phi)
        k, f, phi = k[order], f[order], phi[order]
        # at u = phi_j: F = sum_{i<j} f_i + phi_j sum_{i>=j} k_i (non-decreasing)
        slipped = np.concatenate([[0.0], np.cumsum(f)[:-1]])
        stuck_k = np.cumsum(k[::-1])[::-1]
        at_knots = slipped + phi * stuck_k
        # sliders 0..j-1 slip at the answer (j < N: q below the macroslip force, up to rounding)
        j = min(int(np.searchsorted(at_knots, q, side="right")), len(k) - 1)
        u = (q - slipped[j]) / stuck_k[j]
        return float(np.copysign(u, force))

    def dissipation_per_displacement_cycle(self, displacement_amplitude: float) -> float:
        """Energy [J] per cycle of ``u`` between ``±u*``: ``sum_{phi_i < u*} 4 f_i (u* - phi_i)``.

        Parameters
        ----------
        displacement_amplitude : float
            Displacement amplitude ``u*`` [m], >= 0.

        Returns
        -------
        float
            Energy dissipated per cycle [J].
        """
        a = check_nonnegative("displacement_amplitude", displacement_amplitude)
        _, f, phi = self._table()
        return float(np.sum(4.0 * f * np.maximum(a - phi, 0.0)))

    def sliders(self) -> list[Slider]:
        """The sliders the marcher handles."""
        return [Slider(f, k) for k, f in self.sliders_table]
