"""Hong & Liu's consistency test of one stick/slip status at one state, compiled (numba).

The marcher settles the status at an event by testing a status, changing the most violated slider,
and testing again (:meth:`.Marcher.settle`). Each test needs the event functions of the status and
their first two time derivatives at the state, ``g = cy y + ax x + af F + a0`` with ``y = [0, N^T
v]`` and ``y', y''`` from the configuration's first-order matrix ``A``, and their zero bands. The
row of the event that brought the march here is at zero by construction (the search located its
root): where the direct evaluation puts it slightly above zero, it is taken as zero; so are the rows
that vanish with it (a contact closing: its slider's force and slip limit are both zero), either
side of zero. In
NumPy that is some thirty small array operations per test, each a few microseconds of call
overhead for a few nanoseconds of arithmetic; :func:`check` does one test in one compiled call, and
hands back what the closed-form piece of a consistent status starts from (``y0``, ``b0``, the
constant load, the event functions' constants and the zero bands), so the marcher builds the
:class:`.Interval` without computing them again.

The arithmetic is the one of :meth:`.Marcher.interval` and :meth:`.Interval.start_values`: the
stuck Jenkins springs' force in spring form (``k (d.x - w)`` terms, not ``K_c x - k w d``), the
same zero bands (force rows ``1e-12`` of the load scale, velocity rows ``1e-11`` of the velocity
scale), the same scoring (most violated first, by its band). A row inside its band whose slope is
inside its band too is judged by its curvature, and one that turns up (``g' < 0 < g''``) but whose
Taylor minimum ``g - g'^2 / (2 g'')`` lies below the band is violated (the dip rule): the search
would see it leave the band at once, at the start of the piece (a stiff joint's fast oscillation
taking its force past the slip limit by more than the rounding of ``kt |x|``; judged consistent,
the same event was found again at the same instant, forever). It runs where the event search runs
compiled (:data:`.search.ENABLED`); elsewhere the marcher's NumPy path is used.
"""
from __future__ import annotations

import math

import numpy as np

from ..jit import ENABLED, _jit, matvec, row_dot

__all__ = ["check", "pack", "pack_config", "packed", "unpack", "most_violated", "ROW_KIND", "FLOATS", "CONFIG_FLOATS", "INTS",
           "ENABLED", "KIND_V", "KIND_PLUS", "KIND_MINUS", "KIND_OPEN", "KIND_CLOSE", "EVENT_ROW_SLACK"]

#: row kinds: a slipping slider's velocity, a stuck slider's force at +limit / -limit, a contact's
#: normal load (lift-off) and an open contact's closure
KIND_V, KIND_PLUS, KIND_MINUS, KIND_OPEN, KIND_CLOSE = 0, 1, 2, 3, 4
#: the row kinds of a status's rows (:attr:`.patterns.StatusPattern.meta`: ``(slider, kind)``)
ROW_KIND = {"v": KIND_V, "+": KIND_PLUS, "-": KIND_MINUS, "o": KIND_OPEN, "c": KIND_CLOSE}


#: an event row located by the search (on the piece's modal closed form) that the direct
#: evaluation here puts above zero by at most this many zero bands is at zero: the two
#: evaluations differ by their rounding, which for a row of large terms (a contact's ``kn n.x``
#: beside ``N0``) on a configuration with ill-conditioned modes can exceed the band; judged
#: positive, the row would be found again at the same instant, forever
EVENT_ROW_SLACK = 1e4

#: the float arrays of a configuration, the same for each of its statuses: packed once
#: (:func:`pack_config`, kept on the configuration), then referred to by each status's kern
CONFIG_FLOATS = ("K", "K_c", "N^T", "M_r^-1 N^T", "A21", "A22", "bc", "bs")
#: the float and int arrays of a status, in the order :func:`pack` takes them (the configuration's first) and
#: :func:`check` reads them
FLOATS = CONFIG_FLOATS + ("f_slip", "jst_dt", "jst_k", "cy_q", "cy_v", "ax", "af", "ax_abs", "a0c", "a0k", "cc",
                          "cs", "row_fs", "scales", "slip_j_dir", "slip_j_off", "rigid_dir")
INTS = ("jst_idx", "widx", "row_kind", "row_slider", "flags", "slip_j", "rigid_idx")
_N_CONFIG = len(CONFIG_FLOATS)


