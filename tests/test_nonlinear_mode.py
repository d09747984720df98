"""Nonlinear modes by the extended periodic motion concept (issue 31, parts 1-2): the single-DOF
Jenkins oscillator at H = 1 against the describing function's closed form, written here
independently; the energy balance of the EPMC orbit; a 2-DOF chain and the blade against the
exact free decay from points of the mode.

Tolerances: the closed form 1e-9 (measured 7e-16 in frequency, 4e-15 in damping ratio). Against the
free decay, a cycle is compared with the mode at one amplitude while the decay's amplitude falls by
about 2 pi zeta over it: the difference is of the second order in zeta (measured on the chain about
zeta^2 in frequency, 3 zeta^2 in energy), so the bounds are 2 zeta^2 and 4 zeta^2 where zeta <=
0.017; the stuck points (linear: only the damped against the undamped frequency, zeta^2 / 2) 1e-6.

Against the EPMC's own orbit solved exactly in time (frictionjoint.solvers.marcher.autonomous): a
linear system's closed form to 1e-9 (measured 6e-15 in frequency, 1e-10 in xi: the shooting's
tolerance); the orbit the same from any start to 1e-9 (measured 5e-11); the harmonic balance's
difference from it is its truncation, bounded by what was measured (the blade's: see the guide).
"""
import math
import warnings

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import frictionjoint as fj
from frictionjoint.errors import ParameterError
from frictionjoint.solvers.frequency_domain.nonlinear_mode import free_system, nonlinear_mode, orbit_starts
from frictionjoint.solvers.marcher.autonomous import mode_branch, mode_orbit, mode_orbits

CLOSED_FORM_TOL = 1e-9
#: the exact orbit against a closed form, and against itself from another start
EXACT_TOL = 1e-9


def jenkins_describing_function(a, kt, fs):
    """First-harmonic stiffness and energy per cycle of a Jenkins element (spring kt, slider Fs)
    under u = a cos(theta): stuck (kt, 0) for kt a <= Fs; beyond, with cos(beta) = 1 - 2 Fs/(kt a),
    the loop sticks for theta in (0, beta) after each reversal and slips at -+Fs until the next:
    k_eq = (kt / pi) (beta - sin(2 beta) / 2) (the cosine component of the force over pi a, the
    loop's half-wave symmetry), D = 4 Fs (a - Fs/kt) (the area of the parallelogram)."""
    if kt * a <= fs:
        return kt, 0.0
    beta = math.acos(1.0 - 2.0 * fs / (kt * a))
    return kt / math.pi * (beta - math.sin(2 * beta) / 2), 4.0 * fs * (a - fs / kt)


def sdof_mode_closed_form(a, m, k, c, kt, fs):
    """The EPMC of m x'' + (c - xi m) x' + k x + T = 0 with x = a cos(omega t): omega^2 = (k +
    k_eq)/m from the cosine balance; from the sine balance (the power balance) xi m omega pi a^2 =
    c omega pi a^2 + D, so zeta = xi / (2 omega)."""
    keq, d = jenkins_describing_function(a, kt, fs)
    w = math.sqrt((k + keq) / m)
    xi = c / m + d / (math.pi * a * a * w * m)
    return w, xi / (2 * w)


def test_describing_function_limits_and_quadrature():
    """The closed form itself: kt and 0 at the slip onset a = Fs/kt, continuous there; 0 stiffness
    and D / (4 Fs a) -> 1 deep in slip; k_eq against a direct quadrature of the loop (2^16 points)."""
    kt, fs = 5.0, 0.1
    a0 = fs / kt
    assert jenkins_describing_function(a0, kt, fs) == (kt, 0.0)
    k_just, d_just = jenkins_describing_function(a0 * (1 + 1e-12), kt, fs)
    assert abs(k_just - kt) <= 1e-4 * kt and d_just <= 1e-11
    k_far, d_far = jenkins_describing_function(1e8 * a0, kt, fs)
    assert k_far <= 1e-10 * kt and abs(d_far / (4 * fs * 1e8 * a0) - 1) <= 1e-7
    a = 3.0 * a0
    theta = np.linspace(0.0, 2 * math.pi, 2 ** 16, endpoint=False)
    u = a * np.cos(theta)
    t = np.empty_like(u)
    w = a - fs / kt  # slider position just after the maximum (it slipped forward)
    for _ in range(2):  # march the return map twice round: the second lap is the steady loop
        for i, ui in enumerate(u):
            w = min(max(w, ui - fs / kt), ui + fs / kt)
            t[i] = kt * (ui - w)
    keq_num = 2 * np.mean(t * np.cos(theta)) / a
    assert abs(keq_num - jenkins_describing_function(a, kt, fs)[0]) <= 1e-3 * kt


