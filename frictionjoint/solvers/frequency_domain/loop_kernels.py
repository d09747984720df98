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

from ..jit import ENABLED, _jit

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
def _extremum(c, vals, sgn, dtheta, ng):
    """Phase of the global maximum (``sgn = 1``) or minimum (``-1``) of ``u`` (``vals`` its grid
    values): the extreme sample, refined on ``u' = 0`` between its neighbours."""
    kk = 0
    for j in range(ng):
        if sgn * vals[j] > sgn * vals[kk]:
            kk = j
    lo = (kk - 1) * dtheta
    hi = (kk + 1) * dtheta
    dlo = _value(c, lo, 1)[0]
    dhi = _value(c, hi, 1)[0]
    if sgn * dlo >= 0 and sgn * dhi <= 0:
        t = _root(c, 1, 0.0, lo, hi)
    else:
        t = kk * dtheta
    if t < 0:
        t += 2 * math.pi
    return t


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
    t_max = _extremum(c, u, 1.0, dtheta, ng)
    t_min = _extremum(c, u, -1.0, dtheta, ng)
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
    t0 = t_max  # in [0, 2 pi) (_extremum)
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


@_jit
def _first(x, y):
    """The earlier of two crossings (-1: none)."""
    if x < 0:
        return y
    if y < 0:
        return x
    return min(x, y)


