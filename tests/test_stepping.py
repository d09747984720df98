"""OscillatorRun (the stepping object behind CoulombOscillator.fmu and the sweep drivers) runs on
the closed-form single-DOF kernel: checked against the general n-DOF marcher (the reference) on the
same system, and a snapshot is the complete state, so a restored run continues bit for bit."""
import itertools
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.solvers.marcher.events import EventLog, Marcher
from frictionjoint.solvers.marcher.propagator import Observables
from frictionjoint.solvers.marcher.response import displacement_observables, piece_fourier, piece_peaks, simulate
from frictionjoint.stepping import OscillatorRun


def test_restore_mid_run_continues_bit_identically():
    for f, w, x0 in itertools.product((0.1, 0.5, 0.7), (0.45, 1.5, 2.5), (0.0, 50.0)):
        p = dict(slip_force=f, force_amplitude=1.0, omega=w, x0=x0, harmonics=True)
        a = OscillatorRun(p)
        a.advance(7.3)
        snap = a.snapshot()
        v_scale = a.v_scale
        a.hold(0.2)
        a.advance(41.0)  # the velocity scale (the event tolerances) and the held force move on
        a.restore(snap)
        assert a.v_scale == v_scale
        a.advance(60.0)
        b = OscillatorRun(p)
        b.advance(7.3)
        b.advance(60.0)
        for name in ("x", "v", "friction_force", "dissipated_energy", "event_count", "stop_count", "stuck",
                     "peak_x", "x_cos_integral", "friction_force_sin_integral"):
            assert a.output(name) == b.output(name), (f, w, x0, name)


CASES = [dict(slip_force=0.3, omega=0.8), dict(slip_force=0.5, omega=0.5, damping=0.1),
         dict(slip_force=0.6, omega=2.0, base_amplitude=0.2), dict(slip_force=0.2, omega=1.3, x0=3.0, v0=-1.0)]


@pytest.mark.parametrize("case", CASES)
def test_kernel_run_matches_the_general_marcher(case):
    """Steps of unequal length with a held force that changes between them: states to 1e-12,
    events per kind, dissipation, peak and the exact Fourier integrals of x and of the friction
    force against the n-DOF marcher with the same held forces and pieces evaluated on its side."""
    p = dict(force_amplitude=1.0, harmonics=True, **case)
    run = OscillatorRun(p)
    osc = fj.CoulombOscillator(**{k: v for k, v in p.items() if k not in ("x0", "v0", "harmonics")})
    m = Marcher(osc.system)
    log = EventLog()
    st = m.initial_state([p.get("x0", 0.0)], [p.get("v0", 0.0)], log=log)
    amp = np.abs(st.x).copy()
    ints = np.zeros((3, 2))
    vel = Observables([[0.0]], [[1.0]], [[0.0]], [0.0])
    w = osc.omega
    diss = [0.0]

    def on(itv, tau):
        if itv.status[0] != 0:
            diss[0] += osc.slip_force * abs(float(itv.state(tau)[0][0, 0]) - float(itv.x0[0]))
        if tau > 0:
            piece_peaks(itv, tau, amp)
            for row, obs in enumerate((displacement_observables(1), m.force_observables(itv), vel)):
                c, s = piece_fourier(itv, tau, w, itv.reduce(obs))
                ints[row] += [float(c[0]), float(s[0])]
    t = 0.0
    for k, (dt, force) in enumerate(zip((3.1, 0.7, 11.0, 5.3, 20.0), (0.0, 0.25, 0.25, -0.4, 0.0))):
        run.hold(force)
        m.set_held_force([force])
        t += dt
        run.advance(t)
        m.march(st, t, log, on_interval=on)
        scale = max(1.0, abs(float(st.x[0])))
        assert abs(run.output("x") - float(st.x[0])) <= 1e-12 * scale
        assert abs(run.output("v") - float(st.v[0])) <= 1e-12 * scale * max(1.0, w)
        assert run.output("stuck") == bool(st.status[0] == 0)
        itv = m.interval(st)
        force_now = float(itv.start_values(itv.reduce(m.force_observables(itv)))[0][0])
        assert abs(run.output("friction_force") - force_now) <= 1e-12 * max(1.0, abs(force_now))
    assert run.output("event_count") == len(log)
    assert run.output("stop_count") == log.count("stick")
    assert run.output("dissipated_energy") == pytest.approx(diss[0], rel=1e-11, abs=1e-13)
    assert run.output("peak_x") == pytest.approx(float(amp[0]), rel=1e-12)
    for row, name in enumerate(("x", "friction_force", "v")):
        for col, which in enumerate(("cos", "sin")):
            assert run.output(f"{name}_{which}_integral") == pytest.approx(ints[row, col], rel=1e-10, abs=1e-11 * t)


