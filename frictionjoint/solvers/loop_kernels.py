"""The Jenkins loop of :func:`.hysteresis.jenkins_loop`, compiled (numba): bracketing grid,
safeguarded Newton roots, closed-form piece integrals, the analytic Jacobian (the algorithm of
:mod:`.hysteresis`'s docstring), in plain loops without the overhead of some hundred small NumPy
calls per loop.

Harmonic balance evaluates one loop per slider per Newton iteration: ~70 us at 15 harmonics.
Compiled where the event search is (:data:`.search.ENABLED`); in an FMU's bundled copy, which
never balances harmonics, the same functions run as plain Python.
"""
from __future__ import annotations

import math

import numpy as np

from .search import ENABLED, _jit

__all__ = ["jenkins_loop_kernel", "ENABLED"]

_EPS = 2.220446049250313e-16


@_jit
def _value(c, theta, derivative):
    """``u^(n)(theta)`` and ``u^(n+1)(theta)`` of the coefficient vector ``c``."""
    hh = (c.size - 1) // 2
    a = c[0] if derivative == 0 else 0.0
    b = 0.0
    for h in range(1, hh + 1):
        ch, sh = math.cos(h * theta), math.sin(h * theta)
        ca, sb = c[2 * h - 1], c[2 * h]
        # d^n/dtheta^n (ca cos + sb sin) = h^n (ca cos(. + n pi/2) + sb sin(. + n pi/2))
        hn = float(h) ** derivative
        hn1 = hn * h
        r = derivative % 4
        if r == 0:
            x, y = ca * ch + sb * sh, -ca * sh + sb * ch
        elif r == 1:
            x, y = -ca * sh + sb * ch, -ca * ch - sb * sh
        elif r == 2:
            x, y = -ca * ch - sb * sh, ca * sh - sb * ch
        else:
            x, y = ca * sh - sb * ch, ca * ch + sb * sh
        a += hn * x
        b += hn1 * y
    return a, b


@_jit
def _root(c, derivative, level, a, b):
    """Root of ``u^(n) - level`` in ``[a, b]`` (a sign change): Newton's method safeguarded by
    bisection, to rounding."""
    fa = _value(c, a, derivative)[0] - level
    fb = _value(c, b, derivative)[0] - level
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if fa * fb > 0:
        return a if abs(fa) < abs(fb) else b
    x = 0.5 * (a + b)
    tol = 4 * _EPS * max(1.0, abs(b))
    for _ in range(100):
        f, df = _value(c, x, derivative)
        f -= level
        if f == 0.0:
            return x
        if (f < 0) == (fa < 0):
            a = x
            fa = f
        else:
            b = x
        xn = x - f / df if df != 0.0 else math.inf
        if not (a < xn < b):
            xn = 0.5 * (a + b)
        if abs(xn - x) <= tol or b - a <= tol:
            return xn
        x = xn
    return x


@_jit
def _crossing(c, derivative, level, orient, sign, vals, dtheta, n, start):
    """First ``theta > start`` where ``g = orient (u^(n) - level)`` changes sign from ``sign`` to
    ``-sign`` (``vals``: ``g`` on the grid ``k dtheta``, ``k < n``, repeated per period); -1 if none
    within two periods. A function that starts at zero (a transition at ``start``) is searched from
    the first point after ``start`` where it has the sign ``sign``; if there is none before the
    grid's first crossing, the transition is at ``start`` itself."""
    k0 = int(math.floor(start / dtheta)) + 1
    while k0 * dtheta <= start:
        k0 += 1
    for k in range(k0, 2 * n + 1):
        if sign * vals[k % n] < 0:
            if k > k0:
                return _root(c, derivative, level, (k - 1) * dtheta, k * dtheta)
            tk = k * dtheta
            prev = start
            for j in range(1, 33):
                p = start + (tk - start) * j / 32.0
                if sign * orient * (_value(c, p, derivative)[0] - level) < 0:
                    if j > 1:
                        return _root(c, derivative, level, prev, p)
                    if sign * orient * (_value(c, start, derivative)[0] - level) > 0:
                        return _root(c, derivative, level, start, p)
                    return start
                prev = p
            return _root(c, derivative, level, prev, tk)
    return -1.0


@_jit
def _integrals(a, b, hh, v, pm, want_p):
    """``v[k] = int_a^b psi_k`` and (``want_p``) ``pm[k, j] = int_a^b psi_k phi_j`` in closed form."""
    n2 = 2 * hh + 1
    ci = np.empty(n2)
    si = np.empty(n2)
    ci[0] = b - a
    si[0] = 0.0
    for p in range(1, n2):
        ci[p] = (math.sin(p * b) - math.sin(p * a)) / p
        si[p] = -(math.cos(p * b) - math.cos(p * a)) / p
    v[0] = b - a
    for h in range(1, hh + 1):
        v[2 * h - 1] = ci[h]
        v[2 * h] = si[h]
    if not want_p:
        return
    for k in range(n2):
        km = 0 if (k == 0 or k % 2 == 1) else 1
        m = (k + 1) // 2
        for j in range(n2):
            kq = 0 if (j == 0 or j % 2 == 1) else 1
            q = (j + 1) // 2
            d = abs(m - q)
            s = m + q
            sg = 1.0 if m > q else (-1.0 if m < q else 0.0)
            if km == 0 and kq == 0:
                pm[k, j] = 0.5 * (ci[d] + ci[s])
            elif km == 1 and kq == 1:
                pm[k, j] = 0.5 * (ci[d] - ci[s])
            elif km == 1:  # sin m cos q
                pm[k, j] = 0.5 * (si[s] + sg * si[d])
            else:  # cos m sin q
                pm[k, j] = 0.5 * (si[s] - sg * si[d])


