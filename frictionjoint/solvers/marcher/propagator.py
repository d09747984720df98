"""Closed-form motion of a piecewise-linear friction system inside one configuration.

In a configuration (which sliders stick, which slip and which way) the structure obeys

    M x'' + C x' + K_c x = F_const + f_c cos(w t) + f_s sin(w t) + G^T lam,   G x' = 0,

with ``K_c`` the structure stiffness plus the springs of the stuck Jenkins sliders, ``G`` the
directions of the stuck rigid sliders and ``lam`` their holding forces. With ``x = x0 + N q``
(``N`` an orthonormal basis of the null space of ``G``) the reduced first-order system
``y' = A y + b(t)``, ``y = [q, q']``, is diagonalised once per configuration,
``A = V diag(lam) V^-1``, and every mode is solved in closed form:

    eta(tau) = e^{lam tau} eta0 + beta0 E(lam, 0, tau) + g+ E(lam, iw, tau) + g- E(lam, -iw, tau),
    E(lam, mu, tau) = (e^{mu tau} - e^{lam tau}) / (mu - lam)  (= tau e^{lam tau} phi1((mu-lam) tau)),

which stays exact at resonance (``lam = +-iw``) and for rigid-body modes (``lam = 0``). No time
step is involved: the state, and every quantity linear in state and forcing, is exact at any time.
Defective configurations (ill-conditioned eigenvectors) fall back to the matrix exponential of the
augmented system ``[y, cos, sin, 1]``.
"""
from __future__ import annotations

import cmath
import math

import numpy as np
import scipy.linalg
import scipy.linalg.lapack

from . import mode_update, piece_kernels

__all__ = ["ConfigData", "Interval", "Observables"]

#: stuck Jenkins springs stiffer than this multiple of the structure's largest diagonal stiffness
#: have their configuration's eigenpairs refined (:func:`_refine_modes`)
REFINE_RATIO = 100.0

def _phi1(z: np.ndarray) -> np.ndarray:
    """(e^z - 1)/z, accurate for all complex z: NumPy's complex ``expm1`` is accurate near 0
    (agrees with the 22-term Taylor series formerly used below |z| = 0.5 to 4.5e-16), 1 at 0."""
    z = np.asarray(z, dtype=complex)
    zero = z == 0
    if zero.any():
        return np.where(zero, 1.0 + 0j, np.expm1(z) / np.where(zero, 1.0, z))
    return np.expm1(z) / z


def _E(lam: np.ndarray, mu: complex, tau: np.ndarray) -> np.ndarray:
    """E(lam, mu, tau) for lam (p, 1), tau (1, k): exact integral of e^{lam (tau-s)} e^{mu s}.

    ``tau e^{lam tau} phi1((mu - lam) tau)``, or the same ``tau e^{mu tau} phi1((lam - mu) tau)``
    where ``Re(mu - lam) > 0``: the first form overflows to ``0 * inf`` there (a stiff decaying
    mode, ``e^{lam tau}`` underflowing, over a long piece). Compiled
    (:func:`.piece_kernels.resonant_terms`, the same two forms) where the kernels are."""
    if piece_kernels.ENABLED:
        return piece_kernels.resonant_terms(np.ascontiguousarray(lam, dtype=complex).ravel(), complex(mu),
                                            np.ascontiguousarray(tau, dtype=float).ravel())
    z = (mu - lam) * tau
    up = z.real > 0
    if not up.any():
        return tau * np.exp(lam * tau) * _phi1(z)
    return tau * np.where(up, np.exp(mu * tau) * _phi1(np.where(up, -z, 0.0)),
                          np.exp(lam * tau) * _phi1(np.where(up, 0.0, z)))


def _refine_modes(lam, v, mr, cr, kr, dr, kt, iterations: int = 3):
    """Newton refinement of the eigenpairs of ``lam^2 M + lam C + K + sum kt d d^T`` with the
    residual in spring form (``K phi + sum kt d (d . phi)``).

    With stuck springs far stiffer than the structure (kt/k ~ 1e10) ``K_c = K + kt d d^T`` cannot
    even be stored to better than eps kt absolutely, and ``eig`` of the first-order matrix
    (norm ~ kt) gives the slow modes with relative errors ~ eps kt / k (1e-6); the spring-form
    residual is exact to eps |K phi|, so the refinement restores them to rounding.
    """
    m = mr.shape[0]
    kc = kr + (dr * kt) @ dr.T
    lam = lam.copy()
    v = v.copy()
    for i in range(lam.size):
        li = lam[i]
        phi = v[:m, i].copy()
        nrm = np.linalg.norm(phi)
        if nrm == 0 or li == 0:
            continue
        phi /= nrm
        for _ in range(iterations):
            r = (li * li) * (mr @ phi) + li * (cr @ phi) + kr @ phi + dr @ (kt * (dr.T @ phi))
            q = (li * li) * mr + li * cr + kc
            dq = (2 * li) * (mr @ phi) + cr @ phi
            big = np.zeros((m + 1, m + 1), complex)
            big[:m, :m] = q
            big[:m, m] = dq
            big[m, :m] = phi.conj()
            try:
                sol = np.linalg.solve(big, np.concatenate([-r, [0.0]]))
            except np.linalg.LinAlgError:
                break
            if not np.all(np.isfinite(sol)):
                break
            phi = phi + sol[:m]
            li = li + sol[m]
        lam[i] = li
        v[:m, i] = phi * nrm
        v[m:, i] = li * phi * nrm
    return lam, v


#: largest entry of ``W V - I`` for which :func:`_left_modes`' rows are taken as ``V^-1`` (its
#: rounding is ~ eps |lam_max / lam_min|: 1e-10 at kt/k = 1e12; a repeated eigenvalue whose
#: vectors eig returned not M-orthogonal gives O(1))
LEFT_MODES_CHECK = 1e-6


def _symmetric(a: np.ndarray) -> bool:
    """Whether the square ``a`` is symmetric to a few roundings of its largest entry."""
    return bool(np.max(np.abs(a - a.T), initial=0.0) <= 4 * np.finfo(float).eps * np.max(np.abs(a), initial=0.0))


def _left_modes(lam, v, mr, cr, kr):
    """``V^-1`` of refined modes (:func:`_refine_modes`) from their shapes, or None where it does
    not apply: with ``Mr``, ``Cr`` and ``Kr`` symmetric, the left eigenvector of the mode ``(lam,
    [phi, lam phi])`` of the first-order matrix is ``[lam Mr phi + Cr phi, Mr phi]^T`` over ``2 lam
    phi^T Mr phi + phi^T Cr phi`` (its transpose times ``A`` is ``lam`` times it, by the mode's own
    ``phi^T (lam^2 Mr + lam Cr + Kr) = 0``).

    ``inv(V)`` loses ~ eps cond(V) of each row, and cond(V) grows with the spread of the rates: at
    kt/k = 1e12 the soft modes' rows were 1.1e-10 off, the modal loads of a stuck spring's piece
    1.2e-12 of the motion; these rows are exact to rounding of the shapes. ``W V - I`` is checked
    (:data:`LEFT_MODES_CHECK`): a repeated eigenvalue's shapes need not be M-orthogonal, and the
    rows then are not the inverse."""
    if not (_symmetric(mr) and _symmetric(cr) and _symmetric(kr)):
        return None
    m = mr.shape[0]
    phi = v[:m]
    mp = mr @ phi
    cp = cr @ phi
    den = 2 * lam * np.einsum("ij,ij->j", phi, mp) + np.einsum("ij,ij->j", phi, cp)
    if not np.all(np.isfinite(den) & (den != 0)):
        return None
    w = np.hstack([(lam * mp + cp).T, mp.T]) / den[:, None]
    check = w @ v
    check[np.diag_indices_from(check)] -= 1.0
    if not np.all(np.isfinite(w)) or np.max(np.abs(check)) > LEFT_MODES_CHECK:
        return None
    return w


#: condition number of the (balanced) eigenvector matrix beyond which a configuration is treated
#: as defective (matrix exponential instead of modes)
DEFECTIVE_COND = 1e8
#: largest ``|V W z - z|`` over ``|z|`` on a random probe ``z`` for which :func:`_left_inverse`'s
#: rows are taken as an updated configuration's ``V^-1`` (measured on the damping families'
#: updates: 1e-14 at 20 DOFs, up to 1.9e-12 at 100 and 4e-12 at 200, from the shapes' rounding
#: over the gaps of clustered roots; a cluster whose shapes lost their mutual orthogonality gives
#: O(1) and takes the inverse)
LEFT_PROBE = 1e-10
#: classically damped mode pairs closer than this fraction of their rate (near critical damping)
#: are left to the general path (:func:`_classical_modes`)
CLASSICAL_SEPARATION = 1e4


def _system_cached(system, name: str, build, *inputs):
    """``build()`` cached on the system under ``name``, computed again where one of ``inputs`` (the
    system's arrays it is made of) changed since (a user's in-place edit of the mass matrix must
    not meet a stale inverse): an ``n^2`` comparison per configuration, against its ``n^3``."""
    cached = system.__dict__.get(name)
    if cached is not None and all(np.array_equal(a, b) for a, b in zip(cached[0], inputs)):
        return cached[1]
    value = build()
    system.__dict__[name] = (tuple(np.array(a, copy=True) for a in inputs), value)
    return value


def _mass_proportional(system) -> float | None:
    """``alpha`` if the system's damping is ``alpha M`` to rounding (undamped: 0), else None.

    Then every configuration without contacts is classically damped: its modes are those of the
    symmetric pencil ``(K_c, M)`` (reduced by the stuck rigid sliders' null space), whatever the
    stuck springs, and :func:`_classical_modes` gives them from ``eigh``."""
    c, mass = system.damping, system.mass

    def build():
        alpha = float(np.sum(c * mass) / np.sum(mass * mass))
        # the entries of alpha M, rounded, differ from C by at most a few eps of C's largest entry
        tol = 8 * np.finfo(float).eps * np.max(np.abs(c), initial=0.0)
        exact = bool(np.max(np.abs(c - alpha * mass), initial=0.0) <= tol)
        return alpha if exact and alpha >= 0 else None
    return _system_cached(system, "_mass_proportional", build, c, mass)


def _identity(system) -> np.ndarray:
    """The ``n x n`` identity, ``N`` of every configuration without stuck rigid sliders: one
    read-only array per system instead of one per configuration."""
    eye = system.__dict__.get("_identity")
    if eye is None:
        eye = system.__dict__["_identity"] = np.eye(system.n_dof)
        eye.flags.writeable = False
    return eye


def _mass_inverse(system) -> np.ndarray:
    """``M^-1`` of the system (the reduced mass of every configuration without stuck rigid sliders)."""
    return _system_cached(system, "_mass_inverse", lambda: np.linalg.inv(system.mass), system.mass)


