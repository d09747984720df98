"""Per-piece outputs of the exact marcher: Fourier integrals in closed form and peaks of |x|,
checked against independent quadrature and dense sampling of the same closed-form pieces."""
import math

import numpy as np

import frictionjoint as fj
from frictionjoint.solvers.marcher.events import EventLog, Marcher
from frictionjoint.solvers.marcher.response import displacement_observables, gauss_nodes, interval_fourier, piece_peaks


def _system():
    n = 5
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    els = [fj.Jenkins(0.5 * w1 ** 2, 0.0012, dof=4), fj.CoulombSlider(0.0008, dof=2)]
    return fj.FrictionSystem(fj.LinearStructure.chain(n, damping=0.02 * w1), els, omega=0.9 * w1,
                             excitation=[fj.HarmonicForce(n - 1, 0.01)])


def _pieces(system, periods=3):
    m = Marcher(system)
    out = []
    m.march(m.initial_state(np.zeros(system.n_dof), np.zeros(system.n_dof)), periods * 2 * math.pi / system.omega,
            EventLog(), on_interval=lambda itv, tau: out.append((itv, tau)) if tau > 0 else None)
    return m, out


def test_closed_form_fourier_matches_gauss_quadrature():
    """int Q e^{i k w t} dt of x and of the friction forces, k = 1 and 3, against 12-point
    Gauss-Legendre on sub-pieces of 1/64 of the fastest period (an independent quadrature)."""
    system = _system()
    m, pieces = _pieces(system)
    worst = 0.0
    for itv, tau in pieces:
        for obs in (displacement_observables(system.n_dof), m.force_observables(itv)):
            red = itv.reduce(obs)
            for k in (1, 3):
                nu = k * system.omega
                exact = interval_fourier(itv, red, nu, tau)
                nodes, wts = gauss_nodes(0.0, tau, 8 * max(system.omega * k, itv.config.max_rate))
                ref = (itv.evaluate(red, nodes)[0] * np.exp(1j * nu * (itv.t0 + nodes))) @ wts
                scale = np.max(np.abs(itv.evaluate(red, nodes)[0])) * tau
                worst = max(worst, float(np.max(np.abs(exact - ref))) / scale)
    assert len(pieces) > 10
    assert worst <= 1e-13, worst


def test_piece_peaks_match_dense_sampling():
    """The located peaks are >= every sample of |x| on a grid of 4000 points per piece and exceed
    the sampled maximum by no more than the grid can miss (curvature x half a step squared)."""
    system = _system()
    _, pieces = _pieces(system)
    for itv, tau in pieces:
        amp = np.zeros(system.n_dof)
        piece_peaks(itv, tau, amp)
        taus = np.linspace(0.0, tau, 4000)
        x, _ = itv.state(taus)
        sampled = np.max(np.abs(x), axis=1)
        step = tau / 3999
        acc = np.max(np.abs(itv.y(taus, order=1)[1][itv.config.m:]), initial=0.0) if itv.config.m else 0.0
        assert np.all(amp >= sampled * (1 - 1e-14))
        assert np.all(amp <= sampled + acc * step ** 2 + 1e-15)
