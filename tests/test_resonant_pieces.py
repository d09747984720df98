"""Pieces with a (near-)resonant mode/forcing pair (``Interval.near``: a mode within 1 % of the
forcing frequency keeps the form ``c E(lam, mu, tau)``) in the compiled kernels: the event search,
the end state and the closed-form Fourier integral, against the NumPy path of the same closed form
and against Gauss-Legendre quadrature. The system: a Craig-Bampton blade on its dovetail root
driven at its first bending resonance (100 N at the tip), where the root slips and the slipping configurations have
a mode within 1 % of omega."""
import math

import numpy as np
import pytest

from frictionjoint.solvers.marcher import piece_kernels, search
from frictionjoint.solvers.marcher.events import EventLog, Marcher
from frictionjoint.solvers.marcher.response import displacement_observables, gauss_nodes, interval_fourier
from frictionjoint.structures import MODELS_DIR, BladeAssembly, load_blade_model
from test_search import compare_compiled_and_numpy

pytestmark = pytest.mark.skipif(not search.ENABLED, reason="numba not available")


@pytest.fixture(scope="module")
def resonant():
    model = BladeAssembly.from_model(load_blade_model(MODELS_DIR / "ti64_compressor_blade.toml"))
    # 100 N at the tip: the flanks slip on the orbit (16 events per period)
    blade = BladeAssembly(model.structure, model.joints, {"w30": 100.0})
    sysm = blade.system(2045.0)  # first bending mode, stuck 2045.5 rad/s, slipping 2044.5 rad/s
    n = sysm.n_dof
    z0 = blade.steady_state(2045.0).initial_state  # on the slipping orbit
    m = Marcher(sysm)
    pieces = []
    st = m.initial_state(z0[:n], z0[n:2 * n], z0[2 * n:])
    m.march(st, 3 * 2 * math.pi / sysm.omega, EventLog(),
            on_interval=lambda itv, tau: pieces.append((itv, tau)))
    near = [(itv, tau) for itv, tau in pieces if tau > 0 and itv.modal_search() and itv.near[0].size]
    assert len(near) >= 4
    return sysm, z0, near


def test_compiled_march_matches_numpy_march_at_resonance(resonant):
    sysm, z0, _ = resonant
    n = sysm.n_dof
    compare_compiled_and_numpy(sysm, (z0[:n], z0[n:2 * n], z0[2 * n:]), 20, 1e-11, vfactor=1.0)


def test_compiled_resonant_state_matches_numpy(resonant):
    sysm, _, near = resonant
    for itv, tau in near:
        cfg = itv.config
        for t in (0.3 * tau, tau):
            x, v = piece_kernels.state(cfg.V, cfg.N, itv.x0, cfg.lam, itv._a, *itv._b, sysm.omega, t, *itv.near)
            xr, vr = itv.state(t)
            scale = np.max(np.abs(xr))
            assert np.max(np.abs(x - xr[:, 0])) <= 1e-13 * scale
            assert np.max(np.abs(v - vr[:, 0])) <= 1e-13 * np.max(np.abs(vr)) + 1e-13 * scale * sysm.omega


def test_compiled_resonant_event_functions_match_numpy(resonant):
    """The compiled g and g' of every event row (with the resonant terms) against the NumPy sampler
    of the same piece, and the compiled Taylor bound keeps them above their level where it steps."""
    sysm, _, near = resonant
    for itv, tau in near:
        cy, c0, cc, cs = itv.events[0]
        cfg = itv.config
        p = cy @ cfg.V
        b0, bp, bm = itv._b
        pa, pla, k0, kp, km, harmonic = search._coefficients(p, itv._a, b0, bp, bm, c0, cfg.lam, cc, cs)
        nidx, nmu, nc = itv.near
        pn = search._near_terms(p, nidx, nc)
        nlam = cfg.lam[nidx]
        taus = np.linspace(0.0, tau, 7)
        g_ref, dg_ref = itv.sampler(itv.events[0])(taus)
        g = np.empty((k0.size, 1))
        dg = np.empty((k0.size, 1))
        for k, t in enumerate(taus):
            search._sample(pa, pla, cfg.lam, k0, kp, km, cc, cs, sysm.omega, itv.t0, harmonic, pn, nlam, nmu, t,
                           g, dg, 0)
            scale = np.max(np.abs(g_ref), axis=1) + np.abs(k0)
            assert np.all(np.abs(g[:, 0] - g_ref[:, k]) <= 1e-12 * scale)
            dscale = np.max(np.abs(dg_ref), axis=1) + sysm.omega * scale
            assert np.all(np.abs(dg[:, 0] - dg_ref[:, k]) <= 1e-12 * dscale)
        tol = np.full(k0.size, 0.0)
        curv, level = search._curvature(pa, pla, cfg.lam, k0, kp, km, cc, cs, sysm.omega, itv.t0, harmonic,
                                        pn, nlam, nmu, tol, tau)
        # |g''| <= curv: second differences of dense samples
        dense = np.linspace(0.0, tau, 4001)
        gd, dgd = itv.sampler(itv.events[0])(dense)
        second = np.abs(np.diff(dgd, axis=1)) / np.diff(dense)
        assert np.all(second <= curv[:, None] * (1 + 1e-9) + 1e-9 * np.max(np.abs(dgd), axis=1)[:, None] / tau)


def test_resonant_fourier_integral_is_gauss_legendre(resonant):
    """The closed-form first-harmonic integral of the resonant pieces (Van Loan's block exponential
    for int E e^{i w t}) against 12-point Gauss-Legendre quadrature at 8 pieces per period."""
    sysm, _, near = resonant
    x_obs = displacement_observables(sysm.n_dof)
    worst = 0.0
    for itv, tau in near:
        red = itv.reduce(x_obs)
        exact = interval_fourier(itv, red, sysm.omega, tau)
        nodes, wts = gauss_nodes(0.0, tau, max(sysm.omega, itv.active_rate()))
        yq = itv.evaluate(red, nodes)[0]
        ref = yq @ (wts * np.exp(1j * sysm.omega * (itv.t0 + nodes)))
        scale = np.max(np.abs(yq)) * tau
        worst = max(worst, float(np.max(np.abs(exact - ref))) / scale)
    assert worst <= 1e-12
