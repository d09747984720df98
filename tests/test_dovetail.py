"""Dovetail blade root (DESIGN.md section 4): statics, equivalent Jenkins, driven flanks with normal
load variation and lift-off, and the friction-damper behaviour of a blade on its root."""
import math

import numpy as np
import pytest
import scipy.integrate

import frictionjoint as fj
from frictionjoint.elements.driven import DrivenSliders

G, MU, KN, KT = math.radians(30.0), 0.3, 2e8, 1e8


def root(fc=1e4, **kw):
    args = dict(flank_angle=G, friction_coefficient=MU, normal_stiffness=KN, tangential_stiffness=KT,
                tangential_dof=0)
    args.update(kw)
    return fj.DovetailRoot(fc, **args)


# ------------------------------------------------------------------------ statics
@pytest.mark.parametrize("kt, mu, regime", [(1e8, 0.3, "stuck"), (3e8, 0.3, "slipping"),
                                            (1e8, 1e-9, "slipping"), (1e8, 0.2886751345948129, "stuck")])
def test_static_equilibrium_to_machine_precision(kt, mu, regime):
    fc = 12345.6
    r = root(fc, tangential_stiffness=kt, friction_coefficient=mu, radial_dof=1)
    st = r.static
    assert st.regime == regime
    # radial equilibrium Fc = 2 (N cos g + T sin g); the flank forces on the blade sum to -Fc.
    # Rounding only: each side is about ten roundings of terms no larger than fc (<= 10 u fc, u =
    # 1.1e-16; f[0] cancels two of size fc/2) plus libm's cos/sin, whose last bit differs between
    # platforms; hence 1e-14 (measured <= 1.5e-16 fc here, and <= 2e-16 in the approx checks)
    assert abs(2 * (st.normal_force * math.cos(G) + st.friction_force * math.sin(G)) - fc) <= 1e-14 * fc
    f = r.root_force([st.normal_force] * 2, [st.friction_force] * 2)
    assert abs(f[0]) <= 1e-14 * fc and abs(f[1] + fc) <= 1e-14 * fc
    assert st.friction_force <= mu * st.normal_force * (1 + 1e-14)  # equal at the stuck limit and slipping
    # the flanks' springs: N = kn Y0 cos g always; T = kt Y0 sin g when stuck, mu N when slipping
    assert st.normal_force == pytest.approx(KN * st.radial_displacement * math.cos(G), rel=1e-14)
    if regime == "stuck":
        assert st.friction_force == pytest.approx(kt * st.radial_displacement * math.sin(G), rel=1e-14)
    else:
        assert st.friction_force == pytest.approx(mu * st.normal_force, rel=1e-14)
    if mu < 1e-6:  # frictionless limit N = Fc/(2 cos g)
        assert st.normal_force == pytest.approx(fj.DovetailRoot.frictionless_normal_force(fc, G), rel=1e-9)


def test_attached_root_is_in_equilibrium_at_zero():
    r = root(radial_dof=1)
    s = fj.FrictionSystem(fj.LinearStructure(np.eye(2), np.eye(2) * 1e6), [r])
    # constant force + preloaded sliders' forces -T0 d_i sum to zero at x = 0
    total = s.constant_force - s.slider_direction.T @ s.slider_preload
    assert np.max(np.abs(total)) <= 1e-12 * r.centrifugal_force
    res = fj.simulate(s, 1e-2, t_eval=np.linspace(0, 1e-2, 11))
    assert np.max(np.abs(res.x)) <= 1e-12 * r.static.radial_displacement  # rounding only


