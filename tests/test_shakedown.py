"""Shakedown and cyclic slip of uncoupled discrete frictional systems (frictionjoint.shakedown).

References: the seed ``frictional_contacts_periodic_loading_shakedown`` -- frictional Melan
theorem (Klarbring et al. 2007, seed section 2.5) and Andersson et al. (2014, seed section 2.7):
for B = 0 the steady dissipation per cycle does not depend on the initial slips. Independent
checks: the single-node closed form derived below, the library's exact play operator
(frictionjoint.elements.driven.DrivenSliders) and Iwan closed form, and a backward-Euler
catch-up scheme whose K-norm projection is done by enumerating the faces of the box.
"""
import itertools

import numpy as np
import pytest
from hypothesis import assume, given, settings, strategies as st

import frictionjoint as fj
from frictionjoint.elements.driven import DrivenSliders
from frictionjoint.shakedown import (PeriodicLoad, QuasiStaticFrictionSystem, melan_check,
                                     shakedown_check)

EXACT = 1e-12    # relative: closed forms, play operator, energy balance, subdivision
ANDERSSON = 1e-9  # relative: steady dissipation from different initial slips (the bound)
HYPO = settings(max_examples=12, deadline=None)


def random_case(seed, n, m, amplitude):
    """Random SPD stiffness (coupled nodes), sampled load of mean ~1 N and the given amplitude,
    normal forces in [1, 3] N varying in time (B = 0: they do not depend on the slips)."""
    rng = np.random.default_rng(seed)
    a = rng.normal(size=(n, n))
    k = a @ a.T / n + np.eye(n) * rng.uniform(0.05, 1.0)
    t = np.sort(rng.uniform(0.0, 1.0, m))
    t[0] = 0.0
    q = rng.normal(size=n) + amplitude * rng.normal(size=(m, n))
    normal = 2.0 + rng.uniform(-1.0, 1.0, (m, n))
    return k, PeriodicLoad(t, q, normal, 1.0), rng


def random_admissible_slip(system, load, rng):
    """Slips at t = 0 whose forces lie anywhere inside the friction bound."""
    g0 = system.friction_coefficient * load.normal[0]
    return np.linalg.solve(system.stiffness, load.tangential[0] - g0 * rng.uniform(-1.0, 1.0, g0.size))


def energy_scale(system, load):
    g = system.friction_coefficient * load.normal
    return float(np.max(np.sum(g * np.linalg.solve(system.stiffness, g.T).T, axis=1)))


# --- (3) single node: closed form -------------------------------------------------------------

@pytest.mark.parametrize("amplitude", [10.0, 20.0, 35.0, 100.0])
def test_single_node_closed_form(amplitude):
    """One node (a Jenkins element driven through its spring): q = q_ext - k w, |q| <= F_s.

    Steady state (derivation): once q_ext has swept both extremes, w oscillates between
    (q_max - F_s)/k and (q_min + F_s)/k, each sweep slipping 2 (Q_a - F_s)/k at force F_s, so
    D = 4 F_s (Q_a - F_s)/k = 4 F_s (A - F_s/k), A = Q_a/k the welded displacement amplitude,
    for Q_a > F_s; D = 0 (shakedown, Melan safe) for Q_a <= F_s.
    """
    k, f, normal, mean = 3e4, 0.4, 50.0, 5.0
    fs = f * normal
    load = PeriodicLoad.from_function(lambda t: [mean + amplitude * np.sin(2 * np.pi * t / 0.02)],
                                      lambda t: [normal], period=0.02, n_samples=16)
    system = QuasiStaticFrictionSystem([[k]], f)
    res = shakedown_check(system, load, initial_slip=[0.3 * fs / k])
    exact = 4.0 * fs * (amplitude - fs) / k if amplitude > fs else 0.0
    assert res.success and res.steady_cycle <= 1
    assert abs(res.steady_dissipation - exact) <= EXACT * max(exact, fs * fs / k)
    assert res.shakedown == (amplitude <= fs) == res.melan.safe
    assert abs(res.melan.margin - (1.0 - amplitude / fs)) <= EXACT  # per node interval rule


# --- (1) below the Melan limit: shakedown from every initial state ------------------------------

