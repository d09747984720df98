"""What a configuration of the marcher costs (issue 26): classically damped configurations from the
symmetric pencil (no first-order eig), no SVD for any condition number, and a memory-bounded
cache whose evicted configurations come back as the same numbers."""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.solvers.marcher import events, propagator
from frictionjoint.solvers.marcher.propagator import ConfigData


def _chain(n=12, joints=3, rayleigh=0.0, lumped=True):
    """A chain with Jenkins joints to the ground (benchmarks/chains.py's kind, small): damping
    2 % of critical in the first mode, mass-proportional, plus ``rayleigh`` x K (not classical
    once a joint sticks); ``lumped`` False gives a consistent (non-diagonal) mass matrix."""
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    base = fj.LinearStructure.chain(n, damping=0.02 * w1)
    mass = base.mass.copy()
    if not lumped:
        mass = mass + 0.1 * (np.diag(np.ones(n - 1), 1) + np.diag(np.ones(n - 1), -1)) + 0.2 * np.eye(n)
    structure = fj.LinearStructure(mass, base.stiffness, 0.02 * w1 * mass + rayleigh * base.stiffness)
    dofs = sorted({int(d) for d in np.linspace(n - 1, n // 2, joints).round()})
    kt = 0.5 * w1 ** 2
    elements = [fj.Jenkins(kt, 2e-4, dof=d) for d in dofs]
    return fj.FrictionSystem(structure, elements, omega=0.9 * w1, excitation=[fj.HarmonicForce(n - 1, 0.01)])


@pytest.mark.parametrize("lumped", [True, False])
def test_classical_modes_are_the_first_order_ones(lumped):
    """Mass-proportional damping: the pencil's modes (eigh, V^-1 in closed form) diagonalise the
    first-order matrix A of every configuration: A V = V diag(lam) and V^-1 V = I to 1e-12 of
    their scales (rounding of eigh and of the products, not an approximation); the halved set the
    marcher keeps reproduces a real state."""
    system = _chain(lumped=lumped)
    rng = np.random.default_rng(3)
    for _ in range(4):
        cfg = ConfigData(system, rng.integers(-1, 2, system.n_sliders).astype(np.int8))
        assert cfg.shapes is not None  # the classical path was taken
        a = cfg.A
        lam, v, w = cfg.full_modes()
        assert np.max(np.abs(a @ v - v * lam)) <= 1e-12 * np.max(np.abs(a)) * np.max(np.abs(v))
        assert np.max(np.abs(w @ v - np.eye(lam.size))) <= 1e-12 * np.max(np.abs(w)) * np.max(np.abs(v))
        # the halved modes (one of each conjugate pair, doubled): eigenpairs still, and
        # Re(V (V^-1 y)) = y for a real state y
        assert cfg.lam.size == system.n_dof  # under-damped: every pair halved
        assert np.max(np.abs(a @ cfg.V - cfg.V * cfg.lam)) <= 1e-12 * np.max(np.abs(a)) * np.max(np.abs(cfg.V))
        y = rng.standard_normal((2 * system.n_dof, 3))
        assert np.max(np.abs((cfg.V @ (cfg.W @ y)).real - y)) <= 1e-12 * np.max(np.abs(y))


def test_no_svd_for_a_configuration(monkeypatch):
    """Neither path asks for a condition number by SVD (np.linalg.cond, svd): the general path's
    is the 1-norm one from the inverse it needs anyway."""
    def refuse(*args, **kwargs):
        raise AssertionError("an SVD per configuration")
    monkeypatch.setattr(np.linalg, "svd", refuse)
    monkeypatch.setattr(np.linalg, "cond", refuse)
    for system in (_chain(), _chain(rayleigh=0.01)):
        cfg = ConfigData(system, np.zeros(system.n_sliders, np.int8))
        assert cfg.modal


def test_general_and_classical_paths_find_the_same_orbit(monkeypatch):
    """The steady state through the classical path and through the general one (first-order eig,
    forced by calling the damping non-classical) agree to 1e-10 of the amplitude, as do their
    largest Floquet multipliers: two exact decompositions of the same configurations."""
    system = _chain()
    fast = fj.periodic_response(system)
    monkeypatch.setattr(propagator, "_mass_proportional", lambda system: None)
    slow = fj.periodic_response(_chain())
    assert fast.converged and slow.converged and len(fast.events) > 0
    assert np.max(np.abs(fast.amplitude - slow.amplitude)) <= 1e-10 * np.max(fast.amplitude)
    assert abs(np.max(np.abs(fast.floquet_multipliers)) - np.max(np.abs(slow.floquet_multipliers))) <= 1e-9


def test_rayleigh_damping_takes_the_general_path():
    """C = alpha M + beta K is not classical once a joint sticks (K_c is not K): the general path."""
    system = _chain(rayleigh=0.01)
    assert ConfigData(system, np.zeros(system.n_sliders, np.int8)).shapes is None
    assert ConfigData(_chain(), np.zeros(system.n_sliders, np.int8)).shapes is not None


def test_evicted_configurations_come_back_the_same(monkeypatch):
    """A cache budget of a few configurations: the marcher forgets and decomposes again, and the
    steady state is the same bit for bit (the same operations on the same inputs in one process
    with the library's single BLAS thread: nothing for rounding to change), its cache below the
    budget."""
    full = fj.periodic_response(_chain())
    one = ConfigData(_chain(), np.zeros(3, np.int8)).nbytes
    budget = one  # a configuration or so: every new one evicts the oldest
    monkeypatch.setattr(events, "CONFIG_CACHE_BYTES", budget)
    system = _chain()
    marcher = fj.Marcher(system)
    small = fj.periodic_response(system, marcher=marcher)
    assert np.array_equal(full.amplitude, small.amplitude)
    built = []
    monkeypatch.setattr(events, "ConfigData", lambda *a: built.append(1) or ConfigData(*a))
    again = _chain()
    counted = fj.Marcher(again)
    fj.periodic_response(again, marcher=counted)
    # configurations were decomposed again (more built than kept), the cache stays near the budget
    assert len(counted._configs) < len(built) and counted._config_bytes <= 2 * budget


def test_an_edited_mass_is_not_met_by_a_stale_inverse():
    """The mass inverse, its factor and the damping's proportionality are shared by the
    configurations of a system; a user's in-place edit of its mass matrix is seen by the next
    configuration (the mass no longer proportional to the damping: the general path)."""
    system = _chain()
    first = ConfigData(system, np.zeros(system.n_sliders, np.int8))
    system.mass[0, 0] *= 2.0
    second = ConfigData(system, np.zeros(system.n_sliders, np.int8))
    assert first.shapes is not None and second.shapes is None
    assert np.allclose(second.mr_inv_nt @ system.mass, np.eye(system.n_dof), rtol=0, atol=1e-12)


def test_tridiagonal_pencil_gives_eighs_numbers():
    """A chain with lumped masses: the pencil goes to LAPACK's stevd (eigh_tridiagonal), which
    gives syevd's (eigh's) eigenvalues and vectors bit for bit (the Householder reduction of a
    tridiagonal matrix is the identity exactly), for sizes on both sides of LAPACK's small-matrix
    switch (25)."""
    import scipy.linalg
    for n in (3, 12, 30, 64):
        system = _chain(n, joints=max(1, n // 5))
        factor = propagator._mass_factor(system)
        cfg = ConfigData(system, np.zeros(system.n_sliders, np.int8))
        ks = cfg.stiffness / factor[:, None] / factor[None, :]
        w2, psi = scipy.linalg.eigh(ks, check_finite=False, driver="evd")
        got = propagator._pencil(system.mass, cfg.stiffness, factor)
        assert np.array_equal(got[0], w2) and np.array_equal(got[1], psi / factor[:, None])


def test_a_march_keeps_no_first_order_matrix_and_counts_its_own_arrays():
    """A classical configuration marched (compiled) never builds A or the complex V^-1 (their
    blocks and rows are read in factored form); nbytes counts the configuration's own arrays, not
    the system's stiffness, damping, M^-1 and identity it refers to; the statuses of one
    configuration share its packed consistency arrays."""
    system = _chain()
    marcher = fj.Marcher(system)
    fj.periodic_response(system, marcher=marcher)
    configs = list(marcher._configs.values())
    assert configs and all(cfg._A is None and cfg._W is None for cfg in configs if cfg.shapes is not None)
    n = system.n_dof
    cfg = ConfigData(system, np.zeros(system.n_sliders, np.int8))
    own = sum(a.nbytes for a in (cfg.stiffness, cfg.V, cfg.shapes, cfg.shapes_mass))
    assert own <= cfg.nbytes <= own + 64 * n * 16  # and vectors of n
    kerns = {}
    for pat in marcher._patterns.values():
        if pat.kern is not None:
            kerns.setdefault(id(pat.cfg), set()).add(id(pat.kern[0][0]))
    assert kerns and all(len(k) == 1 for k in kerns.values())
    a21, a22 = cfg.first_order_blocks()  # before A is built: the same numbers as A's blocks
    assert np.array_equal(cfg.A[n:, :n], a21) and np.array_equal(cfg.A[n:, n:], a22)


def _held(marcher) -> tuple[int, int]:
    """The bytes of the distinct arrays the marcher's configurations and status patterns hold (not
    the system's), and those of the configurations' modes and packed arrays alone."""
    seen, total, big = set(), 0, 0
    shared = set()
    for cfg in marcher._configs.values():
        shared.update(id(a) for a in cfg._shared)

    def visit(a, count_big=False):
        nonlocal total, big
        if isinstance(a, (tuple, list)):
            for b in a:
                visit(b, count_big)
        elif isinstance(a, propagator.Observables):  # a status's event rows
            visit((a.ax, a.av, a.af, a.a0))
        elif isinstance(a, np.ndarray):
            base = a if a.base is None else a.base
            if isinstance(base, np.ndarray) and id(base) not in seen and id(base) not in shared:
                seen.add(id(base))
                total += base.nbytes
                big += base.nbytes if count_big else 0
    for cfg in marcher._configs.values():
        for name, value in vars(cfg).items():
            visit(value, name in ("V", "_W", "kern"))
    for pat in marcher._patterns.values():
        for name in type(pat).__slots__:
            visit(getattr(pat, name, None))
    return total, big


def test_the_cache_counts_each_array_once():
    """The configuration cache's count (what eviction compares with its budget) is at most the
    distinct arrays its configurations and statuses hold, plus the modes expected of those still
    waiting for them, and at least their modes and packed arrays: the statuses of one
    configuration counted its packed arrays once each before (1.23 GB counted for 0.68 GB held
    at 200 DOFs), and a waiting configuration held its neighbour's whole eigenvectors uncounted.
    Stiffness damping: general modes, rank-one updates, waiting configurations."""
    system = _chain(rayleigh=0.05)
    marcher = fj.Marcher(system)
    assert fj.periodic_response(system, marcher=marcher).converged
    waiting = [c for c in marcher._configs.values() if "_pending" in c.__dict__]
    # the modes to come: eigenvectors and their inverse, or of a symmetric pencil (this one) the
    # eigenvectors only (the inverse's rows are not held: propagator._left_inverse)
    half = 2 if propagator._symmetric_pencil(system) else 1
    expected = sum(16 * (2 * c.m) ** 2 // half for c in waiting)
    total, big = _held(marcher)
    assert big <= marcher._config_bytes <= total + expected
    assert all(c._roots is None or c._roots[1][0] is None for c in waiting if "_roots" in c.__dict__)
    assert any(c.n_pairs is not None for c in marcher._configs.values() if "_pending" not in c.__dict__)


def test_forgotten_cache_and_memory_given_back():
    """Marcher.forget empties the cache and returns what it counted; the steady state is the same
    after (rebuilt bit for bit: the same operations in one process); glibc gives freed memory
    back (memory.release_freed_memory: True there)."""
    import platform
    from frictionjoint.memory import release_freed_memory
    system = _chain(rayleigh=0.05)
    marcher = fj.Marcher(system)
    first = fj.periodic_response(system, marcher=marcher)
    counted = marcher._config_bytes
    assert counted > 0 and marcher.forget() == counted
    assert marcher._config_bytes == 0 and not marcher._configs and not marcher._patterns
    again = fj.periodic_response(system, marcher=marcher)
    assert np.array_equal(first.amplitude, again.amplitude)
    assert release_freed_memory() == (platform.libc_ver()[0] == "glibc")


@pytest.mark.parametrize("budget", [5_000_000, None])
def test_the_count_follows_the_cache_through_evictions(budget, monkeypatch):
    """What eviction takes off is what was put on (Marcher._charge): with a budget of a dozen
    configurations, two steady states on one marcher keep a dozen cached, and the count is the
    cached configurations' and statuses' own sizes, less at most the first-order matrices built
    after they were counted (ConfigData.A on a rare first use). A halved V that was a view (not
    counted) and a waiting configuration counted at its expected modes but taken off at its actual
    size made the count drift up by each eviction until one configuration was cached (13.6 MB
    counted for 0.3 MB held at this budget)."""
    from frictionjoint.solvers.marcher.events import _nbytes
    if budget is not None:
        monkeypatch.setattr(events, "CONFIG_CACHE_BYTES", budget)
    n, joints = 60, 8
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    base = fj.LinearStructure.chain(n)
    structure = fj.LinearStructure(base.mass, base.stiffness, 0.02 * w1 * base.mass + 0.05 * base.stiffness)
    dofs = sorted({int(d) for d in np.linspace(n - 1, n // 2, joints).round()})
    system = fj.FrictionSystem(structure, [fj.Jenkins(0.5 * w1 ** 2, 2e-4, dof=d) for d in dofs],
                               omega=0.9 * w1, excitation=[fj.HarmonicForce(n - 1, 0.01)])
    marcher = fj.Marcher(system)
    for _ in range(2):
        assert fj.periodic_response(system, marcher=marcher).converged
        configs = list(marcher._configs.values())
        own = sum(c.nbytes for c in configs) + sum(_nbytes(p) for p in marcher._patterns.values())
        late = sum(c._A.nbytes for c in configs if "_pending" not in c.__dict__ and c._A is not None)
        assert own - late <= marcher._config_bytes <= own
        # the modes own their arrays (nbytes counts no view: a halved V was one, uncounted)
        general = [c for c in configs if "_pending" not in c.__dict__ and c.n_pairs is not None]
        # (rows of V^-1 from the left eigenvectors are not held: ConfigData.left_product)
        assert general and all(c.V.base is None and (c._W is None) == (c._left is not None)
                               and (c._W is None or c._W.base is None) for c in general)
        if budget is not None:
            assert len(configs) >= 10 and marcher._config_bytes <= budget