@pytest.mark.parametrize("start_time", [0.0, 2.7])
def test_start_on_orbit(start_time):
    """start_on_orbit: the run starts on the steady state (that of CoulombOscillator.steady_state,
    marched to the start time), one period later it is back to 1e-12, and the monodromy output
    has the steady state's Floquet multipliers."""
    p = dict(slip_force=0.3, force_amplitude=1.0, omega=0.8, start_on_orbit=True, harmonics=True)
    run = OscillatorRun(p, start_time=start_time)
    assert run.output("orbit_found")
    osc = fj.CoulombOscillator(slip_force=0.3, force_amplitude=1.0, omega=0.8)
    ss = osc.steady_state()
    ref = osc.simulate(start_time, *ss.initial_state[:2], t_eval=[start_time], record=("x", "v")) \
        if start_time else None
    x_ref = ss.initial_state[0] if ref is None else ref.x[-1]
    assert abs(run.output("x") - x_ref) <= 1e-11 * ss.amplitude
    x0, v0 = run.output("x"), run.output("v")
    run.advance(start_time + osc.period)
    assert abs(run.output("x") - x0) <= 1e-12 * ss.amplitude
    assert abs(run.output("v") - v0) <= 1e-12 * ss.amplitude * osc.omega
    jac = np.array([[run.output("monodromy_xx"), run.output("monodromy_xv")],
                    [run.output("monodromy_vx"), run.output("monodromy_vv")]])
    got = np.sort_complex(np.linalg.eigvals(jac))
    assert np.max(np.abs(got - np.sort_complex(ss.floquet_multipliers))) <= 1e-12
    assert run.output("peak_x") == pytest.approx(ss.amplitude, rel=1e-12)
    off = OscillatorRun(dict(p, start_on_orbit=False))
    assert not off.output("orbit_found") and off.output("monodromy_xx") == 0.0


def test_start_on_orbit_under_a_held_force():
    """A held force F_h only moves the rest position: the orbit started on is the unforced one
    shifted by F_h / k, and one period later the run is back on it."""
    p = dict(slip_force=0.3, force_amplitude=1.0, omega=0.8, stiffness=2.0, start_on_orbit=True)
    free = OscillatorRun(p)
    held = OscillatorRun(p, force=0.5)
    assert held.output("orbit_found")
    assert abs(held.output("x") - (free.output("x") + 0.25)) <= 1e-12
    x0, v0 = held.output("x"), held.output("v")
    held.advance(2 * math.pi / 0.8)
    assert abs(held.output("x") - x0) <= 1e-12 and abs(held.output("v") - v0) <= 1e-12


@pytest.mark.parametrize("m, k", [(1.0, 1.0), (1e-3, 1e3), (1e3, 1e-3)])
def test_quasi_static_turning_point_marches(m, k):
    """r = 1e-3, F/P0 = 1e-6 from Den Hartog's turning point, where the holding force is within
    rounding of F at every period's end: the kernel's stick/slip rules used to cycle there and
    raise 'no consistent stick/slip status' (they now stay stuck on such a cycle, as
    Marcher.settle does). States agree with the general marcher to 1e-14 of the amplitude."""
    w = 1e-3 * math.sqrt(k / m)
    osc = fj.CoulombOscillator(mass=m, stiffness=k, slip_force=1e-6, force_amplitude=1.0, omega=w)
    x0, v0 = osc.initial_guess()
    run = OscillatorRun(dict(mass=m, stiffness=k, slip_force=1e-6, force_amplitude=1.0, omega=w, x0=x0, v0=v0))
    t = osc.period * np.arange(1, 13) / 4
    ref = simulate(osc.system, t[-1], x0, v0, t_eval=t, record=("x", "v"))
    scale = float(np.max(np.abs(ref.x)))
    for i, tk in enumerate(t):
        run.advance(tk)
        # the same exact march in steps: rounding (measured 3.5e-15 of the scale); 1e-12 is over 100x
        assert abs(run.output("x") - ref.x[0, i]) <= 1e-12 * scale


def test_general_marcher_restart_from_a_copy_is_bit_identical():
    """The general marcher's state (MarchState) carries its velocity scale: a copy taken mid-run
    and marched on by a fresh marcher ends bit for bit where the uninterrupted run ends (the
    velocity scale sets the zero band of the velocity events; a fresh marcher's is 0: restarted
    at 4.0 periods without it, this run ends 1.4e-15 m away, measured)."""
    n = 4
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    sysm = fj.FrictionSystem(fj.LinearStructure.chain(n, damping=0.02 * w1),
                             [fj.Jenkins(0.5 * w1 ** 2, 0.002, dof=3), fj.CoulombSlider(0.001, dof=1)],
                             omega=0.9 * w1, excitation=[fj.HarmonicForce(n - 1, 0.01)])
    period = 2 * math.pi / sysm.omega
    a = Marcher(sysm)
    st = a.initial_state(np.zeros(n), np.zeros(n))
    a.march(st, 4.0 * period, EventLog())
    saved = st.copy()
    assert saved.v_scale is not None and saved.v_scale > 0
    log_a, log_b = EventLog(), EventLog()
    a.march(st, 7.1 * period, log_a)
    b = Marcher(sysm)
    b.march(saved, 7.1 * period, log_b)
    assert len(log_a) > 10 and log_a.time == log_b.time and log_a.kind == log_b.kind
    for name in ("x", "v", "w", "status"):
        assert np.array_equal(getattr(st, name), getattr(saved, name)), name
    assert st.t == saved.t and st.v_scale == saved.v_scale
