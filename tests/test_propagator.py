"""Closed-form pieces (frictionjoint.solvers.marcher.propagator): the near-resonant integral E and the
compiled coefficients and states of plain modal pieces."""
import math

import numpy as np
import pytest
import scipy.integrate

import frictionjoint as fj
from frictionjoint.solvers.marcher import piece_kernels, propagator
from frictionjoint.solvers.marcher.events import EventLog, Marcher
from frictionjoint.solvers.marcher.propagator import _E


def test_near_resonant_integral_matches_quadrature_and_stays_finite():
    """E(lam, mu, tau) = int_0^tau e^{lam (tau - s)} e^{mu s} ds, including a stiff decaying mode over a long piece, where the
    form tau e^{lam tau} phi1((mu - lam) tau) is 0 * inf (NaN before the second form was added).
    Reference: the textbook form (e^{mu tau} - e^{lam tau}) / (mu - lam) where |mu - lam| >= 1,
    adaptive quadrature (scipy.integrate.quad, rtol 1e-13) near resonance."""
    mu = 3j
    lam = np.array([[-1e5 + 0j], [-1.0 + 2j], [1e-9 + 0j], [mu + 1e-12]])
    tau = np.array([[0.0, 1e-3, 0.1, 10.0]])
    got = _E(lam, mu, tau)
    assert np.all(np.isfinite(got))
    for i, l in enumerate(lam[:, 0]):
        for k, t in enumerate(tau[0]):
            if abs(mu - l) >= 1.0:
                # far from resonance the textbook form is well conditioned
                ref = (np.exp(mu * t) - np.exp(l * t)) / (mu - l)
            else:
                def part(s, f):
                    return f(np.exp(l * (t - s) + mu * s))
                ref = (scipy.integrate.quad(part, 0.0, t, args=(np.real,), epsabs=0, epsrel=1e-13, limit=400)[0]
                       + 1j * scipy.integrate.quad(part, 0.0, t, args=(np.imag,), epsabs=0, epsrel=1e-13,
                                                   limit=400)[0])
            assert abs(got[i, k] - ref) <= 1e-12 * abs(ref), (l, t, got[i, k], ref)


def test_compiled_piece_kernels_match_numpy():
    """Coefficients and end states of plain modal pieces (solvers.piece_kernels, numba) against the
    NumPy arithmetic of Interval._prepare / Interval.state, over the pieces of a march."""
    if not piece_kernels.ENABLED:
        pytest.skip("numba not available")
    n = 6
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    sysm = fj.FrictionSystem(fj.LinearStructure.chain(n, damping=0.02 * w1),
                             [fj.Jenkins(0.5 * w1 ** 2, 0.002, dof=5), fj.CoulombSlider(0.001, dof=4)],
                             omega=0.9 * w1, excitation=[fj.HarmonicForce(n - 1, 0.01)])
    m = Marcher(sysm)
    pieces = []
    m.march(m.initial_state(np.zeros(n), np.zeros(n)), 4 * 2 * math.pi / sysm.omega, EventLog(),
            on_interval=lambda itv, tau: pieces.append((itv, tau)))
    checked = 0
    for itv, tau in pieces:
        if not itv.modal_search():
            continue
        ref = propagator.Interval.from_parts(sysm, itv.config, itv.t0, itv.x0, itv.f_const, itv.kx0,
                                             itv._y0, itv._bvec[0])
        piece_kernels.ENABLED = False
        try:
            ref._prepare()
        finally:
            piece_kernels.ENABLED = True
        for a, b in zip([itv._a, *itv._b], [ref._a, *ref._b]):
            # compiled kernel and NumPy reference of the same formulas: rounding (the state below
            # measured at 1.1e-15 of its scale, within 10x of the former 1e-14); 1e-12 is ~1000x
            assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(b))
        x, v = piece_kernels.state(itv.config.V, itv.config.N, itv.x0, itv.config.lam, itv._a, *itv._b,
                                   sysm.omega, tau, *itv.near)
        xr, vr = ref.state(tau)
        assert np.max(np.abs(x - xr[:, 0])) <= 1e-12 * np.max(np.abs(xr))
        assert np.max(np.abs(v - vr[:, 0])) <= 1e-12 * np.max(np.abs(xr)) * itv.config.max_rate
        checked += 1
    assert checked > 10


