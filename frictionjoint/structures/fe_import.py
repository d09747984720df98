"""Structures from the matrices a finite-element code exports, kept sparse (issue 30, part 1).

:func:`read_fe_model` reads a mass, a stiffness and optionally a damping matrix, the DOF table
(node id, direction 1..6) and named node sets (contact surfaces, excitation and response points)
into an :class:`FEModel`, whose matrices are ``scipy.sparse`` CSR arrays from the file to the
model. Formats (``format=``, else from the file's suffix):

``"matrix_market"`` (``.mtx`` with a ``%%MatrixMarket`` first line)
    ``scipy.io.mmread``; general or symmetric storage.
``"harwell_boeing"`` (``.rb``, ``.rua``, ``.rsa``, ``.hb``, ``.matrix``: ANSYS ``HBMAT``)
    ``scipy.io.hb_read``; a symmetric file (type ``RSA``, one triangle stored) is read as the
    unsymmetric type with the same layout and mirrored.
``"nastran_dmig"`` (``.pch``, ``.bdf``, ``.dat``, ``.blk``, ``.dmig``)
    DMIG bulk data entries, small, large (``*``) and free (comma) field, the header entry first;
    real square (IFO 1) or symmetric (IFO 6) matrices of grid points (components 1..6). Read
    here: pyNastran (1.4.1) requires numpy < 2, and pyyeti's ``rddmig`` builds a dense table
    (20 GB for 50,000 DOFs). The file carries the DOF table: the union of the DOFs the chosen
    matrices name, ordered by node then component. Other entries are skipped.
``"nastran_op4"`` (``.op4``)
    OUTPUT4 files, ASCII or binary, dense or sparse, through pyyeti (``pip install pyyeti``),
    which reads sparse OP4 matrices sparse.
``"abaqus_matrix_input"`` (``.mtx`` without a Matrix Market header)
    Abaqus ``*MATRIX OUTPUT, FORMAT=MATRIX INPUT`` (its default): a line ``row node, row DOF,
    column node, column DOF, value`` per entry, one triangle or both. The file carries the DOF
    table, ordered as for DMIG.

A matrix argument is a path, or ``(path, name)`` for a DMIG or OP4 file that holds several
matrices (a file holding one needs no name). The DOF table of the formats that carry none is a
CSV sidecar (or an ``(n_dof, 2)`` array)::

    node,direction        # header; then one row per matrix row, in the matrix's order
    101,1
    101,2

and the node sets a CSV sidecar (or a dict ``name -> node ids``)::

    set,node              # header; a set is the nodes of its rows, in their order
    flank_left,101

Directions 1, 2, 3 are the translations along x, y, z and 4, 5, 6 the rotations about them
(NASTRAN's components, Abaqus's DOFs 1..6); DOF names are ``n<node>_u<d>`` for translations and
``n<node>_r<d>`` for rotations (``n101_u1``, ``n7_r3``).

Checks, each a one-line :class:`~frictionjoint.errors.ParameterError` that names the file:

* sizes: every matrix square, of the DOF table's length; the DOF table's pairs distinct,
  directions in 1..6; every node of a node set in the DOF table.
* symmetry: ``|a_ij - a_ji| <= 1e-8 sqrt(|a_ii a_jj|)`` for every entry. The scale is the
  entry's own rows' (an FE model mixes translations [m] and rotations [rad], whose entries differ
  by many orders: a bound on the largest entry would not see a wrong rotational block). A
  symmetric code writes ``a_ij`` and ``a_ji`` from the same number or from sums that differ in
  the last bits (about 1e-15 of the scale), so any writer that prints 9 or more digits keeps
  them within 1e-8; an unsymmetric matrix (a transposed or missing triangle, a follower-load or
  gyroscopic term) is off by order one.
* mass positive definite: every diagonal entry > 0, then the pivots of ``L D L^T`` of the
  diagonally scaled mass (unit diagonal), from SuperLU (``scipy.sparse.linalg.splu`` in
  symmetric mode with diagonal pivots, no column ordering) after a reverse Cuthill-McKee
  ordering (``scipy.sparse.csgraph``): by Sylvester's law of inertia the mass is positive
  definite if and only if every pivot is > 0; a pivot below 1e-13 (of the unit diagonal) means
  the mass is singular to rounding and is rejected too. A slender body (a blade) has a narrow band
  in that order: on the 50,000-DOF lattice of ``docs/fe-models.md`` with a solid mesh's
  pattern it took 2.6-3.8 s (SuperLU's own minimum-degree ordering 15 s); the smallest
  eigenvalue by ``eigsh(which="SA")`` took 2.6 s on the lattice's mass and 106 s with that
  pattern (and shift-invert needs the factorisation anyway). No sparse Cholesky is in scipy.
* stiffness: every diagonal entry >= 0 (its definiteness is checked where the dense
  :class:`~frictionjoint.LinearStructure` is made, :meth:`FEModel.to_structure`).
* files that end early (cut short by a full disk or an interrupted copy) are refused, each by
  what its format declares: a Matrix Market file's entry count (``scipy.io.mmread`` counts the
  entries it reads against its header), a Harwell-Boeing file's line counts (``TOTCRD``, checked
  here), an OP4 file's matrix sizes (pyyeti). DMIG and Abaqus files declare no size (a DMIG
  header gives ``NCOL`` for rectangular matrices only): their DOF table is the union of the DOFs
  they name, and every one of those DOFs must have a diagonal entry in the mass and in the
  stiffness, which a file cut before its last columns (or rows) lacks; a DOF without stiffness is
  written as an explicit ``0.0``. A text file must end with a newline: a file cut inside its last
  line would otherwise read a shortened number (``0.5`` as ``0.``).
* sizes before anything is allocated: a Matrix Market or Harwell-Boeing header's size against the
  DOF table, and its declared entries against what the file's bytes can hold; node ids in
  1..2**31 - 1; an empty or non-text file (random bytes) is refused by name.
"""
from __future__ import annotations

