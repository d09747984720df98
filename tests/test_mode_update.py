"""The modes of a configuration updated from its neighbour's by the one joint spring they differ by
(frictionjoint.solvers.marcher.mode_update): against LAPACK's dense decomposition of the same
first-order matrix, and the orbits of a march with and without the updates."""
import numpy as np
import pytest

import frictionjoint as fj
from benchmarks.chains import damped_chain
from frictionjoint.solvers.marcher import events, mode_update, propagator
from frictionjoint.solvers.marcher.steady import periodic_response

pytestmark = pytest.mark.skipif(not mode_update.ENABLED, reason="the update's root finder is compiled (numba)")


def _first_order(system, stuck):
    n = system.n_dof
    d, k = system.slider_direction, system.slider_stiffness
    kc = system.stiffness + (d[stuck].T * k[stuck]) @ d[stuck]
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = -np.linalg.solve(system.mass, kc)
    a[n:, n:] = -np.linalg.solve(system.mass, system.damping)
    return a, kc


@pytest.mark.parametrize("damping", ["stiffness", "rayleigh", "modal", "dashpot"])
def test_updated_modes_are_the_dense_ones(damping):
    """A chain of 30 DOFs with 8 joints as stiff as its springs, over a walk of 12 one-spring
    changes (each update from the previous one's modes, the errors carried along): the eigenvalues
    against LAPACK's (dense eig of the new first-order matrix, matched one to one), the eigenvector
    residual ``|A V - V diag(mu)|`` per unit column relative to ``|A|``, and ``V^-1 V - I`` (cond(V)
    at most 9 here). Largest measured over the four damping forms: eigenvalues 6.1e-15 of the
    largest, residuals 2.6e-15, ``V^-1 V - I`` 1.5e-15; the bounds, 1e-12, are 160x to 660x above."""
    system = damped_chain(30, 8, damping, 1.0)
    rng = np.random.default_rng(7)
    stuck = rng.random(system.n_sliders) < 0.5
    a, _ = _first_order(system, stuck)
    lam, (tsc, v), w = propagator._general_modes(a)
    n = system.n_dof
    for _ in range(12):
        i = int(rng.integers(system.n_sliders))
        stuck[i] = not stuck[i]
        d = system.slider_direction[i]
        k = system.slider_stiffness[i] * (1.0 if stuck[i] else -1.0)
        a, kc = _first_order(system, stuck)
        mu, phi = mode_update.rank_one_modes(lam, v, w, -np.linalg.solve(system.mass, d) * k, d)
        v = mode_update.checked_modes(mu, phi, system.mass, system.damping, kc)
        assert v is not None
        w = propagator._real_inverse(mu, v)
        ref = np.linalg.eigvals(a)
        scale = np.max(np.abs(ref))
        got = np.array(mu)
        for x in ref:  # one to one: nearest, then removed
            j = int(np.argmin(np.abs(got - x)))
            assert abs(got[j] - x) <= 1e-12 * scale
            got = np.delete(got, j)
        norm_a = np.linalg.norm(a, 2)
        assert np.max(np.linalg.norm(a @ v - v * mu, axis=0)) <= 1e-12 * norm_a
        assert np.max(np.abs(w @ v - np.eye(2 * n))) <= 1e-12
        lam = mu


@pytest.mark.parametrize("damping", ["stiffness", "rayleigh"])
def test_orbit_is_the_same_with_and_without_updates(damping, monkeypatch):
    """The steady state of a 24-DOF chain with 6 joints as stiff as its springs: every configuration
    decomposed from scratch (no neighbour offered) against the march whose configurations are
    updated from their neighbours. The same orbit to 1e-10 of the largest amplitude (issue 40's
    bound; measured 3.9e-15 and 2.5e-15 here, 1.1e-15 and 4.8e-15 at 100 DOFs), and most configurations were updates."""
    counts = {"updated": 0}
    orig = propagator.ConfigData._updated_modes

    def counted(self, *args):
        out = orig(self, *args)
        counts["updated"] += out is not None
        return out
    monkeypatch.setattr(propagator.ConfigData, "_updated_modes", counted)
    res = periodic_response(damped_chain(24, 6, damping, 1.0))
    assert counts["updated"] >= 3
    monkeypatch.setattr(events.Marcher, "_neighbour", lambda self, status: None)
    ref = periodic_response(damped_chain(24, 6, damping, 1.0))
    assert res.converged and ref.converged
    assert np.max(np.abs(res.amplitude - ref.amplitude)) <= 1e-10 * np.max(np.abs(ref.amplitude))


def test_no_update_without_the_compiled_root_finder(monkeypatch):
    """An FMU's NumPy copy (kernels not compiled) decomposes from scratch: rank_one_modes says None."""
    monkeypatch.setattr(mode_update, "ENABLED", False)
    lam = np.array([-1 + 2j, -1 - 2j])
    v = np.eye(2, dtype=complex)
    assert mode_update.rank_one_modes(lam, v, v, np.ones(1), np.ones(1)) is None
