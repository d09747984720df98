"""A solid blade on its dovetail: the root face's two long edges on the slot's flanks, as contact
patches (issue 30, part 5).

Geometry (:class:`~frictionjoint.structures.SolidBlade`'s frame). The root face ``x = 0`` is the
bottom of the blade's root; the slot holds it on two flanks, one along each of its long edges,
``z = +h/2`` (the right flank) and ``z = -h/2`` (the left), inclined at the flank angle ``gamma``:
the dovetail is the point model's (:class:`~frictionjoint.elements.DovetailRoot`) with its ``X``
along ``z`` (across the root: the blade's flapwise direction, BeamBlade's ``w``) and its ``Y``
along ``x`` (radial, outward). Each edge node is a node of a
:class:`~frictionjoint.elements.FlankPatch`: its ``(X, Y)`` DOFs are its ``u3`` and ``u1``. The
slot holds the root face along the chord (``y``): every root-face node's ``u2`` is clamped (the
patches carry no chordwise friction). The edge between them (the face's middle row of nodes) is
free: the root rocks on its flanks with the lever arm ``h / 2``, as the point model's rocking root
does with its ``flank_half_width``.

Per flank the definition gives totals, as for the point model: the normal and tangential contact
stiffness [N/m] and the normal dashpot [N s/m]. They are spread over the edge's nodes with the
weights of a uniform line load on its quadratic element edges, ``(1, 4, 1) / 6`` of each edge
(Simpson's rule, ``1, 4, 2, 4, ..., 4, 1``): a uniform pressure on the flank. The static node
loads are the spun-up contact solution of the blade under its centrifugal body forces
(:meth:`~frictionjoint.elements.PatchDovetailRoot.static_state`), not equal shares.

The blade is reduced by Craig-Bampton (sparse) to the flank nodes' ``(X, Y)`` DOFs (the root face's
``u2`` in the boundary, then clamped: the reduction of the clamped blade), ``n_modes``
fixed-interface modes and the residual vector of the excitation DOF. Its static solution on the
boundary is exact under the body forces (the reduced load is ``T^T f``; the constraint modes are
the interior's static response, the fixed-interface modes decouple statically), so the reduced
model's static contact state is the full model's.

:class:`SolidBladeRoot` is the joint that :meth:`BladeAssembly.from_model
<frictionjoint.structures.BladeAssembly.from_model>` puts on a solid blade: a
:class:`~frictionjoint.elements.PatchDovetailRoot` with the point model's parameter names (flank
totals), so that ``with_root``, sweeps and studies change it as they change a ``DovetailRoot``.
"""
from __future__ import annotations

from typing import Any, Sequence

import numpy as np

from ..elements.patch import FlankPatch, PatchDovetailRoot
from ..errors import ParameterError, check_bool, check_nonnegative, check_positive, check_real
from .reduction import craig_bampton

__all__ = ["SolidBladeRoot", "flank_edges", "edge_weights", "solid_blade_on_patches", "TIP_POINTS"]

#: where on the tip face a solid blade's excitation acts: the centre, the leading edge (``y =
#: +b/2``) or the trailing edge (``y = -b/2``), each on the face's middle line ``z = 0``
TIP_POINTS = ("centre", "leading_edge", "trailing_edge")


def flank_edges(blade) -> tuple[np.ndarray, np.ndarray]:
    """The root face's long edges: node rows (0-based) at ``z = +h/2`` (right flank) and ``z = -h/2``
    (left flank), each sorted along the chord (``y`` ascending).

    Parameters
    ----------
    blade : SolidBlade

    Returns
    -------
    right, left : (n,) ndarray of int
    """
    root = blade._sets["root"]
    p = blade.nodes[root]
    h = blade.thickness
    edges = []
    for side in (1.0, -1.0):
        on = root[np.abs(p[:, 2] - side * 0.5 * h) <= 1e-9 * h]
        edges.append(on[np.argsort(blade.nodes[on, 1])])
    return edges[0], edges[1]


def edge_weights(n: int) -> np.ndarray:
    """Weights, summing to 1, of a uniform line load on ``n`` nodes of quadratic element edges
    (``n`` odd): Simpson's ``1, 4, 2, 4, ..., 4, 1``."""
    if n < 3 or n % 2 == 0:
        raise ParameterError(f"a flank edge of quadratic elements has an odd number >= 3 of nodes, got {n}")
    w = np.full(n, 2.0)
    w[1::2] = 4.0
    w[[0, -1]] = 1.0
    return w / w.sum()


