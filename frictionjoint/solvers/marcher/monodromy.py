"""The exact Jacobian of a march (the monodromy matrix of a period map) from its closed-form pieces.

A march is a chain of pieces in fixed configurations joined by events. In full coordinates
``Z = [x, v, w]`` (displacements, velocities, all slider positions) each piece is an affine flow,
so a variation ``dZ`` of its start state is carried to its end by a matrix built from the piece's
closed form (:class:`~frictionjoint.solvers.marcher.propagator.Interval`):

    dy(tau) = e^{A tau} dy0 + (int_0^tau e^{A s} ds) db0,
    dy0 = [0, N^T dv0],   db0 = [0, Mr^-1 N^T (-K_c dx0 + sum_stuck Jenkins k_i d_i dw_i)],
    dx = dx0 + N dq,   dv = N dq',

with ``e^{A tau} = V diag(e^{lam tau}) V^-1`` and ``int e^{A s} ds = V diag(tau phi1(lam tau)) V^-1``
from the configuration's modal decomposition (or the matrix exponential of ``[[A, I], [0, 0]]``
where it is defective). The reduced coordinates ``q`` of a configuration with stuck rigid
sliders carry the constraint: a variation off the constraint is projected away at the piece's
start. Stuck Jenkins sliders keep their ``w``; slipping Jenkins and rigid sliders follow
``w = d . x`` (minus the slip offset; a slider on a contact, normal-load variation, ``w = (d - sig
g/k) . x`` minus its offset, and ``w = d . x`` while the contact is open).

An event ``g(Z, t) = 0`` ending a piece moves with the state; the variation just after it is the
saltation matrix times the variation just before (Aizerman & Gantmacher; e.g. Leine & Nijmeijer,
*Dynamics and Bifurcations of Non-Smooth Mechanical Systems*, 2004, sec. 7.2):

    S = I + (f+ - f-) (dg/dZ) / (dg/dt),

``f-`` and ``f+`` the vector fields of the old and the new configuration at the event,
``dg/dt`` the rate of the event function along the old flow. A rigid slider that sticks has a jump
of acceleration (``S`` makes its velocity variation vanish along the slider); a slider that starts
to slip does so at the force limit, where the acceleration is continuous and only a Jenkins
slider's ``w`` rate changes; a zero-duration stop reverses the friction force (a jump of
acceleration). An event at a fixed time (the end of a march, a break in an external force) needs
no saltation.

The rows ``[dx, dv]`` of the variations may be carried in the modal coordinates of the current
configuration instead of physical ones where ``N = I`` (no stuck rigid slider): classical modes
(``xi = Phi^T M dx``, ``eta = Phi^T M dv``, a 2 x 2 map per mode) and, without contacts, the
general modes of a non-classically damped configuration made real: with ``z = V^-1 dy`` the
coordinates of ``dy = [dx, dv]`` on the eigenvectors ``V`` of ``A``, a conjugate pair ``(lam,
conj lam)`` of vectors ``(v, conj v)`` has ``z`` and ``conj z`` (``dy`` is real), so its real pair
``(Re z, Im z)`` says both and ``dy = sum_pairs (2 Re v Re z - 2 Im v Im z) + sum_real v z``. In
absolute coordinates a piece maps ``dy`` by ``e^{A tau}`` plus the stuck Jenkins sliders' ``dw``
through ``int e^{A s} ds [0, M^-1 sum k d dw]``: per pair a rotation-and-decay ``e^{lam tau}``
(2 x 2 real) and per real root a scaling, ``O(m nZ)``; a change of configuration is one real
product with ``V_new^-1 V_old`` made real (cached).
"""
from __future__ import annotations

import collections
import math
import weakref

import numpy as np
import scipy.linalg

from .mode_update import conjugate_pairs
from .propagator import _phi1

__all__ = ["march_jacobian"]

#: memory held by the cached changes of modal basis between configurations (:func:`_basis_change`;
#: per pair of configurations met in a row ``8 n^2`` bytes between classical ones, 0.3 MB at n =
#: 200, ``32 n^2`` where one has general modes, 1.3 MB) [bytes]
BASIS_CACHE_BYTES = 2 ** 29


#: a root is taken as real where ``|Im lam| <= PAIR_TOL |lam|``; the second root of a conjugate
#: pair and its vector must be the first's conjugate to ``PAIR_TOL`` (relative), and a real root's
#: vector real to it up to a phase, for the real modal rows (:class:`_RealModes`); else the
#: configuration takes physical rows. ``eig`` of a real matrix returns exact conjugates (0);
#: refined modes (:func:`.propagator._refine_modes`, each root on its own) differ by rounding.
PAIR_TOL = 1e-10


