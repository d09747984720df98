"""Event search of one closed-form piece: compiled (numba) for modal pieces, NumPy for the others.

The event functions of a piece in modal form are exp-polynomials,

    g_r(tau) = Re(sum_i pa_ri e^{lam_i tau}) + k0_r + Re(kp_r e^{i w tau} + km_r e^{-i w tau})
               + cc_r cos(w (t0 + tau)) + cs_r sin(w (t0 + tau)),

and the first ``tau`` in ``(0, horizon]`` at which one of them leaves its zero band is the next
event. Both paths do the same: the closed-form bound that skips a piece no function can reach zero
on, sampling with derivatives on a grid finer than the fastest mode (16 points per period),
crossings and tangential dips, and the root by Brent's method. The compiled path also steps over
longer stretches where a Taylor bound proves every function stays above its band (``g + g' s -
M s^2/2``, ``M`` a bound of ``|g''|`` over the piece, :func:`_safe_step`): the fast modes of a
multi-DOF structure set the grid, yet carry little of the motion, so far from an event a step of
many grid points is safe. :func:`first_event` does it in one
compiled call: the search is a few hundred scalar evaluations of a sum over the modes, each of which
costs a NumPy call (microseconds) in Python and nanoseconds here. :func:`numpy_first_event` serves
the pieces without a plain modal form (defective or near-resonant configurations) and runs where
the compiled search is off.

numba is the tool: the kernel is plain loops over small complex arrays, compiled once per
installation (``cache=True``: with the marcher's other kernels, :mod:`.consistency` and
:mod:`.piece_kernels`, about 20 s the first time, then loaded from ``__pycache__`` in about 1 s)
and called from the marcher with arrays it already holds. Without numba, and in the copy of
the library bundled into an FMU (:data:`ENABLED` is False there: a fresh compile at every
extraction of an FMU would dominate its start-up), the marcher runs the NumPy search.
"""
from __future__ import annotations

import cmath
import math

import numpy as np
import scipy.optimize

from ..jit import ENABLED, _jit

__all__ = ["first_event", "numpy_first_event", "RTOL", "ENABLED", "CHUNK", "MAX_SAMPLES", "MAX_EXPM_SAMPLES",
           "GAVE_UP"]

#: relative tolerance of the root (as the Python path's brentq)
RTOL = 4 * np.finfo(float).eps
#: iterations of Brent's method at most
_MAXITER = 100
#: samples per chunk of the NumPy search
CHUNK = 48
#: samples of one piece's search at most (both paths), per excitation period of its horizon in
#: the marcher's budget (plus one period's worth): a piece whose search would need more (a mode
#: 1e6 times faster than the excitation that the Taylor bound cannot step over, e.g. a joint or
#: contact stiffness 1e12 times the structure's) ends the search with :data:`GAVE_UP` instead of
#: running for hours (a second or a few of the compiled search, seconds of NumPy's)
MAX_SAMPLES = 1_000_000
#: ... and of a piece without a modal closed form (defective configurations: every sample is a
#: matrix exponential, about 2 ms for a blade; a blade root of normal stiffness 1e18 N/m needs
#: 5e8 samples per excitation period)
MAX_EXPM_SAMPLES = 2048
#: the row returned by a search that used up :data:`MAX_SAMPLES` (``found`` False, ``tau`` where
#: it stopped)
GAVE_UP = -2


@_jit
def _phi1(z):
    """``(e^z - 1)/z`` of a complex ``z``, 1 at 0; ``e^z - 1`` written without cancellation,
    ``Re = expm1(x) cos y - 2 sin^2(y/2)``, ``Im = e^x sin y`` (NumPy's complex ``expm1``)."""
    if z == 0:
        return 1.0 + 0j
    x, y = z.real, z.imag
    sh = math.sin(0.5 * y)
    return complex(math.expm1(x) * math.cos(y) - 2.0 * sh * sh, math.exp(x) * math.sin(y)) / z


@_jit
def _resonant(lam, mu, tau):
    """``E(lam, mu, tau) = int_0^tau e^{lam (tau - s)} e^{mu s} ds`` of a (near-)resonant mode and
    forcing pair (:func:`.propagator._E`): ``tau e^{lam tau} phi1((mu - lam) tau)``, or the same with
    ``lam`` and ``mu`` exchanged where ``Re(mu - lam) > 0`` (no ``0 * inf``)."""
    z = (mu - lam) * tau
    if z.real > 0:
        return tau * cmath.exp(mu * tau) * _phi1(-z)
    return tau * cmath.exp(lam * tau) * _phi1(z)


