"""Tests of frictionjoint.analytic against references built independently in this file.

References: (a) the ODE itself (residuals of the closed-form waveform), (b) a brute-force
event-driven integration with scipy's solve_ivp (DOP853, stick/slip events, Hong & Liu
stop rules) written here, (c) numerical Fourier integration (Gauss-Legendre on the smooth
pieces) of loops constructed here.  Den Hartog (1931); DESIGN.md section 3.
"""
from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, root

from frictionjoint.analytic import (
    DenHartogSolution,
    NoSolutionError,
    coulomb_describing_function,
    den_hartog,
    den_hartog_boundary,
    den_hartog_response,
    harmonic_balance_amplitude,
    jenkins_describing_function,
    wall_base_mapping,
)
from frictionjoint.errors import ParameterError

# Tolerances of this module (stated once).
RTOL_IVP, ATOL_IVP = 1e-12, 1e-14   # brute-force integration
TOL_BRUTE = 1e-7                    # closed form vs brute force (required by the brief)
TOL_RESIDUAL = 1e-11                # ODE residual of the closed form (units P0/k)
TOL_FOURIER = 1e-10                 # describing functions vs numerical Fourier integrals
TOL_QUAD = 1e-11                    # closed-form harmonic vs Gauss-Legendre: rounding, measured 1.7e-14

HYPO = settings(max_examples=60, deadline=None)


# ----------------------------------------------------------------------------- references


def simulate(r, f, y0, n_periods, phase0=0.0):
    """Brute force: x'' + x + f sgn(x') = cos(r tau + phase0), tau = wn t (dimensionless).

    Event-driven: slip phases with solve_ivp (DOP853) until v = 0; at v = 0 the force
    needed to hold the mass decides stick (|net| <= f) or slip in the direction of net
    (Hong & Liu); a stick ends when |cos - x| reaches f.  The state carries the Fourier
    integrals int x cos(.) dtau, int x sin(.) dtau over the run.

    Returns (y, turns, sticks): y = [x, v, Ic, Is]; turns = [(tau, x)] at v = 0 events;
    sticks = [(tau_start, tau_end, direction_before, direction_after)].
    """
    t_end = n_periods * 2.0 * math.pi / r
    t = 0.0
    y = np.array([y0[0], y0[1], 0.0, 0.0], float)
    turns, sticks = [], []
    if y[1] != 0.0:
        mode = 1 if y[1] > 0 else -1
    else:
        net = math.cos(phase0) - y[0]
        mode = 0 if abs(net) <= f else int(math.copysign(1, net))
    previous = mode
    while t < t_end:
        if mode != 0:
            s = mode

            def rhs(tt, yy, s=s):
                ph = r * tt + phase0
                return [yy[1], math.cos(ph) - yy[0] - f * s,
                        yy[0] * math.cos(ph), yy[0] * math.sin(ph)]

            def halt(tt, yy):
                return yy[1]

            halt.terminal, halt.direction = True, -s
            sol = solve_ivp(rhs, (t, t_end), y, method="DOP853", rtol=RTOL_IVP,
                            atol=ATOL_IVP, events=halt)
            t, y = sol.t[-1], sol.y[:, -1].copy()
            if sol.status == 1:
                t, y = sol.t_events[0][0], sol.y_events[0][0].copy()
                y[1] = 0.0
                turns.append((t, y[0]))
                net = math.cos(r * t + phase0) - y[0]
                previous = s
                mode = 0 if abs(net) <= f else int(math.copysign(1, net))
        else:
            xs = y[0]
            if abs(xs) + 1.0 <= f:        # held for ever: force can never beat friction
                sticks.append((t, math.inf, previous, 0))
                return y, turns, sticks

            def rhs0(tt, yy):
                ph = r * tt + phase0
                return [0.0, 0.0, xs * math.cos(ph), xs * math.sin(ph)]

            def release(tt, yy):
                return abs(math.cos(r * tt + phase0) - xs) - f

            release.terminal, release.direction = True, 1
            t0 = t
            sol = solve_ivp(rhs0, (t, t_end), y, method="DOP853", rtol=RTOL_IVP,
                            atol=ATOL_IVP, events=release, max_step=0.1 / r)
            t, y = sol.t[-1], sol.y[:, -1].copy()
            if sol.status == 1:
                t, y = sol.t_events[0][0], sol.y_events[0][0].copy()
                mode = int(math.copysign(1, math.cos(r * t + phase0) - xs))
                sticks.append((t0, t, previous, mode))
            else:
                sticks.append((t0, t, previous, 0))
    return y, turns, sticks


