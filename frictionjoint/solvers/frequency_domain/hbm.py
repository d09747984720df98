"""Multi-harmonic balance of friction systems, with exact hysteresis and condensation to the joints.

The periodic response is sought as ``x(t) = Re(sum_{h=0..H} X_h e^{i h omega t})``. The joints act
on few coordinates, the distinct slider directions ``q = G x``; the linear part (structure, base
springs, the joints' linear springs and, for every Jenkins slider, its spring as if stuck) is solved
per harmonic in closed form, ``X_h = Z_h^-1 (F_h - G^T R_h)`` with ``Z_h = K - (h w)^2 M + i h w
C``, so the unknowns are the harmonics of ``q`` only (``n_q (2H + 1)`` reals, whatever the size of
the structure):

    r(q) = q - G Z^-1 F + G Z^-1 G^T R(q) = 0,

``R`` the joints' forces less their stuck springs. ``R(q)`` is the alternating frequency-time step
without time discretisation: each slider's force over the period from its own exact return map,
its Fourier coefficients and their derivatives in closed form (:mod:`.hysteresis`); the Jacobian
``I + G Z^-1 G^T dR/dq`` is analytic. Newton's method with a backtracking line search solves it.

Scope: Jenkins sliders (Jenkins, Iwan, flat dovetail flanks with the frozen normal load), flat
dovetail flanks with normal-load variation and lift-off (the slider's band follows its contact's
normal load; the contact's normal is a joint coordinate too, and while it is open its closed-state
spring, dashpot and preload are taken out: :func:`.hysteresis.flank_loop`), and rigid Coulomb
sliders in continuous sliding (``T = F sgn(q')``: stops are not represented); harmonic forces and
base motion, the joints' constant loads in the mean.
"""
from __future__ import annotations

import copy
import math
from typing import NamedTuple

import numpy as np
import scipy.linalg

from ...threads import owns_blas_threads
from ...errors import ParameterError, check_count, check_positive, check_system
from ...memory import computation_budget
from ...results.harmonic import HarmonicBalance
from ...system import FrictionSystem
from . import hysteresis, loop_kernels

__all__ = ["harmonic_balance", "Condensed", "exact_orbit", "lyapunov_stable", "truncation_error", "hill_exponents"]


class JointForces(NamedTuple):
    """The joints' forces on a balanced orbit (:meth:`Condensed.forces`)."""

    #: ``R``: per joint coordinate its real Fourier coefficients (index ``q (2H + 1) + j``) [N]
    r: np.ndarray
    #: ``dR/dz`` [N/m], or None
    jacobian: np.ndarray | None
    #: ``dR/domega`` at fixed ``z`` (the open contacts' dashpots) [N s]
    d_omega: np.ndarray
    #: the open contacts' dashpots as a matrix on the velocity coefficients (Hill's method), or None
    damping: np.ndarray | None
    #: the sliders' positions at ``t = 0`` [m]
    slider_positions: np.ndarray
    #: friction energy per period, ``sum oint T ds`` over the sliders that slip or lift off (exactly 0
    #: on a stuck orbit) [J]
    dissipated: float
    #: every slider sticks over the whole period and no contact opens (a linear orbit)
    stuck: bool


def _distinct_rows(a: np.ndarray):
    """``(rows, inverse)`` of ``np.unique(a, axis=0, return_inverse=True)``: the distinct rows of
    ``a`` in lexicographic order and each row's index among them, from a lexicographic sort of the
    rows (``np.unique`` sorts them as a structured array, some 2.8 ms for 40 joints of a 200-DOF
    chain against 0.25 ms)."""
    a = np.asarray(a)
    if a.shape[0] == 0:
        return a.copy(), np.zeros(0, dtype=np.intp)
    order = np.lexsort(a.T[::-1])  # the first column the primary key
    s = a[order]
    new = np.ones(len(s), dtype=bool)
    new[1:] = np.any(s[1:] != s[:-1], axis=1)
    inverse = np.empty(len(s), dtype=np.intp)
    inverse[order] = np.cumsum(new) - 1
    return s[new], inverse


