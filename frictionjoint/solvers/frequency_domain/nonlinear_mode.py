"""Nonlinear modes of friction systems by the extended periodic motion concept (EPMC; Krack,
"Nonlinear modal analysis of nonconservative systems: extension of the periodic motion concept",
Computers & Structures 154, 2015), with the exact hysteresis of :mod:`.hbm`.

The excitation is removed and a negative mass-proportional damping ``-xi M x'`` is added, so that
the free motion at an amplitude is periodic:

    M x'' + (C - xi M) x' + K x + G^T T(G x) = F_0,

``F_0`` the joints' constant loads. With ``x = sum_h (a_h cos h theta + b_h sin h theta)``, ``theta =
omega t``, the unknowns are every DOF's real coefficients, ``omega`` and ``xi``; two more equations
fix the first harmonic at one DOF to ``A cos theta`` (amplitude ``a_1 = A``, phase ``b_1 = 0``).
The damping ratio is ``zeta = xi / (2 omega)``; the energy the negative damping puts in per period,
``xi oint x'^T M x' dt``, is what friction and the dashpots take out (to Newton's tolerance).

Unlike :func:`.hbm.harmonic_balance` the equations are not condensed to the joints: the motion
exists because the linear part is (nearly) singular at the mode, and its condensed form is 0 = 0
while the joints stick. They are written on all DOFs (``n_dof (2H + 1) + 2`` unknowns); the joints'
forces ``R`` (less their stuck springs) and their analytic Jacobian are :class:`.hbm.Condensed`'s.
Newton's method with a backtracking line search solves them at each amplitude, from the previous
amplitude's solution (its harmonics scaled); the first from the stuck system's linear mode. Where
Newton fails, the step in amplitude is halved (in its logarithm).

The check (``check=True``): from the state of a point of the mode (:func:`.hbm.balanced_state`)
the system without excitation and without negative damping is marched exactly
(:func:`~frictionjoint.solvers.marcher.simulate`); each cycle between successive maxima of the
modal coordinate (the point's first-harmonic shape, mass-weighted) gives a frequency ``2 pi / T``,
the energy lost (friction and dashpots, exact at the maxima) and the first-harmonic amplitude at
the DOF over the cycle; the mode is solved at that amplitude and compared. The comparison itself
is exact only for a stationary motion: over a cycle the decay's amplitude falls by about ``2 pi
zeta``, so the decay's frequency and energy differ from the mode's at one amplitude in the second
order of it (on a Jenkins chain about ``zeta^2`` and ``3 zeta^2``), besides the truncation.

The reference at any damping is the EPMC's own orbit solved exactly in time
(:mod:`frictionjoint.solvers.marcher.autonomous`, started from the points :func:`orbit_starts`
gives): its frequency and damping ratio differ from the ones here by the truncation alone.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike

from ...errors import ParameterError, check_count, check_grid, check_system
from ...excitation import HarmonicBaseMotion
from ...results.nonlinear_mode import DecayCheck, NonlinearMode
from ...structure import LinearStructure
from ...system import FrictionSystem
from ...threads import owns_blas_threads
from . import hysteresis
from .hbm import Condensed, balanced_state, check_harmonics

__all__ = ["nonlinear_mode", "orbit_starts"]

#: cycles of the free decay compared per checked point
DECAY_CYCLES = 4
#: output samples per cycle of the free decay (maxima refined between them; first harmonics integrated)
DECAY_SAMPLES = 256
#: halvings (in log amplitude) of a step that Newton could not take
MAX_HALVINGS = 8
#: amplitudes [m] beyond ``[1 / SCALED_BEYOND, SCALED_BEYOND]`` are solved in units of a power of 2
#: near the largest (:func:`_amplitude_scale`): ``k u`` would overflow (or the square of an amplitude
#: underflow)
SCALED_BEYOND = 2.0 ** 500


def free_system(system: FrictionSystem, omega: float | None = None) -> FrictionSystem:
    """``system`` without its excitation: harmonic forces and held forces removed, harmonic base
    motions replaced by their springs and dashpots to a fixed base (in the structure); the joints
    and their constant loads kept.

    Parameters
    ----------
    system : FrictionSystem
    omega : float, optional
        The frequency the returned system carries [rad/s] (no source uses it; a balanced state's
        velocities do); default none.

    Returns
    -------
    FrictionSystem
    """
    st = system.structure
    base = [e for e in system.excitation if isinstance(e, HarmonicBaseMotion)]
    if base:
        k, c = np.array(st.stiffness), np.array(st.damping)
        for e in base:
            i = st.dof_index(e.dof)
            k[i, i] += e.stiffness
            c[i, i] += e.damping
        st = LinearStructure(st.mass, k, c, dof_names=st.dof_names, indefinite_stiffness=st.indefinite_stiffness)
    return FrictionSystem(st, system.elements, omega=omega)


class _Equations:
    """The EPMC equations of a system without excitation at ``H`` harmonics, on all DOFs (module
    docstring); unknowns ``y = (X, omega, xi)``, ``X[dof (2H + 1) + j]`` (``j = 0`` the mean, ``2h -
    1`` cos, ``2h`` sin), ``X`` and the amplitudes in units of ``scale`` [m] (the joints' forces
    divided by it: :meth:`.hbm.Condensed.set_force_scale`). With ``stiffness`` given: that linear
    system, without the joints (a linear limit)."""

    def __init__(self, system: FrictionSystem, hh: int, dof: int, stiffness: np.ndarray | None = None,
                 scale: float = 1.0):
        self.n_harmonics = hh
        self.scale = scale  # the unit of the coefficients and amplitudes [m] (_amplitude_scale)
        self.nc = nc = 2 * hh + 1
        self.dof = dof
        n = system.n_dof
        self.size = n * nc
        d = hysteresis.derivative_matrix(hh)
        eye = np.eye(nc)
        if stiffness is None:
            self.cond = Condensed(system, hh)
            self.cond.set_force_scale(scale)
            k_lin, m, c = self.cond._lin
            self.gk = np.kron(self.cond.G, eye)
        else:
            self.cond = None
            k_lin, m, c = stiffness, system.mass, system.damping
        self.kk, self.m1, self.m2, self.c1 = np.kron(k_lin, eye), np.kron(m, d), np.kron(m, d @ d), np.kron(c, d)
        self.k_lin, self.mass, self.damping = k_lin, m, c
        self.f0 = np.zeros(self.size)
        if stiffness is None:
            self.f0[::nc] = system.constant_force / scale
        self.dk = np.kron(np.eye(n), d)  # the phase derivative of every DOF's coefficients
        # row scales (a DOF's dynamic stiffness), for the line search and the linear solves
        self.row_scale = np.repeat(np.maximum(np.abs(np.diag(k_lin)), 1e-300), nc)

    def joint_forces(self, x: np.ndarray, omega: float, jacobian: bool = True):
        """The joints' forces (:meth:`.hbm.Condensed.forces`) on the orbit ``x`` at ``omega``, or
        None for a linear limit."""
        if self.cond is None:
            return None
        self.cond.omega = omega  # the open contacts' dashpots act at the orbit's frequency
        return self.cond.forces(self.gk @ x, jacobian)

    def residual(self, y: np.ndarray, amplitude: float, jacobian: bool = True):
        """``(r, J, joint forces)``: the equations' residual (forces on the DOFs' coefficients [N],
        then the first harmonic's amplitude and phase conditions [m]) and its Jacobian."""
        nn = self.size
        x, w, xi = y[:nn], y[nn], y[nn + 1]
        jf = self.joint_forces(x, w, jacobian)
        m1x = self.m1 @ x
        ia = self.dof * self.nc + 1
        r = np.empty(nn + 2)
        r[:nn] = self.kk @ x + w * (self.c1 @ x - xi * m1x) + w * w * (self.m2 @ x) - self.f0
        if jf is not None:
            r[:nn] += self.gk.T @ jf.r
        r[nn] = x[ia] - amplitude
        r[nn + 1] = x[ia + 1]
        if not jacobian:
            return r, None, jf
        jac = np.zeros((nn + 2, nn + 2))
        jac[:nn, :nn] = self.kk + w * (self.c1 - xi * self.m1) + w * w * self.m2
        jac[:nn, nn] = self.c1 @ x - xi * m1x + 2.0 * w * (self.m2 @ x)
        jac[:nn, nn + 1] = -w * m1x
        if jf is not None:
            jac[:nn, :nn] += self.gk.T @ jf.jacobian @ self.gk
            jac[:nn, nn] += self.gk.T @ jf.d_omega
        jac[nn, ia] = 1.0
        jac[nn + 1, ia + 1] = 1.0
        return r, jac, jf

    def kinetic_integral(self, x: np.ndarray, matrix: np.ndarray, factor: float = 1.0) -> float:
        """``factor int_0^2pi (dx/dtheta)^T A (dx/dtheta) dtheta`` of the coefficients ``x`` (``A`` = M
        or C), ``x`` scaled by its largest coefficient first (at amplitudes near 1e300 the square
        alone would overflow where the product with a small ``factor`` does not)."""
        s = float(np.max(np.abs(x), initial=0.0))
        if not 0 < s < math.inf:
            return 0.0 if s == 0 else math.nan
        dx = (self.dk @ (x / s)).reshape(-1, self.nc)
        e = math.pi * float(np.einsum("ij,ik,jk->", matrix, dx, dx))
        return 0.0 if e == 0 else float(factor) * s * (s * e)  # inf where the energy itself is beyond floats

    def harmonics(self, x: np.ndarray) -> np.ndarray:
        """Complex harmonics ``(H + 1, n_dof)``, ``X_h = a_h - i b_h`` (as :func:`.hbm.harmonic_balance`'s)."""
        c = x.reshape(-1, self.nc)
        out = np.empty((self.n_harmonics + 1, c.shape[0]), complex)
        out[0] = c[:, 0]
        out[1:] = (c[:, 1::2] - 1j * c[:, 2::2]).T
        return out