@_jit
def _value(pa, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, tau, r):
    g = 0.0
    for i in range(lam.size):
        g += (pa[r, i] * cmath.exp(lam[i] * tau)).real
    for q in range(nlam.size):
        g += (pn[r, q] * _resonant(nlam[q], nmu[q], tau)).real
    e = cmath.exp(1j * w * tau)
    g += k0[r] + (kp[r] * e + km[r] / e).real
    if harmonic:
        ph = w * (t0 + tau)
        g += cc[r] * math.cos(ph) + cs[r] * math.sin(ph)
    return g


@_jit
def _slope(pla, lam, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, tau, r):
    dg = 0.0
    for i in range(lam.size):
        dg += (pla[r, i] * cmath.exp(lam[i] * tau)).real
    for q in range(nlam.size):
        dg += (pn[r, q] * (nlam[q] * _resonant(nlam[q], nmu[q], tau) + cmath.exp(nmu[q] * tau))).real
    e = cmath.exp(1j * w * tau)
    dg += (1j * w * (kp[r] * e - km[r] / e)).real
    if harmonic:
        ph = w * (t0 + tau)
        dg += w * (cs[r] * math.cos(ph) - cc[r] * math.sin(ph))
    return dg


@_jit
def _sample(pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, tau, g, dg, col):
    """g and g' of every row at ``tau`` into column ``col`` of ``g``, ``dg``."""
    p = lam.size
    e = np.empty(p, np.complex128)
    for i in range(p):
        e[i] = cmath.exp(lam[i] * tau)
    nq = nlam.size
    en = np.empty(nq, np.complex128)
    dn = np.empty(nq, np.complex128)
    for q in range(nq):
        en[q] = _resonant(nlam[q], nmu[q], tau)
        dn[q] = nlam[q] * en[q] + cmath.exp(nmu[q] * tau)
    eip = cmath.exp(1j * w * tau)
    eim = eip.conjugate()
    co = si = 0.0
    if harmonic:
        ph = w * (t0 + tau)
        co = math.cos(ph)
        si = math.sin(ph)
    for r in range(k0.size):
        a = 0.0
        b = 0.0
        for i in range(p):
            a += (pa[r, i] * e[i]).real
            b += (pla[r, i] * e[i]).real
        for q in range(nq):
            a += (pn[r, q] * en[q]).real
            b += (pn[r, q] * dn[q]).real
        a += k0[r] + (kp[r] * eip + km[r] * eim).real
        b += (1j * w * (kp[r] * eip - km[r] * eim)).real
        if harmonic:
            a += cc[r] * co + cs[r] * si
            b += w * (cs[r] * co - cc[r] * si)
        g[r, col] = a
        dg[r, col] = b


@_jit
def _brentq(which, pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, xa, xb, xtol):
    """scipy's brentq (scipy/optimize/Zeros/brentq.c) on g (``which = 0``) or g' (1) of row r."""
    xpre, xcur = xa, xb
    xblk = fblk = spre = scur = 0.0
    if which == 0:
        fpre = _value(pa, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, xpre, r)
        fcur = _value(pa, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, xcur, r)
    else:
        fpre = _slope(pla, lam, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, xpre, r)
        fcur = _slope(pla, lam, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, xcur, r)
    if fpre == 0.0:
        return xpre
    if fcur == 0.0:
        return xcur
    for _ in range(_MAXITER):
        if fpre != 0.0 and fcur != 0.0 and (fpre < 0.0) != (fcur < 0.0):
            xblk = xpre
            fblk = fpre
            spre = scur = xcur - xpre
        if abs(fblk) < abs(fcur):
            xpre = xcur
            xcur = xblk
            xblk = xpre
            fpre = fcur
            fcur = fblk
            fblk = fpre
        delta = (xtol + RTOL * abs(xcur)) / 2
        sbis = (xblk - xcur) / 2
        if fcur == 0.0 or abs(sbis) < delta:
            return xcur
        if abs(spre) > delta and abs(fcur) < abs(fpre):
            if xpre == xblk:
                stry = -fcur * (xcur - xpre) / (fcur - fpre)
            else:
                dpre = (fpre - fcur) / (xpre - xcur)
                dblk = (fblk - fcur) / (xblk - xcur)
                stry = -fcur * (fblk * dblk - fpre * dpre) / (dblk * dpre * (fblk - fpre))
            if 2 * abs(stry) < min(abs(spre), 3 * abs(sbis) - delta):
                spre = scur
                scur = stry
            else:
                spre = sbis
                scur = sbis
        else:
            spre = sbis
            scur = sbis
        xpre = xcur
        fpre = fcur
        if abs(scur) > delta:
            xcur += scur
        else:
            xcur += delta if sbis > 0 else -delta
        if which == 0:
            fcur = _value(pa, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, xcur, r)
        else:
            fcur = _slope(pla, lam, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, xcur, r)
    return xcur


