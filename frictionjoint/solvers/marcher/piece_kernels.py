"""Compiled (numba) parts of a plain modal closed-form piece: its coefficients and its state.

A piece in a configuration with a modal decomposition and no (near-)resonant mode/forcing pair is

    eta(tau) = e^{lam tau} a + b0 + bp e^{i w tau} + bm e^{-i w tau},    y = Re(V eta),

with ``b0 = beta0 / (-lam)``, ``bp = gp / (i w - lam)``, ``bm = gm / (-i w - lam)`` and ``a = eta0 -
b0 - bp - bm`` (:meth:`.Interval._prepare`). The marcher builds one piece and evaluates its end state
once per event; in NumPy each is a dozen small-array calls of a few microseconds of overhead each,
here one call. The arithmetic is that of :meth:`.Interval._prepare` and :meth:`.Interval.state`.
Used where the event search is compiled (:data:`.search.ENABLED`).
"""
from __future__ import annotations

import cmath

import numpy as np

from .search import ENABLED, _jit, _resonant

__all__ = ["coefficients", "coefficients_given", "coefficients_factored", "coefficients_modal", "state", "resonant_terms", "ENABLED"]


@_jit(inline=True)
def _terms(e, b, lam, hp, hm, w, t0):
    """The rows of :func:`coefficients` from the modes' ``eta0 = e`` and ``beta0 = b``."""
    p = lam.size
    out = np.empty((8, p), np.complex128)
    ph = cmath.exp(1j * w * t0)
    phc = ph.conjugate()
    for i in range(p):
        gp = hp[i] * ph
        gm = hm[i] * phc
        c0 = b[i] / (0.0 - lam[i])
        cp = gp / (1j * w - lam[i])
        cm = gm / (-1j * w - lam[i])
        out[0, i] = e[i]
        out[1, i] = b[i]
        out[2, i] = gp
        out[3, i] = gm
        out[4, i] = ((e[i] - c0) - cp) - cm
        out[5, i] = c0
        out[6, i] = cp
        out[7, i] = cm
    return out


@_jit
def coefficients(wi, lam, y0, b0, hp, hm, w, t0):
    """Rows ``eta0, beta0, gp, gm, a, b0, bp, bm`` (8, modes) of a plain modal piece.

    Parameters
    ----------
    wi : (modes, 2m) complex ndarray
        Inverse of the eigenvector matrix (its rows for the modes kept).
    lam : (modes,) complex ndarray
        Eigenvalues.
    y0, b0 : (2m,) ndarray
        Reduced start state and constant forcing.
    hp, hm : (modes,) complex ndarray
        Half the modal harmonic loads (``ConfigData.modal_forcing``).
    w, t0 : float
        Forcing frequency [rad/s] and start time [s].
    """
    e = np.zeros(lam.size, np.complex128)
    b = np.zeros(lam.size, np.complex128)
    for i in range(lam.size):
        for k in range(y0.size):  # the reduced state's 2m; p modes (fewer where pairs are halved)
            e[i] += wi[i, k] * y0[k]
            b[i] += wi[i, k] * b0[k]
    return _terms(e, b, lam, hp, hm, w, t0)


@_jit
def coefficients_given(e, b, lam, hp, hm, w, t0):
    """:func:`coefficients` from the modal start ``e`` and constant load ``b`` (modes,) formed
    elsewhere (the left eigenvectors' products, :meth:`.propagator.ConfigData.left_product`)."""
    return _terms(e, b, lam, hp, hm, w, t0)


@_jit(inline=True)
def _factored_start(rows, right, u):
    """``(right rows) @ u`` (modes,) complex, each entry ``right_i rows_ik`` formed as NumPy formed
    it in the complex matrix ``V^-1[:, m:]`` (:func:`.propagator._inverse`), so the same numbers."""
    e = np.zeros(rows.shape[0], np.complex128)
    for i in range(rows.shape[0]):
        sr = right[i].real
        si = right[i].imag
        for k in range(u.size):
            e[i] += complex(sr * rows[i, k], si * rows[i, k]) * u[k]
    return e


