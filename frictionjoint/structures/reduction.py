"""Craig-Bampton reduction: the boundary (joint) DOFs stay physical, the interior is represented by
its static response to the boundary and a few fixed-interface modes.

With the DOFs split into boundary ``b`` and interior ``i``, ``x_i = Psi x_b + Phi q``: the
constraint modes ``Psi = -K_ii^-1 K_ib`` (the static interior response to unit boundary
motions) and the first ``n_modes`` fixed-interface modes ``Phi`` (``K_ii phi = omega^2 M_ii phi``,
mass-normalised). ``T = [[I, 0], [Psi, Phi]]`` gives ``M_r = T^T M T``, ``K_r = T^T K T``,
``C_r = T^T C T``. The reduced model is exact for static boundary loads and for the retained
fixed-interface modes (with the boundary clamped it has exactly their frequencies); its error
below them comes from the truncated modes.

Reference: R. R. Craig, M. C. C. Bampton, "Coupling of substructures for dynamic analyses",
AIAA Journal 6 (1968) 1313-1319.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
import scipy.linalg

from ..errors import ParameterError, check_count
from ..structure import LinearStructure

__all__ = ["craig_bampton"]


def craig_bampton(structure: LinearStructure, boundary_dofs: Sequence, n_modes: int = 5,
                  loaded_dofs: Sequence = ()) -> LinearStructure:
    """Craig-Bampton reduction of ``structure`` to ``boundary_dofs`` plus ``n_modes`` modes.

    A force on an interior DOF (e.g. the excitation at the tip) excites the truncated modes
    statically; ``loaded_dofs`` adds, per such DOF, its residual vector: the interior's static
    response to a unit load there (boundary clamped), made mass-orthogonal to the kept modes and
    mass-normalised (modal coordinates ``r_<dof>``), so that the reduced model's response to that
    load is exact statically and its error below the kept modes is that of the truncation only.

    Parameters
    ----------
    structure : LinearStructure
        The full model (e.g. :attr:`~frictionjoint.structures.BeamBlade.structure`).
    boundary_dofs : sequence of str or int
        The DOFs that stay physical (the joints' DOFs, e.g. ``["u0", "w0", "t0"]``), by name or
        index.
    n_modes : int
        Fixed-interface modes kept, in ``[0, n_interior]``.
    loaded_dofs : sequence of str or int
        Interior DOFs that carry loads, one residual vector each.

    Returns
    -------
    LinearStructure
        DOFs: the boundary DOFs (their names and order), ``q1 ... q{n_modes}`` (modal coordinates,
        unit modal mass), then ``r_<dof>`` per loaded DOF. Its ``transformation`` (full DOFs x
        reduced DOFs) gives the full displacements ``x = T x_r`` and the reduced loads
        ``f_r = T^T f``; ``full_dof_names`` names the rows.
    """
    if not isinstance(structure, LinearStructure):
        raise ParameterError(f"structure must be a LinearStructure, got {type(structure).__name__}")
    b = [structure.dof_index(d) for d in boundary_dofs]
    if not b or len(set(b)) != len(b):
        raise ParameterError(f"boundary_dofs must be distinct DOFs of the structure, got {list(boundary_dofs)!r}")
    i = [k for k in range(structure.n_dof) if k not in set(b)]
    n_modes = check_count("n_modes", n_modes, 0)
    if n_modes > len(i):
        raise ParameterError(f"n_modes must be in [0, {len(i)}] (interior DOFs), got {n_modes}")
    m, k, c = structure.mass, structure.stiffness, structure.damping
    psi, phi = _interior_modes(k, m, b, i, n_modes)
    loaded = [structure.dof_index(d) for d in loaded_dofs]
    if any(d in set(b) for d in loaded) or len(set(loaded)) != len(loaded):
        raise ParameterError(f"loaded_dofs must be distinct interior DOFs, got {list(loaded_dofs)!r}")
    v = _with_residual_vectors(structure, i, loaded, phi)
    nb, nv = len(b), v.shape[1]
    t = np.zeros((structure.n_dof, nb + nv))
    t[b, :nb] = np.eye(nb)
    t[np.ix_(i, range(nb))] = psi
    t[np.ix_(i, range(nb, nb + nv))] = v

    def project(a):
        r = t.T @ a @ t
        return 0.5 * (r + r.T)

    names = ([structure.dof_names[k] for k in b] + [f"q{j + 1}" for j in range(n_modes)]
             + [f"r_{structure.dof_names[d]}" for d in loaded])
    out = LinearStructure(project(m), project(k), project(c), dof_names=names,
                          indefinite_stiffness=structure.indefinite_stiffness)
    out.transformation = t
    out.full_dof_names = structure.dof_names
    return out


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
    return psi, phi


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
        r = r0 = scipy.linalg.solve(kii, f, assume_a="sym")
        for _ in range(2):  # mass-orthogonal to the modes and the earlier vectors (twice: rounding)
            basis = np.column_stack(vectors)
            r = r - basis @ (basis.T @ (mii @ r))
        norm = float(r @ mii @ r)
        if not norm > 1e-20 * float(r0 @ mii @ r0):
            raise ParameterError(f"the residual vector of {structure.dof_names[d]!r} lies in the kept modes")
        vectors.append((r / np.sqrt(norm))[:, None])
    return np.column_stack(vectors)