def test_sdof_jenkins_one_harmonic_is_the_describing_function():
    """H = 1 on m = k = 1, c = 0.02, kt = 5, Fs = 0.1: frequency and damping ratio equal the closed
    form to 1e-9 from fully stuck (a < Fs/kt = 0.02) to deep slip (a = 100)."""
    m, k, c, kt, fs = 1.0, 1.0, 0.02, 5.0, 0.1
    system = fj.FrictionSystem(fj.LinearStructure([[m]], [[k]], [[c]]), [fj.Jenkins(kt, fs, dof=0)])
    amps = np.geomspace(0.005, 100.0, 40)
    nm = nonlinear_mode(system, amplitudes=amps, n_harmonics=1)
    assert nm.success and nm.status == "ok"
    ref = np.array([sdof_mode_closed_form(a, m, k, c, kt, fs) for a in amps])
    assert np.max(np.abs(nm.frequency - ref[:, 0]) / ref[:, 0]) <= CLOSED_FORM_TOL
    assert np.max(np.abs(nm.damping_ratio - ref[:, 1]) / ref[:, 1]) <= CLOSED_FORM_TOL
    assert np.all(nm.stuck == (kt * amps <= fs))
    # the linear limits: stuck sqrt((k + kt)/m), free slip sqrt(k/m), zeta = c / (2 m omega)
    assert abs(nm.stuck_frequency - math.sqrt(6.0)) <= 1e-12 * math.sqrt(6.0)
    assert abs(nm.slipping_frequency - 1.0) <= 1e-12
    assert abs(nm.stuck_damping_ratio - c / (2 * math.sqrt(6.0))) <= 1e-12
    assert abs(nm.slipping_damping_ratio - c / 2) <= 1e-12
    np.testing.assert_allclose(np.abs(nm.harmonics[:, 1, 0]), amps, rtol=1e-12)


def chain(c_ratio=0.002):
    """A 2-DOF chain ground-k-m1-k-m2 (unit masses and springs), C = c_ratio K, a Jenkins joint (kt
    = 0.3, Fs = 0.05) from m1 to the ground."""
    k = np.array([[2.0, -1.0], [-1.0, 1.0]])
    return fj.FrictionSystem(fj.LinearStructure(np.eye(2), k, c_ratio * k), [fj.Jenkins(0.3, 0.05, dof=0)])


def test_energy_balance_and_the_amplitude_dof():
    """The negative damping's energy per period equals friction's plus the dashpots' (the power
    balance of the Galerkin equations, exact to Newton's tolerance); the default DOF is the one
    with the largest component of the stuck mode (m2 on the chain's first mode), and its first
    harmonic is A cos(omega t)."""
    nm = nonlinear_mode(chain(0.02), amplitudes=[0.1, 0.5, 2.0, 10.0], n_harmonics=7)
    assert nm.success and nm.dof == 1
    balance = nm.friction_per_cycle + nm.viscous_per_cycle
    np.testing.assert_allclose(nm.dissipated_per_cycle, balance, rtol=1e-9)
    np.testing.assert_allclose(nm.harmonics[:, 1, 1], nm.amplitude, rtol=0, atol=1e-12 * nm.amplitude.max())
    assert nm.stuck[0] and not nm.stuck[-1]


def test_chain_against_the_exact_free_decay():
    """The chain at H = 15, 4 cycles of the exact free decay from each checked point: the stuck
    points to 1e-6 (measured 1.7e-7 and 1.3e-8: only zeta^2 / 2), the slipping ones with zeta <= 0.017
    within 2 zeta^2 (frequency) and 4 zeta^2 (energy lost per cycle); measured at zeta = 0.0166,
    0.0114, 0.0076, 0.0035, 0.0025: 4.5e-4, 1.1e-4, 3.2e-5, 7.6e-6, 5.8e-6 and 8.4e-4, 3.1e-4,
    1.7e-4, 3.3e-5, 1.6e-5."""
    amps = [0.1, 2.0, 3.165, 5.018, 12.61, 20.0]
    nm = nonlinear_mode(chain(), amplitudes=amps, n_harmonics=15, check=True)
    assert nm.success and len(nm.decays) == len(amps)
    assert nm.stuck[0] and not np.any(nm.stuck[1:])
    assert nm.frequency_error[0] <= 1e-6 and nm.energy_error[0] <= 1e-6
    zeta = nm.damping_ratio[1:]
    assert np.all(zeta <= 0.017)
    assert np.all(nm.frequency_error[1:] <= 2 * zeta ** 2), (nm.frequency_error, zeta)
    assert np.all(nm.energy_error[1:] <= 4 * zeta ** 2), (nm.energy_error, zeta)
    for dc in nm.decays:
        assert dc.success and dc.amplitude.size == 4
        assert np.all(np.diff(dc.amplitude) < 0)  # it decays


