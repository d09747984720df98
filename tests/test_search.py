"""The compiled event search (frictionjoint.solvers.marcher.search, numba) against the marcher's NumPy
search: the same algorithm, so the same events and states up to rounding."""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.solvers.marcher import search
from frictionjoint.solvers.marcher.events import EventLog, Marcher

pytestmark = pytest.mark.skipif(not search.ENABLED, reason="numba not available")


def _system(rigid):
    n = 6
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    els = [fj.Jenkins(0.5 * w1 ** 2, 0.002, dof=5), fj.Jenkins(0.5 * w1 ** 2, 0.002, dof=3)]
    if rigid:
        els.append(fj.CoulombSlider(0.001, dof=4))
    return fj.FrictionSystem(fj.LinearStructure.chain(n, damping=0.02 * w1), els, omega=0.9 * w1,
                             excitation=[fj.HarmonicForce(n - 1, 0.01)])


def compare_compiled_and_numpy(sysm, start, periods: int, rtol: float, vfactor: float = 10.0) -> None:
    """March ``sysm`` from ``start = (x0, v0, w0)`` over ``periods`` with the compiled and the
    NumPy search: the same events (> 20), times to ``1e-12`` of the span, end states to ``rtol``."""
    period = 2 * math.pi / sysm.omega
    out = []
    for jit in (True, False):
        m = Marcher(sysm)
        m.jit = jit
        log = EventLog()
        st = m.initial_state(*start)
        m.march(st, periods * period, log)
        out.append((log, st))
    (la, sa), (lb, sb) = out
    assert len(la) > 20
    assert la.kind == lb.kind and la.slider == lb.slider
    # compiled and NumPy searches: rounding of the event times (measured 1.7e-13 of the run);
    # 1e-10 is over 100x
    assert np.max(np.abs(np.subtract(la.time, lb.time))) <= 1e-10 * periods * period
    scale = np.max(np.abs(sb.x))
    assert np.max(np.abs(sa.x - sb.x)) <= rtol * scale
    assert np.max(np.abs(sa.v - sb.v)) <= rtol * scale * sysm.omega * vfactor
    assert np.array_equal(sa.status, sb.status)


@pytest.mark.parametrize("rigid", [False, True])
def test_compiled_search_matches_numpy_search(rigid):
    compare_compiled_and_numpy(_system(rigid), (np.zeros(6), np.zeros(6), None), 8, 1e-12)


def test_skipped_steps_keep_every_function_above_its_band():
    """The compiled search steps over stretches longer than its sampling step only where a Taylor
    bound (|g''| <= M over the piece) keeps every event function above its band; checked on the
    pieces of a march by dense sampling (2000 points) of each skipped stretch."""
    sysm = _system(True)
    m = Marcher(sysm)
    pieces = []
    st = m.initial_state(np.zeros(6), np.zeros(6))
    m.march(st, 4 * 2 * math.pi / sysm.omega, EventLog(), on_interval=lambda itv, tau: pieces.append((itv, tau)))
    checked = 0
    for itv, tau in pieces:
        if tau <= 0 or not itv.modal_search():
            continue
        cy, c0, cc, cs = itv.events[0]
        cfg = itv.config
        p = cy @ cfg.V
        b0, bp, bm = itv._b
        coef = search._coefficients(p, itv._a, b0, bp, bm, c0, cfg.lam, cc, cs)
        tol = np.asarray(m._tolerances(itv), dtype=float)
        pa, pla, k0, kp, km, harmonic = coef
        nidx, nmu, nc = itv.near
        pn = search._near_terms(p, nidx, nc)
        curv, level = search._curvature(pa, pla, cfg.lam, k0, kp, km, cc, cs, sysm.omega, itv.t0, harmonic,
                                        pn, cfg.lam[nidx], nmu, tol, tau)
        sample = itv.sampler(itv.events[0])
        for t in np.linspace(0.0, tau, 9)[:-1]:
            g, dg = sample(np.array([t]))
            s = search._safe_step(g, dg, 0, curv, level)
            if not 0 < s < math.inf:
                continue
            dense = sample(np.linspace(t, min(t + s, tau), 2000))[0]
            assert np.all(dense > level[:, None])
            checked += 1
    assert checked > 20


def _tiny_reference(g, a, b):
    """The root search just after a start at zero as the compiled path wrote it before the step
    function was shared with the NumPy path (the reference of the next test)."""
    prev = a + (b - a) / 64
    for k in range(2, 65):
        t = a + (b - a) * k / 64
        if g(prev) > 0 > g(t):
            return ("bracket", prev, t)
        prev = t
    hi = a + (b - a) / 64
    if not g(hi) < 0:
        return ("b",)
    d = hi - a
    for _ in range(80):
        d *= 0.5
        lo = a + d
        if lo <= a:
            break
        if g(lo) > 0:
            return ("bracket", lo, hi)
        hi = lo
    return ("b",)


def test_tiny_root_step_function_tries_the_same_points():
    """search._tiny_next (one step, shared by the compiled and the NumPy event location) brackets
    the same root as the loop it replaces, on roots from 1e-30 to 1 of the window."""
    rng = np.random.default_rng(1)
    bracketed = 0
    for _ in range(2000):
        a = rng.uniform(-1, 1)
        b = a + 10 ** rng.uniform(-8, 1)
        root = a + (b - a) * 10 ** rng.uniform(-30, 0)
        c = rng.uniform(0.1, 50)
        g = [lambda t: root - t, lambda t: -(t - a) * (t - root) * 1e3, lambda t: -1.0,
             lambda t: math.sin(c * (t - a) / (b - a)) - 0.3][rng.integers(4)]
        st = np.zeros(8)
        act, ta, tb = search._tiny_next(a, b, st, 0.0)
        while act == search._EVALUATE:
            act, ta, tb = search._tiny_next(a, b, st, float(g(ta)))
        got = ("bracket", ta, tb) if act == search._BRACKET else ("b",)
        assert got == _tiny_reference(g, a, b)
        bracketed += got[0] == "bracket"
    assert bracketed > 500
