"""Work-precision benchmark of the single-DOF Coulomb oscillator: run time against error.

The task
--------
``m x'' + k x + F sgn(x') = P0 cos(w t)`` with ``m = k = P0 = 1`` (so ``r = w`` and ``f = F``):
compute the **amplitude of the periodic steady state**, ``A = max |x|`` over one period of the
periodic orbit. The error of a method is ``|A_method / A_ref - 1|``. Cases (:data:`CASES`):

- ``r = 0.8`` and ``r = 1.5`` at ``F/P0 = 0.3``: stop-free motion, ``A_ref`` is Den Hartog's
  closed form (:func:`frictionjoint.analytic.den_hartog_response`);
- ``r = 2.0``, ``F/P0 = 0.6``: two stops per cycle (Den Hartog's form is real there but not the
  motion), ``A_ref`` is the exact orbit of :meth:`~frictionjoint.CoulombOscillator.steady_state`
  shot to ``tol = 1e-13`` (rounding-level; the independent event-driven ``solve_ivp`` rows of the
  table converge to it).

The protocol
------------
The time-marching methods -- the exact marcher and the scipy baselines -- all start from the
same state, the reference orbit's ``(x, v)`` at ``t = 0`` (favourable to the baselines: none of
them has to march a transient, so the speed ratios are conservative), integrate
:data:`PERIODS` excitation periods and report the largest ``|x|`` over the last one: at the
turning points ``v = 0`` and at the two ends of the period. Every method locates the turning
points exactly within its own model: the marcher stops at every ``v = 0`` (an event), the scipy
baselines find ``v = 0`` as an event, by root finding on the solver's dense output (never by
sampling). Timings include everything from the parameters to the amplitude (building the
system, the marcher's decompositions); each is the best of several repeats in one process, and
the marcher -- the denominator of every ratio -- is timed both first and last on each case.

Methods (``method`` column):

- ``exact marcher``: :class:`frictionjoint.solvers.marcher.events.Marcher`, the general n-DOF marcher:
  closed form between events, no tolerance to set (one setting);
- ``exact SDOF kernel``: :class:`frictionjoint.solvers.sdof.kernel.SdofCoulomb`, the dedicated
  single-DOF closed-form kernel (pure-Python scalar maths, certified event location): the same
  motion and events as the general marcher, no tolerance to set (one setting);
- ``steady_state``: :meth:`CoulombOscillator.steady_state` **from rest** (shooting on the period
  map, its own transient included), at several ``tol``;
- ``FMU sweep``: :func:`frictionjoint.sweep.sweep` of one frequency through
  ``CoulombOscillator.fmu`` (fmpy, in this process, instantiation included; shooting from the
  one-harmonic guess), at several ``n_samples`` (samples per period for the harmonics; the peak is
  exact whatever the number);
- ``describing function``: the one-harmonic balance ``|k - m w^2 + i 4F/(pi X)| X = P0``, closed
  form (:func:`frictionjoint.analytic.harmonic_balance_amplitude`): an approximation whose error
  no setting can reduce;
- ``harmonic balance``: :func:`frictionjoint.harmonic_balance` with ``H`` harmonics (exact
  hysteresis: the friction force's Fourier coefficients integrated between its reversals in closed
  form), the peak of the reconstructed period; a rigid Coulomb slider in continuous sliding, so
  the case with stops is out of its model whatever ``H`` (its error stays);
- ``tanh RK45``/``tanh LSODA``/``tanh Radau``: the baseline a user writes, friction
  ``F tanh(v/eps)`` in :func:`scipy.integrate.solve_ivp` at several widths ``eps`` (in units of
  ``wn P0/k``) and ``rtol`` (``atol = rtol`` times the displacement and velocity scales; the
  implicit methods get the exact Jacobian). A run that needs more than
  ``max_evaluations`` right-hand sides (a stiff stuck phase for an explicit method) is stopped
  and reported as given up;
- ``events DOP853``: exact Coulomb law in ``solve_ivp`` (DOP853) phase by phase, a terminal event
  at ``v = 0`` and Hong & Liu's rule there (stick while ``|P0 cos wt - k x| <= F``, the end of a
  stick found by Brent's method on that force), at several ``rtol`` down to the smallest scipy
  accepts.
  This is a timed baseline (what a careful user writes), not a reference: the one brute-force
  reference of the tests and benchmarks is :mod:`bruteforce` (``benchmarks/bruteforce.py``:
  fixed rtol 1e-12, a step bound, double crossings inside a step found), against which the
  stop-case reference orbit is checked (``tests/test_benchmark.py``).

Matched accuracy (:meth:`WorkPrecision.headline`): the time of the fastest exact marching row (the
SDOF kernel or the general marcher, named in the headline) is compared with the fastest scipy
baseline setting whose error is at most that row's; when no baseline gets there, with the most
accurate baseline setting, and the headline says so. The CSV's ``ratio_to_marcher`` stays the
ratio to the general ``exact marcher``; both exact rows are timed first and again last on each
case (best of both).
"""
from __future__ import annotations

