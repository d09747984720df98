"""Profiles of plane (2D) contacts: the initial gap ``h(x)`` between two bodies pressed together.

``h(x)`` [m] is the separation of the undeformed surfaces at abscissa ``x`` [m] once the bodies
touch (the rigid approach removed), so ``h >= 0`` with ``h = 0`` at the first point of contact;
only its slope ``h'(x)`` enters the half-plane contact problem
(:class:`~frictionjoint.contact.halfplane.HalfPlaneContact`). A profile must be convex
(``h'`` non-decreasing) over the contact for a single contact interval.

Points where ``h'`` or ``h''`` jumps (the corners of a punch, the apex of a wedge) are
*breakpoints*: the quadratures are split there, and a jump of ``h'`` is integrated in closed
form in the pressure (a logarithmic peak, as at a wedge apex).
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

from ..errors import ParameterError, check_nonnegative, check_positive, check_real

__all__ = ["Profile", "HertzCylinder", "RoundedFlatPunch", "Wedge"]

# sixth-order finite-difference stencils for h' (step s): central, and one-sided (forward; the
# backward one is its mirror) for points next to a breakpoint
_CENTRAL = (np.array([-3.0, -2.0, -1.0, 1.0, 2.0, 3.0]),
            np.array([-1.0, 9.0, -45.0, 45.0, -9.0, 1.0]) / 60.0)
_FORWARD = (np.arange(7.0),
            np.array([-49.0 / 20.0, 6.0, -15.0 / 2.0, 20.0 / 3.0, -15.0 / 4.0, 6.0 / 5.0, -1.0 / 6.0]))
_STEP = 1e-3  # finite-difference step relative to the length scale of the contact


class Profile:
    """A general plane profile: the initial gap ``h(x)`` and its slope.

    Parameters
    ----------
    h : callable
        Initial gap ``h(x)`` [m] for ``x`` [m], vectorised over numpy arrays; ``h >= 0`` over the
        contact (only ``h'`` enters the solution, but ``h < 0`` in the contact is rejected as a
        profile that already interpenetrates).
    dh : callable, optional
        Slope ``h'(x)`` [-], vectorised. If omitted, ``h'`` is computed by sixth-order finite
        differences with step ``1e-3`` times the current contact (or stick-zone) half-width,
        one-sided within three steps of a breakpoint; relative error about ``1e-12`` for a
        smooth ``h`` that is small (a gap, not an absolute height) over the contact.
    breakpoints : sequence of float, optional
        Abscissae [m] where ``h'`` or ``h''`` is discontinuous. Quadratures are split there;
        a jump of ``h'`` at an undeclared point loses accuracy (not correctness).
    symmetric : bool, optional
        Declares ``h(-x) = h(x)``; with no tilt the contact and the stick zone are then centred
        on ``x = 0`` without solving for their offsets.
    """

    def __init__(self, h: Callable, dh: Callable | None = None, breakpoints=(), symmetric: bool = False):
        if not callable(h):
            raise ParameterError(f"h must be a callable h(x) [m], got {h!r}")
        if dh is not None and not callable(dh):
            raise ParameterError(f"dh must be None or a callable h'(x) [-], got {dh!r}")
        try:
            points = [check_real(f"breakpoints[{i}]", b) for i, b in enumerate(breakpoints)]
        except TypeError:
            raise ParameterError(f"breakpoints must be a sequence of real numbers [m], got {breakpoints!r}") from None
        if len(set(points)) != len(points):
            raise ParameterError(f"breakpoints must be distinct, got {list(breakpoints)!r}")
        self._h = h
        self._dh = dh
        self.breakpoints = tuple(sorted(points))
        self.symmetric = bool(symmetric)

    def gap(self, x):
        """Initial gap ``h(x)`` [m] at ``x`` [m] (array in, array out)."""
        return np.asarray(self._h(np.asarray(x, dtype=float)), dtype=float)

    def slope(self, x, scale=1.0):
        """Slope ``h'(x)`` [-] at ``x`` [m].

        Parameters
        ----------
        x : array_like
            Abscissae [m].
        scale : float or array_like
            Length [m] resolved by finite differences (the contact half-width), broadcastable
            with ``x``; unused when ``dh`` was given.
        """
        x = np.asarray(x, dtype=float)
        if self._dh is not None:
            return np.broadcast_to(np.asarray(self._dh(x), dtype=float), x.shape).copy()
        step = _STEP * np.broadcast_to(np.asarray(scale, dtype=float), x.shape)
        offsets, weights = _CENTRAL
        out = np.tensordot(weights, self.gap(x + np.multiply.outer(offsets, step)), axes=1) / step
        for b in self.breakpoints:
            near = np.abs(x - b) < 3.0 * step
            if np.any(near):
                side = np.where(x[near] >= b, 1.0, -1.0)  # difference away from the breakpoint
                s = step[near] * side
                fwd_offsets, fwd_weights = _FORWARD
                vals = self.gap(x[near] + np.multiply.outer(fwd_offsets, s))
                out[near] = np.tensordot(fwd_weights, vals, axes=1) / s
        return out

    def _half_width_guess(self, load: float, effective_modulus: float) -> float | None:
        """A starting contact half-width [m] for the load per unit length [N/m], if known."""
        return None


class HertzCylinder(Profile):
    """Cylinder of radius R on a flat (or two cylinders, ``1/R = 1/R1 + 1/R2``): ``h = x^2/(2R)``.

    Hertz (Johnson 1985, Contact Mechanics, ch. 4): ``a^2 = 4 P R/(pi E*)``, ``p0 = 2 P/(pi a)`` per unit length.

    Parameters
    ----------
    radius : float
        Relative radius of curvature R [m], > 0.
    """

    def __init__(self, radius: float):
        self.radius = check_positive("radius", radius)
        r = self.radius
        super().__init__(lambda x: 0.5 * x * x / r, lambda x: x / r, symmetric=True)

    def _half_width_guess(self, load, effective_modulus):
        return math.sqrt(4.0 * load * self.radius / (math.pi * effective_modulus))


class RoundedFlatPunch(Profile):
    """Flat punch of half-width b with corners of radius R: ``h = (|x| - b)^2/(2R)`` for ``|x| > b``.

    Ciavarella, Hills & Monno (1998), Proc. Instn Mech. Engrs 212 C: with ``sin phi0 = b/a``,
    ``P = (E* a^2/(4R)) [pi - 2 phi0 - sin 2 phi0]`` per unit length; the contact always extends
    beyond the flat (``a > b``).

    Parameters
    ----------
    flat_half_width : float
        Half-width b of the flat [m], >= 0 (0 is the Hertz cylinder).
    corner_radius : float
        Radius R of the rounded corners [m], > 0.
    """

    def __init__(self, flat_half_width: float, corner_radius: float):
        self.flat_half_width = check_nonnegative("flat_half_width", flat_half_width)
        self.corner_radius = check_positive("corner_radius", corner_radius)
        b, r = self.flat_half_width, self.corner_radius

        def h(x):
            s = np.maximum(np.abs(x) - b, 0.0)
            return 0.5 * s * s / r

        def dh(x):
            return np.sign(x) * np.maximum(np.abs(x) - b, 0.0) / r

        super().__init__(h, dh, breakpoints=(-b, b) if b > 0 else (), symmetric=True)

    def _half_width_guess(self, load, effective_modulus):
        return self.flat_half_width + math.sqrt(4.0 * load * self.corner_radius / (math.pi * effective_modulus))


class Wedge(Profile):
    """Symmetric blunt wedge: ``h = |x| tan(angle)``.

    The pressure has a logarithmic peak at the apex, ``p = (E* tan(angle)/pi) arccosh(a/|x|)``,
    and ``a = P/(E* tan(angle))`` per unit length (from ``P = (E*/2) int t h'(t)/sqrt(a^2 - t^2) dt``;
    the pressure integrates to P since ``int_0^1 arccosh(1/u) du = pi/2``).

    Parameters
    ----------
    angle : float
        Angle [rad] between each flank and the undeformed surface, in (0, pi/2).
    """

    def __init__(self, angle: float):
        alpha = check_real("angle", angle)
        if not 0.0 < alpha < 0.5 * math.pi:
            raise ParameterError(f"angle must be in (0, pi/2) rad, got {angle!r}")
        self.angle = alpha
        slope = math.tan(alpha)
        super().__init__(lambda x: slope * np.abs(x), lambda x: slope * np.sign(x), breakpoints=(0.0,),
                         symmetric=True)

    def _half_width_guess(self, load, effective_modulus):
        return load / (effective_modulus * math.tan(self.angle))
