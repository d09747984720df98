"""The extended periodic motion concept's orbit solved exactly in the time domain: the reference
the harmonic balance's nonlinear mode (:mod:`..frequency_domain.nonlinear_mode`) is checked against.

A nonlinear mode by the EPMC (Krack 2015) is the periodic motion of the autonomous system

    M x'' + (C - xi M) x' + K x + G^T T(G x) = F_0

(the excitation removed, a negative mass-proportional damping added) whose first harmonic at one
DOF has the amplitude ``A``. Here that motion is found by shooting on the exact event-driven march
(:class:`~.events.Marcher`), with the period ``T`` and ``xi`` as unknowns besides the state ``z =
[x, v, w]`` at a section, and two more conditions:

- the amplitude: ``|X_1| = A`` at the DOF, ``X_1 = (2 / T) int_0^T x_dof e^{-i omega t} dt`` in
  closed form on the march's pieces (:func:`.response.displacement_fourier`);
- the phase: the state component that moves fastest at the section (against its scale) keeps its
  value at the start, which removes the orbit's shift in time.

Then ``omega = 2 pi / T`` and ``zeta = xi / (2 omega)`` are the model's, with no truncation: the
harmonic balance's values differ from them by its truncation alone. The equations are solved by
the house's one shooting Newton (:func:`~frictionjoint.solvers.shooting.fixed_point_newton`) on
the map ``Q(u) = u + R(u)``, ``u = (z, T, xi)``, ``R`` the residuals (periodicity ``P(z) - z``,
then the phase [s] in ``T``'s place and the amplitude's relative error times ``omega`` in
``xi``'s); its Jacobian by forward differences (the amplitude's condition has no monodromy).

The negative damping ``C - xi M`` is not a structure's (``LinearStructure`` refuses a damping that
is not positive semi-definite, as it should for a physical one); it is put on the system the
marcher reads (:attr:`FrictionSystem.damping`), and the marcher's propagators take it (its
configurations with growing modes are marched like any other).
"""
from __future__ import annotations

import math
import numpy as np

from ...results.nonlinear_mode import ModeOrbit
from ...system import FrictionSystem
from ..shooting import fixed_point_newton
from .eventlog import EventLog
from .events import Marcher
from .response import displacement_fourier, piece_slip
from .steady import _PeriodMap

__all__ = ["mode_orbit", "mode_orbits", "mode_branch", "section_state", "negative_damping_system"]

#: forward-difference step of the Jacobian, relative to each unknown's scale
FD_STEP = 1e-7
#: each DOF's scale is at least this fraction of the largest DOF's
SCALE_FLOOR = 1e-3


def negative_damping_system(free: FrictionSystem, xi: float, omega: float) -> FrictionSystem:
    """``free`` with its damping ``C - xi M`` (the EPMC's), carrying ``omega`` [rad/s] (no source
    uses it; it sets a period map's period and a balanced state's velocities)."""
    out = FrictionSystem(free.structure, free.elements, omega=omega)
    out.damping = free.damping - xi * free.mass
    return out