def _newton(eq: _Equations, y: np.ndarray, amplitude: float, tol: float, max_iter: int):
    """Newton's method with backtracking (the row-scaled residual's max norm must fall) from ``y``:
    ``(y, joint forces, iterations, converged)``. Converged: a full Newton step of relative size <=
    ``tol`` (coefficients against ``amplitude``, ``omega`` and ``xi`` against ``omega``), taken."""
    nn = eq.size
    rows = np.r_[eq.row_scale * amplitude, amplitude, amplitude]

    def size(r):
        return float(np.linalg.norm(r / rows))

    r, jac, jf = eq.residual(y, amplitude)
    for it in range(1, max_iter + 1):
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(jac))):
            return y, jf, it, False
        cols = np.r_[np.full(nn, amplitude), abs(y[nn]), abs(y[nn])]
        try:
            step = cols * np.linalg.solve((jac / rows[:, None]) * cols[None, :], -r / rows)
        except np.linalg.LinAlgError:
            return y, jf, it, False
        small = float(np.max(np.abs(step / cols))) <= tol
        rn = size(r)
        lam = 1.0
        for _ in range(30):
            yt = y + lam * step
            if small or yt[nn] <= 0:
                if yt[nn] > 0:
                    break
            else:
                rt, _, _ = eq.residual(yt, amplitude, jacobian=False)
                if size(rt) < rn or lam < 1e-6:
                    break
            lam *= 0.5
        y = yt
        r, jac, jf = eq.residual(y, amplitude)
        if small:
            return y, jf, it, True
    return y, jf, max_iter, False


