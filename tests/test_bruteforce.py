"""Self-tests of the independent brute-force reference (benchmarks/bruteforce.py).

Everything here is checked against closed forms; nothing imports frictionjoint.
"""
import math

import numpy as np
from scipy.integrate import quad, simpson
from scipy.linalg import expm

from benchmarks.bruteforce import (coulomb_response, coulomb_steady_state, iwan_response,
                        jenkins_response)


def linear_exact(m, c, K, A, w, b, x0, v0, t):
    """m x'' + c x' + K x = A cos(wt) + b, exact."""
    Z = K - m * w * w + 1j * c * w
    ph = A / Z
    xp = lambda tt: np.real(ph * np.exp(1j * w * tt)) + b / K
    vp = lambda tt: np.real(1j * w * ph * np.exp(1j * w * tt))
    M = np.array([[0.0, 1.0], [-K / m, -c / m]])
    d0 = np.array([x0 - xp(0.0), v0 - vp(0.0)])
    hom = np.array([expm(M * ti) @ d0 for ti in t]).T
    return xp(t) + hom[0], vp(t) + hom[1]


def den_hartog(r, f):
    V = 1.0 / (1.0 - r * r)
    U = math.tan(math.pi / (2.0 * r)) / r
    return math.sqrt(V * V - f * f * U * U)


# ------------------------------------------------------------------ linear limits
def test_coulomb_linear_limit():
    m, k, c, P, Y, w, x0, v0 = 1.5, 2.0, 0.1, 1.0, 0.3, 1.3, 0.2, -0.1
    t = np.linspace(0.0, 30.0, 301)
    r = coulomb_response(m, k, c, 0.0, P, Y, w, x0, v0, 30.0, t)
    xe, ve = linear_exact(m, c, k, P + k * Y, w, 0.0, x0, v0, t)
    scale = np.max(np.abs(xe))
    assert np.max(np.abs(r.x - xe)) / scale < 1e-9
    assert np.max(np.abs(r.v - ve)) / (scale * math.sqrt(k / m)) < 1e-9
    assert r.dissipated == 0.0
    assert all(kind == "normal" for _, kind in r.events)


def test_jenkins_linear_limit():
    m, k, c, kt, P, Y, w, x0, v0, w0 = 1.0, 1.0, 0.05, 3.0, 1.0, 0.2, 0.8, 0.1, 0.3, -0.05
    t = np.linspace(0.0, 25.0, 251)
    r = jenkins_response(m, k, c, kt, 1e12, P, Y, w, x0, v0, 25.0, t, w0=w0)
    xe, ve = linear_exact(m, c, k + kt, P + k * Y, w, kt * w0, x0, v0, t)
    scale = np.max(np.abs(xe))
    assert np.max(np.abs(r.x - xe)) / scale < 1e-9
    assert np.max(np.abs(r.force - kt * (xe - w0))) / (kt * scale) < 1e-9
    assert r.events == [] and r.dissipated == 0.0
    assert np.all(r.w == w0)