def brute_steady(r, f, n_march=30):
    """March from rest, then Newton-type shooting on the brute-force period map."""
    y, _, _ = simulate(r, f, [0.0, 0.0], n_march)
    sol = root(lambda z: simulate(r, f, z, 1)[0][:2] - z, y[:2], method="hybr",
               options={"xtol": 1e-14})
    y, turns, sticks = simulate(r, f, sol.x, 1)
    assert np.max(np.abs(y[:2] - sol.x)) < 1e-11     # a fixed point of the period map
    a1, b1 = y[2] * r / math.pi, y[3] * r / math.pi
    xs = np.array([x for _, x in turns])
    i = int(np.argmax(xs))
    return {
        "amplitude": float(np.max(np.abs(xs))),
        "peak_phase": math.remainder(r * turns[i][0], 2 * math.pi),
        "harmonic_amplitude": math.hypot(a1, b1),
        "harmonic_phase": math.atan2(b1, a1),
        "sticks": sticks,
    }


def gauss_legendre(func, a, b, n):
    """int_a^b func(t) dt by n-point Gauss-Legendre."""
    x, w = np.polynomial.legendre.leggauss(n)
    t = 0.5 * (b - a) * x + 0.5 * (b + a)
    return 0.5 * (b - a) * np.sum(w * func(t))


def waveform_reference(r, f, phase):
    """Den Hartog's waveform re-derived here (not imported): x̄ at force phase ``phase``."""
    v = 1.0 / (1.0 - r * r)
    u = math.tan(math.pi / (2 * r)) / r
    amp = math.sqrt(v * v - (f * u) ** 2)
    theta = math.atan2(-f * u / v, amp / v)
    s = np.mod(np.asarray(phase) - theta + math.pi, 2 * math.pi)
    sign = np.where(s < math.pi, 1.0, -1.0)
    tau = np.where(s < math.pi, s, s - math.pi) / r
    g = f * np.cos(tau) + r * f * u * np.sin(tau) + v * np.cos(r * tau + theta - math.pi) - f
    return sign * g


STOP_FREE = [(1.5, 0.3), (0.8, 0.3), (0.4, 0.13), (2.5, 0.2), (0.6, 0.4), (0.3, 0.05)]


# ----------------------------------------------------------------------------- waveform


@pytest.mark.parametrize("r, f", STOP_FREE)
def test_waveform_solves_the_ode(r, f):
    sol = den_hartog(r, f)
    assert sol.regime == "stop-free" and sol.applicable and sol.real
    phi = np.linspace(-7.0, 7.0, 4001)
    x = sol.waveform(phi)
    v = sol.waveform(phi, derivative=1)
    a = sol.waveform(phi, derivative=2)
    # x'' + x + f sgn(x') = cos(phi) with derivatives in tau = wn t.
    moving = np.abs(v) > 1e-9
    res = a + x + f * np.sign(v) - np.cos(phi)
    assert np.max(np.abs(res[moving])) < TOL_RESIDUAL
    # Exact derivatives agree with finite differences in phi (d/dtau = r d/dphi).
    h = 1e-5
    fd1 = r * (sol.waveform(phi + h) - sol.waveform(phi - h)) / (2 * h)
    fd2 = r * (sol.waveform(phi + h, 1) - sol.waveform(phi - h, 1)) / (2 * h)
    smooth = np.abs(np.mod(phi - sol.peak_phase + 0.5 * h, math.pi)) > 4 * h
    assert np.max(np.abs(fd1 - v)[smooth]) < 1e-8 * (1 + np.max(np.abs(v)))
    assert np.max(np.abs(fd2 - a)[smooth]) < 1e-8 * (1 + np.max(np.abs(a)))
    # Matches the waveform re-derived in this file.
    np.testing.assert_allclose(x, waveform_reference(r, f, phi), atol=1e-12, rtol=0)


