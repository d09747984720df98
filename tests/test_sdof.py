"""Tests of frictionjoint.solvers.sdof.kernel: the closed-form single-DOF Coulomb kernel.

References: Den Hartog's stop-free steady state (frictionjoint.analytic, DESIGN.md section 3); the
independent general n-DOF marcher (frictionjoint.solvers.marcher.events.Marcher on CoulombOscillator's
system, its own propagator and event search); the linear closed form written out here for
F = 0; the energy balance (work of the excitation = stored + friction + viscous dissipation)
integrated by scipy.integrate.quad on the kernel's pieces.
"""
import cmath
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
import scipy.linalg
from scipy.integrate import quad

from benchmarks import harness as bm  # the harness of the source tree (pytest pythonpath: ".")
from frictionjoint import CoulombOscillator, ParameterError
from frictionjoint.analytic import den_hartog_response
from frictionjoint.solvers.marcher.events import EventLog, Marcher
from frictionjoint.solvers.sdof.kernel import EVENT_KINDS, SdofCoulomb

# tolerances, stated once
DEN_HARTOG = 1e-12      # relative amplitude against the closed form
AGREEMENT = 1e-11       # end state against the general marcher, relative to the state scale
LINEAR = 1e-12          # F = 0 against the closed form written out below
ENERGY = 1e-10          # energy balance, relative to the energy scale


def _general(m, k, f, p0, w, c, x0, v0, t_end):
    """End state and event counts by the general marcher (the independent reference)."""
    osc = CoulombOscillator(m, k, f, p0, w, damping=c)
    marcher, log = Marcher(osc.system), EventLog()
    st_ = marcher.initial_state(x0, v0, t0=0.0, log=log)
    marcher.march(st_, t_end, log=log)
    return float(st_.x[0]), float(st_.v[0]), {kind: log.count(kind) for kind in EVENT_KINDS}


def _agree(m, k, f, p0, w, c, x0, v0, periods):
    t_end = periods * 2 * math.pi / w
    res = SdofCoulomb(m, k, f, p0, w, c).march(0.0, x0, v0, t_end)
    x, v, counts = _general(m, k, f, p0, w, c, x0, v0, t_end)
    scale = max(abs(x), abs(p0) / k, f / k, abs(x0))
    vscale = math.sqrt(k / m) * scale
    assert res.t == t_end
    assert abs(res.x - x) <= AGREEMENT * scale, (res.x, x)
    assert abs(res.v - v) <= AGREEMENT * vscale, (res.v, v)
    assert res.events == counts
    assert res.n_events == sum(counts.values())
    return res


@pytest.mark.parametrize("r, f", [(0.8, 0.3), (1.5, 0.3), (3.0, 0.5), (0.6, 0.1)])
def test_den_hartog_steady_state(r, f):
    dh = den_hartog_response(1.0, 1.0, f, 1.0, r)
    assert dh.applicable and dh.regime == "stop-free"
    p = bm.make_problem(bm.Case(r, f))
    sd = SdofCoulomb(1.0, 1.0, f, 1.0, r)
    period = 2 * math.pi / r
    # the orbit is periodic: marching 5 periods returns to the start, the peak is Den Hartog's
    end = sd.march(0.0, p.x0, p.v0, 5 * period)
    assert abs(end.x - p.x0) <= DEN_HARTOG * dh.amplitude
    assert abs(end.v - p.v0) <= DEN_HARTOG * dh.amplitude * r
    assert end.events == dict.fromkeys(EVENT_KINDS, 0) | {"normal stop": 10}
    peak = sd.peak(0.0, p.x0, p.v0, 4 * period, 5 * period)
    assert abs(peak / dh.amplitude - 1) <= DEN_HARTOG


def test_benchmark_stop_case_against_its_reference():
    p = bm.make_problem(bm.Case(2.0, 0.6))   # exact orbit from steady_state (the general marcher)
    sd = SdofCoulomb(p.mass, p.stiffness, p.slip_force, p.force_amplitude, p.omega)
    assert p.error(sd.peak(0.0, p.x0, p.v0, p.period, 2 * p.period)) <= DEN_HARTOG
    res = sd.march(0.0, p.x0, p.v0, 2 * p.period)
    assert res.events["stick"] == res.events["slip"] == 4   # two stops per cycle