class _ModeMap:
    """``Q(u) = u + R(u)`` on ``u = (z, T, xi)`` (module docstring), for :func:`fixed_point_newton`."""

    def __init__(self, free: FrictionSystem, dof: int, amplitude: float, u0: np.ndarray, x_scale: np.ndarray):
        self.free, self.dof, self.amplitude = free, dof, amplitude
        n = free.n_dof
        self.n, self.nz = n, u0.size - 2
        self._maps: dict = {}
        omega = 2 * math.pi / u0[-2]
        sw = np.abs(free.slider_direction[~free.rigid]) @ x_scale
        self.scale = np.r_[x_scale, x_scale * omega, sw, u0[-2], omega]
        self.omega_ref = omega
        self.calls = 0
        # the phase: the component (x or v) moving fastest against its scale keeps its start value
        rate = np.r_[u0[n:2 * n], self._acceleration(u0)] / self.scale[:2 * n]
        self.pin = int(np.argmax(np.abs(rate)))
        self.pin_value = float(u0[self.pin])
        self.pin_rate = float(abs(rate[self.pin]) * self.scale[self.pin])

    def _acceleration(self, u: np.ndarray) -> np.ndarray:
        """``x''`` at the state ``u[:nz]``: the velocity after a tiny march (one thousandth of
        the period) against the start."""
        _, m, pm = self._map(u[-1])
        st = pm.state(u[:self.nz])
        v0 = st.v.copy()
        dt = 1e-3 * u[-2]
        m.march(st, dt)
        return (st.v - v0) / dt

    def _map(self, xi: float):
        """``(system, marcher, period map)`` of the negative damping ``xi`` (the last few kept)."""
        key = float(xi)
        if key not in self._maps:
            if len(self._maps) >= 4:
                self._maps.pop(next(iter(self._maps)))
            s = negative_damping_system(self.free, key, self.omega_ref)
            m = Marcher(s)
            self._maps[key] = (s, m, _PeriodMap(s, m, 0.0))
        return self._maps[key]

    def march(self, u: np.ndarray, on_interval=None):
        """``(P(z), X_1)``: the state after ``T`` from ``z`` with ``xi``, and every DOF's first
        harmonic over it (complex, ``a_1 - i b_1``)."""
        z, big_t, xi = u[:self.nz], float(u[-2]), float(u[-1])
        s, m, pm = self._map(xi)
        st = pm.state(z)
        w = 2 * math.pi / big_t
        c = np.zeros(self.n)
        s_ = np.zeros(self.n)

        def piece(itv, tau):
            if tau > 0:
                ca, sa = displacement_fourier(itv, tau, w)
                c[:] += ca
                s_[:] += sa
                if on_interval is not None:
                    on_interval(s, itv, tau)
        m.march(st, big_t, EventLog(), on_interval=piece)
        self.calls += 1
        return pm.vector(st), (c - 1j * s_) * (2 / big_t)

    def residual(self, u: np.ndarray) -> np.ndarray:
        pz, x1 = self.march(u)
        r = np.empty(u.size)
        r[:self.nz] = pz - u[:self.nz]
        r[-2] = (u[self.pin] - self.pin_value) / self.pin_rate
        r[-1] = (abs(x1[self.dof]) / self.amplitude - 1.0) * self.omega_ref
        return r

    def __call__(self, u: np.ndarray) -> np.ndarray:
        if not (u[-2] > 0 and np.all(np.isfinite(u))):
            return np.full(u.size, np.inf)
        return u + self.residual(u)

    def jacobian(self, u: np.ndarray, qu: np.ndarray) -> np.ndarray:
        """``dQ/du`` by forward differences; a Jenkins slider's position is moved towards the
        inside of its slip limit (outside, the state clips it back)."""
        r0 = qu - u
        jac = np.eye(u.size)
        for k in range(u.size):
            du = FD_STEP * self.scale[k]
            if 2 * self.n <= k < self.nz:
                j = np.flatnonzero(~self.free.rigid)[k - 2 * self.n]
                s = self.free.slider_direction[j] @ u[:self.n]
                du = -du if u[k] < s else du
            up = u.copy()
            up[k] += du
            jac[:, k] += (self.residual(up) - r0) / du
        return jac


def section_state(free: FrictionSystem, x0, v0, w0, period: float, xi: float) -> np.ndarray:
    """A start ``z = [x, v, w]`` on a smooth stretch of the motion from ``(x0, v0, w0)``: one period
    is marched with the negative damping ``xi``, and the state taken in the middle of its longest
    piece with the fewest sticking sliders (no event near: the period map is smooth there, as
    :mod:`.steady` puts its section)."""
    s = negative_damping_system(free, xi, 2 * math.pi / period)
    m = Marcher(s)
    pm = _PeriodMap(s, m, 0.0)
    st = m.initial_state(x0, v0, w0, t0=0.0)
    pieces = []
    m.march(st, period, EventLog(), on_interval=lambda itv, tau: pieces.append(
        (itv.t0, tau, int(np.count_nonzero(itv.status == 0)))))
    fewest = min(p[2] for p in pieces)
    t_a, tau, _ = max((p for p in pieces if p[2] == fewest), key=lambda p: p[1])
    st = m.initial_state(x0, v0, w0, t0=0.0)
    m.march(st, t_a + 0.5 * tau)
    return pm.vector(st)


