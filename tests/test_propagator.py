"""Closed-form pieces (frictionjoint.solvers.propagator): the near-resonant integral E."""
import numpy as np
import scipy.integrate

from frictionjoint.solvers.propagator import _E


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