@_jit
def _brent(pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, a, b, xtol):
    """Root of g on [a, b] (g(a) >= 0 > g(b) up to rounding): a zero end point wins."""
    if _value(pa, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, a, r) <= 0:
        return a
    if _value(pa, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, b, r) >= 0:
        return b
    return _brentq(0, pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, a, b, xtol)


#: actions of :func:`_tiny_next`
_EVALUATE, _BRACKET, _GIVE_UP = 0, 1, 2


@_jit
def _tiny_next(a, b, st, gv):
    """One step of the search for the root just after a start at zero, shared by the compiled
    and the NumPy paths (each supplies the evaluations of its own ``g``).

    The points tried, in order: ``a + (b - a) k / 64`` for ``k = 1 ... 64``, the root bracketed by
    the first pair ``g > 0 > g``; failing that (the positive stretch after a start at zero can be
    far shorter than the grid, e.g. a slip of a few microseconds where the force exceeds the slip
    limit by 1e-12 of it), halvings ``a + d/2^j`` of the first step towards the start until ``g``
    is positive, the root then between that point and the previous one.

    ``st`` (8 floats, zeros at the start) holds the search's state; ``gv`` is ``g`` at the point
    asked for by the previous call (ignored at the first). Returns ``(action, t0, t1)``:
    ``_EVALUATE`` (call again with ``g(t0)``), ``_BRACKET`` (the root is in ``[t0, t1]``: Brent) or
    ``_GIVE_UP`` (no root found: the answer is ``b``).
    """
    phase = st[0]
    if phase == 0.0:  # first call: ask for g at the first grid point
        st[0], st[1] = 1.0, 1.0
        return _EVALUATE, a + (b - a) * 1 / 64, 0.0
    if phase == 1.0:  # grid: gv = g(t_k)
        k = int(st[1])
        t = a + (b - a) * k / 64
        if k == 1:
            st[6] = gv
        elif st[3] > 0 > gv:
            return _BRACKET, st[2], t
        st[2], st[3] = t, gv
        if k < 64:
            st[1] = k + 1
            return _EVALUATE, a + (b - a) * (k + 1) / 64, 0.0
        hi = a + (b - a) * 1 / 64
        if not st[6] < 0:
            return _GIVE_UP, b, b
        st[0], st[4], st[5], st[7] = 2.0, hi, hi - a, 0.0
    elif gv > 0:  # halvings: gv = g(lo) at lo = a + d
        return _BRACKET, a + st[5], st[4]
    else:
        st[4] = a + st[5]
    # the next halving
    st[5] *= 0.5
    st[7] += 1.0
    lo = a + st[5]
    if st[7] > 80 or lo <= a:
        return _GIVE_UP, b, b
    return _EVALUATE, lo, 0.0


@_jit
def _locate_tiny(pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, a, b, xtol):
    """Root just after a start at zero (:func:`_tiny_next`)."""
    st = np.zeros(8)
    act, ta, tb = _tiny_next(a, b, st, 0.0)
    while act == _EVALUATE:
        act, ta, tb = _tiny_next(a, b, st, _value(pa, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, ta, r))
    if act == _BRACKET:
        return _brent(pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, ta, tb, xtol)
    return b


@_jit
def _in_band(pa, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, a, b, tol):
    """True when row r, which starts at zero and is at once negative, stays inside its zero band
    (``g >= -tol``) at the 32 points of ``(a, b]``: a function the settling judged consistent at
    ``a`` (within the band, its slope too) that only moves inside the band, e.g. the force of a
    joint 1e9 times stiffer than the structure, whose fast oscillation takes it 2e-4 N past its
    limit where the rounding of ``kt |x|`` is 3e-4 N. Its zero just after ``a`` is rounding
    (1e-19 s on, below the time's resolution: the same event found again and again); ``b`` is
    handed to the settling instead, which judges the row there."""
    for k in range(1, 33):
        t = a + (b - a) * k / 32
        if not _value(pa, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, t, r) >= -tol:
            return False
    return True