@pytest.mark.parametrize("seed", [3, 5, 14, 28])
def test_below_melan_limit_shakes_down(seed):
    """Slip stops after a transient from random initial slips; the energy dissipated on the way is
    bounded by Melan's estimate ``(w0 - w_r).K(w0 - w_r) / (2 margin)`` (from
    d/dt |w - w_r|_K^2 / 2 = (q_r - q).w' <= -margin sum g |w'|)."""
    k, load, rng = random_case(seed, n=4, m=8, amplitude=0.15)
    system = QuasiStaticFrictionSystem(k, 0.3)
    melan = melan_check(system, load)
    assert melan.safe and melan.margin > 0.1
    scale = energy_scale(system, load)
    finite = 0
    for _ in range(6):
        w0 = random_admissible_slip(system, load, rng)
        res = shakedown_check(system, load, w0, melan=False)
        assert res.success and res.shakedown
        # shakedown_check's own stopping rule (rtol = 1e-12 of this energy scale, which it computes
        # by cho_solve and this test by solve: the same to rounding), not a measured bound -- a
        # cycle stops anywhere below it (seen 2.9e-12 of 3.3e-12); 1.001e-12 takes the rounding
        assert res.last_cycle.dissipation <= 1.001e-12 * scale
        d = w0 - melan.residual_slip
        assert res.dissipation.sum() <= (d @ k @ d) / (2.0 * melan.margin) * (1 + EXACT)
        finite += res.last_cycle.dissipation <= 1e-15 * scale  # slip stopped at once (rounding)
    assert finite >= 1  # some stop after finitely many cycles; others decay geometrically


@pytest.mark.parametrize("amplitude", [0.1, 0.3, 0.6, 1.0, 2.0])
def test_melan_verdict_agrees_with_march(amplitude):
    """linprog's safe-state verdict = what the march finds; its margin = the per-node interval rule
    (every residual force is reachable with an SPD K)."""
    k, load, rng = random_case(11, n=3, m=10, amplitude=amplitude)
    system = QuasiStaticFrictionSystem(k, 0.3)
    res = shakedown_check(system, load, random_admissible_slip(system, load, rng), n_cycles=400)
    g = 0.3 * load.normal
    q = load.tangential
    # node i: the largest mu with max_t (q - (1-mu) g) <= min_t (q + (1-mu) g), by bisection
    mu_nodes = []
    for i in range(3):
        lo, hi = -50.0, 1.0
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            ok = np.max(q[:, i] - (1 - mid) * g[:, i]) <= np.min(q[:, i] + (1 - mid) * g[:, i])
            lo, hi = (mid, hi) if ok else (lo, mid)
        mu_nodes.append(lo)
    assert abs(res.melan.margin - min(mu_nodes)) <= 1e-9
    assert res.success and res.shakedown == res.melan.safe
    q_r = q - (k @ res.melan.residual_slip)
    assert np.all(np.abs(q_r) <= (1 - res.melan.margin) * g + 1e-9)


# --- (2) above the limit: steady dissipation independent of the initial slips ------------------

@HYPO
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(2, 5), m=st.integers(2, 10),
       amplitude=st.floats(0.3, 3.0), f=st.floats(0.1, 0.8))
def test_andersson_same_steady_dissipation(seed, n, m, amplitude, f):
    """Random SPD K, loads and initial slips: the same steady dissipation per cycle (<= 1e-9
    relative) and the same slip velocities (slips differ by a constant vector)."""
    k, load, rng = random_case(seed, n, m, amplitude)
    system = QuasiStaticFrictionSystem(k, f)
    melan = melan_check(system, load)
    assume(melan.margin < -0.02)  # clearly above the shakedown limit
    runs = [shakedown_check(system, load, random_admissible_slip(system, load, rng), n_cycles=500, melan=False)
            for _ in range(3)]
    assert all(r.success and r.status == "cyclic slip" for r in runs)
    d = np.array([r.steady_dissipation for r in runs])
    assert np.ptp(d) <= ANDERSSON * d.max()
    slip_scale = np.max(np.abs(np.linalg.solve(k, (f * load.normal).T)))
    for r in runs[1:]:
        diff = r.last_cycle.slip_at_samples - runs[0].last_cycle.slip_at_samples
        assert np.max(np.abs(diff - diff[0])) <= ANDERSSON * slip_scale


# --- exactness of the march -----------------------------------------------------------------------

@HYPO
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 5), m=st.integers(1, 8),
       amplitude=st.floats(0.1, 3.0))
