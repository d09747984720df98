"""Time responses from the exact marcher: only the requested quantities, at the requested times.

Nothing is stepped: each closed-form piece of the motion is evaluated at the output times that
fall inside it. Energy terms are integrated piece by piece with Gauss-Legendre quadrature on
sub-pieces shorter than an eighth of the shortest period (smooth integrands: exact to rounding);
friction dissipation is exact (``slip_force * |slip|`` on every slipping piece).
"""
from __future__ import annotations

import cmath
import math
from collections.abc import Sequence

import numpy as np
import scipy.linalg
from numpy.typing import ArrayLike

from ...threads import owns_blas_threads
from ...errors import ConvergenceError, ParameterError, check_real, check_system
from ...system import FrictionSystem
from ...results import TimeResponse
from .events import EventLog, Marcher
from .propagator import Observables, _phi1

__all__ = ["simulate", "check_run", "interval_fourier", "RECORDABLE", "gauss_pieces", "gauss_nodes", "piece_peaks",
           "piece_fourier", "displacement_observables", "displacement_fourier", "varying_friction", "piece_slip"]

RECORDABLE = ("x", "v", "friction_force", "energy")
#: Newton iterations at most of :func:`piece_peaks` (each halves the bracket at worst)
_PEAK_ITERATIONS = 60
#: sample grids of :func:`piece_peaks` from this size on are screened on every ``_STRIDE``-th
#: sample first (:func:`_screened_samples`)
_SCREEN_SAMPLES = 64
_STRIDE = 16
_GL_X, _GL_W = np.polynomial.legendre.leggauss(12)


def gauss_pieces(itv, a: float, b: float, rate: float | None = None):
    """Gauss-Legendre nodes and weights on ``[a, b]`` (local times of ``itv``), sub-divided
    (8 pieces per period of ``rate``, default: the fastest rate of the configuration)."""
    if rate is None:
        rate = max(itv.omega, itv.config.max_rate)
    return gauss_nodes(a, b, rate)


def gauss_nodes(a: float, b: float, rate: float):
    """Gauss-Legendre nodes and weights on ``[a, b]``, sub-divided into 8 pieces per period of
    ``rate`` [rad/s]: exact to rounding for the exponentials times harmonics of a closed-form piece."""
    n = 1 if rate == 0 else max(1, math.ceil((b - a) * rate / (2 * math.pi) * 8))
    edges = np.linspace(a, b, n + 1)
    half = 0.5 * np.diff(edges)
    mid = 0.5 * (edges[1:] + edges[:-1])
    nodes = (mid[:, None] + half[:, None] * _GL_X[None, :]).ravel()
    weights = (half[:, None] * _GL_W[None, :]).ravel()
    return nodes, weights


def piece_peaks(itv, tau_end: float, amp: np.ndarray) -> np.ndarray:
    """Raise ``amp`` (n_dof,) to ``max |x_i|`` over the closed-form piece ``[0, tau_end]`` of
    ``itv``: its ends and every velocity reversal inside. ``v`` and ``a`` are sampled at 16 points
    per period of the active rate (as the event search samples its functions): a sign change of
    ``v`` brackets a reversal; a sign change of ``a`` with ``|v|`` falling brackets an extremum of
    ``v``, which holds two reversals if ``v`` changes sign there (a long piece's samples are taken
    only where a DOF's velocity can vanish, :func:`_screened_samples`). All roots are located
    together by safeguarded Newton iterations on the exact ``v`` and ``a`` of their DOFs only
    (:class:`_PieceRows`), until ``x`` there is the peak to rounding (:func:`_roots`). Returns
    ``x`` at the two ends, (n_dof, 2)."""
    x_end, _ = itv.state(np.array([0.0, tau_end]))
    np.maximum(amp, np.max(np.abs(x_end), axis=1), out=amp)
    if itv.config.m == 0:
        return x_end
    taus = _sample_times(itv, tau_end)
    vs, acc, v_scale, a_scale = _samples(itv, taus)
    rows, ks = np.nonzero(np.sign(vs[:, :-1]) * np.sign(vs[:, 1:]) < 0)
    lo, hi = taus[ks], taus[ks + 1]
    f_lo, f_hi = vs[rows, ks], vs[rows, ks + 1]
    # extrema of v between samples of one sign, |v| falling into them: two reversals if v changes
    # sign at the extremum
    drows, dks = np.nonzero((np.sign(acc[:, :-1]) * np.sign(acc[:, 1:]) < 0)
                            & (np.sign(vs[:, :-1]) == np.sign(vs[:, 1:])) & (vs[:, :-1] * acc[:, :-1] < 0))
    if drows.size:
        ext = _PieceRows(itv, drows)
        tm = _roots(ext, (taus[dks], taus[dks + 1]), (acc[drows, dks], acc[drows, dks + 1]), 1, tau_end,
                    a_scale[drows], v_scale[drows])
        vm = ext.velocity(tm, 0)[0]
        two = np.sign(vm) != np.sign(vs[drows, dks])
        rows = np.concatenate([rows, drows[two], drows[two]])
        lo = np.concatenate([lo, taus[dks][two], tm[two]])
        hi = np.concatenate([hi, tm[two], taus[dks + 1][two]])
        f_lo = np.concatenate([f_lo, vs[drows, dks][two], vm[two]])
        f_hi = np.concatenate([f_hi, vm[two], vs[drows, dks + 1][two]])
    if rows.size == 0:
        return x_end
    rev = _PieceRows(itv, rows)
    t = _roots(rev, (lo, hi), (f_lo, f_hi), 0, tau_end, v_scale[rows], amp[rows])
    np.maximum.at(amp, rows, np.abs(rev.displacement(t)))
    return x_end


