"""The Jenkins loop of :func:`.hysteresis.jenkins_loop`, compiled (numba): bracketing grid,
safeguarded Newton roots, closed-form piece integrals, the analytic Jacobian (the algorithm of
:mod:`.hysteresis`'s docstring), in plain loops without the overhead of some hundred small NumPy
calls per loop.

Harmonic balance evaluates one loop per slider per Newton iteration: ~70 us at 15 harmonics, all
of a system's Jenkins sliders in one call (:func:`jenkins_loops`), each by the path
:func:`jenkins_any` chooses (the exact loop, deep slip, the Coulomb limit). Besides the loops, the
peak search of a balance's harmonics (:func:`peak_magnitudes`), which refines extrema as the loops
refine their reversals. Compiled where the event search is (:data:`..jit.ENABLED`); in an FMU's
bundled copy, which never balances harmonics, the same functions run as plain Python.
"""
from __future__ import annotations

import math

import numpy as np

from ..jit import ENABLED, _jit, row_dot

__all__ = ["jenkins_loop_kernel", "jenkins_any", "jenkins_loops", "deep_slip_kernel", "coulomb_kernel",
           "reversal_roots", "peak_magnitudes", "ENABLED", "DEEP_SLIP", "UNRESOLVED_REACH"]

_EPS = 2.220446049250313e-16
#: a Jenkins loop whose slip reach ``F/k`` is at most this many times ``(2H + 1) eps sum |c|`` (the
#: rounding of ``u``) is Coulomb's (:func:`jenkins_any`): the kernel, which finds the stuck pieces
#: from ``u`` against ``u(theta_r) -+ 2 F/k``, fails from about ``(2H + 1) eps / 3`` (it held the spring
#: over the whole period)
UNRESOLVED_REACH = 4.0
#: the deep-slip form of a Jenkins loop (:func:`deep_slip_kernel`) is tried where ``F/k`` is at most
#: this fraction of ``sum_{h >= 1} |c_h|`` (its error and the kernel's cross near ``eps^0.4 = 5.6e-7``)
DEEP_SLIP = 1e-5


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


@_jit(inline=True)
def _grid_values(c, cos_table, sin_table):
    """``u`` and ``u'`` of the coefficient vector ``c`` on the grid of the tables (``(H, N)``
    values of ``cos/sin(h theta_j)``)."""
    hh = (c.size - 1) // 2
    ng = cos_table.shape[1]
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
    return u, du