def _mass_factor(system) -> np.ndarray | None:
    """Cholesky factor of the system's mass matrix (``M = L L^T``): ``L`` (n, n), or its diagonal
    ``sqrt(m_i)`` (n,) where ``M`` is diagonal (lumped masses: the reductions below are scalings,
    exact as the triangular solves they replace); None where ``M`` is not positive definite (the
    general path decides then)."""
    mass = system.mass

    def build():
        diag = np.diag(mass)
        try:
            if np.count_nonzero(mass) == np.count_nonzero(diag) and np.all(diag > 0):
                return np.sqrt(diag)
            return np.linalg.cholesky(mass)
        except np.linalg.LinAlgError:
            return None
    return _system_cached(system, "_mass_factor", build, mass)


def _tridiagonal(a: np.ndarray) -> bool:
    """Whether the square ``a`` has no nonzero entry off its three central diagonals (a chain of
    lumped masses and springs: a count of nonzeros, ``n^2``)."""
    return a.shape[0] > 2 and (np.count_nonzero(a) == np.count_nonzero(np.diagonal(a))
                               + np.count_nonzero(np.diagonal(a, 1)) + np.count_nonzero(np.diagonal(a, -1)))


def _pencil(mr, kr, factor):
    """``(w^2, Phi, Phi^T Mr)`` of the symmetric pencil ``Kr phi = w^2 Mr phi`` (:func:`_classical_modes`).

    A tridiagonal ``L^-1 Kr L^-T`` (a chain with lumped masses) goes to LAPACK's ``stevd``
    (:func:`scipy.linalg.eigh_tridiagonal`): ``syevd``, which ``eigh`` calls, reduces a matrix to
    tridiagonal form with Householder reflectors, which are the identity (``tau = 0``, exactly)
    where it is tridiagonal already, and then calls the same divide and conquer ``stedc``: the same
    numbers bit for bit, without the reduction's ``4/3 n^3`` and the back-transformation's ``2 n^3``
    (3.1 -> 1.7 ms at n = 200, 17 -> 6.3 ms at 400)."""
    if factor is None:
        w2, phi = scipy.linalg.eigh(kr, mr, check_finite=False)
        return w2, phi, phi.T @ mr
    if factor.ndim == 1:  # diagonal mass: L = diag(sqrt(m))
        ks = kr / factor[:, None] / factor[None, :]
        if _tridiagonal(ks):  # eigh reads the lower triangle: its subdiagonal
            w2, psi = scipy.linalg.eigh_tridiagonal(np.diagonal(ks).copy(), np.diagonal(ks, -1).copy(),
                                                    check_finite=False, lapack_driver="stevd")
        else:
            w2, psi = scipy.linalg.eigh(ks, check_finite=False, driver="evd")
        return w2, psi / factor[:, None], psi.T * factor[None, :]  # Phi^T M = Psi^T L^T
    half = scipy.linalg.solve_triangular(factor, kr, lower=True, check_finite=False)
    ks = scipy.linalg.solve_triangular(factor, half.T, lower=True, check_finite=False)
    w2, psi = scipy.linalg.eigh(ks, check_finite=False, driver="evd")
    phi = scipy.linalg.solve_triangular(factor.T, psi, lower=False, check_finite=False)
    return w2, phi, (factor @ psi).T  # Phi^T M = Psi^T L^T


def _modally_damped(system):
    """The structure's own modes where its damping is classical but not mass-proportional (Rayleigh,
    stiffness-proportional, modal damping): ``(alpha, pencil)`` with ``pencil = (w^2, Phi, Phi^T M)``
    of ``K phi = w^2 M phi`` and ``alpha`` (n,) the diagonal of ``Phi^T C Phi``, else None.

    Classical: the off-diagonal entries of ``Phi^T C Phi`` are rounding of the products, at most
    ``64 n eps`` of its largest entry (the rounding of ``Phi^T K Phi``'s off-diagonal entries is ``~ n
    eps`` of its largest one). Then every configuration whose stiffness is the structure's (no stuck
    Jenkins spring, no contact, no stuck rigid slider) has these modes, each with its own
    ``alpha_i`` (:func:`_classical_modes`): under Rayleigh damping the configurations in which all
    joints slip, which a stuck joint's spring makes non-classical. Cached per system."""
    c, mass, k = system.damping, system.mass, system.stiffness

    def build():
        if not (_symmetric(c) and _symmetric(k) and _symmetric(mass)):
            return None
        try:
            w2, phi, pt = _pencil(mass, k, _mass_factor(system))
        except (np.linalg.LinAlgError, ValueError):
            return None
        d = phi.T @ c @ phi
        alpha = np.diagonal(d).copy()
        off = d - np.diag(alpha)
        if not np.max(np.abs(off), initial=0.0) <= 64 * c.shape[0] * np.finfo(float).eps * np.max(np.abs(d), initial=0.0):
            return None
        return alpha, (w2, phi, pt)
    return _system_cached(system, "_modally_damped", build, c, mass, k)


def _classical_modes(mr, kr, alpha, factor: np.ndarray | None = None, pencil=None):
    """Eigenpairs of ``A = [[0, I], [-Mr^-1 Kr, -alpha I]]`` from the symmetric pencil ``Kr phi =
    w^2 Mr phi`` (``Phi^T Mr Phi = I``): per mode ``lam = -alpha/2 +- sqrt(alpha^2/4 - w^2)``,
    ``V = [[Phi, Phi], [Phi lam+, Phi lam-]]`` and ``V^-1`` in closed form from ``Phi^T Mr``.

    ``alpha``: one rate for every mode (mass-proportional damping) or one per mode (n,), with
    ``pencil`` the modes it is for (:func:`_modally_damped`). Returns ``(lam, V, inverse, (Phi, Phi^T
    Mr, w^2, lam+, lam-))``, the modes halved
    (:func:`_half_modes`): ``V`` is ``2m x p``, ``V^-1`` (its left inverse on real states,
    ``p x 2m``) in factored form, ``inverse = (rows, left, right)`` with ``V^-1 = [left rows,
    right rows]`` (:func:`_inverse`). ``eigh`` of an ``m x m`` symmetric matrix instead of ``eig``
    of the ``2m x 2m`` first-order matrix, an SVD for its condition and an inverse: a fortieth of
    the work at m = 200. ``factor``: the Cholesky factor ``L`` of ``Mr`` where it is the same for
    every configuration (the system's mass), so that the pencil is reduced to ``L^-1 Kr L^-T`` by
    two triangular solves (LAPACK's ``sygv`` does the same, but factors ``Mr`` again each time).
    None where a mode pair is (nearly) defective (``lam+ ~ lam-``: critical damping, an undamped
    rigid-body mode), where the caller's general path decides, or where ``Kr`` is not symmetric."""
    if pencil is not None:  # the structure's own modes (:func:`_modally_damped`)
        w2, phi, pt = pencil
    else:
        # K_c is symmetric by construction without contacts; reduced by a null space, to rounding
        if np.max(np.abs(kr - kr.T)) > 16 * np.finfo(float).eps * np.max(np.abs(kr)):
            return None
        try:
            w2, phi, pt = _pencil(mr, kr, factor)
        except (np.linalg.LinAlgError, ValueError):
            return None
    root = np.sqrt((0.25 * alpha * alpha - w2).astype(complex))
    lp, lm = -0.5 * alpha + root, -0.5 * alpha - root
    diff = lm - lp
    scale = np.maximum(np.abs(lp), np.abs(lm))
    # the closed-form inverse divides by lam- - lam+: its rounding grows as eps |lam| / |lam- -
    # lam+|; beyond CLASSICAL_SEPARATION (1e-12 of the motion) the general path decides
    if np.any(np.abs(diff) * CLASSICAL_SEPARATION <= scale) or not np.all(np.isfinite(root)):
        return None
    lam, v, inverse = _half_modes(phi, pt, lp, lm)
    return lam, v, inverse, (phi, pt, w2, lp, lm)


def _half_modes(phi, pt, lp, lm):
    """``(lam, V, (rows, left, right))`` of the classical modes, a conjugate pair as one mode: the
    state is real, so the pair's two terms are complex conjugates and their sum is twice the real
    part of the first's; every consumer takes the real part of its modal sums (the state ``Re(V
    eta)``, the event functions, the Fourier integrals), so the ``lam-`` half of each pair is left
    out and its ``lam+`` column of ``V`` doubled. Pairs with real roots (over-damped, or a
    rigid-body mode under damping) keep both. Half the modes: half the work of every search, state
    and integral, half the memory.

    ``V^-1 = [left rows, right rows]`` (``left``, ``right`` (p,) complex scale the real rows
    ``Phi^T Mr`` of the kept modes, :func:`_inverse`) is kept factored: a real state ``[0, u]``
    (every piece's start and constant load) has modal coordinates ``right (rows u)``; the complex
    ``p x 2m`` matrix is never needed by the march."""
    m = lp.size
    # a conjugate pair exactly: the complex square root of a negative real is purely imaginary
    pair = (lp.real == lm.real) & (lp.imag > 0) & (lp.imag == -lm.imag)
    if pair.all():  # every mode under-damped: no reordering, no copies
        lam, other, shape, rows, weight = lp, lm, phi, pt, 2.0
    else:
        single = np.flatnonzero(~pair)
        idx = np.concatenate([np.flatnonzero(pair), single])
        lam = np.concatenate([lp[idx], lm[single]])
        other = np.concatenate([lm[idx], lp[single]])  # the pair's other root, per kept mode
        shape = np.concatenate([phi[:, idx], phi[:, single]], axis=1)
        rows = np.concatenate([pt[idx], pt[single]])
        weight = np.concatenate([np.where(pair[idx], 2.0, 1.0), np.ones(single.size)])
    v = np.empty((2 * m, lam.size), complex)
    np.multiply(shape, weight, out=v[:m])
    np.multiply(v[:m], lam, out=v[m:])
    inv_d = 1.0 / (other - lam)
    return lam, v, (rows, other * inv_d, -inv_d)


def _inverse(rows, left, right, half: bool = False) -> np.ndarray:
    """``V^-1 = [left rows, right rows]`` (p, 2m) of :func:`_half_modes`'s factored form, or its
    right half ``right rows`` (p, m) (the columns a state ``[0, u]`` meets): the entries of the
    matrix the modes were built with before (the same products)."""
    m = rows.shape[1]
    if half:
        return right[:, None] * rows
    w = np.empty((rows.shape[0], 2 * m), complex)
    np.multiply(left[:, None], rows, out=w[:, :m])
    np.multiply(right[:, None], rows, out=w[:, m:])
    return w