import csv
import io
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Mapping, Sequence

import numpy as np
import scipy.sparse as sp

from ..errors import ParameterError, check_bool, check_count
from ..structure import LinearStructure

__all__ = ["FEModel", "read_fe_model", "read_dof_table", "read_node_sets", "FE_FORMATS", "dof_name"]

#: the formats :func:`read_fe_model` reads
FE_FORMATS = ("matrix_market", "harwell_boeing", "nastran_dmig", "nastran_op4", "abaqus_matrix_input")

_SUFFIXES = {".mtx": "mtx", ".mm": "matrix_market", ".rb": "harwell_boeing", ".rua": "harwell_boeing",
             ".rsa": "harwell_boeing", ".hb": "harwell_boeing", ".matrix": "harwell_boeing",
             ".pch": "nastran_dmig", ".bdf": "nastran_dmig", ".dat": "nastran_dmig", ".blk": "nastran_dmig",
             ".dmig": "nastran_dmig", ".op4": "nastran_op4"}
_OWN_DOFS = ("nastran_dmig", "abaqus_matrix_input")  # formats whose files carry the DOF table

#: relative bound on |a_ij - a_ji| / sqrt(|a_ii a_jj|) (module docstring)
SYMMETRY_TOLERANCE = 1e-8
#: smallest pivot of the scaled mass's L D L^T taken as positive (module docstring)
PIVOT_TOLERANCE = 1e-13
#: largest node id read (a signed 32-bit integer, as Abaqus and NASTRAN number their nodes)
MAX_NODE_ID = 2**31 - 1
_ROLES = ("mass", "stiffness", "damping")


def dof_name(node: int, direction: int) -> str:
    """The DOF name of ``(node, direction)``: ``n<node>_u<d>`` for directions 1..3 (translations),
    ``n<node>_r<d-3>`` for 4..6 (rotations).

    Parameters
    ----------
    node : int
        Node id.
    direction : int
        1, 2, 3 (translation along x, y, z) or 4, 5, 6 (rotation about x, y, z).

    Returns
    -------
    str
    """
    direction = int(direction)
    return f"n{int(node)}_u{direction}" if direction <= 3 else f"n{int(node)}_r{direction - 3}"