import csv
import datetime
import math
import os
import platform
import sys
import time
from dataclasses import dataclass, field, replace
from typing import Callable, Optional

import numpy as np
import scipy
import scipy.optimize
from scipy.integrate import solve_ivp

from frictionjoint.analytic import den_hartog_response, harmonic_balance_amplitude
from frictionjoint.errors import ParameterError
from frictionjoint.oscillator import CoulombOscillator
from frictionjoint.solvers.marcher.events import Marcher
from frictionjoint.solvers.sdof.kernel import SdofCoulomb

__all__ = ["Case", "Problem", "Row", "WorkPrecision", "CASES", "PERIODS", "COLUMNS",
           "make_problem", "marcher_amplitude", "sdof_amplitude", "steady_state_amplitude",
           "describing_function_amplitude", "hbm_amplitude", "fmu_sweep_amplitude", "regularised_amplitude",
           "event_driven_amplitude", "plan", "run_benchmark", "machine_description", "EXACT_METHODS",
           "script_header", "write_results"]

#: Excitation periods marched by the time-marching methods; the amplitude is taken over the last.
PERIODS = 2
#: Columns of the CSV file, in order.
COLUMNS = ("case", "frequency_ratio", "friction_ratio", "reference", "method", "setting", "amplitude",
           "relative_error", "time_s", "ratio_to_marcher", "repeats", "status")
#: Smallest rtol scipy's Runge-Kutta methods accept (100 eps, rounded up).
RTOL_MIN = 2.3e-14
SCIPY_METHODS = ("tanh RK45", "tanh LSODA", "tanh Radau", "events DOP853")
MARCHER = "exact marcher"
SDOF = "exact SDOF kernel"
#: The exact marching methods (no setting): candidates for the headline.
EXACT_METHODS = (MARCHER, SDOF)


@dataclass(frozen=True)
class Case:
    """One oscillator of the benchmark (``m = k = P0 = 1``).

    Attributes
    ----------
    frequency_ratio, friction_ratio : float
        ``r = w/wn`` and ``f = F/P0`` [-].
    """

    frequency_ratio: float
    friction_ratio: float

    @property
    def label(self) -> str:
        """``'r=0.8 f=0.3'``."""
        return f"r={self.frequency_ratio:g} f={self.friction_ratio:g}"


#: The three cases: two stop-free (Den Hartog), one with stops (exact converged orbit).
CASES = (Case(0.8, 0.3), Case(1.5, 0.3), Case(2.0, 0.6))


@dataclass(frozen=True)
class Problem:
    """A case with its reference answer and the common start.

    Attributes
    ----------
    case : Case
    mass, stiffness, slip_force, force_amplitude, omega : float
        ``m`` [kg], ``k`` [N/m], ``F`` [N], ``P0`` [N], ``w`` [rad/s].
    x0, v0 : float
        State of the reference orbit at ``t = 0`` [m, m/s]: the common start of the marching
        methods.
    reference : float
        Reference amplitude ``max |x|`` [m].
    reference_name : str
        Where the reference comes from.
    regime : str
        Regime of Den Hartog's closed form (``'stop-free'``: it is the motion).
    """

    case: Case
    mass: float
    stiffness: float
    slip_force: float
    force_amplitude: float
    omega: float
    x0: float
    v0: float
    reference: float
    reference_name: str
    regime: str

    @property
    def period(self) -> float:
        """Excitation period ``2 pi/w`` [s]."""
        return 2 * math.pi / self.omega

    @property
    def displacement_scale(self) -> float:
        """``P0/k`` [m]."""
        return abs(self.force_amplitude) / self.stiffness

    @property
    def velocity_scale(self) -> float:
        """``wn P0/k`` [m/s]: the unit of the regularisation width."""
        return math.sqrt(self.stiffness / self.mass) * self.displacement_scale

    def oscillator(self) -> CoulombOscillator:
        """The library's oscillator with these parameters."""
        return CoulombOscillator(self.mass, self.stiffness, self.slip_force, self.force_amplitude,
                                 self.omega)

    def error(self, amplitude: float) -> float:
        """``|amplitude / reference - 1|`` [-]."""
        return abs(amplitude / self.reference - 1.0)