def _predict(eq: _Equations, y: np.ndarray, a_from: float, a_to: float) -> np.ndarray:
    """The start at ``a_to`` from the solution at ``a_from``: its harmonics scaled, mean, ``omega``
    and ``xi`` kept."""
    out = y.copy()
    x = out[:eq.size].reshape(-1, eq.nc)
    x[:, 1:] *= a_to / a_from
    return out


def _reach(eq: _Equations, start: tuple, amplitude: float, tol: float, max_iter: int, depth: int = 0):
    """The mode at ``amplitude`` from the solution ``start = (a, y)``; where Newton fails, the
    midpoint (in log amplitude) first, down to :data:`MAX_HALVINGS` halvings: ``(y, joint forces,
    iterations, converged)``, the iterations summed over the intermediate points."""
    a0, y0 = start
    y, jf, it, ok = _newton(eq, _predict(eq, y0, a0, amplitude), amplitude, tol, max_iter)
    if ok or depth >= MAX_HALVINGS:
        return y, jf, it, ok
    mid = math.sqrt(a0 * amplitude)
    ym, jfm, itm, okm = _reach(eq, start, mid, tol, max_iter, depth + 1)
    if not okm:
        return ym, jfm, it + itm, False
    y, jf, it2, ok = _reach(eq, (mid, ym), amplitude, tol, max_iter, depth + 1)
    return y, jf, it + itm + it2, ok


