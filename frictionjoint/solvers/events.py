"""Exact event-driven marcher for linear structures with Coulomb and Jenkins sliders.

Between events the motion is known in closed form (:mod:`.propagator`); only the event times are
searched for: slipping sliders whose relative velocity reaches zero, stuck sliders whose force
(Jenkins spring force, or the holding force of a rigid slider) reaches the slip limit. Each event
function is sampled on a grid finer than the shortest period of the configuration, with its
derivative (so that tangential dips between samples are found too), and the event time is the root
of the exact expression (Brent's method, to rounding).

At an event the new configuration is settled by Hong & Liu's rules, all derived from one
consistency condition: every event function must be positive, or zero and not decreasing (first,
then second derivative). A slipping slider whose velocity would change sign sticks; a stuck slider
whose force would exceed the limit slips in the direction of that force. Hence a rigid slider that
reaches zero velocity sticks (finite stop), reverses at once (normal stop) or slips on (abnormal
stop) without any small step, and zero-duration stops cannot chatter.
"""
from __future__ import annotations

import math

import numpy as np
import scipy.optimize

from ..errors import ConvergenceError, ParameterError
from .propagator import ConfigData, Interval, Observables

__all__ = ["MarchState", "Marcher", "EventLog", "EVENT_KINDS"]

EVENT_KINDS = ("stick", "slip", "normal stop", "abnormal stop")
_SAMPLES_PER_PERIOD = 16
_CHUNK = 48
_RTOL = 4 * np.finfo(float).eps


class EventLog:
    """Events in time order: ``time`` [s], ``element`` and ``slider`` indices, ``kind``.

    Kinds: ``'stick'`` (slip -> stick, a stop of finite duration begins), ``'slip'``
    (stick -> slip, start to slide), ``'normal stop'`` (zero-duration stop with reversal),
    ``'abnormal stop'`` (zero-duration stop, same direction).
    """

    def __init__(self):
        self.time: list[float] = []
        self.element: list[int] = []
        self.slider: list[int] = []
        self.kind: list[str] = []

    def append(self, t, element, slider, kind):
        self.time.append(float(t))
        self.element.append(int(element))
        self.slider.append(int(slider))
        self.kind.append(kind)

    def __len__(self) -> int:
        return len(self.time)

    def __iter__(self):
        return iter(zip(self.time, self.element, self.slider, self.kind))

    def count(self, kind: str, t_start: float = -math.inf, t_stop: float = math.inf) -> int:
        """Number of events of ``kind`` with ``t_start <= time < t_stop``."""
        return sum(1 for t, k in zip(self.time, self.kind) if k == kind and t_start <= t < t_stop)

    def __repr__(self) -> str:
        return f"EventLog({len(self)} events)"


class MarchState:
    """Complete state of a marched system (copyable; what FMU state save/restore captures).

    Attributes
    ----------
    t : float
        Time [s].
    x, v : (n_dof,) ndarray
        Displacement [m] and velocity [m/s].
    w : (n_sliders,) ndarray
        Slider positions [m] along each slider's direction (used by Jenkins sliders).
    status : (n_sliders,) int ndarray
        0 stuck, +1/-1 slipping in the positive/negative direction.
    """

    __slots__ = ("t", "x", "v", "w", "status")

    def __init__(self, t, x, v, w, status):
        self.t = float(t)
        self.x = np.array(x, dtype=float)
        self.v = np.array(v, dtype=float)
        self.w = np.array(w, dtype=float)
        self.status = np.array(status, dtype=np.int8)

    def copy(self) -> "MarchState":
        return MarchState(self.t, self.x, self.v, self.w, self.status)

    def vector(self) -> np.ndarray:
        """``[x, v, w]`` as one vector."""
        return np.concatenate([self.x, self.v, self.w])


