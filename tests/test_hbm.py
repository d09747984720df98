"""Harmonic balance (frictionjoint.solvers.frequency_domain.hbm) with exact hysteresis (frictionjoint.solvers.frequency_domain.hysteresis).

References: the one-harmonic describing functions of analytic.py (Coulomb: 4F/(pi w X); Jenkins:
Griffin 1980), finite differences of the AFT map, and the exact time-domain steady state of the
same system (the event-driven marcher's shooting), against which the truncation error falls with
H."""
import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import frictionjoint as fj
from frictionjoint.analytic import harmonic_balance_amplitude, jenkins_describing_function
from frictionjoint.errors import ParameterError
from frictionjoint.solvers.frequency_domain import hysteresis
from frictionjoint.solvers.frequency_domain.hbm import Condensed

# the Jenkins SDOF of the issue: m = k = 1, zeta = 1 %, kt = 5, Fs = 0.1
SDOF = fj.LinearStructure([[1.0]], [[1.0]], [[0.02]])


def jenkins_sdof(omega, p):
    return fj.FrictionSystem(SDOF, [fj.Jenkins(5.0, 0.1, dof=0)], omega=omega, excitation=[fj.HarmonicForce(0, p)])


@pytest.mark.parametrize("r, f", [(0.5, 0.3), (1.6, 0.3), (2.5, 0.6), (0.3, 0.1)])
def test_one_harmonic_coulomb_equals_the_describing_function(r, f):
    """Coulomb oscillator (m = k = 1, P0 = 1, no damping), H = 1: |X| equals the describing
    function's closed form sqrt(1 - (4f/pi)^2)/|1 - r^2| to 1e-10 (the force's first harmonic is
    integrated exactly between the velocity reversals)."""
    st = fj.LinearStructure([[1.0]], [[1.0]])
    sysm = fj.FrictionSystem(st, [fj.CoulombSlider(f, dof=0)], omega=r, excitation=[fj.HarmonicForce(0, 1.0)])
    hb = fj.harmonic_balance(sysm, n_harmonics=1, tol=1e-14)
    assert hb.converged
    expected = harmonic_balance_amplitude(r, f)
    assert abs(hb.harmonic_amplitude[0] - expected) <= 1e-10 * expected


@pytest.mark.parametrize("p", [0.05, 0.2, 1.0])
@pytest.mark.parametrize("w", [0.7, 1.1, 1.5, 2.4])
def test_one_harmonic_jenkins_equals_the_describing_function(p, w):
    """Jenkins SDOF, H = 1: the first harmonic X satisfies (k - m w^2 + i w c + K(|X|)) X = P with
    Griffin's describing function K, to 1e-10 of P (stuck or slipping)."""
    hb = fj.harmonic_balance(jenkins_sdof(w, p), n_harmonics=1, tol=1e-14)
    assert hb.converged
    x = hb.harmonics[1, 0]
    k = jenkins_describing_function(5.0, 0.1, abs(x))
    assert abs((1.0 - w * w + 0.02j * w) * x + k * x - p) <= 1e-10 * p


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_analytic_jacobian_against_finite_differences(seed):
    """The AFT map's analytic Jacobian (Jenkins loops from the reversal at the global maximum,
    Coulomb reversals) against central differences on random multi-harmonic states: <= 1e-6."""
    rng = np.random.default_rng(seed)
    hh = 5
    c = rng.normal(size=2 * hh + 1) / np.r_[1.0, np.repeat(np.arange(1, hh + 1), 2)]
    for fun in (lambda cc, jac=True: hysteresis.jenkins_loop(cc, 5.0, 0.4, 0.0, jac)[:2],
                lambda cc, jac=True: hysteresis.coulomb_loop(cc, 0.4, jac)):
        _, jac = fun(c)
        fd = np.empty_like(jac)
        for j in range(c.size):
            e = 1e-6 * max(1.0, abs(c[j]))
            cp, cm = c.copy(), c.copy()
            cp[j] += e
            cm[j] -= e
            fd[:, j] = (fun(cp, False)[0] - fun(cm, False)[0]) / (2 * e)
        assert np.max(np.abs(jac - fd)) <= 1e-6 * np.max(np.abs(jac))
    # and the condensed system's Jacobian (an Iwan joint and a Jenkins on a 2-DOF chain)
    st = fj.LinearStructure(np.diag([1.0, 0.5]), [[3.0, -1.0], [-1.0, 1.0]], 0.02 * np.eye(2))
    sysm = fj.FrictionSystem(st, [fj.Jenkins(2.0, 0.3, dof=1), fj.Iwan.segalman(0.5, 4.0, -0.5, 0.1, 6, dof=0)],
                             omega=1.3, excitation=[fj.HarmonicForce(0, 0.8)])
    cond = Condensed(sysm, 4)
    z = rng.normal(size=cond.n_q * cond.nc) * 0.3
    jr = cond.forces(z).jacobian
    fd = np.empty_like(jr)
    for j in range(z.size):
        zp, zm = z.copy(), z.copy()
        zp[j] += 1e-7
        zm[j] -= 1e-7
        fd[:, j] = (cond.forces(zp, False).r - cond.forces(zm, False).r) / 2e-7
    assert np.max(np.abs(jr - fd)) <= 1e-6 * np.max(np.abs(jr))