def _arc_matrix(eq: _Equations, jac: np.ndarray, t: np.ndarray, scales: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """The extended Jacobian of ``(r(y, A), t . v)`` in the scaled unknowns ``v = (y, A) / scales``,
    rows scaled by ``rows``; ``dr/dA`` is -1 in the amplitude's row."""
    nn = eq.size
    a = np.zeros((nn + 3, nn + 3))
    a[:nn + 2, :nn + 2] = jac * scales[None, :nn + 2] / rows[:, None]
    a[nn, nn + 2] = -scales[nn + 2] / rows[nn]
    a[nn + 2] = t
    return a


def _arc_scales(eq: _Equations, u: np.ndarray, omega: float):
    """``(scales, rows)`` at the branch point ``u = (X, omega, xi, A)``: each DOF's coefficients on
    its largest (at least 1e-3 of the largest DOF's), the amplitude on itself, ``omega`` and ``xi``
    on the stuck frequency; the rows as in :func:`_newton`."""
    a = u[-1]
    per_dof = np.max(np.abs(u[:eq.size].reshape(-1, eq.nc)[:, 1:]), axis=1)
    per_dof = np.maximum(per_dof, 1e-3 * max(float(per_dof.max()), a))
    return np.r_[np.repeat(per_dof, eq.nc), omega, omega, a], np.r_[eq.row_scale * a, a, a]


def _branch(eq: _Equations, y0: np.ndarray, a0: float, a_end: float, tol: float, max_points: int = 300):
    """Pseudo-arclength continuation of the mode from the solution ``y0`` at ``a0`` until the
    amplitude passes ``a_end`` (hbm_sweep's scheme with the amplitude as the parameter, each DOF's
    coefficients scaled by their size): the branch points ``[(A, y)]``, how many folds (turning
    points in amplitude) it passed, and why it stopped; it gives up where the branch turns back
    below half of ``a0``. Amplitude alone cannot pass a fold; this can."""
    nn = eq.size
    omega = float(y0[nn])
    u = np.r_[y0, a0]
    sc, rows = _arc_scales(eq, u, omega)
    _, jac, _ = eq.residual(u[:-1], u[-1])
    e_a = np.zeros(nn + 3)
    e_a[-1] = 1.0
    t = _arc_tangent(eq, jac, e_a, sc, rows)
    pts, folds, ds, u_prev = [(a0, y0)], 0, 0.05, None
    while u[-1] < a_end and len(pts) < max_points:
        if u[-1] < 0.5 * a0:
            return pts, folds, f"it turned back to {u[-1]:.4g} m"
        pred = u / sc + ds * t
        ok, uk, jac = _arc_correct(eq, pred, t, sc, rows, tol)
        # as in hbm_sweep: a corrector that moved farther than the step, or landed nearer the point
        # before the last than the last (it retraces the branch past a kink), takes a shorter step
        if (not ok or np.linalg.norm(uk / sc - pred) > ds
                or (u_prev is not None and np.linalg.norm((uk - u_prev) / sc) < np.linalg.norm((uk - u) / sc))):
            ds *= 0.5
            if ds < 1e-7:
                return pts, folds, f"the branch could not be followed past amplitude {u[-1]:.4g} m"
            continue
        t_new = _arc_tangent(eq, jac, t, sc, rows)
        folds += int(t_new[-1] * t[-1] < 0)
        u_prev, u = u, uk
        sc_new, rows = _arc_scales(eq, u, omega)
        t = t_new * sc / sc_new  # the tangent in the new point's scales
        t /= np.linalg.norm(t)
        sc = sc_new
        pts.append((float(u[-1]), u[:-1].copy()))
        ds = min(ds * 1.5, 0.3)
    return pts, folds, "reached" if u[-1] >= a_end else f"stopped after {max_points} branch points"


def _arc_tangent(eq, jac, t_prev, sc, rows) -> np.ndarray:
    """The branch's unit tangent in scaled unknowns, on the side of ``t_prev``."""
    rhs = np.zeros(eq.size + 3)
    rhs[-1] = 1.0
    t = np.linalg.solve(_arc_matrix(eq, jac, t_prev, sc, rows), rhs)
    t /= np.linalg.norm(t)
    return t if t @ t_prev >= 0 else -t


def _arc_correct(eq, pred, t, sc, rows, tol):
    """Newton's corrector on ``r = 0`` and ``t . (v - pred) = 0`` from ``pred``: ``(ok, u,
    Jacobian there)``."""
    nn = eq.size
    v = pred.copy()
    for _ in range(15):
        u = v * sc
        if u[nn] <= 0 or u[-1] <= 0:
            break
        r, jac, _ = eq.residual(u[:-1], u[-1])
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(jac))):
            break
        try:
            step = np.linalg.solve(_arc_matrix(eq, jac, t, sc, rows), -np.r_[r / rows, t @ (v - pred)])
        except np.linalg.LinAlgError:
            break
        v = v + step
        if float(np.max(np.abs(step))) <= tol:
            u = v * sc
            return True, u, eq.residual(u[:-1], u[-1])[1]
    return False, v * sc, None


def _on_branch(eq: _Equations, pts: list, amplitude: float, tol: float, max_iter: int):
    """The mode at ``amplitude`` from the branch: Newton from the interpolation between the first
    two successive branch points whose amplitudes bracket it; ``(y, joint forces, iterations,
    converged)``, not converged where the branch does not reach it."""
    for (a0, y0), (a1, y1) in zip(pts[:-1], pts[1:]):
        if (a0 - amplitude) * (a1 - amplitude) <= 0:
            f = (amplitude - a0) / (a1 - a0) if a1 != a0 else 0.0
            return _newton(eq, y0 + f * (y1 - y0), amplitude, tol, max_iter)
    return pts[-1][1], None, 0, False


def _linear_mode(k: np.ndarray, m: np.ndarray, mode: int):
    """``(omega, shape)`` of mode ``mode`` (ascending, the rigid-body ones counted) of ``k``, ``m``;
    the shape real, mass-normalised."""
    lam, vec = scipy.linalg.eig(k, m)
    lam, vec = lam.real, vec.real
    order = np.argsort(lam)
    if mode >= lam.size:
        raise ParameterError(f"mode must be < {lam.size} (the system's DOFs), got {mode}")
    v = vec[:, order[mode]]
    v = v / math.sqrt(abs(v @ m @ v))
    return math.sqrt(max(lam[order[mode]], 0.0)), v, lam[order], vec[:, order]


def _start(eq: _Equations, omega: float, shape: np.ndarray, amplitude: float) -> np.ndarray:
    """The linear mode as the unknowns ``y`` at ``amplitude`` (first harmonic at the DOF), ``xi``
    its Rayleigh quotient of ``C / M``."""
    y = np.zeros(eq.size + 2)
    x = y[:eq.size].reshape(-1, eq.nc)
    x[:, 1] = shape * amplitude / shape[eq.dof]
    y[eq.size] = omega
    y[eq.size + 1] = float(shape @ eq.damping @ shape) / float(shape @ eq.mass @ shape)
    return y


