"""Independent brute-force reference for the tests of ``frictionjoint``.

This module deliberately imports nothing from ``frictionjoint``: it is the
independent check of the package's exact event-driven solver.  Every smooth
phase of motion is integrated numerically with ``scipy.integrate.solve_ivp``
(DOP853, rtol 1e-12, atol 1e-14 x amplitude scale, max_step <= 1/24 of the
shortest period) with terminal event functions for the mode changes; the
motion is restarted in the new mode after each event.

Systems (t is absolute time, the excitation is cos(omega t)):

* Coulomb oscillator, friction against fixed ground::

      m x'' + c x' + k (x - Y cos wt) + F sgn(x') = P cos wt

  At v = 0, Hong & Liu's rules on the force sticking would need,
  ``h(t) = (P + k Y) cos wt - k x``: |h| < F -> stop of finite duration
  ('stick'), which ends when |h| reaches F ('slide', direction sign h; the
  exit time is the closed-form arccos root of h = +-F since x is frozen);
  |h| > F -> slip on in direction sign h without stopping ('normal' if
  reversed, 'abnormal' if same direction - only a grazing touch of v = 0).
* Jenkins element (spring kt in series with a slider Fs), and an Iwan
  element = parallel Jenkins sliders, each with its own slider state::

      m x'' + c x' + k (x - Y cos wt) + sum_i T_i = P cos wt,
      T_i = kt_i (x - w_i), |T_i| <= Fs_i.

Public functions: :func:`coulomb_response`, :func:`coulomb_steady_state`,
:func:`jenkins_response`, :func:`iwan_response`.
"""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

__all__ = ["coulomb_response", "coulomb_steady_state", "jenkins_response",
           "iwan_response"]

METHOD = "DOP853"
RTOL = 1e-12
ATOL_FACTOR = 1e-14
STEPS_PER_PERIOD = 24          # max_step = shortest period / this
_GRACE = 1e-11                 # forced progress after a no-change event, x shortest period
_TWO_PI = 2.0 * math.pi


class Result(SimpleNamespace):
    """Plain attribute container for results."""


# --------------------------------------------------------------------------- helpers
def _check_positive(name, value, allow_zero=False):
    value = float(value)
    if not math.isfinite(value) or value < 0 or (value == 0 and not allow_zero):
        raise ValueError(f"{name} must be {'>= 0' if allow_zero else '> 0'} and finite, got {value}")
    return value


def _time_points(t_eval, t_end):
    t_eval = np.atleast_1d(np.asarray(t_eval, dtype=float))
    if t_eval.ndim != 1:
        raise ValueError("t_eval must be one-dimensional")
    slack = 1e-12 * max(1.0, abs(t_end))
    if t_eval.size and (t_eval.min() < -slack or t_eval.max() > t_end + slack):
        raise ValueError("t_eval must lie in [0, t_end]")
    return np.clip(t_eval, 0.0, t_end)


def _scales(m, k_eff, omega, P, k, Y, x0, v0):
    """Reference displacement scale and frequency for the absolute tolerance."""
    wn = math.sqrt(k_eff / m) if k_eff > 0 else 0.0
    wref = max(omega, wn)
    if wref == 0.0:
        wref = 1.0
    kref = max(k_eff, m * omega * omega)
    xs = max(abs(x0), abs(v0) / wref, abs(Y))
    if kref > 0:
        xs = max(xs, (abs(P) + k * abs(Y)) / kref)
    if xs == 0.0 or not math.isfinite(xs):
        xs = 1.0
    periods = [p for p in (_TWO_PI / omega if omega > 0 else 0.0,
                           _TWO_PI / wn if wn > 0 else 0.0) if p > 0]
    tshort = min(periods) if periods else 1.0
    return xs, wref, tshort


