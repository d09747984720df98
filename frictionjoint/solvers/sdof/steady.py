"""Periodic steady state of the single-DOF Coulomb oscillator on its closed-form kernel.

The period map is :meth:`SdofCoulomb.monodromy`: one period of the exact scalar march and, with
it, the exact Jacobian (transition matrices of the slip pieces times the saltation matrices of
the events), so Newton needs no finite differences. The fixed point is found by the one shooting
algorithm (:mod:`frictionjoint.solvers.shooting`) from a section inside the longest slip piece of
the first period (the rule of :func:`frictionjoint.solvers.marcher.steady.periodic_response`), and the
final period is evaluated on the kernel's pieces: peak ``|x|`` at the piece ends (every extreme
of ``x`` is where ``v = 0``), first harmonic by Gauss quadrature per piece, events, stops and
dissipation.

:func:`sdof_periodic_response` answers None where this path does not apply -- no slipping start
for the section, an event without a derivative (a graze), a rule of the kernel that fails, or no
convergence (unbounded growth, slow transients) -- and the caller then takes the general marcher's
path, which reports those cases in words. Two cases it answers itself, in bounded time:

- a guess that stays stuck through the first period is a periodic orbit (a rest position; a
  family when ``|k x| < F - |P0|``), answered from that period;
- a scene whose exact march is refused (:class:`~frictionjoint.solvers.sdof.EventBudgetError`: a
  forcing period far beyond the natural one, where the exact motion sticks and slips about once
  per natural period) is answered by its quasi-static limit with a rigorous bound on the
  difference (:func:`quasi_static_response`).
"""
from __future__ import annotations

import cmath
import math

import numpy as np

from ...errors import ConvergenceError
from ...results import PeriodicResponse
from .kernel import QUASI_STATIC_TOL, EventBudgetError, SdofCoulomb, _phi1, event_kind
from ..shooting import find_periodic_orbit, has_unit_eigenvalue, orbit_message, residual_floor
from ..marcher import SECTION_MARGIN, EventLog, failed_response, gauss_nodes

__all__ = ["sdof_periodic_response", "sdof_orbit", "sdof_piece_fourier", "exp_integral", "quasi_static_response"]


class _NoDerivative(Exception):
    """The period map has no derivative at this state (start at rest, grazing event)."""


class _SdofPeriodMap:
    """Period map of the kernel from the section time ``t_s`` (shooting protocol)."""

    def __init__(self, kernel: SdofCoulomb, t_s: float, tol: float):
        self.k, self.t_s = kernel, t_s
        self.period = 2 * math.pi / kernel.omega
        self.calls = 0
        self.last = None
        # the kernel's slip pieces carry no static offset (SdofCoulomb._at forms x - x0 without
        # cancellation): their rounding is that of the motion, ~ P0/max(k, m w^2, c w), not of P0/k
        # (a floor of P0/k let the nearly neutral mean offset of a heavily damped or fast-forced
        # orbit stray by tol P0/k/(1 - multiplier): 5e-3 of the amplitude at c w = 1.4e6 k)
        w = kernel.omega
        self.x_floor = residual_floor(abs(kernel.force_amplitude), kernel.slip_force,
                                      max(kernel.stiffness, kernel.mass * w * w, kernel.damping * w), kernel.mass,
                                      w, tol)
        self.w_char = max(kernel.omega, math.sqrt(kernel.stiffness / kernel.mass))
        self.exact_jacobian = True  # every call computes the monodromy with the march

    def __call__(self, z):
        x0, v0 = float(z[0]), float(z[1])
        if v0 == 0.0:
            end, jac = self.k.march(self.t_s, x0, v0, self.t_s + self.period), None
        else:
            end, jac = self.k.monodromy(self.t_s, x0, v0, self.t_s + self.period)
        self.calls += 1
        out = np.array([end.x, end.v])
        self.last = (z.copy(), out, jac)
        return out

    def jacobian(self, z, pz, scale):
        if self.last is None or not np.array_equal(self.last[0], z):
            self(z)
        jac = self.last[2]
        if jac is None:
            raise _NoDerivative
        return np.array(jac)

    def scales(self, z):
        sx = max(abs(float(z[0])), abs(float(z[1])) / self.w_char, self.x_floor)
        return np.array([sx, sx * self.w_char])

    def amplitude(self, z) -> float:
        return math.hypot(float(z[0]), float(z[1]) / self.k.omega)


