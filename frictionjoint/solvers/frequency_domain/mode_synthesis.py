"""Forced response near a resonance synthesised from one nonlinear mode (single-nonlinear-mode
theory: Szemplinska-Stupnicka, "The behavior of nonlinear vibrating systems", vol. 2, Kluwer
1990; Krack, "Nonlinear modal analysis of nonconservative systems: extension of the periodic
motion concept", Computers & Structures 154, 2015).

**Derivation.** The forced system is ``M x'' + C x' + K x + g(x) = Re(F e^{i Omega t})``, ``g`` the
joints' forces less their stuck springs (in ``K``). Its nonlinear mode (:mod:`.nonlinear_mode`) at
amplitude ``a`` has the frequency ``omega``, the negative damping ``xi`` and the first harmonic
``X_1`` of every DOF, and its first-harmonic balance is

    (K - omega^2 M + i omega (C - xi M)) X_1 + G_1 = 0,

``G_1`` the first harmonic of ``g`` on the mode's orbit. Friction is rate-independent: on the same
orbit run at another frequency ``Omega``, and shifted in phase, ``x_1 = X_1 e^{i phi}``, the
joints' first harmonic is ``G_1 e^{i phi}`` (the open contacts' dashpots excepted: they act at the
mode's frequency). The ansatz is that the forced response at ``Omega`` is the mode's orbit at the
amplitude it reaches. Its first-harmonic balance, with ``G_1`` taken from the mode's, is

    ((omega^2 - Omega^2) M + i (Omega - omega) C + i omega xi M) X_1 e^{i phi} = F.

Projected on the mode's shape, ``psi = X_1 / q`` with ``psi^H M psi = 1`` (the mass normalisation:
``q = sqrt(X_1^H M X_1)`` is the modal amplitude, real and > 0),

    (omega^2 - Omega^2 + i Omega c + i delta) q e^{i phi} = psi^H F,

with the structure's modal damping ``c = psi^H C psi`` [1/s], viscous (it scales with ``Omega``),
and the joints' ``delta = omega (xi - c)`` [1/s^2], hysteretic (it does not). At ``Omega = omega``
the bracket is ``i omega xi = 2 i zeta omega^2``, Krack's ``omega^2 - Omega^2 + 2 i zeta omega
Omega``; that form scales the joints' damping with ``Omega / omega`` as well, this one does not,
and so it is exact in two limits (``tests/test_mode_synthesis.py``):

- a linear system (every slider stuck) with classical damping: ``X_1`` is the real mode, ``xi =
  c``, and the equation is that mode's term of the modal expansion of the FRF;
- one harmonic on a single-DOF Jenkins oscillator: the describing function's forced response.

**Solved.** With ``P = |psi^H F| / q``, ``|.|^2`` of the equation at amplitude ``a`` is a quartic in
``Omega``,

    g(Omega) = Omega^4 + (c^2 - 2 omega^2) Omega^2 + 2 c delta Omega + omega^4 + delta^2 - P^2 = 0,

whose two positive roots ``Omega_-(a) < Omega_+(a)`` are the two sides of the peak; each root lies
on one side of ``g``'s minimum (from ``g' = 0``, a cubic) and is found by Brent's method to
rounding. The branch follows the mode's amplitudes upwards on the low side and downwards on the
high side; the peak is where the two meet, ``min g = 0``: between the last amplitude that has the
roots and the first that has none it is found by Brent's method in ``log a``, the mode solved
anew at each amplitude tried (the equations of :mod:`.nonlinear_mode`, from the nearest point), so
that the peak is exact for the mode too. The response of an output ``r`` (a row on the DOFs) is
``r psi psi^H F / (omega^2 - Omega^2 + i Omega c + i delta)``. Below the mode's smallest amplitude,
where the mode is stuck (linear), the requested frequencies outside the branch are the linear
tails, with the first point's data.

Only the first harmonic is balanced: the higher ones are the mode's, so the synthesis holds near
a resonance that one mode dominates (no other mode near the force's frequency nor, through the
harmonics, near its multiples).
"""
from __future__ import annotations

