"""Exact periodic hysteresis of friction sliders under a trigonometric-polynomial displacement:
the Fourier coefficients of the force and their derivatives with respect to the displacement's,
in closed form (the alternating frequency-time step of harmonic balance, without time sampling
error).

A displacement of ``H`` harmonics in the phase ``theta = omega t``,

    u(theta) = c[0] + sum_h (c[2h-1] cos(h theta) + c[2h] sin(h theta)),

drives a slider through one period. The force of a Jenkins slider (spring ``k`` in series with a
slider of strength ``F``) is, exactly, piecewise: ``k (u - w)`` while it sticks (``w`` constant),
``sig F`` while it slips. Its transitions are roots of ``u`` against a level (stick -> slip, where
the spring force reaches ``+-F``) and of ``u'`` (slip -> stick, where the motion reverses). They
are bracketed on a grid of :func:`n_samples` points per period (the grid only brackets: its size
is tied to ``H`` so that the roots of a polynomial of ``H`` harmonics are separated, and refined
to rounding by safeguarded Newton steps) and every Fourier integral over a piece is in closed
form. The Jenkins loop is the kernel of :mod:`.loop_kernels`. The
steady loop starts at the global maximum of ``u``, where the slider has just slipped forward
(Masing: the loop closes after one period); a slider that never slips keeps its reference
position ``w_ref`` (its static one), clipped into the band where it stays stuck.

Derivatives: the force is continuous at every transition, so the transition times drop out
(Leibniz); on a piece stuck since a reversal at ``theta_r`` the slider position is ``w = u(theta_r)
- sig F/k`` with ``u'(theta_r) = 0``, so ``dw/dc = phi(theta_r)``: ``dT/dc = k (phi(theta) -
phi(theta_r))`` there and 0 while it slips. A rigid Coulomb slider (``k = inf``) in continuous
sliding has ``T = F sgn(u')``: its coefficients change only through the reversal times,
``d theta_r/dc = -phi'(theta_r)/u''(theta_r)``, at which ``T`` jumps by ``2F``.

Deep slip (``F/k`` a small fraction of the motion): the stuck pieces, found from ``u`` against
``u(theta_r) -+ 2 F/k``, lose ``eps |u| / (F/k)`` of ``F`` to rounding, and below the rounding of ``u``
cannot be found at all; there the loop is Coulomb's plus the stuck pieces' excess expanded in
``sqrt(F/k)`` (:func:`.loop_kernels.deep_slip_kernel`), whose limit is the free slip. A flank whose
band is below the rounding of ``s`` on a contact closed all period slides, ``mu N sgn(s')``
(:func:`_sliding_flank`); between that and moderate slip the flank kernel loses ``eps |s| / (mu N /
k)`` of its force (no expansion yet), and a flank that lifts off is the kernel's at any friction
coefficient.

Coefficients are normalised as the displacement's: ``T[0]`` the mean, ``T[2h-1], T[2h]`` the
cosine and sine amplitudes.
"""
from __future__ import annotations

import math

import numpy as np

from . import loop_kernels
from .loop_kernels import DEEP_SLIP, UNRESOLVED_REACH  # noqa: F401 (the loops' thresholds, documented there)

__all__ = ["n_samples", "evaluate", "segment_integrals", "jenkins_loop", "jenkins_loops", "flank_loop",
           "coulomb_loop", "derivative_matrix"]


_EPS = float(np.finfo(float).eps)


def n_samples(n_harmonics: int) -> int:
    """Grid points per period that bracket the transitions of a loop driven by ``n_harmonics``
    harmonics: ``32 (H + 1)`` (16 per half-period of the highest harmonic, at least 64)."""
    return max(64, 32 * (int(n_harmonics) + 1))


_TABLES: dict = {}


def _trig_tables(n_harmonics: int):
    """``cos(h theta_j)``, ``sin(h theta_j)`` (H, N) on the bracketing grid ``theta_j = 2 pi j / N``
    (:func:`n_samples`), built once per ``H``."""
    t = _TABLES.get(n_harmonics)
    if t is None:
        theta = np.linspace(0.0, 2 * math.pi, n_samples(n_harmonics), endpoint=False)
        e = np.exp(1j * np.outer(np.arange(1, n_harmonics + 1), theta))
        t = _TABLES[n_harmonics] = (np.ascontiguousarray(e.real), np.ascontiguousarray(e.imag))
    return t