@pytest.mark.parametrize("r, f", STOP_FREE)
def test_waveform_junction_antisymmetry_and_turning_points(r, f):
    sol = den_hartog(r, f)
    theta, e = sol.peak_phase, 1e-12
    for junction in (theta, theta - math.pi):
        for d in (0, 1):
            left, right = sol.waveform(junction - e, d), sol.waveform(junction + e, d)
            assert abs(left - right) < 1e-10
    assert sol.waveform(theta) == pytest.approx(sol.amplitude, abs=1e-13)
    assert sol.waveform(theta - math.pi) == pytest.approx(-sol.amplitude, abs=1e-13)
    assert abs(sol.waveform(theta, 1)) < 1e-12
    phi = np.linspace(0, 2 * math.pi, 997)
    np.testing.assert_allclose(sol.waveform(phi + math.pi), -sol.waveform(phi), atol=1e-13)
    np.testing.assert_allclose(sol.waveform(phi + 2 * math.pi), sol.waveform(phi), atol=1e-12)
    # Velocity positive on the open rising half-cycle (stop-free).
    rising = np.linspace(theta - math.pi, theta, 20001)[1:-1]
    assert np.all(sol.waveform(rising, 1) > 0)
    # amplitude = max |x|, and theta is where it is reached (DESIGN claim (3)).
    dense = np.linspace(0, 2 * math.pi, 200001)
    xd = sol.waveform(dense)
    assert np.max(np.abs(xd)) <= sol.amplitude + 1e-13
    assert np.max(np.abs(xd)) == pytest.approx(sol.amplitude, abs=1e-8)
    assert math.remainder(dense[np.argmax(xd)] - theta, 2 * math.pi) == pytest.approx(
        0.0, abs=1e-4)


def test_waveform_scalar_and_shape():
    sol = den_hartog(1.5, 0.3)
    assert isinstance(sol.waveform(0.3), float)
    assert sol.waveform(np.zeros((2, 3))).shape == (2, 3)
    with pytest.raises(ParameterError, match="derivative"):
        sol.waveform(0.0, derivative=4)
    with pytest.raises(NoSolutionError):
        den_hartog(0.2, 0.3).waveform(0.0)


# ----------------------------------------------------------------------------- brute force


@pytest.mark.parametrize("r, f", [(1.5, 0.3), (0.8, 0.3), (0.4, 0.13)])
def test_closed_form_matches_brute_force(r, f):
    sol = den_hartog(r, f)
    ref = brute_steady(r, f)
    assert ref["sticks"] == []
    assert abs(sol.amplitude - ref["amplitude"]) < TOL_BRUTE
    # DESIGN claim: theta is the lag of the displacement maximum behind the force maximum.
    assert abs(math.remainder(sol.peak_phase - ref["peak_phase"], 2 * math.pi)) < TOL_BRUTE
    assert abs(sol.harmonic_amplitude - ref["harmonic_amplitude"]) < TOL_BRUTE
    assert abs(sol.harmonic_phase - ref["harmonic_phase"]) < TOL_BRUTE


def test_peak_phase_is_a_lead_for_r_between_one_third_and_one_half():
    # DESIGN.md says theta in (0, pi); for 1/3 < r < 1/2, U > 0 and V > 0 so
    # sin(theta) = -f U/V < 0: the displacement maximum *leads* the force maximum.
    # Confirmed by brute force in test_closed_form_matches_brute_force at r = 0.4.
    sol = den_hartog(0.4, 0.13)
    assert sol.applicable and sol.peak_phase < 0
    assert 0 < sol.harmonic_phase < math.pi       # first harmonic still lags (energy input)