def harmonics_bytes(n_harmonics: int, n_dof: int, n_q: int, all_dofs: bool = False) -> int:
    """Memory [bytes] a balance with ``n_harmonics`` needs at its peak, counted from its arrays:
    the loops' bracketing tables and a peak search's samples (``(H, 32 (H + 1))`` and ``(H + 1, 64 (H +
    1))`` with their complex temporaries, some 3,600 ``(H + 1)^2``: measured 1.2 GiB at H = 600 on a
    single DOF, this count 1.21 GiB), the linear part per harmonic (``48 (H + 1) n (n + n_q + 1)``), the
    condensed map, the joints' Jacobian and Newton's matrices on the ``n_q (2H + 1)`` joint unknowns
    (6 dense copies); with ``all_dofs`` (:func:`.nonlinear_mode.nonlinear_mode`, not condensed) ten
    dense matrices on the ``n (2H + 1)`` unknowns of every DOF besides."""
    h1 = n_harmonics + 1
    total = 3600 * h1 * h1 + 48 * h1 * n_dof * (n_dof + n_q + 1) + 48 * (n_q * (2 * n_harmonics + 1)) ** 2
    if all_dofs:
        total += 80 * (n_dof * (2 * n_harmonics + 1)) ** 2
    return int(total)


def check_harmonics(n_harmonics, system: FrictionSystem, caller: str, all_dofs: bool = False) -> int:
    """``n_harmonics`` as an int >= 1 whose balance of ``system`` fits the memory one computation may
    take (:func:`~frictionjoint.memory.computation_budget`, from :func:`harmonics_bytes`); refused before anything is allocated,
    with the largest that fits."""
    hh = check_count("n_harmonics", n_harmonics, 1)
    n_q = int(_distinct_rows(np.vstack([system.slider_direction, system.contact_normal]))[0].shape[0])
    budget = computation_budget()
    if harmonics_bytes(hh, system.n_dof, n_q, all_dofs) <= budget:
        return hh
    lo, hi = 0, hh  # the largest H that fits, by bisection (the need grows with H)
    while hi - lo > 1:
        mid = (lo + hi) // 2
        lo, hi = (mid, hi) if harmonics_bytes(mid, system.n_dof, n_q, all_dofs) <= budget else (lo, mid)
    need = harmonics_bytes(hh, system.n_dof, n_q, all_dofs)
    raise ParameterError(f"{caller}: n_harmonics must be in [1, {lo}] for this system ({system.n_dof} DOFs, {n_q} "
                         f"joint coordinates): H = {hh} needs about {need / 2 ** 30:.3g} GiB, more than the "
                         f"{budget / 2 ** 30:.3g} GiB one computation may take (a quarter of this machine's memory)")


def _loop_work(t: np.ndarray, c: np.ndarray, dmat: np.ndarray) -> float:
    """``oint T du`` over the period from the coefficients of ``T`` and ``u``: ``pi sum_h h (T_a,h
    c_b,h - T_b,h c_a,h)``."""
    return float(math.pi * (t[1:] @ (dmat @ c)[1:]))