@pytest.mark.slow
def test_blade_against_the_exact_free_decay():
    """The Ti-6Al-4V blade on its dovetail (frozen normal loads, centrifugal force 259 N), H = 15,
    deep in slip where the friction's share of the damping is small (zeta <= 0.0035): the free decay
    within 1e-3 in energy per cycle and 1e-4 in frequency (measured: see the guide). Where the root
    damps most (zeta up to 0.12 near 2e-5 m at w0) a cycle loses a quarter of its energy and the
    root's slip dies within a cycle or two: a cycle cannot be compared with one amplitude there."""
    from frictionjoint.structures import BladeAssembly, load_blade_model

    asm = BladeAssembly.from_model(load_blade_model("ti64_compressor_blade")).with_root(centrifugal_force=259.0)
    amps = np.geomspace(2e-4, 1e-2, 6)
    nm = nonlinear_mode(asm.system(2000.0), amplitudes=amps, n_harmonics=15, dof="w0", check=amps[-3:])
    assert nm.success
    assert abs(nm.slipping_frequency - nm.frequency[-1]) <= 1e-3 * nm.slipping_frequency
    checked = np.isfinite(nm.energy_error)
    assert checked.sum() == 3
    assert np.all(nm.damping_ratio[checked] <= 0.0035)
    assert np.all(nm.energy_error[checked] <= 1e-3), nm.energy_error
    assert np.all(nm.frequency_error[checked] <= 1e-4), nm.frequency_error