def test_from_rotor_and_stuck_stiffness():
    r = fj.DovetailRoot.from_rotor(1000.0, 0.2, 0.5, flank_angle=G, friction_coefficient=MU,
                                   normal_stiffness=KN, tangential_stiffness=KT, tangential_dof=0)
    assert r.centrifugal_force == pytest.approx(0.2 * 1000.0 ** 2 * 0.5, rel=1e-15)
    k = r.stuck_stiffness()
    # a few roundings and libm's sin/cos (see the statics above): 1e-14, measured 1.7e-16
    assert k[0, 0] == pytest.approx(2 * (KN * math.sin(G) ** 2 + KT * math.cos(G) ** 2), rel=1e-14)
    assert k[1, 1] == pytest.approx(2 * (KN * math.cos(G) ** 2 + KT * math.sin(G) ** 2), rel=1e-14)
    assert abs(k[0, 1]) <= 1e-7 * k[0, 0]  # symmetric flanks: X and Y uncouple while stuck


# ------------------------------------------------------------ equivalent Jenkins
def _blade(elements, omega, k_extra=0.0, p=200.0):
    st = fj.LinearStructure(1.0, 5e7 + k_extra, 300.0)
    return fj.FrictionSystem(st, elements, omega=omega, excitation=[fj.HarmonicForce(0, p)])


def test_flat_flanks_without_preload_are_the_equivalent_jenkins_on_any_path():
    # gamma = 0: no preload (T0 = kt Y0 sin 0 = 0) and no normal-spring term: exact along any path
    r = root(1e3, flank_angle=0.0)
    jen, kpar = r.equivalent_jenkins(dof=0)
    assert kpar == 0.0
    t = np.linspace(0, 5e-3, 201)
    a = fj.simulate(_blade([r], 12000.0), 5e-3, t_eval=t)
    b = fj.simulate(_blade([jen], 12000.0), 5e-3, t_eval=t)
    assert len(a.events) > 10
    assert np.max(np.abs(a.x - b.x)) <= 1e-12 * np.max(np.abs(b.x))


def test_preloaded_flanks_have_the_equivalent_jenkins_steady_state():
    r = root(2e3)
    jen, kpar = r.equivalent_jenkins(dof=0)
    # a few roundings and libm's cos (see the statics above): 1e-14, measured 2e-16
    assert jen.tangential_stiffness == pytest.approx(2 * KT * math.cos(G) ** 2, rel=1e-14)
    assert jen.slip_force == pytest.approx(2 * MU * r.static.normal_force * math.cos(G), rel=1e-14)
    # 14000 rad/s: the flanks stick over the whole orbit. Preloaded to 96 % of their limit, they
    # slip in the transient and shake down to an orbit that touches the limit every cycle: the
    # marcher logs a slip of ~1e-12 s there (1e-21 m, 4e-19 J per cycle), which is no slip
    # (PeriodicResponse.stuck: below 1e-12 of the displacement amplitude)
    for omega, stuck in ((14000.0, True), (16500.0, False)):
        a = fj.periodic_response(_blade([r], omega))
        b = fj.periodic_response(_blade([jen], omega, k_extra=kpar))
        assert a.converged and b.converged and a.stuck == b.stuck == stuck
        assert a.harmonic_amplitude[0] == pytest.approx(b.harmonic_amplitude[0], rel=1e-9)
        assert a.dissipated_per_cycle == pytest.approx(b.dissipated_per_cycle, rel=1e-9)


def test_driven_flanks_varying_normal_load_equal_play_operators_when_n_is_constant():
    # gamma = 0: tangential motion does not change the flank approach, so N stays N0 and the
    # varying-load return map must equal two independent play operators along s = t . u
    r = root(2e3, flank_angle=0.0)
    d = r.driven(normal_load_variation=True)
    st = r.static
    ref = []
    for _ in range(2):
        p = DrivenSliders([KT], [MU * st.normal_force])
        p.w[:] = -st.friction_force / KT
        ref.append(p)
    rng = np.random.default_rng(4)
    path = np.cumsum(rng.normal(scale=3e-6, size=(300, 2)), axis=0)
    path[:, 1] = 0.0
    for u in path:
        d.update(u)
        for i in range(2):
            ref[i].update(float(r.tangents[i] @ u))
        assert d.friction_force == pytest.approx([ref[0].force, ref[1].force], rel=1e-12, abs=1e-9)
    assert d.dissipated_energy == pytest.approx(ref[0].dissipated_energy + ref[1].dissipated_energy,
                                                rel=1e-12)