def test_energy_balance_and_subdivision(seed, n, m, amplitude):
    """work = stored energy change + dissipation per cycle, and splitting every linear load piece
    into three gives the same march (the solution between events is exact, not a time step)."""
    k, load, rng = random_case(seed, n, m, amplitude)
    system = QuasiStaticFrictionSystem(k, 0.4)
    w0 = random_admissible_slip(system, load, rng)
    scale = energy_scale(system, load)
    cycles = system.run(load, w0, 3)
    for c in cycles:
        assert c.dissipation >= 0.0
        assert abs(c.work - c.stored_energy_change - c.dissipation) <= EXACT * scale
    t, q, p = load.closed()
    s = np.linspace(0.0, 1.0, 4)[:-1]
    fine = PeriodicLoad(np.concatenate([t[i] + s * (t[i + 1] - t[i]) for i in range(m)]),
                        np.vstack([q[i] + np.outer(s, q[i + 1] - q[i]) for i in range(m)]),
                        np.vstack([p[i] + np.outer(s, p[i + 1] - p[i]) for i in range(m)]), 1.0)
    w = w0
    for c in cycles:
        cf = system.run_cycle(fine, w)
        w = cf.slip_end
        assert abs(cf.dissipation - c.dissipation) <= EXACT * scale
        assert np.max(np.abs(cf.slip_at_samples[::3] - c.slip_at_samples)) <= EXACT * max(1.0, np.max(np.abs(w0)))


def _catch_up(k, w, q_trial, g):
    """K^-1-norm projection of q_trial onto the box |q| <= g, by enumerating free/upper/lower sets
    (the convex QP's minimum over the feasible stationary points). Returns the new slips."""
    kinv = np.linalg.inv(k)
    n = w.size
    best, best_q = np.inf, None
    for faces in itertools.product((0, 1, -1), repeat=n):
        faces = np.array(faces)
        fixed = faces != 0
        q = q_trial.copy()
        q[fixed] = faces[fixed] * g[fixed]
        free = ~fixed
        if free.any():
            rhs = kinv[np.ix_(free, fixed)] @ (q[fixed] - q_trial[fixed])
            q[free] = q_trial[free] - np.linalg.solve(kinv[np.ix_(free, free)], rhs)
        if np.any(np.abs(q) > g * (1 + 1e-12)):
            continue
        val = (q - q_trial) @ kinv @ (q - q_trial)
        if val < best:
            best, best_q = val, q
    return w + kinv @ (q_trial - best_q)


def test_backward_euler_converges_to_the_exact_march():
    """Backward Euler (catch-up) with 50 and 509 steps per load piece approaches the exact march
    (first order: its error is at most the slip between the last grid point and each event),
    while one projection per piece misses the slip that coupling stops mid-piece."""
    k, load, _ = random_case(31, n=2, m=4, amplitude=1.5)
    system = QuasiStaticFrictionSystem(k, 0.5)
    exact = system.run_cycle(load, [0.0, 0.0]).slip_at_samples
    tc, qc, pc = load.closed()
    errors = []
    for sub in (1, 50, 509):
        w, err = np.zeros(2), 0.0
        for i in range(4):
            for j in range(1, sub + 1):
                s = j / sub
                q_ext = qc[i] + s * (qc[i + 1] - qc[i])
                g = 0.5 * (pc[i] + s * (pc[i + 1] - pc[i]))
                w = _catch_up(k, w, q_ext - k @ w, g)
            err = max(err, float(np.max(np.abs(w - exact[i + 1]))))
        errors.append(err)
    # measured: 5.6e-2, 2.2e-3, 1.4e-4 (slips ~ 1 m)
    assert errors[0] > 1e-2
    assert errors[2] < errors[1] / 3.0
    assert errors[2] < 1e-3


# --- (6) the library's displacement-driven sliders: uncoupled diagonal case ---------------------

def test_driven_iwan_same_steady_dissipation():
    """A discrete Segalman Iwan (DrivenSliders, the exact play operator) driven by a periodic
    displacement from random initial slider positions: the same dissipation per cycle from the
    second cycle on, equal to Iwan's closed form, and to QuasiStaticFrictionSystem with the
    diagonal K = diag(k_i), q_ext = k u(t), f N_i = F_i."""
    iw = fj.Iwan.segalman(slip_force=2.0, stiffness=1e5, chi=-0.5, beta=0.3, n_sliders=20)
    k, fsl = (np.array(c) for c in zip(*iw.sliders_table))
    u_amp = 0.6 * iw.displacement(0.99 * iw.slip_force)  # some sliders never slip (permanent stick)
    period, m = 0.01, 24
    times = period * np.arange(m) / m
    u = u_amp * np.sin(2 * np.pi * times / period)
    exact = iw.dissipation_per_displacement_cycle(u_amp)
    assert np.any(fsl / k > u_amp)
    system = QuasiStaticFrictionSystem(np.diag(k), 1.0)
    load = PeriodicLoad(times, np.outer(u, k), np.tile(fsl, (m, 1)), period)
    rng = np.random.default_rng(7)
    steady = []
    for _ in range(5):
        w0 = u[0] + (fsl / k) * rng.uniform(-1, 1, k.size)
        sliders = DrivenSliders(k, fsl)
        sliders.w = w0.copy()
        per_cycle = []
        for _cycle in range(3):
            e0 = sliders.dissipated_energy
            for x in np.append(u[1:], u[0]):
                sliders.update(float(x))
            per_cycle.append(sliders.dissipated_energy - e0)
        qs = system.run(load, w0, 3)
        for c, d in zip(qs, per_cycle):
            assert abs(c.dissipation - d) <= EXACT * exact
        np.testing.assert_allclose(qs[-1].slip_end, sliders.w, rtol=0, atol=EXACT * u_amp)
        steady.append(per_cycle[1:])
    steady = np.array(steady)
    assert np.max(np.abs(steady - exact)) <= EXACT * exact