class Condensed:

    """The linear part of a system condensed to its joint coordinates at one frequency.

    Parameters
    ----------
    system : FrictionSystem
        The system (its ``omega`` is the frequency).
    n_harmonics : int
        ``H``.
    """

    def __init__(self, system: FrictionSystem, n_harmonics: int):
        if system.external:
            raise ParameterError("harmonic_balance: held external forces (ExternalForce) are not periodic")
        if system.n_sliders == 0:
            raise ParameterError("harmonic_balance: the system has no joint sliders (a linear system)")
        self.system = system
        hh = self.n_harmonics = int(n_harmonics)
        w = self.omega = system.omega
        d = system.slider_direction
        ns = system.n_sliders
        rows, inverse = _distinct_rows(np.vstack([d, system.contact_normal]))
        self.G = rows  # (n_q, n): the distinct slider directions and contact normals
        inverse = np.asarray(inverse).reshape(-1)
        self.slider_q = inverse[:ns]
        self.contact_q = inverse[ns:]
        self.n_q = rows.shape[0]
        # a slider on a contact: its friction coefficient (it slips at mu N0 at x = 0)
        self.mu = np.zeros(ns)
        var = system.varying
        self.mu[var] = system.slip_force[var] / system.contact_preload[system.slider_contact[var]]
        jen = ~system.rigid
        k_lin = system.stiffness + (d[jen].T * system.slider_stiffness[jen]) @ d[jen]
        self.k_stuck = np.zeros(self.n_q)  # stuck springs per coordinate, in the linear part
        np.add.at(self.k_stuck, self.slider_q[jen], system.slider_stiffness[jen])
        # Jenkins sliders' reference positions (their static ones: x = 0 is the static state)
        self._jenkins = np.flatnonzero(~system.varying & ~system.rigid)  # plain Jenkins sliders
        self._jenkins_alone = np.unique(self.slider_q[self._jenkins]).size == self._jenkins.size
        self.w_ref = np.zeros(system.n_sliders)
        pre = system.slider_preload != 0
        self.w_ref[pre] = -system.slider_preload[pre] / system.slider_stiffness[pre]
        self.set_force_scale(1.0)
        n = system.n_dof
        self._lin = (k_lin, system.mass, system.damping)
        # every harmonic's Z_h = K - (h w)^2 M + i h w C solved at once (one batched LAPACK call)
        h = np.arange(hh + 1)
        zs = (k_lin[None] - ((h * w) ** 2)[:, None, None] * system.mass[None]
              + (1j * h * w)[:, None, None] * system.damping[None])
        f = np.zeros((hh + 1, n), complex)
        f[0] = system.constant_force
        if hh >= 1:
            f[1] = system.force_cos - 1j * system.force_sin
        rhs = np.concatenate([np.broadcast_to(rows.T, (hh + 1,) + rows.T.shape), f[:, :, None]], axis=2)
        try:
            sol = np.linalg.solve(zs, rhs.astype(complex))
        except np.linalg.LinAlgError:
            raise ParameterError("harmonic_balance: the linear part is singular at a harmonic (e.g. a mechanism "
                                 "without stuck springs, or a resonance of the stuck system without damping)") from None
        if not np.all(np.isfinite(sol)):
            raise ParameterError("harmonic_balance: the linear part is singular at a harmonic (e.g. a resonance of "
                                 "the stuck system without damping)")
        sol[0] = sol[0].real  # the mean is real
        self._z = zs
        self.zinv_gt = list(sol[:, :, :-1])
        self.zinv_f = list(sol[:, :, -1])
        ys = list(rows[None] @ sol[:, :, :-1])
        qs = list(rows[None] @ sol[:, :, -1:])
        qs = [q[:, 0] for q in qs]
        self._ys, self._qs = ys, qs
        # real form: unknown vector z, index (q, j) -> q (2H+1) + j, j = 0 (mean), 2h-1 (cos), 2h (sin)
        self.nc = nc = 2 * hh + 1
        self._qi = np.arange(self.n_q) * nc
        self.Y, self.q_linear = self._real_form(ys, qs)

    def truncated(self, n_harmonics: int) -> "Condensed":
        """The condensation with the first ``n_harmonics`` (<= ``H``) harmonics only, from this one's
        solves (each harmonic's ``Z_h`` is solved on its own: the same numbers as a condensation made
        with ``n_harmonics``); its arrays are shared with this one.

        Parameters
        ----------
        n_harmonics : int
            ``H' <= H``.

        Returns
        -------
        Condensed
        """
        hh = int(n_harmonics)
        if not 1 <= hh <= self.n_harmonics:
            raise ParameterError(f"n_harmonics must be in [1, {self.n_harmonics}], got {n_harmonics!r}")
        out = copy.copy(self)
        out.n_harmonics = hh
        out._z = self._z[:hh + 1]
        out.zinv_gt, out.zinv_f = self.zinv_gt[:hh + 1], self.zinv_f[:hh + 1]
        out._ys, out._qs = self._ys[:hh + 1], self._qs[:hh + 1]
        out.nc = 2 * hh + 1
        out._qi = np.arange(self.n_q) * out.nc
        out.Y, out.q_linear = out._real_form(out._ys, out._qs)
        return out

    def _real_form(self, ys, qs):
        """``(big, lin)`` of per-harmonic complex ``G Z^-1 G^T`` and ``G Z^-1 F``: the real
        coefficients' map, ``Q = a - i b`` per harmonic (``a = Re Q``, ``b = -Im Q``)."""
        hh, nc, nq = self.n_harmonics, self.nc, self.n_q
        big = np.zeros((nq, nc, nq, nc))
        lin = np.zeros((nq, nc))
        big[:, 0, :, 0] = ys[0].real
        lin[:, 0] = qs[0].real
        for h in range(1, hh + 1):
            ia, ib = 2 * h - 1, 2 * h
            yr, yi = ys[h].real, ys[h].imag
            big[:, ia, :, ia] = yr
            big[:, ia, :, ib] = yi
            big[:, ib, :, ia] = -yi
            big[:, ib, :, ib] = yr
            lin[:, ia] = qs[h].real
            lin[:, ib] = -qs[h].imag
        return big.reshape(nq * nc, nq * nc), lin.reshape(-1)

    def set_force_scale(self, scale: float) -> None:
        """Evaluate :meth:`forces` in units of ``scale`` [m]: the joint coordinates it is given, and
        the forces it returns, are the true ones divided by ``scale`` (the joints' laws are positively
        homogeneous: their slip forces, contact preloads and reference positions are divided by
        ``scale``, their stiffnesses kept). A power of 2 is exact; it keeps ``k u`` finite at
        amplitudes near the largest float (:func:`.nonlinear_mode.nonlinear_mode`)."""
        self.force_scale = float(scale)
        self._slip_force = self.system.slip_force / self.force_scale
        self._preload = self.system.contact_preload / self.force_scale
        self._w_ref = self.w_ref / self.force_scale

    def omega_derivative(self):
        """``(dY/domega, dq_linear/domega)`` from ``d Z^-1 = -Z^-1 Z' Z^-1``, ``Z_h' = -2 h^2 omega M + i h
        C`` (``G Z^-1`` from one batched solve with ``Z^T``: the reduced matrices of a blade are
        symmetric only to rounding)."""
        k_lin, m, c = self._lin
        w = self.omega
        hh = self.n_harmonics
        h = np.arange(hh + 1)
        dz = -2.0 * (h * h * w)[:, None, None] * m[None] + (1j * h)[:, None, None] * c[None]
        left = np.linalg.solve(np.swapaxes(self._z, 1, 2), np.broadcast_to(self.G.T, (hh + 1,) + self.G.T.shape)
                               .astype(complex))
        gz = np.swapaxes(left, 1, 2)  # G Z^-1, (H+1, n_q, n)
        a = np.array(self.zinv_gt)
        f = np.array(self.zinv_f)
        ys = list(-(gz @ dz @ a))
        qs = list(-(gz @ (dz @ f[:, :, None]))[:, :, 0])
        return self._real_form(ys, qs)

    def joint_vector(self, harmonics: np.ndarray) -> np.ndarray:
        """The unknowns ``z`` (joint coordinates' real coefficients) of DOF harmonics ``(H' + 1,
        n_dof)`` (complex, ``x = Re sum X_h e^{i h theta}``; harmonics beyond ``H`` dropped, missing
        ones zero)."""
        qh = np.asarray(harmonics, dtype=complex) @ self.G.T
        nc = self.nc
        z = np.zeros(self.n_q * nc)
        z[::nc] = qh[0].real
        for h in range(1, min(self.n_harmonics, qh.shape[0] - 1) + 1):
            z[2 * h - 1::nc] = qh[h].real
            z[2 * h::nc] = -qh[h].imag
        return z

    def forces(self, z: np.ndarray, jacobian: bool = True) -> JointForces:
        """The joints' forces less their stuck springs ``R(z)`` per coordinate and harmonic, with
        ``dR/dz``, ``dR/domega``, the open contacts' dashpot matrix, the sliders' positions at ``t =
        0`` and the friction energy per period (:class:`JointForces`)."""
        sysm = self.system
        k_rep = np.repeat(self.k_stuck, self.nc)
        r = -k_rep * z
        r_w = np.zeros_like(z)
        jac = None
        if jacobian:
            jac = np.zeros((z.size, z.size))
            jac[np.diag_indices(z.size)] = -k_rep
        w0 = np.zeros(sysm.n_sliders)
        slips = np.zeros(sysm.n_sliders, dtype=bool)
        works = np.zeros(sysm.n_sliders)
        self._jenkins_forces(z, r, jac, w0, slips, works)
        damp = self._other_forces(z, r, r_w, jac, w0, slips, works)
        # a slider that never slips (nor lifts off) is a spring over the period: it dissipates
        # nothing, while its oint k (u - w) du as a sum of products only cancels to rounding
        energy = float(sum(works[slips].tolist(), 0.0))
        return JointForces(r, jac, r_w, damp, w0, energy, not bool(np.any(slips)))

    def _jenkins_forces(self, z, r, jac, w0, slips, works) -> None:
        """:meth:`forces` of the plain Jenkins sliders, every loop in one compiled call
        (:func:`.hysteresis.jenkins_loops`), added into ``r`` and ``jac`` in the sliders' order."""
        jen = self._jenkins
        if jen.size == 0:
            return
        nq, nc = self.n_q, self.nc
        qj = self.slider_q[jen]
        c = z.reshape(nq, nc)[qj]
        coef, jacs, w0[jen], slips[jen] = hysteresis.jenkins_loops(c, self.system.slider_stiffness[jen],
                                                                   self._slip_force[jen], self._w_ref[jen],
                                                                   jac is not None)
        if self._jenkins_alone:  # one plain Jenkins slider per coordinate: plain indexing adds them
            r.reshape(nq, nc)[qj] += coef
            if jac is not None:
                jac.reshape(nq, nc, nq, nc)[qj, :, qj, :] += jacs
        else:  # sliders sharing a coordinate (an Iwan joint): added one after the other
            np.add.at(r.reshape(nq, nc), qj, coef)
            if jac is not None:
                np.add.at(jac.reshape(nq, nc, nq, nc), (qj, slice(None), qj, slice(None)), jacs)
        dc = c @ hysteresis.derivative_matrix(self.n_harmonics).T
        works[jen] = math.pi * np.einsum("ij,ij->i", coef[:, 1:], dc[:, 1:])  # _loop_work of each

    def _other_forces(self, z, r, r_w, jac, w0, slips, works):
        """:meth:`forces` of the flank and rigid sliders, one by one; returns the open contacts'
        dashpot matrix (None without one)."""
        sysm = self.system
        nc = self.nc
        jacobian = jac is not None
        damp = None
        dmat = hysteresis.derivative_matrix(self.n_harmonics)
        for i in np.flatnonzero(sysm.varying | sysm.rigid):
            q = self.slider_q[i]
            sl = slice(q * nc, (q + 1) * nc)
            c = z[sl]
            if sysm.varying[i]:
                ic = sysm.slider_contact[i]
                qn = self.contact_q[ic]
                sn = slice(qn * nc, (qn + 1) * nc)
                t, jts, jtp, rn, jnn, rn_w, m_open, w0[i], slips[i] = hysteresis.flank_loop(
                    c, z[sn], sysm.slider_stiffness[i], self.mu[i], sysm.contact_stiffness[ic],
                    sysm.contact_damping[ic], self._preload[ic], self.omega, self._w_ref[i], jacobian)
                r[sn] += rn
                r_w[sn] += rn_w
                if jacobian:
                    jac[sl, sl] += jts
                    jac[sl, sn] += jtp
                    jac[sn, sn] += jnn
                if sysm.contact_damping[ic] > 0:
                    damp = np.zeros((z.size, z.size)) if damp is None else damp
                    damp[sn, sn] -= sysm.contact_damping[ic] * m_open
            else:
                t, jt = hysteresis.coulomb_loop(c, self._slip_force[i], jacobian)
                w0[i] = float(hysteresis.evaluate(c, 0.0)[0])
                slips[i] = bool(np.any(c[1:]))  # a rigid slider in continuous sliding moves with u
                if jacobian:
                    jac[sl, sl] += jt
            r[sl] += t
            works[i] = _loop_work(t, c, dmat)
        return damp

    def harmonics(self, r: np.ndarray) -> np.ndarray:
        """All DOFs' complex harmonics ``(H + 1, n_dof)`` from the joint forces ``R``."""
        hh, nc = self.n_harmonics, self.nc
        rc = r.reshape(self.n_q, nc)
        out = np.empty((hh + 1, self.system.n_dof), complex)
        out[0] = self.zinv_f[0].real - self.zinv_gt[0].real @ rc[:, 0]
        for h in range(1, hh + 1):
            rh = rc[:, 2 * h - 1] - 1j * rc[:, 2 * h]
            out[h] = self.zinv_f[h] - self.zinv_gt[h] @ rh
        return out


