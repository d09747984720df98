"""Dovetail flanks as contact patches: many nodes per flank, each sticking, slipping and lifting off
on its own.

A :class:`FlankPatch` is one flank's node set: per node the two structure DOFs of its displacement
in the root coordinates ``(X, Y)`` (``X`` across the root, ``Y`` radial, outward) and its contact
stiffnesses. A :class:`PatchDovetailRoot` puts two patches on the flanks of a dovetail of flank
angle ``gamma`` and gives every node the point model's flank law
(:mod:`~frictionjoint.elements.dovetail`: its normal ``n`` and tangent ``t``, sign convention and
force ``N n - T t`` on the blade), node by node:

* a normal spring ``kn_i`` along the flank normal: ``N_i = N0_i - kn_i n . u_i``, ``u_i`` the
  node's displacement from the static state; bilateral with a frozen slip limit, or, with
  ``normal_load_variation=True``, unilateral, ``N_i = kn_i max(N0_i/kn_i - n . u_i, 0)``: the node
  lifts off where ``N_i`` reaches 0 and closes again (stuck, unstressed) where it comes back;
* a Jenkins slider along the flank's slip direction ``t``: the node's tangential stiffness
  ``kt_i`` in series with a Coulomb slider of strength ``mu N0_i`` (frozen) or ``mu N_i``
  (varying), preloaded with the node's static friction force ``T0_i``;
* an optional normal dashpot, on only while the node is closed.

These are the marcher's own primitives (:class:`~frictionjoint.elements.base.Slider` and
:class:`~frictionjoint.elements.base.Contact`), the ones
:class:`~frictionjoint.elements.dovetail.DovetailRoot` gives its two flanks; the march stays exact.

Static state. The node loads ``N0_i``, ``T0_i`` come from the spun-up static contact problem of
the model: the structure's stiffness ``K`` and the nodes' springs under the centrifugal load
``f``, raised proportionally from zero. Each node sticks throughout the run-up (``T_i = kt_i t .
u_i``, ``|T_i| <= mu N_i``), slips throughout in one direction (``T_i = +-mu N_i``, its slip in
the direction of its force) or is open throughout (pulled away from the disc): the problem with
such a set of statuses is linear and homogeneous, so its solution at the full load, scaled, is the
whole run-up. The set is found by an active-set iteration from all stuck (a node over its limit
starts to slip, a node slipping against its force sticks, a node pulled opens, an open node
pressed closes) and checked at the end; where the friction couples the nodes strongly (a slip that
loads its neighbours normally) more than one such set may exist, and this is the one the iteration
reaches. Nodes open at the static state (:attr:`PatchStatic.separated`) are refused by
:meth:`PatchDovetailRoot.attach`: leave them out of the patch (the others' static state is the
same; a node that could close again in the dynamics is not modelled). Refused, with a message
saying which: a run-up with no proportional solution (a set that changes with the load) and a
structure the patches do not hold (singular stiffness). On a rigid flank (all nodes of a flank on
the same root DOFs) with uniform stiffness the node loads are the point model's flank loads ``N0``,
``T0`` (:class:`~frictionjoint.elements.dovetail.DovetailStatic`, stuck or slipping) shared
equally.

The structure's coordinates are measured from the static state ``x0``: the attachment's constant
force ``f - K x0 + sum_i N0_i n_i`` balances the preloaded sliders' ``-T0_i t_i`` at ``x = 0``.
Unlike the point model, whose statics leave the structure unloaded, ``K x0`` is the structure's
own share of the load (zero for a free root block or blade moved rigidly).
"""
from __future__ import annotations

from dataclasses import dataclass
import math
from typing import Any, Mapping, Sequence
import warnings

import numpy as np
from numpy.typing import ArrayLike
import scipy.linalg
import scipy.sparse
import scipy.sparse.linalg

from ..errors import ParameterError, check_bool, check_positive, check_real
from ..structure import LinearStructure
from .base import Attachment, Contact, Slider
from .dovetail import flank_directions

__all__ = ["FlankPatch", "PatchDovetailRoot", "PatchStatic"]

#: stick/slip sets the static state's active-set iteration tries at most (each one linear solve)
MAX_STATIC_ITERATIONS = 50

#: a node's status in the static state's iteration: open (0 stuck, +1/-1 slipping)
_OPEN = 2

#: relative size of a slip against its force that still counts as none in the static state's
#: check (a node exactly at its limit is stuck and slipping alike; rounding picks either)
_SLIP_ROUNDING = 1e-12


