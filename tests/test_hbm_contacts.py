"""Harmonic balance of dovetail flanks with normal-load variation and lift-off
(:func:`frictionjoint.solvers.frequency_domain.hysteresis.flank_loop` in :func:`frictionjoint.harmonic_balance`).

References: :class:`~frictionjoint.elements.dovetail.DrivenDovetail` (an independent
implementation of the flanks' exact return map along a path, with lift-off) driven along a sampled
periodic path, its forces' Fourier coefficients by the trapezoid rule; central finite differences
for the Jacobians; the Jenkins loop (the flank whose normal does not move is a Jenkins slider at
mu N); the exact time-domain steady state (shooting on the event-driven marcher, with lift-offs and
closures) for the truncation error."""
import math

import numpy as np
import pytest

import frictionjoint as fj
from benchmarks.hbm_truncation import root_block as _system  # the root block of the benchmark
from frictionjoint.solvers.frequency_domain import hysteresis
from frictionjoint.solvers.frequency_domain.hbm import Condensed

MU, KN, KT = 0.3, 1e6, 8e5  # the root block's flanks


def _path():
    """Root harmonics (H = 7) of a path on which both flanks slip and lift off (24 % and 31 % of
    the period open)."""
    harm = np.zeros((8, 2), complex)
    harm[0] = [1.5e-4, 4.0e-4]
    harm[1] = [1.2e-3, 1.3e-3j]
    harm[2] = [1e-4j, -1.2e-4]
    harm[5] = [2e-5, 1e-5j]
    return harm


def _flank(cond, sysm, z, i, jacobian=True, omega=None):
    nc = cond.nc
    q, qn = cond.slider_q[i], cond.contact_q[sysm.slider_contact[i]]
    ic = sysm.slider_contact[i]
    return hysteresis.flank_loop(z[q * nc:(q + 1) * nc], z[qn * nc:(qn + 1) * nc], sysm.slider_stiffness[i], cond.mu[i],
                                 sysm.contact_stiffness[ic], sysm.contact_damping[ic], sysm.contact_preload[ic],
                                 sysm.omega if omega is None else omega, 0.0, jacobian)


@pytest.mark.slow
def test_flank_loop_against_the_driven_dovetail():
    """Both flanks slip, lift off and close: the loop's friction-force and contact-correction
    coefficients equal those of DrivenDovetail driven along the same path (two periods, 2^15
    samples each; the trapezoid rule on forces with kinks: ~1e-8) to 1e-7."""
    sysm, root = _system(normal_damping=0.0)
    harm = _path()
    cond = Condensed(sysm, 7)
    z = cond.joint_vector(harm)
    n = 2 ** 15
    theta = np.arange(2 * n) * 2 * math.pi / n
    x = (harm.T @ np.exp(1j * np.outer(np.arange(8), theta))).real
    drv = root.driven(normal_load_variation=True)
    t_ref, n_ref = np.empty((2, 2 * n)), np.empty((2, 2 * n))
    for j in range(2 * n):
        drv.update(x[:, j])
        t_ref[:, j], n_ref[:, j] = drv.friction_force, drv.normal_force
    basis = np.vstack([np.ones(n)] + [f(h * theta[:n]) for h in range(1, 8) for f in (np.cos, np.sin)])
    nrm = np.full(15, 2.0 / n)
    nrm[0] = 1.0 / n
    for i in range(2):
        t, _, _, rn, _, _, m_open, _, slips = _flank(cond, sysm, z, i)
        ref_t = nrm * (basis @ t_ref[i, n:])
        p = sysm.contact_normal[sysm.slider_contact[i]] @ x[:, n:]
        # the correction takes the closed contact's linear force out where it is open
        ref_n = nrm * (basis @ (sysm.contact_preload[sysm.slider_contact[i]] - KN * p - n_ref[i, n:]))
        assert slips and 0.2 < m_open[0, 0] < 0.35
        assert np.max(np.abs(t - ref_t)) <= 1e-7 * np.max(np.abs(ref_t))
        assert np.max(np.abs(rn - ref_n)) <= 1e-7 * np.max(np.abs(ref_n))


@pytest.mark.parametrize("scale", [0.3, 1.0, 1.6])
def test_flank_jacobians_against_finite_differences(scale):
    """dT/dcs, dT/dcp, dRn/dcp (with the dashpot's jumps at lift-off and closure) and dRn/domega
    against central differences: <= 1e-6 (stuck, slipping and open pieces)."""
    sysm, _ = _system()
    cond = Condensed(sysm, 7)
    z = cond.joint_vector(_path() * scale)
    nc = cond.nc
    for i in range(2):
        q, qn = cond.slider_q[i], cond.contact_q[sysm.slider_contact[i]]
        _, jts, jtp, _, jnn, rn_w, _, _, _ = _flank(cond, sysm, z, i)
        step = 1e-10
        for blk, (jac, out) in ((q, (jts, 0)), (qn, (jtp, 0)), (qn, (jnn, 3))):
            fd = np.zeros_like(jac)
            for j in range(nc):
                zp, zm = z.copy(), z.copy()
                zp[blk * nc + j] += step
                zm[blk * nc + j] -= step
                fd[:, j] = (_flank(cond, sysm, zp, i, False)[out] - _flank(cond, sysm, zm, i, False)[out]) / (2 * step)
            assert np.max(np.abs(fd - jac)) <= 1e-6 * np.max(np.abs(fd)), (i, blk, out)
        w = sysm.omega
        fd_w = (_flank(cond, sysm, z, i, False, w * (1 + 1e-7))[3]
                - _flank(cond, sysm, z, i, False, w * (1 - 1e-7))[3]) / (2e-7 * w)
        assert np.max(np.abs(fd_w - rn_w)) <= 1e-6 * max(np.max(np.abs(fd_w)), 1e-300)


