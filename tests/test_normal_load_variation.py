"""Dovetail flanks whose slip limit follows the normal load in the marched dynamics
(``DovetailRoot(normal_load_variation=True)``): N = kn max(N0/kn - n.u, 0) with lift-off.

References: the displacement-driven :class:`DrivenDovetail` (an independent implementation: the
exact return map of each flank along a path, with lift-off), the energy balance of the exact
march, and the limiting case of flanks whose normals do not see the motion (flank angle 0 and a
purely tangential root: the normal loads stay N0, so the model is the frozen one)."""
import math
from collections import Counter

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.solvers.marcher import search
from frictionjoint.solvers.marcher.events import EventLog, Marcher

G, MU, KN, KT, A = math.radians(40.0), 0.3, 1e6, 8e5, 0.005


def _root(rocking=False, **kw):
    args = dict(flank_angle=G, friction_coefficient=MU, normal_stiffness=KN, tangential_stiffness=KT,
                tangential_dof="X", radial_dof="Y", normal_load_variation=True)
    if rocking:
        args.update(rocking_dof="theta", flank_half_width=A)
    args.update(kw)
    return fj.DovetailRoot(1000.0, **args)


def _system(rocking=False, omega=2000.0, fx=900.0, fy=500.0, **kw):
    """A root block on its flanks, shaken hard enough to slip, lift off and close again."""
    names = ["X", "Y", "theta"] if rocking else ["X", "Y"]
    mass = [0.2, 0.2, 2e-5][:len(names)]
    st = fj.LinearStructure(np.diag(mass), np.zeros((len(names), len(names))),
                            np.diag([2.0, 2.0, 1e-4][:len(names)]), dof_names=names)
    root = _root(rocking, **kw)
    exc = [fj.HarmonicForce("X", fx), fj.HarmonicForce("Y", fy, phase=0.7)]
    if rocking:
        exc.append(fj.HarmonicForce("theta", 2.0, phase=1.9))
    return fj.FrictionSystem(st, [root], omega=omega, excitation=exc), root


def _march_samples(sysm, t_end, jit=True):
    """March; at 4 points of every closed-form piece (its end among them) the root coordinates
    and each flank's friction and normal force, from the march's own state."""
    m = Marcher(sysm)
    m.jit = jit and search.ENABLED
    log = EventLog()
    state = m.initial_state(np.zeros(sysm.n_dof), np.zeros(sysm.n_dof), log=log)
    out = []

    def on(itv, tau_end):
        taus = np.linspace(0.0, tau_end, 5)[1:]
        x, _ = itv.state(taus)
        w = np.repeat(itv.w[:, None], taus.size, axis=1)
        pat = itv.pattern
        if pat.has_slip_j:
            w[pat.slip_j] = pat.slip_j_dir @ x - pat.slip_j_off[:, None]
        t = sysm.slider_stiffness[:, None] * (sysm.slider_direction @ x - w)
        n = sysm.normal_loads(x)
        for k in range(taus.size):
            out.append((itv.t0 + taus[k], x[:, k].copy(), t[:, k].copy(), n[:, k].copy()))

    m.march(state, t_end, log=log, on_interval=on)
    return out, Counter(log.kind), state


@pytest.mark.parametrize("rocking", [False, True])
def test_marcher_equals_driven_dovetail_on_its_path(rocking):
    """The marched flanks and DrivenDovetail driven along the marched root path (sampled inside
    every piece, so no status change falls between two samples) agree to 1e-10 of N0 in the
    friction and normal forces, through slips, sticks, lift-offs and closures."""
    sysm, root = _system(rocking)
    samples, kinds, _ = _march_samples(sysm, 10 * 2 * math.pi / sysm.omega)
    assert kinds["lift-off"] >= 5 and kinds["slip"] >= 5 and kinds["stick"] >= 2
    assert kinds["closure"] + kinds["slip"] >= kinds["lift-off"]  # every lift-off but the last closes
    drv = root.driven(normal_load_variation=True)
    err = 0.0
    for _, x, t, n in samples:
        drv.update(x)
        err = max(err, float(np.max(np.abs(drv.friction_force - t))), float(np.max(np.abs(drv.normal_force - n))))
    assert err <= 1e-10 * root.static.normal_force


@pytest.mark.parametrize("rocking, damping", [(False, 0.0), (True, 0.0), (True, 40.0)])
def test_energy_balance(rocking, damping):
    """work = stored change + friction + viscous dissipation to 1e-9 of the work done, with the
    contacts' springs unilateral (their energy kn max(a, 0)^2 / 2) and their dashpots off while open;
    friction dissipation int mu N |w'| over the slipping pieces."""
    sysm, _ = _system(rocking, normal_damping=damping)
    r = fj.simulate(sysm, 10 * 2 * math.pi / sysm.omega, record=("x", "energy"))
    scale = float(np.max(np.abs(r.work)))
    assert r.dissipated_friction[-1] > 0.1 * scale
    if damping:
        assert r.dissipated_viscous[-1] > 1e-4 * scale
    assert float(np.max(np.abs(r.energy_residual()))) <= 1e-9 * scale


