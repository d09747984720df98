"""Drivers of a harmonically excited oscillator for sweeps: the library directly, or an FMU.

A driver (:class:`Driver`) offers six calls -- ``start(parameters)`` (fresh run at ``t = 0``),
``advance(t)``, ``get(names)``, ``save()``, ``restore(saved)`` and ``close()`` -- and names its
``outputs``. :class:`LibraryDriver` and :class:`~frictionjoint.fmi.driver.FMUDriver` run the same
stepping code (:class:`~frictionjoint.stepping.OscillatorRun`; inside the FMU for the latter), so a
sweep through the FMU and the same sweep on the library give the same numbers. :func:`shoot` finds the
periodic steady state through that interface only: shooting on ``(x0, v0)`` (a period map is one
restart and one communication step of a period, events handled inside the step), then one
period sampled at ``n_samples`` points for the first harmonics, with the displacement peaks
located exactly (``v = 0``, Brent's method on restored states).
"""
from __future__ import annotations

import math
from typing import Protocol, runtime_checkable

import numpy as np
import scipy.optimize

from .errors import ConvergenceError, FMUError
from .fmi.driver import FMUDriver
from .results import PeriodicResponse
from .solvers.shooting import ShootingOutcome, find_periodic_orbit, has_unit_eigenvalue, orbit_message
from .solvers.marcher.steady import failed_response
from .stepping import OSCILLATOR_OUTPUTS, OSCILLATOR_PARAMETERS, OscillatorRun

__all__ = ["Driver", "LibraryDriver", "FMUDriver", "shoot"]


@runtime_checkable
class Driver(Protocol):
    """What :func:`shoot` and :func:`frictionjoint.sweep.sweep` need of a stepping oscillator
    with the parameters and outputs of :data:`~frictionjoint.stepping.OSCILLATOR_PARAMETERS` and
    :data:`~frictionjoint.stepping.OSCILLATOR_OUTPUTS` (those it has: ``outputs``)."""

    outputs: tuple

    def start(self, parameters: dict) -> None:
        """A fresh run at ``t = 0`` with these parameters."""

    def advance(self, t: float) -> None:
        """One communication step to time ``t`` [s] (events inside the step)."""

    def get(self, names) -> list:
        """Output values by name."""

    def save(self):
        """The run's complete state."""

    def restore(self, saved) -> None:
        """Back to a state from :meth:`save`."""

    def close(self) -> None:
        """Release the run."""


class LibraryDriver:
    """The Coulomb oscillator stepped directly in the library (no FMU layer)."""

    outputs = tuple(OSCILLATOR_OUTPUTS)

    def __init__(self):
        self.run = None

    def start(self, parameters: dict) -> None:
        self.run = OscillatorRun(parameters)

    def advance(self, t: float) -> None:
        self.run.advance(t)

    def get(self, names) -> list:
        return [self.run.output(n) for n in names]

    def save(self):
        return self.run.snapshot()

    def restore(self, saved) -> None:
        self.run.restore(saved)

    def close(self) -> None:
        self.run = None


def _one_harmonic_guess(p: dict):
    from .oscillator import CoulombOscillator

    keys = ("mass", "stiffness", "slip_force", "force_amplitude", "omega", "damping", "base_amplitude")
    return CoulombOscillator(**{k: p[k] for k in keys if k in p}).initial_guess()


