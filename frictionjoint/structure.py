"""Linear structure: mass, damping and stiffness matrices with named DOFs."""
from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

from .errors import ParameterError, check_count, check_nonnegative, check_positive

__all__ = ["LinearStructure"]


def _square_matrix(name: str, value, n: int | None) -> np.ndarray:
    try:
        a = np.atleast_2d(np.asarray(value, dtype=float))
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be a square matrix of real numbers, got {value!r}") from None
    if a.ndim != 2 or a.shape[0] != a.shape[1]:
        raise ParameterError(f"{name} must be a square matrix, got shape {np.shape(value)}")
    if n is not None and a.shape[0] != n:
        raise ParameterError(f"{name} must have shape ({n}, {n}), got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ParameterError(f"{name} must contain only finite values")
    scale = max(np.max(np.abs(a)), np.finfo(float).tiny)
    if np.max(np.abs(a - a.T)) > 1e-12 * scale:
        raise ParameterError(f"{name} must be symmetric")
    a = 0.5 * (a + a.T)
    a.setflags(write=False)
    return a


def _check_definite(name: str, a: np.ndarray, strict: bool) -> None:
    eig = np.linalg.eigvalsh(a)
    scale = max(np.max(np.abs(eig)), np.finfo(float).tiny)
    if strict and eig[0] <= 1e-14 * scale:
        raise ParameterError(f"{name} must be positive definite (smallest eigenvalue {eig[0]:.3g})")
    if not strict and eig[0] < -1e-12 * scale:
        raise ParameterError(
            f"{name} must be positive semi-definite (smallest eigenvalue {eig[0]:.3g})")


class LinearStructure:
    """Linear multi-DOF structure ``M x'' + C x' + K x = f``.

    Parameters
    ----------
    mass : (n, n) array_like
        Mass matrix [kg], symmetric positive definite (a scalar gives one DOF).
    stiffness : (n, n) array_like
        Stiffness matrix [N/m], symmetric positive semi-definite.
    damping : (n, n) array_like, optional
        Viscous damping matrix [N s/m], symmetric positive semi-definite; zero if omitted.
    dof_names : sequence of str, optional
        Names of the DOFs; ``"x0", "x1", ...`` if omitted.
    indefinite_stiffness : bool
        Accept a stiffness with negative directions: a rotating structure's spin softening of
        DOFs that only its joints hold (a blade's free root); the assembled system must be stable.
    """

    def __init__(self, mass: ArrayLike, stiffness: ArrayLike, damping: ArrayLike | None = None,
                 dof_names: Sequence[str] | None = None, indefinite_stiffness: bool = False):
        self.mass = _square_matrix("mass", mass, None)
        n = self.mass.shape[0]
        self.stiffness = _square_matrix("stiffness", stiffness, n)
        self.damping = _square_matrix("damping", np.zeros((n, n)) if damping is None else damping, n)
        _check_definite("mass", self.mass, strict=True)
        self.indefinite_stiffness = bool(indefinite_stiffness)
        if not indefinite_stiffness:
            _check_definite("stiffness", self.stiffness, strict=False)
        _check_definite("damping", self.damping, strict=False)
        if dof_names is None:
            dof_names = [f"x{i}" for i in range(n)]
        dof_names = [str(s) for s in dof_names]
        if len(dof_names) != n or len(set(dof_names)) != n:
            raise ParameterError(f"dof_names must be {n} distinct names, got {dof_names!r}")
        self.dof_names = tuple(dof_names)

    @classmethod
    def chain(cls, n: int, mass: float = 1.0, stiffness: float = 1.0, damping: float = 0.0) -> "LinearStructure":
        """Fixed-free chain of ``n`` equal masses: a spring from the ground to DOF 0 and one
        between each pair of neighbours, a dashpot from every mass to the ground.

        Parameters
        ----------
        n : int
            Number of masses (DOFs), >= 1.
        mass : float
            Each mass [kg], > 0.
        stiffness : float
            Each spring [N/m], > 0.
        damping : float
            Each dashpot to the ground [N s/m], >= 0 (mass-proportional damping).

        Returns
        -------
        LinearStructure
        """
        n = check_count("n", n, 1)
        mass = check_positive("mass", mass)
        stiffness = check_positive("stiffness", stiffness)
        damping = check_nonnegative("damping", damping)
        k = np.zeros((n, n))
        k[0, 0] = stiffness
        for i in range(n - 1):
            k[i:i + 2, i:i + 2] += stiffness * np.array([[1.0, -1.0], [-1.0, 1.0]])
        return cls(mass * np.eye(n), k, damping * np.eye(n))

    @property
    def n_dof(self) -> int:
        """Number of degrees of freedom."""
        return self.mass.shape[0]

    def dof_index(self, dof: int | str) -> int:
        """Index of a DOF given by name or index.

        Parameters
        ----------
        dof : int or str
            Index or name of the DOF.

        Returns
        -------
        int
            Index of the DOF, in ``[0, n_dof)``.
        """
        if isinstance(dof, str):
            try:
                return self.dof_names.index(dof)
            except ValueError:
                raise ParameterError(f"dof must be one of {self.dof_names}, got {dof!r}") from None
        if isinstance(dof, (bool, np.bool_)) or not isinstance(dof, (int, np.integer)):
            raise ParameterError(f"dof must be a DOF name or an integer index, got {dof!r}")
        if not 0 <= dof < self.n_dof:
            raise ParameterError(f"dof must be in [0, {self.n_dof - 1}], got {dof}")
        return int(dof)

    def direction(self, dof: int | str | None = None, direction: ArrayLike | None = None) -> np.ndarray:
        """Unit-free direction vector (n,) of an element attached at ``dof`` or along ``direction``.

        Parameters
        ----------
        dof : int or str, optional
            Index or name of the DOF the element connects to the ground.
        direction : (n,) array_like, optional
            Finite non-zero direction vector over the DOFs, instead of ``dof`` (exactly one of the
            two must be given).

        Returns
        -------
        (n,) ndarray
            The unit vector of ``dof``, or ``direction`` as a float array (not normalised).
        """
        if (dof is None) == (direction is None):
            raise ParameterError("give exactly one of dof and direction")
        if dof is not None:
            d = np.zeros(self.n_dof)
            d[self.dof_index(dof)] = 1.0
            return d
        try:
            d = np.asarray(direction, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            d = np.zeros(0)
        if d.shape != (self.n_dof,) or not np.all(np.isfinite(d)) or not np.any(d):
            raise ParameterError(
                f"direction must be a finite non-zero vector of length {self.n_dof}, got {direction!r}")
        return d

    def clamped(self, dofs: Sequence[int | str]) -> "LinearStructure":
        """The structure with ``dofs`` held at zero (their rows and columns removed).

        Parameters
        ----------
        dofs : sequence of str or int
            DOFs to clamp, by name or index (e.g. a blade root's slope, held by its slot).

        Returns
        -------
        LinearStructure
            The other DOFs, in their order and with their names (a reduced structure's
            ``transformation`` keeps the columns of the other DOFs).
        """
        gone = {self.dof_index(d) for d in dofs}
        keep = [i for i in range(self.n_dof) if i not in gone]
        if not keep:
            raise ParameterError("dofs must leave at least one DOF free")
        sub = np.ix_(keep, keep)
        out = LinearStructure(self.mass[sub], self.stiffness[sub], self.damping[sub],
                              dof_names=[self.dof_names[i] for i in keep],
                              indefinite_stiffness=self.indefinite_stiffness)
        if getattr(self, "transformation", None) is not None:  # a reduced structure: x = T x_r
            out.transformation = self.transformation[:, keep]
            out.full_dof_names = self.full_dof_names
        return out

    def natural_frequencies(self) -> np.ndarray:
        """Undamped natural angular frequencies [rad/s], ascending."""
        import scipy.linalg

        lam = scipy.linalg.eigh(self.stiffness, self.mass, eigvals_only=True)
        return np.sqrt(np.clip(lam, 0.0, None))

    def harmonic_response(self, omegas: ArrayLike, force: ArrayLike) -> np.ndarray:
        """Complex amplitudes ``X`` of the steady response to ``Re(F e^{i omega t})``: ``(K + i
        omega C - omega^2 M) X = F`` solved at each frequency (direct solves: exact to rounding
        also where the stiffness is singular, e.g. a mechanism, unlike the state-space form).

        Parameters
        ----------
        omegas : (k,) array_like
            Angular frequencies [rad/s].
        force : (n_dof,) array_like
            Complex force amplitudes ``F`` [N].

        Returns
        -------
        (k, n_dof) complex ndarray
            ``X`` [m] per frequency.
        """
        ws = np.atleast_1d(np.asarray(omegas, dtype=float))
        f = np.asarray(force, dtype=complex).reshape(self.n_dof)
        return np.array([np.linalg.solve(self.stiffness + 1j * w * self.damping - w * w * self.mass, f)
                         for w in ws])

    def to_statespace(self):
        """python-control state-space model, state ``[x, v]``, input force, output ``x``."""
        import control

        n = self.n_dof
        minv = np.linalg.inv(self.mass)
        a = np.block([[np.zeros((n, n)), np.eye(n)], [-minv @ self.stiffness, -minv @ self.damping]])
        b = np.vstack([np.zeros((n, n)), minv])
        c = np.hstack([np.eye(n), np.zeros((n, n))])
        return control.ss(a, b, c, np.zeros((n, n)))

    def __repr__(self) -> str:
        return f"LinearStructure(n_dof={self.n_dof}, dof_names={self.dof_names})"
