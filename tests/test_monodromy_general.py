"""The exact Jacobian of non-classically damped marches in real modal rows (issue 40): where a
configuration's modes are general (stiffness-proportional, Rayleigh damping with joints as stiff
as the structure) and it has no stuck rigid slider and no contact,
:func:`~frictionjoint.solvers.marcher.monodromy.march_jacobian` carries the variations as the real
pairs ``(Re z, Im z)`` of the modal coordinates ``z = V^-1 dy`` (:class:`_RealModes`). It must be
the Jacobian of physical rows through every piece (``_march_jacobian_rows``, the complex products
of before) to rounding and the central differences of the march itself, also where the march
mixes real rows with classical modal rows and with physical rows (a stuck rigid slider), where
over-damped modes give real roots, and where a rigid slider's jump of acceleration makes the
saltations count (a consistent mass: with a diagonal one that jump is along the slider alone, and
the stuck slider's reduced coordinates or the moving sliders' ``w`` hide it).

Tolerances (stated once here):

- ``RTOL``: relative (Frobenius) difference of the modal-rows and the physical-rows Jacobians:
  rounding of the changes of basis ``V_new^-1 V_old``, of ``V^-1`` and of the saltations. Measured
  2.6e-15 to 1.1e-14 on the systems below with complex roots only, 1.9e-13 with the over-damped
  modes' close real roots, 6e-13 on the (200, 40) stiffness-proportional chain of issue 40's
  family; 5e-11, 260x above the systems here.
- ``FD_TOL``: the largest entry of the scaled difference to central differences with steps
  ``FD_STEP`` of the state's scale, over the largest scaled entry. Central differences err by
  ``h^2 Z''' / 6`` plus the march's rounding over ``h``; measured on these systems 1e-9 to 5.7e-8
  at ``FD_STEP = 1e-5`` (the largest falls 100x per 10x smaller step above it: truncation; the
  rounding part, 1e-9 to 2.5e-7 at 1e-6, grows below it), so 1e-5, 175x above. Leaving out the
  stuck sliders' forcing in the real rows gives 0.8 to 1.3, leaving out the saltations in the real
  rows 1.4e-2 and 4.8e-2 (the two systems with a rigid slider; measured when the test was written).
"""
import math

import numpy as np
import pytest
import scipy.linalg

import frictionjoint as fj
from frictionjoint.solvers.marcher import monodromy, propagator
from frictionjoint.solvers.marcher.events import EventLog
from test_monodromy_modal import _kinds, _orbit, _rel  # (tests/ is on the path: tests/conftest.py)

RTOL = 5e-11
FD_STEP = 1e-5
FD_TOL = 1e-5