def _peaks(harm: np.ndarray) -> np.ndarray:
    """Max ``|x|`` over the period of each DOF's trigonometric polynomial (harmonics ``(H + 1,
    n_dof)``): the largest of ``max(256, 64 (H + 1))`` samples, refined on ``x' = 0`` between its
    neighbours to rounding (compiled, all DOFs in one call: :func:`.loop_kernels.peak_magnitudes`)."""
    harm = np.asarray(harm)
    hh = harm.shape[0] - 1
    c = np.empty((harm.shape[1], 2 * hh + 1))  # real coefficients: x = c0 + sum a_h cos + b_h sin
    c[:, 0] = harm[0].real
    c[:, 1::2] = harm[1:].real.T
    c[:, 2::2] = -harm[1:].imag.T
    return loop_kernels.peak_magnitudes(c, max(256, 64 * (hh + 1)))


@owns_blas_threads
def harmonic_balance(system: FrictionSystem, omega: float | None = None, n_harmonics: int = 7, *,
                     guess: np.ndarray | None = None, tol: float = 1e-10, max_iter: int = 60,
                     check: bool = False, peaks: bool = True) -> HarmonicBalance:
    """Multi-harmonic balance of ``system`` at ``omega`` with ``n_harmonics`` harmonics (module
    docstring): exact hysteresis, analytic Jacobian, condensed to the joint coordinates.

    Parameters
    ----------
    system : FrictionSystem
        With harmonic excitation.
    omega : float, optional
        Angular frequency [rad/s], > 0; default the system's.
    n_harmonics : int
        ``H`` >= 1 (the mean is always included).
    guess : (H' + 1, n_dof) complex ndarray, optional
        Starting harmonics (e.g. a neighbouring frequency's; any ``H'``); default the balance with
        ``(H - 1) // 2`` harmonics, down to the one-harmonic balance started from the linear
        solution with every slider stuck.
    tol : float
        Newton's tolerance on the residual relative to the joint coordinates' size, in (0, 1).
    max_iter : int
        Newton iterations at most.
    check : bool
        Also find the exact time-domain steady state from the balanced orbit
        (:func:`~frictionjoint.solvers.marcher.steady.periodic_response`) and report the truncation error.
    peaks : bool
        Locate each DOF's peak over the reconstructed period (``amplitude``); false: ``amplitude``
        is NaN, for a caller that needs the harmonics only (the start of an exact search).

    Returns
    -------
    HarmonicBalance
    """
    check_system("system", system, FrictionSystem)
    hh = check_harmonics(n_harmonics, system, "harmonic_balance")
    if omega is not None:
        w = check_positive("omega", omega)
        if w != system.omega:
            system = FrictionSystem(system.structure, system.elements, omega=w, excitation=system.excitation)
    if system.omega <= 0:
        raise ParameterError("harmonic_balance: the system needs harmonic excitation (omega > 0)")
    if not (isinstance(tol, float) and 0 < tol < 1):
        raise ParameterError(f"tol must be a float in (0, 1), got {tol!r}")
    max_iter = check_count("max_iter", max_iter, 1)
    out = _balance(system, Condensed(system, hh), guess, tol, max_iter, peaks)
    if check:
        _check_exact(system, out)
    return out