def _full_modes(phi, pt, lp, lm):
    """``(lam, V, V^-1)`` of the classical modes with both roots of every pair (square ``V``)."""
    m = lp.size
    lam = np.concatenate([lp, lm])
    v = np.empty((2 * m, 2 * m), complex)
    v[:m, :m] = phi
    v[:m, m:] = phi
    np.multiply(phi, lp, out=v[m:, :m])
    np.multiply(phi, lm, out=v[m:, m:])
    inv_d = 1.0 / (lm - lp)
    w = np.empty((2 * m, 2 * m), complex)
    np.multiply((lm * inv_d)[:, None], pt, out=w[:m, :m])
    np.multiply(-inv_d[:, None], pt, out=w[:m, m:])
    np.multiply((-lp * inv_d)[:, None], pt, out=w[m:, :m])
    np.multiply(inv_d[:, None], pt, out=w[m:, m:])
    return lam, v, w


def _general_modes(a):
    """Eigenpairs of the first-order matrix ``a``: ``(lam, (T, V), V^-1)``, or ``(lam, None, None)``
    where ``a`` is (nearly) defective.

    Eigenvectors of the balanced matrix ``B = T^-1 A T`` (``T`` diagonal: powers of 2, no
    rounding), ``V = T V_B``: the conditioning of ``V_B`` says whether the configuration is
    (near-)defective; that of ``V`` also carries the scales of the coordinates (a root rotation
    [rad] and translations [m] beside modal coordinates, masses of 1e-5 and 1 kg: cond(V) ~ 2e8
    for cond(V_B) ~ 1e2), which would flag well-conditioned configurations as defective and send
    them to the matrix exponential. The condition number is the 1-norm one, ``|V_B|_1 |V_B^-1|_1``,
    from the inverse the modal form needs anyway (no SVD)."""
    ab, (tsc, _) = scipy.linalg.matrix_balance(a, permute=False, separate=True)
    lam, vb = np.linalg.eig(ab)
    try:
        wb = _real_inverse(lam, vb)
    except np.linalg.LinAlgError:
        return lam, None, None
    cond = np.linalg.norm(vb, 1) * np.linalg.norm(wb, 1)
    if not np.isfinite(cond) or cond > DEFECTIVE_COND:
        return lam, None, None
    vb = vb.astype(complex, copy=False)  # complex already where a pair is (the usual case): no copy
    vb *= tsc[:, None]
    wb /= tsc[None, :]  # V^-1 = V_B^-1 T^-1
    return lam, (tsc, vb), wb


def _symmetric_pencil(system) -> bool:
    """Whether the system's ``M``, ``C`` and ``K`` are symmetric (to a few roundings): then so is
    every configuration's (no contacts: ``K_c`` adds springs ``k d d^T``), and the left
    eigenvectors of its first-order matrix follow from the right ones (:func:`_left_inverse`)."""
    mass, c, k = system.mass, system.damping, system.stiffness
    return _system_cached(system, "_symmetric_pencil",
                          lambda: _symmetric(mass) and _symmetric(c) and _symmetric(k), mass, c, k)


def _left_mass(system) -> np.ndarray:
    """The system's mass as :func:`_left_inverse` and :meth:`ConfigData.left_product` take it: its
    diagonal (m,) where the masses are lumped (:func:`_mass_factor`: products are scalings), else the
    matrix; one array per system."""
    mass = system.mass
    factor = _mass_factor(system)
    return _system_cached(system, "_left_mass",
                          lambda: np.diag(mass).copy() if factor is not None and factor.ndim == 1 else mass, mass)


def _left_inverse(mu, v, mass, damping, tsc):
    """The modes ``(mu, V = [Phi; Phi diag(mu)])`` of a symmetric pencil halved (:func:`_halved_modes`:
    ``(lam, V, V^-1, p)``, the first root of each of the ``p`` conjugate pairs then the real ones)
    with the rows of ``V^-1`` from their shapes (:func:`_left_modes`' rows: ``[mu M phi + C phi, M
    phi]^T`` over ``2 mu phi^T M phi + phi^T C phi``) and the scale of each row against the halved
    shapes (:meth:`ConfigData.left_product`: the configuration keeps the scale, not the rows), or None where the pairs do not lie side by side
    as exact conjugates (the updates build them so) or a random probe shows ``|Re(V W z) - z| >
    LEFT_PROBE |z|`` in the balanced coordinates (``tsc``, :func:`_general_modes`). One ``N/2 x m x
    m`` product with ``C`` instead of the inverse of the ``2m x 2m`` real matrix (getrf + getri: 13
    of the 24 ms of an update at 200 DOFs); ``mass`` as :func:`_left_mass` gives it (lumped: a scaling)."""
    m = mass.shape[0]
    first = np.flatnonzero(mu.imag > 0)
    second = first + 1
    if (second.size and second[-1] >= mu.size) or 2 * first.size != np.count_nonzero(mu.imag) \
            or not (np.array_equal(mu[second], mu[first].conj())
                    and np.array_equal(v[:m, second], v[:m, first].conj())):
        return None
    keep = np.concatenate([first, np.flatnonzero(mu.imag == 0)])
    lam = mu[keep]
    vh = np.take(v, keep, axis=1)
    phi = vh[:m]
    # the rows laid out as V^-1's (C order): products with Phi^T (C symmetric: Phi^T C = (C Phi)^T)
    re_t, im_t = phi.real.T, phi.imag.T
    w = np.empty((keep.size, 2 * m), complex)
    mp_t = w[:, m:]
    if mass.ndim == 1:  # lumped masses: a column scaling
        np.multiply(phi.T, mass, out=mp_t)
    else:
        mp_t.real[...] = re_t @ mass
        mp_t.imag[...] = im_t @ mass
    cp_t = w[:, :m]
    cp_t.real[...] = re_t @ damping
    cp_t.imag[...] = im_t @ damping
    den = 2 * lam * np.einsum("ji,ij->i", phi, mp_t) + np.einsum("ji,ij->i", phi, cp_t)
    if not np.all(np.isfinite(den) & (den != 0)):
        return None
    cp_t += lam[:, None] * mp_t
    w /= den[:, None]
    p = int(first.size)
    vh[:, :p] *= 2.0  # a power of 2: exact
    z = np.random.default_rng(0).standard_normal(2 * m)
    back = (vh @ (w @ (tsc * z))).real / tsc
    if not (np.all(np.isfinite(w)) and np.max(np.abs(back - z)) <= LEFT_PROBE * np.max(np.abs(z))):
        return None
    scale = 1.0 / den
    scale[:p] *= 0.5  # the rows from the halved vectors (their 2 in Phi): ConfigData.left_product
    return lam, vh, w, p, scale


def _left_times(mat: np.ndarray, z: np.ndarray) -> np.ndarray:
    """``M z`` (``mat`` the mass matrix, or its diagonal (m,) where the masses are lumped: a
    scaling) or ``C z``, for ``z`` (m,) or (m, k)."""
    if mat.ndim == 1:
        return mat * z if z.ndim == 1 else mat[:, None] * z
    return mat @ z


def _halved_modes(lam, v, w):
    """General modes halved as classical ones are (:func:`_half_modes`): ``(lam, V, V^-1, p)`` with
    the first root of each of the ``p`` conjugate pairs (``Im lam > 0``, its vector times 2) then
    the real roots, and their rows of ``V^-1``; a real state is ``Re(V e^{lam t} V^-1 z)``, the
    march's real-part rule. Half the memory of a configuration's modes (10 of the 25 MB a
    configuration held at 400 DOFs) and half the work of every product with them. Only where the
    pairs lie side by side as exact conjugates, roots, vectors and rows (``eig`` of a real matrix,
    :func:`_real_inverse`, the rank-one updates build them so): else None (kept whole).
    :func:`_unhalved_modes` gives the same numbers back."""
    first = np.flatnonzero(lam.imag > 0)
    second = first + 1
    if not first.size or second[-1] >= lam.size or 2 * first.size != np.count_nonzero(lam.imag) \
            or not (np.array_equal(lam[second], lam[first].conj()) and np.array_equal(v[:, second], v[:, first].conj())
                    and np.array_equal(w[second], w[first].conj())):
        return None
    keep = np.concatenate([first, np.flatnonzero(lam.imag == 0)])
    vh = np.take(v, keep, axis=1)  # its own array (v[:, keep] is a view of a transposed copy)
    vh[:, :first.size] *= 2.0  # a power of 2: exact
    return lam[keep], vh, w[keep], int(first.size)


def _unhalved(x: np.ndarray, p: int, axis: int = -1, half: bool = False) -> np.ndarray:
    """``x`` (roots, vectors or rows of :func:`_halved_modes`, ``p`` pairs, along ``axis``) whole:
    each pair's entry (halved where ``half``: the vectors carry the pair's 2) and its conjugate side
    by side, then the real roots'; the same numbers as before halving (C-ordered, as they were)."""
    shape = list(x.shape)
    shape[axis] += p
    out = np.empty(shape, complex)
    o, h = np.moveaxis(out, axis, -1), np.moveaxis(x, axis, -1)
    first = np.arange(0, 2 * p, 2)
    o[..., first] = 0.5 * h[..., :p] if half else h[..., :p]
    o[..., first + 1] = o[..., first].conj()
    o[..., 2 * p:] = h[..., p:]
    return out


def _unhalved_modes(lam, v, w, p: int):
    """``(lam, V, V^-1)`` whole from :func:`_halved_modes`' (``p`` pairs) (:func:`_unhalved`)."""
    return _unhalved(lam, p), _unhalved(v, p, half=True), _unhalved(w, p, axis=0)


def _norm1(a: np.ndarray) -> float:
    """The 1-norm of a complex matrix to within a factor ``sqrt(2)`` (from above): the largest column
    sum of ``|Re| + |Im|``."""
    return float(np.max(np.abs(a.real).sum(axis=0) + np.abs(a.imag).sum(axis=0), initial=0.0))


def _inverse_real(r: np.ndarray) -> np.ndarray:
    """The inverse of the real square matrix ``r`` by LAPACK's ``dgetrf`` and ``dgetri`` (in place
    where ``r`` is Fortran-ordered and may be overwritten): a third fewer flops than NumPy's
    ``inv`` (``getrf`` then ``getrs`` against the identity; 5.9 against 8.4 ms at 400 x 400 on one
    thread). Called directly: SciPy's ``inv`` (1.17) also tests the matrix's structure and
    condition, warns where it is ill-conditioned (a defective configuration goes to the
    exponential without a warning) and crashed on a singular symmetric one. Raises
    ``LinAlgError`` where ``r`` is singular."""
    lu, piv, info = scipy.linalg.lapack.dgetrf(r, overwrite_a=True)
    if info == 0:
        inv, info = scipy.linalg.lapack.dgetri(lu, piv, overwrite_lu=True)
    if info != 0:
        raise np.linalg.LinAlgError("singular matrix" if info > 0 else f"LAPACK argument {-info} invalid")
    return inv