@settings(max_examples=40, deadline=None, derandomize=True)
@given(r=st.sampled_from([0.1, 0.25, 0.5, 0.8, 1.3, 2.0]) | st.floats(0.1, 3.0),
       f=st.sampled_from([0.5, 0.7, 0.95]) | st.floats(0.0, 0.95),
       c=st.sampled_from([0.0, 0.3]) | st.floats(0.0, 0.3),
       x0=st.floats(-2.0, 2.0), v0=st.sampled_from([0.0]) | st.floats(-2.0, 2.0),
       m=st.floats(0.5, 2.0), p0=st.sampled_from([1.0, -0.7]))
def test_agrees_with_the_general_marcher(r, f, c, x0, v0, m, p0):
    k = 1.3
    w = r * math.sqrt(k / m)
    # 3.1 periods: an end time where v = 0 by symmetry (from rest at rational r) would leave the
    # last event to rounding
    _agree(m, k, f * abs(p0), p0, w, c, x0 * abs(p0) / k, v0 * abs(p0) / math.sqrt(k * m), 3.1)


def test_low_frequency_many_stops_and_finite_sticks():
    # r = 0.1, F/P0 = 0.5: several stops per cycle, with sticks of finite duration
    res = _agree(1.0, 1.0, 0.5, 1.0, 0.1, 0.0, 0.0, 0.0, 2)
    assert res.events["stick"] >= 4 and res.events["slip"] >= 4
    res = _agree(1.0, 1.0, 0.5, 1.0, 0.1, 0.05, 0.2, 0.0, 2)
    assert res.events["stick"] >= 4


def test_damping_regimes_agree():
    for c in (0.3, 2.0, 2.0 * math.sqrt(1.7 * 0.8), 5.0):   # under-, critically, over-damped
        _agree(1.7, 0.8, 0.2, 1.0, 0.9, c, 0.5, -0.3, 3)


@pytest.mark.parametrize("f", [0.0, 0.3, 0.9])
def test_exact_undamped_resonance(f):
    # k = m w^2, c = 0: the secular particular solution (growth for F/P0 < pi/4, stops above)
    _agree(1.0, 1.0, f, 1.0, 1.0, 0.0, 0.1, 0.0, 3.1)


def test_permanent_stick():
    sd = SdofCoulomb(1.0, 1.0, 1.2, 1.0, 0.8)   # F > P0, from rest: never slips
    res = sd.march(0.0, 0.0, 0.0, 50.0)
    assert (res.x, res.v, res.status, res.n_events) == (0.0, 0.0, 0, 0)
    assert sd.peak(0.0, 0.0, 0.0, 10.0, 50.0) == 0.0
    _agree(1.0, 1.0, 1.2, 1.0, 0.8, 0.0, 0.0, 0.0, 3)
    # a moving start comes to rest once and stays there (|x| <= (F - P0)/k at the stop)
    res = _agree(1.0, 1.0, 1.5, 1.0, 0.8, 0.0, 0.1, 0.3, 3)
    assert res.status == 0 and res.n_events == res.events["stick"] == 1 and abs(res.x) <= 0.5


@pytest.mark.parametrize("c", [0.0, 0.2, 2.0])
def test_linear_closed_form(c):
    # F = 0: x = Re(X e^{iwt}) + homogeneous part with roots of m l^2 + c l + k (written out here)
    m, k, p0, w, x0, v0 = 1.3, 0.8, 0.7, 0.5, 0.2, -0.1
    X = p0 / (k - m * w * w + 1j * c * w)
    l1 = (-c + cmath.sqrt(c * c - 4 * m * k)) / (2 * m)
    l2 = (-c - cmath.sqrt(c * c - 4 * m * k)) / (2 * m)
    xh, vh = x0 - X.real, v0 - (1j * w * X).real
    a2 = (vh - l1 * xh) / (l2 - l1)
    a1 = xh - a2
    sd = SdofCoulomb(m, k, 0.0, p0, w, c)
    for t in (0.7, 5.0, 31.0):
        res = sd.march(0.0, x0, v0, t)
        x = (X * cmath.exp(1j * w * t) + a1 * cmath.exp(l1 * t) + a2 * cmath.exp(l2 * t)).real
        v = (1j * w * X * cmath.exp(1j * w * t) + a1 * l1 * cmath.exp(l1 * t)
             + a2 * l2 * cmath.exp(l2 * t)).real
        assert abs(res.x - x) <= LINEAR * max(abs(x), 1.0) and abs(res.v - v) <= LINEAR
        assert res.n_events == 0
    # the peak of the linear motion is at v = 0 inside the window: compare with dense sampling
    ts = np.linspace(10.0, 40.0, 20001)
    sampled = max(abs(sd.evaluate(1, 0.0, x0, v0, t)[0]) for t in ts)
    peak = sd.peak(0.0, x0, v0, 10.0, 40.0)
    assert sampled <= peak <= sampled + 1e-6


