"""Iwan elements from a backbone curve: continuous slider density, Masing loops, turning-point memory.

An Iwan element is a continuum of Jenkins sliders in parallel, slider ``phi`` having slip
displacement ``phi`` (strength ``k phi``) and stiffness density ``k rho(phi)``. Its response to
monotonic loading from the unstressed state is the backbone ``F(u)``, and
``k rho(phi) = -F''(phi)`` (Iwan 1966; Segalman 2005). Every reversal branch follows Masing's
rule ``F = F_r + s 2 F(s (u - u_r) / 2)`` from the turning point ``(u_r, F_r)``, and a branch that
reaches the turning point before its own start closes that loop and resumes the branch it left
(Madelung's memory rules). This is exact for any density: the element below evaluates the force
along any displacement path with no slider discretisation. The dissipation per cycle of
amplitude ``u*`` is ``D = 8 int_0^u* F du - 4 u* F(u*)``.
"""
from __future__ import annotations

import math
from typing import Callable, Iterable

import numpy as np
from numpy.typing import ArrayLike
import scipy.integrate
import scipy.optimize

from ..errors import ParameterError, check_nonnegative, check_positive
from .base import MasingCycles
from .iwan import check_backbone_force, segalman_density

__all__ = ["ContinuousIwan", "MasingMemory", "odd_backbone"]


def odd_backbone(positive: Callable, u):
    """``sgn(u) F(|u|)`` for a backbone ``F`` given on ``u >= 0``; a float for a scalar ``u``."""
    u = np.asarray(u, dtype=float)
    if not np.all(np.isfinite(u)):
        raise ParameterError("u must be finite")
    out = np.sign(u) * positive(np.abs(u))
    return float(out) if out.ndim == 0 else out