# --- (5) bad input --------------------------------------------------------------------------------

@pytest.mark.parametrize("stiffness,friction,match", [
    ([[1.0, 2.0], [2.0, 1.0]], 0.3, "stiffness"),           # indefinite
    ([[1.0, 0.5], [0.4, 1.0]], 0.3, "stiffness"),           # not symmetric
    ([[1.0, 1.0], [1.0, 1.0]], 0.3, "stiffness"),           # singular
    ([[1.0, 0.0, 0.0]], 0.3, "stiffness"),                  # not square
    ([[1.0, np.nan], [np.nan, 1.0]], 0.3, "stiffness"),
    ([[1.0, 0.0], [0.0, 1.0]], -0.3, "friction_coefficient"),
    ([[1.0, 0.0], [0.0, 1.0]], [0.3, 0.2, 0.1], "friction_coefficient"),
    ([[1.0, 0.0], [0.0, 1.0]], np.nan, "friction_coefficient"),
])
def test_bad_system(stiffness, friction, match):
    with pytest.raises(fj.ParameterError, match=match):
        QuasiStaticFrictionSystem(stiffness, friction)


@pytest.mark.parametrize("kwargs,match", [
    (dict(normal=[[1.0, -1.0], [1.0, 1.0]]), "normal"),
    (dict(normal=[[1.0, 0.0], [1.0, 1.0]]), "normal"),
    (dict(normal=[1.0, 2.0, 3.0]), "normal"),
    (dict(tangential=[[0.0, np.nan], [1.0, 1.0]]), "tangential"),
    (dict(tangential=[0.0, 1.0]), "tangential"),
    (dict(times=[0.0, 0.0]), "times"),
    (dict(times=[0.1, 0.5]), "times"),
    (dict(period=0.5), "period"),
    (dict(period=np.inf), "period"),
])
def test_bad_load(kwargs, match):
    args = dict(times=[0.0, 0.5], tangential=[[0.0, 0.0], [1.0, -1.0]], normal=[[1.0, 1.0], [1.0, 1.0]],
                period=1.0)
    args.update(kwargs)
    with pytest.raises(fj.ParameterError, match=match):
        PeriodicLoad(**args)


def test_bad_run_arguments():
    system = QuasiStaticFrictionSystem(np.eye(2), 0.5)
    load = PeriodicLoad([0.0, 0.5], [[0.0, 0.0], [1.0, -1.0]], [1.0, 1.0], 1.0)
    with pytest.raises(fj.ParameterError, match="initial_slip"):
        shakedown_check(system, load, initial_slip=[10.0, 0.0])  # outside the friction bound
    with pytest.raises(fj.ParameterError, match="initial_slip"):
        shakedown_check(system, load, initial_slip=[0.0, np.nan])
    with pytest.raises(fj.ParameterError, match="initial_slip"):
        shakedown_check(system, load, initial_slip=[0.0])
    with pytest.raises(fj.ParameterError, match="load"):
        shakedown_check(QuasiStaticFrictionSystem(np.eye(3), 0.5), load)
    with pytest.raises(fj.ParameterError, match="n_cycles"):
        shakedown_check(system, load, n_cycles=0)
    with pytest.raises(fj.ParameterError, match="rtol"):
        shakedown_check(system, load, rtol=-1.0)


# -- coupled systems (B != 0, seed eq. 4; issue 42, first part) ------------------------------------------
def _coupled_case(b=1.0, f=0.3):
    """Two nodes, diagonal K (so that a node-by-node return map is a valid brute force), normal
    forces coupled to the slips by ``B = b [[0, 1], [1, 0]]``: det(K - t S B) = 2 - t^2 s1 s2 b^2, so
    f_cr = sqrt(2) / b (s1 = s2); both nodes slip, each changing the other's friction bound."""
    from frictionjoint.shakedown import PeriodicLoad, QuasiStaticFrictionSystem

    system = QuasiStaticFrictionSystem(np.diag([1.0, 2.0]), f, coupling=b * np.array([[0.0, 1.0], [1.0, 0.0]]))
    load = PeriodicLoad.from_function(lambda t: 0.4 * np.sin(2 * np.pi * t) * np.array([1.0, 1.2]) + [0.05, 0.0],
                                      lambda t: np.array([1.0, 1.0]) + 0.3 * np.cos(2 * np.pi * t) * np.array([1.0, -1.0]),
                                      1.0, 64)
    return system, load


