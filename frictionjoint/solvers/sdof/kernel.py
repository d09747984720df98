"""Closed-form exact marcher of the single-DOF Coulomb oscillator (pure-Python scalar kernel).

Model and notation
------------------
``m x'' + c x' + k x + T = P0 cos(w t)`` with rigid Coulomb friction ``|T| <= F`` (static limit
equal to the kinetic one). ``s`` is the slider status: ``+1``/``-1`` slipping with ``T = s F``,
``0`` stuck (``x`` constant, ``v = 0``, ``T = h = P0 cos(w t) - k x``, the holding force).
DESIGN.md section 2; Hong & Liu (2000) for the rules at ``v = 0``.

- **Slip pieces** are the linear closed form. Far from resonance
  (``|D| >= k/4``, ``D = k - m w^2 - i c w``): particular part ``A cos wt + B sin wt - sF/k``
  (``A + iB = P0/D``) plus the homogeneous part ``e^{-a tau} [x_h (S' + a S) + v_h S]`` with
  ``a = c/(2m)``, ``q = k/m - a^2`` and ``S = sin(sqrt(q) tau)/sqrt(q)``, ``tau`` or
  ``sinh(sqrt(-q) tau)/sqrt(-q)`` (under-, critically, over-damped; ``S'' = -q S`` in all
  three). The displacement is formed as ``x0 + (x_p(t) - x_p(t0)) + (x_h(tau) - x_h(0))``, each
  difference without cancellation (half-angle sines, ``expm1``, the two decaying modes when
  over-damped): far above resonance the offsets ``-sF/k`` are ``r^2`` times the motion and would
  round it away. Near resonance (``|D| < k/4``, then under-damped) the particular and homogeneous parts
  would both be ``~P0/|D|`` and cancel; there the piece is ``-sF/k`` + the free response to its
  initial state + the forced response from rest,
  ``Re[P0/m e^{i w t0} (E(l+) - E(l-))/(l+ - l-)]`` with the roots ``l+-`` of
  ``m l^2 + c l + k`` and the exact integrals ``E(l) = (e^{i w tau} - e^{l tau})/(i w - l) =
  tau e^{l tau} phi1((i w - l) tau)``, ``phi1(z) = (e^z - 1)/z`` evaluated without cancellation
  (as the general marcher's propagator does): accurate to a few ulp of the motion's scale at
  and near resonance, with the secular growth of exact undamped resonance as its continuous
  limit.
- **Event of a slip piece**: the first root of ``g(tau) = s v(tau)`` after the piece start. It is
  *certified*: from a point ``tau`` where ``g >= 0`` the march advances by a step over which a
  Taylor lower bound of ``g`` stays positive (``g + g' d - M2 d^2/2`` with ``M2 >= sup|g''|``, and
  when ``g' >= 0`` also ``d (g' + g'' d/2 - M3 d^2/6)`` with ``M3 >= sup|g'''|``, which starts
  a piece that begins at ``v = 0`` on the sign of its acceleration or jerk). The bounds are
  rigorous. Far from resonance, for the rest of the piece: the homogeneous energy
  ``(m v_h^2 + k x_h^2)/2`` never grows, so ``|x_h| <= D0``, ``|v_h| <= D1`` and
  ``|x_h^(n)| <= Dn = (c D(n-1) + k D(n-2))/m`` (over-damped also ``|a1| l1^n + |a2| l2^n``, the
  modes' decay rates and coefficients, whichever is smaller: ``(c/m)^n`` alone would cut a heavily
  damped piece into ``c/(m w)`` steps); the particular part gives ``w^n |A + iB|``.
  Near resonance (where ``|A + iB|`` is large or infinite), over the next radian of the fastest
  rate: ``E = (m v^2 + k (x + sF/k)^2)/2`` has ``dE/dt = v (P0 cos wt - c v)``, so ``sqrt(E)``
  grows at most like ``|P0| t/sqrt(2m)``, which bounds ``|x|``, ``|v|`` and, through the
  equation of motion, the higher derivatives. Near a simple root the safe steps converge
  quadratically from the left (a conservative Newton iteration), so the event is located to a
  few ulp of ``t`` without a separate polishing stage, and no root can be stepped over.
- **Stuck pieces**: ``|P0 cos(wt) - k x|`` reaches ``F`` where ``cos(wt + phi)`` crosses
  ``(k x +- F)/|P0|``: closed form by ``arccos``. An excursion over the limit smaller than the
  force tolerance (a graze) does not start a slip (the general marcher's stated rule; at
  ``F = |P0|`` it does start one there, see tests/stress/test_stress_sdof.py).
- **Rules at v = 0** (:meth:`SdofCoulomb.settle`) follow
  :meth:`frictionjoint.solvers.marcher.events.Marcher.settle` with the same tolerances: a slipping
  slider whose velocity would change sign sticks; a stuck slider whose holding force would exceed
  ``F`` slips in the direction of that force; at zero the first derivative decides, within its
  tolerance band the second. So a stop is a stick of finite duration, a normal stop (reversal)
  or an abnormal stop (slips on in the same direction), never a chatter of tiny steps: an
  abnormal stop whose slip reverses again within time rounding (decided inside the tolerance
  bands) is a stick.

- **Scales far apart.** Where the forcing period is far beyond the natural one, the exact motion
  sticks and slips about once per natural period (every break-away from a stick starts a free
  oscillation of amplitude ``|v_qs|/wn`` that friction does not end), ``omega_n/omega`` events a
  period. Where :meth:`SdofCoulomb.quasi_static_bound` (about ``(w/wn) |P0|/k``) is at most
  :data:`QUASI_STATIC_TOL` of the slip amplitude ``(|P0| - F)/k`` (of ``|P0|/k`` if ``F >= |P0|``:
  the slips are then a shakedown to a rest position), the kernel is *quasi-static*: a
  slip that starts from a stick (on the curve ``x_qs = (P0 cos wt - sF)/k``, within the bound)
  follows ``x_qs`` to the force's extremum, where it sticks; the particular part is then ``x_qs``
  itself, so :meth:`evaluate` and the Fourier integrals of the pieces are those of ``x_qs``.
  Between that regime and an affordable march (``omega/omega_n`` about 1e-9 .. 1e-5, undamped), a
  march is refused with :class:`EventBudgetError` once it has taken ``_PIECES_PER_PERIOD`` pieces per
  period: bounded time and a message that says why, never hours. Where that count is foreseen
  (:meth:`SdofCoulomb._chatter_rate`: undamped, a break-away every period) the march is refused
  before it starts, and a slip piece that outlasts its safe steps is the same refusal.

Everything in the inner loop is ``math`` on floats: no arrays, no per-event set-up. For the
n-DOF systems (Jenkins elements, several sliders) use :class:`~frictionjoint.solvers.marcher.events.Marcher`.
"""
from __future__ import annotations

import math
from typing import Callable, NamedTuple, Optional

from ...errors import ConvergenceError, ParameterError, check_nonnegative, check_positive, check_real

__all__ = ["SdofCoulomb", "event_kind", "SdofResult", "EVENT_KINDS", "EventBudgetError", "QUASI_STATIC_TOL"]

#: Kinds of events counted by :meth:`SdofCoulomb.march` (as in :class:`~.events.EventLog`).
EVENT_KINDS = ("stick", "slip", "normal stop", "abnormal stop")
_EPS = 2.220446049250313e-16
_TWO_PI = 2.0 * math.pi
#: Safe steps allowed in one piece before giving up (a simple root needs a handful).
_MAX_STEPS = 20_000
#: Near-resonance form of the slip pieces where |k - m w^2 - i c w| < _NEAR k.
_NEAR = 0.25
#: The quasi-static regime: where :meth:`SdofCoulomb.quasi_static_bound` is at most this fraction of
#: the quasi-static slip amplitude ``(|P0| - F)/k``, a slip that starts from a stick follows ``x_qs``.
QUASI_STATIC_TOL = 1e-9
#: the largest stiffness, mass * omega**2 and damping * omega [N/m] and natural frequency
#: sqrt(stiffness / mass) [rad/s] the kernel takes: its closed form squares them (|D|^2 with
#: D = k - m w^2 - i c w, (0.25 k)^2), which overflows beyond ~5e154 (stiffness 1e308 was an
#: OverflowError naming nothing, mass 1e-320 an infinite natural frequency that refused every
#: step); 1e150 is far beyond any physical joint, and the answers hold there (k x at 1e150 is the
#: hand-computed cos(w t) + 0.5, clamped at -F)
MAX_SCALE = 1e150


