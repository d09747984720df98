"""What the marcher needs of a stick/slip status that does not depend on the state: built once
per status and cached by :class:`.events.Marcher`.

For a status (0 stuck, +1/-1 slipping, 2 on an open contact) :class:`StatusPattern` holds the
event functions (one row per slipping slider: its velocity; two per stuck slider: its force
against +limit and -limit; with normal-load variation, the limit is ``mu N(x)`` and a slipping
slider on a contact has a second row, its normal load (lift-off), and one on an open contact the
single row ``-N(x)`` (closure)),
their reduced form on the configuration's coordinates, the constant forces of the status
(slipping sliders' friction, stuck Jenkins springs), the projection of a state onto the status,
and the packed constant arrays of the compiled consistency test (:mod:`.consistency`).
"""
from __future__ import annotations

import numpy as np

from . import consistency
from .propagator import ConfigData, Observables, _system_cached

__all__ = ["StatusPattern"]


class StatusPattern:
    """What depends on the status vector only (not on the state).

    Event functions (rows of ``meta``) are ``g = cy y + ax x0 + af F + a0`` with
    ``a0 = a0c + a0k * w[widx]`` (Jenkins springs' constant parts).

    Parameters
    ----------
    sysm : FrictionSystem
        The marched system.
    status : (n_sliders,) int8 ndarray
        The stick/slip status.
    cfg : ConfigData
        The decomposition of the status's configuration (sliders of status 0 stuck).
    """

    __slots__ = ("system", "cfg", "meta", "obs", "red_cy", "red_cc", "red_cs", "a0c", "a0k", "widx", "has_w",
                 "has_af", "vrows", "any_v", "row_slider", "row_fs", "row_v_list", "f_slip", "jst_dt",
                 "jst_k", "jst", "has_jst", "slip_j", "slip_j_dir", "slip_j_off", "has_slip_j",
                 "has_rigid_stuck", "n_rows", "ax_abs", "modal_p", "modal_abs_p", "kern", "w_dir")

    def __init__(self, sysm, status: np.ndarray, cfg: ConfigData) -> None:
        self.system = sysm
        self.cfg = cfg
        self.modal_p = self.modal_abs_p = None
        self.kern = None
        self._event_functions(status)
        self._constant_force(status)
        self._projection(status)

    def _event_functions(self, status: np.ndarray) -> None:
        """The event functions (:func:`_slider_rows` per slider), their reduced form on the
        configuration's coordinates and what the search and the consistency test read of them."""
        sysm, cfg = self.system, self.cfg
        n = sysm.n_dof
        rows_x, rows_v, rows_f, a0c, a0k, meta = [], [], [], [], [], []
        zero = np.zeros(n)
        rigid_row = {int(i): r for r, i in enumerate(cfg.rigid_stuck)}
        for i, s in enumerate(status):
            rx, rv, rf, c0, ck, kinds = _slider_rows(sysm, cfg, rigid_row, zero, i, s)
            rows_x += rx; rows_v += rv; rows_f += rf; a0c += c0; a0k += ck
            meta += [(i, kind) for kind in kinds]
        self.meta = meta
        self.n_rows = len(meta)
        if meta:
            # the rows of F: zero but for stuck rigid sliders' holding forces (one read-only zero
            # then, not rows x n of them)
            af = (np.broadcast_to(zero, (len(meta), n)) if all(r is zero for r in rows_f)
                  else np.array(rows_f, dtype=float))
            if not cfg.rigid_stuck.size:
                # N = I: the reduced rows are [ax, av] (the products with N would give them again,
                # exact zeros added, at r n^2 each), and ax, av their halves (views: held once)
                cy = np.empty((len(meta), 2 * n))
                cy[:, :n] = rows_x
                cy[:, n:] = rows_v
                obs = Observables(cy[:, :n], cy[:, n:], af, a0c)
                self.red_cy = cy
            else:
                obs = Observables(rows_x, rows_v, af, a0c)
                nb = cfg.N
                self.red_cy = np.hstack([obs.ax @ nb, obs.av @ nb])
            self.obs = obs
            # |coefficients| of x in the event rows: their rounding scale (|ax| |x| >> |ax x| when
            # the DOFs a slider joins move together, e.g. a stiff Jenkins between two masses);
            # once packed, the packed copy (:meth:`pack`)
            self.ax_abs = np.abs(obs.ax)
            self.red_cc = obs.af @ sysm.force_cos
            self.red_cs = obs.af @ sysm.force_sin
            self.has_af = bool(np.any(obs.af != 0))
            self.a0c = obs.a0
            self.a0k = np.array(a0k, dtype=float)
            self.widx = np.array([i for i, _ in meta], dtype=np.intp)
            self.has_w = bool(np.any(self.a0k != 0))
            self.row_slider = [i for i, _ in meta]
            self.row_v_list = [k == "v" for _, k in meta]
            self.row_fs = [float(sysm.slip_force[i]) for i, _ in meta]
        else:
            self.obs = None
            self.ax_abs = None
            self.row_slider, self.row_v_list, self.row_fs = [], [], []
        self.vrows = np.array(self.row_v_list, dtype=bool)
        self.any_v = bool(self.vrows.any())

    def _constant_force(self, status: np.ndarray) -> None:
        """The constant force of the status: slipping sliders' friction (on contacts its constant
        part; the part g.x is in the configuration's stiffness); open contacts take their preload
        off; stuck Jenkins springs' ``k w d`` (``jst_dt``, ``jst_k``)."""
        sysm = self.system
        d = sysm.slider_direction
        sliding = (status != 0) & (status != 2)
        opened = status == 2
        self.f_slip = None
        if np.any(sliding):
            self.f_slip = d[sliding].T @ (status[sliding] * sysm.slip_force[sliding])
        if np.any(opened):
            cs = sysm.slider_contact[opened]
            f_open = sysm.contact_normal[cs].T @ sysm.contact_preload[cs]
            self.f_slip = f_open if self.f_slip is None else self.f_slip + f_open
        jst = (status == 0) & ~sysm.rigid
        self.has_jst = bool(np.any(jst))
        self.jst = jst
        self.jst_dt = d[jst].T
        self.jst_k = sysm.slider_stiffness[jst]

    def _projection(self, status: np.ndarray) -> None:
        """The projection of a state onto the status: moving Jenkins sliders ``w = dir . x - off``
        (on a contact ``dir = d - sig g/k``: the spring force follows ``mu N(x)``; on an open contact
        ``w = d . x``), and ``w' = w_dir . v``."""
        sysm = self.system
        d = sysm.slider_direction
        self.has_rigid_stuck = bool(self.cfg.rigid_stuck.size)
        slip_j = (status != 0) & ~sysm.rigid
        self.has_slip_j = bool(np.any(slip_j))
        self.slip_j = slip_j
        sig = np.where(status == 2, 0, status).astype(float)
        kj = sysm.slider_stiffness[slip_j]
        self.slip_j_dir = d[slip_j] - (sig[slip_j] / kj)[:, None] * sysm.slip_gradient[slip_j]
        self.slip_j_off = sig[slip_j] * sysm.slip_force[slip_j] / kj
        #: rows of w' = w_dir . v of every slider but the stuck Jenkins ones (their rows, w' = 0,
        #: are not read): the directions themselves (a view of the system's) where no
        #: slipping slider is on a contact
        if np.any(sysm.varying[slip_j]):
            self.w_dir = d.copy()
            self.w_dir[slip_j] = self.slip_j_dir
            self.w_dir[self.jst] = 0.0
        else:
            self.w_dir = d[:]

    def pack(self, fscale_fixed: float, mass_scale: float) -> tuple:
        """The constant arrays of :func:`.consistency.check` for this status, packed
        (:func:`.consistency.pack`), kept in :attr:`kern`.

        Parameters
        ----------
        fscale_fixed : float
            The marcher's load scale that does not depend on the state [N].
        mass_scale : float
            The largest diagonal mass [kg].

        Returns
        -------
        ((fc, fk, fs), ik) : ((ndarray, ndarray, ndarray), ndarray)
            The configuration's packed floats (shared by its statuses), the status's, the system's
            (shared by its configurations), the ints.
        """
        pat = self
        sysm = self.system
        cfg = pat.cfg
        rigid_idx = np.flatnonzero(sysm.rigid)
        m = cfg.m
        n = sysm.n_dof
        kinds = consistency.ROW_KIND
        obs = pat.obs
        cy = pat.red_cy
        identity, diagonal = _config_kern(sysm, cfg, n)
        none = np.zeros((0, n))
        pat.kern = consistency.pack(
            cfg.kern,
            (np.zeros(n) if pat.f_slip is None else pat.f_slip, pat.jst_dt, pat.jst_k,
             cy if identity else cy[:, :m], none if identity else cy[:, m:], none if identity else obs.ax,
             obs.af if pat.has_af else none, pat.ax_abs,
             pat.a0c, pat.a0k, pat.red_cc, pat.red_cs, pat.row_fs,
             [fscale_fixed, mass_scale, max(sysm.omega, cfg.max_rate, 1e-300), sysm.omega], pat.slip_j_dir,
             pat.slip_j_off, sysm.slider_direction[rigid_idx]),
            (np.flatnonzero(pat.jst), pat.widx, [kinds[k] for _, k in pat.meta], pat.row_slider,
             [pat.f_slip is not None, pat.has_jst, pat.has_af, pat.has_w,
              bool(np.any(pat.red_cc != 0) or np.any(pat.red_cs != 0)), identity, diagonal],
             np.flatnonzero(pat.slip_j), rigid_idx))
        # the arrays the status keeps that the packed buffer holds now: its copies (views), the
        # status's own freed
        pat.ax_abs = consistency.packed(pat.kern, "ax_abs")
        pat.slip_j_dir = consistency.packed(pat.kern, "slip_j_dir")
        if identity:  # the reduced rows [ax, av] (packed as one block) and ax, av their halves
            cy = pat.red_cy = consistency.packed(pat.kern, "cy_q")
            obs.ax, obs.av = cy[:, :n], cy[:, n:]
        return pat.kern