# ------------------------------------------------------------------ Coulomb free vibration
def test_coulomb_free_vibration():
    m, k, F, x0 = 1.0, 1.0, 0.1, 1.03
    t = np.linspace(0.0, 20.0, 401)
    r = coulomb_response(m, k, 0.0, F, 0.0, 0.0, 0.0, x0, 0.0, 20.0, t)
    # turning points every pi: x_n = (-1)^n (x0 - 2 n F/k) until |x_n| < F/k
    xn = [(-1) ** n * (x0 - 2 * n * F / k) for n in range(6)]
    assert [kind for _, kind in r.events] == ["normal"] * 4 + ["stick"]
    for n, (te, _) in enumerate(r.events, start=1):
        assert abs(te - n * math.pi) < 1e-10
    stop = coulomb_response(m, k, 0.0, F, 0.0, 0.0, 0.0, x0, 0.0, 20.0, [20.0])
    assert abs(stop.x[0] - xn[5]) < 1e-10 and abs(stop.x[0] - (-0.03)) < 1e-10
    assert stop.v[0] == 0.0
    # amplitude decays by 4F/k per cycle: x(2 pi n) = x0 - 4 n F/k
    for n in (1, 2):
        rn = coulomb_response(m, k, 0.0, F, 0.0, 0.0, 0.0, x0, 0.0, 2 * math.pi * n, [2 * math.pi * n])
        assert abs(rn.x[0] - (x0 - 4 * n * F / k)) < 1e-10
    # whole trajectory against the piecewise closed form
    xe = np.empty_like(t)
    for i, ti in enumerate(t):
        n = min(int(ti // math.pi), 5)
        if n >= 5:
            xe[i] = xn[5]
        else:
            s = -1 if n % 2 == 0 else 1          # slip direction in half-cycle n
            ctr = -s * F / k
            xe[i] = ctr + (xn[n] - ctr) * math.cos(ti - n * math.pi)
    assert np.max(np.abs(r.x - xe)) < 1e-10
    # dissipation: F times the path length
    path = sum(abs(xn[n + 1] - xn[n]) for n in range(5))
    assert abs(r.dissipated - F * path) < 1e-10


def test_coulomb_energy_balance():
    m, k, c, F, P, Y, w = 1.0, 1.0, 0.05, 0.4, 1.0, 0.2, 0.6
    t = np.linspace(0.0, 40.0, 40001)
    r = coulomb_response(m, k, c, F, P, Y, w, 0.3, 0.0, 40.0, t)
    A = P + k * Y
    work = simpson(A * np.cos(w * t) * r.v, x=t)
    visc = simpson(c * r.v ** 2, x=t)
    dE = 0.5 * m * (r.v[-1] ** 2 - r.v[0] ** 2) + 0.5 * k * (r.x[-1] ** 2 - r.x[0] ** 2)
    assert any(kind == "stick" for _, kind in r.events)
    assert abs(work - visc - dE - r.dissipated) < 1e-7 * abs(work)


# ------------------------------------------------------------------ steady state
def test_den_hartog_stop_free_steady_state():
    r, f = 1.5, 0.3
    s = coulomb_steady_state(1.0, 1.0, 0.0, f, 1.0, 0.0, r)
    X = den_hartog(r, f)
    assert s.converged and s.stops_per_cycle == 0 and not s.permanently_stuck
    assert abs(s.amplitude - X) <= 1e-8 * X
    assert abs(s.dissipated_per_cycle - 4 * f * X) <= 1e-8 * 4 * f * X   # exactly 4 F X
    kinds = {kind for _, kind in s.events}
    assert kinds == {"normal"} and len(s.events) == 2
    # first harmonic and phase against the exact Den Hartog waveform (DESIGN 3):
    # on the rising half-cycle wt in [theta - pi, theta], tau = (wt - theta + pi)/r,
    # x = f cos tau + r f U sin tau + V cos wt - f, and x(t + T/2) = -x(t)
    V = 1.0 / (1.0 - r * r)
    U = math.tan(math.pi / (2.0 * r)) / r
    th = math.atan2(-f * U / V, X / V)
    xw = lambda p: (f * math.cos((p - th + math.pi) / r) + r * f * U * math.sin((p - th + math.pi) / r)
                    + V * math.cos(p) - f)
    a1 = 2 / math.pi * quad(lambda p: xw(p) * math.cos(p), th - math.pi, th, epsabs=1e-14, epsrel=1e-13)[0]
    b1 = 2 / math.pi * quad(lambda p: xw(p) * math.sin(p), th - math.pi, th, epsabs=1e-14, epsrel=1e-13)[0]
    assert abs(s.a1 - a1) < 1e-9 and abs(s.b1 - b1) < 1e-9
    assert abs(s.phase - math.atan2(b1, a1)) < 1e-9


def test_stop_regime_point_is_periodic():
    m = k = P0 = 1.0
    r, f = 0.45, 0.5
    w = r
    s = coulomb_steady_state(m, k, 0.0, f * P0, P0, 0.0, w)
    assert s.converged and s.residual < 1e-11
    assert s.stops_per_cycle == 2
    assert [kind for _, kind in s.events].count("stick") == 2
    T = 2 * math.pi / w
    # restart from the reported period-start state: it repeats after 1 and 2 periods
    rr = coulomb_response(m, k, 0.0, f * P0, P0, 0.0, w, s.x0, s.v0, 2 * T, [T, 2 * T])
    assert np.max(np.abs(rr.x - s.x0)) < 1e-10 * s.amplitude
    assert np.max(np.abs(rr.v - s.v0)) < 1e-10 * s.amplitude
    # the amplitude is the largest |x| on a dense grid of the period
    tt = np.linspace(0, T, 4001)
    rd = coulomb_response(m, k, 0.0, f * P0, P0, 0.0, w, s.x0, s.v0, T, tt)
    assert abs(np.max(np.abs(rd.x)) - s.amplitude) < 1e-6 * s.amplitude
    # half-period antisymmetry of the symmetric response
    half = coulomb_response(m, k, 0.0, f * P0, P0, 0.0, w, s.x0, s.v0, T / 2, [T / 2])
    assert abs(half.x[0] + s.x0) < 1e-9 * s.amplitude
    # the amplitude differs from the (invalid here) Den Hartog value
    assert den_hartog(r, f) * r * r < f
    print(f"r=0.45 f=0.5: stops/cycle={s.stops_per_cycle} amplitude={s.amplitude:.12f} "
          f"phase={s.phase:.12f} periods={s.periods} residual={s.residual:.2e}")


# ------------------------------------------------------------------ Jenkins / Iwan
def test_jenkins_hysteresis_quasi_static_and_dissipation():
    # slow forcing, heavy damping-free mass: slider force is bounded and the
    # dissipated energy equals Fs times the slider travel
    m, k, kt, Fs, P, w = 1.0, 0.5, 2.0, 0.3, 1.0, 0.7
    t = np.linspace(0.0, 60.0, 6001)
    r = jenkins_response(m, k, 0.02, kt, Fs, P, 0.0, w, 0.0, 0.0, 60.0, t)
    assert np.max(np.abs(r.force)) <= Fs * (1 + 1e-12)
    assert np.allclose(r.force, kt * (r.x - r.w), rtol=0, atol=1e-14)
    kinds = [kind for _, kind in r.events]
    assert "stick" in kinds and "slide" in kinds
    travel = np.sum(np.abs(np.diff(r.w)))
    assert abs(r.dissipated - Fs * travel) < 1e-6 * r.dissipated
    # events alternate slide/stick, slip force at +-Fs at every event
    assert all(a != b for a, b in zip(kinds, kinds[1:]))
    te = np.array([e[0] for e in r.events])
    re = jenkins_response(m, k, 0.02, kt, Fs, P, 0.0, w, 0.0, 0.0, 60.0, te)
    assert np.max(np.abs(np.abs(re.force) - Fs)) < 1e-12


def test_iwan_identical_sliders_equal_jenkins():
    m, k, c, kt, Fs, P, Y, w = 1.0, 1.0, 0.03, 2.0, 0.4, 1.0, 0.1, 1.2
    t = np.linspace(0.0, 30.0, 301)
    rj = jenkins_response(m, k, c, kt, Fs, P, Y, w, 0.1, 0.0, 30.0, t)
    ri = iwan_response(m, k, c, [(kt / 3, Fs / 3)] * 3, P, Y, w, 0.1, 0.0, 30.0, t)
    assert np.max(np.abs(ri.x - rj.x)) < 1e-10
    assert np.max(np.abs(ri.force - rj.force)) < 1e-10
    assert ri.w.shape == (3, t.size)
    assert abs(ri.dissipated - rj.dissipated) < 1e-10
    assert [e[1] for e in ri.events] == [e[1] for e in rj.events]
    # two different sliders: total force bounded, each slider within its limit
    ri2 = iwan_response(m, k, c, [(1.0, 0.1), (1.0, 0.3)], P, Y, w, 0.0, 0.0, 30.0, t)
    assert np.all(np.abs(ri2.slider_force[0]) <= 0.1 * (1 + 1e-12))
    assert np.all(np.abs(ri2.slider_force[1]) <= 0.3 * (1 + 1e-12))
    assert np.allclose(ri2.force, ri2.slider_force.sum(axis=0))