def test_abnormal_stop():
    # built backwards: slipping forwards, v touches 0 at t* where P0 cos(w t*) - k x* = F and rises
    m = k = p0 = 1.0
    f, w = 0.3, 0.8
    t_star = (2 * math.pi - math.pi / 3) / w
    x_star = p0 * math.cos(w * t_star) - f
    sd = SdofCoulomb(m, k, f, p0, w)
    t0 = t_star - 1.0
    x0, v0 = sd.evaluate(1, t_star, x_star, 0.0, t0)
    assert v0 > 0
    pieces = []
    res = sd.march(t0, x0, v0, t0 + 3.0, on_piece=lambda *a: pieces.append(a))
    assert res.events["abnormal stop"] == 1 and res.n_events == 1 and res.status == 1
    assert abs(pieces[0][4] - t_star) <= 1e-12 * t_star
    # the general marcher (started at t0) sees the same
    osc = CoulombOscillator(m, k, f, p0, w)
    marcher, log = Marcher(osc.system), EventLog()
    st_ = marcher.initial_state(x0, v0, t0=t0, log=log)
    marcher.march(st_, t0 + 3.0, log=log)
    # the start is the touch only to an ulp (x0 within 5e-17 of an extended-precision evaluation):
    # the marcher may see the velocity dip below zero by that much, a stop whose stick ends at t*
    # (4e-8 s before it, its time resolution there); it slips on at t* in the same direction
    kinds = [kind for *_, kind in log]
    assert kinds in (["abnormal stop"], ["stick", "slip"])
    # a dip of delta below zero starts sqrt(2 delta / v''), v'' = P0 w sin(w t*) = 0.69 m/s^3, before
    # t*: measured 4.9e-8 s (delta = 8e-16 m/s, a few ulps, which another libm may make larger);
    # 1e-6 s allows delta up to 3e-13 m/s
    assert abs(log.time[-1] - t_star) <= 1e-12 * t_star and t_star - log.time[0] <= 1e-6
    assert abs(res.x - st_.x[0]) <= AGREEMENT and abs(res.v - st_.v[0]) <= AGREEMENT


def test_continuation_is_exact():
    sd = SdofCoulomb(1.0, 1.0, 0.6, 1.0, 2.0, 0.05)
    whole = sd.march(0.0, 0.1, 0.0, 20.0)
    part = sd.march(0.0, 0.1, 0.0, 7.3)
    rest = sd.march(part.t, part.x, part.v, 20.0, status=part.status)
    assert rest.x == pytest.approx(whole.x, abs=1e-13) and rest.v == pytest.approx(whole.v, abs=1e-13)
    assert part.n_events + rest.n_events == whole.n_events


@pytest.mark.parametrize("r, f, c", [(0.8, 0.3, 0.0), (2.0, 0.6, 0.1), (0.3, 0.7, 0.05)])
def test_energy_balance(r, f, c):
    m, k, p0 = 1.0, 1.0, 1.0
    w = r
    sd = SdofCoulomb(m, k, f, p0, w, c)
    x0, v0 = 0.4, 0.2
    work, friction, viscous = [0.0], [0.0], [0.0]

    def piece(ta, xa, va, s, tb, xb, vb):
        if s == 0:
            return

        def v(t):
            return sd.evaluate(s, ta, xa, va, t)[1]
        opts = dict(epsabs=0.0, epsrel=1e-13, limit=200)
        work[0] += quad(lambda t: p0 * math.cos(w * t) * v(t), ta, tb, **opts)[0]
        viscous[0] += quad(lambda t: c * v(t) ** 2, ta, tb, **opts)[0] if c else 0.0
        friction[0] += f * abs(xb - xa)   # v keeps its sign on a slip piece

    res = sd.march(0.0, x0, v0, 3 * 2 * math.pi / w, on_piece=piece)
    stored = 0.5 * m * (res.v ** 2 - v0 ** 2) + 0.5 * k * (res.x ** 2 - x0 ** 2)
    scale = p0 ** 2 / k * max(1.0, 1 / abs(1 - r * r))
    assert abs(work[0] - stored - friction[0] - viscous[0]) <= ENERGY * scale
    assert friction[0] > 0


