"""Stop regimes of the single-DOF Coulomb oscillator: Hong & Liu's map over (F/P0, r).

For ``m x'' + k x + F sgn(x') = P0 cos(w t)`` with ``m = k = P0 = 1`` (so ``w = r`` and
``F = f``) the periodic steady state is computed exactly at every grid point
(:meth:`frictionjoint.CoulombOscillator.steady_state`) and classified by the number of stops
of finite duration per cycle: zero (Den Hartog's continuous motion), one (odd counts exist),
two, four, ..., permanent stick; unbounded growth (resonance with ``f < pi/4``) and points
where no periodic orbit was found are marked separately (DESIGN.md section 3).

References
----------
J.-H. Hong and C.-S. Liu, "Coulomb friction oscillator: modelling and responses to harmonic
loads and base excitations", J. Sound Vib. 229 (2000) 1171-1192.
"""
from __future__ import annotations

import math
import os
import sys
import warnings

import numpy as np
from numpy.typing import ArrayLike

from .errors import ParameterError, check_grid
from .frequencies import check_omegas
from .results.regime_map import RegimeMap

__all__ = ["RegimeMap", "regime_map", "classify", "REGIMES"]

#: Regime words, shared with :mod:`frictionjoint.analytic` (plus ``'not converged'``).
REGIMES = ("stop-free", "stops", "stuck", "unbounded", "not converged")


def classify(response) -> str:
    """Regime word of a :class:`~frictionjoint.results.PeriodicResponse`.

    Parameters
    ----------
    response : PeriodicResponse
        Result of :meth:`~frictionjoint.CoulombOscillator.steady_state`.

    Returns
    -------
    str
        One of :data:`REGIMES`: ``'stop-free'``, ``'stops'`` (at least one stop of finite
        duration per cycle), ``'stuck'`` (nothing slips over the period), ``'unbounded'``
        (growth without bound) or ``'not converged'``.
    """
    if response.status != "periodic":  # 'unbounded', 'not converged' or 'failed' (the march)
        return "not converged" if response.status == "failed" else response.status
    if response.stuck:
        return "stuck"
    return "stops" if response.stops_per_cycle > 0 else "stop-free"




_FAILED = "steady-state solver failed"


def _point(args):
    """Steady state at one grid point (module level so that worker processes can run it)."""
    from .oscillator import CoulombOscillator

    f, r = args
    osc = CoulombOscillator(mass=1.0, stiffness=1.0, slip_force=f, force_amplitude=1.0, omega=r)
    ss = osc.steady_state()
    if ss.status == "failed":  # the march failed: a status of the result
        return "not converged", -1, False, True, 0.0, f"{_FAILED}: {ss.message}"
    regime = classify(ss)
    return regime, int(ss.stops_per_cycle), bool(ss.converged), bool(ss.unique), float(ss.periods), ss.message




def regime_map(friction_ratios: ArrayLike, frequency_ratios: ArrayLike, progress: bool = False,
               jobs: int = 1) -> RegimeMap:
    """Hong & Liu's map of the number of stops per cycle over ``(F/P0, r)``.

    Every grid point is an independent steady-state computation for ``m = k = P0 = 1``
    (``omega = r``, ``slip_force = f``), started from the one-harmonic estimate, so the map does
    not depend on the order of the grid. The cost is roughly 0.05-0.15 s per point (more at small
    ``r``, where the motion has many events per period).

    Parameters
    ----------
    friction_ratios : (n_f,) array_like
        ``f = F/P0`` [-], each >= 0.
    frequency_ratios : str or (n_r,) array_like
        ``r = w/wn`` [-], each > 0 (``omega = r`` rad/s): ``"START:STOP:N"`` or the ratios themselves,
        as every frequency grid (:mod:`frictionjoint.frequencies`; ``(0.1, 2.0, 39)`` is refused
        as ambiguous).
    progress : bool
        Show a progress bar (tqdm, on stderr).
    jobs : int
        Worker processes (>= 1); 1 computes in this process.

    Returns
    -------
    RegimeMap

    Raises
    ------
    ParameterError
        If a ratio is negative (``f``), non-positive (``r``) or not finite, or ``jobs < 1``.
    """
    fs = check_grid("friction_ratios", friction_ratios, positive=False)
    rs = check_omegas("frequency_ratios", frequency_ratios)  # omega = r rad/s here
    if not isinstance(progress, (bool, np.bool_)):
        raise ParameterError(f"progress must be True or False, got {progress!r}")
    if isinstance(jobs, bool) or not isinstance(jobs, (int, np.integer)) or jobs < 1:
        raise ParameterError(f"jobs must be an integer >= 1, got {jobs!r}")
    from tqdm import tqdm

    points = [(float(f), float(r)) for f in fs for r in rs]
    bar = tqdm(total=len(points), desc="regime map", unit="pt", file=sys.stderr,
               disable=not progress, leave=False)
    results = []
    try:
        if jobs == 1 or len(points) < 4:
            for p in points:
                results.append(_point(p))
                bar.update()
        else:
            from concurrent.futures import ProcessPoolExecutor

            chunk = max(1, math.ceil(len(points) / (8 * jobs)))
            with ProcessPoolExecutor(max_workers=min(jobs, os.cpu_count() or 1)) as pool:
                for res in pool.map(_point, points, chunksize=chunk):
                    results.append(res)
                    bar.update()
    finally:
        bar.close()
    failed = [(p, res[5]) for p, res in zip(points, results) if res[5].startswith(_FAILED)]
    if failed:
        (f, r), msg = failed[0]
        warnings.warn(f"{len(failed)} point(s) of the regime map marked 'not converged' after a "
                      f"solver failure, e.g. F/P0 = {f!r}, r = {r!r}: {msg}", RuntimeWarning,
                      stacklevel=2)
    shape = (fs.size, rs.size)
    regime = np.array([res[0] for res in results], dtype=object).reshape(shape).astype(str)
    stops = np.array([res[1] for res in results], dtype=int).reshape(shape)
    stops[~np.isin(regime, ("stop-free", "stops"))] = -1
    return RegimeMap(
        friction_ratios=fs, frequency_ratios=rs, regime=regime, stops_per_cycle=stops,
        converged=np.array([res[2] for res in results], dtype=bool).reshape(shape),
        unique=np.array([res[3] for res in results], dtype=bool).reshape(shape),
        periods=np.array([res[4] for res in results], dtype=float).reshape(shape),
        messages=np.array([res[5] for res in results], dtype=object).reshape(shape).astype(str),
    )
