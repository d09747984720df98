"""Shakedown and cyclic slip of discrete frictional systems under periodic load.

Model (Barber, Klarbring, Ciavarella et al.; seed ``frictional_contacts_periodic_loading_shakedown``,
eq. 4; first with ``B = 0``): ``n`` contact nodes with tangential slips ``w`` [m], a symmetric positive
definite tangential contact stiffness ``K`` (n x n) [N/m] that couples the nodes elastically, and
the tangential nodal forces::

    q(t) = q_ext(t) - K w,        |q_i| <= g_i(t) = f_i N_i(t),

where ``q_ext`` is the force the external load would produce with all nodes welded (``w = 0``)
and ``N_i(t) > 0`` the normal nodal forces. Coulomb's law at each node: stick (``w_i' = 0``) or
slip in the direction of the force (``q_i = g_i sgn(w_i')``). Quasi-static, no inertia.

Uncoupled means ``B = 0`` in the seed's eq. (4): the normal forces do not depend on the slips,
so ``N(t)`` is part of the load. Coupled systems (``coupling = B``, issue 42, first part): the
normal forces ``N = N_ext(t) - B w`` depend on the slips; the march below stays exact with the rate
problem's matrix ``S K S - F B S``, which has one solution for every load rate iff the friction is
below Klarbring's critical coefficient (:func:`critical_friction_coefficient`; a march above it is
refused). Separation (a node whose normal force reaches zero) is not modelled yet: the march stops
there with a :class:`~frictionjoint.errors.ConvergenceError` naming the node; nor are rigid-body
slip modes (``K`` is positive definite). The critical load factors of a load ``mean + lambda
cyclic(t)`` and the extreme constraints of Ahn's diagram are at the end of the module.

What is exact. The load (``q_ext`` and ``N``) is linear in time between its samples. On such a
piece the rate problem -- for the nodes at the friction bound (signs ``s``), slip rates
``lambda >= 0`` with ``y = g' - s q_ext' + (S K S) lambda >= 0`` and ``lambda . y = 0`` -- is a
linear complementarity problem with the positive definite matrix ``S K S`` (``S = diag(s)``; with
coupling ``S K S - F B S``, a P-matrix below ``f_cr``), hence has one solution, found by Murty's least-index principal pivoting (finite for P-matrices).
The rates stay constant until a stuck node reaches its bound, and that time is the root of a
linear function; so the march from event to event is exact up to rounding, with no time step.
(The one-step projection ``q_new = argmin_{|q| <= g} ||q - q_trial||_{K^-1}`` -- backward Euler --
is exact only for diagonal ``K``: with coupling, a node that slips early in a step and is
unloaded by its neighbours later is mispredicted; it converges at first order in the step.)
Dissipation ``sum_i int g_i |w_i'| dt`` and the work ``int q . K^-1 q_ext' dt`` are integrals of
linear functions over each piece, evaluated exactly; the stored energy is ``q . K^-1 q / 2``.

Theorems checked by :func:`shakedown_check` and the tests: the frictional Melan theorem
(Klarbring et al. 2007) -- for ``B = 0`` the system shakes down from every initial state iff
a residual slip ``w_r`` exists with ``|q_ext(t) - K w_r| <= g(t)`` for all ``t`` (a linear
feasibility problem, :func:`melan_check`); and Andersson et al. (2014) -- above that limit the
steady-state dissipation per cycle does not depend on the initial slips.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

import itertools

import numpy as np
from numpy.typing import ArrayLike
import scipy.linalg
import scipy.optimize

from .errors import ConvergenceError, ParameterError, check_positive
from .results.shakedown import CriticalLoadFactors, CycleResult, MelanResult, ShakedownResult

__all__ = [
    "PeriodicLoad",
    "QuasiStaticFrictionSystem",
    "CycleResult",
    "MelanResult",
    "ShakedownResult",
    "melan_check",
    "shakedown_check",
    "critical_friction_coefficient",
    "CRITICAL_ENUMERATION_NODES",
    "CriticalLoadFactors",
    "factored_load",
    "critical_load_factors",
    "extreme_constraints",
]

_RTOL = 1e-12  # relative tolerance of the friction bound (rounding of q = q_ext - K w)


def _check_count(name: str, value) -> int:
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1:
        raise ParameterError(f"{name} must be an integer >= 1, got {value!r}")
    return int(value)


def _finite_array(name: str, value, shape_text: str) -> np.ndarray:
    try:
        arr = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} must be an array of real numbers {shape_text}, got {value!r}") from None
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} must be finite (no NaN or inf)")
    return arr


@dataclass(frozen=True, eq=False)
class PeriodicLoad:
    """A periodic load sampled over one period, linear in time between the samples.

    The path runs through the samples in order and from the last one back to the first at
    ``t = period``.

    Parameters
    ----------
    times : (m,) array_like
        Sample times [s], strictly increasing, ``times[0] = 0``, ``times[-1] < period``.
    tangential : (m, n) array_like
        Welded tangential nodal forces ``q_ext`` [N] at the sample times.
    normal : (m, n) or (n,) array_like
        Normal nodal forces ``N`` [N] > 0 at the sample times (``(n,)``: constant).
    period : float
        Period [s], > ``times[-1]``.
    """

    times: np.ndarray
    tangential: np.ndarray
    normal: np.ndarray
    period: float

    def __post_init__(self):
        t = _finite_array("times", self.times, "(m,)")
        if t.ndim != 1 or t.size == 0:
            raise ParameterError(f"times must be a non-empty 1-D array (m,), got shape {t.shape}")
        if t[0] != 0.0 or np.any(np.diff(t) <= 0):
            raise ParameterError("times must start at 0 and increase strictly")
        period = check_positive("period", self.period)
        if not period > t[-1]:
            raise ParameterError(f"period must be > times[-1] = {t[-1]!r} s, got {period!r}")
        q = _finite_array("tangential", self.tangential, "(m, n)")
        if q.ndim != 2 or q.shape[0] != t.size or q.shape[1] == 0:
            raise ParameterError(f"tangential must have shape (m, n) = ({t.size}, n), got {q.shape}")
        p = _finite_array("normal", self.normal, "(m, n) or (n,)")
        if p.ndim == 1:
            p = np.broadcast_to(p, q.shape).copy() if p.shape == (q.shape[1],) else p
        if p.shape != q.shape:
            raise ParameterError(f"normal must have shape {q.shape} or ({q.shape[1]},), got {np.shape(self.normal)}")
        if not np.all(p > 0):
            raise ParameterError("normal must be > 0 at every sample (allowed range (0, inf); separation "
                                 "is out of scope)")
        for name, value in (("times", t), ("tangential", q), ("normal", p), ("period", period)):
            object.__setattr__(self, name, value)

    @property
    def n_nodes(self) -> int:
        return int(self.tangential.shape[1])

    def closed(self):
        """``(times, tangential, normal)`` with the first sample repeated at ``t = period``."""
        return (np.append(self.times, self.period), np.vstack([self.tangential, self.tangential[:1]]),
                np.vstack([self.normal, self.normal[:1]]))

    @classmethod
    def from_function(cls, tangential: Callable[[float], ArrayLike], normal: Callable[[float], ArrayLike],
                      period: float, n_samples: int) -> "PeriodicLoad":
        """Sample ``tangential(t)`` and ``normal(t)`` (callables returning ``(n,)`` [N]) at
        ``n_samples`` equally spaced times ``k period / n_samples``.

        Parameters
        ----------
        tangential : callable
            ``tangential(t) -> (n,) array_like``: welded tangential nodal forces ``q_ext`` [N] at
            time ``t`` [s].
        normal : callable
            ``normal(t) -> (n,) array_like``: normal nodal forces ``N`` [N] > 0 at time ``t`` [s].
        period : float
            Period [s], > 0.
        n_samples : int
            Samples per period, >= 1.

        Returns
        -------
        PeriodicLoad
        """
        period = check_positive("period", period)
        n_samples = _check_count("n_samples", n_samples)
        t = period * np.arange(n_samples) / n_samples
        return cls(t, [tangential(x) for x in t], [normal(x) for x in t], period)


def _lcp(m: np.ndarray, r: np.ndarray, tol: float):
    """``lambda >= 0``, ``y = r + m lambda >= 0``, ``lambda . y = 0`` for a P-matrix ``m``.

    Murty's least-index (Bard-type) principal pivoting: finite for every P-matrix. ``tol`` [units
    of r] absorbs rounding in the sign tests.
    """
    n = r.size
    basis = r < -tol
    tol_lam = tol / max(float(np.max(np.diag(m))), 1e-300)
    for _ in range(50 * n * n + 100):
        lam = np.zeros(n)
        if basis.any():
            lam[basis] = np.linalg.solve(m[np.ix_(basis, basis)], -r[basis])
        y = r + m @ lam
        bad = np.flatnonzero((basis & (lam < -tol_lam)) | (~basis & (y < -tol)))
        if bad.size == 0:
            return np.maximum(lam, 0.0), np.where(basis, 0.0, y)
        basis[bad[0]] = ~basis[bad[0]]
    raise ConvergenceError("the slip-rate complementarity problem did not terminate (is K positive definite?)")


def _march_piece(k, w, q_a, q_b, g_a, g_b, dt, tol_q, kinv_dq, fb=None):
    """March the slips exactly over one linear piece of the load; see the module docstring.
    ``fb``: the coupling ``diag(f) B`` (the bound is ``g = f (N_ext - B w)``), or None (``B = 0``).

    Returns ``(w, dissipation, slip_variation, work, n_events)``.
    """
    dq = (q_b - q_a) / dt
    dg = (g_b - g_a) / dt
    tau = 0.0
    dissipation = work = 0.0
    variation = np.zeros(w.size)
    tol_r = _RTOL * (float(np.max(np.abs(dq) + np.abs(dg))) + 1e-300)
    n_events = 0
    max_events = 20 * w.size + 100
    while tau < dt:
        if n_events >= max_events:
            raise ConvergenceError(f"more than {max_events} slip events in one load piece")
        n_events += 1
        q = q_a + tau * dq - k @ w
        g = g_a + tau * dg if fb is None else g_a + tau * dg - fb @ w
        sign = np.where(q >= 0, 1.0, -1.0)
        active = np.flatnonzero(np.abs(q) >= g - tol_q)
        lam = np.zeros(w.size)
        if active.size:
            s = sign[active]
            m = s[:, None] * k[np.ix_(active, active)] * s[None, :]
            if fb is not None:  # d/dt (g_i - s_i q_i) = ... + sum_j (s_i K_ij - f_i B_ij) s_j lambda_j
                m = m - fb[np.ix_(active, active)] * s[None, :]
            lam[active], _ = _lcp(m, dg[active] - s * dq[active], tol_r)
        rate = sign * lam  # w'
        q_rate = dq - k @ rate
        g_rate = dg if fb is None else dg - fb @ rate
        step = dt - tau
        free = lam == 0.0
        for gap, closing in ((g - q, g_rate - q_rate), (g + q, g_rate + q_rate)):
            hit = free & (gap > tol_q) & (closing < 0)
            if hit.any():
                step = min(step, float(np.min(gap[hit] / -closing[hit])))
        if fb is not None:  # a node whose normal force reaches zero would open: not modelled
            opening = (g > tol_q) & (g_rate < 0)
            if opening.any() and float(np.min(g[opening] / -g_rate[opening])) < min(step, dt - tau):
                i = int(np.flatnonzero(opening)[np.argmin(g[opening] / -g_rate[opening])])
                raise ConvergenceError(f"node {i}'s normal force reaches zero at t = {tau + float(g[i] / -g_rate[i]):.6g} s "
                                       "into a load piece: separation is not modelled")
        end = step >= dt - tau
        if end:
            step = dt - tau
        g_next = g + step * g_rate if fb is not None else (g_b if end else g + step * dg)
        dissipation += float(np.sum(lam * step * 0.5 * (g + g_next)))
        variation += lam * step
        work += float((q + 0.5 * step * q_rate) @ kinv_dq) * step
        w = w + rate * step
        tau = dt if end else tau + step
    return w, dissipation, variation, work, n_events


@dataclass(frozen=True, eq=False)
class QuasiStaticFrictionSystem:
    """Discrete frictional system: n contact nodes coupled elastically.

    ``q = q_ext(t) - K w``, ``|q_i| <= f_i N_i``, ``N = N_ext(t) - B w`` (module docstring; ``B = 0``
    unless ``coupling`` is given).

    Parameters
    ----------
    stiffness : (n, n) array_like
        Tangential contact stiffness ``K`` [N/m], symmetric positive definite (statically
        reduced onto the contact nodes).
    friction_coefficient : float or (n,) array_like
        Coulomb friction coefficient ``f`` [-] per node, > 0.
    coupling : (n, n) array_like, optional
        ``B`` [N/m]: the normal forces' dependence on the slips, ``N = N_ext - B w`` (any real
        matrix, not necessarily symmetric); None or zero: uncoupled, today's march bit for bit. With
        coupling the balance ``work = stored_energy_change + dissipation`` still holds: the normal
        forces do no work (no normal motion).
    """

    stiffness: np.ndarray
    friction_coefficient: np.ndarray
    coupling: np.ndarray | None = None
    _cho: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        k = _finite_array("stiffness", self.stiffness, "(n, n)")
        if k.ndim == 0:
            k = k.reshape(1, 1)
        if k.ndim != 2 or k.shape[0] != k.shape[1] or k.shape[0] == 0:
            raise ParameterError(f"stiffness must be a square (n, n) matrix, got shape {k.shape}")
        scale = float(np.max(np.abs(k)))
        if not np.allclose(k, k.T, rtol=0.0, atol=1e-12 * scale):
            raise ParameterError("stiffness must be symmetric")
        try:
            cho = scipy.linalg.cho_factor(k)
        except np.linalg.LinAlgError:
            raise ParameterError("stiffness must be positive definite") from None
        if np.min(np.linalg.eigvalsh(k)) <= 1e-13 * scale * k.shape[0]:
            raise ParameterError("stiffness must be positive definite (it is singular to rounding)")
        f = _finite_array("friction_coefficient", self.friction_coefficient, "scalar or (n,)")
        if f.ndim == 0:
            f = np.full(k.shape[0], float(f))
        if f.shape != (k.shape[0],):
            raise ParameterError(f"friction_coefficient must be a scalar or shape ({k.shape[0]},), got {f.shape}")
        if not np.all(f > 0):
            raise ParameterError("friction_coefficient must be > 0 (allowed range (0, inf))")
        object.__setattr__(self, "stiffness", k)
        object.__setattr__(self, "friction_coefficient", f)
        object.__setattr__(self, "_cho", cho)
        if self.coupling is not None:
            b = _finite_array("coupling", self.coupling, "(n, n)")
            if b.shape != k.shape:
                raise ParameterError(f"coupling must have the stiffness's shape {k.shape}, got {b.shape}")
            object.__setattr__(self, "coupling", None if not np.any(b) else b)

    @property
    def _fb(self):
        """``diag(f) B`` (None for an uncoupled system)."""
        return None if self.coupling is None else self.friction_coefficient[:, None] * self.coupling

    def normal_force(self, load_normal: ArrayLike, slip: ArrayLike) -> np.ndarray:
        """``N = N_ext - B w`` [N], (n,) (``N_ext`` for an uncoupled system).

        Parameters
        ----------
        load_normal : (n,) array_like
            Welded normal nodal forces ``N_ext`` [N] (one sample of :attr:`PeriodicLoad.normal`).
        slip : (n,) array_like
            Tangential slips ``w`` [m].

        Returns
        -------
        (n,) ndarray
            Normal nodal forces ``N`` [N].
        """
        n = np.asarray(load_normal, dtype=float)
        return n if self.coupling is None else n - self.coupling @ np.asarray(slip, dtype=float)

    @property
    def n_nodes(self) -> int:
        return int(self.stiffness.shape[0])

    def _check_load(self, load: PeriodicLoad) -> None:
        if not isinstance(load, PeriodicLoad):
            raise ParameterError(f"load must be a PeriodicLoad, got {type(load).__name__}")
        if load.n_nodes != self.n_nodes:
            raise ParameterError(f"load has {load.n_nodes} nodes, the system {self.n_nodes}")

    def _tol(self, load: PeriodicLoad) -> np.ndarray:
        """Per-node tolerance [N] of the friction bound: rounding of ``q = q_ext - K w``."""
        g = self.friction_coefficient * load.normal
        return _RTOL * np.max(g + np.abs(load.tangential), axis=0)

    def tangential_force(self, load_tangential: ArrayLike, slip: ArrayLike) -> np.ndarray:
        """``q = q_ext - K w`` [N], (n,).

        Parameters
        ----------
        load_tangential : (n,) array_like
            Welded tangential nodal forces ``q_ext`` [N] (one sample of
            :attr:`PeriodicLoad.tangential`).
        slip : (n,) array_like
            Tangential slips ``w`` [m].

        Returns
        -------
        (n,) ndarray
            Tangential nodal forces ``q`` [N].
        """
        return np.asarray(load_tangential, dtype=float) - self.stiffness @ np.asarray(slip, dtype=float)

    def check_slip(self, load: PeriodicLoad, slip: ArrayLike, name: str = "slip") -> np.ndarray:
        """Return ``slip`` (n,) [m] as an array if it satisfies the friction bound at ``t = 0``,
        else raise :class:`ParameterError` naming ``name`` and the first violating node.

        Parameters
        ----------
        load : PeriodicLoad
            The load; its first sample (``t = 0``) gives the friction bound, and it must have
            :attr:`n_nodes` nodes.
        slip : (n,) array_like
            Slips ``w`` [m] at ``t = 0``, finite.
        name : str
            Name of the argument in the error messages.

        Returns
        -------
        (n,) ndarray
            ``slip`` as a new float array [m].

        Raises
        ------
        ParameterError
            If ``load`` is not a :class:`PeriodicLoad` with :attr:`n_nodes` nodes, ``slip`` is
            not finite or of shape (n,), or it violates ``|q_i| <= f_i N_i`` at ``t = 0``.
        """
        self._check_load(load)
        w = _finite_array(name, slip, f"({self.n_nodes},)")
        if w.shape != (self.n_nodes,):
            raise ParameterError(f"{name} must have shape ({self.n_nodes},), got {w.shape}")
        excess = np.abs(self.tangential_force(load.tangential[0], w)) \
            - self.friction_coefficient * self.normal_force(load.normal[0], w)
        bad = np.flatnonzero(excess > self._tol(load))
        if bad.size:
            raise ParameterError(f"{name} violates the friction bound |q_i| <= f_i N_i at t = 0 at node "
                                 f"{bad[0]} (by {excess[bad[0]]:.3g} N)")
        return w

    def run_cycle(self, load: PeriodicLoad, slip: ArrayLike) -> CycleResult:
        """March one period of ``load`` exactly from the slips ``slip`` (n,) [m] at ``t = 0``.

        ``slip`` must satisfy the friction bound at ``t = 0`` (see :meth:`check_slip`).
        Nothing is mutated: the state is the returned ``slip_end``.

        Parameters
        ----------
        load : PeriodicLoad
            Periodic load with :attr:`n_nodes` nodes.
        slip : (n,) array_like
            Slips ``w`` [m] at ``t = 0``, within the friction bound.

        Returns
        -------
        CycleResult
            Slips at the samples, dissipation, work and stored-energy change of the period.
        """
        w = self.check_slip(load, slip)
        fb = self._fb
        if fb is not None:
            self._check_critical()
        times, q_ext, normal = load.closed()
        g = self.friction_coefficient * normal
        k = self.stiffness
        tol = self._tol(load)
        out = [w]
        dissipation = work = 0.0
        variation = np.zeros(w.size)
        n_events = 0
        for i in range(times.size - 1):
            dt = times[i + 1] - times[i]
            kinv_dq = scipy.linalg.cho_solve(self._cho, (q_ext[i + 1] - q_ext[i]) / dt)
            w, d, v, wk, ne = _march_piece(k, w, q_ext[i], q_ext[i + 1], g[i], g[i + 1], dt, tol, kinv_dq, fb)
            dissipation += d
            work += wk
            variation += v
            n_events += ne
            out.append(w)
        q0 = self.tangential_force(q_ext[0], out[0])
        q1 = self.tangential_force(q_ext[0], w)
        energy = 0.5 * (q1 @ scipy.linalg.cho_solve(self._cho, q1) - q0 @ scipy.linalg.cho_solve(self._cho, q0))
        return CycleResult(np.array(out), dissipation, variation, work, float(energy), n_events)

    def _check_critical(self) -> None:
        """Refuse a coupled system whose rate problem may have no unique solution: friction at or
        above :func:`critical_friction_coefficient` (computed once per system), or more nodes than it
        can enumerate (the complementarity solver could pick one of several solutions silently)."""
        if self.n_nodes > CRITICAL_ENUMERATION_NODES:
            raise ParameterError(f"a coupled system of more than {CRITICAL_ENUMERATION_NODES} nodes cannot be "
                                 f"checked against Klarbring's condition (3^n pencils), got {self.n_nodes}: its "
                                 "rate problem might have several solutions")
        f_cr = self.__dict__.get("_f_cr")
        if f_cr is None:
            f_cr = critical_friction_coefficient(self)
            object.__setattr__(self, "_f_cr", f_cr)
        if float(np.max(self.friction_coefficient)) >= f_cr:
            raise ParameterError(f"friction_coefficient must be < the critical coefficient f_cr = {f_cr:.6g} of this "
                                 "coupling (Klarbring's P-matrix condition): above it the rate problem need not have "
                                 "a unique solution")

    def run(self, load: PeriodicLoad, initial_slip: ArrayLike, n_cycles: int) -> list[CycleResult]:
        """``n_cycles`` consecutive periods from ``initial_slip`` (n,) [m]: list of :class:`CycleResult`.

        Parameters
        ----------
        load : PeriodicLoad
            Periodic load with :attr:`n_nodes` nodes.
        initial_slip : (n,) array_like
            Slips ``w`` [m] at ``t = 0``, within the friction bound.
        n_cycles : int
            Number of periods to march, >= 1.

        Returns
        -------
        list of CycleResult
            One per period, in order; each starts from the previous one's ``slip_end``.
        """
        n_cycles = _check_count("n_cycles", n_cycles)
        w = self.check_slip(load, initial_slip, "initial_slip")
        out = []
        for _ in range(n_cycles):
            out.append(self.run_cycle(load, w))
            w = out[-1].slip_end
        return out


#: the most nodes :func:`critical_friction_coefficient` enumerates (3^n - 1 pencils: 3^12 take ~10 s)
CRITICAL_ENUMERATION_NODES = 12


def critical_friction_coefficient(system: QuasiStaticFrictionSystem) -> float:
    """Klarbring's critical friction coefficient ``f_cr`` of a coupled system (seed Sec. 2.1).

    The rate problem's matrix over the nodes ``J`` at their bound with slip signs ``s`` is
    ``M = S K S - F B S`` (``S = diag(s_J)``, ``F = diag(f_J)``); the rate problem has a unique
    solution for every load rate iff every such ``M`` is a P-matrix. Its principal minors are
    ``det(K_JJ - S_J F_J B_JJ)``, positive at ``f = 0`` (``K`` positive definite); scaling the
    friction coefficients by ``t``, the first ``t`` where one vanishes is the smallest positive real
    generalised eigenvalue of the pencil ``(K_JJ, S_J F_J B_JJ)``. Enumerated over every subset
    ``J`` and sign pattern (``3^n - 1`` pencils, at most :data:`CRITICAL_ENUMERATION_NODES` nodes).

    Parameters
    ----------
    system : QuasiStaticFrictionSystem

    Returns
    -------
    float
        The critical value of the largest friction coefficient (the others scaled with it);
        ``inf`` for an uncoupled system (``B = 0``) or a coupling that never loses uniqueness.

    Raises
    ------
    ParameterError
        If the system has more than :data:`CRITICAL_ENUMERATION_NODES` nodes.
    """
    if not isinstance(system, QuasiStaticFrictionSystem):
        raise ParameterError(f"system must be a QuasiStaticFrictionSystem, got {type(system).__name__}")
    if system.coupling is None:
        return float("inf")
    n = system.n_nodes
    if n > CRITICAL_ENUMERATION_NODES:
        raise ParameterError(f"critical_friction_coefficient enumerates 3^n pencils: at most "
                             f"{CRITICAL_ENUMERATION_NODES} nodes, the system has {n}")
    f = system.friction_coefficient
    scale = float(np.max(f))
    fb = (f / scale)[:, None] * system.coupling
    k = system.stiffness
    best = float("inf")
    for size in range(1, n + 1):
        for nodes in itertools.combinations(range(n), size):
            idx = np.array(nodes)
            kj, fbj = k[np.ix_(idx, idx)], fb[np.ix_(idx, idx)]
            if not np.any(fbj):
                continue
            for signs in itertools.product((1.0, -1.0), repeat=size):
                lam = scipy.linalg.eigvals(kj, np.asarray(signs)[:, None] * fbj)
                ok = np.isfinite(lam) & (np.abs(lam.imag) <= 1e-8 * np.abs(lam)) & (lam.real > 0)  # (a double root splits by ~sqrt(eps))
                if ok.any():
                    best = min(best, float(np.min(lam.real[ok])))
    return best  # (the pencil scales the profile f / max(f): its eigenvalue is the largest coefficient's)


def melan_check(system: QuasiStaticFrictionSystem, load: PeriodicLoad) -> MelanResult:
    """Frictional Melan theorem: the largest uniform safety margin of a residual slip state.

    Linear programme (``scipy.optimize.linprog``, HiGHS) in ``z = K w_r`` and ``mu``: maximise
    ``mu`` subject to ``|q_ext(t_k) - z| <= (1 - mu) g(t_k)`` at every sample ``t_k``, ``mu <= 1``.
    The load is linear between samples, so the samples suffice (each constraint is linear in
    ``t`` on every piece). With a positive definite ``K`` every residual force ``z`` is reachable,
    so the programme separates node by node: node ``i`` is safe iff
    ``max_t (q_ext,i - g_i) <= min_t (q_ext,i + g_i)``; the LP also returns ``w_r``.

    Parameters
    ----------
    system : QuasiStaticFrictionSystem
    load : PeriodicLoad

    Returns
    -------
    MelanResult
    """
    system._check_load(load)
    q = load.tangential
    g = system.friction_coefficient * load.normal
    m, n = q.shape
    eye = np.tile(np.eye(n), (m, 1))
    gcol = g.reshape(-1, 1)
    a_ub = np.vstack([np.hstack([-eye, gcol]), np.hstack([eye, gcol])])
    b_ub = np.concatenate([(g - q).ravel(), (g + q).ravel()])
    cost = np.zeros(n + 1)
    cost[-1] = -1.0
    bounds = [(None, None)] * n + [(None, 1.0)]
    res = scipy.optimize.linprog(cost, A_ub=a_ub, b_ub=b_ub, bounds=bounds, method="highs")
    if res.status != 0:
        return MelanResult(False, float("nan"), np.full(n, np.nan), False, res.message)
    z, mu = res.x[:n], float(res.x[-1])
    w_r = scipy.linalg.cho_solve(system._cho, z)
    return MelanResult(bool(mu >= -_RTOL), mu, w_r)


def shakedown_check(system: QuasiStaticFrictionSystem, load: PeriodicLoad, initial_slip: ArrayLike | None = None,
                    n_cycles: int = 200, rtol: float = 1e-12, melan: bool = True) -> ShakedownResult:
    """March periods of ``load`` until the response is periodic, and classify it.

    Slip stops (shakedown) when a whole period passes without slip -- the state then repeats
    for ever. Otherwise the march stops at the first period whose end state equals its start
    state to ``rtol`` times the slip scale ``max_t |K^-1 g(t)|``, or whose dissipation is below
    ``rtol`` times the energy scale ``max_t g . K^-1 g`` (shakedown approached geometrically, as in
    a zig-zag towards a corner of the safe region). Above the Melan limit the steady dissipation
    per cycle is the same for every initial state (Andersson et al. 2014, ``B = 0``).

    Parameters
    ----------
    system : QuasiStaticFrictionSystem
    load : PeriodicLoad
    initial_slip : (n,) array_like, optional
        Slips [m] at ``t = 0`` (default 0), within the friction bound at ``t = 0``.
    n_cycles : int
        Most periods to march, >= 1.
    rtol : float
        Relative tolerance of the periodicity test, > 0.
    melan : bool
        Also run :func:`melan_check` (uncoupled systems only: with coupling it is not run).

    Returns
    -------
    ShakedownResult
    """
    system._check_load(load)
    n_cycles = _check_count("n_cycles", n_cycles)
    rtol = check_positive("rtol", rtol)
    w = np.zeros(system.n_nodes) if initial_slip is None else initial_slip
    w = system.check_slip(load, w, "initial_slip")
    g = system.friction_coefficient * load.normal
    kinv_g = scipy.linalg.cho_solve(system._cho, g.T)
    slip_scale = float(np.max(np.abs(kinv_g)))
    energy_scale = float(np.max(np.sum(g.T * kinv_g, axis=0)))
    dissipation, increment = [], []
    status, steady, first = "transient", float("nan"), -1
    cycle = None
    for k in range(n_cycles):
        cycle = system.run_cycle(load, w)
        dissipation.append(cycle.dissipation)
        increment.append(float(np.max(np.abs(cycle.slip_end - w))))
        w = cycle.slip_end
        if not np.any(cycle.slip_variation > 0) or cycle.dissipation <= rtol * energy_scale:
            status, steady, first = "shakedown", 0.0, k
            break
        if increment[-1] <= rtol * slip_scale:
            status, steady, first = "cyclic slip", cycle.dissipation, k
            break
    # (Melan's theorem holds for B = 0 only: a coupled system shakes down or not by its initial state)
    result = ShakedownResult(status, np.array(dissipation), np.array(increment), steady, first, w, cycle,
                             melan_check(system, load) if melan and system.coupling is None else None)
    if status == "transient":
        result.success = False
        result.message = f"no periodic state within {n_cycles} periods"
    return result


def _factor_parts(system, mean_tangential, mean_normal, cyclic_tangential, cyclic_normal, times):
    """The load of seed eq. 5 as arrays: means (n,), cyclic parts (m, n) at ``times``."""
    n = system.n_nodes
    times = _finite_array("times", times, "(m,)")
    m = times.size
    parts = []
    for name, value, shape in (("mean_tangential", mean_tangential, (n,)), ("mean_normal", mean_normal, (n,)),
                               ("cyclic_tangential", cyclic_tangential, (m, n)),
                               ("cyclic_normal", cyclic_normal, (m, n))):
        a = _finite_array(name, value, str(shape))
        if a.shape != shape:
            raise ParameterError(f"{name} must have shape {shape}, got {a.shape}")
        parts.append(a)
    return parts


def factored_load(mean_tangential: ArrayLike, mean_normal: ArrayLike, cyclic_tangential: ArrayLike,
                  cyclic_normal: ArrayLike, times: ArrayLike, period: float, load_factor: float) -> PeriodicLoad:
    """The load of seed eq. 5: ``mean + load_factor * cyclic(t)``, linear between the samples.

    Parameters
    ----------
    mean_tangential, mean_normal : (n,) array_like
        Mean welded tangential and normal nodal forces ``q_0``, ``N_0`` [N].
    cyclic_tangential, cyclic_normal : (m, n) array_like
        Cyclic parts ``q_1(t)``, ``N_1(t)`` [N] at ``times`` (normalised, zero mean).
    times : (m,) array_like
        Sample times [s] (as :class:`PeriodicLoad`'s).
    period : float
        Period [s].
    load_factor : float
        ``lambda`` [-]; the normal force must stay > 0.

    Returns
    -------
    PeriodicLoad
    """
    lam = float(load_factor)
    if not np.isfinite(lam):
        raise ParameterError(f"load_factor must be finite, got {load_factor!r}")
    q0, n0, q1, n1 = (np.asarray(a, dtype=float) for a in (mean_tangential, mean_normal, cyclic_tangential,
                                                            cyclic_normal))
    return PeriodicLoad(times, q0 + lam * q1, n0 + lam * n1, period)


def critical_load_factors(system: QuasiStaticFrictionSystem, mean_tangential: ArrayLike, mean_normal: ArrayLike,
                          cyclic_tangential: ArrayLike, cyclic_normal: ArrayLike, times: ArrayLike,
                          period: float) -> CriticalLoadFactors:
    """Critical load factors ``lambda1 <= lambda2`` of the load ``mean + lambda cyclic(t)`` (seed Sec. 3.3).

    A node ``i`` sticks while ``(f B_i - K_i) w <= f N_i - q_i`` and ``(K_i + f B_i) w <= f N_i + q_i``;
    with the load linear between its samples, each constraint's tightest position over the cycle is
    at a sample, ``c + lambda d`` with ``d`` the minimum over the samples of the cyclic part's
    right-hand side (``lambda >= 0``): the ``2N`` extreme constraints ``R w <= c + lambda d``.

    - ``lambda2``: the largest ``lambda`` for which some ``w`` satisfies them all (a linear programme
      in ``(w, lambda)``, HiGHS): above it no slip state stays stuck, so nothing shakes down.
    - ``lambda1``: the largest ``lambda`` below which every extreme constraint is a facet of the safe
      region (each one cuts the region of the others: one small programme per constraint, bisected
      on ``lambda``); 0, with a message, where one is redundant already at ``lambda = 0``. For two
      nodes the seed's enumeration of the ``2^(N-1) N`` vertices gives it again
      (``lambda1_enumerated``) and ``lambda2`` too (``lambda2_enumerated``).

    For ``B = 0`` a node's two constraints are parallel, and both factors are the Melan limit.

    Parameters
    ----------
    system : QuasiStaticFrictionSystem
    mean_tangential, mean_normal : (n,) array_like
        Mean welded nodal forces ``q_0``, ``N_0`` [N].
    cyclic_tangential, cyclic_normal : (m, n) array_like
        Cyclic parts ``q_1(t)``, ``N_1(t)`` [N] at ``times``.
    times : (m,) array_like
        Sample times [s] of one period (the cyclic part is linear between them and periodic).
    period : float
        Period [s] (the times' span; only checked, the extremes are at the samples).

    Returns
    -------
    CriticalLoadFactors
    """
    if not isinstance(system, QuasiStaticFrictionSystem):
        raise ParameterError(f"system must be a QuasiStaticFrictionSystem, got {type(system).__name__}")
    q0, n0, q1, n1 = _factor_parts(system, mean_tangential, mean_normal, cyclic_tangential, cyclic_normal, times)
    PeriodicLoad(times, q0 + 0 * q1, n0 + 0 * n1, period)  # the times and period as a load's
    f = system.friction_coefficient
    rows = _constraint_rows(system)
    c = np.concatenate([f * n0 - q0, f * n0 + q0])
    d = np.concatenate([np.min(f * n1 - q1, axis=0), np.min(f * n1 + q1, axis=0)])
    n = system.n_nodes
    # scaled (the programmes' tolerances are absolute): rows by their largest entry, c and d by theirs
    rs = float(np.max(np.abs(rows))) or 1.0
    cs = max(float(np.max(np.abs(c))), float(np.max(np.abs(d)))) or 1.0
    rows_s, c_s, d_s = rows / rs, c / cs, d / cs
    # lambda2: maximise lambda subject to rows w - lambda d <= c
    res = scipy.optimize.linprog(np.r_[np.zeros(n), -1.0], A_ub=np.hstack([rows_s, -d_s[:, None]]), b_ub=c_s,
                                 bounds=[(None, None)] * n + [(0.0, None)], method="highs")
    if res.status == 3:  # unbounded: every lambda keeps a stuck state (the cyclic part never tightens)
        lambda2, safe = float("inf"), np.full(n, np.nan)
    elif res.status != 0:
        return CriticalLoadFactors(float("nan"), float("nan"), float("nan"), np.full(n, np.nan), success=False,
                                   message=res.message)
    else:
        lambda2, safe = float(res.x[-1]), res.x[:n] * cs / rs
    lambda1, message = _first_lost_facet(rows_s, c_s, d_s, lambda2)
    enumerated = (float("nan"), float("nan"))
    if n == 2:  # the seed's vertex rule: exact for two nodes (in 3D and up an edge can collapse first)
        enumerated = _enumerate_load_factors(rows_s, c_s, d_s, n)
    return CriticalLoadFactors(lambda1, lambda2, enumerated[1], safe, lambda1_enumerated=enumerated[0],
                               message=message)


def _cuts(rows, bound, k) -> bool:
    """Whether constraint ``k`` cuts the region of the others (a facet of the region): the largest
    ``rows[k] @ w`` over the others' region exceeds ``bound[k]`` (or is unbounded)."""
    others = np.delete(np.arange(len(bound)), k)
    res = scipy.optimize.linprog(-rows[k], A_ub=rows[others], b_ub=bound[others],
                                 bounds=[(None, None)] * rows.shape[1], method="highs")
    if res.status == 3:
        return True
    if res.status != 0:  # the others leave no room: nothing is a facet
        return False
    return -res.fun > bound[k] + 1e-12 * (1.0 + abs(bound[k]))


def _first_lost_facet(rows, c, d, lambda2):
    """``(lambda1, message)``: the largest ``lambda`` in ``[0, lambda2]`` below which every one of the
    ``2N`` extreme constraints is a facet of the safe region (seed Sec. 3.3: shakedown from every initial
    state), by bisection to 1e-12 of ``lambda2`` on one small programme per constraint (the facets are
    lost once, as the region shrinks with ``lambda``); 0 where a constraint is redundant already at
    ``lambda = 0``."""
    def all_facets(lam):
        return all(_cuts(rows, c + lam * d, k) for k in range(len(c)))

    if not all_facets(0.0):
        return 0.0, ("an extreme constraint is redundant already at lambda = 0: some initial states cannot "
                     "reach the safe region at any load factor")
    if not np.isfinite(lambda2):
        return float("inf"), "ok"
    lo, hi = 0.0, lambda2
    while hi - lo > 1e-12 * lambda2:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if all_facets(mid) else (lo, mid)
    return lo, "ok"


def _enumerate_load_factors(rows, c, d, n):
    """``(lambda1, lambda2)`` from the seed's enumeration: every node ``j`` with both constraints and
    one constraint of each other node, as equalities (``N + 1`` equations in ``w`` and ``lambda``).
    ``lambda1``: the least ``lambda >= 0`` found; ``lambda2``: the largest one whose point satisfies
    every extreme constraint (the safe region's last point). Used for two nodes, where a vertex is
    where a facet vanishes (for three and more an edge can collapse first: the least value is then a
    lower bound of ``lambda1``)."""
    scale = float(np.max(np.abs(rows))) + 1e-300
    tol = 1e-9 * (float(np.max(np.abs(c))) + float(np.max(np.abs(d))) + 1e-300)
    lambdas, feasible = [], []
    for j in range(n):
        others = [i for i in range(n) if i != j]
        for choice in itertools.product((0, 1), repeat=n - 1):
            sel = [j, n + j] + [i + n * side for i, side in zip(others, choice)]
            a = np.hstack([rows[sel], -d[sel, None]])
            try:
                sol = np.linalg.solve(a, c[sel])
            except np.linalg.LinAlgError:
                continue
            if not np.all(np.isfinite(sol)) or np.linalg.cond(a) > 1e12 * max(1.0, scale):
                continue
            lam = float(sol[-1])
            if lam < 0:
                continue
            lambdas.append(lam)
            if np.all(rows @ sol[:n] - lam * d <= c + tol):
                feasible.append(lam)
    lambda1 = min(lambdas) if lambdas else float("inf")
    lambda2 = max(feasible) if feasible else float("nan")
    return lambda1, lambda2


def _constraint_rows(system: QuasiStaticFrictionSystem) -> np.ndarray:
    """``(2n, n)``: node ``i`` sticks while ``(f B_i - K_i) w <= f N_ext,i - q_ext,i`` (rows ``0..n-1``,
    its force at ``+g``) and ``(K_i + f B_i) w <= f N_ext,i + q_ext,i`` (rows ``n..2n-1``, at ``-g``)."""
    f, k = system.friction_coefficient, system.stiffness
    fb = np.zeros_like(k) if system.coupling is None else f[:, None] * system.coupling
    return np.vstack([fb - k, k + fb])


def extreme_constraints(system: QuasiStaticFrictionSystem, load: PeriodicLoad) -> tuple[np.ndarray, np.ndarray]:
    """The ``2N`` extreme friction constraints of a load (seed Sec. 3.1): ``rows @ w <= bound``.

    Node ``i``'s two constraints (its tangential force reaching ``+f N_i`` and ``-f N_i``) move with
    the load and keep their slope; the extreme one excludes the most slip space over the cycle, at a
    sample (the load is linear between them). The slips that satisfy all ``2N`` stay stuck for the
    whole cycle: the safe shakedown region of Ahn's diagram.

    Parameters
    ----------
    system : QuasiStaticFrictionSystem
    load : PeriodicLoad

    Returns
    -------
    rows : (2n, n) ndarray
        Rows ``0 .. n-1``: node ``i`` at ``q_i = +f N_i``; rows ``n .. 2n-1``: at ``q_i = -f N_i`` [N/m].
    bound : (2n,) ndarray
        Their tightest right-hand sides over the samples [N].
    """
    system._check_load(load)
    f = system.friction_coefficient
    q, n = load.tangential, load.normal
    bound = np.concatenate([np.min(f * n - q, axis=0), np.min(f * n + q, axis=0)])
    return _constraint_rows(system), bound