def test_critical_friction_coefficient_against_closed_forms():
    """Klarbring's f_cr (seed Sec. 2.1) from the principal minors det(K_JJ - S_J F_J B_JJ): for
    K = [[2, -1], [-1, 2]], B = b [[0, 1], [1, 0]] and a uniform f, det = 4 - (1 + f s1 b)(1 + f s2 b)
    vanishes first at f = 1 / b (s1 = s2 = 1); with f = (0.3, 0.15) (profile 1, 1/2) the largest
    coefficient's critical value solves 4 = (1 + t b)(1 + t b / 2): t = -3 + sqrt(33) for b = 1/2; no
    coupling, or a diagonal K with B = 0: inf. Rounding of an eigenvalue: a few eps."""
    from frictionjoint.shakedown import QuasiStaticFrictionSystem, critical_friction_coefficient

    k, b = np.array([[2.0, -1.0], [-1.0, 2.0]]), 0.5
    swap = np.array([[0.0, 1.0], [1.0, 0.0]])
    assert critical_friction_coefficient(QuasiStaticFrictionSystem(k, 0.3, coupling=b * swap)) == pytest.approx(
        1 / b, rel=1e-13)
    assert critical_friction_coefficient(QuasiStaticFrictionSystem(k, [0.3, 0.15], coupling=b * swap)) == \
        pytest.approx(-3 + np.sqrt(33), rel=1e-13)
    assert critical_friction_coefficient(QuasiStaticFrictionSystem(k, 0.3)) == np.inf
    assert critical_friction_coefficient(QuasiStaticFrictionSystem(k, 0.3, coupling=np.zeros((2, 2)))) == np.inf


def test_coupling_none_or_zero_gives_todays_numbers():
    """B = 0 (None, or a zero matrix, which is dropped at construction) marches as before the coupling
    was added: the third period of two systems against the numbers the module gave at commit 42a5ca2
    (its dissipation and end slips, 68 pieces). rel 1e-11: the exact march's rounding is a few eps per
    piece, ~6e-14 over 68 (bit for bit on the machine that recorded them), with a factor 100."""
    from frictionjoint.shakedown import QuasiStaticFrictionSystem

    _, load = _coupled_case()
    recorded = {"diagonal": (np.diag([1.0, 2.0]), 0.23465695030620165, [-0.059872241142743754, -0.09416753178750109]),
                "coupled K": (np.array([[2.0, -1.0], [-1.0, 2.0]]), 0.3372349919305553,
                              [-0.0942193309233575, -0.14127719724917984])}
    for k, dissipation, slips in recorded.values():
        for coupling in (None, np.zeros((2, 2))):
            cycle = QuasiStaticFrictionSystem(k, 0.3, coupling=coupling).run(load, np.zeros(2), 3)[-1]
            assert cycle.dissipation == pytest.approx(dissipation, rel=1e-11)
            np.testing.assert_allclose(cycle.slip_at_samples[-1], slips, rtol=1e-11)
            assert cycle.n_events == 68


def test_coupled_march_against_a_small_step_return_map():
    """The exact coupled march against a brute force: a node-by-node return map (K diagonal, so the
    projection onto |q_i| <= f (N_ext,i - (B w)_i) is exact for the bound at the step's start) with
    n = 64 ... 4096 steps per period on the same piecewise-linear load, two periods. It is first
    order (the bound lags a step): the error of the end slips falls 4x per 4x steps (measured 3.85,
    4.0006, 4.000000000005), and its Richardson extrapolation (4 w_4096 - w_1024) / 3 meets the exact
    march to 1.0e-15 of the slips (bound 1e-12: the extrapolation's O(h^2) remainder, measured by the
    ratio's 5e-12 departure from 4, times the 6.5e-4 error)."""
    system, load = _coupled_case()
    cycles = system.run(load, np.zeros(2), 2)
    exact = cycles[-1].slip_end
    assert np.all(cycles[-1].slip_variation > 0.1)  # both nodes slip in the steady cycle
    times, q_ext, normal = load.closed()
    k, f, b = np.diag(system.stiffness), system.friction_coefficient, system.coupling
    slips, errors = {}, []
    for n in (64, 256, 1024, 4096):
        w = np.zeros(2)
        for t in np.arange(1, 2 * n + 1) / n:
            phase = t % 1.0 if t % 1.0 else 1.0
            q = np.array([np.interp(phase, times, q_ext[:, i]) for i in range(2)]) - k * w
            g = f * (np.array([np.interp(phase, times, normal[:, i]) for i in range(2)]) - b @ w)
            over = np.abs(q) > g
            w[over] += np.sign(q[over]) * (np.abs(q[over]) - g[over]) / k[over]
        slips[n] = w
        errors.append(float(np.max(np.abs(w - exact)) / np.max(np.abs(exact))))
    assert all(3.5 < e1 / e2 < 4.5 for e1, e2 in zip(errors, errors[1:])), errors
    richardson = (4 * slips[4096] - slips[1024]) / 3
    assert np.max(np.abs(richardson - exact)) / np.max(np.abs(exact)) < 1e-12