def _check_scales(m: float, k: float, c: float, w: float) -> None:
    """A :class:`ParameterError` naming the parameter whose scale is beyond :data:`MAX_SCALE`."""
    top = MAX_SCALE
    if k > top:
        raise ParameterError(f"stiffness must be in (0, {top:.0e}] N/m (the closed form squares it), got {k!r}")
    if k / m > top * top:
        raise ParameterError(f"mass must be >= stiffness / {top * top:.0e} = {k / (top * top):.3g} kg (a natural "
                             f"frequency sqrt(stiffness/mass) <= {top:.0e} rad/s), got {m!r}")
    for name, value in (("mass * omega**2", m * w * w), ("damping * omega", c * w)):
        if value > top:
            raise ParameterError(f"{name} must be <= {top:.0e} N/m (the closed form squares it), got {value:.3g} "
                                 f"(mass = {m!r}, omega = {w!r}, damping = {c!r})")
#: Pieces a march may take per excitation period it spans (plus two periods' worth): the exact
#: motion of a forcing period far beyond the natural one sticks and slips about once per natural
#: period (Coulomb friction restarts the free oscillation at every break-away), so its event count
#: grows with omega_n/omega; beyond this a march is refused (:class:`EventBudgetError`) instead of
#: running for hours (a one-period march exhausts it in 3 to 10 s). 1e4 events per period
#: (omega/omega_n = 1e-4, undamped) take about 0.6 s.
_PIECES_PER_PERIOD = 12_000


class EventBudgetError(ConvergenceError):
    """A march would take more pieces than :data:`_PIECES_PER_PERIOD` per excitation period."""


def _matmul(a, b):
    """2x2 matrix product on nested tuples."""
    return ((a[0][0] * b[0][0] + a[0][1] * b[1][0], a[0][0] * b[0][1] + a[0][1] * b[1][1]),
            (a[1][0] * b[0][0] + a[1][1] * b[1][0], a[1][0] * b[0][1] + a[1][1] * b[1][1]))


def _phi1(z: complex) -> complex:
    """``(e^z - 1)/z`` for a complex ``z`` (1 at 0), accurate to a few ulp near 0: ``e^z - 1``
    from ``expm1`` and half-angle sines, without cancellation."""
    if z == 0:
        return 1.0
    x, y = z.real, z.imag
    em = math.expm1(x)
    sh, ch = math.sin(0.5 * y), math.cos(0.5 * y)
    s2 = 2.0 * sh * sh
    return complex(em * (1.0 - s2) - s2, (1.0 + em) * 2.0 * sh * ch) / z


def event_kind(before: int, after: int) -> str:
    """Kind of the event (:data:`EVENT_KINDS`) between a piece of status ``before`` and the next of
    status ``after`` (the same status: an abnormal stop)."""
    if before == 0:
        return "slip"
    return "stick" if after == 0 else "normal stop" if after == -before else "abnormal stop"


def _start_status(v: float, status: Optional[int]):
    """``(s, settle_first)``: the status a march starts with from velocity ``v`` and the ``status``
    argument of :meth:`SdofCoulomb.march` (validated), and whether the rules at ``v = 0`` must
    settle it first (``status`` None and ``v = 0``)."""
    if status is None:
        return ((1 if v > 0 else -1) if v != 0.0 else 0), v == 0.0
    if status not in (-1, 0, 1) or isinstance(status, bool):
        raise ParameterError(f"status must be None, -1, 0 or 1, got {status!r}")
    s = int(status)
    if (s == 0 and v != 0.0) or s * v < 0:
        raise ParameterError(f"v0 = {v!r} is inconsistent with status = {s!r} "
                             "(stuck needs v0 = 0; slipping needs v0 of its sign or 0)")
    return s, False


class SdofResult(NamedTuple):
    """State at the end of :meth:`SdofCoulomb.march`.

    Attributes
    ----------
    t : float
        Time [s].
    x, v : float
        Displacement [m] and velocity [m/s].
    status : int
        ``0`` stuck, ``+1``/``-1`` slipping in the positive/negative direction (for
        ``slip_force = 0``: the sign of ``v``). Pass it back as ``status`` to continue exactly.
    n_events : int
        Number of events on the way (stick, slip, normal and abnormal stops).
    events : dict
        Count per kind, keys :data:`EVENT_KINDS`.
    v_scale : float
        The march's velocity scale at the end (its event tolerances): pass it back as
        ``v_scale`` to continue exactly as an unbroken march.
    """

    t: float
    x: float
    v: float
    status: int
    n_events: int
    events: dict
    v_scale: float = 0.0