def _flat(floats) -> tuple:
    """The float arrays one after the other in one buffer (one copy each, transposed views
    included) and their header: offset and shape as two numbers (1-D arrays: ``(size, 1)``)."""
    floats = [np.asarray(a, dtype=float) for a in floats]
    hdr, off = [], 0
    for a in floats:
        r, c = (a.shape[0], a.shape[1]) if a.ndim == 2 else (a.size, 1)
        hdr += [off, r, c]
        off += a.size
    buf = np.empty(off)
    for a, o in zip(floats, hdr[::3]):
        buf[o:o + a.size].reshape(a.shape)[...] = a
    return buf, hdr


def pack_config(floats, shared=None) -> tuple:
    """The configuration's arrays :data:`CONFIG_FLOATS` packed once for all its statuses:
    ``(buffer, header, shared buffer)``, for :func:`pack`. Each status packed them again before:
    four ``m x m`` and ``n x n`` matrices, 1.3 MB at n = 200, per status.

    ``shared``: :func:`pack_shared`'s ``(buffer, {index: (offset, rows, cols)})`` of the arrays
    that are the same for every configuration of a system (``K`` and ``A22`` without contacts and
    stuck rigid sliders), packed once per system instead of once per configuration: their header
    entries point into the shared buffer (offset ``-1 - offset``; their entries in ``floats`` are
    not read)."""
    if len(floats) != _N_CONFIG:
        raise ValueError(f"pack_config takes {_N_CONFIG} float arrays")
    if not shared:
        buf, hdr = _flat(floats)
        return buf, hdr, np.zeros(0)
    fs, hs = shared
    own = [np.zeros(0) if i in hs else a for i, a in enumerate(floats)]
    buf, hdr = _flat(own)
    for i, (off, r, c) in hs.items():
        hdr[3 * i:3 * i + 3] = [-1 - off, r, c]
    return buf, hdr, fs


def pack_shared(arrays: dict) -> tuple:
    """``(buffer, {index: (offset, rows, cols)})`` of :func:`pack_config`'s arrays shared by the
    configurations of a system, ``arrays`` ``{index: array}``."""
    idx = sorted(arrays)
    buf, hdr = _flat([arrays[i] for i in idx])
    return buf, {i: tuple(hdr[3 * k:3 * k + 3]) for k, i in enumerate(idx)}


def pack(config, floats, ints) -> tuple:
    """The status's constant arrays as ``((fc, fk, fs), ik)`` for :func:`check`: the configuration's
    buffer ``fc`` (:func:`pack_config`, shared), the status's own floats ``fk`` (the rest of
    :data:`FLOATS`), the system's shared buffer ``fs`` (:func:`pack_shared`) and the ints.

    Numba checks the type of every argument at every call: a tuple of 27 arrays cost ~4.5 us per
    call (two calls per event), two arrays ~0.2 us. ``ik`` starts with a header: for each float
    array its offset (in ``fc`` for the configuration's, in ``fk`` for the others) and its shape
    as two numbers (1-D arrays: ``(size, 1)``), then for each int array its offset in ``ik`` and
    its size; the int arrays follow.
    """
    if len(floats) != len(FLOATS) - _N_CONFIG or len(ints) != len(INTS):
        raise ValueError(f"pack takes {len(FLOATS) - _N_CONFIG} float and {len(INTS)} int arrays")
    fc, hc, fs = config
    fk, hk = _flat(floats)
    ints = [np.asarray(a, dtype=np.intp).ravel() for a in ints]
    hdr = hc + hk
    ioff = len(hdr) + 2 * len(ints)
    for a in ints:
        hdr += [ioff, a.size]
        ioff += a.size
    ik = np.concatenate([np.array(hdr, np.intp)] + ints)
    return (fc, fk, fs), ik


def packed(kern, name: str) -> np.ndarray:
    """The packed copy (a view) of the status's float array ``name`` (:data:`FLOATS`, after the
    configuration's) in :func:`pack`'s ``kern``, shaped as it was packed (2-D)."""
    i = FLOATS.index(name)
    if i < _N_CONFIG:
        raise ValueError(f"{name!r} is a configuration's array, not a status's")
    (_, fk, _), ik = kern
    off, r, c = (int(v) for v in ik[3 * i:3 * i + 3])
    return fk[off:off + r * c].reshape(r, c)


@_jit
def _f1(fk, ik, i):
    off, r, c = ik[3 * i], ik[3 * i + 1], ik[3 * i + 2]
    if i >= _N_CONFIG:
        buf = fk[1]
    elif off < 0:  # in the system's shared buffer (pack_config)
        buf = fk[2]
        off = -1 - off
    else:
        buf = fk[0]
    return buf[off:off + r * c]


