"""Interface reduction of a Craig-Bampton model whose boundary has many nodes (contact patches of
tens to hundreds of nodes): characteristic constraint modes, with the DOFs that friction contact
needs kept physical.

A Craig-Bampton model (:func:`~frictionjoint.structures.craig_bampton`) keeps every boundary DOF:
``K_r = [[Kt_bb, 0], [0, Lambda]]``, ``M_r = [[Mt_bb, Mt_bq], [Mt_qb, I]]``, where ``Kt_bb`` is
the static condensation of the structure on its boundary and ``Mt_bb`` the matching mass. A root
face of 175 nodes is 525 boundary DOFs; the contact elements act on few of them, and the others
only make the model large. The boundary is split into ``P`` (kept: the DOFs the contact elements
act on) and ``R`` (the rest), and ``R`` is represented by

``x_R = G x_P + Phi_R eta``, ``G = -Kt_RR^-1 Kt_RP``, ``Kt_RR Phi_R = Mt_RR Phi_R diag(omega_c^2)``:

the static response of the rest of the boundary to the kept DOFs, and the first ``n_modes``
modes of the rest of the boundary with the kept DOFs clamped. With nothing kept (``P`` empty)
these are the characteristic constraint (CC) modes of Castanier, Tan and Pierre: the eigenvectors
of the Craig-Bampton boundary partition. The modal coordinates ``q`` and residual vectors of the
Craig-Bampton model are untouched.

How the contact nodes stay physical, and what it costs. Friction contact (a Jenkins slider and a
normal spring per node, lift-off) needs each contact node's own displacement: its slip and its
gap are functions of that node alone. Two ways, both offered:

* ``keep`` the contact DOFs (the patch nodes, in the directions their elements act on): they stay
  physical, exactly; only the rest of the boundary is reduced. The error is then in the rest of
  the boundary (exact for any static load on the kept DOFs, for the kept modes, and when ``R``
  carries neither loads nor springs); the cost is that the reduced model has at least as many
  DOFs as the contact has, ``n_P + n_modes + n_q``: a patch of 100 nodes in 3 directions is 300
  DOFs whatever the reduction, and the exact marcher's and harmonic balance's cost grows with
  them.
* keep nothing (plain CC modes): every contact node's displacement is then a row of the
  ``transformation``, ``x_node = T[node] x_r``, and a contact element acts on it as a
  ``direction`` over the reduced DOFs (the library's elements take ``direction=``). The model is
  small, but the contact's stiffness is seen through ``n_modes`` shapes only: the stuck contact's
  static response and frequencies carry the truncation error measured in
  ``tests/test_reduction_sparse.py`` and ``benchmarks/reduction.py`` (it falls with the modes
  kept; a stiff contact needs many), and a node's own slip is no longer independent of the others'.
  Use it for contacts that stay stuck or for a first look; use ``keep`` for the contact studied.

The error against the unreduced interface (the Craig-Bampton model with every root DOF), stuck
flanks (springs on their DOFs), first ten frequencies and the static tip response
(``benchmarks/reduction.py``, the 50,925-DOF blade, 525 root DOFs, 20 fixed-interface modes):

====================================  ========  ===========  ===========
interface                             DOFs      frequencies  static tip
====================================  ========  ===========  ===========
unreduced                             546       --           --
flanks kept (210 DOFs), 5 modes       236       1.1e-2       3.8e-7
flanks kept, 10 modes                 241       2.5e-6       3.6e-9
flanks kept, 20 modes                 251       4.7e-7       1.1e-9
CC modes (nothing kept), 10 modes     31        8.9e-2       1.3e-1
CC modes, 20 modes                    41        1.7e-2       2.8e-2
CC modes, 40 modes                    61        1.0e-2       1.6e-2
====================================  ========  ===========  ===========

With the flanks kept the static error is only the tip load's share on the rest of the root face
(the rest carries no springs); the characteristic constraint modes see the stiff stuck flanks
through a few shapes and converge slowly: a friction contact on them would be a first look only.

Reference: M. P. Castanier, Y.-C. Tan, C. Pierre, "Characteristic constraint modes for component
mode synthesis", AIAA Journal 39 (2001) 1182-1187.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
import scipy.linalg

from ..errors import ParameterError, check_count
from ..threads import owns_blas_threads
from ..structure import LinearStructure

__all__ = ["interface_reduction"]


@owns_blas_threads
def interface_reduction(reduced: LinearStructure, n_modes: int, keep: Sequence = ()) -> LinearStructure:
    """Reduce the boundary of a Craig-Bampton model to the ``keep`` DOFs plus ``n_modes``
    interface modes (module docstring).

    Parameters
    ----------
    reduced : LinearStructure
        A model made by :func:`~frictionjoint.structures.craig_bampton` (it has
        ``boundary_dofs`` and ``transformation``).
    n_modes : int
        Interface modes kept, in ``[0, n_boundary - n_keep]`` (all of them: a change of basis,
        exact).
    keep : sequence of str or int
        Boundary DOFs that stay physical (the contact nodes' DOFs), by name or index of
        ``reduced``.

    Returns
    -------
    LinearStructure
        DOFs: the kept DOFs (their names, in the order given), ``c1 ... c{n_modes}`` (interface
        modes, unit modal mass of the rest of the boundary), then the Craig-Bampton model's
        modal coordinates and residual vectors. ``transformation`` maps it to the full model's
        DOFs (``full_dof_names``), ``interface_transformation`` to ``reduced``'s DOFs;
        ``boundary_dofs`` are the kept DOFs, ``interface_frequencies`` the kept interface modes'
        angular frequencies [rad/s].
    """
    if not isinstance(reduced, LinearStructure) or getattr(reduced, "boundary_dofs", None) is None:
        raise ParameterError("reduced must be a LinearStructure made by craig_bampton (with boundary_dofs)")
    b = [reduced.dof_index(d) for d in reduced.boundary_dofs]
    p = [reduced.dof_index(d) for d in keep]
    if len(set(p)) != len(p) or not set(p) <= set(b):
        raise ParameterError(f"keep must be distinct boundary DOFs of reduced, got {list(keep)!r}")
    r = [k for k in b if k not in set(p)]
    n_modes = check_count("n_modes", n_modes, 0)
    if n_modes > len(r):
        raise ParameterError(f"n_modes must be in [0, {len(r)}] (boundary DOFs not kept), got {n_modes}")
    others = [k for k in range(reduced.n_dof) if k not in set(b)]
    k_rr = reduced.stiffness[np.ix_(r, r)]
    # every mode of the rest (a few hundred DOFs: dense): the kept ones, and the lowest, which
    # says whether the kept DOFs hold the rest (G needs K_RR regular)
    lam, phi = scipy.linalg.eigh(k_rr, reduced.mass[np.ix_(r, r)]) if r else (np.zeros(0), np.zeros((0, 0)))
    if p and r and not abs(lam[0]) > 1e-12 * np.max(np.abs(lam)):
        raise ParameterError(f"the kept DOFs do not hold the rest of the boundary (omega^2 = {lam[0]:.3g} with them "
                             "clamped): keep DOFs that hold the structure, or none")
    g = -scipy.linalg.solve(k_rr, reduced.stiffness[np.ix_(r, p)], assume_a="sym") if p else np.zeros((len(r), 0))
    lam, phi = lam[:n_modes], phi[:, :n_modes]
    n_p = len(p)
    t2 = np.zeros((reduced.n_dof, n_p + n_modes + len(others)))
    t2[p, np.arange(n_p)] = 1.0
    t2[np.ix_(r, range(n_p))] = g
    t2[np.ix_(r, range(n_p, n_p + n_modes))] = phi
    t2[others, n_p + n_modes + np.arange(len(others))] = 1.0

    def project(a):
        a = t2.T @ a @ t2
        return 0.5 * (a + a.T)

    names = ([reduced.dof_names[k] for k in p] + [f"c{j + 1}" for j in range(n_modes)]
             + [reduced.dof_names[k] for k in others])
    if not reduced.indefinite_stiffness:
        lam = np.clip(lam, 0.0, None)  # a negative omega^2 here is a rigid-body mode's rounding
    stiffness = _stiffness(reduced, p, r, others, g, lam)
    out = LinearStructure(project(reduced.mass), stiffness, project(reduced.damping),
                          dof_names=names, indefinite_stiffness=reduced.indefinite_stiffness)
    out.interface_transformation = t2
    t = reduced.transformation  # T @ t2, by its blocks (t2 is the identity but on the rest's rows)
    out.transformation = np.hstack([t[:, p] + t[:, r] @ g, t[:, r] @ phi, t[:, others]])
    out.full_dof_names = reduced.full_dof_names
    out.boundary_dofs = tuple(names[:n_p])
    out.interface_frequencies = np.sqrt(np.clip(lam, 0.0, None))
    out.fixed_interface_frequencies = getattr(reduced, "fixed_interface_frequencies", None)
    return out


def _stiffness(reduced, p, r, others, g, lam) -> np.ndarray:
    """The reduced stiffness block by block: Craig-Bampton's has no boundary-modal coupling, the
    interface modes (``omega^2 = lam``) are stiffness-orthogonal to each other and to the kept
    DOFs' static shapes, whose block is the static condensation on the kept DOFs."""
    n_p, n_modes = len(p), len(lam)
    k = reduced.stiffness
    out = np.zeros((n_p + n_modes + len(others),) * 2)
    cond = k[np.ix_(p, p)] + k[np.ix_(p, r)] @ g
    cond = 0.5 * (cond + cond.T)
    out[:n_p, :n_p] = cond if reduced.indefinite_stiffness else _semidefinite(cond)
    out[range(n_p, n_p + n_modes), range(n_p, n_p + n_modes)] = lam
    out[n_p + n_modes:, n_p + n_modes:] = k[np.ix_(others, others)]
    return out


def _semidefinite(a: np.ndarray) -> np.ndarray:
    """A static condensation ``a`` of a positive semi-definite stiffness with the rounding of its
    rigid-body modes (eigenvalues of either sign, ``eps`` times the stiffness's scale: the blade
    free but for its boundary) set to zero; a larger negative eigenvalue is left for the
    structure's own check to refuse."""
    if not a.size:
        return a
    lam, v = np.linalg.eigh(a)
    small = np.abs(lam) <= 1e-10 * np.max(np.abs(lam))
    if not np.any(small & (lam < 0)):
        return a
    lam = np.where(small, 0.0, lam)
    out = (v * lam) @ v.T
    return 0.5 * (out + out.T)