def _per_node(name: str, value, n: int, positive: bool) -> np.ndarray:
    """``value`` (a number or one per node) as an (n,) float array, > 0 or >= 0."""
    a = np.asarray(value, dtype=float)
    if a.ndim == 0:
        a = np.full(n, float(a))
    if a.shape != (n,) or not np.all(np.isfinite(a)) or np.any(a <= 0 if positive else a < 0):
        sign = "> 0" if positive else ">= 0"
        raise ParameterError(f"{name} must be a finite number {sign} or one per node ({n}), got {value!r}")
    return a


class FlankPatch:
    """One flank's contact patch: its nodes and their contact stiffnesses.

    Parameters
    ----------
    nodes : sequence of (dof, dof) pairs
        Per node, the structure DOFs (names or indices) of its displacement along the root's ``X``
        (across the root) and ``Y`` (radial, outward), in that order. Nodes may share DOFs (a rigid
        flank: all nodes on the root's DOFs).
    normal_stiffness : float or (n_nodes,) array_like
        Normal contact stiffness ``kn_i`` of each node [N/m], > 0.
    tangential_stiffness : float or (n_nodes,) array_like
        Tangential stiffness ``kt_i`` of each node [N/m], > 0, in series with its slider.
    normal_damping : float or (n_nodes,) array_like
        Normal dashpot of each node [N s/m], >= 0, on while the node is closed.

    Attributes
    ----------
    nodes : tuple of (dof, dof)
    normal_stiffness, tangential_stiffness, normal_damping : (n_nodes,) ndarray
    """

    def __init__(self, nodes: Sequence[tuple[str | int, str | int]], normal_stiffness: float | ArrayLike,
                 tangential_stiffness: float | ArrayLike, normal_damping: float | ArrayLike = 0.0):
        try:
            nodes = tuple((a, b) for a, b in nodes)
        except (TypeError, ValueError):
            raise ParameterError(f"nodes must be a sequence of (X dof, Y dof) pairs, got {nodes!r}") from None
        if not nodes:
            raise ParameterError("nodes must name at least one node (an (X dof, Y dof) pair)")
        self.nodes = nodes
        n = len(nodes)
        self.normal_stiffness = _per_node("normal_stiffness", normal_stiffness, n, True)
        self.tangential_stiffness = _per_node("tangential_stiffness", tangential_stiffness, n, True)
        self.normal_damping = _per_node("normal_damping", normal_damping, n, False)

    @property
    def n_nodes(self) -> int:
        """Number of nodes of the patch."""
        return len(self.nodes)

    def __repr__(self) -> str:
        return (f"FlankPatch({self.n_nodes} nodes, normal_stiffness={self.normal_stiffness.sum():g} N/m, "
                f"tangential_stiffness={self.tangential_stiffness.sum():g} N/m in all)")


@dataclass(frozen=True)
class PatchStatic:
    """Static (spun-up) state of a patch root, node by node (right flank's nodes first).

    Attributes
    ----------
    normal_force : (n_nodes,) ndarray
        ``N0_i`` [N], > 0 (0 where the node is open).
    friction_force : (n_nodes,) ndarray
        ``T0_i`` [N], positive radially inward on the blade (restoring the node's outward slip).
    slipping : (n_nodes,) bool ndarray
        Nodes that slip during the run-up (``|T0_i| = mu N0_i``); the others stick throughout.
    displacement : (n_dof,) ndarray
        Static displacement ``x0`` of the structure [m] from its unloaded state.
    flank : (n_nodes,) int ndarray
        0 for a node of the right flank, 1 for the left.
    regime : str
        ``'stuck'`` (every closed node sticks during run-up), ``'slipping'`` (every closed node
        slips) or ``'partial slip'``.
    separated : (n_nodes,) bool ndarray
        Nodes that open under the centrifugal load (no contact force, ``N0_i = T0_i = 0``).
        :meth:`PatchDovetailRoot.attach` refuses them: leave them out of the patch.
    """

    normal_force: np.ndarray
    friction_force: np.ndarray
    slipping: np.ndarray
    displacement: np.ndarray
    flank: np.ndarray
    regime: str
    separated: np.ndarray

    @property
    def flank_normal_force(self) -> np.ndarray:
        """Normal force of each flank, (2,) [N]: right, left (the point model's ``N0`` each)."""
        return np.bincount(self.flank, self.normal_force, minlength=2)

    @property
    def flank_friction_force(self) -> np.ndarray:
        """Friction force of each flank, (2,) [N]: right, left (the point model's ``T0`` each)."""
        return np.bincount(self.flank, self.friction_force, minlength=2)