def test_bad_input():
    with pytest.raises(ParameterError, match="mass"):
        SdofCoulomb(0.0, 1.0, 0.1, 1.0, 1.0)
    with pytest.raises(ParameterError, match="stiffness"):
        SdofCoulomb(1.0, -1.0, 0.1, 1.0, 1.0)
    with pytest.raises(ParameterError, match="slip_force"):
        SdofCoulomb(1.0, 1.0, -0.1, 1.0, 1.0)
    with pytest.raises(ParameterError, match="force_amplitude"):
        SdofCoulomb(1.0, 1.0, 0.1, math.nan, 1.0)
    with pytest.raises(ParameterError, match="omega"):
        SdofCoulomb(1.0, 1.0, 0.1, 1.0, 0.0)
    with pytest.raises(ParameterError, match="damping"):
        SdofCoulomb(1.0, 1.0, 0.1, 1.0, 1.0, damping=-1.0)
    sd = SdofCoulomb(1.0, 1.0, 0.1, 1.0, 1.0)
    with pytest.raises(ParameterError, match="t_end"):
        sd.march(1.0, 0.0, 0.0, 0.5)
    with pytest.raises(ParameterError, match="status"):
        sd.march(0.0, 0.0, 0.0, 1.0, status=2)
    with pytest.raises(ParameterError, match="v0"):
        sd.march(0.0, 0.0, 0.5, 1.0, status=0)
    with pytest.raises(ParameterError, match="v0"):
        sd.march(0.0, 0.0, 0.5, 1.0, status=-1)
    with pytest.raises(ParameterError, match="x0"):
        sd.march(0.0, math.inf, 0.0, 1.0)
    with pytest.raises(ParameterError, match="t_start"):
        sd.peak(1.0, 0.0, 0.0, 0.5, 2.0)


# ---------------------------------------------------------------- monodromy (exact Jacobian)
@pytest.mark.parametrize("f", [0.1, 0.3, 0.5, 0.7])
@pytest.mark.parametrize("r", [0.45, 0.8, 1.3, 2.0, 3.0])
@pytest.mark.parametrize("c", [0.0, 0.05])
def test_monodromy_equals_central_differences(f, r, c):
    """Transition matrices of the slip pieces times the saltation matrices of the events against
    central differences of the exact march over three periods (with stops and reversals)."""
    k = SdofCoulomb(1.0, 1.0, f, 1.0, r, c)
    t0, t1 = 0.13, 0.13 + 3 * 2 * math.pi / r
    x0, v0 = 0.3, 0.7
    end, jac = k.monodromy(t0, x0, v0, t1)
    assert jac is not None
    ref = k.march(t0, x0, v0, t1)
    assert (end.x, end.v) == (ref.x, ref.v)
    fd = np.empty((2, 2))
    h = 1e-6
    for col in range(2):
        d = np.zeros(2)
        d[col] = h
        ep, em = k.march(t0, x0 + d[0], v0 + d[1], t1), k.march(t0, x0 - d[0], v0 - d[1], t1)
        fd[:, col] = [(ep.x - em.x) / (2 * h), (ep.v - em.v) / (2 * h)]
    assert np.max(np.abs(np.array(jac) - fd)) <= 1e-7 * max(1.0, np.max(np.abs(fd)))  # measured <= 3.9e-9


@pytest.mark.parametrize("c", [0.0, 0.02, 2.0, 3.0])  # under-, critically and over-damped
def test_linear_floquet_multipliers_are_the_modes(c):
    """Without friction the period map is linear: the monodromy is expm(A T) (scipy) and its
    multipliers are exp(lambda_i T), lambda_i the roots of m l^2 + c l + k."""
    m, kk, w = 1.0, 1.0, 0.8
    k = SdofCoulomb(m, kk, 0.0, 1.0, w, c)
    period = 2 * math.pi / w
    _, jac = k.monodromy(0.0, 0.1, 0.2, period)
    jac = np.array(jac)
    expm = scipy.linalg.expm(np.array([[0.0, 1.0], [-kk / m, -c / m]]) * period)
    assert np.max(np.abs(jac - expm)) <= 1e-12 * np.max(np.abs(expm))
    if c != 2.0:  # (a double root at critical damping: its eigenvalues are ill-conditioned, sqrt(eps))
        mult = np.sort_complex(np.linalg.eigvals(jac))
        ref = np.sort_complex(np.exp(np.roots([m, c, kk]).astype(complex) * period))
        assert np.max(np.abs(mult - ref)) <= 1e-12