import math

import numpy as np
import scipy.optimize
from numpy.typing import ArrayLike

from ...errors import ParameterError, check_count, check_system
from ...excitation import HarmonicForce
from ...frequencies import check_omegas
from ...results.mode_synthesis import SynthesisedResponse
from ...results.nonlinear_mode import NonlinearMode
from ...system import FrictionSystem
from ...threads import owns_blas_threads
from .nonlinear_mode import _coefficients, _Equations, _reach, free_system

__all__ = ["mode_synthesis"]

#: the largest relative residual the mode's first point may leave in the system's own equations
MODE_CHECK = 1e-6


class _Point:
    """The modal data of the mode at one amplitude (module docstring): ``omega``, ``c``, ``delta``,
    ``q``, ``p = psi^H F``, ``r = row psi``, stuck, friction energy per cycle [J]."""

    def __init__(self, amplitude, omega, xi, x1, mass, damping, force, row, stuck, friction):
        self.amplitude, self.omega, self.stuck, self.friction = float(amplitude), float(omega), bool(stuck), float(friction)
        self.q = math.sqrt(float(np.real(np.vdot(x1, mass @ x1))))
        psi = x1 / self.q
        self.c = float(np.real(np.vdot(psi, damping @ psi)))
        self.delta = self.omega * (float(xi) - self.c)
        self.p = complex(np.vdot(psi, force))
        self.r = complex(row @ psi)
        big = abs(self.p) / self.q
        # g(Omega) = Omega^4 + b Omega^2 + e Omega + f
        self.b = self.c ** 2 - 2.0 * self.omega ** 2
        self.e = 2.0 * self.c * self.delta
        self.f = self.omega ** 4 + self.delta ** 2 - big ** 2

    def g(self, w: float) -> float:
        """The quartic ``g(Omega)`` [1/s^4]."""
        return ((w * w + self.b) * w + self.e) * w + self.f

    def minimum(self) -> tuple[float, float]:
        """``(Omega_m, g(Omega_m))``: the quartic's smallest value on ``Omega > 0`` (a root of ``g'
        = 4 Omega^3 + 2 b Omega + e``)."""
        roots = np.roots([4.0, 0.0, 2.0 * self.b, self.e])
        roots = roots[(np.abs(roots.imag) <= 1e-9 * np.abs(roots)) & (roots.real > 0)].real
        if roots.size == 0:
            return 0.0, self.f
        w = float(min(roots, key=self.g))
        for _ in range(3):  # Newton on g' to rounding
            d2 = 12.0 * w * w + 2.0 * self.b
            if d2 <= 0:
                break
            w -= (4.0 * w ** 3 + 2.0 * self.b * w + self.e) / d2
        return w, self.g(w)

    def sides(self) -> tuple[float, float]:
        """``(Omega_-, Omega_+)``: the quartic's roots below and above its minimum [rad/s] (NaN
        where there is none: above the peak, or below where the static response exceeds ``a``)."""
        wm, gm = self.minimum()
        if not gm <= 0:
            return math.nan, math.nan
        lo = math.nan
        if self.g(0.0) > 0 and wm > 0:
            lo = scipy.optimize.brentq(self.g, 0.0, wm, xtol=1e-300, rtol=4 * np.finfo(float).eps)
        hi_end = max(2.0 * wm, 1.0)
        while self.g(hi_end) <= 0:
            hi_end *= 2.0
        hi = scipy.optimize.brentq(self.g, wm, hi_end, xtol=1e-300, rtol=4 * np.finfo(float).eps)
        return lo, hi

    def response(self, w: float) -> complex:
        """The output's first harmonic at ``Omega = w`` on this point's data [m]."""
        return self.r * self.p / (self.omega ** 2 - w * w + 1j * w * self.c + 1j * self.delta)