def _basis(theta, n_harmonics: int, derivative: int = 0) -> np.ndarray:
    """(2H+1, k) values of the basis ``1, cos h theta, sin h theta`` (or its derivative)."""
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    h = np.arange(1, n_harmonics + 1)[:, None]
    ht = h * theta[None, :]
    out = np.empty((2 * n_harmonics + 1, theta.size))
    c, s = np.cos(ht), np.sin(ht)
    hd = h.astype(float) ** derivative
    # d^n/dtheta^n of (cos, sin)(h theta) = h^n (cos, sin)(h theta + n pi/2)
    rot = derivative % 4
    if rot == 0:
        dc, ds = c, s
    elif rot == 1:
        dc, ds = -s, c
    elif rot == 2:
        dc, ds = -c, -s
    else:
        dc, ds = s, -c
    out[0] = 1.0 if derivative == 0 else 0.0
    out[1::2] = hd * dc
    out[2::2] = hd * ds
    return out


def evaluate(c: np.ndarray, theta, derivative: int = 0) -> np.ndarray:
    """``u`` (or its ``derivative``-th derivative in ``theta``) at the phases ``theta``."""
    h = (c.size - 1) // 2
    return c @ _basis(theta, h, derivative)


def segment_integrals(a: float, b: float, n_harmonics: int) -> np.ndarray:
    """``v[k] = int_a^b psi_k`` for the basis ``1, cos h, sin h``, in closed form."""
    h = np.arange(1, n_harmonics + 1)
    v = np.empty(2 * n_harmonics + 1)
    v[0] = b - a
    v[1::2] = (np.sin(h * b) - np.sin(h * a)) / h
    v[2::2] = -(np.cos(h * b) - np.cos(h * a)) / h
    return v


def _norm(n_harmonics: int) -> np.ndarray:
    """Fourier normalisation: ``1/(2 pi)`` for the mean, ``1/pi`` for the others."""
    w = np.full(2 * n_harmonics + 1, 1.0 / math.pi)
    w[0] = 0.5 / math.pi
    return w


