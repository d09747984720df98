"""Plane (half-plane) contact of a general profile and its Cattaneo partial slip (issue 4 item 1).

References, all evaluated here independently of the library:
- Hertz cylinder (Johnson 1985, Contact Mechanics, ch. 4): a^2 = 4 P R/(pi E*), p0 = 2 P/(pi a),
  p = p0 sqrt(1 - x^2/a^2); Cattaneo stick zone Q/fP = 1 - (c/a)^2 (Johnson ch. 7; DESIGN.md section 4).
- Rounded flat punch (Ciavarella, Hills & Monno 1998, Proc. IMechE 212 C): sin phi0 = b/a,
  P = (E* a^2/(4R)) [pi - 2 phi0 - sin 2 phi0]; stick zone sin psi0 = b/c,
  Q/fP = 1 - c^2 (pi - 2 psi0 - sin 2 psi0)/(a^2 (pi - 2 phi0 - sin 2 phi0)).
- Blunt wedge: p = (E* tan(alpha)/pi) arccosh(a/|x|), a = P/(E* tan(alpha)) (pressure checked against
  the integral equation itself below).
- Hertz cylinder dissipation per unit length (DESIGN.md section 4), u = Q*/(fP):
  D' = (2 f^2 P^2/(pi E*)) [2u - u^2 + 2 (1 - u) ln(1 - u)].
- The half-plane integral equations (seed generalized_cattaneo_partial_slip eqs. 4, 19, 21 with
  A = 2/E*): (2/(pi E*)) PV int p(s)/(x - s) ds = h'(x) in the contact; for the shear,
  (2/(pi E*)) PV int q(s)/(x - s) ds = 0 in the stick zone and = d(slip)/dx in the slip zones.
  Cauchy principal values here by singularity subtraction and Gauss-Legendre quadrature.
"""
import math
import time

import numpy as np
import pytest
import scipy.optimize as so

from frictionjoint.contact import HalfPlaneContact, HertzCylinder, Profile, RoundedFlatPunch, Wedge
from frictionjoint.elements.iwan import Iwan
from frictionjoint.elements.masing import ContinuousIwan
from frictionjoint.errors import ParameterError

E, NU, F = 210e9, 0.3, 0.5
E_STAR = E / (2.0 * (1.0 - NU ** 2))  # two bodies of one material
P, R, DEPTH = 1e5, 0.05, 0.05  # N/m, m, m

TOL_CLOSED = 1e-10  # normal contact and dissipation vs closed forms (smooth profiles)
TOL_STICK = 1e-8  # stick-zone size vs closed forms
TOL_PV = 1e-9  # integral equations, relative to the largest term
TOL_IWAN = 1e-8  # continuous Iwan element vs the contact

TS_T = np.arange(-60, 61) / 16.0  # tanh-sinh abscissae, step 1/16


def integrate(fun, lo, hi):
    """int_lo^hi fun by the tanh-sinh rule: accurate with square-root, logarithmic or x ln x
    behaviour at the ends (nodes placed by their distance to the nearer end)."""
    u = 0.5 * math.pi * np.sinh(TS_T)
    gap = (hi - lo) / (1.0 + np.exp(2.0 * np.abs(u)))
    x = np.where(TS_T < 0, lo + gap, hi - gap)
    w = (hi - lo) / 16.0 * 0.25 * math.pi * np.cosh(TS_T) / np.cosh(u) ** 2
    return float(np.sum(w * fun(x)))


def principal_value(fun, pieces, x):
    """PV int fun(s)/(x - s) ds over the union of consecutive ``pieces`` (edges), x inside:
    int (fun(s) - fun(x))/(x - s) ds + fun(x) ln((x - lo)/(hi - x)), piecewise."""
    fx = fun(np.array([x]))[0]
    total = sum(integrate(lambda s: (fun(s) - fx) / (x - s), lo, hi) for lo, hi in zip(pieces[:-1], pieces[1:]))
    return total + fx * math.log((x - pieces[0]) / (pieces[-1] - x))


