"""The compiled consistency test of the marcher's settling (frictionjoint.solvers.marcher.consistency)
against the NumPy settling it replaces: at every event state of a march, the same settled status,
the same zero bands and start values of the event functions, the same closed-form piece."""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.solvers.marcher import consistency
from frictionjoint.solvers.marcher.events import EventLog, Marcher, MarchState

pytestmark = pytest.mark.skipif(not consistency.ENABLED, reason="numba not available")


def _chain(rigid: bool, held: bool):
    n = 6
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    els = [fj.Jenkins(0.5 * w1 ** 2, 0.002, dof=5), fj.Jenkins(0.5 * w1 ** 2, 0.002, dof=3)]
    if rigid:
        els.append(fj.CoulombSlider(0.001, dof=4))
    exc = [fj.HarmonicForce(n - 1, 0.01)]
    if held:
        exc.append(fj.ExternalForce(2, [0.0, 40.0, 90.0, 1e9], [0.0, 0.004, -0.002]))
    return fj.FrictionSystem(fj.LinearStructure.chain(n, damping=0.02 * w1), els, omega=0.9 * w1,
                             excitation=exc)


def _dovetail():
    root = fj.DovetailRoot(1e4, flank_angle=math.radians(30.0), friction_coefficient=0.3,
                           normal_stiffness=2e8, tangential_stiffness=1e8, tangential_dof=0)
    s = fj.LinearStructure([[2.0, 0.0], [0.0, 1.0]], [[3e8, -1e8], [-1e8, 1e8]],
                           [[20.0, 0.0], [0.0, 10.0]])
    return fj.FrictionSystem(s, [root], omega=6000.0, excitation=[fj.HarmonicForce(1, 1e6)])


SYSTEMS = {"jenkins": lambda: _chain(False, False), "rigid": lambda: _chain(True, False),
           "held force": lambda: _chain(True, True), "dovetail": _dovetail}


@pytest.mark.parametrize("name", list(SYSTEMS))
def test_compiled_settle_matches_numpy_settle(name):
    sysm = SYSTEMS[name]()
    n = sysm.n_dof
    ref = Marcher(sysm)
    ref.jit = False
    pieces = []
    st = ref.initial_state(np.zeros(n), np.zeros(n))
    ref.march(st, 12 * 2 * math.pi / sysm.omega, EventLog(), on_interval=lambda itv, tau: pieces.append((itv, tau)))
    fast = Marcher(sysm)
    fast.jit = True
    changed = 0
    for itv, tau in pieces:
        pre = MarchState(itv.t0, itv.x0.copy(), np.zeros(n), itv.w.copy(), itv.status.copy())
        ref.advance(itv, tau, pre)  # the state at the end of the piece, before settling
        out = []
        for m in (ref, fast):
            s = pre.copy()
            m.v_scale = ref.v_scale
            out.append((s, m.settle(s)))
        (sa, ia), (sb, ib) = out
        changed += not np.array_equal(sa.status, itv.status)
        assert np.array_equal(sa.status, sb.status)
        assert np.array_equal(ia.atzero, ib.atzero)
        ta, tb = ref._tolerances(ia), fast._tolerances(ib)
        assert np.allclose(ta, tb, rtol=1e-14, atol=0.0)
        rate = max(sysm.omega, ia.config.max_rate)
        for k, (a, b) in enumerate(zip(ia.start_values(ia.events[0]), ib.start_values(ib.events[0]))):
            # g, g', g'' to rounding of their terms: a tenth of the zero band (1e-12 of the terms)
            # times rate^k, harmless as the settling judges g' against 10 band x rate (measured
            # 4.6e-4 of the band: a bound of 1e-3 was within 10x of it)
            assert np.max(np.abs(a - b)) <= 1e-1 * np.min(ta) * rate ** k
        ya, yb = ia.y(np.array([0.0, 0.5 * tau]))[0], ib.y(np.array([0.0, 0.5 * tau]))[0]
        assert np.max(np.abs(ya - yb)) <= 1e-13 * (np.max(np.abs(ya)) + 1e-300)
        assert np.array_equal(ia.w, ib.w) and np.array_equal(ia.f_const, ib.f_const)
    assert changed >= 10  # the events were settled, not only re-tested


def test_holding_force_at_the_limit_stays_stuck_on_both_paths():
    """A rigid slider held exactly at its slip force with zero slip acceleration stays stuck on
    both paths (the zero band and the curvature rule, not a zero-length slip)."""
    s = fj.FrictionSystem(fj.LinearStructure(1.0, 0.0, 1.0), [fj.CoulombSlider(1.0, dof=0)], omega=1.0,
                          excitation=[fj.ExternalForce(0, [0.0, 1e9], [1.0])])
    for jit in (False, True):
        m = Marcher(s)
        m.jit = jit
        st = m.initial_state([0.0], [0.0])
        # holding force exactly at the limit, zero slip acceleration: stays stuck
        assert st.status.tolist() == [0]