def test_coupled_system_refuses_friction_at_or_above_critical_and_bad_coupling():
    from frictionjoint.errors import ParameterError
    from frictionjoint.shakedown import QuasiStaticFrictionSystem

    system, load = _coupled_case(b=1.0, f=1.5)  # f_cr = sqrt(2)
    with pytest.raises(ParameterError, match="critical coefficient f_cr = 1.41421"):
        system.run(load, np.zeros(2), 1)
    with pytest.raises(ParameterError, match="coupling must have the stiffness's shape"):
        QuasiStaticFrictionSystem(np.eye(2), 0.3, coupling=np.eye(3))
    with pytest.raises(ParameterError, match="coupling"):
        QuasiStaticFrictionSystem(np.eye(2), 0.3, coupling=[[np.nan, 0.0], [0.0, 0.0]])


def test_coupled_memory_resides_in_the_stuck_node():
    """Memory (seed Sec. 2.5, 3): node 2 never slips (|q2| = k2 |w2| <= 0.2 N < f N2 ~ 3 N) and its
    initial slip w2 sets node 1's normal force N1 = N1_ext - b w2 for ever; node 1, loaded by
    A sin(2 pi t) with A = 0.5 N > g1 = f (N1_ext - b w2), cycles between q1 = -g1 and g1, so its steady
    dissipation per cycle is 4 g1 (A - g1) / k1 (a single node: the slip between the extremes of the
    load, which the samples hit exactly). With B = 0 the dissipation is 4 g (A - g) / k1 for every w2
    (Andersson et al.). Closed forms to 1e-12 (measured 1.1e-16: a few roundings of q and g)."""
    from frictionjoint.shakedown import PeriodicLoad, QuasiStaticFrictionSystem, shakedown_check

    b, f, amplitude = 1.0, 0.3, 0.5
    load = PeriodicLoad.from_function(lambda t: amplitude * np.sin(2 * np.pi * t) * np.array([1.0, 0.0]),
                                      lambda t: np.array([1.0, 10.0]), 1.0, 64)
    for coupling in (b * np.array([[0.0, 1.0], [1.0, 0.0]]), None):
        system = QuasiStaticFrictionSystem(np.diag([1.0, 2.0]), f, coupling=coupling)
        steady = []
        for w2 in (-0.1, 0.0, 0.1):
            result = shakedown_check(system, load, initial_slip=[0.0, w2], n_cycles=50)
            g1 = f * (1.0 - (b * w2 if coupling is not None else 0.0))
            assert result.status == "cyclic slip"
            assert result.steady_dissipation == pytest.approx(4 * g1 * (amplitude - g1), rel=1e-12)
            assert result.final_slip[1] == w2  # node 2 never slipped: its slip is exactly the initial one
            assert list(result.stuck_nodes) == [1]  # the permanent stick set, where the memory is
            steady.append(result.steady_dissipation)
        if coupling is None:
            assert max(steady) - min(steady) <= 1e-12 * max(steady)
        else:  # 0.2244, 0.24, 0.2484 J: the initial state is remembered
            assert steady[0] < steady[1] < steady[2] and steady[2] - steady[0] > 0.02


def _factor_case():
    t = np.arange(64) / 64
    cyclic_t = np.sin(2 * np.pi * t)[:, None] * np.array([1.0, 0.5])
    cyclic_n = np.cos(2 * np.pi * t)[:, None] * np.array([0.2, -0.2])
    return t, ([0.05, 0.0], [1.0, 1.0], cyclic_t, cyclic_n, t, 1.0)