def hertz_dissipation(q_star, p=P, f=F):
    u = q_star / (f * p)
    if u < 0.1:  # bracket = sum_{k>=3} 2 u^k/(k (k-1)), free of cancellation
        bracket = sum(2.0 * u ** k / (k * (k - 1)) for k in range(3, 40))
    else:
        bracket = 2.0 * u - u * u + (2.0 * (1.0 - u) * math.log1p(-u) if u < 1 else 0.0)
    return 2.0 * f * f * p * p / (math.pi * E_STAR) * bracket


@pytest.fixture(scope="module")
def hertz():
    return HalfPlaneContact(HertzCylinder(R), P, F, E, NU, reference_depth=DEPTH)


@pytest.fixture(scope="module")
def skew():
    """A convex non-symmetric profile h = x^2/(2R) (1 + x/(3 L)) with its exact slope."""
    length = 0.01
    prof = Profile(lambda x: x * x / (2 * R) * (1 + x / (3 * length)), lambda x: x / R + x * x / (2 * R * length))
    return HalfPlaneContact(prof, P, F, E, NU, reference_depth=DEPTH), prof


# ------------------------------------------------------------------ normal contact
def test_hertz_half_width_pressure_and_load(hertz):
    a = math.sqrt(4 * P * R / (math.pi * E_STAR))
    p0 = 2 * P / (math.pi * a)
    assert abs(hertz.contact_half_width / a - 1) <= TOL_CLOSED
    assert abs(hertz.peak_pressure / p0 - 1) <= TOL_CLOSED
    assert hertz.contact_offset == 0.0
    x = a * np.array([-0.95, -0.5, 0.1, 0.7, 0.999])
    assert np.max(np.abs(hertz.pressure(x) / (p0 * np.sqrt(1 - (x / a) ** 2)) - 1)) <= TOL_CLOSED
    assert hertz.pressure(1.01 * a) == 0.0
    assert abs(integrate(hertz.pressure, -a, a) / P - 1) <= TOL_CLOSED


@pytest.mark.parametrize("b, radius", [(1e-3, 0.01), (5e-3, 0.002), (1e-4, 0.05)])
@pytest.mark.parametrize("load", [1e4, 1e6])
def test_rounded_punch_half_width_and_stick_zone(b, radius, load):
    contact = HalfPlaneContact(RoundedFlatPunch(b, radius), load, F, E, NU, reference_depth=1.0)

    def carried(half):  # Ciavarella, Hills & Monno (1998)
        phi = math.asin(b / half)
        return E_STAR * half ** 2 / (4 * radius) * (math.pi - 2 * phi - math.sin(2 * phi))

    a = so.brentq(lambda s: carried(s) - load, b, 1.0, xtol=1e-300, rtol=1e-15)
    assert abs(contact.contact_half_width / a - 1) <= TOL_STICK
    total = sum(integrate(contact.pressure, lo, hi) for lo, hi in ((-a, -b), (-b, b), (b, a)))
    assert abs(total / load - 1) <= TOL_CLOSED  # pieces: p ~ x ln x at the corners
    for ratio in (0.1, 0.5, 0.9, 0.99):
        c, d = contact.stick_zone(ratio * F * load)
        c_ref = so.brentq(lambda s: 1 - carried(s) / carried(a) - ratio, b, a, xtol=1e-300, rtol=1e-15)
        assert abs(c / c_ref - 1) <= TOL_STICK and d == 0.0
        assert c > b  # the stick zone never enters the flat


@pytest.mark.parametrize("alpha", [0.01, 0.3])
def test_wedge_closed_form_and_integral_equation(alpha):
    contact = HalfPlaneContact(Wedge(alpha), P, F, E, NU, reference_depth=1.0)
    a = P / (E_STAR * math.tan(alpha))
    assert abs(contact.contact_half_width / a - 1) <= TOL_CLOSED
    assert contact.peak_pressure == math.inf  # log peak at the apex
    x = a * np.array([-0.9, -0.3, 0.05, 0.6, 0.99])
    closed = E_STAR * math.tan(alpha) / math.pi * np.arccosh(a / np.abs(x))
    assert np.max(np.abs(contact.pressure(x) / closed - 1)) <= TOL_CLOSED
    for xi in (-0.6 * a, 0.35 * a):  # (2/(pi E*)) PV int p/(x - s) = h'(x) = tan(alpha) sgn(x)
        pv = 2 / (math.pi * E_STAR) * principal_value(contact.pressure, [-a, 0.0, a], xi)
        assert abs(pv / (math.tan(alpha) * math.copysign(1, xi)) - 1) <= TOL_PV
    c, _ = contact.stick_zone(0.4 * F * P)  # P* proportional to c: c/a = 1 - Q/fP
    assert abs(c / (0.6 * a) - 1) <= TOL_STICK