def _balance(system: FrictionSystem, cond: Condensed, guess, tol: float, max_iter: int,
             peaks: bool) -> HarmonicBalance:
    """:func:`harmonic_balance` on the condensation ``cond`` (arguments checked)."""
    hh = cond.n_harmonics
    z = _start(system, cond, guess, tol, max_iter)
    z, res, jf, it, converged, message = _newton(cond, z, tol, max_iter)
    rel = float(np.max(np.abs(res))) / max(float(np.max(np.abs(z))), 1e-300)
    harm = cond.harmonics(jf.r)
    if not message:
        message = (f"harmonic balance converged in {it} Newton iterations (H = {hh}, residual {rel:.2e})"
                   if converged else f"harmonic balance did not converge in {max_iter} iterations "
                                     f"(residual {rel:.2e})")
    return HarmonicBalance(omega=system.omega, n_harmonics=hh, harmonics=harm,
                           harmonic_amplitude=np.abs(harm[1]), phase=-np.angle(harm[1]),
                           amplitude=_peaks(harm) if peaks else np.full(system.n_dof, np.nan),
                           converged=bool(converged), message=message, iterations=it, residual=rel,
                           dissipated_per_cycle=jf.dissipated,
                           slider_positions=jf.slider_positions, stuck=jf.stuck)