def _pieces(kernel, t0, x0, v0, t_end, status=None):
    out = []
    end = kernel.march(t0, x0, v0, t_end, status, on_piece=lambda *p: out.append(p))
    return end, out


def _section(kernel: SdofCoulomb, x0: float, v0: float):
    """Section time and the state there, or None (see :func:`periodic_response`'s rule)."""
    period = 2 * math.pi / kernel.omega
    end, pieces = _pieces(kernel, 0.0, x0, v0, period)
    slips = [p for p in pieces if p[3] != 0 and p[4] > p[0]]
    if not slips:
        return None  # stuck through the first period: the general path decides
    first, last = pieces[0], pieces[-1]
    margin = SECTION_MARGIN * period
    if (first[3] != 0 and last[3] != 0 and first[4] - first[0] > margin and last[4] - last[0] > margin
            and len(pieces) > 1 and v0 != 0.0 and not _near_reversal(kernel, 0.0, x0, v0, first[3], margin)):
        return 0.0, np.array([x0, v0]), 1.0
    # the middle of the longest slip piece of a period; where the next period sticks there (the
    # first period's longest slip was its transient), the next period's longest slip, a few times
    for n in range(1, 4):
        ta, _, _, _, tb, _, _ = max(slips, key=lambda p: p[4] - p[0])
        t_s = (ta + 0.5 * (tb - ta)) % period
        sec = kernel.march(n * period, end.x, end.v, n * period + t_s, end.status)
        if sec.v != 0.0:
            return t_s, np.array([sec.x, sec.v]), n + t_s / period
        end, pieces = _pieces(kernel, n * period, end.x, end.v, (n + 1) * period, end.status)
        slips = [p for p in pieces if p[3] != 0 and p[4] > p[0]]
        if not slips:
            return None
    return None


def _near_reversal(kernel, t, x, v, s, margin) -> bool:
    """``|v| < margin |a|``: a velocity reversal within ``margin`` of the start (a kink of the map)."""
    acc = (kernel.force_amplitude * math.cos(kernel.omega * t) - kernel.stiffness * x - kernel.damping * v
           - s * kernel.slip_force) / kernel.mass
    return abs(v) < margin * abs(acc)


def sdof_periodic_response(kernel: SdofCoulomb, x0: float, v0: float, *, tol: float, max_newton: int,
                           max_periods: int, n_samples: int = 0) -> PeriodicResponse | None:
    """Periodic steady state on the kernel, or None where the general path must answer.

    Parameters
    ----------
    kernel : SdofCoulomb
    x0, v0 : float
        Initial guess at ``t = 0`` [m, m/s].
    tol, max_newton, max_periods, n_samples :
        As :func:`frictionjoint.solvers.marcher.steady.periodic_response`.

    Returns
    -------
    PeriodicResponse or None
        Scalar ``amplitude``, ``phase``, ``harmonic_amplitude``; exact Floquet multipliers.
    """
    try:
        stuck = _stuck_orbit(kernel, x0, v0, n_samples)
        if stuck is not None:
            return stuck
        if kernel._quasi:  # the quasi-static limit is within QUASI_STATIC_TOL of the amplitude
            return quasi_static_response(kernel, n_samples)
        orbit = _orbit(kernel, x0, v0, tol=tol, max_newton=max_newton, max_periods=max_periods)
    except EventBudgetError as err:
        return quasi_static_response(kernel, n_samples, reason=str(err))
    if orbit is None:
        return None
    pmap, outcome, jac, periods = orbit
    z = outcome.z
    try:
        end, pieces = _pieces(kernel, pmap.t_s, float(z[0]), float(z[1]), pmap.t_s + pmap.period)
    except ConvergenceError:
        return None
    return _evaluate(kernel, pmap, outcome, z, jac, pieces, periods + 1, max_periods, n_samples)


