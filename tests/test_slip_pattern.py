"""The stick/slip pattern of a periodic orbit (frictionjoint.solvers.marcher.slip_pattern): each
slider's status between the orbit's events, against the marcher's own status vector when the same
orbit is marched again in small steps (an independent reading: the march's state, not the log).

References: the two-flank point model shaken hard enough to slip and, with varying normal loads, to
lift off and close again (tests/test_contact_patch.py's system); a stuck orbit (nothing changes).
"""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.results.slip_pattern import OPEN, SLIPPING, STUCK, SlipPattern
from frictionjoint.solvers.marcher import Marcher, failed_response
from frictionjoint.solvers.marcher.slip_pattern import slip_pattern

#: marched checkpoints per period; those within EDGE of an event are not compared
N_CHECK, EDGE = 400, 1e-9

G, MU, KN, KT, FC = math.radians(40.0), 0.3, 1e6, 2e5, 1000.0


def _shaken(vary, force=400.0):
    block = fj.LinearStructure(np.diag([0.2, 0.2]), np.zeros((2, 2)), np.diag([2.0, 2.0]), dof_names=["X", "Y"])
    root = fj.DovetailRoot(FC, G, MU, KN, KT, tangential_dof="X", radial_dof="Y", normal_load_variation=vary)
    return fj.FrictionSystem(block, [root], omega=2000.0,
                             excitation=[fj.HarmonicForce("X", force), fj.HarmonicForce("Y", force / 2, phase=0.7)])


def _marched_statuses(system, r, times):
    """The marcher's status vector at ``times`` (from the section time on), marching the orbit."""
    m = Marcher(system)
    n = system.n_dof
    z = r.state
    state = m.initial_state(z[:n], z[n:2 * n], z[2 * n:], t0=r.section_time)
    out = []
    for t in times:
        m.march(state, t)
        s = state.status
        out.append(np.where(s == 2, OPEN, np.where(s == 0, STUCK, SLIPPING)))
    return np.array(out).T


@pytest.mark.parametrize("vary", [False, True], ids=["frozen", "varying"])
def test_pattern_is_the_marchers_status(vary):
    system = _shaken(vary)
    r = fj.periodic_response(system)
    assert r.converged
    p = slip_pattern(r, system)
    period = 2 * math.pi / system.omega
    assert p.times[0] == 0.0 and p.times[-1] == pytest.approx(period, rel=1e-14) and np.all(np.diff(p.times) >= 0)
    assert p.pattern.shape == (system.n_sliders, p.times.size - 1)
    fractions = sum(p.fraction(s) for s in (STUCK, SLIPPING, OPEN))
    assert np.max(np.abs(fractions - 1.0)) <= 1e-12
    assert (p.pattern == SLIPPING).any()
    if vary:
        assert (p.pattern == OPEN).any() and r.events.count("lift-off") >= 1
    times = r.section_time + period * (np.arange(1, N_CHECK + 1) - 0.5) / N_CHECK
    marched = _marched_statuses(system, r, times)
    read = p.at(times)
    events = np.array([t for t, *_ in r.events])
    far = np.min(np.abs(times[:, None] - events[None, :]), axis=1) > EDGE * period
    print(f"{'varying' if vary else 'frozen'}: {p.message}; {int(far.sum())} checkpoints compared; slipping "
          f"fractions {p.fraction(SLIPPING).round(4)}, open {p.fraction(OPEN).round(4)}")
    assert np.array_equal(read[:, far], marched[:, far])


def test_stuck_orbit_is_one_stuck_piece():
    system = _shaken(False, force=1.0)
    r = fj.periodic_response(system)
    p = slip_pattern(r, system)
    assert r.stuck and p.pattern.shape == (2, 1) and np.all(p.pattern == STUCK)
    assert np.all(p.fraction(STUCK) == 1.0) and isinstance(p, SlipPattern) and p.success


def test_refused_input():
    system = _shaken(False)
    r = fj.periodic_response(system)
    other = fj.FrictionSystem(system.structure, system.elements, omega=1000.0, excitation=system.excitation)
    with pytest.raises(ParameterError, match="omega"):
        slip_pattern(r, other)
    with pytest.raises(ParameterError, match="converged"):
        slip_pattern(failed_response(system.omega, system.n_dof, "made to fail"), system)


def test_plot_writes_the_pattern(tmp_path):
    """The pattern's picture: one flank with a static quantity beside it, or into given axes."""
    from frictionjoint.plotting import new_figure

    system = _shaken(True)
    p = slip_pattern(fj.periodic_response(system), system)
    ax = p.plot(path=tmp_path / "pattern.png", sliders=[1], positions=[0.0], static_load=[FC])
    assert ax.get_xlim() == (0.0, 1.0) and (tmp_path / "pattern.png").read_bytes()[:4] == b"\x89PNG"
    fig = new_figure()
    axes = fig.subplots(1, 2)
    assert p.plot(ax=tuple(axes), static_load=[1.0, 2.0], title="both flanks") is axes[0]
    assert {t.get_text() for t in axes[0].get_legend().get_texts()} == {"stuck", "slipping", "open"}
    with pytest.raises(ValueError, match="positions"):
        p.plot(positions=[0.0])