def _start(system: FrictionSystem, cond: Condensed, guess, tol: float, max_iter: int) -> np.ndarray:
    """Newton's starting joint coordinates: from ``guess``; without one, from the balance with
    fewer harmonics, ``H' = (H - 1) // 2`` down to 1 (the one-harmonic balance from the stuck linear
    solution; from the linear start Newton may wander on the loops' kinks: a blade root at its
    damper optimum), or the linear solution where that fails or ``H = 1``."""
    hh = cond.n_harmonics
    if guess is None and hh > 1:
        # the smaller balance on this one's condensation (its first harmonics' solves)
        first = _balance(system, cond.truncated(max(1, (hh - 1) // 2)), None, tol, max_iter, peaks=False)
        if first.converged:
            guess = first.harmonics
    if guess is None:
        return cond.q_linear.copy()
    g = np.asarray(guess, dtype=complex)
    if g.ndim != 2 or g.shape[1] != system.n_dof:
        raise ParameterError(f"guess must have shape (H' + 1, n_dof = {system.n_dof}), got {g.shape}")
    return cond.joint_vector(g)


def _newton(cond: Condensed, z: np.ndarray, tol: float, max_iter: int):
    """Newton's method with a backtracking line search (the residual's max norm must fall) on
    ``r(z) = z - G Z^-1 F + G Z^-1 G^T R(z)`` from ``z``: ``(z, r, joint forces, iterations,
    converged, message)`` (the message only where it stopped on a failure: non-finite forces, a
    singular Jacobian)."""

    def residual(zz, jac=True):
        f = cond.forces(zz, jac)
        res = zz - cond.q_linear + cond.Y @ f.r
        if not jac:
            return res, None, f
        big = cond.Y @ f.jacobian
        big[np.diag_indices(zz.size)] += 1.0
        return res, big, f

    scale_floor = max(float(np.max(np.abs(cond.q_linear))), 1e-300)
    res, jac, jf = residual(z)
    it = 0
    converged = False
    message = ""
    for it in range(1, max_iter + 1):
        scale = max(float(np.max(np.abs(z))), 1e-6 * scale_floor)
        rn = float(np.max(np.abs(res)))
        if not math.isfinite(rn):
            message = "a friction loop could not be resolved on its bracketing grid (non-finite joint forces)"
            break
        if rn <= tol * scale:
            converged = True
            it -= 1
            break
        try:
            step = np.linalg.solve(jac, -res)
        except np.linalg.LinAlgError:
            message = "singular Jacobian"
            break
        lam = 1.0
        for _ in range(30):  # backtracking: the residual's max norm must fall
            zt = z + lam * step
            rt, _, _ = residual(zt, jac=False)
            if float(np.max(np.abs(rt))) < rn or lam < 1e-6:
                break
            lam *= 0.5
        z = zt
        res, jac, jf = residual(z)
    else:
        scale = max(float(np.max(np.abs(z))), 1e-6 * scale_floor)
        converged = float(np.max(np.abs(res))) <= tol * scale
    return z, res, jf, it, converged, message


def balanced_state(system: FrictionSystem, harmonics: np.ndarray, slider_positions: np.ndarray):
    """The state ``(x0, v0, w0)`` at ``t = 0`` of a balanced orbit (``harmonics``, ``slider_positions``)
    as the marcher takes it: displacements and velocities summed from the harmonics, the sliders'
    positions moved into their slip bands there (the balance holds the joint coordinates to its
    tolerance only)."""
    hh = harmonics.shape[0] - 1
    x0 = harmonics.sum(axis=0).real
    v0 = (harmonics * (1j * system.omega * np.arange(hh + 1))[:, None]).sum(axis=0).real
    s = system.slider_direction @ x0
    jen = ~system.rigid
    w0 = np.asarray(slider_positions, dtype=float).copy()
    limit = system.slip_force.copy()
    if system.n_contacts:  # a slider on a contact slips at mu N(x0), zero where it is open
        var = system.varying
        n_c = system.normal_loads(x0)[system.slider_contact[var]]
        limit[var] *= n_c / system.contact_preload[system.slider_contact[var]]
    reach = limit[jen] / system.slider_stiffness[jen]
    w0[jen] = np.clip(w0[jen], s[jen] - reach, s[jen] + reach)
    return x0, v0, w0


def exact_orbit(system: FrictionSystem, harmonics: np.ndarray, slider_positions: np.ndarray, peaks: bool = True):
    """The exact time-domain steady state (:func:`~frictionjoint.solvers.marcher.steady.periodic_response`)
    started from a balanced orbit (:func:`balanced_state`)."""
    from ..marcher import periodic_response

    x0, v0, w0 = balanced_state(system, harmonics, slider_positions)
    return periodic_response(system, x0, v0, w0, peaks=peaks)


def lyapunov_stable(orbit) -> bool | None:
    """Stability of an exact orbit from its Floquet multipliers: not unstable, every modulus <= 1 +
    :data:`~frictionjoint.results.response.STABILITY_MARGIN` (a neutral family of stuck orbits,
    multiplier 1, counts as stable); None without multipliers."""
    from ...results.response import STABILITY_MARGIN

    mu = getattr(orbit, "floquet_multipliers", None)
    if mu is None or not orbit.converged:
        return None
    return bool(np.max(np.abs(mu), initial=0.0) <= 1.0 + STABILITY_MARGIN)


def truncation_error(harmonics: np.ndarray, exact) -> float | None:
    """``max |X1_hbm - X1_exact| / max |X1_exact|`` over the DOFs, of balanced ``harmonics`` against
    an exact orbit (None if it was not found)."""
    if not exact.converged:
        return None
    x1 = exact.harmonic_amplitude * np.exp(-1j * exact.phase)
    return float(np.max(np.abs(harmonics[1] - x1)) / np.max(np.abs(x1)))


def _check_exact(system: FrictionSystem, hb: HarmonicBalance) -> None:
    """The exact time-domain steady state from the balanced orbit; the truncation error."""
    ex = exact_orbit(system, hb.harmonics, hb.slider_positions)
    hb.exact = ex
    hb.stable = lyapunov_stable(ex)  # the Floquet multipliers of the matching exact orbit
    hb.truncation_error = truncation_error(hb.harmonics, ex)
    if ex.converged and np.all(np.isfinite(hb.amplitude)):  # peaks located (``peaks=True``)
        hb.amplitude_error = float(np.max(np.abs(hb.amplitude - ex.amplitude)) / np.max(ex.amplitude))


def hill_exponents(system: FrictionSystem, hb: HarmonicBalance) -> np.ndarray:
    """Floquet exponents of a balanced orbit by Hill's method: the quadratic eigenproblem

        [lam^2 M~ + lam (C~ + 2 w M~ D) + (K~ + w C~ D + w^2 M~ D^2 + G~^T J G~)] P = 0

    in the real Fourier basis of ``H`` harmonics (``D`` the phase derivative, ``~`` block-diagonal
    copies per harmonic coefficient, ``J`` the analytic Jacobian of the joints' forces, the stuck
    springs in ``K``), linearised to a generalised eigenproblem of size ``2 n (2H + 1)``; of its
    eigenvalues the ``2 n`` with the smallest ``|Im lam|`` are the exponents (the others are their
    copies shifted by ``i h w``). An approximation (the sliders' memory enters only through the
    periodic Jacobian); the exact alternative is the Floquet multipliers of the matching exact
    orbit (``check=True``).

    Parameters
    ----------
    system : FrictionSystem
        The system the balance was made for.
    hb : HarmonicBalance
        A converged balance of it.

    Returns
    -------
    (2 n_dof,) complex ndarray
        The exponents ``lam`` [1/s]; the orbit is asymptotically stable when every real part is < 0.
    """
    if hb.omega != system.omega:
        system = FrictionSystem(system.structure, system.elements, omega=hb.omega, excitation=system.excitation)
    hh = hb.n_harmonics
    cond = Condensed(system, hh)
    nc = cond.nc
    n = system.n_dof
    # the joints' Jacobian on the balanced orbit (and the open contacts' dashpots)
    jf = cond.forces(cond.joint_vector(hb.harmonics))
    k_lin, m, c = cond._lin
    w = system.omega
    # basis index (dof, j): dof * nc + j; D on one DOF's coefficients: (a_h, b_h) -> h (b_h, -a_h)
    d1 = hysteresis.derivative_matrix(hh)
    eye = np.eye(nc)
    mt, ct, kt = np.kron(m, eye), np.kron(c, eye), np.kron(k_lin, eye)
    dd = np.kron(np.eye(n), d1)
    g = np.kron(cond.G, eye)  # joint coordinates' coefficients from the DOFs'
    k_total = kt + w * ct @ dd + w * w * mt @ dd @ dd + g.T @ jf.jacobian @ g
    c_total = ct + 2 * w * mt @ dd
    if jf.damping is not None:  # an open contact's dashpot is off (its omega D part is in the Jacobian)
        c_total = c_total + g.T @ jf.damping @ g
    size = n * nc
    a = np.block([[np.zeros((size, size)), np.eye(size)], [-k_total, -c_total]])
    b = np.block([[np.eye(size), np.zeros((size, size))], [np.zeros((size, size)), mt]])
    lam = scipy.linalg.eigvals(a, b)
    lam = lam[np.isfinite(lam)]
    return lam[np.argsort(np.abs(lam.imag))][:2 * n]