def _solve(rhs, t0, y0, t1, events, xs, wref, tshort):
    """Integrate from t0 towards t1, stopping at the first mode-change event.

    events: list of (g, direction, dg, gscale): g(t, y) the switching function
    (crossing in `direction` ends the phase), dg its time derivative.  Besides
    the sign changes at step ends that solve_ivp watches, the extrema of g
    (roots of dg, non-terminal events) are checked: an extremum beyond the
    threshold means g crossed and came back inside one step (a double crossing
    solve_ivp cannot see); the first crossing is then found by brentq on the
    dense output.  Returns (sol, fired, te, ye): fired is the index of the
    event that ended the phase (None if t1 was reached).
    """
    evf = []
    for g, d, _, _ in events:
        evf.append(_make_event(g, d))
    for _, d, dg, _ in events:
        f = (lambda t, y, dg=dg: dg(t, y))
        f.terminal = False
        f.direction = -d          # local max of g (d = +1) / local min of g (d = -1)
        evf.append(f)
    atol = np.array([ATOL_FACTOR * xs, ATOL_FACTOR * xs * wref])
    sol = solve_ivp(rhs, (t0, t1), np.asarray(y0, dtype=float), method=METHOD,
                    events=evf if evf else None, dense_output=True,
                    rtol=RTOL, atol=atol, max_step=tshort / STEPS_PER_PERIOD)
    if sol.status == -1:
        raise RuntimeError(f"solve_ivp failed: {sol.message}")
    n = len(events)
    fired, te, ye = None, float(sol.t[-1]), sol.y[:, -1].copy()
    if sol.status == 1:
        best = math.inf
        for i in range(n):
            if len(sol.t_events[i]) and sol.t_events[i][0] < best:
                best, fired = float(sol.t_events[i][0]), i
        te, ye = best, np.asarray(sol.y_events[fired][0], dtype=float).copy()
    # double crossings hidden inside one step
    tiny = 1e-13 * max(abs(t0), tshort)
    missed = None
    for i, (g, d, _, gs) in enumerate(events):
        for tx, yx in zip(sol.t_events[n + i], sol.y_events[n + i]):
            if tx >= te:
                break
            if tx > t0 + tiny and d * g(tx, yx) > 1e-13 * gs:
                if missed is None or tx < missed[0]:
                    missed = (float(tx), i)
                break
    if missed is not None:
        tx, i = missed
        g, d = events[i][0], events[i][1]
        G = lambda tt: g(tt, sol.sol(tt))
        ts = np.asarray(sol.sol.ts)
        k = max(int(np.searchsorted(ts, tx, side="right")) - 1, 0)
        tl = float(ts[k])
        while k > 0 and d * G(tl) >= 0:        # step start must be on the inner side
            k -= 1
            tl = float(ts[k])
        if d * G(tl) < 0:
            te = brentq(G, tl, tx, xtol=1e-15 * max(1.0, abs(tx)), rtol=4 * np.finfo(float).eps,
                        maxiter=200)
        else:
            te = tl
        fired, ye = i, np.asarray(sol.sol(te), dtype=float)
    return sol, fired, te, ye


def _eval_segments(segments, t_eval, ncomp):
    """Evaluate the piecewise solution. segments: (ta, tb, fun) with fun(t)->(ncomp, n)."""
    out = np.empty((ncomp, t_eval.size))
    if t_eval.size == 0:
        return out
    starts = np.array([s[0] for s in segments])
    idx = np.clip(np.searchsorted(starts, t_eval, side="right") - 1, 0, len(segments) - 1)
    for j in np.unique(idx):
        sel = idx == j
        out[:, sel] = segments[j][2](t_eval[sel])
    return out


