"""Stress suite of the closed-form single-DOF kernel (frictionjoint.solvers.sdof.kernel.SdofCoulomb).

Settings as in test_stress.py: hypothesis, ``derandomize=True``, ``deadline=None``, no database,
no shrinking; ``max_examples`` = 10 x ``STRESS_EXAMPLES`` (environment variable, default 15: one
example costs a few ms). Ranges: mass and stiffness 1e-3 … 1e3 (log-uniform), slip force
1e-12 … 1e6 of the excitation P0, frequency ratio r = omega/omega_n 1e-3 … 1e3, damping ratio 0 or
1e-6 … 0.3, initial state up to 2 P0/k (and the matching velocity), ~3 excitation periods capped
at 150 natural periods.

Every run is compared with the general n-DOF marcher (:class:`frictionjoint.solvers.marcher.events.Marcher`
on :class:`frictionjoint.CoulombOscillator`, independent propagator and event search): end state
to AGREEMENT of the state scale and identical event counts per kind; and checked for finite
values, monotone contiguous pieces and a bounded number of events per period.

The explicit examples are former failures of the kernel (all fixed):

- undamped near resonance (r = 1 ± a few ulp): the particular solution P0/(k - m w^2) cancelled
  against the homogeneous part, O(1) errors (now the phi1 form of the forced response);
- "no event located after 20000 safe steps" at and near undamped resonance (the step bounds grew
  with the particular amplitude or the secular term over the whole horizon; now energy bounds);
- F/P0 = 1 and 1 + 4e-16 with light damping at resonance: event-count mismatches (the same
  cancellation, ~1e-10 errors splitting grazes differently).

- F/P0 = 5e-12 near resonance: a dip search without bound (end time 1e5 x too late), then a
  chatter of vanishing pieces after an abnormal stop (now a stick).

Two narrowly excluded cases come from a defect of the *general marcher* (documented in
test_force_limit_graze_at_f_equal_p0): with F = |P0| and a stuck state ``|k x| <= 1e-12 F``, the
holding force crosses the limit by ``|k x|`` (below the force tolerance) at each force peak; the
kernel treats it as a graze (stays stuck; the exact motion slips for ~3 sqrt(2|x|/(P0/m w^2))
with a displacement ~1e-30), the marcher slips for a sampling sub-interval and drifts. The same
defect shows when F <= 1e-10 P0, where the rules at v = 0 are decided inside the tolerance bands
(counts differ, and near resonance the marcher's state strays by ~1e-7): there the kernel is
checked against the frictionless motion within the rigorous friction bound instead.
"""
import math
import os

import pytest
from hypothesis import HealthCheck, Phase, example, given, settings, strategies as st

import frictionjoint as fj
from frictionjoint.solvers.marcher.events import EventLog
from frictionjoint.solvers.sdof.kernel import EVENT_KINDS, SdofCoulomb

EXAMPLES = 10 * int(os.environ.get("STRESS_EXAMPLES", "15"))
AGREEMENT = 1e-9   # end state against the general marcher, relative to the state scale
SETTINGS = settings(max_examples=EXAMPLES, deadline=None, derandomize=True, database=None,
                    phases=(Phase.explicit, Phase.generate),
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])


def log10(lo, hi):
    """10**u for u uniform in [lo, hi]."""
    return st.floats(lo, hi).map(lambda u: 10.0 ** u)


def _general(m, k, f, p, w, c, x0, v0, t_end):
    osc = fj.CoulombOscillator(mass=m, stiffness=k, slip_force=f, force_amplitude=p, omega=w, damping=c)
    marcher, log = fj.Marcher(osc.system), EventLog()
    s = marcher.initial_state(x0, v0, t0=0.0, log=log)
    marcher.march(s, t_end, log=log)
    return float(s.x[0]), float(s.v[0]), {kind: log.count(kind) for kind in EVENT_KINDS}


@SETTINGS
@given(m=log10(-3, 3), k=log10(-3, 3), f=log10(-12, 6), r=log10(-3, 3),
       zeta=st.one_of(st.just(0.0), log10(-6, math.log10(0.3))), x0=st.floats(-2, 2), v0=st.floats(-2, 2),
       p=st.sampled_from([1.0, -3e-4, 2e5]))
# undamped near resonance, O(1) errors before (particular part ~1e15 cancelling)
@example(m=1.0002302850208247, k=0.08021989513153957, f=113320.02035225157, r=1.0000000000000004,
         zeta=0.0, x0=-0.7925823066866806, v0=1e-11, p=1.0)
@example(m=0.9999999999999921, k=1.0, f=335234.86090520344, r=0.9999999999999921, zeta=0.0,
         x0=-3.4287296894055626e-15, v0=-0.14355328847422966, p=1.0)
