"""A dovetail root that rocks on its flanks (DovetailRoot with rocking_dof and flank_half_width) and
its contact dashpots: geometry, statics, the free-slip mechanism, and stuck orbits shaken down in
closed form (the driven flanks' tangent stiffness with rocking: tests/test_dovetail.py)."""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.errors import ParameterError

G, MU, KN, KT, A = math.radians(30.0), 0.3, 2e8, 1e8, 0.005


def rocking_root(fc=1e4, **kw):
    args = dict(flank_angle=G, friction_coefficient=MU, normal_stiffness=KN, tangential_stiffness=KT,
                tangential_dof=0, radial_dof=1, rocking_dof=2, flank_half_width=A)
    args.update(kw)
    return fj.DovetailRoot(fc, **args)


def test_rocking_rows_and_stuck_stiffness():
    """Each flank's contact point at X = +-a moves by (X, Y - x_i theta); the stuck stiffness is the
    sum over the flanks of kn r r^T + kt q q^T: XX = 2 (kn s^2 + kt c^2), YY = 2 (kn c^2 + kt s^2),
    rocking 2 a^2 (kn c^2 + kt s^2) (DESIGN section 4 for the translations, the lever arm a for the
    rocking), no coupling of theta with X or Y (symmetric flanks)."""
    r = rocking_root()
    assert r.root_coordinates == ("X", "Y", "theta")
    c, s = math.cos(G), math.sin(G)
    assert np.allclose(r.normal_rows, [[-s, -c, c * A], [s, -c, -c * A]], rtol=0, atol=1e-18)
    assert np.allclose(r.tangent_rows, [[-c, s, -s * A], [c, s, s * A]], rtol=0, atol=1e-18)
    k = r.stuck_stiffness()
    assert k[0, 0] == pytest.approx(2 * (KN * s * s + KT * c * c), rel=1e-15)
    assert k[1, 1] == pytest.approx(2 * (KN * c * c + KT * s * s), rel=1e-15)
    assert k[2, 2] == pytest.approx(2 * A * A * (KN * c * c + KT * s * s), rel=1e-15)
    assert abs(k[0, 1]) <= 1e-7 * k[0, 0] and abs(k[1, 2]) <= 1e-7 * k[1, 1] * A
    # without rocking the translation block is the same
    assert np.allclose(rocking_root(rocking_dof=None, flank_half_width=None).stuck_stiffness(), k[:2, :2],
                       rtol=1e-15, atol=1e-7 * k[0, 0])


def test_free_slip_mechanism():
    """Slipping on both flanks (no tangential stiffness), the normal springs alone leave one
    mechanism: translation X with rocking theta = X tan(g) / a, the root rolling along its inclined
    flanks; its normal approaches stay zero, so the normal forces stay N0 along it."""
    r = rocking_root()
    mech = np.array([1.0, 0.0, math.tan(G) / A])
    assert np.max(np.abs(r.normal_rows @ mech)) <= 1e-15
    d = r.driven(normal_load_variation=True)
    d.update(1e-7 * mech)
    assert np.allclose(d.normal_force, r.static.normal_force, rtol=1e-12)


def test_rocking_root_is_in_equilibrium_at_zero_and_has_its_dashpots():
    r = rocking_root(normal_damping=400.0)
    s = fj.FrictionSystem(fj.LinearStructure(np.diag([0.06, 0.06, 2e-5]), np.diag([1e6, 1e6, 10.0])), [r])
    total = s.constant_force - s.slider_direction.T @ s.slider_preload
    assert np.max(np.abs(total)) <= 1e-12 * r.centrifugal_force
    nn = r.normal_rows.T @ r.normal_rows
    assert np.max(np.abs(s.damping - 400.0 * nn)) <= 1e-15 * 400.0 * np.max(nn)
    assert np.max(np.abs(s.stiffness - np.diag([1e6, 1e6, 10.0]) - KN * nn)) <= 1e-15 * KN * np.max(nn)


@pytest.mark.parametrize("kw, name", [(dict(flank_half_width=None), "flank_half_width"),
                                      (dict(rocking_dof=None), "rocking_dof"),
                                      (dict(flank_half_width=-1e-3), "flank_half_width"),
                                      (dict(normal_damping=-1.0), "normal_damping")])
def test_bad_rocking_input_names_the_parameter(kw, name):
    with pytest.raises(ParameterError, match=name):
        rocking_root(**kw)


