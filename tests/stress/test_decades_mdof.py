"""Issue 25, section 6: the multi-DOF marcher, its shooting and the blade answer scenes whose
parameters span many decades in bounded time: the exact answer, or a failed status whose message
says why (never a hang, never NaN with success).

Each test runs under a wall-clock guard (:func:`faulthandler.dump_traceback_later`: a hang ends
the run with the stack of the hanging call after ``GUARD`` seconds; pytest-timeout is not
installed). Before the fix, ``kt = 1e9, 1e12`` slipping, ``omega / omega_n = 1e-12, 1e-9, 1e-6`` and
the blade root at ``normal_stiffness = 1e18, 1e20`` never returned.

Tolerances (stated once): ``EXACT`` for a closed-form answer against an independent linear solve.
"""
import faulthandler
import math
import time

import numpy as np
import pytest

import frictionjoint as fj

#: seconds a case may take before the guard ends the run
GUARD = 60.0
#: closed-form stuck orbits against an independent linear solve (rounding of K_c: eps kt / k)
EXACT = 1e-8


@pytest.fixture(autouse=True)
def _wall_clock_guard():
    faulthandler.dump_traceback_later(GUARD, exit=True)
    start = time.monotonic()
    yield start
    faulthandler.cancel_dump_traceback_later()


def _sdof(kt, omega, slip_force, damping=0.02):
    """A unit-mass, unit-stiffness oscillator with a Jenkins joint to ground, force cos(omega t)."""
    return fj.FrictionSystem(fj.LinearStructure(1.0, 1.0, damping), [fj.Jenkins(kt, slip_force, dof=0)],
                             omega=omega, excitation=[fj.HarmonicForce(0, 1.0)])


def _assert_failed_with_reason(pr, *words):
    assert not pr.converged
    assert np.all(np.isnan(pr.harmonic_amplitude))
    assert any(w in pr.message for w in words), pr.message


# ------------------------------------------------------------------ a stiff joint that sticks
M = np.diag([1.0, 0.5])
K = np.array([[2.0, -1.0], [-1.0, 1.0]])
ZETA = 0.05


@pytest.mark.parametrize("ratio", [1e3, 1e6, 1e9, 1e12])
def test_stiff_stuck_joint_is_the_rigid_constraint(ratio):
    # Reference: the chain with the joint x1 - x2 as a rigid constraint (x = [1, 1] q, one mass
    # m1 + m2 on the ground spring K[0,0] + K[0,1] + ..., written as T^T (K - w^2 M + i w C) T), an
    # independent 1x1 solve; the stiff joint's own compliance moves the answer by O(k / kt)
    # (second reference: the joint as a spring on s = x1 - x2 alone, the FRF in u = [x1, s]
    # coordinates, which does not round K by eps kt).
    w = 1.3
    pr = fj.periodic_response(fj.FrictionSystem(
        fj.LinearStructure(M, K, ZETA * K), [fj.Jenkins(ratio, 1e6 * ratio, direction=[1.0, -1.0])],
        omega=w, excitation=[fj.HarmonicForce(1, 1.0)]))
    assert pr.converged and pr.stuck, pr.message
    t = np.array([[1.0], [1.0]])
    z = t.T @ (K - w * w * M + 1j * w * ZETA * K) @ t
    rigid = np.abs(t @ np.linalg.solve(z, t.T @ np.array([0.0, 1.0])))
    np.testing.assert_allclose(pr.harmonic_amplitude, rigid, rtol=10 / ratio + EXACT, atol=0)
    tu = np.array([[1.0, 0.0], [1.0, -1.0]])
    zu = tu.T @ (K - w * w * M + 1j * w * ZETA * K) @ tu
    zu[1, 1] += ratio
    spring = np.abs(tu @ np.linalg.solve(zu, tu.T @ np.array([0.0, 1.0])))
    np.testing.assert_allclose(pr.harmonic_amplitude, spring, rtol=EXACT, atol=0)


# ----------------------------------------------------------------- a stiff joint that slips
@pytest.mark.parametrize("kt", [1e3, 1e6, 1e9, pytest.param(1e12, marks=pytest.mark.slow)])
def test_stiff_slipping_joint_answers_in_bounded_time(kt, _wall_clock_guard):
    # Continuous slip near resonance (r = 0.8, F/P0 = 0.5). Reference: the Coulomb oscillator of
    # the closed-form single-DOF kernel (frictionjoint.solvers.sdof.kernel, independent of the marcher),
    # the joint's rigid limit. A Jenkins joint differs by the stuck phase at each reversal: its
    # fast mode (sqrt(kt/m)) releases the mass with a velocity of order 2 F / sqrt(kt m), which
    # moves X by that over omega X: rtol 4 F / (sqrt(kt m) omega X) (measured: 1.5e-2 at 1e3,
    # 4.8e-4 at 1e6, 1.5e-5 at 1e9, 1e-9 at 1e12, all inside it). Before the fix, kt >= 1e9 looped
    # forever on events 1e-19 s apart (the joint's force inside the rounding of kt |x| past its
    # limit after the transient from rest).
    w, fs = 0.8, 0.5
    ref = fj.CoulombOscillator(mass=1.0, stiffness=1.0, slip_force=fs, damping=0.02, force_amplitude=1.0,
                               omega=w).steady_state()
    assert ref.converged
    pr = fj.periodic_response(_sdof(kt, w, fs))
    assert time.monotonic() - _wall_clock_guard < GUARD
    assert pr.converged, pr.message
    x = float(ref.amplitude)
    np.testing.assert_allclose(pr.amplitude, x, rtol=4 * fs / (math.sqrt(kt) * w * x) + EXACT)