# --------------------------------------------------------------------------- Coulomb
class _Coulomb:
    def __init__(self, m, k, c, F, P, Y, w):
        self.m = _check_positive("mass", m)
        self.k = _check_positive("stiffness", k, allow_zero=True)
        self.c = _check_positive("damping", c, allow_zero=True)
        self.F = _check_positive("slip_force", F, allow_zero=True)
        self.w = _check_positive("omega", w, allow_zero=True)
        self.P, self.Y = float(P), float(Y)
        self.A = self.P + self.k * self.Y         # amplitude of the ground-relative drive

    def h(self, t, x):
        """Force the ground must supply to hold the mass at rest (c v = 0 at v = 0)."""
        return self.A * math.cos(self.w * t) - self.k * x

    def hdot(self, t):
        return -self.A * self.w * math.sin(self.w * t)

    def rhs(self, s):
        m, k, c, A, w, Fs = self.m, self.k, self.c, self.A, self.w, self.F * s

        def f(t, y):
            return [y[1], (A * math.cos(w * t) - k * y[0] - c * y[1] - Fs) / m]
        return f

    def decide(self, t, x, s_old):
        """Hong & Liu at v = 0. Returns (new_mode, kind); new_mode 0 = stuck."""
        h = self.h(t, x)
        tol = 1e-12 * (abs(self.A) + self.k * abs(x) + self.F)
        outward = h * self.hdot(t) > 0
        if abs(h) > self.F + tol or (abs(h) >= self.F - tol and outward and h != 0.0):
            s_new = 1 if h > 0 else -1
            if s_old == 0:
                kind = "slide"
            else:
                kind = "normal" if s_new == -s_old else "abnormal"
            return s_new, kind
        return 0, "stick"

    def stick_exit(self, t, x):
        """First time > t at which |h| grows through F while x is frozen (closed form)."""
        A, k, F, w = self.A, self.k, self.F, self.w
        if A == 0.0 or w == 0.0:
            return None, 0
        Aa = abs(A)
        phi = 0.0 if A > 0 else math.pi          # A cos(wt) = Aa cos(wt + phi)
        theta_now = w * t + phi
        best, s_best = math.inf, 0
        b1 = (k * x + F) / Aa                     # h = +F, h increasing: sin(theta) < 0
        b2 = (k * x - F) / Aa                     # h = -F, h decreasing: sin(theta) > 0
        for b, s, sign in ((b1, 1, -1.0), (b2, -1, 1.0)):
            if not (-1.0 < b < 1.0):
                continue
            base = sign * math.acos(b)
            n = math.ceil((theta_now - base) / _TWO_PI)
            theta = base + _TWO_PI * n
            if theta <= theta_now:
                theta += _TWO_PI
            tc = (theta - phi) / w
            if tc <= t:
                tc = math.nextafter(t, math.inf)
            if tc < best:
                best, s_best = tc, s
        if not math.isfinite(best):
            return None, 0
        return best, s_best


def _coulomb_march(sy, t0, x, v, mode, t1, scl, events, segments, diss):
    """Advance from t0 to t1. mode: +1/-1 slipping, 0 stuck. Returns (x, v, mode, diss)."""
    xs, wref, tshort = scl
    t = t0
    last_restart = None
    while t < t1:
        if mode == 0:
            te, s_new = sy.stick_exit(t, x)
            tb = t1 if te is None or te >= t1 else te
            xc = x
            segments.append((t, tb, 0, lambda tt, xc=xc: np.vstack([np.full_like(tt, xc), np.zeros_like(tt)]), None))
            if tb == t1 and (te is None or te > t1):
                t, v = t1, 0.0
                break
            t, v, mode = te, 0.0, s_new
            events.append((te, "slide"))
            last_restart = t
            continue
        rhs = sy.rhs(mode)
        ev = (lambda tt, y, s=mode: s * y[1], -1,
              lambda tt, y, s=mode, f=rhs: s * f(tt, y)[1], xs * wref)
        sol, fired, te, ye = _solve(rhs, t, [x, v], t1, [ev], xs, wref, tshort)
        segments.append((t, te, mode, sol.sol, sol))
        if fired is None:
            diss += sy.F * abs(ye[0] - x)
            t, x, v = t1, float(ye[0]), float(ye[1])
            break
        xe = float(ye[0])
        diss += sy.F * abs(xe - x)
        new_mode, kind = sy.decide(te, xe, mode)
        if new_mode == mode and last_restart is not None and te - last_restart <= _GRACE * tshort:
            # re-detection of the event just handled (grazing): force progress
            sol2, _, t2, y2 = _solve(sy.rhs(mode), te, [xe, 0.0], min(t1, te + _GRACE * tshort), [],
                                     xs, wref, tshort)
            segments.append((te, t2, mode, sol2.sol, sol2))
            diss += sy.F * abs(y2[0] - xe)
            t, x, v = t2, float(y2[0]), float(y2[1])
            last_restart = None
            continue
        events.append((te, kind))
        t, x, v, mode = te, xe, 0.0, new_mode
        last_restart = t
    return x, v, mode, diss