def _samples(itv, taus: np.ndarray):
    """``v`` and ``a`` (n_dof, k) at the sample times ``taus`` of :func:`piece_peaks` and their
    scales (n_dof,): a long uniform grid of a plain modal piece whose forcing is slow is screened
    first (:func:`_screened_samples`)."""
    h = taus[1] - taus[0]
    cut = 2 * math.pi / (16 * _STRIDE * h) if h > 0 else 0.0
    uniform = h > 0 and abs(taus[-1] - taus[-2] - h) <= 1e-9 * h  # not cut at the decay time
    if taus.size < _SCREEN_SAMPLES or not uniform or itv.omega > cut or not itv.modal_search() or itv._near:
        vs, acc = itv.velocity(taus, order=1)
        return vs, acc, np.max(np.abs(vs), axis=1), np.max(np.abs(acc), axis=1)
    return _screened_samples(itv, taus, cut)


def _screened_samples(itv, taus: np.ndarray, cut: float):
    """:func:`_samples` of a long piece, NaN where no DOF's velocity can vanish (no bracket there).
    The modes no faster than ``cut`` and the constant and harmonic terms, ``v_s``, are sampled on
    every ``_STRIDE``-th sample (16 per period of ``cut``, as the whole motion is sampled on every
    one); the other modes' velocity is at most ``B = sum |P_ij a_j| max(1, e^{Re lam_j tau})`` over
    the piece (:meth:`.Interval.bounds`). Between two such samples where ``v_s`` and its
    acceleration keep their signs (``v_s`` monotone) and ``|v_s|`` exceeds ``B`` at both, ``v`` does
    not vanish: only the other intervals are sampled as before. The chain(200, 40)'s orbit has
    five pieces of 172 to 1437 samples (200 modes live: 16 per period of the fastest), of which
    about 1 % of the DOFs' intervals are sampled so."""
    cfg = itv.config
    n = itv.system.n_dof
    motion = _PieceRows(itv, np.arange(n))
    slow = np.abs(cfg.lam) <= cut
    grow = np.exp(np.maximum(cfg.lam.real[~slow], 0.0) * taus[-1])
    bound_v, bound_a = (np.abs(motion._modal(q)[:, ~slow]) @ grow for q in (0, 1))
    coarse = np.unique(np.append(np.arange(0, taus.size, _STRIDE), taus.size - 1))
    v, a = motion.grid(taus[coarse], modes=slow)
    # rounding of the sums of these terms
    slack = 1e-12 * (np.sum(np.abs(motion._modal(0)[:, slow]), axis=1) + sum(np.abs(k[:, 0]) for k in motion._k)
                     + bound_v)
    clear = ((np.sign(v[:, :-1]) * np.sign(v[:, 1:]) > 0) & (np.sign(a[:, :-1]) * np.sign(a[:, 1:]) > 0)
             & (np.minimum(np.abs(v[:, :-1]), np.abs(v[:, 1:])) > (bound_v + slack)[:, None]))
    vs = np.full((n, taus.size), np.nan)
    acc = np.full((n, taus.size), np.nan)
    for c in np.flatnonzero(~np.all(clear, axis=0)):
        rows = np.flatnonzero(~clear[:, c])
        span = slice(coarse[c], coarse[c + 1] + 1)
        vs[rows, span], acc[rows, span] = motion.grid(taus[span], rows)
    # the scales of the samples for the root finder's rounding floor
    v_scale = np.fmax(np.max(np.abs(v), axis=1) + bound_v, np.max(np.nan_to_num(np.abs(vs)), axis=1))
    a_scale = np.fmax(np.max(np.abs(a), axis=1) + bound_a, np.max(np.nan_to_num(np.abs(acc)), axis=1))
    return vs, acc, v_scale, a_scale


