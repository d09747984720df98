"""The exact Jacobian of the general period map (closed-form pieces x saltation matrices) against
central finite differences of the same map, and the Floquet multipliers it gives."""
import math

import numpy as np
import pytest
import scipy.linalg

import frictionjoint as fj
from frictionjoint.solvers.marcher.events import Marcher
from frictionjoint.solvers.marcher.steady import _PeriodMap, periodic_response


def chain(n, joints, slip=0.3, r=0.9, rigid=False):
    """n unit masses, fixed-free, unit springs, 2 % mass-proportional damping of the first mode;
    ``joints`` Jenkins (or Coulomb) joints to ground on the outer half, force at the tip."""
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))  # first mode of the fixed-free chain
    s = fj.LinearStructure.chain(n, damping=0.02 * w1)
    dofs = sorted({int(d) for d in np.linspace(n - 1, n // 2, joints).round()})
    kt = 0.5 * w1 ** 2
    if rigid:
        els = [fj.CoulombSlider(slip, dof=d) for d in dofs]
    else:
        els = [fj.Jenkins(kt, slip, dof=d) for d in dofs]
    return fj.FrictionSystem(s, els, omega=r * w1, excitation=[fj.HarmonicForce(n - 1, 0.01)])


def _scaled_error(system):
    pr = periodic_response(system)
    assert pr.converged
    pmap = _PeriodMap(system, Marcher(system), pr.section_time)
    z = pr.state
    sc = pmap.scales(z)
    jac = pmap.jacobian(z, pmap(z), sc)
    fd = np.empty_like(jac)
    for k in range(z.size):
        h = 1e-6 * sc[k]
        zp, zm = z.copy(), z.copy()
        zp[k] += h
        zm[k] -= h
        fd[:, k] = (pmap(zp) - pmap(zm)) / (2 * h)
    scaled = sc[None, :] / sc[:, None]
    return float(np.max(np.abs((jac - fd) * scaled)) / max(1.0, np.max(np.abs(jac * scaled)))), pr


SYSTEMS = {
    "sdof stick-slip": lambda: fj.FrictionSystem(fj.LinearStructure(1.0, 1.0, 0.1), [fj.CoulombSlider(0.5, dof=0)],
                                                 omega=0.5, excitation=[fj.HarmonicForce(0, 1.0)]),
    "2-DOF Coulomb": lambda: fj.FrictionSystem(
        fj.LinearStructure(np.eye(2), [[2.0, -1.0], [-1.0, 1.0]], 0.05 * np.eye(2)),
        [fj.CoulombSlider(0.3, dof=1)], omega=0.8, excitation=[fj.HarmonicForce(1, 1.0)]),
    "2-DOF chain, 2 Jenkins": lambda: chain(2, 2, slip=0.002),
    "5-DOF chain, 2 Jenkins": lambda: chain(5, 2, slip=0.0012),
    "10-DOF chain, 3 Coulomb": lambda: chain(10, 3, slip=0.002, rigid=True),
}


@pytest.mark.parametrize("name", SYSTEMS)
def test_exact_jacobian_matches_central_differences(name):
    err, pr = _scaled_error(SYSTEMS[name]())
    assert len(pr.events) > 0  # the orbit has stick-slip events (saltation matrices are used)
    assert err <= 1e-7, err


def test_stuck_only_multipliers_are_the_modes_exponentials():
    """A joint that never slips: the period map is linear, its multipliers are exp(lam_i T) of the
    stuck structure's modes, and 1 for the Jenkins slider position (a family of rest positions)."""
    sysm = chain(5, 2, slip=1e3)
    pr = periodic_response(sysm)
    assert pr.converged and len(pr.events) == 0
    cfg = Marcher(sysm).config(np.zeros(sysm.n_sliders, np.int8))
    t = 2 * math.pi / sysm.omega
    ref = np.concatenate([np.linalg.eigvals(scipy.linalg.expm(cfg.A * t)), np.ones(sysm.n_sliders)])
    got = np.sort_complex(pr.floquet_multipliers)
    ref = np.sort_complex(ref)
    assert np.max(np.abs(got - ref)) <= 1e-12
    assert not pr.unique


@pytest.mark.parametrize("name", ["sdof stick-slip", "2-DOF Coulomb", "5-DOF chain, 2 Jenkins",
                                  "10-DOF chain, 3 Coulomb"])
def test_damped_orbits_are_stable(name):
    pr = periodic_response(SYSTEMS[name]())
    assert pr.converged and pr.stable
    assert np.max(np.abs(pr.floquet_multipliers)) < 1


def test_chain_structure_first_mode():
    """LinearStructure.chain: the fixed-free chain of unit masses and springs has the natural
    frequencies w_k = 2 sin((2k - 1) pi / (2 (2n + 1))) (the eigenvalues of its tridiagonal
    stiffness matrix, from the ansatz x_j = sin(j theta) with the free end's condition)."""
    for n in (1, 2, 7, 20):
        w = fj.LinearStructure.chain(n).natural_frequencies()
        assert abs(w[0] / (2 * math.sin(math.pi / (2 * (2 * n + 1)))) - 1) <= 1e-12
    with pytest.raises(fj.ParameterError, match="n"):
        fj.LinearStructure.chain(0)


def test_chain_steady_state_needs_few_periods():
    """Newton on the exact Jacobian: the 20-DOF chain with 5 Jenkins joints in at most 15 periods
    (the finite-difference Jacobian needed 188)."""
    pr = periodic_response(chain(20, 5, slip=0.0004))
    assert pr.converged and pr.stops_per_cycle > 0
    assert pr.periods <= 15


def test_stuck_only_orbit_is_the_linear_solution_without_marching():
    """Joints that never slip: no period is marched; the orbit is the harmonic response of the
    structure with the Jenkins springs added, (K + sum k d d^T - w^2 M + i w C)^-1 (f_c - i f_s),
    computed here independently in full coordinates."""
    sysm = chain(20, 3, slip=10.0)
    pr = periodic_response(sysm, n_samples=64)
    assert pr.converged and pr.stuck and pr.periods == 0 and len(pr.events) == 0
    k = sysm.stiffness + (sysm.slider_direction.T * sysm.slider_stiffness) @ sysm.slider_direction
    w = sysm.omega
    x = np.linalg.solve(k - w * w * sysm.mass + 1j * w * sysm.damping, sysm.force_cos - 1j * sysm.force_sin)
    # two solves, each to eps cond(K - w^2 M + i w C) = 4.9e-13 (cond 2.2e3), compared DOF by DOF:
    # 1e-10 (measured 2.6e-13, 1.2e-13 of max |x| in x(t))
    assert np.max(np.abs(pr.harmonic_amplitude / np.abs(x) - 1)) <= 1e-10
    assert np.max(np.abs(pr.amplitude / np.abs(x) - 1)) <= 1e-10  # no static offset from rest
    t = pr.t
    ref = (x[:, None] * np.exp(1j * w * t)[None, :]).real
    assert np.max(np.abs(pr.x - ref)) <= 1e-10 * np.max(np.abs(x))
    # a joint that would slip somewhere in the period is not taken for stuck
    assert periodic_response(chain(20, 3, slip=0.0004)).periods > 0


def test_a_failed_march_is_a_status_not_an_exception(monkeypatch):
    """periodic_response and simulate report a march that fails (here: made to fail by a
    marcher whose settling raises, as it does on no consistent stick/slip status) in the result."""
    from frictionjoint.solvers.marcher import response
    from frictionjoint.solvers.marcher.events import Marcher as M

    sysm = chain(5, 2, slip=0.0012)

    def broken(self, state, log=None, trigger=None):
        if state.t > 0:
            raise fj.ConvergenceError(f"no consistent stick/slip configuration at t = {state.t!r}")
        return original(self, state, log, trigger)
    original = M.settle
    monkeypatch.setattr(M, "settle", broken)
    pr = periodic_response(sysm)
    assert pr.status == "failed" and not pr.success and not pr.converged
    assert "the march failed" in pr.message and np.all(np.isnan(pr.amplitude))
    tr = response.simulate(sysm, 50.0, t_eval=[0.0, 49.0])
    assert not tr.success and tr.status == "failed" and "the march failed" in tr.message
    assert np.all(np.abs(tr.x[:, 0]) <= 1e-15) and np.all(np.isnan(tr.x[:, 1]))
