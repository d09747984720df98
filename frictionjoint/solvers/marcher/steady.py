"""Periodic steady state of a FrictionSystem by shooting on its exact period map.

The period map ``P`` takes the state ``z = [x, v, w]`` at a section time ``t_s`` to the state one
excitation period later, marched exactly (:class:`~frictionjoint.solvers.marcher.events.Marcher`); its
Jacobian is the exact monodromy matrix of the march (:mod:`.monodromy`; finite differences on
request). The section time is put in the middle of the longest slipping piece of the first
period, where the map is smooth. The fixed point is found by the one shooting algorithm of
:mod:`frictionjoint.solvers.shooting` (Newton, marching fallback, growth, uniqueness); the final
period is then evaluated on its closed-form pieces (exact peaks, first harmonics in closed form,
stops, dissipation). A system whose sliders all stick for good is not marched: its orbit is the
linear one of the stuck configuration.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np
from numpy.typing import ArrayLike

from ...threads import owns_blas_threads
from ...errors import ConvergenceError, ParameterError, check_count, check_system
from ...memory import release_freed_memory
from ...system import FrictionSystem
from ...results import PeriodicResponse
from .events import EventLog, MarchState, Marcher
from .monodromy import march_jacobian
from .response import displacement_fourier, piece_peaks, piece_slip, rigid_note
from ..shooting import ShootingOutcome, find_periodic_orbit, has_unit_eigenvalue, orbit_message, residual_floor

__all__ = ["periodic_response", "failed_response", "FD_STEP", "FD_FLOOR", "SECTION_MARGIN", "JACOBIAN_AT_ORBIT",
           "NONMODAL_COND"]

#: finite-difference step of the period map's Jacobian, relative to the component scale
FD_STEP = 1e-7
#: ... and its floor relative to the static deflection excitation / K (the map's rounding is
#: eps excitation / K; the step stays well above it)
FD_FLOOR = 1e-9
#: the section is put at t = 0 only if the pieces on both sides of it are longer than this
#: fraction of the period and no event function is that close to a zero (else mid-piece)
SECTION_MARGIN = 0.02
#: a configuration without a modal form has its stuck orbit solved in state space where the
#: solve's condition number is below this (its error ~ cond eps stays below 1e-9)
NONMODAL_COND = 1e6
#: a Jacobian taken where the residual was above this is retaken at the orbit for the
#: uniqueness test and the Floquet multipliers
JACOBIAN_AT_ORBIT = 1e-6
#: state size (``2 n + sliders``) above which the exact Jacobian is kept over chord iterations
CHORD_SIZE = 64
#: a steady-state search whose own marcher cached more than this [bytes] gives the memory back to
#: the operating system when it ends (:func:`~frictionjoint.memory.release_freed_memory`, about
#: 50 ms per GB; the stiffness-damped chain of 200 DOFs and 40 joints caches 0.6 GB in 6 s)
RELEASE_BYTES = 2 ** 28


class _PeriodMap:
    def __init__(self, system, marcher: Marcher, t_s: float, tol: float = 1e-12, jacobian: str = "exact"):
        self.system = system
        self.m = marcher
        self.t_s = t_s
        self.period = 2 * math.pi / system.omega
        n = system.n_dof
        self.n = n
        self.jen = np.flatnonzero(~system.rigid)
        self.calls = 0
        self.last = None
        self._embedding = None
        self.exact_jacobian = jacobian == "exact"
        # chord iterations (a Jacobian kept while the residual falls fast) where the exact Jacobian
        # costs more than the periods they add: it grows as pieces x n^2 x (2n + sliders), a period
        # as pieces x n x modes; full Newton on small systems
        self.chord = not self.exact_jacobian or 2 * n + system.n_sliders > CHORD_SIZE
        # the exact Jacobian taken again near the orbit serves as its monodromy (no extra one after)
        self.refresh_below = JACOBIAN_AT_ORBIT if self.exact_jacobian and self.chord else 0.0
        if jacobian == "fd":
            self.jacobian = self.fd_jacobian
        excitation = max(float(np.max(np.abs(system.force_cos), initial=0)),
                         float(np.max(np.abs(system.force_sin), initial=0)))
        k_static = float(np.max(np.abs(system.stiffness)))
        self.x_floor = residual_floor(excitation, float(np.max(system.slip_force, initial=0)), k_static,
                                      float(np.max(np.abs(system.mass))), system.omega, tol)
        # finite-difference steps stay well above the map's rounding, eps excitation / K (the
        # static deflections the closed-form pieces carry; see residual_floor)
        self.fd_floor = FD_FLOOR * excitation / k_static if excitation > 0 and k_static > 0 else 0.0
        self.w_char = max(system.omega, float(np.max(system.structure.natural_frequencies(), initial=0)))

    def state(self, z: np.ndarray) -> MarchState:
        sysm = self.system
        n = self.n
        x, v = z[:n], z[n:2 * n]
        s = sysm.slider_direction @ x
        w = s.copy()
        if self.jen.size:
            j = self.jen
            fs = sysm.slip_force[j]
            if sysm.n_contacts:  # slip limits mu N(x) of sliders on contacts
                fs = np.maximum(fs + sysm.slip_gradient[j] @ x, 0.0)
            lim = fs / sysm.slider_stiffness[j]
            w[j] = np.clip(z[2 * n:], s[j] - lim, s[j] + lim)
        return self.m.initial_state(x, v, w, t0=self.t_s)

    def vector(self, st: MarchState) -> np.ndarray:
        return np.concatenate([st.x, st.v, st.w[self.jen]])

    def __call__(self, z, log=None, on_interval=None):
        # the previous call's pieces hold its period's configurations: let them go before this
        # period builds its own (at 400 DOFs and 80 joints, a period's are about 3 GB)
        self.last = None
        st = self.state(z)
        log = EventLog() if log is None else log
        pieces = []

        def keep(itv, tau):
            pieces.append((itv, tau))
            if on_interval is not None:
                on_interval(itv, tau)
        self.m.march(st, self.t_s + self.period, log, on_interval=keep)
        self.calls += 1
        out = self.vector(st)
        # the closed-form pieces of the last call: the orbit, once converged (no re-march)
        self.last = (z.copy(), out, pieces, log)
        return out

    def jacobian(self, z, pz, scale) -> np.ndarray:
        """Exact Jacobian of the map at ``z`` (``pz = P(z)``): the monodromy matrix of the march,
        from its closed-form pieces and saltation matrices (:mod:`.monodromy`)."""
        if self.last is None or not np.array_equal(self.last[0], z):
            self(z)
        return self.reduce(march_jacobian(self.m, self.last[2]))

    def reduce(self, full: np.ndarray) -> np.ndarray:
        """A Jacobian in full coordinates ``[x, v, w of all sliders]`` as the map's Jacobian in ``z
        = [x, v, w of the Jenkins sliders]`` (rigid sliders' ``w = d . x``)."""
        if self._embedding is None:
            sysm, n = self.system, self.n
            embed = np.zeros((2 * n + sysm.n_sliders, 2 * n + self.jen.size))
            embed[:2 * n, :2 * n] = np.eye(2 * n)
            embed[2 * n + self.jen, 2 * n + np.arange(self.jen.size)] = 1.0
            rigid = np.flatnonzero(sysm.rigid)
            embed[2 * n + rigid, :n] = sysm.slider_direction[rigid]
            self._embedding = embed
        return full[np.r_[0:2 * self.n, 2 * self.n + self.jen]] @ self._embedding

    def fd_jacobian(self, z, pz, scale) -> np.ndarray:
        """Finite-difference Jacobian of the map at ``z`` (the check of :meth:`jacobian`)."""
        return _jacobian(self, z, pz, scale)

    def amplitude(self, z) -> float:
        """Size of the motion ``sqrt(|x|^2 + |v / omega|^2)`` [m] (watched for unbounded growth)."""
        n = self.n
        return math.sqrt(float(np.sum(z[:n] ** 2)) + float(np.sum(z[n:2 * n] ** 2)) / self.system.omega ** 2)

    def scales(self, z) -> np.ndarray:
        n = self.n
        w_char = self.w_char
        sx = max(float(np.max(np.abs(z[:n]))), float(np.max(np.abs(z[n:2 * n]))) / w_char, self.x_floor)
        sc = np.full(z.size, sx)
        sc[n:2 * n] = sx * w_char
        return sc


def _jacobian(pmap: _PeriodMap, z, pz, scale):
    nz = z.size
    jac = np.empty((nz, nz))
    n = pmap.n
    for k in range(nz):
        dz = max(FD_STEP * scale[k], pmap.fd_floor * (pmap.w_char if n <= k < 2 * n else 1.0))
        if k >= 2 * n:  # Jenkins slider position: perturb towards the inside of the slip limit
            j = pmap.jen[k - 2 * n]
            s = pmap.system.slider_direction[j] @ z[:n]
            dz = -dz if z[k] < s else dz
        zp = z.copy()
        zp[k] += dz
        jac[:, k] = (pmap(zp) - pz) / dz
    return jac


def _near_event(itv, margin: float) -> bool:
    """True when an event function of ``itv`` is within ``margin`` [s] of a zero at its start,
    judged from its slope (``|g| < margin |g'|``): e.g. a velocity reversal just before ``t = 0``,
    which a section at ``t = 0`` would put on a kink of the period map (low friction, where the
    displacement peak lags the force peak by a tiny angle)."""
    red, _ = itv.events
    if red is None:
        return False
    g, dg, _ = itv.start_values(red)
    return bool(np.any(np.abs(g) < margin * np.abs(dg)))


def _stuck_orbit(system, marcher: Marcher, st: MarchState, pmap_tol: float, n_samples: int):
    """The steady state of a system whose sliders all stick from ``st`` on and never slip: the
    linear orbit of the stuck configuration (a static and a complex harmonic solve in its modes),
    checked against every event function over the whole period (closed-form bounds: constant
    part minus harmonic amplitude). None when it does not apply (something slips or may slip, a
    mode that does not decay, a defective configuration)."""
    if system.n_sliders == 0 or np.any(st.status != 0) or marcher.held_force is not None:
        return None
    itv0 = marcher.interval(st)
    cfg = itv0.config
    m = cfg.m
    if not m or not np.all(np.isfinite(cfg.lam)) or float(np.max(cfg.lam.real)) >= 0 or system.external:
        return None
    w = system.omega
    period = 2 * math.pi / w
    b0, bc, bs = itv0._bvec
    if cfg.modal:
        lam, v, wi = cfg.full_modes()
        y_static = -(v @ ((wi @ b0) / lam)).real
        y_harm = v @ ((wi @ (bc - 1j * bs)) / (1j * w - lam))
    else:
        # no modal form (a defective configuration): the orbit is the same linear solve in state
        # space, where it is well conditioned (a stiffness 1e10 times the structure's is rounded
        # into K_c by eps k, and the solve's answer by cond eps: 30 % at 1e20 N/m on the blade's
        # root, not an answer; the march then says why it cannot answer either)
        z_harm = 1j * w * np.eye(2 * m) - cfg.A
        if max(np.linalg.cond(cfg.A), np.linalg.cond(z_harm)) > NONMODAL_COND:
            return None
        try:
            y_static = -np.linalg.solve(cfg.A, b0)
            y_harm = np.linalg.solve(z_harm, bc - 1j * bs)
        except np.linalg.LinAlgError:
            return None
    y_start = y_static + y_harm.real
    nb = cfg.N
    x_static = st.x + nb @ y_static[:m]
    x_harm = nb @ y_harm[:m]
    found = _admissible_orbit(system, marcher, st, st.x + nb @ y_start[:m], nb @ y_start[m:], x_static, y_harm)
    if found is None:
        return None
    orbit, shift = found
    if shift is not None:
        x_static = x_static + shift
    itv = marcher.interval(orbit)
    jen = ~system.rigid
    z = np.concatenate([orbit.x, orbit.v, orbit.w[jen]])
    pmap = _PeriodMap(system, marcher, 0.0, pmap_tol)
    jac = pmap.reduce(march_jacobian(marcher, [(itv, period)]))
    unique = not has_unit_eigenvalue(jac, pmap.scales(z))
    t_s = x_s = None
    if n_samples:
        t_s = period * np.arange(n_samples) / n_samples
        x_s = x_static[:, None] + (x_harm[:, None] * np.exp(1j * w * t_s)[None, :]).real
    res = PeriodicResponse(
        omega=w, amplitude=np.abs(x_static) + np.abs(x_harm), phase=np.arctan2(-x_harm.imag, x_harm.real),
        harmonic_amplitude=np.abs(x_harm), stops_per_cycle=0, stuck=True, status="periodic", converged=True,
        unique=unique, message=orbit_message(ShootingOutcome(True, z, 0.0), unique, 0.0, 0),
        periods=0.0, state=z, section_time=0.0, initial_state=z, events=EventLog(), dissipated_per_cycle=0.0,
        t=t_s, x=x_s)
    res.set_multipliers(np.linalg.eigvals(jac))
    return res


def _admissible_orbit(system, marcher: Marcher, st: MarchState, x0, v0, x_static, y_harm):
    """The all-stuck linear orbit at ``t = 0``, ``(x0, v0)`` for the slider positions ``st.w``
    (static part ``x_static``, harmonic part ``y_harm`` in the configuration's reduced
    coordinates ``[q, q']``), with every event function above its band over the period, and the
    shift of its static part (None: unshifted); or None.

    On the orbit each event function is a constant plus one harmonic, ``Q(t) = Q0 + Re(Z
    e^{i w t})``, so its minimum over the period is ``Q0 - |Z|``: exact, also near resonance,
    where the closed-form bounds of a piece (:meth:`.Interval.bounds`) do not apply.

    Where some slider's force would exceed its limit but the harmonic part alone stays below it
    (``A_i = k_i |d_i . x_harm| < fs_i``), the slider positions are moved, ``w + dw``, so that each
    mean force lies within ``fs_i - A_i`` (less 1e-9 of ``fs_i``) and moves the least, the mean
    forces being linear in ``w`` through the static deflection: the shaken-down orbit (Melan) that
    marching approaches only as fast as the lightest damping lets its transient decay. A member of
    the family of stuck orbits (they differ in ``w`` and their static offsets; all have the same
    harmonic part)."""
    cfg = marcher.config(st.status)
    m = cfg.m
    x_harm = cfg.N @ y_harm[:m]

    def build(x, w):
        orbit = MarchState(0.0, x, v0.copy(), w, st.status.copy())
        marcher._project(orbit)
        itv = marcher.interval(orbit)
        cy, c0, cc, cs = itv.events[0]
        q0 = c0 - cy[:, :m] @ y_harm[:m].real  # y(t) = Re(y_harm (e^{iwt} - 1)) in q, Re(y_harm e^{iwt}) in q'
        z = np.abs(cy @ y_harm + cc - 1j * cs)
        low = q0 - z - 1e-12 * (np.abs(q0) + z)
        return orbit, all(lo > tol for lo, tol in zip(low.tolist(), marcher._tolerances(itv)))

    orbit, ok = build(x0, st.w)
    if ok:
        return orbit, None
    if np.any(system.rigid):
        return None  # a rigid slider's holding force has no position to shake down
    d, k, fs = system.slider_direction, system.slider_stiffness, system.slip_force
    amp = k * np.abs(d @ x_harm)
    room = fs * (1 - 1e-9) - amp
    if np.any(room <= 0):
        return None  # some slider slips on every stuck orbit: no shakedown into stick
    mean = k * (d @ x_static - st.w)
    target = np.clip(mean, -room, room)
    # static deflection of the stuck configuration per unit slider position: K_c dx = k_j d_j
    try:
        dx = np.linalg.solve(cfg.stiffness, (d * k[:, None]).T)
        sens = k[:, None] * (d @ dx - np.eye(k.size))  # d(mean forces)/d(w)
        dw = np.linalg.solve(sens, target - mean)
    except np.linalg.LinAlgError:
        return None
    shift = dx @ dw
    orbit, ok = build(x0 + shift, st.w + dw)
    return (orbit, shift) if ok else None


def _first_section(system, m: Marcher, st: MarchState, z_start, tol: float, jacobian: str):
    """March the first period from ``st`` (at ``t = 0``) and choose the section time: ``t = 0`` if it
    lies well inside pieces with the fewest stuck sliders, else the middle of the longest such piece
    (the period map is smooth there). Returns ``(pmap, z, P(z), periods marched)``."""
    period = 2 * math.pi / system.omega
    pieces = []
    first_itv = []
    marched = []  # the period's (interval, duration): the map's call at z_start when t_s = 0
    log = EventLog()
    start = (st.x.copy(), st.v.copy(), st.w.copy(), st.status.copy())

    def keep_first(itv, tau):
        if not first_itv:
            first_itv.append(itv)
        marched.append((itv, tau))
        pieces.append((itv.t0, tau, int(np.count_nonzero(itv.status == 0))))
    m.march(st, period, log, on_interval=keep_first)
    fewest = min(p[2] for p in pieces)
    first, last = pieces[0], pieces[-1]
    margin = SECTION_MARGIN * period
    if (first[2] == fewest and last[2] == fewest and first[1] > margin
            and last[1] > margin and len(pieces) > 1 and not _near_event(first_itv[0], margin)):
        t_s = 0.0
        pmap = _PeriodMap(system, m, t_s, tol, jacobian)
        z = z_start
        st.t = 0.0
        pz = pmap.vector(st)
        periods = 1.0
        again = pmap.state(z)
        if all(np.array_equal(a, b) for a, b in zip(start, (again.x, again.v, again.w, again.status))):
            # the period just marched is the map's call at z (it starts from the same state): its
            # pieces serve the Jacobian there, no second march of it
            pmap.last = (z.copy(), pz.copy(), marched, log)
    else:
        t_a, tau, _ = max((p for p in pieces if p[2] == fewest), key=lambda p: p[1])
        t_s = (t_a + 0.5 * tau) % period
        m.march(st, period + t_s)
        st.t = t_s
        pmap = _PeriodMap(system, m, t_s, tol, jacobian)
        z = pmap.vector(st)
        pz = pmap(z)
        periods = 1.0 + t_s / period  # first period + shift; map calls are added at the end
    return pmap, z, pz, periods


def _orbit_period(system, m: Marcher, pmap: _PeriodMap, z, orbit, peaks: bool = True):
    """The orbit's period on its closed-form pieces (those of the map's last call at ``z``, or
    marched again): per-DOF peaks (NaN unless ``peaks``), first-harmonic coefficients ``a1, b1``,
    friction dissipation, whether all stuck, the state at ``t = 0`` and the event log."""
    period = pmap.period
    t_s = pmap.t_s
    log = EventLog()
    ndof = system.n_dof
    amp = np.zeros(ndof)
    a1 = np.zeros(ndof)
    b1 = np.zeros(ndof)
    diss = [0.0]
    slipped = np.zeros(system.n_sliders)  # |slip| of each slider over the period [m]
    w = system.omega
    z0 = [None]

    def on_interval(itv, tau_end):
        t_zero = period if t_s > 0 else t_s
        if z0[0] is None and itv.t0 <= t_zero <= itv.t0 + tau_end:
            xz, vz = itv.state(t_zero - itv.t0)
            st0 = MarchState(0.0, xz[:, 0], vz[:, 0], itv.w, itv.status)
            m._project(st0)
            z0[0] = pmap.vector(st0)
        if tau_end <= 0:
            return
        if peaks:
            x_end = piece_peaks(itv, tau_end, amp)
        else:  # the piece's ends only (evaluated as piece_peaks does: the same numbers)
            x_end = itv.state(np.array([0.0, tau_end]))[0]
        ca, sa = displacement_fourier(itv, tau_end, w)
        a1[:] += ca
        b1[:] += sa
        ds, energy = piece_slip(system, itv, tau_end, x_end[:, 1] - x_end[:, 0])
        slipped[:] += ds
        diss[0] += energy

    if orbit is not None:
        _, _, pieces, log = orbit
        for itv, tau in pieces:
            on_interval(itv, tau)
    else:
        pmap(z, log=log, on_interval=on_interval)
    # stuck: no slider slips by more than rounding of its displacement over the period (a flank
    # shaken down to its slip limit grazes it every cycle: a slip piece of ~1e-12 s, 1e-21 m)
    # (without the peaks, the first harmonic's amplitude is the displacement scale)
    scale = amp if peaks else np.hypot(a1, b1) * (2 / period)
    stuck_all = bool(np.all(slipped <= 1e-12 * (np.abs(system.slider_direction) @ scale)))
    if not peaks:
        amp = np.full(ndof, np.nan)
    return amp, a1 * (2 / period), b1 * (2 / period), diss[0], stuck_all, z0[0], log


@owns_blas_threads
def periodic_response(system: FrictionSystem, x0: ArrayLike = 0.0, v0: ArrayLike = 0.0,
                      w0: ArrayLike | None = None, *, marcher: Marcher | None = None,
                      tol: float = 1e-12, max_newton: int = 25, max_periods: int = 2000,
                      n_samples: int = 0, jacobian: str = "exact", peaks: bool = True) -> PeriodicResponse:
    """Periodic steady state of a harmonically excited :class:`FrictionSystem`.

    Parameters
    ----------
    system : FrictionSystem
        Must have harmonic excitation (``omega > 0``).
    x0, v0, w0 :
        Initial guess (state at ``t = 0``) [m, m/s, m].
    marcher : Marcher, optional
        Reuse a marcher and its cache of configurations.
    tol : float
        Tolerance on the scaled fixed-point residual ``|P(z) - z|``.
    max_newton : int
        Newton iterations before falling back to marching.
    max_periods : int
        Excitation periods marched at most in the fallback.
    n_samples : int
        If > 0, also return ``n_samples`` samples of ``x`` over the period (``t``, ``x``).
    jacobian : {'exact', 'fd'}
        Jacobian of the period map for Newton: ``'exact'`` (the monodromy matrix from the
        closed-form pieces and the events' saltation matrices, no extra marching) or ``'fd'``
        (finite differences, one period per state component; a check and a baseline).
    peaks : bool
        Locate the displacement peaks over the period (``amplitude``; every velocity reversal of
        every DOF, half of a point's time on the blade at its damper optimum); false:
        ``amplitude`` is NaN unless the orbit is stuck (its closed form gives it), for a sweep
        that needs the first harmonics only.

    Returns
    -------
    PeriodicResponse
    """
    check_system("system", system, FrictionSystem)
    if system.omega <= 0:
        raise ParameterError("the system needs harmonic excitation with omega > 0 for a periodic response")
    if not (isinstance(tol, float) and 0 < tol < 1):
        raise ParameterError(f"tol must be a float in (0, 1), got {tol!r}")
    max_newton = check_count("max_newton", max_newton, 1)
    max_periods = check_count("max_periods", max_periods, 0)
    n_samples = check_count("n_samples", n_samples, 0)
    if jacobian not in ("exact", "fd"):
        raise ParameterError(f"jacobian must be 'exact' or 'fd', got {jacobian!r}")
    rigid = ()
    if marcher is None:  # a caller's marcher marches its own system as it is
        system, rigid = system.rigid_limit()
    m = marcher if marcher is not None else Marcher(system)
    try:
        res = _periodic_response(system, m, x0, v0, w0, tol, max_newton, max_periods, n_samples, jacobian,
                                 bool(peaks))
        res.message += rigid_note(rigid)
        return res
    except (ConvergenceError, np.linalg.LinAlgError) as exc:
        # a failed march (no consistent stick/slip status, chattering, a non-finite state) is a
        # status of the result, not an exception for the caller to catch
        return failed_response(system.omega, system.n_dof, f"the march failed: {exc}")
    finally:
        # its own marcher's cache, freed here: back to the operating system where it was large
        if marcher is None and m.forget() > RELEASE_BYTES:
            release_freed_memory()


def failed_response(omega: float, n_dof: int | None, message: str, unique: bool = True) -> PeriodicResponse:
    """The result of a steady-state search that could not march (status ``'failed'``): NaN
    amplitudes and phases, per DOF (``n_dof``) or scalars (``None``: a single-DOF result)."""
    def nan():
        return float("nan") if n_dof is None else np.full(n_dof, np.nan)
    return PeriodicResponse(omega=omega, amplitude=nan(), phase=nan(), harmonic_amplitude=nan(),
                            stops_per_cycle=0, stuck=False, converged=False, unique=unique, message=message,
                            periods=0.0, status="failed")


def _periodic_response(system, m, x0, v0, w0, tol, max_newton, max_periods, n_samples, jacobian, peaks=True):
    period = 2 * math.pi / system.omega
    st = m.initial_state(x0, v0, w0, t0=0.0)
    linear = _stuck_orbit(system, m, st, tol, n_samples)
    if linear is not None:
        return linear  # nothing slips: the linear orbit, without marching
    z_start = np.concatenate([st.x, st.v, st.w[~system.rigid]])
    pmap, z, pz, periods = _first_section(system, m, st, z_start, tol, jacobian)
    pmap.closed_form = lambda z: _stuck_orbit(system, m, pmap.state(z), tol, n_samples)
    outcome = find_periodic_orbit(pmap, z, pz, tol=tol, max_newton=max_newton, max_periods=max_periods,
                                  z_start=z_start)
    if outcome.closed is not None:  # shaken down into permanent stick: the linear orbit
        return dataclasses.replace(outcome.closed, periods=periods + pmap.calls)
    converged, z, jac, jac_rnorm = outcome.converged, outcome.z, outcome.jac, outcome.jac_rnorm

    orbit = pmap.last if pmap.last is not None and np.array_equal(pmap.last[0], z) else None
    unique = True
    if converged:
        if jac is None or jac_rnorm > JACOBIAN_AT_ORBIT:
            # the uniqueness test needs the Jacobian at the orbit, not at a far iterate
            pz_orbit = orbit[1] if orbit is not None else pmap(z)
            jac = pmap.jacobian(z, pz_orbit, pmap.scales(z))
        unique = not has_unit_eigenvalue(jac, pmap.scales(z))

    amp, a1, b1, diss, stuck_all, z0, log = _orbit_period(system, m, pmap, z, orbit, peaks)
    periods += pmap.calls  # every call of the period map marches one period
    t_s = pmap.t_s
    stops = log.count("stick")
    message = orbit_message(outcome, unique, periods, max_periods)
    t_s_arr = x_s = None
    if n_samples:
        t_s_arr = t_s + period * np.arange(n_samples) / n_samples
        from .response import simulate
        ndof = system.n_dof
        tr = simulate(system, t_s + period, z[:ndof], z[ndof:2 * ndof], pmap.state(z).w, t0=t_s,
                      t_eval=t_s_arr, record=("x",), marcher=m)
        x_s = tr.x
    res = PeriodicResponse(
        omega=system.omega, amplitude=amp, phase=np.arctan2(b1, a1), harmonic_amplitude=np.hypot(a1, b1),
        stops_per_cycle=stops, stuck=stuck_all and system.n_sliders > 0,
        status=outcome.status, converged=converged, unique=unique, message=message,
        periods=periods, state=z, section_time=t_s, initial_state=z0, events=log, dissipated_per_cycle=diss,
        t=t_s_arr, x=x_s)
    if converged:  # the Jacobian at the orbit (taken for the uniqueness test) is the monodromy
        res.set_multipliers(np.linalg.eigvals(jac))
    return res