def _real_inverse(lam, vb, exact: bool = False) -> np.ndarray:
    """``V^-1`` (complex) of the eigenvectors of a real matrix from the inverse of the real matrix
    ``R`` of their real and imaginary parts: a complex pair ``v, conj(v)`` (``eig`` of a real matrix
    gives them side by side, exactly conjugate: LAPACK's ``dgeev`` returns ``Re v, Im v``) has the
    columns ``Re v, Im v`` in ``R``, and the rows ``rho_1, rho_2`` of ``R^-1`` give the rows ``(rho_1 -+
    i rho_2) / 2`` of ``V^-1``. A real inverse is a quarter of a complex one's work (28 of the 76 ms
    of a configuration's decomposition at 200 DOFs). Falls back to the complex inverse where the
    pairs are not laid out so; ``exact``: the vectors of the pairs are known to be exact conjugates
    (built so), only the roots' layout is checked. Raises ``LinAlgError`` where ``V`` is singular."""
    if not np.iscomplexobj(vb):  # every eigenvalue real
        return _inverse_real(np.array(vb, order="F")).astype(complex)
    first = np.flatnonzero(lam.imag > 0)
    second = first + 1
    if (second.size and second[-1] >= lam.size) or 2 * first.size != np.count_nonzero(lam.imag) \
            or not (np.array_equal(lam[second], lam[first].conj())
                    and (exact or np.array_equal(vb[:, second], vb[:, first].conj()))):
        return np.linalg.inv(vb)
    r = np.empty(vb.shape, order="F")  # LAPACK's layout: getrf and getri work on it in place
    r[...] = vb.real
    r[:, second] = vb[:, first].imag
    ri = _inverse_real(r)
    w = np.empty(ri.shape, complex)  # written through its real and imaginary views: no temporaries
    w.real[...] = ri
    w.imag[...] = 0.0
    half_im = 0.5 * ri[second]
    w.real[first] *= 0.5
    w.real[second] = w.real[first]
    w.imag[first] = -half_im
    w.imag[second] = half_im
    return w


def _first_order(mr_inv, kr, cr, diagonal: bool) -> np.ndarray:
    """``A = [[0, I], [-Mr^-1 Kr, -Mr^-1 Cr]]`` (2m, 2m); ``diagonal``: ``Mr^-1`` is diagonal (row
    scalings, the same numbers as the products)."""
    m = kr.shape[0]
    a = np.zeros((2 * m, 2 * m))
    a[:m, m:] = np.eye(m)
    if diagonal:
        inv_m = np.diag(mr_inv)[:, None]
        np.multiply(-inv_m, kr, out=a[m:, :m])
        np.multiply(-inv_m, cr, out=a[m:, m:])
    else:
        np.matmul(-mr_inv, kr, out=a[m:, :m])
        np.matmul(-mr_inv, cr, out=a[m:, m:])
    return a


#: the attributes of a configuration's modes, decomposed on first use where they are a neighbour's
#: updated (:meth:`ConfigData.__getattr__`)
_MODAL = frozenset({"lam", "V", "_W", "_left", "modal", "max_rate", "shapes", "shapes_mass", "shapes_w2", "pairs",
                    "_inverse", "_balance", "n_pairs"})