def test_user_parabola_reproduces_hertz(hertz):
    """A plain callable (slope by finite differences) against the Hertz closed forms."""
    user = HalfPlaneContact(lambda x: x * x / (2 * R), P, F, E, NU, reference_depth=DEPTH)
    assert abs(user.contact_half_width / hertz.contact_half_width - 1) <= TOL_CLOSED
    assert abs(user.peak_pressure / hertz.peak_pressure - 1) <= TOL_CLOSED
    assert abs(user.contact_offset) <= TOL_CLOSED * user.contact_half_width
    q = 0.7 * F * P
    assert abs(user.stick_zone(q)[0] / hertz.stick_zone(q)[0] - 1) <= TOL_CLOSED
    assert abs(user.dissipation_per_cycle(q) / hertz_dissipation(q) - 1) <= TOL_CLOSED


def test_shifted_parabola_offset(hertz):
    x0 = 3e-3
    user = HalfPlaneContact(lambda x: (x - x0) ** 2 / (2 * R), P, F, E, NU, reference_depth=DEPTH)
    assert abs(user.contact_offset / x0 - 1) <= TOL_CLOSED
    assert abs(user.contact_half_width / hertz.contact_half_width - 1) <= TOL_CLOSED
    c, d = user.stick_zone(0.5 * F * P)
    assert abs(d / x0 - 1) <= TOL_CLOSED and abs(c / hertz.stick_zone(0.5 * F * P)[0] - 1) <= TOL_CLOSED


def test_tilt_and_load_line_on_a_cylinder(hertz):
    """Gap x^2/(2R) - theta x is a parabola centred at R theta; with free tilt the contact centres
    under the load line (theta = x_L/R)."""
    tilted = HalfPlaneContact(HertzCylinder(R), P, F, E, NU, reference_depth=DEPTH, tilt=0.01)
    assert abs(tilted.contact_offset / (R * 0.01) - 1) <= TOL_CLOSED
    assert abs(tilted.stick_zone(0.5 * F * P)[1] / (R * 0.01) - 1) <= TOL_CLOSED
    free = HalfPlaneContact(HertzCylinder(R), P, F, E, NU, reference_depth=DEPTH, load_line=2e-4)
    assert abs(free.contact_offset / 2e-4 - 1) <= TOL_CLOSED
    assert abs(free.tilt / (2e-4 / R) - 1) <= TOL_CLOSED
    assert abs(free.contact_half_width / hertz.contact_half_width - 1) <= TOL_CLOSED


def test_non_symmetric_profile_equilibrium_and_integral_equation(skew):
    contact, prof = skew
    a, e = contact.contact_half_width, contact.contact_offset
    assert e < 0  # the profile rises faster on the right
    assert abs(integrate(contact.pressure, e - a, e + a) / P - 1) <= TOL_CLOSED
    for x in e + a * np.array([-0.8, -0.1, 0.5]):
        pv = 2 / (math.pi * E_STAR) * principal_value(contact.pressure, [e - a, e + a], x)
        assert abs(pv - prof.slope(x)) <= TOL_PV * prof.slope(e + a)
    # zero moment about x_L = 0 when the tilt is free
    free = HalfPlaneContact(prof, P, F, E, NU, reference_depth=DEPTH, load_line=0.0)
    a, e = free.contact_half_width, free.contact_offset
    assert abs(integrate(lambda x: free.pressure(x) * x, e - a, e + a)) <= TOL_CLOSED * P * a
    assert abs(integrate(free.pressure, e - a, e + a) / P - 1) <= TOL_CLOSED