@_jit
def _f2(fk, ik, i):
    return _f1(fk, ik, i).reshape((ik[3 * i + 1], ik[3 * i + 2]))


@_jit
def _i1(ik, i):
    h = 3 * len(FLOATS) + 2 * i
    off, size = ik[h], ik[h + 1]
    return ik[off:off + size]


@_jit
def _positions(w, x, d, off, idx):
    """``w[idx[q]] = d[q] . x - off[q]`` in place (``off`` empty: no offsets)."""
    for q in range(idx.size):
        s = row_dot(d, q, x)
        w[idx[q]] = s - off[q] if off.size else s


@_jit
def check(fk, ik, x, v, w, f_ext, t0, v_scale, forced, event_row, zero_rows):
    """Consistency test of a status (its constant arrays ``kern``, see :meth:`.patterns.StatusPattern.pack`).

    Its zero bands and the choice of the most violated row are compiled steps; the piece's start
    (constant load, reduced forcing, the event functions' values and derivatives) stays written out
    here: as compiled helpers, inlined or called, they made a test 6-10 % slower (about 0.25 us of
    4, measured on 400 real calls).

    Parameters
    ----------
    fk : (ndarray, ndarray) tuple
    ik : ndarray
        The status's constant arrays packed by :func:`pack` (see ``Marcher._kernel``): the float
        arrays :data:`FLOATS` (``scales``: fixed load scale, mass scale, rate, omega) and the int
        arrays :data:`INTS` (``flags``: has_slip, has_jst, has_af, has_w, harmonic, identity,
        diagonal). ``identity``: ``N = I`` (no stuck rigid sliders), ``N^T`` is not packed (nor
        ``A21 = -M^-1 K_c`` where ``M^-1`` is also diagonal: its products are formed from ``K_c``, the
        same to rounding; 1.3 MB of a configuration at 400 DOFs), and the
        reduced rows ``[ax, av]`` are one block in ``cy_q``'s place (``cy_q = ax`` and ``cy_v = av``
        its halves; the status's ``red_cy`` is a view of it: held once); ``diagonal``: ``M_r^-1 N^T`` is diagonal and packed as its diagonal
        (m, 1); ``af`` is packed only where ``has_af``. Each gives the numbers of the product it
        replaces: the terms of the zero entries add exact zeros.
    x, v : (n,) ndarray
        State.
    w : (n_sliders,) ndarray
        Slider positions, projected on the status in place (as ``Marcher._project``: slipping
        Jenkins sliders and rigid ones follow ``x``); the velocity's projection (stuck rigid
        sliders) is the caller's.
    f_ext : (n,) ndarray
        Held external force at ``t0``.
    t0 : float
        Time [s].
    v_scale : float
        The marcher's velocity scale.
    forced : (n_sliders,) bool ndarray
        Sliders set slipping by this settling because their force exceeded the limit.
    event_row : int
        Row whose zero the event search located at ``t0`` (-1: none): taken as zero where it
        comes out above zero by at most :data:`EVENT_ROW_SLACK` of its band (module docstring).
    zero_rows : (k,) intp ndarray
        Rows that vanish at the event by construction (a contact that closes: its slider's
        force and slip limit; one that opens: its closure row): taken as zero where they come
        out within :data:`EVENT_ROW_SLACK` of their bands, either side.

    Returns
    -------
    j : int
        Most violated row, -1 if the status is consistent.
    gj, tolj : float
        Its value and zero band.
    atzero : (rows,) bool ndarray
        Rows within their zero band.
    buf : ndarray
        ``tol, f_const, kx0, c0, y0, b0`` one after the other (:func:`unpack`): the zero bands, the
        piece's constant load, ``K_c x``, the event functions' constants, and the start state and
        constant forcing in reduced coordinates.
    """
    k_sys, k_c, f_slip, jst_dt, jst_k = _f2(fk, ik, 0), _f2(fk, ik, 1), _f1(fk, ik, 8), _f2(fk, ik, 9), _f1(fk, ik, 10)
    nt, mint, a21, a22 = _f2(fk, ik, 2), _f2(fk, ik, 3), _f2(fk, ik, 4), _f2(fk, ik, 5)
    bcv, bsv, cyq, cyv = _f1(fk, ik, 6), _f1(fk, ik, 7), _f2(fk, ik, 11), _f2(fk, ik, 12)
    ax, af, ax_abs = _f2(fk, ik, 13), _f2(fk, ik, 14), _f2(fk, ik, 15)
    a0c, a0k, cc, cs, row_fs, scales = (_f1(fk, ik, 16), _f1(fk, ik, 17), _f1(fk, ik, 18), _f1(fk, ik, 19),
                                        _f1(fk, ik, 20), _f1(fk, ik, 21))
    jst_idx, widx, row_kind, row_slider, flags = _i1(ik, 0), _i1(ik, 1), _i1(ik, 2), _i1(ik, 3), _i1(ik, 4)
    n = x.size
    # the slider positions projected on the status first (Marcher._project): slipping Jenkins
    # sliders w = d.x - F/k sign, rigid ones w = d.x
    _positions(w, x, _f2(fk, ik, 22), _f1(fk, ik, 23), _i1(ik, 5))
    _positions(w, x, _f2(fk, ik, 24), np.zeros(0), _i1(ik, 6))
    has_slip, has_jst, has_af, has_w, harmonic = flags[0], flags[1], flags[2], flags[3], flags[4]
    identity, diagonal = flags[5], flags[6]
    fscale_fixed, mass_scale, rate, om = scales[0], scales[1], scales[2], scales[3]
    m = a22.shape[0]
    if identity:  # the reduced rows [ax, av], one block: ax (= cy_q) and cy_v its halves
        cy = _f2(fk, ik, 11)
        ax = cy[:, :n]
        cyq = ax
        cyv = cy[:, n:]
    nr = a0c.size
    # constant load of the piece and the reduced forcing (as Marcher.interval)
    f_const = f_ext.copy()
    if has_slip:
        f_const -= f_slip
    nj = jst_k.size
    kw = np.empty(nj)
    for q in range(nj):
        kw[q] = jst_k[q] * w[jst_idx[q]]
    if has_jst:
        f_const += matvec(jst_dt, kw)
    sf = np.zeros(0)
    kx0 = matvec(k_c, x)
    if has_jst:
        rhs = f_ext - matvec(k_sys, x)
        if has_slip:
            rhs -= f_slip
        # each stuck spring's force k (d.x - w) as one scalar (Marcher.interval)
        sf = np.empty(nj)
        for q in range(nj):
            s = 0.0
            for k in range(n):
                s += jst_dt[k, q] * x[k]
            sf[q] = jst_k[q] * (s - w[jst_idx[q]])
        rhs -= matvec(jst_dt, sf)
    else:
        rhs = f_const - kx0
    u = v.copy() if identity else matvec(nt, v)
    r = mint[:, 0] * rhs if diagonal else matvec(mint, rhs)
    y0 = np.zeros(2 * m)
    b0 = np.zeros(2 * m)
    y0[m:] = u
    b0[m:] = r
    # event functions' constants
    c0 = matvec(ax, x)
    if has_af:
        c0 += matvec(af, f_const)
    for q in range(nr):
        c0[q] += a0c[q] + a0k[q] * w[widx[q]] if has_w else a0c[q]
    co = math.cos(om * t0)
    si = math.sin(om * t0)
    # start values: y1 = A y0 + b0 + bc co + bs si, y2 = A y1 + w (bs co - bc si)
    y1v = matvec(a22, u) + r + bcv * co + bsv * si
    if a21.shape[0] == m:
        a21u = matvec(a21, u)
    else:  # not packed (N = I, M^-1 diagonal): A21 u = -M^-1 (K_c u)
        a21u = -(mint[:, 0] * matvec(k_c, u))
    y2v = a21u + matvec(a22, y1v) + om * (bsv * co - bcv * si)
    g = matvec(cyv, u) + c0
    dg = matvec(cyq, u) + matvec(cyv, y1v)
    ddg = matvec(cyq, y1v) + matvec(cyv, y2v)
    if harmonic:
        for q in range(nr):
            g[q] += cc[q] * co + cs[q] * si
            dg[q] += om * (cs[q] * co - cc[q] * si)
            ddg[q] -= om * om * (cc[q] * co + cs[q] * si)
    # the velocity rows' load scale: with stuck Jenkins springs the spring-form terms of the load
    # (f_ext, friction, K x, the springs' forces k (d.x - w)), not the force rows' rounding scale
    # (k (d.x) and k w, ~ kt |x|), which over the stiff rate made a velocity band of 6e-7 m/s at
    # kt = 1e10 (sliders kept slipping while moving backwards); elsewhere the force scale (-1)
    lscale = -1.0
    if has_jst:
        lscale = fscale_fixed
        for k in range(n):
            lscale = max(lscale, abs(f_ext[k]))
        if has_slip:
            for k in range(n):
                lscale = max(lscale, abs(f_slip[k]))
        kb = matvec(k_sys, x)
        for k in range(n):
            lscale = max(lscale, abs(kb[k]))
        for q in range(nj):
            lscale = max(lscale, abs(sf[q]))
    tol = _zero_bands(ax_abs, row_fs, row_kind, x, f_const, kx0, fscale_fixed, mass_scale, rate, v_scale, lscale)
    j, atzero = _most_violated(g, dg, ddg, tol, rate, row_kind, row_slider, forced, event_row, zero_rows)
    gj = g[j] if j >= 0 else 0.0
    tolj = tol[j] if j >= 0 else 0.0
    # one buffer for the float arrays (each array handed back to Python costs a boxing)
    buf = np.concatenate((tol, f_const, kx0, c0, y0, b0))
    return j, gj, tolj, atzero, buf


