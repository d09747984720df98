"""Plane-strain contact of two elastically similar half-planes with a general profile: normal
contact, Cattaneo partial slip under constant normal load, its backbone, Masing dissipation and
Iwan element (DESIGN.md section 4; seed ``generalized_cattaneo_partial_slip``, Ciavarella 1998).

Notation (per unit length along the contact line; ``x`` along the surface): initial gap
``h(x)`` (:mod:`~frictionjoint.contact.profiles`), rigid tilt ``theta`` (the gap is
``h(x) - theta x``), composite modulus ``1/E* = 2 (1 - nu^2)/E`` (one material, so Dundurs'
``beta = 0`` and the normal and tangential problems uncouple). Contact on ``[e - a, e + a]``.

Normal contact (bounded pressure at both ends; Hills, Nowell & Sackfield 1993, Mechanics of
Elastic Contacts; Barber 2018, Contact Mechanics; seed eqs. 27-30 with ``A = 2/E*`` and the
seed's ``h`` equal to minus ours). The integral equation
``(2/(pi E*)) PV int p(s)/(x - s) ds = h'(x) - theta`` is inverted, with ``tau = a cos(phi)``
and ``x = e + a t``, as

    p(x) = (E*/(2 pi)) sqrt(1 - t^2) int_0^pi [h'(e + a cos phi) - h'(x)]/(cos phi - t) dphi.

The divided difference is regular where ``h'`` is smooth. At a breakpoint ``x_k`` (``t_k``) a
step ``J H(x - x_k)`` and a ramp ``K (x - x_k)_+`` of ``h'`` are taken out and integrated in
closed form, ``(E*/(2 pi)) [J L + K (sqrt(a^2 - (x - e)^2) arccos(t_k) + (x - x_k) L)]`` with
``L = ln[(1 - t t_k + sqrt((1 - t^2)(1 - t_k^2)))/|t - t_k|]``. Consistency and load:

    int_0^pi h'(e + a cos phi) dphi = pi theta,     P = (E*/2) a int_0^pi h'(e + a cos phi) cos phi dphi.

Either ``theta`` is given (default 0) and these fix ``a`` and ``e``; or the load acts along the
line ``x = x_L`` (zero moment about it) and ``theta`` is eliminated, the moment condition being
``P (e - x_L) + (E* a^2/4) int_0^pi h'(e + a cos phi) cos(2 phi) dphi = 0``. The integrals use
Gauss-Legendre rules in ``phi`` split where ``e + a cos(phi)`` crosses a profile breakpoint.

Partial slip (Ciavarella 1998; Jaeger): under constant ``P`` and monotonic ``Q``,
``q(x) = f [p(x) - p*(x)]`` where ``p*`` is the pressure at ``P* = P - Q/f`` at the same tilt,
on the stick zone ``[d - c, d + c]``. The slip in the slip zones (seed eq. 21 integrated) is
``s(x) = f g*(x)``, with ``g*`` the gap of the reduced normal problem,
``g*'(x) = sgn(t) sqrt(t^2 - 1) (1/pi) int_0^pi [h'(d + c cos phi) - h'(x)]/(cos phi - t) dphi``,
``t = (x - d)/c``. The load increment of an incomplete contact is the flat-punch pressure on the
current contact, whose log potential is ``(2/(pi E*)) ln(2/c)`` per unit load; hence the
tangential compliance ``d delta/dQ = (2/(pi E*)) [ln(2 D/c(Q)) + 1/(2 (1 - nu))]`` for the
displacement between points at depth ``D`` below the contact in both bodies, the last term being
the depth term of Flamant's tangential line-load solution. Integrated by parts:

    delta(Q) = (2/(pi E*)) [Q (ln(2 D/a) + 1/(2 (1 - nu))) + f int_c^a (P*(s) - P*(c)) ds/s],
    W(Q*)    = 4 Q* delta(Q*) - 8 int_0^Q* delta = (8 f^2/(pi E*)) int_c*^a (P - P*(s)) (P*(s) - P* (c*)) ds/s

(Masing: the unloading branch is the loading curve scaled by 2; ``P*(s)`` is the reduced load
whose stick half-width is ``s``). ``W`` does not depend on ``D``: the depth only adds a term
linear in ``Q``. For the Hertz cylinder ``W = (2 f^2 P^2/(pi E*)) [2u - u^2 + 2 (1 - u) ln(1 - u)]``,
``u = Q*/(f P)``.
"""
from __future__ import annotations

import functools
import math

import numpy as np
import scipy.optimize
from scipy.optimize import elementwise