class Marcher:
    """Marches a :class:`~frictionjoint.system.FrictionSystem` exactly from event to event.

    Configurations are decomposed lazily, the first time they are visited, and cached.
    """

    def __init__(self, system):
        self.system = system
        self._configs: dict[bytes, ConfigData] = {}
        self.v_scale = 0.0
        self._breaks = system.external_breaks()
        self._mass_scale = float(np.max(np.diag(system.mass)))
        self.held_force = None

    def set_held_force(self, force) -> None:
        """Hold an extra force vector (n_dof,) [N] from now on (zero-order-hold input, e.g. an
        FMU input over a communication step); ``None`` removes it. Call :meth:`settle` (or
        :meth:`march`, which settles at its start) afterwards: holding forces may have jumped."""
        if force is None:
            self.held_force = None
            return
        f = np.broadcast_to(np.asarray(force, dtype=float), (self.system.n_dof,)).copy()
        if not np.all(np.isfinite(f)):
            raise ParameterError("held force must be finite")
        self.held_force = f

    # ---------------------------------------------------------------- set-up
    def config(self, status: np.ndarray) -> ConfigData:
        stuck = status == 0
        key = stuck.tobytes()
        cfg = self._configs.get(key)
        if cfg is None:
            cfg = self._configs[key] = ConfigData(self.system, stuck)
        return cfg

    @property
    def n_configurations(self) -> int:
        """Number of configurations decomposed so far."""
        return len(self._configs)

    def initial_state(self, x0, v0, w0=None, t0: float = 0.0, log: EventLog | None = None) -> MarchState:
        """Consistent state at ``t0`` from displacement, velocity and slider positions.

        ``w0`` defaults to ``s = d . x0`` minus the slider's preload over its stiffness (unstressed
        Jenkins springs unless an element declares a static preload). Sliders moving at ``t0``
        slip in their direction of motion; the others are settled by the stick/slip rules.
        """
        sysm = self.system
        n = sysm.n_dof
        x0 = np.broadcast_to(np.asarray(x0, dtype=float), (n,)).copy()
        v0 = np.broadcast_to(np.asarray(v0, dtype=float), (n,)).copy()
        for name, val in (("x0", x0), ("v0", v0)):
            if not np.all(np.isfinite(val)):
                raise ParameterError(f"{name} must be finite")
        s = sysm.slider_direction @ x0
        if w0 is None:
            w0 = s.copy()
            pre = sysm.slider_preload != 0
            w0[pre] -= sysm.slider_preload[pre] / sysm.slider_stiffness[pre]
        w0 = np.broadcast_to(np.asarray(w0, dtype=float), s.shape).copy()
        if not np.all(np.isfinite(w0)):
            raise ParameterError("w0 must be finite")
        jen = ~sysm.rigid
        # rounding of s - w0 (both may be far larger than the slip reach F/k) is allowed for
        k_jen = sysm.slider_stiffness[jen]
        over = (np.abs(k_jen * (s[jen] - w0[jen]))
                > sysm.slip_force[jen] * (1 + 1e-12) + 4 * np.finfo(float).eps * k_jen * np.abs(s[jen]))
        if np.any(over):
            raise ParameterError("w0 must keep every Jenkins spring force within its slip force "
                                 "(|stiffness (d.x0 - w0)| <= slip_force)")
        w0[~jen] = s[~jen]
        sv = sysm.slider_direction @ v0
        status = np.sign(sv).astype(np.int8)
        self.v_scale = float(np.max(np.abs(v0), initial=0.0))
        # a moving Jenkins slider slips only if its spring is at the limit in the direction of motion
        tj = sysm.slider_stiffness[jen] * (s[jen] - w0[jen])
        at_limit = np.abs(np.abs(tj) - sysm.slip_force[jen]) <= 1e-12 * sysm.slip_force[jen]
        moving_out = np.sign(tj) == status[jen]
        status[jen] = np.where(at_limit & moving_out, status[jen], 0)
        state = MarchState(t0, x0, v0, w0, status)
        self._project(state)
        self.settle(state, log)
        return state

    # ---------------------------------------------------------- observables
    def _f_ext(self, t: float) -> np.ndarray:
        sysm = self.system
        f = sysm.external_force(t)
        if self.held_force is not None:
            f = f + self.held_force
        return f

    def _f_const(self, state: MarchState, f_ext: np.ndarray) -> np.ndarray:
        sysm = self.system
        f = f_ext.copy()
        st = state.status
        d = sysm.slider_direction
        slip = st != 0
        if np.any(slip):
            f -= d[slip].T @ (st[slip] * sysm.slip_force[slip])
        jst = (st == 0) & ~sysm.rigid
        if np.any(jst):
            f += d[jst].T @ (sysm.slider_stiffness[jst] * state.w[jst])
        return f

    def _event_observables(self, cfg: ConfigData, state):
        """Event functions (valid while > 0) and their meta ``(slider, kind)``, kind in v/+/-."""
        sysm = self.system
        n = sysm.n_dof
        d = sysm.slider_direction
        rows_x, rows_v, rows_f, a0, meta = [], [], [], [], []
        zero = np.zeros(n)
        rigid_row = {int(i): r for r, i in enumerate(cfg.rigid_stuck)}
        for i, s in enumerate(state.status):
            fs = sysm.slip_force[i]
            if s != 0:
                rows_x.append(zero); rows_v.append(s * d[i]); rows_f.append(zero); a0.append(0.0)
                meta.append((i, "v"))
            elif not sysm.rigid[i]:
                k = sysm.slider_stiffness[i]
                rows_x += [-k * d[i], k * d[i]]; rows_v += [zero, zero]; rows_f += [zero, zero]
                a0 += [fs + k * state.w[i], fs - k * state.w[i]]
                meta += [(i, "+"), (i, "-")]
            else:
                lr = cfg.L[rigid_row[i]]
                hx = lr @ cfg.stiffness
                hv = lr @ sysm.damping
                # holding force T = -lr F + lr C v + lr Kc x
                rows_x += [-hx, hx]; rows_v += [-hv, hv]; rows_f += [lr, -lr]
                a0 += [fs, fs]
                meta += [(i, "+"), (i, "-")]
        if not meta:
            return None, meta
        return Observables(rows_x, rows_v, rows_f, a0), meta

    def force_observables(self, itv: Interval) -> Observables:
        """Slider forces ``T`` (restoring convention) on an interval, one row per slider."""
        cfg, state = itv.config, itv
        sysm = self.system
        n = sysm.n_dof
        ns = sysm.n_sliders
        ax = np.zeros((ns, n)); av = np.zeros((ns, n)); af = np.zeros((ns, n)); a0 = np.zeros(ns)
        d = sysm.slider_direction
        rigid_row = {int(i): r for r, i in enumerate(cfg.rigid_stuck)}
        for i, s in enumerate(state.status):
            if s != 0:
                a0[i] = s * sysm.slip_force[i]
            elif not sysm.rigid[i]:
                k = sysm.slider_stiffness[i]
                ax[i] = k * d[i]
                a0[i] = -k * state.w[i]
            else:
                lr = cfg.L[rigid_row[i]]
                ax[i] = lr @ cfg.stiffness; av[i] = lr @ sysm.damping; af[i] = -lr
        return Observables(ax, av, af, a0)

    def interval(self, state: MarchState, f_ext=None):
        """Closed-form :class:`Interval` from ``state`` and its event functions."""
        cfg = self.config(state.status)
        if f_ext is None:
            f_ext = self._f_ext(state.t)
        itv = Interval(self.system, cfg, state.t, state.x, state.v, self._f_const(state, f_ext))
        itv.f_ext = f_ext
        itv.status = state.status.copy()
        itv.w = state.w.copy()
        obs, meta = self._event_observables(cfg, state)
        itv.events = (itv.reduce(obs) if obs is not None else None, meta)
        return itv

    def _tolerances(self, itv, meta) -> np.ndarray:
        """Zero tolerances of the event functions: force and velocity scales times 1e-12/1e-11."""
        sysm = self.system
        fscale = max(float(np.max(np.abs(itv.f_const), initial=0.0)),
                     float(np.max(np.abs(sysm.force_cos), initial=0.0)),
                     float(np.max(np.abs(sysm.force_sin), initial=0.0)),
                     float(np.max(sysm.slip_force, initial=0.0)),
                     float(np.max(np.abs(itv.config.stiffness @ itv.x0), initial=0.0)))
        rate = max(sysm.omega, itv.config.max_rate, 1e-300)
        # velocity scale: what has been seen, or what the loads can produce in 1/rate
        v_ref = max(self.v_scale, fscale / (self._mass_scale * rate))
        tol = np.empty(len(meta))
        for j, (i, kind) in enumerate(meta):
            if kind == "v":
                tol[j] = 1e-11 * v_ref
            else:
                tol[j] = 1e-12 * max(sysm.slip_force[i], fscale)
        return tol

    # -------------------------------------------------------------- settling
    def _project(self, state: MarchState) -> None:
        """Make the state exactly consistent with its status (stuck velocities, Jenkins w)."""
        sysm = self.system
        st = state.status
        cfg = self.config(st)
        if cfg.rigid_stuck.size:
            state.v = cfg.N @ (cfg.N.T @ state.v)
        slip_j = (st != 0) & ~sysm.rigid
        if np.any(slip_j):
            s = sysm.slider_direction[slip_j] @ state.x
            state.w[slip_j] = s - st[slip_j] * sysm.slip_force[slip_j] / sysm.slider_stiffness[slip_j]
        rig = sysm.rigid
        state.w[rig] = sysm.slider_direction[rig] @ state.x

    def settle(self, state: MarchState, log: EventLog | None = None, trigger=None) -> Interval:
        """Settle the stick/slip status at ``state.t`` (Hong & Liu's rules); return the interval.

        ``trigger`` is the ``(slider, kind)`` of the event that brought the march here, if any.
        """
        sysm = self.system
        old = state.status.copy()
        max_iter = 4 * sysm.n_sliders + 4
        f_ext = self._f_ext(state.t)
        # sliders just set slipping because their stick force exceeded the limit: the net force
        # has the slip direction (Hong & Liu), so their velocity event is judged by the sign of
        # its derivative alone (a tolerance band on it could send them back to stick, forever,
        # when the motion is far below the velocity scale seen earlier in the run)
        forced = np.zeros(sysm.n_sliders, dtype=bool)
        for _ in range(max_iter):
            itv = self.interval(state, f_ext)
            red, meta = itv.events
            if red is None:
                break
            g, dg, ddg = itv.start_values(red)
            tol = self._tolerances(itv, meta)
            rate = max(self.system.omega, itv.config.max_rate, 1e-300)
            atzero = np.abs(g) <= tol
            dtol = 10.0 * np.maximum(tol, 1e-300) * rate
            sure = np.array([kind == "v" and forced[i] for i, kind in meta], dtype=bool)
            # within the band |dg| <= dtol the curvature decides, except that a forced slider
            # whose velocity already grows (dg > 0) stays slipping
            bad = np.where(atzero, (dg < -dtol) | ((np.abs(dg) <= dtol) & (ddg < 0) & ~(sure & (dg > 0))),
                           g < 0)
            itv.atzero = atzero
            if not np.any(bad):
                break
            # most violated first, normalised by its tolerance scale
            score = np.where(atzero, np.where(dg < -dtol, dg / dtol, -1.0), g / np.maximum(tol, 1e-300))
            score = np.where(bad, score, np.inf)
            j = int(np.argmin(score))
            i, kind = meta[j]
            if kind == "v":
                state.status[i] = 0
                forced[i] = False
            else:
                state.status[i] = 1 if kind == "+" else -1
                forced[i] = True
            self._project(state)
        else:
            raise ConvergenceError(
                f"no consistent stick/slip configuration at t = {state.t!r} after {max_iter} changes")
        if log is not None:
            self._log(state, old, log, trigger)
        return itv

    def _log(self, state, old, log, trigger):
        owner = self.system.slider_owner
        new = state.status
        for i in np.flatnonzero(old != new):
            a, b = old[i], new[i]
            kind = "stick" if b == 0 else ("slip" if a == 0 else "normal stop")
            log.append(state.t, owner[i], i, kind)
        if trigger is not None:
            i, k = trigger
            if k == "v" and old[i] == new[i] != 0:
                log.append(state.t, owner[i], i, "abnormal stop")

    # ----------------------------------------------------------- event search
    def find_event(self, itv: Interval, horizon: float):
        """First event in ``(0, horizon]`` of the interval: ``(tau, j)`` or ``None``."""
        red, meta = itv.events
        if red is None or horizon <= 0:
            return None
        rate = max(self.system.omega, itv.config.max_rate)
        if rate == 0.0:
            return None
        h = 2.0 * math.pi / rate / _SAMPLES_PER_PERIOD
        tol = self._tolerances(itv, meta)
        atzero = getattr(itv, "atzero", np.zeros(len(meta), bool))
        g_a, dg_a = itv.evaluate(red, 0.0, order=1)
        g_a = np.where(atzero, 0.0, g_a[:, 0])
        dg_a = dg_a[:, 0]
        tau_a = 0.0
        vrows = np.array([k == "v" for _, k in meta])
        # velocity scale with a fading memory (halved per interval, raised by what is seen), so
        # that tolerances follow a response that decays by many orders of magnitude instead of
        # staying tied to the largest velocity ever seen
        self.v_scale *= 0.5
        if vrows.any():
            self.v_scale = max(self.v_scale, float(np.max(np.abs(g_a[vrows]), initial=0.0)))
        while tau_a < horizon:
            n = min(_CHUNK, max(1, math.ceil((horizon - tau_a) / h)))
            taus = tau_a + h * np.arange(1, n + 1)
            taus[-1] = min(taus[-1], horizon)
            taus = taus[taus <= horizon]
            g, dg = itv.evaluate(red, taus, order=1)
            if vrows.any():
                self.v_scale = max(self.v_scale, float(np.max(np.abs(g[vrows]))))
            ga = np.hstack([g_a[:, None], g])
            dga = np.hstack([dg_a[:, None], dg])
            ta = np.concatenate([[tau_a], taus])
            cross = (ga[:, :-1] >= 0) & (ga[:, 1:] < 0)
            dip = (dga[:, :-1] < 0) & (dga[:, 1:] > 0) & ~cross
            cand = cross | dip
            if cand.any():
                cols = np.flatnonzero(cand.any(axis=0))
                for k in cols:
                    best = None
                    for j in np.flatnonzero(cand[:, k]):
                        tau = self._locate(itv, red, j, ta[k], ta[k + 1], bool(cross[j, k]),
                                           tol[j], h, start_zero=(k == 0 and tau_a == 0.0 and atzero[j]))
                        if tau is not None and (best is None or tau < best[0]):
                            best = (tau, j)
                    if best is not None:
                        return best
            tau_a = taus[-1]
            g_a, dg_a = g[:, -1], dg[:, -1]
        return None

    def _locate(self, itv, red, j, a, b, crossing, tol, h, start_zero):
        one = tuple(r[j:j + 1] for r in red)
        g, dg = itv.scalar(red, j)

        xtol = 1e-16 * h
        if crossing:
            if start_zero or g(a) < 0:
                # the function starts at zero: find a positive point before the crossing
                ts = np.linspace(a, b, 33)[1:]
                vals = itv.evaluate(one, ts)[0][0]
                neg = np.flatnonzero(vals < 0)
                first = neg[0]
                if first == 0:
                    return a if not start_zero else self._locate_tiny(g, a, ts[0], xtol)
                a = ts[first - 1]
                b = ts[first]
            return self._brent(g, a, b, xtol)
        # dip: local minimum between a and b
        if dg(a) >= 0 or dg(b) <= 0:  # a sign change of g' that was rounding noise
            return None
        tm = scipy.optimize.brentq(dg, a, b, xtol=xtol, rtol=_RTOL)
        if start_zero and tm <= 1e-9 * h:
            return None
        gm = g(tm)
        if gm < 0:
            return self._brent(g, a, tm, xtol)
        if gm <= tol:
            return tm
        return None

    @staticmethod
    def _brent(g, a, b, xtol):
        """Root of ``g`` on ``[a, b]`` (g(a) >= 0 > g(b) up to rounding): where the scalar and the
        vectorised evaluations disagree in the last bits, the end point that is zero wins."""
        ga, gb = g(a), g(b)
        if ga <= 0:
            return a
        if gb >= 0:
            return b
        return scipy.optimize.brentq(g, a, b, xtol=xtol, rtol=_RTOL)

    def _locate_tiny(self, g, a, b, xtol):
        ts = np.linspace(a, b, 65)[1:]
        for lo, hi in zip(ts[:-1], ts[1:]):
            if g(lo) > 0 > g(hi):
                return self._brent(g, lo, hi, xtol)
        return b

    # ----------------------------------------------------------------- march
    def advance(self, itv: Interval, tau: float, state: MarchState) -> None:
        """Move ``state`` to local time ``tau`` of ``itv`` (same configuration)."""
        x, v = itv.state(tau)
        state.t = itv.t0 + tau
        state.x = x[:, 0]
        state.v = v[:, 0]
        self._project(state)

    def march(self, state: MarchState, t_end: float, log: EventLog | None = None,
              on_interval=None, itv: Interval | None = None) -> Interval:
        """March ``state`` (in place) to ``t_end``; return the interval valid at ``t_end``.

        ``on_interval(itv, tau_end)`` is called for every closed-form piece, so callers evaluate
        exactly what they need on it (outputs, energy, Fourier integrals) and nothing else.
        """
        if itv is None or itv.t0 != state.t:
            itv = self.settle(state, log)
        zero_steps = 0
        while state.t < t_end:
            t_stop = t_end
            nb = self._breaks[self._breaks > state.t]
            if nb.size and nb[0] < t_stop:
                t_stop = float(nb[0])
            horizon = t_stop - state.t
            ev = self.find_event(itv, horizon)
            if ev is None:
                tau, trigger = horizon, None
            else:
                tau, j = ev
                trigger = itv.events[1][j]
            if on_interval is not None:
                on_interval(itv, tau)
            self.advance(itv, tau, state)
            if trigger is None:
                state.t = t_stop
            zero_steps = zero_steps + 1 if tau <= 0 else 0
            if zero_steps > 4 * self.system.n_sliders + 8:
                raise ConvergenceError(f"events do not advance time at t = {state.t!r} (chattering)")
            if not (np.all(np.isfinite(state.x)) and np.all(np.isfinite(state.v))):
                raise ConvergenceError(f"non-finite state at t = {state.t!r}")
            itv = self.settle(state, log, trigger)
        return itv