def make_problem(case: Case) -> Problem:
    """Reference amplitude and common start of a case.

    Stop-free (Den Hartog applies): the closed form and its waveform at ``t = 0``. Otherwise the
    orbit of ``steady_state(tol=1e-13)``.

    Parameters
    ----------
    case : Case

    Returns
    -------
    Problem
    """
    m = k = p0 = 1.0
    f = case.friction_ratio * p0
    w = case.frequency_ratio * math.sqrt(k / m)
    dh = den_hartog_response(m, k, f, p0, w)
    if dh.applicable:
        x0 = float(dh.displacement(0.0))
        v0 = float(dh.dimensionless.waveform(0.0, 1)) * dh.natural_frequency * p0 / k
        return Problem(case, m, k, f, p0, w, x0, v0, float(dh.amplitude), "Den Hartog (closed form)",
                       dh.regime)
    ss = CoulombOscillator(m, k, f, p0, w).steady_state(tol=1e-13)
    if not (ss.converged and ss.unique):
        raise ParameterError(f"case {case.label}: no unique periodic orbit ({ss.message})")
    return Problem(case, m, k, f, p0, w, float(ss.initial_state[0]), float(ss.initial_state[1]),
                   float(ss.amplitude), "exact orbit (steady_state, tol 1e-13)", dh.regime)


# --------------------------------------------------------------------------- the methods


def marcher_amplitude(problem: Problem, periods: int = PERIODS) -> float:
    """Amplitude by the exact event-driven marcher from the common start.

    The marcher ends a closed-form piece at every ``v = 0`` (an event of the slipping slider), so
    the largest ``|x|`` over the last period is the largest at the ends of its pieces: exact.

    Parameters
    ----------
    problem : Problem
    periods : int
        Periods marched; the peak is taken over the last.

    Returns
    -------
    float
        ``max |x|`` over the last period [m].
    """
    marcher = Marcher(problem.oscillator().system)
    st = marcher.initial_state(problem.x0, problem.v0, t0=0.0)
    t_last = (periods - 1) * problem.period
    if t_last > 0:
        marcher.march(st, t_last)
    peak = [abs(float(st.x[0]))]

    def piece_end(itv, tau):
        x, _ = itv.state(tau)
        peak[0] = max(peak[0], abs(float(x[0, 0])))

    marcher.march(st, periods * problem.period, on_interval=piece_end)
    return peak[0]


def sdof_amplitude(problem: Problem, periods: int = PERIODS) -> float:
    """Amplitude by the dedicated single-DOF kernel from the common start: parameters and answer
    (``max |x|`` over the last period [m]) as :func:`marcher_amplitude`'s.

    :meth:`SdofCoulomb.peak` over the last period: the largest ``|x|`` at the ends of the
    closed-form pieces (every ``v = 0`` is one) and at the window ends, as for the marcher.
    """
    kernel = SdofCoulomb(problem.mass, problem.stiffness, problem.slip_force, problem.force_amplitude,
                         problem.omega)
    return kernel.peak(0.0, problem.x0, problem.v0, (periods - 1) * problem.period,
                       periods * problem.period)


def steady_state_amplitude(problem: Problem, tol: float) -> float:
    """Amplitude by :meth:`CoulombOscillator.steady_state` shooting from rest.

    Parameters
    ----------
    problem : Problem
    tol : float
        Shooting tolerance (scaled fixed-point residual).

    Returns
    -------
    float
        Amplitude [m] (``nan`` if not converged).
    """
    ss = problem.oscillator().steady_state(0.0, 0.0, tol=tol)
    return float(ss.amplitude) if ss.converged else math.nan


def describing_function_amplitude(problem: Problem) -> float:
    """One-harmonic balance ``|k - m w^2 + i 4F/(pi X)| X = P0`` solved in closed form.

    Parameters
    ----------
    problem : Problem

    Returns
    -------
    float
        ``X`` [m].
    """
    r = problem.omega / math.sqrt(problem.stiffness / problem.mass)
    f = problem.slip_force / abs(problem.force_amplitude)
    return harmonic_balance_amplitude(r, f) * problem.displacement_scale


def hbm_amplitude(problem: Problem, n_harmonics: int) -> float:
    """Peak of the harmonic balance's period (:func:`frictionjoint.harmonic_balance`).

    Parameters
    ----------
    problem : Problem
    n_harmonics : int
        ``H``.

    Returns
    -------
    float
        ``max |x|`` [m] (NaN when Newton did not converge).
    """
    import frictionjoint as fj

    p = problem
    st = fj.LinearStructure([[p.mass]], [[p.stiffness]])
    sysm = fj.FrictionSystem(st, [fj.CoulombSlider(p.slip_force, dof=0)], omega=p.omega,
                             excitation=[fj.HarmonicForce(0, p.force_amplitude)])
    hb = fj.harmonic_balance(sysm, n_harmonics=n_harmonics)
    return float(hb.amplitude[0]) if hb.converged else math.nan


