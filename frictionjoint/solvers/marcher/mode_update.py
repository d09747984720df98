"""A configuration's modes from its neighbour's: one joint spring more or less is a rank-one change
of the first-order matrix, whose new eigenvalues are the roots of a secular equation.

Configurations met in a row differ by one slider: a stuck Jenkins spring ``k d d^T`` is added to
the stiffness or taken from it, and the first-order matrix ``A = [[0, I], [-M^-1 K, -M^-1 C]]``
changes by ``p r^T``, ``p = [0, -+ M^-1 d k]``, ``r = [d, 0]``. In the neighbour's modes ``A = V
diag(lam) V^-1`` the new matrix is similar to ``diag(lam) + a b^T`` (``a = V^-1 p``, ``b = V^T r``),
whose eigenvalues ``mu`` are the roots of

    f(mu) = 1 + sum_i c_i / (lam_i - mu),    c_i = a_i b_i,

and whose eigenvectors are ``(diag(lam) - mu)^-1 a``; the new mode shapes are the neighbour's times
these. The roots are found together by Aberth's iteration (Aberth 1973; Bini 1996, "Numerical
computation of polynomial zeros by means of Aberth's method", the simultaneous Newton iteration
that MPSolve runs on secular equations), one root of each conjugate pair (the matrix is real) and
the real roots on the real axis. Each root is held as an offset from the pole it is nearest, so
that ``lam_i - mu`` keeps its relative accuracy where a root lies close to a pole (as LAPACK's
``dlaed4`` holds the roots of the symmetric secular equation). The vectors are built with the
weights recomputed from the roots found (the Loewner formula of Gu & Eisenstat 1994, "A stable and
efficient algorithm for the rank-one modification of the symmetric eigenproblem"): ``c_i =
prod_k (mu_k - lam_i) / prod_{l != i} (lam_l - lam_i)``, for which the computed roots are exact.

``V^-1`` is the inverse of the new eigenvectors (:func:`.propagator._real_inverse`), not an update:
left vectors built from the secular equation are off by ``eps`` times its condition, which reached
1e-9 on the benchmark chains. Each result is checked on random probes (each mode's backward error in
the quadratic eigenproblem ``(mu^2 M + mu C + K) phi = 0``, the inverse) and the caller decomposes
the configuration from scratch where a check fails, where a root did not converge or where a pair
of roots would leave the real axis (an over-damped pair turning oscillatory).

Cost: ``O(N^2)`` per Aberth sweep (``N = 2 n``), one ``n x N x N/2`` complex product and a real
inverse, against a dense non-symmetric eigendecomposition (20 ms at ``n = 100``, 57 ms at 200).
"""
from __future__ import annotations

import numpy as np

from ..jit import ENABLED, _jit

__all__ = ["rank_one_modes", "rank_one_roots", "rank_one_roots_top", "rank_one_shapes", "checked_modes", "conjugate_pairs", "MAX_SWEEPS", "BACKWARD_ERROR", "WEIGHTS_CHECK"]

#: Aberth sweeps at most (from the neighbour's eigenvalues the roots converge in 5 to 15 sweeps on
#: the benchmark chains)
MAX_SWEEPS = 60
#: Newton steps on each root after the symmetry is imposed (:func:`_polish`)
POLISH_STEPS = 3
#: largest backward error of the updated modes in the quadratic eigenproblem on a random probe
#: ``x``: ``|(K Phi + C Phi diag(mu) + M Phi diag(mu)^2) x|`` against the same products of absolute
#: values (LAPACK's dense decomposition leaves ~1e-16; the updates measured 1e-16 to 1e-15)
BACKWARD_ERROR = 1e-12
#: largest change of the secular weights ``c`` recomputed from the roots (Loewner), relative to the
#: largest weight: a root that converged onto another's leaves one weight far off (measured 1e-13
#: to 3e-13 where all roots are found)
WEIGHTS_CHECK = 1e-12