@dataclass(frozen=True, eq=False)
class FEModel:
    """A finite-element model's sparse matrices with its DOF table and node sets.

    Made by :func:`read_fe_model`, or directly from matrices (checked the same way).

    Parameters
    ----------
    mass : (n_dof, n_dof) sparse or array_like
        Mass matrix [kg, kg m^2 for rotations], symmetric positive definite.
    stiffness : (n_dof, n_dof) sparse or array_like
        Stiffness matrix [N/m, N m/rad], symmetric, non-negative diagonal.
    damping : (n_dof, n_dof) sparse or array_like, optional
        Viscous damping matrix [N s/m], symmetric.
    dofs : (n_dof, 2) array_like of int
        The DOF table: node id and direction (1..6) of each matrix row.
    node_sets : dict, optional
        Set name -> node ids (each in the DOF table).
    source : str
        Where the matrices come from (the files).
    files : dict, optional
        ``"mass"``, ``"stiffness"``, ``"damping"``, ``"dofs"``, ``"node_sets"`` -> the file each
        was read from: the errors name it.
    indefinite_stiffness : bool
        The stiffness may have negative directions where the joints do not hold it: a spinning
        blade's (stress stiffening and spin softening in ``K``), whose free root the contacts
        hold. Passed on to the structures made from the model
        (:func:`~frictionjoint.structures.craig_bampton`), which otherwise refuse it.

    Attributes
    ----------
    mass, stiffness : (n_dof, n_dof) scipy.sparse.csr_array
    damping : (n_dof, n_dof) scipy.sparse.csr_array or None
    dofs : (n_dof, 2) ndarray of int64
    node_sets : dict of str to tuple of int
    """

    mass: object
    stiffness: object
    damping: object = None
    dofs: object = None
    node_sets: Mapping = field(default_factory=dict)
    source: str = ""
    files: Mapping = field(default_factory=dict)
    indefinite_stiffness: bool = False

    def __post_init__(self):
        object.__setattr__(self, "indefinite_stiffness", check_bool("indefinite_stiffness", self.indefinite_stiffness))
        files = {k: str(v) for k, v in dict(self.files).items()}
        label = {role: f"{files[role]}: {role}" if role in files else role for role in _ROLES + ("dofs", "node_sets")}
        n = None
        for role in _ROLES:
            value = getattr(self, role)
            if value is None:
                if role != "damping":
                    raise ParameterError(f"{role} is required")
                continue
            a = _as_csr(label[role], value, n)
            n = a.shape[0]
            object.__setattr__(self, role, a)
        dofs = _dof_table(label["dofs"], self.dofs, n)
        object.__setattr__(self, "dofs", dofs)
        object.__setattr__(self, "files", files)
        object.__setattr__(self, "_index", {(int(a), int(b)): i for i, (a, b) in enumerate(dofs)})
        object.__setattr__(self, "node_sets", _node_sets(label["node_sets"], self.node_sets, self._index))
        for role in _ROLES:
            a = getattr(self, role)
            if a is not None:
                _check_symmetric(label[role], a, self.dof_names)
        _check_positive_definite(label["mass"], self.mass, self.dof_names)
        diag = self.stiffness.diagonal()
        if np.any(diag < 0.0):
            i = int(np.argmin(diag))
            raise ParameterError(f"{label['stiffness']} has a negative diagonal entry {diag[i]:.6g} at "
                                 f"{self.dof_names[i]} (a stiffness is positive semi-definite)")

    @property
    def n_dof(self) -> int:
        """Number of DOFs."""
        return self.mass.shape[0]

    @property
    def dof_names(self) -> tuple:
        """The DOF names, ``n<node>_u<d>`` / ``n<node>_r<d>`` (:func:`dof_name`), in matrix order."""
        names = self.__dict__.get("_names")
        if names is None:
            names = tuple(dof_name(a, b) for a, b in self.dofs)
            object.__setattr__(self, "_names", names)
        return names

    def dof_index(self, node: int, direction: int) -> int:
        """The matrix row of ``(node, direction)``.

        Parameters
        ----------
        node : int
            Node id.
        direction : int
            Direction, 1..6.

        Returns
        -------
        int
        """
        try:
            return self._index[(int(node), int(direction))]
        except (KeyError, TypeError, ValueError):
            raise ParameterError(f"no DOF (node {node!r}, direction {direction!r}) in the DOF table") from None

    def dofs_of(self, set_name: str, directions: Sequence[int] | None = None) -> np.ndarray:
        """The matrix rows of a node set's DOFs: node by node in the set's order, each node's
        DOFs in the table's order.

        Parameters
        ----------
        set_name : str
            A name of :attr:`node_sets`.
        directions : sequence of int, optional
            Only these directions (each node must have them); all the node's DOFs if omitted.

        Returns
        -------
        (k,) ndarray of int
        """
        if set_name not in self.node_sets:
            raise ParameterError(f"set_name must be one of {sorted(self.node_sets)}, got {set_name!r}")
        rows = []
        for node in self.node_sets[set_name]:
            if directions is None:
                rows.extend(np.flatnonzero(self.dofs[:, 0] == node))
            else:
                rows.extend(self.dof_index(node, d) for d in directions)
        return np.asarray(rows, dtype=np.int64)

    def to_structure(self, max_dof: int = 2000) -> LinearStructure:
        """The model as a dense :class:`~frictionjoint.LinearStructure` with DOF names
        ``n<node>_u<d>``: for models small enough to be dense (reduce larger ones first).

        Parameters
        ----------
        max_dof : int
            Largest number of DOFs made dense (LinearStructure checks its matrices with dense
            eigenvalues: seconds at 2,000 DOFs).

        Returns
        -------
        LinearStructure
        """
        max_dof = check_count("max_dof", max_dof)
        if self.n_dof > max_dof:
            raise ParameterError(f"the model has {self.n_dof} DOFs, more than max_dof={max_dof} for a dense "
                                 f"LinearStructure: reduce it first")
        damping = None if self.damping is None else self.damping.toarray()
        return LinearStructure(self.mass.toarray(), self.stiffness.toarray(), damping, dof_names=self.dof_names)


def _as_csr(label: str, value, n: int | None) -> sp.csr_array:
    """``value`` as a square real CSR array of size ``n`` (if given), finite, duplicates summed."""
    try:
        if np.iscomplexobj(value.data if sp.issparse(value) else np.asarray(value)):
            raise TypeError("complex")
        a = sp.csr_array(value, dtype=float) if sp.issparse(value) else sp.csr_array(np.asarray(value, dtype=float))
    except (TypeError, ValueError):
        raise ParameterError(f"{label} must be a matrix of real numbers") from None
    if a.ndim != 2 or a.shape[0] != a.shape[1]:
        raise ParameterError(f"{label} must be square, got shape {a.shape}")
    if n is not None and a.shape[0] != n:
        raise ParameterError(f"{label} is {a.shape[0]} x {a.shape[1]}, the mass {n} x {n}: sizes differ")
    a.sum_duplicates()
    if not np.all(np.isfinite(a.data)):
        raise ParameterError(f"{label} has entries that are not finite")
    return a


def _dof_table(label: str, dofs, n: int) -> np.ndarray:
    if dofs is None:
        raise ParameterError(f"{label}: the DOF table is required (node id, direction per matrix row)")
    try:
        table = np.asarray(dofs, dtype=float)
        ok = table.ndim == 2 and table.shape[1] == 2 and np.all(table == np.round(table))
    except (TypeError, ValueError, OverflowError):
        ok = False
    if not ok:
        raise ParameterError(f"{label}: the DOF table must be (n_dof, 2) integers (node id, direction)")
    if table.shape[0] != n:
        raise ParameterError(f"{label}: the DOF table has {table.shape[0]} rows, the matrices {n}")
    bad = np.flatnonzero(~((table[:, 0] >= 1) & (table[:, 0] <= MAX_NODE_ID)))
    if bad.size:
        raise ParameterError(f"{label}: node id {table[bad[0], 0]:.0f} (row {bad[0] + 1}) is not in "
                             f"1..{MAX_NODE_ID}")
    bad = np.flatnonzero((table[:, 1] < 1) | (table[:, 1] > 6))
    if bad.size:
        raise ParameterError(f"{label}: direction {table[bad[0], 1]:.0f} of node {table[bad[0], 0]:.0f} "
                             f"(row {bad[0] + 1}) is not in 1..6")
    table = table.astype(np.int64)
    keys = table[:, 0] * 8 + table[:, 1]
    uniq, counts = np.unique(keys, return_counts=True)
    if np.any(counts > 1):
        node, direction = divmod(int(uniq[np.argmax(counts > 1)]), 8)
        raise ParameterError(f"{label}: (node {node}, direction {direction}) appears more than once")
    table.setflags(write=False)
    return table