@_jit
def _locate(pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, a, b, crossing, tol, h, start_zero):
    """Event time of row r in [a, b] (a crossing or a dip found by the sampling), or -1."""
    xtol = 1e-16 * h
    if crossing:
        if start_zero or _value(pa, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, a, r) < 0:
            # the function starts at zero: find a positive point before the crossing
            prev = a
            for k in range(1, 33):
                t = a + (b - a) * k / 32
                if _value(pa, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, t, r) < 0:
                    if k == 1:
                        if not start_zero:
                            return a
                        if _in_band(pa, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, a, b, tol):
                            return b
                        return _locate_tiny(pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, a, t, xtol)
                    return _brent(pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, prev, t, xtol)
                prev = t
            return b
        return _brent(pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, a, b, xtol)
    # dip: a local minimum between a and b
    if (_slope(pla, lam, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, a, r) >= 0
            or _slope(pla, lam, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, b, r) <= 0):
        return -1.0
    tm = _brentq(1, pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, a, b, xtol)
    if start_zero and (tm <= 1e-9 * h or tm <= 1e-14 * abs(t0)):
        # the bottom at the start (or within the time's resolution at t0: the same instant, found
        # again and again, e.g. at a load reversal 3e9 s into quasi-static forcing). The event
        # functions take the absolute time t0 + tau in their harmonic terms, so instants a few ulps
        # of t0 apart are the same instant: 1e-14 |t0| is about 64 ulps (a grazing stuck row on the
        # solid blade, at 13 ulps under another CPU's BLAS rounding, was found again 13 ulps at a
        # time until the march's piece cap, where 't0 + tm == t0' caught only 1 ulp)
        return -1.0
    gm = _value(pa, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, tm, r)
    if start_zero and gm >= 0:
        # a row at zero, judged consistent, that turns up without going below zero: no event
        # (its bottom, 1e-10 s on under quasi-static forcing, was found again and again)
        return -1.0
    if gm < 0:
        if start_zero and gm >= -tol:
            return tm
        return _brent(pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, a, tm, xtol)
    if gm <= tol:
        return tm
    return -1.0


@_jit
def _coefficients(p, a, b0, bp, bm, c0, lam, cc, cs):
    """``pa, pla, k0, kp, km`` of the event functions (module docstring) and whether any has a
    direct harmonic part."""
    nr, nm = p.shape
    pa = np.empty((nr, nm), np.complex128)
    pla = np.empty((nr, nm), np.complex128)
    k0 = np.empty(nr)
    kp = np.empty(nr, np.complex128)
    km = np.empty(nr, np.complex128)
    harmonic = False
    for r in range(nr):
        s0 = 0.0
        sp = 0j
        sm = 0j
        for i in range(nm):
            pa[r, i] = p[r, i] * a[i]
            pla[r, i] = pa[r, i] * lam[i]
            s0 += (p[r, i] * b0[i]).real
            sp += p[r, i] * bp[i]
            sm += p[r, i] * bm[i]
        k0[r] = s0 + c0[r]
        kp[r] = sp
        km[r] = sm
        if cc[r] != 0.0 or cs[r] != 0.0:
            harmonic = True
    return pa, pla, k0, kp, km, harmonic


@_jit
def magnitudes(z):
    """``|z|`` of a complex matrix, elementwise (the event functions' ``|p|``, cached per status)."""
    out = np.empty(z.shape)
    for r in range(z.shape[0]):
        for i in range(z.shape[1]):
            out[r, i] = abs(z[r, i])
    return out


@_jit
def _near_terms(p, nidx, nc):
    """``pn[r, q] = p[r, nidx[q]] nc[q]``: the event functions' coefficients of the resonant
    terms ``E(lam_q, mu_q, tau)`` of the piece."""
    nr = p.shape[0]
    pn = np.empty((nr, nidx.size), np.complex128)
    for r in range(nr):
        for q in range(nidx.size):
            pn[r, q] = p[r, nidx[q]] * nc[q]
    return pn


@_jit
def _near_bounds(pn, nlam, nmu, horizon):
    """Per row, bounds over ``[0, horizon]`` of the resonant terms and of their second derivative:
    ``|E| <= horizon G``, ``|E''| = |lam^2 E + (lam + mu) e^{mu tau}| <= |lam|^2 horizon G + (|lam|
    + |mu|) G``, ``G = max(1, e^{Re lam horizon}, e^{Re mu horizon})``."""
    nr, nq = pn.shape
    size = np.zeros(nr)
    curv = np.zeros(nr)
    for q in range(nq):
        gq = math.exp(max(nlam[q].real, nmu[q].real, 0.0) * horizon)
        al = abs(nlam[q])
        s_q = horizon * gq
        c_q = al * al * horizon * gq + (al + abs(nmu[q])) * gq
        for r in range(nr):
            apn = abs(pn[r, q])
            size[r] += apn * s_q
            curv[r] += apn * c_q
    return size, curv