@_jit
def flank_loop_kernel(cs, cp, k, mu, kn, cn, n0, omega, w_ref, want_jac, cos_table, sin_table):
    """Steady loop of a Jenkins slider on a unilateral contact with a varying normal load, driven by
    the tangential displacement ``s`` (coefficients ``cs``) and the normal one ``p`` (``cp``): the
    algorithm of :func:`.hysteresis.flank_loop`. Returns ``(T, dT/dcs, dT/dcp, Rn, dRn/dcp,
    open_matrix, w0, slips)`` with the Fourier normalisation applied (``open_matrix[i, j]`` the
    normalised ``int_open psi_i phi_j``)."""
    n = cs.size
    hh = (n - 1) // 2
    ng = cos_table.shape[1]
    dtheta = 2 * math.pi / ng
    a = mu * kn / k  # the band's half-width r = a max(gap - p, 0)
    gap = n0 / kn
    b = a * gap
    cl = cs + a * cp  # the band's edges while closed: L = cl - b, U = cu + b
    cu = cs - a * cp
    s_g = np.empty(ng)
    p_g = np.empty(ng)
    dl_g = np.empty(ng)
    du_g = np.empty(ng)
    for j in range(ng):
        s0 = cs[0]
        p0 = cp[0]
        ds = 0.0
        dp = 0.0
        for h in range(1, hh + 1):
            ct, st = cos_table[h - 1, j], sin_table[h - 1, j]
            s0 += cs[2 * h - 1] * ct + cs[2 * h] * st
            p0 += cp[2 * h - 1] * ct + cp[2 * h] * st
            ds += h * (-cs[2 * h - 1] * st + cs[2 * h] * ct)
            dp += h * (-cp[2 * h - 1] * st + cp[2 * h] * ct)
        s_g[j] = s0
        p_g[j] = p0
        dl_g[j] = ds + a * dp
        du_g[j] = ds - a * dp
    coef = np.zeros(n)
    jts = np.zeros((n, n))
    jtp = np.zeros((n, n))
    rn = np.zeros(n)
    jnn = np.zeros((n, n))
    m_open = np.zeros((n, n))
    phi = np.empty(n)
    v = np.empty(n)
    pm = np.empty((n, n))
    dws = np.zeros(n)  # d w / d cs, d w / d cp of a stuck piece
    dwp = np.zeros(n)
    # dcp: coefficients of p' = dp/dtheta (the dashpot's)
    dcp = np.zeros(n)
    for h in range(1, hh + 1):
        dcp[2 * h - 1] = h * cp[2 * h]
        dcp[2 * h] = -h * cp[2 * h - 1]
    opens = False
    for j in range(ng):
        if p_g[j] > gap:
            opens = True
            break
    g_a = np.empty(ng)
    g_b = np.empty(ng)
    # state: 0 stuck, 1 slipping forward (w = L), -1 backward (w = U), 2 open (w = s)
    if opens:
        # start at a lift-off (p rising through gap): the slider has no memory there (w = s)
        for j in range(ng):
            g_a[j] = p_g[j] - gap
        kk = 0
        for j in range(ng):
            if g_a[j] <= 0 and g_a[(j + 1) % ng] > 0:
                kk = j
                break
        t0 = _root(cp, 0, gap, kk * dtheta, (kk + 1) * dtheta)
        state = 2
        w = _value(cs, t0, 0)[0]
    else:
        cl_g = np.empty(ng)
        cu_g = np.empty(ng)
        for j in range(ng):
            cl_g[j] = s_g[j] + a * p_g[j]
            cu_g[j] = s_g[j] - a * p_g[j]
        t_l = _extremum(cl, cl_g, 1.0, dtheta, ng)
        t_u = _extremum(cu, cu_g, -1.0, dtheta, ng)
        l_max = _value(cl, t_l, 0)[0] - b
        u_min = _value(cu, t_u, 0)[0] + b
        if l_max <= u_min:  # never slips: w stays in [max L, min U]
            w = min(max(w_ref, l_max), u_min)
            for i in range(n):
                coef[i] = k * cs[i]
            coef[0] -= k * w
            if want_jac:
                for i in range(n):
                    jts[i, i] = k
                if w != w_ref:
                    at_l = w == l_max
                    _phi(t_l if at_l else t_u, hh, phi)
                    for i in range(n):
                        jts[0, i] -= k * phi[i]
                        jtp[0, i] -= k * (a if at_l else -a) * phi[i]
            return coef, jts, jtp, rn, jnn, m_open, w, False
        # start at the maximum of L: the slider has just slipped forward and sticks (Masing)
        t0 = t_l
        state = 0
        w = l_max
        _phi(t0, hh, dws)
        for i in range(n):
            dwp[i] = a * dws[i]
    t_end = t0 + 2 * math.pi
    t = t0
    w0 = math.nan
    pieces = 0
    while t < t_end:
        pieces += 1
        if pieces > 8 * ng:  # more pieces than the grid can bracket: no loop (never a hang)
            for i in range(n):
                coef[i] = math.nan
                rn[i] = math.nan
            return coef, jts, jtp, rn, jnn, m_open, math.nan, True
        if state == 0:
            for j in range(ng):
                g_a[j] = w + b - (s_g[j] + a * p_g[j])  # L reaches w
                g_b[j] = (s_g[j] - a * p_g[j]) + b - w  # U reaches w
            x_up = _crossing(cl, 0, w + b, -1.0, 1.0, g_a, dtheta, ng, t)
            x_dn = _crossing(cu, 0, w - b, 1.0, 1.0, g_b, dtheta, ng, t)
            x = _first(x_up if x_up > t else -1.0, x_dn if x_dn > t else -1.0)
            e = t_end if (x < 0 or x > t_end) else x
            new_state = 1 if (x >= 0 and x == x_up) else -1
            _integrals(t, e, hh, v, pm, True)
            for i in range(n):
                acc = 0.0
                for j in range(n):
                    acc += pm[i, j] * cs[j]
                coef[i] += k * acc - k * w * v[i]
            if want_jac:
                for i in range(n):
                    for j in range(n):
                        jts[i, j] += k * (pm[i, j] - v[i] * dws[j])
                        jtp[i, j] -= k * v[i] * dwp[j]
            if math.isnan(w0) and t <= 2 * math.pi <= e:
                w0 = w
            t = e
            state = new_state
        elif state == 2:
            for j in range(ng):
                g_a[j] = p_g[j] - gap
            x = _crossing(cp, 0, gap, 1.0, 1.0, g_a, dtheta, ng, t)  # closure
            e = t_end if (x < 0 or x <= t or x > t_end) else x
            _integrals(t, e, hh, v, pm, True)
            # the contact's closed-state spring, dashpot and preload are taken out while it is open
            for i in range(n):
                acc = 0.0
                accd = 0.0
                for j in range(n):
                    acc += pm[i, j] * cp[j]
                    accd += pm[i, j] * dcp[j]
                rn[i] += n0 * v[i] - kn * acc - cn * omega * accd
            if want_jac:
                for i in range(n):
                    for j in range(n):
                        m_open[i, j] += pm[i, j]
                # the dashpot's force jumps where the contact opens and closes: d(theta)/dcp =
                # -phi/p', the jump -cn omega p': the boundary terms cn omega psi phi^T
                _phi(t, hh, phi)
                for i in range(n):
                    for j in range(n):
                        jnn[i, j] -= cn * omega * phi[i] * phi[j]
                _phi(e, hh, phi)
                for i in range(n):
                    for j in range(n):
                        jnn[i, j] += cn * omega * phi[i] * phi[j]
            if math.isnan(w0) and t <= 2 * math.pi <= e:
                w0 = _value(cs, 2 * math.pi, 0)[0]
            t = e
            if t < t_end:
                # closure: the band opens from zero width around w = s; the slider sticks unless
                # an edge outruns it
                w = _value(cs, t, 0)[0]
                ds_c = _value(cs, t, 1)[0]
                dp_c = _value(cp, t, 1)[0]
                if ds_c + a * dp_c > 0:
                    state = 1
                elif ds_c - a * dp_c < 0:
                    state = -1
                else:
                    state = 0
                    _phi(t, hh, dws)
                    ratio = -ds_c / dp_c if dp_c != 0.0 else 0.0
                    for i in range(n):
                        dwp[i] = ratio * dws[i]
        else:
            sig = float(state)
            for j in range(ng):
                g_a[j] = dl_g[j] if state == 1 else du_g[j]
                g_b[j] = gap - p_g[j]
            x_rev = _crossing(cl if state == 1 else cu, 1, 0.0, 1.0, sig, g_a, dtheta, ng, t)
            x_lift = _crossing(cp, 0, gap, -1.0, 1.0, g_b, dtheta, ng, t)
            x = _first(x_rev if x_rev > t else -1.0, x_lift if x_lift > t else -1.0)
            e = t_end if (x < 0 or x > t_end) else x
            lift = x >= 0 and x == x_lift and x_lift != x_rev
            _integrals(t, e, hh, v, pm, True)
            for i in range(n):
                acc = 0.0
                for j in range(n):
                    acc += pm[i, j] * cp[j]
                coef[i] += sig * mu * (n0 * v[i] - kn * acc)
            if want_jac:
                for i in range(n):
                    for j in range(n):
                        jtp[i, j] -= sig * mu * kn * pm[i, j]
            if math.isnan(w0) and t <= 2 * math.pi <= e:
                w0 = _value(cs, 2 * math.pi, 0)[0] - sig * a * (gap - _value(cp, 2 * math.pi, 0)[0])
            t = e
            if t < t_end:
                if lift:
                    state = 2
                else:  # reversal: the slider sticks where the edge turned
                    w = _value(cs, t, 0)[0] - sig * a * (gap - _value(cp, t, 0)[0])
                    _phi(t, hh, dws)
                    for i in range(n):
                        dwp[i] = sig * a * dws[i]
                    state = 0
    if math.isnan(w0):
        w0 = w
    inv_pi = 1.0 / math.pi
    for i in range(n):
        sc = 0.5 * inv_pi if i == 0 else inv_pi
        coef[i] *= sc
        rn[i] *= sc
        for j in range(n):
            jts[i, j] *= sc
            jtp[i, j] *= sc
            jnn[i, j] *= sc
            m_open[i, j] *= sc
    return coef, jts, jtp, rn, jnn, m_open, w0, True