class _DriverPeriodMap:
    """The period map of a driver (:mod:`frictionjoint.solvers.shooting`'s protocol): one restart
    at ``t = 0`` from ``z = (x0, v0)`` and one communication step of a period."""

    def __init__(self, driver, parameters: dict):
        self.driver, self.p = driver, parameters
        self.omega = float(parameters["omega"])
        self.period = 2 * math.pi / self.omega
        self.calls = 0
        self.last = None
        load = max(abs(parameters.get("force_amplitude", 0.0)
                       + parameters["stiffness"] * parameters.get("base_amplitude", 0.0)),
                   parameters.get("slip_force", 0.0))
        self.x_floor = 1e-6 * load / parameters["stiffness"] if load > 0 else 1e-6

    def __call__(self, z):
        self.driver.start(dict(self.p, x0=float(z[0]), v0=float(z[1])))
        self.driver.advance(self.period)
        self.calls += 1
        out = np.array(self.driver.get(["x", "v"]), dtype=float)
        self.last = (z.copy(), out)
        return out

    def image(self, z):
        """``P(z)``, from the last call when it was at ``z``."""
        if self.last is not None and np.array_equal(self.last[0], z):
            return self.last[1]
        return self(z)

    def scales(self, z):
        sx = max(self.x_floor, abs(z[0]), abs(z[1]) / self.omega)
        return np.array([sx, sx * self.omega])

    def amplitude(self, z) -> float:
        return math.hypot(z[0], z[1] / self.omega)

    def jacobian(self, z, pz, scale):
        """Forward differences with steps 1e-7 of the scales at ``z`` (``scale`` is not used)."""
        sc = self.scales(z)
        jac = np.empty((2, 2))
        for k in range(2):
            zp = z.copy()
            zp[k] += 1e-7 * sc[k]
            jac[:, k] = (self(zp) - pz) / (1e-7 * sc[k])
        return jac


def shoot(driver, parameters: dict, state=None, outputs=("x",), n_samples: int = 256, tol: float = 1e-11,
          max_periods: int = 500) -> PeriodicResponse:
    """Periodic steady state through a driver.

    Parameters
    ----------
    driver : LibraryDriver or FMUDriver
    parameters : dict
        Oscillator parameters (``omega`` included; ``x0``, ``v0`` are set here).
    state : (float, float), optional
        Start ``(x0, v0)`` at ``t = 0``; the one-harmonic estimate if omitted.
    outputs : sequence of str
        Outputs whose first harmonic and peak are reported (``x`` always).
    n_samples : int
        Samples over the period for the first harmonics (trapezoidal rule), used only for outputs
        the stepping object does not integrate exactly: ``x`` and ``friction_force`` come from its
        exact Fourier integrals and peak over one communication step of a period.
    tol : float
        Tolerance on the scaled fixed-point residual.
    max_periods : int
        Periods marched at most when Newton fails.

    Returns
    -------
    PeriodicResponse
        ``amplitude`` (exact peak of ``|x|``), ``phase`` and ``harmonic_amplitude`` of ``x`` from the
        samples, ``harmonics`` per requested output, ``stops_per_cycle`` (stick intervals seen
        in the samples).
    """
    p = {k: v[0] for k, v in OSCILLATOR_PARAMETERS.items()}
    p.update(parameters)
    try:
        return _shoot(driver, p, state, outputs, n_samples, tol, max_periods)
    except (ConvergenceError, FMUError) as exc:
        # a march the kernel or the FMU refuses (its event budget, a step it cannot answer): this
        # point fails with the reason, the sweep goes on
        return failed_response(float(p["omega"]), None, f"the march failed: {exc}", unique=False)


def _shoot(driver, p, state, outputs, n_samples, tol, max_periods) -> PeriodicResponse:
    """:func:`shoot` with the parameters ``p`` complete."""
    w = float(p["omega"])
    period = 2 * math.pi / w
    outputs = tuple(dict.fromkeys(("x",) + tuple(outputs)))
    pmap = _DriverPeriodMap(driver, p)
    on_orbit = _orbit_start(driver, p, pmap, state, outputs, tol)
    if on_orbit is not None:
        return on_orbit
    z = np.array(state if state is not None else _one_harmonic_guess(p), dtype=float)
    outcome = find_periodic_orbit(pmap, z, pmap(z), tol=tol, max_newton=20, max_periods=max_periods)
    z, converged = outcome.z, outcome.converged
    unique, monodromy = True, None
    if converged:  # the Jacobian at the orbit: P(z) is usually the map's last call already
        monodromy = pmap.jacobian(z, pmap.image(z), None)
        unique = not has_unit_eigenvalue(monodromy, pmap.scales(z))
    # the orbit's period: exact Fourier integrals where the stepping object has them, else samples
    final = _exact_period(driver, p, z, period, outputs) or _sampled_period(driver, p, z, period, outputs,
                                                                             n_samples)
    harmonics, peak, stops, stuck_all = final
    periods = pmap.calls + 1
    status = outcome.status
    message = orbit_message(outcome, unique, periods, max_periods)
    res = PeriodicResponse(
        omega=w, amplitude=peak, phase=harmonics["x"]["phase"], harmonic_amplitude=harmonics["x"]["amplitude"],
        stops_per_cycle=stops, stuck=stuck_all and p.get("slip_force", 0.0) > 0,
        converged=converged, unique=unique, message=message, periods=float(periods),
        state=z, section_time=0.0, initial_state=z, status=status, harmonics=harmonics)
    if monodromy is not None:
        res.set_multipliers(np.linalg.eigvals(monodromy))
    return res