def _make_event(fun, direction):
    fun.terminal = True
    fun.direction = direction
    return fun


def _coulomb_initial_mode(sy, x0, v0):
    if v0 > 0:
        return 1
    if v0 < 0:
        return -1
    return sy.decide(0.0, x0, 0)[0]


def coulomb_response(mass, stiffness, damping, slip_force, force_amplitude, base_amplitude,
                     omega, x0, v0, t_end, t_eval):
    """Time response of the Coulomb oscillator from (x0, v0) at t = 0 to t_end.

    Returns Result with t, x, v (at t_eval), events [(t, kind)], dissipated
    (F * integral |v| dt over [0, t_end]), final_mode (+1/-1 slipping, 0 stuck).
    """
    sy = _Coulomb(mass, stiffness, damping, slip_force, force_amplitude, base_amplitude, omega)
    t_end = float(t_end)
    if not (t_end >= 0):
        raise ValueError("t_end must be >= 0")
    t_eval = _time_points(t_eval, t_end)
    scl = _scales(sy.m, sy.k, sy.w, sy.P, sy.k, sy.Y, float(x0), float(v0))
    mode = _coulomb_initial_mode(sy, float(x0), float(v0))
    events, segments = [], []
    x, v, mode, diss = _coulomb_march(sy, 0.0, float(x0), float(v0), mode, t_end, scl,
                                      events, segments, 0.0)
    if not segments:
        segments.append((0.0, t_end, mode, lambda tt: np.vstack([np.full_like(tt, x0), np.full_like(tt, v0)]), None))
    y = _eval_segments([(s[0], s[1], s[3]) for s in segments], t_eval, 2)
    return Result(t=t_eval, x=y[0], v=y[1], events=events, dissipated=diss,
                  final_state=(x, v), final_mode=mode)


_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)


def _period_properties(sy, segments, t0, T):
    """Amplitude, first harmonic, stops over one period from its segments."""
    w = sy.w
    xmax = 0.0
    a1 = b1 = 0.0
    for ta, tb, mode, fun, sol in segments:
        if tb <= ta:
            continue
        xa, xb = fun(np.array([ta, tb]))[0]
        xmax = max(xmax, abs(xa), abs(xb))
        if mode == 0:
            a1 += xa * (math.sin(w * tb) - math.sin(w * ta)) / w
            b1 += xa * (math.cos(w * ta) - math.cos(w * tb)) / w
            continue
        # Gauss-Legendre on every solver step of the dense output (each a polynomial)
        ts = np.asarray(sol.sol.ts) if sol is not None else np.array([ta, tb])
        ts = ts[(ts >= ta) & (ts <= tb)]
        ts = np.unique(np.concatenate([[ta], ts, [tb]]))
        lo, hi = ts[:-1], ts[1:]
        half, mid = 0.5 * (hi - lo), 0.5 * (hi + lo)
        tq = (mid[:, None] + half[:, None] * _GL_X[None, :]).ravel()
        wq = (half[:, None] * _GL_W[None, :]).ravel()
        xq = fun(tq)[0]
        a1 += np.sum(wq * xq * np.cos(w * tq))
        b1 += np.sum(wq * xq * np.sin(w * tq))
        xmax = max(xmax, float(np.max(np.abs(xq))))        # dense check
    a1 *= 2.0 / T
    b1 *= 2.0 / T
    return xmax, a1, b1


_QUIET_PERIODS = 20


def _contraction(hist, tol):
    """Contraction factor of the period map from the differences still well above the
    integration noise (> 1e3 tol); None if there are too few."""
    clean = [d for d in hist if d > 1e3 * tol]
    if len(clean) < 3 or hist[-1] > 1e3 * tol:
        return None if len(clean) < 3 else min(1.0, (clean[-1] / clean[-3]) ** 0.5)
    k = min(len(clean), 11)
    return min(1.0, (clean[-1] / clean[-k]) ** (1.0 / (k - 1)))