def _limit(system: FrictionSystem, stiffness: np.ndarray, shape: np.ndarray, dof: int, tol: float):
    """``(omega, zeta)`` of a linear limit by the same equations (``H = 1``, no joints): the mode
    of ``stiffness`` most like ``shape`` (mass-weighted MAC); NaN for a rigid-body mode."""
    m = system.mass
    _, _, lam, vec = _linear_mode(stiffness, m, 0)
    mac = (vec.T @ m @ shape) ** 2 / (np.einsum("ij,ik,kj->j", vec, m, vec) * (shape @ m @ shape))
    j = int(np.argmax(mac))
    if not lam[j] > 0 or vec[dof, j] == 0:
        return math.nan, math.nan
    eq = _Equations(system, 1, dof, stiffness=stiffness)
    v = vec[:, j] / math.sqrt(abs(vec[:, j] @ m @ vec[:, j]))
    y, _, _, ok = _newton(eq, _start(eq, math.sqrt(lam[j]), v, 1.0), 1.0, tol, 30)
    if not ok:
        return math.nan, math.nan
    return float(y[eq.size]), float(y[eq.size + 1] / (2 * y[eq.size]))


def _check_args(system, mode, amplitudes, n_harmonics, dof, check, tol, max_iter):
    """The cleaned arguments of :func:`nonlinear_mode` (its Parameters); refuses what they cannot be."""
    check_system("system", system, FrictionSystem)
    mode = check_count("mode", mode, 0)
    hh = check_harmonics(n_harmonics, system, "nonlinear_mode", all_dofs=True)
    max_iter = check_count("max_iter", max_iter, 1)
    amps = check_grid("amplitudes", amplitudes, unit="m")
    if check is not True and check is not False:
        check_grid("check", check, unit="m")
    if not (isinstance(tol, float) and 0 < tol < 1):
        raise ParameterError(f"tol must be a float in (0, 1), got {tol!r}")
    if system.n_sliders == 0:
        raise ParameterError("nonlinear_mode: the system has no joint sliders (a linear system)")
    if np.any(system.rigid):
        raise ParameterError("nonlinear_mode: rigid Coulomb sliders have no stuck linear mode to start from "
                             "(give them a stiffness: Jenkins)")
    if dof is not None:
        dof = system.structure.dof_index(dof)
    return mode, amps, hh, dof, max_iter


@owns_blas_threads
def nonlinear_mode(system: FrictionSystem, mode: int = 0, amplitudes: ArrayLike = (1e-3,), n_harmonics: int = 7,
                   dof: str | int | None = None, *, check: bool | ArrayLike = False,
                   exact: bool | ArrayLike = False, tol: float = 1e-11, max_iter: int = 40) -> NonlinearMode:
    """Nonlinear mode of ``system`` by the extended periodic motion concept (module docstring):
    frequency and damping ratio against amplitude, with exact hysteresis.

    Parameters
    ----------
    system : FrictionSystem
        Structure and joints (Jenkins sliders: Jenkins, Iwan, dovetail flanks, frozen or varying
        normal loads); its excitation is removed (base motions leave their springs and dashpots to
        a fixed base).
    mode : int
        Which mode of the stuck system (every slider stuck), ascending from 0.
    amplitudes : (n,) array_like
        First-harmonic amplitudes at ``dof`` [m], > 0, in the order they are followed (usually
        ascending); the first is reached from the stuck linear mode.
    n_harmonics : int
        ``H`` >= 1 (the mean is always included).
    dof : str or int, optional
        The DOF whose first harmonic is ``A cos(omega t)``; default the DOF with the largest
        component of the stuck linear mode (mass-normalised).
    check : bool or sequence of float
        Compare points with the exact free decay from them (module docstring): True every point,
        amplitudes [m] the points nearest each.
    exact : bool or sequence of float
        Solve the EPMC orbit exactly in time at points of the mode (shooting on the event-driven
        march for the state, the period and ``xi``:
        :func:`~frictionjoint.solvers.marcher.autonomous.mode_orbits`, from each point's balanced
        state): ``exact_frequency`` and ``exact_damping_ratio``, the model's values without
        truncation; True every converged point, amplitudes [m] the points nearest each. About
        0.1-3 s a point on the reduced blade.
    tol : float
        Newton's tolerance on the relative step, in (0, 1).
    max_iter : int
        Newton iterations per amplitude at most.

    Returns
    -------
    NonlinearMode
    """
    mode, amps, hh, dof, max_iter = _check_args(system, mode, amplitudes, n_harmonics, dof, check, tol,
                                                max_iter)
    if exact is not True and exact is not False:
        check_grid("exact", exact, unit="m")
    free = free_system(system)
    k_stuck = free.stiffness + (free.slider_direction.T * free.slider_stiffness) @ free.slider_direction
    w_lin, shape, _, _ = _linear_mode(k_stuck, free.mass, mode)
    if not w_lin > 0:
        raise ParameterError(f"nonlinear_mode: mode {mode} of the stuck system is a rigid-body mode")
    if dof is None:
        dof = int(np.argmax(np.abs(shape)))
    elif shape[dof] == 0:
        raise ParameterError(f"nonlinear_mode: the stuck linear mode {mode} has a node at dof {dof}")
    scale = _amplitude_scale(amps)
    if scale != 1.0 and (check is not False or exact is not False):
        raise ParameterError(f"nonlinear_mode: check and exact march the motion in time, which needs amplitudes in "
                             f"[{1 / SCALED_BEYOND:.3g}, {SCALED_BEYOND:.3g}] m (got {amps.min():.3g} to "
                             f"{amps.max():.3g} m)")
    eq = _Equations(free, hh, dof, scale=scale)
    rows, note = _follow(eq, amps / scale, _start(eq, w_lin, shape, 1.0), tol, max_iter)
    out = _result(system, free, eq, mode, amps, rows, tol)
    out.message += note
    if check is not False:
        _check(free, eq, out, check, tol, max_iter)
    if exact is not False:
        _exact(system, free, eq, out, exact)
    return out