def test_stuck_orbit_is_exact_at_any_h():
    """A motion that never slips is linear: every H gives the exact steady state (rounding)."""
    for hh in (1, 3, 7):
        hb = fj.harmonic_balance(jenkins_sdof(0.8, 0.05), n_harmonics=hh, check=True)
        assert hb.converged and hb.exact.stuck and hb.stuck
        assert not fj.harmonic_balance(jenkins_sdof(1.2, 0.2), n_harmonics=hh).stuck
        assert hb.truncation_error <= 1e-13 and hb.amplitude_error <= 1e-13
        # exactly 0.0: no slider slips, so no friction work is summed (a stuck slider is a spring;
        # its oint k (u - w) du as a sum of products had left 7e-23 of rounding)
        assert np.max(np.abs(hb.harmonics[2:]), initial=0.0) <= 1e-15 and hb.dissipated_per_cycle == 0.0


@pytest.mark.parametrize("p, w", [(0.2, 1.2), (1.0, 0.8), (0.05, 2.2)])
def test_truncation_error_falls_with_h(p, w):
    """Against the exact time-domain steady state (check=True): the first harmonic's error falls
    with H (measured 1e-3..1e-2 at H = 3, 5e-5..1e-4 at H = 7, 2e-6..5e-5 at H = 15), and the
    dissipation per cycle of the balanced loops approaches the exact one."""
    errs = []
    for hh in (3, 7, 15):
        hb = fj.harmonic_balance(jenkins_sdof(w, p), n_harmonics=hh, check=True)
        assert hb.converged and hb.exact.converged and not hb.exact.stuck
        errs.append(hb.truncation_error)
        d_err = abs(hb.dissipated_per_cycle - hb.exact.dissipated_per_cycle) / hb.exact.dissipated_per_cycle
    assert errs[0] > errs[1] > errs[2] and errs[2] <= 1e-4
    assert d_err <= 1e-3


def test_condensed_unknowns_and_chain_against_the_time_domain():
    """A 2-DOF chain with a Jenkins and an Iwan joint: the unknowns are the joint coordinates'
    harmonics (2 coordinates x (2H + 1)), and at H = 15 the balance is within 1e-3 of the exact
    steady state."""
    st = fj.LinearStructure(np.diag([1.0, 0.5]), [[3.0, -1.0], [-1.0, 1.0]], 0.02 * np.eye(2))
    sysm = fj.FrictionSystem(st, [fj.Jenkins(2.0, 0.3, dof=1), fj.Iwan.segalman(0.5, 4.0, -0.5, 0.1, 6, dof=0)],
                             omega=1.3, excitation=[fj.HarmonicForce(0, 0.8)])
    assert Condensed(sysm, 15).Y.shape == (2 * 31, 2 * 31)
    hb = fj.harmonic_balance(sysm, n_harmonics=15, check=True)
    assert hb.converged and hb.exact.converged
    assert hb.truncation_error <= 1e-3


def test_bad_input_names_the_parameter():
    sysm = jenkins_sdof(1.0, 0.2)
    with pytest.raises(ParameterError, match="n_harmonics"):
        fj.harmonic_balance(sysm, n_harmonics=0)
    with pytest.raises(ParameterError, match="omega"):
        fj.harmonic_balance(sysm, omega=-1.0)
    with pytest.raises(ParameterError, match="tol"):
        fj.harmonic_balance(sysm, tol=2.0)
    ext = fj.FrictionSystem(SDOF, [fj.Jenkins(5.0, 0.1, dof=0)], omega=1.0,
                            excitation=[fj.HarmonicForce(0, 0.2), fj.ExternalForce(0, [0.0, 1.0], [1.0])])
    with pytest.raises(ParameterError, match="ExternalForce"):
        fj.harmonic_balance(ext)