class _RealModes:
    """The real modal coordinates of a configuration's general modes (``N = I``, ``V`` and ``V^-1``
    of the first-order matrix, both roots of every conjugate pair, or halved: the first root of
    each pair, its vector times 2, :func:`.propagator._halved_modes`): ``keep`` the root kept of each
    pair (``Im lam > 0``, the first ``p``) then the real roots, ``lam`` theirs (real roots with
    imaginary part 0), ``phase`` the unit factors that make the real roots' vectors real. The
    rows of a variation are ``(Re z, Im z)`` of each kept pair's root, interleaved, then ``z`` of
    each real root (times its phase's inverse): ``2m`` real rows."""

    __slots__ = ("p", "keep", "lam", "phase", "pair_weight")

    def __init__(self, p, keep, lam, phase, pair_weight=2.0):
        self.p, self.keep, self.lam, self.phase = p, keep, lam, phase
        #: the factor of a pair's columns in :meth:`cols`: 2, or 1 where the configuration's
        #: modes are halved (:func:`.propagator._halved_modes`: the vectors carry the 2)
        self.pair_weight = pair_weight

    @classmethod
    def of(cls, cfg) -> _RealModes | None:
        """The real modal coordinates of ``cfg``'s modes, None where its roots or vectors do not
        come in conjugate pairs to :data:`PAIR_TOL` (the march takes physical rows there)."""
        lam, v = cfg.lam, cfg.V
        if cfg.n_pairs is not None:  # halved: the pairs' first roots, then the real ones
            return cls._halved(cfg.n_pairs, lam, v)
        pairs = conjugate_pairs(lam, PAIR_TOL)
        if pairs is None:
            return None
        up, down, real_mask = pairs
        cplx = ~real_mask
        vu = v[:, up]
        size = np.max(np.abs(vu), axis=0, initial=0.0)
        if np.any(np.max(np.abs(v[:, down] - vu.conj()), axis=0, initial=0.0) > PAIR_TOL * size):
            return None
        real = np.flatnonzero(~cplx)
        vr = v[:, real]
        big = vr[np.argmax(np.abs(vr), axis=0), np.arange(real.size)]
        if real.size and np.any(big == 0):
            return None
        phase = big.conj() / np.abs(big) if real.size else np.ones(0, complex)
        if np.any(np.max(np.abs((vr * phase).imag), axis=0, initial=0.0) > PAIR_TOL * np.abs(big)):
            return None
        keep = np.concatenate((up, real))
        lam_k = lam[keep].copy()
        lam_k[up.size:] = lam_k[up.size:].real
        return cls(up.size, keep, lam_k, phase)

    @classmethod
    def _halved(cls, p: int, lam, v) -> _RealModes | None:
        """Of halved modes (``p`` pairs' first roots, then the real roots): the phases of the real
        roots' vectors as in :meth:`of`."""
        vr = v[:, p:]
        phase = np.ones(vr.shape[1], complex)
        if vr.shape[1]:
            big = vr[np.argmax(np.abs(vr), axis=0), np.arange(vr.shape[1])]
            if np.any(big == 0):
                return None
            phase = big.conj() / np.abs(big)
            if np.any(np.max(np.abs((vr * phase).imag), axis=0) > PAIR_TOL * np.abs(big)):
                return None
        lam_k = lam.copy()
        lam_k[p:] = lam_k[p:].real
        return cls(p, np.arange(lam.size), lam_k, phase, pair_weight=1.0)

    def rows(self, z: np.ndarray) -> np.ndarray:
        """Real rows ``(2m, ...)`` of complex modal coordinates ``z`` of the kept roots (rows in
        :attr:`keep`'s order): a pair's ``Re z``, ``Im z``, a real root's ``z / phase``."""
        p = self.p
        out = np.empty((2 * p + self.phase.size,) + z.shape[1:])
        out[0:2 * p:2] = z[:p].real
        out[1:2 * p:2] = z[:p].imag
        ph = self.phase.reshape((-1,) + (1,) * (z.ndim - 1))
        out[2 * p:] = (z[p:] / ph).real
        return out

    def cols(self, c: np.ndarray) -> np.ndarray:
        """Real columns ``(..., 2m)`` that take the real rows back: ``c`` the kept roots' vectors
        (columns in :attr:`keep`'s order) or a row vector times them; a pair's ``2 Re c``, ``-2 Im
        c``, a real root's ``c phase``."""
        p = self.p
        out = np.empty(c.shape[:-1] + (2 * p + self.phase.size,))
        out[..., 0:2 * p:2] = self.pair_weight * c[..., :p].real
        out[..., 1:2 * p:2] = -self.pair_weight * c[..., :p].imag
        out[..., 2 * p:] = (c[..., p:] * self.phase).real
        return out