def _node_sets(label: str, sets, index: dict) -> dict:
    nodes = {node for node, _ in index}
    out = {}
    for name, members in dict(sets).items():
        if not isinstance(name, str) or not re.match(r"[A-Za-z_][A-Za-z0-9_]*\Z", name):
            raise ParameterError(f"{label}: set names must be identifiers (letters, digits, _), got {name!r}")
        try:
            members = tuple(int(m) for m in np.atleast_1d(np.asarray(members)))
        except (TypeError, ValueError):
            raise ParameterError(f"{label}: set {name!r} must be a list of node ids, got {members!r}") from None
        missing = [m for m in members if m not in nodes]
        if missing:
            raise ParameterError(f"{label}: set {name!r} names node {missing[0]}, which is not in the DOF table")
        if len(set(members)) != len(members):
            raise ParameterError(f"{label}: set {name!r} names a node twice")
        out[name] = members
    return out


def _check_symmetric(label: str, a: sp.csr_array, names: tuple) -> None:
    """One line if ``a`` is not symmetric to SYMMETRY_TOLERANCE of its rows' scale (module docstring)."""
    diff = (a - a.T).tocoo()
    if diff.nnz == 0:
        return
    d = np.abs(a.diagonal())
    scale = np.sqrt(d[diff.row] * d[diff.col])
    over = np.abs(diff.data) > SYMMETRY_TOLERANCE * scale
    if np.any(over):
        k = np.argmax(np.where(over, np.abs(diff.data) / np.maximum(scale, np.finfo(float).tiny), -1.0))
        i, j = int(diff.row[k]), int(diff.col[k])
        raise ParameterError(f"{label} is not symmetric: entry ({names[i]}, {names[j]}) is {a[i, j]:.9g}, "
                             f"({names[j]}, {names[i]}) is {a[j, i]:.9g} (relative tolerance "
                             f"{SYMMETRY_TOLERANCE:g} of sqrt(|a_ii a_jj|))")


def _check_positive_definite(label: str, a: sp.csr_array, names: tuple) -> None:
    """One line if the mass is not positive definite: the L D L^T pivots of its scaled form in
    reverse Cuthill-McKee order (module docstring)."""
    from scipy.sparse.csgraph import reverse_cuthill_mckee
    from scipy.sparse.linalg import splu

    diag = a.diagonal()
    if np.any(~(diag > 0.0)):
        i = int(np.argmin(diag))
        raise ParameterError(f"{label} is not positive definite: its diagonal entry at {names[i]} is {diag[i]:.6g}")
    s = sp.diags_array(1.0 / np.sqrt(diag))
    scaled = (s @ (0.5 * (a + a.T)) @ s).tocsr()
    order = reverse_cuthill_mckee(scaled, symmetric_mode=True)
    try:
        lu = splu(scaled[order][:, order].tocsc(), permc_spec="NATURAL", diag_pivot_thresh=0.0,
                  options={"SymmetricMode": True})
    except RuntimeError:  # an exactly zero pivot: singular
        raise ParameterError(f"{label} is not positive definite: it is singular") from None
    if not (np.array_equal(lu.perm_r, lu.perm_c) and np.array_equal(lu.perm_c, np.arange(len(order)))):
        raise ParameterError(f"{label}: the L D L^T test pivoted off the diagonal: the mass is not positive definite")
    pivots = lu.U.diagonal()
    k = int(np.argmin(pivots))
    if not pivots[k] > PIVOT_TOLERANCE:
        raise ParameterError(f"{label} is not positive definite: pivot {pivots[k]:.3g} of its scaled L D L^T "
                             f"at {names[order[k]]} (all must be > {PIVOT_TOLERANCE:g})")


# ----------------------------------------------------------------------------------- readers