from ..elements.iwan import Iwan, check_n_sliders
from ..elements.masing import ContinuousIwan, odd_backbone
from ..errors import (ConvergenceError, ParameterError, check_nonnegative, check_poisson_ratio, check_positive,
                      check_real)
from .profiles import Profile

__all__ = ["HalfPlaneContact"]

_N_GRADED = 16  # Gauss-Legendre nodes per interval of the geometric meshes in the stick half-width
_N_SAMPLES = 401  # points at which the solution is checked (convexity, h >= 0, p >= 0) and p is maximised


@functools.lru_cache(maxsize=None)
def _gauss_legendre(n: int):
    """Gauss-Legendre nodes on [0, 1] and weights (sum 1)."""
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def _geometric_mesh(lo: float, hi: float, singular) -> np.ndarray:
    """Edges of a mesh of ``[lo, hi]`` graded geometrically (ratio 2) towards each point of
    ``singular`` (inside or below the interval): every cell is no longer than its distance to them."""
    length = hi - lo
    edges = [lo, hi]
    steps = length * 2.0 ** -np.arange(0, 54)
    for s in singular:
        for pt in (s + steps, s - steps):
            edges.extend(pt[(pt > lo) & (pt < hi)])
    edges = np.unique(edges)
    return edges[np.concatenate([[True], np.diff(edges) > 1e-15 * max(abs(hi), length)])]


def _mesh_rule(edges: np.ndarray):
    """Gauss-Legendre nodes and weights on every cell of ``edges``."""
    x, w = _gauss_legendre(_N_GRADED)
    width = np.diff(edges)[:, None]
    return (edges[:-1, None] + width * x).ravel(), (width * w).ravel()


def _positive_int(name, value, minimum):
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise ParameterError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