def _real_modes(marcher, cfg) -> _RealModes | None:
    """:meth:`_RealModes.of` of ``cfg``, cached on the marcher with a weak key (a configuration
    the marcher forgot takes its entry with it)."""
    cache = marcher.__dict__.get("_real_modes")
    if cache is None:
        cache = marcher.__dict__["_real_modes"] = weakref.WeakKeyDictionary()
    if cfg not in cache:
        cache[cfg] = _RealModes.of(cfg)
    return cache[cfg]


class _ConfigSensitivity:
    """Per-configuration parts of the piece maps, cached on the marcher.

    Modal configurations: ``W B_y`` and ``W B_b`` restricted to their nonzero columns (the
    velocity block ``v`` and the displacement and stuck-``w`` blocks ``x``, ``w``), built on first
    use (:meth:`general`). Classically damped ones (:attr:`~.propagator.ConfigData.shapes`): real
    mode shapes instead, ``U = N Phi``, ``P = Phi^T Mr N^T`` (velocity to modal velocity) and ``S =
    U^T K_c`` (displacement to modal force), so that a piece in physical rows costs four real
    products with the ``n x m`` shapes instead of complex ones with the ``2m x 2m`` eigenvectors;
    with ``N = I`` (``modal_rows``) the march carries the rows in modal coordinates instead
    (:func:`_modal_piece`) and needs only the moving sliders' ``w = (d Phi) xi`` rows (``wphi``),
    ``S`` is built where physical rows ask for it. General modes with ``N = I`` and no contacts
    (``real``, :class:`_RealModes`): the march carries real modal rows (:func:`_real_piece`),
    ``sj`` the stuck Jenkins sliders' ``dw`` as real rows of ``V^-1 [0, M^-1 sum k d]`` and
    ``wphi`` the moving sliders' ``w = d . x`` from the ``2m`` rows. Defective ones: ``B_y``,
    ``B_b`` for the exponential.
    """

    __slots__ = ("n", "nz", "by", "bb", "wby", "wbb", "wsj", "u", "p", "s", "sj", "jcols", "modal_rows", "moving",
                 "wphi", "real")

    def __init__(self, system, itv, real: _RealModes | None = None):
        cfg = itv.config
        pat = itv.pattern
        n = system.n_dof
        ns = system.n_sliders
        nz = 2 * n + ns
        m = cfg.m
        nb = cfg.N
        self.n, self.nz = n, nz
        self.by = self.bb = self.wby = self.wbb = self.wsj = self.u = self.p = self.s = self.sj = None
        self.wphi = self.real = None
        self.jcols = 2 * n + np.flatnonzero(pat.jst) if pat.has_jst else None
        self.moving = np.flatnonzero(~pat.jst)
        self.modal_rows = bool(m) and cfg.shapes is not None and not cfg.rigid_stuck.size
        if not m:
            return
        if cfg.shapes is not None:
            if cfg.rigid_stuck.size:
                u = nb @ cfg.shapes
                self.p = cfg.shapes_mass @ nb.T
                self.s = u.T @ cfg.stiffness
            else:  # N = I: S on demand (apply_piece); a moving slider's w = d . x = (d Phi) xi
                u = cfg.shapes
                self.p = cfg.shapes_mass
                self.wphi = pat.w_dir[self.moving] @ u
            self.u = u
            self.sj = u.T @ (pat.jst_dt * pat.jst_k) if pat.has_jst else None
            return
        if real is not None:  # general modes, N = I: real modal rows (_real_piece)
            self.real = real
            keep = real.keep
            if pat.has_jst:
                self.sj = real.rows(cfg.velocity_inverse()[keep] @ (cfg.mr_inv_nt @ (pat.jst_dt * pat.jst_k)))
            self.wphi = real.cols(pat.w_dir[self.moving] @ cfg.V[:n, keep])
        elif not cfg.modal:
            by = np.zeros((2 * m, nz))
            bb = np.zeros((2 * m, nz))
            by[m:, n:2 * n] = nb.T
            bb[m:, :n] = -cfg.mr_inv_nt @ cfg.stiffness
            if pat.has_jst:
                bb[m:, self.jcols] = cfg.mr_inv_nt @ (pat.jst_dt * pat.jst_k)
            self.by, self.bb = by, bb

    def general(self, cfg, pat):
        """``(W2 N^T, W2 Mr^-1 N^T (-K_c), W2 Mr^-1 N^T sum_stuck k d)`` with ``W2 = V^-1[:, m:]``
        (the last None without stuck Jenkins sliders): the general modes' parts of a piece in
        physical rows (:func:`apply_piece`), built on first use (the real modal rows do not
        need them)."""
        if self.wby is None:
            w2 = cfg.velocity_inverse()
            self.wby = w2 @ cfg.N.T                          # acts on dv
            self.wbb = w2 @ (-cfg.mr_inv_nt @ cfg.stiffness)  # acts on dx
            if pat.has_jst:                                   # acts on the stuck Jenkins sliders' dw
                self.wsj = w2 @ (cfg.mr_inv_nt @ (pat.jst_dt * pat.jst_k))
        return self.wby, self.wbb, self.wsj