def read_fe_model(mass: str | Path | tuple, stiffness: str | Path | tuple, damping: str | Path | tuple | None = None,
                  *, dofs: str | Path | np.ndarray | None = None, node_sets: str | Path | Mapping | None = None,
                  format: str | None = None, source: str | None = None,
                  indefinite_stiffness: bool = False) -> FEModel:
    """Read an FE model's matrices, DOF table and node sets (module docstring for the formats).

    Parameters
    ----------
    mass, stiffness : path or (path, name)
        The mass [kg] and stiffness [N/m] matrices' files; ``(path, name)`` picks a matrix of a
        DMIG or OP4 file that holds several (the same file may hold all).
    damping : path or (path, name), optional
        The viscous damping matrix [N s/m].
    dofs : path or (n_dof, 2) array_like, optional
        The DOF table (node id, direction 1..6 per matrix row): a CSV file with the header
        ``node,direction``. Required except for the formats whose files carry it (DMIG, Abaqus).
    node_sets : path or dict, optional
        Named node sets: a CSV file with the header ``set,node``, or ``{name: [node ids]}``.
    format : str, optional
        One of :data:`FE_FORMATS`; from each file's suffix (and first line for ``.mtx``) if omitted.
    source : str, optional
        Where the model comes from; the files' names if omitted.
    indefinite_stiffness : bool
        The stiffness of a spinning structure, indefinite until its joints hold it
        (:class:`FEModel`).

    Returns
    -------
    FEModel
    """
    given = {"mass": mass, "stiffness": stiffness, "damping": damping}
    specs = {role: _spec(role, v) for role, v in given.items() if v is not None}
    formats = {role: _format(path, format) for role, (path, _) in specs.items()}
    if len(set(formats.values())) != 1:
        raise ParameterError(f"the matrices' files must have one format, got {formats}")
    fmt = formats["mass"]
    files = {role: str(path) for role, (path, _) in specs.items()}
    if fmt in _OWN_DOFS:
        if dofs is not None:
            why = (" (a .mtx file whose first line is not '%%MatrixMarket ...' is Abaqus matrix input)"
                   if fmt == "abaqus_matrix_input" and format is None else "")
            raise ParameterError(f"{files['mass']}: a {fmt} file carries its own DOF table; give no dofs{why}")
        matrices, table = _read_keyed(fmt, specs)
    else:  # the DOF table first: the matrices' declared sizes are checked against it before they are read
        if dofs is None:
            raise ParameterError(f"{files['mass']}: a {fmt} file has no DOF table: give dofs (a node,direction CSV)")
        if isinstance(dofs, (str, Path)):
            files["dofs"] = str(dofs)
            table = read_dof_table(dofs)
        else:
            table = dofs
        n_dof = (len(table), f"the DOF table ({files['dofs']})" if "dofs" in files else "dofs") \
            if np.ndim(table) == 2 else None
        matrices = {role: _read_plain(fmt, path, name, n_dof) for role, (path, name) in specs.items()}
    if isinstance(node_sets, (str, Path)):
        files["node_sets"] = str(node_sets)
        node_sets = read_node_sets(node_sets)
    if source is None:
        source = ", ".join(f"{role}: {Path(p).name}" for role, p in files.items())
    return FEModel(matrices["mass"], matrices["stiffness"], matrices.get("damping"), table, node_sets or {},
                   source, files, indefinite_stiffness)


def _spec(role: str, value) -> tuple[Path, str | None]:
    if isinstance(value, (str, Path)):
        path, name = Path(value), None
    elif isinstance(value, (tuple, list)) and len(value) == 2 and all(isinstance(v, (str, Path)) for v in value):
        path, name = Path(value[0]), str(value[1])
    else:
        raise ParameterError(f"{role} must be a path or (path, matrix name), got {value!r}")
    if not path.is_file():
        raise ParameterError(f"{role} file {str(path)!r} not found")
    if path.stat().st_size == 0:
        raise ParameterError(f"{role} file {str(path)!r} is empty")
    return path, name


def _format(path: Path, given: str | None) -> str:
    if given is not None:
        if given not in FE_FORMATS:
            raise ParameterError(f"format must be one of {FE_FORMATS}, got {given!r}")
        return given
    fmt = _SUFFIXES.get(path.suffix.lower())
    if fmt is None:
        raise ParameterError(f"{path}: cannot tell the format from the suffix {path.suffix!r}; give format= "
                             f"(one of {FE_FORMATS})")
    if fmt == "mtx":
        with open(path, "rb") as fh:
            first = fh.readline()
        fmt = "matrix_market" if first.lower().startswith(b"%%matrixmarket") else "abaqus_matrix_input"
    return fmt


def read_dof_table(path: str | Path) -> np.ndarray:
    """The DOF table of a CSV file with the header ``node,direction`` (``#`` starts a comment).

    Parameters
    ----------
    path : path
        The file.

    Returns
    -------
    (n_dof, 2) ndarray of int64
    """
    rows = _csv_rows(path, ("node", "direction"))
    try:
        table = [[int(a), int(b)] for a, b in rows]
    except ValueError as exc:
        raise ParameterError(f"{path}: the DOF table must hold integers ({exc})") from None
    bad = next((k for k, row in enumerate(table) if max(map(abs, row)) > MAX_NODE_ID), None)
    if bad is not None:  # beyond int64 too; the rest is checked where the table is used (FEModel)
        raise ParameterError(f"{path}: data row {bad + 1} ({table[bad][0]}, {table[bad][1]}): node ids are "
                             f"1..{MAX_NODE_ID}, directions 1..6")
    return np.array(table, dtype=np.int64).reshape(-1, 2)


def read_node_sets(path: str | Path) -> dict:
    """Node sets from a CSV file with the header ``set,node`` (``#`` starts a comment).

    Parameters
    ----------
    path : path
        The file.

    Returns
    -------
    dict of str to list of int
    """
    sets: dict = {}
    for name, node in _csv_rows(path, ("set", "node")):
        try:
            sets.setdefault(name, []).append(int(node))
        except ValueError:
            raise ParameterError(f"{path}: node {node!r} of set {name!r} is not an integer") from None
    return sets


def _csv_rows(path, header: tuple) -> list:
    path = Path(path)
    if not path.is_file():
        raise ParameterError(f"file {str(path)!r} not found")
    lines = [ln.split("#", 1)[0].strip() for ln in _text(path, "CSV").splitlines()]
    rows = [[f.strip() for f in r] for r in csv.reader(ln for ln in lines if ln)]
    if not rows or tuple(f.lower() for f in rows[0]) != header:
        raise ParameterError(f"{path}: the first line must be the header {','.join(header)}")
    bad = next((k for k, r in enumerate(rows[1:]) if len(r) != len(header)), None)
    if bad is not None:
        raise ParameterError(f"{path}: data row {bad + 1} has {len(rows[bad + 1])} fields, not {len(header)}")
    return rows[1:]


