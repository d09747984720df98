"""Closed-form pieces (frictionjoint.solvers.marcher.propagator): the near-resonant integral E and the
compiled coefficients and states of plain modal pieces."""
import math

import numpy as np
import pytest
import scipy.integrate

import frictionjoint as fj
from frictionjoint.solvers.marcher import piece_kernels, propagator
from frictionjoint.solvers.marcher.events import EventLog, Marcher
from frictionjoint.solvers.marcher.propagator import _E


def test_near_resonant_integral_matches_quadrature_and_stays_finite():
    """E(lam, mu, tau) = int_0^tau e^{lam (tau - s)} e^{mu s} ds, including a stiff decaying mode over a long piece, where the
    form tau e^{lam tau} phi1((mu - lam) tau) is 0 * inf (NaN before the second form was added).
    Reference: the textbook form (e^{mu tau} - e^{lam tau}) / (mu - lam) where |mu - lam| >= 1,
    adaptive quadrature (scipy.integrate.quad, rtol 1e-13) near resonance."""
    mu = 3j
    lam = np.array([[-1e5 + 0j], [-1.0 + 2j], [1e-9 + 0j], [mu + 1e-12]])
    tau = np.array([[0.0, 1e-3, 0.1, 10.0]])
    got = _E(lam, mu, tau)
    assert np.all(np.isfinite(got))
    for i, l in enumerate(lam[:, 0]):
        for k, t in enumerate(tau[0]):
            if abs(mu - l) >= 1.0:
                # far from resonance the textbook form is well conditioned
                ref = (np.exp(mu * t) - np.exp(l * t)) / (mu - l)
            else:
                def part(s, f):
                    return f(np.exp(l * (t - s) + mu * s))
                ref = (scipy.integrate.quad(part, 0.0, t, args=(np.real,), epsabs=0, epsrel=1e-13, limit=400)[0]
                       + 1j * scipy.integrate.quad(part, 0.0, t, args=(np.imag,), epsabs=0, epsrel=1e-13,
                                                   limit=400)[0])
            assert abs(got[i, k] - ref) <= 1e-12 * abs(ref), (l, t, got[i, k], ref)


def test_compiled_piece_kernels_match_numpy():
    """Coefficients and end states of plain modal pieces (solvers.piece_kernels, numba) against the
    NumPy arithmetic of Interval._prepare / Interval.state, over the pieces of a march."""
    if not piece_kernels.ENABLED:
        pytest.skip("numba not available")
    n = 6
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    sysm = fj.FrictionSystem(fj.LinearStructure.chain(n, damping=0.02 * w1),
                             [fj.Jenkins(0.5 * w1 ** 2, 0.002, dof=5), fj.CoulombSlider(0.001, dof=4)],
                             omega=0.9 * w1, excitation=[fj.HarmonicForce(n - 1, 0.01)])
    m = Marcher(sysm)
    pieces = []
    m.march(m.initial_state(np.zeros(n), np.zeros(n)), 4 * 2 * math.pi / sysm.omega, EventLog(),
            on_interval=lambda itv, tau: pieces.append((itv, tau)))
    checked = 0
    for itv, tau in pieces:
        if not itv.modal_search():
            continue
        ref = propagator.Interval.from_parts(sysm, itv.config, itv.t0, itv.x0, itv.f_const, itv.kx0,
                                             itv._y0, itv._bvec[0])
        piece_kernels.ENABLED = False
        try:
            ref._prepare()
        finally:
            piece_kernels.ENABLED = True
        for a, b in zip([itv._a, *itv._b], [ref._a, *ref._b]):
            # compiled kernel and NumPy reference of the same formulas: rounding (the state below
            # measured at 1.1e-15 of its scale, within 10x of the former 1e-14); 1e-12 is ~1000x
            assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(b))
        x, v = piece_kernels.state(itv.config.V, itv.config.N, itv.x0, itv.config.lam, itv._a, *itv._b,
                                   sysm.omega, tau, *itv.near)
        xr, vr = ref.state(tau)
        assert np.max(np.abs(x - xr[:, 0])) <= 1e-12 * np.max(np.abs(xr))
        assert np.max(np.abs(v - vr[:, 0])) <= 1e-12 * np.max(np.abs(xr)) * itv.config.max_rate
        checked += 1
    assert checked > 10


def test_left_modes_are_the_inverse_of_refined_modes():
    """propagator._left_modes: V^-1 of a symmetric pencil's refined modes from their shapes. Against
    inv(V) on a damped 3-DOF configuration with a stuck spring at kt/k = 1e4 (inv(V) is accurate
    there: ~eps cond(V), cond ~ 1e3), to 1e-12 of each row; None where it does not apply (an
    unsymmetric damping, a repeated eigenvalue whose shapes are not M-orthogonal)."""
    mr = np.diag([1.0, 0.5, 2.0])
    kr = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    cr = 0.01 * kr + 0.002 * mr
    dr = np.array([[1.0], [0.0], [-1.0]])
    kt = np.array([1e4])
    kc = kr + kt[0] * dr @ dr.T
    a = np.block([[np.zeros((3, 3)), np.eye(3)], [-np.linalg.solve(mr, kc), -np.linalg.solve(mr, cr)]])
    lam, (tsc, v), _ = propagator._general_modes(a)
    lam, v = propagator._refine_modes(lam.astype(complex), v, mr, cr, kr, dr, kt)
    w = propagator._left_modes(lam, v, mr, cr, kr)
    ref = np.linalg.inv(v)
    assert w is not None
    assert np.all(np.max(np.abs(w - ref), axis=1) <= 1e-12 * np.max(np.abs(ref), axis=1))
    assert propagator._left_modes(lam, v, mr, cr + np.triu(cr, 1) * 1e-3, kr) is None
    # K = M = I: every mode at +-i; shapes (1, 0) and (1, 1)/sqrt(2) are modes but not M-orthogonal
    phi = np.array([[1.0, 0.0], [1.0, 1.0]]).T / [1.0, math.sqrt(2.0)]
    lam2 = np.array([1j, 1j, -1j, -1j])
    shapes = np.hstack([phi, phi]).astype(complex)
    v2 = np.vstack([shapes, shapes * lam2])
    assert propagator._left_modes(lam2, v2, np.eye(2), np.zeros((2, 2)), np.eye(2)) is None