_EPS4 = 4 * np.finfo(float).eps


@_jit
def _aberth(lam, c, anchor, tau, max_sweeps):
    """Aberth's iteration on ``1 + sum_i c_i / (lam_i - mu)`` for all its roots ``mu_k =
    lam[anchor[k]] + tau[k]``, in place, in Gauss-Seidel order. The pass over the poles that sums
    ``f`` also finds the pole nearest to the root, at which it is anchored after its step. A root
    whose step is below a hundredth of its distance to the nearest other root goes on by Newton's
    steps (the other roots' repulsion changes the path, not the roots: ``f(mu) = 0`` is the fixed
    point either way), one pass per step instead of two. A root is done when its step is below
    rounding of its offset or ``|f|`` below rounding of its terms. Returns the sweeps taken, -1
    where ``max_sweeps`` did not suffice."""
    n = lam.size
    done = np.zeros(n, np.bool_)
    alone = np.zeros(n, np.bool_)
    for sweep in range(max_sweeps):
        moved = False
        for k in range(n):
            if done[k]:
                continue
            j = anchor[k]
            t = tau[k]
            lj = lam[j]
            f = 1.0 + 0j
            fp = 0j
            s1 = 0j
            size = 1.0
            jb = j
            best = np.inf
            for i in range(n):
                d = (lam[i] - lj) - t
                m2 = d.real * d.real + d.imag * d.imag
                if m2 < best:
                    best = m2
                    jb = i
                if m2 == 0:
                    break
                r = d.conjugate() * (1.0 / m2)
                q = c[i] * r
                f += q
                fp += q * r
                s1 += r
                size += abs(q.real) + abs(q.imag)  # |q| within a factor sqrt(2), without a root
            if best == 0:  # on a pole exactly: step off it by rounding of the pole
                tau[k] = t + _EPS4 * (abs(lj) + 1e-300) * (1 + 1j)
                moved = True
                continue
            if abs(f) <= _EPS4 * size:
                done[k] = True
                continue
            s2 = 0j
            near = np.inf
            if not alone[k]:
                for l in range(n):
                    if l != k:
                        e = (lj - lam[anchor[l]]) + (t - tau[l])
                        e2 = e.real * e.real + e.imag * e.imag
                        near = min(near, e2)
                        s2 += e.conjugate() * (1.0 / e2)
            step = 1.0 / ((fp / f - s1) - s2)
            if not alone[k] and (step.real * step.real + step.imag * step.imag) < 1e-4 * near:
                alone[k] = True
            t = (lj - lam[jb]) + (t - step)  # anchored at the pole nearest before the step
            anchor[k] = jb
            tau[k] = t
            if abs(step) <= _EPS4 * abs(t):
                done[k] = True
            else:
                moved = True
        if not moved:
            return sweep + 1
    return -1


@_jit
def _first_offsets(lam, c):
    """First guess of the root started at each pole: ``-c_k / g_k``, ``g_k = 1 + sum_{i != k} c_i /
    (lam_i - lam_k)`` (the root near ``lam_k`` if the other terms held still), kept within half the
    distance to the nearest other pole; a real pole's guess is nudged off the real axis by 1e-6 of
    that distance, up for one and down for the next (Aberth's iteration keeps a symmetric start
    symmetric: two real roots that become a complex pair would stay on the axis)."""
    n = lam.size
    tau = np.empty(n, np.complex128)
    flip = 1.0
    for k in range(n):
        g = 1.0 + 0j
        near = np.inf
        for i in range(n):
            if i != k:
                dd = lam[i] - lam[k]
                m2 = dd.real * dd.real + dd.imag * dd.imag
                g += c[i] * dd.conjugate() * (1.0 / m2)
                near = min(near, m2)
        near = np.sqrt(near)
        t = -c[k] / g if g != 0 else 0j
        lim = 0.5 * near if near < np.inf else abs(t)
        if not abs(t) <= lim:
            t = t * (lim / abs(t))
        if t == 0:
            t = 1e-8 * (abs(lam[k]) + 1e-300) + 0j
        if lam[k].imag == 0:
            t = t + 1j * flip * 1e-6 * (lim if lim > 0 else abs(lam[k]) + 1e-300)
            flip = -flip
        tau[k] = t
    return tau