def test_shaken_down_stuck_orbit_in_closed_form():
    """Flanks preloaded to 96 % of their limit (stuck run-up, (kt/kn) tan g = 0.289 of mu = 0.3)
    slip in the transient and shake down into stick. The steady state is then the stuck linear
    orbit with the slider positions moved so that every flank force stays within its limit
    (Melan): found in closed form (no period marched), it is a fixed point of the exact period
    map (one period marched from it: no event, back to the start to 1e-12), its first harmonic is
    the stuck configuration's linear FRF, and its flank forces touch no limit."""
    from frictionjoint.solvers.marcher.events import EventLog, Marcher

    r = rocking_root(fc=2e3, normal_damping=10.0)
    st = fj.LinearStructure(np.diag([0.06, 0.06, 2e-5]), np.diag([2e6, 2e6, 50.0]), np.diag([30.0, 30.0, 1e-3]))
    omega = 2000.0
    sysm = fj.FrictionSystem(st, [r], omega=omega, excitation=[fj.HarmonicForce(2, 0.3)])
    res = fj.periodic_response(sysm)
    assert res.converged and res.stuck and res.periods == 0.0
    n = sysm.n_dof
    z = res.initial_state
    m = Marcher(sysm)
    state = m.initial_state(z[:n], z[n:2 * n], z[2 * n:])
    log = EventLog()
    m.march(state, 2 * math.pi / omega, log)
    assert len(log) == 0
    assert np.max(np.abs(state.x - z[:n])) <= 1e-12 * np.max(np.abs(z[:n]))
    # first harmonic: the stuck configuration's FRF
    k = sysm.stiffness + sum(kt * np.outer(d, d) for kt, d in zip(sysm.slider_stiffness, sysm.slider_direction))
    f = sysm.force_cos - 1j * sysm.force_sin
    x = np.linalg.solve(k + 1j * omega * sysm.damping - omega ** 2 * sysm.mass, f)
    assert np.allclose(res.harmonic_amplitude, np.abs(x), rtol=1e-10)
    # the preloaded start would slip: the positions moved, every force within its limit
    force = sysm.slider_stiffness * (sysm.slider_direction @ z[:n] - z[2 * n:])
    amp = sysm.slider_stiffness * np.abs(sysm.slider_direction @ x)
    assert np.all(np.abs(force - sysm.slider_stiffness * (sysm.slider_direction @ x).real) + amp
                  <= sysm.slip_force * (1 + 1e-12))
    assert np.any(np.abs(z[2 * n:] + sysm.slider_preload / sysm.slider_stiffness) > 1e-12)


def test_peak_of_an_output_and_root_replacement():
    """peak_response(output=row) maximises |row . X| (X the first harmonics of the DOFs): with the
    row of one DOF it is that DOF's peak; with_root/replace rebuild the root with new parameters,
    and bad ones name themselves."""
    st = fj.LinearStructure(np.diag([0.06, 0.06, 2e-5]), np.diag([2e6, 2e6, 50.0]), np.diag([30.0, 30.0, 1e-3]))

    def build(omega):
        return fj.FrictionSystem(st, [rocking_root(fc=2e3)], omega=omega, excitation=[fj.HarmonicForce(2, 0.3)])
    # the free-slip limit's first mode is 2845 rad/s, the stuck one's 19972 rad/s
    w1, a1, _ = fj.peak_response(build, 1000.0, 30000.0, dof=2, n_grid=15)
    w2, a2, _ = fj.peak_response(build, 1000.0, 30000.0, n_grid=15, output=[0.0, 0.0, 1.0])
    assert 1000.0 < w1 < 30000.0  # an interior peak
    assert w2 == pytest.approx(w1, rel=1e-6) and a2 == pytest.approx(a1, rel=1e-12)
    with pytest.raises(ParameterError, match="output"):
        fj.peak_response(build, 1000.0, 3000.0, output=[1.0, 0.0])
    r = rocking_root(fc=2e3)
    r2 = r.replace(centrifugal_force=4e3)
    assert r2.static.normal_force == pytest.approx(2 * r.static.normal_force, rel=1e-15)
    assert r2.flank_half_width == A and r.centrifugal_force == 2e3
    with pytest.raises(ParameterError, match="rotor"):
        r.replace(rotor=1.0)