@_jit
def _growth(lam, horizon):
    """``max(1, e^{Re lam_i horizon})`` per mode."""
    grow = np.empty(lam.size)
    for i in range(lam.size):
        grow[i] = math.exp(max(lam[i].real, 0.0) * horizon)
    return grow


@_jit
def _bounded_away(apa, abs_p, b0, grow, k0, kp, km, cc, cs, w, t0, tol, atzero, vrows, near_size):
    """True when no function can reach its zero band over ``[0, horizon]`` (closed-form bound
    about k0, see ``Interval.bounds``: forced part |Z|, free modes sum |pa_i| max(1, e^{Re lam_i
    horizon}), and the rounding of terms of these sizes), with the velocity rows' upper bound.
    ``apa = |pa|``, ``abs_p = |p|`` and ``grow`` (:func:`_growth`) are computed once per piece
    (status) and shared with :func:`_curvature_bound`; ``near_size`` bounds the resonant terms
    (:func:`_near_bounds`)."""
    nr, nm = apa.shape
    ab0 = np.empty(nm)
    for i in range(nm):
        ab0[i] = abs(b0[i])
    e0 = cmath.exp(1j * w * t0)
    skip = True
    spread = np.empty(nr)
    for r in range(nr):
        z = kp[r] + km[r].conjugate() + (cc[r] - 1j * cs[r]) * e0
        free = 0.0
        pb = 0.0
        for i in range(nm):
            free += apa[r, i] * grow[i]
            pb += abs_p[r, i] * ab0[i]
        sr = abs(z) + free + near_size[r]
        spread[r] = sr + 1e-12 * (abs(k0[r]) + sr + pb)
        if atzero[r] or not (k0[r] - spread[r] > tol[r]):
            skip = False
    vmax = 0.0
    if skip:
        for r in range(nr):
            if vrows[r]:
                vmax = max(vmax, abs(k0[r] + spread[r]))
    return skip, vmax


@_jit
def _curvature(pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, tol, horizon):
    """Per row: a bound ``M`` of ``|g''|`` over ``[0, horizon]`` (free modes ``sum |pa_i| |lam_i|^2
    max(1, e^{Re lam_i horizon})``, forced part ``w^2 (|kp| + |km| + |(cc, cs)|)``) and the level
    ``tol + 1e-12 (|k0| + spread)`` the function must stay above for a step to be skipped (its zero
    band plus the rounding of terms of the function's size)."""
    return _curvature_bound(magnitudes(pa), lam, _growth(lam, horizon), k0, kp, km, cc, cs, w,
                            harmonic, tol, *_near_bounds(pn, nlam, nmu, horizon))


@_jit
def _curvature_bound(apa, lam, grow, k0, kp, km, cc, cs, w, harmonic, tol, near_size, near_curv):
    """:func:`_curvature` from ``apa = |pa|``, ``grow`` (:func:`_growth`) and the resonant terms'
    bounds (:func:`_near_bounds`), all computed once per piece by :func:`first_event`."""
    nr, nm = apa.shape
    curv = np.empty(nr)
    level = np.empty(nr)
    # |pla_i| |lam_i| = |pa_i| |lam_i|^2 (no second complex modulus per row and mode; the
    # rounding, a few ulp, is far inside the 0.999 of _safe_step)
    alam = np.empty(nm)
    for i in range(nm):
        al = abs(lam[i])
        alam[i] = al * al * grow[i]
    for r in range(nr):
        m2 = 0.0
        spread = 0.0
        for i in range(nm):
            m2 += apa[r, i] * alam[i]
            spread += apa[r, i] * grow[i]
        forced = abs(kp[r]) + abs(km[r])
        if harmonic:
            forced += math.hypot(cc[r], cs[r])
        curv[r] = m2 + w * w * forced + near_curv[r]
        level[r] = tol[r] + 1e-12 * (abs(k0[r]) + spread + forced + near_size[r])
    return curv, level


@_jit
def _curvature_now(apa, lam, grow, grow_t, t, kp, km, cc, cs, w, harmonic, near_curv):
    """The curvature part of :func:`_curvature_bound` over ``[t, horizon]`` (``grow_t`` is
    overwritten: ``e^{Re lam_i t}`` for the decaying modes, ``grow_i`` for the others)."""
    nr, nm = apa.shape
    for i in range(nm):
        lr = lam[i].real
        grow_t[i] = math.exp(lr * t) if lr < 0 else grow[i]
        al = abs(lam[i])
        grow_t[i] *= al * al
    curv = np.empty(nr)
    for r in range(nr):
        m2 = 0.0
        for i in range(nm):
            m2 += apa[r, i] * grow_t[i]
        forced = abs(kp[r]) + abs(km[r])
        if harmonic:
            forced += math.hypot(cc[r], cs[r])
        curv[r] = m2 + w * w * forced + near_curv[r]
    return curv