class ContinuousIwan(MasingCycles):
    """Iwan element with a continuous slider density, given by its backbone.

    Parameters
    ----------
    backbone : callable
        ``F(u)`` [N] for ``0 <= u`` [m], increasing and concave, ``F(0) = 0``, reaching
        ``slip_force`` at ``u = slip_displacement`` and constant beyond (vectorised over u).
    stiffness : float
        Initial stiffness ``F'(0)`` [N/m], > 0.
    slip_force : float
        Macroslip force [N], > 0.
    slip_displacement : float
        Displacement at which the last slider slips [m], > 0 (``inf`` if never reached).
    inverse : callable, optional
        ``u(F)`` on ``0 <= F < slip_force``, if known in closed form (else Brent's method).
    primitive : callable, optional
        ``int_0^u F(s) ds`` in closed form (else adaptive quadrature, ~2e-14 relative).
    density : callable, optional
        Slider stiffness density ``k rho(phi) = -F''(phi)`` [N/m^2] on ``0 < phi < slip_displacement``.
        With it the dissipation is ``int_0^u* 4 k rho(phi) phi (u* - phi) dphi`` (a positive
        integrand, accurate at small amplitude); without it, Masing's
        ``8 int F - 4 u* F(u*)``, which loses digits to cancellation as ``u*`` -> 0 (the
        result is ``O(u*^3)`` from terms ``O(u*^2)``).
    point_sliders : sequence of (stiffness, slip_displacement) pairs, optional
        Concentrated parts of the density, ``k_j delta(phi - phi_j)`` (e.g. Segalman's delta at
        ``phi_max``): stiffness ``k_j`` [N/m] > 0 and slip displacement ``phi_j`` [m] > 0. They are
        already in ``backbone``; with ``density`` they add ``4 k_j phi_j (u* - phi_j)`` for
        ``u* > phi_j`` to the dissipation (a delta is no density function).
    """

    def __init__(self, backbone: Callable, stiffness: float, slip_force: float, slip_displacement: float,
                 inverse: Callable | None = None, primitive: Callable | None = None,
                 density: Callable | None = None, point_sliders: Iterable[tuple[float, float]] = ()):
        for name, fun in (("backbone", backbone), ("inverse", inverse), ("primitive", primitive),
                          ("density", density)):
            if not callable(fun) and (name == "backbone" or fun is not None):
                raise ParameterError(f"{name} must be a callable of the slip displacement u [m], got {fun!r}")
        self._backbone = backbone
        self.stiffness = check_positive("stiffness", stiffness)
        self.slip_force = check_positive("slip_force", slip_force)
        self.slip_displacement = check_positive("slip_displacement", slip_displacement)
        self._inverse = inverse
        self._primitive = primitive
        self._density = density
        pairs = []
        for i, pair in enumerate(point_sliders):
            if np.shape(pair) != (2,):
                raise ParameterError(f"point_sliders[{i}] must be a (stiffness, slip_displacement) pair, "
                                     f"got {pair!r}")
            pairs.append((check_positive(f"point_sliders[{i}] stiffness", pair[0]),
                          check_positive(f"point_sliders[{i}] slip_displacement", pair[1])))
        self._point_sliders = tuple(pairs)

    @classmethod
    def segalman(cls, slip_force: float, stiffness: float, chi: float, beta: float) -> "ContinuousIwan":
        """Segalman's 4-parameter Iwan element, continuous (no slider discretisation).

        Density ``R phi**chi`` on ``0 < phi < phi_max`` plus ``S delta(phi - phi_max)`` (parameters
        as in :func:`~frictionjoint.elements.iwan.segalman_density`). Backbone, primitive and
        dissipation in closed form (DESIGN.md section 4, checked with sympy), ``u* = |u|``:

        - ``F = K_T u - R u**(chi+2)/((chi+1)(chi+2))`` for ``u <= phi_max``, ``F_S`` beyond: the
          slope drops from ``S`` to 0 at ``phi_max`` (the delta's sliders slip at once);
        - ``D = 4 R u***(chi+3)/((chi+2)(chi+3))`` for ``u* <= phi_max`` and
          ``D = 4 R phi_max**(chi+3)/((chi+2)(chi+3)) + 4 F_S (u* - phi_max)`` beyond.

        The backbone has no closed-form inverse (Brent's method is used).

        Parameters
        ----------
        slip_force, stiffness, chi, beta : float
            Macroslip force F_S [N] > 0, initial stiffness K_T [N/m] > 0, exponent
            -1 < chi <= 0 and delta-to-power-law stiffness ratio beta >= 0, as in
            :meth:`frictionjoint.elements.iwan.Iwan.segalman`.
        """
        chi, phi_max, r, s = segalman_density(slip_force, stiffness, chi, beta)
        kt = float(stiffness)
        c = r / ((chi + 1.0) * (chi + 2.0))

        def backbone(u):
            return kt * u - c * u ** (chi + 2.0)

        def primitive(u):
            return 0.5 * kt * u * u - c * u ** (chi + 3.0) / (chi + 3.0)

        def density(phi):
            return r * phi ** chi

        return cls(backbone, kt, float(slip_force), phi_max, primitive=primitive, density=density,
                   point_sliders=((s, phi_max),) if s > 0 else ())

    def backbone(self, u: ArrayLike) -> float | np.ndarray:
        """Force [N] on monotonic loading from the unstressed state to displacement ``u`` [m] (odd).

        Parameters
        ----------
        u : float or array_like
            Displacement [m], finite; beyond ``slip_displacement`` the force stays at ``slip_force``.

        Returns
        -------
        float or ndarray
            Backbone force [N], a float for a scalar ``u``, else an array of the shape of ``u``.
        """
        return odd_backbone(lambda a: self._backbone(np.minimum(a, self.slip_displacement)), u)

    def displacement(self, force: float) -> float:
        """Displacement amplitude [m] at which the backbone reaches ``force`` [N], ``|force| < slip_force``.

        Parameters
        ----------
        force : float
            Backbone force [N], ``|force| < slip_force``.

        Returns
        -------
        float
            Displacement [m] on the backbone, with the sign of ``force`` (closed-form ``inverse`` if
            given, else Brent's method).
        """
        q = check_backbone_force(force, self.slip_force)
        if q == 0.0:
            return 0.0
        if self._inverse is not None:
            return math.copysign(float(self._inverse(q)), force)
        hi = self.slip_displacement if math.isfinite(self.slip_displacement) else q / self.stiffness
        while not math.isfinite(self.slip_displacement) and self._backbone(hi) < q:
            hi *= 2.0
        u = scipy.optimize.brentq(lambda x: self._backbone(x) - q, 0.0, hi, xtol=1e-300, rtol=4.0 * np.finfo(float).eps)
        return math.copysign(u, force)

    def _energy(self, u: float) -> float:
        """``int_0^u F(s) ds`` for ``u >= 0``."""
        if self._primitive is not None:
            return float(self._primitive(u))
        val, _ = scipy.integrate.quad(self._backbone, 0.0, u, epsabs=0.0, epsrel=2e-14, limit=200)
        return float(val)

    def dissipation_per_displacement_cycle(self, displacement_amplitude: float) -> float:
        """Energy [J] dissipated per cycle of ``u`` between ``±u*`` (Masing: ``8 int F - 4 u* F(u*)``).

        Parameters
        ----------
        displacement_amplitude : float
            Displacement amplitude ``u*`` [m], >= 0.

        Returns
        -------
        float
            Energy dissipated per cycle [J] (from ``density`` and ``point_sliders`` if a density is
            given, else from Masing's rule).
        """
        a = check_nonnegative("displacement_amplitude", displacement_amplitude)
        if self._density is not None:
            top = min(a, self.slip_displacement)
            val, _ = scipy.integrate.quad(lambda p: 4.0 * self._density(p) * p * (a - p), 0.0, top,
                                          epsabs=0.0, epsrel=1e-13, limit=400)
            return float(val) + sum(4.0 * k * phi * (a - phi) for k, phi in self._point_sliders if a > phi)
        return 8.0 * self._energy(min(a, self.slip_displacement)) \
            + 8.0 * self.slip_force * max(a - self.slip_displacement, 0.0) - 4.0 * a * self.backbone(a)

    def memory(self) -> "MasingMemory":
        """A fresh turning-point memory (unstressed state at ``u = 0``) for arbitrary paths."""
        return MasingMemory(self.backbone)


