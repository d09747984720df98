"""Regression: 2-DOF chain with a Jenkins joint between the masses that is far stiffer than the
structure (kt/k up to 1e11), nearly frictionless (slip force 1e-12 of the excitation) or stuck
(1e6 x): periodic_response is the linear FRF (its speed, once > 20 s, is not timed here).

The reference is computed independently with numpy in coordinates u = [x1, s = x1 - x2] where the
joint spring acts on s alone: forming K + kt d d^T directly rounds the structure's stiffness by
eps * kt (a 1e-7 error in the reference itself at kt/k ~ 1e11)."""
import numpy as np
import pytest

import frictionjoint as fj

M = np.diag([1.0, 0.5])
K = np.array([[2.0, -1.0], [-1.0, 1.0]])
F = np.array([0.0, 1.0])
T = np.array([[1.0, 0.0], [1.0, -1.0]])  # x = T u, u = [x1, x1 - x2]


def _system(kt, fs, w, zeta, n_iwan=0):
    els = [fj.Jenkins(kt, fs, direction=[1.0, -1.0])]
    if n_iwan:
        els.append(fj.Iwan([(kt * (j + 1) / n_iwan, fs * (j + 1) / n_iwan) for j in range(n_iwan)], dof=0))
    return fj.FrictionSystem(fj.LinearStructure(M, K, zeta * K), els, omega=w,
                             excitation=[fj.HarmonicForce(1, 1.0)])


def _frf(w, zeta, k_joint=0.0, k_ground=0.0):
    """X = (K_stuck - w^2 M + i w C)^-1 F with the joint stiffness on u[1] only."""
    z = T.T @ (K - w * w * M + 1j * w * zeta * K) @ T
    z[1, 1] += k_joint
    z[0, 0] += k_ground
    return T @ np.linalg.solve(z, T.T @ F)


@pytest.mark.parametrize("kt, w, zeta", [
    (5.217430516349216e9, 3.3121865544033025, 0.04883797300273825),  # the stress-suite failure
    (4.363e9, 4.1885, 0.1133), (4.078e11, 4.4476, 0.0105), (6.285e7, 3.2681, 0.0154)])
def test_nearly_frictionless_stiff_joint_is_the_frictionless_frf(kt, w, zeta):
    h = _frf(w, zeta)
    pr = fj.periodic_response(_system(kt, 1e-12, w, zeta), x0=h.real, v0=-w * h.imag)
    assert pr.converged, pr.message
    np.testing.assert_allclose(pr.harmonic_amplitude, np.abs(h), rtol=1e-8, atol=0)


@pytest.mark.parametrize("kt, w, zeta, n_iwan", [
    (3e8, 2.0, 0.17, 0), (1e10, 3.0, 0.18, 0), (9.7e10, 4.35, 0.19, 0),
    (1e9, 2.5, 0.18, 2), (1e10, 4.0, 0.17, 3)])
def test_stuck_stiff_joint_is_the_stuck_frf(kt, w, zeta, n_iwan):
    h = _frf(w, zeta, k_joint=kt, k_ground=sum(kt * (j + 1) / n_iwan for j in range(n_iwan)))
    pr = fj.periodic_response(_system(kt, 1e6, w, zeta, n_iwan), x0=h.real, v0=-w * h.imag)
    assert pr.converged and pr.stuck, pr.message
    assert len(pr.events) == 0
    np.testing.assert_allclose(pr.harmonic_amplitude, np.abs(h), rtol=1e-8, atol=0)