@_jit
def _safe_step(g, dg, col, curv, level):
    """Longest step from the sample in column ``col`` over which every row provably stays above
    its level: ``g + g' s - M s^2 / 2 > level`` (0 if a row is at or below it)."""
    best = math.inf
    for r in range(g.shape[0]):
        gr = g[r, col] - level[r]
        if not gr > 0:
            return 0.0
        d = dg[r, col]
        m = curv[r]
        if m > 0:
            # the root of m s^2 / 2 - d s - gr in the form without cancellation (the denominator
            # is >= |d| > 0 for d < 0: no underflow to zero)
            root = math.sqrt(d * d + 2.0 * m * gr)
            s = 2.0 * gr / (root - d) if d < 0 else (d + root) / m
        elif d < 0:
            s = gr / -d
        else:
            continue
        best = min(best, s)
    return 0.999 * best


@_jit
def first_event(p, abs_p, a, b0, bp, bm, c0, lam, cc, cs, w, t0, tol, atzero, vrows, horizon, h,
                nidx, nmu, nc, max_samples=MAX_SAMPLES):
    """First event of a modal piece in ``(0, horizon]``.

    One piece on purpose: its sample loop is the marcher's hottest, and its steps as compiled
    helpers (the start sample, the rows' crossings and dips per step; inlined or called) cost
    3-8 % per call, measured on 400 real calls.

    Parameters
    ----------
    p : (rows, modes) complex ndarray
        Event functions in modal coordinates (``C_y V``).
    abs_p : (rows, modes) ndarray
        ``|p|`` (:func:`magnitudes`; constant per status, computed once by the caller).
    a, b0, bp, bm : (modes,) complex ndarray
        The piece's modal solution ``eta = e^{lam tau} a + b0 + bp e^{i w tau} + bm e^{-i w tau}``.
    c0, cc, cs : (rows,) ndarray
        Constant and direct harmonic parts of the event functions.
    lam : (modes,) complex ndarray
        Eigenvalues of the configuration.
    w, t0 : float
        Excitation angular frequency [rad/s] and the piece's start time [s].
    tol : (rows,) ndarray
        Zero bands; ``atzero`` (rows,) bool: functions that start inside theirs.
    vrows : (rows,) bool ndarray
        Velocity rows (their values set the marcher's velocity scale).
    horizon, h : float
        End of the search and sampling step [s].
    nidx : (q,) int ndarray
        Modes with a (near-)resonant term ``nc_q E(lam_q, mu_q, tau)`` added to their ``eta``
        (``Interval._near``; empty for a plain piece).
    nmu, nc : (q,) complex ndarray
        Their forcing exponents ``mu`` (0 or ``+-i w``) and coefficients.
    max_samples : int
        Samples at most; beyond, the search gives up (``row`` :data:`GAVE_UP`).

    Returns
    -------
    found : bool
    tau : float
        Local time of the event (where the search stopped, if it gave up).
    row : int
        Row of the event function (:data:`GAVE_UP` if the search gave up).
    vmax : float
        Largest ``|g|`` of the velocity rows seen (bound, start or samples).
    """
    pa, pla, k0, kp, km, harmonic = _coefficients(p, a, b0, bp, bm, c0, lam, cc, cs)
    pn = _near_terms(p, nidx, nc)
    nlam = np.empty(nidx.size, np.complex128)
    for q in range(nidx.size):
        nlam[q] = lam[nidx[q]]
    nr = k0.size
    vmax = 0.0
    apa = magnitudes(pa)
    grow = _growth(lam, horizon)
    near_size, near_curv = _near_bounds(pn, nlam, nmu, horizon)
    if horizon > 4 * h:
        skip, vmax = _bounded_away(apa, abs_p, b0, grow, k0, kp, km, cc, cs, w, t0, tol, atzero, vrows,
                                   near_size)
        if skip:
            return False, 0.0, -1, vmax
    # two sample columns (previous, current), filled one sample at a time: the search stops at
    # the first sample step with a located event, with nothing evaluated beyond it
    g = np.empty((nr, 2))
    dg = np.empty((nr, 2))
    _sample(pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, 0.0, g, dg, 0)
    for r in range(nr):
        if atzero[r]:
            g[r, 0] = 0.0
        if vrows[r]:
            vmax = max(vmax, abs(g[r, 0]))
    curv, level = _curvature_bound(apa, lam, grow, k0, kp, km, cc, cs, w, harmonic, tol, near_size, near_curv)
    # the free modes' share of the curvature bound decays with the piece: from a sample at t on,
    # |pa_i e^{lam_i s}| |lam_i|^2 <= |pa_i| |lam_i|^2 e^{Re lam_i t} for a decaying mode (the
    # bound from the start would keep the steps at the transient's scale for the whole piece:
    # quasi-static forcing, period 1e12 of the structure's, took 1e12 steps)
    decaying = False
    for i in range(lam.size):
        if lam[i].real < 0:
            decaying = True
    grow_t = grow.copy()
    t_prev = 0.0
    prev, cur = 0, 1
    k = 0
    while t_prev < horizon:
        k += 1
        if k > max_samples:
            return False, t_prev, GAVE_UP, vmax
        if decaying and t_prev > 0:
            curv = _curvature_now(apa, lam, grow, grow_t, t_prev, kp, km, cc, cs, w, harmonic, near_curv)
        # a step longer than h where no function can reach its band (Taylor bound, see _safe_step)
        t = min(t_prev + max(h, _safe_step(g, dg, prev, curv, level)), horizon)
        _sample(pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, t, g, dg, cur)
        best_tau = math.inf
        best_row = -1
        for r in range(nr):
            if vrows[r]:
                vmax = max(vmax, abs(g[r, cur]))
            cross = g[r, prev] >= 0 and g[r, cur] < 0
            dip = dg[r, prev] < 0 and dg[r, cur] > 0 and not cross
            if not (cross or dip):
                continue
            start_zero = k == 1 and atzero[r]
            tau = _locate(pa, pla, lam, k0, kp, km, cc, cs, w, t0, harmonic, pn, nlam, nmu, r, t_prev, t, cross,
                          tol[r], h, start_zero)
            if tau >= 0 and tau < best_tau:
                best_tau = tau
                best_row = r
        if best_row >= 0:
            return True, best_tau, best_row, vmax
        t_prev = t
        prev, cur = cur, prev
    return False, 0.0, -1, vmax