def _amplitude_scale(amps: np.ndarray) -> float:
    """The unit of the equations' coefficients [m]: 1 where every amplitude is within
    ``[1 / SCALED_BEYOND, SCALED_BEYOND]``, else the power of 2 at or just below the largest (exact:
    the equations are homogeneous in the coefficients and the joints' forces)."""
    top = float(np.max(amps))
    if 1.0 / SCALED_BEYOND <= float(np.min(amps)) and top <= SCALED_BEYOND:
        return 1.0
    return math.ldexp(1.0, math.frexp(top)[1] - 1)


def _picked(out: NonlinearMode, which) -> list:
    """The converged points ``which`` names: True all, amplitudes [m] the points nearest each."""
    if which is True:
        picked = range(out.amplitude.size)
    else:
        targets = np.asarray(which, dtype=float).reshape(-1)
        picked = sorted({int(np.argmin(np.abs(out.amplitude - a))) for a in targets})
    return [k for k in picked if out.converged[k]]


def _exact(system: FrictionSystem, free: FrictionSystem, eq: _Equations, out: NonlinearMode, which) -> None:
    """The EPMC orbit solved exactly in time at each picked point (``exact``); ``free`` is
    :func:`free_system` of ``system``."""
    from ..marcher import mode_orbits

    picked = _picked(out, which)
    orbits = mode_orbits(free, eq.dof, orbit_starts(system, out, picked),
                         n_harmonics=out.n_harmonics)
    out.exact_frequency = np.full(out.amplitude.size, np.nan)
    out.exact_damping_ratio = np.full(out.amplitude.size, np.nan)
    for k, orbit in zip(picked, orbits):
        if orbit.converged:
            out.exact_frequency[k], out.exact_damping_ratio[k] = orbit.frequency, orbit.damping_ratio
    out.orbits = tuple(orbits)
    failed = sum(not o.converged for o in orbits)
    if failed:
        out.message += f"; the exact orbit did not converge at {failed} of {len(orbits)} points"


def _follow(eq: _Equations, amps: np.ndarray, y_lin: np.ndarray, tol: float, max_iter: int):
    """The mode at each amplitude, each from the previous solved one (:func:`_reach`), the first
    from the stuck linear mode ``y_lin`` (at amplitude 1). Where that fails, the branch by arc
    length (:func:`_branch`) from the last solved point to the amplitude; where the branch turns
    back (a modal interaction can leave the amplitude's branch in pieces), the point fails and the
    next amplitude is tried from the last solved one. ``(rows (y, joint forces, iterations,
    converged), note on the arc-length passages)``."""
    a_lin = float(np.min(amps)) * 1e-3
    start = (a_lin, _predict(eq, y_lin, 1.0, a_lin))
    rows, notes = [], []
    for a in amps:
        y, jf, it, ok = _reach(eq, start, float(a), tol, max_iter)
        if not ok and start[0] > a_lin:
            pts, folds, how = _branch(eq, start[1], start[0], float(a), tol)
            y_b, jf_b, it_b, ok_b = _on_branch(eq, pts, float(a), tol, max_iter)
            notes.append(f"{a:.4g} m by arc length from {start[0]:.4g} m ({len(pts)} points, {folds} folds"
                         + (")" if ok_b else f", {how})"))
            if ok_b:
                y, jf, it, ok = y_b, jf_b, it + it_b, ok_b
        if jf is None:
            jf = eq.joint_forces(y[:eq.size], y[eq.size], jacobian=False)
        rows.append((y, jf, it, ok))
        if ok:
            start = (float(a), y)
    return rows, ("; " + "; ".join(notes)) if notes else ""


def _result(system, free, eq, mode, amps, rows, tol) -> NonlinearMode:
    """The mode's points as a :class:`NonlinearMode`, with both linear limits (``rows`` in units of
    ``eq.scale``, ``amps`` in metres)."""
    nn = eq.size
    s = eq.scale
    conv = np.array([r[3] for r in rows])
    # a point Newton did not solve has no frequency nor damping (its last iterate is in harmonics)
    w = np.where(conv, [r[0][nn] for r in rows], np.nan)
    xi = np.where(conv, [r[0][nn + 1] for r in rows], np.nan)
    inp = np.array([eq.kinetic_integral(r[0][:nn], eq.mass, r[0][nn + 1] * r[0][nn] * s) * s for r in rows])
    visc = np.array([eq.kinetic_integral(r[0][:nn], eq.damping, r[0][nn] * s) * s for r in rows])
    k_stuck = eq.k_lin
    _, shape, _, _ = _linear_mode(k_stuck, free.mass, mode)
    stuck_lim = _limit(free, k_stuck, shape, eq.dof, tol)
    slip_lim = _limit(free, free.stiffness, shape, eq.dof, tol)
    n_ok = int(conv.sum())
    message = (f"{n_ok} of {conv.size} amplitudes converged (H = {eq.n_harmonics})" if n_ok < conv.size else
               f"all {conv.size} amplitudes converged (H = {eq.n_harmonics}, {sum(r[2] for r in rows)} Newton iterations)")
    return NonlinearMode(
        amplitude=amps.copy(), frequency=w, damping_ratio=xi / (2 * w), negative_damping=xi,
        harmonics=np.array([eq.harmonics(r[0][:nn]) * s for r in rows]), converged=conv,
        dissipated_per_cycle=inp, friction_per_cycle=np.array([r[1].dissipated * s * s for r in rows]),
        viscous_per_cycle=visc, stuck=np.array([r[1].stuck for r in rows]),
        slider_positions=np.array([r[1].slider_positions * s for r in rows]),
        iterations=np.array([r[2] for r in rows]), mode=mode, dof=eq.dof,
        dof_name=str(system.structure.dof_names[eq.dof]), n_harmonics=eq.n_harmonics,
        stuck_frequency=stuck_lim[0], stuck_damping_ratio=stuck_lim[1],
        slipping_frequency=slip_lim[0], slipping_damping_ratio=slip_lim[1], message=message)