class HalfPlaneContact:
    """Plane contact of a general profile, Cattaneo partial slip and its Iwan element.

    Both bodies are half-planes of one material in plane strain. Forces are resultants over
    ``length`` along the contact line (with the default ``length = 1`` m they are per unit
    length, N/m); tractions are in Pa.

    Parameters
    ----------
    profile : Profile or callable
        Initial gap ``h(x)`` [m] (a :class:`~frictionjoint.contact.profiles.Profile`; a plain
        callable ``h`` is wrapped as ``Profile(h)``, its slope then found by finite differences).
    normal_load : float
        Normal force P [N] over ``length``, > 0 (constant).
    friction_coefficient : float
        f [-], > 0.
    youngs_modulus : float
        E [Pa] of both bodies, > 0.
    poisson_ratio : float
        nu [-] of both bodies, in (-1, 0.5).
    reference_depth : float
        Depth D [m] of the points of both bodies between which the tangential displacement is
        measured, > ``contact_half_width``. In 2D the absolute displacement is logarithmically
        undefined; the contact tractions are replaced by their resultant for the displacement at
        depth (error O((a/D)^2)). Only the part of the displacement linear in Q depends on D:
        the dissipation does not.
    length : float, optional
        Length [m] of the contact line, > 0 (default 1 m).
    tilt : float, optional
        Rigid rotation theta [rad] of the profile (gap ``h(x) - theta x``), held during the
        tangential loading. Default 0 unless ``load_line`` is given.
    load_line : float, optional
        Abscissa x_L [m] of the line of action of the normal load: the tilt is then found from
        zero moment about it. Give ``tilt`` or ``load_line``, not both.
    n_nodes : int, optional
        Gauss-Legendre nodes per smooth piece of the angular quadratures, >= 8 (default 64).

    Attributes
    ----------
    contact_half_width : float
        a [m].
    contact_offset : float
        Centre e [m] of the contact.
    tilt : float
        theta [rad] (given, or solved from ``load_line``).
    effective_modulus : float
        E* = E/(2 (1 - nu^2)) [Pa].
    peak_pressure : float
        Maximum contact pressure [Pa] (``inf`` at a corner of the profile such as a wedge apex).
    slip_force : float
        f P [N].
    tangential_stiffness : float
        Initial tangential stiffness [N/m] for the reference depth.
    slip_displacement : float
        Tangential displacement [m] at gross slip, ``Q = f P``.
    """

    def __init__(self, profile, normal_load: float, friction_coefficient: float, youngs_modulus: float,
                 poisson_ratio: float, reference_depth: float, *, length: float = 1.0,
                 tilt: float | None = None, load_line: float | None = None, n_nodes: int = 64):
        if isinstance(profile, Profile):
            self.profile = profile
        elif callable(profile):
            self.profile = Profile(profile)
        else:
            raise ParameterError(f"profile must be a Profile or a callable h(x) [m], got {profile!r}")
        self.normal_load = check_positive("normal_load", normal_load)
        self.friction_coefficient = check_positive("friction_coefficient", friction_coefficient)
        self.youngs_modulus = check_positive("youngs_modulus", youngs_modulus)
        nu = check_poisson_ratio("poisson_ratio", poisson_ratio)
        self.poisson_ratio = nu
        self.reference_depth = check_positive("reference_depth", reference_depth)
        self.length = check_positive("length", length)
        if tilt is not None and load_line is not None:
            raise ParameterError("give tilt (fixed rotation) or load_line (zero moment about it), not both")
        self.tilt = 0.0 if tilt is None else check_real("tilt", tilt)
        self.load_line = None if load_line is None else check_real("load_line", load_line)
        self.n_nodes = _positive_int("n_nodes", n_nodes, 8)
        self.effective_modulus = self.youngs_modulus / (2.0 * (1.0 - nu * nu))
        self._breaks = np.array(self.profile.breakpoints, dtype=float)
        self._load = self.normal_load / self.length  # per unit length [N/m]
        # symmetric profile with no tilt: contact and stick zone centred on x = 0
        self._centred = self.profile.symmetric and (
            (self.load_line is None and self.tilt == 0.0) or self.load_line == 0.0)
        self._solve_normal()
        a = self.contact_half_width
        if not self.reference_depth > a:
            raise ParameterError(f"reference_depth must be > the contact half-width a = {a:g} m "
                                 f"(allowed range (a, inf)), got {reference_depth!r}")
        slope_scale = float(np.max(np.abs(self._slope(self.contact_offset + a * np.linspace(-1, 1, 9), a))))
        eps = np.finfo(float).eps
        # root tolerances: stick half-width c (reduced load) and centre d (consistency, noisy near 0)
        self._tol_c = {"xatol": 1e-15 * a, "xrtol": 4.0 * eps, "fatol": 1e-15 * self._load}
        self._tol_d = {"xatol": 1e-13 * a, "xrtol": 4.0 * eps, "fatol": 1e-14 * slope_scale}
        self._jumps, self._kinks = self._slope_jumps()
        self._check_solution()
        self._c_min = self._smallest_stick_half_width()
        self._state = functools.lru_cache(maxsize=1024)(self._state_uncached)
        self._depth_term = math.log(2.0 * self.reference_depth / a) + 0.5 / (1.0 - nu)
        self._flex = 2.0 / (math.pi * self.effective_modulus)  # (2/(pi E*)) [1/Pa]
        self.slip_force = self.friction_coefficient * self.normal_load
        self.tangential_stiffness = self.length / (self._flex * self._depth_term)
        self.slip_displacement = self._delta(self._load * self.friction_coefficient)
        self.peak_pressure = self._peak_pressure()

    # ------------------------------------------------------------ quadrature kernels
    def _phi_rule(self, half, centre):
        """Gauss-Legendre nodes ``phi`` and weights on [0, pi], split where
        ``centre + half cos(phi)`` crosses a breakpoint; shapes ``half.shape + (pieces, n)``."""
        half = np.asarray(half, dtype=float)[..., None]
        centre = np.asarray(centre, dtype=float)[..., None]
        shape = np.broadcast_shapes(half.shape, centre.shape)[:-1]
        ends = [np.zeros(shape + (1,)), np.full(shape + (1,), math.pi)]
        if self._breaks.size:
            ratio = (self._breaks - centre) / np.where(half > 0.0, half, 1.0)  # half = 0: any cut
            cuts = np.arccos(np.clip(ratio, -1.0, 1.0))[..., ::-1]
            ends.insert(1, cuts)
        bounds = np.concatenate(ends, axis=-1)
        x, w = _gauss_legendre(self.n_nodes)
        width = np.diff(bounds, axis=-1)[..., None]
        return bounds[..., :-1, None] + width * x, width * w

    def _slope(self, x, scale):
        return self.profile.slope(x, scale)

    def _angular(self, half, centre, kernels):
        """``int_0^pi h'(centre + half cos phi) k(phi) dphi`` for each kernel k (arrays)."""
        half = np.asarray(half, dtype=float)
        centre = np.asarray(centre, dtype=float)
        phi, w = self._phi_rule(half, centre)
        h1 = self._slope(centre[..., None, None] + half[..., None, None] * np.cos(phi), half[..., None, None])
        return [np.sum(w * h1 * k(phi), axis=(-2, -1)) for k in kernels]

    def _consistency(self, half, centre):
        """``int_0^pi h' dphi - pi theta`` (zero for a pressure bounded at both ends)."""
        (g,) = self._angular(half, centre, [np.ones_like])
        return g - math.pi * self.tilt

    def _load_of(self, half, centre):
        """Normal load per unit length [N/m] carried on ``[centre - half, centre + half]``."""
        (g,) = self._angular(half, centre, [np.cos])
        return 0.5 * self.effective_modulus * np.asarray(half) * g

    # ------------------------------------------------------------ normal contact
    @staticmethod
    def _bracket(fun, x0, step, multiplicative, message):
        """``(lo, hi)`` around the root of the increasing scalar ``fun``, expanding from ``x0``."""
        f0 = fun(x0)
        if f0 == 0.0:
            return x0, x0
        sign = 1.0 if f0 < 0 else -1.0
        prev = x0
        for k in range(1, 120):
            x = x0 * 2.0 ** (sign * k) if multiplicative else x0 + sign * step * 2.0 ** (k - 1)
            fx = fun(x)
            if fx == 0.0 or (fx > 0) == (sign > 0):
                return (prev, x) if sign > 0 else (x, prev)
            prev = x
        raise ParameterError(message)

    def _root(self, fun, x0, step, multiplicative, message):
        lo, hi = self._bracket(fun, x0, step, multiplicative, message)
        if lo == hi:
            return lo
        return scipy.optimize.brentq(fun, lo, hi, xtol=1e-300, rtol=4 * np.finfo(float).eps, maxiter=400)

    def _solve_normal(self):
        p = self._load
        e_star = self.effective_modulus
        last = {"e": 0.0 if self.load_line is None else self.load_line}

        def centre(a):
            if self._centred:
                return 0.0
            if self.load_line is None:
                def fun(e):
                    return float(self._consistency(a, e))
                msg = (f"profile: no contact centre satisfies the consistency condition "
                       f"int h'(e + a cos phi) dphi = pi tilt at half-width a = {a:g} m "
                       f"(the profile needs a minimum, and |tilt| below its slopes)")
            else:
                def fun(e):
                    (g,) = self._angular(a, e, [lambda f: np.cos(2.0 * f)])
                    return p * (e - self.load_line) + 0.25 * e_star * a * a * float(g)
                msg = (f"profile: no contact centre gives zero moment about load_line at half-width "
                       f"a = {a:g} m (the profile must be convex)")
            e = self._root(fun, last["e"], a, False, msg)
            last["e"] = e
            return e

        def excess(a):
            return float(self._load_of(a, centre(a))) - p

        guess = self.profile._half_width_guess(p, e_star) or 1e-3
        msg = ("profile: no contact half-width carries the normal load (the profile must be convex with "
               "a minimum; a flat punch with sharp edges has no incomplete contact)")
        a = self._root(excess, guess, 0.0, True, msg)
        if not (math.isfinite(a) and a > 0.0):
            raise ParameterError(msg)
        self.contact_half_width = a
        self.contact_offset = centre(a)
        if self.load_line is not None:
            self.tilt = float(self._angular(a, self.contact_offset, [np.ones_like])[0]) / math.pi

    def _slope_jumps(self):
        """Jumps of ``h'`` [-] and of ``h''`` [1/m] at the breakpoints: one-sided limits by cubic
        extrapolation from 4 points on each side (step 1e-3 a); zero below 1e-9 of the scale."""
        if not self._breaks.size:
            return self._breaks, self._breaks
        a = self.contact_half_width
        eta = 1e-3 * a
        m = np.arange(1.0, 5.0)[:, None]
        right = self._slope(self._breaks + m * eta, a)
        left = self._slope(self._breaks - m * eta, a)
        value = np.array([4.0, -6.0, 4.0, -1.0])  # cubic through m = 1..4, at m = 0
        deriv = np.array([-13.0 / 3.0, 9.5, -7.0, 11.0 / 6.0])
        jump = value @ (right - left)
        kink = deriv @ (right + left) / eta  # h''(x+) - h''(x-)
        scale = np.max(np.abs(self._slope(self.contact_offset + a * np.linspace(-1, 1, 9), a)))
        return (np.where(np.abs(jump) > 1e-9 * scale, jump, 0.0),
                np.where(np.abs(kink) > 1e-9 * scale / a, kink, 0.0))

    def _samples(self):
        a, e = self.contact_half_width, self.contact_offset
        x = e + a * np.cos(np.linspace(math.pi, 0.0, _N_SAMPLES))
        inside = self._breaks[np.abs(self._breaks - e) < a]
        return np.sort(np.concatenate([x, inside]))

    def _check_solution(self):
        """The profile must give one contact interval: h >= 0, h' non-decreasing, p >= 0."""
        x = self._samples()
        a = self.contact_half_width
        h = self.profile.gap(x)
        if np.any(h < -1e-9 * np.max(np.abs(h))):
            i = int(np.argmin(h))
            raise ParameterError(f"profile: h must be >= 0 (the initial gap), got h({x[i]:g}) = {h[i]:g} m")
        h1 = self._slope(x, a)
        drop = np.diff(h1)
        if np.any(drop < -1e-9 * (np.ptp(h1) + 1e-300)):
            i = int(np.argmin(drop))
            raise ParameterError(f"profile: h must be convex (h' non-decreasing) over the contact, got "
                                 f"h'({x[i]:g}) = {h1[i]:g} > h'({x[i + 1]:g}) = {h1[i + 1]:g}")
        p = self._pressure(x[1:-1], a, self.contact_offset)
        if np.any(p < -1e-9 * np.max(p)):
            raise ParameterError("profile: the contact pressure is negative somewhere (not a single "
                                 "incomplete contact)")

    def _pressure(self, x, half, centre):
        """Pressure [Pa] of the normal problem on ``[centre - half, centre + half]`` at the same tilt."""
        x = np.asarray(x, dtype=float)
        t = (x - centre) / half
        inside = np.abs(t) < 1.0
        out = np.zeros_like(t)
        if not np.any(inside):
            return out
        xi, ti = x[inside], t[inside]
        phi, w = self._phi_rule(half, centre)
        tau = centre + half * np.cos(phi)

        def continuous(y):  # h' without its jumps and kinks at the breakpoints
            s = self._slope(y, half)
            for xk, jk, kk in zip(self._breaks, self._jumps, self._kinks):
                if jk:
                    s = s - jk * np.where(y > xk, 1.0, np.where(y == xk, 0.5, 0.0))
                if kk:
                    s = s - kk * np.maximum(y - xk, 0.0)
            return s

        num = continuous(tau)[None] - continuous(xi)[:, None, None]
        den = np.cos(phi)[None] - ti[:, None, None]
        small = np.abs(den) < 1e-6
        if np.any(small):  # node at the evaluation point: the divided difference is h'' there
            eta = 1e-3 * half
            mid = (0.5 * (tau[None] + xi[:, None, None]))[small]
            num = np.where(small, 0.0, num)
            den = np.where(small, 1.0, den)
            num[small] = (continuous(mid + eta) - continuous(mid - eta)) / (2.0 * eta) * half
        dd = np.sum(w[None] * num / den, axis=(-2, -1)) / math.pi
        beta = np.arccos(ti)  # t = cos(beta)
        p = 0.5 * self.effective_modulus * np.sqrt(1.0 - ti * ti) * dd
        for xk, jk, kk in zip(self._breaks, self._jumps, self._kinks):
            if jk or kk:  # closed forms for a step J H(x - xk) and a ramp K (x - xk)_+ in h'
                tk = min(max((xk - centre) / half, -1.0), 1.0)
                pk = math.acos(tk)
                with np.errstate(divide="ignore", invalid="ignore"):
                    # ln|sin((pk + beta)/2)/sin((pk - beta)/2)|, written without cancellation at x -> xk
                    log = (np.log(1.0 - ti * tk + np.sqrt((1.0 - ti * ti) * (1.0 - tk * tk)))
                           - np.log(np.abs(xi - xk) / half))
                    if jk:
                        p = p + self.effective_modulus * jk / (2.0 * math.pi) * log
                    if kk:
                        ramp = half * np.sin(beta) * pk + np.where(xi == xk, 0.0, (xi - xk) * log)
                        p = p + self.effective_modulus * kk / (2.0 * math.pi) * ramp
        out[inside] = p
        return out

    def _peak_pressure(self):
        a, e = self.contact_half_width, self.contact_offset
        if np.any((np.abs(self._breaks - e) < a) & (self._jumps > 0)):
            return math.inf
        x = self._samples()
        p = self._pressure(x, a, e)
        i = int(np.argmax(p))
        lo, hi = x[max(i - 1, 0)], x[min(i + 1, x.size - 1)]
        res = scipy.optimize.minimize_scalar(lambda y: -float(self._pressure(np.array([y]), a, e)[0]),
                                             bounds=(lo, hi), method="bounded",
                                             options={"xatol": 1e-12 * a})
        return max(float(p[i]), -float(res.fun))

    def pressure(self, x):
        """Contact pressure p(x) [Pa] at ``x`` [m] (0 outside the contact).

        Parameters
        ----------
        x : float or array_like
            Abscissae [m].

        Returns
        -------
        float or ndarray
            Pressure [Pa], shape of ``x``.
        """
        x = np.asarray(x, dtype=float)
        out = self._pressure(x.ravel(), self.contact_half_width, self.contact_offset).reshape(x.shape)
        return float(out) if out.ndim == 0 else out

    # ------------------------------------------------------------ reduced problem (stick zone)
    def _stick_centre(self, half):
        """Centre d of the stick zone of half-width ``half`` (array): consistency at the same tilt."""
        half = np.asarray(half, dtype=float)
        e = self.contact_offset
        if self._centred:
            return np.full_like(half, e)
        room = np.maximum(self.contact_half_width - half, 0.0)
        lo, hi = e - room, e + room
        g_lo, g_hi = self._consistency(half, lo), self._consistency(half, hi)
        out = np.where(g_lo >= 0.0, lo, np.where(g_hi <= 0.0, hi, np.nan))
        todo = np.isnan(out)
        if np.any(todo):
            with np.errstate(invalid="ignore"):
                res = elementwise.find_root(lambda d, c: self._consistency(c, d), (lo[todo], hi[todo]),
                                            args=(half[todo],), tolerances=self._tol_d)
            out[todo] = res.x
        return out

    def _reduced_load(self, half):
        """Normal load per unit length [N/m] of the reduced problem whose contact half-width is ``half``."""
        half = np.asarray(half, dtype=float)
        return self._load_of(half, self._stick_centre(half))

    def _smallest_stick_half_width(self):
        """Largest c with zero reduced load (b for a rounded flat punch, 0 for a smooth profile)."""
        a, p = self.contact_half_width, self._load
        lo, hi = 0.0, a
        while hi - lo > 1e-15 * a:  # multisection: 32 points per pass
            c = np.linspace(lo, hi, 34)[1:-1]
            loaded = self._reduced_load(c) > 1e-14 * p * (c / a) ** 2
            k = int(np.argmax(loaded)) if np.any(loaded) else c.size
            lo, hi = (c[k - 1] if k > 0 else lo), (c[k] if k < c.size else hi)
        return lo

    def _stick_half_width(self, target):
        """Stick half-width c (array) at reduced loads ``target`` [N/m] (array, 0 <= target <= P)."""
        target = np.asarray(target, dtype=float)
        a, lo = self.contact_half_width, self._c_min
        out = np.where(target >= self._load, a, np.where(target <= 0.0, lo, np.nan))
        todo = np.isnan(out)
        if np.any(todo):
            with np.errstate(invalid="ignore"):
                res = elementwise.find_root(lambda c, t: self._reduced_load(c) - t,
                                            (np.full(int(todo.sum()), lo), np.full(int(todo.sum()), a)),
                                            args=(target[todo],), tolerances=self._tol_c)
            if not np.all(res.success):
                raise ConvergenceError("stick-zone half-width: root finding failed")
            out[todo] = res.x
        return out

    def _singular(self):
        """Stick half-widths where the reduced load is not smooth (its first zero, 0, breakpoints)."""
        return {0.0, self._c_min, *np.abs(self._breaks - self.contact_offset)}

    def _state_uncached(self, q):
        """(c, d, reduced load) at tangential force ``q`` [N/m] per unit length, 0 <= q <= f P."""
        target = self._load - q / self.friction_coefficient
        c = float(self._stick_half_width(np.array([target]))[0])
        return c, float(self._stick_centre(np.array([c]))[0]), target

    def _delta(self, q):
        """Tangential displacement [m] at tangential force ``q`` [N/m] per unit length."""
        c, _, target = self._state(float(q))
        a = self.contact_half_width
        nonlinear = 0.0
        if c < a:
            s, w = _mesh_rule(_geometric_mesh(c, a, self._singular()))
            nonlinear = float(np.sum(w * (self._reduced_load(s) - target) / s))
        return self._flex * (q * self._depth_term + self.friction_coefficient * nonlinear)

    def _compliance(self, q):
        """``d delta/dQ`` [m/(N/m)] per unit length at tangential force ``q`` [N/m]."""
        c = self._state(float(q))[0]
        if c <= 0.0:
            return math.inf
        return self._flex * (math.log(2.0 * self.reference_depth / c) + 0.5 / (1.0 - self.poisson_ratio))

    def _dissipation(self, q):
        """Energy per cycle [J/m] per unit length for amplitude ``q`` [N/m]."""
        c, _, target = self._state(float(q))
        a = self.contact_half_width
        if c >= a:
            return 0.0
        s, w = _mesh_rule(_geometric_mesh(c, a, self._singular()))
        ps = self._reduced_load(s)
        f = self.friction_coefficient
        return 4.0 * self._flex * f * f * float(np.sum(w * (self._load - ps) * (ps - target) / s))

    # ------------------------------------------------------------ public tangential interface
    def _check_force(self, name, q):
        q = check_nonnegative(name, q)
        if q > self.slip_force:
            raise ParameterError(f"{name} must be in [0, f P] = [0, {self.slip_force:g}] N, got {q!r}")
        return q

    def stick_zone(self, tangential_force: float):
        """Stick zone at tangential force Q (monotonic loading from 0 at constant P).

        Parameters
        ----------
        tangential_force : float
            Q [N], in [0, f P].

        Returns
        -------
        (float, float)
            Half-width c [m] and centre d [m] of the stick zone.
        """
        q = self._check_force("tangential_force", tangential_force)
        c, d, _ = self._state(q / self.length)
        return c, d

    def shear_traction(self, x, tangential_force: float):
        """Shear traction q(x) = f [p(x) - p*(x)] [Pa] at tangential force Q (Ciavarella-Jaeger).

        Parameters
        ----------
        x : float or array_like
            Abscissae [m].
        tangential_force : float
            Q [N], in [0, f P].

        Returns
        -------
        float or ndarray
            Shear traction [Pa], shape of ``x``; it integrates to Q / length.
        """
        q = self._check_force("tangential_force", tangential_force)
        c, d, _ = self._state(q / self.length)
        x = np.asarray(x, dtype=float)
        flat = x.ravel()
        out = self._pressure(flat, self.contact_half_width, self.contact_offset)
        if c > 0.0:
            out = out - self._pressure(flat, c, d)
        out = (self.friction_coefficient * out).reshape(x.shape)
        return float(out) if out.ndim == 0 else out

    def local_slip(self, x, tangential_force: float):
        """Relative slip s(x) [m] of the surfaces in the contact after monotonic loading to Q.

        ``s = f g*(x)`` with ``g*`` the gap of the normal problem at ``P* = P - Q/f`` and the
        same tilt (seed eq. 21 integrated from the stick-zone edge); 0 in the stick zone.

        Parameters
        ----------
        x : float or array_like
            Abscissae [m] in the contact ``[e - a, e + a]``.
        tangential_force : float
            Q [N], in [0, f P].

        Returns
        -------
        float or ndarray
            Slip [m] in the direction of Q, shape of ``x``.
        """
        q = self._check_force("tangential_force", tangential_force)
        c, d, _ = self._state(q / self.length)
        x = np.asarray(x, dtype=float)
        a, e = self.contact_half_width, self.contact_offset
        if np.any(np.abs(x - e) > a * (1.0 + 1e-14)):
            raise ParameterError(f"x must lie in the contact [{e - a:g}, {e + a:g}] m")
        flat = x.ravel()
        out = np.zeros_like(flat)
        for i, xi in enumerate(flat):
            t = (xi - d) / c if c > 0.0 else math.copysign(math.inf, xi - d)
            if abs(t) > 1.0:
                out[i] = self.friction_coefficient * self._reduced_gap(xi, c, d)
        out = out.reshape(x.shape)
        return float(out) if out.ndim == 0 else out

    def _reduced_gap(self, x, c, d):
        """Gap [m] at ``x`` outside the contact ``[d - c, d + c]`` of the reduced normal problem."""
        side = 1.0 if x > d else -1.0
        edge = d + side * c
        if c <= 0.0:  # no stick zone (gross slip): the gap is the profile's rise from its first contact
            return float(self.profile.gap(np.array([x]))[0] - self.profile.gap(np.array([edge]))[0]
                         - self.tilt * (x - edge))
        top = math.acosh(abs(x - d) / c)
        inner = [math.acosh(abs(b - d) / c) for b in self._breaks if 0.0 < side * (b - edge) < side * (x - edge)]
        s, wts = _mesh_rule(np.unique([0.0, top, *inner]))
        t = side * np.cosh(s)
        phi, w = self._phi_rule(c, d)
        tau = d + c * np.cos(phi)
        y = d + c * t
        num = self._slope(tau, c)[None] - self._slope(y, c)[:, None, None]
        dd = np.sum(w[None] * num / (np.cos(phi)[None] - t[:, None, None]), axis=(-2, -1)) / math.pi
        return c * float(np.sum(wts * np.sinh(s) ** 2 * dd))

    def displacement(self, tangential_force: float) -> float:
        """Tangential displacement [m] on monotonic loading to Q, between points at the reference depth.

        Parameters
        ----------
        tangential_force : float
            Q [N], in [0, f P].
        """
        q = self._check_force("tangential_force", tangential_force)
        return self._delta(q / self.length)

    def _force(self, u: float) -> float:
        """Tangential force per unit length [N/m] at displacement ``0 <= u <= slip_displacement``:
        safeguarded Newton on ``delta(q) = u`` (delta is convex, so q = K u starts from above)."""
        fp = self._load * self.friction_coefficient
        if u >= self.slip_displacement:
            return fp
        lo, hi = 0.0, fp
        q = min(u * self.tangential_stiffness / self.length, fp)
        for _ in range(100):
            r = self._delta(q) - u
            if r > 0:
                hi = q
            else:
                lo = q
            step = r / self._compliance(q)
            q_new = q - step
            if not lo < q_new < hi:
                q_new = 0.5 * (lo + hi)
            if abs(q_new - q) <= 4e-16 * fp or hi - lo <= 4e-16 * fp:
                return q_new
            q = q_new
        raise ConvergenceError(f"backbone: no convergence at u = {u!r}")

    def backbone(self, u):
        """Tangential force [N] on monotonic loading to displacement ``u`` [m] (odd; f P beyond
        ``slip_displacement``).

        Parameters
        ----------
        u : float or array_like
            Displacement [m].

        Returns
        -------
        float or ndarray
            Force [N], shape of ``u``.
        """
        return odd_backbone(self._backbone_positive, u)

    def _backbone_positive(self, u):
        u = np.asarray(u, dtype=float)
        out = np.array([self._force(float(v)) for v in u.ravel()]).reshape(u.shape) * self.length
        return out

    def dissipation_per_cycle(self, force_amplitude: float) -> float:
        """Energy [J] dissipated per cycle of Q between ``±Q*`` at constant P (Masing).

        Parameters
        ----------
        force_amplitude : float
            Q* [N], in [0, f P].
        """
        q = self._check_force("force_amplitude", force_amplitude)
        return self.length * self._dissipation(q / self.length)

    def to_iwan(self, n_sliders: int | None = None, dof=None, direction=None):
        """The Iwan element with this contact's backbone.

        Parameters
        ----------
        n_sliders : int or None
            ``None``: the exact continuous element
            (:class:`~frictionjoint.elements.masing.ContinuousIwan`). An integer ``N >= 1``: a
            discrete :class:`~frictionjoint.elements.iwan.Iwan` whose sliders are the parts of the
            slider continuum slipping between ``Q = (j - 1) f P/N`` and ``j f P/N``, each carrying
            that part's exact stiffness and strength (stuck stiffness ``1/delta'(Q)``,
            strength ``Q - delta(Q)/delta'(Q)``); the total stiffness and slip force are exact, and
            the last slider also takes the stiffness still stuck at gross slip (a flat region
            slips as a whole).
        dof, direction :
            Attachment of the discrete element (see :class:`~frictionjoint.elements.iwan.Iwan`).
        """
        if n_sliders is None:
            def primitive(u):  # int_0^u F = F u/2 + W(F)/8 (Masing)
                force = min(float(self._backbone_positive(np.array(u))), self.slip_force)
                return 0.5 * force * u + self.dissipation_per_cycle(force) / 8.0

            return ContinuousIwan(self._backbone_positive, self.tangential_stiffness, self.slip_force,
                                  self.slip_displacement, inverse=self.displacement, primitive=primitive)
        n = check_n_sliders("n_sliders", n_sliders)  # before the slider table is built
        fp = self._load * self.friction_coefficient
        k_total = self.tangential_stiffness / self.length
        k_cum, f_cum = [0.0], [0.0]
        for j in range(1, n):
            q = j * fp / n
            comp = self._compliance(q)
            k_cum.append(k_total - 1.0 / comp)
            f_cum.append(q - self._delta(q) / comp)
        k_cum.append(k_total)
        f_cum.append(fp)
        table = [(self.length * dk, self.length * df) for dk, df in zip(np.diff(k_cum), np.diff(f_cum))]
        return Iwan(table, dof=dof, direction=direction)