# ------------------------------------------------------------------------------ the NumPy path
def numpy_first_event(itv, red, tol, atzero, vrows, horizon: float, h: float, max_samples: int | None = None):
    """:func:`first_event` for any piece (defective or near-resonant configurations included),
    with NumPy: the closed-form bound, samples in chunks of :data:`CHUNK` with derivatives, and
    each candidate located on the piece's scalar closed form (scipy's brentq). Same arguments and
    returns as :func:`first_event`, for the piece ``itv`` and its reduced event functions ``red``
    (``max_samples``: by default :data:`MAX_SAMPLES`, :data:`MAX_EXPM_SAMPLES` for a piece
    without a modal closed form)."""
    if max_samples is None:
        max_samples = MAX_SAMPLES if itv.modal_search() else MAX_EXPM_SAMPLES
    vmax = 0.0
    any_v = bool(np.any(vrows))
    if horizon > 4 * h:
        # no event function can reach its zero band over the whole horizon (bounds of the
        # closed form): skip the sampling, which costs horizon * rate / 2pi * 16 evaluations
        # (a stiff stuck joint: rate ~ 1e5 rad/s, ~1e5 samples per excitation period)
        bnd = itv.bounds(red, horizon)
        if bnd is not None:
            lo, hi = bnd
            if not atzero.any() and all(lv > tv for lv, tv in zip(lo.tolist(), tol)):
                return False, 0.0, -1, (float(np.max(np.abs(hi[vrows]))) if any_v else 0.0)
    steps = h * np.arange(1, CHUNK + 1)
    # the start values are evaluated together with the first chunk of samples
    n = min(CHUNK, max(1, math.ceil(horizon / h)))
    taus = steps[:n].copy()
    taus[-1] = min(taus[-1], horizon)
    taus = taus[taus <= horizon]
    sample = itv.sampler(red)
    g, dg = sample(np.concatenate([[0.0], taus]))
    g_a = np.where(atzero, 0.0, g[:, 0])
    dg_a = dg[:, 0]
    g, dg = g[:, 1:], dg[:, 1:]
    tau_a = 0.0
    if any_v:
        vmax = float(np.max(np.abs(g_a[vrows])))
    n_sampled = 0
    while tau_a < horizon:
        n_sampled += CHUNK
        if n_sampled > max_samples:
            return False, tau_a, GAVE_UP, vmax
        if g is None:
            n = min(CHUNK, max(1, math.ceil((horizon - tau_a) / h)))
            taus = tau_a + steps[:n]
            taus[-1] = min(taus[-1], horizon)
            taus = taus[taus <= horizon]
            g, dg = sample(taus)
        if any_v:
            vmax = max(vmax, float(np.max(np.abs(g[vrows]))))
        ga = np.hstack([g_a[:, None], g])
        dga = np.hstack([dg_a[:, None], dg])
        ta = np.concatenate([[tau_a], taus])
        cross = (ga[:, :-1] >= 0) & (ga[:, 1:] < 0)
        dip = (dga[:, :-1] < 0) & (dga[:, 1:] > 0) & ~cross
        cand = cross | dip
        if cand.any():
            for k in np.flatnonzero(cand.any(axis=0)):
                best = None
                for j in np.flatnonzero(cand[:, k]):
                    tau = _np_locate(itv, red, j, ta[k], ta[k + 1], bool(cross[j, k]), tol[j], h,
                                     start_zero=(k == 0 and tau_a == 0.0 and atzero[j]))
                    if tau is not None and (best is None or tau < best[0]):
                        best = (tau, int(j))
                if best is not None:
                    return True, best[0], best[1], vmax
        tau_a = taus[-1]
        g_a, dg_a = g[:, -1], dg[:, -1]
        g = None
    return False, 0.0, -1, vmax


