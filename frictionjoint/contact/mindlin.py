"""Sphere on a flat under constant normal load and varying tangential load (Cattaneo 1938;
Mindlin 1949; Mindlin & Deresiewicz 1953), both bodies of one material.

Hertz: ``a = (3 P R / (4 E*))^(1/3)`` with ``1/E* = 2 (1 - nu^2)/E``; peak pressure
``p0 = 3 P / (2 pi a^2)``. Tangential: ``S = 2 (2 - nu)/G`` with ``G = E / (2 (1 + nu))``;
stick radius ``c = a (1 - Q/(f P))^(1/3)``; tangential displacement (relative approach of remote
points) ``delta(Q) = C [1 - (1 - Q/(f P))^(2/3)]`` with ``C = 3 f P S / (16 a)``, so the initial
stiffness is ``8 a / S``; energy per cycle of ``Q`` between ``±Q*`` (``u = Q*/(f P)``)
``W = (9 f^2 P^2 S / (10 a)) [1 - (1 - u)^(5/3) - (5 u / 6) (1 + (1 - u)^(2/3))]``
(Johnson 1985, Contact Mechanics, sections 7.2-7.3; DESIGN.md section 4).

The backbone ``F(delta) = f P [1 - (1 - delta/C)^(3/2)]`` is an Iwan element with density
``k rho(phi) = (3 f P / (4 C^2)) (1 - phi/C)^(-1/2)`` on ``0 < phi < C``.
"""
from __future__ import annotations

import math

import numpy as np

from ..elements.iwan import Iwan, check_n_sliders
from ..elements.masing import ContinuousIwan, odd_backbone
from ..errors import ParameterError, check_nonnegative, check_poisson_ratio, check_positive

__all__ = ["MindlinContact"]