def _sample_times(itv, tau_end: float) -> np.ndarray:
    """Sample times of :func:`piece_peaks` on ``[0, tau_end]``: 16 per period of the active rate
    until the free modes have decayed below rounding (:meth:`.Interval.decay_time`), 16 per
    excitation period after (half a period of quasi-static forcing at 1e-9 of the structure's
    frequency asked for 1e11 samples)."""
    rate = itv.active_rate()
    omega = itv.omega
    t_d = itv.decay_time() if rate > omega > 0 else math.inf
    if not t_d < tau_end:
        return np.linspace(0.0, tau_end, max(2, math.ceil(tau_end * rate / (2 * math.pi) * 16) + 1))
    fast = np.linspace(0.0, t_d, max(2, math.ceil(t_d * rate / (2 * math.pi) * 16) + 1))
    slow = np.linspace(t_d, tau_end, max(2, math.ceil((tau_end - t_d) * omega / (2 * math.pi) * 16) + 1))
    return np.concatenate([fast, slow[1:]])


class _PieceRows:
    """The motion of DOFs ``rows`` of the piece ``itv``, for :func:`piece_peaks`: each row at its
    own local time (the roots: ``m`` terms each, not the whole structure's motion at every time
    asked, ``n_dof x m`` per time), or some rows and modes on a grid of times (the samples of a
    long piece, :func:`_screened_samples`). On a plain modal piece (no resonant terms),
    ``v = Re(P eta)`` with ``eta = a e^{lam t} + b0 + b+ e^{iwt} + b- e^{-iwt}`` is differentiated
    term by term; elsewhere the rows are read from :meth:`.Interval.velocity` and
    :meth:`.Interval.state`."""

    def __init__(self, itv, rows: np.ndarray) -> None:
        self.itv = itv
        self.rows = rows
        cfg = itv.config
        self.fast = itv.modal_search() and not itv._near
        if self.fast:
            self.lam = cfg.lam
            pv = _modal_rows(cfg, rows, 1)
            self._pa = pv * itv._a
            b0, bp, bm = itv._b
            # the constant and harmonic terms, (rows, 1)
            self._k = [c[:, None] for c in ((pv @ b0).real, pv @ bp, pv @ bm)]
            self._pq = {}

    def _modal(self, q: int) -> np.ndarray:
        """``P a lam^q`` (rows, modes): the coefficients of ``e^{lam t}`` in ``d^q v / dt^q``."""
        pq = self._pq.get(q)
        if pq is None:
            pq = self._pq[q] = self._pa * self.lam ** q
        return pq

    def _forced(self, eip: np.ndarray, q: int, rows=slice(None)) -> np.ndarray:
        """``d^q / dt^q`` of the constant and harmonic terms of the rows ``rows`` (of :attr:`rows`)
        at ``e^{iwt}`` (rows, k)."""
        k0, kp, km = (k[rows] for k in self._k)
        iw = 1j * self.itv.omega
        out = (kp * iw ** q * eip + km * (-iw) ** q * eip.conj()).real
        return out + k0 if q == 0 else out

    def velocity(self, t: np.ndarray, order: int):
        """The ``order``-th and next time derivatives of ``v`` of each row at its time ``t[i]``."""
        rows = self.rows
        if not self.fast:
            vals = self.itv.velocity(t, order + 1)
            idx = np.arange(rows.size)
            return vals[order][rows, idx], vals[order + 1][rows, idx]
        e = np.exp(self.lam[None, :] * t[:, None])
        eip = np.exp(1j * self.itv.omega * t)[:, None]
        return tuple(np.einsum("km,km->k", self._modal(q), e).real + self._forced(eip, q)[:, 0]
                     for q in (order, order + 1))

    def grid(self, taus: np.ndarray, rows=slice(None), modes=slice(None)):
        """``v`` and ``a`` (rows, k) of the rows ``rows`` (of :attr:`rows`; default all) at the
        times ``taus``: the modes ``modes`` (default all) and the constant and harmonic terms."""
        e = np.exp(self.lam[modes][:, None] * taus[None, :])
        eip = np.exp(1j * self.itv.omega * taus)[None, :]
        return tuple((self._modal(q)[rows][:, modes] @ e).real + self._forced(eip, q, rows) for q in (0, 1))

    def displacement(self, t: np.ndarray) -> np.ndarray:
        """``x`` of each row at its time ``t[i]``."""
        itv, rows = self.itv, self.rows
        if not self.fast:
            return itv.state(t)[0][rows, np.arange(rows.size)]
        px = _modal_rows(itv.config, rows, 0)
        b0, bp, bm = itv._b
        e = np.exp(self.lam[None, :] * t[:, None])
        eip = np.exp(1j * itv.omega * t)[:, None]
        eta = e * itv._a + b0 + bp * eip + bm * eip.conj()
        return itv.x0[rows] + np.einsum("km,km->k", px, eta).real


def _modal_rows(cfg, rows: np.ndarray, part: int) -> np.ndarray:
    """Rows ``rows`` of the displacements' (``part`` 0) or velocities' (1) modal coefficients
    ``N V``, (rows.size, modes)."""
    v = cfg.V[part * cfg.m:(part + 1) * cfg.m]
    return v[rows] if cfg.rigid_stuck.size == 0 else cfg.N[rows] @ v