def test_monodromy_needs_a_slipping_start():
    k = SdofCoulomb(1.0, 1.0, 0.3, 1.0, 0.8)
    end, jac = k.monodromy(0.0, 0.1, 0.0, 1.0)
    assert jac is None and end == k.march(0.0, 0.1, 0.0, 1.0)


def test_a_late_stick_end_is_not_lost_to_the_rounding_of_the_phase():
    """m = k = P0 = 1, F = 0.5, omega = 0.3: the orbit sticks at x = 0.82562 (v = 0) at every
    period start, and the holding force P0 cos(wt) - k x reaches -1.83 N, far beyond F, so every
    period has its stick -> slip onset (4 events per period on the orbit). Found by marching an
    FMU period by period: from t = 4e4 s on (w t = 1.3e4 rad, whose rounding moves the holding
    force by 2e-12 N, more than the 1e-12 F band of the rules) the located exit read as still
    inside the band, the mass stayed stuck and the next exit was a period later: 18089 of 28571
    sampled periods up to n = 2e5 had no event. Sampled over n = 10^2 .. 10^11 periods."""
    k = SdofCoulomb(1.0, 1.0, 0.5, 1.0, 0.3, 0.0)
    period = 2.0 * math.pi / 0.3
    x = 0.8256157754765914
    rng = np.random.default_rng(1)
    for e in range(2, 12):
        for n in rng.integers(10 ** (e - 1), 10 ** e, 40):
            assert k.march(n * period, x, 0.0, (n + 1) * period, status=0).n_events == 4, n


def test_a_very_late_start_still_slips():
    """Defaults (m = k = P0 = 1, F = 0.5, omega = 1), from rest at t0 = 1e12 .. 1e15 s: P0 > F, so
    the mass slips about twice per period (50 events in 100 s from t0 = 0). A zero band widened by
    the phase's rounding (8 eps |w t| P0 = 0.05 N at w t = 1e14) once kept it stuck for ever,
    with every step OK; the located limit is now set to zero and the derivatives decide."""
    from frictionjoint.stepping import OscillatorRun

    for t0 in (1e12, 1e14, 1e15):
        run = OscillatorRun({}, start_time=t0)
        for i in range(1, 201):
            run.advance(t0 + 0.5 * i)
        assert run.event_count >= 40, (t0, run.event_count)


def test_a_stuck_mass_without_forcing_stays_stuck():
    """P0 = 0 and |k x| <= F: the holding force never changes, so the mass stays stuck for ever
    (no stick end: _stick_end answers (inf, 0))."""
    k = SdofCoulomb(1.0, 1.0, 0.5, 0.0, 0.3, 0.0)
    res = k.march(0.0, 0.2, 0.0, 10.0, status=0)
    assert (res.t, res.x, res.v, res.status, res.n_events) == (10.0, 0.2, 0.0, 0, 0)


@pytest.mark.parametrize("kw, name", [
    (dict(stiffness=1e308), r"stiffness must be in \(0, 1e\+150\] N/m"),
    (dict(mass=1e-320), r"mass must be >= stiffness / 1e\+300"),
    (dict(omega=1e80), r"mass \* omega\*\*2 must be <= 1e\+150 N/m"),
    (dict(damping=1e160), r"damping \* omega must be <= 1e\+150 N/m"),
])
def test_scales_beyond_the_closed_form_are_refused_by_name(kw, name):
    """Issue 39: stiffness 1e308 was an OverflowError naming nothing (the closed form squares k,
    m w^2 and c w), mass 1e-320 an infinite natural frequency; refused where the kernel is made,
    which the library's oscillator and the CoulombOscillator FMU share."""
    from frictionjoint.solvers.sdof.kernel import SdofCoulomb

    args = dict(mass=1.0, stiffness=1.0, slip_force=0.5, force_amplitude=1.0, omega=1.5, damping=0.0)
    args.update(kw)
    with pytest.raises(ParameterError, match=name):
        SdofCoulomb(**args)
    assert SdofCoulomb(1.0, 1e150, 0.5, 1.0, 1.5).stiffness == 1e150  # the bound itself is taken
