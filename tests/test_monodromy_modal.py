"""The exact Jacobian with its rows in modal coordinates (issues 26, 40): where consecutive pieces
are modal without stuck rigid sliders,
:func:`~frictionjoint.solvers.marcher.monodromy.march_jacobian` carries the variations as modal
coordinates (classical modes, or the real pairs of general modes without contacts) and changes
basis between configurations; it must be the Jacobian of physical rows through every piece
(``_march_jacobian_rows``, the implementation before) to rounding, on every path: classical
configurations only, a mix with stuck rigid sliders (``N != I``), classical modes and general ones
of stiff stuck springs, Rayleigh damping (general modes' real rows; the all-slip configuration may
be classical), a root on its flanks with normal-load variation and lift-off (contacts: physical
rows); lumped and consistent masses, under- and over-damped modes. tests/test_monodromy_general.py
checks the general modes' real rows further (against central differences too)."""
import math

import numpy as np
import pytest

import frictionjoint as fj
from frictionjoint.solvers.marcher import events, monodromy
from frictionjoint.solvers.marcher.steady import _PeriodMap

#: relative difference (Frobenius) of the two Jacobians: rounding of the changes of basis
#: (``Phi^T M Phi = I`` to eigh's rounding, ``V^-1 V = I`` to eig's and inv's); measured up to
#: 1e-14 on the classical systems below, 5.8e-14 on Rayleigh damping's real rows, 4e-14 on the
#: (200, 40) chain of benchmarks/chains.py
RTOL = 1e-11