# -------------------------------------------------------------- forcing far below resonance
@pytest.mark.parametrize("ratio", [1e-12, 1e-9, 1e-6, 1e-3])
def test_quasi_static_forcing_answers_in_bounded_time(ratio, _wall_clock_guard):
    # Reference (static hysteresis): with inertia and damping negligible, k x + T = P(t), and at
    # the load's extremes +-P0 the joint slips (2 P0 > 2 F (1 + k / kt)) with T = +-F, so the peak
    # displacement is (P0 - F) / k exactly; inertia and damping move it by O(r^2) and O(c omega / k).
    fs, kt = 0.5, 1e3
    pr = fj.periodic_response(_sdof(kt, ratio, fs))
    assert time.monotonic() - _wall_clock_guard < GUARD
    if ratio >= 1e-6:
        assert pr.converged, pr.message
        np.testing.assert_allclose(pr.amplitude, 1.0 - fs, rtol=10 * (ratio ** 2 + 0.02 * ratio) + EXACT)
    else:
        # a forcing period 1e9-1e12 times the natural one: the slip velocity (omega X) lies
        # inside its zero band (1e-11 of the velocities the loads can make in a natural period)
        # for most of the period, and the search cannot step over it; it stops with the reason
        _assert_failed_with_reason(pr, "gave up", "chattering", "closed-form pieces")


@pytest.mark.parametrize("ratio", [1e3, 1e6, 1e9])
def test_forcing_far_above_resonance_is_the_stuck_frf(ratio):
    # Reference: |1 / (k + kt - m w^2 + i w c)|, the stuck oscillator's FRF (the joint's force
    # kt X ~ kt / w^2 stays far below its slip force at these frequencies).
    kt = 1e3
    pr = fj.periodic_response(_sdof(kt, ratio, 0.5))
    assert pr.converged and pr.stuck, pr.message
    ref = abs(1.0 / (1.0 + kt - ratio * ratio + 1j * ratio * 0.02))
    np.testing.assert_allclose(pr.harmonic_amplitude, ref, rtol=EXACT, atol=0)


# -------------------------------------------------------------- a blade on a very stiff root
@pytest.mark.slow
@pytest.mark.parametrize("variation", [False, True])
@pytest.mark.parametrize("kn", [1e14, 1e16, 1e18, 1e20])
def test_blade_root_normal_stiffness_answers_in_bounded_time(kn, variation, _wall_clock_guard):
    # Reference: the sweep's own 'stuck' linear limit (frictionjoint.linear_limits: the blade on
    # its stuck root, a complex linear solve independent of the marcher). The assembled
    # stiffness carries the root's normal springs, rounded by eps kn against the blade's: the
    # stuck orbit differs from the limit by 4e-6 at 1e14 and 3.4e-4 at 1e16 (measured): rounding,
    # which differs between CPUs and BLAS builds, so the tolerance is 100x the largest, 3e-2 (the
    # slipping root's response differs from the stuck one by far more); beyond, the march cannot
    # resolve the root's normal modes (5.7e10 rad/s at
    # 1e18, 3e7 times the excitation) and gives up with the reason.
    r = fj.sweep("ti64_compressor_blade", [2000.0], {"normal_stiffness": kn, "normal_load_variation": variation})
    assert time.monotonic() - _wall_clock_guard < GUARD
    if kn <= 1e16:
        assert r.converged.all() and r.stuck.all(), r.messages
        np.testing.assert_allclose(np.abs(r.response), np.abs(r.limits["stuck"]), rtol=3e-2)
    else:
        assert not r.converged.any()
        assert np.all(np.isnan(r.response))
        assert all("gave up" in m and "fastest mode" in m for m in r.messages), r.messages


@pytest.mark.slow
def test_sweep_of_a_stiff_joint_answers_in_bounded_time(_wall_clock_guard):
    # sweep(build) with the kt = 1e12 joint (it looped forever at its first point before the fix).
    # Reference: the closed-form Coulomb oscillator at each frequency (see
    # test_stiff_slipping_joint_answers_in_bounded_time for the tolerance: 4 F / (sqrt(kt) omega X)).
    omegas = np.array([0.8, 1.0])
    r = fj.sweep(lambda w: _sdof(1e12, w, 0.5), omegas)
    assert time.monotonic() - _wall_clock_guard < GUARD
    assert r.converged.all(), r.messages
    for w, amp in zip(omegas, r.amplitude[:, 0]):
        ref = fj.CoulombOscillator(mass=1.0, stiffness=1.0, slip_force=0.5, damping=0.02, force_amplitude=1.0,
                                   omega=w).steady_state()
        x = float(ref.amplitude)
        np.testing.assert_allclose(amp, x, rtol=4 * 0.5 / (1e6 * w * x) + EXACT)
