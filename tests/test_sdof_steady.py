"""Steady state of the single-DOF oscillator on the closed-form kernel (exact Jacobian) against the
general marcher's path (periodic_response, finite-difference Jacobian) and Den Hartog."""
import itertools
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.analytic import den_hartog
from frictionjoint.solvers.sdof.kernel import SdofCoulomb
from frictionjoint.solvers.sdof.steady import sdof_periodic_response
from frictionjoint.solvers.marcher.steady import periodic_response

RTOL = 2e-12  # both paths converge to tol = 1e-12 of the scaled residual


def _both(f, r, c):
    osc = fj.CoulombOscillator(slip_force=f, force_amplitude=1.0, omega=r, damping=c)
    x0, v0 = osc.initial_guess()
    kernel = SdofCoulomb(1.0, 1.0, f, 1.0, r, c)
    a = sdof_periodic_response(kernel, x0, v0, tol=1e-12, max_newton=25, max_periods=2000, n_samples=64)
    b = periodic_response(osc.system, x0, v0, n_samples=64)
    return a, b


@pytest.mark.parametrize("f,r,c", list(itertools.product((0.1, 0.5, 0.9), (0.45, 0.8, 1.1, 2.0), (0.0, 0.05))))
def test_agrees_with_the_general_path(f, r, c):
    a, b = _both(f, r, c)
    assert a is not None and a.converged and b.converged
    assert a.amplitude == pytest.approx(float(b.amplitude[0]), rel=RTOL)
    assert a.harmonic_amplitude == pytest.approx(float(b.harmonic_amplitude[0]), rel=RTOL)
    assert abs(a.phase - float(b.phase[0])) <= RTOL * math.pi
    assert a.dissipated_per_cycle == pytest.approx(b.dissipated_per_cycle, rel=RTOL, abs=1e-15)
    assert (a.stops_per_cycle, a.stuck, a.unique) == (b.stops_per_cycle, b.stuck, b.unique)
    assert sorted(a.events.kind) == sorted(b.events.kind)
    # the initial state is on the orbit: one period from it returns to it
    k = SdofCoulomb(1.0, 1.0, f, 1.0, r, c)
    end = k.march(0.0, a.initial_state[0], a.initial_state[1], 2 * math.pi / r)
    scale = max(a.amplitude, 1e-300)
    assert abs(end.x - a.initial_state[0]) <= 1e-10 * scale
    # the samples are the orbit
    assert np.max(np.abs(a.x - b.x[0])) <= 1e-10 * scale
    # exact multipliers against the finite-difference ones of the general path
    assert np.max(np.abs(np.sort(np.abs(a.floquet_multipliers)) - np.sort(np.abs(b.floquet_multipliers)))) <= 1e-6


@pytest.mark.parametrize("f,r", [(0.1, 0.8), (0.3, 0.8), (0.5, 0.8), (0.1, 1.5), (0.3, 1.5), (0.1, 3.0),
                                 (0.3, 3.0)])
def test_den_hartog(f, r):
    """Stop-free orbits: Den Hartog's closed form (DESIGN.md section 3)."""
    sol = den_hartog(r, f)
    assert sol.applicable
    res = fj.CoulombOscillator(slip_force=f, force_amplitude=1.0, omega=r).steady_state()
    assert res.floquet_multipliers is not None and res.stable
    assert res.amplitude == pytest.approx(sol.amplitude, rel=1e-11)


def test_cases_it_leaves_to_the_general_path():
    """Unbounded growth (r = 1, F/P0 < pi/4): None here; steady_state then answers from the general
    marcher, in words."""
    k = SdofCoulomb(1.0, 1.0, 0.5, 1.0, 1.0)
    assert sdof_periodic_response(k, 0.0, 0.0, tol=1e-12, max_newton=25, max_periods=300) is None
    res = fj.CoulombOscillator(slip_force=0.5, force_amplitude=1.0, omega=1.0).steady_state(max_periods=300)
    assert res.status == "unbounded" and "grows without bound" in res.message


@pytest.mark.parametrize("x0", [0.0, 0.7])
def test_permanent_stick_answered_like_the_general_path(x0):
    """F > P0 and a guess at rest with |k x0| <= F - P0: stuck through the period, so a periodic
    orbit exactly (a member of the family of rest positions), answered by the kernel from that
    period with the general marcher's fields (it answered this case before, in the first call
    of a process after seconds of set-up)."""
    osc = fj.CoulombOscillator(slip_force=2.0, force_amplitude=1.0, omega=0.8)
    res = sdof_periodic_response(osc._kernel(), x0, 0.0, tol=1e-12, max_newton=25, max_periods=300, n_samples=8)
    ref = periodic_response(osc.system, x0, 0.0, marcher=osc._marcher, tol=1e-12, max_periods=300, n_samples=8)
    assert res.converged and ref.converged and res.stuck and ref.stuck
    assert not res.unique and not ref.unique and "NOT UNIQUE" in res.message
    # a stuck mass does not move: x0 itself, no arithmetic on it
    assert res.amplitude == float(ref.amplitude[0]) == abs(x0)
    assert res.stops_per_cycle == ref.stops_per_cycle == 0 and res.dissipated_per_cycle == 0.0
    assert np.array_equal(res.x, np.full(8, x0))
    assert sorted(abs(res.floquet_multipliers)) == sorted(abs(ref.floquet_multipliers)) == [0.0, 1.0]