class MindlinContact:
    """Cattaneo-Mindlin contact of a sphere of radius R on a flat, one material.

    Parameters
    ----------
    normal_load : float
        P [N], > 0 (constant).
    friction_coefficient : float
        f [-], > 0.
    radius : float
        Sphere radius R [m], > 0.
    youngs_modulus : float
        E [Pa], > 0 (both bodies).
    poisson_ratio : float
        nu [-], in (-1, 0.5).

    Attributes
    ----------
    contact_radius : float
        Hertz contact radius a [m].
    peak_pressure : float
        Hertz peak pressure p0 [Pa].
    tangential_stiffness : float
        Initial (Q = 0) tangential stiffness 8 a / S [N/m].
    slip_force : float
        f P [N] (gross slip).
    slip_displacement : float
        C = 3 f P S / (16 a) [m], the tangential displacement at gross slip.
    """

    def __init__(self, normal_load: float, friction_coefficient: float, radius: float,
                 youngs_modulus: float, poisson_ratio: float):
        self.normal_load = check_positive("normal_load", normal_load)
        self.friction_coefficient = check_positive("friction_coefficient", friction_coefficient)
        self.radius = check_positive("radius", radius)
        self.youngs_modulus = check_positive("youngs_modulus", youngs_modulus)
        nu = check_poisson_ratio("poisson_ratio", poisson_ratio)
        self.poisson_ratio = nu
        e_star = self.youngs_modulus / (2.0 * (1.0 - nu * nu))
        shear = self.youngs_modulus / (2.0 * (1.0 + nu))
        self.effective_modulus = e_star
        self.compliance = 2.0 * (2.0 - nu) / shear  # S [1/Pa]
        p = self.normal_load
        self.contact_radius = (3.0 * p * self.radius / (4.0 * e_star)) ** (1.0 / 3.0)
        a = self.contact_radius
        self.peak_pressure = 3.0 * p / (2.0 * math.pi * a * a)
        self.tangential_stiffness = 8.0 * a / self.compliance
        self.slip_force = self.friction_coefficient * p
        self.slip_displacement = 3.0 * self.slip_force * self.compliance / (16.0 * a)

    # ------------------------------------------------------------ monotonic loading
    def _check_force(self, name, q, closed=False):
        q = check_nonnegative(name, q)
        if q > self.slip_force or (not closed and q == self.slip_force):
            rel = "<=" if closed else "<"
            raise ParameterError(f"{name} must be in [0, f P] = [0, {self.slip_force:g}] N "
                                 f"({rel} f P: partial slip), got {q!r}")
        return q

    def stick_radius(self, tangential_force: float) -> float:
        """Radius of the stick zone c [m] at tangential force ``Q`` in ``[0, f P]``: ``a (1 - Q/fP)^(1/3)``."""
        q = self._check_force("tangential_force", tangential_force, closed=True)
        return self.contact_radius * (1.0 - q / self.slip_force) ** (1.0 / 3.0)

    def displacement(self, tangential_force: float) -> float:
        """Tangential displacement [m] on monotonic loading to ``Q`` in ``[0, f P]``."""
        q = self._check_force("tangential_force", tangential_force, closed=True)
        return self.slip_displacement * -math.expm1((2.0 / 3.0) * math.log1p(-q / self.slip_force)) \
            if q < self.slip_force else self.slip_displacement

    def backbone(self, u):
        """Tangential force [N] on monotonic loading to displacement ``u`` [m] (odd; f P beyond C)."""
        return odd_backbone(self._backbone_positive, u)

    def _backbone_positive(self, u):
        """``f P [1 - (1 - u/C)^(3/2)]`` for ``u >= 0`` (``f P`` beyond ``C``)."""
        x = np.minimum(np.asarray(u, dtype=float) / self.slip_displacement, 1.0)
        with np.errstate(divide="ignore"):  # log1p(-1) = -inf -> F = f P exactly
            return self.slip_force * -np.expm1(1.5 * np.log1p(-x))

    def _primitive(self, u: float) -> float:
        """``int_0^u F`` for ``0 <= u <= C``: ``f P [u - (2 C/5) (1 - (1 - u/C)^(5/2))]``."""
        c = self.slip_displacement
        x = min(u / c, 1.0)
        return self.slip_force * (u + 0.4 * c * math.expm1(2.5 * math.log1p(-x))) if x < 1 else \
            self.slip_force * (u - 0.4 * c)

    # ------------------------------------------------------------ cyclic loading
    def dissipation_per_cycle(self, force_amplitude: float) -> float:
        """Energy [J] dissipated per cycle of Q between ``±Q*``, ``0 <= Q* <= f P``
        (Mindlin & Deresiewicz 1953; Johnson 1985 eq. 7.60 with ``S`` for two bodies)."""
        q = self._check_force("force_amplitude", force_amplitude, closed=True)
        # bracket = 1 - (1-u)^(5/3) - (5u/6)(1 + (1-u)^(2/3)) = (1-t)^3 (1 + 3t + t^2)/6 with
        # t = (1-u)^(1/3): no cancellation as u -> 0 (bracket -> 5 u^3/162)
        one_minus_t = -math.expm1(math.log1p(-q / self.slip_force) / 3.0) if q < self.slip_force else 1.0
        t = 1.0 - one_minus_t
        bracket = one_minus_t ** 3 * (1.0 + 3.0 * t + t * t) / 6.0
        return 9.0 * self.slip_force ** 2 * self.compliance / (10.0 * self.contact_radius) * bracket

    def to_iwan(self, n_sliders: int | None = None, dof=None, direction=None):
        """The Iwan element with this contact's backbone.

        Parameters
        ----------
        n_sliders : int or None
            ``None``: the continuous element (:class:`~frictionjoint.elements.masing.ContinuousIwan`,
            exact). An integer ``N >= 1``: a discrete :class:`~frictionjoint.elements.iwan.Iwan` of
            ``N`` sliders over equal intervals of slider stiffness of the density
            ``k rho(phi) = (3 f P/(4 C^2)) (1 - phi/C)^(-1/2)``, each slider carrying its interval's
            exact stiffness and strength (total stiffness and slip force exact).
        dof, direction :
            Attachment of the discrete element (see :class:`~frictionjoint.elements.iwan.Iwan`).
        """
        c, fs = self.slip_displacement, self.slip_force
        if n_sliders is None:
            def density(phi):
                return 0.75 * fs / (c * c) / math.sqrt(1.0 - phi / c)

            return ContinuousIwan(self._backbone_positive, self.tangential_stiffness, fs, c,
                                  inverse=self.displacement, primitive=self._primitive, density=density)
        n_sliders = check_n_sliders("n_sliders", n_sliders)  # before the slider table is built
        # with t = sqrt(1 - phi/C): stiffness of the sliders below phi, int_0^phi k rho, is
        # (3 fP/(2C)) (1 - t), linear in t, and their strength, int_0^phi k rho(s) s ds, is
        # fP (1 - 3t/2 + t^3/2); equal steps of t are equal-stiffness intervals
        t = np.linspace(1.0, 0.0, int(n_sliders) + 1)
        k_cum = 1.5 * fs / c * (1.0 - t)
        f_cum = fs * (1.0 - 1.5 * t + 0.5 * t ** 3)
        table = list(zip(np.diff(k_cum), np.diff(f_cum)))
        return Iwan(table, dof=dof, direction=direction)