@pytest.mark.parametrize("r, f", [(0.4, 0.16), (0.34, 0.03)])
def test_mid_cycle_stops_although_den_hartog_boundary_holds(r, f):
    # Den Hartog's boundary X̄ r^2 >= f holds and the closed form is real, yet the exact
    # velocity vanishes inside the half-cycle (r < 1/2).  Found by scanning r in (0.25, 0.5):
    # at f = 0.5 (the brief's suggestion) the boundary fails for every r < 1/2
    # (den_hartog_boundary <= 1/3 there), so smaller f is needed.
    sol = den_hartog(r, f)
    assert sol.real and sol.amplitude * r * r >= f
    assert sol.regime == "stops" and not sol.applicable
    assert "inside the half-cycle" in sol.message
    # Independent: the re-derived waveform's velocity changes sign on the rising half.
    v = 1.0 / (1 - r * r)
    u = math.tan(math.pi / (2 * r)) / r
    theta = math.atan2(-f * u / v, math.sqrt(v * v - (f * u) ** 2) / v)
    tau = np.linspace(0, math.pi / r, 100001)[1:-1]
    vel = -f * np.sin(tau) + r * f * u * np.cos(tau) - r * v * np.sin(r * tau + theta - math.pi)
    assert np.min(vel) < 0
    # Brute force: the steady motion sticks, and resumes in the same direction (a stop
    # inside the half-cycle, not at a turning point).
    _, _, sticks = simulate(r, f, [0.0, 0.0], 30)
    t_last = 20 * 2 * math.pi / r
    late = [s for s in sticks if s[0] > t_last]
    assert late
    assert any(before == after for _, _, before, after in late if after != 0)


def test_stop_free_just_below_the_true_limit():
    # r = 0.4: Den Hartog's boundary is f = 0.1769 but stops begin near f = 0.1439.
    assert den_hartog_boundary(0.4) == pytest.approx(0.17685270302576, rel=1e-10)
    assert den_hartog(0.4, 0.14).regime == "stop-free"
    assert den_hartog(0.4, 0.15).regime == "stops"
    _, _, sticks = simulate(0.4, 0.14, [0.0, 0.0], 40)
    assert not [s for s in sticks if s[0] > 30 * 2 * math.pi / 0.4]


@settings(max_examples=80, deadline=None)
@given(r=st.floats(0.5, 6.0), q=st.floats(0.0, 1.0))
def test_den_hartog_boundary_is_sufficient_for_r_at_least_half(r, q):
    # DESIGN: for r >= 1/2, X̄ r^2 >= f is sufficient (velocity never vanishes inside).
    f = q * den_hartog_boundary(r) * (1 - 1e-9)
    if r == 1.0 or f >= 1.0:
        return
    sol = den_hartog(r, f)
    assert sol.regime == "stop-free", (r, f, sol.message)


def test_boundary_tends_to_pi_over_4_at_resonance():
    for eps in (1e-3, -1e-3, 1e-6):
        assert den_hartog_boundary(1 + eps) == pytest.approx(math.pi / 4, rel=5e-3)
    assert den_hartog_boundary(1.0) == math.pi / 4


def test_unbounded_at_resonance_grows_by_pi_minus_4f():
    r, f = 1.0, 0.5
    sol = den_hartog(r, f)
    assert sol.regime == "unbounded" and sol.amplitude == math.inf and not sol.real
    _, turns, _ = simulate(r, f, [0.0, 0.0], 30)
    xs = np.abs([x for _, x in turns])
    # per period (two turning points later), in units P0/k
    assert xs[-1] - xs[-3] == pytest.approx(math.pi - 4 * f, rel=1e-6)
    assert den_hartog(1.0, 0.9).regime == "stops"
    assert den_hartog(1.0, 0.9).amplitude != den_hartog(1.0, 0.9).amplitude  # nan


def test_permanent_stick_for_f_at_least_one():
    sol = den_hartog(0.7, 1.2)
    assert sol.regime == "stuck" and not sol.applicable
    _, _, sticks = simulate(0.7, 1.2, [3.0, 0.0], 40)
    assert sticks[-1][1] == math.inf
    assert den_hartog(2.0, 1.0).regime == "stuck"
    assert den_hartog(1.0, 1.0).regime == "stuck"
    assert den_hartog(0.99, 0.999).regime == "stops"