class _Mode:
    """The mode's points as :class:`_Point`, and the mode at any amplitude (solved anew from the
    nearest solved point)."""

    def __init__(self, mode: NonlinearMode, system: FrictionSystem, force: np.ndarray, row: np.ndarray, tol: float,
                 max_iter: int):
        self.eq = _Equations(free_system(system), mode.n_harmonics, mode.dof)
        self.force, self.row, self.tol, self.max_iter = force, row, tol, max_iter
        ok = np.flatnonzero(mode.converged)
        ok = ok[np.argsort(mode.amplitude[ok], kind="stable")]
        self.points = [self._point(mode.amplitude[k], mode.frequency[k], mode.negative_damping[k], mode.harmonics[k],
                                   mode.stuck[k], mode.friction_per_cycle[k]) for k in ok]
        self.solved = [(float(mode.amplitude[k]), np.r_[_coefficients(self.eq, mode.harmonics[k]), mode.frequency[k],
                                                        mode.negative_damping[k]]) for k in ok]
        self.solves = 0
        if ok.size:  # the mode's own equations on this system: a mode of another system is refused
            a, y = self.solved[0]
            r = self.eq.residual(y, a, jacobian=False)[0]
            size = float(np.max(np.abs(r / np.r_[self.eq.row_scale * a, a, a])))
            if not size <= MODE_CHECK:
                raise ParameterError(f"mode: not a mode of this system (its point at {a:.4g} m leaves a relative "
                                     f"residual {size:.2g} in this system's equations, more than {MODE_CHECK:g})")

    def _point(self, a, w, xi, harmonics, stuck, friction) -> _Point:
        return _Point(a, w, xi, harmonics[1], self.eq.mass, self.eq.damping, self.force, self.row, stuck, friction)

    def at(self, amplitude: float) -> _Point | None:
        """The mode at ``amplitude`` [m] from the solved point nearest in ``log a`` (None where
        Newton did not converge)."""
        start = min(self.solved, key=lambda s: abs(math.log(s[0] / amplitude)))
        y, jf, _, ok = _reach(self.eq, start, amplitude, self.tol, self.max_iter)
        self.solves += 1
        if not ok:
            return None
        self.solved.append((amplitude, y))
        n = self.eq.size
        if jf is None:
            jf = self.eq.joint_forces(y[:n], y[n], jacobian=False)
        return self._point(amplitude, y[n], y[n + 1], self.eq.harmonics(y[:n]), jf.stuck, jf.dissipated)


def _peak(mode: _Mode, below: _Point, above: _Point) -> _Point | None:
    """The point of the mode between ``below`` (``min g <= 0``) and ``above`` (``min g > 0``) where
    ``min g = 0`` (the peak), by Brent's method in ``log a``; None where the mode failed."""
    lo, hi = math.log(below.amplitude), math.log(above.amplitude)
    cache = {lo: below, hi: above}  # Brent's method starts with the ends: the mode's own points

    def s(la: float) -> float:
        pt = cache.get(la) or mode.at(math.exp(la))
        if pt is None:
            raise _ModeFailed(math.exp(la))
        cache[la] = pt
        return pt.minimum()[1] / pt.omega ** 4

    try:
        la = scipy.optimize.brentq(s, lo, hi, xtol=1e-14, rtol=4 * np.finfo(float).eps)
    except _ModeFailed:
        return None
    return cache[la] if la in cache else mode.at(math.exp(la))


class _ModeFailed(Exception):
    """Newton did not converge on the mode at an amplitude the peak's search tried."""


def _output_row(system: FrictionSystem, output) -> tuple[str, np.ndarray]:
    """``(name, row)`` of the output: a DOF of the structure, or of the full model a reduced
    structure's ``transformation`` maps from."""
    st = system.structure
    full = list(getattr(st, "full_dof_names", ()))
    if isinstance(output, str) and output not in st.dof_names and output in full:
        return output, np.asarray(st.transformation[full.index(output)], dtype=float)
    try:
        k = st.dof_index(output)
    except (ParameterError, IndexError, TypeError, ValueError):
        raise ParameterError(f"output must be a DOF of the system{' or of the full model' if full else ''} "
                             f"(name or index), got {output!r}") from None
    row = np.zeros(st.n_dof)
    row[k] = 1.0
    return str(st.dof_names[k]), row