def _roots(motion: _PieceRows, bracket, ends, order: int, tau_end: float, scale, prim) -> np.ndarray:
    """Roots of ``v`` (``order`` 0) or ``a`` (1) of the rows of ``motion`` in ``bracket = (lo, hi)``
    (one sign change each between ``ends``, the values there: the samples'): Newton steps on the
    exact function ``f`` and its derivative ``f'`` from the secant's root, bisection where a step
    would leave the bracket. A root is done when

    - its primitive (``x`` for ``v``, ``v`` for ``a``: what the caller wants there) is its value
      at the root to 1e-16 of ``prim``, the primitive's scale: near a simple root ``f`` is linear
      and the primitive is off by ``f^2 / 2 f'`` at the current step, by far less at the next,
      which is kept if it stays in the bracket. ``f`` near its root is the rounding of its terms,
      and further steps bisect that noise down to rounding of ``t`` (the 91 calls on the orbit of
      ``chain(200, 40)`` took 1172 evaluations of ``f`` so, with ``f`` evaluated again at the
      bracket's ends; 130 now);
    - or the step is at rounding of ``t``;
    - or ``|f|`` is below 1e-15 of its ``scale`` (a near-double root, where the primitive no
      longer changes: its error is ~ ``|f|`` times the distance to the root)."""
    lo, hi = bracket
    f_lo, f_hi = ends
    # secant start, inside the bracket also where f at an end is rounding of zero (an extremum of
    # v at rounding of zero found at a sample leaves an empty bracket)
    with np.errstate(divide="ignore", invalid="ignore"):
        frac = f_lo / (f_lo - f_hi)
    t = np.clip(lo + (hi - lo) * np.where(np.isfinite(frac), frac, 0.5), lo, hi)
    sign_lo = np.sign(f_lo)
    done = np.zeros(t.size, dtype=bool)
    for _ in range(_PEAK_ITERATIONS):
        f, df = motion.velocity(t, order)
        left = np.sign(f) == sign_lo
        lo = np.where(left, t, lo)
        hi = np.where(left, hi, t)
        with np.errstate(divide="ignore", invalid="ignore"):
            t_new = t - f / df
        inside = (t_new > lo) & (t_new < hi)
        t_new = np.where(inside, t_new, 0.5 * (lo + hi))
        # a root whose |f| is at its floor stays where it is: the next step, below rounding of t,
        # may fail the bracket test and bisect away from it
        small = np.abs(f) <= 1e-15 * scale
        settled = f * f <= 1e-16 * prim * np.abs(df)  # stays where the Newton step leaves the bracket
        step = np.abs(t_new - t) <= 4 * np.finfo(float).eps * np.abs(t) + 1e-16 * tau_end
        t = np.where(done | small | (f == 0) | (settled & ~inside), t, t_new)
        done |= step | small | settled
        if np.all(done):
            break
    return t


def _resonant_integral(a: complex, b: complex, big_t: float) -> complex:
    """``int_0^T E(a, b, t) dt`` of a resonant term (:func:`.propagator._E`), ``E(lam, mu, t) e^{z t}
    = E(lam + z, mu + z, t)``: the integral of ``e^{a (t - s) + b s}`` over the simplex ``0 <= s <= t
    <= T``, the corner entry of the exponential of the bidiagonal matrix with diagonal ``(0, a, b)``
    times ``T`` (Van Loan 1978, "Computing integrals involving the matrix exponential"); no
    cancellation at ``a = b``, where the divided differences ``(I(b) - I(a))/(b - a)`` lose
    ``eps/|b - a| T`` of it."""
    m = np.array([[0.0, 1.0, 0.0], [0.0, a, 1.0], [0.0, 0.0, b]], dtype=complex) * big_t
    return complex(scipy.linalg.expm(m)[0, 2])


