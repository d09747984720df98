"""CoulombOscillator against Den Hartog's closed form (stop-free) and its own consistency.

Reference: Den Hartog (1931), closed form in frictionjoint.analytic (itself checked against an
independent solve_ivp brute force in tests/test_analytic.py). First-harmonic phase: closed-form
Fourier integrals of Den Hartog's waveform.
"""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.analytic import den_hartog

RTOL_EXACT = 1e-9  # exact methods: relative amplitude and phase error

GRID = [(r, f) for r in (0.8, 0.9, 1.1, 1.5, 2.0) for f in (0.1, 0.3, 0.5, 0.7)
        if den_hartog(r, f).regime == "stop-free"]


def test_grid_is_mostly_stop_free():
    assert len(GRID) >= 17  # r=1.5 and 2.0 at f=0.7 have stops


@pytest.mark.parametrize("r,f", GRID)
def test_den_hartog_stop_free(r, f):
    osc = fj.CoulombOscillator(mass=1.0, stiffness=1.0, slip_force=f, force_amplitude=1.0, omega=r)
    ss = osc.steady_state()
    ref = den_hartog(r, f)
    assert ss.converged and ss.unique, ss.message
    assert ss.stops_per_cycle == 0
    assert abs(ss.amplitude / ref.amplitude - 1) <= RTOL_EXACT
    assert abs(ss.phase - ref.harmonic_phase) <= RTOL_EXACT * abs(ref.harmonic_phase)
    assert abs(ss.harmonic_amplitude / ref.harmonic_amplitude - 1) <= RTOL_EXACT
    # dissipation per cycle is exactly 4 F X (Den Hartog)
    assert abs(ss.dissipated_per_cycle / (4 * f * ref.amplitude) - 1) <= RTOL_EXACT


@pytest.mark.parametrize("mass,stiffness,force,base", [(2.0, 8.0, 3.0, 0.0), (0.5, 3.0, 0.0, 0.2),
                                                        (1.5, 6.0, 1.0, 0.1)])
def test_physical_units_and_base_excitation(mass, stiffness, force, base):
    """Base motion through the spring maps onto Den Hartog with P0 = P + k Y (seed)."""
    wn = math.sqrt(stiffness / mass)
    p0 = force + stiffness * base
    osc = fj.CoulombOscillator(mass=mass, stiffness=stiffness, slip_force=0.3 * p0,
                               force_amplitude=force, base_amplitude=base, omega=1.3 * wn)
    ss = osc.steady_state()
    ref = den_hartog(1.3, 0.3)
    assert abs(ss.amplitude / (ref.amplitude * p0 / stiffness) - 1) <= RTOL_EXACT
    assert abs(ss.phase - ref.harmonic_phase) <= RTOL_EXACT


def test_negative_force_amplitude_shifts_phase_by_pi():
    a = fj.CoulombOscillator(slip_force=0.3, force_amplitude=1.0, omega=1.5).steady_state()
    b = fj.CoulombOscillator(slip_force=0.3, force_amplitude=-1.0, omega=1.5).steady_state()
    assert abs(a.amplitude - b.amplitude) <= 1e-12
    assert abs(abs(a.phase - b.phase) - math.pi) <= 1e-10


def test_time_response_reaches_den_hartog_orbit():
    """A simulation started on the orbit stays on it (exact to rounding over 50 periods)."""
    r, f = 1.5, 0.3
    osc = fj.CoulombOscillator(slip_force=f, force_amplitude=1.0, omega=r)
    ss = osc.steady_state()
    x0, v0 = ss.initial_state[:2]
    t = osc.period * np.arange(51)
    tr = osc.simulate(t[-1], x0, v0, t_eval=t)
    assert np.max(np.abs(tr.x - x0)) <= 1e-10 * ss.amplitude
    assert np.max(np.abs(tr.v - v0)) <= 1e-10 * ss.amplitude * r
    # waveform against the closed form, at 200 points of one period
    ref = den_hartog(r, f)
    ts = np.linspace(0, osc.period, 200)
    tr = osc.simulate(osc.period, x0, v0, t_eval=ts)
    # Den Hartog's waveform is given against the force phase: x = X(phi), phi = w t
    xr = ref.waveform(r * ts)
    assert np.max(np.abs(tr.x - xr)) <= RTOL_EXACT * ref.amplitude


def test_unbounded_growth_at_resonance():
    """r = 1, F/P0 < pi/4: amplitude grows by (pi P0 - 4F)/k per period (DESIGN 3)."""
    ss = fj.CoulombOscillator(slip_force=0.5, force_amplitude=1.0, omega=1.0).steady_state()
    assert not ss.converged
    assert "grows without bound" in ss.message
    growth = float(ss.message.split("about ")[1].split()[0])
    assert abs(growth - (math.pi - 2.0)) <= 1e-4 * (math.pi - 2.0)


def test_resonance_with_high_friction_is_bounded():
    ss = fj.CoulombOscillator(slip_force=0.9, force_amplitude=1.0, omega=1.0).steady_state()
    assert ss.converged, ss.message
    assert ss.stops_per_cycle >= 2


