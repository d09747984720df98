"""Cattaneo-Mindlin sphere contact and the Iwan elements built from it (issue 4).

References: Hertz and Cattaneo-Mindlin closed forms (Johnson 1985, Contact Mechanics, sections
4.2, 7.2, 7.3) evaluated here independently of the library, and independent numerical
checks: quadrature of the Hertz pressure and of the Cattaneo shear traction, the hysteresis loop
area of the Mindlin-Deresiewicz unloading/reloading curves, and the exact play operator of
tests-independent discrete sliders (frictionjoint.elements.driven)."""
import math

import numpy as np
import pytest
import scipy.integrate as si

import frictionjoint as fj
from frictionjoint.contact import MindlinContact
from frictionjoint.elements.driven import DrivenSliders

P, MU, R, E, NU = 100.0, 0.3, 0.01, 210e9, 0.3


@pytest.fixture(scope="module")
def contact():
    return MindlinContact(normal_load=P, friction_coefficient=MU, radius=R, youngs_modulus=E, poisson_ratio=NU)


def test_hertz_radius_pressure_and_load(contact):
    e_star = 1.0 / (2.0 * (1.0 - NU ** 2) / E)  # two bodies of one material
    a = (3.0 * P * R / (4.0 * e_star)) ** (1.0 / 3.0)
    assert abs(contact.contact_radius - a) <= 1e-14 * a
    p0 = contact.peak_pressure
    total, _ = si.quad(lambda r: p0 * math.sqrt(1.0 - (r / a) ** 2) * 2.0 * math.pi * r, 0.0, a,
                       epsabs=0.0, epsrel=1e-13)
    assert abs(total - P) <= 1e-12 * P  # the Hertz pressure carries the load


@pytest.mark.parametrize("ratio", [0.1, 0.5, 0.9, 0.999])
def test_stick_zone_carries_the_tangential_force(contact, ratio):
    """Cattaneo: q = (f p0/a)[sqrt(a^2 - r^2) - sqrt(c^2 - r^2)]; its integral must be Q."""
    a, q_star = contact.contact_radius, ratio * contact.slip_force
    c = contact.stick_radius(q_star)
    k = MU * contact.peak_pressure / a
    total = 2 * math.pi * (si.quad(lambda r: k * math.sqrt(a * a - r * r) * r, 0, a, epsabs=0, epsrel=1e-13)[0]
                           - si.quad(lambda r: k * math.sqrt(c * c - r * r) * r, 0, c, epsabs=0, epsrel=1e-13)[0])
    assert abs(total - q_star) <= 1e-10 * q_star


def test_stiffness_backbone_and_inverse(contact):
    shear = E / (2 * (1 + NU))
    assert abs(contact.tangential_stiffness - 8 * contact.contact_radius * shear / (2 * (2 - NU))) \
        <= 1e-14 * contact.tangential_stiffness
    h = 1e-6 * contact.slip_displacement
    slope = (contact.backbone(h) - contact.backbone(-h)) / (2 * h)
    assert abs(slope / contact.tangential_stiffness - 1) <= 1e-6
    for q in np.linspace(0, 0.999, 7) * contact.slip_force:
        assert abs(contact.backbone(contact.displacement(q)) - q) <= 1e-13 * contact.slip_force
    assert contact.backbone(2 * contact.slip_displacement) == contact.slip_force
    assert contact.backbone(-0.3 * contact.slip_displacement) == -contact.backbone(0.3 * contact.slip_displacement)