def _sensitivity(marcher, itv) -> _ConfigSensitivity:
    cache = marcher.__dict__.setdefault("_sensitivities", {})
    key = itv.status.astype(np.int8, copy=False).tobytes()  # as the marcher's patterns (eviction)
    s = cache.get(key)
    if s is None:
        cfg = itv.config
        real = None
        if cfg.m and cfg.modal and cfg.shapes is None and not cfg.rigid_stuck.size and not marcher.system.n_contacts:
            real = _real_modes(marcher, cfg)
        s = cache[key] = _ConfigSensitivity(marcher.system, itv, real)
    return s


def _mode_responses(pairs, tau: float):
    """Per classically damped mode ``eta'' + alpha eta' + w^2 eta = f`` of a configuration whose
    roots are ``pairs = (lam+, lam-)``: the impulse response ``h1``, its rate ``h1'`` and the step
    response ``h0`` at ``tau`` (``h0' = h1``), real.

    ``h1 = (e^{lam+ tau} - e^{lam- tau}) / (lam+ - lam-) = tau e^{lam+ tau} phi1(-(lam+ - lam-) tau)``
    (``Re lam+ >= Re lam-``: bounded, and no cancellation as the pair approaches), ``h1' = lam+ h1
    + e^{lam- tau}``, ``h0 = (g+ - g-) / (lam+ - lam-)`` with ``g = tau phi1(lam tau)``."""
    lp, lm = pairs
    dl = lp - lm
    h1 = tau * np.exp(lp * tau) * _phi1(-dl * tau)
    h1d = lp * h1 + np.exp(lm * tau)
    h0 = tau * (_phi1(lp * tau) - _phi1(lm * tau)) / dl
    return h1.real, h1d.real, h0.real


def apply_piece(marcher, itv, tau: float, jac: np.ndarray) -> np.ndarray:
    """The piece's ``(nZ, nZ)`` transition matrix times ``jac``, without forming the matrix: the
    rows of ``jac`` (variations of ``[x, v, w]``) carried to the piece's local time ``tau``."""
    sens = _sensitivity(marcher, itv)
    n = sens.n
    cfg = itv.config
    m = cfg.m
    dx, dv, dw = jac[:n], jac[n:2 * n], jac[2 * n:]
    out = np.empty_like(jac)
    if m == 0:
        out[:n] = dx
        out[n:2 * n] = 0.0
    elif sens.u is not None:
        h1, h1d, h0 = _mode_responses(cfg.pairs, tau)
        if sens.s is None:  # N = I: Phi^T K_c = w^2 Phi^T M (to the eigensolver's residual)
            sens.s = cfg.shapes_w2[:, None] * cfg.shapes_mass
        qd0 = sens.p @ dv
        f = -(sens.s @ dx)
        if sens.sj is not None:
            f += sens.sj @ jac[sens.jcols]
        out[:n] = dx + sens.u @ (h1[:, None] * qd0 + h0[:, None] * f)
        out[n:2 * n] = sens.u @ (h1d[:, None] * qd0 + h1[:, None] * f)
    else:
        if cfg.modal:
            wby, wbb, wsj = sens.general(cfg, itv.pattern)
            lt = cfg.lam * tau
            e = np.exp(lt)
            g = tau * _phi1(lt)
            c = e[:, None] * (wby @ dv) + g[:, None] * (wbb @ dx)
            if wsj is not None:
                c += g[:, None] * (wsj @ jac[sens.jcols])
            y = (cfg.V @ c).real
        else:
            aug = np.zeros((4 * m, 4 * m))
            aug[:2 * m, :2 * m] = cfg.A
            aug[:2 * m, 2 * m:] = np.eye(2 * m)
            big = scipy.linalg.expm(aug * tau)
            y = (big[:2 * m, :2 * m] @ sens.by + big[:2 * m, 2 * m:] @ sens.bb) @ jac
        out[:n] = dx + cfg.N @ y[:m]
        out[n:2 * n] = cfg.N @ y[m:]
    jst = itv.pattern.jst
    moving = np.flatnonzero(~jst)
    out[2 * n:] = dw
    if moving.size:
        out[2 * n + moving] = itv.pattern.w_dir[moving] @ out[:n]
    return out