def _chain(n, joints, damping="stiffness", zeta=0.01, coulomb=None, coulomb_dof=2, coupled=False):
    """n unit masses, fixed-free, unit springs; ``C = beta K`` with ``zeta`` of critical damping in
    the first mode (``damping='rayleigh'``: ``a M + b K``, ``zeta`` in modes 1 and about n/10);
    Jenkins joints of stiffness 1 (the chain's own springs) on the outer half, each slipping at
    0.3 x its force in the stuck linear response; 0.01 N at the tip at 0.9 w1 (the draft benchmark
    family of issue 40). ``coulomb``: also a Coulomb slider of that slip force at ``coulomb_dof``;
    ``coupled``: a consistent (non-diagonal) mass matrix, so that the jump of acceleration where
    the rigid slider sticks or reverses is not along the slider alone (the saltation shows)."""
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    base = fj.LinearStructure.chain(n)
    stiffness, mass = base.stiffness, base.mass
    if coupled:
        mass = mass + 0.1 * (np.eye(n, k=1) + np.eye(n, k=-1)) + 0.2 * np.eye(n)
    dofs = sorted({int(d) for d in np.linspace(n - 1, n // 2, joints).round()})
    k = stiffness + np.diag(np.bincount(dofs, np.ones(len(dofs)), n))
    if damping == "stiffness":
        c = (2 * zeta / w1) * stiffness
    else:
        w2 = 2 * math.sin(math.pi * (2 * max(n // 10, 2) - 1) / (2 * (2 * n + 1)))
        c = (2 * zeta * w1 * w2 / (w1 + w2)) * mass + (2 * zeta / (w1 + w2)) * stiffness
    w = 0.9 * w1
    x = np.linalg.solve(k - w * w * mass + 1j * w * c, 0.01 * np.eye(n)[n - 1])
    els = [fj.Jenkins(1.0, 0.3 * abs(x[d]), dof=d) for d in dofs]
    if coulomb is not None:
        els.append(fj.CoulombSlider(coulomb, dof=coulomb_dof))
    return fj.FrictionSystem(fj.LinearStructure(mass, stiffness, c), els, omega=w,
                             excitation=[fj.HarmonicForce(n - 1, 0.01)])


#: name: (system, the kinds of rows its pieces must take: R real modal, C classical modal, P physical)
SYSTEMS = {
    "stiffness-proportional, 6 DOF": (lambda: _chain(6, 2), "R"),
    "stiffness-proportional, 12 DOF": (lambda: _chain(12, 3), "R"),
    "stiffness-proportional, 30 DOF": (lambda: _chain(30, 8), "R"),
    "over-damped high modes (real roots)": (lambda: _chain(12, 3, zeta=0.3), "R"),
    "Rayleigh, 20 DOF": (lambda: _chain(20, 5, damping="rayleigh"), "R"),
    "a stuck rigid slider (physical rows between)": (lambda: _chain(12, 3, coulomb=3e-3, coupled=True), "RP"),
    "a rigid slider's reversals (saltations between real rows)":
        (lambda: _chain(12, 3, coulomb=1e-3, coulomb_dof=7, coupled=True), "R"),
}


def _central_differences(pmap, z0, steps):
    """Central differences of the full-coordinate march of one period from ``z0 = [x, v, w]``.
    A slider slipping at the start keeps its offset ``w - d . x`` (its ``w`` follows ``x``, as the
    exact Jacobian's moving sliders); its own ``w`` column is left out (a one-sided derivative:
    inward the slider sticks)."""
    system = pmap.system
    n = system.n_dof
    slip = pmap.last[2][0][0].status != 0
    d = system.slider_direction

    def end(z):
        st = pmap.m.initial_state(z[:n], z[n:2 * n], z[2 * n:], t0=pmap.t_s)
        pmap.m.march(st, pmap.t_s + pmap.period, EventLog())
        return np.concatenate((st.x, st.v, st.w))

    cols = np.concatenate((np.arange(2 * n), 2 * n + np.flatnonzero(~slip)))
    fd = np.zeros((z0.size, z0.size))
    for k in cols:
        dz = np.zeros(z0.size)
        dz[k] = steps[k]
        if k < n:
            dz[2 * n:][slip] += d[slip, k] * steps[k]
        fd[:, k] = (end(z0 + dz) - end(z0 - dz)) / (2 * steps[k])
    return fd, cols


@pytest.mark.parametrize("name", SYSTEMS)
def test_real_modal_rows_give_the_exact_jacobian(name):
    make, kinds = SYSTEMS[name]
    system = make()
    pmap = _orbit(system)
    marcher, pieces = pmap.m, pmap.last[2]
    got = _kinds(marcher, pieces)
    assert set(got) - set("C") == set(kinds), got  # the all-slip configuration may be classical
    if name.startswith("over-damped"):
        assert any(monodromy._sensitivity(marcher, itv).real.phase.size for itv, _ in pieces
                   if monodromy._sensitivity(marcher, itv).real is not None)
    ref = monodromy._march_jacobian_rows(marcher, pieces)
    first = monodromy.march_jacobian(marcher, pieces)  # forms the changes of basis
    again = monodromy.march_jacobian(marcher, pieces)  # takes them from the cache
    assert _rel(first, ref) <= RTOL, _rel(first, ref)
    assert np.array_equal(first, again)
    # against central differences of the march
    n = system.n_dof
    st = pmap.state(pmap.last[0])
    z0 = np.concatenate((st.x, st.v, st.w))
    xs, vs = np.max(np.abs(st.x)), np.max(np.abs(st.v))
    sc = np.concatenate((np.full(n, xs), np.full(n, vs), np.full(system.n_sliders, xs)))
    fd, cols = _central_differences(pmap, z0, FD_STEP * sc)
    scaled = sc[None, :] / sc[:, None]
    err = float(np.max(np.abs((first - fd) * scaled)[:, cols]) / np.max(np.abs(first * scaled)))
    assert err <= FD_TOL, err


def _fake_config(seed):
    """A configuration-like object with the modes of a random real 6 x 6 first-order matrix with
    two real roots: its eigenvectors scaled by random complex factors (conjugate ones on a pair's
    second root) and shuffled."""
    rng = np.random.default_rng(seed)
    a = rng.standard_normal((6, 6))
    lam, v = np.linalg.eig(a)
    while np.sum(np.abs(lam.imag) < 1e-9) != 2:
        a = rng.standard_normal((6, 6))
        lam, v = np.linalg.eig(a)
    phase = np.exp(1j * rng.uniform(0, 2 * np.pi, 6))
    for k in np.flatnonzero(lam.imag > 0):  # eig puts a pair's roots next to each other
        phase[k + 1] = phase[k].conj()
    v = v * phase
    order = rng.permutation(6)
    lam, v = lam[order], v[:, order]

    class Config:
        pass
    cfg = Config()
    cfg.lam, cfg.V, cfg.W, cfg.A = lam, v, np.linalg.inv(v), a
    cfg.n_pairs = None
    return cfg


def _halved_config(seed):
    """:func:`_fake_config`'s modes as ``eig`` gives them (pairs side by side, exact conjugates),
    halved as a configuration keeps them (:func:`.propagator._halved_modes`)."""
    cfg = _fake_config(seed)
    lam, v = np.linalg.eig(cfg.A)
    halved = propagator._halved_modes(lam, v, propagator._real_inverse(lam, v))
    assert halved is not None
    cfg.lam, cfg.V, cfg.W, cfg.n_pairs = halved
    return cfg


@pytest.mark.parametrize("halved", [False, True])
@pytest.mark.parametrize("seed", range(4))
def test_real_rows_carry_the_exponential(seed, halved):
    """``R diag(real blocks of e^{lam tau}) Q = e^{A tau}`` and ``Q R = I`` for roots in any order
    and vectors with any complex factors (real roots' vectors not real), and for halved modes (a
    pair's first root, its vector times 2): the real form is the complex one. To rounding of
    ``eig`` and ``inv`` on a 6 x 6 (1e-13, 1000 eps)."""
    cfg = _halved_config(seed) if halved else _fake_config(seed)
    real = monodromy._RealModes.of(cfg)
    assert real is not None and real.p == 2 and real.phase.size == 2
    right = real.cols(cfg.V[:, real.keep])
    left = real.rows(cfg.W[real.keep])
    assert np.max(np.abs(left @ right - np.eye(6))) <= 1e-13
    tau = 0.7
    e = np.exp(real.lam * tau)
    step = np.zeros((6, 6))
    for i in range(real.p):
        step[2 * i:2 * i + 2, 2 * i:2 * i + 2] = [[e[i].real, -e[i].imag], [e[i].imag, e[i].real]]
    step[2 * real.p:, 2 * real.p:] = np.diag(e[real.p:].real)
    assert np.max(np.abs(right @ step @ left - scipy.linalg.expm(cfg.A * tau))) <= 1e-13


def test_unpaired_roots_take_physical_rows():
    """A pair whose second vector is not the first's conjugate has no real form: None (the march
    takes physical rows)."""
    cfg = _fake_config(0)
    k = int(np.flatnonzero(cfg.lam.imag < -1e-9)[0])
    cfg.V = cfg.V.copy()
    cfg.V[:, k] *= 1j
    assert monodromy._RealModes.of(cfg) is None
