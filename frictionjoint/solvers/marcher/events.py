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

import collections
import math
import weakref
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from ...errors import ConvergenceError, ParameterError, check_system, check_vector
from ...memory import computation_budget
from ...system import FrictionSystem
from .eventlog import EVENT_KINDS, EventLog, MarchState
from .patterns import StatusPattern
from .propagator import ConfigData, Interval, Observables
from . import consistency
from . import piece_kernels
from . import search

__all__ = ["MarchState", "Marcher", "EventLog", "EVENT_KINDS"]


#: memory of decomposed configurations and their status patterns one marcher keeps [bytes], as
#: counted when they are built and packed (the event search's modal coefficients included; a
#: first-order matrix built on a rare first use is not): beyond, the least recently used are
#: forgotten (:meth:`Marcher._evict`). A quarter of the machine's memory, at least 2 GiB: a
#: period's configurations must fit, or least-recently-used eviction forgets each one before the
#: march comes back to it. The stiffness-damped chain of 400 DOFs and 80 joints (issue 40) meets
#: 160 configurations and 395 statuses in a period on its orbit, 3.7 GB as counted (without their
#: event rows), and more than 5.9 GB over its whole steady-state search: with a 5.9 GB cache it
#: evicts 18 times (85 s, 7.0 GB resident at the peak); a 3.5 GB cache evicted 527 times (122 s),
#: the least recently used being the next period's first. At 200
#: DOFs a configuration of that family holds about 4.1 MB of modes (halved, but stiffness damping
#: overdamps 122 of the 200 modes, whose two real roots are both kept) and 0.6 MB packed for the
#: consistency test, a status pattern about 0.8 MB
CONFIG_CACHE_BYTES = computation_budget()
_SAMPLES_PER_PERIOD = 16
#: closed-form pieces one march may take per excitation period (plus one period's worth): beyond,
#: it stops with a ConvergenceError (a scene whose events come faster than the march can take
#: them, e.g. a slip velocity inside its zero band for a whole period of quasi-static forcing,
#: would otherwise march for days; 2e5 pieces are about 5 s)
MAX_PIECES_PER_PERIOD = 200_000
#: fast events (each ending a piece shorter than 1/CHATTER_PIECES of the excitation period) a march
#: may take per excitation period it has marched (plus two periods' worth) before it stops as chattering:
#: the stuck mode of a Jenkins spring far stiffer than the structure rings at every stop with the
#: stop's inertial force, whatever its stiffness (the structure's damping does not reach it), and
#: sticks and slips once per period of that mode while the load nears the slip force, about
#: sqrt(kt) events a period (a unit oscillator at F/P0 = 0.8, r = 1.2: 416 at kt/k = 1e6, 1312 at
#: 1e7, 4144 at 1e8, 13112 at 1e9; the 2-DOF chain of tests/stress/test_mdof_stiff_joint.py took
#: 25 s at 1e8 at load 7, and is refused from about 3e8 on). A transient's chatter that ends passes
#: (2761 events within 0.23-0.4 of the first period at kt/k = 1e9, F/P0 = 0.5, r = 0.8). Springs stiff enough for their rigid limit to be exact are
#: marched rigid (FrictionSystem.rigid_limit); below, a chatter that lasts is refused. A system of
#: more than CHATTER_PIECES / 8 sliders is allowed 8 such events a slider and period instead
CHATTER_PIECES = 2_000
#: the status a slider takes when its event row of kind ``v`` (stop), ``o`` (lift-off) or ``c``
#: (closure) is violated
_AFTER = {"v": 0, "o": 2, "c": 0}


def _chatter_message(system, t: float, fast: int, chatter: int) -> str:
    """Why a march stopped after ``fast`` fast events (:data:`CHATTER_PIECES`), naming the stiffest
    Jenkins springs against the structure (:meth:`~frictionjoint.system.FrictionSystem.rigid_limit`)."""
    jen = np.flatnonzero(~system.rigid)
    stiff = ""
    if jen.size:
        ratio = system.stiffness_ratio()[jen]
        i = int(np.argmax(ratio))
        stiff = (f"; the stiffest Jenkins spring, slider {int(jen[i])}, is {ratio[i]:.3g} times the structure's "
                 "stiffness along it: its stuck mode rings at every stop and sticks and slips once per period "
                 "of that mode (about sqrt(kt) events a period); from 1e11 times on, periodic_response and "
                 "simulate march a spring as rigid (its limit, exact to about 50 k/kt)")
    return (f"chattering: {fast} events up to t = {t!r} s each within 1/{chatter} of the excitation "
            f"period after the previous one, more than {chatter} a period{stiff}")


_NO_ROWS = np.zeros(0, np.intp)


def _change_status(status: np.ndarray, row: tuple, in_band: bool, visited: set, forced: np.ndarray) -> bool:
    """Hong & Liu's change of ``status`` for its most violated row ``(slider, kind)`` (in place);
    False where the status stays as it is.

    A slipping slider stops, a contact opens or closes. A stuck slider slips, unless that closes a
    cycle stick -> slip -> stick at one instant: every function is within its zero band
    (``in_band``) and only the curvatures disagree (the holding force is within rounding of the
    slip limit, and the slip acceleration within rounding of 0). It stays stuck then: the sticking
    force is within the limit now, and the event search finds when it leaves it, at a later time
    (never a zero-length chatter)."""
    i, kind = row
    if kind in "voc":
        status[i] = _AFTER[kind]
        forced[i] = False
        return True
    new = 1 if kind == "+" else -1
    trial = status.copy()
    trial[i] = new
    if trial.tobytes() in visited and in_band:
        return False
    status[i] = new
    forced[i] = True
    return True