def test_compiled_and_numpy_marches_agree():
    sysm, _ = _system(True)
    if not search.ENABLED:
        pytest.skip("numba not available: one path only")
    period = 2 * math.pi / sysm.omega
    a, ka, sa = _march_samples(sysm, 4 * period, jit=True)
    b, kb, sb = _march_samples(sysm, 4 * period, jit=False)
    assert ka == kb
    scale = float(np.max(np.abs([s[1] for s in a])))
    # compiled and NumPy kernels: rounding, carried through 4 periods of events (measured 3.6e-12
    # of the scale); 1e-9 is over 100x that
    assert np.max(np.abs(sa.x - sb.x)) <= 1e-9 * scale

    def ends(samples):  # piece ends, pieces shorter than 1e-12 of the period merged (the two paths'
        t = np.array([s[0] for s in samples][3::4])  # event times differ by rounding, which may
        return t[np.concatenate([np.diff(t) > 1e-12 * period, [True]])]  # leave a 1e-15 s piece in one
    ta, tb = ends(a), ends(b)
    # rounding of the event times (measured 5.4e-12 of the period); 1e-9 is over 100x that
    assert ta.size == tb.size and np.max(np.abs(ta - tb)) <= 1e-9 * period


def test_normals_blind_to_the_motion_give_the_frozen_model():
    """Flank angle 0 and only the tangential root DOF: the flank normals are radial, the motion
    never changes N, and the marched response with normal-load variation is the frozen one's."""
    st = fj.LinearStructure([[0.2]], [[1e4]], [[2.0]], dof_names=["X"])
    out = []
    for vary in (False, True):
        root = fj.DovetailRoot(1000.0, flank_angle=0.0, friction_coefficient=MU, normal_stiffness=KN,
                               tangential_stiffness=KT, tangential_dof="X", normal_load_variation=vary)
        sysm = fj.FrictionSystem(st, [root], omega=2000.0, excitation=[fj.HarmonicForce("X", 400.0)])
        out.append(fj.simulate(sysm, 5 * 2 * math.pi / 2000.0, record=("x", "friction_force")))
    assert np.max(np.abs(out[0].x - out[1].x)) <= 1e-12 * np.max(np.abs(out[0].x))
    assert np.max(np.abs(out[0].friction_force - out[1].friction_force)) <= 1e-10 * MU * 500.0


def test_initially_open_flank_and_bad_input():
    sysm, root = _system()
    gap = root.static.normal_force / KN
    # a root pushed inward (against Fc) beyond both flanks' static approach starts with both open
    x0 = np.array([0.0, -2.0 * gap / math.cos(G)])
    state = Marcher(sysm).initial_state(x0, np.zeros(2))
    assert list(state.status) == [2, 2]
    with pytest.raises(ParameterError, match="flat flanks"):
        fj.DovetailRoot(1000.0, G, MU, KN, flank_contact=lambda n: None, tangential_dof="X",
                        normal_load_variation=True)
    with pytest.raises(ParameterError, match="normal_load_variation"):
        _root(normal_load_variation=0.5)  # a switch is True/False or 1/0 (check_bool); 0.5 is neither


def test_periodic_orbit_with_lift_off():
    """Shooting on the piecewise-linear dynamics with lift-off: the exact monodromy Jacobian (with
    the saltation of closures and lift-offs) and finite differences find the same orbit, and over
    one period of it the friction dissipation the orbit reports equals that of the energy record of
    a march from its state (int mu N |w'|), whose balance closes."""
    sysm, _ = _system(False, fx=400.0, fy=200.0)
    r = fj.solvers.marcher.periodic_response(sysm)
    assert r.converged and r.events.count("lift-off") >= 1 and r.events.count("closure") >= 1
    fd = fj.solvers.marcher.periodic_response(sysm, jacobian="fd")
    assert fd.converged
    assert np.max(np.abs(fd.amplitude - r.amplitude)) <= 1e-9 * np.max(r.amplitude)
    n = sysm.n_dof
    period = 2 * math.pi / sysm.omega
    z = r.state
    t_s = r.section_time
    w0 = fj.solvers.marcher.steady._PeriodMap(sysm, Marcher(sysm), t_s).state(z).w
    e = fj.simulate(sysm, t_s + period, z[:n], z[n:2 * n], w0, t0=t_s, record=("x", "energy"))
    assert abs(e.dissipated_friction[-1] - r.dissipated_per_cycle) <= 1e-9 * r.dissipated_per_cycle
    assert abs(e.energy_residual()[-1]) <= 1e-9 * r.dissipated_per_cycle
    assert np.max(np.abs(e.x[:, -1] - z[:n])) <= 1e-9 * np.max(np.abs(z[:n]))