def mode_orbit(free: FrictionSystem, z0, period: float, xi: float, dof: int, amplitude: float, *,
               x_scale=None, n_harmonics: int = 15, tol: float = 1e-10, max_iter: int = 15) -> ModeOrbit:
    """The EPMC orbit of ``free`` (no excitation) at the first-harmonic amplitude ``amplitude`` [m]
    at ``dof``, by shooting on the exact march (module docstring) from the start ``z0 = [x, v, w of
    the Jenkins sliders]`` (e.g. :func:`section_state` of a harmonic balance's point), ``period``
    [s] and ``xi`` [1/s].

    Parameters
    ----------
    free : FrictionSystem
        The system without excitation (Jenkins sliders; constant loads kept).
    z0 : (2 n_dof + n_jenkins,) array_like
        Start state.
    period, xi : float
        Start period [s] and negative damping [1/s].
    dof : int
        The DOF of the amplitude.
    amplitude : float
        First-harmonic amplitude there [m].
    x_scale : (n_dof,) array_like, optional
        Each DOF's displacement scale [m] (residuals and steps are measured against it); default
        from ``z0``, at least :data:`SCALE_FLOOR` of the largest.
    n_harmonics : int
        Harmonics of the orbit returned.
    tol : float
        Tolerance of the scaled residual.
    max_iter : int
        Newton iterations at most.

    Returns
    -------
    ModeOrbit
    """
    z0 = np.asarray(z0, dtype=float)
    n = free.n_dof
    w0 = 2 * math.pi / period
    if x_scale is None:
        x_scale = np.maximum(np.abs(z0[:n]), np.abs(z0[n:2 * n]) / w0)
    x_scale = np.maximum(np.asarray(x_scale, dtype=float), SCALE_FLOOR * float(np.max(x_scale)))
    qmap = _ModeMap(free, dof, amplitude, np.r_[z0, period, xi], x_scale)
    ok, u, rnorm, its = _solve(qmap, np.r_[z0, period, xi], tol, max_iter)
    return _result(qmap, u, ok, rnorm, its, amplitude, n_harmonics)


def _solve(qmap, u0: np.ndarray, tol: float, max_iter: int):
    """:func:`fixed_point_newton` on ``qmap`` from ``u0``: ``(converged, u, residual, Newton
    iterations)``."""
    its = [0]

    def jacobian(u, qu):
        its[0] += 1
        return qmap.jacobian(u, qu)
    ok, u, _, rnorm, _, _ = fixed_point_newton(qmap, jacobian, u0, qmap(u0), qmap.scale, tol, max_iter, chord=False)
    return ok, u, rnorm, its[0]