def fmu_sweep_amplitude(problem: Problem, fmu, n_samples: int = 256) -> float:
    """Amplitude by a one-frequency :func:`frictionjoint.sweep.sweep` through the FMU.

    Parameters
    ----------
    problem : Problem
    fmu : str or os.PathLike
        ``CoulombOscillator.fmu``.
    n_samples : int
        Samples per period for the first harmonics (the peak is located exactly anyway).

    Returns
    -------
    float
        Amplitude [m] (``nan`` if not converged).
    """
    from frictionjoint.sweep import sweep

    params = dict(mass=problem.mass, stiffness=problem.stiffness, slip_force=problem.slip_force,
                  force_amplitude=problem.force_amplitude)
    fr = sweep(str(fmu), [problem.omega], params, n_samples=n_samples)
    return float(fr.amplitude[0]) if fr.converged[0] else math.nan


class _GaveUp(RuntimeError):
    """A baseline used more right-hand-side evaluations than allowed."""


def _counted(fun, limit):
    calls = [0]

    def wrapped(t, y):
        calls[0] += 1
        if calls[0] > limit:
            raise _GaveUp(f"gave up after {limit} right-hand-side evaluations")
        return fun(t, y)
    return wrapped


def _peak(problem: Problem, periods: int, turning, ends) -> float:
    """Largest ``|x|`` over the last period from the turning points ``(t, x)`` and the ends."""
    t_last = (periods - 1) * problem.period * (1 - 1e-14)
    vals = [abs(x) for t, x in turning if t >= t_last] + [abs(x) for x in ends]
    return float(max(vals))


def regularised_amplitude(problem: Problem, method: str, width: float, rtol: float,
                          periods: int = PERIODS, max_evaluations: int = 100_000) -> float:
    """Amplitude with tanh-regularised friction in ``solve_ivp`` from the common start.

    ``m x'' + k x + F tanh(v/eps) = P0 cos(w t)``, ``eps = width * wn P0/k``; turning points from
    a (non-terminal) ``v = 0`` event located on the dense output.

    Parameters
    ----------
    problem : Problem
    method : {'RK45', 'LSODA', 'Radau', ...}
        scipy method; implicit ones get the exact Jacobian.
    width : float
        Regularisation width in units of ``wn P0/k`` [-].
    rtol : float
        Relative tolerance; ``atol = rtol * [P0/k, wn P0/k]``.
    periods : int
        Periods integrated; the peak is taken over the last.
    max_evaluations : int
        Right-hand-side evaluations at most.

    Returns
    -------
    float
        Amplitude [m].

    Raises
    ------
    RuntimeError
        If the solver fails or needs more than ``max_evaluations`` evaluations.
    """
    m, k, f, p0, w = (problem.mass, problem.stiffness, problem.slip_force, problem.force_amplitude,
                      problem.omega)
    eps = width * problem.velocity_scale

    def rhs(t, y):
        return [y[1], (p0 * math.cos(w * t) - k * y[0] - f * math.tanh(y[1] / eps)) / m]

    def jac(t, y):
        sech = 1.0 / math.cosh(min(abs(y[1]) / eps, 350.0))
        return [[0.0, 1.0], [-k / m, -f * sech * sech / (eps * m)]]

    def turning(t, y):
        return y[1]

    t_end = periods * problem.period
    extra = {} if method in ("RK23", "RK45", "DOP853") else {"jac": jac}
    sol = solve_ivp(_counted(rhs, max_evaluations), (0.0, t_end), [problem.x0, problem.v0],
                    method=method, rtol=rtol,
                    atol=rtol * np.array([problem.displacement_scale, problem.velocity_scale]),
                    events=turning, t_eval=[(periods - 1) * problem.period, t_end], **extra)
    if sol.status != 0:
        raise RuntimeError(f"solve_ivp ({method}) failed: {sol.message}")
    return _peak(problem, periods, zip(sol.t_events[0], sol.y_events[0][:, 0]), sol.y[0])