def interval_fourier(itv, red, nu: float, tau_end: float, modes=None):
    """``int Q(t) e^{i nu t} dt`` over the piece ``[0, tau_end]`` of ``itv`` (absolute time
    ``t = t0 + tau``) of the observables ``red`` (:meth:`Interval.reduce`), (n_obs,) complex, in
    closed form: each term of the modal solution is an exponential, ``int_0^T e^{mu tau} d tau =
    T phi1(mu T)``. None where the closed form is not available (defective or near-resonant
    configuration). ``modes``: ``Cy V`` where the caller has it (the displacements' is cached on
    the configuration, :meth:`~.propagator.ConfigData.displacement_modes`)."""
    cfg = itv.config
    if not itv._ready:
        itv._prepare()
    if cfg.m and not cfg.modal:
        return None
    cy, c0, cc, cs = red
    w = itv.omega
    t0 = itv.t0
    big_t = tau_end

    def ints(mu):  # int_0^T e^{mu tau} d tau for an array of mu
        return big_t * _phi1(np.asarray(mu, dtype=complex) * big_t)

    e0 = cmath.exp(1j * nu * t0)
    out = c0 * (e0 * ints([1j * nu])[0])
    if np.any(cc) or np.any(cs):
        ep = cmath.exp(1j * (nu + w) * t0) * ints([1j * (nu + w)])[0]
        em = cmath.exp(1j * (nu - w) * t0) * ints([1j * (nu - w)])[0]
        out = out + cc * (0.5 * (ep + em)) + cs * ((ep - em) / 2j)
    if cfg.m:
        p = cy @ cfg.V if modes is None else modes
        b0, bp, bm = itv._b
        lam = cfg.lam

        nidx, nmu, nc = itv.near

        def modal(n_):  # int_0^T eta(tau) e^{i n_ tau} d tau, per mode
            z = 1j * n_
            out = (itv._a * ints(lam + z) + b0 * ints([z])[0] + bp * ints([z + 1j * w])[0]
                   + bm * ints([z - 1j * w])[0])
            for i, mu, c in zip(nidx.tolist(), nmu.tolist(), nc.tolist()):
                out[i] += c * _resonant_integral(lam[i] + z, mu + z, big_t)
            return out
        plus = e0 * (p @ modal(nu))
        minus = np.conj(np.conj(e0) * (p @ modal(-nu)))
        out = out + 0.5 * (plus + minus)
    return out


def piece_fourier(itv, tau_end: float, omega: float, red, modes=None):
    """``int Q(t) cos(omega t) dt`` and ``int Q(t) sin(omega t) dt`` over the piece ``[0, tau_end]``
    of ``itv`` for the observables ``red`` (:meth:`Interval.reduce`): in closed form
    (:func:`interval_fourier`), or by Gauss-Legendre per piece at the active rate where the
    configuration has no plain modal form (exact to rounding for its exponentials times harmonics).
    ``modes``: ``Cy V`` if the caller has it (:func:`interval_fourier`)."""
    exact = interval_fourier(itv, red, omega, tau_end, modes)
    if exact is not None:
        return exact.real, exact.imag
    nodes, wts = gauss_pieces(itv, 0.0, tau_end, itv.active_rate())
    yq = itv.evaluate(red, nodes)[0]
    ph = omega * (itv.t0 + nodes)
    return yq @ (wts * np.cos(ph)), yq @ (wts * np.sin(ph))


def displacement_observables(n: int) -> Observables:
    """The displacements ``x`` (n rows) as :class:`Observables` (for :func:`piece_fourier`)."""
    z = np.zeros((n, n))
    return Observables(np.eye(n), z, z, np.zeros(n))


def displacement_fourier(itv, tau_end: float, omega: float):
    """:func:`piece_fourier` of the displacements ``x`` (every DOF): their reduced form is ``N``
    and ``x0``, their modal one cached on the configuration, so that a piece costs no product
    with the ``n x n`` identity of :func:`displacement_observables` (``n^2 m`` each) nor with the
    eigenvectors (``n m^2``)."""
    cfg = itv.config
    n = itv.system.n_dof
    cy = np.zeros((n, 2 * cfg.m))
    cy[:, :cfg.m] = cfg.N
    zero = np.zeros(n)
    red = (cy, itv.x0.copy(), zero, zero)
    return piece_fourier(itv, tau_end, omega, red, cfg.displacement_modes() if cfg.modal and cfg.m else None)


def check_run(omega: float, t0, t_end, t_eval, record):
    """Checked ``(t0, t_end, t_eval, record)`` of a time response; ``t_eval`` defaults to 32 points
    per period of ``omega`` [rad/s] (1000 intervals without excitation)."""
    t0 = check_real("t0", t0)
    t_end = check_real("t_end", t_end)
    if t_end <= t0:
        raise ParameterError(f"t_end must be > t0 = {t0}, got {t_end}")
    record = _check_record(record)
    if t_eval is None:
        period = 2 * math.pi / omega if omega > 0 else (t_end - t0) / 1000
        n = max(2, math.ceil(32 * (t_end - t0) / period) + 1)
        t_eval = np.linspace(t0, t_end, n)
    t_eval = np.asarray(t_eval, dtype=float).reshape(-1)
    if (t_eval.size == 0 or not np.all(np.isfinite(t_eval)) or np.any(np.diff(t_eval) < 0)
            or t_eval[0] < t0 or t_eval[-1] > t_end):
        raise ParameterError(f"t_eval must be finite, ascending and within [t0, t_end] = [{t0}, {t_end}]")
    return t0, t_end, t_eval, record


def _check_record(record):
    if isinstance(record, str):
        record = (record,)
    record = tuple(record)
    for r in record:
        if r not in RECORDABLE:
            raise ParameterError(f"record items must be among {RECORDABLE}, got {r!r}")
    return record