def sdof_orbit(kernel: SdofCoulomb, x0: float, v0: float, *, tol: float, max_newton: int, max_periods: int):
    """The periodic orbit on the kernel, nothing evaluated on it: ``(pmap, outcome, jac, periods)``
    (``pmap.t_s`` the section time, ``outcome.z`` the state there, ``jac`` the exact monodromy,
    ``periods`` marched), or None where the general path must answer (see
    :func:`sdof_periodic_response`). A march refused for its event count raises
    :class:`EventBudgetError`: the general path would meet the same events, slower."""
    return _orbit(kernel, x0, v0, tol=tol, max_newton=max_newton, max_periods=max_periods)


def _orbit(kernel, x0, v0, *, tol, max_newton, max_periods):
    """:func:`sdof_orbit`, but a march refused for its event count raises :class:`EventBudgetError`."""
    try:
        section = _section(kernel, x0, v0)
        if section is None:
            return None
        t_s, z, periods = section
        pmap = _SdofPeriodMap(kernel, t_s, tol)
        outcome = find_periodic_orbit(pmap, z, pmap(z), tol=tol, max_newton=max_newton, max_periods=max_periods)
        if not outcome.converged:
            return None
        # shooting judges the residual on the scales of its guess: a guess far larger than the orbit
        # (the one-harmonic guess ignores viscous damping: 1e5 x too large at c w = 1.4e5 k) passes a
        # residual far above the orbit's own, which a nearly neutral mean offset turns into an error
        # (5e-3 of the amplitude there); polish on the orbit's own scales
        z = outcome.z
        pz = pmap.last[1] if np.array_equal(pmap.last[0], z) else pmap(z)
        if np.max(np.abs(pz - z) / pmap.scales(z)) > tol:
            polished = find_periodic_orbit(pmap, z, pz, tol=tol, max_newton=max_newton, max_periods=0)
            if polished.converged:
                outcome = polished
        jac = pmap.jacobian(outcome.z, None, None)
        calls = pmap.calls
        # a multiplier near 1 leaves the mean offset ill-conditioned (a family, or omega >> omega_n:
        # 1 - lambda ~ 2 pi^2 (omega_n/omega)^2): the antisymmetric orbit pins it -- any member of a
        # family, else only the same orbit (within 1e-6 of the scales), not another branch
        scales = pmap.scales(outcome.z)
        family = has_unit_eigenvalue(np.array(jac), scales)
        if family or np.min(np.abs(np.linalg.eigvals(np.array(jac)) - 1.0)) < 0.1:
            half = _HalfPeriodMap(kernel, t_s, tol)
            anti = _antisymmetric(half, outcome.z, tol, max_newton)
            calls += half.calls
            if anti is not None and (family or np.all(np.abs(anti.z - outcome.z) <= 1e-6 * scales)):
                outcome = anti
                pmap(anti.z)
                jac = pmap.jacobian(anti.z, None, None)
                calls += 1
    except EventBudgetError:
        raise
    except (_NoDerivative, ConvergenceError):
        return None
    return pmap, outcome, jac, periods + calls


class _HalfPeriodMap(_SdofPeriodMap):
    """``z -> -z(t_s + T/2)``: its fixed points are the orbits with ``x(t + T/2) = -x(t)`` (the
    forcing changes sign over half a period and friction is odd, so two such half-periods are the
    period map). Where the period map has an eigenvalue near 1 (a family of orbits, or a free mode
    far slower than the forcing, omega >> omega_n, whose mean offset one period cannot pin), the
    half map's Jacobian is near -1: its fixed point is well-conditioned."""

    def __init__(self, kernel: SdofCoulomb, t_s: float, tol: float):
        super().__init__(kernel, t_s, tol)
        self.period = math.pi / kernel.omega

    def __call__(self, z):
        out = -super().__call__(z)
        z0, _, jac = self.last
        self.last = (z0, out, None if jac is None else tuple(tuple(-a for a in row) for row in jac))
        return out


def _antisymmetric(half: _HalfPeriodMap, z, tol: float, max_newton: int):
    """The antisymmetric member near ``z`` of a family of orbits (or of a nearly neutral one), or
    None (no such orbit found, e.g. a period-doubled or asymmetric orbit)."""
    try:
        outcome = find_periodic_orbit(half, z, half(z), tol=tol, max_newton=max_newton, max_periods=0)
    except (_NoDerivative, ConvergenceError):
        return None
    return outcome if outcome.converged else None