def event_driven_amplitude(problem: Problem, rtol: float, periods: int = PERIODS,
                           method: str = "DOP853", max_evaluations: int = 100_000) -> float:
    """Amplitude with the exact Coulomb law in ``solve_ivp``, stick/slip by events.

    Slipping in direction ``s``: ``m x'' + k x = P0 cos(w t) - s F`` until ``v = 0`` (terminal
    event on the dense output). There, with ``h = P0 cos(w t) - k x`` the force sticking needs:
    ``|h| <= F`` sticks until ``|h|`` reaches ``F`` (Brent's method on ``h``), otherwise the mass
    slips on in the direction of ``h`` (Hong & Liu 2000).

    Parameters
    ----------
    problem : Problem
    rtol : float
        Relative tolerance (``atol = rtol * [P0/k, wn P0/k]``), >= :data:`RTOL_MIN`.
    periods : int
        Periods integrated; the peak is taken over the last.
    method : str
        scipy explicit method.
    max_evaluations : int
        Right-hand-side evaluations at most (over all phases).

    Returns
    -------
    float
        Amplitude [m].
    """
    m, k, f, p0, w = (problem.mass, problem.stiffness, problem.slip_force, problem.force_amplitude,
                      problem.omega)
    period = problem.period
    t_end = periods * period
    t_last = (periods - 1) * period
    atol = rtol * np.array([problem.displacement_scale, problem.velocity_scale])
    budget = [max_evaluations]

    def hold(t, x):
        return p0 * math.cos(w * t) - k * x

    def decide(t, x):
        h = hold(t, x)
        return 0 if abs(h) <= f else (1 if h > 0 else -1)

    t, x, v = 0.0, problem.x0, problem.v0
    s = (1 if v > 0 else -1) if v != 0 else decide(t, x)
    turning, ends = [], []
    while t < t_end:
        marks = [tb for tb in (t_last, t_end) if t < tb <= t_end]
        if s != 0:
            def rhs(tt, y, s=s):
                return [y[1], (p0 * math.cos(w * tt) - k * y[0] - s * f) / m]

            def stop(tt, y):
                return y[1]
            stop.terminal, stop.direction = True, -s
            fun = _counted(rhs, budget[0])
            sol = solve_ivp(fun, (t, t_end), [x, v], method=method, rtol=rtol, atol=atol,
                            events=stop, t_eval=marks or None)
            if sol.status == -1:
                raise RuntimeError(f"solve_ivp ({method}) failed: {sol.message}")
            budget[0] -= sol.nfev
            if marks:  # x at the marks reached (the ends of the last period)
                ends += list(np.abs(np.asarray(sol.y)[0])) if len(sol.t) else []
            if sol.status == 1:
                t, x, v = float(sol.t_events[0][0]), float(sol.y_events[0][0][0]), 0.0
                turning.append((t, x))
                s = decide(t, x)
            else:
                t = t_end
        else:  # stuck at x until |h| reaches F
            n = 64
            grid = t + period * np.arange(1, n * periods + 2) / n
            out = np.flatnonzero(np.abs(p0 * np.cos(w * grid) - k * x) > f)
            t_exit = t_end
            if out.size:
                j = out[0]
                lo = t if j == 0 else grid[j - 1]
                t_exit = scipy.optimize.brentq(lambda tt: abs(hold(tt, x)) - f, lo, grid[j],
                                               xtol=1e-15 * period, rtol=4 * np.finfo(float).eps)
            ends += [abs(x) for tb in marks if tb <= t_exit]
            if t_exit >= t_end:
                break
            t = float(t_exit)
            s = 1 if hold(t, x) > 0 else -1
    return _peak(problem, periods, turning, ends)


# --------------------------------------------------------------------------- results


@dataclass
class Row:
    """One method at one setting on one case.

    Attributes
    ----------
    case : Case
    method, setting : str
    amplitude : float
        Computed amplitude [m] (``nan`` when the method gave up or failed).
    error : float
        Relative amplitude error [-] (``nan`` likewise).
    time : float
        Best wall time over the repeats [s] (for a failed run: the time until it gave up).
    repeats : int
    status : str
        ``'ok'`` or why there is no answer.
    ratio : float
        ``time`` over the general exact marcher's (``exact marcher`` row) on the same case.
    """

    case: Case
    method: str
    setting: str
    amplitude: float
    error: float
    time: float
    repeats: int
    status: str = "ok"
    ratio: float = math.nan

    @property
    def ok(self) -> bool:
        """True when the method returned an amplitude."""
        return self.status == "ok" and math.isfinite(self.error)


def machine_description() -> dict:
    """Platform, CPU (from ``/proc/cpuinfo``), cores, Python, numpy and scipy versions, date.

    Returns
    -------
    dict of str
    """
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as fh:
            for line in fh:
                if line.lower().startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return {"platform": platform.platform(), "cpu": cpu, "cores": str(os.cpu_count()),
            "python": platform.python_version(), "numpy": np.__version__, "scipy": scipy.__version__,
            "date": datetime.datetime.now().astimezone().isoformat(timespec="seconds")}