def varying_friction(system, itv, wts, xq, vq) -> float:
    """Energy [J] dissipated on the piece ``itv`` by its slipping sliders on contacts (normal-load
    variation): ``int mu N(x) |w'| dt`` from the state ``xq, vq`` at Gauss nodes with weights
    ``wts`` (:func:`gauss_pieces`; the integrand is smooth on a piece: exact to rounding), with
    ``|w'| = (sig d - g/k) . v``."""
    sl, rate_rows = _varying_slip(system, itv)
    if not sl.any():
        return 0.0
    limit = system.slip_force[sl][:, None] + system.slip_gradient[sl] @ xq
    return float(np.sum(wts * np.sum(limit * (rate_rows @ vq), axis=0)))


def _varying_slip(system, itv):
    """The piece's slipping sliders on contacts (a mask) and the rows of their slip rate,
    ``|w'| = (sig d - g/k) . v``."""
    sl = system.varying & (itv.status != 0) & (itv.status != 2)
    sig = itv.status[sl].astype(float)
    rows = sig[:, None] * system.slider_direction[sl] - system.slip_gradient[sl] / system.slider_stiffness[sl][:, None]
    return sl, rows


def piece_slip(system, itv, tau_end: float, dx: np.ndarray) -> tuple[np.ndarray, float]:
    """Slip ``|dw|`` [m] of each slider over the piece ``[0, tau_end]`` of ``itv`` (zero where it
    sticks or its contact is open; ``w`` is monotonic on a slipping piece), from the piece's
    displacement change ``dx``, and the friction energy [J] dissipated on it: ``slip_force |dw|``,
    or ``int mu N |w'|`` for sliders on contacts (:func:`varying_friction`)."""
    ds = np.zeros(system.n_sliders)
    slip = (itv.status != 0) & (itv.status != 2)
    if not slip.any():
        return ds, 0.0
    ds[slip] = np.abs(itv.pattern.w_dir[slip] @ dx)
    const = slip & ~system.varying
    energy = float(system.slip_force[const] @ ds[const])
    if np.any(slip & system.varying):
        closed = modal_varying_friction(system, itv, 0.0, tau_end)
        if closed is None:
            nodes, wts = gauss_pieces(itv, 0.0, tau_end)
            xq, vq = itv.state(nodes)
            closed = varying_friction(system, itv, wts, xq, vq)
        energy += closed
    return ds, energy


def modal_varying_friction(system, itv, a: float, b: float) -> float | None:
    """:func:`varying_friction` on ``[a, b]`` (local times of ``itv``) in closed form, or None where
    the piece is not a plain modal one (non-classical damping, or a mode near resonance with the
    excitation: then the Gauss rule).

    On a modal piece the modal coordinates are sums of exponentials, ``eta(tau) = e^{lam tau} a +
    b0 + b+ e^{i w tau} + b- e^{-i w tau}``, so each slider's limit ``mu N(x)`` and slip rate
    ``|w'|`` are ``Re(sum_j p_j e^{s_j tau})`` and ``Re(sum_j q_j e^{s_j tau})`` over the same
    exponents ``s = (lam, 0, i w, -i w)``, and ``int_a^b Re(P) Re(Q) = Re(p^T (E q + E' conj(q))) / 2``
    with ``E_jl = int_a^b e^{(s_j + s_l) tau}`` and ``E'_jl = int_a^b e^{(s_j + conj(s_l)) tau}``
    (``e^{z a} (b - a) phi1(z (b - a))``, as :func:`interval_fourier`'s). The Gauss rule needs 8
    sub-intervals per period of the fastest mode: a stiff contact's, hundreds of times the
    excitation's, made this integral most of a patch root's steady state (58 of 59 s with 8 nodes
    per flank)."""
    sl, rate_rows = _varying_slip(system, itv)
    if not sl.any():
        return 0.0
    cfg = itv.config
    if not (cfg.modal and cfg.m):
        return None
    if not itv._ready:
        itv._prepare()
    if itv._near:
        return None
    m = cfg.m
    grad = system.slip_gradient[sl]
    a_rows = grad @ (cfg.N @ cfg.V[:m])  # x = x0 + Re(N V[:m] eta): limit = const + Re(a_rows eta)
    b_rows = rate_rows @ (cfg.N @ cfg.V[m:])  # v = Re(N V[m:] eta): |w'| = Re(b_rows eta)
    b0, bp, bm = itv._b
    const = system.slip_force[sl] + grad @ itv.x0
    p = np.hstack([a_rows * itv._a, (a_rows @ b0 + const)[:, None], (a_rows @ bp)[:, None], (a_rows @ bm)[:, None]])
    q = np.hstack([b_rows * itv._a, (b_rows @ b0)[:, None], (b_rows @ bp)[:, None], (b_rows @ bm)[:, None]])
    w = itv.omega
    s = np.concatenate([cfg.lam, [0.0, 1j * w, -1j * w]])
    e_same = _exp_integral(s[:, None] + s[None, :], a, b)
    e_conj = _exp_integral(s[:, None] + s.conj()[None, :], a, b)
    total = np.einsum("ij,jl,il->", p, e_same, q) + np.einsum("ij,jl,il->", p, e_conj, q.conj())
    return 0.5 * float(total.real)