def _result(qmap, u: np.ndarray, ok: bool, rnorm: float, its: int, amplitude: float, n_harmonics: int) -> ModeOrbit:
    """The :class:`ModeOrbit` of the unknowns ``u = (z, T, xi)``: its harmonics and friction
    energy from one more march over its pieces."""
    n, dof = qmap.n, qmap.dof
    big_t, xi = float(u[-2]), float(u[-1])
    omega = 2 * math.pi / big_t
    harm = np.zeros((n_harmonics + 1, n), complex)
    friction = [0.0]

    def piece(s, itv, tau):
        for h in range(n_harmonics + 1):
            ca, sa = displacement_fourier(itv, tau, h * omega)
            harm[h] += ca - 1j * sa
        x_ends = itv.state(np.array([0.0, tau]))[0]
        friction[0] += piece_slip(s, itv, tau, x_ends[:, 1] - x_ends[:, 0])[1]
    qmap.march(u, on_interval=piece)
    harm *= 2 / big_t
    harm[0] *= 0.5
    shift = -np.angle(harm[1, dof])  # the first harmonic at the DOF real and positive
    harm *= np.exp(1j * shift * np.arange(n_harmonics + 1))[:, None]
    message = (f"EPMC orbit solved exactly in time ({its} Newton iterations, {qmap.calls} periods marched, "
               f"residual {rnorm:.3g})" if ok else
               f"the exact EPMC orbit was not found (residual {rnorm:.3g} after {its} Newton iterations)")
    return ModeOrbit(amplitude=float(amplitude), frequency=omega if ok else math.nan,
                     damping_ratio=xi / (2 * omega) if ok else math.nan, negative_damping=xi, harmonics=harm,
                     friction_per_cycle=friction[0], state=u[:-2].copy(), residual=rnorm, iterations=its,
                     converged=bool(ok), message=message)


#: halvings (in log amplitude) of a step from the last solved orbit that Newton could not take
MAX_HALVINGS = 3


def mode_orbits(free: FrictionSystem, dof: int, starts, *, n_harmonics: int = 15, tol: float = 1e-10,
                max_iter: int = 15) -> list:
    """The EPMC orbit at each of several amplitudes, each from its start (e.g. a harmonic
    balance's point; the section is put on a smooth stretch of it, :func:`section_state`); where
    Newton fails from it, from the last orbit solved (in the order given), by steps in log
    amplitude halved down to :data:`MAX_HALVINGS` times.

    Parameters
    ----------
    free : FrictionSystem
        The system without excitation.
    dof : int
        The DOF of the amplitudes.
    starts : sequence of tuple
        ``(amplitude [m], x0 [m], v0 [m/s], w0 [m], period [s], xi [1/s], x_scale [m])`` per point:
        the start's displacements, velocities and slider positions (every slider's), and
        :func:`mode_orbit`'s arguments; usually in ascending amplitude.
    n_harmonics, tol, max_iter :
        As :func:`mode_orbit`'s.

    Returns
    -------
    list of ModeOrbit
    """
    out, last = [], None
    for amplitude, x0, v0, w0, period, xi, x_scale in starts:
        z0 = section_state(free, x0, v0, w0, period, xi)
        orbit = mode_orbit(free, z0, period, xi, dof, amplitude, x_scale=x_scale, n_harmonics=n_harmonics,
                           tol=tol, max_iter=max_iter)
        if not orbit.converged and last is not None:
            again = _reach(free, dof, last, amplitude, x_scale, n_harmonics, tol, max_iter, 0)
            if again.converged:
                again.message += f"; from the orbit at {last.amplitude:.4g} m (not from its start)"
                orbit = again
        if orbit.converged:
            last = orbit
        out.append(orbit)
    return out


def _reach(free, dof, last: ModeOrbit, amplitude, x_scale, n_harmonics, tol, max_iter, depth) -> ModeOrbit:
    """The orbit at ``amplitude`` from the solved orbit ``last`` (its state, period and ``xi``);
    where Newton fails, through the midpoint in log amplitude first."""
    orbit = mode_orbit(free, last.state, 2 * math.pi / last.frequency, last.negative_damping, dof, amplitude,
                       x_scale=x_scale, n_harmonics=n_harmonics, tol=tol, max_iter=max_iter)
    if orbit.converged or depth >= MAX_HALVINGS:
        return orbit
    mid = _reach(free, dof, last, math.sqrt(last.amplitude * amplitude), x_scale, n_harmonics, tol, max_iter,
                 depth + 1)
    if not mid.converged:
        return mid
    return _reach(free, dof, mid, amplitude, x_scale, n_harmonics, tol, max_iter, depth + 1)