def exp_integral(mu: complex, ta: float, tb: float) -> complex:
    """``int_ta^tb e^{mu t} dt = e^{mu ta} T phi1(mu T)``, ``T = tb - ta`` (exact at ``mu = 0``)."""
    return cmath.exp(mu * ta) * (tb - ta) * _phi1(mu * (tb - ta))


def sdof_piece_fourier(kernel: SdofCoulomb, s: int, ta: float, xa: float, va: float, tb: float,
                       nu: float) -> complex:
    """``int_ta^tb x(t) e^{i nu t} dt`` over a piece of the kernel.

    In closed form: a stuck piece holds ``x = xa``; a slip piece is ``A cos wt + B sin wt + xc +
    Re(C e^{lam tau})`` (``lam = -a + i r``, ``C = xh0 - i (a xh0 + vh0) / r``), or, over-damped,
    ``... + al e^{l1 tau} + be e^{l2 tau}`` (the two decaying modes, ``be = (vh0 - l1 xh0)/(l2 -
    l1)``, ``al = xh0 - be``), each term an exponential (:func:`exp_integral`). Near critical damping
    (``r < a/100``, where the modes' coefficients would cancel) the homogeneous part by
    Gauss-Legendre over the 50 time constants it lives; near resonance the whole piece by
    Gauss-Legendre at its fastest rate (exact to rounding; both cost a few hundred nodes at most)."""
    if tb <= ta:
        return 0j
    if s == 0 and kernel.slip_force > 0:
        return xa * exp_integral(1j * nu, ta, tb)
    if kernel._near:
        nodes, weights = gauss_nodes(ta, tb, max(kernel.omega, kernel._rate_slip))
        xs = np.array([kernel.evaluate(s, ta, xa, va, t)[0] for t in nodes])
        return complex(xs @ (weights * np.cos(nu * nodes)), xs @ (weights * np.sin(nu * nodes)))
    big_t = tb - ta
    co = kernel._start(ta, xa, va, s)
    t0, xh0, vh0, _, xc, _ = co
    w, a, r = kernel.omega, kernel._a, kernel._root
    jp, jm = exp_integral(1j * (nu + w), ta, tb), exp_integral(1j * (nu - w), ta, tb)
    out = kernel._A * 0.5 * (jp + jm) + kernel._B * (jp - jm) / 2j + xc * exp_integral(1j * nu, ta, tb)
    if kernel._q <= 0.0 and not r >= 0.01 * a:
        # critically or nearly critically damped: the homogeneous part by Gauss-Legendre over the
        # window where it lives (50 time constants of its slower mode, beyond which it is below
        # e^-50 of its start), not over the whole piece at the fast rate (millions of nodes where
        # the decay is far faster than the forcing: c = 2e6 at k = 1e12)
        rate = a + r
        t_cut = min(tb, ta + 50.0 * rate / kernel._wn2)
        nodes, weights = gauss_nodes(ta, t_cut, rate)
        xs = np.array([kernel._at(co, t - ta)[4] for t in nodes])
        return out + complex(xs @ (weights * np.cos(nu * nodes)), xs @ (weights * np.sin(nu * nodes)))
    if kernel._q < 0.0:  # over-damped: two real decaying modes
        l1, l2 = -kernel._wn2 / (a + r), -(a + r)
        be = (vh0 - l1 * xh0) / (l2 - l1)
        return out + cmath.exp(1j * nu * ta) * big_t * ((xh0 - be) * _phi1((l1 + 1j * nu) * big_t)
                                                        + be * _phi1((l2 + 1j * nu) * big_t))
    c = complex(xh0, -(a * xh0 + vh0) / r)
    lam = complex(-a, r)
    e0 = cmath.exp(1j * nu * ta)
    return out + 0.5 * e0 * big_t * (c * _phi1((lam + 1j * nu) * big_t)
                                      + c.conjugate() * _phi1((lam.conjugate() + 1j * nu) * big_t))


