"""The forced response synthesised from a nonlinear mode (issue 31, part 3): exact in its two
limits, a linear system (the mode's term of the modal expansion) and the single-DOF Jenkins
oscillator at H = 1 (the describing function's forced response, written here independently); on
the blade beside hbm_sweep's branch.

Tolerance of the closed forms: 1e-9 (relative).
"""
import math
import time

import numpy as np
import pytest
import scipy.linalg

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.solvers.frequency_domain.mode_synthesis import mode_synthesis
from frictionjoint.solvers.frequency_domain.nonlinear_mode import nonlinear_mode

CLOSED_FORM_TOL = 1e-9


def _three_dof(alpha=0.3, beta=2e-3):
    """A free-free-grounded 3-DOF chain (masses 1, 2, 1.5; springs 100, 60, 40 from the ground) with
    a Jenkins joint from DOF 0 to the ground that never slips (slip force 1e6 N), Rayleigh damping
    C = alpha M + beta K_stuck (classical): a linear system."""
    m = np.diag([1.0, 2.0, 1.5])
    k = np.array([[160.0, -60.0, 0.0], [-60.0, 100.0, -40.0], [0.0, -40.0, 40.0]])
    kt = 50.0
    k_stuck = k + np.diag([kt, 0.0, 0.0])
    c = alpha * m + beta * k_stuck
    system = fj.FrictionSystem(fj.LinearStructure(m, k, c), [fj.Jenkins(kt, 1e6, dof=0)],
                               omega=10.0, excitation=[fj.HarmonicForce(2, 1.0, 0.3)])
    return system, m, k_stuck, alpha, beta


def test_linear_system_is_the_modal_frf_of_the_mode():
    """No slip: every point (linear tails, both sides, the peak) is the mode's term of the modal
    expansion, phi_o phi^T F / (omega^2 - Omega^2 + i Omega (alpha + beta omega^2)), and the peak is
    at Omega^2 = omega^2 - c^2 / 2."""
    system, m, k_stuck, alpha, beta = _three_dof()
    lam, vec = scipy.linalg.eigh(k_stuck, m)  # mass-normalised
    w1, phi = math.sqrt(lam[1]), vec[:, 1]
    nm = nonlinear_mode(system, mode=1, amplitudes=np.geomspace(3e-3, 1.0, 30), n_harmonics=3)
    assert nm.success and np.all(nm.stuck)
    syn = mode_synthesis(nm, system, f"{0.5 * w1}:{1.5 * w1}:40", output=2)
    assert syn.success and syn.peak_found, syn.message
    force = np.array([0.0, 0.0, math.cos(0.3) - 1j * math.sin(0.3)])

    def modal(om):
        return phi[2] * (phi @ force) / (lam[1] - om ** 2 + 1j * om * (alpha + beta * lam[1]))
    ref = np.array([modal(om) for om in syn.omega])
    err = np.max(np.abs(syn.response - ref) / np.abs(ref))
    print(f"linear: {syn.omega.size} points, largest relative error against the modal term {err:.2e}")
    assert err <= CLOSED_FORM_TOL
    tails = np.array(["linear tail" in msg for msg in syn.messages])
    assert tails.sum() >= 30 and syn.messages[int(np.argmax(syn.amplitude))].startswith("the peak")
    c1 = alpha + beta * lam[1]
    w_pk, a_pk = syn.peak()
    w_ref = math.sqrt(lam[1] - c1 ** 2 / 2)
    print(f"linear peak: frequency {abs(w_pk / w_ref - 1):.2e}, amplitude {abs(a_pk / abs(modal(w_ref)) - 1):.2e}")
    assert abs(w_pk / w_ref - 1) <= CLOSED_FORM_TOL and abs(a_pk / abs(modal(w_ref)) - 1) <= CLOSED_FORM_TOL


def _jenkins_forced(a, m, k, kt, fs, force):
    """The describing function's forced response of m x'' + k x + T = F cos(Omega t), T a Jenkins
    element (spring kt, slip force fs), x = a cos(Omega t - phi): with the loop's first harmonic
    T_1 = (k_eq + i eta) a, k_eq = kt (2 beta - sin 2 beta) / (2 pi) and eta = 4 fs (a - fs/kt) /
    (pi a^2) (1 - cos beta = 2 fs / (kt a); kt and 0 while stuck), |k + k_eq - m Omega^2 + i eta| a
    = F gives Omega^2 = (k + k_eq -+ sqrt((F/a)^2 - eta^2)) / m: ``(Omega_-, Omega_+)``."""
    if a * kt > fs:
        beta = math.acos(1.0 - 2.0 * fs / (kt * a))
        k_eq, eta = kt * (2.0 * beta - math.sin(2.0 * beta)) / (2.0 * math.pi), 4.0 * fs * (a - fs / kt) / (math.pi * a * a)
    else:
        k_eq, eta = kt, 0.0
    root = math.sqrt((force / a) ** 2 - eta ** 2)
    return math.sqrt((k + k_eq - root) / m), math.sqrt((k + k_eq + root) / m)


def test_sdof_jenkins_one_harmonic_is_the_describing_function():
    """H = 1 on m = 2, k = 3, kt = 5, Fs = 0.1, F = 0.05 (no dashpot): both sides against the
    closed form from stuck to near the peak; the peak a* = (Fs/kt) / (1 - pi F / (4 Fs)), where
    F/a = eta, at Omega*^2 = (k + k_eq(a*)) / m."""
    m, k, kt, fs, f = 2.0, 3.0, 5.0, 0.1, 0.05
    system = fj.FrictionSystem(fj.LinearStructure([[m]], [[k]], [[0.0]]), [fj.Jenkins(kt, fs, dof=0)],
                               omega=1.5, excitation=[fj.HarmonicForce(0, f)])
    a_pk = (fs / kt) / (1.0 - math.pi * f / (4.0 * fs))
    nm = nonlinear_mode(system, amplitudes=np.geomspace(0.002, 3 * a_pk, 40), n_harmonics=1)
    assert nm.success
    syn = mode_synthesis(nm, system, "0.8:2.5:30")
    assert syn.success and syn.peak_found, syn.message
    w_pk, amp = syn.peak()
    errors = []
    for w, a, msg in zip(syn.omega, syn.mode_amplitude, syn.messages):
        if not msg.startswith("the peak"):  # linear tails and the two sides
            lo, hi = _jenkins_forced(a, m, k, kt, fs, f)
            errors.append(abs(w - (lo if w < w_pk else hi)) / w)
    np.testing.assert_allclose(syn.amplitude, syn.mode_amplitude, rtol=1e-13)
    assert np.count_nonzero(~syn.stuck) >= 10
    beta = math.acos(1.0 - 2.0 * fs / (kt * a_pk))
    w_ref = math.sqrt((k + kt * (2.0 * beta - math.sin(2.0 * beta)) / (2.0 * math.pi)) / m)
    print(f"Jenkins H = 1: {len(errors)} points, largest frequency error {max(errors):.2e}; peak amplitude "
          f"{abs(amp / a_pk - 1):.2e}, frequency {abs(w_pk / w_ref - 1):.2e}")
    assert max(errors) <= CLOSED_FORM_TOL
    assert abs(amp / a_pk - 1) <= CLOSED_FORM_TOL and abs(w_pk / w_ref - 1) <= CLOSED_FORM_TOL
