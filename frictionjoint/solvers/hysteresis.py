"""Exact periodic hysteresis of friction sliders under a trigonometric-polynomial displacement:
the Fourier coefficients of the force and their derivatives with respect to the displacement's,
in closed form (the alternating frequency-time step of harmonic balance, without time sampling
error).

A displacement of ``H`` harmonics in the phase ``theta = omega t``,

    u(theta) = c[0] + sum_h (c[2h-1] cos(h theta) + c[2h] sin(h theta)),

drives a slider through one period. The force of a Jenkins slider (spring ``k`` in series with a
slider of strength ``F``) is, exactly, piecewise: ``k (u - w)`` while it sticks (``w`` constant),
``sig F`` while it slips. Its transitions are roots of ``u`` against a level (stick -> slip, where
the spring force reaches ``+-F``) and of ``u'`` (slip -> stick, where the motion reverses). They
are bracketed on a grid of :func:`n_samples` points per period (the grid only brackets: its size
is tied to ``H`` so that the roots of a polynomial of ``H`` harmonics are separated, and refined
to rounding by Brent's method) and every Fourier integral over a piece is in closed form. The
steady loop starts at the global maximum of ``u``, where the slider has just slipped forward
(Masing: the loop closes after one period); a slider that never slips keeps its reference
position ``w_ref`` (its static one), clipped into the band where it stays stuck.

Derivatives: the force is continuous at every transition, so the transition times drop out
(Leibniz); on a piece stuck since a reversal at ``theta_r`` the slider position is ``w = u(theta_r)
- sig F/k`` with ``u'(theta_r) = 0``, so ``dw/dc = phi(theta_r)``: ``dT/dc = k (phi(theta) -
phi(theta_r))`` there and 0 while it slips. A rigid Coulomb slider (``k = inf``) in continuous
sliding has ``T = F sgn(u')``: its coefficients change only through the reversal times,
``d theta_r/dc = -phi'(theta_r)/u''(theta_r)``, at which ``T`` jumps by ``2F``.

Coefficients are normalised as the displacement's: ``T[0]`` the mean, ``T[2h-1], T[2h]`` the
cosine and sine amplitudes.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.optimize

from . import loop_kernels

__all__ = ["n_samples", "evaluate", "segment_integrals", "jenkins_loop", "coulomb_loop"]


def n_samples(n_harmonics: int) -> int:
    """Grid points per period that bracket the transitions of a loop driven by ``n_harmonics``
    harmonics: ``32 (H + 1)`` (16 per half-period of the highest harmonic, at least 64)."""
    return max(64, 32 * (int(n_harmonics) + 1))


_GRIDS: dict = {}


def _trig_tables(n_harmonics: int):
    """``cos(h theta_j)``, ``sin(h theta_j)`` (H, N) on the bracketing grid (the compiled loop's)."""
    key = (n_harmonics, "trig")
    t = _GRIDS.get(key)
    if t is None:
        table = _grid(n_harmonics)[1]
        t = _GRIDS[key] = (np.ascontiguousarray(table.real), np.ascontiguousarray(table.imag))
    return t


def _grid(n_harmonics: int, closed: bool = False):
    """The bracketing grid over one period (``closed``: with its end point) and its table
    ``e^{i h theta}``, built once per ``H``."""
    key = (n_harmonics, closed)
    g = _GRIDS.get(key)
    if g is None:
        m = n_samples(n_harmonics)
        theta = np.linspace(0.0, 2 * math.pi, m + 1) if closed else np.linspace(0.0, 2 * math.pi, m, endpoint=False)
        g = _GRIDS[key] = (theta, np.exp(1j * np.outer(np.arange(1, n_harmonics + 1), theta)))
    return g


def _basis(theta, n_harmonics: int, derivative: int = 0) -> np.ndarray:
    """(2H+1, k) values of the basis ``1, cos h theta, sin h theta`` (or its derivative)."""
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    h = np.arange(1, n_harmonics + 1)[:, None]
    ht = h * theta[None, :]
    out = np.empty((2 * n_harmonics + 1, theta.size))
    c, s = np.cos(ht), np.sin(ht)
    hd = h.astype(float) ** derivative
    # d^n/dtheta^n of (cos, sin)(h theta) = h^n (cos, sin)(h theta + n pi/2)
    rot = derivative % 4
    if rot == 0:
        dc, ds = c, s
    elif rot == 1:
        dc, ds = -s, c
    elif rot == 2:
        dc, ds = -c, -s
    else:
        dc, ds = s, -c
    out[0] = 1.0 if derivative == 0 else 0.0
    out[1::2] = hd * dc
    out[2::2] = hd * ds
    return out


def evaluate(c: np.ndarray, theta, derivative: int = 0) -> np.ndarray:
    """``u`` (or its ``derivative``-th derivative in ``theta``) at the phases ``theta``."""
    h = (c.size - 1) // 2
    return c @ _basis(theta, h, derivative)


class _Poly:
    """``u`` as ``c0 + Re(sum_h C_h e^{i h theta})``, ``C_h = a_h - i b_h``: fast scalar values of
    ``u`` and its derivatives (root refinement)."""

    __slots__ = ("c0", "cd")

    def __init__(self, c: np.ndarray):
        hh = (c.size - 1) // 2
        h = np.arange(1, hh + 1)
        cc = c[1::2] - 1j * c[2::2]
        self.c0 = float(c[0])
        # C_h (i h)^n for n = 0, 1, 2, 3
        self.cd = [cc, cc * (1j * h), cc * (1j * h) ** 2, cc * (1j * h) ** 3]

    def values(self, theta: np.ndarray, derivative: int = 0, table: np.ndarray | None = None) -> np.ndarray:
        """``u^(n)`` at the phases ``theta`` (1-D); ``table``: ``e^{i h theta}`` if known."""
        n = self.cd[0].size
        e = np.exp(1j * np.outer(np.arange(1, n + 1), theta)) if table is None else table
        out = (self.cd[derivative] @ e).real
        return out + self.c0 if derivative == 0 else out

    def __call__(self, theta: float, derivative: int = 0) -> tuple:
        """``(u^(n), u^(n+1))`` at the scalar ``theta``."""
        n = self.cd[0].size
        e = np.exp(1j * theta * np.arange(1, n + 1))
        a = float((self.cd[derivative] @ e).real)
        b = float((self.cd[derivative + 1] @ e).real)
        if derivative == 0:
            a += self.c0
        return a, b


def _newton_root(poly: _Poly, derivative: int, level: float, a: float, b: float) -> float:
    """Root of ``u^(n)(theta) - level`` in the bracket ``[a, b]`` (a sign change): Newton's
    method safeguarded by bisection, to rounding."""
    fa = poly(a, derivative)[0] - level
    fb = poly(b, derivative)[0] - level
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    if fa * fb > 0:  # no sign change (rounding at a bracket end): the nearer end
        return a if abs(fa) < abs(fb) else b
    x = 0.5 * (a + b)
    tol = 4 * np.finfo(float).eps * max(1.0, abs(b))
    for _ in range(100):
        f, df = poly(x, derivative)
        f -= level
        if f == 0.0:
            return x
        if (f < 0) == (fa < 0):
            a, fa = x, f
        else:
            b = x
        step = f / df if df != 0 else math.inf
        xn = x - step
        if not (a < xn < b):  # outside the bracket: bisect
            xn = 0.5 * (a + b)
        if abs(xn - x) <= tol or b - a <= tol:
            return xn
        x = xn
    return x


def _cos_sin_integrals(p: np.ndarray, a: float, b: float):
    """``int_a^b cos(p theta)`` and ``int_a^b sin(p theta)`` for integer arrays ``p`` (any sign)."""
    p = np.asarray(p, dtype=float)
    zero = p == 0
    ps = np.where(zero, 1.0, p)
    ci = np.where(zero, b - a, (np.sin(ps * b) - np.sin(ps * a)) / ps)
    si = np.where(zero, 0.0, -(np.cos(ps * b) - np.cos(ps * a)) / ps)
    return ci, si


_TABLES: dict = {}


def _tables(hh: int):
    """Index tables of :func:`segment_integrals` for ``H`` harmonics (built once per ``H``)."""
    t = _TABLES.get(hh)
    if t is None:
        n = 2 * hh + 1
        kind = np.zeros(n, int)  # 0: cos (or the mean), 1: sin
        order = np.zeros(n, int)
        kind[2::2] = 1
        order[1::2] = np.arange(1, hh + 1)
        order[2::2] = np.arange(1, hh + 1)
        km, kq = kind[:, None], kind[None, :]
        om, oq = order[:, None], order[None, :]
        diff, total = om - oq, om + oq
        # int psi_k phi_j = 0.5 (A int cos(|m-q| t) + B int cos((m+q) t) + C int sin(|m-q| t) + D int sin((m+q) t))
        a = np.where(km == kq, 1.0, 0.0)
        b = np.where((km == 0) & (kq == 0), 1.0, np.where((km == 1) & (kq == 1), -1.0, 0.0))
        sgn = np.sign(diff)
        # sin m cos q: (sin(m+q) + sin(m-q))/2; cos m sin q: (sin(m+q) - sin(m-q))/2
        cc = np.where((km == 1) & (kq == 0), sgn, np.where((km == 0) & (kq == 1), -sgn, 0.0))
        d = np.where(km != kq, 1.0, 0.0)
        t = _TABLES[hh] = (np.abs(diff), total, 0.5 * a, 0.5 * b, 0.5 * cc, 0.5 * d, kind, order)
    return t


def segment_integrals(a: float, b: float, n_harmonics: int, vector_only: bool = False):
    """``(v, P)`` over ``[a, b]``: ``v[k] = int psi_k``, ``P[k, j] = int psi_k phi_j`` for the basis
    ``1, cos h, sin h`` (both indices), in closed form (``vector_only``: ``v`` alone)."""
    hh = n_harmonics
    ad, tot, ca, cb, cc, cd, kind, order = _tables(hh)
    p = np.arange(2 * hh + 1, dtype=float)  # frequencies 0 .. 2H
    p[0] = 1.0
    ci = (np.sin(p * b) - np.sin(p * a)) / p
    si = -(np.cos(p * b) - np.cos(p * a)) / p
    ci[0], si[0] = b - a, 0.0
    v = np.where(kind == 1, si[order], ci[order])
    v[0] = b - a
    if vector_only:
        return v
    pm = ca * ci[ad] + cb * ci[tot] + cc * si[ad] + cd * si[tot]
    return v, pm


def _norm(n_harmonics: int) -> np.ndarray:
    """Fourier normalisation: ``1/(2 pi)`` for the mean, ``1/pi`` for the others."""
    w = np.full(2 * n_harmonics + 1, 1.0 / math.pi)
    w[0] = 0.5 / math.pi
    return w


def _root(fun, a: float, b: float) -> float:
    """Root of ``fun`` in ``[a, b]`` (a sign change), to rounding."""
    fa, fb = fun(a), fun(b)
    if fa == 0.0:
        return a
    if fb == 0.0:
        return b
    return scipy.optimize.brentq(fun, a, b, xtol=4 * np.finfo(float).eps * max(1.0, abs(b)), rtol=4 * np.finfo(float).eps,
                                 maxiter=200)


def _first_crossing(poly: "_Poly", derivative: int, level: float, orient: int, grid: np.ndarray,
                    values: np.ndarray, start: float, sign: int):
    """First ``theta > start`` where ``g = orient (u^(n) - level)`` (``values``: ``g`` on ``grid``)
    changes sign from ``sign`` to ``-sign``, refined to rounding; None if the grid shows none. A
    function that starts at zero (a transition at ``start``) is searched from the first point after
    ``start`` where it has the sign ``sign``; if there is none before the grid's first crossing, the
    transition is at ``start`` itself."""
    k0 = int(np.searchsorted(grid, start, side="right"))
    if k0 >= grid.size:
        return None
    hits = np.flatnonzero(sign * values[k0:] < 0)
    if hits.size == 0:
        return None
    k = k0 + int(hits[0])
    if k > k0:
        return _newton_root(poly, derivative, level, float(grid[k - 1]), float(grid[k]))
    # the first grid point after start is already across: look between start and it
    pts = start + (grid[k] - start) * np.linspace(0.0, 1.0, 33)[1:]
    vals = sign * orient * (poly.values(pts, derivative) - level)
    j = int(np.flatnonzero(vals < 0)[0])
    if j > 0:
        return _newton_root(poly, derivative, level, float(pts[j - 1]), float(pts[j]))
    if sign * orient * (poly(start, derivative)[0] - level) > 0:
        return _newton_root(poly, derivative, level, start, float(pts[0]))
    return start


def _extremum(poly: "_Poly", grid: np.ndarray, u: np.ndarray, du: np.ndarray, sign: int) -> float:
    """Phase of the global maximum (``sign`` +1) or minimum (-1) of ``u``, refined on ``u' = 0``
    between the largest sample's neighbours."""
    k = int(np.argmax(sign * u))
    n = grid.size
    lo = grid[k - 1] if k > 0 else grid[-1] - 2 * math.pi
    hi = grid[k + 1] if k + 1 < n else grid[0] + 2 * math.pi
    dlo, dhi = poly(lo, 1)[0], poly(hi, 1)[0]
    if sign * dlo >= 0 >= sign * dhi:
        return _newton_root(poly, 1, 0.0, lo, hi)
    return float(grid[k])


def jenkins_loop(c: np.ndarray, stiffness: float, slip_force: float, w_ref: float = 0.0,
                 jacobian: bool = True):
    """Steady force loop of a Jenkins slider driven by ``u`` (coefficients ``c``).

    Parameters
    ----------
    c : (2H+1,) ndarray
        Displacement coefficients [m].
    stiffness, slip_force : float
        ``k`` [N/m] and ``F`` [N], > 0.
    w_ref : float
        Slider position [m] kept when the slider never slips (clipped into the stuck band).
    jacobian : bool
        Also return ``dT/dc``.

    Returns
    -------
    coefficients : (2H+1,) ndarray
        Force coefficients [N].
    jac : (2H+1, 2H+1) ndarray or None
        ``dT/dc`` [N/m].
    w0 : float
        Slider position at ``theta = 0`` [m].
    slips : bool
        Whether the slider slips over the period.
    """
    c = np.asarray(c, dtype=float)
    hh = (c.size - 1) // 2
    k, f = float(stiffness), float(slip_force)
    if loop_kernels.ENABLED:  # the same loop, compiled
        cos_t, sin_t = _trig_tables(hh)
        coef, jac, w0, slips = loop_kernels.jenkins_loop_kernel(np.ascontiguousarray(c), k, f, float(w_ref),
                                                                bool(jacobian), cos_t, sin_t)
        return coef, (jac if jacobian else None), float(w0), bool(slips)
    reach = f / k
    nrm = _norm(hh)
    grid, table = _grid(hh)
    poly = _Poly(c)
    u = poly.values(grid, 0, table)
    du = poly.values(grid, 1, table)
    t_max = _extremum(poly, grid, u, du, +1) % (2 * math.pi)  # in [0, 2 pi): the loop covers theta = 2 pi
    t_min = _extremum(poly, grid, u, du, -1)
    u_max = poly(t_max)[0]
    u_min = poly(t_min)[0]
    n = c.size
    if u_max - u_min <= 2 * reach:  # never slips: T = k (u - w), w fixed
        lo, hi = u_max - reach, u_min + reach
        w = min(max(w_ref, lo), hi)
        coef = k * c.copy()
        coef[0] -= k * w
        jac = None
        if jacobian:
            jac = k * np.eye(n)
            if w != w_ref:  # clipped: w follows the extremum that bounds it
                jac[0] -= k * _basis(t_max if w == lo else t_min, hh)[:, 0]
        return coef, jac, w, False
    # the loop from the global maximum (slipped forward, reversing): pieces over one period
    t0 = t_max
    t_end = t0 + 2 * math.pi
    ext = np.concatenate([grid, grid + 2 * math.pi, [4 * math.pi]])
    u_ext = np.concatenate([u, u, [u[0]]])
    du_ext = np.concatenate([du, du, [du[0]]])
    coef = np.zeros(n)
    jac = np.zeros((n, n)) if jacobian else None
    t = t0
    sig = 1  # the direction of the last slip
    w = u_max - reach
    t_rev = t0  # the reversal the current stuck piece started from
    stuck = True
    w_at_zero = None
    while t < t_end:
        if stuck:
            # stuck until u - w reaches +reach (slip forward) or -reach (slip back)
            # the exit the grid shows first (both refined only where their grid steps tie)
            k0 = int(np.searchsorted(ext, t, side="right"))
            iu = np.flatnonzero(u_ext[k0:] > w + reach)
            idn = np.flatnonzero(u_ext[k0:] < w - reach)
            ku = int(iu[0]) if iu.size else None
            kd = int(idn[0]) if idn.size else None
            up = dn = None
            if ku is not None and (kd is None or ku <= kd):
                up = _first_crossing(poly, 0, w + reach, -1, ext, w + reach - u_ext, t, +1)
            if kd is not None and (ku is None or kd <= ku):
                dn = _first_crossing(poly, 0, w - reach, +1, ext, u_ext - (w - reach), t, +1)
            cands = [(x, s) for x, s in ((up, 1), (dn, -1)) if x is not None and x > t]
            b, new_sig = min(cands) if cands else (t_end, sig)
            b = min(b, t_end)
            v, p = segment_integrals(t, b, hh)
            coef += k * (p @ c) - k * w * v
            if jacobian:
                jac += k * (p - np.outer(v, _basis(t_rev, hh)[:, 0]))
            if w_at_zero is None and t <= 2 * math.pi <= b:
                w_at_zero = w
            t, stuck, sig = b, False, new_sig
        else:
            # slipping in sig until u' turns from sig to -sig
            b = _first_crossing(poly, 1, 0.0, +1, ext, du_ext, t, sig)
            b = t_end if b is None or b <= t else min(b, t_end)
            v, _ = segment_integrals(t, b, hh)
            coef += sig * f * v
            if w_at_zero is None and t <= 2 * math.pi <= b:
                w_at_zero = poly(2 * math.pi)[0] - sig * reach
            t, stuck = b, True
            w = poly(b)[0] - sig * reach
            t_rev = b
    if w_at_zero is None:
        w_at_zero = w
    return nrm * coef, (nrm[:, None] * jac if jacobian else None), w_at_zero, True


def coulomb_loop(c: np.ndarray, slip_force: float, jacobian: bool = True):
    """Force of a rigid Coulomb slider in continuous sliding, ``F sgn(u')``, driven by ``u``.

    Returns ``(coefficients, dT/dc or None)``; a motion with no reversal (``u'`` of one sign, or
    zero) has the constant force ``F sgn(u')`` and no derivative.
    """
    c = np.asarray(c, dtype=float)
    hh = (c.size - 1) // 2
    f = float(slip_force)
    nrm = _norm(hh)
    n = c.size
    grid, table = _grid(hh, closed=True)
    poly = _Poly(c)
    du = poly.values(grid, 1, table)
    roots = [_newton_root(poly, 1, 0.0, float(grid[k]), float(grid[k + 1]))
             for k in np.flatnonzero(du[:-1] * du[1:] < 0)]
    roots += [float(grid[k]) for k in np.flatnonzero(du[:-1] == 0)]
    roots = sorted(set(roots))
    coef = np.zeros(n)
    jac = np.zeros((n, n)) if jacobian else None
    if not roots:
        coef[0] = f * math.copysign(1.0, du[0]) if du[0] != 0 else 0.0
        return nrm * coef, (jac if jacobian else None)
    edges = roots + [roots[0] + 2 * math.pi]
    for a, b in zip(edges[:-1], edges[1:]):
        sgn = math.copysign(1.0, poly(0.5 * (a + b), 1)[0])
        coef += sgn * f * segment_integrals(a, b, hh, vector_only=True)
    if jacobian:
        for r in roots:
            dd = poly(r, 2)[0]
            if dd == 0.0:
                continue
            jump = -2 * f * math.copysign(1.0, dd)  # T(r-) - T(r+): -2F at a minimum of u, +2F at a maximum
            psi = _basis(r, hh)[:, 0]
            dphi = _basis(r, hh, 1)[:, 0]
            jac += jump * np.outer(psi, -dphi / dd)
    return nrm * coef, (nrm[:, None] * jac if jacobian else None)