def test_family_at_r_one_over_2n():
    # U = 0 at r = 1/4: offsets of the closed form are periodic under the brute-force
    # period map too (a family), so the solution is flagged non-unique.
    r, f = 0.25, 0.01
    sol = den_hartog(r, f)
    assert sol.applicable and not sol.unique and sol.friction_factor == 0.0
    assert "family" in sol.message
    for c in (-0.03, 0.0, 0.03):
        z0 = np.array([-sol.amplitude + c, 0.0])
        y, _, sticks = simulate(r, f, z0, 1, phase0=sol.peak_phase - math.pi)
        assert not sticks
        assert np.max(np.abs(y[:2] - z0)) < 1e-9
    assert den_hartog(0.25 + 1e-9, f).unique
    assert den_hartog(0.5, 0.1).unique is False
    assert den_hartog(1 / 3, 0.0).unique is False      # undamped: r = 1/n
    assert den_hartog(1 / 3, 0.01).unique is True


# ----------------------------------------------------------------------------- harmonic


@pytest.mark.parametrize("r, f", STOP_FREE)
def test_first_harmonic_closed_form_vs_gauss_legendre(r, f):
    # Gauss-Legendre of the (smooth) half-cycles converges spectrally to the closed form.
    sol = den_hartog(r, f)
    lo = sol.peak_phase - math.pi
    errors = []
    for n in (8, 16, 32, 64, 128):
        a1 = 2 / math.pi * gauss_legendre(lambda p: sol.waveform(p) * np.cos(p), lo,
                                          lo + math.pi, n)
        b1 = 2 / math.pi * gauss_legendre(lambda p: sol.waveform(p) * np.sin(p), lo,
                                          lo + math.pi, n)
        errors.append(max(abs(math.hypot(a1, b1) - sol.harmonic_amplitude),
                          abs(math.atan2(b1, a1) - sol.harmonic_phase)))
    assert errors[-1] < TOL_QUAD and errors[-2] < TOL_QUAD
    # FFT of the periodic waveform agrees too.
    n = 4096
    phi = 2 * math.pi * np.arange(n) / n
    c1 = 2 * np.fft.rfft(sol.waveform(phi))[1] / n     # a1 - i b1
    assert abs(c1) == pytest.approx(sol.harmonic_amplitude, abs=1e-6)


@HYPO
@given(r=st.floats(0.15, 5.0), q=st.floats(0.01, 0.99))
def test_energy_balance_passivity_and_residual(r, q):
    # Work of the force per cycle, int cos(phi) dx, equals the friction dissipation 4 f X̄.
    f = min(q * den_hartog_boundary(r), 0.99)
    sol = den_hartog(r, f)
    assume(sol.applicable)
    phi = np.linspace(0, 2 * math.pi, 513)
    vel = sol.waveform(phi, 1)
    res = sol.waveform(phi, 2) + sol.waveform(phi) + f * np.sign(vel) - np.cos(phi)
    assert np.max(np.abs(res[np.abs(vel) > 1e-9])) < TOL_RESIDUAL * max(1.0, sol.amplitude)
    lo = sol.peak_phase - math.pi
    work = 2 * gauss_legendre(lambda p: np.cos(p) * sol.waveform(p, 1) / r, lo, lo + math.pi,
                              max(160, int(8 / r)))
    scale = max(1.0, sol.dissipation_per_cycle)
    assert work == pytest.approx(sol.dissipation_per_cycle, abs=1e-9 * scale)
    assert sol.dissipation_per_cycle >= 0
    assert 0 < sol.harmonic_phase < math.pi
    assert math.cos(sol.peak_phase) == pytest.approx(
        sol.amplitude * (1 - r * r), rel=1e-9, abs=1e-12)


def test_no_friction_is_the_linear_response():
    for r in (0.3, 0.7, 1.3, 4.0):
        sol = den_hartog(r, 0.0)
        assert sol.applicable
        assert sol.amplitude == pytest.approx(1 / abs(1 - r * r), rel=1e-14)
        assert sol.harmonic_amplitude == pytest.approx(sol.amplitude, rel=1e-14)
        assert sol.harmonic_phase == (0.0 if r < 1 else math.pi)