def _nbytes(obj) -> int:
    """Memory held by the arrays of a slotted object (a :class:`StatusPattern`) [bytes], in its
    slots, their (nested) tuples and its event rows (:class:`.propagator.Observables`), each array
    once, without its configuration's packed arrays (``cfg.kern``, shared by the configuration's
    statuses and counted with it)."""
    kern = getattr(getattr(obj, "cfg", None), "kern", None)
    # (buffer, header, system buffer): every status's packed arrays hold the configuration's buffer
    # (counted with it) and the system's (counted with neither)
    shared = {id(kern[0]), id(kern[2])} if kern is not None else set()

    def size(a) -> int:
        if isinstance(a, tuple):
            return sum(size(b) for b in a)
        if isinstance(a, Observables):  # the status's event rows (ax, av, af: rows x n each)
            return size((a.ax, a.av, a.af, a.a0))
        if isinstance(a, np.ndarray) and a.base is None and id(a) not in shared:
            shared.add(id(a))  # each array once
            return a.nbytes
        return 0
    return sum(size(getattr(obj, name, None)) for name in type(obj).__slots__)


def _zero_rows(meta, trigger) -> np.ndarray:
    """Rows of a status (``meta``) that vanish at the event ``trigger`` by construction: where a
    contact closed (kind ``c``), its slider's force and slip limit (rows ``+``, ``-``) and its
    normal load (row ``o``, once it slips); where one opened (``o``), its closure row."""
    if trigger is None or trigger[1] not in "oc":
        return _NO_ROWS
    i, kind = trigger
    kinds = ("+", "-", "o") if kind == "c" else ("c",)
    return np.array([r for r, (j, k) in enumerate(meta) if j == i and k in kinds], dtype=np.intp)


def _absmax(a: np.ndarray) -> float:
    """``max |a|`` (0 for an empty array); plain Python for the tiny arrays of the marcher."""
    if a.size <= 16:
        return max(map(abs, a.ravel().tolist()), default=0.0)
    return float(np.max(np.abs(a), initial=0.0))


def _sample_budget(itv, horizon: float, omega: float) -> int:
    """Samples the search of a piece may take: :data:`.search.MAX_SAMPLES` (or
    :data:`.search.MAX_EXPM_SAMPLES` without a modal form) per excitation period of the horizon,
    and one period's worth (a long piece, e.g. an FMU's communication step of many periods, costs
    in proportion to the time simulated; a piece of one period at most the budget's two)."""
    n = search.MAX_SAMPLES if itv.modal_search() else search.MAX_EXPM_SAMPLES
    periods = horizon * omega / (2 * math.pi) if omega > 0 else 0.0
    return int(min(n * (1.0 + periods), 2.0 ** 62))


def _gave_up_message(itv, tau: float, horizon: float, rate: float, omega: float, budget: int) -> str:
    """Why the event search of a piece stopped after its sample budget (:func:`_sample_budget`)."""
    ratio = f"{rate / omega:.3g} times the excitation frequency" if omega > 0 else f"{rate:.3g} rad/s"
    return (f"the event search of the piece from t = {itv.t0!r} s gave up after {budget} "
            f"samples at {tau:.6g} of {horizon:.6g} s: the configuration's fastest mode "
            f"({rate:.3g} rad/s) is {ratio}, and the search resolves every one of its periods "
            "where the motion is near an event (a joint or contact stiffness many decades above the "
            "structure's, or a forcing period many decades beyond its natural periods)")