class ConfigData:
    """Decomposition of one stuck/slipping pattern, built once and cached.

    Parameters
    ----------
    system : FrictionSystem
    status : (n_sliders,) int ndarray
        Stick/slip status (0 stuck, +-1 slipping, 2 on an open contact). Which sliders stick sets
        the configuration; with normal-load variation (:attr:`FrictionSystem.varying`) so do the
        slip directions of the sliders on contacts (their slip force ``sig mu N(x)`` is a stiffness
        ``sig d g^T``) and the open contacts (their spring and dashpot are off).

    Attributes
    ----------
    base_stiffness, damping : (n_dof, n_dof) ndarray
        Stiffness without the stuck Jenkins springs (the system's, with the slip-force gradients
        of slipping sliders on contacts and without open contacts' springs) and damping (without
        open contacts' dashpots); the system's own arrays when there are no contacts.
    stiffness : (n_dof, n_dof) ndarray
        ``K_c``: ``base_stiffness`` plus the stuck Jenkins springs.
    """

    def __init__(self, system, status: np.ndarray, neighbour: tuple | None = None):
        status = np.asarray(status)
        stuck = status == 0
        jen_stuck = stuck & ~system.rigid
        self._stiffness(system, status, jen_stuck)
        self.rigid_stuck = np.flatnonzero(stuck & system.rigid)
        mr, kr, cr = self._reduce(system)
        if self.m and neighbour is not None and self._updatable(system, *self._route(system, jen_stuck)[:2]):
            # decomposed on first use of its modes (:meth:`__getattr__`): a status tested for
            # consistency only needs the fastest rate, which the update's roots give
            self._pending = (system, jen_stuck, mr, kr, cr, neighbour)
        else:
            self._decompose(system, jen_stuck, mr, kr, cr, neighbour)
        # forcing terms that depend on the configuration only (reused by every interval)
        zm = np.zeros(self.m)
        self.bc = np.concatenate([zm, self.mr_inv_nt @ system.force_cos])
        self.bs = np.concatenate([zm, self.mr_inv_nt @ system.force_sin])
        self.bc_zero = not self.bc.any()
        self.bs_zero = not self.bs.any()
        self._modal_omega = None
        #: the consistency test's packed arrays of the configuration, shared by its statuses
        #: (:func:`.consistency.pack_config`), set by the first status packed
        self.kern = None

    def _decompose(self, system, jen_stuck, mr, kr, cr, neighbour=None, roots=None) -> None:
        """The modes: ``lam``, ``V``, ``V^-1``, ``max_rate`` and, classically damped, the shapes
        (:meth:`_modes`)."""
        self.modal = True
        #: mass-normalised mode shapes ``Phi`` (reduced coordinates), ``Phi^T Mr``, ``w^2`` and the
        #: roots ``(lam+, lam-)`` of each pair where the configuration is classically damped
        #: (:func:`_classical_modes`), else None
        self.shapes = self.shapes_mass = self.shapes_w2 = self.pairs = None
        #: ``V^-1`` of classical modes in factored form ``(rows, left, right)`` (:func:`_half_modes`)
        self._inverse = None
        halved = None
        #: ``(scale, M, C)`` where ``V^-1`` is the left eigenvectors' (:func:`_left_inverse`): not
        #: held, its products formed from the shapes (:meth:`left_product`) and those that set a
        #: piece's start refined once (:meth:`refined`); else None
        self._left = None
        if self.m:
            modes = self._modes(system, jen_stuck, mr, kr, cr, neighbour, roots)
            lam, v, w = modes[:3]
            if len(modes) == 5:  # halved already, V^-1 from the left eigenvectors (:func:`_left_inverse`)
                # kept as a scale per mode: the rows are products with the shapes, M and C (the
                # system's), formed where they are used (:meth:`left_product`), not held (half the
                # memory of a configuration's modes)
                self._left = (modes[4], _left_mass(system), self.damping)
                self._shared += (self._left[1],)  # the system's (not in nbytes)
                halved = modes[:2] + (None,) + modes[3:4]
        else:
            lam = np.zeros(0, complex)
            v = np.zeros((0, 0), complex)
            w = np.zeros((0, 0), complex)
        lam = np.asarray(lam, dtype=complex)
        #: general modes kept halved (:func:`_halved_modes`): the number of conjugate pairs (their
        #: first roots lead ``lam``), else None (classical, defective or not paired exactly)
        self.n_pairs = None
        if v is not None and self.pairs is None:
            if halved is None:
                halved = _halved_modes(lam, v, w)
            if halved is not None:
                lam, v, w, self.n_pairs = halved
        self.lam = lam
        self.V = v
        self._W = w
        rates = np.abs(self.lam)
        self.max_rate = float(rates.max()) if rates.size else 0.0

    def __getattr__(self, name: str):
        """The modes of a configuration decomposed lazily (built with a neighbour whose modes are
        updated, :meth:`_updated_modes`), on first use of one of :data:`_MODAL`: ``max_rate`` alone
        from the update's roots (:func:`.mode_update.rank_one_roots`; the consistency test of a
        status reads nothing else, and more than half the statuses tested are not kept), the rest
        by finishing the update (or, where it fails, decomposing from scratch)."""
        pending = self.__dict__.get("_pending")
        if pending is None or name not in _MODAL:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        if name == "max_rate" and "_roots" not in self.__dict__:
            system, jen_stuck, _, _, _, (old, slider) = pending
            roots = self._roots = self._update_roots(system, jen_stuck, old, slider)
            if roots is not None:
                # without the neighbour's eigenvectors (a view of its whole modes, built for the
                # update where they are kept halved or factored: 2m x 2m held for nothing while
                # the configuration waits); :meth:`_updated_modes` takes them again
                self._roots = (roots[0], (None,) + roots[1][1:])
                self.max_rate = float(np.max(np.abs(roots[0]), initial=0.0))
                return self.max_rate
        del self._pending
        if "_roots" in self.__dict__:
            roots = self.__dict__.pop("_roots")
            if roots is None:  # the update was tried and failed: from scratch, not a second time
                pending = pending[:5] + (None,)
        else:
            roots = None
        self._decompose(*pending, roots)
        hook = self.__dict__.pop("_on_decomposed", None)  # the cache that counts it (weak)
        recount = hook() if hook is not None else None
        if recount is not None:
            recount(self)
        return self.__dict__[name]

    def _stiffness(self, system, status: np.ndarray, jen_stuck: np.ndarray) -> None:
        """``base_stiffness`` and ``damping`` (contacts: open ones' spring and dashpot off, slipping
        sliders' slip-force gradients on) and ``stiffness`` ``K_c`` (plus the stuck Jenkins springs)."""
        d = system.slider_direction
        kb, cb = system.stiffness, system.damping
        if system.n_contacts:
            kb, cb = kb.copy(), cb.copy()
            for i in np.flatnonzero(system.varying):
                c = system.slider_contact[i]
                if status[i] == 2:
                    nn = np.outer(system.contact_normal[c], system.contact_normal[c])
                    kb -= system.contact_stiffness[c] * nn
                    cb -= system.contact_damping[c] * nn
                elif status[i] != 0:
                    kb += status[i] * np.outer(d[i], system.slip_gradient[i])
        self.base_stiffness = kb
        self.damping = cb
        #: the system's arrays a configuration refers to (not its own: not in :attr:`nbytes`)
        self._shared = (kb, cb) if kb is system.stiffness else ()
        kc = kb.copy()
        stuck = np.flatnonzero(jen_stuck)
        if stuck.size:  # sum_i k_i d_i d_i^T as one product (one term per entry for DOF directions)
            kc += (d[stuck].T * system.slider_stiffness[stuck]) @ d[stuck]
        self.stiffness = kc

    def _reduce(self, system):
        """The reduced coordinates ``x = x0 + N q`` of the stuck rigid sliders' null space: ``N``,
        ``m``, ``Mr^-1 N^T``, the first-order matrix ``A`` (with stuck rigid sliders; else what it is
        made of, :attr:`A` builds it on first use), the holding-force map ``L``; returns the reduced
        ``(Mr, Kr, Cr)``."""
        n = system.n_dof
        mass, kc, cb = system.mass, self.stiffness, self.damping
        if self.rigid_stuck.size:
            g = system.slider_direction[self.rigid_stuck]
            nb = scipy.linalg.null_space(g)
        else:
            nb = _identity(system)
        self.N = nb
        m = self.m = nb.shape[1]
        if self.rigid_stuck.size:
            mr, kr, cr = nb.T @ mass @ nb, nb.T @ kc @ nb, nb.T @ cb @ nb
        else:  # N = I: the products would copy (at n^3 each)
            mr, kr, cr = mass, kc, cb
        self._A = self._a_parts = None
        if m:
            if self.rigid_stuck.size:
                mr_inv = np.linalg.inv(mr)
                self.mr_inv_nt = mr_inv @ nb.T
                self._A = _first_order(mr_inv, kr, cr, False)
            else:
                mr_inv = self.mr_inv_nt = _mass_inverse(system)
                factor = _mass_factor(system)
                # N = I: M^-1, K_c and C are held anyway (A: 4 m^2 more, read by rare paths only)
                self._a_parts = (mr_inv, kr, cr, factor is not None and factor.ndim == 1)
                self._shared += (nb, mr_inv, mass)  # Mr = M: the system's (a waiting configuration holds it)
        else:
            self.mr_inv_nt = np.zeros((0, n))
            self._A = np.zeros((0, 0))
        # holding forces of stuck rigid sliders: lam = L (F - C v - K_c x)
        if self.rigid_stuck.size:
            proj = np.eye(n) - mass @ nb @ self.mr_inv_nt
            self.L = -np.linalg.solve(g @ g.T, g @ proj)
        else:
            self.L = np.zeros((0, n))
        return mr, kr, cr

    def _route(self, system, jen_stuck: np.ndarray):
        """``(refine, alpha, pencil)``: whether the stuck springs are stiff enough for the modes to
        be refined (:func:`_refine_modes`), and the classical damping rate(s) and modes where the
        configuration is classically damped (:func:`_classical_modes`), else None: system-level
        facts, cached on the system."""
        kt = system.slider_stiffness[jen_stuck]
        k_ref = float(np.max(np.abs(np.diag(system.stiffness))))
        # springs no stiffer than REFINE_RATIO x the structure lose at most ~ eps x ratio of
        # the slow modes in eig: refinement (3 Newton solves per mode) is only paid where
        # it restores digits
        refine = bool(kt.size and float(np.max(kt)) > REFINE_RATIO * k_ref)
        alpha = _mass_proportional(system)
        pencil = None
        if alpha is None and not kt.size and not system.n_contacts and not self.rigid_stuck.size:
            own = _modally_damped(system)  # K_c = K: the structure's modes, if its damping is classical
            if own is not None:
                alpha, pencil = own
        return refine, alpha, pencil

    def _updatable(self, system, refine: bool, alpha=None) -> bool:
        """Whether a neighbour's modes may be updated into this configuration's: no refinement
        (:meth:`_route`), no contacts, no stuck rigid sliders, and not classically damped
        (``alpha``, :meth:`_route`'s, None)."""
        return not refine and alpha is None and not system.n_contacts and not self.rigid_stuck.size

    def _modes(self, system, jen_stuck: np.ndarray, mr, kr, cr, neighbour=None, roots=None):
        """``(lam, V, V^-1)``: classical modes (:func:`_classical_modes`) where they apply, else
        the neighbour's updated by the one spring they differ by (:meth:`_updated_modes`, from
        ``roots`` where its first half was done; five items where halved with the left
        eigenvectors' rows), else the first-order matrix's
        (:func:`_general_modes`), refined where a stuck spring is far stiffer than the structure
        (:func:`_refine_modes`); ``modal`` False where defective."""
        refine, alpha, pencil = self._route(system, jen_stuck)
        kt = system.slider_stiffness[jen_stuck]
        if alpha is not None and not refine and not system.n_contacts:
            modes = _classical_modes(mr, kr, alpha, None if self.rigid_stuck.size else _mass_factor(system), pencil)
            if modes is not None:
                lam, v, self._inverse, (self.shapes, self.shapes_mass, self.shapes_w2, lp, lm) = modes
                self.pairs = (lp, lm)
                return lam, v, None
        if neighbour is not None and self._updatable(system, refine):  # also where classical failed
            modes = self._updated_modes(system, jen_stuck, *neighbour, roots)
            if modes is not None:
                return modes
        lam, v, w = _general_modes(self.A)
        if v is None:
            self.modal = False
            return np.linalg.eigvals(self.A), None, None
        tsc, v = v
        self._balance = tsc
        if refine:
            nb = self.N
            kb = nb.T @ self.base_stiffness @ nb
            lam, v = _refine_modes(lam.astype(complex), v, mr, cr, kb, nb.T @ system.slider_direction[jen_stuck].T, kt)
            w = _left_modes(lam, v, mr, cr, kb)
            if w is None:
                w = np.linalg.inv(v / tsc[:, None]) / tsc[None, :]  # V^-1 = V_B^-1 T^-1
        return lam, v, w

    def _update_roots(self, system, jen_stuck: np.ndarray, old: "ConfigData", slider: int):
        """:func:`.mode_update.rank_one_roots` of the update from ``old`` (its modes, both roots of
        every pair, and the spring of ``slider`` as ``(-M^-1 d k, d)``), or None where ``old`` has
        no modes to update (defective, or with stuck rigid sliders) or the roots were not found."""
        if old.rigid_stuck.size or old.m != self.m or not old.modal or old.V is None:
            return None
        d = system.slider_direction[slider]
        k = float(system.slider_stiffness[slider]) * (1.0 if jen_stuck[slider] else -1.0)
        lam, v_top, a = old.update_basis(-(_mass_inverse(system) @ d) * k)
        return mode_update.rank_one_roots_top(lam, v_top, a, d)

    def _updated_modes(self, system, jen_stuck: np.ndarray, old: "ConfigData", slider: int, roots=None):
        """``(lam, V, V^-1)`` from the modes of ``old``, the configuration that differs from this one
        by the Jenkins spring of ``slider`` only (both without stuck rigid sliders and contacts): the
        rank-one update of its eigenvalues and shapes (:func:`.mode_update.rank_one_modes`), checked
        (:func:`.mode_update.checked_modes`), and ``V^-1``: of a symmetric pencil from the left
        eigenvectors, halved (:func:`_left_inverse`'s ``(lam, V, V^-1, p, scale)``), else the
        inverse of the new eigenvectors, balanced as ``old``'s were (:func:`_general_modes`); under
        :data:`DEFECTIVE_COND` either way; None where any of it does not hold (the caller
        decomposes from scratch)."""
        if roots is None:
            roots = self._update_roots(system, jen_stuck, old, slider)
            if roots is None:
                return None
        elif roots[1][0] is None:  # the eigenvectors the roots were found with, again
            roots = (roots[0], (old.update_basis()[1],) + roots[1][1:])
        n = self.m
        mu, phi = mode_update.rank_one_shapes(roots)
        v = mode_update.checked_modes(mu, phi, system.mass, self.damping, self.stiffness)
        if v is None:
            return None
        tsc = getattr(old, "_balance", None)
        if tsc is None:
            tsc = np.ones(2 * n)
        halved = _left_inverse(mu, v, _left_mass(system), self.damping, tsc) if _symmetric_pencil(system) else None
        if halved is not None:
            # halved: the 1-norms within a factor 2 of the whole modes' (a pair's columns and rows)
            vb, wb = halved[1] / tsc[:, None], halved[2] * tsc[None, :]
        else:
            vb = v / tsc[:, None]
            try:
                wb = _real_inverse(mu, vb, exact=True)
            except np.linalg.LinAlgError:
                return None
        # the 1-norms within a factor sqrt(2) each (|Re| + |Im|: no square roots of N^2 entries)
        cond = _norm1(vb) * _norm1(wb)
        if not np.isfinite(cond) or cond > DEFECTIVE_COND:
            return None
        self._balance = tsc
        if halved is not None:
            return halved
        wb /= tsc[None, :]
        return mu, v, wb

    @property
    def A(self) -> np.ndarray:
        """The first-order matrix ``[[0, I], [-Mr^-1 Kr, -Mr^-1 Cr]]`` (2m, 2m), built on first use
        and kept where the configuration has no stuck rigid sliders (the march of a modal
        configuration does not read it: :meth:`first_order_blocks`)."""
        if self._A is None:
            self._A = _first_order(*self._a_parts)
        return self._A

    def first_order_blocks(self) -> tuple[np.ndarray, np.ndarray]:
        """``(A21, A22) = (-Mr^-1 Kr, -Mr^-1 Cr)`` (m, m), the lower blocks of :attr:`A` (the same
        numbers), without building or keeping ``A``."""
        m = self.m
        a = self._A
        if a is None:
            mr_inv, kr, cr, diagonal = self._a_parts
            if diagonal:  # row scalings, as _first_order
                inv_m = -np.diag(mr_inv)[:, None]
                return inv_m * kr, inv_m * cr
            a = _first_order(*self._a_parts)
        return a[m:, :m], a[m:, m:]

    @property
    def W(self) -> np.ndarray | None:
        """``V^-1`` (p, 2m) (None where the configuration is defective); for classical modes built
        on each use from its factored form (the march needs :meth:`velocity_inverse` only), and from
        the left eigenvectors' shapes where they gave it (:meth:`left_product`: the same rows)."""
        if self._left is not None:
            m = self.m
            scale, mass, damping = self._left
            psi = self.V[:m]
            w = np.empty((psi.shape[1], 2 * m), complex)
            w[:, m:] = _left_times(mass, psi).T  # psi^T M = (M psi)^T: M symmetric
            w[:, :m] = (damping @ psi).T
            w[:, :m] += self.lam[:, None] * w[:, m:]
            w *= scale[:, None]
            return w
        if self._inverse is None:
            return self._W
        return _inverse(*self._inverse)

    def left_product(self, z: np.ndarray) -> np.ndarray:
        """``V^-1 z`` for a reduced state ``z`` (2m,) or states (2m, k), real or complex. Where the
        left eigenvectors gave ``V^-1`` (rows ``s_i [lam_i (M psi_i)^T + (C psi_i)^T, (M psi_i)^T]``,
        ``psi`` the halved shapes, ``s`` :func:`_left_inverse`'s scale) it is formed from the shapes:
        ``s (lam psi^T M x + psi^T (C x + M v))``, two products with ``psi^T``, the work of one with
        ``V^-1``; else the product with :attr:`W`."""
        if self._left is None:
            return self.W @ z
        m = self.m
        scale, mass, damping = self._left
        x, v = z[:m], z[m:]
        psi_t = self.V[:m].T
        per_mode = (slice(None),) + (None,) * (z.ndim - 1)  # a mode's factor on its row of each state
        out = psi_t @ _left_times(mass, x)
        out *= self.lam[per_mode]
        out += psi_t @ (damping @ x + _left_times(mass, v))
        out *= scale[per_mode]
        return out

    def diagonal_mass_inverse(self) -> bool:
        """Whether ``N = I`` (no stuck rigid slider) and ``M^-1`` (:attr:`mr_inv_nt`) is diagonal
        (lumped masses): its diagonal then serves as the matrix. Counted once per configuration."""
        diag = getattr(self, "_diagonal", None)
        if diag is None:
            mint = self.mr_inv_nt
            diag = self._diagonal = bool(not self.rigid_stuck.size
                                         and np.count_nonzero(mint) == np.count_nonzero(np.diagonal(mint)))
        return diag

    def modal_w2(self) -> np.ndarray:
        """``w^2`` of each kept classical mode (p,), the product of its pair's roots ``lam other``
        (:func:`_half_modes`), real; built on first use."""
        w2 = getattr(self, "_w2", None)
        if w2 is None:
            _, left, right = self._inverse
            w2 = self._w2 = np.ascontiguousarray((self.lam * (-left / right)).real)
        return w2

    def velocity_inverse(self) -> np.ndarray:
        """``V^-1[:, m:]`` (p, m): the columns of ``V^-1`` a reduced state ``[0, u]`` meets (every
        piece's start and constant load); for classical modes and where the left eigenvectors gave
        ``V^-1`` (:meth:`left_product`) built on each use (:meth:`velocity_product` for a product)."""
        if self._left is not None:
            scale, mass, _ = self._left
            return _left_times(mass, self.V[:self.m]).T * scale[:, None]
        if self._inverse is None:
            return self._W[:, self.m:]
        return _inverse(*self._inverse, half=True)

    def velocity_product(self, u: np.ndarray) -> np.ndarray:
        """``V^-1[:, m:] u`` for ``u`` (m,) or (m, k): a product with :meth:`velocity_inverse`,
        without building it where the left eigenvectors gave ``V^-1`` (:meth:`left_product`)."""
        if self._left is None:
            return self.velocity_inverse() @ u
        return self.left_product(np.concatenate([np.zeros((self.m,) + u.shape[1:]), u]))

    def refined(self, z: np.ndarray) -> np.ndarray:
        """A real reduced state ``z`` (2m,) whose modal coordinates ``V^-1 z`` are those of ``z`` to
        rounding: ``z`` itself, or where ``V^-1`` is the left eigenvectors' (:func:`_left_inverse`,
        exact only to the shapes' rounding over the gaps of clustered roots, up to
        :data:`LEFT_PROBE`), ``z + (z - Re(V V^-1 z))``, one step of iterative refinement (the
        error squared: the orbits of the (200, 40) chains as with the inverse, 1.4e-12)."""
        if self._left is None:
            return z
        return 2.0 * z - (self.V @ self.left_product(z)).real

    def full_modes(self):
        """``(lam, V, V^-1)`` with both roots of every conjugate pair (square ``V``): for a
        complex response (the stuck orbit's harmonic solve), where the halved modes' real-part
        rule does not apply; ``V^-1`` exact to rounding (the inverse, where the left eigenvectors
        gave it)."""
        if self._left is not None:  # the inverse, balanced as the update's (:meth:`_updated_modes`)
            lam, v = _unhalved(self.lam, self.n_pairs), _unhalved(self.V, self.n_pairs, half=True)
            tsc = self._balance
            return lam, v, _real_inverse(lam, v / tsc[:, None], exact=True) / tsc[None, :]
        if self.n_pairs is not None:
            return _unhalved_modes(self.lam, self.V, self._W, self.n_pairs)
        if self.pairs is None:
            return self.lam, self.V, self.W
        return _full_modes(self.shapes, self.shapes_mass, *self.pairs)

    def adopt_stiffness(self, packed: np.ndarray) -> None:
        """Refer to ``packed``, a copy of ``K_c`` (the consistency test's packed arrays), wherever
        the configuration held its own: its stiffness and, with ``N = I``, the ``Kr`` of its
        first-order parts and of a decomposition still to come; the own copy is then freed."""
        own = self.stiffness
        self.stiffness = packed
        if self._a_parts is not None and self._a_parts[1] is own:
            self._a_parts = self._a_parts[:1] + (packed,) + self._a_parts[2:]
        pending = self.__dict__.get("_pending")
        if pending is not None and pending[3] is own:
            self._pending = pending[:3] + (packed,) + pending[4:]

    def update_basis(self, force: np.ndarray | None = None):
        """What a rank-one update from this configuration reads of its modes
        (:func:`.mode_update.rank_one_roots_top`): ``(lam, V[:m], V^-1[:, m:] force)`` with both
        roots of every pair (the last None without ``force``). Halved modes give them without
        their whole ``V`` and ``V^-1`` (:func:`_unhalved_modes`: the same numbers; where the left
        eigenvectors gave ``V^-1``, its product refined once, :meth:`refined`)."""
        p, m = self.n_pairs, self.m
        if p is None:
            lam, v, w = self.full_modes()
            return lam, v[:m], None if force is None else w[:, m:] @ force
        if force is None:
            a = None
        elif self._left is not None:
            a = _unhalved(self.left_product(self.refined(np.concatenate([np.zeros(m), force]))), p)
        else:
            a = _unhalved(self._W[:, m:] @ force, p)
        return _unhalved(self.lam, p), _unhalved(self.V[:m], p, half=True), a

    def modal_rows(self, rows: np.ndarray) -> np.ndarray:
        """``rows @ V`` for real ``rows`` on the reduced state ``[q, q']`` (``2m`` columns), e.g. the
        event functions' modal coefficients. Classical modes have ``V = [[S], [S diag(lam)]]`` with
        ``S`` real (the shapes times the pair weights, :func:`_half_modes`): two real products and a
        column scaling instead of a complex product with ``V``, an eighth of the work, equal to it
        to rounding (``sum c_k (S_k lam)`` is summed as ``(sum c_k S_k) lam``)."""
        if self.pairs is None:
            return rows @ self.V
        m = self.m
        shapes = np.ascontiguousarray(self.V[:m].real)  # imaginary part exactly 0 (real shapes x weights)
        return rows[:, :m] @ shapes + (rows[:, m:] @ shapes) * self.lam

    def displacement_modes(self) -> np.ndarray:
        """``N V[:m]`` (n_dof, 2m): the displacements' modal coefficients, built on first use."""
        modes = getattr(self, "_xv", None)
        if modes is None:  # N = I: a view, no copy
            modes = self._xv = self.V[:self.m] if self.rigid_stuck.size == 0 else self.N @ self.V[:self.m]
        return modes

    @property
    def nbytes(self) -> int:
        """Memory held by the configuration's own arrays [bytes] (what its cache entry costs): its
        arrays and those in its tuples, each once, not the views and not the system's arrays it
        refers to (stiffness, damping, ``M^-1``, the identity ``N``)."""
        seen = {id(a) for a in self._shared}
        # a configuration decomposed on first use counts its eigenvectors and their inverse to come
        # (halved, :func:`_halved_modes`: 2m x m complex each where every mode is under-damped, up
        # to 2m x 2m where all are over-damped; counted at their size once decomposed), of a
        # symmetric pencil its eigenvectors only (the inverse's rows are not held, :func:`_left_inverse`)
        pending = self.__dict__.get("_pending")
        total = 0
        if pending is not None:
            total = 16 * (2 * self.m) ** 2 // (2 if _symmetric_pencil(pending[0]) else 1)
        for value in vars(self).values():
            for a in value if isinstance(value, tuple) else (value,):
                if isinstance(a, np.ndarray) and a.base is None and id(a) not in seen:
                    seen.add(id(a))
                    total += a.nbytes
        return total

    def modal_forcing(self, w: float):
        """Per-configuration parts of :meth:`Interval._prepare` at forcing frequency ``w``:
        half the modal harmonic loads and, for ``mu`` in ``0, iw, -iw``, ``(mu, mu - lam, near)``."""
        if self._modal_omega != w:
            m = self.m
            lam = self.lam
            # nearness per mode, relative to that mode's own rate (or w): the closed form
            # c / (mu - lam) loses ~ eps * max(|lam|, w) / |mu - lam| of the mode's response; a
            # scale from the fastest mode (max_rate) would flag every slow mode of a stiff
            # configuration (e.g. a stuck kt/k ~ 1e10 joint: 1e-4 * 1.7e5 rad/s) as resonant
            # and send all sampling through the slow phi1 path
            scale = np.maximum(np.maximum(np.abs(lam), w), 1e-300)
            terms = []
            for mu, band in ((0.0, 1e-4), (1j * w, 1e-2), (-1j * w, 1e-2)):
                dmu = mu - lam
                # a mode within 1 % of the forcing frequency keeps the phi1 form: the split into
                # a particular (c/dmu) and a homogeneous part would cancel terms |scale/dmu| times
                # larger than the motion (rounding of 1e-12 at 1e-4 off resonance: spurious slips
                # and an unreachable shooting tolerance)
                near = np.abs(dmu) < band * scale
                terms.append((mu, dmu, near, bool(near.any())))
            if self._left is not None:
                hc, hs = self.left_product(self.refined(self.bc)), self.left_product(self.refined(self.bs))
                self._modal_cache = ((hc - 1j * hs) * 0.5, (hc + 1j * hs) * 0.5, terms)
            else:
                wi = self.velocity_inverse()  # bc, bs: [0, Mr^-1 N^T f]
                self._modal_cache = (wi @ (self.bc[m:] - 1j * self.bs[m:]) * 0.5,
                                     wi @ (self.bc[m:] + 1j * self.bs[m:]) * 0.5, terms)
            self._modal_omega = w
        return self._modal_cache