def coulomb_steady_state(mass, stiffness, damping, slip_force, force_amplitude, base_amplitude,
                         omega, x0=0.0, v0=0.0, tol=1e-11, max_periods=2000):
    """Periodic steady state of the Coulomb oscillator by plain period-by-period marching.

    Converged when the state at t = nT repeats: d = max(|dx|, |dv|/w_ref)/scale <= tol,
    scale = max |x| over the period, and either the geometric estimate d q/(1-q)
    of the remaining distance to the fixed point is <= tol (q = contraction of the
    period map measured while d > 1e3 tol) or d has stayed <= tol for 20
    consecutive periods (slow contraction at the integration-noise floor, ~1e-12).

    Returns Result: amplitude (max |x| over the period), phase = atan2(b1, a1)
    (lag of the first harmonic of x behind cos wt), a1, b1, first_harmonic,
    stops_per_cycle (stick intervals starting in one period), permanently_stuck,
    periods (periods marched), converged, x0, v0, mode0 (state at the period
    start nT), t0 = nT, events (of that period, absolute times),
    dissipated_per_cycle, residual (last d), error_estimate (max(d, d q/(1-q))).
    """
    sy = _Coulomb(mass, stiffness, damping, slip_force, force_amplitude, base_amplitude, omega)
    if sy.w <= 0:
        raise ValueError("omega must be > 0 for a steady state")
    T = _TWO_PI / sy.w
    scl = _scales(sy.m, sy.k, sy.w, sy.P, sy.k, sy.Y, float(x0), float(v0))
    wref = scl[1]
    x, v = float(x0), float(v0)
    mode = _coulomb_initial_mode(sy, x, v)
    hist = []
    quiet = 0
    converged = False
    n = 0
    last = None
    while n < max_periods:
        t_a, t_b = n * T, (n + 1) * T
        events, segments = [], []
        x1, v1, mode1, diss = _coulomb_march(sy, t_a, x, v, mode, t_b, scl, events, segments, 0.0)
        xmax = max(abs(x), abs(x1), max((abs(s[3](np.array([s[0]]))[0][0]) for s in segments), default=0.0))
        scale = max(xmax, 1e-300)
        d = max(abs(x1 - x), abs(v1 - v) / wref) / scale
        n += 1
        hist.append(d)
        quiet = quiet + 1 if (d <= tol and mode1 == mode) else 0
        q = _contraction(hist, tol)
        est = d if q is None else (d * q / (1.0 - q) if q < 1.0 else math.inf)
        last = (t_a, x, v, mode, events, segments, diss, d, est)
        if mode1 == mode and (d == 0.0 or (d <= tol and (est <= tol or quiet >= _QUIET_PERIODS))):
            converged = True
            break
        x, v, mode = x1, v1, mode1
    t_a, xs0, vs0, mode0, events, segments, diss, d, est = last
    amp, a1, b1 = _period_properties(sy, segments, t_a, T)
    stops = sum(1 for _, kind in events if kind == "stick")
    stuck = all(s[2] == 0 for s in segments)
    return Result(amplitude=amp, phase=math.atan2(b1, a1), a1=a1, b1=b1,
                  first_harmonic=math.hypot(a1, b1), stops_per_cycle=stops,
                  permanently_stuck=stuck, periods=n, converged=converged,
                  x0=xs0, v0=vs0, mode0=mode0, t0=t_a, events=events,
                  dissipated_per_cycle=diss, residual=d, error_estimate=max(d, est))


