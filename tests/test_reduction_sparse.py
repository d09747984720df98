"""Craig-Bampton on sparse matrices and interface reduction (issue 30, part 4): the sparse path
against the dense one, the interface reduction against the unreduced interface, and the reduced
model's linear frequency response against the unreduced one's in the root's limits.

The model is ``benchmarks/reduction.py``'s blade of hexahedra (root face ``x = 0`` the boundary,
its outer node columns the flanks, the far corner the tip), small enough for dense references."""
import numpy as np
import pytest
import scipy.linalg
import scipy.sparse as sp

# the benchmark's blade and receptances (pytest's pythonpath has the repository root)
from benchmarks.reduction import hex_blade, reduced_tip_receptance, root_springs, tip_receptance
from frictionjoint import LinearStructure
from frictionjoint.errors import ParameterError
from frictionjoint.structures import FEModel, craig_bampton
from frictionjoint.structures.interface import interface_reduction

SAME = 1e-10        # the sparse and the dense path; an exact change of basis
SPRING = 2e7        # root springs [N/m] of the stuck and slipping limits (per DOF)


@pytest.fixture(scope="module")
def blade():
    return hex_blade(8, 3, 2)  # 324 DOFs, a root face of 12 nodes


def _tip(model):
    return model.dof_index(model.node_sets["tip"][0], 3)


def _aligned(a, b):
    """Columns of ``a`` signed as ``b``'s (a mode's sign is arbitrary)."""
    return a * np.where(np.sum(a * b, axis=0) < 0, -1.0, 1.0)


def _dense(model, damping=None):
    return LinearStructure(model.mass.toarray(), model.stiffness.toarray(), damping, dof_names=model.dof_names)


@pytest.mark.parametrize("damping", ["rayleigh", "matrix"])
def test_sparse_path_is_the_dense_one(blade, damping):
    root, tip = blade.dofs_of("root"), _tip(blade)
    alpha, beta = 3.0, 2e-7
    c = alpha * blade.mass + beta * blade.stiffness
    if damping == "rayleigh":
        sparse = craig_bampton(blade, root, 6, [tip], rayleigh=(alpha, beta))
    else:
        sparse = craig_bampton(FEModel(blade.mass, blade.stiffness, c, dofs=blade.dofs), root, 6, [tip])
    dense = craig_bampton(_dense(blade, c.toarray()), list(root), 6, [int(tip)])
    assert sparse.dof_names == dense.dof_names and sparse.boundary_dofs == dense.boundary_dofs
    w_s, w_d = sparse.fixed_interface_frequencies, dense.fixed_interface_frequencies
    t_d = dense.transformation
    t_s = _aligned(sparse.transformation, t_d)
    sign = np.sign(np.sum(sparse.transformation * t_d, axis=0))
    errors = {"frequencies": np.max(np.abs(w_s / w_d - 1)),
              "T": np.max(np.abs(t_s - t_d)) / np.max(np.abs(t_d))}
    for name in ("mass", "stiffness", "damping"):
        a, b = getattr(sparse, name), getattr(dense, name)
        errors[name] = np.max(np.abs(sign[:, None] * a * sign - b)) / np.max(np.abs(b))
    print(damping, {k: f"{v:.1e}" for k, v in errors.items()})
    assert max(errors.values()) <= SAME
    # the fixed-interface modes are the clamped model's, which ARPACK found by shift-invert at 0
    clamped = _dense(blade).clamped(list(root))
    assert np.max(np.abs(w_s / clamped.natural_frequencies()[:6] - 1)) <= SAME


def test_sparse_path_refuses_what_the_dense_one_refuses(blade):
    root, tip = blade.dofs_of("root"), _tip(blade)
    with pytest.raises(ParameterError, match="clamped is singular|not positive definite"):
        craig_bampton(blade, [tip], 3)  # one DOF does not hold the blade
    with pytest.raises(ParameterError, match="not both"):
        craig_bampton(FEModel(blade.mass, blade.stiffness, blade.mass, dofs=blade.dofs), root, 3,
                      rayleigh=(1.0, 0.0))
    with pytest.raises(ParameterError, match="distinct interior"):
        craig_bampton(blade, root, 3, [root[0]])
    with pytest.raises(ParameterError, match="n_modes"):
        craig_bampton(blade, root, blade.n_dof)
    with pytest.raises(ParameterError, match="no DOF named"):
        craig_bampton(blade, ["n1_u9"], 3)
    with pytest.raises(ParameterError, match="LinearStructure or have scipy.sparse"):
        craig_bampton(object(), [0], 3)


def _stuck(model, reduced):
    """Stiffness of ``reduced`` with the stuck limit's flank springs (on its transformation's rows)."""
    k = root_springs(model, "stuck", SPRING)
    held = np.flatnonzero(k)
    t = reduced.transformation
    return reduced.stiffness + t[held].T @ (k[held, None] * t[held])