def _config_kern(sysm, cfg: ConfigData, n: int) -> tuple[bool, bool]:
    """The configuration's part of the consistency test's arrays (:func:`.consistency.pack_config`),
    packed on the first status of the configuration and kept in ``cfg.kern``; returns the flags
    ``(identity, diagonal)``: ``N = I`` (``N^T`` not packed; the statuses' ``cy_q`` holds their
    rows ``[ax, av]``), ``M^-1`` diagonal (packed as its diagonal; with ``N = I`` also ``A21 = -M^-1
    K_c`` not packed, formed from ``K_c`` where read). Where the configuration's ``K`` and
    ``A22 = -M^-1 C`` are the system's (``N = I``, no contact changes them), they are packed once
    per system (:func:`.consistency.pack_shared`): two of the four ``n x n`` matrices, 2.6 MB of a
    configuration's memory at 400 DOFs."""
    identity = not cfg.rigid_stuck.size
    mint = cfg.mr_inv_nt
    diagonal = cfg.diagonal_mass_inverse()
    if cfg.kern is None:
        m = cfg.m
        shared = None
        if identity and cfg.base_stiffness is sysm.stiffness and cfg.damping is sysm.damping:
            shared = _system_cached(sysm, "_kern_shared",
                                    lambda: consistency.pack_shared({0: sysm.stiffness, 5: cfg.first_order_blocks()[1]}),
                                    sysm.stiffness, sysm.damping, sysm.mass)
        if identity and diagonal:  # A21 = -M^-1 K_c: formed from K_c where it is read (consistency.check)
            a21, a22 = np.zeros((0, m)), (np.zeros((0, m)) if shared else cfg.first_order_blocks()[1])
        else:
            a21, a22 = cfg.first_order_blocks()
        cfg.kern = consistency.pack_config(
            (cfg.base_stiffness, cfg.stiffness, np.zeros((0, n)) if identity else cfg.N.T,
             np.diagonal(mint)[:, None] if diagonal else mint, a21, a22, cfg.bc[m:], cfg.bs[m:]), shared)
        if shared is not None:
            cfg._shared += (shared[0],)  # the system's: not in the configuration's nbytes
        off, r, c = cfg.kern[1][3:6]  # K_c, now packed: the configuration refers to that copy
        cfg.adopt_stiffness(cfg.kern[0][off:off + r * c].reshape(r, c))
    return identity, diagonal