def _event_gradient(marcher, itv, j: int) -> np.ndarray:
    """Gradient of event row ``j`` of ``itv`` with respect to the full state at fixed time."""
    system = marcher.system
    n = system.n_dof
    pat = itv.pattern
    obs = pat.obs
    grad = np.zeros(2 * n + system.n_sliders)
    grad[:n] = obs.ax[j]
    grad[n:2 * n] = obs.av[j]
    if pat.a0k[j] != 0:
        grad[2 * n + pat.widx[j]] += pat.a0k[j]
    if pat.has_jst and pat.has_af:
        grad[2 * n + np.flatnonzero(pat.jst)] += (obs.af[j] @ pat.jst_dt) * pat.jst_k
    return grad


def _field(system, itv, tau: float, row: int | None = None):
    """Rates ``[v', w']`` of the piece at local time ``tau`` (x' = v is continuous at events) and,
    for an event ``row``, the rate of its event function there (one state evaluation for both).
    A modal configuration with ``N = I`` evaluates the velocity rows only (half its modes'
    products; ``y' = [v, v']``)."""
    n = system.n_dof
    cfg = itv.config
    m = cfg.m
    out = np.zeros(n + system.n_sliders)
    dy = None
    if m and cfg.modal and not cfg.rigid_stuck.size:
        v, acc = (a[:, 0] for a in itv.velocity(np.array([tau]), order=1))
        out[:n] = acc
        dy = np.concatenate((v, acc))
    elif m:
        y, dy = (a[:, 0] for a in itv.y(np.array([tau]), order=1))
        v = cfg.N @ y[m:]
        out[:n] = cfg.N @ dy[m:]
    else:
        v = np.zeros(n)
    moving = ~itv.pattern.jst
    out[n:][moving] = itv.pattern.w_dir[moving] @ v
    if row is None:
        return out
    # g' = cy y' + w (cs cos - cc sin), as Interval.evaluate with order 1
    cy, _, cc, cs = itv.events[0]
    ph = itv.omega * (itv.t0 + tau)
    rate = itv.omega * (cs[row] * math.cos(ph) - cc[row] * math.sin(ph))
    if m:
        rate += float(cy[row] @ dy)
    return out, float(rate)


def saltation(marcher, before, tau: float, row: int, after):
    """Saltation of event ``row`` of piece ``before`` at its local time ``tau``, the march going on
    in piece ``after``: ``S = I + e_[v,w] jump (grad / rate)^T``, returned as ``(jump, grad / rate)``
    (the rows ``n:`` of the state get ``jump`` times the row vector); None when it is the identity."""
    system = marcher.system
    if np.array_equal(before.status, after.status):
        return None  # abnormal stop: the configuration is kept, the flow is continuous
    f_before, rate = _field(system, before, tau, row)
    jump = _field(system, after, 0.0) - f_before
    grad = _event_gradient(marcher, before, row)
    if rate == 0.0 or not np.any(jump):
        return None
    return jump, grad / rate


def _left(marcher, cfg) -> np.ndarray:
    """``Q`` (2m, 2m): the modal rows of ``cfg`` from physical rows ``[dx, dv]``, ``r = Q dy``;
    classical modes ``xi_i = (Phi^T M)_i dx``, ``eta_i = (Phi^T M)_i dv`` interleaved, general ones
    the real rows of ``V^-1 dy`` (:class:`_RealModes`)."""
    m = cfg.m
    if cfg.shapes is not None:
        q = np.zeros((2 * m, 2 * m))
        q[0::2, :m] = cfg.shapes_mass
        q[1::2, m:] = cfg.shapes_mass
        return q
    real = _real_modes(marcher, cfg)
    # where the left eigenvectors gave V^-1 its rows are exact to LEFT_PROBE (1e-10) of V V^-1 = I,
    # not refined as a piece's start is: the Jacobian's and the multipliers' error, not the orbit's
    return real.rows(cfg.W[real.keep])