def test_critical_load_factors_enumeration_programme_and_melan():
    """lambda2 by the linear programme equals the enumeration's feasible intersection (the seed's two
    ways, to 1e-12: two solves of the same vertex; measured 1e-16); for B = 0 lambda1 = lambda2 is
    the Melan limit (melan_check's margin changes sign across it) and for a coupled system
    lambda1 < lambda2."""
    from frictionjoint.shakedown import (QuasiStaticFrictionSystem, critical_load_factors, factored_load,
                                         melan_check)

    _, args = _factor_case()
    k = np.array([[2.0, -1.0], [-1.0, 2.0]])
    for coupling in (None, 0.3 * np.array([[0.0, 1.0], [1.0, 0.0]]), np.array([[0.2, 0.5], [-0.3, 0.1]])):
        system = QuasiStaticFrictionSystem(k, 0.3, coupling=coupling)
        r = critical_load_factors(system, *args)
        assert r.success and r.lambda2_enumerated == pytest.approx(r.lambda2, rel=1e-12)
        # the facet bisection stops within 1e-12 of lambda2 (and the programmes' own tolerances): 1e-11
        assert r.lambda1 == pytest.approx(r.lambda1_enumerated, rel=1e-11)
        if coupling is None:
            assert r.lambda1 == pytest.approx(r.lambda2, rel=1e-11)
            below, above = (melan_check(system, factored_load(*args, r.lambda2 * x)).margin for x in (0.999, 1.001))
            assert below > 0 > above
        else:
            assert r.lambda1 < r.lambda2 - 0.01


def test_critical_load_factors_against_marches():
    """The exact march from sampled initial slips (zero and 40 uniform in [-0.3, 0.3]^2 that satisfy
    the bound at t = 0) on the coupled two-node system: at 0.95 lambda1 every one shakes down, half way
    between lambda1 and lambda2 some shake down and some cycle (the initial state decides, seed
    Sec. 3.3), at 1.05 lambda2 none shakes down."""
    from frictionjoint.shakedown import (QuasiStaticFrictionSystem, critical_load_factors, factored_load,
                                         shakedown_check)

    _, args = _factor_case()
    system = QuasiStaticFrictionSystem(np.array([[2.0, -1.0], [-1.0, 2.0]]), 0.3,
                                       coupling=0.3 * np.array([[0.0, 1.0], [1.0, 0.0]]))
    r = critical_load_factors(system, *args)
    rng = np.random.default_rng(3)
    starts = [np.zeros(2)] + [rng.uniform(-0.3, 0.3, 2) for _ in range(40)]
    outcomes = {}
    for name, lam in (("below", 0.95 * r.lambda1), ("between", 0.5 * (r.lambda1 + r.lambda2)),
                      ("above", 1.05 * r.lambda2)):
        load = factored_load(*args, lam)
        statuses = []
        for w0 in starts:
            try:
                system.check_slip(load, w0)
            except fj.ParameterError:
                continue
            statuses.append(shakedown_check(system, load, initial_slip=w0, n_cycles=400).status)
        outcomes[name] = set(statuses)
    assert outcomes == {"below": {"shakedown"}, "between": {"shakedown", "cyclic slip"}, "above": {"cyclic slip"}}


