"""Regressions of the single-DOF Coulomb oscillator found by the stress suite (test_stress.py),
each against an independent reference: Den Hartog's closed form (``analytic.den_hartog``,
DESIGN.md §3) or a small-time expansion of the slip from rest, never the solver's own output.

``m x'' + k x + T = P0 cos(w t)``, ``|T| <= F``, r = w/wn, f = F/P0.

1. r = 1e-3, f = 1e-6 (and m = 1e-3, k = 1e3; m = 1e3, k = 1e-3): the mass follows
   quasi-statically; starting at Den Hartog's turning point the holding force is within
   rounding of the slip limit. The marcher chattered (a slip velocity reversing by ~1e-20, whose
   "crossing" was the start itself; then a stick/slip cycle decided by curvatures alone).
2. f = 1e-11, r = 0.75: the displacement peak lags the force peak by ~1e-11 rad, so the section
   t = 0 sat on the velocity reversal (a kink of the period map): Newton never converged.
3. Undamped, r = 1 +- 1e-6, f < pi/4: bounded stop-free orbits of amplitude ~5e5 P0/k; the
   shooting started from rest (the one-harmonic guess was switched off near resonance), met the
   start-up stops, failed, and the marching fallback's growth test misread the beating
   transient (period ~1e6 excitation periods) as unbounded growth.
4. r = 1000: the residual was scaled by the motion (~1e-6 P0/k) while the map's rounding is
   ~eps F/k: the tolerance was unreachable (and the finite-difference steps sat in the noise).
5. F = P0 (1 - eps), from rest: a slip of ~3 sqrt(2 eps)/w (shorter than the event search's
   finest grid) ran on to that grid's first point (1/512 of the shortest period), in the wrong
   direction: a spurious slip of ~1e-9 P0/k that broke the energy balance by ~5e-9.
6. 1e-4 < |r - 1| < 1e-2 (found with STRESS_EXAMPLES=80): the closed form split each mode into a
   particular and a homogeneous part ~1/|r - 1| times larger than the motion, so the map carried
   rounding of ~eps/|r - 1| (1e-12): spurious wrong-way slips just below the stick limit and
   an unreachable shooting tolerance (F/P0 = 0.98, r = 1.00014: 3800 periods, not converged).
"""
import math
import time

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.analytic import den_hartog

RTOL_ANALYTIC = 1e-8   # amplitudes against Den Hartog
RTOL_ENERGY = 1e-10    # energy balance, relative to the energy scale
SECONDS = 5.0          # wall time per steady state (a generous bound; measured <= 0.7 s)


def _den_hartog_amplitude(m, k, f, p0, omega):
    """Den Hartog's max |x| [m] (DESIGN.md §3: X = X̄ P0/k) and the solution object."""
    sol = den_hartog(omega / math.sqrt(k / m), f / p0)
    return sol.amplitude * p0 / k, sol


# ------------------------------------------------------------------ 1. quasi-static, r = 1e-3
@pytest.mark.parametrize("m, k", [(1.0, 1.0), (1e-3, 1e3), (1e3, 1e-3)])
def test_quasi_static_r_1e_3_no_chatter_and_family_reported(m, k):
    """r = 1e-3 = 1/(2 * 500): U = tan(pi/(2r))/r = 0, so Den Hartog's stop-free orbit is one of
    a family (DESIGN.md §3, r = 1/(2n)); the solver must find a member quickly and say so."""
    f, p0 = 1e-6, 1.0
    omega = 1e-3 * math.sqrt(k / m)
    osc = fj.CoulombOscillator(mass=m, stiffness=k, slip_force=f, force_amplitude=p0, omega=omega)
    amp, sol = _den_hartog_amplitude(m, k, f, p0, omega)
    assert sol.regime == "stop-free" and not sol.unique  # the reference's own verdict
    t0 = time.perf_counter()
    ss = osc.steady_state()
    assert time.perf_counter() - t0 < SECONDS
    assert ss.converged, ss.message
    assert not ss.unique and "NOT UNIQUE" in ss.message
    # the member reached from Den Hartog's start is Den Hartog's (mean offset 0)
    assert ss.amplitude == pytest.approx(amp, rel=RTOL_ANALYTIC)
    # one period from the turning point of the closed form, where the holding force is within
    # rounding of F: the march that used to raise "events do not advance time (chattering)"
    x0, v0 = osc.initial_guess()
    tr = osc.simulate(osc.period, x0, v0, record=("x", "energy"))
    scale = max(np.max(np.abs(tr.work)), np.max(tr.stored_energy), np.max(tr.dissipated_friction))
    assert np.max(np.abs(tr.energy_residual())) <= RTOL_ENERGY * scale