def _right(marcher, cfg) -> np.ndarray:
    """``R`` (2m, 2m): physical rows ``dy = R r`` from the modal rows of ``cfg`` (``Q R = I``)."""
    m = cfg.m
    if cfg.shapes is not None:
        r = np.zeros((2 * m, 2 * m))
        r[:m, 0::2] = cfg.shapes
        r[m:, 1::2] = cfg.shapes
        return r
    real = _real_modes(marcher, cfg)
    return real.cols(cfg.V[:, real.keep])


def _basis_change(marcher, old, new) -> np.ndarray:
    """The modal rows of configuration ``old`` taken to those of ``new``: between classical ones
    ``T = Phi_new^T M Phi_old`` (n, n) (``Phi^T M Phi = I``, so ``dx = Phi_old xi`` is ``Phi_new T
    xi``; the same for ``eta``), else ``Q_new R_old`` (2n, 2n) (:func:`_left`, :func:`_right`;
    between general modes the real form of ``V_new^-1 V_old``), cached on the marcher: a march's
    configurations follow each other in the same pairs in every Jacobian of a steady-state search.
    The cache holds :data:`BASIS_CACHE_BYTES` at most (the least recently used pairs forgotten)
    and its keys are weak references: a configuration the marcher forgot leaves its pairs
    unreachable, and a new one decomposed in its place gets its own."""
    cache = marcher.__dict__.get("_basis_changes")
    if cache is None:
        cache = marcher.__dict__["_basis_changes"] = collections.OrderedDict()
    key = (weakref.ref(old), weakref.ref(new))
    t = cache.get(key)
    if t is not None:
        cache.move_to_end(key)
        return t
    if old.shapes is not None and new.shapes is not None:
        t = new.shapes_mass @ old.shapes
    else:
        t = _left(marcher, new) @ _right(marcher, old)
    cache[key] = t
    total = sum(a.nbytes for a in cache.values())
    for k in [k for k in cache if k[0]() is None or k[1]() is None]:  # forgotten configurations
        total -= cache.pop(k).nbytes
    while total > BASIS_CACHE_BYTES and len(cache) > 1:
        total -= cache.popitem(last=False)[1].nbytes
    return t


def _to_modal(marcher, jac, basis, cfg, stage) -> None:
    """Rows ``[x, v]`` of ``jac`` (physical where ``basis`` is None, else modal in ``basis``) as the
    modal coordinates of the classically damped ``cfg``, ``xi = Phi^T M dx`` and ``eta = Phi^T M
    dv``, into ``stage`` ``(n, 3, nZ)``: per mode its rows ``xi``, ``eta`` (the third is the
    piece's modal force, :func:`_modal_piece`). The ``(n, 2 nZ)`` view of the rows ``[xi_i,
    eta_i]`` makes a change of basis between classical configurations one product (as fast as one
    of half the size, for half the calls)."""
    n = cfg.m
    nz = jac.shape[1]
    rows = stage[:, :2].reshape(n, 2 * nz)  # a view: the two rows of a mode are adjacent
    if basis is None:
        np.matmul(cfg.shapes_mass, np.concatenate((jac[:n], jac[n:2 * n]), axis=1), out=rows)
    elif basis is cfg:
        stage[:, :2] = jac[:2 * n].reshape(n, 2, nz)
    elif basis.shapes is not None:
        np.matmul(_basis_change(marcher, basis, cfg), jac[:2 * n].reshape(n, 2 * nz), out=rows)
    else:  # from general modes' real rows
        stage[:, :2] = (_basis_change(marcher, basis, cfg) @ jac[:2 * n]).reshape(n, 2, nz)


def _to_real(marcher, jac, basis, cfg, stage) -> None:
    """Rows ``[x, v]`` of ``jac`` (physical where ``basis`` is None, else modal in ``basis``) as the
    real modal rows of the general modes of ``cfg`` (:class:`_RealModes`) into ``stage`` ``(2n,
    nZ)``: one real product."""
    n = cfg.m
    if basis is None:
        np.matmul(_left(marcher, cfg), jac[:2 * n], out=stage)
    elif basis is cfg:
        stage[:] = jac[:2 * n]
    else:
        np.matmul(_basis_change(marcher, basis, cfg), jac[:2 * n], out=stage)


