"""Results of the quasi-static shakedown analysis (:mod:`frictionjoint.shakedown`): one marched
period, the frictional Melan check, and the shakedown verdict."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import numpy as np

__all__ = ["CycleResult", "MelanResult", "ShakedownResult", "CriticalLoadFactors"]


@dataclass
class CycleResult:
    """One period of the exact quasi-static march.

    Attributes
    ----------
    slip_at_samples : (m+1, n) ndarray
        Slips ``w`` [m] at the sample times and at the end of the period.
    dissipation : float
        Energy dissipated by friction over the period [J].
    slip_variation : (n,) ndarray
        ``int |w_i'| dt`` over the period [m] (0: node ``i`` did not slip).
    work : float
        Work of the load, ``int q . K^-1 q_ext' dt`` [J].
    stored_energy_change : float
        Change of ``q . K^-1 q / 2`` over the period [J]; ``work = stored_energy_change + dissipation``.
    n_events : int
        Pieces of constant slip rates marched.
    success, status, message
        The result contract: a marched period is exact (a march that cannot go on raises
        :class:`~frictionjoint.errors.ConvergenceError` inside :func:`shakedown_check`, which
        reports it as its own status).
    """

    slip_at_samples: np.ndarray
    dissipation: float
    slip_variation: np.ndarray
    work: float
    stored_energy_change: float
    n_events: int
    success: bool = True
    status: str = "ok"
    message: str = "ok"

    @property
    def slip_end(self) -> np.ndarray:
        """Slips [m] at the end of the period, (n,)."""
        return self.slip_at_samples[-1]


@dataclass
class MelanResult:
    """Frictional Melan check: is there a residual slip that keeps the load inside the friction cone?

    Attributes
    ----------
    safe : bool
        ``margin >= 0``: a residual slip ``w_r`` exists with ``|q_ext(t) - K w_r| <= g(t)`` for all
        ``t``. For ``B = 0``, ``margin > 0`` means shakedown from every initial state (Klarbring et al.
        2007); ``margin < 0`` means cyclic slip from every initial state.
    margin : float
        Largest ``mu <= 1`` with ``|q_ext(t) - K w_r| <= (1 - mu) g(t)`` for all ``t`` [-].
    residual_slip : (n,) ndarray
        The ``w_r`` [m] attaining ``margin``.
    success : bool
        The linear programme was solved.
    status : str
        ``'safe'``, ``'unsafe'`` or ``'failed'`` (the programme; ``message`` says why).
    message : str
    """

    safe: bool
    margin: float
    residual_slip: np.ndarray
    success: bool = True
    message: str = "ok"

    @property
    def status(self) -> str:
        """``'safe'``, ``'unsafe'`` or ``'failed'``."""
        return "failed" if not self.success else ("safe" if self.safe else "unsafe")


@dataclass
class ShakedownResult:
    """Outcome of :func:`shakedown_check`.

    Attributes
    ----------
    status : str
        ``'shakedown'`` (a whole period without slip: slip has stopped for good),
        ``'cyclic slip'`` (the state repeats after a period and the period dissipates energy) or
        ``'transient'`` (neither within ``n_cycles``).
    shakedown : bool
        ``status == 'shakedown'``.
    dissipation : (n_run,) ndarray
        Energy dissipated in each period marched [J].
    slip_increment : (n_run,) ndarray
        ``max_i |w_i(end) - w_i(start)|`` of each period [m].
    steady_dissipation : float
        Dissipation per period in the steady state [J] (0 after shakedown; ``nan`` if transient).
    steady_cycle : int
        Index of the first period of the steady state (-1 if transient).
    final_slip : (n,) ndarray
        Slips [m] at the end of the last period.
    last_cycle : CycleResult
    melan : MelanResult or None
    success : bool
    message : str
    """

    status: str
    dissipation: np.ndarray
    slip_increment: np.ndarray
    steady_dissipation: float
    steady_cycle: int
    final_slip: np.ndarray
    last_cycle: CycleResult
    melan: Optional[MelanResult] = None
    success: bool = True
    message: str = "ok"

    @property
    def shakedown(self) -> bool:
        return self.status == "shakedown"

    @property
    def stuck_nodes(self) -> np.ndarray:
        """The nodes that did not slip in the last period marched (indices): in a steady state the
        permanent stick set (seed Sec. 2.7), where a coupled system keeps its memory (Sec. 3)."""
        variation = self.last_cycle.slip_variation
        scale = float(np.max(np.abs(self.last_cycle.slip_at_samples))) + float(np.max(variation))
        return np.flatnonzero(variation <= 1e-12 * scale)  # (a slip at rounding level is none)




@dataclass
class CriticalLoadFactors:
    """Critical load factors of a load ``mean + lambda cyclic(t)`` (seed eq. 5, Sec. 3.3).

    Attributes
    ----------
    lambda1 : float
        Below it the system shakes down from every initial state: the largest ``lambda`` below which
        every extreme friction constraint is a facet of the safe region (0 where one is redundant at
        ``lambda = 0``: ``message`` says so).
    lambda2 : float
        Above it no initial state shakes down: the largest ``lambda`` for which a slip state keeps
        every node stuck for the whole cycle (a linear programme).
    lambda2_enumerated : float
        Two nodes: ``lambda2`` from the seed's enumeration of the ``2^(N-1) N`` vertices (a check of
        the programme); ``nan`` otherwise.
    safe_slip : (n,) ndarray
        A slip state [m] that stays stuck at ``lambda2`` (the programme's).
    lambda1_enumerated : float
        Two nodes: ``lambda1`` from the same enumeration (where every constraint is a facet at
        ``lambda = 0``); ``nan`` otherwise.
    success : bool
    status : str
        ``'ok'`` or ``'failed'`` (the programme; ``message`` says why).
    message : str
    """

    lambda1: float
    lambda2: float
    lambda2_enumerated: float
    safe_slip: np.ndarray
    lambda1_enumerated: float = float("nan")
    success: bool = True
    message: str = "ok"

    @property
    def status(self) -> str:
        """``'ok'`` or ``'failed'``."""
        return "ok" if self.success else "failed"