class SolidBladeRoot:
    """The dovetail root of a solid blade on contact patches (module docstring), with the point
    model's parameter names.

    Parameters
    ----------
    right, left : sequence of (X dof, Y dof)
        The flank nodes' DOFs (names), along the chord.
    weights_right, weights_left : (n,) array_like
        Each node's share of its flank's stiffness and damping, summing to 1.
    load : (n_dof,) array_like
        The blade's centrifugal load on the DOFs of the structure it is attached to [N].
    blade_centrifugal_force : float
        The load's resultant along the radial axis [N], > 0 (``centrifugal_force``'s reference).
    flank_angle : float
        ``gamma`` [rad] in ``[0, pi/2)``.
    friction_coefficient : float
        ``mu`` [-], > 0.
    normal_stiffness, tangential_stiffness : float
        Per flank [N/m], > 0.
    normal_damping : float
        Per flank [N s/m], >= 0.
    normal_load_variation : bool
        Each node's slip limit follows its normal load, with lift-off.
    centrifugal_force : float
        The root's radial load [N], >= 0: the blade's load scaled to it; 0 (default): the blade's own.
    """

    def __init__(self, right: Sequence, left: Sequence, weights_right, weights_left, load, blade_centrifugal_force: float,
                 flank_angle: float, friction_coefficient: float, normal_stiffness: float,
                 tangential_stiffness: float, normal_damping: float = 0.0, normal_load_variation: bool = False,
                 centrifugal_force: float = 0.0) -> None:
        self._args = dict(right=right, left=left, weights_right=weights_right, weights_left=weights_left, load=load,
                          blade_centrifugal_force=blade_centrifugal_force, flank_angle=flank_angle,
                          friction_coefficient=friction_coefficient, normal_stiffness=normal_stiffness,
                          tangential_stiffness=tangential_stiffness, normal_damping=normal_damping,
                          normal_load_variation=normal_load_variation, centrifugal_force=centrifugal_force)
        kn = check_positive("normal_stiffness", normal_stiffness)
        kt = check_positive("tangential_stiffness", tangential_stiffness)
        cn = check_nonnegative("normal_damping", normal_damping)
        fc = check_nonnegative("centrifugal_force", check_real("centrifugal_force", centrifugal_force))
        reference = check_positive("blade_centrifugal_force", blade_centrifugal_force)
        scale = 1.0 if fc == 0.0 else fc / reference
        patches = [FlankPatch(nodes, kn * np.asarray(w, float), kt * np.asarray(w, float), cn * np.asarray(w, float))
                   for nodes, w in ((right, weights_right), (left, weights_left))]
        self.centrifugal_force = reference * scale
        self.patch_root = PatchDovetailRoot(*patches, flank_angle, friction_coefficient,
                                            scale * np.asarray(load, dtype=float),
                                            normal_load_variation=check_bool("normal_load_variation",
                                                                             normal_load_variation))

    def replace(self, **changes: Any) -> SolidBladeRoot:
        """The same root with some parameters changed (e.g. ``friction_coefficient``,
        ``centrifugal_force`` [N], ``normal_stiffness`` per flank [N/m]).

        Parameters
        ----------
        **changes
            Constructor arguments, by keyword.

        Returns
        -------
        SolidBladeRoot
        """
        unknown = set(changes) - set(self._args)
        if unknown:
            raise ParameterError(f"not SolidBladeRoot arguments: {sorted(unknown)} (allowed: {sorted(self._args)})")
        return SolidBladeRoot(**{**self._args, **changes})

    def __getattr__(self, name: str):
        # the patch root's attributes and methods (nodes, flank, static_state, ...)
        if name.startswith("_") or name == "patch_root":
            raise AttributeError(name)
        return getattr(self.patch_root, name)

    def attach(self, structure: Any):
        """:meth:`PatchDovetailRoot.attach <frictionjoint.elements.PatchDovetailRoot.attach>`."""
        return self.patch_root.attach(structure)

    def __repr__(self) -> str:
        r = self.patch_root
        return (f"SolidBladeRoot({r.right.n_nodes} + {r.left.n_nodes} nodes, flank_angle={r.flank_angle:g}, "
                f"friction_coefficient={r.friction_coefficient:g}, centrifugal_force={self.centrifugal_force:g} N)")


def solid_blade_on_patches(blade, root: dict, n_modes: int, tip_point: str = "centre"):
    """A solid blade reduced on its root's flank nodes with its :class:`SolidBladeRoot` (module
    docstring).

    Parameters
    ----------
    blade : SolidBlade
        Rotating (the root is loaded by the centrifugal body forces).
    root : dict
        ``flank_angle``, ``friction_coefficient``, ``normal_stiffness``, ``tangential_stiffness``,
        optionally ``normal_damping`` (per flank), ``normal_load_variation``.
    n_modes : int
        Fixed-interface modes kept, >= 0.
    tip_point : str
        One of :data:`TIP_POINTS`: the excitation's DOF is this tip node's ``u3`` (flapwise).

    Returns
    -------
    reduced : LinearStructure
        Craig-Bampton, with ``transformation`` to the blade's DOFs.
    joint : SolidBladeRoot
    tip : str
        The excitation DOF's name.
    """
    from .fe_import import dof_name

    if not blade.rotor_speed > 0:
        raise ParameterError("the model's rotor_speed must be > 0 (the dovetail is loaded by the centrifugal force)")
    if "flank_half_width" in root:
        raise ParameterError("[root] flank_half_width: a solid blade's root rocks on its face's edges (lever "
                             "thickness / 2); leave it out")
    if tip_point not in TIP_POINTS:
        raise ParameterError(f"tip_point must be one of {TIP_POINTS}, got {tip_point!r}")
    right, left = flank_edges(blade)
    nodes = [[(dof_name(i + 1, 3), dof_name(i + 1, 1)) for i in edge] for edge in (right, left)]
    held = [dof_name(i + 1, 2) for i in blade._sets["root"]]
    tip = blade._sets["tip"]
    grid = blade._reference_grid(blade.nodes[tip].T)  # before taper and twist: the tip face's own (y, z)
    mid = tip[grid[2] == 0]  # its middle line through the thickness
    y = grid[1][grid[2] == 0]
    k = {"centre": np.argmin(np.abs(y)), "leading_edge": np.argmax(y), "trailing_edge": np.argmin(y)}[tip_point]
    tip_dof = dof_name(int(mid[k]) + 1, 3)
    boundary = [d for node in nodes[0] + nodes[1] for d in node] + held
    reduced = craig_bampton(blade, boundary, n_modes, loaded_dofs=[tip_dof]).clamped(held)
    load = reduced.transformation.T @ blade.centrifugal_load
    joint = SolidBladeRoot(nodes[0], nodes[1], edge_weights(right.size), edge_weights(left.size), load,
                           float(blade.centrifugal_load[0::3].sum()), **root)
    return reduced, joint, tip_dof
