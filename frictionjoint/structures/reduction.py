"""Craig-Bampton reduction: the boundary (joint) DOFs stay physical, the interior is represented by
its static response to the boundary and a few fixed-interface modes.

With the DOFs split into boundary ``b`` and interior ``i``, ``x_i = Psi x_b + Phi q``: the
constraint modes ``Psi = -K_ii^-1 K_ib`` (the static interior response to unit boundary
motions) and the first ``n_modes`` fixed-interface modes ``Phi`` (``K_ii phi = omega^2 M_ii phi``,
mass-normalised). ``T = [[I, 0], [Psi, Phi]]`` gives ``M_r = T^T M T``, ``K_r = T^T K T``,
``C_r = T^T C T``. The reduced model is exact for static boundary loads and for the retained
fixed-interface modes (with the boundary clamped it has exactly their frequencies); its error
below them comes from the truncated modes.

Two paths, one result. A :class:`~frictionjoint.LinearStructure` (dense matrices) is reduced with
dense LAPACK (``scipy.linalg``). A model with ``scipy.sparse`` matrices -- an
:class:`~frictionjoint.structures.FEModel` read from an FE code's export, or any object with
sparse ``mass``, ``stiffness`` (and optionally ``damping``) and ``dof_names`` -- is reduced
without ever making an ``n x n`` dense matrix:

* one sparse LU of ``K_ii`` (SuperLU, minimum-degree ordering of ``K + K^T``, symmetric mode, no
  pivoting: ``K_ii`` is symmetric positive definite when the boundary holds the structure, and
  the signs of the pivots are its inertia, so an unstable clamped structure is refused from the
  factor itself);
* the constraint modes from that factor, the columns of ``K_ib`` solved in blocks of
  :data:`BLOCK` right-hand sides (each block one pass over the factor; ``Psi`` is dense anyway);
* the fixed-interface modes by ARPACK in shift-invert mode (``scipy.sparse.linalg.eigsh``) with
  the shift ``sigma = 0``: the eigenvalues nearest the shift are the lowest, which are the ones
  kept; the operator ``(K_ii - sigma M_ii)^-1`` is then ``K_ii^-1``, whose factor is the one
  already made for the constraint modes (any other shift would need a second factorisation of
  the same cost, the largest single cost of the reduction), and the lowest modes are the best
  separated eigenvalues ``1/omega^2`` of that operator, so that ARPACK converges in few
  iterations. ``K_ii`` is positive definite (boundary clamped), so the zero shift is never an
  eigenvalue. The Ritz vectors are made exactly mass-orthonormal by a Rayleigh-Ritz step in their
  own span, and each is signed so that its first entry of largest magnitude is positive (ties
  within 1e-6 of it counted as largest; ARPACK starts from a fixed vector): a model reduced twice
  gives the same basis;
* the residual vectors of the loaded DOFs by the same factor;
* ``T`` dense and thin (``n x n_reduced``: 220 MB for 50,925 DOFs and 546 reduced DOFs), the
  projections ``T^T A T`` made a block of columns at a time.

Cost on this machine (2 shared cores, ``benchmarks/reduction.py``): a 50,925-DOF blade of
hexahedra (3.6 million stiffness entries) to its 525-DOF root face, 20 modes and a residual
vector, 546 DOFs: 41-107 s wall, 52-58 s CPU, of which the factor (44 million entries)
3.4-6.4 s, the solves 29-50 s (525 constraint modes; ARPACK's some 60 shift-invert steps),
``eigsh`` as a whole 3-12 s, the projections 3-5 s; peak memory 1.6 GB (the model 0.9 GB of it). The range is the
machine's load (3 to 5 on 2 cores while it was measured).

Damping: the structure's (a dense or sparse matrix, projected) or ``rayleigh = (alpha, beta)``,
``C = alpha M + beta K``, whose projection is ``alpha M_r + beta K_r`` exactly.

On a small model both paths give the same frequencies and the same ``T`` (each mode up to its
sign) to their rounding bounds (``tests/test_reduction_sparse.py``). The sparse path is the more
accurate: its lowest eigenvalue is within 1e-12 to 5e-12 of the exact one (a long-double Rayleigh
quotient), where dense LAPACK's error scales with the largest eigenvalue (``p(n) eps ||K||
||M^-1||``): 0.4e-10 to 2.5e-10 on a 324-DOF blade whose eigenvalues span 3e6, depending on the
CPU's BLAS kernels. Interface reduction of a boundary of many
nodes, after this one: :func:`frictionjoint.structures.interface.interface_reduction`.

Reference: R. R. Craig, M. C. C. Bampton, "Coupling of substructures for dynamic analyses",
AIAA Journal 6 (1968) 1313-1319.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Sequence

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from ..errors import ParameterError, check_count, check_nonnegative
from ..memory import check_fits
from ..threads import owns_blas_threads
from ..structure import LinearStructure

if TYPE_CHECKING:
    from .fe_import import FEModel

__all__ = ["craig_bampton", "BLOCK"]

#: right-hand sides per sparse solve (constraint modes) and columns per block of a projection
BLOCK = 64


@owns_blas_threads
def craig_bampton(structure: LinearStructure | FEModel, boundary_dofs: Sequence, n_modes: int = 5,
                  loaded_dofs: Sequence = (), *, rayleigh: tuple | None = None) -> LinearStructure:
    """Craig-Bampton reduction of ``structure`` to ``boundary_dofs`` plus ``n_modes`` modes.

    A force on an interior DOF (e.g. the excitation at the tip) excites the truncated modes
    statically; ``loaded_dofs`` adds, per such DOF, its residual vector: the interior's static
    response to a unit load there (boundary clamped), made mass-orthogonal to the kept modes and
    mass-normalised (modal coordinates ``r_<dof>``), so that the reduced model's response to that
    load is exact statically and its error below the kept modes is that of the truncation only.

    Parameters
    ----------
    structure : LinearStructure or FEModel
        The full model (e.g. :attr:`~frictionjoint.structures.BeamBlade.structure`, dense), or a
        sparse one: an :class:`~frictionjoint.structures.FEModel` or any object with
        ``scipy.sparse`` ``mass`` [kg] and ``stiffness`` [N/m], optional ``damping`` [N s/m],
        ``dof_names`` and optionally ``indefinite_stiffness`` (module docstring: the sparse path).
    boundary_dofs : sequence of str or int
        The DOFs that stay physical (the joints' DOFs, e.g. ``["u0", "w0", "t0"]``, or an
        FEModel's ``dofs_of("flank")``), by name or index.
    n_modes : int
        Fixed-interface modes kept, in ``[0, n_interior]``.
    loaded_dofs : sequence of str or int
        Interior DOFs that carry loads, one residual vector each.
    rayleigh : (float, float), optional
        ``(alpha [1/s], beta [s])``: damping ``alpha M + beta K`` instead of the structure's
        (which must then be absent or zero).

    Returns
    -------
    LinearStructure
        DOFs: the boundary DOFs (their names and order), ``q1 ... q{n_modes}`` (modal coordinates,
        unit modal mass), then ``r_<dof>`` per loaded DOF. Its ``transformation`` (full DOFs x
        reduced DOFs, a dense array) gives the full displacements ``x = T x_r`` and the reduced
        loads ``f_r = T^T f``; ``full_dof_names`` names the rows, ``boundary_dofs`` the boundary
        DOFs, ``fixed_interface_frequencies`` the kept modes' angular frequencies [rad/s].
    """
    sparse = not isinstance(structure, LinearStructure)
    if sparse and not (sp.issparse(getattr(structure, "stiffness", None))
                       and sp.issparse(getattr(structure, "mass", None)) and hasattr(structure, "dof_names")):
        raise ParameterError("structure must be a LinearStructure or have scipy.sparse mass and stiffness and "
                             f"dof_names (an FEModel), got {type(structure).__name__}")
    names = tuple(structure.dof_names)
    index = _dof_lookup(names) if sparse else structure.dof_index
    b = [index(d) for d in boundary_dofs]
    if not b or len(set(b)) != len(b):
        raise ParameterError(f"boundary_dofs must be distinct DOFs of the structure, got {list(boundary_dofs)!r}")
    in_b = np.zeros(len(names), dtype=bool)
    in_b[b] = True
    i = np.flatnonzero(~in_b)
    n_modes = check_count("n_modes", n_modes, 0)
    if n_modes > len(i):
        raise ParameterError(f"n_modes must be in [0, {len(i)}] (interior DOFs), got {n_modes}")
    loaded = [index(d) for d in loaded_dofs]
    if any(in_b[d] for d in loaded) or len(set(loaded)) != len(loaded):
        raise ParameterError(f"loaded_dofs must be distinct interior DOFs, got {list(loaded_dofs)!r}")
    damping = _damping(structure, rayleigh)
    # the dense transformation (every DOF x the reduced ones) and ARPACK's Lanczos vectors, or the
    # dense interior eigenproblem's copies, checked before either is allocated
    n_red, ncv = len(b) + n_modes + len(loaded), max(2 * n_modes + 1, 20)
    check_fits(8.0 * len(names) * (n_red + ncv) + (0.0 if sparse else 24.0 * len(i) ** 2),
               f"n_modes = {n_modes} on {len(names)} DOFs ({len(b)} boundary)",
               f"the {len(names)} x {n_red} transformation and the interior eigenproblem's work")
    t, lam = (_sparse_basis if sparse else _dense_basis)(structure, b, i, n_modes, loaded)
    m_r, k_r = _project(structure.mass, t), _project(structure.stiffness, t)
    if rayleigh is not None:
        c_r = rayleigh[0] * m_r + rayleigh[1] * k_r
    else:
        c_r = None if damping is None else _project(damping, t)
    out_names = ([names[k] for k in b] + [f"q{j + 1}" for j in range(n_modes)]
                 + [f"r_{names[d]}" for d in loaded])
    out = LinearStructure(m_r, k_r, c_r, dof_names=out_names,
                          indefinite_stiffness=bool(getattr(structure, "indefinite_stiffness", False)))
    out.transformation = t
    out.full_dof_names = names
    out.boundary_dofs = tuple(names[k] for k in b)
    if lam is None:
        lam = np.diag(k_r)[len(b):len(b) + n_modes]  # the kept modes' omega^2 (unit modal mass)
    out.fixed_interface_frequencies = np.sqrt(np.asarray(lam, dtype=float))
    return out


def _dof_lookup(names: tuple):
    """``dof -> index`` for DOF names or integer indices of a model with DOF ``names``."""
    position = {name: k for k, name in enumerate(names)}

    def index(dof) -> int:
        if isinstance(dof, str):
            if dof not in position:
                raise ParameterError(f"no DOF named {dof!r} in the structure")
            return position[dof]
        if isinstance(dof, (bool, np.bool_)) or not isinstance(dof, (int, np.integer)):
            raise ParameterError(f"a DOF must be a name or an integer index, got {dof!r}")
        if not 0 <= dof < len(names):
            raise ParameterError(f"a DOF index must be in [0, {len(names) - 1}], got {dof}")
        return int(dof)

    return index


def _damping(structure, rayleigh):
    """The structure's damping matrix (None if absent or zero); with ``rayleigh``, checked absent."""
    c = getattr(structure, "damping", None)
    if c is not None and not (c.count_nonzero() if sp.issparse(c) else np.any(c)):
        c = None
    if rayleigh is None:
        return c
    if c is not None:
        raise ParameterError("give the damping in the structure or as rayleigh, not both")
    try:
        alpha, beta = rayleigh
    except (TypeError, ValueError):
        raise ParameterError(f"rayleigh must be (alpha, beta), got {rayleigh!r}") from None
    check_nonnegative("rayleigh alpha", alpha), check_nonnegative("rayleigh beta", beta)
    return None


def _project(a, t: np.ndarray) -> np.ndarray:
    """``T^T A T``, symmetrised, a block of :data:`BLOCK` columns of ``T`` at a time (``A`` dense or
    sparse: no ``n x n_reduced`` temporary beside ``T``)."""
    if not sp.issparse(a):
        r = t.T @ a @ t
        return 0.5 * (r + r.T)
    a = sp.csr_array(a)
    r = np.empty((t.shape[1], t.shape[1]))
    for j in range(0, t.shape[1], BLOCK):
        r[:, j:j + BLOCK] = t.T @ (a @ t[:, j:j + BLOCK])
    return 0.5 * (r + r.T)


def _sparse_basis(structure, b, i, n_modes, loaded):
    """``(T, omega^2)`` of the sparse path (module docstring): one LU of ``K_ii`` for the constraint
    modes, the fixed-interface modes (shift-invert at 0) and the residual vectors."""
    import scipy.sparse.linalg as spla

    k = sp.csr_array(structure.stiffness)
    m = sp.csr_array(structure.mass)
    kii, mii = k[i][:, i].tocsc(), m[i][:, i].tocsc()
    lu = _factor(kii)
    nb, n_i = len(b), len(i)
    t = np.zeros((k.shape[0], nb + n_modes + len(loaded)))
    t[b, np.arange(nb)] = 1.0
    kib = k[i][:, b].tocsc()
    for j in range(0, nb, BLOCK):  # Psi = -K_ii^-1 K_ib, BLOCK right-hand sides per solve
        e = min(j + BLOCK, nb)
        t[i, j:e] = -lu.solve(kib[:, j:e].toarray())
    if n_modes:
        op = spla.LinearOperator((n_i, n_i), matvec=lu.solve, dtype=float)
        ncv = min(n_i, max(2 * n_modes + 1, 20))
        # a fixed start vector (ARPACK's default is random: two reductions of one model differed
        # by ~3e-12), pseudo-random so that no mode of a symmetric structure is orthogonal to it
        v0 = np.random.default_rng(0).standard_normal(n_i)
        lam, phi = spla.eigsh(kii, k=n_modes, M=mii, sigma=0.0, which="LM", OPinv=op, tol=0.0, ncv=ncv, v0=v0) \
            if n_modes < n_i else scipy.linalg.eigh(kii.toarray(), mii.toarray())
        # Rayleigh-Ritz in the span: exactly mass-orthonormal, ascending; signed (_signed)
        lam, w = scipy.linalg.eigh(_sym(phi.T @ (kii @ phi)), _sym(phi.T @ (mii @ phi)))
        phi = _signed(phi @ w)
        if lam[0] <= 0:
            raise ParameterError(f"the structure with its boundary clamped is not stable (omega^2 = {lam[0]:.3g})")
    else:
        lam, phi = np.zeros(0), np.zeros((n_i, 0))
    vectors = [phi]
    position = {d: p for p, d in enumerate(i)}
    for d in loaded:
        f = np.zeros(n_i)
        f[position[d]] = 1.0
        vectors.append(_residual_vector(lu.solve(f), mii, vectors, structure.dof_names[d])[:, None])
    t[i, nb:] = np.column_stack(vectors)
    return t, lam


def _sym(a: np.ndarray) -> np.ndarray:
    return 0.5 * (a + a.T)


#: entries within this fraction of a mode's largest magnitude count as its largest (_signed)
SIGN_TIE = 1e-6


def _signed(phi: np.ndarray) -> np.ndarray:
    """Each mode (column) signed so that its first entry of largest magnitude is positive, entries
    within :data:`SIGN_TIE` of the largest counting as largest: where two entries are equal but
    for rounding (a structure with a symmetry), rounding does not choose the sign (it flipped a
    mode between two reductions of one model)."""
    mag = np.abs(phi)
    first = np.argmax(mag >= (1.0 - SIGN_TIE) * mag.max(axis=0, initial=0.0), axis=0)
    sign = np.sign(phi[first, np.arange(phi.shape[1])])
    return phi * np.where(sign == 0, 1.0, sign)


def _factor(kii):
    """SuperLU of the clamped stiffness ``K_ii`` in symmetric mode without pivoting (module
    docstring); refused if singular or not positive definite (a pivot <= 0: Sylvester's inertia)."""
    import scipy.sparse.linalg as spla

    try:
        lu = spla.splu(kii, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                       options={"SymmetricMode": True})
    except RuntimeError as exc:
        raise ParameterError(f"the structure with its boundary DOFs clamped is singular: {exc}") from None
    pivots = lu.U.diagonal()
    scale = max(np.max(np.abs(pivots)), np.finfo(float).tiny)
    if not np.min(pivots) > 1e-14 * scale:
        raise ParameterError("the structure with its boundary DOFs clamped is not positive definite "
                             f"(smallest pivot {np.min(pivots) / scale:.3g} of the largest): singular or not stable")
    return lu


def _residual_vector(r0, mii, vectors, name):
    """A loaded DOF's static response ``r0`` made mass-orthogonal to ``vectors`` (twice: rounding)
    and mass-normalised; refused if it lies in them."""
    r = r0
    for _ in range(2):
        basis = np.column_stack(vectors)
        r = r - basis @ (basis.T @ (mii @ r))
    norm = float(r @ mii @ r)
    if not norm > 1e-20 * float(r0 @ mii @ r0):
        raise ParameterError(f"the residual vector of {name!r} lies in the kept modes")
    return r / np.sqrt(norm)


def _dense_basis(structure, b, i, n_modes, loaded):
    """``(T, None)`` of the dense path: ``scipy.linalg`` on the dense matrices."""
    i = list(i)
    psi, phi = _interior_modes(structure.stiffness, structure.mass, b, i, n_modes)
    v = _with_residual_vectors(structure, i, loaded, phi)
    nb, nv = len(b), v.shape[1]
    t = np.zeros((structure.n_dof, nb + nv))
    t[b, :nb] = np.eye(nb)
    t[np.ix_(i, range(nb))] = psi
    t[np.ix_(i, range(nb, nb + nv))] = v
    return t, None


def _interior_modes(k, m, b, i, n_modes):
    """``(Psi, Phi)``: the constraint modes ``-K_ii^-1 K_ib`` and the first ``n_modes``
    fixed-interface modes (mass-normalised) of the interior ``i`` with the boundary ``b`` clamped;
    a singular or unstable clamped structure is refused."""
    kii = k[np.ix_(i, i)]
    try:
        psi = -scipy.linalg.solve(kii, k[np.ix_(i, b)], assume_a="sym")
        lam, phi = scipy.linalg.eigh(kii, m[np.ix_(i, i)], subset_by_index=[0, n_modes - 1]) if n_modes else \
            (np.zeros(0), np.zeros((len(i), 0)))
    except (np.linalg.LinAlgError, scipy.linalg.LinAlgError) as exc:
        raise ParameterError(f"the structure with its boundary DOFs clamped is singular: {exc}") from None
    if lam.size and lam[0] <= 0:
        raise ParameterError(f"the structure with its boundary clamped is not stable (omega^2 = {lam[0]:.3g})")
    return psi, _signed(phi)


def _with_residual_vectors(structure, i, loaded, phi):
    """The interior vectors ``[Phi, r_1, ...]``: the kept modes and, per loaded DOF, the interior's
    static response to a unit load there (boundary clamped), made mass-orthogonal to the modes and
    the earlier vectors and mass-normalised (refused if it lies in them)."""
    kii = structure.stiffness[np.ix_(i, i)]
    mii = structure.mass[np.ix_(i, i)]
    vectors = [phi]
    for d in loaded:
        f = np.zeros(len(i))
        f[i.index(d)] = 1.0
        r0 = scipy.linalg.solve(kii, f, assume_a="sym")
        vectors.append(_residual_vector(r0, mii, vectors, structure.dof_names[d])[:, None])
    return np.column_stack(vectors)