_ORBIT_OUTPUTS = ("orbit_found", "x", "v", "monodromy_xx", "monodromy_xv", "monodromy_vx", "monodromy_vv")


def _orbit_start(driver, p, pmap, state, outputs, tol):
    """The steady state from a driver that starts on it (``start_on_orbit``: the stepping object
    shoots with the exact period-map Jacobian at its initialisation), checked through the driver:
    one communication step of a period must return to the start state to ``100 tol`` (scaled as
    the shooting residual). None where the driver cannot, or the check fails (shooting through
    the driver then)."""
    if not (_exact_applies(driver, outputs) and set(_ORBIT_OUTPUTS) <= set(driver.outputs)):
        return None
    guess = {} if state is None else dict(x0=float(state[0]), v0=float(state[1]))
    driver.start(dict(p, start_on_orbit=True, harmonics=True, **guess))
    start = dict(zip(_ORBIT_OUTPUTS + ("stuck",), driver.get(_ORBIT_OUTPUTS + ("stuck",))))
    if not start["orbit_found"]:
        return None
    final = _period_integrals(driver, p, pmap.period, outputs, start["stuck"], end_state=True)
    if final is None:
        return None
    harmonics, peak, stops, stuck_all, end = final
    z = np.array([start["x"], start["v"]])
    pz = np.array([end["x"], end["v"]])
    rnorm = float(np.max(np.abs(pz - z) / pmap.scales(z)))
    if not rnorm <= 100 * tol:
        return None
    jac = np.array([[start["monodromy_xx"], start["monodromy_xv"]], [start["monodromy_vx"], start["monodromy_vv"]]])
    known = bool(np.any(jac))
    unique = not has_unit_eigenvalue(jac, pmap.scales(z)) if known else True
    outcome = ShootingOutcome(True, z, rnorm)
    res = PeriodicResponse(
        omega=float(p["omega"]), amplitude=peak, phase=harmonics["x"]["phase"],
        harmonic_amplitude=harmonics["x"]["amplitude"], stops_per_cycle=stops,
        stuck=stuck_all and p.get("slip_force", 0.0) > 0, converged=True, unique=unique,
        message=orbit_message(outcome, unique, 1.0, 0) + " (the driver started on it; one period checked)",
        periods=1.0, state=z, section_time=0.0, initial_state=z, status="periodic", harmonics=harmonics)
    if known:
        res.set_multipliers(np.linalg.eigvals(jac))
    return res


#: outputs whose harmonics a driver with exact Fourier integrals gives without sampling
_EXACT_OUTPUTS = ("x", "friction_force")
_INTEGRAL_OUTPUTS = ("peak_x", "stop_count", "x_cos_integral", "x_sin_integral", "friction_force_cos_integral",
                     "friction_force_sin_integral", "event_count", "stuck")


def _exact_applies(driver, outputs) -> bool:
    """The driver integrates the requested outputs' harmonics exactly (see :func:`_exact_period`)."""
    return set(outputs) <= set(_EXACT_OUTPUTS) and set(_INTEGRAL_OUTPUTS) <= set(driver.outputs)