@pytest.mark.parametrize("ratio", [0.1, 0.5, 0.9, 1.0])
def test_dissipation_equals_the_loop_area(contact, ratio):
    """Mindlin-Deresiewicz unloading delta_dn(Q) = d* - 2 d((Q* - Q)/2) and reloading
    delta_up(Q) = -d* + 2 d((Q + Q*)/2); the loop area by quadrature against the closed form."""
    q_star = ratio * contact.slip_force
    d = contact.displacement
    d_star = d(q_star)
    area, _ = si.quad(lambda q: (d_star - 2 * d((q_star - q) / 2)) - (-d_star + 2 * d((q + q_star) / 2)),
                      -q_star, q_star, epsabs=0.0, epsrel=1e-13, limit=200)
    assert abs(contact.dissipation_per_cycle(q_star) - area) <= 1e-10 * area


@pytest.mark.parametrize("u", [1e-9, 1e-6, 1e-3])
def test_dissipation_small_amplitude_no_cancellation(contact, u):
    """Series of the closed form: W = (9 f^2 P^2 S/(10 a)) 5u^3/162 (1 + 2u/3 + 7u^2/15 + ...)."""
    pref = 9 * contact.slip_force ** 2 * contact.compliance / (10 * contact.contact_radius)
    series = pref * 5 * u ** 3 / 162 * (1 + 2 * u / 3 + 7 * u ** 2 / 15 + 28 * u ** 3 / 81)
    # derived: at u = 1e-3 the four-term series' own truncation is 2.68e-13 (50-digit mpmath), the
    # rest rounding (measured 2.2e-16 at u = 1e-6, 0 at 1e-9)
    assert abs(contact.dissipation_per_cycle(u * contact.slip_force) / series - 1) <= 1e-12


def test_continuous_iwan_reproduces_backbone_and_dissipation(contact):
    iwan = contact.to_iwan()
    u = np.linspace(-1.2, 1.2, 241) * contact.slip_displacement
    assert np.max(np.abs(iwan.backbone(u) - contact.backbone(u))) <= 1e-14 * contact.slip_force
    for ratio in (1e-6, 1e-3, 0.1, 0.5, 0.9, 0.9999):
        q = ratio * contact.slip_force
        ref = contact.dissipation_per_cycle(q)
        # the element integrates its slider density: int 4 k rho(phi) phi (u* - phi) dphi
        assert abs(iwan.dissipation_per_cycle(q) - ref) <= 1e-8 * ref
    assert iwan.stiffness == contact.tangential_stiffness


def test_masing_memory_against_the_exact_play_operator(contact):
    """The continuous element along a path with nested loops equals the limit of N discrete
    play-operator sliders (elements.driven, independent code); error ~ N^-2."""
    c, fs = contact.slip_displacement, contact.slip_force
    turns = np.array([0, 0.6, -0.3, 0.4, 0.1, 0.5, -0.8, 0.9, -0.2, 0.3, 0.0]) * c
    path = np.concatenate([np.linspace(a, b, 40, endpoint=False) for a, b in zip(turns[:-1], turns[1:])]
                          + [turns[-1:]])
    exact = contact.to_iwan().memory().path(path)
    errors = {}
    for n in (256, 1024):
        table = contact.to_iwan(n).sliders_table
        ds = DrivenSliders([k for k, _ in table], [f for _, f in table])
        discrete = []
        for x in path:
            ds.update(x)
            discrete.append(ds.force)
        errors[n] = np.max(np.abs(np.array(discrete) - exact)) / fs
    assert errors[1024] < 1e-5 and errors[256] / errors[1024] > 10  # ~16 for N^-2
    # memory: the inner loop 0.4 -> 0.1 -> 0.5 closes at 0.4 and the branch from -0.3 resumes
    mem = contact.to_iwan().memory()
    for x in turns[:6]:
        mem.update(x)
    direct = contact.to_iwan().memory()
    for x in (0.0, 0.6 * c, -0.3 * c, 0.5 * c):
        direct.update(x)
    assert abs(mem.force - direct.force) <= 1e-15 * fs