def _chain(n, joints, slip=0.3, rigid=False, rayleigh=0.0, stiff=1.0, alpha=None, coupled=False):
    """n unit masses, fixed-free, unit springs, mass-proportional damping ``alpha M`` (2 % of the
    first mode's critical by default; plus ``rayleigh`` x K: the general path), ``joints`` Jenkins
    joints (Coulomb sliders where ``rigid``) to the ground on the outer half, the last ``stiff``
    times stiffer than the others; force 0.01 N at the tip near the first mode. ``slip``: slip
    force over the spring force of the stuck linear response (stick and slip every period);
    ``coupled``: a consistent (non-diagonal) mass matrix (the mass's Cholesky factor)."""
    w1 = 2 * math.sin(math.pi / (2 * (2 * n + 1)))
    base = fj.LinearStructure.chain(n)
    mass = base.mass + (0.1 * (np.eye(n, k=1) + np.eye(n, k=-1)) + 0.2 * np.eye(n) if coupled else 0.0)
    alpha = 0.02 * w1 if alpha is None else alpha
    structure = fj.LinearStructure(mass, base.stiffness, alpha * mass + rayleigh * base.stiffness)
    dofs = sorted({int(d) for d in np.linspace(n - 1, n // 2, joints).round()})
    kt = np.full(len(dofs), 0.5 * w1 ** 2)
    kt[-1] *= stiff
    k = structure.stiffness + np.diag(np.bincount(dofs, kt, n))
    w = 0.9 * w1
    x = np.linalg.solve(k - w * w * structure.mass + 1j * w * structure.damping, 0.01 * np.eye(n)[n - 1])
    force = slip * float(np.max(kt * np.abs(x[dofs])))
    if rigid:
        els = [fj.CoulombSlider(force, dof=d) for d in dofs]
    else:
        els = [fj.Jenkins(float(kd), force, dof=d) for kd, d in zip(kt, dofs)]
    return fj.FrictionSystem(structure, els, omega=w, excitation=[fj.HarmonicForce(n - 1, 0.01)])


def _root_on_flanks():
    """A root block on dovetail flanks whose normal loads follow the motion, shaken to slip, lift
    off and close (tests/test_normal_load_variation.py's system)."""
    g = math.radians(40.0)
    st = fj.LinearStructure(np.diag([0.2, 0.2]), np.zeros((2, 2)), np.diag([2.0, 2.0]), dof_names=["X", "Y"])
    root = fj.DovetailRoot(1000.0, flank_angle=g, friction_coefficient=0.3, normal_stiffness=1e6,
                           tangential_stiffness=8e5, tangential_dof="X", radial_dof="Y",
                           normal_load_variation=True)
    exc = [fj.HarmonicForce("X", 400.0), fj.HarmonicForce("Y", 200.0, phase=0.7)]
    return fj.FrictionSystem(st, [root], omega=2000.0, excitation=exc)


SYSTEMS = {
    "classical chain": lambda: _chain(20, 5),
    "classical chain, consistent mass": lambda: _chain(12, 3, coupled=True),
    "classical chain, over-damped modes": lambda: _chain(12, 3, alpha=0.5),
    "stuck rigid sliders": lambda: _chain(10, 3, slip=1.5, rigid=True),
    "stiff joint (general path when stuck)": lambda: _chain(12, 3, stiff=1e6),
    "Rayleigh damping": lambda: _chain(12, 3, rayleigh=0.01),
    "root on flanks, lift-off": _root_on_flanks,
}


def _orbit(system):
    """The period map at the system's steady state, its last call being the orbit's period (also
    tests/test_monodromy_general.py's)."""
    pr = fj.periodic_response(system)
    assert pr.converged
    pmap = _PeriodMap(system, fj.Marcher(system), pr.section_time)
    pmap(pr.state)
    return pmap


def _orbit_pieces(system):
    """The marcher and the closed-form pieces of one period from the system's steady state."""
    pmap = _orbit(system)
    return pmap.m, pmap.last[2]


def _kinds(marcher, pieces) -> str:
    """The rows each piece takes: C classical modal, R real rows of general modes, P physical."""
    out = ""
    for itv, _ in pieces:
        sens = monodromy._sensitivity(marcher, itv)
        out += "C" if sens.modal_rows else "R" if sens.real is not None else "P"
    return out


def _rel(a, b) -> float:
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


@pytest.mark.parametrize("name", SYSTEMS)
def test_modal_rows_give_the_jacobian_of_physical_rows(name):
    marcher, pieces = _orbit_pieces(SYSTEMS[name]())
    kinds = set(_kinds(marcher, pieces))
    # the paths the case is there for: classical modal rows only, a mix with physical rows, with
    # real rows, real rows (and maybe classical ones), physical rows only
    if name.startswith("classical"):
        assert kinds == {"C"}
    elif name.startswith("stuck"):
        assert kinds == {"C", "P"}
    elif name.startswith("stiff"):
        assert kinds == {"C", "R"}
    elif name.startswith("Rayleigh"):
        assert "R" in kinds and "P" not in kinds
    else:
        assert kinds == {"P"}
    ref = monodromy._march_jacobian_rows(marcher, pieces)
    first = monodromy.march_jacobian(marcher, pieces)  # forms the changes of basis
    again = monodromy.march_jacobian(marcher, pieces)  # takes them from the cache
    assert _rel(first, ref) <= RTOL, _rel(first, ref)
    assert np.array_equal(first, again)


def test_basis_cache_is_bounded_and_survives_forgotten_configurations(monkeypatch):
    """A budget of one change of basis: the cache keeps the last one and the Jacobian is the same
    bit for bit. A marcher that forgets its configurations (a budget of one) decomposes them again
    as new objects: their changes of basis are formed again (weak keys), the Jacobian the same."""
    system = _chain(20, 5)
    marcher, pieces = _orbit_pieces(system)
    full = monodromy.march_jacobian(marcher, pieces)
    n = system.n_dof
    assert len(marcher._basis_changes) > 1
    marcher._basis_changes.clear()
    monkeypatch.setattr(monodromy, "BASIS_CACHE_BYTES", 8 * n * n)
    assert np.array_equal(monodromy.march_jacobian(marcher, pieces), full)
    assert len(marcher._basis_changes) == 1
    monkeypatch.setattr(monodromy, "BASIS_CACHE_BYTES", 2 ** 29)
    monkeypatch.setattr(events, "CONFIG_CACHE_BYTES", 1)  # every new configuration evicts the others
    small = fj.Marcher(system)
    pr = fj.periodic_response(system, marcher=small)
    pmap = _PeriodMap(system, small, pr.section_time)
    pmap(pr.state)
    jac = monodromy.march_jacobian(small, pmap.last[2])
    assert _rel(jac, monodromy._march_jacobian_rows(small, pmap.last[2])) <= RTOL