def test_ahn_diagram_safe_region_loses_a_facet_at_lambda1(tmp_path):
    """Seed Sec. 3.1-3.3: below lambda1 the safe shakedown region of a two-node system is a
    quadrilateral (all four extreme constraints active: shakedown from every initial state);
    between lambda1 and lambda2 one constraint is no longer active and it is a triangle (shakedown
    depends on the initial state); for B = 0 a node's two constraints are parallel and it is a
    parallelogram. The diagram is drawn with the slips of twelve cycles from rest."""
    from frictionjoint.plotting import plot_ahn_diagram, safe_region
    from frictionjoint.shakedown import (QuasiStaticFrictionSystem, critical_load_factors, extreme_constraints,
                                         factored_load)

    _, args = _factor_case()
    box = np.array([[-10.0, -10.0], [10.0, -10.0], [10.0, 10.0], [-10.0, 10.0]])
    k = np.array([[2.0, -1.0], [-1.0, 2.0]])
    coupled = QuasiStaticFrictionSystem(k, 0.3, coupling=0.3 * np.array([[0.0, 1.0], [1.0, 0.0]]))
    r = critical_load_factors(coupled, *args)
    for lam, vertices in ((0.9 * r.lambda1, 4), ((1 - 1e-6) * r.lambda1, 4), ((1 + 1e-6) * r.lambda1, 3),
                          (0.5 * (r.lambda1 + r.lambda2), 3)):
        rows, bound = extreme_constraints(coupled, factored_load(*args, lam))
        region = safe_region(rows, bound, box)
        assert len(region) == vertices
        assert np.all(rows @ region.T <= bound[:, None] + 1e-12)
    plain = QuasiStaticFrictionSystem(k, 0.3)
    rows, bound = extreme_constraints(plain, factored_load(*args, 0.9 * critical_load_factors(plain, *args).lambda2))
    region = safe_region(rows, bound, box)
    assert len(region) == 4
    edges = np.diff(np.vstack([region, region[:1]]), axis=0)
    cross = edges[0, 0] * edges[2, 1] - edges[0, 1] * edges[2, 0]  # opposite sides parallel
    assert abs(cross) <= 1e-12 * np.linalg.norm(edges[0]) * np.linalg.norm(edges[2])
    load = factored_load(*args, 0.5 * (r.lambda1 + r.lambda2))
    slips = np.vstack([c.slip_at_samples for c in coupled.run(load, np.zeros(2), 12)])
    plot_ahn_diagram(*extreme_constraints(coupled, load), [slips], path=tmp_path / "ahn.png")
    assert (tmp_path / "ahn.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_lambda1_is_zero_where_a_constraint_is_redundant_from_the_start():
    """A coupled two-node system (random, found by a review) whose safe region is a triangle already at
    lambda = 0: lambda1 = 0 with the reason, not the seed's lowest vertex (0.478, lambda1_enumerated),
    below which an initial slip still ends in cyclic slip (the exact march at 0.9 x 0.478: 2.3e-3 J per
    cycle)."""
    from frictionjoint.plotting import safe_region
    from frictionjoint.shakedown import (QuasiStaticFrictionSystem, critical_load_factors, extreme_constraints,
                                         factored_load, shakedown_check)

    k = np.array([[5.198804052296091, -0.7507440528458584], [-0.7507440528458584, 0.6203578795131817]])
    b = np.array([[-0.1604372522772445, -1.363996756920735], [1.2394980573661591, 0.7847271647360403]])
    t = np.arange(64) / 64
    phase = np.array([4.083462392010725, 2.1251112589415664, 1.016248470709016, 2.9570091350424756])
    args = (np.array([0.022928816893680395, -0.06715777258117438]), np.ones(2),
            np.sin(2 * np.pi * t[:, None] + phase[:2]) * np.array([0.32985491491851554, 0.6463474900247088]),
            np.sin(2 * np.pi * t[:, None] + phase[2:]) * np.array([0.13709881848686412, 0.2984421771528513]), t, 1.0)
    system = QuasiStaticFrictionSystem(k, 0.3, coupling=b)
    r = critical_load_factors(system, *args)
    assert r.lambda1 == 0.0 and "redundant already at lambda = 0" in r.message
    box = np.array([[-1e3, -1e3], [1e3, -1e3], [1e3, 1e3], [-1e3, 1e3]])
    assert len(safe_region(*extreme_constraints(system, factored_load(*args, 0.0)), box)) == 3
    load = factored_load(*args, 0.9 * r.lambda1_enumerated)
    result = shakedown_check(system, load, initial_slip=[-0.09026533125283484, -0.4447374477215763], n_cycles=300)
    assert result.status == "cyclic slip" and result.steady_dissipation > 1e-3


def test_coupled_march_stops_where_a_normal_force_reaches_zero_and_keeps_its_energy_balance():
    """One node, K = 1, f = 0.5, B = 1 (N = 1 - w), q_ext rising 0 -> 2 N over half the period: the node
    slips once q_ext = f N, and with w = q_ext - f (1 - w) its normal force N = 1 - w reaches zero at
    q_ext = 1, t = 0.25 s (a closed form): separation, not modelled, stops the march naming the node and
    the time. With B = -1 it does not open (N grows with w), and the balance work = stored energy
    change + dissipation holds to rounding (the normal forces do no work; measured 1e-16, bound 1e-12)."""
    from frictionjoint.errors import ConvergenceError
    from frictionjoint.shakedown import PeriodicLoad, QuasiStaticFrictionSystem

    load = PeriodicLoad(np.array([0.0, 0.5]), np.array([[0.0], [2.0]]), np.array([[1.0], [1.0]]), 1.0)
    with pytest.raises(ConvergenceError, match=r"node 0's normal force reaches zero at t = 0.25 s"):
        QuasiStaticFrictionSystem(np.eye(1), 0.5, coupling=np.eye(1)).run_cycle(load, np.zeros(1))
    cycle = QuasiStaticFrictionSystem(np.eye(1), 0.5, coupling=-np.eye(1)).run_cycle(load, np.zeros(1))
    assert cycle.dissipation > 0
    assert abs(cycle.work - cycle.stored_energy_change - cycle.dissipation) <= 1e-12 * cycle.dissipation
