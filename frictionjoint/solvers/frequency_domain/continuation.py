"""Pseudo-arclength continuation of harmonic-balance solutions in the excitation frequency.

The branch ``r(z, omega) = 0`` (:mod:`.hbm`, ``z`` the joint coordinates' harmonics) is followed
in scaled coordinates ``y = (z / z_s, omega / omega_s)`` (``z_s`` the size of the first solution,
``omega_s`` the length of the frequency range; ``z_s`` grows with the largest solution met):
predictor along the unit tangent ``t``, corrector
by Newton's method on ``r = 0`` and ``t . (y - y_pred) = 0`` with the analytic Jacobian (``dr/dz``
from the exact hysteresis, ``dr/domega`` from ``d Z^-1 = -Z^-1 Z' Z^-1``). The step grows by 1.5
after an easy correction (<= 3 iterations) and halves after a failed one or one that does not
continue the branch (:func:`_continues`: it jumped to another stretch, went back in omega without a
fold, or turned by more than ``MAX_TURN`` in one step). A fold (turning point)
is where the tangent's ``omega`` component changes sign: both branches of a hysteretic resonance
come out in one run.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from ...threads import owns_blas_threads
from ...errors import ParameterError, check_count, check_system
from ...frequencies import check_omegas
from ...results.harmonic import HarmonicBalanceSweep
from ...system import FrictionSystem
from .hbm import Condensed, _peaks, check_harmonics, exact_orbit, harmonic_balance, lyapunov_stable, truncation_error

__all__ = ["hbm_sweep"]


def _at(system: FrictionSystem, omega: float) -> FrictionSystem:
    return FrictionSystem(system.structure, system.elements, omega=omega, excitation=system.excitation)


@owns_blas_threads
def hbm_sweep(system: FrictionSystem, omega_range: ArrayLike, n_harmonics: int = 7, *, n_points: int | None = None,
              tol: float = 1e-10, max_points: int | None = None, progress: bool = False,
              check: bool | ArrayLike = False) -> HarmonicBalanceSweep:
    """Harmonic-balance branch from ``omega_range[0]`` to ``omega_range[-1]`` by pseudo-arclength
    continuation (module docstring).

    Parameters
    ----------
    system : FrictionSystem
        The system (its excitation is kept; ``omega`` varies).
    omega_range : str or sequence of float
        Where the branch runs [rad/s], in the package's one convention (:mod:`frictionjoint.frequencies`):
        ``"START:STOP:N"`` (from ``START`` to ``STOP``, ``n_points`` defaulting to ``N``), or
        frequencies: two, ``(start, stop)``, or those of a sweep (from the first to the last,
        ``n_points`` defaulting to their number). Either order; first and last > 0 and different;
        the points are the branch's own. ``(0.5, 3.0, 40)`` could be three frequencies or a range
        of 40: refused (write ``"0.5:3.0:40"``).
    n_harmonics : int
        ``H`` >= 1.
    n_points : int, optional
        About how many points the branch should have over the range without folds (the initial
        step is ``1/n_points`` of the scaled range), >= 2; default 200 for ``(start, stop)``, else
        ``N`` or the number of frequencies given.
    tol : float
        Corrector tolerance, relative, in (0, 1).
    max_points : int, optional
        Points at most (default ``20 n_points``).
    progress : bool
        Show a progress bar (the part of the range covered [rad/s], and the points found).
    check : bool or sequence of float
        Check points against the exact time-domain steady state started from them
        (:func:`~frictionjoint.solvers.frequency_domain.hbm.exact_orbit`; one shooting each, usually a few Newton
        steps from the balanced state): their truncation error and their stability from the exact
        orbit's Floquet multipliers. True: every point; frequencies [rad/s]: the branch point
        nearest each.

    Returns
    -------
    HarmonicBalanceSweep
    """
    check_system("system", system, FrictionSystem)
    w_a, w_b, n_points, targets = _check_range(omega_range, n_points, check)
    hh = check_harmonics(n_harmonics, system, "hbm_sweep")
    n_points = check_count("n_points", n_points, 2)
    max_points = 20 * n_points if max_points is None else check_count("max_points", max_points, 1)
    if not (isinstance(tol, float) and 0 < tol < 1):
        raise ParameterError(f"tol must be a float in (0, 1), got {tol!r}")
    first = harmonic_balance(_at(system, w_a), n_harmonics=hh, tol=tol)
    rows, message = _follow(system, hh, tol, first, w_a, w_b, n_points, max_points, progress)
    return _sweep_result(system, rows, hh, message, check, targets)


def _follow(system: FrictionSystem, hh: int, tol: float, first, w_a: float, w_b: float, n_points: int,
            max_points: int, progress: bool) -> tuple:
    """The branch from the balance ``first`` at ``w_a`` towards ``w_b`` (module docstring): its
    points as rows ``(omega, harmonics, dissipated, fold, converged, message, slider positions,
    stuck)`` and the message that says where and why it ended."""
    from tqdm import tqdm

    cond = Condensed(_at(system, w_a), hh)
    z = cond.joint_vector(first.harmonics)
    zs = max(float(np.max(np.abs(z))), 1e-300)
    ws = abs(w_b - w_a)
    sense = 1.0 if w_b > w_a else -1.0
    nz = z.size
    w = w_a
    res, jz, jw, jf = _equations(z, cond)
    t = _tangent(jz, jw, np.r_[np.zeros(nz), sense], ws, zs)
    y = np.r_[z / zs, w / ws]
    y_prev = None
    ds = 1.0 / n_points
    ds_min, ds_max = 1e-7, 4.0 / n_points
    ds_corner = ds / 64  # at or below it a turn of more than MAX_TURN is a corner of the branch (_continues)
    rows = [(w, cond.harmonics(jf.r), jf.dissipated, False, first.converged, first.message, jf.slider_positions,
             jf.stuck)]
    message = ""
    if not first.converged:  # nothing to follow: say so rather than step from a wrong point
        message = (f"no balance at the start omega = {w_a:.6g} rad/s ({first.message}); start the branch "
                   f"where the response is simpler (the other end of the range, or farther from resonance)")
        max_points = 1
    # the bar covers the range in rad/s (the number of points is the branch's own: folds add some),
    # and counts the points found
    bar = tqdm(total=ws, desc="hbm", file=__import__("sys").stderr, disable=not progress, leave=False,
               bar_format="{desc}: {percentage:3.0f}%|{bar}| {n:.6g}/{total:.6g} rad/s of the range [{elapsed}{postfix}]")
    try:
        while len(rows) < max_points:
            y_pred = y + ds * t
            ok, yk, it, ck, jz, jw, jf = _correct(system, hh, y_pred, t, ws, zs, tol, y if ds <= ds_corner else None)
            t_new = _tangent(jz, jw, t, ws, zs) if ok else None
            if not ok or not _continues(y, y_prev, y_pred, yk, t, t_new, ds, ds_corner):
                ds *= 0.5
                if ds < ds_min:
                    message = f"step below {ds_min:g} at omega = {y[nz] * ws:.6g} rad/s: the branch could not be followed"
                    break
                continue
            fold = (t_new[nz] * t[nz]) < 0
            y_prev = y
            y, t = yk, t_new
            w = y[nz] * ws
            rows.append((w, ck.harmonics(jf.r), jf.dissipated, bool(fold), True,
                         f"converged in {it - 1} corrector iterations", jf.slider_positions, jf.stuck))
            ds = min(ds * 1.5, ds_max) if it <= 4 else ds
            zs = _rescale(y, y_prev, t, yk[:nz] * zs, zs)
            done = (w - w_b) * sense >= 0
            bar.n = ws * min(max((w - w_a) / (w_b - w_a), 0.0), 1.0)
            bar.set_postfix_str(f"{len(rows)} points", refresh=True)
            if done:
                message = f"reached omega = {w:.6g} rad/s"
                break
            if not (min(w_a, w_b) - ws <= w <= max(w_a, w_b) + ws):
                message = f"left the range at omega = {w:.6g} rad/s"
                break
        else:
            message = message or f"stopped after max_points = {max_points} points"
    finally:
        bar.close()
    return rows, message


#: The largest turn of the unit tangent over one step [rad] (Allgower & Georg, *Introduction to
#: Numerical Continuation Methods*, SIAM 2003, the steplength control of their Program 1: ``amax``)
MAX_TURN = np.pi / 3


def _continues(y, y_prev, y_pred, yk, t, t_new, ds, ds_corner) -> bool:
    """Whether the corrected point ``yk`` (unit tangent ``t_new``) continues the branch from ``y``
    (unit tangent ``t``; the point before it ``y_prev``) along the step ``ds`` predicted at ``y_pred``.

    Refused (the caller halves the step), at any step:

    - a point nearer the one before the last than the last: it retraces the branch (at a corner the
      hyperplane can cut the branch twice; a shorter step goes on past the corner);
    - a point behind the last in omega while both tangents point ahead in omega: no fold lies
      between them, so a smooth arc from ``y`` to ``yk`` would have to turn back and forth (two folds)
      within one step. This is the jump across a sharp peak: its loop brings the flanks below and
      above it within a step of each other (a lightly damped linear peak, the free-slip limit of a
      friction joint), and the hyperplane through a coarse predictor cuts the other flank (the
      Ti-64 blade at friction_coefficient = 1e-20 went 1715 -> 1613 -> 1840 rad/s).

    and above ``ds_corner`` (Allgower & Georg's steplength control, *Introduction to Numerical
    Continuation Methods*, SIAM 2003, ch. 6: the distance to the curve and the angle between
    tangents):

    - a corrector that moved farther than the step from its predictor (it jumped to another stretch
      of the branch);
    - a step whose arc turns by more than ``MAX_TURN``: any smooth arc from ``y`` to ``yk`` turns by
      at least ``a + b``, ``a`` and ``b`` the angles between the chord ``yk - y`` and the tangents
      ``t`` and ``t_new`` (the chord is a mean of the arc's tangents, which lie within the spherical
      ellipse of directions whose angles to ``t`` and ``t_new`` add up to at most the arc's turn).
      On a plane arc ``a + b`` is the angle between the tangents; it is larger where the corrector
      landed on another stretch of the branch.

    At or below ``ds_corner`` a larger turn is a corner of the branch (a slider's stick/slip
    boundary, a contact's lift-off: the loops' Jacobian jumps there), and passes; there the corrector
    solves on the sphere of radius ``ds`` about ``y`` (:func:`_correct`), which cuts the branch
    past a corner of any angle.
    """
    if y_prev is not None and np.linalg.norm(yk - y_prev) < np.linalg.norm(yk - y):
        return False
    if t[-1] * t_new[-1] > 0 and (yk[-1] - y[-1]) * t[-1] < -1e-6 * ds * abs(t[-1]):
        return False
    if ds <= ds_corner:
        return True
    chord = (yk - y) / np.linalg.norm(yk - y)
    turn = np.arccos(np.clip(t @ chord, -1.0, 1.0)) + np.arccos(np.clip(chord @ t_new, -1.0, 1.0))
    return bool(np.linalg.norm(yk - y_pred) <= ds and turn <= MAX_TURN)


def _check_range(omega_range, n_points, check):
    """``(w_a, w_b, n_points, targets)`` of :func:`hbm_sweep`'s range and check arguments: the first
    and last frequency, the default number of points, the check's frequencies (None for True or
    False); refuses what they cannot be."""
    ws_in = check_omegas("omega_range", omega_range)
    if ws_in.size < 2:
        raise ParameterError(f"omega_range must hold a start and an end angular frequency [rad/s] ('START:STOP:N', "
                             f"(start, stop) or the frequencies of a sweep), got {omega_range!r}")
    w_a, w_b = float(ws_in[0]), float(ws_in[-1])
    if n_points is None:
        n_points = ws_in.size if isinstance(omega_range, str) or ws_in.size > 2 else 200
    targets = None
    if check is not True and check is not False:
        try:
            targets = np.asarray(check, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise ParameterError(f"check must be True, False or frequencies [rad/s], got {check!r}") from None
        if targets.size == 0 or not np.all(np.isfinite(targets)) or np.any(targets <= 0):
            raise ParameterError(f"check: frequencies must be finite and > 0 [rad/s], got {check!r}")
    if w_a == w_b:
        raise ParameterError("omega_range must have two different frequencies")
    return w_a, w_b, n_points, targets


def _equations(zz: np.ndarray, c: Condensed):
    """The branch's residual ``r(z, omega)`` at the joint coordinates ``zz`` and the frequency of
    ``c``, its derivatives ``dr/dz`` and ``dr/domega``, and the joints' forces."""
    f = c.forces(zz)
    res = zz - c.q_linear + c.Y @ f.r
    jz = np.eye(zz.size) + c.Y @ f.jacobian
    dy, dl = c.omega_derivative()
    jw = -dl + dy @ f.r + c.Y @ f.d_omega
    return res, jz, jw, f