def test_left_modes_are_the_inverse_of_refined_modes():
    """propagator._left_modes: V^-1 of a symmetric pencil's refined modes from their shapes. Against
    inv(V) on a damped 3-DOF configuration with a stuck spring at kt/k = 1e4 (inv(V) is accurate
    there: ~eps cond(V), cond ~ 1e3), to 1e-12 of each row; None where it does not apply (an
    unsymmetric damping, a repeated eigenvalue whose shapes are not M-orthogonal)."""
    mr = np.diag([1.0, 0.5, 2.0])
    kr = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    cr = 0.01 * kr + 0.002 * mr
    dr = np.array([[1.0], [0.0], [-1.0]])
    kt = np.array([1e4])
    kc = kr + kt[0] * dr @ dr.T
    a = np.block([[np.zeros((3, 3)), np.eye(3)], [-np.linalg.solve(mr, kc), -np.linalg.solve(mr, cr)]])
    lam, (tsc, v), _ = propagator._general_modes(a)
    lam, v = propagator._refine_modes(lam.astype(complex), v, mr, cr, kr, dr, kt)
    w = propagator._left_modes(lam, v, mr, cr, kr)
    ref = np.linalg.inv(v)
    assert w is not None
    assert np.all(np.max(np.abs(w - ref), axis=1) <= 1e-12 * np.max(np.abs(ref), axis=1))
    assert propagator._left_modes(lam, v, mr, cr + np.triu(cr, 1) * 1e-3, kr) is None
    # K = M = I: every mode at +-i; shapes (1, 0) and (1, 1)/sqrt(2) are modes but not M-orthogonal
    phi = np.array([[1.0, 0.0], [1.0, 1.0]]).T / [1.0, math.sqrt(2.0)]
    lam2 = np.array([1j, 1j, -1j, -1j])
    shapes = np.hstack([phi, phi]).astype(complex)
    v2 = np.vstack([shapes, shapes * lam2])
    assert propagator._left_modes(lam2, v2, np.eye(2), np.zeros((2, 2)), np.eye(2)) is None