def test_driven_flanks_frozen_normal_load_follow_the_loop_formula():
    r = root(2e3)
    st = r.static
    # tangential cycles X = +-A: D = 8 mu N0 (A cos g - mu N0/kt) once the preload is washed out
    a = 5 * MU * st.normal_force / (KT * math.cos(G))
    d = r.driven(normal_load_variation=False)
    for x in (a, -a, a):
        d.update([x, 0.0])
    e0 = d.dissipated_energy
    d.update([-a, 0.0])
    d.update([a, 0.0])
    n0 = st.normal_force
    assert d.dissipated_energy - e0 == pytest.approx(8 * MU * n0 * (a * math.cos(G) - MU * n0 / KT), rel=1e-12)


@pytest.mark.slow
def test_driven_flanks_with_normal_load_variation_and_lift_off_balance_energy():
    r = root(2e3, radial_dof=1)
    d = r.driven(normal_load_variation=True)
    y_lift = r.static.normal_force / KN / math.cos(G)  # radial pull-out that opens both flanks
    rng = np.random.default_rng(7)
    path = np.cumsum(rng.normal(scale=0.25 * y_lift, size=(400, 2)), axis=0)
    path[150:170, 1] = -2.0 * y_lift  # both flanks lifted off for a while
    lifted = 0
    work = 0.0
    probe = r.driven(normal_load_variation=True)

    def stored(dd):
        n = dd.normal_force
        return float(np.sum(n ** 2) / (2 * KN) + np.sum(dd.friction_force ** 2) / (2 * KT))

    e_start = stored(d)
    for u in path:
        # work done on the flanks along the straight segment, -int F . du, by adaptive quadrature
        # of the force of a copy moved to each node (piecewise linear in lambda, with kinks)
        du = u - d.u

        def power(lam):
            probe.set_state(d.state())
            probe.update(d.u + lam * du)
            return float(-probe.root_force @ du)
        work += scipy.integrate.quad(power, 0.0, 1.0, epsabs=0.0, epsrel=1e-11, limit=200)[0]
        d.update(u)
        lifted += int(np.all(d.normal_force == 0))
        assert np.all(d.normal_force >= 0)
        assert np.all(np.abs(d.friction_force) <= MU * d.normal_force * (1 + 1e-12) + 1e-9)
    assert lifted >= 20
    # the static part of the root force does work too: include it via stored energy of springs
    assert abs(work - (stored(d) - e_start) - d.dissipated_energy) <= 1e-10 * d.dissipated_energy
    assert d.dissipated_energy > 0


@pytest.mark.parametrize("rocking", [False, True])
def test_driven_tangent_stiffness_matches_finite_differences(rocking):
    """-d(root force)/du of the driven flanks (stuck, then slipping with varying normal load), in
    (X, Y) or, rocking on flank contacts 5 mm off the centre line, (X, Y, theta), against central
    differences of the exact return map about a point a small step further along the same path
    (so that slipping flanks keep slipping)."""
    a = 0.005
    if rocking:
        r = root(2e3, radial_dof=1, rocking_dof=2, flank_half_width=a)
        targets = ([1e-7, 2e-8, 1e-6], [3e-5, 1e-6, 2e-3], [-2e-5, 3e-6, 5e-3])
        scale = np.array([1.0, 1.0, 1.0 / a])  # theta in units of a flank displacement
    else:
        r = root(2e3, radial_dof=1)
        targets = ([1e-7, 2e-8], [3e-5, 1e-6])
        scale = np.ones(2)
    for target in targets:
        target = np.array(target)
        d = r.driven(normal_load_variation=True)
        d.update(target)
        k = d.tangent_stiffness()
        step = 1e-4 * target
        h = 1e-3 * np.linalg.norm(step / scale) * scale
        fd = np.zeros((scale.size, scale.size))
        for j in range(scale.size):
            for sgn in (1.0, -1.0):
                p = r.driven(normal_load_variation=True)
                p.set_state(d.state())
                e = np.zeros(scale.size)
                e[j] = sgn * h[j]
                p.update(d.u + step + e)
                fd[:, j] -= sgn * p.root_force / (2 * h[j])
        q = r.driven(normal_load_variation=True)
        q.set_state(d.state())
        q.update(d.u + step)
        assert np.allclose(q.tangent_stiffness(), k)
        both = scale[:, None] * scale[None, :]  # force x length per unit of each coordinate
        assert np.max(np.abs((fd - k) * both)) <= 1e-6 * np.max(np.abs(k * both))