@dataclass
class WorkPrecision:
    """Result of :func:`run_benchmark`: rows, the references and the machine.

    Attributes
    ----------
    rows : list of Row
    problems : dict
        ``Case -> Problem``.
    machine : dict
        :func:`machine_description`.
    periods : int
        Periods marched by the time-marching methods.
    """

    rows: list
    problems: dict
    machine: dict = field(default_factory=machine_description)
    periods: int = PERIODS

    def case_rows(self, case: Case) -> list:
        """Rows of one case."""
        return [r for r in self.rows if r.case == case]

    def headline(self, case: Case, threshold: float = 1e-10) -> dict:
        """The fastest exact marching row against the scipy baselines at matched or better accuracy.

        Parameters
        ----------
        case : Case
        threshold : float
            Also report the fastest baseline with error at most this.

        Returns
        -------
        dict
            ``marcher`` (Row: the fastest exact marching row that returned an answer, see
            :data:`EXACT_METHODS`; its ``method`` says which), ``matched`` (a baseline reached its
            error), ``baseline`` (the fastest such row, else the most accurate baseline row),
            ``ratio`` (its time over the exact row's), ``at_threshold``/``ratio_at_threshold``
            (fastest baseline with error <= threshold, or None), ``best_regularised`` (most
            accurate tanh row).
        """
        rows = self.case_rows(case)
        exact = [r for r in rows if r.method in EXACT_METHODS]
        marcher = min((r for r in exact if r.ok), key=lambda r: r.time, default=exact[0])
        base = [r for r in rows if r.method in SCIPY_METHODS and r.ok]
        good = [r for r in base if r.error <= marcher.error]
        matched = bool(good)
        best = (min(good, key=lambda r: r.time) if good
                else min(base, key=lambda r: (r.error, r.time)) if base else None)
        below = [r for r in base if r.error <= threshold]
        at = min(below, key=lambda r: r.time) if below else None
        reg = [r for r in base if r.method.startswith("tanh")]
        return {"marcher": marcher, "matched": matched, "baseline": best,
                "ratio": best.time / marcher.time if best else math.nan,
                "threshold": threshold, "at_threshold": at,
                "ratio_at_threshold": at.time / marcher.time if at else math.nan,
                "best_regularised": min(reg, key=lambda r: (r.error, r.time)) if reg else None}

    def summary(self) -> str:
        """The headline of each case in words."""
        lines = []
        for case in self.problems:
            h = self.headline(case)
            mr, b = h["marcher"], h["baseline"]
            line = f"{case.label}: fastest exact: {mr.method}, error {mr.error:.1e} in {1e3 * mr.time:.3f} ms"
            others = [r for r in self.case_rows(case) if r.method in EXACT_METHODS and r is not mr]
            line += "".join(f" ({r.method}: {1e3 * r.time:.3f} ms)" for r in others) + "; "
            if b is None:
                line += "no scipy baseline returned an answer"
            elif h["matched"]:
                line += (f"fastest scipy baseline at matched accuracy: {b.method} {b.setting} "
                         f"(error {b.error:.1e}), {h['ratio']:.1f}x the time")
            else:
                line += (f"no scipy baseline reaches that error; the most accurate, {b.method} "
                         f"{b.setting} (error {b.error:.1e}), takes {h['ratio']:.1f}x the time")
            at = h["at_threshold"]
            line += (f"; fastest baseline with error <= {h['threshold']:.0e}: "
                     + (f"{at.method} {at.setting} ({at.error:.1e}), {h['ratio_at_threshold']:.1f}x"
                        if at else "none"))
            reg = h["best_regularised"]
            if reg is not None:
                line += f"; best regularised: {reg.method} {reg.setting} ({reg.error:.1e})"
            lines.append(line)
        return "\n".join(lines)

    def table(self) -> str:
        """Fixed-width text table: case, method, setting, error, time, ratio to the marcher."""
        head = (f"{'case':<12} {'method':<20} {'setting':<22} {'rel. error':>10} {'time [ms]':>10} "
                f"{'x marcher':>10}  status")
        out = [head, "-" * len(head)]
        for r in self.rows:
            err = f"{r.error:10.2e}" if r.ok else f"{'-':>10}"
            out.append(f"{r.case.label:<12} {r.method:<20} {r.setting:<22} {err} {1e3 * r.time:10.3f} "
                       f"{r.ratio:10.2f}  {r.status}")
        return "\n".join(out)

    def header_lines(self) -> list:
        """Comment lines (without ``#``) describing the task and the machine."""
        mc = self.machine
        refs = "; ".join(f"{c.label}: {p.reference_name}, A_ref = {p.reference!r}"
                         for c, p in self.problems.items())
        return [
            "work-precision benchmark of frictionjoint (benchmarks/harness.py, `frictionjoint bench`)",
            "task: amplitude max|x| of the periodic steady state of m x'' + k x + F sgn(x') = P0 cos(w t), "
            "m = k = P0 = 1; relative_error = |A/A_ref - 1|",
            f"marching methods start on the reference orbit at t = 0, integrate {self.periods} periods, "
            "peak over the last; steady_state shoots from rest; time_s = best wall time over `repeats`",
            f"references: {refs}",
            f"machine: {mc['platform']}; CPU {mc['cpu']}; {mc['cores']} cores (shared, noisy)",
            f"python {mc['python']}, numpy {mc['numpy']}, scipy {mc['scipy']}; date {mc['date']}",
        ]

    def to_csv(self, path) -> None:
        """Write the rows as CSV (``#`` comment lines first: task and machine).

        Parameters
        ----------
        path : str or os.PathLike
        """
        with open(path, "w", newline="", encoding="utf-8") as fh:
            for line in self.header_lines():
                fh.write(f"# {line}\n")
            wr = csv.writer(fh)
            wr.writerow(COLUMNS)
            for r in self.rows:
                p = self.problems[r.case]
                wr.writerow([r.case.label, f"{r.case.frequency_ratio:g}", f"{r.case.friction_ratio:g}",
                             repr(float(p.reference)), r.method, r.setting, repr(float(r.amplitude)),
                             f"{r.error:.3e}", f"{r.time:.6e}", f"{r.ratio:.4g}", r.repeats, r.status])

    def plot(self, ax=None, path=None):
        """Work-precision plot (error against time, log-log), one panel per case.

        Parameters
        ----------
        ax : sequence of matplotlib Axes, optional
            One axes per case, instead of a new figure. A path given here is taken as ``path``.
        path : str or os.PathLike, optional
            Write the figure there.

        Returns
        -------
        matplotlib.figure.Figure
        """
        from frictionjoint.plotting import plot_target, plot_work_precision

        ax, path = plot_target(ax, path)
        return plot_work_precision(self, path, ax=ax)