def _tangent(jz: np.ndarray, jw: np.ndarray, t_prev: np.ndarray, ws: float, zs: float) -> np.ndarray:
    """The branch's unit tangent in scaled coordinates, on the side of ``t_prev``."""
    nz = jz.shape[0]
    a = np.zeros((nz + 1, nz + 1))
    a[:nz, :nz] = jz  # in scaled coordinates: d/d(z/zs) = jz zs, d/d(w/ws) = jw ws; rows / zs
    a[:nz, nz] = jw * ws / zs
    a[nz] = t_prev
    rhs = np.zeros(nz + 1)
    rhs[nz] = 1.0
    t = np.linalg.solve(a, rhs)
    t /= np.linalg.norm(t)
    return t if t @ t_prev >= 0 else -t


def _correct(system: FrictionSystem, hh: int, y_pred: np.ndarray, t: np.ndarray, ws: float, zs: float, tol: float,
             centre: np.ndarray | None = None):
    """Newton's corrector from the predicted ``y_pred`` on ``r = 0`` and ``t . (y - y_pred) = 0``
    (or, given ``centre``, on the sphere ``|y - centre| = |y_pred - centre|``: it cuts the branch
    past a corner of any angle, where the hyperplane cuts the branch's new stretch far away or not
    at all): ``(ok, y, iterations + 1, condensed system, dr/dz, dr/domega, joint forces)`` (``ok``
    False: no convergence in 15 iterations, a frequency <= 0 or a singular matrix)."""
    nz = y_pred.size - 1
    radius = None if centre is None else float(np.linalg.norm(y_pred - centre))
    yk = y_pred.copy()
    ck = jz = jw = jf = None
    for it in range(1, 16):
        wk = yk[nz] * ws
        if wk <= 0:
            break
        ck = Condensed(_at(system, wk), hh)
        zk = yk[:nz] * zs
        res, jz, jw, jf = _equations(zk, ck)
        if centre is None:
            arc, row = t @ (yk - y_pred), t
        else:  # (|y - centre|^2 - radius^2) / (2 radius): the hyperplane's arc to first order
            arc, row = ((yk - centre) @ (yk - centre) - radius ** 2) / (2.0 * radius), (yk - centre) / radius
        if float(np.max(np.abs(res))) <= tol * max(float(np.max(np.abs(zk))), 1e-6 * zs) and abs(arc) <= 1e-12:
            return True, yk, it, ck, jz, jw, jf
        a = np.zeros((nz + 1, nz + 1))
        a[:nz, :nz] = jz * zs
        a[:nz, nz] = jw * ws
        a[nz] = row
        try:
            step = np.linalg.solve(a, -np.r_[res, arc])
        except np.linalg.LinAlgError:
            break
        yk = yk + step
    return False, yk, 0, ck, jz, jw, jf