# ------------------------------------------------------------- microslip flanks
def test_microslip_flanks_from_mindlin_contact():
    def contact(n):
        return fj.contact.MindlinContact(n, MU, 0.02, 210e9, 0.3)
    r = root(2e3, tangential_stiffness=None, flank_contact=contact, n_sliders=6)
    n0 = r.static.normal_force
    sl = r.flank_sliders()
    assert len(sl) == 6
    assert sum(s.slip_force for s, _ in sl) == pytest.approx(MU * n0, rel=1e-12)
    assert sum(s.stiffness for s, _ in sl) == pytest.approx(contact(n0).to_iwan(6).stiffness, rel=1e-12)
    assert r.tangential_stiffness == pytest.approx(contact(n0).tangential_stiffness, rel=1e-12)
    # preload: the sliders carry T0 in total, each within its strength
    assert sum(p for _, p in sl) == pytest.approx(r.static.friction_force, rel=1e-12)
    assert all(p <= s.slip_force * (1 + 1e-12) for s, p in sl)
    a = fj.periodic_response(_blade([r], 16000.0, p=2000.0))
    assert a.converged and a.dissipated_per_cycle > 0


# ------------------------------------------------------- friction-damper behaviour
@pytest.mark.slow
def test_blade_on_dovetail_root_shows_the_friction_damper_optimum():
    """Single-DOF blade (examples/dovetail_damper.py) at three centrifugal loads."""
    import importlib.util
    from pathlib import Path

    spec = importlib.util.spec_from_file_location(
        "dovetail_damper", Path(__file__).parents[1] / "examples" / "dovetail_damper.py")
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    w_free, w_stuck, c = ex.limits()
    m, p = ex.BLADE["mass"], ex.BLADE["force_amplitude"]

    def linear(k, w):  # |x| of the linear oscillator m x'' + c x' + k x = P cos(w t)
        return p / abs(complex(k - m * w * w, c * w))

    # high load: the flanks never slip; the response is the stuck linear one (peak at
    # w = wn sqrt(1 - 2 zeta^2)) to 1e-9
    zeta_s = c / (2 * m * w_stuck)
    w_pk = w_stuck * math.sqrt(1 - 2 * zeta_s ** 2)
    hi = fj.periodic_response(ex.build(1e7)(w_pk))
    assert hi.stuck
    assert hi.harmonic_amplitude[0] == pytest.approx(linear(m * w_stuck ** 2, w_pk), rel=1e-9)
    # low load: nearly free slip, the peak within 1 % of the free-slip linear peak
    lo_w, lo_a, _ = fj.peak_response(ex.build(1.0), 0.97 * w_free, 1.03 * w_free, n_grid=7)
    free_peak = linear(m * w_free ** 2, w_free * math.sqrt(1 - 2 * (c / (2 * m * w_free)) ** 2))
    assert lo_w == pytest.approx(w_free, rel=1e-3)
    assert lo_a == pytest.approx(free_peak, rel=1e-2) and lo_a < free_peak
    # intermediate load: the peak over the whole band is far below both limits
    mid_w, mid_a, _ = fj.peak_response(ex.build(1e3), 0.8 * w_free, 1.15 * w_stuck, n_grid=15)
    stuck_peak = linear(m * w_stuck ** 2, w_pk)
    assert mid_a < 0.1 * min(stuck_peak, lo_a)
    assert w_free < mid_w < w_stuck


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize("kw, name", [
    (dict(centrifugal_force=-1.0), "centrifugal_force"),
    (dict(flank_angle=math.pi / 2), "flank_angle"),
    (dict(flank_angle=-0.1), "flank_angle"),
    (dict(friction_coefficient=0.0), "friction_coefficient"),
    (dict(normal_stiffness=float("nan")), "normal_stiffness"),
    (dict(tangential_stiffness=None), "tangential_stiffness"),
    (dict(tangential_dof=None), "tangential_dof"),
    (dict(flank_contact=lambda n: fj.contact.MindlinContact(n, 0.5, 0.02, 210e9, 0.3)), "slip_force"),
])
def test_bad_input_names_the_parameter(kw, name):
    args = dict(centrifugal_force=1e4, flank_angle=G, friction_coefficient=MU, normal_stiffness=KN,
                tangential_stiffness=KT, tangential_dof=0)
    args.update(kw)
    with pytest.raises(fj.ParameterError, match=name):
        fj.DovetailRoot(**args)