def test_continuation_follows_the_branch_and_matches_point_solutions():
    """hbm_sweep (pseudo-arclength in omega) over the Jenkins SDOF's band: it reaches the end of
    the range, its points are harmonic-balance solutions (a point solve at the same omega from
    scratch gives the same harmonics to 1e-8), and the Jenkins resonance (no fold here) is
    single-valued."""
    from frictionjoint.solvers.frequency_domain.continuation import hbm_sweep

    sw = hbm_sweep(jenkins_sdof(1.0, 0.2), (0.5, 3.0), n_harmonics=3, n_points=60)
    assert sw.success and sw.message.startswith("reached") and sw.n_folds == 0
    assert 30 <= sw.omega.size <= 400 and np.all(np.diff(sw.omega) > 0)
    for k in (5, sw.omega.size // 2, sw.omega.size - 3):
        hb = fj.harmonic_balance(jenkins_sdof(sw.omega[k], 0.2), n_harmonics=3, tol=1e-12)
        assert np.max(np.abs(hb.harmonics - sw.harmonics[k])) <= 1e-8 * np.max(np.abs(hb.harmonics))
    with pytest.raises(ParameterError, match="omega_range"):
        hbm_sweep(jenkins_sdof(1.0, 0.2), (1.0, 1.0))
    with pytest.raises(ParameterError, match="omega_range"):
        hbm_sweep(jenkins_sdof(1.0, 0.2), [1.0])
    with pytest.raises(ParameterError, match="check"):
        hbm_sweep(jenkins_sdof(1.0, 0.2), (0.5, 3.0), check=[-1.0])
    assert sw.stable is None and sw.truncation_error is None


def test_stability_along_a_branch_from_the_exact_orbits():
    """check=True: each branch point's verdict from the Floquet multipliers of the exact orbit
    started from it, and its truncation error; the damped Jenkins SDOF's single-valued resonance
    is stable everywhere, and a single balance's check gives the same verdict. check=[frequencies]
    checks only the branch points nearest them, with the same errors as a single balance's check."""
    from frictionjoint.solvers.frequency_domain.continuation import hbm_sweep

    sw = hbm_sweep(jenkins_sdof(1.0, 0.2), (0.8, 1.6), n_harmonics=5, n_points=15, check=True)
    assert sw.stable is not None and all(v is True for v in sw.stable)
    assert np.all(sw.truncation_error <= 5e-2) and np.any(sw.truncation_error > 1e-6)
    hb = fj.harmonic_balance(jenkins_sdof(1.2, 0.2), n_harmonics=5, check=True)
    assert hb.stable is True and np.max(np.abs(hb.exact.floquet_multipliers)) < 1.0
    some = hbm_sweep(jenkins_sdof(1.0, 0.2), np.linspace(0.8, 1.6, 15), n_harmonics=5, check=[1.0, 1.3])
    np.testing.assert_array_equal(some.omega, sw.omega)  # the frequencies' form: n_points = 15
    picked = [k for k in range(some.omega.size) if some.stable[k] is not None]
    assert len(picked) == 2 and np.isnan(np.delete(some.truncation_error, picked)).all()
    for k in picked:
        assert some.stable[k] is True and abs(some.truncation_error[k] - sw.truncation_error[k]) <= 1e-12
        one = fj.harmonic_balance(jenkins_sdof(float(some.omega[k]), 0.2), n_harmonics=5, guess=some.harmonics[k],
                                  check=True)
        assert abs(one.truncation_error - some.truncation_error[k]) <= 1e-6 * one.truncation_error


@pytest.mark.slow  # the exact peak: about 17 shootings of the blade's orbit, 11-23 s
@pytest.mark.parametrize("varying", [False, True])
def test_blade_peak_against_the_time_domain(varying):
    """The Craig-Bampton blade on its dovetail, 1 N at the tip, at the root load nearest the damper
    optimum of test_blade_peak_against_the_time_domain_at_three_loads (weekly), 259 N, where the
    root slips most and the truncation is largest: the peak tip amplitude of the HBM branch
    (pseudo-arclength, H = 11) agrees with the exact time-domain peak (BladeAssembly.peak: shooting
    on the event-driven marcher) to 0.5 % with frozen normal loads (measured 0.25 %) and with
    normal-load variation and lift-off (0.21 %), both peaks inside 2010-2055 rad/s (measured 2026
    and 2029 rad/s exact, 2031 HBM). The three loads with lift-off at H = 3 to 15:
    benchmarks/hbm_truncation.py, part 3."""
    from frictionjoint.structures import BladeAssembly, load_blade_model

    lo, hi = 2010.0, 2055.0
    asm = BladeAssembly.from_model(load_blade_model("ti64_compressor_blade")).with_root(
        centrifugal_force=259.0, normal_load_variation=varying)
    w_ex, a_ex = asm.peak(lo, hi, asm.tip, n_grid=7)
    sw = fj.hbm_sweep(asm.system(lo), (lo, hi), n_harmonics=11, n_points=18)
    assert sw.success
    tip = np.abs(sw.harmonics[:, 1] @ asm._row(asm.tip))
    assert lo < w_ex < hi and lo < sw.omega[tip.argmax()] < hi  # the peaks, not the window's edges
    assert abs(tip.max() - a_ex) <= 5e-3 * a_ex, (tip.max(), a_ex)


@pytest.mark.weekly
@pytest.mark.parametrize("varying", [False, True])
def test_blade_peak_against_the_time_domain_at_three_loads(varying):
    """The Craig-Bampton blade on its dovetail, 1 N at the tip: the peak tip amplitude of the HBM
    branch (pseudo-arclength, H = 11) agrees with the exact time-domain peak (BladeAssembly.peak:
    shooting on the event-driven marcher) to 0.5 % at three root loads above the damper optimum,
    with frozen normal loads (measured 0.25 %, 0.22 %, 0.10 %) and with normal-load variation and
    lift-off (0.21 %, 0.19 %, 0.08 %). At the optimum itself (46 N) the truncation converges
    slowly (H = 15: 2.6 %; README). Weekly (54 and 50 s under load): test_blade_peak_against_the_time_domain
    covers its code paths at 259 N."""
    from frictionjoint.structures import BladeAssembly, load_blade_model

    asm0 = BladeAssembly.from_model(load_blade_model("ti64_compressor_blade"))
    for fc in (259.0, 615.0, 1458.0):
        asm = asm0.with_root(centrifugal_force=fc, normal_load_variation=varying)
        w_ex, a_ex = asm.peak(1950.0, 2100.0, asm.tip, n_grid=15)
        sw = fj.hbm_sweep(asm.system(1950.0), (1950.0, 2100.0), n_harmonics=11, n_points=60)
        assert sw.success
        tip = np.abs(sw.harmonics[:, 1] @ asm._row(asm.tip))
        assert abs(tip.max() - a_ex) <= 5e-3 * a_ex, (fc, tip.max(), a_ex)


def test_branch_plot(tmp_path):
    from frictionjoint.solvers.frequency_domain.continuation import hbm_sweep

    sw = hbm_sweep(jenkins_sdof(1.0, 0.2), (0.8, 1.6), n_harmonics=3, n_points=10, check=True)
    sw.stable[3] = False  # an unstable stretch is drawn dashed
    fig = sw.plot(path=tmp_path / "branch.png", output=0)
    assert (tmp_path / "branch.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    styles = {line.get_linestyle() for line in fig.axes[0].lines}
    assert {"-", "--"} <= styles


def test_base_motion_and_a_preloaded_dovetail_against_the_time_domain():
    """Base excitation (spring and dashpot to a moving base) and a dovetail root with the frozen
    normal load (preloaded flanks, constant centrifugal load in the mean): H = 15 within 1e-3 of the
    exact steady state."""
    st = fj.LinearStructure([[1.0]], [[0.5]], [[0.01]])
    base = fj.FrictionSystem(st, [fj.Jenkins(5.0, 0.1, dof=0)], omega=1.4,
                             excitation=[fj.HarmonicBaseMotion(0, 0.5, 0.3, damping=0.01)])
    hb = fj.harmonic_balance(base, n_harmonics=15, check=True)
    assert hb.converged and hb.exact.converged and not hb.exact.stuck
    assert hb.truncation_error <= 1e-3
    root = fj.DovetailRoot(50.0, math.radians(30), 0.3, 200.0, 100.0, tangential_dof=0, radial_dof=1)
    st2 = fj.LinearStructure(np.diag([1.0, 1.0]), np.diag([20.0, 50.0]), 0.05 * np.eye(2))
    dove = fj.FrictionSystem(st2, [root], omega=14.0, excitation=[fj.HarmonicForce(0, 8.0)])
    hb = fj.harmonic_balance(dove, n_harmonics=15, check=True)
    assert hb.converged and hb.exact.converged and not hb.exact.stuck
    assert hb.truncation_error <= 1e-3
    # the flanks slip under the tangential shaking: the root settles 0.020 m outward on average (mean
    # radial offset), and the dissipation per cycle is the exact one to 1e-6
    assert hb.harmonics[0, 1].real > 0.01
    assert abs(hb.dissipated_per_cycle - hb.exact.dissipated_per_cycle) <= 1e-5 * hb.exact.dissipated_per_cycle


def test_hill_exponents_against_the_exact_floquet_multipliers():
    """Hill's method on the balanced orbit: on a stuck orbit (linear) its exponents are the stuck
    system's eigenvalues -c/2 +- i wd (modulo i omega) to rounding; on slipping orbits it agrees in
    sign with the exact orbit's multipliers (both stable), closely where the slider slips over most
    of the cycle (P = 1: -0.01146 and -0.0100 against the exact -0.01146 and -0.0100) and loosely
    where it sticks over part of it (P = 0.2, omega = 2.5: Hill -0.01, exact -0.36: the slips
    erase the slider's memory, which the periodic Jacobian does not see)."""
    from frictionjoint.solvers.frequency_domain.hbm import hill_exponents

    hb = fj.harmonic_balance(jenkins_sdof(0.8, 0.05), n_harmonics=7, check=True)
    lam = hill_exponents(jenkins_sdof(0.8, 0.05), hb)
    wd = math.sqrt(6.0 - 0.01 ** 2)
    assert np.max(np.abs(lam.real + 0.01)) <= 1e-10
    shifted = np.abs(lam.imag) % 0.8
    assert np.min(np.abs(shifted - wd % 0.8)) <= 1e-9
    for p, w in ((1.0, 1.0), (0.2, 1.2), (0.2, 2.5)):
        sysm = jenkins_sdof(w, p)
        hb = fj.harmonic_balance(sysm, n_harmonics=7, check=True)
        lam = hill_exponents(sysm, hb)
        assert hb.stable is True and np.max(lam.real) < 0
        if p == 1.0:
            exact = np.sort(np.log(np.abs(hb.exact.floquet_multipliers[np.abs(hb.exact.floquet_multipliers) > 0]))
                            * w / (2 * math.pi))
            assert np.max(np.abs(np.sort(lam.real) - exact[:2])) <= 1e-4


def test_continuation_stays_on_a_steep_lightly_damped_branch():
    """A friction damper between two masses (Jenkins along x1 - x2, zeta ~ 0.1 %): the branch
    through the steep first resonance used to jump to its other flank (a corrector that moved
    farther than its step) and then run back to omega -> 0; now it reaches the end, monotone in
    omega (no fold here), each point a balance."""
    from frictionjoint.solvers.frequency_domain.continuation import hbm_sweep

    k = np.array([[1.1, -0.1], [-0.1, 2.1]])
    st = fj.LinearStructure(np.eye(2), k, 0.002 * np.eye(2))

    def damper(w):
        return fj.FrictionSystem(st, [fj.Jenkins(2.0, 0.05, direction=[1.0, -1.0])], omega=w,
                                 excitation=[fj.HarmonicForce(0, 0.1)])
    sw = hbm_sweep(damper(0.5), (0.5, 3.0), n_harmonics=1, n_points=80)
    assert sw.success and sw.n_folds == 0 and np.all(np.diff(sw.omega) > 0)
    k_peak = int(np.argmax(sw.harmonic_amplitude[:, 0]))
    hb = fj.harmonic_balance(damper(sw.omega[k_peak]), n_harmonics=1, guess=sw.harmonics[k_peak], tol=1e-12)
    assert np.max(np.abs(hb.harmonics - sw.harmonics[k_peak])) <= 1e-8 * np.max(np.abs(hb.harmonics))


# Issue 39: deep slip and vanishing friction. A Jenkins loop whose slip reach F/k is small against
# the motion: the kernel finds its stuck pieces from u against u(theta_r) -+ 2 F/k, which fails once
# F/k is below the rounding of u (it held the spring over the whole period: the stuck answer), and
# loses eps |u| / (F/k) of F before that; the deep-slip form (Coulomb's loop and the stuck pieces'
# excess, hysteresis._deep_slip) is exact for the dissipation of a single harmonic. Reference: b_1 =
# -(4 F/pi) (1 - F/(k A)) for u = A cos(theta - phi) (the loop's area 4 F (A - F/k) = -pi A b_1),
# in floating point without cancellation. Tolerance 1e-8: the worst measured over x = F/(k A) from
# 1e-300 to 1e-2 is 1.7e-11 (the kernel near x = 1e-6), a margin of 500.
DEEP_SLIP_TOL = 1e-8


@settings(max_examples=25, deadline=None)
@given(log_x=st.floats(-300.0, -2.0), phase=st.floats(0.0, 2 * math.pi), mean=st.floats(-3.0, 3.0),
       hh=st.sampled_from([1, 3, 7]))
def test_jenkins_loop_in_deep_slip_dissipates_exactly(log_x, phase, mean, hh):
    a, kt = 1.7, 5.0
    x = 10.0 ** log_x
    fs = x * kt * a
    c = np.zeros(2 * hh + 1)
    c[0], c[1], c[2] = mean * a, a * math.cos(phase), a * math.sin(phase)
    t, jac, _, slips = hysteresis.jenkins_loop(c, kt, fs)
    b1 = -t[1] * math.sin(phase) + t[2] * math.cos(phase)  # the force's quadrature to u
    assert slips and np.all(np.isfinite(jac))
    assert abs(b1 / (-(4 * fs / math.pi) * (1 - x)) - 1) <= DEEP_SLIP_TOL


def test_coulomb_loop_with_a_reversal_within_rounding_of_the_period_start():
    """u'(0) < 0 by a third harmonic while u'(2 pi) > 0 by the rounding of sin(2 pi) A: the reversal
    lies between the two; found on a periodic grid, the force is F sgn(u') (b_1 = -4 F/pi, its quadrature
    to u = A cos theta; it was a constant +F: the one reversal seen made one piece of the period)."""
    c = np.array([7.95138670e-17, 1e14, 0.0, -5.65431943e-17, 1.71710400e-32, 1.43656159e-17, -5.30516477e-03])
    t, _ = hysteresis.coulomb_loop(c, 0.1)
    assert abs(t[2] / (-0.4 / math.pi) - 1) <= 1e-12 and abs(t[0]) <= 1e-12 * 0.1


@settings(max_examples=12, deadline=None)
@given(log_fs=st.floats(-300.0, -13.0))
def test_vanishing_friction_gives_the_free_slip_response(log_fs):
    """Slip force Fs under a 1 N load at the stuck resonance (omega = sqrt(6) = 2.449): the answer tends
    to the free-slip one, |P / (k - m w^2 + i c w)| = 0.2000864 (the joint's spring slips freely); the
    friction moves it by O(Fs/P) <= 1e-13, the bound 1e-9 is Newton's tolerance 1e-10 times 10. At Fs =
    1e-15 it gave 122.35 in '0 Newton iterations' (the loop held its spring: the stuck response)."""
    w = 2.449
    sysm = fj.FrictionSystem(SDOF, [fj.Jenkins(5.0, 10.0 ** log_fs, dof=0)], omega=w,
                             excitation=[fj.HarmonicForce(0, 1.0)])
    hb = fj.harmonic_balance(sysm, w, 7)
    free = 1.0 / abs(1.0 - w * w + 0.02j * w)
    assert hb.converged and not hb.stuck
    assert abs(hb.amplitude[0] / free - 1) <= 1e-9


@pytest.mark.parametrize("hh", [100_000, 10 ** 9])
def test_n_harmonics_is_bounded_by_the_memory_before_any_allocation(hh):
    """Issue 39: H = 10^5 asked for hundreds of GiB (the loops' tables alone, (H, 32 (H + 1))), 10^9
    failed inside NumPy ("array is too big"). Refused at once (well within a second), naming
    n_harmonics and the largest H that fits, for the balance, the branch and the nonlinear mode."""
    import time

    from frictionjoint.memory import computation_budget
    from frictionjoint.solvers.frequency_domain.hbm import harmonics_bytes

    sysm = jenkins_sdof(1.2, 0.2)
    t0 = time.perf_counter()
    for call, name in ((lambda: fj.harmonic_balance(sysm, 1.2, hh), "harmonic_balance"),
                       (lambda: fj.hbm_sweep(sysm, (1.0, 1.5), hh), "hbm_sweep"),
                       (lambda: fj.nonlinear_mode(sysm, 0, [1.0], hh), "nonlinear_mode")):
        with pytest.raises(ParameterError, match=rf"{name}: n_harmonics must be in \[1, (\d+)\]") as info:
            call()
        most = int(info.value.args[0].split("[1, ")[1].split("]")[0])
        all_dofs = name == "nonlinear_mode"
        assert harmonics_bytes(most, 1, 1, all_dofs) <= computation_budget() < harmonics_bytes(most + 1, 1, 1, all_dofs)
    assert time.perf_counter() - t0 < 5.0  # measured 0.05 s


def test_sweep_progress_bar_counts_the_range_and_the_points(capsys):
    """The branch's bar went to '1000 it' whatever the points (147 on the blade): it now shows the
    range covered in rad/s and the points found, the last count the result's."""
    sw = fj.hbm_sweep(jenkins_sdof(1.0, 0.2), "0.5:2:20", 3, progress=True)
    err = capsys.readouterr().err
    assert "1000" not in err and "1.5/1.5 rad/s of the range" in err
    assert f"{sw.omega.size} points" in err


# Issue 39 §2: with friction vanishing, the branch is the free-slip response: a linear peak, sharp where
# the structure is lightly damped, without a fold. The continuation's step control let it jump back and
# forth in omega: the peak's loop brings the flanks below and above it within a step of each other, and
# the corrector's hyperplane through a coarse predictor cut the other flank (the Ti-64 blade at
# friction_coefficient = 1e-20 went 1715 -> 1613 -> 1840 rad/s).
from hypothesis import example  # noqa: E402


@settings(max_examples=6, deadline=None)
@example(log_zeta=-2.0, n_points=10)  # went 1.067 -> 0.935 rad/s, round the peak three times
@example(log_zeta=-3.0, n_points=10)  # circled the peak until max_points = 200
@given(log_zeta=st.floats(-3.0, -1.0), n_points=st.integers(3, 20))
def test_vanishing_friction_branch_is_monotonic_and_the_free_slip_response(log_zeta, n_points):
    """Jenkins SDOF (m = k = 1, kt = 5) with a slip force of 1e-20 N under 1 N, damping ratio zeta
    log-uniform in [1e-3, 1e-1], over 0.5-1.5 rad/s: the branch reaches the end, increasing in omega
    (no fold), and every harmonic equals the free-slip closed form X = P / (k - m w^2 + i c w) (higher
    harmonics 0). Bound, derived: the corrector stops at a residual <= tol max|z|; in deep slip the
    joint's force does not move with z, so Newton's matrix is D_free(h w) / D_stuck(h w) per harmonic
    h (D = k - m w^2 + i c w, D_stuck with k + kt), and the error is <= 2 tol max_h |D_stuck / D_free| |X|
    (2: the max norm over a harmonic's cos and sin parts against its modulus; the friction force moves
    X by 1e-20)."""
    zeta, tol, kt = 10.0 ** log_zeta, 1e-12, 5.0
    c = 2.0 * zeta
    sysm = fj.FrictionSystem(fj.LinearStructure([[1.0]], [[1.0]], [[c]]), [fj.Jenkins(kt, 1e-20, dof=0)],
                             omega=0.5, excitation=[fj.HarmonicForce(0, 1.0)])
    hh = 3
    sw = fj.hbm_sweep(sysm, (0.5, 1.5), hh, n_points=n_points, tol=tol)
    assert sw.success and sw.n_folds == 0 and sw.omega[-1] >= 1.5
    assert np.all(np.diff(sw.omega) > 0), np.round(sw.omega, 4)
    w = sw.omega
    d_free = np.array([1.0 - (h * w) ** 2 + 1j * c * h * w for h in range(hh + 1)]).T  # (points, H + 1)
    amplification = np.max(np.abs((d_free + kt) / d_free), axis=1)
    x = 1.0 / d_free[:, 1]
    expected = np.zeros_like(sw.harmonics[:, :, 0])
    expected[:, 1] = x
    err = np.max(np.abs(sw.harmonics[:, :, 0] - expected), axis=1)
    assert np.all(err <= 2.0 * tol * amplification * np.abs(x)), np.max(err / (tol * amplification * np.abs(x)))


def test_blade_branch_at_vanishing_friction_is_monotonic_and_free_slip():
    """The symptom: `frictionjoint sweep ti64_compressor_blade --omega 1700:2040:3 --set
    friction_coefficient=1e-20 --method hbm` (its system and range: H = 7, n_points = 3). The branch
    is the free-slip response (the root's flanks slipping freely: linear_limits' 'slipping'
    structure), which has no fold: increasing in omega (it went 1715 -> 1613 -> 1840 rad/s), each
    point within 1e-7 of it at tol = 1e-12 (measured 3.3e-10: the corrector's residual times the
    condensed Jacobian's amplification near the peak; margin 300)."""
    from frictionjoint.linear_limits import limit_structures
    from frictionjoint.structures import load_blade_model
    from frictionjoint.structures.blade_run import BladeRun

    sysm = BladeRun(load_blade_model("ti64_compressor_blade"), {"friction_coefficient": 1e-20, "omega": 1700.0}).system
    sw = fj.hbm_sweep(sysm, "1700:2040:3", 7, tol=1e-12)
    assert sw.success and sw.n_folds == 0 and sw.omega[-1] >= 2040.0
    assert np.all(np.diff(sw.omega) > 0), np.round(sw.omega, 1)
    free = limit_structures(sysm)["slipping"]
    x = np.array([np.ravel(free.harmonic_response(w, sysm.force_cos - 1j * sysm.force_sin)) for w in sw.omega])
    assert np.max(np.abs(sw.harmonics[:, 1] - x).max(axis=1) / np.abs(x).max(axis=1)) <= 1e-7


def test_batched_jenkins_loops_are_the_single_loops():
    """hysteresis.jenkins_loops (one compiled call for every slider of a balance) returns each
    slider's jenkins_loop bit for bit, across its three paths: the exact loop, deep slip (F/k below
    1e-5 of the motion) and the Coulomb limit (F/k below the rounding of u)."""
    rng = np.random.default_rng(7)
    hh = 7
    cs = rng.normal(size=(30, 2 * hh + 1)) / np.r_[1.0, np.repeat(np.arange(1, hh + 1), 2)]
    k = 10.0 ** rng.uniform(-1, 2, 30)
    f = k * np.abs(cs[:, 1:]).sum(axis=1) * 10.0 ** np.r_[rng.uniform(-3, 0, 10), rng.uniform(-9, -6, 10),
                                                            rng.uniform(-19, -17, 10)]
    w_ref = rng.normal(size=30) * 0.01
    for jac in (True, False):
        coef, jacs, w0, slips = hysteresis.jenkins_loops(cs, k, f, w_ref, jac)
        for i in range(30):
            t, jt, w, s = hysteresis.jenkins_loop(cs[i], k[i], f[i], w_ref[i], jac)
            assert np.array_equal(coef[i], t) and w0[i] == w and slips[i] == s
            assert not jac or np.array_equal(jacs[i], jt)


# the peaks of a balance (hbm._peaks: the largest sample refined on x' = 0 to rounding) against scipy's
# brentq on x' around the largest of 100,001 samples at xtol 1e-15: measured within 8.7e-16 of the
# peak at H <= 15 (the rounding of a sum of 31 terms); bound over 100x that
PEAK_TOL = 1e-13


@pytest.mark.parametrize("hh", [1, 3, 7, 15])
def test_peaks_are_the_extrema_of_the_harmonics(hh):
    import scipy.optimize

    from frictionjoint.solvers.frequency_domain.hbm import _peaks

    rng = np.random.default_rng(hh)
    harm = rng.normal(size=(hh + 1, 12)) + 1j * rng.normal(size=(hh + 1, 12))
    harm *= np.exp(-0.5 * np.arange(hh + 1))[:, None]
    harm[0] = harm[0].real
    peaks = _peaks(harm)
    t = np.linspace(0.0, 2 * math.pi, 100_001)
    hs = np.arange(hh + 1)
    for i in range(harm.shape[1]):
        x = (harm[:, i, None] * np.exp(1j * hs[:, None] * t)).real.sum(axis=0)
        k = int(np.argmax(np.abs(x)))
        root = scipy.optimize.brentq(lambda s: (1j * hs * harm[:, i] * np.exp(1j * hs * s)).real.sum(),
                                     t[k - 1], t[k + 1], xtol=1e-15)
        ref = abs((harm[:, i] * np.exp(1j * hs * root)).real.sum())
        assert abs(peaks[i] - ref) <= PEAK_TOL * ref
    assert np.all(np.isnan(_peaks(np.full((3, 2), np.nan + 0j))))


def test_truncated_condensation_is_the_smaller_one():
    """Condensed.truncated(H') (the starts of a balance: H' = 3, then 1, from H = 7's solves) equals
    Condensed(system, H') bit for bit: each harmonic's Z_h is solved on its own."""
    st_ = fj.LinearStructure.chain(4, damping=0.03)
    sysm = fj.FrictionSystem(st_, [fj.Jenkins(0.5, 0.01, dof=2), fj.Jenkins(0.7, 0.02, dof=3),
                                   fj.Jenkins(0.2, 0.005, dof=3)],
                             omega=0.5, excitation=[fj.HarmonicForce(3, 0.05)])
    big = Condensed(sysm, 7)
    for hh in (1, 3, 7):
        a, b = big.truncated(hh), Condensed(sysm, hh)
        assert a.n_harmonics == hh and a.nc == b.nc
        for name in ("Y", "q_linear", "_qi", "_z"):
            assert np.array_equal(getattr(a, name), getattr(b, name)), name
        for h in range(hh + 1):
            assert np.array_equal(a.zinv_gt[h], b.zinv_gt[h]) and np.array_equal(a.zinv_f[h], b.zinv_f[h])
        z = b.q_linear * 3.0
        fa, fb = a.forces(z), b.forces(z)
        assert np.array_equal(fa.r, fb.r) and np.array_equal(fa.jacobian, fb.jacobian)
    with pytest.raises(ParameterError, match="n_harmonics"):
        big.truncated(8)


def test_distinct_rows_are_numpys():
    """hbm._distinct_rows (the joint coordinates from the slider directions and contact normals)
    equals np.unique(axis=0, return_inverse=True), signed zeros and repeated rows included."""
    from frictionjoint.solvers.frequency_domain.hbm import _distinct_rows

    rng = np.random.default_rng(3)
    for _ in range(300):
        m, n = int(rng.integers(1, 25)), int(rng.integers(1, 9))
        a = rng.choice([0.0, -0.0, 1.0, -1.0, 0.5, math.sqrt(0.5)], size=(m, n))
        rows, inverse = np.unique(a, axis=0, return_inverse=True)
        r2, i2 = _distinct_rows(a)
        assert np.array_equal(rows, r2) and np.array_equal(np.ravel(inverse), i2)
