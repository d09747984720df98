"""Stuck Jenkins springs far stiffer than the structure beside a slipping slider
(frictionjoint.solvers.marcher: Marcher.interval, consistency.check, Interval).

2-DOF chain M = diag(1, 0.5), K = [[2, -1], [-1, 1]], undamped, a Jenkins joint of stiffness kt between
the masses (slip force 1e6: always stuck) with its slider offset (x0 = (-1, 0), w = -1: the spring
unstressed, d.x0 = w = -1), a Coulomb slider on DOF 0 that slips from the start, excitation cos(0.01 t)
on DOF 1. The piece's constant load held k (d.x) and k w d (each ~ kt |x|) apart in the load vector:
their rounding there, eps kt |x| in every DOF, drove the soft modes (2e-6 of the slip force's response
at kt = 1e8). The reference is the closed form of the linear piece in decimal arithmetic (50 digits:
the modes of K + kt d d^T from the quadratic of its pencil, the modal responses to the constant and
harmonic loads written out), independent of the library's modal arithmetic.
"""
import decimal
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.solvers.marcher.events import EventLog, Marcher

# tolerances, stated once
RTOL_PIECE = 2e-14      # the piece's state at 1 s against the decimal closed form, relative to max |x| (|v|)
ENERGY_RESIDUAL = 1e-9  # tests/stress/test_stress.py::test_mdof_jenkins_iwan_wide_ranges' bar

M = np.diag([1.0, 0.5])
K = np.array([[2.0, -1.0], [-1.0, 1.0]])
OMEGA = 0.01
X0 = (-1.0, 0.0)
T_END = 1.0
D = decimal.Decimal


def _pi() -> decimal.Decimal:
    """pi to the context's precision (the decimal module's documented recipe)."""
    decimal.getcontext().prec += 2
    three = D(3)
    lasts, t, s, n, na, d, da = 0, three, 3, 1, 0, 0, 24
    while s != lasts:
        lasts = s
        n, na = n + na, na + 8
        d, da = d + da, da + 32
        t = (t * n) / d
        s += t
    decimal.getcontext().prec -= 2
    return +s


def _cos_sin(x: decimal.Decimal) -> tuple:
    """``(cos x, sin x)`` by their Taylor series after reducing ``x`` to ``[-pi, pi]``."""
    two_pi = 2 * _pi()
    x = x - two_pi * (x / two_pi).to_integral_value()
    small = D(10) ** -(decimal.getcontext().prec + 5)
    c, s, term, k = D(0), D(0), D(1), 0  # term = x^k / k!, signs + + - - per four terms
    while abs(term) > small:
        signed = -term if k % 4 >= 2 else term
        if k % 2:
            s += signed
        else:
            c += signed
        k += 1
        term = term * x / k
    return c, s


def _reference(kt: float, fs: float, t: float) -> tuple[np.ndarray, np.ndarray]:
    """``(x, v)`` at ``t`` of the linear piece (joint stuck, the slider on DOF 0 slipping forward with
    force ``fs``; none where ``fs`` is 0) from ``X0`` at rest, in decimal arithmetic.

    Mass-normalised modes ``phi_i`` of ``(K_c, M)``, ``K_c = K + kt d d^T`` exact in decimal; with
    ``x = X0 + sum phi_i q_i`` each ``q_i'' + w_i^2 q_i = p_i + h_i cos(W t)`` from rest, ``p_i =
    phi_i^T (-K X0 - kt d (d.X0 - w) - fs e_0)`` (``w = d.X0``), ``h_i = phi_i^T e_1``."""
    with decimal.localcontext() as ctx:
        ctx.prec = 50
        m1, m2 = D(M[0, 0]), D(M[1, 1])
        k = [[D(K[i, j]) for j in range(2)] for i in range(2)]
        kt_, fs_, w_, t_ = D(kt), D(fs), D(OMEGA), D(t)
        x0 = [D(X0[0]), D(X0[1])]
        dd = [D(1), D(-1)]
        kc = [[k[i][j] + kt_ * dd[i] * dd[j] for j in range(2)] for i in range(2)]
        # the spring unstressed at the start (w = d.X0): no spring force in the constant load
        f0 = [-(k[i][0] * x0[0] + k[i][1] * x0[1]) for i in range(2)]
        f0[0] -= fs_
        a = m1 * m2
        b = m1 * kc[1][1] + m2 * kc[0][0]
        c = kc[0][0] * kc[1][1] - kc[0][1] * kc[1][0]
        root = (b * b - 4 * a * c).sqrt()
        x = list(x0)
        v = [D(0), D(0)]
        cw, sw = _cos_sin(w_ * t_)
        for lam in ((b - root) / (2 * a), (b + root) / (2 * a)):
            phi = [kc[1][1] - lam * m2, -kc[1][0]]
            nrm = (m1 * phi[0] ** 2 + m2 * phi[1] ** 2).sqrt()
            phi = [p / nrm for p in phi]
            p = phi[0] * f0[0] + phi[1] * f0[1]
            h = phi[1]
            om = lam.sqrt()
            co, so = _cos_sin(om * t_)
            q = p / lam * (1 - co) + h * (cw - co) / (lam - w_ * w_)
            dq = p / om * so + h * (-w_ * sw + om * so) / (lam - w_ * w_)
            for i in range(2):
                x[i] += phi[i] * q
                v[i] += phi[i] * dq
        return np.array([float(e) for e in x]), np.array([float(e) for e in v])