# ------------------------------------------------------------------ partial slip
@pytest.mark.parametrize("ratio", [0.1, 0.5, 0.9, 0.99])
def test_hertz_stick_zone_and_shear(hertz, ratio):
    a = hertz.contact_half_width
    q = ratio * F * P
    c, d = hertz.stick_zone(q)
    assert abs((1 - (c / a) ** 2) / ratio - 1) <= TOL_STICK and d == 0.0
    total = (integrate(lambda x: hertz.shear_traction(x, q), -a, -c) + integrate(lambda x: hertz.shear_traction(x, q), -c, c)
             + integrate(lambda x: hertz.shear_traction(x, q), c, a))
    assert abs(total / q - 1) <= TOL_CLOSED
    x = np.linspace(-a, a, 41)
    assert np.all(hertz.shear_traction(x, q) <= F * hertz.pressure(x) * (1 + 1e-12))  # Coulomb


@pytest.mark.parametrize("ratio", [0.3, 0.8])
def test_stick_and_slip_satisfy_the_tangential_integral_equation(skew, ratio):
    """Seed eqs. 19 and 21: g' = (2/(pi E*)) PV int q/(x - s) ds is 0 in the stick zone and the
    slope of the slip in the slip zones (non-symmetric profile: offset stick zone)."""
    contact, _ = skew
    a, e = contact.contact_half_width, contact.contact_offset
    q = ratio * F * P
    c, d = contact.stick_zone(q)
    assert abs(integrate(lambda x: contact.shear_traction(x, q), e - a, d - c)
               + integrate(lambda x: contact.shear_traction(x, q), d - c, d + c)
               + integrate(lambda x: contact.shear_traction(x, q), d + c, e + a) - q) <= TOL_CLOSED * q
    edges = [e - a, d - c, d + c, e + a]
    scale = F * contact.peak_pressure / E_STAR  # natural size of g'

    def g1(x):
        return 2 / (math.pi * E_STAR) * principal_value(lambda s: contact.shear_traction(s, q), edges, x)

    for x in (d - 0.6 * c, d + 0.3 * c):
        assert abs(g1(x)) <= TOL_PV * scale
    for x in (e - a + 0.4 * (d - c - e + a), d + c + 0.45 * (e + a - d - c)):  # not a node
        h = 1e-5 * a
        slope = (contact.local_slip(x + h, q) - contact.local_slip(x - h, q)) / (2 * h)
        assert abs(g1(x) - slope) <= 1e-8 * scale  # central difference O(h^2): 5e-10 measured
    assert contact.local_slip(d, q) == 0.0
    assert contact.local_slip(e + a, q) > contact.local_slip(d + c + 0.5 * (e + a - d - c), q) > 0


@pytest.mark.parametrize("ratio", [1e-3, 0.1, 0.5, 0.9, 0.99, 1.0])
def test_hertz_dissipation_closed_form(hertz, ratio):
    q = ratio * F * P
    assert abs(hertz.dissipation_per_cycle(q) / hertz_dissipation(q) - 1) <= TOL_CLOSED


@pytest.mark.parametrize("profile", [HertzCylinder(R), RoundedFlatPunch(2e-4, 0.02)])
def test_dissipation_is_friction_work(profile):
    """Independent of the compliance integral: per cycle each slip-zone point slides 2 s(x) back
    and 2 s(x) forth under f p, D = 4 f int p(x) s(x) dx (s = slip at Q*)."""
    contact = HalfPlaneContact(profile, P, F, E, NU, reference_depth=DEPTH)
    a = contact.contact_half_width
    q = 0.6 * F * P
    c, _ = contact.stick_zone(q)

    def work(x):
        return np.array([contact.pressure(xi) * contact.local_slip(xi, q) for xi in x])

    brute = 4 * F * (integrate(work, -a, -c) + integrate(work, c, a))
    assert abs(contact.dissipation_per_cycle(q) / brute - 1) <= 1e-9