def _check_args(mode, system, omegas, tol, max_iter):
    """The cleaned arguments of :func:`mode_synthesis`: ``(omegas, force, max_iter)``."""
    check_system("mode", mode, NonlinearMode)
    check_system("system", system, FrictionSystem)
    ws = check_omegas("omegas", omegas)
    if mode.harmonics.shape[-1] != system.n_dof:
        raise ParameterError(f"mode: a mode of a system with {mode.harmonics.shape[-1]} DOFs, the system has "
                             f"{system.n_dof}")
    if not system.excitation or not all(isinstance(e, HarmonicForce) for e in system.excitation):
        raise ParameterError("system: the synthesis takes harmonic forces (HarmonicForce) as its excitation, got "
                             f"{[type(e).__name__ for e in system.excitation]}")
    if not (isinstance(tol, float) and 0 < tol < 1):
        raise ParameterError(f"tol must be a float in (0, 1), got {tol!r}")
    force = system.force_cos - 1j * system.force_sin
    if not np.any(force != 0):
        raise ParameterError("system: its harmonic forces are all zero")
    return ws, force, check_count("max_iter", max_iter, 1)


@owns_blas_threads
def mode_synthesis(mode: NonlinearMode, system: FrictionSystem, omegas: ArrayLike, output: str | int | None = None, *,
                   tol: float = 1e-11, max_iter: int = 40) -> SynthesisedResponse:
    """Forced response of ``system`` near the resonance of ``mode``, synthesised from the mode's
    frequency, damping and shape and the force's modal projection (module docstring).

    Parameters
    ----------
    mode : NonlinearMode
        A nonlinear mode of ``system`` (:func:`~frictionjoint.nonlinear_mode`), its amplitudes
        from below the resonance's response (a stuck first point gives the linear tails) to
        above its peak.
    system : FrictionSystem
        The system the mode is of, with its harmonic forces (``HarmonicForce``, any phases; the
        first harmonic ``F`` of ``Re(F e^{i Omega t})`` does not depend on the frequency).
    omegas : str or sequence of float
        The frequency range [rad/s] (:mod:`frictionjoint.frequencies`: ``"START:STOP:N"`` or
        frequencies): the branch's points between the lowest and the highest, and these
        frequencies where the linear tails are.
    output : str or int, optional
        The output DOF: of the system, or of the full model a reduced structure maps from (e.g. a
        blade's tip ``'w30'``); default the mode's DOF.
    tol : float
        Newton's tolerance of the mode solved at the amplitudes the peak's search tries, in (0, 1).
    max_iter : int
        Newton's iterations there at most, >= 1.

    Returns
    -------
    SynthesisedResponse
    """
    ws, force, max_iter = _check_args(mode, system, omegas, tol, max_iter)
    name, row = _output_row(system, mode.dof if output is None else output)
    md = _Mode(mode, system, force, row, tol, max_iter)
    if not md.points:
        raise ParameterError("mode: none of its amplitudes converged")
    pts, notes = md.points, []
    low, high, peak = [], [], None
    for k, pt in enumerate(pts):
        lo, hi = pt.sides()
        if math.isnan(hi):  # above the peak: the sides meet between this amplitude and the one before
            if k:
                peak = _peak(md, pts[k - 1], pt)
                notes.append(f"peak at {peak.amplitude:.6g} m of the mode ({md.solves} modes solved)" if peak else
                             "the mode did not converge where the peak's search tried it")
            else:
                notes.append("the response stays below the mode's first amplitude")
            break
        if not math.isnan(lo):
            low.append((lo, pt))
        high.append((hi, pt))
    else:
        notes.append(f"the mode's amplitudes end below the peak ({pts[-1].amplitude:.4g} m): extend them")
    n_stuck = next((k for k, pt in enumerate(pts) if not pt.stuck), len(pts))
    stuck_limit = pts[n_stuck - 1].amplitude if n_stuck else 0.0
    rows, linear_peak = _tails(ws, pts[0], stuck_limit, low, high, peak, notes)
    w_lo, w_hi = float(ws.min()), float(ws.max())
    rows = [r for r in rows if w_lo <= r[0] <= w_hi]
    return _result(system, name, row, force, rows, md, peak is not None or linear_peak, "; ".join(notes))