@example(m=0.9999999999999994, k=0.9999999999999994, f=0.9999999999999994, r=0.9999999999999994,
         zeta=0.0, x0=-0.23842974202970302, v0=-2.220446049250313e-16, p=-3e-4)
@example(m=0.19936896301827098, k=1.0, f=1.0, r=1.0, zeta=0.0, x0=-1.707568595544962,
         v0=-2.225073858507e-311, p=2e5)
# ConvergenceError "no event located after 20000 safe steps" (resonance, F = P0 near rest)
@example(m=0.09493487091742792, k=0.03125239923524382, f=1e-07, r=1.0, zeta=0.0,
         x0=-1.6702534422569162, v0=-1.4487670434153335e-190, p=-3e-4)
@example(m=0.023268571079223265, k=0.012589254117941675, f=1.0, r=1.0, zeta=0.0,
         x0=-2.418768574438815e-84, v0=1.6122885870741843, p=-3e-4)
@example(m=1.0, k=1.0, f=1.000000002302585, r=1.000000002302585, zeta=0.0, x0=0.6957987428114802,
         v0=-1.5870743146256237e-123, p=1.0)
@example(m=0.020706190858986506, k=22.864934560075046, f=4.96003719640627, r=0.9999999999999994,
         zeta=0.0, x0=-0.23842974202970302, v0=1.0, p=-3e-4)
@example(m=0.01, k=252.9508497638358, f=1.0, r=1.0, zeta=0.0, x0=0.75, v0=0.010181269553125372, p=1.0)
@example(m=1.0000000000000004, k=1.0000000000000004, f=1.0000000000000004, r=1.0000000000000004,
         zeta=0.0, x0=-5e-324, v0=1.5, p=1.0)
# F/P0 = 1 (and 1 + 4e-16), light damping at resonance: event-count mismatches before
@example(m=1.0, k=1.0, f=0.6085739213857542, r=1.0, zeta=1e-06, x0=-0.21568666196951414,
         v0=5.362672048568168e-155, p=1.0)
@example(m=1.0, k=1.0, f=1.0, r=1.0, zeta=1e-06, x0=0.8124276558900516, v0=-0.5895933126610158, p=1.0)
@example(m=1.0, k=1.0, f=1.0, r=1.0, zeta=1e-06, x0=-1.9, v0=-0.35089740756515075, p=2e5)
@example(m=0.05360680941430773, k=1.0, f=1.0000000000000004, r=1.0, zeta=2.4505838207814587e-06,
         x0=-0.7614836054374547, v0=-0.7614836054374547, p=-3e-4)
@example(m=31.622776601683793, k=1.0, f=1.0, r=1.0, zeta=1e-06, x0=0.0, v0=-1.9790327548701319, p=2e5)
# F/P0 = 5e-12 (inside the force tolerance band), near resonance: the kernel ran to t = 1e5 x t_end
# (an unbounded dip search), then chattered; now it sticks at the stop (see below for the counts)
@example(m=10.0 ** 1e-12, k=2.6689223342221395, f=4.833319661270088e-12, r=10.0 ** 2e-14,
         zeta=2.8902832112406058e-05, x0=1.0, v0=4.361424341473157e-163, p=1.0)
def test_kernel_agrees_with_the_general_marcher(m, k, f, r, zeta, x0, v0, p):
    wn = math.sqrt(k / m)
    w, c, fs = r * wn, 2 * zeta * math.sqrt(k * m), f * abs(p)
    period, tn = 2 * math.pi / w, 2 * math.pi / wn
    t_end = min(3.1 * period, 150.1 * tn)
    X0, V0 = x0 * abs(p) / k, v0 * abs(p) / math.sqrt(k * m)
    pieces = []
    kernel = SdofCoulomb(m, k, fs, p, w, c)
    res = kernel.march(0.0, X0, V0, t_end, on_piece=lambda *a: pieces.append(a))
    # finite, monotone and contiguous pieces, bounded events
    assert res.t == t_end and math.isfinite(res.x) and math.isfinite(res.v)
    assert pieces[0][0] == 0.0 and pieces[-1][4] == t_end
    for (ta, xa, va, s, tb, xb, vb), nxt in zip(pieces, pieces[1:] + [None]):
        assert ta <= tb and all(math.isfinite(u) for u in (xa, va, xb, vb))
        assert nxt is None or nxt[0] == tb
    # a reversal or stop/slip pair per natural half period, plus per excitation half period
    assert res.n_events <= 4 * (2 * t_end / tn + 2 * t_end / period) + 8
    assert res.n_events == sum(res.events.values())
    # the general marcher
    x, v, counts = _general(m, k, fs, p, w, c, X0, V0, t_end)
    xs = abs(p) / k * (1 + abs(x0) + abs(v0))
    vs = xs * max(wn, w)
    if (abs(fs - abs(p)) <= 1e-12 * abs(p) and res.status == 0 and abs(k * res.x) <= 1e-12 * fs
            and abs(x - res.x) <= 1e-6 * xs):
        return   # the marcher's graze defect at F = |P0| (module docstring)
    if fs <= 1e-10 * abs(p):
        # F within 100 x the marcher's force tolerance (1e-12 of the load): a stop where the
        # holding force is within F of the slip limit both ways is decided inside tolerance bands;
        # the marcher may slip on against the velocity up to its first sampling point (the defect
        # of test_force_limit_graze_at_f_equal_p0; near resonance its end state then strays by up
        # to ~1e-7). Reference: the frictionless motion (marcher, F = 0), from which a friction
        # force |T| <= F moves the state by at most F t/(m w_d) and F t (1 + a/w_d)/m.
        x, v, _ = _general(m, k, 0.0, p, w, c, X0, V0, t_end)
        wd, a = wn * math.sqrt(1 - zeta * zeta), c / (2 * m)
        assert abs(res.x - x) <= AGREEMENT * xs + fs * t_end / (m * wd), (res.x, x)
        assert abs(res.v - v) <= AGREEMENT * vs + fs * t_end * (1 + a / wd) / m, (res.v, v)
        return
    assert abs(res.x - x) <= AGREEMENT * xs, (res.x, x)
    assert abs(res.v - v) <= AGREEMENT * vs, (res.v, v)
    assert res.events == counts