@_jit
def coefficients_factored(rows, right, lam, u, r, hp, hm, w, t0):
    """:func:`coefficients` of classical modes, whose inverse is kept factored (``V^-1[:, m:] =
    right rows``, :func:`.propagator._half_modes`), for a start state ``[0, u]`` and constant
    forcing ``[0, r]``: each entry ``right_i rows_ik`` is formed as NumPy formed it in the complex
    matrix before (and the zero half's terms added nothing), so the numbers are the same.

    Parameters
    ----------
    rows : (modes, m) ndarray
        ``Phi^T Mr`` of the modes kept.
    right : (modes,) complex ndarray
        The scale of each row in ``V^-1``'s velocity columns.
    u, r : (m,) ndarray
        Velocity halves of the reduced start state and constant forcing.
    lam, hp, hm, w, t0
        As :func:`coefficients`.
    """
    e = _factored_start(rows, right, u)
    b = _factored_start(rows, right, r)
    return _terms(e, b, lam, hp, hm, w, t0)


@_jit
def coefficients_modal(rows, right, w2, lam, u, f, x0, hp, hm, w, t0):
    """:func:`coefficients_factored` with the constant load from the modal identity ``Phi^T K_c =
    W^2 Phi^T M``: ``b_i = right_i (rows_i . f - w2_i rows_i . x0)`` with ``f = M^-1 f_const``
    (:meth:`.propagator.Interval._modal_load`), instead of ``right_i rows_i . M^-1 (f_const - K_c
    x0)``; the start ``e`` is formed as there (the same numbers).

    Parameters
    ----------
    rows, right, lam, u, hp, hm, w, t0
        As :func:`coefficients_factored`.
    w2 : (modes,) ndarray
        Each kept mode's ``w^2`` (the product of its pair's roots).
    f, x0 : (m,) ndarray
        ``M^-1 f_const`` and the start displacement.
    """
    e = _factored_start(rows, right, u)
    b = np.zeros(lam.size, np.complex128)
    for i in range(lam.size):
        sf = 0.0
        sx = 0.0
        for k in range(u.size):
            sf += rows[i, k] * f[k]
            sx += rows[i, k] * x0[k]
        b[i] = right[i] * (sf - w2[i] * sx)
    return _terms(e, b, lam, hp, hm, w, t0)


@_jit
def state(v, nb, x0, lam, a, b0, bp, bm, w, tau, nidx, nmu, nc):
    """Structural displacement and velocity (n_dof,) of a modal piece at local time ``tau``:
    ``x = x0 + N Re(V eta)[:m]``, ``v = N Re(V eta)[m:]``, with the resonant terms ``nc_q
    E(lam_q, mu_q, tau)`` of the modes ``nidx`` (:attr:`.Interval.near`; none for a plain piece)."""
    p = lam.size
    m = v.shape[0] // 2  # the reduced state's 2m rows; p modes (fewer where pairs are halved)
    eta = np.empty(p, np.complex128)
    eip = cmath.exp(1j * w * tau)
    eim = eip.conjugate()
    for i in range(p):
        eta[i] = cmath.exp(lam[i] * tau) * a[i] + b0[i] + bp[i] * eip + bm[i] * eim
    for q in range(nidx.size):
        i = nidx[q]
        eta[i] += nc[q] * _resonant(lam[i], nmu[q], tau)
    y = np.empty(2 * m)
    for r in range(2 * m):
        s = 0j
        for i in range(p):
            s += v[r, i] * eta[i]
        y[r] = s.real
    n = x0.size
    x = x0.copy()
    vel = np.zeros(n)
    for r in range(n):
        sx = 0.0
        sv = 0.0
        for k in range(m):
            sx += nb[r, k] * y[k]
            sv += nb[r, k] * y[m + k]
        x[r] += sx
        vel[r] = sv
    return x, vel


@_jit
def resonant_terms(lam, mu, tau):
    """``E(lam_i, mu, tau_k)`` (modes, times) of :func:`.propagator._E`, element by element
    (:func:`.search._resonant`): the resonant terms of a piece at many times in one call."""
    out = np.empty((lam.size, tau.size), np.complex128)
    for i in range(lam.size):
        for k in range(tau.size):
            out[i, k] = _resonant(lam[i], mu, tau[k])
    return out