def _to_physical(marcher, jac, basis) -> np.ndarray:
    """Modal rows of ``jac`` in ``basis`` (:func:`_modal_piece`: ``xi_i``, ``eta_i`` interleaved;
    :func:`_real_piece`: real rows of the general modes) back to ``[x, v, w]``: classical ``dx =
    Phi xi``, ``dv = Phi eta``, general ``dy = R r`` (:func:`_right`)."""
    n = basis.m
    nz = jac.shape[1]
    out = np.empty_like(jac)
    if basis.shapes is not None:
        both = basis.shapes @ jac[:2 * n].reshape(n, 2 * nz)
        out[:n] = both[:, :nz]
        out[n:2 * n] = both[:, nz:]
    else:
        np.matmul(_right(marcher, basis), jac[:2 * n], out=out[:2 * n])
    out[2 * n:] = jac[2 * n:]
    return out


def _modal_piece(sens, itv, tau: float, stage, jac) -> None:
    """:func:`apply_piece` on modal rows: the piece's start rows ``[xi_i, eta_i]`` in ``stage``
    (:func:`_to_modal`) carried to its end in the rows ``2i``, ``2i + 1`` of ``jac`` (rows ``w``
    stay). Per mode ``xi' = xi + h1 eta + h0 f``, ``eta' = h1' eta + h1 f`` with the modal force
    ``f = -w^2 xi + Phi^T sum_stuck k d dw`` (the responses of :func:`_mode_responses`): with
    ``Phi^T sum k d dw`` as the third row of ``stage``, one 2 x 3 matrix per mode, ``O(n nZ)``
    instead of the four ``n x n x nZ`` products of physical rows. Moving sliders follow ``w = d .
    x = (d Phi) xi``."""
    cfg = itv.config
    n = cfg.m
    nz = jac.shape[1]
    h1, h1d, h0 = _mode_responses(cfg.pairs, tau)
    w2 = cfg.shapes_w2
    step = np.empty((n, 2, 3))
    step[:, 0, 0] = 1.0 - h0 * w2
    step[:, 0, 1] = h1
    step[:, 0, 2] = h0
    step[:, 1, 0] = -h1 * w2
    step[:, 1, 1] = h1d
    step[:, 1, 2] = h1
    if sens.sj is not None:
        np.matmul(sens.sj, jac[sens.jcols], out=stage[:, 2])
    else:
        stage[:, 2] = 0.0
    np.matmul(step, stage, out=jac[:2 * n].reshape(n, 2, nz))
    if sens.moving.size:
        jac[2 * n + sens.moving] = sens.wphi @ jac[0:2 * n:2]


def _real_piece(sens, tau: float, stage, jac) -> None:
    """:func:`apply_piece` on the real modal rows of general modes: the start rows in ``stage``
    (:func:`_to_real`) carried to the piece's end in ``jac[:2n]`` (rows ``w`` stay). In complex
    modal coordinates ``z' = e^{lam tau} z + tau phi1(lam tau) s`` with ``s`` the stuck Jenkins
    sliders' ``V^-1 [0, M^-1 sum k d dw]``; on a pair's ``(Re z, Im z)`` the products with
    ``e^{lam tau}`` and ``tau phi1(lam tau)`` are 2 x 2 real rotations-and-scalings, on a real
    root scalings: ``O(n nZ)``. Moving sliders follow ``w = d . x`` (``sens.wphi`` on the rows)."""
    real = sens.real
    p = real.p
    m2 = stage.shape[0]
    lt = real.lam * tau
    e = np.exp(lt)
    er, ei = e[:p].real[:, None], e[:p].imag[:, None]
    a, b = stage[0:2 * p:2], stage[1:2 * p:2]
    out_a, out_b = jac[0:2 * p:2], jac[1:2 * p:2]
    np.multiply(er, a, out=out_a)
    out_a -= ei * b
    np.multiply(ei, a, out=out_b)
    out_b += er * b
    np.multiply(e[p:].real[:, None], stage[2 * p:], out=jac[2 * p:m2])
    if sens.sj is not None:
        g = tau * _phi1(lt)
        gr, gi = g[:p].real[:, None], g[:p].imag[:, None]
        f = sens.sj @ jac[sens.jcols]
        fa, fb = f[0:2 * p:2], f[1:2 * p:2]
        out_a += gr * fa - gi * fb
        out_b += gi * fa + gr * fb
        jac[2 * p:m2] += g[p:].real[:, None] * f[2 * p:]
    if sens.moving.size:
        jac[m2 + sens.moving] = sens.wphi @ jac[:m2]