# ----------------------------------------------------------------------------- HB / DF


def test_harmonic_balance_errors_at_f_0p7():
    # DESIGN: "+/-20-30 % at f = 0.7".  Measured: -30 % at r = 0.8, +23 % at r = 1.1,
    # only -9 %/+10 % at r = 0.95/1.05, but -42 % at the low edge (r ~ 0.687) and +82 % at
    # the high edge (r ~ 1.245) of the stop-free band.
    f = 0.7
    rel = {}
    for r in (0.8, 0.95, 1.05, 1.1):
        rel[r] = harmonic_balance_amplitude(r, f) / den_hartog(r, f).amplitude - 1
    assert -0.32 < rel[0.8] < -0.28 and 0.21 < rel[1.1] < 0.25
    assert abs(rel[0.95]) < 0.1 and abs(rel[1.05]) < 0.11
    band = [r for r in np.linspace(0.6, 1.4, 801) if den_hartog(r, f).applicable]
    errs = [harmonic_balance_amplitude(r, f) / den_hartog(r, f).amplitude - 1 for r in band]
    assert min(errs) < -0.4 and max(errs) > 0.8
    assert 0.68 < band[0] < 0.70 and 1.24 < band[-1] < 1.26


def test_harmonic_balance_limits():
    assert harmonic_balance_amplitude(2.0, 0.0) == pytest.approx(1 / 3)
    assert harmonic_balance_amplitude(1.0, 0.5) == math.inf
    assert harmonic_balance_amplitude(0.5, math.pi / 4) == 0.0
    with pytest.raises(NoSolutionError, match="friction_ratio"):
        harmonic_balance_amplitude(0.5, 0.8)
    with pytest.raises(ValueError):
        harmonic_balance_amplitude(1.0, math.pi / 4)


def test_coulomb_describing_function_vs_fourier():
    F, X, w = 3.0, 0.02, 50.0
    # friction force F sgn(x') with x = X cos(phi): x' < 0 on (0, pi)
    b1 = (gauss_legendre(lambda p: -F * np.sin(p), 0, math.pi, 40)
          + gauss_legendre(lambda p: F * np.sin(p), math.pi, 2 * math.pi, 40)) / math.pi
    # first harmonic b1 sin(phi) = c_eq x' = -c_eq X w sin(phi)
    assert coulomb_describing_function(F, X, w) == pytest.approx(-b1 / (X * w), rel=1e-13)


def jenkins_loop_harmonic(kt, fs, u0, n=60):
    """First harmonic (a1, b1) of the exact Jenkins loop under u = u0 cos(phi), built here.

    The element (spring kt to a slider at s; force kt (u - s), |force| <= fs) is driven
    from rest up to u0, then through a whole cycle; on each monotone half the force is
    smooth apart from the stick->slip switch, located by Brent's method; each piece is
    integrated by n-point Gauss-Legendre.
    """
    def step(s, u):
        q = kt * (u - s)
        if q > fs:
            s = u - fs / kt
        elif q < -fs:
            s = u + fs / kt
        return s

    s = step(0.0, u0)                       # loading from rest to u = u0
    a1 = b1 = 0.0
    for lo in (0.0, math.pi):
        s0 = s

        def force(p, s0=s0):
            return np.array([kt * (u0 * math.cos(q) - step(s0, u0 * math.cos(q)))
                             for q in np.atleast_1d(p)])

        sign = math.copysign(1.0, kt * (u0 * math.cos(lo) - s0))

        def stuck_margin(p, s0=s0, sign=sign):   # > 0 while the stuck force is within fs
            return sign * kt * (u0 * math.cos(p) - s0) + fs

        pieces = [lo, lo + math.pi]
        if stuck_margin(lo + math.pi) < 0:
            pieces = [lo, brentq(stuck_margin, lo, lo + math.pi, xtol=1e-16, rtol=1e-15),
                      lo + math.pi]
        for a, b in zip(pieces, pieces[1:]):
            a1 += gauss_legendre(lambda p: force(p) * np.cos(p), a, b, n) / math.pi
            b1 += gauss_legendre(lambda p: force(p) * np.sin(p), a, b, n) / math.pi
        s = step(s0, u0 * math.cos(lo + math.pi))
    return a1, b1