class PatchDovetailRoot:
    """Dovetail root whose flanks are contact patches (module docstring).

    Parameters
    ----------
    right, left : FlankPatch
        The node sets of the right (``X > 0``) and left flanks.
    flank_angle : float
        ``gamma`` [rad] in ``[0, pi/2)``: angle between each flank's normal and the radial axis.
    friction_coefficient : float
        ``mu`` [-], > 0, of every node.
    centrifugal_load : mapping of dof to float, or (n_dof,) array_like
        The spun-up load on the structure [N]: ``{dof: force}`` (e.g. ``{"Y": Fc}`` on a root
        block) or a vector over the structure's DOFs (e.g. a blade's body forces).
    normal_load_variation : bool
        If true, each node's slip limit follows its own normal load, with lift-off; otherwise the
        slip limits are the static ``mu N0_i`` and the normal springs bilateral.
    """

    def __init__(self, right: FlankPatch, left: FlankPatch, flank_angle: float, friction_coefficient: float,
                 centrifugal_load: Mapping[str | int, float] | ArrayLike, normal_load_variation: bool = False):
        self._args = dict(right=right, left=left, flank_angle=flank_angle,
                          friction_coefficient=friction_coefficient, centrifugal_load=centrifugal_load,
                          normal_load_variation=normal_load_variation)
        for name, p in (("right", right), ("left", left)):
            if not isinstance(p, FlankPatch):
                raise ParameterError(f"{name} must be a FlankPatch, got {type(p).__name__}")
        self.right, self.left = right, left
        g = check_real("flank_angle", flank_angle)
        if not 0.0 <= g < 0.5 * math.pi:
            raise ParameterError(f"flank_angle must be in [0, pi/2) rad, got {flank_angle!r}")
        self.flank_angle = g
        self.friction_coefficient = check_positive("friction_coefficient", friction_coefficient)
        self.normal_load_variation = check_bool("normal_load_variation", normal_load_variation)
        if isinstance(centrifugal_load, Mapping):
            self.centrifugal_load = {k: check_real(f"centrifugal_load[{k!r}]", v)
                                     for k, v in centrifugal_load.items()}
        else:
            a = np.asarray(centrifugal_load, dtype=float)
            if a.ndim != 1 or not np.all(np.isfinite(a)):
                raise ParameterError("centrifugal_load must be {dof: force} or a finite vector over the "
                                     f"structure's DOFs [N], got {centrifugal_load!r}")
            self.centrifugal_load = a
        #: flank normals (force directions on the blade) and tangents, rows right/left, (X, Y)
        self.normals, self.tangents = flank_directions(g)
        patches = (right, left)
        #: per node (right flank first): its flank, 0 or 1, and its contact parameters
        self.flank = np.repeat([0, 1], [p.n_nodes for p in patches])
        self.nodes = right.nodes + left.nodes
        self.normal_stiffness = np.concatenate([p.normal_stiffness for p in patches])
        self.tangential_stiffness = np.concatenate([p.tangential_stiffness for p in patches])
        self.normal_damping = np.concatenate([p.normal_damping for p in patches])

    @property
    def n_nodes(self) -> int:
        """Number of nodes on both flanks."""
        return len(self.nodes)

    def replace(self, **changes: Any) -> PatchDovetailRoot:
        """The same root with some constructor arguments changed (e.g. ``centrifugal_load``,
        ``friction_coefficient``).

        Parameters
        ----------
        **changes
            Constructor arguments, by keyword.

        Returns
        -------
        PatchDovetailRoot
        """
        unknown = set(changes) - set(self._args)
        if unknown:
            raise ParameterError(f"not PatchDovetailRoot arguments: {sorted(unknown)} (allowed: {sorted(self._args)})")
        return PatchDovetailRoot(**{**self._args, **changes})

    # ------------------------------------------------------------ geometry
    def _node_rows(self, structure) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(index, normal, tangent)``: each node's two DOF indices (n_nodes, 2) and its flank's
        normal and tangent (n_nodes, 2) over them."""
        index = np.array([[_dof_index(structure, d) for d in node] for node in self.nodes], dtype=np.intp)
        same = np.flatnonzero(index[:, 0] == index[:, 1])
        if same.size:
            raise ParameterError(f"node {self.nodes[same[0]]!r}: its X and Y displacements must be two "
                                 "different DOFs")
        return index, self.normals[self.flank], self.tangents[self.flank]

    def _rows(self, structure, index, vectors) -> np.ndarray:
        """(n_nodes, n_dof) rows over the structure's DOFs of per-node (X, Y) ``vectors``."""
        rows = np.zeros((self.n_nodes, _n_dof(structure)))
        nodes = np.arange(self.n_nodes)
        rows[nodes, index[:, 0]] = vectors[:, 0]
        rows[nodes, index[:, 1]] = vectors[:, 1]
        return rows

    def _load(self, structure) -> np.ndarray:
        n = _n_dof(structure)
        if isinstance(self.centrifugal_load, dict):
            f = np.zeros(n)
            for dof, value in self.centrifugal_load.items():
                f[_dof_index(structure, dof)] += value
            return f
        if self.centrifugal_load.shape != (n,):
            raise ParameterError(f"centrifugal_load has {self.centrifugal_load.size} entries; the structure has "
                                 f"{n} DOFs")
        return self.centrifugal_load.copy()

    # ------------------------------------------------------------ statics
    def static_state(self, structure: Any) -> PatchStatic:
        """The spun-up static contact solution of the structure on the patches (module docstring).

        Parameters
        ----------
        structure : LinearStructure or FEModel
            Any structure with ``stiffness`` (dense or ``scipy.sparse``, [N/m]) and ``dof_names``.

        Returns
        -------
        PatchStatic
        """
        index, normal, tangent = self._node_rows(structure)
        f = self._load(structure)
        kn, kt, mu = self.normal_stiffness, self.tangential_stiffness, self.friction_coefficient
        status = np.zeros(self.n_nodes, dtype=np.int8)  # 0 stuck, +1/-1 slipping (T = +-mu N), 2 open
        seen = set()
        while status.tobytes() not in seen and len(seen) <= MAX_STATIC_ITERATIONS:
            seen.add(status.tobytes())
            x = self._solve_static(structure, index, normal, tangent, status, f)
            u = x[index]  # (n_nodes, 2): each node's (X, Y) displacement
            approach = -np.einsum("ij,ij->i", normal, u)
            s = np.einsum("ij,ij->i", tangent, u)
            closed, slipping = status != _OPEN, np.abs(status) == 1
            n0 = np.where(closed, kn * approach, 0.0)
            t0 = np.where(status == 0, kt * s, np.where(slipping, status * mu * n0, 0.0))
            w = s - t0 / kt  # each node's slip during run-up (0 where it sticks)
            new = status.copy()
            over = (status == 0) & (np.abs(t0) > mu * n0)
            new[over] = np.sign(t0[over])
            new[slipping & (status * w < -_SLIP_ROUNDING * np.abs(s))] = 0  # slips against its force
            new[closed & (n0 <= 0.0)] = _OPEN  # pulled: it opens
            new[~closed & (approach > 0.0)] = 0  # pressed: it closes
            if np.array_equal(new, status):
                return PatchStatic(n0, t0, slipping, x, self.flank.copy(), _regime(status), ~closed)
            status = new
        raise ParameterError(
            f"no proportional run-up found in {len(seen)} stick/slip sets (the nodes' stick/slip set may change "
            "with the centrifugal load): every node sticking, slipping or open throughout the run-up is what is "
            "handled")

    def _solve_static(self, structure, index, normal, tangent, status, f) -> np.ndarray:
        """Displacement of the structure on its patches under ``f`` with the nodes' ``status``:
        stuck nodes ``kn n n^T + kt t t^T``, slipping ones ``kn n n^T - sig mu kn t n^T`` (the
        friction ``sig mu N`` follows the normal approach), open ones nothing."""
        kn, kt, mu = self.normal_stiffness, self.tangential_stiffness, self.friction_coefficient
        slip = np.where(status == _OPEN, 0, status)
        blocks = (kn[:, None, None] * normal[:, :, None] * normal[:, None, :]
                  + np.where(slip[:, None, None] == 0, kt[:, None, None] * tangent[:, :, None] * tangent[:, None, :],
                             -(slip * mu * kn)[:, None, None] * tangent[:, :, None] * normal[:, None, :]))
        blocks[status == _OPEN] = 0.0
        rows = np.repeat(index, 2, axis=1)  # block entry (a, b) at (index[a], index[b])
        cols = np.tile(index, (1, 2))
        k = structure.stiffness
        n = _n_dof(structure)
        contact = scipy.sparse.coo_array((blocks.reshape(-1, 4).ravel(), (rows.ravel(), cols.ravel())),
                                         shape=(n, n))
        what = ("the structure's stiffness with the patches' springs is singular: the patches do not hold "
                "every rigid-body motion of the structure (a free DOF no node and no support restrains?)")
        try:
            if scipy.sparse.issparse(k):
                x = scipy.sparse.linalg.splu(scipy.sparse.csc_array(k + contact)).solve(f)
            else:
                with warnings.catch_warnings():
                    warnings.simplefilter("error", scipy.linalg.LinAlgWarning)
                    x = scipy.linalg.solve(np.asarray(k) + contact.toarray(), f)
        except (RuntimeError, np.linalg.LinAlgError, scipy.linalg.LinAlgWarning):
            raise ParameterError(what) from None
        if not np.all(np.isfinite(x)):
            raise ParameterError(what)
        return x

    # ------------------------------------------------------------ attachment
    def attach(self, structure: Any) -> Attachment:
        """Per node a slider along its flank's tangent and a normal spring (a contact with
        ``normal_load_variation``), preloaded from :meth:`static_state`; coordinates measured from
        the static state.

        Parameters
        ----------
        structure : LinearStructure
            Structure holding every node's DOFs.

        Returns
        -------
        Attachment
            One slider per node (right flank's nodes first) with its static preload ``T0_i`` [N],
            the normal springs' stiffness and dashpots, the constant force ``f - K x0 + sum_i N0_i
            n_i`` [N] and, with normal-load variation, one contact per node.
        """
        st = self.static_state(structure)
        if st.separated.any():
            names = [self.nodes[i] for i in np.flatnonzero(st.separated)]
            raise ParameterError(
                f"nodes {names} open under the centrifugal load (static_state(...).separated): leave them out of "
                "the patch (the static state of the others is the same); nodes that separate during run-up and "
                "may close in the dynamics are not handled")
        index, normal, tangent = self._node_rows(structure)
        rn = self._rows(structure, index, normal)
        rt = self._rows(structure, index, tangent)
        kn, c = self.normal_stiffness, self.normal_damping
        mu = self.friction_coefficient
        force = self._load(structure) - np.asarray(structure.stiffness @ st.displacement) + st.normal_force @ rn
        sliders = [Slider(mu * n0, k) for n0, k in zip(st.normal_force, self.tangential_stiffness)]
        contacts, slider_contact = (), None
        if self.normal_load_variation:
            contacts = tuple(Contact(rn[i], kn[i], c[i], st.normal_force[i], mu) for i in range(self.n_nodes))
            slider_contact = list(range(self.n_nodes))
        return Attachment(rt, sliders, st.friction_force.copy(), (rn.T * kn) @ rn, force,
                          (rn.T * c) @ rn if np.any(c > 0) else None, contacts, slider_contact)

    def __repr__(self) -> str:
        return (f"PatchDovetailRoot({self.right.n_nodes} + {self.left.n_nodes} nodes, flank_angle="
                f"{self.flank_angle:g}, friction_coefficient={self.friction_coefficient:g})")


def _regime(status: np.ndarray) -> str:
    """``'stuck'``, ``'slipping'`` or ``'partial slip'``: the closed nodes' run-up."""
    slipping = np.abs(status[status != _OPEN]) == 1
    return "slipping" if slipping.size and slipping.all() else "partial slip" if slipping.any() else "stuck"


def _n_dof(structure) -> int:
    return int(structure.stiffness.shape[0])


def _dof_index(structure, dof) -> int:
    """Index of ``dof`` (name or index) among the structure's DOFs."""
    if isinstance(structure, LinearStructure):
        return structure.dof_index(dof)
    names = tuple(structure.dof_names)
    if isinstance(dof, str):
        if dof not in names:
            raise ParameterError(f"dof {dof!r} is not a DOF of the structure ({len(names)} DOFs)")
        return names.index(dof)
    if isinstance(dof, (bool, np.bool_)) or not isinstance(dof, (int, np.integer)) or not 0 <= dof < len(names):
        raise ParameterError(f"dof must be a DOF name or an index in [0, {len(names) - 1}], got {dof!r}")
    return int(dof)