def _exp_integral(z: np.ndarray, a: float, b: float) -> np.ndarray:
    """``int_a^b e^{z tau} d tau`` elementwise: ``e^{z a} (b - a) phi1(z (b - a))``."""
    span = (b - a) * _phi1(z * (b - a))
    return span if a == 0 else np.exp(z * a) * span


class _EnergyRecord:
    """The energy accounting of :func:`simulate` (``record`` with ``'energy'``): work of the
    applied forces and viscous dissipation integrated by Gauss rules on each piece, friction
    dissipation exact (slip force times slip), stored energy at the output times."""

    def __init__(self, system: FrictionSystem, out: dict, n_t: int) -> None:
        self.system = system
        self.out = out
        self.acc = {"work": 0.0, "fric": 0.0, "visc": 0.0}
        for key in ("work", "stored", "fric", "visc"):
            out[key] = np.empty(n_t)
        # unilateral contacts (normal-load variation): their springs' energy is
        # kn max(N0/kn - n.x, 0)^2 / 2 (less its static value), and their preloads N0 n, internal
        # forces, do no work; the structure's own springs are the rest of the stiffness
        self.k_linear = system.stiffness
        self.f_internal = None
        if system.n_contacts:
            nrm, kn = system.contact_normal, system.contact_stiffness
            self.k_linear = system.stiffness - (nrm.T * kn) @ nrm
            self.f_internal = nrm.T @ system.contact_preload

    def _stored(self, x, v, w):
        system = self.system
        e = 0.5 * np.einsum("ik,ij,jk->k", v, system.mass, v) + 0.5 * np.einsum(
            "ik,ij,jk->k", x, self.k_linear, x)
        jen = ~system.rigid
        if np.any(jen):
            s = system.slider_direction[jen] @ x
            e = e + 0.5 * system.slider_stiffness[jen] @ (s - w[jen]) ** 2
        if system.n_contacts:
            kn = system.contact_stiffness[:, None]
            e = e + np.sum((0.5 / kn) * (system.normal_loads(x) ** 2 - system.contact_preload[:, None] ** 2), axis=0)
        return e

    def _w_at(self, itv, x):
        """Slider positions (n_sliders, k) along the interval."""
        pat = itv.pattern
        w = np.repeat(itv.w[:, None], x.shape[1], axis=1)
        if pat.has_slip_j:
            w[pat.slip_j] = pat.slip_j_dir @ x - pat.slip_j_off[:, None]
        return w

    def piece(self, itv, k0: int, taus: np.ndarray, tau_end: float) -> None:
        """Accumulate over the piece ``[0, tau_end]`` of ``itv``; record at the output times
        ``taus`` (local), the first of which has index ``k0``."""
        system, out, acc = self.system, self.out, self.acc
        bounds = np.concatenate([[0.0], taus, [tau_end]])
        slip = (itv.status != 0) & ~system.varying  # constant slip limits: slip force x slip
        fsl = system.slip_force[slip]
        d_slip = system.slider_direction[slip]
        s_start = d_slip @ itv.x0
        for k in range(bounds.size - 1):
            a, b = bounds[k], bounds[k + 1]
            if b > a:
                nodes, wts = gauss_pieces(itv, a, b)
                xq, vq = itv.state(nodes)
                f = system.harmonic_force(itv.t0 + nodes) + itv.f_ext[:, None]
                if self.f_internal is not None:
                    f -= self.f_internal[:, None]
                acc["work"] += float(np.sum(wts * np.einsum("ik,ik->k", f, vq)))
                acc["visc"] += float(np.sum(wts * np.einsum("ik,ij,jk->k", vq, itv.config.damping, vq)))
                if system.n_contacts:
                    closed = modal_varying_friction(system, itv, a, b)
                    acc["fric"] += varying_friction(system, itv, wts, xq, vq) if closed is None else closed
            if k < taus.size:
                idx = k0 + k
                xb, vb = itv.state(b)
                if slip.any():
                    fric = float(fsl @ np.abs(d_slip @ xb[:, 0] - s_start))
                else:
                    fric = 0.0
                out["work"][idx] = acc["work"]
                out["visc"][idx] = acc["visc"]
                out["fric"][idx] = acc["fric"] + fric
                out["stored"][idx] = self._stored(xb, vb, self._w_at(itv, xb))[0]
        if slip.any():
            xe, _ = itv.state(tau_end)
            acc["fric"] += float(fsl @ np.abs(d_slip @ xe[:, 0] - s_start))


