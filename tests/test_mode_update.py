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


@pytest.mark.parametrize("damping", ["stiffness", "rayleigh", "dashpot"])
def test_left_rows_refine_to_the_inverse(damping, monkeypatch):
    """Updated configurations of a symmetric pencil take ``V^-1`` from their left eigenvectors
    (propagator._left_inverse: no inverse of the 2m x 2m matrix), and a piece's start from them
    refined once (ConfigData.refined). A 60-DOF chain with 12 joints as stiff as its springs: the
    refined modal coordinates of a random state against the inverse's (full_modes) within 1e-12
    (measured 7.7e-15 at most over the three forms), and the steady state against the march that
    inverts (left form off) within 1e-10 of the largest amplitude (issue 40's bound; measured
    6.2e-14 at most)."""
    system = damped_chain(60, 12, damping, 1.0)
    m = events.Marcher(system)
    res = periodic_response(system, marcher=m)
    left = [c for c in m._configs.values() if "_pending" not in c.__dict__ and c._left]
    assert len(left) >= len(m._configs) // 2
    z = np.random.default_rng(3).standard_normal(2 * system.n_dof)
    for c in left:
        _, _, w = c.full_modes()  # the inverse of the whole modes
        exact = w @ z
        got = propagator._unhalved(c.left_product(c.refined(z)), c.n_pairs)
        assert np.max(np.abs(got - exact)) <= 1e-12 * np.max(np.abs(exact))
    monkeypatch.setattr(propagator, "_symmetric_pencil", lambda system: False)
    ref = periodic_response(system, marcher=events.Marcher(system))
    assert res.converged and ref.converged
    assert np.max(np.abs(res.amplitude - ref.amplitude)) <= 1e-10 * np.max(np.abs(ref.amplitude))


def test_left_rows_are_refused_where_shapes_are_not_orthogonal():
    """Two equal oscillators, uncoupled: each root is double, and any two independent shapes are
    eigenvectors. Shapes ``[1, 0]`` and ``[1, 1]`` are not M-orthogonal, so the left-eigenvector rows
    are not ``V^-1`` (``V W - I`` of order 1): the probe refuses them (None, the caller inverts),
    while orthogonal shapes of the same roots pass."""
    mass, damping, stiffness = np.eye(2), 0.1 * np.eye(2), np.eye(2)
    lam = -0.05 + 1j * np.sqrt(1 - 0.05 ** 2)
    mu = np.array([lam, lam.conjugate(), lam, lam.conjugate()])

    def modes(phi_a, phi_b):
        phi = np.array([phi_a, phi_a, phi_b, phi_b], dtype=complex).T
        return np.vstack([phi, phi * mu])
    assert propagator._left_inverse(mu, modes([1, 0], [1, 1]), mass, damping, np.ones(4)) is None
    halved = propagator._left_inverse(mu, modes([1, 0], [0, 1]), mass, damping, np.ones(4))
    assert halved is not None
    lam_h, v, w, p, _ = halved
    # each entry a sum of 4 products of numbers of magnitude <= 2 (the pairs' vectors carry 2):
    # at most ~16 eps = 3.6e-15 of rounding (measured 1.1e-16)
    assert p == 2 and np.max(np.abs((v @ w).real - np.eye(4))) <= 1e-14