def test_driven_microslip_flanks_dissipate_as_their_iwan_elements():
    def contact(n):
        return fj.contact.MindlinContact(n, MU, 0.02, 210e9, 0.3)
    r = root(2e3, tangential_stiffness=None, flank_contact=contact, n_sliders=8)
    iwan = contact(r.static.normal_force).to_iwan(8)
    d = r.driven()
    for amp in (0.3, 0.8, 2.0):  # of the slip displacement C
        a = amp * iwan.slip_force / iwan.stiffness / math.cos(G) * 3.0
        for x in (a, -a, a):  # wash out the preload
            d.update([x, 0.0])
        e0 = d.dissipated_energy
        d.update([-a, 0.0])
        d.update([a, 0.0])
        expected = 2 * iwan.dissipation_per_displacement_cycle(a * math.cos(G))
        assert d.dissipated_energy - e0 == pytest.approx(expected, rel=1e-12)
    with pytest.raises(fj.ParameterError, match="normal_load_variation"):
        r.driven(normal_load_variation=True)


def test_rounded_flanks_microslip_where_flat_flanks_stick():
    """A flat flank with sharp edges sticks as a whole below its slip onset (seed: a flat region
    sticks or slips as a whole); a flat with rounded edges (half-plane Ciavarella-Jaeger contact)
    dissipates by microslip at every amplitude, growing like A^3 at small amplitude, and equals
    its contact theory's Iwan element."""
    def contact(n):
        return fj.contact.HalfPlaneContact(fj.contact.RoundedFlatPunch(2e-3, 5e-3), n, MU, 210e9, 0.3,
                                           reference_depth=0.01, length=0.02)
    rounded = root(2e3, tangential_stiffness=None, flank_contact=contact, n_sliders=64)
    flat = root(2e3, tangential_stiffness=rounded.tangential_stiffness)
    iwan = contact(rounded.static.normal_force).to_iwan(64)
    x_slip = MU * flat.static.normal_force * (1 - 0.2) / (flat.tangential_stiffness * math.cos(G))
    d = {}
    for name, r in (("flat", flat), ("rounded", rounded)):
        for a in (0.1 * x_slip, 0.2 * x_slip):
            drv = r.driven()
            for x in (a, -a, a):
                drv.update([x, 0.0])
            e0 = drv.dissipated_energy
            drv.update([-a, 0.0])
            drv.update([a, 0.0])
            d[name, a] = drv.dissipated_energy - e0
    a1, a2 = 0.1 * x_slip, 0.2 * x_slip
    assert d["flat", a1] == 0.0 and d["flat", a2] == 0.0
    assert d["rounded", a1] > 0
    assert d["rounded", a2] == pytest.approx(2 * iwan.dissipation_per_displacement_cycle(a2 * math.cos(G)),
                                             rel=1e-12)
    assert 6.0 < d["rounded", a2] / d["rounded", a1] < 10.0  # ~A^3 (8) with 64 sliders