class Observables:
    """Quantities linear in state and forcing: ``Q = Ax x + Av v + AF F(t) + a0``.

    ``F(t)`` is the total applied force on the structure (external, harmonic, and the forces of
    slipping sliders and stuck Jenkins springs' constant parts, i.e. everything except
    ``-C v - K_c x``) -- in practice only holding forces use ``AF``.
    """

    def __init__(self, ax, av, af, a0):
        self.ax = np.atleast_2d(np.asarray(ax, dtype=float))
        self.av = np.atleast_2d(np.asarray(av, dtype=float))
        self.af = np.atleast_2d(np.asarray(af, dtype=float))
        self.a0 = np.asarray(a0, dtype=float).reshape(-1)

    @property
    def size(self) -> int:
        return self.a0.size


#: the resonant terms of a plain piece (none): ``(nidx, nmu, nc)`` of :attr:`Interval.near`
_NO_NEAR = (np.zeros(0, np.intp), np.zeros(0, complex), np.zeros(0, complex))


def _near_arrays(near) -> tuple:
    """``(nidx, nmu, nc)``: the resonant terms ``nc_q E(lam_q, mu_q, tau)`` of ``Interval._near``
    (one per mode and forcing exponent with a nonzero coefficient), flat for the compiled kernels."""
    if not near:
        return _NO_NEAR
    idx, mus, cs = [], [], []
    for mu, c in near:
        k = np.flatnonzero(c != 0)
        idx.append(k)
        mus.append(np.full(k.size, mu, dtype=complex))
        cs.append(c[k])
    return (np.concatenate(idx).astype(np.intp), np.concatenate(mus), np.concatenate(cs).astype(complex))