# --------------------------------------------------------------------------- Jenkins / Iwan
def _iwan_core(m, k, c, kts, fss, P, Y, w, x0, v0, t_end, t_eval, w0):
    m = _check_positive("mass", m)
    k = _check_positive("stiffness", k, allow_zero=True)
    c = _check_positive("damping", c, allow_zero=True)
    w = _check_positive("omega", w, allow_zero=True)
    kts = np.asarray(kts, dtype=float)
    fss = np.asarray(fss, dtype=float)
    if kts.ndim != 1 or kts.size == 0 or kts.shape != fss.shape:
        raise ValueError("sliders must be a non-empty list of (kt, Fs)")
    if np.any(~np.isfinite(kts)) or np.any(kts <= 0) or np.any(fss < 0) or np.any(np.isnan(fss)):
        raise ValueError("slider stiffness must be > 0 and slip force >= 0")
    P, Y = float(P), float(Y)
    A = P + k * Y
    t_end = float(t_end)
    if not (t_end >= 0):
        raise ValueError("t_end must be >= 0")
    t_eval = _time_points(t_eval, t_end)
    x, v = float(x0), float(v0)
    nsl = kts.size
    anchor = np.zeros(nsl) if w0 is None else np.broadcast_to(np.asarray(w0, dtype=float), (nsl,)).copy()
    lim = fss / kts                                   # slider elastic reach
    # initial slider states (an over-stretched slider is clipped to its limit)
    mode = np.zeros(nsl, dtype=int)
    stretch = x - anchor
    over = np.abs(stretch) >= lim * (1 - 1e-14)
    anchor[over] = x - np.sign(stretch[over]) * lim[over]
    for i in np.nonzero(over)[0]:
        sgn = 1 if stretch[i] > 0 else -1
        if v * sgn > 0:
            mode[i] = sgn
    xs, wref, tshort = _scales(m, k + kts.sum(), w, P, k, Y, x, v)
    xs = max(xs, float(np.max(np.abs(anchor))) if nsl else 0.0)

    def forces(xx, md, an):
        st = md == 0
        return np.where(st, kts * (xx - an), md * fss)

    def make_rhs(md, an):
        st = md == 0
        kst, ast = kts[st], an[st]
        fsl = float(np.sum(md[~st] * fss[~st]))
        ksum = float(kst.sum())
        kw = float(np.dot(kst, ast))

        def f(t, y):
            T = ksum * y[0] - kw + fsl
            return [y[1], (A * math.cos(w * t) - k * y[0] - c * y[1] - T) / m]
        return f

    events, slider_events, segments = [], [], []
    diss = 0.0
    t = 0.0
    last_restart = None
    while t < t_end:
        st = mode == 0
        evs, tags = [], []
        if np.any(st):
            x_up = float(np.min(anchor[st] + lim[st]))      # first stuck slider to reach +Fs
            x_dn = float(np.max(anchor[st] - lim[st]))      # first stuck slider to reach -Fs
            evs.append((lambda tt, y, a=x_up: y[0] - a, 1, lambda tt, y: y[1], xs))
            tags.append("up")
            evs.append((lambda tt, y, a=x_dn: y[0] - a, -1, lambda tt, y: y[1], xs))
            tags.append("dn")
        md, an = mode.copy(), anchor.copy()
        rhs = make_rhs(md, an)
        s_dir = 0
        if np.any(~st):
            s_dir = int(mode[~st][0])
            evs.append((lambda tt, y, s=s_dir: s * y[1], -1,
                        lambda tt, y, s=s_dir, f=rhs: s * f(tt, y)[1], xs * wref))
            tags.append("v0")
        sol, fired, te, ye = _solve(rhs, t, [x, v], t_end, evs, xs, wref, tshort)
        segments.append((t, te, md, an, sol.sol))
        xe, ve = float(ye[0]), float(ye[1])
        diss += float(np.sum(fss[~st])) * abs(xe - x)
        if fired is None:
            t, x, v = t_end, xe, ve
            break
        tag = tags[fired]
        changed = False
        if tag == "v0":
            ve = 0.0
            a = rhs(te, [xe, 0.0])[1]
            if a * s_dir < 0:
                for i in np.nonzero(~st)[0]:
                    anchor[i] = xe - mode[i] * lim[i]
                    mode[i] = 0
                    slider_events.append((te, "stick", int(i)))
                events.append((te, "stick"))
                changed = True
            else:
                kind = "abnormal"
        else:
            sgn = 1 if tag == "up" else -1
            tol = 1e-13 * max(xs, abs(xe))
            idx_st = np.nonzero(st)[0]
            reach = sgn * (xe - anchor[idx_st]) - lim[idx_st]       # >= 0 at the limit
            first = idx_st[int(np.argmax(reach))]
            for i in idx_st:
                if i == first or sgn * (xe - anchor[i]) >= lim[i] - tol:
                    mode[i] = sgn
                    slider_events.append((te, "slide", int(i)))
                    changed = True
            if changed:
                events.append((te, "slide"))
                if ve * sgn < 0:           # cannot slip against the motion (only at v = 0)
                    ve = 0.0
            else:
                kind = "none"
        if not changed:
            if last_restart is not None and te - last_restart <= _GRACE * tshort:
                t2 = min(t_end, te + _GRACE * tshort)
                sol2, _, t2, y2 = _solve(make_rhs(mode, anchor), te, [xe, ve], t2, [], xs, wref, tshort)
                segments.append((te, t2, mode.copy(), anchor.copy(), sol2.sol))
                diss += float(np.sum(fss[mode != 0])) * abs(float(y2[0]) - xe)
                t, x, v = t2, float(y2[0]), float(y2[1])
                last_restart = None
                continue
            if kind == "abnormal":
                events.append((te, "abnormal"))
                for i in np.nonzero(~st)[0]:
                    slider_events.append((te, "abnormal", int(i)))
        t, x, v = te, xe, ve
        last_restart = t

    # evaluation at t_eval
    nt = t_eval.size
    xo, vo = np.empty(nt), np.empty(nt)
    wo = np.empty((nsl, nt))
    if nt:
        if not segments:
            segments.append((0.0, t_end, mode.copy(), anchor.copy(),
                             lambda tt: np.vstack([np.full_like(tt, x), np.full_like(tt, v)])))
        starts = np.array([s[0] for s in segments])
        idx = np.clip(np.searchsorted(starts, t_eval, side="right") - 1, 0, len(segments) - 1)
        for j in np.unique(idx):
            sel = idx == j
            _, _, md, an, fun = segments[j]
            y = fun(t_eval[sel])
            xo[sel], vo[sel] = y[0], y[1]
            slip = md != 0
            wo[:, sel] = np.where(slip[:, None], y[0][None, :] - (md * lim)[:, None], an[:, None])
    fo = kts[:, None] * (xo[None, :] - wo)
    return Result(t=t_eval, x=xo, v=vo, w=wo, slider_force=fo, force=fo.sum(axis=0),
                  events=events, slider_events=slider_events, dissipated=diss,
                  final_state=(x, v), final_modes=mode.copy(),
                  final_w=np.where(mode != 0, x - mode * lim, anchor))