def test_quasi_static_generic_low_r_is_den_hartog():
    """r = 1.234e-3 (not 1/(2n)), f = 1e-6: Den Hartog's unique stop-free orbit."""
    f, r = 1e-6, 1.234e-3
    amp, sol = _den_hartog_amplitude(1.0, 1.0, f, 1.0, r)
    assert sol.regime == "stop-free" and sol.unique
    t0 = time.perf_counter()
    ss = fj.CoulombOscillator(slip_force=f, force_amplitude=1.0, omega=r).steady_state()
    assert time.perf_counter() - t0 < SECONDS
    assert ss.converged and ss.unique, ss.message
    assert ss.amplitude == pytest.approx(amp, rel=RTOL_ANALYTIC)
    assert ss.stops_per_cycle == 0


# ------------------------------------------------------------------ 2. tiny friction
@pytest.mark.parametrize("f", [1e-11, 1e-12, 1e-9])
@pytest.mark.parametrize("r", [0.75, 0.3, 2.5])
def test_tiny_friction_converges_to_den_hartog(f, r):
    amp, sol = _den_hartog_amplitude(1.0, 1.0, f, 1.0, r)
    assert sol.regime == "stop-free"
    ss = fj.CoulombOscillator(slip_force=f, force_amplitude=1.0, omega=r).steady_state()
    assert ss.converged, ss.message
    assert ss.amplitude == pytest.approx(amp, rel=RTOL_ANALYTIC)
    assert ss.periods < 20


# ------------------------------------------------------------------ 3. near resonance, undamped
@pytest.mark.parametrize("f", [1e-12, 1e-6, 0.3, 0.5, 0.78])
@pytest.mark.parametrize("delta", [1e-6, -1e-6, 1e-4, -3e-3])
@pytest.mark.parametrize("p0", [1.0, -1.0])
def test_near_resonance_undamped_below_pi_over_4_is_bounded(f, delta, p0):
    """r = 1 + delta, f < pi/4: bounded stop-free motion (Den Hartog), amplitude up to ~5e5 P0/k;
    only at r = 1 exactly is it unbounded (test_stress.py)."""
    omega = 1.0 + delta
    amp, sol = _den_hartog_amplitude(1.0, 1.0, f, abs(p0), omega)
    assert sol.regime == "stop-free"
    t0 = time.perf_counter()
    ss = fj.CoulombOscillator(slip_force=f, force_amplitude=p0, omega=omega).steady_state()
    assert time.perf_counter() - t0 < SECONDS
    assert ss.converged and ss.status == "periodic", ss.message
    assert ss.amplitude == pytest.approx(amp, rel=RTOL_ANALYTIC)
    assert ss.stops_per_cycle == 0


# ------------------------------------------------------------------ 4. far above resonance
@pytest.mark.parametrize("f, r, rel", [
    (0.3, 200.0, RTOL_ANALYTIC), (1e-3, 500.0, RTOL_ANALYTIC), (1e-6, 1000.0, RTOL_ANALYTIC),
    # the mean offset is held only weakly (an eigenvalue 1 - O(1/r^2) of the period map) against
    # the map's rounding ~eps F/k: the orbit is computable to ~1e-16 f r^4 relative, no better
    (0.3, 500.0, 1e-6), (0.3, 1000.0, 1e-5)])