@pytest.mark.parametrize("ratio", [1.0001, 1.3, 2.0, 5.0, 40.0, 3000.0])
def test_jenkins_describing_function_vs_loop(ratio):
    kt, fs = 2.0e6, 150.0
    u0 = ratio * fs / kt
    k = jenkins_describing_function(kt, fs, u0)
    a1, b1 = jenkins_loop_harmonic(kt, fs, u0)
    # force first harmonic = u0 (Re K cos - Im K sin)
    assert abs(k - complex(a1, -b1) / u0) < TOL_FOURIER * abs(k)
    # dissipation = loop area 4 fs (u0 - uy)
    assert math.pi * u0 ** 2 * k.imag == pytest.approx(4 * fs * (u0 - fs / kt), rel=1e-12)


def test_jenkins_no_slip_and_continuity():
    kt, fs = 1e5, 10.0
    uy = fs / kt
    assert jenkins_describing_function(kt, fs, 0.5 * uy) == complex(kt, 0)
    assert jenkins_describing_function(kt, fs, uy) == complex(kt, 0)
    above = jenkins_describing_function(kt, fs, uy * (1 + 1e-9))
    assert abs(above - kt) < 1e-6 * kt
    assert jenkins_describing_function(kt, 0.0, 1e-3) == complex(0.0, 0.0)
    # series branch (beta < 0.05) continuous with the direct formula
    u_switch = uy / math.sin(0.025) ** 2
    lo, hi = (jenkins_describing_function(kt, fs, u_switch * (1 + d)) for d in (-1e-15, 1e-15))
    assert abs(lo - hi) < 1e-12 * abs(lo)


# ----------------------------------------------------------------------------- physical units


def test_den_hartog_response_units_and_base():
    m, k, F, P, Y = 2.0, 800.0, 3.0, 6.0, 0.01
    wn = math.sqrt(k / m)
    w = 1.5 * wn
    resp = den_hartog_response(m, k, F, P, w, base_amplitude=Y)
    p0 = P + k * Y
    sol = den_hartog(1.5, F / p0)
    assert resp.equivalent_force_amplitude == p0
    assert resp.amplitude == pytest.approx(sol.amplitude * p0 / k, rel=1e-15)
    assert resp.phase == sol.harmonic_phase and resp.regime == "stop-free" and resp.applicable
    assert resp.dissipation_per_cycle == pytest.approx(4 * F * resp.amplitude)
    # x(t) satisfies m x'' + k (x - y) + F sgn(x') = P cos(w t), y = Y cos(w t)
    t = np.linspace(0, 3 * 2 * math.pi / w, 3001)
    x = resp.displacement(t)
    xdd = p0 / m * sol.waveform(w * t, 2)
    xd = sol.waveform(w * t, 1)
    res = m * xdd + k * (x - Y * np.cos(w * t)) + F * np.sign(xd) - P * np.cos(w * t)
    assert np.max(np.abs(res[np.abs(xd) > 1e-9])) < 1e-9 * p0


def test_den_hartog_response_negative_equivalent_force():
    m, k, F, w = 1.0, 100.0, 1.0, 15.0
    pos = den_hartog_response(m, k, F, 5.0, w)
    neg = den_hartog_response(m, k, F, -5.0, w)
    assert neg.amplitude == pos.amplitude
    assert math.cos(neg.phase - pos.phase) == pytest.approx(-1.0)
    assert -math.pi < neg.phase < 0
    t = np.linspace(0, 1, 101)
    np.testing.assert_allclose(neg.displacement(t), -pos.displacement(t), atol=1e-14)
    with pytest.raises(ParameterError, match="nonzero"):
        den_hartog_response(m, k, F, 1.0, w, base_amplitude=-0.01)