@owns_blas_threads
def simulate(system: FrictionSystem, t_end: float, x0: ArrayLike = 0.0, v0: ArrayLike = 0.0,
             w0: ArrayLike | None = None, t0: float = 0.0, t_eval: ArrayLike | None = None,
             record: str | Sequence[str] = ("x", "v", "friction_force"),
             marcher: Marcher | None = None) -> TimeResponse:
    """Exact time response of a :class:`~frictionjoint.system.FrictionSystem`.

    Parameters
    ----------
    system : FrictionSystem
    t_end : float
        End time [s], > ``t0``.
    x0, v0 : float or (n_dof,) array_like
        Initial displacement [m] and velocity [m/s].
    w0 : (n_sliders,) array_like, optional
        Initial slider positions [m]; unstressed Jenkins springs if omitted.
    t0 : float
        Start time [s].
    t_eval : (n_t,) array_like, optional
        Output times within ``[t0, t_end]``, ascending; default 32 per excitation period.
    record : sequence of str
        Quantities to store, among ``'x'``, ``'v'``, ``'friction_force'``, ``'energy'``.
    marcher : Marcher, optional
        Reuse a marcher (and its cache of decomposed configurations).

    Returns
    -------
    TimeResponse
    """
    check_system("system", system, FrictionSystem)
    t0, t_end, t_eval, record = check_run(system.omega, t0, t_end, t_eval, record)
    rigid = ()
    if marcher is None:  # a caller's marcher marches its own system as it is
        system, rigid = system.rigid_limit()
    m = marcher if marcher is not None else Marcher(system)
    log = EventLog()
    state = m.initial_state(x0, v0, w0, t0=t0, log=log)
    rec = _Recorder(system, m, t_eval, t_end, record)
    success, message = True, "ok"
    try:
        m.march(state, t_end, log, on_interval=rec.on_interval)
    except ConvergenceError as exc:
        # a failed march is a status of the result: the outputs after the failure are NaN
        success, message = False, f"the march failed at t = {state.t!r}: {exc}"
        rec.fail()
    return rec.result(log, state, success, message + rigid_note(rigid))


def rigid_note(rigid) -> str:
    """The words a result carries where Jenkins sliders were marched as rigid
    (:meth:`~frictionjoint.system.FrictionSystem.rigid_limit`); empty where none was."""
    if not len(rigid):
        return ""
    return (f"; Jenkins slider(s) {', '.join(str(int(i)) for i in rigid)} marched as rigid (stiffness >= 1e11 "
            "times the structure's along them: the rigid limit, within about 50 k/kt of the spring's motion)")


class _Recorder:
    """The outputs of :func:`simulate` at ``t_eval``, filled piece by piece (``on_interval``)."""

    def __init__(self, system, marcher, t_eval: np.ndarray, t_end: float, record):
        self.marcher = marcher
        self.t_eval = t_eval
        self.t_end = t_end
        n_t = t_eval.size
        ndof = system.n_dof
        n_el = len(system.elements)
        out = self.out = {}
        if "x" in record:
            out["x"] = np.empty((ndof, n_t))
        if "v" in record:
            out["v"] = np.empty((ndof, n_t))
        if "friction_force" in record:
            out["friction_force"] = np.empty((n_el, n_t))
            self.owner = np.zeros((n_el, system.n_sliders))
            self.owner[system.slider_owner, np.arange(system.n_sliders)] = 1.0
        self.energy = _EnergyRecord(system, out, n_t) if "energy" in record else None
        self.pos = 0
        self.t_close = 8.0 * np.finfo(float).eps * max(1.0, abs(t_end))

    def on_interval(self, itv, tau_end: float) -> None:
        """Store the outputs at the times of ``t_eval`` in the piece ``[itv.t0, itv.t0 + tau_end]``."""
        t_eval, out = self.t_eval, self.out
        t1 = itv.t0 + tau_end
        if self.t_end - t1 <= self.t_close:  # the last interval: t0 + tau may fall an ulp short of t_end
            t1 = max(t1, self.t_end)
        k0 = k1 = self.pos
        while k1 < t_eval.size and t_eval[k1] <= t1:
            k1 += 1
        if k1 == k0 and self.energy is None:
            return
        taus = t_eval[k0:k1] - itv.t0
        if k1 > k0:
            x, v = itv.state(taus)
            if "x" in out:
                out["x"][:, k0:k1] = x
            if "v" in out:
                out["v"][:, k0:k1] = v
            if "friction_force" in out:
                red = itv.reduce(self.marcher.force_observables(itv))
                out["friction_force"][:, k0:k1] = self.owner @ itv.evaluate(red, taus)[0]
        if self.energy is not None:
            self.energy.piece(itv, k0, taus, tau_end)
        self.pos = k1

    def fail(self) -> None:
        """The outputs after a failed march are NaN."""
        for key in self.out:
            self.out[key][..., self.pos:] = np.nan

    def result(self, log, state, success: bool, message: str) -> TimeResponse:
        out = self.out
        res = TimeResponse(t=self.t_eval, x=out.get("x"), v=out.get("v"), friction_force=out.get("friction_force"),
                           events=log, final_state=state, success=success, message=message)
        if self.energy is not None:
            res.work = out["work"]
            res.stored_energy = out["stored"]
            res.dissipated_friction = out["fric"]
            res.dissipated_viscous = out["visc"]
        return res