def _tails(ws, first: _Point, stuck_limit: float, low: list, high: list, peak, notes: list) -> tuple[list, bool]:
    """The branch's rows ``(Omega, response, mode amplitude, stuck, friction, message)`` in branch
    order, and whether the peak is linear. Up to ``stuck_limit``, the last amplitude of the mode's
    first stuck run, the response is linear: there the rows are the requested frequencies (the
    linear tails, from the first point's data); above it, the mode's amplitudes on the low side,
    the peak, the mode's amplitudes on the high side."""
    def on(w, pt, what):
        return (w, pt.response(w), pt.amplitude * abs(pt.p / (pt.omega ** 2 - w * w + 1j * w * pt.c + 1j * pt.delta))
                / pt.q, pt.stuck, pt.friction, what)

    limit = stuck_limit * (1 + 1e-12)
    low = [(w, pt) for w, pt in low if pt.amplitude > limit]
    high = [(w, pt) for w, pt in high if pt.amplitude > limit]
    rows = [on(w, pt, f"from the mode at {pt.amplitude:.6g} m, below the peak") for w, pt in low]
    linear_peak = peak is None and not low and not high and first.stuck
    if peak is not None:
        rows.append(on(peak.minimum()[0], peak, f"the peak, the mode at {peak.amplitude:.6g} m"))
    elif linear_peak:  # the response below the mode's first stuck run: linear, its peak too
        peak_row = on(first.minimum()[0], first, "the peak, linear (the mode's first point, stuck)")
        linear_peak = peak_row[2] <= limit
        rows += [peak_row] if linear_peak else []
    rows += [on(w, pt, f"from the mode at {pt.amplitude:.6g} m, above the peak") for w, pt in high[::-1]]
    if not first.stuck:
        notes.append("no linear tails: the mode's first amplitude slips")
        return rows, False
    tails = [on(float(w), first, "linear tail (the mode's first point, stuck)") for w in np.sort(ws)]
    kept = [t for t in tails if t[2] <= limit]
    if len(kept) < len(tails) and not rows:
        notes.append(f"{len(tails) - len(kept)} of the frequencies left out (their linear response would exceed "
                     f"{stuck_limit:.4g} m, the mode's last stuck amplitude, and the mode does not reach the peak)")
    w_mid = first.minimum()[0] if peak is None else rows[len(low)][0]
    return [t for t in kept if t[0] < w_mid] + rows + [t for t in kept if t[0] > w_mid], linear_peak


def _result(system, name, row, force, rows, md: _Mode, peak_found: bool, note: str) -> SynthesisedResponse:
    """The branch's rows as a :class:`SynthesisedResponse`, the linear limits beside it."""
    from ...linear_limits import limit_structures

    omega = np.array([r[0] for r in rows], dtype=float)
    fold = np.zeros(omega.size, bool)
    if omega.size > 2:
        d = np.diff(omega)
        fold[1:-1] = d[:-1] * d[1:] < 0
    limits = {k: st.harmonic_response(omega, force) @ row if omega.size else np.zeros(0, complex)
              for k, st in limit_structures(system).items()}
    return SynthesisedResponse(
        omega=omega, output=name, response=np.array([r[1] for r in rows], dtype=complex), limits=limits,
        stuck=np.array([r[3] for r in rows], dtype=bool), converged=np.ones(omega.size, bool),
        dissipated_per_cycle=np.array([r[4] for r in rows], dtype=float), messages=tuple(r[5] for r in rows),
        fold=fold, mode_amplitude=np.array([r[2] for r in rows], dtype=float),
        backbone_omega=np.array([p.omega for p in md.points]),
        backbone_response=np.array([p.r * p.q for p in md.points]), peak_found=peak_found, note=note)