def _exact_period(driver, p, z, period, outputs):
    """The orbit's period from the exact Fourier integrals and peak of the stepping object (one
    communication step from ``z``), or None where they do not apply (an older FMU, an output
    without them, an orbit stuck all along: its holding force has no exact peak here)."""
    if not _exact_applies(driver, outputs):
        return None
    driver.start(dict(p, x0=float(z[0]), v0=float(z[1]), harmonics=True))
    return _period_integrals(driver, p, period, outputs, bool(driver.get(["stuck"])[0]))


def _period_integrals(driver, p, period, outputs, stuck0: bool, end_state: bool = False):
    """One communication step of a period from a started driver (``harmonics`` on):
    ``(harmonics, peak of |x|, stops, stuck all along)`` from its exact integrals, and with
    ``end_state`` the ``x``, ``v`` at the end too; None for an orbit stuck all along when the
    friction force is asked for."""
    driver.advance(period)
    names = _INTEGRAL_OUTPUTS + (("x", "v") if end_state else ())
    vals = dict(zip(names, driver.get(names)))
    stuck_all = stuck0 and vals["event_count"] == 0
    if stuck_all and "friction_force" in outputs:
        return None
    harmonics = {}
    for n in outputs:
        a1, b1 = (2 / period * vals[f"{n}_{k}_integral"] for k in ("cos", "sin"))
        # |friction force| <= F, = F while slipping: its peak is F once the orbit slips
        peak = vals["peak_x"] if n == "x" else float(p.get("slip_force", 0.0))
        harmonics[n] = {"amplitude": float(math.hypot(a1, b1)), "phase": float(math.atan2(b1, a1)), "peak": peak}
    out = (harmonics, vals["peak_x"], int(vals["stop_count"]), stuck_all)
    return out + ({"x": vals["x"], "v": vals["v"]},) if end_state else out


def _sampled_period(driver, p, z, period, outputs, n_samples):
    """The orbit's period from ``n_samples`` communication points (first harmonics by the
    trapezoidal rule) and exact peaks of ``|x|`` (Brent on restored states at ``v = 0``)."""
    w = float(p["omega"])
    names = tuple(dict.fromkeys(outputs + ("v", "stuck")))
    driver.start(dict(p, x0=float(z[0]), v0=float(z[1])))
    t = period * np.arange(1, n_samples + 1) / n_samples
    samples = np.empty((len(names), n_samples))
    for k, tk in enumerate(t):
        driver.advance(float(tk))
        samples[:, k] = np.array(driver.get(names), dtype=float)
    col = {n: samples[i] for i, n in enumerate(names)}
    c, s = np.cos(w * t), np.sin(w * t)
    harmonics = {}
    for n in outputs:
        y = col[n]
        a1, b1 = 2 * np.mean(y * c), 2 * np.mean(y * s)
        harmonics[n] = {"amplitude": float(math.hypot(a1, b1)), "phase": float(math.atan2(b1, a1)),
                        "peak": float(np.max(np.abs(y)))}
    # exact peaks of |x|: where v changes sign between samples
    v = col["v"]
    peak = harmonics["x"]["peak"]
    x0 = float(z[0])
    peak = max(peak, abs(x0))
    tprev = np.concatenate([[0.0], t[:-1]])
    vprev = np.concatenate([[float(z[1])], v[:-1]])
    for k in np.flatnonzero(vprev * v < 0):
        driver.start(dict(p, x0=float(z[0]), v0=float(z[1])))
        if tprev[k] > 0:
            driver.advance(float(tprev[k]))
        saved = driver.save()

        def vel(tt, saved=saved):
            driver.restore(saved)
            driver.advance(float(tt))
            return float(driver.get(["v"])[0])

        tr = scipy.optimize.brentq(vel, tprev[k], t[k], xtol=1e-15 * period, rtol=4 * np.finfo(float).eps)
        vel(tr)
        peak = max(peak, abs(float(driver.get(["x"])[0])))
    harmonics["x"]["peak"] = peak
    stuck = col["stuck"] > 0.5
    stops = int(np.count_nonzero(stuck & ~np.roll(stuck, 1)))
    return harmonics, peak, stops, bool(stuck.all())
