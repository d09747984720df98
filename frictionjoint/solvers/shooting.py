"""Shooting: the periodic orbit as a fixed point of a period map, one algorithm for every caller.

A period map ``P`` takes a state ``z`` at a section time to the state one excitation period
later; a periodic orbit is ``P(z) = z``. :func:`find_periodic_orbit` runs Newton's method (chord
iterations with backtracking) on ``P(z) - z``; when Newton fails it marches period after period
(fixed-point iteration), retrying Newton now and then, and recognises unbounded growth and a
residual that marching cannot bring down in time. At the orbit, an eigenvalue 1 of ``P``'s
Jacobian (a singular ``J - I``) means a family of periodic orbits (``unique = False``).

The period map is any object with

- ``pmap(z) -> P(z)`` (one period marched);
- ``pmap.jacobian(z, pz, scale) -> J`` (``pz = P(z)`` given);
- ``pmap.scales(z) -> (nz,)`` component scales of the residual (its norm is ``max |r_i| / scale_i``);
- ``pmap.amplitude(z) -> float``, a size of the motion, watched for unbounded growth;
- optionally ``pmap.exact_jacobian = True``: the Jacobian comes with the map's last call at no
  marching cost (full Newton steps instead of chord steps);
- optionally ``pmap.closed_form(z) -> orbit or None``: an exact periodic orbit found in closed
  form from the state ``z``, e.g. with every slider stuck, the linear orbit of that configuration
  for the sliders' positions, moved the least into the slip limits (a friction oscillator shaken
  down into permanent stick: one member of the family of stuck orbits). Marching tries it after
  every period, so that a lightly damped transient need not decay to the tolerance.

The library's exact period map (:func:`frictionjoint.solvers.marcher.steady.periodic_response`) and the
period map of a stepping driver (the library's or an FMU's, :func:`frictionjoint.drivers.shoot`)
are its two inputs.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["ShootingOutcome", "find_periodic_orbit", "residual_floor", "fixed_point_newton", "has_unit_eigenvalue",
           "steady_growth", "orbit_message", "NEWTON_ITERATIONS_RETRY", "FIRST_RETRY_PERIOD",
           "RETRY_EVERY", "WANDERED_RESIDUAL", "UNIT_EIGENVALUE_TOL"]

#: Newton iterations of each retry during the marching fallback
NEWTON_ITERATIONS_RETRY = 8
#: the marching fallback first checks growth, retries Newton and judges its pace after this many periods ...
FIRST_RETRY_PERIOD = 40
#: ... and then every this many periods
RETRY_EVERY = 20
#: a Newton iterate with a residual above this (or not finite) has wandered off: march from the start
WANDERED_RESIDUAL = 1e-3
#: ``J - I`` is singular (a family of orbits) when its smallest singular value is below this
#: fraction of its largest
UNIT_EIGENVALUE_TOL = 1e-6
#: chord iterations keep their Jacobian while the residual falls by at least this factor per step
CHORD_RATE = 0.05
#: singular values of the scaled ``J - I`` below this fraction of ``max(1, largest)`` are dropped
#: from a Newton step (a neutral direction of the period map)
NEWTON_RCOND = 1e-13
#: smallest backtracking factor of a Newton step
MIN_STEP = 1 / 32
#: Newton steps that may raise the residual (the best backtracking trial, taken when none falls)
NONMONOTONE_STEPS = 3


@dataclass
class ShootingOutcome:
    """What :func:`find_periodic_orbit` found.

    Attributes
    ----------
    converged : bool
        ``|P(z) - z| <= tol`` (scaled).
    z : ndarray
        The orbit state (or the last iterate).
    rnorm : float
        Scaled residual of the last residual evaluation.
    jac : ndarray or None
        The last Jacobian of ``P`` computed, and ``jac_rnorm`` the residual where it was.
    growth : float or None
        Growth per period when the motion grows without bound.
    slow : (float, float) or None
        ``(rate, periods needed)`` when marching stopped early as too slow.
    closed : object or None
        The orbit of ``pmap.closed_form`` when marching reached a state that determines it.
    """

    converged: bool
    z: np.ndarray
    rnorm: float
    jac: np.ndarray | None = None
    jac_rnorm: float = math.inf
    growth: float | None = None
    slow: tuple | None = None
    closed: object = None

    @property
    def status(self) -> str:
        """``'periodic'``, ``'unbounded'`` or ``'not converged'``."""
        if self.converged:
            return "periodic"
        return "unbounded" if self.growth is not None else "not converged"


def residual_floor(excitation: float, slip_force: float, stiffness: float, mass: float, omega: float,
                   tol: float) -> float:
    """Displacement floor [m] of the residual scales of an exact period map.

    A scale from the loads (``1e-6`` of the larger of excitation and slip force over the
    dynamic stiffness ``max(K, M omega^2)``), raised to the map's rounding: the closed-form pieces
    carry static deflections ``excitation / K``, whose rounding (about ``eps excitation / K``)
    ``tol`` cannot go below -- a motion far smaller than the static deflection (``omega >>
    omega_n``) is judged against it, not against its own size. Only the excitation counts there:
    a slip force far above it (a stuck joint) deflects nothing.
    """
    load = max(excitation, slip_force)
    stiff = max(stiffness, mass * omega ** 2)
    floor = 1e-6 * load / stiff if load > 0 else 1e-6
    if excitation > 0 and stiffness > 0:
        floor = max(floor, np.finfo(float).eps * excitation / stiffness / tol)
    return floor


def has_unit_eigenvalue(jac, scale) -> bool:
    """True when ``J - I`` (scaled by ``scale``) is singular to :data:`UNIT_EIGENVALUE_TOL`: the
    fixed point belongs to a family of periodic orbits."""
    a = (jac - np.eye(jac.shape[0])) / scale[:, None] * scale[None, :]
    sv = np.linalg.svd(a, compute_uv=False)
    return bool(sv[-1] <= UNIT_EIGENVALUE_TOL * max(sv[0], 1.0))


def _newton_factors(a):
    """The parts of ``a = J - I`` (scaled) that :func:`_newton_step` solves with: its SVD without
    the directions in which it is singular to :data:`NEWTON_RCOND` *of the identity* (not of its
    largest singular value). Computed once per Jacobian (chord steps reuse them)."""
    u, sv, vt = np.linalg.svd(a)
    keep = sv > NEWTON_RCOND * max(1.0, sv[0])
    return u[:, keep], sv[keep], vt[keep]


def _newton_step(factors, rhs):
    """Least-squares solution of ``a s = rhs`` on the directions :func:`_newton_factors` keeps:
    where ``J = I`` up to rounding (undamped exact resonance, ``P(z) = z + c``), no step is taken
    along the neutral directions, where a relative cut-off would step to ``|z| ~ 1e16`` and call
    the rounding of ``P`` there a fixed point."""
    u, sv, vt = factors
    return vt.T @ ((u.T @ rhs) / sv)


def fixed_point_newton(pmap, jacobian, z, pz, scale, tol, iterations, chord: bool = True,
                       refresh_below: float = 0.0):
    """Chord/Newton iterations on ``P(z) - z = 0`` with backtracking.

    Parameters
    ----------
    pmap : callable
        The map ``P``.
    jacobian : callable
        ``jacobian(z, pz)``: Jacobian of ``P`` at ``z`` (``pz = P(z)`` given).
    z, pz : ndarray
        Start and its image.
    scale : ndarray
        Component scales of the residual (the norm is ``max |r_i| / scale_i``).
    tol : float
        Residual tolerance.
    iterations : int
        Newton iterations at most.
    chord : bool
        Keep a Jacobian while the residual falls fast (chord iterations: for a Jacobian that costs
        periods, e.g. finite differences); False takes a fresh one at every step (full Newton: for
        an exact Jacobian that the last period's pieces give at no marching cost).
    refresh_below : float
        Chord iterations take a fresh Jacobian once the residual falls below this (0: never), so
        that the last Jacobian is one near the orbit (the caller's monodromy) and the last steps
        converge quadratically.

    Returns
    -------
    tuple
        ``(converged, z, pz, rnorm, jac, jac_rnorm)``: the last iterate, its image and residual,
        the last Jacobian and the residual where it was computed.
    """
    jac, jac_rnorm = None, math.inf
    rnorm = float(np.max(np.abs(pz - z) / scale))
    best = (z, pz, rnorm)
    escapes = 0
    for _ in range(iterations):
        if rnorm <= tol:
            return True, z, pz, rnorm, jac, jac_rnorm
        fresh = jac is None
        if fresh:
            jac = jacobian(z, pz)
            jac_rnorm = rnorm
            factors = _newton_factors((jac - np.eye(z.size)) / scale[:, None] * scale[None, :])
        step = _newton_step(factors, -(pz - z) / scale) * scale
        lam = 1.0
        trial = None
        while lam >= MIN_STEP:
            zn = z + lam * step
            pzn = pmap(zn)
            rn = float(np.max(np.abs(pzn - zn) / scale))
            if rn < rnorm:
                break
            if trial is None or rn < trial[2]:
                trial = (zn, pzn, rn)
            lam *= 0.5
        else:
            if not fresh:
                jac = None  # the chord Jacobian was stale: refresh it and retry
                continue
            if escapes >= NONMONOTONE_STEPS:
                break  # no descent even with a fresh Jacobian
            # no descent even with a fresh Jacobian: on a period map with events the linearisation
            # holds only while the events keep their order, and the orbit may lie beyond a change
            # of that order (a flank that starts to slip twice per period); take the best trial
            # and go on from there, a few times at most
            escapes += 1
            zn, pzn, rn = trial
        # chord method: keep the Jacobian while the residual falls fast
        if not chord or rn > CHORD_RATE * rnorm or rn >= rnorm or rn <= refresh_below < jac_rnorm:
            jac = None
        z, pz, rnorm = zn, pzn, rn
        if rnorm < best[2]:
            best = (z, pz, rnorm)
    if rnorm > tol and best[2] < rnorm:
        z, pz, rnorm = best  # the best iterate (its Jacobian is not the last one)
        jac, jac_rnorm = None, math.inf
    return rnorm <= tol, z, pz, rnorm, jac, jac_rnorm


def _too_slow(residuals, tol: float, remaining: int):
    """``(rate, periods)`` if marching cannot reach ``tol`` within twice the ``remaining``
    periods at its present pace, and is still more than 1e3 ``tol`` away, else None.

    The pace is that of the best residual of the last 20 periods against the best of the 20
    before (minima, so that a beating residual is not mistaken for progress or for a stall);
    ``rate`` is the factor per period (>= 1: no progress, ``periods`` is inf).
    """
    if len(residuals) < 40:
        return None
    now, before = min(residuals[-20:]), min(residuals[-40:-20])
    if not (now > 1e3 * tol and before > 0):
        return None  # near the tolerance, rounding noise may still carry the residual below it
    rate = (now / before) ** (1 / 20)
    need = math.inf if rate >= 1 else math.log(tol / now) / math.log(rate)
    return (rate, need) if need > 2 * max(remaining, 0) else None


def steady_growth(amplitudes) -> float | None:
    """Growth per period if a sequence of per-period amplitudes grows without bound, else None.

    Unbounded (resonant) growth of a friction oscillator is linear in time: the last 30
    increments are all positive, nearly equal (spread <= 5 % of the mean), do not decay, and
    the amplitude has at least doubled over them.
    """
    amps = np.asarray(amplitudes[-30:], dtype=float)
    if amps.size < 30:
        return None
    inc = np.diff(amps)
    if (np.all(inc > 0) and np.std(inc) <= 0.05 * np.mean(inc)
            and np.mean(inc[-10:]) >= 0.98 * np.mean(inc[:10]) and amps[-1] >= 2 * amps[0]):
        return float(np.mean(inc[-10:]))
    return None


def find_periodic_orbit(pmap, z, pz, *, tol: float, max_newton: int, max_periods: int,
                        z_start=None) -> ShootingOutcome:
    """Newton on ``P(z) - z``, then marching with Newton retries (see the module docstring).

    Parameters
    ----------
    pmap : period map
        See the module docstring.
    z, pz : ndarray
        Initial guess and its image ``P(z)``.
    tol : float
        Tolerance on the scaled residual.
    max_newton : int
        Newton iterations before the marching fallback.
    max_periods : int
        Periods marched at most in the fallback.
    z_start : ndarray, optional
        Where marching starts when Newton wandered off (``z`` if omitted).

    Returns
    -------
    ShootingOutcome
        ``z`` is the orbit, ``P(z)`` is the map's last call when ``converged`` by Newton.
    """
    z_start = z if z_start is None else z_start
    scale0 = np.maximum(pmap.scales(z), pmap.scales(pz))

    def newton(z, pz, iterations):
        return fixed_point_newton(pmap, lambda z, pz: pmap.jacobian(z, pz, scale0), z, pz, scale0, tol,
                                  iterations, chord=getattr(pmap, "chord", not getattr(pmap, "exact_jacobian", False)),
                                  refresh_below=getattr(pmap, "refresh_below", 0.0))

    converged, z, pz, rnorm, jac, jac_rnorm = newton(z, pz, max_newton)
    growth = slow = None
    if not converged:
        amps, hist = [], []
        if not (np.all(np.isfinite(z)) and rnorm < WANDERED_RESIDUAL):
            z = z_start  # Newton wandered off: march from the start instead
        closed_form = getattr(pmap, "closed_form", None)
        for k in range(max_periods):
            if closed_form is not None:
                closed = closed_form(z)
                if closed is not None:
                    return ShootingOutcome(True, z, 0.0, closed=closed)
            pz = pmap(z)
            rnorm = float(np.max(np.abs(pz - z) / pmap.scales(z)))
            hist.append(rnorm)
            z = pz
            amps.append(pmap.amplitude(z))
            if rnorm <= tol:
                converged = True
                break
            if k >= FIRST_RETRY_PERIOD and k % RETRY_EVERY == 0:
                growth = steady_growth(amps)
                if growth is not None:
                    break
                scale0 = np.maximum(pmap.scales(z), pmap.scales(pz))
                converged, z, pz, rnorm, jac, jac_rnorm = newton(z, pmap(z), NEWTON_ITERATIONS_RETRY)
                if converged:
                    break
                slow = _too_slow(hist, tol, max_periods - k - 1)
                if slow is not None:
                    break
    return ShootingOutcome(converged, z, rnorm, jac, jac_rnorm, growth, slow)


def orbit_message(outcome: ShootingOutcome, unique: bool, periods: float, max_periods: int) -> str:
    """The one message table of shooting, in words."""
    if outcome.converged:
        message = "periodic steady state found"
        if not unique:
            message += ("; NOT UNIQUE: the period map has an eigenvalue 1 (a family of periodic "
                        "orbits, e.g. different mean offsets or rest positions); this is one member")
        return message
    if outcome.growth is not None:
        return f"the response grows without bound (about {outcome.growth:.6g} m per period)"
    message = (f"no periodic steady state found (residual {outcome.rnorm:.3g} after {periods:.0f} periods): "
               "the response may be non-periodic or converge too slowly")
    if outcome.slow is not None:
        rate, need = outcome.slow
        message += (f"; stopped early: shooting failed and marching reduces the residual by a "
                    f"factor {rate:.6g} per period, so about {need:.3g} more periods would be "
                    f"needed (max_periods={max_periods}); e.g. a very lightly damped transient "
                    "(tiny friction near a super-harmonic resonance r = 1/n) or a non-smooth "
                    "period map")
    return message