@_jit(inline=True)
def _zero_bands(ax_abs, row_fs, row_kind, x, f_const, kx0, fscale_fixed, mass_scale, rate, v_scale, lscale):
    """The rows' zero bands (``Marcher._tolerances``): velocity rows ``1e-11`` of the velocity scale
    (at least the load scale's ``fscale / (mass_scale rate)``), force rows ``1e-12`` of the larger
    of their slip force and the load scale (the fixed one, ``|f_const|``, ``|K_c x|`` and ``|ax|
    |x|``)."""
    n = x.size
    nr = row_fs.size
    fscale = fscale_fixed
    for k in range(n):
        fscale = max(fscale, abs(f_const[k]), abs(kx0[k]))
    if nr:
        ab = matvec(ax_abs, np.abs(x))
        for q in range(nr):
            fscale = max(fscale, abs(ab[q]))
    v_floor = (fscale if lscale < 0 else lscale) / (mass_scale * rate)
    tv = 1e-11 * max(v_scale, v_floor)
    tol = np.empty(nr)
    for q in range(nr):
        tol[q] = tv if row_kind[q] == KIND_V else 1e-12 * max(row_fs[q], fscale)
    return tol


@_jit(inline=True)
def _most_violated(g, dg, ddg, tol, rate, row_kind, row_slider, forced, event_row, zero_rows):
    """Hong & Liu: the most violated row, normalised by its band (first of equals; -1: none), and
    the rows within their bands. The event's row and the rows that vanish with it are taken as
    zero first, where they are within :data:`EVENT_ROW_SLACK` bands of it (``g`` is changed)."""
    nr = g.size
    if event_row >= 0 and 0.0 < g[event_row] <= EVENT_ROW_SLACK * tol[event_row]:
        g[event_row] = 0.0
    for q in zero_rows:
        if abs(g[q]) <= EVENT_ROW_SLACK * tol[q]:
            g[q] = 0.0
    atzero = np.zeros(nr, np.bool_)
    best = math.inf
    j = -1
    for q in range(nr):
        gr = g[q]
        dgr = dg[q]
        tr = tol[q]
        tr_ = max(tr, 1e-300)
        if abs(gr) <= tr:
            atzero[q] = True
            dtol = 10.0 * tr_ * rate
            if dgr < -dtol:
                score = dgr / dtol
            elif (abs(dgr) <= dtol and ddg[q] < 0
                  and not (row_kind[q] == KIND_V and forced[row_slider[q]] and dgr > 0)):
                score = -1.0
            elif dgr < 0 and ddg[q] > 0 and gr - dgr * dgr / (2.0 * ddg[q]) < -tr:
                # turning up, but below the band first (its Taylor minimum): the dip rule
                score = -1.0
            else:
                continue
        else:
            if not gr < 0:
                continue
            score = gr / tr_
        if j < 0 or score < best:
            best = score
            j = q
    return j, atzero


#: :func:`_most_violated` for the marcher's NumPy settling loop (the same rule, one code)
most_violated = _most_violated


def unpack(buf: np.ndarray, rows: int, n: int) -> tuple:
    """``tol, f_const, kx0, c0, y0, b0`` (views) of the buffer returned by :func:`check`."""
    a = rows + n
    b = a + n
    c = b + rows
    m2 = (buf.size - c) // 2
    return buf[:rows], buf[rows:a], buf[a:b], buf[b:c], buf[c:c + m2], buf[c + m2:]