def _check(free, eq, out: NonlinearMode, check, tol, max_iter) -> None:
    """Each checked point against the exact free decay from it (:func:`free_decay`)."""
    picked = _picked(out, check)
    out.frequency_error = np.full(out.amplitude.size, np.nan)
    out.energy_error = np.full(out.amplitude.size, np.nan)
    checks = []
    for k in picked:  # converged points only (_picked)
        dc = free_decay(free, eq, out, k, tol, max_iter)
        checks.append(dc)
        out.frequency_error[k] = dc.frequency_error
        out.energy_error[k] = dc.energy_error
    out.decays = tuple(checks)


def _maxima(t: np.ndarray, x: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Times of the maxima of ``x`` (``v`` from + to -) between samples, from the cubic Hermite
    interpolant of ``x`` and ``v`` on each interval (its derivative's root)."""
    out = []
    for i in np.flatnonzero((v[:-1] > 0) & (v[1:] <= 0)):
        h = t[i + 1] - t[i]
        x0, x1, v0, v1 = x[i], x[i + 1], v[i] * h, v[i + 1] * h
        # p(s) = x0 + v0 s + c2 s^2 + c3 s^3 on s in [0, 1]; p'(s) = v0 + 2 c2 s + 3 c3 s^2
        c2 = 3 * (x1 - x0) - 2 * v0 - v1
        c3 = 2 * (x0 - x1) + v0 + v1
        roots = np.roots([3 * c3, 2 * c2, v0]) if abs(c3) > 0 else np.array([-v0 / (2 * c2)])
        roots = roots[np.isreal(roots)].real
        roots = roots[(roots >= -1e-9) & (roots <= 1 + 1e-9)]
        s = float(roots[np.argmin(np.abs(roots - v0 / (v0 - v1)))]) if roots.size else v0 / (v0 - v1)
        out.append(t[i] + s * h)
    return np.array(out)


def free_decay(free: FrictionSystem, eq: _Equations, mode: NonlinearMode, k: int, tol: float = 1e-11,
               max_iter: int = 40, n_cycles: int = DECAY_CYCLES) -> DecayCheck:
    """Point ``k`` of ``mode`` against the exact free decay from its state (module docstring)."""
    from ..marcher import simulate

    w = float(mode.frequency[k])
    sys_w = FrictionSystem(free.structure, free.elements, omega=w)
    x0, v0, w0 = balanced_state(sys_w, mode.harmonics[k], mode.slider_positions[k])
    t_end = (n_cycles + 1.5) * 2 * math.pi / w
    t = np.linspace(0.0, t_end, int(round((n_cycles + 1.5) * DECAY_SAMPLES)) + 1)
    tr = simulate(sys_w, t_end, x0, v0, w0, t_eval=t, record=("x", "v"))
    # the modal coordinate (the point's first-harmonic shape, mass-weighted): the truncated
    # harmonics' start rings a stiff root's fast modes, which a root DOF itself shows
    phi = free.mass @ mode.harmonics[k, 1].real
    peaks = _maxima(t, phi @ tr.x, phi @ tr.v)
    peaks = peaks[peaks > 0][:n_cycles + 1]
    if not tr.success or peaks.size < 2:
        empty = np.array([])
        return DecayCheck(k, empty, empty, empty, empty, empty, empty, math.nan, math.nan,
                          f"the free decay gave no two maxima ({tr.message})")
    # exact outputs at the maxima and on a uniform grid inside each cycle
    tt = np.concatenate([np.linspace(a, b, DECAY_SAMPLES + 1)[:-1] for a, b in zip(peaks[:-1], peaks[1:])]
                        + [peaks[-1:]])
    ex = simulate(sys_w, float(peaks[-1]), x0, v0, w0, t_eval=tt, record=("x", "energy"))
    at_peak = np.arange(0, tt.size, DECAY_SAMPLES)
    energy = np.diff((ex.dissipated_friction + ex.dissipated_viscous)[at_peak])
    freqs = 2 * math.pi / np.diff(peaks)
    modal = phi @ ex.x
    amps, mw, md = [], [], []
    for c in range(peaks.size - 1):
        sl = slice(at_peak[c], at_peak[c + 1] + 1)
        ph = freqs[c] * (tt[sl] - tt[sl][0])
        target = math.hypot(np.trapezoid(modal[sl] * np.cos(ph), tt[sl]),
                            np.trapezoid(modal[sl] * np.sin(ph), tt[sl])) * freqs[c] / math.pi
        a, y = _at_modal_amplitude(eq, mode, phi, target, tol, max_iter)
        amps.append(a)
        mw.append(y[eq.size] if y is not None else math.nan)
        md.append(eq.kinetic_integral(y[:eq.size], eq.mass, y[eq.size + 1] * y[eq.size]) if y is not None else math.nan)
    amps, mw, md = np.array(amps), np.array(mw), np.array(md)
    f_err = float(np.max(np.abs(freqs - mw) / mw))
    e_err = float(np.max(np.abs(energy - md) / md)) if np.all(md > 0) else math.nan
    return DecayCheck(k, peaks, amps, freqs, energy, mw, md, f_err, e_err,
                      f"{peaks.size - 1} cycles of the exact free decay from amplitude {mode.amplitude[k]:.4g} m")


def _at_modal_amplitude(eq: _Equations, mode: NonlinearMode, phi: np.ndarray, target: float, tol: float,
                        max_iter: int):
    """``(amplitude, y)``: the point of the mode whose modal coordinate ``phi . x`` has the first-
    harmonic amplitude ``target``, by secant steps in log amplitude from the mode's nearest points
    (``y`` None where it was not found). A decay's cycle is matched by this coordinate, not by the
    DOF's amplitude: where the joint's share of the motion grows fast with amplitude (a root that
    starts to slide), the DOF's amplitude falls many times faster than the energy."""
    ok = np.flatnonzero(mode.converged)
    s_mode = np.abs(mode.harmonics[ok, 1] @ phi)
    order = np.argsort(s_mode)
    la = np.interp(math.log(target), np.log(s_mode[order]), np.log(mode.amplitude[ok][order]))
    j = ok[np.argmin(np.abs(np.log(mode.amplitude[ok]) - la))]
    start = (float(mode.amplitude[j]), np.r_[_coefficients(eq, mode.harmonics[j]), mode.frequency[j],
                                             mode.negative_damping[j]])
    pts = []
    for _ in range(12):
        a = math.exp(la)
        y, _, _, conv = _reach(eq, start, a, tol, max_iter)
        if not conv:
            return a, None
        start = (a, y)
        g = math.log(abs(_coefficients_first(eq, y) @ phi)) - math.log(target)
        if abs(g) <= 1e-11:
            return a, y
        pts.append((la, g))
        if len(pts) == 1:
            la -= g  # the modal coordinate roughly proportional to the amplitude
        else:
            (l0, g0), (l1, g1) = pts[-2:]
            la = l1 - g1 * (l1 - l0) / (g1 - g0) if g1 != g0 else l1 - g1
    return math.exp(la), None


def _coefficients_first(eq: _Equations, y: np.ndarray) -> np.ndarray:
    """Every DOF's complex first harmonic of the unknowns ``y``."""
    c = y[:eq.size].reshape(-1, eq.nc)
    return c[:, 1] - 1j * c[:, 2]


def _coefficients(eq: _Equations, harmonics: np.ndarray) -> np.ndarray:
    """The unknowns' coefficients ``X`` of complex harmonics ``(H + 1, n_dof)`` (inverse of
    :meth:`_Equations.harmonics`)."""
    c = np.empty((harmonics.shape[1], eq.nc))
    c[:, 0] = harmonics[0].real
    c[:, 1::2] = harmonics[1:].real.T
    c[:, 2::2] = -harmonics[1:].imag.T
    return c.reshape(-1)


def orbit_starts(system: FrictionSystem, mode: NonlinearMode, points) -> list:
    """Starts of the EPMC orbits solved exactly in time
    (:func:`frictionjoint.solvers.marcher.autonomous.mode_orbits`) from points of ``mode``.

    Parameters
    ----------
    system : FrictionSystem
        The system of ``mode`` (its excitation is removed: :func:`free_system`).
    mode : NonlinearMode
        The harmonic balance's mode.
    points : sequence of int
        Its converged points.

    Returns
    -------
    list of tuple
        Per point ``(amplitude [m], x0 [m], v0 [m/s], w0 [m], period [s], xi [1/s], x_scale [m])``:
        the balanced state at ``t = 0`` (:func:`.hbm.balanced_state`), the period and negative
        damping, and each DOF's first-harmonic amplitude as its scale.
    """
    free = free_system(system)
    out = []
    for k in points:
        w, xi = float(mode.frequency[k]), float(mode.negative_damping[k])
        x0, v0, w0 = balanced_state(FrictionSystem(free.structure, free.elements, omega=w), mode.harmonics[k],
                                    mode.slider_positions[k])
        out.append((float(mode.amplitude[k]), x0, v0, w0, 2 * math.pi / w, xi, np.abs(mode.harmonics[k, 1])))
    return out