@_jit
def _loewner(lam, anchor, tau):
    """Weights ``c_i`` for which the roots ``mu_k = lam[anchor[k]] + tau[k]`` (as many as poles)
    are exact, ``prod_k (mu_k - lam_i) / prod_{l != i} (lam_l - lam_i)``, root ``k`` taken with pole
    ``k`` in each factor (ratios near 1 where the roots stay near their poles: no overflow)."""
    n = lam.size
    chat = np.empty(n, np.complex128)
    for i in range(n):
        p = 1.0 + 0j
        for k in range(n):
            dk = (lam[anchor[k]] - lam[i]) + tau[k]  # mu_k - lam_i
            p *= dk if k == i else dk / (lam[k] - lam[i])
        chat[i] = p
    return chat


@_jit
def _polish(lam, c, anchor, tau, real, steps):
    """Newton steps on ``f`` for the roots ``keep``-ed after :func:`_symmetric_roots` (each alone:
    they are separated now), a real root's step real: the symmetry's snapping moved roots by up to
    :data:`PAIR_TOL` of their size; two or three steps take them back to rounding."""
    n = lam.size
    for k in range(tau.size):
        j = anchor[k]
        lj = lam[j]
        t = tau[k]
        for _ in range(steps):
            f = 1.0 + 0j
            fp = 0j
            for i in range(n):
                d = (lam[i] - lj) - t
                m2 = d.real * d.real + d.imag * d.imag
                if m2 == 0:  # on a pole (its weight below rounding of the offset): stays there
                    fp = 0j
                    break
                r = d.conjugate() * (1.0 / m2)
                q = c[i] * r
                f += q
                fp += q * r
            if fp == 0:
                break
            step = f / fp
            if real[k]:
                step = step.real + 0j
            t = t - step
            if abs(step) <= _EPS4 * abs(t):
                break
        tau[k] = t


#: a root is real where its imaginary part is at most this fraction of its modulus, and the roots
#: of a pair must be conjugate to this fraction (Aberth's iteration does not keep the symmetry of
#: the real equation exactly: measured 1e-16 to 1e-14)
PAIR_TOL = 1e-10


def conjugate_pairs(lam: np.ndarray, tol: float):
    """The conjugate pairs of the roots ``lam`` of a real equation computed in complex arithmetic:
    ``(upper, lower, real)``, the indices of each pair's roots (``lower[k]`` the conjugate of
    ``upper[k]`` to ``tol`` of its size, pairs in order of real part and size of the imaginary one;
    stable sorts keep the given order among equal roots) and a mask of the real roots (imaginary part
    at most ``tol`` of the size), or None where the roots do not pair so.

    Parameters
    ----------
    lam : (N,) complex ndarray
        The roots.
    tol : float
        Relative tolerance of the pairing and of a real root's imaginary part.

    Returns
    -------
    tuple of (p,) int ndarray, (p,) int ndarray, (N,) bool ndarray, or None
    """
    size = np.abs(lam)
    real = np.abs(lam.imag) <= tol * size
    upper = np.flatnonzero(~real & (lam.imag > 0))
    lower = np.flatnonzero(~real & (lam.imag < 0))
    if upper.size != lower.size:
        return None
    upper = upper[np.lexsort((lam[upper].imag, lam[upper].real))]
    lower = lower[np.lexsort((-lam[lower].imag, lam[lower].real))]
    if np.any(np.abs(lam[lower] - lam[upper].conj()) > tol * size[upper]):
        return None
    return upper, lower, real


