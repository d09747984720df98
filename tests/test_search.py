"""The compiled event search (frictionjoint.solvers.search, numba) against the marcher's NumPy
search: the same algorithm, so the same events and states up to rounding."""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.solvers import search
from frictionjoint.solvers.events import EventLog, Marcher

pytestmark = pytest.mark.skipif(not search.ENABLED, reason="numba not available")


def _system(rigid):
    n = 6
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    els = [fj.Jenkins(0.5 * w1 ** 2, 0.002, dof=5), fj.Jenkins(0.5 * w1 ** 2, 0.002, dof=3)]
    if rigid:
        els.append(fj.CoulombSlider(0.001, dof=4))
    return fj.FrictionSystem(fj.LinearStructure.chain(n, damping=0.02 * w1), els, omega=0.9 * w1,
                             excitation=[fj.HarmonicForce(n - 1, 0.01)])


@pytest.mark.parametrize("rigid", [False, True])
def test_compiled_search_matches_numpy_search(rigid):
    sysm = _system(rigid)
    period = 2 * math.pi / sysm.omega
    out = []
    for jit in (True, False):
        m = Marcher(sysm)
        m.jit = jit
        log = EventLog()
        st = m.initial_state(np.zeros(6), np.zeros(6))
        m.march(st, 8 * period, log)
        out.append((log, st))
    (la, sa), (lb, sb) = out
    assert len(la) > 20
    assert la.kind == lb.kind and la.slider == lb.slider
    assert np.max(np.abs(np.subtract(la.time, lb.time))) <= 1e-12 * 8 * period
    scale = np.max(np.abs(sb.x))
    assert np.max(np.abs(sa.x - sb.x)) <= 1e-12 * scale
    assert np.max(np.abs(sa.v - sb.v)) <= 1e-12 * scale * sysm.omega * 10
    assert np.array_equal(sa.status, sb.status)