def jenkins_loop(c: np.ndarray, stiffness: float, slip_force: float, w_ref: float = 0.0,
                 jacobian: bool = True):
    """Steady force loop of a Jenkins slider driven by ``u`` (coefficients ``c``).

    Where the slip reach ``F/k`` is below the rounding of ``u`` (:data:`UNRESOLVED_REACH`) and the
    slider slips, the loop is its limit ``F/k -> 0``, the rigid slider's ``F sgn(u')``
    (:func:`coulomb_loop`; deep slip, vanishing friction): exact to the rounding of ``k u``.

    Parameters
    ----------
    c : (2H+1,) ndarray
        Displacement coefficients [m].
    stiffness, slip_force : float
        ``k`` [N/m] and ``F`` [N], > 0.
    w_ref : float
        Slider position [m] kept when the slider never slips (clipped into the stuck band).
    jacobian : bool
        Also return ``dT/dc``.

    Returns
    -------
    coefficients : (2H+1,) ndarray
        Force coefficients [N].
    jac : (2H+1, 2H+1) ndarray or None
        ``dT/dc`` [N/m].
    w0 : float
        Slider position at ``theta = 0`` [m].
    slips : bool
        Whether the slider slips over the period.
    """
    c = np.ascontiguousarray(c, dtype=float)
    cos_t, sin_t = _trig_tables((c.size - 1) // 2)
    # one algorithm: the kernels of .loop_kernels (compiled where numba is; plain Python in an FMU's
    # bundled copy, which never balances harmonics), the path chosen there (deep slip, Coulomb's
    # limit, the exact loop)
    coef, jac, w0, slips = loop_kernels.jenkins_any(c, float(stiffness), float(slip_force), float(w_ref),
                                                    bool(jacobian), cos_t, sin_t)
    return coef, (jac if jacobian else None), float(w0), bool(slips)


def jenkins_loops(cs: np.ndarray, stiffness: np.ndarray, slip_force: np.ndarray, w_ref: np.ndarray,
                  jacobian: bool = True):
    """:func:`jenkins_loop` of ``m`` sliders at once (one compiled call).

    Parameters
    ----------
    cs : (m, 2H+1) ndarray
        Displacement coefficients [m], a row per slider.
    stiffness, slip_force, w_ref : (m,) ndarray
        ``k`` [N/m], ``F`` [N] (> 0) and the reference positions [m].
    jacobian : bool
        Also return ``dT/dc`` (else its rows are zeros).

    Returns
    -------
    coefficients : (m, 2H+1) ndarray
    jac : (m, 2H+1, 2H+1) ndarray
    w0 : (m,) ndarray
    slips : (m,) bool ndarray
    """
    cs = np.ascontiguousarray(cs, dtype=float)
    cos_t, sin_t = _trig_tables((cs.shape[1] - 1) // 2)
    return loop_kernels.jenkins_loops(cs, np.ascontiguousarray(stiffness, dtype=float),
                                      np.ascontiguousarray(slip_force, dtype=float),
                                      np.ascontiguousarray(w_ref, dtype=float), bool(jacobian), cos_t, sin_t)


_DERIVATIVES: dict = {}


def derivative_matrix(n_harmonics: int) -> np.ndarray:
    """``D`` with ``D c`` the coefficients of ``du/dtheta``: ``(a_h, b_h) -> h (b_h, -a_h)``; built
    once per ``H`` (read-only: every loop of every Newton iteration uses it)."""
    d = _DERIVATIVES.get(n_harmonics)
    if d is None:
        n = 2 * n_harmonics + 1
        d = np.zeros((n, n))
        for h in range(1, n_harmonics + 1):
            d[2 * h - 1, 2 * h] = h
            d[2 * h, 2 * h - 1] = -h
        d.flags.writeable = False
        d = _DERIVATIVES[n_harmonics] = d
    return d


def flank_loop(cs: np.ndarray, cp: np.ndarray, stiffness: float, friction_coefficient: float,
               normal_stiffness: float, normal_damping: float, preload: float, omega: float,
               w_ref: float = 0.0, jacobian: bool = True):
    """Steady loop of a Jenkins slider on a unilateral contact whose normal load varies (a dovetail
    flank with ``normal_load_variation``), driven by the tangential displacement ``s`` and the
    normal one ``p`` (coefficients ``cs``, ``cp``).

    The contact is closed while ``N = N0 - kn p > 0``; the slider's band is ``|k (s - w)| <= mu
    N``, i.e. ``w`` in ``[s - r, s + r]`` with ``r = (mu kn / k) max(gap - p, 0)``, ``gap = N0 / kn``:
    a sweeping process whose edges ``L = s - r``, ``U = s + r`` are trigonometric polynomials while
    the contact is closed (``s + a p - a gap``, ``s - a p + a gap``, ``a = mu kn / k``) and meet at
    ``s`` while it is open. The slider sticks (``w`` constant, ``T = k (s - w)``) until an edge
    reaches it, slips with the edge (``T = +-mu N``) until the edge turns (a root of ``L'`` or
    ``U'``) or the contact opens (a root of ``p - gap``); open, it carries nothing (``w = s``) and
    at the closure it sticks unless an edge outruns it.

    Memory: a lift-off erases it (the band has zero width), so a loop that opens is marched from a
    lift-off. Otherwise, if the slider slips at all it slips both ways, and then its position at
    the maximum of ``L`` is that maximum (it can rise only with ``L``): the loop is marched from
    there (Masing, for a varying band). If ``max L <= min U`` it never slips and keeps ``w_ref``
    clipped into ``[max L, min U]``.

    While the contact is open, its closed-state spring, dashpot and preload (part of the linear
    part) are taken out: ``Rn = N0 - kn p - cn omega dp/dtheta`` there, 0 while closed.

    Derivatives: ``T`` is continuous at every transition (stick-slip, reversal, lift-off, closure),
    so the transition times drop out; a stuck piece's ``w`` depends on the coefficients through the
    event that started it (a reversal at ``theta_r``: ``dw = phi(theta_r) (dcs +- a dcp)``; a
    closure at ``theta_c``, ``p = gap``: ``dw = phi(theta_c) (dcs - s'/p' dcp)``). ``Rn``'s
    dashpot part jumps at the opening and closing, which adds ``+-cn omega psi phi^T`` there.

    Returns
    -------
    T : (2H+1,) ndarray
        The slider's force coefficients [N].
    dT_dcs, dT_dcp : (2H+1, 2H+1) ndarray or None
    Rn : (2H+1,) ndarray
        The contact's correction (restoring sense: the force on the structure is ``-Rn`` along the
        normal) [N].
    dRn_dcp : (2H+1, 2H+1) ndarray or None
    dRn_domega : (2H+1,) ndarray
        ``dRn/domega`` at fixed coefficients (the dashpot's) [N s].
    open_matrix : (2H+1, 2H+1) ndarray
        Normalised ``int_open psi_i phi_j``: multiplication by the open indicator.
    w0 : float
        Slider position at ``theta = 0`` [m].
    slips : bool
        Whether it slips or lifts off over the period.
    """
    cs = np.ascontiguousarray(cs, dtype=float)
    cp = np.ascontiguousarray(cp, dtype=float)
    hh = (cs.size - 1) // 2
    cos_t, sin_t = _trig_tables(hh)
    kn, cn = float(normal_stiffness), float(normal_damping)
    if hh >= 1 and friction_coefficient * kn * (preload / kn + abs(cp[0]) + float(np.sum(np.abs(cp[1:])))) <= (
            UNRESOLVED_REACH * cs.size * _EPS * float(stiffness) * float(np.sum(np.abs(cs)))) \
            and cp[0] + float(np.sum(np.abs(cp[1:]))) < preload / kn:
        # the band's half-width mu N / k is below the rounding of s and the contact never opens: the
        # stuck pieces cannot be resolved (the kernel held the spring over the period), and the loop
        # is its limit, mu N(theta) sgn(s') (as jenkins_loop's, there exact to the rounding of k s)
        slip = _sliding_flank(cs, cp, float(friction_coefficient), kn, float(preload), jacobian)
        if slip is not None:
            return slip
    t, jts, jtp, rn, jb, m_open, w0, slips = loop_kernels.flank_loop_kernel(
        cs, cp, float(stiffness), float(friction_coefficient), kn, cn, float(preload), float(omega),
        float(w_ref), True, cos_t, sin_t)
    d = derivative_matrix(hh)
    jnn = jb - kn * m_open - cn * omega * (m_open @ d)
    rn_w = -cn * (m_open @ (d @ cp))
    if not jacobian:
        jts = jtp = jnn = None
    return t, jts, jtp, rn, jnn, rn_w, m_open, float(w0), bool(slips)


def _sliding_flank(cs: np.ndarray, cp: np.ndarray, mu: float, kn: float, n0: float, jacobian: bool):
    """:func:`flank_loop` in continuous sliding on a closed contact (``N = N0 - kn p > 0`` throughout):
    ``T = mu N sgn(s')``, in closed form between the reversals of ``s``, ``int N psi = N0 int psi - kn
    int p psi``; ``dT/dcs`` from the reversal times (``T`` jumps by ``2 mu N``), ``dT/dcp = -mu kn
    sgn(s') psi phi^T`` integrated; the contact carries no correction (closed). None without two
    reversals."""
    roots, _ = _reversals(cs)
    if len(roots) < 2:
        return None
    hh = (cs.size - 1) // 2
    n = cs.size
    nrm = _norm(hh)
    t = np.zeros(n)
    jts = np.zeros((n, n))
    jtp = np.zeros((n, n))
    v = np.empty(n)
    pm = np.empty((n, n))
    edges = list(roots) + [roots[0] + 2 * math.pi]
    for a, b in zip(edges[:-1], edges[1:]):
        sgn = math.copysign(1.0, loop_kernels._value(cs, 0.5 * (a + b), 1)[0])
        loop_kernels._integrals(a, b, hh, v, pm, True)
        t += sgn * mu * (n0 * v - kn * (pm @ cp))
        jtp -= sgn * mu * kn * pm
    for r in roots:
        dd = loop_kernels._value(cs, r, 2)[0]
        if dd != 0.0:
            force = mu * (n0 - kn * loop_kernels._value(cp, r, 0)[0])
            jts += -2 * force * math.copysign(1.0, dd) * np.outer(_basis(r, hh)[:, 0], -_basis(r, hh, 1)[:, 0] / dd)
    zero = np.zeros((n, n))
    w0 = float(evaluate(cs, 0.0)[0])
    return (nrm * t, nrm[:, None] * jts if jacobian else None, nrm[:, None] * jtp if jacobian else None,
            np.zeros(n), zero if jacobian else None, np.zeros(n), zero, w0, True)


def _reversals(c: np.ndarray):
    """``(roots, du)``: the sorted phases in ``[0, 2 pi]`` where ``u'`` changes sign (the reversals,
    refined as the Jenkins loop refines its transitions: :func:`.loop_kernels.reversal_roots`) and
    ``u'`` on the bracketing grid."""
    cos_t, sin_t = _trig_tables((c.size - 1) // 2)
    _, du = loop_kernels._grid_values(c, cos_t, sin_t)
    return loop_kernels.reversal_roots(c, du, 2 * math.pi / du.size), du


def coulomb_loop(c: np.ndarray, slip_force: float, jacobian: bool = True):
    """Force of a rigid Coulomb slider in continuous sliding, ``F sgn(u')``, driven by ``u``.

    Returns ``(coefficients, dT/dc or None)``; a motion with no reversal (``u'`` of one sign, or
    zero) has the constant force ``F sgn(u')`` and no derivative.
    """
    c = np.ascontiguousarray(c, dtype=float)
    return _coulomb(c, float(slip_force), jacobian, *_reversals(c))


def _coulomb(c: np.ndarray, f: float, jacobian: bool, roots: np.ndarray, du: np.ndarray):
    """:func:`coulomb_loop` from the reversals ``roots`` (:func:`_reversals`)."""
    coef, jac = loop_kernels.coulomb_kernel(c, f, bool(jacobian), roots, float(du[0]))
    return coef, (jac if jacobian else None)