def _symmetric_roots(la, anchor, tau):
    """The roots made exactly real or exactly conjugate in pairs: ``(anchor, tau, keep, (upper,
    lower))`` with ``keep`` the indices of the roots kept (one of each pair, upper, and the real
    ones) and the pairs' indices, or None where the
    roots do not pair to :data:`PAIR_TOL`. A real root keeps its anchor if that pole is real (its
    offset made real), else is re-anchored at the nearest real pole."""
    mu = la[anchor] + tau
    pairs = conjugate_pairs(mu, PAIR_TOL)
    if pairs is None:
        return None
    ou, ol, real = pairs
    anchor, tau = anchor.copy(), tau.copy()
    partner = _partners(la)
    if partner is None:
        return None
    anchor[ol] = partner[anchor[ou]]
    tau[ol] = tau[ou].conj()
    rl = np.flatnonzero(real)
    on_real = la[anchor[rl]].imag == 0
    tau[rl[on_real]] = tau[rl[on_real]].real  # the offset from a real pole: its real part
    moved = rl[~on_real]
    if moved.size:  # anchored at a complex pole: at the nearest real one instead
        poles_real = np.flatnonzero(la.imag == 0)
        if not poles_real.size:
            return None
        mr = mu[moved].real
        near = poles_real[np.argmin(np.abs(la[poles_real][None, :] - mr[:, None]), axis=1)]
        tau[moved] = (mr - la[near].real) + 0j
        anchor[moved] = near
    return anchor, tau, np.sort(np.concatenate([ou, rl])), (ou, ol)


@_jit
def _vectors(lam, anchor, tau, a):
    """``z_ik = a_i / (lam_i - mu_k)`` (poles, roots) with ``lam_i - mu_k = (lam_i - lam[anchor[k]])
    - tau[k]``; a root on a pole (its weight below rounding of its offset) has that pole's mode,
    the unit vector."""
    n, m = lam.size, tau.size
    z = np.empty((n, m), np.complex128)
    for k in range(m):
        lk = lam[anchor[k]]
        t = tau[k]
        hit = -1
        for i in range(n):
            d = (lam[i] - lk) - t
            m2 = d.real * d.real + d.imag * d.imag
            if m2 == 0:
                hit = i
                break
            z[i, k] = a[i] * d.conjugate() * (1.0 / m2)
        if hit >= 0:
            for i in range(n):
                z[i, k] = 0j
            z[hit, k] = 1.0 + 0j
    return z


def _partners(lam: np.ndarray) -> np.ndarray | None:
    """``partner[i]``: the index of ``conj(lam_i)`` (itself for a real pole), or None where the poles
    are not exactly conjugate-closed."""
    order = np.lexsort((lam.imag, lam.real))
    conj_order = np.lexsort((-lam.imag, lam.real))
    partner = np.empty(lam.size, np.intp)
    partner[order] = conj_order
    if not np.array_equal(lam[partner], lam.conj()):
        return None
    return partner


def rank_one_modes(lam: np.ndarray, v: np.ndarray, w: np.ndarray, force: np.ndarray, direction: np.ndarray):
    """Eigenvalues and mode shapes of ``A + p r^T`` from the modes ``(lam, V, W = V^-1)`` of the
    real first-order matrix ``A`` (``V = [Phi; Phi diag(lam)]``), or None where the update does not
    apply or did not converge (the caller decomposes from scratch); the checks of the result are
    :func:`checked_modes`'. :func:`rank_one_roots` then :func:`rank_one_shapes`.

    Parameters
    ----------
    lam : (N,) complex ndarray
        Eigenvalues of ``A`` (``N = 2 n``, both roots of every pair, exactly conjugate).
    v, w : (N, N) complex ndarray
        Its eigenvectors and their inverse.
    force, direction : (n,) ndarray
        The rank-one change ``p r^T`` by its nonzero halves, ``p = [0, force]``, ``r = [direction,
        0]`` (a spring ``k`` along ``d`` added: ``force = -M^-1 d k``, ``direction = d``), real.

    Returns
    -------
    tuple of (N,) complex ndarray and (n, N) complex ndarray, or None
        ``(mu, Phi)``: the new eigenvalues (conjugate pairs side by side, exactly conjugate) and
        mode shapes (displacement rows).
    """
    roots = rank_one_roots(lam, v, w, force, direction)
    return None if roots is None else rank_one_shapes(roots)


