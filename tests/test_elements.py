"""Joint elements in the exact marcher: Jenkins loop corners, Coulomb limit, Iwan, linear limits.

References: exact piecewise-linear Jenkins loop (corners at T = +-Fs, slope kt between);
Den Hartog (1931) for the rigid limit; an independent scipy solve_ivp (rtol 1e-12) for linear
systems; Segalman (2005) for the 4-parameter Iwan totals.
"""
import math

import numpy as np
import pytest
import scipy.integrate

import frictionjoint as fj
from frictionjoint.analytic import den_hartog


def _jenkins_system(kt=20.0, fs=0.3, r=0.9, damping=0.02):
    s = fj.LinearStructure(1.0, 1.0, damping)
    return fj.FrictionSystem(s, [fj.Jenkins(kt, fs, dof=0)], omega=r,
                             excitation=[fj.HarmonicForce(0, 1.0)])


def test_jenkins_loop_corners_exact():
    kt, fs = 20.0, 0.3
    sysm = _jenkins_system(kt, fs)
    tr = fj.simulate(sysm, 40.0, 0.0, 0.0)
    times = np.array([t for t, _, _, k in tr.events])
    kinds = [k for _, _, _, k in tr.events]
    assert kinds.count("stick") >= 8 and kinds.count("slip") >= 8
    at = fj.simulate(sysm, 40.0, 0.0, 0.0, t_eval=times, record=("x", "v", "friction_force"))
    x, v, T = at.x[0], at.v[0], at.friction_force[0]
    for i, kind in enumerate(kinds):
        if kind == "stick":
            assert abs(v[i]) <= 1e-12  # sticks where the velocity reverses
            assert abs(abs(T[i]) - fs) <= 1e-12 * fs  # ... from the slip limit
            # the next slip starts at the opposite limit after a travel of exactly 2 Fs / kt
            j = kinds.index("slip", i + 1) if "slip" in kinds[i + 1:] else None
            if j is not None:
                assert abs(T[j] + T[i]) <= 1e-12 * fs
                # rounding of the event states (measured 1.1e-13 of the travel); 1e-10 is ~1000x
                assert abs((x[i] - x[j]) - 2 * T[i] / kt) <= 1e-10 * (2 * fs / kt)
        else:
            assert abs(abs(T[i]) - fs) <= 1e-12 * fs


@pytest.mark.parametrize("kt,err_max", [(10.0, 0.2), (100.0, 0.06), (1e3, 0.02), (1e4, 0.006)])
def test_jenkins_approaches_coulomb_slowly(kt, err_max):
    """As kt grows the Jenkins oscillator tends to the rigid Coulomb one -- slowly.

    Measured relative amplitude error at r = 1.5, F/P0 = 0.3: 0.134 (kt/k = 10), 0.0446 (100),
    0.0143 (1e3), 0.0046 (1e4): it falls like (kt/k)^(-1/2), not 1/kt.
    """
    r, f = 1.5, 0.3
    s = fj.LinearStructure(1.0, 1.0)
    sysm = fj.FrictionSystem(s, [fj.Jenkins(kt, f, dof=0)], omega=r, excitation=[fj.HarmonicForce(0, 1.0)])
    ss = fj.periodic_response(sysm, 0.7, 0.0)
    assert ss.converged
    err = ss.amplitude[0] / den_hartog(r, f).amplitude - 1
    assert 0 < err <= err_max
    assert err >= 0.3 * err_max  # and not faster than documented


def test_jenkins_convergence_rate_is_half_order():
    r, f = 1.5, 0.3
    errs = []
    for kt in (100.0, 1e4):
        sysm = fj.FrictionSystem(fj.LinearStructure(1.0, 1.0), [fj.Jenkins(kt, f, dof=0)], omega=r,
                                 excitation=[fj.HarmonicForce(0, 1.0)])
        errs.append(fj.periodic_response(sysm, 0.7, 0.0).amplitude[0] / den_hartog(r, f).amplitude - 1)
    rate = math.log10(errs[0] / errs[1]) / 2
    assert 0.4 <= rate <= 0.6


def _linear_reference(m, c, k, fc, omega, x0, v0, t):
    """Independent solve_ivp solution of M x'' + C x' + K x = fc cos(omega t)."""
    n = m.shape[0]
    minv = np.linalg.inv(m)

    def rhs(tt, y):
        x, v = y[:n], y[n:]
        return np.concatenate([v, minv @ (fc * np.cos(omega * tt) - c @ v - k @ x)])

    sol = scipy.integrate.solve_ivp(rhs, (0, t[-1]), np.concatenate([x0, v0]), method="DOP853",
                                    rtol=1e-12, atol=1e-14, t_eval=t)
    return sol.y[:n]