def test_wall_base_mapping_residual():
    m, k, F, Y = 1.5, 600.0, 2.0, 0.01
    wn = math.sqrt(k / m)
    w = 1.4 * wn
    r = w / wn
    p0, f = wall_base_mapping(k, F, Y, w, m)
    assert p0 == pytest.approx(k * Y * r * r, rel=1e-14)
    assert f == pytest.approx(F / (k * Y) / r ** 2, rel=1e-14)
    sol = den_hartog(r, f)
    assert sol.applicable
    # x = y + z: m x'' + k (x - y) + F sgn(x' - y') = 0 with y = Y cos(w t)
    t = np.linspace(0, 2 * 2 * math.pi / w, 2001)
    z = p0 / k * sol.waveform(w * t)
    zd = sol.waveform(w * t, 1)
    zdd = p0 / m * sol.waveform(w * t, 2)
    xdd = zdd - Y * w * w * np.cos(w * t)
    res = m * xdd + k * z + F * np.sign(zd)
    assert np.max(np.abs(res[np.abs(zd) > 1e-9])) < 1e-9 * p0


# ----------------------------------------------------------------------------- validation


@pytest.mark.parametrize("args, name", [
    ((0.0, 0.1), "frequency_ratio"), ((-1.0, 0.1), "frequency_ratio"),
    ((math.nan, 0.1), "frequency_ratio"), ((math.inf, 0.1), "frequency_ratio"),
    ((1.5, -0.1), "friction_ratio"), ((1.5, math.nan), "friction_ratio"),
    ((1.5, True), "friction_ratio"), (("1.5", 0.1), "frequency_ratio"),
])
def test_den_hartog_rejects_bad_input(args, name):
    with pytest.raises(ParameterError, match=name):
        den_hartog(*args)


@pytest.mark.parametrize("kwargs, name", [
    ({"mass": 0.0}, "mass"), ({"stiffness": -1.0}, "stiffness"),
    ({"slip_force": -1.0}, "slip_force"), ({"force_amplitude": math.inf}, "force_amplitude"),
    ({"omega": 0.0}, "omega"), ({"base_amplitude": math.nan}, "base_amplitude"),
])
def test_response_rejects_bad_input(kwargs, name):
    good = dict(mass=1.0, stiffness=100.0, slip_force=1.0, force_amplitude=5.0, omega=12.0)
    good.update(kwargs)
    with pytest.raises(ParameterError, match=name):
        den_hartog_response(**good)


def test_other_functions_reject_bad_input():
    with pytest.raises(ParameterError, match="amplitude"):
        coulomb_describing_function(1.0, 0.0, 1.0)
    with pytest.raises(ParameterError, match="omega"):
        coulomb_describing_function(1.0, 1.0, -1.0)
    with pytest.raises(ParameterError, match="tangential_stiffness"):
        jenkins_describing_function(0.0, 1.0, 1.0)
    with pytest.raises(ParameterError, match="amplitude"):
        jenkins_describing_function(1.0, 1.0, -1.0)
    with pytest.raises(ParameterError, match="base_amplitude"):
        wall_base_mapping(1.0, 1.0, 0.0, 1.0, 1.0)
    with pytest.raises(ParameterError, match="friction_ratio"):
        harmonic_balance_amplitude(1.0, -0.1)
    with pytest.raises(ParameterError, match="frequency_ratio"):
        den_hartog_boundary(0.0)
    assert issubclass(NoSolutionError, ParameterError)


def test_solution_is_frozen_and_not_real_is_nan():
    sol = den_hartog(0.2, 0.3)         # r = 1/5: U infinite, closed form complex
    assert isinstance(sol, DenHartogSolution)
    assert not sol.real and sol.regime == "stops" and math.isnan(sol.amplitude)
    with pytest.raises(AttributeError):
        sol.amplitude = 1.0
    real_with_stops = den_hartog(5.0, 0.6)
    assert real_with_stops.real and real_with_stops.regime == "stops"
    assert math.isfinite(real_with_stops.amplitude)