def test_interface_reduction_against_the_unreduced_interface(blade):
    root, tip = blade.dofs_of("root"), _tip(blade)
    cb = craig_bampton(blade, root, 8, [tip])
    n_b = len(root)
    f = cb.transformation[tip]  # the reduced tip load
    w_cb = np.sqrt(scipy.linalg.eigh(_stuck(blade, cb), cb.mass, eigvals_only=True))
    x_cb = np.linalg.solve(_stuck(blade, cb), f)
    # every interface mode kept: a change of basis, the same model
    whole = interface_reduction(cb, n_b)
    assert whole.dof_names[:2] == ("c1", "c2") and whole.dof_names[n_b:] == cb.dof_names[n_b:]
    w = np.sqrt(scipy.linalg.eigh(_stuck(blade, whole), whole.mass, eigvals_only=True))
    # dense eigh's rounding is a multiple of eps times the largest eigenvalue (3e-12 of it here,
    # 7e-10 of the lowest omega)
    assert np.max(np.abs(w ** 2 - w_cb ** 2)) <= 1e-11 * w_cb[-1] ** 2
    # the flanks kept physical: their rows of the transformation are unit rows
    flank_rows = set(blade.dofs_of("flank_a")) | set(blade.dofs_of("flank_b"))
    flanks = [blade.dof_names[j] for j in root if j in flank_rows]
    lines, errors = [], {}
    for keep in ((), flanks):
        for n_modes in (2, 6, 12):
            red = interface_reduction(cb, n_modes, keep)
            rows = red.transformation[[cb.full_dof_names.index(d) for d in keep]]
            assert np.array_equal(rows, np.eye(red.n_dof)[:len(keep)])
            w = np.sqrt(scipy.linalg.eigh(_stuck(blade, red), red.mass, eigvals_only=True))
            x = red.interface_transformation @ np.linalg.solve(_stuck(blade, red), red.transformation[tip])
            errors[len(keep), n_modes] = (np.max(np.abs(w[:5] / w_cb[:5] - 1)), abs(f @ x / (f @ x_cb) - 1))
            lines.append(f"keep {len(keep):2d}, {n_modes:2d} modes ({red.n_dof} DOFs): frequencies 1-5 "
                         f"{errors[len(keep), n_modes][0]:.1e}, static tip {errors[len(keep), n_modes][1]:.1e}")
    print("\n".join(lines))
    # flanks kept: the rest of the root face carries no springs, only the tip load's share
    # (9.9e-7 and 6.1e-9 here); characteristic constraint modes see the stiff flanks through 12 shapes
    assert max(errors[len(flanks), 12]) <= 1e-5 and errors[0, 12][0] <= 0.05
    with pytest.raises(ParameterError, match="do not hold the rest"):
        interface_reduction(cb, 2, flanks[:1])  # one DOF does not hold a free blade
    with pytest.raises(ParameterError, match="keep must be distinct boundary"):
        interface_reduction(cb, 2, ["q1"])
    with pytest.raises(ParameterError, match="made by craig_bampton"):
        interface_reduction(_dense(blade), 2)


@pytest.mark.slow
def test_receptance_in_the_root_limits_below_the_cut_off():
    """The reduced blade's tip receptance against the unreduced one's (a sparse LU per frequency),
    boundary the whole root face, flanks stuck (springs on their DOFs), slipping (normal springs
    only) and free, below the cut-off omega_n / 3 (omega_n the highest fixed-interface mode kept),
    damping 1 % at 10^4 rad/s (Rayleigh beta = 2e-6 s): within 1e-3 of the peak over the band.
    Near a resonance the error is the mode's frequency error over its damping ratio: at 0.1 %
    (beta = 2e-7 s) it is 4e-3 to 1e-2 with these 20 modes (benchmarks/reduction.py --beta 2e-7)."""
    model = hex_blade(24, 6, 2)  # 1,575 DOFs
    tip = _tip(model)
    rayleigh = (0.0, 2e-6)
    cb = craig_bampton(model, model.dofs_of("root"), 20, [tip], rayleigh=rayleigh)
    cut_off = cb.fixed_interface_frequencies[-1] / 3
    omegas = np.linspace(0.005, 1.0, 60) * cut_off
    mass = model.mass.toarray()
    for limit in ("stuck", "slipping", "free"):
        springs = root_springs(model, limit, SPRING)
        full = tip_receptance(model, springs, omegas, rayleigh)
        error = np.max(np.abs(reduced_tip_receptance(model, cb, springs, omegas) - full)) / np.max(np.abs(full))
        w_full = np.sqrt(np.abs(scipy.linalg.eigh(model.stiffness.toarray() + np.diag(springs), mass,
                                                  eigvals_only=True, subset_by_index=[0, 29])))
        held, t = np.flatnonzero(springs), cb.transformation
        w_red = np.sqrt(np.abs(scipy.linalg.eigh(cb.stiffness + t[held].T @ (springs[held, None] * t[held]), cb.mass,
                                                 eigvals_only=True)))
        band = np.flatnonzero((w_full > 1.0) & (w_full < cut_off))
        print(f"{limit}: receptance error / peak {error:.1e}, {len(band)} modes below the cut-off, "
              f"their frequencies {np.max(np.abs(w_red[band] / w_full[band] - 1)):.1e}")
        assert error <= 1e-3


def test_a_rotating_solid_blade_reduced_to_its_root_face():
    """SolidBlade (sparse, spin-softened stiffness: indefinite_stiffness) reduces as it is, without
    a dense structure: the fixed-interface modes are the blade's root-clamped modes."""
    from frictionjoint.structures.solid import SolidBlade

    blade = SolidBlade(0.2, 0.05, 0.004, 110e9, 0.3, 4430.0, n_elements=(8, 2, 1), rotor_speed=1000.0,
                       hub_radius=0.25)
    red = craig_bampton(blade, blade.dofs_of("root"), 6, [blade.dofs_of("tip")[2]])
    assert red.indefinite_stiffness and red.transformation.shape == (blade.n_dof, red.n_dof)
    error = np.max(np.abs(red.fixed_interface_frequencies / blade.natural_frequencies(6) - 1))
    print(f"SolidBlade {blade.n_dof} DOFs: fixed-interface frequencies against natural_frequencies {error:.1e}")
    assert error <= SAME