def test_far_above_resonance_converges(f, r, rel):
    amp, sol = _den_hartog_amplitude(1.0, 1.0, f, 1.0, r)
    assert sol.regime == "stop-free"
    t0 = time.perf_counter()
    ss = fj.CoulombOscillator(slip_force=f, force_amplitude=1.0, omega=r).steady_state()
    assert time.perf_counter() - t0 < SECONDS
    assert ss.converged, ss.message
    assert ss.amplitude == pytest.approx(amp, rel=rel)


# ------------------------------------------------------------------ 5. just below the stick limit
@pytest.mark.parametrize("eps", [1e-8, 1e-9, 1e-10, 1e-11, 1e-12])
@pytest.mark.parametrize("r", [0.1, 1.0, 3.0, 10.0])
def test_just_below_the_stick_limit_slips_are_tiny_and_energy_balances(eps, r):
    """F = P0 (1 - eps) from rest. The slips are real but tiny: near a force extremum the net force
    is P0 (eps - w^2 t^2/2) (k x is negligible), so from v = 0 the velocity
    (P0/m)(eps t - w^2 t^3/6) returns to 0 at t1 = sqrt(6 eps)/w, after a slip of
    x1 = 1.5 eps^2 P0/(m w^2) (+ O(eps) relative; from rest at t = 0, and the same at each later
    extremum of the force where the holding force exceeds F). Anything larger than rounding
    (~eps_machine P0/k) above that is spurious."""
    m = k = p0 = 1.0
    osc = fj.CoulombOscillator(mass=m, stiffness=k, slip_force=p0 * (1 - eps), force_amplitude=p0, omega=r)
    tr = osc.simulate(5 * osc.period, 0.0, 0.0, record=("x", "energy"))
    slip = 1.5 * eps ** 2 * p0 / (m * r ** 2)  # the small-time expansion above, per slip
    n_slips = 10  # at most two per period (the force extremes), five periods
    assert np.max(np.abs(tr.x)) <= n_slips * slip * (1 + 1e-3) + 1e-14 * p0 / k
    scale = max(np.max(np.abs(tr.work)), np.max(tr.stored_energy), np.max(tr.dissipated_friction),
                p0 ** 2 / k)
    assert np.max(np.abs(tr.energy_residual())) <= RTOL_ENERGY * scale


# ------------------------------------------------------------------ 6. 1e-4 < |r - 1| < 1e-2
@pytest.mark.parametrize("eps, r", [(9.994137019699967e-09, 1.0001405485169472), (1e-10, 1.003),
                                    (1e-12, 0.9995)])
def test_near_resonance_just_below_the_stick_limit_is_passive(eps, r):
    """As test 5, near resonance: the same analytic slip bound, and the friction work never
    decreases (no wrong-way slip)."""
    osc = fj.CoulombOscillator(slip_force=1 - eps, force_amplitude=1.0, omega=r)
    tr = osc.simulate(5 * osc.period, 0.0, 0.0, record=("x", "energy"))
    slip = 1.5 * eps ** 2 / r ** 2  # the small-time expansion of test 5 (m = k = P0 = 1)
    assert np.max(np.abs(tr.x)) <= 10 * slip * (1 + 1e-3) + 1e-14
    assert np.all(np.diff(tr.dissipated_friction) >= -1e-15)
    assert np.max(np.abs(tr.energy_residual())) <= RTOL_ENERGY


@pytest.mark.parametrize("delta", [1.4001347258008802e-4, -5e-4, 3e-3])
def test_near_resonance_above_pi_over_4_converges_by_shooting(delta):
    """F/P0 = 0.98 > pi/4, r = 1 + delta: bounded motion with stops (Hong & Liu 2000; no closed
    form): it must converge by shooting, in a few periods, with at least one stop per cycle."""
    t0 = time.perf_counter()
    ss = fj.CoulombOscillator(slip_force=0.98, force_amplitude=1.0, omega=1.0 + delta).steady_state()
    assert time.perf_counter() - t0 < SECONDS
    assert ss.converged, ss.message
    assert ss.periods < 40 and ss.stops_per_cycle >= 1