def test_base_motion_leaves_its_spring_and_the_plot(tmp_path):
    """A harmonic base motion is removed but its spring to the base stays: the stuck frequency is
    sqrt((k + kb + kt) / m). The plot draws frequency and damping ratio with both limits."""
    st = fj.LinearStructure([[1.0]], [[0.5]], [[0.01]])
    system = fj.FrictionSystem(st, [fj.Jenkins(5.0, 0.1, dof=0)], omega=1.4,
                               excitation=[fj.HarmonicBaseMotion(0, 0.5, 0.3, damping=0.01)])
    nm = nonlinear_mode(system, amplitudes=np.geomspace(0.01, 1.0, 8), n_harmonics=3, check=[1.0])
    assert abs(nm.stuck_frequency - math.sqrt(6.0)) <= 1e-12 * math.sqrt(6.0)
    assert abs(nm.frequency[0] - math.sqrt(6.0)) <= 1e-10
    assert abs(nm.slipping_frequency - 1.0) <= 1e-12
    fig = nm.plot(path=tmp_path / "mode.png")
    assert (tmp_path / "mode.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(fig.axes) == 2
    dashed = [line for line in fig.axes[0].lines if line.get_linestyle() == "--"]
    assert len(dashed) == 2


def test_refusals():
    system = chain()
    for bad in ([], [0.1, -1.0], [np.nan]):
        with pytest.raises(ParameterError, match="amplitudes"):
            nonlinear_mode(system, amplitudes=bad)
    with pytest.raises(ParameterError, match="no joint sliders"):
        nonlinear_mode(fj.FrictionSystem(fj.LinearStructure([[1.0]], [[1.0]])), amplitudes=[0.1])
    with pytest.raises(ParameterError, match="rigid"):
        nonlinear_mode(fj.FrictionSystem(fj.LinearStructure([[1.0]], [[1.0]]), [fj.CoulombSlider(0.1, dof=0)]),
                       amplitudes=[0.1])
    with pytest.raises(ParameterError, match="mode"):
        nonlinear_mode(system, mode=5, amplitudes=[0.1])


def test_guide_example_runs(tmp_path, monkeypatch):
    """The Python example of docs/nonlinear-modes.md."""
    from pathlib import Path
    import re

    text = (Path(__file__).resolve().parents[1] / "docs" / "nonlinear-modes.md").read_text()
    blocks = [b for b in re.findall(r"^```python\n(.*?)^```", text, re.S | re.M) if "nm = fj.nonlinear_mode(" in b]
    assert len(blocks) == 1
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "guide"}
    exec(compile(blocks[0], "docs/nonlinear-modes.md:python-example", "exec"), namespace)
    nm = namespace["nm"]
    checked = np.isfinite(nm.energy_error)
    assert nm.success and checked.sum() == 2
    zeta = nm.damping_ratio[checked]
    assert np.all(nm.frequency_error[checked] <= 2 * zeta ** 2) and np.all(nm.energy_error[checked] <= 4 * zeta ** 2)
    assert (tmp_path / "nonlinear_mode.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.slow
def test_blade_branch_through_the_modal_interaction():
    """The blade's mode at H = 7 from stuck (1e-7 m at w0) to deep slip (1e-2 m): between 1.5e-5 and
    3e-5 m the third harmonic meets the second flapwise mode and the branch folds in amplitude
    (twice each time); arc length takes the point-by-point continuation past both, so every
    amplitude converges, and the frequency falls from the stuck limit to the free-slip one."""
    from frictionjoint.structures import BladeAssembly, load_blade_model

    asm = BladeAssembly.from_model(load_blade_model("ti64_compressor_blade")).with_root(centrifugal_force=259.0)
    nm = nonlinear_mode(asm.system(2000.0), amplitudes=np.geomspace(1e-7, 1e-2, 41), n_harmonics=7, dof="w0")
    assert nm.success, nm.message
    assert "by arc length" in nm.message and "2 folds" in nm.message
    assert abs(nm.frequency[0] - nm.stuck_frequency) <= 1e-9 * nm.stuck_frequency
    assert abs(nm.frequency[-1] - nm.slipping_frequency) <= 1e-4 * nm.slipping_frequency
    assert 0.1 <= nm.damping_ratio.max() <= 0.13  # measured 0.117


def exact_against_balance(system, nm, points=None):
    """The exact EPMC orbits at the converged points of ``nm`` (each from its balanced state) and
    the balance's relative differences from them in frequency and damping ratio, printed."""
    points = np.flatnonzero(nm.converged) if points is None else points
    orbits = mode_orbits(free_system(system), nm.dof, orbit_starts(system, nm, points))
    w = np.array([o.frequency for o in orbits])
    z = np.array([o.damping_ratio for o in orbits])
    dw = np.abs(nm.frequency[points] / w - 1)
    dz = np.abs(nm.damping_ratio[points] / z - 1)
    print(f"\n  amplitude [m]  zeta exact  omega exact [rad/s]  H = {nm.n_harmonics}: d omega  d zeta  (Newton its)")
    for k, o, a, b in zip(points, orbits, dw, dz):
        print(f"  {nm.amplitude[k]:.4e}  {o.damping_ratio:.6f}  {o.frequency:.6f}  {a:.2e}  {b:.2e}  ({o.iterations})")
    return orbits, dw, dz


def test_exact_orbit_closed_form_and_harmonic_convergence():
    """The exact EPMC orbit (shooting on the event-driven march with the period and xi unknown):
    (1) on a linear system (a 2-DOF chain whose Jenkins joint never slips, C = alpha M + beta K_stuck)
    from a start 10 % off, omega = the undamped mode's and xi = alpha + beta omega^2 exactly, for
    both modes; (2) on the single-DOF Jenkins, the same orbit from the H = 1 and the H = 45 points
    (to 1e-9), and the harmonic balance converging to it as H grows (measured: H = 1 3.4e-2 in
    zeta, H = 15 2.5e-5, H = 45 3.5e-7); (3) its branch by arc length through the same orbits."""
    import scipy.linalg

    alpha, beta, kt = 0.01, 0.002, 0.3
    k, m = np.array([[2.0, -1.0], [-1.0, 1.0]]), np.diag([1.0, 2.0])
    k_stuck = k + np.diag([kt, 0.0])
    linear = fj.FrictionSystem(fj.LinearStructure(m, k, alpha * m + beta * k_stuck), [fj.Jenkins(kt, 1e6, dof=0)])
    lam, vec = scipy.linalg.eigh(k_stuck, m)
    for j in range(2):
        w, phi = math.sqrt(lam[j]), vec[:, j] / vec[1, j]
        o = mode_orbit(linear, np.r_[1.1 * phi, 0.05 * w * phi, 1.1 * phi[0]], 2 * math.pi / w * 1.02, 0.0, 1, 1.0)
        assert o.converged, o.message
        assert abs(o.frequency / w - 1) <= EXACT_TOL
        assert abs(o.negative_damping / (alpha + beta * w * w) - 1) <= EXACT_TOL
        assert abs(abs(o.harmonics[1, 1]) - 1.0) <= EXACT_TOL and np.max(np.abs(o.harmonics[2:])) <= 1e-9

    system = fj.FrictionSystem(fj.LinearStructure([[1.0]], [[1.0]], [[0.02]]), [fj.Jenkins(5.0, 0.1, dof=0)])
    amps = np.array([0.01, 0.03, 0.1, 1.0, 10.0])
    errors, exact = {}, {}
    for hh in (1, 15, 45):
        nm = nonlinear_mode(system, amplitudes=amps, n_harmonics=hh)
        orbits, dw, dz = exact_against_balance(system, nm)
        assert all(o.converged for o in orbits)
        exact[hh] = np.array([[o.frequency, o.damping_ratio] for o in orbits])
        errors[hh] = max(dw.max(), dz.max())
    np.testing.assert_allclose(exact[1], exact[45], rtol=EXACT_TOL)
    assert errors[1] > 1e-2 and errors[15] <= 5e-5 and errors[45] <= 1e-6, errors
    # (3) the branch by pseudo-arclength from the orbits at 0.1 and 0.12 to 1: each point is the
    # orbit solved at its amplitude from a start 1 % off (measured 7e-12)
    nm = nonlinear_mode(system, amplitudes=[0.1, 0.12], n_harmonics=15)
    first, second = mode_orbits(free_system(system), 0, orbit_starts(system, nm, [0, 1]))
    branch = mode_branch(free_system(system), 0, first, second, 1.0, x_scale=[0.1])
    assert len(branch) >= 5 and branch[-1].amplitude >= 1.0 and np.all(np.diff([o.amplitude for o in branch]) > 0)
    for o in branch:
        ref = mode_orbit(free_system(system), o.state, 2 * math.pi / o.frequency * 1.01, o.negative_damping * 1.01,
                         0, o.amplitude)
        assert abs(o.frequency / ref.frequency - 1) <= EXACT_TOL and abs(o.damping_ratio / ref.damping_ratio - 1) <= EXACT_TOL


def blade(normal_load_variation=False):
    """The Ti-6Al-4V blade on its dovetail (centrifugal force 259 N), as the guide's."""
    from frictionjoint.structures import BladeAssembly, load_blade_model

    asm = BladeAssembly.from_model(load_blade_model("ti64_compressor_blade")).with_root(
        centrifugal_force=259.0, normal_load_variation=normal_load_variation)
    return asm.system(2000.0)


@pytest.fixture(scope="module")
def blade_below_the_folds():
    """The blade (frozen normal loads) at H = 15 and H = 7 from stuck (1e-7 m at w0) to 1e-5 m, where
    the root sticks and slips by turns below the modal interaction's folds (zeta = 0.069), and the
    exact EPMC orbits at the H = 15 points: ``(system, nm15, nm7, orbits, dw15, dz15)``."""
    system = blade()
    amps = np.geomspace(1e-7, 1e-5, 5)
    nm15 = nonlinear_mode(system, amplitudes=amps, n_harmonics=15, dof="w0")
    nm7 = nonlinear_mode(system, amplitudes=amps, n_harmonics=7, dof="w0")
    assert nm15.success and nm7.success, (nm15.message, nm7.message)
    orbits, dw, dz = exact_against_balance(system, nm15)
    return system, nm15, nm7, orbits, dw, dz


@pytest.mark.slow  # the blade's exact EPMC orbits: 4-9 s
def test_blade_against_the_exact_epmc_orbit(blade_below_the_folds):
    """The blade (frozen normal loads), H = 15, against the EPMC orbit solved exactly in time, with
    the bounds of the full branch (test_blade_full_branch_against_the_exact_epmc_orbit, weekly) on
    its two ends, without the modal interaction's folds (their arc length:
    test_blade_branch_through_the_modal_interaction): from stuck (1e-7 m) to 1e-5 m, stuck the same (a linear mode) and where the root
    sticks and slips by turns within 3e-3 in frequency and 3.5e-2 in zeta (measured 2.0e-4, 8.9e-3);
    followed down from deep slip (1e-2 m to 5.6e-4 m) within 1e-4 and 1e-3 (measured 5.6e-5, 8.1e-4)."""
    system, nm, _, orbits, dw, dz = blade_below_the_folds
    assert all(o.converged for o in orbits) and nm.stuck[0]
    assert np.all(dw[nm.stuck] <= EXACT_TOL) and np.all(dz[nm.stuck] <= EXACT_TOL)
    assert np.max(dw) <= 3e-3 and np.max(dz) <= 3.5e-2, (dw, dz)
    deep = nonlinear_mode(system, amplitudes=[1e-2, 1e-3, 5.6e-4], n_harmonics=15, dof="w0")
    assert deep.success and not deep.stuck.any(), deep.message
    orbits, dw, dz = exact_against_balance(system, deep)
    assert all(o.converged for o in orbits)
    assert np.all(dw <= 1e-4) and np.all(dz <= 1e-3), (dw, dz)


@pytest.mark.weekly
def test_blade_full_branch_against_the_exact_epmc_orbit():
    """The blade (frozen normal loads), H = 15, 21 amplitudes at w0 from stuck (1e-7 m) through the
    damping peak (zeta = 0.129 at 1.8e-5 m) to deep slip (1e-2 m), against the EPMC orbit solved
    exactly in time at each: stuck the same (a linear mode); deep in slip (>= 5.6e-4 m) within 1e-4
    in frequency and 1e-3 in zeta (measured 5.6e-5, 8.0e-4); where the root sticks and slips by turns
    the truncation shows, up to 2.7e-3 in frequency and 3.1e-2 in zeta (at 5.6e-5 m), which
    test_blade_truncation_falls_with_the_harmonics_past_the_folds shows falling with H. Weekly (83 s
    under load): test_blade_against_the_exact_epmc_orbit covers its code paths on the branch's ends."""
    system = blade()
    nm = nonlinear_mode(system, amplitudes=np.geomspace(1e-7, 1e-2, 21), n_harmonics=15, dof="w0")
    assert nm.success, nm.message
    orbits, dw, dz = exact_against_balance(system, nm)
    assert all(o.converged for o in orbits)
    assert np.all(dw[nm.stuck] <= EXACT_TOL) and np.all(dz[nm.stuck] <= EXACT_TOL)
    deep = nm.amplitude >= 5.6e-4
    assert np.all(dw[deep] <= 1e-4) and np.all(dz[deep] <= 1e-3), (dw[deep], dz[deep])
    assert np.max(dw) <= 3e-3 and np.max(dz) <= 3.5e-2, (dw, dz)
    assert 0.12 <= max(o.damping_ratio for o in orbits) <= 0.14  # measured 0.129


@pytest.mark.slow  # the blade's exact EPMC orbits: 4-9 s
def test_blade_truncation_falls_with_the_harmonics(blade_below_the_folds):
    """At 1e-5 m at w0 (the root sticks and slips by turns, zeta = 0.069) the balance's difference
    from the exact EPMC orbit is its truncation: it falls with H (measured in zeta 2.3e-2 and 6.2e-3
    at H = 7 and 15, in frequency 1.3e-3 and 7.8e-7). The same past the folds, at H = 15 and 31:
    test_blade_truncation_falls_with_the_harmonics_past_the_folds (weekly)."""
    _, nm15, nm7, orbits, dw, dz = blade_below_the_folds
    exact = orbits[-1]
    assert exact.converged and nm7.amplitude[-1] == nm15.amplitude[-1]
    dw7 = abs(nm7.frequency[-1] / exact.frequency - 1)
    dz7 = abs(nm7.damping_ratio[-1] / exact.damping_ratio - 1)
    assert dz7 > 1e-2 and dz[-1] <= dz7 / 3 and dw[-1] <= dw7 / 3, (dw7, dz7, dw[-1], dz[-1])


@pytest.mark.weekly
def test_blade_truncation_falls_with_the_harmonics_past_the_folds():
    """At 5.6e-5 m at w0 (past the modal interaction's folds, zeta = 0.056) the balance's difference
    from the exact EPMC orbit is its truncation: it falls about as 1 / H^2 (measured in zeta 3.1e-2,
    8.0e-3 and 2.0e-3 at H = 15, 31 and 63; in frequency 1.9e-3, 4.9e-4, 1.2e-4); H = 63 is left out
    here for its cost (2 minutes). Weekly (166 s under load): test_blade_truncation_falls_with_the_harmonics
    covers its code paths below the folds, test_blade_branch_through_the_modal_interaction the folds."""
    system = blade()
    amps = np.geomspace(1e-7, 5.623e-5, 12)
    errors = []
    for hh in (15, 31):
        nm = nonlinear_mode(system, amplitudes=amps, n_harmonics=hh, dof="w0")
        assert nm.success, nm.message
        orbits, dw, dz = exact_against_balance(system, nm, [amps.size - 1])
        assert orbits[0].converged
        errors.append((dw[0], dz[0]))
    (dw15, dz15), (dw31, dz31) = errors
    assert dz15 > 1e-2 and dz31 <= dz15 / 3 and dw31 <= dw15 / 3, errors


@pytest.mark.slow  # the blade's exact EPMC orbits: 4-9 s
def test_blade_with_normal_load_variation_against_the_exact_epmc_orbit():
    """The blade with its flanks' normal loads varying, H = 15, from stuck (1e-7 m at w0) to 1e-5 m
    (below the modal interaction's folds), against the exact EPMC orbit: stuck the same; within the
    bounds of the full branch (2.5e-3 in frequency and 2.9e-2 in zeta; measured here 2.6e-4 and
    1.2e-2), the same truncation as with frozen loads. The full branch through the damping peak:
    test_blade_with_normal_load_variation_full_branch (weekly)."""
    system = blade(normal_load_variation=True)
    nm = nonlinear_mode(system, amplitudes=np.geomspace(1e-7, 1e-5, 5), n_harmonics=15, dof="w0")
    assert nm.success, nm.message
    orbits, dw, dz = exact_against_balance(system, nm)
    assert all(o.converged for o in orbits) and nm.stuck[0]
    assert np.all(dw[nm.stuck] <= EXACT_TOL) and np.all(dz[nm.stuck] <= EXACT_TOL)
    assert np.max(dw) <= 2.5e-3 and np.max(dz) <= 2.9e-2, (dw, dz)


@pytest.mark.weekly
def test_blade_with_normal_load_variation_full_branch():
    """The blade with its flanks' normal loads varying, H = 15, from stuck (1e-7 m at w0) through the
    damping peak (zeta = 0.132 at 1.8e-5 m) to 5.6e-5 m, against the exact EPMC orbit: stuck the
    same; up to 2.5e-3 in frequency and 2.9e-2 in zeta (measured 2.4e-3 and 2.8e-2), the same
    truncation as with frozen loads. Beyond, the exact orbit's flanks lift off (its least normal
    load 5.4 N at 5.6e-5 m; lifted 3 % of the period at 6.5e-5 m): a motion of impacts on the stiff
    normal contact, where the exact orbit was solved at 6.3e-5 and 6.5e-5 m and not beyond, by
    amplitude or by arc length, and where the balance folds twice and stops at 1.15e-4 m. Weekly (69 s
    under load): test_blade_with_normal_load_variation_against_the_exact_epmc_orbit covers its code
    paths below the folds."""
    system = blade(normal_load_variation=True)
    nm = nonlinear_mode(system, amplitudes=np.geomspace(1e-7, 1e-4, 13)[:12], n_harmonics=15, dof="w0")
    assert nm.success, nm.message
    orbits, dw, dz = exact_against_balance(system, nm)
    assert all(o.converged for o in orbits)
    assert np.all(dw[nm.stuck] <= EXACT_TOL) and np.all(dz[nm.stuck] <= EXACT_TOL)
    assert np.max(dw) <= 2.5e-3 and np.max(dz) <= 2.9e-2, (dw, dz)
    assert 0.125 <= max(o.damping_ratio for o in orbits) <= 0.14  # measured 0.132


def test_exact_option_gives_the_orbits_without_truncation():
    """``exact=True``: the EPMC orbit solved exactly at every point, in the result beside the
    balance's values: on the single-DOF Jenkins at H = 15 the balance's truncation is within 5e-5
    (measured 2.5e-5 in zeta, as test_exact_orbit_closed_form_and_harmonic_convergence), the stuck
    point's orbit is the linear mode's (EXACT_TOL), and ``exact=[A]`` solves the point nearest A
    only, to the same numbers (one computation, the same start)."""
    system = fj.FrictionSystem(fj.LinearStructure([[1.0]], [[1.0]], [[0.02]]), [fj.Jenkins(5.0, 0.1, dof=0)])
    amps = np.array([0.001, 0.03, 0.1, 1.0])
    nm = nonlinear_mode(system, amplitudes=amps, n_harmonics=15, exact=True)
    assert len(nm.orbits) == 4 and all(o.converged for o in nm.orbits)
    dw = np.abs(nm.frequency / nm.exact_frequency - 1)
    dz = np.abs(nm.damping_ratio / nm.exact_damping_ratio - 1)
    print("truncation at H = 15: frequency", dw, "zeta", dz)
    assert nm.stuck[0] and dw[0] <= EXACT_TOL and dz[0] <= EXACT_TOL
    assert dw.max() <= 5e-5 and dz.max() <= 5e-5
    one = nonlinear_mode(system, amplitudes=amps, n_harmonics=15, exact=[0.09])
    assert np.isnan(one.exact_frequency[[0, 1, 3]]).all() and len(one.orbits) == 1
    assert abs(one.exact_damping_ratio[2] / nm.exact_damping_ratio[2] - 1) <= EXACT_TOL
    with pytest.raises(ParameterError, match="exact"):
        nonlinear_mode(system, amplitudes=amps, exact=[-1.0])


def sdof_mode_deep_slip(a, c, kt, fs):
    """:func:`sdof_mode_closed_form` (m = k = 1) written for any amplitude: beta from ``sin(beta/2) =
    sqrt(x)``, ``x = Fs/(kt a)`` (``1 - cos beta`` would cancel), the energy per cycle over ``pi a^2``
    as ``4 Fs (1 - x) / (pi a)`` (``a^2`` overflows past 1e154)."""
    x = fs / (kt * a)
    beta = 2 * math.asin(math.sqrt(x))
    w = math.sqrt(1.0 + kt / math.pi * (beta - math.sin(2 * beta) / 2))
    return w, (c + 4 * fs * (1 - x) / (math.pi * a * w)) / (2 * w)


@settings(max_examples=12, deadline=None)
@given(log_a=st.floats(2.0, 300.0), c=st.sampled_from([0.0, 0.02]))
def test_deep_slip_tends_to_the_free_slip_mode(log_a, c):
    """Issue 39: the Jenkins SDOF (m = k = 1, kt = 5, Fs = 0.1) deep in slip, H = 1: frequency and
    damping ratio equal the describing function's closed form to CLOSED_FORM_TOL (measured <= 5e-15;
    without dashpots the damping ratio is friction's alone, 2 Fs (1 - x) / (pi a w^2)), with no
    floating-point warning. From a = 1e15 it gave the stuck frequency sqrt(6) (the loop held its
    spring once Fs/kt was below the rounding of a); at 1e300 k a overflowed."""
    a = 10.0 ** log_a
    system = fj.FrictionSystem(fj.LinearStructure([[1.0]], [[1.0]], [[c]]), [fj.Jenkins(5.0, 0.1, dof=0)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        nm = nonlinear_mode(system, amplitudes=[a], n_harmonics=1)
    w, zeta = sdof_mode_deep_slip(a, c, 5.0, 0.1)
    assert nm.success and not nm.stuck[0]
    assert abs(nm.frequency[0] / w - 1) <= CLOSED_FORM_TOL
    assert abs(nm.damping_ratio[0] / zeta - 1) <= CLOSED_FORM_TOL
    # the energy balance, in metres and joules however large (equations solved in units of 2^k m)
    assert abs(nm.friction_per_cycle[0] / (4 * 0.1 * a * (1 - 0.1 / (5.0 * a))) - 1) <= CLOSED_FORM_TOL


def test_deep_slip_chain_is_its_free_slip_mode_at_any_amplitude():
    """The chain (H = 7) from 1e6 to 1e300 m: the free-slip linear mode's frequency (0.618) to 1e-9
    (the joint's force is below 1e-7 of the springs' from 1e6 m; measured 4e-16), no overflow
    warning; at 1e300 it gave the stuck 0.995 with overflow warnings. The checks against the time
    march need amplitudes it can represent: refused beyond 2^500 m."""
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        nm = nonlinear_mode(chain(), amplitudes=[1e6, 1e20, 1e150, 1e300], n_harmonics=7)
    assert nm.success
    np.testing.assert_allclose(nm.frequency, nm.slipping_frequency, rtol=1e-9)
    assert abs(nm.slipping_frequency - math.sqrt((3 - math.sqrt(5)) / 2)) <= 1e-12
    with pytest.raises(ParameterError, match="check and exact"):
        nonlinear_mode(chain(), amplitudes=[1e300], n_harmonics=1, check=True)


def test_printout_is_a_table_with_the_checked_points_only():
    """The printout was the dataclass's: every array, frequency_error a wall of NaN wherever a point was
    not checked. Now one row per amplitude, then the checked points only."""
    nm = nonlinear_mode(chain(), amplitudes=np.geomspace(0.01, 10, 8), n_harmonics=1, check=[5.0])
    text = repr(nm)
    assert "nan" not in text.lower() and "array(" not in text
    assert "checked against the exact free decay (1 points)" in text
    assert len(text.splitlines()) == 3 + 8 + 2 + 1
    assert f"{nm.frequency_error[np.isfinite(nm.frequency_error)][0]:.8g}" in text
