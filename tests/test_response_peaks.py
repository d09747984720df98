"""Peaks of |x| on structures of many DOFs (:func:`piece_peaks`): the velocity reversals are located
on their own DOFs' rows of the modal sum (``response._PieceRows``), and a long piece's samples are
screened (``response._screened_samples``), checked against the whole structure's motion of :meth:`.Interval.velocity` and :meth:`.Interval.state`, and the peaks against
dense sampling of the same closed-form pieces, on a chain's transient from rest (pieces that start
at a reversal, DOFs at rest to rounding) and on a chain with stuck Coulomb sliders (``N != I``)."""
import math

import numpy as np

import frictionjoint as fj
from benchmarks.chains import chain
from frictionjoint.solvers.marcher.events import EventLog, Marcher
from frictionjoint.solvers.marcher.response import _PieceRows, _sample_times, _samples, piece_peaks

#: rows against the whole structure's motion, relative to the largest value over the piece (both
#: are the same modal sum, added in another order)
ROWS_RTOL = 1e-13
#: peaks against the samples, relative to the largest |x| over the piece
PEAK_RTOL = 1e-14


def _pieces(system, periods: float):
    """The closed-form pieces of a march from rest over ``periods`` excitation periods."""
    m = Marcher(system)
    out = []
    n = system.n_dof
    m.march(m.initial_state(np.zeros(n), np.zeros(n)), periods * 2 * math.pi / system.omega, EventLog(),
            on_interval=lambda itv, tau: out.append((itv, tau)) if tau > 0 else None)
    return out


def _slider_chain():
    """8 masses, a Jenkins joint at the free end and two Coulomb sliders (rigid: stuck, they remove
    their DOF from the configuration's coordinates)."""
    n = 8
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    els = [fj.Jenkins(0.5 * w1 ** 2, 0.002, dof=7), fj.CoulombSlider(0.0015, dof=3), fj.CoulombSlider(0.001, dof=5)]
    return fj.FrictionSystem(fj.LinearStructure.chain(n, damping=0.02 * w1), els, omega=0.9 * w1,
                             excitation=[fj.HarmonicForce(n - 1, 0.01)])


def test_rows_are_the_structures_motion():
    """v, a, a' and x of DOF ``rows[i]`` at its own time ``t[i]``, and v and a of every DOF on a
    grid of times, equal the entries of the whole structure's motion at those times."""
    rng = np.random.default_rng(3)
    rigid = 0
    for system in (chain(20, 4), _slider_chain()):
        n = system.n_dof
        for itv, tau in _pieces(system, 2):
            rigid += itv.config.rigid_stuck.size > 0
            rows = np.tile(np.arange(n), 2)
            t = rng.uniform(0.0, tau, rows.size)
            idx = np.arange(rows.size)
            pr = _PieceRows(itv, rows)
            grid = np.linspace(0.0, tau, 64)
            full = itv.velocity(t, 2)
            scales = [np.max(np.abs(d)) for d in itv.velocity(grid, 2)]
            for order in (0, 1):
                f, df = pr.velocity(t, order)
                assert np.max(np.abs(f - full[order][rows, idx])) <= ROWS_RTOL * scales[order]
                assert np.max(np.abs(df - full[order + 1][rows, idx])) <= ROWS_RTOL * scales[order + 1]
            x = pr.displacement(t)
            scale = np.max(np.abs(itv.state(grid)[0]))
            assert np.max(np.abs(x - itv.state(t)[0][rows, idx])) <= ROWS_RTOL * scale
            # every row on one grid of times
            on_grid = _PieceRows(itv, np.arange(n)).grid(grid)
            for order in (0, 1):
                assert np.max(np.abs(on_grid[order] - itv.velocity(grid, 1)[order])) <= ROWS_RTOL * scales[order]
    assert rigid > 0


def test_peaks_against_dense_sampling():
    """The peaks are finite, at least every sample of |x| on 4000 points per piece and above the
    sampled maximum by no more than the grid can miss (curvature x half a step squared)."""
    for system, periods in ((chain(30, 6), 1), (_slider_chain(), 3)):
        for itv, tau in _pieces(system, periods):
            amp = np.zeros(system.n_dof)
            piece_peaks(itv, tau, amp)
            taus = np.linspace(0.0, tau, 4000)
            x = itv.state(taus)[0]
            sampled = np.max(np.abs(x), axis=1)
            step = tau / 3999
            acc = np.max(np.abs(itv.velocity(taus, 1)[1]), axis=1) if itv.config.m else 0.0
            slack = PEAK_RTOL * np.max(sampled)
            assert np.all(np.isfinite(amp))
            assert np.all(amp >= sampled - slack)
            assert np.all(amp <= sampled + acc * step ** 2 + slack)


def test_screened_samples_skip_no_reversal():
    """On the long pieces of chain(30, 6)'s transient, the samples left out by the screening (NaN)
    are where the whole structure's velocity keeps its sign between samples (no reversal to
    bracket), and the samples taken are Interval.velocity's."""
    system = chain(30, 6)
    screened = 0
    for itv, tau in _pieces(system, 1):
        taus = _sample_times(itv, tau)
        vs, acc, _, _ = _samples(itv, taus)
        if not np.isnan(vs).any():
            continue
        screened += 1
        v, a = itv.velocity(taus, 1)
        taken = ~np.isnan(vs)
        assert np.max(np.abs(vs[taken] - v[taken])) <= ROWS_RTOL * np.max(np.abs(v))
        assert np.max(np.abs(acc[taken] - a[taken])) <= ROWS_RTOL * np.max(np.abs(a))
        # a sample interval is skipped when both its ends are
        skipped = ~taken[:, :-1] & ~taken[:, 1:]
        assert np.all(v[:, :-1][skipped] * v[:, 1:][skipped] > 0)
    assert screened >= 3