class Interval:
    """The exact motion from ``t0`` in one configuration.

    Parameters
    ----------
    system : FrictionSystem
    config : ConfigData
    t0 : float
        Start time [s].
    x0, v0 : (n_dof,) ndarray
        State at ``t0``.
    f_const : (n_dof,) ndarray
        Constant applied force over the interval [N]: held external force, slipping sliders'
        friction and the stuck Jenkins springs' ``k w d`` terms.
    """

    def __init__(self, system, config: ConfigData, t0: float, x0, v0, f_const, spring_force=None):
        self.system = system
        self.config = config
        self.t0 = float(t0)
        self.x0 = x0 = np.asarray(x0, dtype=float)
        self.f_const = np.asarray(f_const, dtype=float)
        m = config.m
        self.omega = system.omega
        # K_c x0, kept for the tolerance scales of the marcher
        self.kx0 = kx0 = config.stiffness @ x0
        b0 = np.zeros(2 * m)
        if spring_force is None:
            b0[m:] = config.mr_inv_nt @ (self.f_const - kx0)
        else:
            # f_const - K_c x0 with the stuck Jenkins springs in spring form, given by the caller
            # (f_ext - friction - K x0 - sum k (d.x0 - w) d): K_c x0 and k w d are each ~ kt |x|
            # and cancel, so their difference would carry an error eps kt |x| in every DOF
            # (not along d) that drives the soft modes of a stiff stuck joint
            b0[m:] = config.mr_inv_nt @ spring_force
        y0 = np.zeros(2 * m)
        y0[m:] = config.N.T @ np.asarray(v0, dtype=float)
        self._bvec = (b0, config.bc, config.bs)
        self._y0 = y0
        self._ready = False

    @classmethod
    def from_parts(cls, system, config: ConfigData, t0: float, x0: np.ndarray, f_const: np.ndarray,
                   kx0: np.ndarray, y0: np.ndarray, b0: np.ndarray) -> "Interval":
        """The interval of the constructor, from its start parts computed elsewhere (the compiled
        consistency test of :mod:`.consistency`): ``K_c x0``, the reduced start state ``y0 = [0,
        N^T v0]`` and constant forcing ``b0 = [0, M_r^-1 N^T (f_const - K_c x0)]`` (spring form)."""
        self = cls.__new__(cls)
        self.system = system
        self.config = config
        self.t0 = float(t0)
        self.x0 = x0
        self.f_const = f_const
        self.omega = system.omega
        self.kx0 = kx0
        self._bvec = (b0, config.bc, config.bs)
        self._y0 = y0
        self._ready = False
        return self

    def _mass_load(self) -> np.ndarray:
        """``M^-1 f_const`` (n_dof,) of a configuration without stuck rigid sliders (``N = I``).

        Classically damped pieces form their constant modal load from it and the modal identity
        ``Phi^T K_c = W^2 Phi^T M``, ``right_i (phi_i^T f_const - w_i^2 phi_i^T M x0)``, instead of
        projecting ``f_const - K_c x0``: the double-precision modes satisfy the identity only to
        ``eps |K|``, and that residual times ``x0``, over the slowest ``w^2``, was a static shift of
        ``eps cond(K) |x0|`` that every piece's start brought anew (splitting a period's march at a
        time that is no event moved its end by 6.9e-12 of the motion at 200 DOFs, 7e-15 now)."""
        minv = self.config.mr_inv_nt
        return np.diagonal(minv) * self.f_const if self.config.diagonal_mass_inverse() else minv @ self.f_const

    def _prepare(self):
        """Modal coefficients (or the augmented matrix), computed on first use only."""
        self._ready = True
        self.near = _NO_NEAR
        config = self.config
        m = config.m
        w = self.omega
        b0, bc, bs = self._bvec
        y0 = self._y0
        if config.modal and m:
            hp, hm, terms = config.modal_forcing(w)
            # the constant load from the modal identity (:meth:`_mass_load`): classical, N = I
            modal_load = config._inverse is not None and not config.rigid_stuck.size
            if piece_kernels.ENABLED and not (terms[0][3] or terms[1][3] or terms[2][3]):
                # plain modal piece: one compiled call (same arithmetic as below); y0, b0 = [0, .]
                if modal_load:
                    rows, _, right = config._inverse
                    out = piece_kernels.coefficients_modal(rows, right, config.modal_w2(), config.lam, y0[m:],
                                                           self._mass_load(), self.x0, hp, hm, w, self.t0)
                elif config._inverse is not None:
                    rows, _, right = config._inverse
                    out = piece_kernels.coefficients_factored(rows, right, config.lam, y0[m:], b0[m:], hp, hm,
                                                              w, self.t0)
                elif config._left is not None:
                    out = piece_kernels.coefficients_given(config.left_product(config.refined(y0)),
                                                           config.left_product(config.refined(b0)),
                                                           config.lam, hp, hm, w, self.t0)
                else:
                    out = piece_kernels.coefficients(config.W, config.lam, y0, b0, hp, hm, w, self.t0)
                (self.eta0, self.beta0, self.gp, self.gm, self._a, *b) = out
                self._b = b
                self._near = []
                self.near = _NO_NEAR
                return
            if config._left is not None:  # the left eigenvectors' products, refined
                self.eta0 = config.left_product(config.refined(y0))
                self.beta0 = config.left_product(config.refined(b0))
            else:
                wi = config.velocity_inverse()  # y0, b0 = [0, .]
                self.eta0 = wi @ y0[m:]
                if modal_load:
                    rows, _, right = config._inverse
                    self.beta0 = right * (rows @ self._mass_load() - config.modal_w2() * (rows @ self.x0))
                else:
                    self.beta0 = wi @ b0[m:]
            ph = cmath.exp(1j * w * self.t0)
            self.gp = hp * ph
            self.gm = hm * ph.conjugate()
            # exp-polynomial form eta = e^{lam tau} a + b0 + b+ e^{iw tau} + b- e^{-iw tau}, with the
            # (near-)resonant mode/forcing pairs kept in the phi1 form (exact at resonance)
            a = self.eta0.copy()
            self._near = []
            self._b = []
            for (mu, dmu, near, any_near), c in zip(terms, (self.beta0, self.gp, self.gm)):
                if any_near:
                    bk = np.where(near, 0.0, c / np.where(near, 1.0, dmu))
                    if np.any(near & (c != 0)):
                        self._near.append((mu, np.where(near, c, 0.0)))
                else:
                    bk = c / dmu
                a -= bk
                self._b.append(bk)
            self._a = a
            self.near = _near_arrays(self._near)
        elif m:
            n2 = 2 * m
            aug = np.zeros((n2 + 3, n2 + 3))
            aug[:n2, :n2] = config.A
            c0, s0 = math.cos(w * self.t0), math.sin(w * self.t0)
            # local harmonic states: cos(w(t0+tau)), sin(w(t0+tau))
            aug[:n2, n2] = bc
            aug[:n2, n2 + 1] = bs
            aug[:n2, n2 + 2] = b0
            aug[n2, n2 + 1] = -w
            aug[n2 + 1, n2] = w
            self._aug = aug
            self._z0 = np.concatenate([y0, [c0, s0, 1.0]])

    # ------------------------------------------------------------------ state
    def _eta(self, tau: np.ndarray, order: int):
        """Modal coordinates and their derivatives up to ``order`` at local times ``tau``."""
        lam = self.config.lam[:, None]
        t = tau[None, :]
        w = self.omega
        eip = np.exp(1j * w * t)
        eim = np.conj(eip)
        b0, bp, bm = self._b
        eta = (np.exp(lam * t) * self._a[:, None] + b0[:, None]
               + bp[:, None] * eip + bm[:, None] * eim)
        for mu, c in self._near:
            eta = eta + c[:, None] * _E(lam, mu, t)
        out = [eta]
        if order >= 1:
            beta = self.beta0[:, None] + self.gp[:, None] * eip + self.gm[:, None] * eim
            d1 = lam * eta + beta
            out.append(d1)
            if order >= 2:
                dbeta = 1j * w * (self.gp[:, None] * eip - self.gm[:, None] * eim)
                out.append(lam * d1 + dbeta)
        return out

    def y(self, tau, order: int = 0) -> list[np.ndarray]:
        """Reduced state ``[q, q']`` (2m, k) and its time derivatives up to ``order``."""
        if not self._ready:
            self._prepare()
        tau = np.atleast_1d(np.asarray(tau, dtype=float))
        cfg = self.config
        m2 = 2 * cfg.m
        if m2 == 0:
            return [np.zeros((0, tau.size)) for _ in range(order + 1)]
        if cfg.modal:
            return [(cfg.V @ e).real for e in self._eta(tau, order)]
        zs = np.empty((m2 + 3, tau.size))
        for k, tk in enumerate(tau):
            zs[:, k] = scipy.linalg.expm(self._aug * tk) @ self._z0
        out = [zs[:m2]]
        dz = zs
        for _ in range(order):  # d^k z / dt^k = aug^k z
            dz = self._aug @ dz
            out.append(dz[:m2])
        return out

    def velocity(self, tau, order: int = 0) -> list[np.ndarray]:
        """Structural velocity (n_dof, k) at local times ``tau`` and its time derivatives up to
        ``order`` (no displacements computed)."""
        cfg = self.config
        if not self._ready:
            self._prepare()
        tau = np.atleast_1d(np.asarray(tau, dtype=float))
        if not (cfg.modal and cfg.m):
            return [cfg.N @ y[cfg.m:] for y in self.y(tau, order + 1)[1:]] if cfg.m else \
                [np.zeros((self.system.n_dof, tau.size))] * (order + 1)
        nv = getattr(cfg, "_nv", None)
        if nv is None:  # N = I: a view, no copy
            nv = cfg._nv = cfg.V[cfg.m:] if cfg.rigid_stuck.size == 0 else cfg.N @ cfg.V[cfg.m:]
        return [(nv @ e).real for e in self._eta(tau, order)]

    def state(self, tau):
        """Structural displacement and velocity (n_dof, k) at local times ``tau``."""
        y = self.y(tau)[0]
        m = self.config.m
        nb = self.config.N
        x = self.x0[:, None] + nb @ y[:m]
        v = nb @ y[m:]
        return x, v

    # ------------------------------------------------------------ observables
    def reduce(self, obs: Observables):
        """Coefficients of an observable in reduced form: ``Q = Cy y + c0 + cc cos + cs sin``."""
        nb = self.config.N
        cy = np.hstack([obs.ax @ nb, obs.av @ nb])
        c0 = obs.ax @ self.x0 + obs.af @ self.f_const + obs.a0
        cc = obs.af @ self.system.force_cos
        cs = obs.af @ self.system.force_sin
        return cy, c0, cc, cs

    def start_values(self, red) -> list[np.ndarray]:
        """Observable values and first two time derivatives at ``tau = 0`` (no modal transform)."""
        cy, c0, cc, cs = red
        w = self.omega
        co, si = math.cos(w * self.t0), math.sin(w * self.t0)
        if self.config.m:
            b0, bc, bs = self._bvec
            cfg = self.config
            a = cfg.A
            y0 = self._y0
            # terms of all-zero harmonic loads are skipped (adding exact zeros)
            if cfg.bc_zero and cfg.bs_zero:
                y1 = a @ y0 + b0
                y2 = a @ y1
            elif cfg.bs_zero:
                y1 = a @ y0 + b0 + bc * co
                y2 = a @ y1 + w * (-(bc * si))
            else:
                y1 = a @ y0 + b0 + bc * co + bs * si
                y2 = a @ y1 + w * (bs * co - bc * si)
            vals = [cy @ y0, cy @ y1, cy @ y2]
        else:
            vals = [np.zeros(c0.size)] * 3
        if not (cc.any() or cs.any()):
            return [vals[0] + c0, vals[1], vals[2]]
        return [vals[0] + c0 + cc * co + cs * si,
                vals[1] + w * (cs * co - cc * si),
                vals[2] - w * w * (cc * co + cs * si)]

    def modal_search(self) -> bool:
        """True when the piece has a modal closed form (modal configuration): the compiled search
        and state apply, with the (near-)resonant terms of :attr:`near` if any."""
        if not self._ready:
            self._prepare()
        return bool(self.config.modal and self.config.m)

    def scalar(self, red, j: int):
        """Fast scalar ``g(tau)`` and ``g'(tau)`` of observable row ``j`` (for root finding)."""
        one = tuple(r[j:j + 1] for r in red)
        cfg = self.config
        if not self._ready:
            self._prepare()
        if not (cfg.modal and cfg.m) or self._near:
            def g(t):
                return float(self.evaluate(one, t)[0][0, 0])

            def dg(t):
                return float(self.evaluate(one, t, order=1)[1][0, 0])
            return g, dg
        cy, c0, cc, cs = one
        p = (cy @ cfg.V)[0]
        lam = cfg.lam
        pa = p * self._a
        pla = pa * lam
        b0, bp, bm = self._b
        k0 = float((p @ b0).real) + float(c0[0])
        kp = complex(p @ bp)
        km = complex(p @ bm)
        w = self.omega
        t0 = self.t0
        ccf, csf = float(cc[0]), float(cs[0])
        exp = np.exp

        def g(t):
            e = cmath.exp(1j * w * t)
            ph = w * (t0 + t)
            return (float((pa @ exp(lam * t)).real) + k0 + (kp * e + km / e).real
                    + ccf * math.cos(ph) + csf * math.sin(ph))

        def dg(t):
            e = cmath.exp(1j * w * t)
            ph = w * (t0 + t)
            return (float((pla @ exp(lam * t)).real) + (1j * w * (kp * e - km / e)).real
                    + w * (csf * math.cos(ph) - ccf * math.sin(ph)))
        return g, dg

    def active_rate(self, rel: float = 1e-12) -> float:
        """Largest rate present in the displacements: ``max(omega, |lam_i|)`` over the modes whose
        free response ``V_i a_i e^{lam_i tau}`` is not negligible (``> rel`` of the largest term);
        a stiff mode that is not excited (stuck joint on its periodic orbit) adds nothing to the
        motion and need not be resolved when sampling or integrating it."""
        cfg = self.config
        if not self._ready:
            self._prepare()
        if not (cfg.modal and cfg.m):
            return max(self.omega, cfg.max_rate)
        free, ref = self._free_sizes()
        nidx = self.near[0]
        live = free > rel * ref
        rate = float(np.max(np.abs(cfg.lam[live]), initial=0.0))
        if nidx.size:
            rate = max(rate, float(np.max(np.abs(cfg.lam[nidx]))))
        return max(self.omega, rate)

    def _free_sizes(self):
        """Sizes of the modes' free responses ``|V_i| |a_i|`` at the start of a modal piece and
        the scale of its largest term (free, forced or resonant) [m]."""
        cfg = self.config
        vn = np.linalg.norm(cfg.V[:cfg.m], axis=0)
        free = vn * np.abs(self._a)
        ref = max(float(np.max(free)), float(np.max(vn * (np.abs(self._b[0]) + np.abs(self._b[1])
                                                            + np.abs(self._b[2])))), 1e-300)
        nidx, _, nc = self.near
        if nidx.size:
            # a resonant term nc E(lam, mu, tau) grows like tau e^{lam tau}: its size over a period
            span = 2 * math.pi / self.omega if self.omega > 0 else 0.0
            ref = max(ref, float(np.max(vn[nidx] * np.abs(nc))) * span)
        return free, ref

    def decay_time(self, rel: float = 1e-12) -> float:
        """Local time [s] from which every mode's free response is below ``rel`` of the piece's
        largest term (:meth:`active_rate` from then on is ``omega``): 0 if none is above it at the
        start, ``inf`` if one does not decay or the piece has no plain modal form (or a resonant
        term). A piece of quasi-static forcing, half a period of 1e9 s, need not be sampled at the
        structure's rate beyond it."""
        cfg = self.config
        if not self._ready:
            self._prepare()
        if not (cfg.modal and cfg.m) or self.near[0].size:
            return math.inf
        free, ref = self._free_sizes()
        live = free > rel * ref
        if not live.any():
            return 0.0
        re = cfg.lam.real[live]
        if np.any(re >= 0):
            return math.inf
        return float(np.max(np.log(free[live] / (rel * ref)) / -re))

    def bounds(self, red, horizon: float):
        """Lower and upper bounds ``(lo, hi)`` (n_obs,) of the observables over local times
        ``[0, horizon]``, or ``None`` where the modal closed form is not available.

        ``g = Re(pa . e^{lam tau}) + k0 + Re(Z e^{iw tau})``: the forced part is bounded by its
        amplitude ``|Z|``, the free modes by ``sum |pa_i| max(1, e^{Re lam_i horizon})``. Lets the
        event search skip a whole interval whose event functions cannot reach zero, instead of
        sampling every fast (stiff) mode at a fraction of its period.
        """
        cfg = self.config
        if not self._ready:
            self._prepare()
        if not (cfg.modal and cfg.m) or self._near:
            return None
        cy, c0, cc, cs = red
        p = cy @ cfg.V
        pa = p * self._a
        b0, bp, bm = self._b
        k0 = (p @ b0).real + c0
        z = p @ bp + np.conj(p @ bm) + (cc - 1j * cs) * cmath.exp(1j * self.omega * self.t0)
        grow = np.exp(np.maximum(self.config.lam.real, 0.0) * horizon)
        free = np.abs(pa) @ grow
        spread = np.abs(z) + free
        # rounding of the sum of terms of these sizes
        slack = 1e-12 * (np.abs(k0) + spread + np.abs(p) @ np.abs(b0))
        return k0 - spread - slack, k0 + spread + slack

    def sampler(self, red):
        """``f(tau) -> (g, g')`` of all observable rows at local times ``tau`` (1-D array): the
        modal exp-polynomial contracted with the observables once (fast sampling for event
        search; equal to :meth:`evaluate` with ``order=1`` up to rounding)."""
        cfg = self.config
        if not self._ready:
            self._prepare()
        if not (cfg.modal and cfg.m) or self._near:
            return lambda tau: self.evaluate(red, tau, order=1)
        cy, c0, cc, cs = red
        p = cy @ cfg.V
        lam = cfg.lam
        pa = p * self._a
        pla = pa * lam
        b0, bp, bm = self._b
        k0 = ((p @ b0).real + c0)[:, None]
        kp = (p @ bp)[:, None]
        km = (p @ bm)[:, None]
        iwkp, iwkm = 1j * self.omega * kp, 1j * self.omega * km
        lamc = lam[:, None]
        w = self.omega
        t0 = self.t0
        harmonic = bool(np.any(cc != 0) or np.any(cs != 0))

        def f(tau):
            eip = np.exp(1j * w * tau)[None, :]
            eim = eip.conj()
            e = np.exp(lamc * tau[None, :])
            g = (pa @ e).real + k0 + (kp * eip + km * eim).real
            dg = (pla @ e).real + (iwkp * eip - iwkm * eim).real
            if harmonic:
                ph = w * (t0 + tau)
                co, si = np.cos(ph), np.sin(ph)
                g = g + np.outer(cc, co) + np.outer(cs, si)
                dg = dg + w * (np.outer(cs, co) - np.outer(cc, si))
            return g, dg
        return f

    def evaluate(self, red, tau, order: int = 0) -> list[np.ndarray]:
        """Observable values (n_obs, k) and time derivatives up to ``order`` at local times ``tau``."""
        cy, c0, cc, cs = red
        tau = np.atleast_1d(np.asarray(tau, dtype=float))
        ys = self.y(tau, order)
        w = self.omega
        ph = w * (self.t0 + tau)
        co, si = np.cos(ph), np.sin(ph)
        out = [cy @ ys[0] + c0[:, None] + np.outer(cc, co) + np.outer(cs, si)]
        if order >= 1:
            out.append(cy @ ys[1] + w * (np.outer(cs, co) - np.outer(cc, si)))
        if order >= 2:
            out.append(cy @ ys[2] - w * w * (np.outer(cc, co) + np.outer(cs, si)))
        return out