def _read_plain(fmt: str, path: Path, name: str | None, n_dof: tuple | None):
    """One matrix of a format without a DOF table, sparse; its declared size is checked against the
    DOF table's rows (``n_dof``: their number and the table's name) and the file before anything is
    allocated."""
    try:
        if fmt == "matrix_market":
            import scipy.io

            _check_last_line(path)
            rows, cols, entries, layout, field, symmetry = scipy.io.mminfo(path)
            if field not in ("real", "integer", "double"):
                raise ParameterError(f"{path}: a Matrix Market file of {field} entries; a mass, stiffness or "
                                     f"damping matrix is real")
            _check_declared_size(path, rows, cols, n_dof)
            if layout == "array":  # every value written (one triangle if symmetric), one a line
                stored = rows * (rows + 1) // 2 if symmetry == "symmetric" else rows * cols
                if symmetry == "skew-symmetric":
                    stored = rows * (rows - 1) // 2
                _check_declared_entries(path, stored, 2, "values")  # '1' and a newline
                _check_array_values(path, stored)
            else:
                _check_declared_entries(path, entries, 6, "entries")  # 'i j v' and a newline
            return sp.csr_array(scipy.io.mmread(path))
        if fmt == "harwell_boeing":
            return _read_harwell_boeing(path, n_dof)
        return _read_op4(path, name, n_dof)
    except ParameterError:
        raise
    except (ValueError, TypeError, OSError, IndexError, EOFError) as exc:
        raise ParameterError(f"{path}: not a readable {fmt} file ({' '.join(str(exc).split())})") from None


def _check_declared_size(path: Path, rows: int, cols: int, n_dof: tuple | None) -> None:
    """A matrix header's size against the DOF table (``n_dof``: its rows and its name), before the
    matrix is read."""
    if rows != cols:
        raise ParameterError(f"{path}: the header declares a {rows} x {cols} matrix; a mass, stiffness or damping "
                             f"matrix is square")
    if n_dof is not None and rows != n_dof[0]:
        raise ParameterError(f"{path}: the header declares a {rows} x {cols} matrix, {n_dof[1]} has {n_dof[0]} "
                             f"rows")


def _check_declared_entries(path: Path, declared: int, least_bytes: int, what: str) -> None:
    """A header's entry count against what the file's bytes can hold, before the entries are allocated."""
    size = path.stat().st_size
    if declared > size // least_bytes:
        raise ParameterError(f"{path}: the header declares {declared} {what}, more than a file of {size} bytes "
                             f"holds (at least {least_bytes} bytes each): the file ends early or the header is wrong")


def _check_array_values(path: Path, stored: int) -> None:
    """A Matrix Market array file's values counted (one a line after the size line): scipy 1.17's
    reader (fast_matrix_market) fills a symmetric array file that ends early with zeros."""
    found, header = 0, True
    with open(path, "rb") as fh:
        for line in fh:
            if header:
                header = line.startswith(b"%") or not line.strip()
                continue  # the size line ends the header
            found += bool(line.strip())
    if found != stored:
        raise ParameterError(f"{path}: the header declares {stored} values, the file has {found}"
                             + (": it ends early" if found < stored else ""))


def _check_last_line(path: Path) -> None:
    """A text file cut inside its last line would read a shortened number: it must end with a newline."""
    size = path.stat().st_size
    if size == 0:
        return
    with open(path, "rb") as fh:
        fh.seek(size - 1)
        if fh.read(1) not in (b"\n", b"\r"):
            raise ParameterError(f"{path}: the file ends inside a line (no newline after its last line): it seems "
                                 f"cut short; if its last line is whole, end it with a newline")


def _text(path: Path, fmt: str) -> str:
    """The text of a text-format file, refused by name if it is not text or ends inside a line."""
    data = path.read_bytes()
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise ParameterError(f"{path}: byte {data[exc.start]:#04x} at offset {exc.start} is not text: not a file "
                             f"of the {fmt} format") from None
    _check_last_line(path)
    return text


def _read_harwell_boeing(path: Path, n_dof: tuple | None) -> sp.csr_array:
    """scipy's reader takes unsymmetric assembled files only: a symmetric one (RSA: one triangle
    in the same layout) is read as RUA and mirrored. The header's size is checked against the DOF
    table and its line count (TOTCRD) against the file first."""
    import scipy.io

    lines = _text(path, "harwell_boeing").splitlines(keepends=True)
    try:
        totcrd, rhscrd = int(lines[1][:14]), int(lines[1][56:70].strip() or 0)
        rows, cols, nnz = int(lines[2][14:28]), int(lines[2][28:42]), int(lines[2][42:56])
    except (IndexError, ValueError):
        raise ParameterError(f"{path}: not a readable harwell_boeing file (its header's second and third lines "
                             f"hold the line counts and the matrix size)") from None
    _check_declared_size(path, rows, cols, n_dof)
    _check_declared_entries(path, nnz, 2, "entries")  # an index and a value of one character each at least
    data_lines = len(lines) - (5 if rhscrd > 0 else 4)
    if data_lines < totcrd:
        raise ParameterError(f"{path}: the header declares {totcrd} lines of data, the file has {max(data_lines, 0)}: "
                             f"it ends early")
    kind = lines[2][:3].upper() if len(lines) > 2 else ""
    if kind in ("RSA", "ISA"):
        lines[2] = kind[0] + "UA" + lines[2][3:]
        a = sp.csr_array(scipy.io.hb_read(io.StringIO("".join(lines))))
        upper, lower = sp.triu(a, k=1), sp.tril(a, k=-1)
        if upper.nnz and lower.nnz:
            raise ParameterError(f"{path}: a symmetric ({kind}) file stores one triangle; this one has entries in both")
        return (a + upper.T + lower.T).tocsr()
    return sp.csr_array(scipy.io.hb_read(io.StringIO("".join(lines))))