def _modal_saltation(marcher, basis, jac, jump, dg) -> None:
    """The saltation ``S = I + e_[v,w] jump dg^T`` (:func:`saltation`) on modal rows of ``jac`` in
    ``basis``, in place: ``dg^T dy = (dg^T R) r`` and the jump of the velocities enters the rows as
    ``Q [0, jump_v]`` (rank one, ``O(n^2 + n nZ)``). Classical modes: ``dg^T [dx; dv] = (Phi^T
    dg_x)^T xi + (Phi^T dg_v)^T eta``, ``Q [0, jump_v]`` the rows ``eta`` of ``Phi^T M jump_v``;
    general ones: ``dg^T R`` from ``dg^T V`` and ``Q [0, jump_v]`` from ``V^-1[:, n:] jump_v``
    (:class:`_RealModes`)."""
    n = basis.m
    grad = np.empty(jac.shape[0])
    grad[2 * n:] = dg[2 * n:]
    if basis.shapes is not None:
        grad[0:2 * n:2] = dg[:n] @ basis.shapes
        grad[1:2 * n:2] = dg[n:2 * n] @ basis.shapes
        r = grad @ jac
        jac[1:2 * n:2] += np.outer(basis.shapes_mass @ jump[:n], r)
    else:
        real = _real_modes(marcher, basis)
        grad[:2 * n] = real.cols((dg[:2 * n] @ basis.V)[real.keep])
        r = grad @ jac
        jac[:2 * n] += np.outer(real.rows(basis.velocity_product(jump[:n])[real.keep]), r)
    jac[2 * n:] += np.outer(jump[n:], r)


def march_jacobian(marcher, pieces) -> np.ndarray:
    """Jacobian ``(nZ, nZ)`` of the end state of a march with respect to its start state, both in
    full coordinates ``[x, v, w]``.

    The variations are carried as rows of ``[x, v, w]`` through the pieces (:func:`apply_piece`,
    saltations between them). While consecutive pieces are modal without stuck rigid sliders
    (``N = I``) the rows ``[x, v]`` are kept in the modal coordinates of the current configuration
    instead: a classically damped piece is then a 2 x 2 matrix per mode (:func:`_modal_piece`), a
    non-classically damped one (without contacts) a 2 x 2 real matrix per conjugate pair of its
    general modes (:func:`_real_piece`), and a new configuration a change of basis
    (:func:`_basis_change`), one real product where physical rows take four real or three complex
    ones; other pieces and the end take physical rows. The same Jacobian to rounding.

    Parameters
    ----------
    marcher : Marcher
        The marcher that made the pieces.
    pieces : sequence of (Interval, float)
        The march's pieces and their durations, in order, as passed to ``on_interval`` of
        :meth:`~frictionjoint.solvers.marcher.events.Marcher.march` (each piece ended by an event carries
        the event's row as ``end_row``).
    """
    return _march_rows(marcher, pieces, modal=True)


def _march_jacobian_rows(marcher, pieces) -> np.ndarray:
    """:func:`march_jacobian` with physical rows through every piece (four real products per
    classical piece, three complex ones per general one): the reference of the modal rows' test."""
    return _march_rows(marcher, pieces, modal=False)


def _march_rows(marcher, pieces, modal: bool) -> np.ndarray:
    """:func:`march_jacobian`'s march of the rows; ``modal`` False: physical rows throughout."""
    system = marcher.system
    n = system.n_dof
    nz = 2 * n + system.n_sliders
    jac, stage, stage_real = np.eye(nz), None, None
    basis = None  # the configuration whose modal coordinates the rows [x, v] are in (None: physical)
    for k, (itv, tau) in enumerate(pieces):
        sens = _sensitivity(marcher, itv)
        if modal and sens.modal_rows:
            if stage is None:
                stage = np.empty((n, 3, nz))
            _to_modal(marcher, jac, basis, itv.config, stage)
            basis = itv.config
            _modal_piece(sens, itv, tau, stage, jac)
        elif modal and sens.real is not None:
            if stage_real is None:
                stage_real = np.empty((2 * n, nz))
            _to_real(marcher, jac, basis, itv.config, stage_real)
            basis = itv.config
            _real_piece(sens, tau, stage_real, jac)
        else:
            if basis is not None:
                jac, basis = _to_physical(marcher, jac, basis), None
            jac = apply_piece(marcher, itv, tau, jac)
        row = getattr(itv, "end_row", None)
        if row is not None and k + 1 < len(pieces):
            s = saltation(marcher, itv, tau, row, pieces[k + 1][0])
            if s is not None:
                jump, dg = s
                if basis is None:
                    jac[n:] += np.outer(jump, dg @ jac)
                else:
                    _modal_saltation(marcher, basis, jac, jump, dg)
    return jac if basis is None else _to_physical(marcher, jac, basis)