def test_discrete_iwan_converges_at_second_order(contact):
    """sup over 0 < Q* <= 0.99 fP of |D_N - D| / D(fP): measured 5.1e-2 (N=4) ... 3.0e-6 (N=512),
    i.e. 0.81 / N^2; the backbone's sup error is 0.33 fP / N^2."""
    qs = np.linspace(0.0, 0.99, 300)[1:] * contact.slip_force
    ref = np.array([contact.dissipation_per_cycle(q) for q in qs])
    dmax = contact.dissipation_per_cycle(contact.slip_force)
    u = np.linspace(0, 1, 1001) * contact.slip_displacement
    errs, berrs = [], []
    for n in (8, 16, 32, 64, 128):
        iwan = contact.to_iwan(n)
        assert isinstance(iwan, fj.Iwan)
        assert abs(iwan.stiffness / contact.tangential_stiffness - 1) <= 1e-14
        assert abs(iwan.slip_force / contact.slip_force - 1) <= 1e-14
        d = np.array([iwan.dissipation_per_cycle(q) for q in qs])
        errs.append(np.max(np.abs(d - ref)) / dmax)
        berrs.append(np.max(np.abs(iwan.backbone(u) - contact.backbone(u))) / contact.slip_force)
    for e, b, n in zip(errs, berrs, (8, 16, 32, 64, 128)):
        assert 0.5 / n ** 2 < e < 1.2 / n ** 2
        assert 0.2 / n ** 2 < b < 0.5 / n ** 2
    rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all((rates > 1.8) & (rates < 2.2))


def test_discrete_iwan_dissipation_is_the_sum_of_jenkins_loops():
    """Two Jenkins sliders: D = sum 4 f_i (u* - phi_i) over the slipping ones (exact)."""
    iwan = fj.Iwan([(10.0, 1.0), (5.0, 2.0)])  # phi = 0.1, 0.4
    assert iwan.dissipation_per_displacement_cycle(0.3) == pytest.approx(4 * 1.0 * 0.2, rel=1e-15)
    q = iwan.backbone(0.3)
    assert q == pytest.approx(1.0 + 5.0 * 0.3, rel=1e-15)
    assert iwan.displacement(q) == pytest.approx(0.3, rel=1e-15)
    assert iwan.dissipation_per_cycle(q) == pytest.approx(0.8, rel=1e-14)
    # just below the macroslip force (3 N): the last slider's knot, not an index error
    assert iwan.displacement(np.nextafter(3.0, 0.0)) == pytest.approx(0.4, rel=1e-14)
    assert iwan.displacement(-1.0) == pytest.approx(-1.0 / 15.0, rel=1e-15)


@pytest.mark.parametrize("kwargs, name", [
    (dict(normal_load=-1.0), "normal_load"),
    (dict(normal_load=0.0), "normal_load"),
    (dict(friction_coefficient=0.0), "friction_coefficient"),
    (dict(friction_coefficient=float("nan")), "friction_coefficient"),
    (dict(radius=-0.01), "radius"),
    (dict(youngs_modulus=float("inf")), "youngs_modulus"),
    (dict(poisson_ratio=0.5), "poisson_ratio"),
    (dict(poisson_ratio=-1.0), "poisson_ratio"),
])
def test_invalid_contact_data(kwargs, name):
    args = dict(normal_load=P, friction_coefficient=MU, radius=R, youngs_modulus=E, poisson_ratio=NU)
    args.update(kwargs)
    with pytest.raises(fj.ParameterError, match=name):
        MindlinContact(**args)


def test_invalid_amplitudes(contact):
    with pytest.raises(fj.ParameterError, match="force_amplitude"):
        contact.dissipation_per_cycle(1.01 * contact.slip_force)
    with pytest.raises(fj.ParameterError, match="force_amplitude"):
        contact.dissipation_per_cycle(-1.0)
    with pytest.raises(fj.ParameterError, match="n_sliders"):
        contact.to_iwan(0)
    with pytest.raises(fj.ParameterError, match="force"):
        contact.to_iwan().dissipation_per_cycle(contact.slip_force)  # gross slip: no finite loop
