"""Closed-form answers for the single-DOF Coulomb oscillator and describing functions.

The oscillator (DESIGN.md section 3) is::

    m x'' + k x + F sgn(x') = P0 cos(w t)

with ``wn = sqrt(k/m)``, frequency ratio ``r = w/wn``, friction ratio ``f = F/P0`` and
dimensionless amplitude ``X̄ = X k / P0``.  Den Hartog (1931) found the continuous
("stop-free") steady motion in closed form; this module evaluates it, decides whether
it is the physical motion, and supplies the one-harmonic (describing-function)
approximations used for comparison.

Notation of the kernels (dimensionless time ``tau = wn t``, force phase ``phi = w t``)::

    V = 1/(1 - r^2),   U = tan(pi/(2 r))/r,   X̄ = sqrt(V^2 - f^2 U^2)
    cos(theta) = X̄/V,  sin(theta) = -f U/V
    rising half-cycle (tau from the displacement minimum, force ∝ cos(r tau + theta - pi)):
    x̄(tau) = f cos(tau) + r f U sin(tau) + V cos(r tau + theta - pi) - f
    x̄(tau + pi/r) = -x̄(tau)

``theta`` is the force phase at which the displacement is largest, i.e. the lag of the
displacement maximum behind the force maximum.  It lies in ``(0, pi)`` where ``U/V < 0``
(``r > 1`` and ``1/(2n) < r < 1/(2n-1)``) but is *negative* (the displacement maximum
leads the force maximum) for ``1/(2n+1) < r < 1/(2n)``, e.g. ``1/3 < r < 1/2``; this
corrects DESIGN.md, which states ``theta in (0, pi)`` throughout.  The first harmonic of
the waveform, integrated in closed form over the half-cycle, is::

    x̄1 = a1 cos(phi) + b1 sin(phi),  a1 = V + 4 f^2 U/pi,  b1 = 4 f X̄/pi

so its lag ``atan2(b1, a1)`` is always in ``(0, pi)`` for ``f > 0`` and the work of the
force per cycle, ``pi b1 = 4 f X̄``, equals the friction dissipation.

References
----------
J. P. Den Hartog, "Forced vibrations with combined Coulomb and viscous friction",
Trans. ASME APM-53-9 (1931) 107-115.
J.-H. Hong and C.-S. Liu, "Non-sticking oscillation formulae for Coulomb friction under
harmonic loading", J. Sound Vib. 244 (2001) / "Coulomb friction oscillator: modelling and
responses to harmonic loads and base excitations", J. Sound Vib. 229 (2000) 1171-1192.
frictionjoint DESIGN.md, section 3.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from .errors import (
    NoSolutionError,
    ParameterError,
    check_nonnegative,
    check_oscillator,
    check_positive,
)

__all__ = [
    "NoSolutionError",
    "DenHartogSolution",
    "DenHartogResponse",
    "den_hartog",
    "den_hartog_boundary",
    "den_hartog_response",
    "den_hartog_curve",
    "wall_base_mapping",
    "coulomb_describing_function",
    "harmonic_balance_amplitude",
    "jenkins_describing_function",
]

REGIMES = ("stop-free", "stops", "unbounded", "stuck")

_EPS = np.finfo(float).eps
# Velocity sampling density: points per shortest period (2 pi / max(1, r)) of the waveform.
_POINTS_PER_PERIOD = 64
_MIN_POINTS = 256
_BLOCK = 1 << 16


# --------------------------------------------------------------------------- kernels


def _special_ratio(r: float, m: int) -> bool:
    """True when ``m r == 1`` to rounding (``r = 1/m`` for a positive integer ``m``)."""
    return m >= 1 and abs(m * r - 1.0) <= 8.0 * _EPS


def _coefficients(r: float) -> tuple[float, float]:
    """Return Den Hartog's ``V = 1/(1-r^2)`` and ``U = tan(pi/(2r))/r`` (``r != 1``).

    ``U`` is set to exactly 0 at ``r = 1/(2n)`` (within rounding), where the stop-free
    solution is one member of a family (DESIGN.md section 3).
    """
    v = 1.0 / ((1.0 - r) * (1.0 + r))
    n = round(0.5 / r)
    if _special_ratio(r, 2 * n):
        u = 0.0
    else:
        u = math.tan(0.5 * math.pi / r) / r
    return v, u


def _half_cycle(tau, f, r, v, u, theta, derivative=0):
    """Derivative ``derivative`` (0-3, w.r.t. tau) of the rising half-cycle ``x̄(tau)``.

    ``x̄(tau) = f cos tau + r f U sin tau - V cos(r tau + theta) - f`` (Den Hartog 1931;
    ``cos(a - pi) = -cos a``), valid on ``0 <= tau <= pi/r``.
    """
    c, s = np.cos(tau), np.sin(tau)
    ph = r * tau + theta
    cp, sp = np.cos(ph), np.sin(ph)
    rfu = r * f * u
    if derivative == 0:
        return f * c + rfu * s - v * cp - f
    if derivative == 1:
        return -f * s + rfu * c + r * v * sp
    if derivative == 2:
        return -f * c - rfu * s + r * r * v * cp
    if derivative == 3:
        return f * s - rfu * c - r**3 * v * sp
    raise ParameterError(f"derivative must be 0, 1, 2 or 3, got {derivative!r}")


def _interior_stop(f, r, v, u, theta):
    """Return the first ``tau`` in ``(0, pi/r)`` where the velocity vanishes, else ``None``.

    The exact velocity ``x̄'(tau)`` is sampled with at least ``_POINTS_PER_PERIOD`` points
    per shortest period; a negative sample is located by Brent's method on ``x̄'``; every
    discrete local minimum is refined by Brent's method on ``x̄''`` (confirmed a minimum by
    ``x̄''' >= 0``) so that tangential zeros, which do not change the sign of the velocity,
    are caught as well.  A minimum within ``64 eps`` of the velocity scale counts as zero.
    """
    period = math.pi / r
    h_target = 2.0 * math.pi / max(1.0, r) / _POINTS_PER_PERIOD
    n = max(_MIN_POINTS, int(math.ceil(period / h_target)))
    scale = abs(v) * r + f * (1.0 + r * abs(u))
    tol = 64.0 * _EPS * scale

    def vel(t):
        return _half_cycle(t, f, r, v, u, theta, 1)

    def acc(t):
        return _half_cycle(t, f, r, v, u, theta, 2)

    for start in range(0, n, _BLOCK):
        stop = min(start + _BLOCK + 1, n)
        idx = np.arange(start, stop + 1)
        tau = period * idx / n
        w = vel(tau)
        # Both ends of the half-cycle are turning points: the velocity is exactly zero there.
        w[idx == 0] = 0.0
        w[idx == n] = 0.0
        neg = np.flatnonzero((w < 0.0) & (idx > 0) & (idx < n))
        if neg.size:
            j = neg[0]
            a, b = tau[j - 1], tau[j]
            if idx[j - 1] > 0 and w[j - 1] > 0.0:
                return brentq(vel, a, b, xtol=1e-15, rtol=4 * _EPS)
            return a
        inner = np.arange(1, len(idx) - 1)
        mins = inner[(w[inner] <= w[inner - 1]) & (w[inner] <= w[inner + 1])]
        for j in mins:
            a, b = tau[j - 1], tau[j + 1]
            ga, gb = acc(a), acc(b)
            if ga < 0.0 < gb:
                t_star = brentq(acc, a, b, xtol=1e-15, rtol=4 * _EPS)
            else:
                t_star = tau[j]
            if _half_cycle(t_star, f, r, v, u, theta, 3) < 0.0:
                continue
            if vel(t_star) <= tol:
                return float(t_star)
    return None


def _wrap(angle: float) -> float:
    """Wrap an angle to ``(-pi, pi]``."""
    a = math.remainder(angle, 2.0 * math.pi)
    return math.pi if a == -math.pi else a


# --------------------------------------------------------------------------- results


@dataclass(frozen=True)
class DenHartogSolution:
    """Den Hartog's closed-form steady motion of the Coulomb oscillator (dimensionless).

    Built by :func:`den_hartog`; all quantities are dimensionless (displacement in units
    of ``P0/k``, energy in units of ``P0^2/k``, angles in rad).

    Attributes
    ----------
    frequency_ratio : float
        ``r = w/wn`` [-].
    friction_ratio : float
        ``f = F/P0`` [-].
    regime : str
        ``'stop-free'`` (the closed form is the steady motion), ``'stops'`` (no stop-free
        periodic motion: the steady motion sticks or stops during the cycle, or the closed
        form is complex), ``'unbounded'`` (``r = 1`` and ``f < pi/4``: the amplitude grows
        by about ``pi - 4 f`` per period without bound) or ``'stuck'`` (``f >= 1``: the
        mechanical energy cannot increase while the mass moves, so every motion dies out
        and the mass ends at rest; for ``f < 1`` no position can hold the mass for a whole
        cycle, so permanent sticking happens exactly when ``f >= 1``).
    applicable : bool
        ``regime == 'stop-free'``: only then are the fields below the physical answer.
    unique : bool
        False where the stop-free periodic motion is one member of a family: ``U = 0``,
        i.e. ``r = 1/(2n)``, a family of mean offsets (for ``f = 0``: ``r = 1/n``, free
        vibration at ``wn`` is periodic with the forcing).  Reported whatever the regime.
    real : bool
        The closed form gives a finite real amplitude (``V^2 >= f^2 U^2``, ``r != 1``).
    amplitude : float
        ``X̄ = X k/P0``; ``math.nan`` when not ``real``, except ``math.inf`` in the
        ``'unbounded'`` regime.  Where ``real`` but not ``applicable`` this is the (wrong)
        closed-form value.
    peak_phase : float
        ``theta``: force phase at which the displacement is largest, i.e. lag of the
        displacement maximum behind the force maximum, in ``(-pi, pi]`` [rad] (negative,
        a lead, for ``1/(2n+1) < r < 1/(2n)``).  ``nan`` when not ``real``.
    harmonic_amplitude : float
        Amplitude ``A1`` of the first harmonic of ``x̄`` (closed-form Fourier integral) [-].
    harmonic_phase : float
        Lag of the first harmonic behind the force, ``atan2(b1, a1)`` in ``[0, pi]`` [rad].
    dissipation_per_cycle : float
        Friction work per cycle ``4 f X̄`` (energy in units of ``P0^2/k``).
    linear_magnification : float
        Den Hartog's ``V = 1/(1 - r^2)`` (``inf`` at ``r = 1``).
    friction_factor : float
        Den Hartog's ``U = tan(pi/(2r))/r`` (``inf`` at ``r = 1``).
    message : str
        Human-readable explanation of the regime.
    """

    frequency_ratio: float
    friction_ratio: float
    regime: str
    unique: bool
    real: bool
    amplitude: float
    peak_phase: float
    harmonic_amplitude: float
    harmonic_phase: float
    dissipation_per_cycle: float
    linear_magnification: float
    friction_factor: float
    message: str = field(default="")

    @property
    def applicable(self) -> bool:
        """True iff the closed form is the steady motion (``regime == 'stop-free'``)."""
        return self.regime == "stop-free"

    def waveform(self, phase, derivative: int = 0):
        """Evaluate the closed-form waveform at force phase ``phase = w t``.

        Exact (no quadrature, no time step).  The force is ``cos(phase)``.  This is the
        physical motion only when :attr:`applicable`; it is available whenever
        :attr:`real` so that callers can inspect why it fails.

        Parameters
        ----------
        phase : float or ndarray
            Force phase ``w t`` [rad], any shape.
        derivative : {0, 1, 2, 3}
            Order of the derivative with respect to ``tau = wn t`` (``1``: velocity in units
            of ``wn P0/k``; ``2``: acceleration in units of ``P0/m``).

        Returns
        -------
        float or ndarray
            ``d^n x̄/d tau^n`` with the shape of ``phase``.

        Raises
        ------
        NoSolutionError
            If the closed form is not real (``real`` is False).
        """
        if not self.real:
            raise NoSolutionError(
                f"no closed-form waveform at frequency_ratio={self.frequency_ratio!r}, "
                f"friction_ratio={self.friction_ratio!r}: {self.message}"
            )
        if derivative not in (0, 1, 2, 3):
            raise ParameterError(f"derivative must be 0, 1, 2 or 3, got {derivative!r}")
        phi = np.asarray(phase, dtype=float)
        if not np.all(np.isfinite(phi)):
            raise ParameterError("phase must be finite")
        r, f = self.frequency_ratio, self.friction_ratio
        theta = self.peak_phase
        # Force phase at the start of the rising half-cycle (displacement minimum): theta - pi.
        s = np.mod(phi - (theta - math.pi), 2.0 * math.pi)
        second = s >= math.pi
        tau = np.where(second, s - math.pi, s) / r
        out = _half_cycle(
            tau, f, r, self.linear_magnification, self.friction_factor, theta, derivative
        )
        out = np.where(second, -out, out)
        return out[()] if out.ndim == 0 else out


@dataclass(frozen=True)
class DenHartogResponse:
    """Den Hartog's answer in physical units (from :func:`den_hartog_response`).

    Attributes
    ----------
    amplitude : float
        ``max |x|`` over a period, ``X = X̄ |P0|/k`` [m] (same ``nan``/``inf`` convention
        as :attr:`DenHartogSolution.amplitude`).
    phase : float
        Lag of the first harmonic of ``x`` behind ``cos(w t)`` [rad], in ``(-pi, pi]``
        (in ``(0, pi)`` when the equivalent force amplitude ``P0 > 0``).
    peak_phase : float
        Lag of the displacement maximum behind ``cos(w t)`` [rad], in ``(-pi, pi]``.
    harmonic_amplitude : float
        Amplitude of the first harmonic of ``x`` [m].
    dissipation_per_cycle : float
        Friction work per cycle ``4 F X`` [J].
    equivalent_force_amplitude : float
        ``P0 = P + k Y`` [N] (signed).
    natural_frequency : float
        ``wn = sqrt(k/m)`` [rad/s].
    omega : float
        Excitation angular frequency ``w`` [rad/s].
    stiffness : float
        ``k`` [N/m].
    regime, applicable, unique, message
        As in :class:`DenHartogSolution`.
    dimensionless : DenHartogSolution
        The underlying dimensionless solution (for ``|P0|``).
    """

    amplitude: float
    phase: float
    peak_phase: float
    harmonic_amplitude: float
    dissipation_per_cycle: float
    equivalent_force_amplitude: float
    natural_frequency: float
    omega: float
    stiffness: float
    dimensionless: DenHartogSolution

    @property
    def regime(self) -> str:
        """Regime of the dimensionless solution (see :class:`DenHartogSolution`)."""
        return self.dimensionless.regime

    @property
    def applicable(self) -> bool:
        """True iff the closed form is the steady motion."""
        return self.dimensionless.applicable

    @property
    def unique(self) -> bool:
        """False at ``r = 1/(2n)`` (family of stop-free solutions)."""
        return self.dimensionless.unique

    @property
    def message(self) -> str:
        """Human-readable explanation of the regime."""
        return self.dimensionless.message

    def displacement(self, t):
        """Closed-form displacement ``x(t)`` [m] at time ``t`` [s] (any shape).

        Only the physical motion when :attr:`applicable`.

        Raises
        ------
        NoSolutionError
            If the closed form is not real.
        """
        p0 = self.equivalent_force_amplitude
        t = np.asarray(t, dtype=float)
        shift = 0.0 if p0 > 0 else math.pi
        return abs(p0) / self.stiffness * self.dimensionless.waveform(self.omega * t + shift)


# --------------------------------------------------------------------------- public API


def den_hartog(frequency_ratio: float, friction_ratio: float) -> DenHartogSolution:
    """Den Hartog's stop-free steady motion of the Coulomb oscillator, with its validity.

    Solves ``x̄'' + x̄ + f sgn(x̄') = cos(r tau + const)`` (``tau = wn t``) for the
    half-wave-antisymmetric motion without stops (Den Hartog 1931; DESIGN.md section 3)
    and classifies the parameters:

    1. ``f >= 1``: ``'stuck'`` (permanent sticking, see :class:`DenHartogSolution`);
    2. ``r == 1``: ``'unbounded'`` if ``f < pi/4`` (growth about ``pi - 4 f`` per
       period), else ``'stops'``;
    3. ``V^2 < f^2 U^2``: no real closed form, ``'stops'``;
    4. Den Hartog's boundary ``X̄ r^2 >= f`` violated (the mass sticks at the turning
       point), ``'stops'``;
    5. the exact velocity vanishes inside the half-cycle (possible for ``r < 1/2`` even
       when 4. holds; checked for every ``r`` by dense sampling and Brent's method on the
       exact derivatives), ``'stops'``;
    6. otherwise ``'stop-free'``.

    Parameters
    ----------
    frequency_ratio : float
        ``r = w/wn`` [-], in ``(0, inf)``.
    friction_ratio : float
        ``f = F/P0`` [-], in ``[0, inf)``.

    Returns
    -------
    DenHartogSolution
        Dimensionless solution and its regime.

    Raises
    ------
    ParameterError
        If an argument is non-finite or out of range.

    Notes
    -----
    The run time of step 5 grows like ``1/r`` (about ``32/r`` velocity samples); it is
    skipped for ``f = 0``, where the velocity ``|V| r sin(r tau)`` is positive inside.
    """
    r = check_positive("frequency_ratio", frequency_ratio)
    f = check_nonnegative("friction_ratio", friction_ratio)
    unique = _unique(r, f)
    nan = math.nan
    if r == 1.0:
        return _at_resonance(r, f, unique)

    v, u = _coefficients(r)
    disc = v * v - (f * u) ** 2
    real = disc >= 0.0 and math.isfinite(disc)
    if not real:
        regime = "stuck" if f >= 1.0 else "stops"
        msg = _stuck_message(f) if f >= 1.0 else (
            f"no stop-free motion: Den Hartog's closed form is complex (V^2 - f^2 U^2 = "
            f"{disc:.6g} < 0); the steady motion has stops"
        )
        return DenHartogSolution(
            r, f, regime, unique, False, nan, nan, nan, nan, nan, v, u, msg
        )

    amp = math.sqrt(disc)
    # cos(theta) = X̄/V, sin(theta) = -f U/V; scaling both by |V| keeps atan2 exact.
    sv = math.copysign(1.0, v)
    theta = math.atan2(-f * u * sv + 0.0, amp * sv)
    a1 = v + 4.0 * f * f * u / math.pi
    b1 = 4.0 * f * amp / math.pi
    h_amp = math.hypot(a1, b1)
    h_phase = math.atan2(b1 + 0.0, a1)
    dissipation = 4.0 * f * amp
    regime, msg = _real_regime(r, f, v, u, amp, theta, unique)
    return DenHartogSolution(
        r, f, regime, unique, True, amp, theta, h_amp, h_phase, dissipation, v, u, msg
    )


def _unique(r: float, f: float) -> bool:
    """Whether the stop-free periodic motion is unique: not at ``r = 1/(2n)`` (``U = 0``, a family
    of mean offsets), for ``f = 0`` not at ``r = 1/n`` (free vibration is periodic with the force)."""
    if f == 0.0:
        return not _special_ratio(r, round(1.0 / r))
    return not _special_ratio(r, 2 * round(0.5 / r))


def _at_resonance(r: float, f: float, unique: bool) -> DenHartogSolution:
    """The answer at ``r = 1``, where Den Hartog's closed form does not exist: unbounded growth
    for ``f < pi/4``, a bounded motion with stops above, permanent sticking for ``f >= 1``."""
    nan = math.nan
    if f < math.pi / 4.0:
        regime, amp = "unbounded", math.inf
        msg = (
            f"resonance r = 1 with f = {f:g} < pi/4: no steady state; the amplitude "
            f"grows by about (pi - 4 f) = {math.pi - 4.0 * f:g} (units P0/k) per period"
        )
    else:
        regime, amp = "stops", nan
        msg = (
            f"resonance r = 1 with f = {f:g} >= pi/4: Den Hartog's closed form does not "
            "exist; the bounded steady motion has stops"
        )
    if f >= 1.0:
        regime = "stuck"
        msg = _stuck_message(f)
    return DenHartogSolution(
        r, f, regime, unique, False, amp, nan, nan, nan, nan, math.inf, math.inf, msg
    )


def _real_regime(r: float, f: float, v: float, u: float, amp: float, theta: float,
                 unique: bool) -> tuple[str, str]:
    """``(regime, message)`` where the closed form is real (steps 1, 4, 5 and 6 of
    :func:`den_hartog`): permanent sticking, a stop at the turning point (Den Hartog's boundary),
    a stop inside the half-cycle (the exact velocity), else stop-free."""
    margin = amp * r * r - f
    if f >= 1.0:
        return "stuck", _stuck_message(f)
    if margin < 0.0:
        return "stops", (
            f"the mass sticks at the turning point: Den Hartog's boundary X̄ r^2 >= f "
            f"fails (X̄ r^2 - f = {margin:.6g}); the closed form is real but not the motion"
        )
    tau_stop = _interior_stop(f, r, v, u, theta) if f > 0.0 else None
    if tau_stop is not None:
        return "stops", (
            f"the velocity of the closed-form waveform vanishes inside the half-cycle "
            f"(tau = wn t = {tau_stop:.9g} after the turning point, force phase "
            f"{_wrap(r * tau_stop + theta - math.pi):.9g} rad) although X̄ r^2 >= f: "
            "the steady motion has stops and the closed form is not the motion"
        )
    msg = "stop-free motion: Den Hartog's closed form is the steady motion"
    if not unique:
        msg += (
            " (not unique: at r = 1/(2n) it is one member of a family of stop-free "
            "periodic motions with different mean offsets)"
            if f > 0.0
            else " (not unique: without friction, free vibration at wn is periodic "
            "with the forcing at r = 1/n)"
        )
    return "stop-free", msg


def _stuck_message(f: float) -> str:
    return (
        f"permanent sticking: f = {f:g} >= 1, the force can never do more work than friction "
        "dissipates, so every motion dies out and the mass ends at rest"
    )


def den_hartog_boundary(frequency_ratio: float) -> float:
    """Den Hartog's stop boundary ``f_b(r)``: ``X̄ r^2 = f`` solved for ``f``.

    ``f_b = r^2 |V| / sqrt(1 + r^4 U^2)``; ``f_b -> pi/4`` as ``r -> 1``.  Necessary for
    stop-free motion; sufficient only for ``r >= 1/2`` (DESIGN.md section 3).

    Parameters
    ----------
    frequency_ratio : float
        ``r = w/wn`` [-], in ``(0, inf)``.

    Returns
    -------
    float
        ``f_b`` [-] (``pi/4`` at ``r = 1``; ``0`` at ``r = 1/(2n+1)``).
    """
    r = check_positive("frequency_ratio", frequency_ratio)
    if r == 1.0:
        return math.pi / 4.0
    v, u = _coefficients(r)
    if not math.isfinite(u) or abs(u) > 1e300:
        return 0.0
    r2 = r * r
    return r2 * abs(v) / math.sqrt(1.0 + (r2 * u) ** 2)


def den_hartog_response(
    mass: float,
    stiffness: float,
    slip_force: float,
    force_amplitude: float,
    omega: float,
    base_amplitude: float = 0.0,
) -> DenHartogResponse:
    """Den Hartog's steady response in physical units, force and base excitation.

    ``m x'' + k (x - y) + F sgn(x') = P cos(w t)`` with ``y = Y cos(w t)`` and friction
    against fixed ground is the oscillator of :func:`den_hartog` with
    ``P0 = P + k Y`` (DESIGN.md section 3).  For ``P0 < 0`` the response is the one for
    ``|P0|`` shifted by half a period; phases are measured against ``cos(w t)``.

    Parameters
    ----------
    mass : float
        ``m`` [kg], in ``(0, inf)``.
    stiffness : float
        ``k`` [N/m], in ``(0, inf)``.
    slip_force : float
        Coulomb slip force ``F`` [N], in ``[0, inf)``.
    force_amplitude : float
        ``P`` [N], real.
    omega : float
        Excitation angular frequency ``w`` [rad/s], in ``(0, inf)``.
    base_amplitude : float, optional
        ``Y`` [m], real (default 0).

    Returns
    -------
    DenHartogResponse

    Raises
    ------
    ParameterError
        If an argument is out of range or ``P + k Y == 0`` (no excitation).
    """
    m, k, friction, p, y, p0 = check_oscillator(mass, stiffness, slip_force, force_amplitude, base_amplitude)
    w = check_positive("omega", omega)
    wn = math.sqrt(k / m)
    sol = den_hartog(w / wn, friction / abs(p0))
    scale = abs(p0) / k
    shift = 0.0 if p0 > 0.0 else math.pi
    return DenHartogResponse(
        amplitude=sol.amplitude * scale,
        phase=_wrap_or_nan(sol.harmonic_phase - shift),
        peak_phase=_wrap_or_nan(sol.peak_phase - shift),
        harmonic_amplitude=sol.harmonic_amplitude * scale,
        dissipation_per_cycle=4.0 * friction * sol.amplitude * scale,
        equivalent_force_amplitude=p0,
        natural_frequency=wn,
        omega=w,
        stiffness=k,
        dimensionless=sol,
    )


def den_hartog_curve(omegas, mass: float, stiffness: float, slip_force: float,
                     force_amplitude: float, base_amplitude: float = 0.0):
    """Den Hartog's amplitude and phase at many frequencies, masked where it is not the motion.

    Parameters
    ----------
    omegas : (n,) array_like
        Angular frequencies [rad/s], > 0.
    mass, stiffness, slip_force, force_amplitude, base_amplitude : float
        As in :class:`frictionjoint.CoulombOscillator` [kg, N/m, N, N, m].

    Returns
    -------
    amplitude : (n,) masked ndarray
        Max ``|x|`` [m].
    phase : (n,) masked ndarray
        First-harmonic lag behind ``cos(omega t)`` [rad].
    regime : (n,) ndarray of str
        Regime word of :func:`frictionjoint.analytic.den_hartog`.
    """
    amps, phases, regimes = [], [], []
    for w in np.atleast_1d(np.asarray(omegas, dtype=float)):
        dh = den_hartog_response(mass, stiffness, slip_force, force_amplitude, float(w),
                                 base_amplitude)
        ok = dh.applicable and math.isfinite(dh.amplitude)
        amps.append(dh.amplitude if ok else math.nan)
        phases.append(dh.phase if ok else math.nan)
        regimes.append(dh.regime)
    amps, phases = np.array(amps), np.array(phases)
    return (np.ma.MaskedArray(np.where(np.isfinite(amps), amps, 0.0), mask=~np.isfinite(amps)),
            np.ma.MaskedArray(np.where(np.isfinite(phases), phases, 0.0), mask=~np.isfinite(phases)),
            np.array(regimes, dtype=str))


def _wrap_or_nan(angle: float) -> float:
    return angle if math.isnan(angle) else _wrap(angle)


def wall_base_mapping(
    stiffness: float, slip_force: float, base_amplitude: float, omega: float, mass: float
) -> tuple[float, float]:
    """Map base excitation with friction *relative to the base* onto Den Hartog's problem.

    With ``y = Y cos(w t)`` driving both the spring and the friction wall,
    ``z = x - y`` obeys ``m z'' + k z + F sgn(z') = m w^2 Y cos(w t)``, i.e. Den Hartog
    with ``P0 = k Y r^2 = m w^2 Y`` and ``f = beta/r^2``, ``beta = F/(k Y)`` (DESIGN.md
    section 3).  The answer of :func:`den_hartog` is then for the relative motion ``z``.

    Parameters
    ----------
    stiffness : float
        ``k`` [N/m], in ``(0, inf)``.
    slip_force : float
        ``F`` [N], in ``[0, inf)``.
    base_amplitude : float
        ``Y`` [m], in ``(0, inf)``.
    omega : float
        ``w`` [rad/s], in ``(0, inf)``.
    mass : float
        ``m`` [kg], in ``(0, inf)``.

    Returns
    -------
    equivalent_force_amplitude : float
        ``P0 = m w^2 Y`` [N].
    friction_ratio : float
        ``f = F/P0`` [-].
    """
    check_positive("stiffness", stiffness)  # validated; f = F/(m w^2 Y) does not depend on k
    friction = check_nonnegative("slip_force", slip_force)
    y = check_positive("base_amplitude", base_amplitude)
    w = check_positive("omega", omega)
    m = check_positive("mass", mass)
    p0 = m * w * w * y
    if not (math.isfinite(p0) and p0 > 0.0):
        raise ParameterError(f"mass * omega**2 * base_amplitude must be in (0, inf), got {p0!r}")
    return p0, friction / p0


def coulomb_describing_function(slip_force: float, amplitude: float, omega: float) -> float:
    """Equivalent viscous damping of a Coulomb slider, ``c_eq = 4 F/(pi w X)``.

    One-harmonic describing function: under ``x = X cos(w t)`` the first harmonic of the
    friction force ``F sgn(x')`` equals ``c_eq x'`` (DESIGN.md section 3).

    Parameters
    ----------
    slip_force : float
        ``F`` [N], in ``[0, inf)``.
    amplitude : float
        ``X`` [m], in ``(0, inf)``.
    omega : float
        ``w`` [rad/s], in ``(0, inf)``.

    Returns
    -------
    float
        ``c_eq`` [N s/m].
    """
    friction = check_nonnegative("slip_force", slip_force)
    x = check_positive("amplitude", amplitude)
    w = check_positive("omega", omega)
    return 4.0 * friction / (math.pi * w * x)


def harmonic_balance_amplitude(frequency_ratio: float, friction_ratio: float) -> float:
    """One-harmonic balance amplitude ``X̄_HB = sqrt(1 - (4 f/pi)^2)/|1 - r^2|``.

    From ``m x'' + c_eq x' + k x = P0 cos(w t)`` with ``c_eq = 4 F/(pi w X)``
    (DESIGN.md section 3).  An approximation: compare with :func:`den_hartog`.

    Parameters
    ----------
    frequency_ratio : float
        ``r`` [-], in ``(0, inf)``.
    friction_ratio : float
        ``f`` [-], in ``[0, pi/4]``.

    Returns
    -------
    float
        ``X̄_HB = X k/P0`` [-]; ``inf`` at ``r = 1`` with ``f < pi/4``.

    Raises
    ------
    NoSolutionError
        If ``4 f/pi > 1`` (no one-harmonic solution), or ``r = 1`` with ``f = pi/4``
        (every amplitude balances: indeterminate).
    """
    r = check_positive("frequency_ratio", frequency_ratio)
    f = check_nonnegative("friction_ratio", friction_ratio)
    q = 4.0 * f / math.pi
    if q > 1.0:
        raise NoSolutionError(
            f"friction_ratio must be <= pi/4 = {math.pi / 4:.17g} for a one-harmonic "
            f"solution (allowed range [0, pi/4]), got {f!r}: friction exceeds the force's "
            "first harmonic"
        )
    num = math.sqrt((1.0 - q) * (1.0 + q))
    if r == 1.0:
        if num == 0.0:
            raise NoSolutionError(
                "frequency_ratio = 1 with friction_ratio = pi/4: every amplitude satisfies "
                "the one-harmonic balance (indeterminate)"
            )
        return math.inf
    return num / abs((1.0 - r) * (1.0 + r))


def jenkins_describing_function(
    tangential_stiffness: float, slip_force: float, amplitude: float
) -> complex:
    """One-harmonic complex stiffness of a Jenkins element (spring in series with a slider).

    Under ``u = u0 cos(w t)`` the steady force has first harmonic
    ``Re(K u0 exp(i w t)) = u0 (Re K cos(w t) - Im K sin(w t))``.  With the slip
    displacement ``uy = Fs/kt`` and ``sin(beta/2) = sqrt(uy/u0)`` (``cos beta = 1 - 2 uy/u0``,
    the phase at which the stuck branch reaches the opposite slip limit)::

        Re K = (kt/pi) (beta - sin(2 beta)/2),   Im K = (4 Fs/(pi u0)) (1 - uy/u0)

    for ``u0 > uy`` and ``K = kt`` for ``u0 <= uy`` (no slip).  ``pi u0^2 Im K`` is the loop
    area ``4 Fs (u0 - uy)``.  Classical result (e.g. Griffin 1980; DESIGN.md section 3).

    Parameters
    ----------
    tangential_stiffness : float
        ``kt`` [N/m], in ``(0, inf)``.
    slip_force : float
        ``Fs`` [N], in ``[0, inf)``.
    amplitude : float
        ``u0`` [m], in ``[0, inf)``.

    Returns
    -------
    complex
        ``K`` [N/m].
    """
    kt = check_positive("tangential_stiffness", tangential_stiffness)
    fs = check_nonnegative("slip_force", slip_force)
    u0 = check_nonnegative("amplitude", amplitude)
    uy = fs / kt
    if u0 <= uy:
        return complex(kt, 0.0)
    ratio = uy / u0
    beta = 2.0 * math.asin(math.sqrt(ratio))
    if beta < 0.05:
        # beta - sin(2 beta)/2 = sum_{j>=1} (-1)^(j+1) 2^(2j) beta^(2j+1)/(2j+1)!, no cancellation.
        b2 = beta * beta
        term, series, j = 4.0 * b2 * beta / 6.0, 0.0, 1
        while True:
            series += term
            j += 1
            term *= -4.0 * b2 / ((2 * j) * (2 * j + 1))
            if abs(term) <= 1e-18 * abs(series):
                break
        real = kt / math.pi * series
    else:
        real = kt / math.pi * (beta - 0.5 * math.sin(2.0 * beta))
    imag = 4.0 * fs / (math.pi * u0) * (1.0 - ratio)
    return complex(real, imag)