def _rayleigh_chain(n=8, damping="rayleigh"):
    """A chain with classical but not mass-proportional damping and two Jenkins joints as stiff as
    its springs (a stuck one makes the configuration non-classical)."""
    base = fj.LinearStructure.chain(n)
    m, k = base.mass, base.stiffness
    if damping == "rayleigh":
        c = 0.01 * m + 0.05 * k
    else:  # modal damping: 2 % in every mode of the structure
        w2, phi = np.linalg.eigh(k)  # M = I
        c = phi @ np.diag(2 * 0.02 * np.sqrt(w2)) @ phi.T
    return fj.FrictionSystem(fj.LinearStructure(m, k, c), [fj.Jenkins(1.0, 0.002, dof=n - 1),
                                                           fj.Jenkins(1.0, 0.002, dof=n // 2)],
                             omega=0.3, excitation=[fj.HarmonicForce(n - 1, 0.01)])


@pytest.mark.parametrize("damping", ["rayleigh", "modal"])
def test_all_slip_configuration_of_a_classically_damped_structure_is_classical(damping, monkeypatch):
    """Rayleigh and modal damping: the configuration in which every joint slips has the structure's
    own modes, each with its own rate (propagator._modally_damped), and its pieces equal those of
    the general path (the first-order matrix's eig) to rounding; a stuck spring's configuration is
    not classical and takes the general path."""
    sysm = _rayleigh_chain(damping=damping)
    slip = np.array([1, -1], np.int8)
    cfg = propagator.ConfigData(sysm, slip)
    assert cfg.pairs is not None
    assert propagator.ConfigData(sysm, np.array([0, 1], np.int8)).pairs is None
    monkeypatch.setattr(propagator, "_modally_damped", lambda system: None)
    ref = propagator.ConfigData(sysm, slip)
    assert ref.pairs is None
    rng = np.random.default_rng(3)
    x0, v0 = rng.standard_normal(sysm.n_dof), rng.standard_normal(sysm.n_dof)
    f = np.zeros(sysm.n_dof)
    taus = np.array([0.0, 0.7, 3.1, 20.0])
    states = []
    for c in (cfg, ref):
        itv = propagator.Interval(sysm, c, 0.0, x0, v0, f)
        states.append(itv.state(taus))
    scale = max(np.max(np.abs(states[1][0])), np.max(np.abs(states[1][1])))
    # two decompositions of the same configuration: rounding of each (cond(V) ~ 10 here); 2e-12 is
    # ~120x above the 1.2e-14 (Rayleigh) and 1.7e-14 (modal) measured
    for a, b in zip(*states):
        assert np.max(np.abs(a - b)) <= 2e-12 * scale


def test_real_inverse_of_conjugate_eigenvectors():
    """propagator._real_inverse: V^-1 from the real matrix of the pairs' real and imaginary parts,
    against NumPy's complex inverse (both rounding of an inverse of cond ~ 1e2: 1e-12 of the entries
    is ~1000x above the 1.1e-15 measured; the triangular, all-real case is exact, 0); the complex
    and the all-real cases."""
    rng = np.random.default_rng(0)
    for a in (rng.standard_normal((12, 12)), np.diag(rng.standard_normal(5)) + np.triu(rng.standard_normal((5, 5)), 1)):
        lam, v = np.linalg.eig(a)
        w = propagator._real_inverse(lam, v)
        ref = np.linalg.inv(v.astype(complex))
        assert np.max(np.abs(w - ref)) <= 1e-12 * np.max(np.abs(ref))


def test_halved_general_modes_give_the_whole_ones_back():
    """propagator._halved_modes keeps a pair's first root (its vector times 2) and the real roots;
    _unhalved_modes gives the same numbers back, exactly (a factor 2 and a conjugate: no rounding).
    Pairs that are not exact conjugates are kept whole (None)."""
    rng = np.random.default_rng(1)
    a = rng.standard_normal((10, 10))
    lam, v = np.linalg.eig(a)
    w = propagator._real_inverse(lam, v)
    lam_h, v_h, w_h, p = propagator._halved_modes(lam, v, w)
    assert p == np.count_nonzero(lam.imag > 0) and lam_h.size == lam.size - p
    back = propagator._unhalved_modes(lam_h, v_h, w_h, p)
    # the same set of (root, vector, row) triples, exactly
    i, j = np.lexsort((lam.imag, lam.real)), np.lexsort((back[0].imag, back[0].real))
    assert np.array_equal(lam[i], back[0][j])
    assert np.array_equal(v.astype(complex)[:, i], back[1][:, j])
    assert np.array_equal(w[i], back[2][j])
    v_bad = v.astype(complex)
    k = int(np.flatnonzero(lam.imag > 0)[0])
    v_bad[:, k + 1] *= 1 + 1e-15
    assert propagator._halved_modes(lam, v_bad, w) is None


def test_halved_general_modes_march_the_same_orbit(monkeypatch):
    """A stiffness-damped chain's stuck configurations have general modes, kept halved; its steady
    state equals the one with the modes kept whole (monkeypatched off) to rounding: the real-part
    rule sums a pair's two conjugate terms as twice the real part of one. 1e-12 of the largest
    amplitude is ~100x above the 8.7e-15 measured (two Newton solves' rounding)."""
    n = 12
    base = fj.LinearStructure.chain(n)
    sysm = fj.FrictionSystem(fj.LinearStructure(base.mass, base.stiffness, 0.02 * base.stiffness),
                             [fj.Jenkins(1.0, 0.004, dof=n - 1), fj.Jenkins(1.0, 0.003, dof=n // 2)],
                             omega=0.12, excitation=[fj.HarmonicForce(n - 1, 0.01)])
    m = Marcher(sysm)
    got = fj.periodic_response(sysm, marcher=m)
    assert got.converged
    halved = [c for c in m._configs.values() if "_pending" not in c.__dict__ and c.n_pairs is not None]
    assert halved
    f = np.linspace(-1.0, 1.0, n)
    for c in halved:  # the whole modes back: V V^-1 = I to rounding of the inverse
        lam, v, w = c.full_modes()
        assert lam.size == 2 * n and np.max(np.abs(v @ w - np.eye(2 * n))) <= 1e-10
        # what an update reads, without the whole modes: the same numbers (a conjugate commutes
        # with sums and products by reals)
        lam_u, top, a = c.update_basis(f)
        assert np.array_equal(lam_u, lam) and np.array_equal(top, v[:n])
        if c._left:  # the left eigenvectors' rows, refined once, against the inverse (whole modes)
            assert np.max(np.abs(a - w[:, n:] @ f)) <= 1e-12 * np.max(np.abs(a))
        else:
            assert np.array_equal(a, w[:, n:] @ f)
    monkeypatch.setattr(propagator, "_halved_modes", lambda lam, v, w: None)
    monkeypatch.setattr(propagator, "_symmetric_pencil", lambda system: False)  # its modes come halved
    ref = fj.periodic_response(sysm, marcher=Marcher(sysm))
    assert np.max(np.abs(got.amplitude - ref.amplitude)) <= 1e-12 * np.max(ref.amplitude)


def test_real_inverse_of_a_singular_matrix_raises_and_does_not_warn():
    """propagator._real_inverse (LAPACK getrf + getri called directly): a singular matrix of the
    pairs' real and imaginary parts raises LinAlgError (SciPy 1.17's inv crashed on this symmetric
    one), and an ill-conditioned one returns without a warning (the caller's condition test sends
    a defective configuration to the exponential)."""
    import warnings
    v = np.array([1 + 1j, 1 + 1j])
    with pytest.raises(np.linalg.LinAlgError):
        propagator._real_inverse(np.array([1j, -1j]), np.stack([v, v.conj()], axis=1))
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        lam, vb, w = propagator._general_modes(np.array([[0.0, 1.0], [0.0, 0.0]]))
    assert vb is None and w is None