class MasingMemory:
    """Force of an Iwan element along an arbitrary displacement path, exactly.

    Masing branches from turning points with Madelung's memory rules: a loop closes when its
    branch reaches the turning point before its start, and the branch interrupted by the loop
    resumes; the virgin curve is the backbone itself.

    Parameters
    ----------
    backbone : callable
        Odd backbone ``F(u)`` [N] (e.g. :meth:`ContinuousIwan.backbone`).
    """

    def __init__(self, backbone: Callable):
        self._f = backbone
        self.u = 0.0
        self.force = 0.0
        self._turns: list[tuple[float, float]] = []  # alternating turning points, oldest first
        self._dir = 0  # direction of the current branch: +1, -1, 0 (none yet)

    def _branch(self, u: float) -> float:
        if not self._turns:
            return float(self._f(u))
        ur, fr = self._turns[-1]
        s = self._dir
        return fr + s * 2.0 * float(self._f(s * (u - ur) / 2.0))

    def _closure(self):
        """The point where the current branch closes a loop: the turning point before its start,
        or the mirror of the first turning point on the virgin curve."""
        if len(self._turns) >= 2:
            return self._turns[-2]
        ur, fr = self._turns[-1]
        return -ur, -fr

    def update(self, u: float) -> float:
        """Move monotonically from the current displacement to ``u`` [m]; return the force [N]."""
        u = float(u)
        if not math.isfinite(u):
            raise ParameterError(f"u must be finite, got {u!r}")
        if u == self.u:
            return self.force
        s = 1 if u > self.u else -1
        if s != self._dir and self._dir != 0:  # a reversal: a new turning point
            self._turns.append((self.u, self.force))
        self._dir = s
        while self._turns:
            uc, _ = self._closure()
            if s * (u - uc) < 0:
                break
            # the loop closes at uc: forget it and resume the interrupted branch
            if len(self._turns) >= 2:
                del self._turns[-2:]
            else:
                self._turns.clear()
        self.u = u
        self.force = self._branch(u)
        return self.force

    def path(self, displacements) -> np.ndarray:
        """Forces [N] along a sequence of displacements [m] (each step monotonic)."""
        return np.array([self.update(x) for x in np.asarray(displacements, dtype=float)])