def _read_op4(path: Path, name: str | None, n_dof: tuple | None) -> sp.csr_array:
    try:
        from pyyeti.nastran import op4
    except ImportError:
        raise ParameterError(f"{path}: reading OP4 files needs pyyeti (pip install pyyeti, or "
                             "frictionjoint[nastran])") from None
    with open(path, "rb") as fh:
        ascii_file = fh.read(1) in b" 0123456789"  # a binary file starts with a record length
    if ascii_file:
        _check_last_line(path)
    names, sizes = op4.dir(str(path), verbose=False)[:2]  # the headers, without reading the matrices
    found, size = _pick(path, {k.upper(): (k, v) for k, v in zip(names, sizes)}, name)
    _check_declared_size(path, *size, n_dof)
    return sp.csr_array(op4.read(str(path), namelist=[found], sparse=True)[found])  # this matrix only


def _pick(path: Path, matrices: dict, name: str | None):
    if name is None:
        if len(matrices) != 1:
            raise ParameterError(f"{path} holds the matrices {sorted(matrices)}: name the one to read "
                                 f"(path, name)")
        return next(iter(matrices.values()))
    if name.upper() not in matrices:
        raise ParameterError(f"{path} has no matrix {name!r}; it holds {sorted(matrices)}")
    return matrices[name.upper()]


def _read_keyed(fmt: str, specs: dict) -> tuple[dict, np.ndarray]:
    """Matrices whose entries are keyed by (node, direction): the DOF table is the union of their
    keys, ordered by node then direction; each file is read once."""
    parsed = {}
    for path, _ in specs.values():
        if path not in parsed:
            parsed[path] = _read_dmig(path) if fmt == "nastran_dmig" else {"MATRIX": _read_abaqus(path)}
    entries = {role: (path, _pick(path, parsed[path], name)) for role, (path, name) in specs.items()}
    keys = np.unique(np.concatenate([np.concatenate([e.row_keys, e.col_keys]) for _, e in entries.values()]))
    table = np.stack(divmod(keys, 8), axis=1)
    n = keys.size
    matrices = {}
    for role, (path, e) in entries.items():
        rows, cols = np.searchsorted(keys, e.row_keys), np.searchsorted(keys, e.col_keys)
        matrices[role] = _assemble(f"{path}: {role}", rows, cols, e.values, n, e.symmetric_storage, table)
        if role != "damping":  # the files declare no size: a missing diagonal is how a cut file shows
            missing = np.setdiff1d(np.arange(n), rows[rows == cols])
            if missing.size:
                raise ParameterError(f"{path}: {role} has no diagonal entry at {dof_name(*table[missing[0]])} "
                                     f"({missing.size} of the {n} DOFs the files name have none): the file seems "
                                     f"cut short; a DOF without {role} is written as an explicit 0.0")
    return matrices, table


@dataclass(frozen=True)
class _Entries:
    """A matrix's entries keyed by ``node * 8 + direction`` of its row and column."""

    row_keys: np.ndarray
    col_keys: np.ndarray
    values: np.ndarray
    symmetric_storage: bool  # one triangle stored: the other is its mirror


def _assemble(label: str, rows, cols, values, n: int, symmetric_storage: bool, table) -> sp.csr_array:
    """The sparse matrix of keyed entries; an entry given twice (or, in symmetric storage, given
    in both triangles) is an error, as NASTRAN makes it."""
    names = [dof_name(a, b) for a, b in table]
    key = rows.astype(np.int64) * n + cols
    uniq, first, counts = np.unique(key, return_index=True, return_counts=True)
    if np.any(counts > 1):
        k = first[np.argmax(counts > 1)]
        raise ParameterError(f"{label}: entry ({names[rows[k]]}, {names[cols[k]]}) is given twice")
    if symmetric_storage:
        off = rows != cols
        mirrored = np.isin(cols[off].astype(np.int64) * n + rows[off], uniq)
        if np.any(mirrored):
            k = np.flatnonzero(off)[np.argmax(mirrored)]
            raise ParameterError(f"{label}: symmetric storage gives both ({names[rows[k]]}, {names[cols[k]]}) "
                                 f"and its mirror")
        rows, cols, values = (np.concatenate([rows, cols[off]]), np.concatenate([cols, rows[off]]),
                              np.concatenate([values, values[off]]))
    return sp.csr_array((values, (rows, cols)), shape=(n, n))


_REAL = re.compile(r"([+-]?(?:\d+\.\d*|\.\d+))(?:[EeDd]([+-]?\d+)|([+-]\d+))?\Z")


def _real(text: str, where: str) -> float:
    """A NASTRAN real field: a decimal point, an exponent with E, D or a bare sign (1.5+3)."""
    m = _REAL.match(text)
    if not m:
        raise ParameterError(f"{where}: {text!r} is not a real number (NASTRAN reals have a decimal point)")
    exponent = m.group(2) or m.group(3)
    return float(m.group(1) + ("e" + exponent if exponent else ""))


def _integer(text: str, where: str) -> int:
    try:
        return int(text)
    except ValueError:
        raise ParameterError(f"{where}: {text!r} is not an integer") from None