# --------------------------------------------------------------------------- running


def _timed(fn: Callable, repeat: int, budget: float = 2.0):
    """Best wall time of ``fn()`` over up to ``repeat`` runs (fewer once ``budget`` s are spent)."""
    best, out, spent, n = math.inf, None, 0.0, 0
    while n < repeat:
        t0 = time.perf_counter()
        out = fn()
        dt = time.perf_counter() - t0
        best, spent, n = min(best, dt), spent + dt, n + 1
        if spent > budget:
            break
    return best, out, n


def plan(problem: Problem, quick: bool = False, fmu=None) -> list:
    """The (method, setting, callable) triples run on one case.

    Parameters
    ----------
    problem : Problem
    quick : bool
        The short grid (fewer widths, tolerances and shooting tolerances).
    fmu : str or os.PathLike, optional
        ``CoulombOscillator.fmu``; without it the FMU rows are left out.

    Returns
    -------
    list of (str, str, callable)
    """
    p = problem
    items = [(MARCHER, f"{PERIODS} periods", lambda: marcher_amplitude(p)),
             (SDOF, f"{PERIODS} periods", lambda: sdof_amplitude(p))]
    for tol in ((1e-6, 1e-12) if quick else (1e-6, 1e-9, 1e-12)):
        items.append(("steady_state", f"from rest, tol={tol:.0e}",
                      lambda tol=tol: steady_state_amplitude(p, tol)))
    if fmu is not None:
        for ns in ((64,) if quick else (64, 256)):
            items.append(("FMU sweep", f"n_samples={ns}", lambda ns=ns: fmu_sweep_amplitude(p, fmu, ns)))
    items.append(("describing function", "one harmonic", lambda: describing_function_amplitude(p)))
    for hh in ((1, 7) if quick else (1, 3, 7, 15, 31)):
        items.append(("harmonic balance", f"H={hh}", lambda hh=hh: hbm_amplitude(p, hh)))
    widths = (1e-3, 1e-6) if quick else (1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
    for method in ("RK45", "LSODA", "Radau"):
        tols = (1e-6, 1e-10) if quick else ((1e-6, 1e-9) if method == "Radau" else (1e-6, 1e-9, 1e-12))
        if quick and method == "Radau":
            tols = (1e-6,)
        for width in widths:
            for rtol in tols:
                items.append((f"tanh {method}", f"eps={width:.0e}, rtol={rtol:.0e}",
                              lambda m=method, w=width, r=rtol: regularised_amplitude(p, m, w, r)))
    for rtol in ((1e-6, 1e-10, RTOL_MIN) if quick else (1e-6, 1e-9, 1e-12, RTOL_MIN)):
        items.append(("events DOP853", f"rtol={rtol:.1e}" if rtol == RTOL_MIN else f"rtol={rtol:.0e}",
                      lambda r=rtol: event_driven_amplitude(p, r)))
    return items


def run_benchmark(quick: bool = False, cases=None, repeat: Optional[int] = None, fmu="build",
                  progress: bool = False) -> WorkPrecision:
    """Run every method at every setting on every case.

    Parameters
    ----------
    quick : bool
        The short version (under 30 s): fewer settings, fewer repeats, the FMU on the first case
        only.
    cases : sequence of Case, optional
        Default :data:`CASES`.
    repeat : int, optional
        Best of this many runs (default 5, quick 2; the exact marching rows, the denominators of
        the ratios, get at least 7, timed first and again last); runs that take long are repeated
        less.
    fmu : str, os.PathLike or None
        ``'build'`` builds ``CoulombOscillator.fmu`` into a temporary folder; a path uses that
        FMU; ``None`` leaves the FMU rows out.
    progress : bool
        Progress bar on stderr (tqdm).

    Returns
    -------
    WorkPrecision
    """
    import tempfile

    from tqdm import tqdm

    cases = tuple(CASES if cases is None else cases)
    repeat = (2 if quick else 5) if repeat is None else int(repeat)
    if repeat < 1:
        raise ParameterError(f"repeat must be an integer >= 1, got {repeat!r}")
    tmp = None
    if isinstance(fmu, str) and fmu == "build":
        from frictionjoint.fmi.build import build_fmus

        tmp = tempfile.TemporaryDirectory(prefix="fj-bench-")
        fmu = str(build_fmus(tmp.name, names=["CoulombOscillator"])[0])
    try:
        problems = {c: make_problem(c) for c in cases}
        jobs = []
        for i, (case, p) in enumerate(problems.items()):
            use_fmu = fmu if (not quick or i == 0) else None
            items = plan(p, quick, use_fmu)
            # the exact rows, denominators of the ratios, are timed first and again last (best of both)
            jobs += ([(case, p, *item) for item in items]
                     + [(case, p, m, None, fn) for m, _, fn in items if m in EXACT_METHODS])
        rows = []
        with tqdm(total=len(jobs), desc="work-precision", unit="run", file=sys.stderr,
                  disable=not progress, leave=False) as bar:
            for case, p, method, setting, fn in jobs:
                n = max(repeat, 7) if method in EXACT_METHODS else repeat
                if method == "FMU sweep":
                    n = min(n, 2)
                t0 = time.perf_counter()
                try:
                    dt, amp, n = _timed(fn, n)
                    status = "ok" if math.isfinite(amp) else "not converged"
                except (_GaveUp, RuntimeError) as exc:
                    dt, amp, n, status = time.perf_counter() - t0, math.nan, 1, str(exc)
                if setting is None:  # second timing of an exact row
                    k = next(j for j, r in enumerate(rows) if r.case == case and r.method == method)
                    rows[k] = replace(rows[k], time=min(rows[k].time, dt), repeats=rows[k].repeats + n)
                else:
                    rows.append(Row(case, method, setting, amp,
                                    p.error(amp) if math.isfinite(amp) else math.nan, dt, n, status))
                bar.set_postfix_str(f"{case.label} {method}", refresh=False)
                bar.update()
    finally:
        if tmp is not None:
            tmp.cleanup()
    marcher_time = {r.case: r.time for r in rows if r.method == MARCHER}
    rows = [replace(r, ratio=r.time / marcher_time[r.case]) for r in rows]
    return WorkPrecision(rows, problems)


# --------------------------------------------------------------------------- the scripts' tables


def script_header(script: str, quick: bool) -> str:
    """The first line of a benchmark script's table: the script (``--quick`` if so), the machine,
    its cores and the date.

    Parameters
    ----------
    script : str
        The script's file name in ``benchmarks/``.
    quick : bool
        Whether the script runs its ``--quick`` variant.

    Returns
    -------
    str
    """
    return (f"# benchmarks/{script}{' --quick' if quick else ''}: {platform.machine()}, "
            f"{os.cpu_count()} cores, {time.strftime('%Y-%m-%d')}")


def write_results(name: str, lines: list, quick: bool) -> None:
    """Write a benchmark script's table to ``benchmarks/<name>`` and say so; a quick run's table is
    only printed (the files hold full runs).

    Parameters
    ----------
    name : str
        The results file's name in ``benchmarks/`` (e.g. ``results_blade.txt``).
    lines : list of str
        The table, one row a line.
    quick : bool
        Whether the script ran its ``--quick`` variant (nothing is written then).
    """
    if quick:
        return
    out = os.path.join(os.path.dirname(__file__), name)
    with open(out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"wrote {out}")