def _slider_rows(sysm, cfg: ConfigData, rigid_row: dict, zero: np.ndarray, i: int, s: int) -> tuple:
    """The event rows of slider ``i`` in status ``s``, as in the reference construction: ``(rows_x,
    rows_v, rows_f, a0c, a0k, kinds)``, a list each, one entry a row (``a0 = a0c + a0k w_i``; kinds
    ``v`` a slipping slider's velocity, ``+``/``-`` a stuck one's force against +limit/-limit,
    ``o`` a contact's normal load (lift-off), ``c`` an open contact's closure)."""
    d = sysm.slider_direction
    fs = sysm.slip_force[i]
    grad = sysm.slip_gradient
    if sysm.varying[i]:
        # slip limit mu N(x) = fs + g.x; normal load N(x) = N0 - kn n.x (the contact's row)
        c = sysm.slider_contact[i]
        nrow = -sysm.contact_stiffness[c] * sysm.contact_normal[c]
        n0 = sysm.contact_preload[c]
        k = sysm.slider_stiffness[i]
        if s == 2:  # open: closes when N(x) reaches 0 from below
            return [-nrow], [zero], [zero], [-n0], [0.0], "c"
        if s != 0:  # slipping: s w' = (s d - g/k).v >= 0, and N(x) >= 0 (lift-off)
            return [zero, nrow], [s * d[i] - grad[i] / k, zero], [zero, zero], [0.0, n0], [0.0, 0.0], "vo"
        # stuck: fs + g.x -+ k (d.x - w) >= 0
        return [grad[i] - k * d[i], grad[i] + k * d[i]], [zero, zero], [zero, zero], [fs, fs], [k, -k], "+-"
    if s != 0:
        return [zero], [s * d[i]], [zero], [0.0], [0.0], "v"
    if not sysm.rigid[i]:
        k = sysm.slider_stiffness[i]
        return [-k * d[i], k * d[i]], [zero, zero], [zero, zero], [fs, fs], [k, -k], "+-"
    lr = cfg.L[rigid_row[i]]
    hx = lr @ cfg.stiffness
    hv = lr @ cfg.damping
    # holding force T = -lr F + lr C v + lr Kc x
    return [-hx, hx], [-hv, hv], [lr, -lr], [fs, fs], [0.0, 0.0], "+-"