def _bulk_cards(path: Path):
    """``(name, data fields, line number)`` of each entry of a bulk data file: small field (8
    characters), large field (16, ``*`` after the name or on the continuation), free field (commas);
    continuation lines start with ``+``, ``*`` or a blank field; ``$`` starts a comment."""
    card = None
    for lineno, raw in enumerate(_text(path, "nastran_dmig").split("\n"), 1):
        line = raw.split("$", 1)[0].rstrip("\r").expandtabs(8)
        if not line.strip():
            continue
        if "," in line:
            parts = line.split(",")
            head = parts[0].strip()
            per = 4 if (head.endswith("*") or head.startswith("*")) else 8
            fields = [p.strip() for p in parts[1:]]
            if len(fields) > per + 1:
                raise ParameterError(f"{path}, line {lineno}: more than {per} data fields on a free-field line")
            fields = (fields[:per] + [""] * per)[:per]
        else:
            head = line[:8].strip()
            width, per = (16, 4) if (head.endswith("*") or head.startswith("*")) else (8, 8)
            body = line[8:8 + width * per].ljust(width * per)
            fields = [body[k * width:(k + 1) * width].strip() for k in range(per)]
        if head == "" or head[0] in "+*":
            if card is None:
                raise ParameterError(f"{path}, line {lineno}: a continuation line with no entry before it")
            card[1].extend(fields)
            continue
        if card is not None:
            yield card
        name = head.rstrip("*").upper()
        if name == "INCLUDE":
            raise ParameterError(f"{path}, line {lineno}: INCLUDE is not followed; give the included file")
        card = (name, fields, lineno)
    if card is not None:
        yield card


def _read_dmig(path: Path) -> dict:
    """The DMIG matrices of a bulk data or punch file: name -> _Entries."""
    headers, columns = {}, {}
    for name, fields, lineno in _bulk_cards(path):
        if name != "DMIG":
            continue
        where = f"{path}, line {lineno}"
        matrix = fields[0].upper()
        if fields[1] == "0":
            if matrix in headers:
                raise ParameterError(f"{where}: a second header entry of DMIG {matrix}")
            form, tin = _integer(fields[2], where), _integer(fields[3], where)
            if form not in (1, 6):
                raise ParameterError(f"{where}: DMIG {matrix} has form IFO={form}; a mass, stiffness or damping "
                                     f"matrix is square (1) or symmetric (6)")
            if tin not in (1, 2):
                raise ParameterError(f"{where}: DMIG {matrix} is complex (TIN={tin}); only real matrices are read")
            headers[matrix] = form
            columns[matrix] = ([], [], [])
            continue
        if matrix not in headers:
            raise ParameterError(f"{where}: a DMIG {matrix} column before its header entry")
        col = _grid_key(fields[1], fields[2], where)
        rows, cols, vals = columns[matrix]
        for k in range(4, len(fields) - 3, 4):
            g, c, a, b = fields[k:k + 4]
            if not (g or c or a or b):
                continue
            if b:
                raise ParameterError(f"{where}: DMIG {matrix} has an imaginary part; only real matrices are read")
            rows.append(_grid_key(g, c, where))
            cols.append(col)
            vals.append(_real(a, where))
    if not headers:
        raise ParameterError(f"{path}: no DMIG entries (a NASTRAN bulk data or punch file with DMIG matrices "
                             f"is read)")
    return {m: _Entries(np.array(r, dtype=np.int64), np.array(c, dtype=np.int64), np.array(v, dtype=float),
                        headers[m] == 6) for m, (r, c, v) in columns.items()}


def _grid_key(grid: str, component: str, where: str) -> int:
    node, direction = _integer(grid, where), _integer(component or "0", where)
    if node < 1:
        raise ParameterError(f"{where}: point id {node} is not a positive integer")
    if node > MAX_NODE_ID:
        raise ParameterError(f"{where}: point id {node} is larger than {MAX_NODE_ID}")
    if not 1 <= direction <= 6:
        raise ParameterError(f"{where}: component {direction} of point {node}: only grid points' components "
                             f"1..6 are read (no scalar points)")
    return node * 8 + direction


def _read_abaqus(path: Path) -> _Entries:
    """Abaqus ``*MATRIX OUTPUT, FORMAT=MATRIX INPUT``: ``row node, row DOF, column node, column
    DOF, value`` per line (``**`` comments); one triangle is mirrored, both are taken as given."""
    text = _text(path, "abaqus_matrix_input")
    try:
        data = np.loadtxt(io.StringIO(text), delimiter=",", comments="**", ndmin=2)
    except ValueError as exc:
        raise ParameterError(f"{path}: not an Abaqus matrix-input file of lines 'node, dof, node, dof, value' "
                             f"({exc})") from None
    if data.size == 0:
        raise ParameterError(f"{path}: no data lines 'node, dof, node, dof, value'")
    if data.shape[1] != 5:
        raise ParameterError(f"{path}: lines must have 5 fields (node, dof, node, dof, value), got {data.shape[1]}")
    ids = data[:, :4]
    if np.any(ids != np.round(ids)):
        raise ParameterError(f"{path}: node and DOF fields must be integers")
    bad = np.flatnonzero(~((ids[:, [0, 2]] >= 1) & (ids[:, [0, 2]] <= MAX_NODE_ID)).all(axis=1))
    if bad.size:
        raise ParameterError(f"{path}: data line {bad[0] + 1} has a node id outside 1..{MAX_NODE_ID}")
    bad = np.flatnonzero((ids[:, [1, 3]] < 1).any(axis=1) | (ids[:, [1, 3]] > 6).any(axis=1))
    if bad.size:
        raise ParameterError(f"{path}: data line {bad[0] + 1} has a DOF outside 1..6 (only displacements and "
                             f"rotations are read)")
    ids = ids.astype(np.int64)
    rows, cols = ids[:, 0] * 8 + ids[:, 1], ids[:, 2] * 8 + ids[:, 3]
    one_triangle = not (np.any(rows > cols) and np.any(rows < cols))
    return _Entries(rows, cols, data[:, 4].copy(), one_triangle)