def _rescale(y: np.ndarray, y_prev: np.ndarray, t: np.ndarray, z: np.ndarray, zs: float) -> float:
    """z's scale follows the largest solution so far (a resonance many times the start's size would
    otherwise make the arclength, and the number of points, that many times longer): ``y``,
    ``y_prev`` and ``t`` rescaled in place where ``max |z|`` passed twice the scale ``zs``; returns
    the scale."""
    nz = z.size
    zmax = float(np.max(np.abs(z)))
    if zmax > 2.0 * zs:
        y[:nz] *= zs / zmax
        y_prev[:nz] *= zs / zmax
        t[:nz] *= zs / zmax
        t /= np.linalg.norm(t)
        zs = zmax
    return zs


def _sweep_result(system: FrictionSystem, rows: list, hh: int, message: str, check, targets) -> HarmonicBalanceSweep:
    """The branch's points as a :class:`HarmonicBalanceSweep`, the checked ones against the exact
    time-domain steady state (truncation error, stability)."""
    omegas = np.array([row[0] for row in rows])
    harm = np.array([row[1] for row in rows])
    stable = trunc = None
    if check is not False:
        picked = (range(len(rows)) if check is True
                  else sorted({int(np.argmin(np.abs(omegas - w))) for w in targets}))
        stable = np.full(len(rows), None, dtype=object)
        trunc = np.full(len(rows), np.nan)
        for k in picked:
            ex = exact_orbit(_at(system, rows[k][0]), rows[k][1], rows[k][6], peaks=False)
            stable[k] = lyapunov_stable(ex)
            err = truncation_error(rows[k][1], ex)
            trunc[k] = np.nan if err is None else err
    return HarmonicBalanceSweep(
        omega=omegas, harmonics=harm, harmonic_amplitude=np.abs(harm[:, 1]), phase=-np.angle(harm[:, 1]),
        amplitude=np.array([_peaks(hm) for hm in harm]), dissipated_per_cycle=np.array([row[2] for row in rows]),
        fold=np.array([row[3] for row in rows]), converged=np.array([row[4] for row in rows]), n_harmonics=hh,
        messages=tuple(row[5] for row in rows), message=message, stable=stable, truncation_error=trunc,
        stuck=np.array([row[7] for row in rows]))
