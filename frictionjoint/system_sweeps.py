"""Stepped-sine sweeps of a multi-DOF friction system: :func:`system_sweep`, the periodic steady
state of ``build(omega)`` at each frequency started from the previous orbit, and
:func:`peak_response`, a resonance peak bracketed by such a sweep and refined.

They need a :class:`~frictionjoint.system.FrictionSystem` and the marcher only, and sit below the
blade assembly (:class:`~frictionjoint.structures.BladeAssembly`, whose sweeps they run) and below the
one entry point :func:`frictionjoint.sweep.sweep`, which hands them a ``build`` callable and
re-exports them: imports point down.
"""
from __future__ import annotations

import math
import sys
from typing import Callable

import numpy as np
from numpy.typing import ArrayLike

from .errors import ParameterError, check_count, check_positive, check_system
from .frequencies import check_omegas
from .results.frequency import SystemSweep
from .system import FrictionSystem
from .threads import owns_blas_threads

__all__ = ["system_sweep", "peak_response"]


def _check_build(build) -> None:
    if not callable(build):
        raise ParameterError(f"build must be a callable build(omega) -> FrictionSystem, got {build!r}")


@owns_blas_threads
def system_sweep(build: Callable, omegas: ArrayLike, progress: bool = False, peaks: bool = True) -> SystemSweep:
    """Periodic steady state of ``build(omega)`` at each ``omega`` [rad/s], in the given order,
    each started from the previous orbit (its state at ``t = 0``).

    Parameters
    ----------
    build : callable
        ``build(omega) -> FrictionSystem`` with harmonic excitation at ``omega``.
    omegas : str or sequence of float
        Angular frequencies [rad/s], > 0: ``"START:STOP:N"`` or the frequencies themselves
        (:mod:`frictionjoint.frequencies`; ``(start, stop, n)`` is refused as ambiguous).
    progress : bool
        Show a progress bar.
    peaks : bool
        Locate each orbit's displacement peaks (``amplitude``); false: NaN there but on stuck
        orbits, the first harmonics only (:func:`~frictionjoint.solvers.marcher.steady.periodic_response`).

    Returns
    -------
    SystemSweep
        One row per frequency, in the order of ``omegas``.
    """
    from tqdm import tqdm

    from .solvers.frequency_domain.hbm import lyapunov_stable
    from .solvers.steady_state import periodic_response

    _check_build(build)
    ws = check_omegas("omegas", omegas)
    rows = []
    z = None
    for w in tqdm(ws, desc="sweep", unit="pt", file=sys.stderr, disable=not progress, leave=False):
        system = check_system("build(omega)", build(float(w)), FrictionSystem)
        n = system.n_dof
        if z is None or not np.all(np.isfinite(z)):
            r = periodic_response(system, peaks=peaks)
        else:
            r = periodic_response(system, z[:n], z[n:2 * n], z[2 * n:] if z.size > 2 * n else None, peaks=peaks)
            if not r.converged:
                # the previous orbit is one guess; rest is the other (near a stuck resonance the
                # stuck orbits form a neutral family, and the neighbour's member can graze the
                # slip limit where the period map is not smooth: shooting from it fails)
                r = periodic_response(system, peaks=peaks)
        z = r.initial_state if r.converged else None
        rows.append(r)
    return SystemSweep(
        omega=ws, amplitude=np.array([r.amplitude for r in rows]),
        harmonic_amplitude=np.array([r.harmonic_amplitude for r in rows]),
        phase=np.array([r.phase for r in rows]),
        dissipated_per_cycle=np.array([r.dissipated_per_cycle for r in rows]),
        stuck=np.array([r.stuck for r in rows]), converged=np.array([r.converged for r in rows]),
        messages=tuple(r.message for r in rows), stable=np.array([lyapunov_stable(r) for r in rows], dtype=object))


def peak_response(build: Callable, omega_min: float, omega_max: float, dof: int = 0, n_grid: int = 25,
                  xtol: float = 1e-6, output: ArrayLike | None = None,
                  peaks: bool = True) -> tuple[float, float, SystemSweep]:
    """Resonance peak of the first-harmonic amplitude of DOF ``dof`` (or of the output ``output .
    x``) over ``[omega_min, omega_max]``.

    A stepped sweep over ``n_grid`` frequencies brackets the largest amplitude, then a bounded
    scalar search (Brent) refines it to ``xtol`` relative in ``omega``.

    Parameters
    ----------
    build : callable
        ``build(omega) -> FrictionSystem`` with harmonic excitation at ``omega`` [rad/s].
    omega_min, omega_max : float
        Frequency interval [rad/s], ``0 < omega_min < omega_max``.
    dof : int
        Index of the DOF whose first-harmonic amplitude is maximised, in ``[0, n_dof)``.
    n_grid : int
        Equally spaced frequencies of the bracketing sweep, >= 3.
    xtol : float
        Tolerance of the search relative in ``omega`` [-], in ``(0, 1)``.
    output : (n_dof,) array_like, optional
        Coefficients of an output linear in the DOFs (e.g. a blade tip recovered from a reduced
        model), maximised instead of DOF ``dof``.
    peaks : bool
        Locate the displacement peaks of the bracketing sweep's orbits (its ``amplitude``;
        :func:`system_sweep`); the search itself needs the first harmonics only.

    Returns
    -------
    (omega_peak, amplitude_peak, sweep) : (float, float, SystemSweep)
        The peak [rad/s], its first-harmonic amplitude [m] and the bracketing sweep.
    """
    import scipy.optimize

    lo = check_positive("omega_min", omega_min)
    hi = check_positive("omega_max", omega_max)
    if not hi > lo:
        raise ParameterError(f"omega_max must be > omega_min = {lo:g}, got {hi!r}")
    n_grid = check_count("n_grid", n_grid, 3)
    xtol = check_positive("xtol", xtol)
    if not xtol < 1:
        raise ParameterError(f"xtol must be in (0, 1) (relative in omega), got {xtol!r}")
    dof = check_count("dof", dof, 0)
    _check_build(build)
    n_dof = check_system("build(omega)", build(lo), FrictionSystem).n_dof
    if dof >= n_dof:
        raise ParameterError(f"dof must be in [0, {n_dof - 1}] (the system's DOFs), got {dof}")
    if output is not None:
        row = np.asarray(output, dtype=float).reshape(-1)
        if row.shape != (n_dof,) or not np.all(np.isfinite(row)) or not np.any(row):
            raise ParameterError(f"output must be {n_dof} finite coefficients, not all zero")

    def first_harmonic(sw):  # per point: DOF dof's amplitude, or |row . X|
        return sw.harmonic_amplitude[:, dof] if output is None else np.abs(sw.harmonics @ row)

    grid = np.linspace(lo, hi, n_grid)
    sw = system_sweep(build, grid, peaks=peaks)
    # a frequency without a periodic orbit has no amplitude (NaN): it must not win the argmax, nor
    # steer the search (there it counts as zero)
    amps = np.where(sw.converged, first_harmonic(sw), -np.inf)
    if not np.any(sw.converged):
        return math.nan, math.nan, sw
    i = int(np.argmax(amps))
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]

    def neg(w):
        one = system_sweep(build, [w], peaks=False)  # harmonics only
        return -float(first_harmonic(one)[0]) if one.converged[0] else 0.0

    res = scipy.optimize.minimize_scalar(neg, bounds=(a, b), method="bounded",
                                         options={"xatol": xtol * b})
    if -res.fun >= amps[i]:
        return float(res.x), float(-res.fun), sw
    return float(grid[i]), float(amps[i]), sw