class _ArcMap(_ModeMap):
    """:class:`_ModeMap` with the amplitude an unknown too, ``u = (z, T, xi, A)``, and one more
    equation: the step ``ds`` along the branch's unit tangent ``t`` from the point ``base``, in
    the scaled unknowns ``u / scale`` (pseudo-arclength; its residual times ``A``'s scale)."""

    def __init__(self, free, dof, base: np.ndarray, tangent: np.ndarray, ds: float, x_scale: np.ndarray):
        super().__init__(free, dof, float(base[-1]), base[:-1], x_scale)
        self.scale = np.r_[self.scale, base[-1]]
        self.base, self.tangent, self.ds = base, tangent, ds

    def residual(self, u: np.ndarray) -> np.ndarray:
        self.amplitude = float(u[-1])
        arc = (self.tangent @ ((u - self.base) / self.scale) - self.ds) * self.scale[-1]
        return np.r_[super().residual(u[:-1]), arc]

    def march(self, u: np.ndarray, on_interval=None):
        return super().march(u[:self.nz + 2], on_interval)

    def __call__(self, u: np.ndarray) -> np.ndarray:
        if not (u[-3] > 0 and u[-1] > 0 and np.all(np.isfinite(u))):
            return np.full(u.size, np.inf)
        return u + self.residual(u)


def mode_branch(free: FrictionSystem, dof: int, first: ModeOrbit, second: ModeOrbit, amplitude_end: float, *,
                x_scale, n_harmonics: int = 15, tol: float = 1e-10, max_iter: int = 15,
                max_points: int = 60) -> list:
    """The EPMC orbit continued along its branch by pseudo-arclength from two solved orbits
    ``first`` and ``second`` (their secant the first tangent), until the amplitude passes
    ``amplitude_end`` [m]: turning points in amplitude (folds) are passed, which continuation in the
    amplitude alone (:func:`mode_orbits`) cannot. Each point is solved by the same Newton with the
    amplitude an unknown and the step's length an equation; a step that fails is halved (down to
    1/64 of the first), a step that succeeds grows by half.

    Parameters
    ----------
    free : FrictionSystem
        The system without excitation.
    dof : int
        The DOF of the amplitude.
    first, second : ModeOrbit
        Two converged orbits of the branch, the direction of continuation from ``first`` to
        ``second``.
    amplitude_end : float
        Stop once the amplitude passes it [m].
    x_scale : (n_dof,) array_like
        Each DOF's displacement scale [m] (:func:`mode_orbit`).
    n_harmonics, tol, max_iter :
        As :func:`mode_orbit`'s.
    max_points : int
        Branch points at most.

    Returns
    -------
    list of ModeOrbit
        The branch's points after ``second``, in order (their amplitudes need not grow).
    """
    x_scale = np.maximum(np.asarray(x_scale, dtype=float), SCALE_FLOOR * float(np.max(x_scale)))

    def unknowns(o):
        return np.r_[o.state, 2 * math.pi / o.frequency, o.negative_damping, o.amplitude]
    u0, u1 = unknowns(first), unknowns(second)
    scale = _ArcMap(free, dof, u1, np.zeros(u1.size), 0.0, x_scale).scale
    step = (u1 - u0) / scale
    ds0 = ds = float(np.linalg.norm(step))
    tangent = step / ds
    out = []
    while len(out) < max_points and u1[-1] < amplitude_end and ds >= ds0 / 64:
        qmap = _ArcMap(free, dof, u1, tangent, ds, x_scale)
        ok, u, rnorm, its = _solve(qmap, u1 + ds * tangent * qmap.scale, tol, max_iter)
        if not ok:
            ds *= 0.5
            continue
        step = (u - u1) / qmap.scale
        tangent = step / float(np.linalg.norm(step))
        out.append(_result(qmap, u[:-1], ok, rnorm, its, float(u[-1]), n_harmonics))
        u1, ds = u, ds * 1.5
    return out