def test_never_slipping_elements_cost_nothing_beyond_linear():
    """Jenkins and Coulomb elements that never reach their limit: exactly the linear solution,
    one configuration decomposed, no events."""
    m = np.diag([1.0, 2.0])
    k = np.array([[3.0, -1.0], [-1.0, 2.0]])
    c = 0.01 * k
    kt = 5.0
    d = np.array([1.0, -1.0])
    s = fj.LinearStructure(m, k, c)
    sysm = fj.FrictionSystem(s, [fj.Jenkins(kt, 1e6, direction=d), fj.Iwan([(1.0, 1e6), (2.0, 2e6)], dof=1)],
                             omega=1.3, excitation=[fj.HarmonicForce(0, 1.0)])
    t = np.linspace(0, 30, 301)
    marcher = fj.Marcher(sysm)
    tr = fj.simulate(sysm, 30.0, [0.1, 0.0], [0.0, 0.2], w0=[0.0, 0.0, 0.0], t_eval=t, marcher=marcher)
    kk = k + kt * np.outer(d, d) + np.diag([0.0, 3.0])
    ref = _linear_reference(m, c, kk, np.array([1.0, 0.0]), 1.3, np.array([0.1, 0.0]), np.array([0.0, 0.2]), t)
    assert np.max(np.abs(tr.x - ref)) <= 1e-9 * np.max(np.abs(ref))
    assert len(tr.events) == 0
    assert marcher.n_configurations == 1


def test_resonant_undamped_linear_structure_is_exact():
    """Excitation exactly at a natural frequency: the secular term is exact (phi1 form)."""
    s = fj.LinearStructure(1.0, 4.0)
    sysm = fj.FrictionSystem(s, [], omega=2.0, excitation=[fj.HarmonicForce(0, 1.0)])
    t = np.linspace(0, 50, 101)
    tr = fj.simulate(sysm, 50.0, 0.0, 0.0, t_eval=t)
    exact = t * np.sin(2.0 * t) / (2 * 2.0)  # x = F t sin(wt) / (2 m w)
    assert np.max(np.abs(tr.x[0] - exact)) <= 1e-11 * np.max(np.abs(exact))


def test_segalman_totals():
    """Discrete Segalman Iwan reproduces K_T and F_S exactly for every slider count."""
    for n in (1, 5, 40):
        iw = fj.Iwan.segalman(slip_force=2.0, stiffness=1e5, chi=-0.5, beta=0.3, n_sliders=n, dof=0)
        assert abs(iw.stiffness / 1e5 - 1) <= 1e-13
        assert abs(iw.slip_force / 2.0 - 1) <= 1e-13
        assert len(iw.sliders()) == n + 1


def test_iwan_backbone_macroslip():
    """Under a slow monotonic push far beyond macroslip, the Iwan force saturates at F_S."""
    iw = fj.Iwan.segalman(slip_force=0.5, stiffness=10.0, chi=-0.3, beta=0.5, n_sliders=8, dof=0)
    s = fj.LinearStructure(1.0, 0.0, 5.0)  # overdamped mass, pushed by a held force
    sysm = fj.FrictionSystem(s, [iw], excitation=[fj.ExternalForce(0, [0.0, 1e3], [0.6])])
    tr = fj.simulate(sysm, 50.0, t_eval=[50.0])
    assert abs(tr.friction_force[0, -1] - 0.5) <= 1e-12


@pytest.mark.parametrize("bad", [dict(chi=-1.0), dict(chi=0.5), dict(beta=-0.1), dict(n_sliders=0),
                                 dict(slip_force=0.0), dict(stiffness=-1.0)])
def test_segalman_invalid(bad):
    args = dict(slip_force=1.0, stiffness=1.0, chi=-0.5, beta=0.1, n_sliders=5, dof=0)
    args.update(bad)
    with pytest.raises(fj.ParameterError, match=list(bad)[0]):
        fj.Iwan.segalman(**args)


@pytest.mark.parametrize("make,match", [
    (lambda: fj.Jenkins(0.0, 1.0, dof=0), "tangential_stiffness"),
    (lambda: fj.Jenkins(1.0, -1.0, dof=0), "slip_force"),
    (lambda: fj.CoulombSlider(math.nan, dof=0), "slip_force"),
    (lambda: fj.Iwan([(1.0, -2.0)], dof=0), "slip_force"),
    (lambda: fj.Iwan([], dof=0), "sliders"),
    (lambda: fj.LinearStructure([[1.0, 0.0], [0.0, -1.0]], np.eye(2)), "mass"),
    (lambda: fj.LinearStructure(np.eye(2), [[1.0, 2.0], [0.0, 1.0]]), "stiffness"),
    (lambda: fj.LinearStructure(np.eye(2), [[1.0, 2.0], [2.0, 1.0]]), "stiffness"),
    (lambda: fj.LinearStructure(np.eye(2), np.eye(3)), "stiffness"),
    (lambda: fj.LinearStructure(np.eye(2), np.eye(2), -np.eye(2)), "damping"),
    (lambda: fj.FrictionSystem(fj.LinearStructure(1.0, 1.0), [fj.Jenkins(1.0, 1.0, dof=3)]), "dof"),
    (lambda: fj.FrictionSystem(fj.LinearStructure(1.0, 1.0), [fj.Jenkins(1.0, 1.0, direction=[0.0])]),
     "direction"),
    (lambda: fj.FrictionSystem(fj.LinearStructure(1.0, 1.0), [], excitation=[fj.HarmonicForce(0, 1.0)]),
     "omega"),
    (lambda: fj.HarmonicForce(0, math.inf), "amplitude"),
    (lambda: fj.ExternalForce(0, [0.0, 1.0], [1.0, 2.0]), "values"),
])
def test_invalid_model_input(make, match):
    with pytest.raises(fj.ParameterError, match=match):
        make()


def test_initial_slider_state_checked():
    sysm = _jenkins_system(kt=10.0, fs=0.3)
    with pytest.raises(fj.ParameterError, match="w0"):
        fj.simulate(sysm, 1.0, 0.0, 0.0, w0=[0.5])