def test_reference_depth_changes_only_the_linear_part(hertz):
    deep = HalfPlaneContact(HertzCylinder(R), P, F, E, NU, reference_depth=100 * DEPTH)
    a = hertz.contact_half_width
    flex = 2 / (math.pi * E_STAR)
    k0 = 1 / (flex * (math.log(2 * DEPTH / a) + 1 / (2 * (1 - NU))))  # Flamant depth term
    assert abs(hertz.tangential_stiffness / k0 - 1) <= 1e-13
    for ratio in (0.2, 0.9):
        q = ratio * F * P
        shift = deep.displacement(q) - hertz.displacement(q)
        assert abs(shift / (flex * q * math.log(100)) - 1) <= 1e-12
        # compliance d delta/dQ = (2/(pi E*)) [ln(2 D/c) + 1/(2(1 - nu))] by central differences
        c, _ = hertz.stick_zone(q)
        h = 1e-4 * q
        slope = (hertz.displacement(q + h) - hertz.displacement(q - h)) / (2 * h)
        assert abs(slope * E_STAR * math.pi / 2 - math.log(2 * DEPTH / c) - 1 / (2 * (1 - NU))) <= 1e-6
        # Masing dissipation from either backbone: the same
        d1 = hertz.to_iwan().dissipation_per_cycle(q)
        d2 = deep.to_iwan().dissipation_per_cycle(q)
        assert abs(d1 / d2 - 1) <= TOL_IWAN and abs(d1 / hertz_dissipation(q) - 1) <= TOL_IWAN


def test_masing_loop_area_from_displacements(hertz):
    """Loop area of delta_dn(Q) = d* - 2 d((Q* - Q)/2) and delta_up(Q) = -d* + 2 d((Q + Q*)/2)."""
    q_star = 0.5 * F * P
    d = hertz.displacement
    d_star = d(q_star)
    x, w = np.polynomial.legendre.leggauss(24)
    q = q_star * x
    area = q_star * sum(wi * ((d_star - 2 * d((q_star - qi) / 2)) - (-d_star + 2 * d((qi + q_star) / 2)))
                        for qi, wi in zip(q, w))
    assert abs(area / hertz_dissipation(q_star) - 1) <= 1e-9


# ------------------------------------------------------------------ Iwan elements and length
@pytest.mark.parametrize("profile", [HertzCylinder(R), RoundedFlatPunch(2e-4, 0.02)])
def test_continuous_iwan_reproduces_backbone_and_dissipation(profile):
    contact = HalfPlaneContact(profile, 2e3, F, E, NU, reference_depth=DEPTH, length=0.02)  # 1e5 N/m
    iwan = contact.to_iwan()
    assert isinstance(iwan, ContinuousIwan)
    assert iwan.stiffness == contact.tangential_stiffness and iwan.slip_force == contact.slip_force
    for ratio in (0.05, 0.5, 0.999):
        q = ratio * contact.slip_force
        u = contact.displacement(q)
        assert abs(iwan.backbone(u) / q - 1) <= TOL_IWAN
        assert abs(contact.backbone(-u) / -q - 1) <= TOL_IWAN
        assert abs(iwan.dissipation_per_cycle(q) / contact.dissipation_per_cycle(q) - 1) <= TOL_IWAN
    assert contact.backbone(2 * contact.slip_displacement) == contact.slip_force
    if isinstance(profile, HertzCylinder):  # forces over length = 0.02 m: N/m times 0.02
        assert abs(contact.dissipation_per_cycle(0.5 * contact.slip_force)
                   / (0.02 * hertz_dissipation(0.5 * F * 1e5)) - 1) <= TOL_CLOSED