def rank_one_roots(lam: np.ndarray, v: np.ndarray, w: np.ndarray, force: np.ndarray, direction: np.ndarray):
    """The first half of :func:`rank_one_modes`: the new eigenvalues only, and what the shapes are
    built from (:func:`rank_one_shapes`), or None. A configuration whose status is only tested for
    consistency needs its fastest rate, not its modes.

    Parameters
    ----------
    lam, v, w, force, direction :
        As :func:`rank_one_modes`.

    Returns
    -------
    tuple or None
        ``(mu, parts)``: the new eigenvalues (N,) in the order of :func:`rank_one_shapes`' and the
        parts of the shapes.
    """
    if not ENABLED:
        return None  # an FMU's NumPy copy decomposes from scratch: the root finder is compiled
    n = v.shape[0] // 2
    return rank_one_roots_top(lam, v[:n], w[:, n:] @ force, direction)


def rank_one_roots_top(lam: np.ndarray, v_top: np.ndarray, a: np.ndarray, direction: np.ndarray):
    """:func:`rank_one_roots` from the displacement rows of the eigenvectors and the modal force:
    what the update reads of the modes (a configuration that keeps its modes halved gives these
    without building its whole ``V`` and ``V^-1``).

    Parameters
    ----------
    lam : (N,) complex ndarray
        Eigenvalues, both roots of every conjugate pair.
    v_top : (n, N) complex ndarray
        The eigenvectors' displacement rows ``V[:n]``.
    a : (N,) complex ndarray
        ``V^-1[:, n:] force``.
    direction : (n,) ndarray
        As :func:`rank_one_modes`.

    Returns
    -------
    tuple or None
        As :func:`rank_one_roots`.
    """
    if not ENABLED:
        return None
    partner = _partners(lam)
    if partner is None:
        return None
    b = direction @ v_top
    scale = float(np.max(np.abs(lam), initial=0.0)) + float(np.linalg.norm(a) * np.linalg.norm(b))
    # poles whose terms of a b^T are rounding of the matrix keep their eigenvalue and mode
    kept = np.abs(a) * np.linalg.norm(b) + np.linalg.norm(a) * np.abs(b) <= 8 * np.finfo(float).eps * scale
    kept |= kept[partner]
    act = np.flatnonzero(~kept)
    if not act.size:
        return lam.copy(), (v_top, act, kept, None)
    la = np.ascontiguousarray(lam[act])
    c = a[act] * b[act]
    anchor = np.arange(la.size, dtype=np.int64)
    tau = _first_offsets(la, c)
    if _aberth(la, c, anchor, tau, MAX_SWEEPS) < 0:
        return None
    sym = _symmetric_roots(la, anchor, tau)
    if sym is None:
        return None
    anchor, tau, keep, (upper, lower) = sym
    ka, kt = anchor[keep], tau[keep]
    _polish(la, c, ka, kt, (kt.imag == 0) & (la[ka].imag == 0), POLISH_STEPS)
    tau[keep] = kt
    tau[lower] = tau[upper].conj()
    chat = _loewner(la, anchor, tau)
    # the weights' change as a change of a: |dc_i / b_i| |b|, against the matrix's scale
    moved = np.abs(chat - c) / np.abs(b[act]) * np.linalg.norm(b)
    if not (np.all(np.isfinite(chat)) and np.all(moved <= WEIGHTS_CHECK * scale)):
        return None
    anchor, tau = anchor[keep], tau[keep]
    mu_rep = la[anchor] + tau
    real = (tau.imag == 0) & (la[anchor].imag == 0)
    mu = np.concatenate([lam[kept], _paired(mu_rep, real)])
    return mu, (v_top, act, kept, (la, anchor, tau, chat / b[act], real))