@pytest.mark.parametrize("r", [0.5, 0.25])
def test_non_unique_family_is_reported(r):
    """r = 1/(2n): U = 0, a family of stop-free orbits with different offsets (DESIGN 3)."""
    ss = fj.CoulombOscillator(slip_force=0.05, force_amplitude=1.0, omega=r).steady_state()
    assert ss.converged
    assert not ss.unique
    assert "NOT UNIQUE" in ss.message


def test_permanent_stick():
    osc = fj.CoulombOscillator(slip_force=1.5, force_amplitude=1.0, omega=0.7)
    ss = osc.steady_state()
    assert ss.stuck and ss.converged
    assert ss.amplitude == 0.0 and ss.stops_per_cycle == 0
    osc = fj.CoulombOscillator(slip_force=1.5, force_amplitude=1.0, omega=0.7)
    tr = osc.simulate(10 * osc.period)
    assert len(tr.events) == 0 and np.all(tr.x == 0.0)
    # simulate runs on the closed-form kernel: the general marcher decomposed no configuration
    # (on the marcher, only the stuck one would have been built)
    assert osc._marcher.n_configurations == 0


@pytest.mark.parametrize("name,value", [
    ("mass", 0.0), ("mass", -1.0), ("mass", math.nan), ("stiffness", 0.0), ("stiffness", math.inf),
    ("slip_force", -0.1), ("slip_force", math.nan), ("omega", 0.0), ("omega", math.inf),
    ("omega", math.nan), ("damping", -1.0), ("force_amplitude", math.nan), ("base_amplitude", math.inf),
])
def test_invalid_input_names_parameter(name, value):
    with pytest.raises(fj.ParameterError, match=name):
        fj.CoulombOscillator(**{name: value})
    assert issubclass(fj.ParameterError, ValueError)


def test_invalid_simulate_arguments():
    osc = fj.CoulombOscillator(slip_force=0.3, force_amplitude=1.0, omega=0.8)
    with pytest.raises(fj.ParameterError, match="t_end"):
        osc.simulate(-1.0)
    with pytest.raises(fj.ParameterError, match="x0"):
        osc.simulate(1.0, x0=math.nan)
    with pytest.raises(fj.ParameterError, match="record"):
        osc.simulate(1.0, record=("x", "acceleration"))
    with pytest.raises(fj.ParameterError, match="t_eval"):
        osc.simulate(1.0, t_eval=[0.0, 2.0])


def test_record_only_what_is_asked():
    osc = fj.CoulombOscillator(slip_force=0.3, force_amplitude=1.0, omega=0.8)
    tr = osc.simulate(5.0, record=("x",))
    assert tr.x is not None and tr.v is None and tr.friction_force is None and tr.work is None


@pytest.mark.parametrize("r,f,per_period", [(1.5, 0.3, {"normal stop": 2}),
                                            (0.45, 0.5, {"stick": 2, "slip": 2})])
def test_zero_duration_stops_do_not_chatter(r, f, per_period):
    """Over 200 steady periods: exactly the expected events per period, strictly increasing times
    (a zero-duration stop is decided from the force, never by tiny steps)."""
    osc = fj.CoulombOscillator(slip_force=f, force_amplitude=1.0, omega=r)
    ss = osc.steady_state()
    x0, v0 = ss.initial_state[:2]
    tr = osc.simulate(200 * osc.period, x0, v0, t_eval=[0.0, 200 * osc.period])
    times = np.array(tr.events.time)
    assert np.all(np.diff(times) > 1e-6 * osc.period)
    for kind, n in per_period.items():
        assert tr.events.count(kind) == 200 * n
    assert len(tr.events) == 200 * sum(per_period.values())


@pytest.mark.parametrize("f,r,c", [(0.3, 0.8, 0.0), (0.3, 1.5, 0.0), (0.6, 2.0, 0.0), (0.5, 0.45, 0.0),
                                   (0.3, 0.8, 0.1), (0.1, 1.2, 0.05)])
def test_floquet_multipliers_exact_and_stable(f, r, c):
    """steady_state's multipliers come from the SDOF kernel's exact monodromy; they equal the
    eigenvalues of the general path's finite-difference Jacobian (periodic_response) to its
    accuracy, and every one of these damped (viscously or by friction) orbits is stable."""
    osc = fj.CoulombOscillator(slip_force=f, force_amplitude=1.0, omega=r, damping=c)
    res = osc.steady_state()
    assert res.converged and res.stable
    assert np.all(np.abs(res.floquet_multipliers) < 1.0)
    exact = osc.monodromy(res.section_time, float(res.state[0]), float(res.state[1]))
    assert exact is not None
    general = fj.periodic_response(osc.system, res.initial_state[0], res.initial_state[1])
    a = np.sort(np.abs(np.linalg.eigvals(exact)))
    b = np.sort(np.abs(general.floquet_multipliers))
    assert np.max(np.abs(a - b)) <= 1e-6


def test_unique_linear_orbit_is_not_stable_without_damping():
    """No friction and no damping: the free vibration neither grows nor decays, every multiplier
    is on the unit circle (neutral), so the orbit is not (asymptotically) stable."""
    osc = fj.CoulombOscillator(slip_force=0.0, force_amplitude=1.0, omega=0.8)
    res = osc.steady_state()
    assert res.converged and res.stable is False
    assert np.allclose(np.abs(res.floquet_multipliers), 1.0, rtol=0, atol=1e-12)