def _evaluate(kernel, pmap, outcome, z, jac, pieces, periods, max_periods, n_samples) -> PeriodicResponse:
    """The orbit's period on the kernel's pieces."""
    w, period, t_s = kernel.omega, pmap.period, pmap.t_s
    ev = kernel.evaluate
    log = EventLog()
    amp, a1, b1, diss = abs(float(z[0])), 0.0, 0.0, 0.0
    z0 = None
    for i, (ta, xa, va, s, tb, xb, vb) in enumerate(pieces):
        amp = max(amp, abs(xb))
        c1 = sdof_piece_fourier(kernel, s, ta, xa, va, tb, w)
        a1 += c1.real
        b1 += c1.imag
        if s != 0:
            diss += kernel.slip_force * abs(xb - xa)
        if z0 is None and t_s > 0 and ta <= period <= tb:
            z0 = np.array(ev(s, ta, xa, va, period))
        if i + 1 < len(pieces):
            log.append(tb, 0, 0, event_kind(s, pieces[i + 1][3]))
    a1 *= 2 / period
    b1 *= 2 / period
    unique = not has_unit_eigenvalue(jac, pmap.scales(z))
    t_arr = x_arr = None
    if n_samples:
        t_arr = t_s + period * np.arange(n_samples) / n_samples
        x_arr = np.empty(n_samples)
        j = 0
        for i, t in enumerate(t_arr):
            while j + 1 < len(pieces) and pieces[j][4] <= t:
                j += 1
            ta, xa, va, s = pieces[j][:4]
            x_arr[i] = ev(s, ta, xa, va, t)[0]
    res = PeriodicResponse(
        omega=w, amplitude=amp, phase=math.atan2(b1, a1), harmonic_amplitude=math.hypot(a1, b1),
        stops_per_cycle=log.count("stick"), stuck=all(p[3] == 0 for p in pieces),
        converged=True, unique=unique, message=orbit_message(outcome, unique, periods, max_periods),
        periods=periods, state=np.array(z), section_time=t_s, initial_state=z if t_s == 0 else z0,
        events=log, dissipated_per_cycle=diss, t=t_arr, x=x_arr)
    res.set_multipliers(np.linalg.eigvals(jac))
    return res


def _stuck_orbit(kernel: SdofCoulomb, x0: float, v0: float, n_samples: int) -> PeriodicResponse | None:
    """The orbit of a guess at rest that stays stuck through the first period, or None.

    Stuck at ``t = 0`` (the rules at ``v = 0`` keep it) and no break-away before ``t = T``: the
    state at ``T`` is the state at 0 and the forcing is ``T``-periodic, so this is a periodic orbit,
    exactly. The period map holds ``x`` and forgets ``v`` (multipliers 1 and 0): nearby rest
    positions are orbits too, a family (as the general path reports it)."""
    if v0 != 0.0 or kernel.slip_force == 0.0:
        return None
    period = 2 * math.pi / kernel.omega
    # the start of SdofCoulomb.march from rest: the rules at v = 0, then the stuck piece's end
    if kernel.settle(0.0, x0, 0) != 0 or kernel._stick_end(0.0, x0)[0] < period:
        return None
    t_arr = x_arr = None
    if n_samples:
        t_arr = period * np.arange(n_samples) / n_samples
        x_arr = np.full(n_samples, x0)
    res = PeriodicResponse(
        omega=kernel.omega, amplitude=abs(x0), phase=0.0, harmonic_amplitude=0.0, stops_per_cycle=0, stuck=True,
        converged=True, unique=False,
        message=("periodic steady state found: stuck at rest through the period; NOT UNIQUE: the period map "
                 "has an eigenvalue 1 (a family of rest positions); this is one member"),
        periods=1.0, state=np.array([x0, 0.0]), section_time=0.0, initial_state=np.array([x0, 0.0]),
        events=EventLog(), dissipated_per_cycle=0.0, t=t_arr, x=x_arr)
    res.set_multipliers([1.0, 0.0])
    return res