def test_flank_whose_normal_does_not_move_is_a_jenkins_slider():
    """p constant below the gap: N = N0 - kn p0 stays, and the loop is the Jenkins loop of slip force
    mu N, to rounding (never slipping as well as slipping)."""
    rng = np.random.default_rng(3)
    hh = 5
    for amp in (1e-5, 1e-3):
        cs = amp * rng.normal(size=2 * hh + 1) / np.r_[1.0, np.repeat(np.arange(1, hh + 1), 2)]
        cp = np.zeros(2 * hh + 1)
        cp[0] = 2e-4
        t, jts, _, rn, _, _, _, _, _ = hysteresis.flank_loop(cs, cp, KT, MU, KN, 40.0, 1000.0, 3000.0)
        tj, jj, _, _ = hysteresis.jenkins_loop(cs, KT, MU * (1000.0 - KN * 2e-4))
        assert np.max(np.abs(t - tj)) <= 1e-12 * np.max(np.abs(tj))
        assert np.max(np.abs(jts - jj)) <= 1e-12 * np.max(np.abs(jj))
        assert not np.any(rn)


@pytest.mark.slow
@pytest.mark.parametrize("damping, stable", [(0.0, False), (40.0, True)])
def test_balance_with_lift_off_against_the_exact_orbit(damping, stable):
    """The root block at 3000 rad/s: in the exact orbit from the balanced one each flank lifts off
    once per period (and slips as it closes); the truncation error falls with H (H = 15: <= 1e-5,
    measured 7e-7 and 3e-7), the balanced friction dissipation equals the exact orbit's to 1e-4,
    and the exact Floquet multipliers judge the orbit (without the contacts' dashpots it is weakly
    unstable, |mu| = 1.005; with them stable, 0.80)."""
    sysm, _ = _system(normal_damping=damping)
    errs = []
    for hh in (3, 7, 15):
        hb = fj.harmonic_balance(sysm, n_harmonics=hh, check=True)
        assert hb.converged and hb.exact.converged
        assert hb.exact.events.count("lift-off") == 2
        errs.append(hb.truncation_error)
    assert errs[2] <= 1e-5 and errs[2] < errs[1] < errs[0]
    assert abs(hb.dissipated_per_cycle / hb.exact.dissipated_per_cycle - 1) <= 1e-4
    assert hb.stable is stable