def _system(kt: float, fs: float):
    elements = [fj.Jenkins(kt, 1e6, direction=[1.0, -1.0])]
    if fs:
        elements.append(fj.CoulombSlider(fs, dof=0))
    return fj.FrictionSystem(fj.LinearStructure(M, K), elements, omega=OMEGA,
                             excitation=[fj.HarmonicForce(1, 1.0)])


def test_decimal_reference_is_the_ode():
    """The reference against DOP853 on the spring-form ODE (kt = 1e4: soft enough to integrate
    tightly in a fraction of a second), to the integrator's 1e-11."""
    scipy_integrate = pytest.importorskip("scipy.integrate")
    kt, fs = 1e4, 1e-3
    d = np.array([1.0, -1.0])

    def rhs(t, y):
        f = np.array([-fs, math.cos(OMEGA * t)]) - K @ y[:2] - kt * (d @ y[:2] + 1.0) * d
        return np.concatenate([y[2:], f / np.diag(M)])

    sol = scipy_integrate.solve_ivp(rhs, (0.0, T_END), [*X0, 0.0, 0.0], method="DOP853", rtol=1e-13, atol=1e-16)
    x, v = _reference(kt, fs, T_END)
    # DOP853's global error is not bounded by its rtol and varies with its steps (measured 2.3e-12);
    # 1e-9 is over 100x that, and far above the 50-digit reference's own error
    assert np.max(np.abs(sol.y[:2, -1] - x)) <= 1e-9
    assert np.max(np.abs(sol.y[2:, -1] - v)) <= 1e-9


# the NumPy event search resolves each period of the stuck mode (1.7e5 rad/s at kt = 1e10) while the
# slider's velocity row sits in its zero band at the start: ~10 s there, against 0.1 s compiled; at
# kt = 1e12 (1.7e6 rad/s) it gives up after its 1e6 samples (not run)
CASES = [(kt, fs, jit) for kt in (1e4, 1e8) for fs in (1e-3, 0.0) for jit in (True, False)] + [
    (1e10, 1e-3, True), pytest.param(1e10, 1e-3, False, marks=pytest.mark.slow), (1e10, 0.0, True), (1e10, 0.0, False),
    (1e12, 1e-3, True), (1e12, 0.0, True), (1e12, 0.0, False)]


@pytest.mark.parametrize("kt, fs, jit", CASES)
def test_stuck_stiff_spring_piece_is_exact(kt, fs, jit):
    """The first piece (one configuration to past 1 s) at 1 s, on both settling paths (the compiled
    consistency test and the NumPy start), to rounding of the motion. With the slider, the spring's
    k (d.x) and k w d in the load vector had put it off by 1e-13, 1e-9 and 2.8e-7 of the motion at
    kt = 1e4, 1e8 and 1e10 (1.2e-5 at 1e12); at kt = 1e12 the soft modes' rows of inv(V) were then
    still 1.1e-10 off (1.2e-12 of the motion; the rows from the shapes now, propagator._left_modes)."""
    mar = Marcher(_system(kt, fs))
    mar.jit = jit
    pieces = []
    mar.march(mar.initial_state(list(X0), [0.0, 0.0]), T_END, EventLog(),
              on_interval=lambda itv, tau: pieces.append((itv, tau)))
    assert len(pieces) == 1 and pieces[0][1] == T_END
    itv = pieces[0][0]
    assert np.array_equal(itv.status, [0, 1] if fs else [0])
    x, v = (a[:, 0] for a in itv.state(T_END))
    xr, vr = _reference(kt, fs, T_END)
    assert np.max(np.abs(x - xr)) <= RTOL_PIECE * np.max(np.abs(xr)), (x - xr)
    assert np.max(np.abs(v - vr)) <= RTOL_PIECE * np.max(np.abs(vr)), (v - vr)


def test_wide_range_chain_energy_balance():
    """tests/stress/test_stress.py::test_mdof_jenkins_iwan_wide_ranges at kt = 1e8, fs = 0.1, r = 0.01,
    zeta = 0, three Iwan sliders, x0 = -1 (10 s): its energy residual was 1.5e-9 of the scale."""
    kt, fs = 1e8, 0.1
    iwan = fj.Iwan([(kt * (j + 1) / 3, fs * (j + 1) / 3) for j in range(3)], dof=0)
    sysm = fj.FrictionSystem(fj.LinearStructure(M, K), [fj.Jenkins(kt, fs, direction=[1.0, -1.0]), iwan],
                             omega=0.01, excitation=[fj.HarmonicForce(1, 1.0)])
    tr = fj.simulate(sysm, 10.0, [-1.0, 0.0], [0.0, 0.0], record=("x", "energy"))
    assert tr.success, tr.message
    scale = max(np.max(np.abs(tr.work)), np.max(tr.stored_energy), np.max(tr.dissipated_friction), 2.0)
    assert np.max(np.abs(tr.energy_residual())) <= ENERGY_RESIDUAL * scale