class SdofCoulomb:
    """Exact stick/slip dynamics of ``m x'' + c x' + k x + T = P0 cos(w t)``, ``|T| <= F``.

    A dedicated closed-form kernel for the single-DOF Coulomb oscillator: the same motion and the
    same events as :class:`frictionjoint.solvers.marcher.events.Marcher` on
    :class:`frictionjoint.CoulombOscillator`, some 20-40 times faster (pure-Python scalar maths;
    see the module docstring for the method).

    Parameters
    ----------
    mass : float
        ``m`` [kg], in ``(0, inf)``.
    stiffness : float
        ``k`` [N/m], in ``(0, inf)``.
    slip_force : float
        Coulomb slip force ``F`` [N], in ``[0, inf)`` (0: linear, no events).
    force_amplitude : float
        ``P0`` [N], real.
    omega : float
        Excitation angular frequency ``w`` [rad/s], in ``(0, inf)``.
    damping : float, optional
        Viscous damping ``c`` [N s/m], in ``[0, inf)`` (default 0).

    Notes
    -----
    Near resonance (``|k - m w^2 - i c w| < k/4``) the slip pieces use the resonance-stable
    phi1 form of the forced response (module docstring): exact undamped resonance needs no
    special case, and the relative error stays a few ulp (times the growth of the motion) at
    ``r = 1 +- 1e-15``.
    """

    def __init__(self, mass: float, stiffness: float, slip_force: float, force_amplitude: float,
                 omega: float, damping: float = 0.0):
        m = self.mass = check_positive("mass", mass)
        k = self.stiffness = check_positive("stiffness", stiffness)
        f = self.slip_force = check_nonnegative("slip_force", slip_force)
        p0 = self.force_amplitude = check_real("force_amplitude", force_amplitude)
        w = self.omega = check_positive("omega", omega)
        c = self.damping = check_nonnegative("damping", damping)
        _check_scales(m, k, c, w)
        wn = math.sqrt(k / m)
        self._wn, self._wn2 = wn, k / m
        self._a = a = c / (2.0 * m)
        # q = wn^2 - a^2, factored for accuracy near critical damping
        self._q = q = (wn - a) * (wn + a)
        self._root = math.sqrt(abs(q))
        # particular part A cos wt + B sin wt (A + iB = P0/D, D = k - m w^2 - i c w), or, near
        # resonance (|D| < k/4: then q > 0.6 k/m), the resonance-stable form (see _at)
        d_, e_ = k - m * w * w, c * w
        den = d_ * d_ + e_ * e_
        self._near = q > 0.0 and den < (_NEAR * k) ** 2
        if self._near:
            b = self._root
            self._A = self._B = 0.0
            self._lp, self._lm = complex(-a, b), complex(-a, -b)        # lambda_+-
            self._mup, self._mum = complex(a, w - b), complex(a, w + b)  # i w - lambda_+-
            self._K = complex(0.0, -p0 / (2.0 * m * b))                   # P0/(m (l+ - l-))
        else:
            self._A, self._B = p0 * d_ / den, p0 * e_ / den
        # the quasi-static regime (module docstring): slips that start from a stick follow x_qs
        # (F >= |P0|: the slips are a shakedown to a rest position, on the scale |P0|/k)
        self._qs_delta = self.quasi_static_bound()
        slip_amp = (abs(p0) - f if abs(p0) > f else abs(p0)) / k
        self._quasi = f > 0.0 and slip_amp > 0.0 and not self._near and self._qs_delta <= QUASI_STATIC_TOL * slip_amp
        if self._quasi:
            self._A, self._B = p0 / k, 0.0  # x_p = x_qs: within _qs_delta of the exact motion
        self._R = math.hypot(self._A, self._B)
        # largest rate of the slipping configuration (|eigenvalue|), as the general marcher's
        if q >= 0.0:
            lam = wn
        else:
            lam = a + self._root
        self._rate_slip = max(w, lam)
        self._rate_stick = w
        self._fscale_fixed = max(abs(p0), f)
        # a slip piece's force scale (|P0| + F, the larger of |k x|) and m times its rate (a force
        # over it is the velocity scale of the event tolerances)
        self._fscale_slip = max(abs(p0) + f, self._fscale_fixed)
        self._m_rate = m * self._rate_slip
        # stuck pieces: P0 cos(wt) = |P0| cos(wt + phi)
        self._p0abs = abs(p0)
        self._phi = math.pi if p0 < 0 else 0.0
        self._period = _TWO_PI / w
        self._bound_constants()

    def __repr__(self) -> str:
        return (f"SdofCoulomb(mass={self.mass!r}, stiffness={self.stiffness!r}, "
                f"slip_force={self.slip_force!r}, force_amplitude={self.force_amplitude!r}, "
                f"omega={self.omega!r}, damping={self.damping!r})")

    # ----------------------------------------------------------------- closed forms
    def _hom(self, tau: float):
        """``e^{-a tau} S(tau)`` and ``e^{-a tau} S'(tau)``."""
        q, a, r = self._q, self._a, self._root
        if q > 0.0:
            e = math.exp(-a * tau) if a else 1.0
            return e * math.sin(r * tau) / r, e * math.cos(r * tau)
        if q == 0.0:
            e = math.exp(-a * tau)
            return e * tau, e
        # over-damped: e^{-a tau} sinh(r tau)/r without overflow or cancellation
        e = math.exp(-self._wn2 / (a + r) * tau)   # e^{-(a - r) tau}
        em = math.exp(-2.0 * r * tau)
        return e * (-math.expm1(-2.0 * r * tau)) / (2.0 * r), e * (1.0 + em) * 0.5

    def _hom_change(self, tau: float, xh0: float, vh0: float, es: float, esd: float) -> float:
        """``x_h(tau) - xh0 = xh0 (C - 1) + vh0 es`` (``C = esd + a es``, from :meth:`_at`) with
        ``C - 1`` formed without cancellation where the closed form allows: ``expm1`` and half-angle
        sines (under- and critically damped), the two decaying modes (over-damped, ``r >= a/100``)."""
        q, a, r = self._q, self._a, self._root
        if q > 0.0:
            cb, sb = math.cos(r * tau), math.sin(r * tau)
            h = math.sin(0.5 * r * tau)
            cm1 = (math.expm1(-a * tau) * (cb + a * sb / r) if a else 0.0) - 2.0 * h * h + a * sb / r
            return xh0 * cm1 + vh0 * es
        if q == 0.0:
            return xh0 * (math.expm1(-a * tau) * (1.0 + a * tau) + a * tau) + vh0 * es
        if r >= 0.01 * a:
            l1, l2 = -self._wn2 / (a + r), -(a + r)
            be = (vh0 - l1 * xh0) / (l2 - l1)
            return (xh0 - be) * math.expm1(l1 * tau) + be * math.expm1(l2 * tau)
        return xh0 * (esd + a * es - 1.0) + vh0 * es

    def _particular(self, t: float, s: int):
        """Particular solution ``(x_p, v_p)`` at absolute time ``t`` for status ``s``."""
        w = self.omega
        cw, sw = math.cos(w * t), math.sin(w * t)
        A, B = self._A, self._B
        xp = A * cw + B * sw - s * self.slip_force / self.stiffness
        vp = w * (B * cw - A * sw)
        return xp, vp, cw, sw

    def _start(self, t0: float, x0: float, v0: float, s: int):
        """Coefficients of the slip piece (or linear motion) from ``(t0, x0, v0)`` with status ``s``:
        ``(t0, xh0, vh0, z0, xc, x0)``. Far from resonance ``xh0, vh0`` are the initial homogeneous
        part and ``z0 = None``; near it the free response starts at ``(x0 - xc, v0)`` about
        ``xc = -s F/k`` and ``z0 = e^{i w t0}`` (the forced part starts at rest)."""
        if self._near:
            xc = -s * self.slip_force / self.stiffness
            wt = self.omega * t0
            return t0, x0 - xc, v0, complex(math.cos(wt), math.sin(wt)), xc, x0
        xp0, vp0, _, _ = self._particular(t0, s)
        return t0, x0 - xp0, v0 - vp0, None, -s * self.slip_force / self.stiffness, x0

    def _at(self, co, tau: float):
        """State ``(x, v, cos wt, sin wt, xh, vh)`` at ``t0 + tau`` of the piece ``co`` (:meth:`_start`).

        Far from resonance: particular + homogeneous part (``xh, vh``). Near it: ``xc`` + free
        response + the forced response from rest
        ``Re[P0/m e^{i w t0} (E+ - E-)/(l+ - l-)]`` with the exact integrals
        ``E(l) = int_0^tau e^{l (tau - u)} e^{i w u} du = tau e^{l tau} phi1((i w - l) tau)``,
        stable at and near resonance (``phi1(z) = (e^z - 1)/z``, continuous at ``z = 0``: the
        secular growth is its limit); ``xh, vh`` are then ``x - xc`` and ``v``.
        """
        t0, xh0, vh0, z0, xc, x0 = co
        w = self.omega
        wt = w * (t0 + tau)
        cw, sw = math.cos(wt), math.sin(wt)
        q, a, r = self._q, self._a, self._root
        if q > 0.0:
            e = math.exp(-a * tau) if a else 1.0
            cb, sb = math.cos(r * tau), math.sin(r * tau)
            es, esd = e * sb / r, e * cb
        else:
            es, esd = self._hom(tau)
        vh = vh0 * (esd - a * es) - self._wn2 * xh0 * es
        if z0 is None:
            # x = x0 + (x_p(t) - x_p(t0)) + (x_h - xh0), each difference without cancellation: the
            # parts x_p and xc + xh0 may be far larger than the motion (omega >> omega_n: the
            # offsets -s F/k against a motion ~ P0/(m w^2)), whose rounding would swamp it
            A, B = self._A, self._B
            sh, mid = math.sin(0.5 * w * tau), w * (t0 + 0.5 * tau)
            dxp = 2.0 * sh * (B * math.cos(mid) - A * math.sin(mid))
            dxh = self._hom_change(tau, xh0, vh0, es, esd)
            return (x0 + dxp + dxh, w * (B * cw - A * sw) + vh, cw, sw, xh0 + dxh, vh)
        xh = xh0 * (esd + a * es) + vh0 * es
        ew = complex(cw, sw)
        ec, esn = e * cb, e * sb
        lp = z0 * complex(ec, esn)     # e^{i w t0} e^{l+ tau}
        lm = z0 * complex(ec, -esn)    # e^{i w t0} e^{l- tau}
        mup, mum = self._mup, self._mum
        zp, zm = mup * tau, mum * tau
        ep = tau * lp * _phi1(zp) if abs(zp) < 0.5 else (ew - lp) / mup
        em = tau * lm * _phi1(zm) if abs(zm) < 0.5 else (ew - lm) / mum
        K = self._K
        xf = (K * (ep - em)).real
        vf = (K * (self._lp * ep - self._lm * em)).real
        x = xc + xh + xf
        v = vh + vf
        return x, v, cw, sw, x - xc, v

    def evaluate(self, status: int, t0: float, x0: float, v0: float, t: float):
        """Closed-form state at ``t`` of the piece that starts at ``(t0, x0, v0)`` with ``status``.

        Parameters
        ----------
        status : {-1, 0, 1}
            Slider status over the piece (``0``: stuck, the state is constant).
        t0 : float
            Start of the piece [s].
        x0, v0 : float
            State at ``t0`` [m, m/s].
        t : float
            Time [s], ``>= t0`` and within the piece.

        Returns
        -------
        x, v : float
            Displacement [m] and velocity [m/s].
        """
        if status == 0 and self.slip_force > 0:
            return x0, 0.0
        x, v = self._at(self._start(t0, x0, v0, status), t - t0)[:2]
        return x, v

    def quasi_static_bound(self) -> float:
        """Rigorous bound ``delta`` [m] on ``|x(t) - x_qs(t)|`` over a slip that starts from a stick.

        ``x_qs = (P0 cos wt - s F)/k`` is the quasi-static position of a slip in direction ``s``. A
        slip that starts from a stick starts where the holding force reaches ``s F``, i.e. at
        ``x = x_qs``, with ``v = 0``. The exact slip is ``x_p + x_h``: the particular part
        ``x_p = Re(P0 e^{iwt}/D) - s F/k`` (``D = k - m w^2 - i c w``) is within
        ``e_p = |P0| |k - D|/(k |D|)`` of ``x_qs``, and the homogeneous part starts at
        ``(x_qs - x_p, -v_p)`` with ``|v_p| <= w |P0|/|D|``; its energy ``(m v_h^2 + k x_h^2)/2``
        never grows (``c >= 0``), so ``|x_h| <= sqrt(e_p^2 + (m/k) v_p^2)``. Hence
        ``delta = e_p + sqrt(e_p^2 + (m/k) (w P0/|D|)^2)``, about ``(w/wn) |P0|/k`` for
        ``w << wn`` (first order in ``omega/omega_n``); the velocity is within
        ``(wn + w) delta`` of ``v_qs``.

        Returns
        -------
        float
            ``delta`` [m] (inf at an undamped resonance, where ``D = 0``).
        """
        m, k, c, w = self.mass, self.stiffness, self.damping, self.omega
        pa = abs(self.force_amplitude)
        dd = abs(complex(k - m * w * w, -c * w))  # |D|
        if dd == 0.0:
            return math.inf
        e_p = pa * abs(complex(m * w * w, c * w)) / (k * dd)
        return e_p + math.hypot(e_p, math.sqrt(m / k) * w * pa / dd)

    def _qs_state(self, t: float, s: int):
        """Quasi-static slip state ``(x_qs, v_qs)`` at ``t`` in direction ``s``."""
        p0, k, w = self.force_amplitude, self.stiffness, self.omega
        return (p0 * math.cos(w * t) - s * self.slip_force) / k, -p0 * w * math.sin(w * t) / k

    def _quasi_static_piece(self, t: float, x: float, v: float, s: int, t_end: float):
        """The slip piece from ``(t, x, v)`` in direction ``s`` in the quasi-static regime, or None
        where the state is not within :meth:`quasi_static_bound` of the quasi-static slip of that
        direction (then the exact march answers, e.g. the transient of an arbitrary start).

        Returns ``(t_stop, x_stop, v_stop, v_start, turned)``: the piece runs to the next turning
        point of ``x_qs`` (``sin wt = 0``, where the mass sticks: the force passes its extremum) or
        to ``t_end``; ``v_start`` is the velocity the piece's closed form starts from (``v_qs``)."""
        w, delta = self.omega, self._qs_delta
        scale = max(abs(self.force_amplitude), self.slip_force, abs(self.stiffness * x)) / self.stiffness
        xq, vq = self._qs_state(t, s)
        if (abs(x - xq) > delta + 1e-12 * scale or s * v < 0.0
                or abs(v - vq) > 2.0 * (self._wn + w) * delta + 1e-12 * w * scale):
            return None
        half = math.pi / w
        n = math.floor(t / half) + 1
        t_turn = n * half
        while t_turn <= t:
            n += 1
            t_turn = n * half
        if s * self._qs_state(0.5 * (t + t_turn), s)[1] <= 0.0:
            return None  # x_qs moves against s until the turn
        t_stop = min(t_turn, t_end)
        xe, ve = self._at(self._start(t, x, vq, s), t_stop - t)[:2]
        return t_stop, xe, ve, vq, t_turn <= t_end

    # ------------------------------------------------------------------ settling
    def settle(self, t: float, x: float, status: int, v_scale: float = 0.0, trigger: int = 0) -> int:
        """Stick/slip status at a state with ``v = 0`` (Hong & Liu's rules).

        The rules and tolerances of :meth:`frictionjoint.solvers.marcher.events.Marcher.settle`: the
        velocity of a slipping slider must not change sign (else it sticks); the holding force
        of a stuck one must stay within ``F`` (else it slips in the direction of that force);
        at the limit the first derivative decides and, within its tolerance band, the second.

        Parameters
        ----------
        t : float
            Time [s].
        x : float
            Displacement [m] (the velocity is 0).
        status : {-1, 0, 1}
            Status before the decision (the one the march arrived with).
        v_scale : float, optional
            Velocity scale seen so far [m/s] (velocity tolerance ``1e-11`` of it or of the
            load scale).
        trigger : {0, 1, -1}, optional
            The slip limit (``+1``: the holding force reaches ``+F``; ``-1``: ``-F``) that
            :meth:`_stick_end` located at ``t`` in closed form, if any. Its holding force is at
            the limit there, and a slip in its direction starts with zero net force, whatever the
            rounding of the phase ``w t`` (``8 eps |w t| |P0|``: 2e-12 N at ``t = 4e4 s``,
            ``w = 0.3``, more than the ``1e-12 F`` band): the derivatives decide.

        Returns
        -------
        int
            The new status.
        """
        f = self.slip_force
        if f == 0.0:
            return 0
        w, p0 = self.omega, self.force_amplitude
        cw, sw = math.cos(w * t), math.sin(w * t)
        h = p0 * cw - self.stiffness * x
        hd = -p0 * w * sw
        hdd = -p0 * w * w * cw
        # the located limit is at zero within the rounding of the phase w t; without this, a
        # stick end located by _stick_end read as still inside the band (or, slipping, as a net
        # force against the slip), the mass stayed stuck and the next exit found was a period later
        h_round = 8.0 * _EPS * abs(w * t) * abs(p0) if trigger else 0.0
        s, forced = int(status), False
        visited = set()
        kx = abs(self.stiffness * x)
        for _ in range(8):
            visited.add(s)
            fscale = max(abs(p0 * cw - s * f), self._fscale_fixed, kx)  # the general marcher's force scale
            if s != 0:
                if self._slip_holds(s, h, hd, fscale, v_scale, trigger, h_round, forced):
                    return s
                s, forced = 0, False
                continue
            new, g_new, tol = self._stick_breaks(h, hd, hdd, fscale, trigger, h_round)
            if new == 0:
                return 0
            if new in visited and g_new >= -tol:
                # a cycle stick -> slip -> stick at one instant (Marcher.settle's rule): the
                # holding force is within rounding of F and only the curvatures disagree; stay
                # stuck, the next event is found where the force leaves its zero band
                return 0
            s, forced = new, True
        raise ConvergenceError(f"no consistent stick/slip status at t = {t!r}")

    def _slip_holds(self, s: int, h: float, hd: float, fscale: float, v_scale: float, trigger: int,
                    h_round: float, forced: bool) -> bool:
        """The slipping rule of :meth:`settle`: a slider slipping in direction ``s`` at ``v = 0``
        (holding force ``h``, its rate ``hd``) slips on unless its velocity would change sign (the
        acceleration ``s v'`` below its band, or in it with ``s v'' < 0``; a slip just started from
        a stick (``forced``) keeps a positive ``s v'``)."""
        m, f = self.mass, self.slip_force
        v_ref = max(v_scale, fscale / self._m_rate)
        dtol = 10.0 * max(1e-11 * v_ref, 1e-300) * self._rate_slip
        net = h - s * f
        if s == trigger and abs(net) <= 1e-12 * max(f, fscale) + h_round:
            net = 0.0  # the onset at the located limit: zero net force
        acc = net / m
        dg, ddg = s * acc, s * (hd - self.damping * acc) / m
        return not (dg < -dtol or (abs(dg) <= dtol and ddg < 0 and not (forced and dg > 0)))

    def _stick_breaks(self, h: float, hd: float, hdd: float, fscale: float, trigger: int,
                      h_round: float):
        """The stuck rule of :meth:`settle`: ``(direction, g, tol)``, the limit (``+1``: ``+F``,
        ``-1``: ``-F``; 0: none) that the holding force ``h`` (rates ``hd``, ``hdd``) goes over
        most, its margin ``g = F -+ h`` and the force tolerance. At the limit (``|g| <= tol``)
        the first derivative decides and, within its band, the second."""
        f = self.slip_force
        tol = 1e-12 * max(f, fscale)
        dtol = 10.0 * max(tol, 1e-300) * self._rate_stick
        best, new, g_new = math.inf, 0, 0.0
        for sign, g, dg, ddg in ((1, f - h, -hd, -hdd), (-1, f + h, hd, hdd)):
            if sign == trigger and abs(g) <= tol + h_round:
                g = 0.0  # the located limit
            if abs(g) <= tol:
                if dg < -dtol:
                    score = dg / dtol
                elif abs(dg) <= dtol and ddg < 0:
                    score = -1.0
                else:
                    continue
            elif g < 0:
                score = g / max(tol, 1e-300)
            else:
                continue
            if score < best:
                best, new, g_new = score, sign, g
        return new, g_new, tol

    # -------------------------------------------------------------- stuck pieces
    def _stick_end(self, t0: float, x: float) -> tuple[float, int]:
        """First time after ``t0`` at which ``|P0 cos(wt) - k x|`` goes over ``F`` (inf if never),
        and the limit reached there (``+1``: ``+F``, ``-1``: ``-F``; 0 if never)."""
        p0a = self._p0abs
        if p0a == 0.0:
            return math.inf, 0
        z, f, phi = self.stiffness * x, self.slip_force, self._phi
        tol = 1e-12 * max(f, self._fscale_fixed, abs(z))
        best, side = math.inf, 0
        # upper limit: |P0| cos(psi) > z + F on psi in (-alpha, alpha), entered at -alpha
        if p0a - (z + f) > tol:
            c1 = (z + f) / p0a
            best, side = self._next_phase(t0, -math.acos(max(c1, -1.0)) - phi), 1
        # lower limit: |P0| cos(psi) < z - F on psi in (beta, 2 pi - beta), entered at beta
        if -p0a - (z - f) < -tol:
            c2 = (z - f) / p0a
            t_low = self._next_phase(t0, math.acos(min(c2, 1.0)) - phi)
            if t_low < best:
                best, side = t_low, -1
        return best, side

    def _next_phase(self, t0: float, theta: float) -> float:
        """Smallest ``t > t0`` with ``w t = theta (mod 2 pi)``."""
        w = self.omega
        n = math.floor((w * t0 - theta) / _TWO_PI) + 1
        t = (theta + _TWO_PI * n) / w
        while t <= t0:
            n += 1
            t = (theta + _TWO_PI * n) / w
        return t

    # -------------------------------------------------------------- slip pieces
    def _slip_event(self, t0: float, x0: float, v0: float, s: int, horizon: float, v_scale: float):
        """First ``tau`` in ``(0, horizon]`` with ``s v(t0 + tau) = 0``, or ``None``.

        Returns ``(tau, x, v, vmax)``: the event (or ``horizon``), the state there and the largest
        ``|v|`` seen on the way.
        """
        m, k, c, w = self.mass, self.stiffness, self.damping, self.omega
        p0, f = self.force_amplitude, self.slip_force
        sf = s * f
        co = self._start(t0, x0, v0, s)
        near = co[3] is not None
        xh, vh = (x0 - co[4], v0) if near else co[1:3]
        bounds = self._near_bounds if near else self._far_bounds
        v_ref = max(v_scale, max(self._fscale_slip, abs(k * x0)) / self._m_rate)
        tol_v = 1e-11 * v_ref
        tau = 0.0
        x, v = x0, v0
        cw, sw = math.cos(w * t0), math.sin(w * t0)
        vmax = abs(v0)
        start_zero = v0 == 0.0
        g_prev = g1_prev = None
        tau_prev = 0.0
        A, B = self._A, self._B
        eps_period = _EPS * self._period
        w2, w3 = w * w, w * w * w
        for _ in range(_MAX_STEPS):
            if near:
                acc = (p0 * cw - k * x - c * v - sf) / m
                jerk = (-p0 * w * sw - k * v - c * acc) / m
            else:
                # the derivatives of the closed form, part by part: from the force balance they
                # carry its rounding eps |k x| (c/m)^n, far above the motion's own where the
                # scales are far apart (k x ~ F, c w >> m w^2: a wrong-signed jerk, a root stepped
                # over at omega/omega_n = 1e-6, zeta = 0.01)
                ah = -(c * vh + k * xh) / m
                acc = ah - w2 * (A * cw + B * sw)
                jerk = w3 * (A * sw - B * cw) - (c * ah + k * vh) / m
            g, g1, g2 = s * v, s * acc, s * jerk
            if tau == 0.0 and start_zero:
                g, g1 = 0.0, max(g1, 0.0)
            elif g <= 0.0:
                return self._touch(t0, x0, v0, s, tau, x, tol_v, horizon) + (0.0, vmax)
            # a tangential dip of the velocity to (almost) zero counts as an event, as in the
            # general marcher (its dip tolerance 1e-11 of the velocity scale)
            if (g1_prev is not None and g1_prev < 0.0 <= g1 and min(g_prev, g) <= 100.0 * tol_v):
                dip = self._dip(t0, x0, v0, s, tau_prev, tau, tol_v)
                if dip is not None:
                    return dip + (0.0, vmax)
            m2, m3, cap = bounds(xh, vh)
            # safe step: g + g1 d - m2 d^2/2 > 0, and (g1 >= 0) d (g1 + g2 d/2 - m3 d^2/6) > 0
            disc = math.sqrt(g1 * g1 + 2.0 * m2 * g)
            step = (g1 + disc) / m2 if g1 >= 0.0 else 2.0 * g / (disc - g1)
            if g1 >= 0.0:
                b = 0.5 * g2
                disc3 = math.sqrt(b * b + 4.0 * (m3 / 6.0) * g1)
                step3 = (b + disc3) / (m3 / 3.0) if b >= 0.0 else 2.0 * g1 / (disc3 - b)
                step = max(step, step3)
            step = min(step, cap)
            tol_t = 4.0 * _EPS * abs(t0 + tau) + eps_period  # the time's resolution
            g_prev, g1_prev, tau_prev = g, g1, tau
            if tau + step >= horizon:
                tau = horizon
            elif step <= tol_t and not (tau == 0.0 and start_zero and step > 0.0):
                tau += step
                x = self._at(co, tau)[0]
                return self._touch(t0, x0, v0, s, tau, x, tol_v, horizon) + (0.0, vmax)
            else:
                tau += step
            x, v, cw, sw, xh, vh = self._at(co, tau)
            vmax = max(vmax, abs(v))
            if tau >= horizon:
                if s * v <= 0.0 and not (start_zero and tau == 0.0):
                    return self._touch(t0, x0, v0, s, tau, x, tol_v, horizon) + (0.0, vmax)
                return None, x, v, vmax
        # every safe step covers a fraction of the fastest period: a slip piece that outlasts them
        # spans thousands of natural periods, the scales-far-apart regime whose march is refused
        raise EventBudgetError(f"no event located after {_MAX_STEPS} safe steps from t = {t0!r} "
                               f"(omega/omega_n = {self.omega / self._wn:.3g}: the slip spans more natural "
                               "periods than a march resolves)")

    def _bound_constants(self):
        """Sets the constants of :meth:`_near_bounds` and :meth:`_far_bounds`, the parameters' alone
        (once: a slip piece's search then starts without set-up)."""
        m, k, c, w, wn2 = self.mass, self.stiffness, self.damping, self.omega, self._wn2
        p0a = abs(self.force_amplitude)
        # near resonance: bounds over the next dlt from the energy about xc
        dlt = 1.0 / self._rate_slip
        ge = p0a * dlt / math.sqrt(2.0 * m)
        self._near_consts = (m, k, c, p0a, p0a * w, p0a * w * w, dlt, ge, math.sqrt(2.0 / m),
                             math.sqrt(2.0 / k))
        # far from it: the particular part's bounds on |x_p^(3)| and |x_p^(4)| over the piece and,
        # over-damped, the decay rates l1a < l2a of the two real modes (module docstring)
        w3 = w * w * w
        over = self._q < 0.0
        l1a = l2a = inv_dl = 1.0  # (unused unless over-damped)
        if over:
            l1a, l2a = wn2 / (self._a + self._root), self._a + self._root
            inv_dl = 1.0 / (l2a - l1a)
        self._far_consts = (m, k, c, wn2, math.sqrt(wn2), w3 * self._R, w3 * w * self._R, over)
        self._over_consts = (l1a, l2a, inv_dl, 8.0 * _EPS * inv_dl)

    def _near_bounds(self, xh: float, vh: float):
        """``(M2, M3, cap)``: bounds on ``|g''|`` and ``|g'''|`` (``g = s v``) over the next ``cap``
        seconds of a slip piece near resonance at the state ``x - xc = xh``, ``v = vh``.

        Rigorous: the energy ``E = (m v^2 + k (x - xc)^2)/2`` has ``dE/dt = v (P0 cos wt - c v) <=
        |P0| |v|``, so ``sqrt(E)`` grows at most by ``|P0| cap/sqrt(2 m)`` (resonance-proof)."""
        m, k, c, p0a, p0a_w, p0a_w2, dlt, ge, rm, rk = self._near_consts
        se = math.sqrt(0.5 * (m * vh * vh + k * xh * xh)) + ge
        d1, d0 = rm * se, rk * se
        d2 = (p0a + k * d0 + c * d1) / m
        d3 = (p0a_w + k * d1 + c * d2) / m
        d4 = (p0a_w2 + k * d2 + c * d3) / m
        return d3 * (1.0 + 1e-12) + 1e-300, d4 * (1.0 + 1e-12) + 1e-300, dlt

    def _far_bounds(self, xh: float, vh: float):
        """``(M2, M3, inf)``: bounds on ``|g''|`` and ``|g'''|`` (``g = s v``) for the rest of a slip
        piece far from resonance, from its homogeneous state ``(xh, vh)`` (whose energy never
        grows) and the particular part's ``w^n |A + iB|``."""
        m, k, c, wn2, wn, mp3, mp4, over = self._far_consts
        d0 = math.sqrt(xh * xh + vh * vh / wn2)
        d1 = wn * d0
        d2 = (c * d1 + k * d0) / m
        d3 = (c * d2 + k * d1) / m
        d4 = (c * d3 + k * d2) / m
        if over:
            # over-damped: the modes a e^{l1 tau} + b e^{l2 tau} both decay, so |x_h^(n)| <=
            # |a| |l1|^n + |b| |l2|^n (with the rounding of a, b); the energy bound's
            # (c/m)^n alone would cut a heavily damped piece into ~c/(m w) steps per period
            l1a, l2a, inv_dl, slack = self._over_consts
            l1, l2 = -l1a, -l2a
            ra = abs(l2 * xh - vh) * inv_dl + slack * (abs(l2 * xh) + abs(vh))
            rb = abs(vh - l1 * xh) * inv_dl + slack * (abs(l1 * xh) + abs(vh))
            d3 = min(d3, ra * l1a ** 3 + rb * l2a ** 3)
            d4 = min(d4, ra * l1a ** 4 + rb * l2a ** 4)
        d3 += mp3
        d4 += mp4
        return d3 * (1.0 + 1e-12) + 1e-300, d4 * (1.0 + 1e-12) + 1e-300, math.inf

    def _touch(self, t0, x0, v0, s, tau, x, tol_v, horizon):
        """An event at ``tau`` where ``s v'' > 0`` and ``s v'`` is within its tolerance band, or
        the dip of ``s v`` below zero is within rounding, is a tangential touch that rounding
        turned into a crossing: it is moved to the minimum of ``s v`` (as the general marcher's
        dip location), where the rules see ``v' = 0`` (an abnormal stop)."""
        m, k, c, w, p0 = self.mass, self.stiffness, self.damping, self.omega, self.force_amplitude
        t = t0 + tau
        cw, sw = math.cos(w * t), math.sin(w * t)
        acc = (p0 * cw - k * x - s * self.slip_force) / m
        jerk = (-p0 * w * sw - c * acc) / m
        g1, g2 = s * acc, s * jerk
        dtol = 10.0 * tol_v * self._rate_slip
        # the crossing is a touch if the velocity's dip below zero is within rounding
        round_v = 64.0 * _EPS * tol_v * 1e11
        if g1 < 0.0 < g2 and (g1 >= -dtol or g1 * g1 <= 2.0 * g2 * round_v):
            # (the quadratic model of s v is local: look no further than a radian of the fastest
            # rate, nor past the piece)
            hi = min(tau + 4.0 * (-g1) / g2 + 4.0 * _EPS * abs(t), tau + 1.0 / self._rate_slip, horizon)
            dip = self._dip(t0, x0, v0, s, tau, hi, tol_v) if hi > tau else None
            if dip is not None:
                return dip
        return tau, x

    def _dip(self, t0, x0, v0, s, lo, hi, tol_v):
        """Minimum of ``s v`` between ``lo`` and ``hi`` (where ``s v'`` goes from - to +): an event
        ``(tau, x)`` if the minimum is within ``tol_v`` of zero (either side), else ``None``."""
        m, k, c, w, p0, sf = (self.mass, self.stiffness, self.damping, self.omega,
                              self.force_amplitude, s * self.slip_force)

        def sacc(tau):
            x, v = self.evaluate(s, t0, x0, v0, t0 + tau)
            return s * (p0 * math.cos(w * (t0 + tau)) - k * x - c * v - sf) / m, x, v

        if sacc(hi)[0] < 0.0:
            return None
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if mid <= lo or mid >= hi:
                break
            if sacc(mid)[0] < 0.0:
                lo = mid
            else:
                hi = mid
        _, x, v = sacc(hi)
        return (hi, x) if -tol_v <= s * v <= tol_v else None

    # ------------------------------------------------------------------- march
    def march(self, t0: float, x0: float, v0: float, t_end: float, status: Optional[int] = None,
              on_piece: Optional[Callable] = None, v_scale: Optional[float] = None,
              max_events: Optional[int] = None) -> SdofResult:
        """March exactly from ``(t0, x0, v0)`` to ``t_end``, event by event.

        Parameters
        ----------
        t0 : float
            Start time [s].
        x0, v0 : float
            Initial displacement [m] and velocity [m/s].
        t_end : float
            End time [s], ``>= t0``.
        status : {None, -1, 0, 1}, optional
            Slider status at the start: ``None`` (default) slips in the direction of ``v0`` or,
            if ``v0 = 0``, is settled by the stick/slip rules from stick (as
            :meth:`Marcher.initial_state`); ``0`` requires ``v0 = 0``; ``+1``/``-1`` continue a
            march (a returned :attr:`SdofResult.status`), ``v0`` must not oppose it.
        on_piece : callable, optional
            ``on_piece(t_start, x_start, v_start, status, t_stop, x_stop, v_stop)`` for every
            closed-form piece, in time order (``v_stop = 0`` at an event, before the rules at
            ``v = 0`` are applied); :meth:`evaluate` gives the state anywhere on it.
        v_scale : float, optional
            Velocity scale of the event tolerances at the start (``|v0|`` if omitted); a
            returned :attr:`SdofResult.v_scale` continues a march exactly.
        max_events : int, optional
            Stop just after this many events after ``t0`` (their rules applied): ``res.t < t_end``.

        Returns
        -------
        SdofResult
        """
        t = check_real("t0", t0)
        x = check_real("x0", x0)
        v = check_real("v0", v0)
        t_end = check_real("t_end", t_end)
        if t_end < t:
            raise ParameterError(f"t_end must be >= t0 = {t!r}, got {t_end!r}")
        s, settle_first = _start_status(v, status)
        counts = [0, 0, 0, 0]
        if self.slip_force == 0.0:
            return self._march_linear(t, x, v, t_end, on_piece)
        v_scale = abs(v) if v_scale is None else max(float(v_scale), 0.0)
        if settle_first:
            new = self.settle(t, x, s, v_scale)
            if new != s:
                counts[1] += 1
            s = new
        budget, n_pieces, first, zero_steps = self._budget(t, t_end), 0, sum(counts), 0  # (a settle at t0 is at t0)
        if self._chatter_rate() * (t_end - t) > budget:
            raise EventBudgetError(self._budget_message(budget, t0, t_end, "stick/slip events", "foreseen: "))
        while t < t_end and (max_events is None or sum(counts) - first < max_events):
            n_pieces += 1
            if n_pieces > budget:
                raise EventBudgetError(self._budget_message(budget, t0, t_end, "stick/slip events"))
            if s == 0:
                t, s = self._stuck_piece(t, x, t_end, v_scale, counts, on_piece)
                continue
            if self._quasi:
                qs = self._quasi_static_piece(t, x, v, s, t_end)
                if qs is not None:
                    t_stop, xe, ve, vq, turned = qs
                    if on_piece is not None:
                        on_piece(t, x, vq, s, t_stop, xe, 0.0 if turned else ve)
                    t, x, v = t_stop, xe, ve
                    v_scale = max(v_scale, abs(vq), abs(ve))
                    if turned:  # the force passes its extremum: the mass sticks
                        counts[0] += 1
                        s, v = 0, 0.0
                    continue
            start_v = v
            ev, t, x, v, v_scale, zero_steps = self._slip_piece(t, x, v, s, t_end, v_scale, zero_steps,
                                                               on_piece, "events")
            if ev is None:
                s, v = self._settle_at_end(t, x, v, s, v_scale, counts)
                break
            if not (math.isfinite(x) and math.isfinite(t)):
                raise ConvergenceError(f"non-finite state at t = {t!r}")
            s = self._after_stop(t, x, s, ev, start_v == 0.0, v_scale, counts)
        return SdofResult(t, x, v, s, sum(counts), dict(zip(EVENT_KINDS, counts)), v_scale)

    def _stuck_piece(self, t, x, t_end, v_scale, counts, on_piece):
        """A stuck piece from ``t`` at ``x`` to the end of the stick (:meth:`_stick_end`) or
        ``t_end``, handed to ``on_piece``; at the stick's end the rules decide (a slip is counted
        in ``counts``). Returns ``(t, status)`` at its end."""
        t_exit, side = self._stick_end(t, x)
        if on_piece is not None:
            on_piece(t, x, 0.0, 0, min(t_exit, t_end), x, 0.0)
        if t_exit >= t_end:
            return t_end, 0
        new = self.settle(t_exit, x, 0, v_scale, trigger=side)
        if new != 0:
            counts[1] += 1
        return t_exit, new

    def _after_stop(self, t, x, s, ev, from_rest, v_scale, counts):
        """The status after a slip piece of direction ``s`` stopped (``v = 0``) at ``(t, x)``, ``ev``
        after its start (``from_rest``: it started at ``v = 0``), counted in ``counts`` by kind:
        stick, normal or abnormal stop. An abnormal stop whose slip reverses again within time
        rounding (``s v'`` in its tolerance band, ``s v'' > 0`` only for an instant) is a stick:
        the slider does not leave the stop (no chatter of vanishing pieces)."""
        new = self.settle(t, x, s, v_scale)
        if new == s and from_rest and ev <= 4.0 * _EPS * abs(t) + _EPS * self._period:
            new = 0
        counts[0 if new == 0 else (3 if new == s else 2)] += 1
        return new

    def _budget(self, t0: float, t_end: float) -> float:
        """Pieces allowed to a march from ``t0`` to ``t_end`` (:data:`_PIECES_PER_PERIOD`)."""
        return _PIECES_PER_PERIOD * (2.0 + (t_end - t0) / self._period)

    def _chatter_rate(self) -> float:
        """Stick/slip events per second that a march is sure to meet (0 where none is foreseen).

        Where the mass breaks away every period (``F < |P0|``), the slips are not the quasi-static
        ones (:attr:`_quasi` false) and damping cannot end the free oscillation a break-away starts
        within the slip (``zeta <= 0.01 omega/omega_n``: it lives ``~0.14/zeta`` natural periods,
        measured, against the ``omega_n/(2 omega)`` of a half period), the velocity comes back to
        zero about once per natural period: ``omega_n/omega`` events a period (measured 0.997 of it
        undamped at ``omega/omega_n = 8e-4 .. 8e-5``, 0.83 of it in the first period from rest).
        0.8 of that rate is foreseen, so that a march refused up front (:meth:`march`) is one that
        would exhaust its budget, in no time instead of after ``_PIECES_PER_PERIOD`` pieces a period."""
        r = self.omega / self._wn
        zeta = self._a / self._wn
        if self._quasi or not 0.0 < self.slip_force < self._p0abs or zeta > 0.01 * r:
            return 0.0
        return 0.8 / (r * self._period)

    def _budget_message(self, budget: float, t0: float, t_end: float, what: str, foreseen: str = "") -> str:
        """Why a march was refused, in words (``foreseen``: refused before marching)."""
        r = self.omega / self._wn
        return (f"{foreseen}more than {budget:.6g} {what} from t = {t0!r} to {t_end!r} s "
                f"({(t_end - t0) / self._period:.3g} excitation periods): too many to march event by "
                f"event (omega/omega_n = {r:.3g}; where the forcing period is far beyond the natural "
                "one, the exact motion sticks and slips about once per natural period)")

    def _slip_piece(self, t, x, v, s, t_end, v_scale, zero_steps, on_piece, what):
        """One slip piece of direction ``s`` from ``(t, x, v)`` to its first event (``v = 0``) or
        ``t_end``, handed to ``on_piece``; returns ``(ev, t, x, v, v_scale, zero_steps)`` at its
        end (``ev``: the event's local time, None at ``t_end``). More than 8 pieces in a row that
        do not advance time are chattering (``what`` names the events in the error)."""
        ev, xe, ve, vmax = self._slip_event(t, x, v, s, t_end - t, v_scale)
        v_scale = max(0.5 * v_scale, vmax)
        t_stop = t_end if ev is None else t + ev
        if on_piece is not None:
            on_piece(t, x, v, s, t_stop, xe, ve)
        zero_steps = zero_steps + 1 if ev is not None and ev <= 0.0 else 0
        if zero_steps > 8:
            raise ConvergenceError(f"{what} do not advance time at t = {t!r} (chattering)")
        return ev, t_stop, xe, ve, v_scale, zero_steps

    def _settle_at_end(self, t, x, v, s, v_scale, counts):
        """At the end of a march in a slip piece, a velocity within its zero band is an event at
        ``t_end`` (as :meth:`Marcher.settle` judges the state it arrives at): settled by the rules,
        counted, ``v = 0`` if the status changes. Returns ``(status, v)``."""
        fscale = max(abs(self.force_amplitude) + self.slip_force, self._fscale_fixed, abs(self.stiffness * x))
        if abs(v) > 1e-11 * max(v_scale, fscale / (self.mass * self._rate_slip)):
            return s, v
        new = self.settle(t, x, s, v_scale)
        if new == s:
            return s, v
        counts[0 if new == 0 else 2] += 1
        return new, 0.0

    def _march_linear(self, t, x, v, t_end, on_piece):
        """``slip_force = 0``: one closed form; with ``on_piece``, pieces split at ``v = 0`` (not
        events) so that every extreme of ``x`` is at a piece end."""
        counts = dict.fromkeys(EVENT_KINDS, 0)
        if on_piece is None or t_end <= t:
            xe, ve = self.evaluate(1, t, x, v, t_end) if t_end > t else (x, v)
            return SdofResult(t_end, xe, ve, (ve > 0) - (ve < 0), 0, counts)
        v_scale, zero_steps = abs(v), 0
        budget, n_pieces = self._budget(t, t_end), 0
        while True:
            n_pieces += 1
            if n_pieces > budget:
                raise EventBudgetError(self._budget_message(budget, t, t_end, "turning points"))
            if v != 0.0:
                s = 1 if v > 0 else -1
            else:  # direction of the acceleration, else of the jerk
                w = self.omega
                h = self.force_amplitude * math.cos(w * t) - self.stiffness * x
                hd = -self.force_amplitude * w * math.sin(w * t)
                s = 1 if (h > 0 or (h == 0 and hd >= 0)) else -1
            ev, t, x, v, v_scale, zero_steps = self._slip_piece(t, x, v, s, t_end, v_scale, zero_steps,
                                                               on_piece, "turning points")
            if ev is None:
                return SdofResult(t, x, v, (v > 0) - (v < 0), 0, counts)

    def transition(self, tau: float):
        """Transition matrix of the slipping dynamics over ``tau`` [s]: ``d(x, v)(t0 + tau) /
        d(x, v)(t0)`` of a slip piece (the homogeneous part of :meth:`_at`), rows ``(x, v)``.

        Parameters
        ----------
        tau : float
            Time elapsed in the slip piece [s].

        Returns
        -------
        ((float, float), (float, float))
            The 2x2 transition matrix as nested tuples, rows ``(x, v)``, columns ``(x0, v0)``.
        """
        es, esd = self._hom(tau)
        a = self._a
        return ((esd + a * es, es), (-self._wn2 * es, esd - a * es))

    def monodromy(self, t0: float, x0: float, v0: float, t_end: float):
        """The state at ``t_end`` and its exact Jacobian with respect to ``(x0, v0)``.

        The Jacobian is the product, in time order, of each slip piece's transition matrix
        (:meth:`transition`) and the saltation matrix of each event (the linearised jump of the
        state's variation where the vector field ``f = (v, a)`` changes at ``g = v = 0``,
        ``S = I + (f+ - f-) (dg/dz)^T / (dg/dz . f-)``):

        - slip -> stick at ``v = 0``: ``f+ = 0``, ``S = [[1, 0], [0, 0]]`` (a stop forgets the
          velocity);
        - reversal ``s -> -s`` at ``v = 0``: the friction force changes sign,
          ``S = [[1, 0], [0, a+/a-]]``, ``a-+ = (P0 cos wt - k x -+ s F)/m``;
        - stick -> slip: the acceleration starts from zero (``f+ = f-``), ``S = I``; a stuck piece
          holds ``x`` and keeps ``v = 0``: identity;
        - a quasi-static slip piece (module docstring) follows ``x_qs`` whatever its start: zero.

        The start must be slipping (``v0 != 0``; a section inside a slip piece) and every event
        transversal: an abnormal stop (``v`` touches zero and goes on) or a reversal with a
        vanishing ``a-`` has no derivative, and the Jacobian is then ``None``.

        Parameters
        ----------
        t0 : float
            Start time [s].
        x0, v0 : float
            Initial state [m, m/s], ``v0 != 0``.
        t_end : float
            End time [s], ``>= t0``.

        Returns
        -------
        (SdofResult, tuple or None)
            The end state, and the 2x2 Jacobian as nested tuples (or None, see above).
        """
        if check_real("v0", v0) == 0.0 or self.slip_force == 0.0:
            end = self.march(t0, x0, v0, t_end)
            if self.slip_force == 0.0:  # linear: one transition matrix
                return end, self.transition(end.t - t0)
            return end, None
        pieces = []
        end = self.march(t0, x0, v0, t_end, on_piece=lambda *piece: pieces.append(piece))
        j = ((1.0, 0.0), (0.0, 1.0))
        m, k, f, p0, w = self.mass, self.stiffness, self.slip_force, self.force_amplitude, self.omega
        for i, (ta, xa, va, s, tb, xb, vb) in enumerate(pieces):
            if s == 0:
                continue  # stuck: x held, v = 0 (its variation was cleared at the stop)
            if self._quasi and self._quasi_static_piece(ta, xa, va, s, tb) is not None:
                j = ((0.0, 0.0), (0.0, 0.0))  # a quasi-static slip forgets its start: it follows x_qs
            else:
                j = _matmul(self.transition(tb - ta), j)
            if i + 1 == len(pieces):
                break  # the last piece ends at t_end, not at an event
            after = pieces[i + 1][3]
            h = p0 * math.cos(w * tb) - k * xb
            a_minus = (h - s * f) / m
            if after == 0:
                j = ((j[0][0], j[0][1]), (0.0, 0.0))
            elif after == -s and a_minus != 0.0 and s * a_minus < 0:
                ratio = ((h + s * f) / m) / a_minus
                j = (j[0], (ratio * j[1][0], ratio * j[1][1]))
            else:  # an abnormal stop (grazing) or a degenerate reversal: no derivative
                return end, None
        if end.status == 0 and pieces and pieces[-1][3] != 0:
            j = ((j[0][0], j[0][1]), (0.0, 0.0))  # stopped exactly at t_end
        return end, j

    def peak(self, t0: float, x0: float, v0: float, t_start: float, t_end: float,
             status: Optional[int] = None) -> float:
        """Exact ``max |x|`` over ``[t_start, t_end]`` of the motion from ``(t0, x0, v0)``.

        Extremes of ``x`` are where ``v = 0``: at the ends of the slip pieces (every ``v = 0``
        inside a slip piece is an event) and on stuck pieces, or at the window ends.

        Parameters
        ----------
        t0 : float
            Start time [s].
        x0, v0 : float
            Initial state [m, m/s].
        t_start, t_end : float
            Window [s], ``t0 <= t_start <= t_end``.
        status : {None, -1, 0, 1}, optional
            As in :meth:`march`.

        Returns
        -------
        float
            ``max |x|`` over the window [m].
        """
        t0 = check_real("t0", t0)
        t_start = check_real("t_start", t_start)
        t_end = check_real("t_end", t_end)
        if t_start < t0:
            raise ParameterError(f"t_start must be >= t0 = {t0!r}, got {t_start!r}")
        if t_end < t_start:
            raise ParameterError(f"t_end must be >= t_start = {t_start!r}, got {t_end!r}")
        peak = [0.0]
        ev = self.evaluate

        def piece(ta, xa, va, s, tb, xb, vb):
            if tb < t_start:
                return
            if ta <= t_start:  # the piece that holds the window start
                peak[0] = max(peak[0], abs(ev(s, ta, xa, va, t_start)[0]))
            peak[0] = max(peak[0], abs(xb))

        end = self.march(t0, x0, v0, t_end, status, on_piece=piece)
        return max(peak[0], abs(end.x))