@pytest.mark.parametrize("eps", [-1e-15, -4.4e-16, 0.0, 4.4e-16, 1e-15, 1e-9])
def test_near_resonance_pieces_are_accurate(eps):
    """One slip piece at r = 1 + eps (undamped), three periods: against the exact closed form with
    the secular limit, x(t) = xc + (x0 - xc) cos t + v0 sin t + P0 [cos(w t) - cos t]/(k - m w^2),
    whose last factor is written as a difference quotient evaluated stably here (m = k = 1)."""
    m = k = p0 = 1.0
    w = 1.0 + eps
    f = 0.3
    x0, v0 = 0.1, 0.2
    t = 3 * 2 * math.pi
    kernel = SdofCoulomb(m, k, f, p0, w)
    x, v = kernel.evaluate(1, 0.0, x0, v0, t)
    # (cos(w t) - cos t)/(1 - w^2) = -2 sin((w+1) t/2) sin((w-1) t/2)/((1-w)(1+w)), stable
    d = w - 1.0
    sinc = math.sin(0.5 * d * t) / (0.5 * d * t) if d else 1.0
    xf = 2 * math.sin(0.5 * (w + 1) * t) * 0.5 * t * sinc / (1 + w)
    xc = -f / k
    x_ref = xc + (x0 - xc) * math.cos(t) + v0 * math.sin(t) + xf
    # rounding of the phase w t to ulp(19) = 3.6e-15 rad, times |v| up to ~9: ~3e-14 (measured 3.2e-14,
    # within 3x of the former 1e-13); 1e-12
    assert abs(x - x_ref) <= 1e-12 * max(1.0, abs(x_ref))


def test_force_limit_graze_at_f_equal_p0():
    """F = P0, stuck at x0 = 1e-15 P0/k from rest: at the force peaks |P0 cos wt - k x0| exceeds F
    by k x0 = 1e-15 F, below the 1e-12 F force tolerance. The kernel stays stuck (a graze). The
    exact motion slips from u = -u0 to 2 u0 about each peak, u0 = sqrt(2 k x0 m/(P0 w^2)) = 2.2e-8,
    moving x by ~k x0 u0^2/m ~ 1e-30: the kernel is right to 1e-29.

    The general marcher (events.py) used to start a slip there whose velocity left zero *against*
    its slip direction, unseen by its start-at-zero search, so x drifted by 2.4e-10 P0/k per force
    peak; it now halves towards the start (``Marcher._locate_tiny``) and agrees to rounding."""
    kernel = SdofCoulomb(1.0, 1.0, 1.0, 1.0, 2.0)
    res = kernel.march(0.0, 1e-15, 0.0, 3 * math.pi)
    assert (res.x, res.v, res.status, res.n_events) == (1e-15, 0.0, 0, 0)
    x, _, counts = _general(1.0, 1.0, 1.0, 1.0, 2.0, 0.0, 1e-15, 0.0, 3 * math.pi)
    # exact motion: x moves by ~1e-30 (docstring); both marchers stay within rounding of x0, of terms
    # of size F/k = 1 (measured 3.3e-16, 1.5 ulps, within 3x of the former 1e-15); 1e-13 is still
    # 2400x below the old drift of 2.4e-10 per force peak
    assert abs(x - 1e-15) <= 1e-13 and counts["slip"] == counts["stick"]