@_jit(inline=True)
def _held_spring(c, k, lo, hi, t_lo, t_hi, w_ref, want_jac, coef, jac, phi):
    """A slider that never slips: a spring ``k (u - w)`` with ``w = w_ref`` clipped into its stuck
    band ``[lo, hi]`` (the band's edges at ``t_lo``, ``t_hi``). Fills ``coef`` and ``jac`` (not
    normalised) and returns ``w``; where ``w`` was clipped, ``phi`` holds the basis at the edge
    that holds it (``w`` moves with ``u`` there)."""
    n = c.size
    w = min(max(w_ref, lo), hi)
    for i in range(n):
        coef[i] = k * c[i]
    coef[0] -= k * w
    if want_jac:
        for i in range(n):
            jac[i, i] = k
        if w != w_ref:
            _phi(t_lo if w == lo else t_hi, (n - 1) // 2, phi)
            for i in range(n):
                jac[0, i] -= k * phi[i]
    return w


@_jit(inline=True)
def _add_stuck(coef, k, c, w, v, pm):
    """A stuck piece's force ``k (u - w)`` into ``coef`` (``v``, ``pm``: its :func:`_integrals`)."""
    for i in range(coef.size):
        coef[i] += k * row_dot(pm, i, c) - k * w * v[i]


@_jit(inline=True)
def _add_stuck_jacobian(jac, k, pm, v, dw):
    """... and its derivative by the coefficients of ``u``, ``w`` moving by ``dw`` (the basis at
    the event that started the piece)."""
    n = v.size
    for i in range(n):
        for j in range(n):
            jac[i, j] += k * (pm[i, j] - v[i] * dw[j])


@_jit(inline=True)
def _spans_start(w0, t, e):
    """Whether the piece ``[t, e]`` is the first that holds ``theta = 2 pi`` (the period's start:
    the slider's position there is ``w0``)."""
    return math.isnan(w0) and t <= 2 * math.pi <= e


@_jit(inline=True)
def _normalise(x):
    """The Fourier normalisation of the coefficients ``x``, in place: ``1/(2 pi)`` for the mean,
    ``1/pi`` for the others."""
    inv_pi = 1.0 / math.pi
    for i in range(x.size):
        x[i] *= 0.5 * inv_pi if i == 0 else inv_pi


@_jit(inline=True)
def _normalise_rows(m):
    """... of the rows of a matrix of coefficients (a derivative of ``x`` or an integral matrix)."""
    inv_pi = 1.0 / math.pi
    for i in range(m.shape[0]):
        sc = 0.5 * inv_pi if i == 0 else inv_pi
        for j in range(m.shape[1]):
            m[i, j] *= sc


@_jit(inline=True)
def _first_exit(g_up, g_dn, t, dtheta, ng):
    """Grid indices (``k`` for ``theta = k dtheta``, beyond ``t``, up to two periods) where the
    stuck band's upper and lower exit functions first go negative: ``(ku, kd)``, -1 for the one
    that does not before the other."""
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
    return ku, kd


@_jit(inline=True)
def _jenkins_stuck(c, k, reach, w, sig, t, t_end, t_rev, u, dtheta, want_jac, coef, jac, phi, v, pm, g_up, g_dn):
    """A stuck piece of the Jenkins loop from ``t``: its end (where ``u`` leaves ``w +- reach``, the
    exit the grid shows first; ``t_end`` if none) and the slip direction there (``sig`` if none);
    its force and derivatives added to ``coef``, ``jac`` (``w`` set by the reversal at ``t_rev``)."""
    ng = u.size
    hh = (c.size - 1) // 2
    for j in range(ng):
        g_up[j] = w + reach - u[j]
        g_dn[j] = u[j] - (w - reach)
    ku, kd = _first_exit(g_up, g_dn, t, dtheta, ng)
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
    _add_stuck(coef, k, c, w, v, pm)
    if want_jac:
        _phi(t_rev, hh, phi)
        _add_stuck_jacobian(jac, k, pm, v, phi)
    return b, new_sig


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
    u, du = _grid_values(c, cos_table, sin_table)
    coef = np.zeros(n)
    jac = np.zeros((n, n))
    phi = np.empty(n)
    # global extrema, refined on u' = 0 between the largest sample's neighbours
    t_max = _extremum(c, u, 1.0, dtheta, ng)
    t_min = _extremum(c, u, -1.0, dtheta, ng)
    u_max = _value(c, t_max, 0)[0]
    u_min = _value(c, t_min, 0)[0]
    if u_max - u_min <= 2 * reach:  # never slips
        w = _held_spring(c, k, u_max - reach, u_min + reach, t_max, t_min, w_ref, want_jac, coef, jac, phi)
        return coef, jac, w, False
    # from the maximum of u (in [0, 2 pi), _extremum): the slider has just slipped forward and sticks
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
            b, new_sig = _jenkins_stuck(c, k, reach, w, sig, t, t_end, t_rev, u, dtheta, want_jac, coef, jac, phi,
                                        v, pm, g_up, g_dn)
            if _spans_start(w0, t, b):
                w0 = w
            t = b
            stuck = False
            sig = new_sig
        else:  # slipping with u until u' changes sign
            x = _crossing(c, 1, 0.0, 1.0, sig, du, dtheta, ng, t)
            b = t_end if (x < 0 or x <= t) else min(x, t_end)
            _integrals(t, b, hh, v, pm, False)
            for i in range(n):
                coef[i] += sig * f * v[i]
            if _spans_start(w0, t, b):
                w0 = _value(c, 2 * math.pi, 0)[0] - sig * reach
            t = b
            stuck = True
            w = _value(c, b, 0)[0] - sig * reach
            t_rev = b
    if math.isnan(w0):
        w0 = w
    _normalise(coef)
    _normalise_rows(jac)
    return coef, jac, w0, True


@_jit
def reversal_roots(c, du, dtheta):
    """The sorted phases where ``u'`` changes sign (the reversals), ``du``: ``u'`` on the grid ``k
    dtheta`` (periodic: ``u'(2 pi)`` is ``du[0]``, the last bracket ends at ``2 pi`` exactly); each
    sign change refined by :func:`_root`, and every grid point where ``u'`` is exactly 0."""
    ng = du.size
    out = np.empty(2 * ng)
    m = 0
    for k in range(ng):
        s0 = 1 if du[k] > 0 else (-1 if du[k] < 0 else 0)
        d1 = du[(k + 1) % ng]
        s1 = 1 if d1 > 0 else (-1 if d1 < 0 else 0)
        if s0 * s1 < 0:
            out[m] = _root(c, 1, 0.0, k * dtheta, (k + 1) * dtheta if k + 1 < ng else 2 * math.pi)
            m += 1
    for k in range(ng):
        if du[k] == 0:
            out[m] = k * dtheta
            m += 1
    r = np.sort(out[:m])
    keep = 0
    for i in range(m):  # distinct values only
        if i == 0 or r[i] != r[keep - 1]:
            r[keep] = r[i]
            keep += 1
    return r[:keep]


@_jit(inline=True)
def _dphi(theta, hh, out):
    """The basis' derivative at ``theta``: ``0, -h sin h theta, h cos h theta``."""
    out[0] = 0.0
    for h in range(1, hh + 1):
        out[2 * h - 1] = -h * math.sin(h * theta)
        out[2 * h] = h * math.cos(h * theta)


@_jit
def coulomb_kernel(c, f, want_jac, roots, du0):
    """The rigid slider's loop ``F sgn(u')`` between the reversals ``roots`` (:func:`reversal_roots`;
    ``du0 = u'(0)`` gives the sign of a motion without any): ``(coef, jac)`` normalised, ``jac`` the
    reversal times' part, ``T`` jumping by ``-+2 F`` at a minimum (maximum) of ``u``."""
    n = c.size
    hh = (n - 1) // 2
    coef = np.zeros(n)
    jac = np.zeros((n, n))
    if roots.size == 0:
        coef[0] = f * math.copysign(1.0, du0) if du0 != 0 else 0.0
        _normalise(coef)
        return coef, jac
    v = np.empty(n)
    dummy = np.empty((1, 1))
    m = roots.size
    for i in range(m):
        a = roots[i]
        b = roots[i + 1] if i + 1 < m else roots[0] + 2 * math.pi
        sgn = math.copysign(1.0, _value(c, 0.5 * (a + b), 1)[0])
        _integrals(a, b, hh, v, dummy, False)
        for j in range(n):
            coef[j] += sgn * f * v[j]
    if want_jac:
        psi = np.empty(n)
        dphi = np.empty(n)
        for r in roots:
            dd = _value(c, r, 2)[0]
            if dd == 0.0:
                continue
            jump = -2 * f * math.copysign(1.0, dd)  # T(r-) - T(r+): -2F at a minimum of u, +2F at a maximum
            _phi(r, hh, psi)
            _dphi(r, hh, dphi)
            for i in range(n):
                for j in range(n):
                    jac[i, j] += jump * psi[i] * (-dphi[j] / dd)
    _normalise(coef)
    _normalise_rows(jac)
    return coef, jac


@_jit
def deep_slip_kernel(c, k, f, want_jac, unresolved, roots):
    """The Jenkins loop in deep slip (the expansion in ``sqrt(F/k)`` of :mod:`.hysteresis`'s
    docstring) from the reversals ``roots``: ``(ok, coef, jac, w0)``, ``ok`` false where the
    reversals are not all well apart (``u`` moves by less than ``8 F/k`` between two: the slider may
    stick through them), some second derivative vanishes, or (unless ``unresolved``: the kernel
    cannot resolve the loop) the kernel is the more accurate; the Jacobian is Coulomb's."""
    n = c.size
    hh = (n - 1) // 2
    reach = f / k
    m = roots.size
    if m < 2:
        return False, np.zeros(n), np.zeros((n, n)), 0.0
    u_r = np.empty(m)
    d2 = np.empty(m)  # the second and third derivatives at each reversal
    d3 = np.empty(m)
    for i in range(m):
        u_r[i] = _value(c, roots[i], 0)[0]
        d2[i], d3[i] = _value(c, roots[i], 2)
    d_min = math.inf
    gap = math.inf
    for i in range(m):
        gap = min(gap, abs(u_r[(i + 1) % m] - u_r[i]))
        d_min = min(d_min, abs(d2[i]))
    if gap <= 8 * reach or d_min == 0:
        return False, np.zeros(n), np.zeros((n, n)), 0.0
    h3 = 0.0
    size = abs(c[0])
    for h in range(1, hh + 1):
        h3 += h ** 3 * (abs(c[2 * h - 1]) + abs(c[2 * h]))
        size += abs(c[2 * h - 1]) + abs(c[2 * h])
    e = 4 * (reach / d_min) * (h3 / d_min)
    if not unresolved and e ** 1.5 > _EPS * (size / reach):
        return False, np.zeros(n), np.zeros((n, n)), 0.0
    coef, jac = coulomb_kernel(c, f, want_jac, roots, 0.0)
    corr = np.zeros(n)
    psi = np.empty(n)
    dphi = np.empty(n)
    for i in range(m):
        sigma = -math.copysign(1.0, d2[i])
        a = (sigma * (4.0 / 3.0) * math.sqrt(4 * reach / abs(d2[i]))
             + (2.0 / 3.0) * (reach / d2[i]) * (d3[i] / d2[i])) * f
        b = sigma * 2 * f * (reach / abs(d2[i]))
        _phi(roots[i], hh, psi)
        _dphi(roots[i], hh, dphi)
        for j in range(n):
            corr[j] += a * psi[j] + b * dphi[j]
    _normalise(corr)
    for j in range(n):
        coef[j] += corr[j]
    w0 = _value(c, 0.0, 0)[0] - math.copysign(reach, _value(c, 0.0, 1)[0])
    return True, coef, jac, w0


@_jit
def jenkins_any(c, k, f, w_ref, want_jac, cos_table, sin_table):
    """A Jenkins slider's loop by the path :func:`.hysteresis.jenkins_loop` chooses: deep slip
    (:func:`deep_slip_kernel`) where ``F/k`` is at most :data:`DEEP_SLIP` of ``sum_{h >= 1} |c_h|``
    and the expansion is the more accurate, Coulomb's loop (:func:`coulomb_kernel`) where ``F/k`` is
    below the rounding of ``u`` (:data:`UNRESOLVED_REACH`) and the slider slips, else
    :func:`jenkins_loop_kernel`. Returns ``(coef, jac, w0, slips)``."""
    n = c.size
    reach = f / k
    motion = 0.0
    for i in range(1, n):
        motion += abs(c[i])
    size = abs(c[0]) + motion
    if reach <= DEEP_SLIP * motion:
        unresolved = reach <= UNRESOLVED_REACH * n * _EPS * size
        u, du = _grid_values(c, cos_table, sin_table)
        roots = reversal_roots(c, du, 2 * math.pi / du.size)
        ok, coef, jac, w0 = deep_slip_kernel(c, k, f, want_jac, unresolved, roots)
        if ok:
            return coef, jac, w0, True
        if unresolved and np.max(u) - np.min(u) > 2 * reach:
            # the slip reach is below the rounding of u: the stuck pieces after the reversals (where
            # u moves by 2 F/k) cannot be resolved, and the loop is its limit F/k -> 0, Coulomb's F
            # sgn(u') (off by O(F sqrt(reach / |u|)), itself below the rounding of k u)
            coef, jac = coulomb_kernel(c, f, want_jac, roots, du[0])
            return coef, jac, _value(c, 0.0, 0)[0], True
    return jenkins_loop_kernel(c, k, f, w_ref, want_jac, cos_table, sin_table)


@_jit
def jenkins_loops(cs, k, f, w_ref, want_jac, cos_table, sin_table):
    """:func:`jenkins_any` of ``m`` sliders at once, ``cs`` their ``(m, 2H+1)`` displacement
    coefficients, ``k``, ``f``, ``w_ref`` ``(m,)``: ``(coef (m, 2H+1), jac (m, 2H+1, 2H+1), w0 (m,),
    slips (m,))`` (one call from harmonic balance per Newton residual instead of one per slider)."""
    m, n = cs.shape
    coef = np.empty((m, n))
    jac = np.empty((m, n, n))
    w0 = np.empty(m)
    slips = np.empty(m, dtype=np.bool_)
    for i in range(m):
        ci, ji, w0[i], slips[i] = jenkins_any(np.ascontiguousarray(cs[i]), k[i], f[i], w_ref[i], want_jac,
                                              cos_table, sin_table)
        coef[i] = ci
        jac[i] = ji
    return coef, jac, w0, slips

@_jit
def _first(x, y):
    """The earlier of two crossings (-1: none)."""
    if x < 0:
        return y
    if y < 0:
        return x
    return min(x, y)


@_jit(inline=True)
def _flank_grid(cs, cp, a, cos_table, sin_table):
    """``s``, ``p`` and the closed band's edges' slopes ``L' = s' + a p'``, ``U' = s' - a p'`` on the
    grid of the tables (one pass: as :func:`_grid_values` twice, without its second sweep)."""
    hh = (cs.size - 1) // 2
    ng = cos_table.shape[1]
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
    return s_g, p_g, dl_g, du_g


@_jit(inline=True)
def _derivative(c):
    """The coefficients of ``du/dtheta``: ``(a_h, b_h) -> h (b_h, -a_h)``."""
    d = np.zeros(c.size)
    for h in range(1, (c.size - 1) // 2 + 1):
        d[2 * h - 1] = h * c[2 * h]
        d[2 * h] = -h * c[2 * h - 1]
    return d


@_jit(inline=True)
def _band_extrema(cl, cu, s_g, p_g, a, b, dtheta):
    """``(theta, max L)`` and ``(theta, min U)`` of the closed band's edges ``L = s + a p - b``,
    ``U = s - a p + b``."""
    ng = s_g.size
    t_l = _extremum(cl, s_g + a * p_g, 1.0, dtheta, ng)
    t_u = _extremum(cu, s_g - a * p_g, -1.0, dtheta, ng)
    return t_l, _value(cl, t_l, 0)[0] - b, t_u, _value(cu, t_u, 0)[0] + b


@_jit(inline=True)
def _held_flank(cs, k, a, l_max, u_min, t_l, t_u, w_ref, want_jac, coef, jts, jtp, phi):
    """:func:`_held_spring` of a flank slider that never slips; where ``w`` is clipped, it is held
    by ``L`` (it moves with ``s + a p``) or by ``U`` (``s - a p``): its derivative by ``cp`` too."""
    w = _held_spring(cs, k, l_max, u_min, t_l, t_u, w_ref, want_jac, coef, jts, phi)
    if want_jac and w != w_ref:
        sa = a if w == l_max else -a
        for i in range(cs.size):
            jtp[0, i] -= k * sa * phi[i]
    return w


@_jit(inline=True)
def _band_edge(cs, cp, sig, a, gap, theta):
    """The closed contact's slip-band edge that a slider slipping in direction ``sig`` moves with:
    ``s - sig a (gap - p)`` at ``theta`` (``L`` for ``sig = 1``, ``U`` for -1)."""
    return _value(cs, theta, 0)[0] - sig * a * (gap - _value(cp, theta, 0)[0])


@_jit(inline=True)
def _lift_off(cp, p_g, gap, dtheta, ng, g):
    """The first lift-off on the grid: the root of ``p - gap`` where ``p`` rises through ``gap``
    (``g`` overwritten with ``p - gap`` on the grid)."""
    for j in range(ng):
        g[j] = p_g[j] - gap
    kk = 0
    for j in range(ng):
        if g[j] <= 0 and g[(j + 1) % ng] > 0:
            kk = j
            break
    return _root(cp, 0, gap, kk * dtheta, (kk + 1) * dtheta)


@_jit(inline=True)
def _flank_stuck(cs, cl, cu, k, a, b, w, t, t_end, s_g, p_g, dtheta, want_jac, coef, jts, jtp, dws, dwp, v, pm,
                 g_a, g_b):
    """A stuck piece of the flank loop from ``t``: its end (where an edge of the band ``[L, U]``
    reaches ``w``; ``t_end`` if none) and the state after it (1: ``L`` pushes forward, -1: ``U``
    backward); the spring's force and its derivatives (``w`` moving by ``dws dcs + dwp dcp``) added
    to ``coef``, ``jts``, ``jtp``."""
    ng = s_g.size
    n = cs.size
    for j in range(ng):
        g_a[j] = w + b - (s_g[j] + a * p_g[j])  # L reaches w
        g_b[j] = (s_g[j] - a * p_g[j]) + b - w  # U reaches w
    x_up = _crossing(cl, 0, w + b, -1.0, 1.0, g_a, dtheta, ng, t)
    x_dn = _crossing(cu, 0, w - b, 1.0, 1.0, g_b, dtheta, ng, t)
    x = _first(x_up if x_up > t else -1.0, x_dn if x_dn > t else -1.0)
    e = t_end if (x < 0 or x > t_end) else x
    new_state = 1 if (x >= 0 and x == x_up) else -1
    _integrals(t, e, (n - 1) // 2, v, pm, True)
    _add_stuck(coef, k, cs, w, v, pm)
    if want_jac:
        _add_stuck_jacobian(jts, k, pm, v, dws)
        for i in range(n):
            for j in range(n):
                jtp[i, j] -= k * v[i] * dwp[j]
    return e, new_state


@_jit(inline=True)
def _flank_open(cp, dcp, kn, cn, n0, omega, gap, t, t_end, p_g, dtheta, want_jac, rn, jnn, m_open, phi, v, pm, g_a):
    """An open piece of the flank loop from ``t``: its end (the closure, a root of ``p - gap``;
    ``t_end`` if none); the contact's closed-state spring, dashpot and preload, which are taken out
    while it is open, into ``rn``, the open indicator into ``m_open``, and the dashpot's jumps at
    the opening and closing into ``jnn``."""
    ng = p_g.size
    n = cp.size
    hh = (n - 1) // 2
    for j in range(ng):
        g_a[j] = p_g[j] - gap
    x = _crossing(cp, 0, gap, 1.0, 1.0, g_a, dtheta, ng, t)  # closure
    e = t_end if (x < 0 or x <= t or x > t_end) else x
    _integrals(t, e, hh, v, pm, True)
    for i in range(n):
        rn[i] += n0 * v[i] - kn * row_dot(pm, i, cp) - cn * omega * row_dot(pm, i, dcp)
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
    return e


@_jit(inline=True)
def _closure(cs, cp, a, t, dws, dwp):
    """The slider's position and state where the contact closes at ``t``: the band opens from zero
    width around ``w = s``; the slider sticks (``dws``, ``dwp``: how ``w`` moves with the
    coefficients) unless an edge outruns it (state 1 or -1)."""
    w = _value(cs, t, 0)[0]
    ds_c = _value(cs, t, 1)[0]
    dp_c = _value(cp, t, 1)[0]
    if ds_c + a * dp_c > 0:
        return w, 1
    if ds_c - a * dp_c < 0:
        return w, -1
    _phi(t, (cs.size - 1) // 2, dws)
    ratio = -ds_c / dp_c if dp_c != 0.0 else 0.0
    for i in range(cs.size):
        dwp[i] = ratio * dws[i]
    return w, 0


@_jit(inline=True)
def _flank_slip(cp, cl, cu, mu, kn, n0, gap, sig, t, t_end, dl_g, du_g, p_g, dtheta, want_jac, coef, jtp, v, pm,
                g_b):
    """A slipping piece of the flank loop from ``t`` (direction ``sig``, with the edge ``L`` or
    ``U``): its end (the edge's reversal or a lift-off; ``t_end`` if neither) and whether it ends
    by lifting off; the friction force ``sig mu N`` and its derivative added to ``coef``, ``jtp``."""
    ng = p_g.size
    n = cp.size
    for j in range(ng):
        g_b[j] = gap - p_g[j]
    x_rev = _crossing(cl if sig > 0 else cu, 1, 0.0, 1.0, sig, dl_g if sig > 0 else du_g, dtheta, ng, t)
    x_lift = _crossing(cp, 0, gap, -1.0, 1.0, g_b, dtheta, ng, t)
    x = _first(x_rev if x_rev > t else -1.0, x_lift if x_lift > t else -1.0)
    e = t_end if (x < 0 or x > t_end) else x
    lift = x >= 0 and x == x_lift and x_lift != x_rev
    _integrals(t, e, (n - 1) // 2, v, pm, True)
    for i in range(n):
        coef[i] += sig * mu * (n0 * v[i] - kn * row_dot(pm, i, cp))
    if want_jac:
        for i in range(n):
            for j in range(n):
                jtp[i, j] -= sig * mu * kn * pm[i, j]
    return e, lift


@_jit
def flank_loop_kernel(cs, cp, k, mu, kn, cn, n0, omega, w_ref, want_jac, cos_table, sin_table):
    """Steady loop of a Jenkins slider on a unilateral contact with a varying normal load, driven by
    the tangential displacement ``s`` (coefficients ``cs``) and the normal one ``p`` (``cp``): the
    algorithm of :func:`.hysteresis.flank_loop`. Returns ``(T, dT/dcs, dT/dcp, Rn, dRn/dcp,
    open_matrix, w0, slips)`` with the Fourier normalisation applied (``open_matrix[i, j]`` the
    normalised ``int_open psi_i phi_j``).

    Over 80 lines on purpose: each piece (stuck, slipping, open, the closure) is a compiled step;
    what stays is the workspace, the three starts (a lift-off, a slider that never slips, the
    maximum of ``L``) and the march that dispatches the pieces, which a further split would hand
    some thirty arrays and numbers per call."""
    n = cs.size
    hh = (n - 1) // 2
    ng = cos_table.shape[1]
    dtheta = 2 * math.pi / ng
    a = mu * kn / k  # the band's half-width r = a max(gap - p, 0)
    gap = n0 / kn
    b = a * gap
    cl = cs + a * cp  # the band's edges while closed: L = cl - b, U = cu + b
    cu = cs - a * cp
    s_g, p_g, dl_g, du_g = _flank_grid(cs, cp, a, cos_table, sin_table)
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
    dcp = _derivative(cp)  # the dashpot's p' = dp/dtheta
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
        t0 = _lift_off(cp, p_g, gap, dtheta, ng, g_a)
        state = 2
        w = _value(cs, t0, 0)[0]
    else:
        t_l, l_max, t_u, u_min = _band_extrema(cl, cu, s_g, p_g, a, b, dtheta)
        if l_max <= u_min:  # never slips: w stays in [max L, min U]
            w = _held_flank(cs, k, a, l_max, u_min, t_l, t_u, w_ref, want_jac, coef, jts, jtp, phi)
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
            e, new_state = _flank_stuck(cs, cl, cu, k, a, b, w, t, t_end, s_g, p_g, dtheta, want_jac, coef, jts, jtp,
                                        dws, dwp, v, pm, g_a, g_b)
            if _spans_start(w0, t, e):
                w0 = w
            t = e
            state = new_state
        elif state == 2:
            e = _flank_open(cp, dcp, kn, cn, n0, omega, gap, t, t_end, p_g, dtheta, want_jac, rn, jnn, m_open, phi,
                            v, pm, g_a)
            if _spans_start(w0, t, e):
                w0 = _value(cs, 2 * math.pi, 0)[0]
            t = e
            if t < t_end:
                w, state = _closure(cs, cp, a, t, dws, dwp)
        else:
            sig = float(state)
            e, lift = _flank_slip(cp, cl, cu, mu, kn, n0, gap, sig, t, t_end, dl_g, du_g, p_g, dtheta, want_jac, coef,
                                  jtp, v, pm, g_b)
            if _spans_start(w0, t, e):
                w0 = _band_edge(cs, cp, sig, a, gap, 2 * math.pi)
            t = e
            if t < t_end:
                if lift:
                    state = 2
                else:  # reversal: the slider sticks where the edge turned
                    w = _band_edge(cs, cp, sig, a, gap, t)
                    _phi(t, hh, dws)
                    for i in range(n):
                        dwp[i] = sig * a * dws[i]
                    state = 0
    if math.isnan(w0):
        w0 = w
    _normalise(coef)
    _normalise(rn)
    for m in (jts, jtp, jnn, m_open):
        _normalise_rows(m)
    return coef, jts, jtp, rn, jnn, m_open, w0, True


@_jit
def peak_magnitudes(c, n_grid):
    """``max |u|`` over the period of each row of ``c`` (``(m, 2H+1)`` coefficients): the largest of
    ``n_grid`` equispaced samples, refined on ``u' = 0`` between its neighbours (:func:`_root`, to
    rounding) where ``u'`` brackets the extremum there; NaN for a row with a non-finite coefficient
    (the peaks of a balance, :func:`.hbm.harmonic_balance`)."""
    m, n = c.shape
    hh = (n - 1) // 2
    step = 2 * math.pi / n_grid
    cos_t = np.empty((hh, n_grid))
    sin_t = np.empty((hh, n_grid))
    for j in range(n_grid):
        for h in range(1, hh + 1):
            cos_t[h - 1, j] = math.cos(h * j * step)
            sin_t[h - 1, j] = math.sin(h * j * step)
    out = np.empty(m)
    for i in range(m):
        ci = np.ascontiguousarray(c[i])
        if not np.all(np.isfinite(ci)):
            out[i] = math.nan
            continue
        best = -1.0
        kk = 0
        xk = 0.0
        for j in range(n_grid):
            x = ci[0]
            for h in range(1, hh + 1):
                x += ci[2 * h - 1] * cos_t[h - 1, j] + ci[2 * h] * sin_t[h - 1, j]
            if abs(x) > best:
                best, kk, xk = abs(x), j, x
        lo = (kk - 1) * step
        hi = (kk + 1) * step
        sgn = 1.0 if xk >= 0 else -1.0
        if sgn * _value(ci, lo, 1)[0] >= 0 and sgn * _value(ci, hi, 1)[0] <= 0:
            best = max(best, abs(_value(ci, _root(ci, 1, 0.0, lo, hi), 0)[0]))
        out[i] = best
    return out