def rank_one_shapes(roots) -> tuple:
    """The second half of :func:`rank_one_modes`: ``(mu, Phi)`` from :func:`rank_one_roots`' result.

    Parameters
    ----------
    roots : tuple
        :func:`rank_one_roots`' result (not None).

    Returns
    -------
    tuple of (N,) complex ndarray and (n, N) complex ndarray
    """
    mu, (v_top, act, kept, found) = roots
    if found is None:
        return mu, v_top.copy()
    la, anchor, tau, a_hat, real = found
    shapes = v_top[:, act] @ _vectors(la, anchor, tau, a_hat)
    return mu, np.concatenate([v_top[:, kept], _paired(shapes, real)], axis=1)


def _paired(x: np.ndarray, real: np.ndarray) -> np.ndarray:
    """The roots found (or their shapes, columns of ``x``), each complex one followed by its
    conjugate (exactly: the same numbers with the sign of the imaginary part flipped)."""
    cplx = ~real
    slot = np.arange(real.size) + np.concatenate(([0], np.cumsum(cplx)[:-1]))
    out = np.empty(x.shape[:-1] + (real.size + np.count_nonzero(cplx),), complex)
    out[..., slot] = x
    out[..., slot[cplx] + 1] = x[..., cplx].conj()
    return out


def checked_modes(mu: np.ndarray, phi: np.ndarray, mass: np.ndarray, damping: np.ndarray,
                  stiffness: np.ndarray) -> np.ndarray | None:
    """``V = [Phi; Phi diag(mu)]`` (2n, N) of updated modes, columns of unit norm, or None where a random probe ``x``
    shows a backward error in the quadratic eigenproblem above :data:`BACKWARD_ERROR`: ``(K Phi + C
    Phi diag(mu) + M Phi diag(mu)^2) x`` against the same products of absolute values, ``O(n N)``.

    Parameters
    ----------
    mu : (N,) complex ndarray
        Eigenvalues.
    phi : (n, N) complex ndarray
        Mode shapes.
    mass, damping, stiffness : (n, n) ndarray
        The configuration's ``M``, ``C``, ``K``.

    Returns
    -------
    (2n, N) complex ndarray or None
    """
    n = phi.shape[0]
    rng = np.random.default_rng(0)
    x = rng.standard_normal(mu.size) + 1j * rng.standard_normal(mu.size)
    mats = (stiffness, damping, mass)
    res = np.zeros(n, complex)
    size = np.zeros(n)
    aphi = np.abs(phi.real) + np.abs(phi.imag)  # |phi| within sqrt(2): a scale, no roots
    for q, m in enumerate(mats):
        xq = x * mu ** q
        u = phi @ xq
        res += m @ u.real + 1j * (m @ u.imag)
        size += np.abs(m) @ (aphi @ np.abs(xq))
    if not np.all(np.abs(res) <= BACKWARD_ERROR * np.max(size)):
        return None
    # unit columns, as LAPACK's (the update's scale is arbitrary): |[phi; mu phi]|^2 = |phi|^2 (1 + |mu|^2)
    sq = np.einsum("ij,ij->j", phi.real, phi.real) + np.einsum("ij,ij->j", phi.imag, phi.imag)
    unit = 1.0 / np.sqrt(sq * (1.0 + mu.real ** 2 + mu.imag ** 2))
    v = np.empty((2 * n, mu.size), complex)
    np.multiply(phi, unit, out=v[:n])
    np.multiply(v[:n], mu, out=v[n:])
    return v