@_jit
def _phi(theta, hh, out):
    out[0] = 1.0
    for h in range(1, hh + 1):
        out[2 * h - 1] = math.cos(h * theta)
        out[2 * h] = math.sin(h * theta)


@_jit
def jenkins_loop_kernel(c, k, f, w_ref, want_jac, cos_table, sin_table):
    """The loop of :func:`.hysteresis.jenkins_loop`; ``cos_table, sin_table``: ``(H, N)`` values of
    ``cos/sin(h theta_j)`` on the grid ``theta_j = 2 pi j / N``. Returns ``(coef, jac, w0,
    slips)`` with the Fourier normalisation applied."""
    n = c.size
    hh = (n - 1) // 2
    ng = cos_table.shape[1]
    dtheta = 2 * math.pi / ng
    reach = f / k
    u = np.empty(ng)
    du = np.empty(ng)
    for j in range(ng):
        s0 = c[0]
        s1 = 0.0
        for h in range(1, hh + 1):
            ca, sb = c[2 * h - 1], c[2 * h]
            s0 += ca * cos_table[h - 1, j] + sb * sin_table[h - 1, j]
            s1 += h * (-ca * sin_table[h - 1, j] + sb * cos_table[h - 1, j])
        u[j] = s0
        du[j] = s1
    coef = np.zeros(n)
    jac = np.zeros((n, n))
    phi = np.empty(n)
    # global extrema, refined on u' = 0 between the largest sample's neighbours
    ext = np.empty(2)
    for e in range(2):
        sgn = 1.0 if e == 0 else -1.0
        kk = 0
        for j in range(ng):
            if sgn * u[j] > sgn * u[kk]:
                kk = j
        lo = (kk - 1) * dtheta
        hi = (kk + 1) * dtheta
        dlo = _value(c, lo, 1)[0]
        dhi = _value(c, hi, 1)[0]
        if sgn * dlo >= 0 and sgn * dhi <= 0:
            ext[e] = _root(c, 1, 0.0, lo, hi)
        else:
            ext[e] = kk * dtheta
    t_max, t_min = ext[0], ext[1]
    u_max = _value(c, t_max, 0)[0]
    u_min = _value(c, t_min, 0)[0]
    if u_max - u_min <= 2 * reach:  # never slips
        lo_w, hi_w = u_max - reach, u_min + reach
        w = min(max(w_ref, lo_w), hi_w)
        for i in range(n):
            coef[i] = k * c[i]
        coef[0] -= k * w
        if want_jac:
            for i in range(n):
                jac[i, i] = k
            if w != w_ref:
                _phi(t_max if w == lo_w else t_min, hh, phi)
                for i in range(n):
                    jac[0, i] -= k * phi[i]
        return coef, jac, w, False
    if t_max < 0:
        t_max += 2 * math.pi
    t0 = t_max
    t_end = t0 + 2 * math.pi
    t = t0
    sig = 1.0
    w = u_max - reach
    t_rev = t0
    stuck = True
    w0 = math.nan
    v = np.empty(n)
    pm = np.empty((n, n))
    g_up = np.empty(ng)
    g_dn = np.empty(ng)
    while t < t_end:
        if stuck:
            for j in range(ng):
                g_up[j] = w + reach - u[j]
                g_dn[j] = u[j] - (w - reach)
            # the exit the grid shows first
            k0 = int(math.floor(t / dtheta)) + 1
            while k0 * dtheta <= t:
                k0 += 1
            ku = -1
            kd = -1
            for kk in range(k0, 2 * ng + 1):
                if ku < 0 and g_up[kk % ng] < 0:
                    ku = kk
                if kd < 0 and g_dn[kk % ng] < 0:
                    kd = kk
                if ku >= 0 or kd >= 0:
                    break
            b = t_end
            new_sig = sig
            if ku >= 0 and (kd < 0 or ku <= kd):
                x = _crossing(c, 0, w + reach, -1.0, 1.0, g_up, dtheta, ng, t)
                if x > t and x < b:
                    b = x
                    new_sig = 1.0
            if kd >= 0 and (ku < 0 or kd <= ku):
                x = _crossing(c, 0, w - reach, 1.0, 1.0, g_dn, dtheta, ng, t)
                if x > t and x < b:
                    b = x
                    new_sig = -1.0
            _integrals(t, b, hh, v, pm, True)
            for i in range(n):
                s = 0.0
                for j in range(n):
                    s += pm[i, j] * c[j]
                coef[i] += k * s - k * w * v[i]
            if want_jac:
                _phi(t_rev, hh, phi)
                for i in range(n):
                    for j in range(n):
                        jac[i, j] += k * (pm[i, j] - v[i] * phi[j])
            if math.isnan(w0) and t <= 2 * math.pi <= b:
                w0 = w
            t = b
            stuck = False
            sig = new_sig
        else:
            x = _crossing(c, 1, 0.0, 1.0, sig, du, dtheta, ng, t)
            b = t_end if (x < 0 or x <= t) else min(x, t_end)
            _integrals(t, b, hh, v, pm, False)
            for i in range(n):
                coef[i] += sig * f * v[i]
            if math.isnan(w0) and t <= 2 * math.pi <= b:
                w0 = _value(c, 2 * math.pi, 0)[0] - sig * reach
            t = b
            stuck = True
            w = _value(c, b, 0)[0] - sig * reach
            t_rev = b
    if math.isnan(w0):
        w0 = w
    inv_pi = 1.0 / math.pi
    for i in range(n):
        sc = 0.5 * inv_pi if i == 0 else inv_pi
        coef[i] *= sc
        for j in range(n):
            jac[i, j] *= sc
    return coef, jac, w0, True