@pytest.mark.slow
def test_continuation_through_lift_off_matches_point_solutions():
    """A branch down from 3200 rad/s into the frequencies where the flanks lift off over a large
    part of the period (the contacts' dashpots enter dr/domega): the single-frequency balance from
    its default start fails at 2000 and 2250 rad/s, the branch reaches them, and its points equal
    single-frequency balances started from them to 1e-8."""
    sysm, _ = _system()
    assert not fj.harmonic_balance(sysm, 2000.0, n_harmonics=7).converged
    sw = fj.hbm_sweep(sysm, (3200.0, 2000.0), n_harmonics=7, n_points=20)
    assert sw.success and sw.omega.min() <= 2000.0
    for k in range(1, len(sw.omega), max(1, len(sw.omega) // 5)):
        hb = fj.harmonic_balance(sysm, float(sw.omega[k]), n_harmonics=7, guess=sw.harmonics[k])
        assert hb.converged
        assert np.max(np.abs(hb.harmonics - sw.harmonics[k])) <= 1e-8 * np.max(np.abs(hb.harmonics))


def test_branch_from_a_start_without_balance_says_so():
    """A branch whose first frequency has no balance from the default start stops there with a
    message naming it (instead of stepping from an unconverged point)."""
    sysm, _ = _system()
    sw = fj.hbm_sweep(sysm, (2000.0, 3200.0), n_harmonics=7, n_points=20)
    assert not sw.success and len(sw.omega) == 1 and not sw.converged[0]
    assert "no balance at the start omega = 2000 rad/s" in sw.message


@pytest.mark.slow
def test_fold_pair_with_three_coexisting_orbits():
    """The root block shaken radially only (100 N; no dashpots): the flanks' slip softens the
    resonance near 2770 rad/s until the branch turns twice. The continuation flags both folds;
    between them three balances coexist, each the first harmonic of an exact orbit (H = 7:
    measured 1.5e-4, 1.4e-4 and, stuck, 7e-15), and the exact Floquet multipliers find the upper
    and lower orbits stable and the middle one unstable (max |mu| 0.92, 1.05, 0.97), as the
    branch's stability column does."""
    sysm, _ = _system(fx=0.0, fy=100.0, normal_damping=0.0)
    sw = fj.hbm_sweep(sysm, (3200.0, 2400.0), n_harmonics=7, n_points=40, check=True)
    assert sw.success
    folds = np.flatnonzero(sw.fold)
    assert len(folds) == 2
    w_mid = float(sw.omega[folds].mean())
    cross = np.flatnonzero(np.diff(np.sign(sw.omega - w_mid)))
    assert len(cross) == 3
    amps, verdicts = [], []
    for k in cross:
        a = (w_mid - sw.omega[k]) / (sw.omega[k + 1] - sw.omega[k])
        hb = fj.harmonic_balance(sysm, w_mid, n_harmonics=7, guess=(1 - a) * sw.harmonics[k] + a * sw.harmonics[k + 1],
                                 check=True)
        assert hb.converged and hb.truncation_error <= 1e-3
        amps.append(hb.harmonic_amplitude[1])
        verdicts.append(hb.stable)
        assert sw.stable[k] is hb.stable and sw.stable[k + 1] is hb.stable
    assert amps[0] > amps[1] > amps[2] and amps[2] > 0.5 * amps[0]  # three distinct orbits
    assert verdicts == [True, False, True]


@pytest.mark.parametrize("mu", [1e-14, 1e-20, 1e-300])
def test_vanishing_friction_on_varying_flanks_is_the_free_slip_response(mu):
    """Issue 39: flanks with normal-load variation and a friction coefficient that vanishes (the
    contact closed all period): the response tends to the free-slip linear limit's (the flanks'
    normal springs kept, their tangential ones slipping freely), within 1e-9 (the friction force
    mu N over the springs' k x is below 1e-10 here; measured 1.2e-14 at 1e-20). At mu = 1e-20 the
    loop held its tangential spring over the whole period: 97 % off (the stuck response)."""
    from frictionjoint.linear_limits import limit_structures

    st = fj.LinearStructure(np.diag([0.2, 0.2]), np.zeros((2, 2)), np.diag([2.0, 2.0]), dof_names=["X", "Y"])
    root = fj.DovetailRoot(1000.0, flank_angle=math.radians(40.0), friction_coefficient=mu, normal_stiffness=KN,
                           tangential_stiffness=KT, tangential_dof="X", radial_dof="Y", normal_load_variation=True,
                           normal_damping=0.0)
    sysm = fj.FrictionSystem(st, [root], omega=2000.0,
                             excitation=[fj.HarmonicForce("X", 20.0), fj.HarmonicForce("Y", 10.0, phase=0.7)])
    hb = fj.harmonic_balance(sysm, 2000.0, 5)
    free = limit_structures(sysm)["slipping"].harmonic_response(2000.0, sysm.force_cos - 1j * sysm.force_sin)
    assert hb.converged and not hb.stuck
    np.testing.assert_allclose(hb.harmonics[1], np.ravel(free), rtol=1e-9)


def test_sliding_flank_jacobians_against_finite_differences():
    """The flank's loop in continuous sliding on a closed contact (mu N sgn(s'), used where the band is
    below the rounding of s): its Jacobians against central differences (step 1e-7) to 1e-6 (measured
    1.2e-8 and 1.4e-10), and with p = 0 Coulomb's loop at mu N0."""
    rng = np.random.default_rng(1)
    cs = rng.normal(size=7) / np.r_[1, 1, 1, 2, 2, 3, 3]
    cp = rng.normal(size=7) * 1e-3
    loop = hysteresis._sliding_flank
    t, jts, jtp = loop(cs, cp, MU, 1e3, 100.0, True)[:3]
    e, eye = 1e-7, np.eye(7)
    fd_s = np.array([(loop(cs + e * eye[j], cp, MU, 1e3, 100.0, False)[0]
                      - loop(cs - e * eye[j], cp, MU, 1e3, 100.0, False)[0]) / (2 * e) for j in range(7)]).T
    fd_p = np.array([(loop(cs, cp + e * eye[j], MU, 1e3, 100.0, False)[0]
                      - loop(cs, cp - e * eye[j], MU, 1e3, 100.0, False)[0]) / (2 * e) for j in range(7)]).T
    assert np.max(np.abs(fd_s - jts)) <= 1e-6 * np.max(np.abs(jts))
    assert np.max(np.abs(fd_p - jtp)) <= 1e-6 * np.max(np.abs(jtp))
    np.testing.assert_allclose(loop(cs, 0 * cp, MU, 1e3, 100.0, False)[0], hysteresis.coulomb_loop(cs, MU * 100.0)[0],
                               rtol=0, atol=1e-12 * MU * 100.0)