def _np_locate(itv, red, j, a, b, crossing, tol, h, start_zero):
    """Event time of row ``j`` in ``[a, b]`` (see :func:`_locate`), or None."""
    one = tuple(r[j:j + 1] for r in red)
    g, dg = itv.scalar(red, j)
    xtol = 1e-16 * h
    if crossing:
        if start_zero or g(a) < 0:
            # the function starts at zero: find a positive point before the crossing
            ts = np.linspace(a, b, 33)[1:]
            vals = itv.evaluate(one, ts)[0][0]
            neg = np.flatnonzero(vals < 0)
            if neg.size == 0:
                # the sampler saw g(b) < 0, the scalar evaluations do not (last-bit rounding)
                return b
            first = neg[0]
            if first == 0:
                if not start_zero:
                    return a
                if np.all(vals >= -tol):  # inside its band throughout (see _in_band)
                    return b
                return _np_locate_tiny(g, a, ts[0], xtol)
            a = ts[first - 1]
            b = ts[first]
        return _np_brent(g, a, b, xtol)
    # dip: local minimum between a and b
    if dg(a) >= 0 or dg(b) <= 0:  # a sign change of g' that was rounding noise
        return None
    # disp=False: after _MAXITER iterations the best point so far, as the compiled _brentq (both
    # tolerances are at a few ulps of the time, where g' is rounding noise and Brent's
    # interpolation steps can use up the iterations without reaching them: scipy would raise)
    tm = scipy.optimize.brentq(dg, a, b, xtol=xtol, rtol=RTOL, maxiter=_MAXITER, disp=False)
    if start_zero and (tm <= 1e-9 * h or tm <= 1e-14 * abs(itv.t0)):  # see _locate
        return None
    gm = g(tm)
    if start_zero and gm >= 0:  # turns up without going below zero: no event (see _locate)
        return None
    if gm < 0:
        if start_zero and gm >= -tol:
            # a function that starts in its zero band and dips only inside it (e.g. a slip
            # velocity that reverses by a few ulps where the holding force is within
            # rounding of the slip limit): no crossing to locate (its root would be the
            # start itself, and time would not advance); the bottom of the dip is the event
            return tm
        return _np_brent(g, a, tm, xtol)
    if gm <= tol:
        return tm
    return None


def _np_brent(g, a, b, xtol):
    """Root of ``g`` on ``[a, b]`` (g(a) >= 0 > g(b) up to rounding): where the scalar and the
    vectorised evaluations disagree in the last bits, the end point that is zero wins."""
    ga, gb = g(a), g(b)
    if ga <= 0:
        return a
    if gb >= 0:
        return b
    return scipy.optimize.brentq(g, a, b, xtol=xtol, rtol=RTOL, maxiter=_MAXITER, disp=False)


def _np_locate_tiny(g, a, b, xtol):
    """:func:`_locate_tiny` for the NumPy path's ``g``."""
    st = np.zeros(8)
    act, ta, tb = _tiny_next(a, b, st, 0.0)
    while act == _EVALUATE:
        act, ta, tb = _tiny_next(a, b, st, float(g(ta)))
    return _np_brent(g, ta, tb, xtol) if act == _BRACKET else b