class Marcher:
    """Marches a :class:`~frictionjoint.system.FrictionSystem` exactly from event to event.

    Configurations are decomposed lazily, the first time they are visited, and cached.

    Parameters
    ----------
    system : FrictionSystem
        The system to march.
    """

    def __init__(self, system: FrictionSystem) -> None:
        self.system = check_system("system", system, FrictionSystem)
        self._configs: collections.OrderedDict[bytes, ConfigData] = collections.OrderedDict()
        self._config_bytes = 0
        #: what each cached configuration (``("c", key)``) and status pattern (``("p", key)``) was
        #: last counted at (:meth:`_charge`): eviction takes off what was put on
        self._charges: dict[tuple[str, bytes], int] = {}
        self._patterns: dict[bytes, StatusPattern] = {}
        self.v_scale = 0.0
        self._breaks = system.external_breaks()
        self._mass_scale = float(np.max(np.diag(system.mass)))
        # load scales of the tolerances that do not depend on the state
        self._fscale_fixed = max(float(np.max(np.abs(system.force_cos), initial=0.0)),
                                 float(np.max(np.abs(system.force_sin), initial=0.0)),
                                 float(np.max(system.slip_force, initial=0.0)))
        self._rigid_idx = np.flatnonzero(system.rigid)
        self._rigid_dir = system.slider_direction[self._rigid_idx]
        self.held_force = None
        #: event search of modal pieces compiled (:mod:`.search`) or in NumPy (same algorithm)
        self.jit = search.ENABLED

    def set_held_force(self, force: ArrayLike | None) -> None:
        """Hold an extra force vector (n_dof,) [N] from now on (zero-order-hold input, e.g. an
        FMU input over a communication step); ``None`` removes it. Call :meth:`settle` (or
        :meth:`march`, which settles at its start) afterwards: holding forces may have jumped.

        Parameters
        ----------
        force : float or (n_dof,) array_like or None
            Extra force [N] added to the system's external force (a scalar is applied to every
            DOF); must be finite. ``None`` removes the held force.
        """
        if force is None:
            self.held_force = None
            return
        f = np.broadcast_to(np.asarray(force, dtype=float), (self.system.n_dof,)).copy()
        if not np.all(np.isfinite(f)):
            raise ParameterError("held force must be finite")
        self.held_force = f

    # ---------------------------------------------------------------- set-up
    def config(self, status: np.ndarray) -> ConfigData:
        """Decomposition of the configuration of ``status`` (built on first use, then cached).

        Parameters
        ----------
        status : (n_sliders,) int ndarray
            Stick/slip status: 0 stuck, +1/-1 slipping in the positive/negative direction (only
            which sliders stick matters).

        Returns
        -------
        ConfigData
            The decomposition of the configuration in which the sliders of status 0 stick.
        """
        key = self.system.config_key(status)
        cfg = self._configs.get(key)
        if cfg is None:
            cfg = self._configs[key] = ConfigData(self.system, status, self._neighbour(status))
            if "_pending" in cfg.__dict__:  # counted again once its modes are decomposed
                cfg._cache_key = key
                cfg._on_decomposed = weakref.WeakMethod(self._recount_config)
            self._charge(("c", key), cfg)
            if self._config_bytes > CONFIG_CACHE_BYTES and len(self._configs) > 1:
                self._evict()
        else:
            self._configs.move_to_end(key)
        return cfg

    def _charge(self, key: tuple, obj) -> None:
        """Count the cached ``obj`` (a configuration, ``key = ("c", config key)``, or a status
        pattern, ``("p", status)``) at its present size, in place of what it was counted at."""
        size = obj.nbytes if key[0] == "c" else _nbytes(obj)
        self._config_bytes += size - self._charges.get(key, 0)
        self._charges[key] = size

    def _recount_config(self, cfg: ConfigData) -> None:
        """A cached configuration's modes were decomposed on first use: counted at its new size."""
        key = cfg.__dict__.get("_cache_key")
        if key is not None and self._configs.get(key) is cfg:
            self._charge(("c", key), cfg)
            self._configs.move_to_end(key)  # in use: the last to go
            self._within_budget()

    def _recount(self, pat: StatusPattern, status: np.ndarray) -> None:
        """A status pattern packed or given its modal coefficients (and its configuration, which
        that may have decomposed), counted again where they are cached."""
        key = status.astype(np.int8, copy=False).tobytes()
        if self._patterns.get(key) is pat:
            self._charge(("p", key), pat)
        ckey = self.system.config_key(status)
        if self._configs.get(ckey) is pat.cfg:
            self._charge(("c", ckey), pat.cfg)
            self._configs.move_to_end(ckey)  # in use (a pattern hit does not refresh it): the last to go
        self._within_budget()

    def _within_budget(self) -> None:
        """Evict where a recount grew the cache past its budget (a status packed, a configuration
        decomposed on first use): the caller keeps what it holds, the cache forgets it."""
        if self._config_bytes > CONFIG_CACHE_BYTES and len(self._configs) > 1:
            self._evict()

    def _neighbour(self, status: np.ndarray) -> tuple | None:
        """A decomposed configuration that differs from the one of ``status`` by one Jenkins
        slider's spring, and that slider, ``(config, index)``; None where there is none or the
        update does not apply (contacts, stuck rigid sliders): the new one's modes are the
        neighbour's updated by a rank-one change (:meth:`.propagator.ConfigData._updated_modes`)
        instead of decomposed from scratch. One dictionary look-up per slider."""
        sysm = self.system
        if sysm.n_contacts or not self._configs:
            return None
        mask = status == 0
        if np.any(mask & sysm.rigid):
            return None
        lazy = None
        for i in np.flatnonzero(~sysm.rigid):
            mask[i] = not mask[i]
            cfg = self._configs.get(mask.tobytes())
            mask[i] = not mask[i]
            if cfg is None:
                continue
            if "_pending" in cfg.__dict__:  # its modes not decomposed yet: taken if none is
                lazy = lazy or (cfg, int(i))
            elif cfg.modal:
                return cfg, int(i)
        return lazy

    def _evict(self) -> None:
        """Forget the least recently used configurations (and their patterns and Jacobian parts)
        until the cache (configurations and patterns) holds :data:`CONFIG_CACHE_BYTES` at most:
        a structure of hundreds of DOFs with tens of joints visits hundreds of configurations of
        megabytes each; the evicted ones are decomposed again if the march comes back to them."""
        sens = self.__dict__.get("_sensitivities", {})
        key_of = self.system.config_key
        while self._config_bytes > CONFIG_CACHE_BYTES and len(self._configs) > 1:
            key, cfg = self._configs.popitem(last=False)
            self._config_bytes -= self._charges.pop(("c", key), 0)
            for k in [k for k in self._patterns if key_of(np.frombuffer(k, np.int8)) == key]:
                del self._patterns[k]
                self._config_bytes -= self._charges.pop(("p", k), 0)
            for k in [k for k in sens if key_of(np.frombuffer(k, np.int8)) == key]:
                del sens[k]

    def _pattern(self, status: np.ndarray) -> StatusPattern:
        if status.dtype != np.int8:
            status = status.astype(np.int8)
        key = status.tobytes()
        pat = self._patterns.get(key)
        if pat is None:
            status = status.copy()
            pat = self._patterns[key] = StatusPattern(self.system, status, self.config(status))
            self._charge(("p", key), pat)
            if self._config_bytes > CONFIG_CACHE_BYTES:
                self._evict()
        return pat

    def forget(self) -> int:
        """Forget every cached configuration, status pattern and Jacobian part (they are built
        again on the next visit); returns the bytes the cache counted.

        Returns
        -------
        int
            Memory the cache held [bytes], as counted (:data:`CONFIG_CACHE_BYTES`).
        """
        held = self._config_bytes
        self._configs.clear()
        self._patterns.clear()
        self._charges.clear()
        for name in ("_sensitivities", "_basis_changes", "_real_modes"):
            self.__dict__.pop(name, None)
        self._config_bytes = 0
        return held

    @property
    def n_configurations(self) -> int:
        """Number of configurations decomposed so far."""
        return len(self._configs)

    def initial_state(self, x0: ArrayLike, v0: ArrayLike, w0: ArrayLike | None = None, t0: float = 0.0,
                      log: EventLog | None = None) -> MarchState:
        """Consistent state at ``t0`` from displacement, velocity and slider positions.

        ``w0`` defaults to ``s = d . x0`` minus the slider's preload over its stiffness (unstressed
        Jenkins springs unless an element declares a static preload). Sliders moving at ``t0``
        slip in their direction of motion; the others are settled by the stick/slip rules.

        Parameters
        ----------
        x0 : float or (n_dof,) array_like
            Initial displacement [m].
        v0 : float or (n_dof,) array_like
            Initial velocity [m/s].
        w0 : float or (n_sliders,) array_like, optional
            Initial slider positions [m] along each slider's direction; every Jenkins spring force
            ``stiffness (d . x0 - w0)`` must be within its slip force. Rigid sliders' entries are
            replaced by ``d . x0``.
        t0 : float
            Start time [s].
        log : EventLog, optional
            Receives the status changes made by the initial settling.

        Returns
        -------
        MarchState
            The state at ``t0``, its status settled and consistent with it.
        """
        sysm = self.system
        n = sysm.n_dof
        x0 = check_vector("x0", x0, n, "n_dof")
        v0 = check_vector("v0", v0, n, "n_dof")
        s = sysm.slider_direction @ x0
        if w0 is None:
            w0 = s.copy()
            pre = sysm.slider_preload != 0
            w0[pre] -= sysm.slider_preload[pre] / sysm.slider_stiffness[pre]
        w0 = check_vector("w0", w0, s.size, "n_sliders")
        jen = ~sysm.rigid
        # slip limits at x0 (normal-load variation: mu N(x0), zero on an open contact)
        limit = sysm.slip_force.copy()
        opened = np.zeros(s.size, bool)
        if sysm.n_contacts:
            var = sysm.varying
            limit[var] = np.maximum(limit[var] + sysm.slip_gradient[var] @ x0, 0.0)
            opened[var] = sysm.normal_loads(x0)[sysm.slider_contact[var]] <= 0.0
            w0[opened] = s[opened]
        # rounding of s - w0 (both may be far larger than the slip reach F/k) is allowed for
        k_jen = sysm.slider_stiffness[jen]
        over = (np.abs(k_jen * (s[jen] - w0[jen]))
                > limit[jen] * (1 + 1e-12) + 4 * np.finfo(float).eps * k_jen * np.abs(s[jen]))
        if np.any(over):
            raise ParameterError("w0 must keep every Jenkins spring force within its slip force "
                                 "(|stiffness (d.x0 - w0)| <= slip_force)")
        w0[~jen] = s[~jen]
        sv = sysm.slider_direction @ v0
        status = np.sign(sv).astype(np.int8)
        self.v_scale = float(np.max(np.abs(v0), initial=0.0))
        # a moving Jenkins slider slips only if its spring is at the limit in the direction of motion
        tj = sysm.slider_stiffness[jen] * (s[jen] - w0[jen])
        at_limit = np.abs(np.abs(tj) - limit[jen]) <= 1e-12 * sysm.slip_force[jen]
        moving_out = np.sign(tj) == status[jen]
        status[jen] = np.where(at_limit & moving_out, status[jen], 0)
        status[opened] = 2
        state = MarchState(t0, x0, v0, w0, status, self.v_scale)
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

    def _f_const(self, state: MarchState, f_ext: np.ndarray, pat: StatusPattern | None = None) -> np.ndarray:
        if pat is None:
            pat = self._pattern(state.status)
        f = f_ext.copy()
        if pat.f_slip is not None:
            f -= pat.f_slip
        if pat.has_jst:
            f += pat.jst_dt @ (pat.jst_k * state.w[pat.jst])
        return f

    def _reduced_events(self, pat: StatusPattern, itv: Interval, w: np.ndarray):
        """:meth:`Interval.reduce` of the event functions, from the cached per-status parts."""
        obs = pat.obs
        c0 = obs.ax @ itv.x0
        if pat.has_af:
            c0 = c0 + obs.af @ itv.f_const
        c0 = c0 + (pat.a0c + pat.a0k * w[pat.widx] if pat.has_w else pat.a0c)
        return pat.red_cy, c0, pat.red_cc, pat.red_cs

    def force_observables(self, itv: Interval) -> Observables:
        """Slider forces ``T`` (restoring convention) on an interval, one row per slider.

        Parameters
        ----------
        itv : Interval
            A closed-form piece (from :meth:`interval`, :meth:`settle` or :meth:`march`).

        Returns
        -------
        Observables
            One row per slider [N]: ``status * slip_force`` for a slipping slider, the spring force
            ``k (d . x - w)`` for a stuck Jenkins slider, the holding force for a stuck rigid one
            (evaluate them on the piece with :meth:`Interval.reduce`).
        """
        cfg, state = itv.config, itv
        sysm = self.system
        n = sysm.n_dof
        ns = sysm.n_sliders
        ax = np.zeros((ns, n)); av = np.zeros((ns, n)); af = np.zeros((ns, n)); a0 = np.zeros(ns)
        d = sysm.slider_direction
        rigid_row = {int(i): r for r, i in enumerate(cfg.rigid_stuck)}
        for i, s in enumerate(state.status):
            if s == 2:
                continue  # open contact: no force
            if s != 0:
                a0[i] = s * sysm.slip_force[i]
                ax[i] = s * sysm.slip_gradient[i]  # zero unless the limit follows a normal load
            elif not sysm.rigid[i]:
                k = sysm.slider_stiffness[i]
                ax[i] = k * d[i]
                a0[i] = -k * state.w[i]
            else:
                lr = cfg.L[rigid_row[i]]
                ax[i] = lr @ cfg.stiffness; av[i] = lr @ cfg.damping; af[i] = -lr
        return Observables(ax, av, af, a0)

    def interval(self, state: MarchState, f_ext: np.ndarray | None = None) -> Interval:
        """Closed-form :class:`Interval` from ``state`` and its event functions.

        Parameters
        ----------
        state : MarchState
            Start of the piece (its status is taken as it is, not settled).
        f_ext : (n_dof,) ndarray, optional
            External force held over the piece [N] (the system's held external force plus the
            force set by :meth:`set_held_force`); default: evaluated at ``state.t``.

        Returns
        -------
        Interval
            The exact motion from ``state.t`` in the configuration of ``state.status``, with its
            status, slider positions ``w`` and event functions attached.
        """
        pat = self._pattern(state.status)
        if f_ext is None:
            f_ext = self._f_ext(state.t)
        f_const = self._f_const(state, f_ext, pat)
        rhs = None
        if pat.has_jst:
            # f_const - K_c x in spring form (see Interval): each stuck spring's force k (d.x - w)
            # as one scalar along d, its stretch d.x - w formed first (rounding ~ eps k |x|, along
            # d only). Neither k (d.x) nor k w d (each ~ kt |x|) may enter the load vector alone:
            # its rounding there, eps kt |x| in every DOF, drives the soft modes (a 1e-3 slip
            # force beside a stuck kt = 1e8 spring at |x| = 1 lost 2e-6 of its response)
            jd = pat.jst_dt
            rhs = f_ext - pat.cfg.base_stiffness @ state.x
            if pat.f_slip is not None:
                rhs -= pat.f_slip
            rhs -= jd @ (pat.jst_k * (jd.T @ state.x - state.w[pat.jst]))
        itv = Interval(self.system, pat.cfg, state.t, state.x, state.v, f_const, rhs)
        return self._attach(itv, state, f_ext, pat)

    def _attach(self, itv: Interval, state: MarchState, f_ext: np.ndarray, pat: StatusPattern,
                c0: np.ndarray | None = None) -> Interval:
        """Give a new interval its status, slider positions and event functions (``c0``: their
        constants, computed from the interval when not given)."""
        itv.f_ext = f_ext
        itv.status = state.status.copy()
        itv.w = w = state.w.copy()
        itv.pattern = pat
        if pat.obs is None:
            red = None
        elif c0 is None:
            red = self._reduced_events(pat, itv, w)
        else:
            red = pat.red_cy, c0, pat.red_cc, pat.red_cs
        itv.events = (red, pat.meta)
        return itv

    def _tolerances(self, itv) -> list:
        """Zero tolerances of the event functions (list of floats): force and velocity scales
        times 1e-12/1e-11. Cached on the interval: the force parts once, the list for the velocity
        scale it was made with."""
        cached = getattr(itv, "_tol", None)
        v_scale = self.v_scale
        if cached is not None and cached[0] == v_scale:
            return cached[1]
        parts = getattr(itv, "_tol_parts", None)
        if parts is None:
            pat = itv.pattern
            fscale = max(_absmax(itv.f_const), self._fscale_fixed, _absmax(itv.kx0))
            if pat.ax_abs is not None:
                # the event functions are sums of terms of size |ax| |x0|: rounding is relative to
                # those terms, not to their (possibly cancelling) sum
                fscale = max(fscale, _absmax(pat.ax_abs @ np.abs(itv.x0)))
            rate = max(self.system.omega, itv.config.max_rate, 1e-300)
            force_tol = [None if isv else 1e-12 * max(fs, fscale) for isv, fs in zip(pat.row_v_list, pat.row_fs)]
            # velocity scale: what has been seen, or what the loads can produce in 1/rate (with
            # stuck Jenkins springs the load's spring-form terms, consistency.check)
            lscale = fscale
            if pat.has_jst:
                x0 = itv.x0
                lscale = max(self._fscale_fixed, _absmax(itv.f_ext), _absmax(pat.cfg.base_stiffness @ x0),
                             _absmax(pat.jst_k * (pat.jst_dt.T @ x0 - itv.w[pat.jst])))
                if pat.f_slip is not None:
                    lscale = max(lscale, _absmax(pat.f_slip))
            parts = itv._tol_parts = (lscale / (self._mass_scale * rate), force_tol)
        v_floor, force_tol = parts
        tv = 1e-11 * max(v_scale, v_floor)
        tol = [tv if ft is None else ft for ft in force_tol]
        itv._tol = (v_scale, tol)
        return tol

    # -------------------------------------------------------------- settling
    def _project(self, state: MarchState) -> None:
        """Make the state exactly consistent with its status (stuck velocities, Jenkins w)."""
        pat = self._pattern(state.status)
        if pat.has_rigid_stuck:
            cfg = pat.cfg
            state.v = cfg.N @ (cfg.N.T @ state.v)
        if pat.has_slip_j:
            s = pat.slip_j_dir @ state.x
            state.w[pat.slip_j] = s - pat.slip_j_off
        if self._rigid_idx.size:
            state.w[self._rigid_idx] = self._rigid_dir @ state.x

    def settle(self, state: MarchState, log: EventLog | None = None,
               trigger: tuple[int, str] | None = None) -> Interval:
        """Settle the stick/slip status at ``state.t`` (Hong & Liu's rules); return the interval.

        ``trigger`` is the ``(slider, kind)`` of the event that brought the march here, if any.

        Parameters
        ----------
        state : MarchState
            Settled in place: its status is changed until consistent, and the state is projected
            on it (stuck velocities, slider positions).
        log : EventLog, optional
            Receives the status changes (and an abnormal stop: a slider whose velocity reached
            zero, ``trigger`` kind ``'v'``, that slips on in the same direction).
        trigger : (int, str) tuple, optional
            ``(slider, kind)`` of the event that brought the march here: kind ``'v'`` (a slipping
            slider's velocity reached zero) or ``'+'``/``'-'`` (a stuck slider's force reached its
            positive/negative slip limit). None at the start of a march or at a time with no event.

        Returns
        -------
        Interval
            The closed-form piece from ``state.t`` in the settled configuration.
        """
        sysm = self.system
        old = state.status.copy()
        max_iter = 4 * sysm.n_sliders + 4
        f_ext = self._f_ext(state.t)
        if self.jit:
            itv = self._settle_compiled(state, f_ext, max_iter, trigger)
            if log is not None:
                self._log(state, old, log, trigger)
            return itv
        # sliders just set slipping because their stick force exceeded the limit: the net force
        # has the slip direction (Hong & Liu), so their velocity event is judged by the sign of
        # its derivative alone (a tolerance band on it could send them back to stick, forever,
        # when the motion is far below the velocity scale seen earlier in the run)
        forced = np.zeros(sysm.n_sliders, dtype=bool)
        omega = sysm.omega
        visited = set()
        for _ in range(max_iter):
            visited.add(state.status.tobytes())
            itv = self.interval(state, f_ext)
            red, meta = itv.events
            if red is None:
                break
            g, dg, ddg = itv.start_values(red)
            g = np.array(g, dtype=float)
            tol = np.asarray(self._tolerances(itv), dtype=float)
            # the event's row is at zero, and so are the rows that vanish with it
            # (consistency.EVENT_ROW_SLACK); Hong & Liu's choice as the compiled test makes it
            event_row = meta.index(trigger) if (trigger is not None and trigger in meta
                                                and np.array_equal(state.status, old)) else -1
            kinds = np.array([consistency.ROW_KIND[k] for _, k in meta], dtype=np.int64)
            sliders = np.array([i for i, _ in meta], dtype=np.int64)
            j, atzero = consistency.most_violated(g, np.asarray(dg, float), np.asarray(ddg, float), tol,
                                                  max(omega, itv.config.max_rate, 1e-300), kinds, sliders,
                                                  forced, event_row, _zero_rows(meta, trigger).astype(np.int64))
            j = int(j)
            g = g.tolist()
            tol = tol.tolist()
            itv.atzero = np.asarray(atzero, dtype=bool)
            if j < 0:
                break
            if not _change_status(state.status, meta[j], g[j] >= -tol[j], visited, forced):
                break
            self._project(state)
        else:
            raise ConvergenceError(
                f"no consistent stick/slip configuration at t = {state.t!r} after {max_iter} changes")
        if log is not None:
            self._log(state, old, log, trigger)
        return itv

    def _settle_compiled(self, state: MarchState, f_ext: np.ndarray, max_iter: int,
                         trigger: tuple[int, str] | None = None) -> Interval:
        """The settling loop of :meth:`settle`, each status tested by :func:`.consistency.check`
        (one compiled call; the interval is built once, for the consistent status)."""
        forced = np.zeros(self.system.n_sliders, bool)
        visited = set()
        for it in range(max_iter):
            visited.add(state.status.tobytes())
            pat = self._pattern(state.status)
            if pat.obs is None:
                self._project(state)
                return self.interval(state, f_ext)
            if pat.has_rigid_stuck:  # the state projected on the status (Marcher._project): v here,
                cfg = pat.cfg       # the slider positions in check
                state.v = cfg.N @ (cfg.N.T @ state.v)
            if pat.kern is None:  # packed on first use: counted in the cache then
                pat.pack(self._fscale_fixed, self._mass_scale)
                self._recount(pat, state.status)
            fk, ik = pat.kern
            # the event's row (in the status of the piece it ended: the first test only) and the
            # rows that vanish with it
            er = pat.meta.index(trigger) if it == 0 and trigger is not None and trigger in pat.meta else -1
            zr = _zero_rows(pat.meta, trigger)
            j, gj, tolj, atzero, buf = consistency.check(fk, ik, state.x, state.v, state.w, f_ext, state.t,
                                                         self.v_scale, forced, er, zr)
            if j >= 0:
                i, kind = pat.meta[j]
                if kind in "voc":
                    state.status[i] = _AFTER[kind]
                    forced[i] = False
                    continue  # the next check projects the state on the new status
                # the stick -> slip -> stick cycle at one instant of settle: stay stuck
                new_status = state.status.copy()
                new_status[i] = 1 if kind == "+" else -1
                if not (new_status.tobytes() in visited and gj >= -tolj):
                    state.status[i] = new_status[i]
                    forced[i] = True
                    continue
            tol, f_const, kx0, c0, y0, b0 = consistency.unpack(buf, pat.n_rows, self.system.n_dof)
            itv = Interval.from_parts(self.system, pat.cfg, state.t, state.x, f_const, kx0, y0, b0)
            self._attach(itv, state, f_ext, pat, c0)
            itv.atzero = atzero
            itv._tol = (self.v_scale, tol)
            return itv
        raise ConvergenceError(
            f"no consistent stick/slip configuration at t = {state.t!r} after {max_iter} changes")

    def _log(self, state, old, log, trigger):
        owner = self.system.slider_owner
        old = old.tolist()
        new = state.status.tolist()
        for i, (a, b) in enumerate(zip(old, new)):
            if a != b:
                kind = ("lift-off" if b == 2 else "closure" if a == 2 and b == 0 else "stick" if b == 0
                        else "slip" if a in (0, 2) else "normal stop")
                log.append(state.t, owner[i], i, kind)
        if trigger is not None:
            i, k = trigger
            if k == "v" and old[i] == new[i] != 0:
                log.append(state.t, owner[i], i, "abnormal stop")

    # ----------------------------------------------------------- event search
    def find_event(self, itv: Interval, horizon: float) -> tuple[float, int] | None:
        """First event in ``(0, horizon]`` of the interval: ``(tau, j)`` or ``None``.

        The search of :mod:`.search` (compiled for modal pieces, NumPy otherwise). The velocity
        scale has a fading memory: halved per interval, raised by the velocity rows seen, so that
        the tolerances follow a response that decays by many orders of magnitude instead of
        staying tied to the largest velocity ever seen.

        Parameters
        ----------
        itv : Interval
            The closed-form piece to search (from :meth:`interval` or :meth:`settle`).
        horizon : float
            Length of the search window [s], in local time of ``itv``.

        Returns
        -------
        (float, int) tuple or None
            ``(tau, j)``: the local time [s] of the first event and its row ``j`` in
            ``itv.events[1]`` (the ``(slider, kind)`` of the event function); None if no event
            function reaches zero in ``(0, horizon]``.
        """
        red, meta = itv.events
        if red is None or horizon <= 0:
            return None
        rate = max(self.system.omega, itv.config.max_rate)
        if rate == 0.0:
            return None
        h = 2.0 * math.pi / rate / _SAMPLES_PER_PERIOD
        pat = itv.pattern
        tol = self._tolerances(itv)
        atzero = getattr(itv, "atzero", None)
        if atzero is None:
            atzero = np.zeros(len(meta), bool)
        budget = _sample_budget(itv, horizon, self.system.omega)
        if self.jit and itv.modal_search():
            cy, c0, cc, cs = red
            cfg = itv.config
            if pat.modal_p is None:
                pat.modal_p = cfg.modal_rows(cy)
                pat.modal_abs_p = search.magnitudes(pat.modal_p)
                self._recount(pat, itv.status)
            b0, bp, bm = itv._b
            found, tau, row, vmax = search.first_event(pat.modal_p, pat.modal_abs_p, itv._a, b0, bp, bm, c0,
                                                       cfg.lam, cc, cs, self.system.omega, itv.t0,
                                                       np.asarray(tol, dtype=float), atzero, pat.vrows,
                                                       float(horizon), h, *itv.near, budget)
        else:
            found, tau, row, vmax = search.numpy_first_event(itv, red, tol, atzero, pat.vrows, horizon, h,
                                                             budget)
        self.v_scale *= 0.5
        if pat.any_v:
            self.v_scale = max(self.v_scale, vmax)
        if row == search.GAVE_UP:
            raise ConvergenceError(_gave_up_message(itv, tau, horizon, rate, self.system.omega, budget))
        return (tau, row) if found else None

    # ----------------------------------------------------------------- march
    def advance(self, itv: Interval, tau: float, state: MarchState) -> None:
        """Move ``state`` to local time ``tau`` of ``itv`` (same configuration).

        Parameters
        ----------
        itv : Interval
            The closed-form piece ``state`` is on.
        tau : float
            Local time [s] from ``itv.t0``.
        state : MarchState
            Moved in place (``t``, ``x``, ``v``; projected on its status).
        """
        self._move(itv, tau, state)
        self._project(state)

    def _move(self, itv: Interval, tau: float, state: MarchState) -> None:
        """:meth:`advance` without the projection (the compiled settling projects)."""
        state.t = itv.t0 + tau
        if self.jit and itv.modal_search():
            cfg = itv.config
            b0, bp, bm = itv._b
            state.x, state.v = piece_kernels.state(cfg.V, cfg.N, itv.x0, cfg.lam, itv._a, b0, bp, bm,
                                                   itv.omega, float(tau), *itv.near)
        else:
            x, v = itv.state(tau)
            state.x = x[:, 0]
            state.v = v[:, 0]

    def march(self, state: MarchState, t_end: float, log: EventLog | None = None,
              on_interval: Callable[[Interval, float], object] | None = None,
              itv: Interval | None = None, max_events: int | None = None) -> Interval:
        """March ``state`` (in place) to ``t_end``; return the interval valid at ``t_end``.

        ``on_interval(itv, tau_end)`` is called for every closed-form piece, so callers evaluate
        exactly what they need on it (outputs, energy, Fourier integrals) and nothing else.

        Parameters
        ----------
        state : MarchState
            Start state, marched in place (settled first unless ``itv`` is given); its
            ``v_scale``, when set, is the marcher's velocity scale from the start, and holds the
            marcher's at the end (a copy of the state restarts the run bit for bit).
        t_end : float
            End time [s].
        log : EventLog, optional
            Receives the events of the march.
        on_interval : callable, optional
            ``on_interval(itv, tau_end)``, called for every closed-form piece: the
            :class:`Interval` and its local end time ``tau_end`` [s] (the piece covers
            ``[itv.t0, itv.t0 + tau_end]`` and ends at an event, a switching time of the held
            external forces, or ``t_end``).
        itv : Interval, optional
            An interval valid at ``state.t`` (e.g. returned by a previous :meth:`march` or
            :meth:`settle`), reused instead of settling again if its ``t0`` equals ``state.t``.
        max_events : int, optional
            Stop just after this many events (an event function reaching zero inside the march,
            not a switching time of the held external forces), their rules applied: ``state.t``
            is then that event's instant (below ``t_end`` unless the event is at it), the returned
            interval the one settled there, and marching on from it (``itv=``) is the march
            without the stop, bit for bit.

        Returns
        -------
        Interval
            The closed-form piece valid at ``t_end`` (settled there), or at the event it stopped at.
        """
        if max_events is not None and (isinstance(max_events, bool) or not isinstance(max_events, (int, np.integer))
                                       or max_events < 1):
            raise ParameterError(f"max_events must be an integer >= 1 (or None), got {max_events!r}")
        if state.v_scale is not None:  # the state carries the velocity scale of its run
            self.v_scale = state.v_scale
        try:
            return self._march(state, t_end, log, on_interval, itv, max_events)
        finally:
            state.v_scale = self.v_scale

    def _march(self, state, t_end, log, on_interval, itv, max_events=None):
        if itv is None or itv.t0 != state.t:
            itv = self.settle(state, log)
        zero_steps = 0
        omega = self.system.omega
        max_pieces = math.inf
        if omega > 0:
            max_pieces = MAX_PIECES_PER_PERIOD * (1.0 + max(t_end - state.t, 0.0) * omega / (2 * math.pi))
        pieces = fast = 0
        # a slider has a few events a period (stick, slip, stops): an Iwan of many sliders is not a chatter
        chatter = max(CHATTER_PIECES, 8 * self.system.n_sliders)
        fast_piece = 2 * math.pi / omega / chatter if omega > 0 else 0.0
        t_start = state.t
        events_left = math.inf if max_events is None else max_events
        while state.t < t_end and events_left > 0:
            pieces += 1
            if pieces > max_pieces:
                raise ConvergenceError(
                    f"the march took {pieces - 1} closed-form pieces from t = {itv.t0!r} s, "
                    f"{MAX_PIECES_PER_PERIOD} per excitation period, without reaching t = {t_end!r} s "
                    "(events faster than the march can take them: an event function inside its zero band "
                    "for long stretches, e.g. a slip velocity of a forcing period many decades beyond "
                    "the structure's natural periods)")
            t_stop = t_end
            if self._breaks.size:
                nb = self._breaks[self._breaks > state.t]
                if nb.size and nb[0] < t_stop:
                    t_stop = float(nb[0])
            horizon = t_stop - state.t
            ev = self.find_event(itv, horizon)
            if ev is None:
                tau, trigger = horizon, None
                itv.end_row = None
            else:
                tau, j = ev
                trigger = itv.events[1][j]
                itv.end_row = j  # the event that ends the piece (saltation of the march's Jacobian)
            if on_interval is not None:
                on_interval(itv, tau)
            t_before = state.t
            if self.jit:  # settle projects the state on its status (consistency.check)
                self._move(itv, tau, state)
            else:
                self.advance(itv, tau, state)
            if trigger is None:
                state.t = t_stop
            # an event below the resolution of the time (tau > 0 with t + tau == t, e.g. a stiff
            # joint's force within rounding of its slip limit) does not advance time either
            zero_steps = zero_steps + 1 if not state.t > t_before else 0
            if zero_steps > 4 * self.system.n_sliders + 8:
                raise ConvergenceError(
                    f"events do not advance time at t = {state.t!r} (chattering: each next event is found "
                    f"within the resolution of the time there, {math.ulp(state.t):.3g} s, or an event "
                    "function stays within rounding of its zero, e.g. the force of a joint many decades "
                    "stiffer than the structure, or a forcing period many decades beyond its natural periods)")
            if not (np.isfinite(state.x).all() and np.isfinite(state.v).all()):
                raise ConvergenceError(f"non-finite state at t = {state.t!r}")
            fast += trigger is not None and tau < fast_piece
            if fast > chatter * (2.0 + (state.t - t_start) * omega / (2 * math.pi)):
                raise ConvergenceError(_chatter_message(self.system, state.t, fast - 1, chatter))
            itv = self.settle(state, log, trigger)
            if trigger is not None:
                events_left -= 1
        return itv