def jenkins_response(mass, stiffness, damping, tangential_stiffness, slip_force, force_amplitude,
                     base_amplitude, omega, x0, v0, t_end, t_eval, w0=0.0):
    """Mass on spring k, dashpot c and one Jenkins element (kt in series with slider Fs).

    Returns Result: t, x, v, force (T = kt (x - w)), w (slider position), events
    [(t, kind)] with kinds 'stick', 'slide', 'abnormal', dissipated (Fs * total
    slider travel over [0, t_end]), final_mode.
    """
    r = _iwan_core(mass, stiffness, damping, [tangential_stiffness], [slip_force],
                   force_amplitude, base_amplitude, omega, x0, v0, t_end, t_eval, w0)
    r.w = r.w[0]
    r.force = r.slider_force[0]
    r.final_mode = int(r.final_modes[0])
    r.final_w = float(r.final_w[0])
    del r.slider_force, r.slider_events, r.final_modes
    return r


def iwan_response(mass, stiffness, damping, sliders, force_amplitude, base_amplitude, omega,
                  x0, v0, t_end, t_eval, w0=None):
    """Mass with N parallel Jenkins sliders, sliders = [(kt_i, Fs_i), ...].

    Returns Result: t, x, v, force (sum of slider forces), w (n_sliders, n_t),
    slider_force (n_sliders, n_t), events [(t, kind)] (one entry per
    transition time), slider_events [(t, kind, i)], dissipated, final_modes.
    """
    sl = np.asarray(sliders, dtype=float).reshape(-1, 2)
    return _iwan_core(mass, stiffness, damping, sl[:, 0], sl[:, 1], force_amplitude,
                      base_amplitude, omega, x0, v0, t_end, t_eval, w0)