def quasi_static_response(kernel: SdofCoulomb, n_samples: int = 0, reason: str = "") -> PeriodicResponse:
    """Periodic response of the quasi-static limit (``omega/omega_n -> 0``), with its error bound.

    The limit is the play operator: with ``f = F/|P0| < 1``, ``X = (|P0| - F)/k`` and ``theta1 =
    arccos(1 - 2 f)``, for ``P0 > 0`` the mass sticks at ``X`` on ``0 <= wt < theta1``, slips at
    ``x = (P0 cos wt + F)/k`` to ``wt = pi``, sticks at ``-X`` to ``pi + theta1`` and slips at
    ``x = (P0 cos wt - F)/k`` to ``2 pi`` (``x`` is odd in ``P0``). Its first harmonic
    ``a1 cos wt + b1 sin wt`` (integrals of these pieces):
    ``a1 = (2/pi)(P0/k) [(pi - theta1)/2 + sin(2 theta1)/4]``, ``b1 = (4/pi)(P0/k) f (1 - f)``
    (the work ``pi P0 b1`` equals the dissipation ``4 F X``); two stops per cycle.

    The exact steady motion is within ``delta`` (:meth:`SdofCoulomb.quasi_static_bound`) of it: every slip
    starts from a stick; a stop needs ``x >= x_qs`` (else the holding force exceeds ``F`` and the
    slip goes on) and a stuck mass below ``max x_qs = X`` breaks away again before the force turns,
    so the exact amplitude lies in ``[X, X + delta]``. Where ``delta <= QUASI_STATIC_TOL X`` the
    limit is the answer (``converged``); else it is given with status ``'not converged'`` and the
    bound in the message (``'failed'`` if ``delta >= X``, where the limit says nothing).

    Parameters
    ----------
    kernel : SdofCoulomb
    n_samples : int
        If > 0, also return that many samples of ``x`` over the period.
    reason : str
        Why the exact march was not taken (for the message).

    Returns
    -------
    PeriodicResponse
    """
    m, k, f_slip, p0, w = (kernel.mass, kernel.stiffness, kernel.slip_force, kernel.force_amplitude,
                           kernel.omega)
    pa, sgn = abs(p0), (1.0 if p0 >= 0 else -1.0)
    period = 2 * math.pi / w
    ratio = w / math.sqrt(k / m)
    if f_slip >= pa:  # stuck in the limit: a rest position (x = 0 is one)
        res = _stuck_orbit(kernel, 0.0, 0.0, n_samples)
        if res is not None:
            return res
    delta = kernel.quasi_static_bound()
    amp = (pa - f_slip) / k
    why = f" ({reason})" if reason else ""
    if not delta < amp:
        return failed_response(
            w, None, f"the exact march was refused{why}, and the quasi-static limit says nothing here: its "
                     f"error bound {delta:.3g} m is not below its amplitude {amp:.3g} m "
                     f"(omega/omega_n = {ratio:.3g})", unique=False)
    f = f_slip / pa
    th1 = math.acos(1.0 - 2.0 * f)
    a1 = sgn * (2.0 / math.pi) * (pa / k) * (0.5 * (math.pi - th1) + 0.25 * math.sin(2.0 * th1))
    b1 = sgn * (4.0 / math.pi) * (pa / k) * f * (1.0 - f)
    log = EventLog()
    for theta, kind in ((th1, "slip"), (math.pi, "stick"), (math.pi + th1, "slip"), (2 * math.pi, "stick")):
        log.append(theta / w, 0, 0, kind)
    t_arr = x_arr = None
    if n_samples:
        t_arr = period * np.arange(n_samples) / n_samples
        th = (w * t_arr) % (2 * math.pi)
        x_arr = sgn * np.select([th < th1, th < math.pi, th < math.pi + th1],
                                [amp, (pa * np.cos(th) + f_slip) / k, -amp],
                                (pa * np.cos(th) - f_slip) / k)
    rel = delta / amp
    converged = rel <= QUASI_STATIC_TOL
    limit = (f"the quasi-static limit (omega/omega_n = {ratio:.3g}): the exact motion is within {delta:.3g} m "
             f"of it ({rel:.2g} of the amplitude)")
    message = (f"periodic steady state found: {limit}{why}" if converged else
               f"no exact periodic steady state{why}; given here: {limit}, more than {QUASI_STATIC_TOL:g}")
    z = np.array([sgn * amp, 0.0])
    res = PeriodicResponse(
        omega=w, amplitude=amp, phase=math.atan2(b1, a1), harmonic_amplitude=math.hypot(a1, b1),
        stops_per_cycle=2, stuck=False, converged=converged, unique=True, message=message, periods=0.0,
        status="periodic" if converged else "not converged", state=z, section_time=0.0, initial_state=z.copy(),
        events=log, dissipated_per_cycle=4.0 * f_slip * amp, t=t_arr, x=x_arr)
    if converged:
        res.set_multipliers([0.0, 0.0])  # every slip starts from a stick, where the state is forgotten
    return res