def test_discrete_iwan_converges_at_second_order():
    """Worst relative dissipation error over Q*/fP in [0.25, 0.95]: measured rate 2.00 (N = 8 ... 64)."""
    contact = HalfPlaneContact(RoundedFlatPunch(2e-4, 0.02), P, F, E, NU, reference_depth=DEPTH)
    q = np.linspace(0.25, 0.95, 8) * contact.slip_force
    exact = [contact.dissipation_per_cycle(qi) for qi in q]
    errors = []
    for n in (8, 16, 32, 64):
        iwan = contact.to_iwan(n)
        assert isinstance(iwan, Iwan)
        assert abs(iwan.stiffness / contact.tangential_stiffness - 1) <= 1e-12
        assert abs(iwan.slip_force / contact.slip_force - 1) <= 1e-12
        errors.append(max(abs(iwan.dissipation_per_cycle(qi) / ei - 1) for qi, ei in zip(q, exact)))
    rates = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(rates > 1.9) and errors[-1] < 3e-3


def test_fast_enough():
    """A general profile's dissipation in well under a second: the process's CPU time, not the wall
    time (another process on a shared 2-core machine stretched the wall time from 0.7 s to 3 s and
    failed a 2 s bound), measured 0.5 s; the bound, 20x that, catches a regression by an order of
    magnitude on any machine, and leaves the speed itself to the benchmarks."""
    start = time.process_time()
    contact = HalfPlaneContact(lambda x: np.cosh(x / R) - 1.0, P, F, E, NU, reference_depth=DEPTH)
    contact.dissipation_per_cycle(0.5 * contact.slip_force)
    assert time.process_time() - start < 10.0


# ------------------------------------------------------------------ invalid data
def _args(**change):
    kw = dict(profile=HertzCylinder(R), normal_load=P, friction_coefficient=F, youngs_modulus=E,
              poisson_ratio=NU, reference_depth=DEPTH)
    kw.update(change)
    return kw


@pytest.mark.parametrize("change, name", [
    (dict(normal_load=0.0), "normal_load"),
    (dict(normal_load=-1.0), "normal_load"),
    (dict(friction_coefficient=0.0), "friction_coefficient"),
    (dict(youngs_modulus=-E), "youngs_modulus"),
    (dict(poisson_ratio=0.5), "poisson_ratio"),
    (dict(poisson_ratio=-1.0), "poisson_ratio"),
    (dict(reference_depth=1e-4), "reference_depth"),  # inside the contact (a = 0.18 mm)
    (dict(length=0.0), "length"),
    (dict(tilt=0.0, load_line=0.0), "tilt"),
    (dict(n_nodes=4), "n_nodes"),
    (dict(profile=3.0), "profile"),
    (dict(profile=lambda x: 0.0 * x), "profile"),  # flat with sharp edges: no incomplete contact
    (dict(profile=lambda x: 1e-3 * x), "profile"),  # no minimum: consistency has no root
    (dict(profile=lambda x: x * x / (2 * R) - 1e-6), "h must be >= 0"),
    (dict(profile=lambda x: (x * x - 1e-8) ** 2 / 1e-6), "convex"),  # two wells
    (dict(profile=Wedge(0.1), tilt=0.2), "tilt"),  # steeper than the flanks
])
def test_invalid_data_is_named(change, name):
    with pytest.raises(ParameterError, match=name):
        HalfPlaneContact(**_args(**change))


def test_invalid_profiles_and_forces(hertz):
    with pytest.raises(ParameterError, match="radius"):
        HertzCylinder(0.0)
    with pytest.raises(ParameterError, match="corner_radius"):
        RoundedFlatPunch(1e-3, -1.0)
    with pytest.raises(ParameterError, match="flat_half_width"):
        RoundedFlatPunch(-1e-3, 1.0)
    with pytest.raises(ParameterError, match="angle"):
        Wedge(math.pi / 2)
    with pytest.raises(ParameterError, match="breakpoints"):
        Profile(lambda x: x * x, breakpoints=[0.0, 0.0])
    with pytest.raises(ParameterError, match="tangential_force"):
        hertz.stick_zone(1.01 * hertz.slip_force)
    with pytest.raises(ParameterError, match="force_amplitude"):
        hertz.dissipation_per_cycle(-1.0)
    with pytest.raises(ParameterError, match="x must lie"):
        hertz.local_slip(2 * hertz.contact_half_width, 0.5 * hertz.slip_force)
    with pytest.raises(ParameterError, match="n_sliders"):
        hertz.to_iwan(0)
