"""Single-DOF Coulomb oscillator: the convenience API over structure + elements + solvers."""
from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from numpy.typing import ArrayLike

from .elements import CoulombSlider
from .errors import ConvergenceError, check_count, check_nonnegative, check_positive, check_real
from .excitation import HarmonicBaseMotion, HarmonicForce
from .results import PeriodicResponse, TimeResponse
from .solvers.marcher.events import Marcher
from .solvers.marcher.response import check_run
from .solvers.marcher.response import simulate as _simulate
from .solvers.marcher.steady import periodic_response
from .structure import LinearStructure
from .system import FrictionSystem

__all__ = ["CoulombOscillator"]


class CoulombOscillator:
    """Mass on a Coulomb friction surface, with a spring to a moving base.

    ``m x'' + c x' + k (x - Y cos(omega t)) + T = P cos(omega t)``, ``T`` the Coulomb friction
    force (``|T| <= slip_force``, exact stick/slip, Hong & Liu's stop rules), friction and damper
    acting against the fixed ground (Den Hartog 1931; Hong & Liu 2000).

    Parameters
    ----------
    mass : float
        Mass m [kg], > 0.
    stiffness : float
        Spring k to the base [N/m], > 0.
    slip_force : float
        Friction force limit [N], >= 0.
    force_amplitude : float
        Amplitude P of the force on the mass [N].
    omega : float
        Excitation angular frequency [rad/s], > 0.
    damping : float
        Viscous damper c to the ground [N s/m], >= 0.
    base_amplitude : float
        Amplitude Y of the base motion [m].
    """

    def __init__(self, mass: float = 1.0, stiffness: float = 1.0, slip_force: float = 0.0,
                 force_amplitude: float = 0.0, omega: float = 1.0, damping: float = 0.0,
                 base_amplitude: float = 0.0):
        self.mass = check_positive("mass", mass)
        self.stiffness = check_positive("stiffness", stiffness)
        self.slip_force = check_nonnegative("slip_force", slip_force)
        self.force_amplitude = check_real("force_amplitude", force_amplitude)
        self.omega = check_positive("omega", omega)
        self.damping = check_nonnegative("damping", damping)
        self.base_amplitude = check_real("base_amplitude", base_amplitude)
        structure = LinearStructure(self.mass, 0.0, self.damping, dof_names=["x"])
        self.system = FrictionSystem(
            structure, [CoulombSlider(self.slip_force, dof=0)], omega=self.omega,
            excitation=[HarmonicForce(0, self.force_amplitude),
                        HarmonicBaseMotion(0, self.stiffness, self.base_amplitude)])
        self._marcher = Marcher(self.system)

    # ------------------------------------------------------------ derived
    @property
    def natural_frequency(self) -> float:
        """Undamped natural angular frequency sqrt(k/m) [rad/s]."""
        return math.sqrt(self.stiffness / self.mass)

    @property
    def frequency_ratio(self) -> float:
        """r = omega / omega_n."""
        return self.omega / self.natural_frequency

    @property
    def equivalent_force_amplitude(self) -> float:
        """P0 = P + k Y [N]: force and base motion act in phase on the mass."""
        return self.force_amplitude + self.stiffness * self.base_amplitude

    @property
    def friction_ratio(self) -> float:
        """``f = F / |P0|`` (inf without excitation)."""
        p0 = abs(self.equivalent_force_amplitude)
        return self.slip_force / p0 if p0 > 0 else math.inf

    @property
    def period(self) -> float:
        """Excitation period 2 pi / omega [s]."""
        return 2 * math.pi / self.omega

    def __repr__(self) -> str:
        return (f"CoulombOscillator(mass={self.mass}, stiffness={self.stiffness}, "
                f"slip_force={self.slip_force}, force_amplitude={self.force_amplitude}, "
                f"omega={self.omega}, damping={self.damping}, base_amplitude={self.base_amplitude})")

    # ------------------------------------------------------------ solvers
    def simulate(self, t_end: float, x0: float = 0.0, v0: float = 0.0, t_eval: ArrayLike | None = None,
                 record: str | Sequence[str] = ("x", "v", "friction_force")) -> TimeResponse:
        """Exact time response from ``t = 0``.

        Parameters
        ----------
        t_end : float
            End time [s], > 0.
        x0, v0 : float
            Initial displacement [m] and velocity [m/s].
        t_eval : (n_t,) array_like, optional
            Output times in ``[0, t_end]``; default 32 per period.
        record : str or sequence of str
            Among ``'x'``, ``'v'``, ``'friction_force'``, ``'energy'`` (a single name may be given
            as a str).

        Returns
        -------
        TimeResponse
            With 1-D arrays ``x``, ``v``, ``friction_force`` and the event log.

        Raises
        ------
        frictionjoint.solvers.sdof.kernel.EventBudgetError
            A :class:`ConvergenceError` where the exact motion has far too many events to march
            (a forcing period far beyond the natural one sticks and slips about once per natural
            period; deep in that regime the quasi-static motion is the answer, within its bound).
        """
        x0 = check_real("x0", x0)
        v0 = check_real("v0", v0)
        _, t_end, t_eval, record = check_run(self.omega, 0.0, t_end, t_eval, record)
        if "energy" not in record:
            # the closed-form kernel; the general marcher (the reference) keeps the energy
            # accounting, and answers should the kernel's rules ever find no consistent status
            # (no such case is known since they break stick/slip cycles as Marcher.settle does)
            from .solvers.sdof.kernel import EventBudgetError
            from .solvers.sdof.simulate import sdof_simulate

            try:
                return sdof_simulate(self._kernel(), t_end, x0, v0, t_eval, record)
            except EventBudgetError:
                raise  # far too many events for any event-driven march (the message says why)
            except ConvergenceError:
                pass
        tr = _simulate(self.system, t_end, x0, v0, t_eval=t_eval, record=record, marcher=self._marcher)
        for name in ("x", "v", "friction_force"):
            a = getattr(tr, name)
            if a is not None:
                setattr(tr, name, a[0])
        return tr

    def _kernel(self):
        """The closed-form single-DOF kernel of this oscillator (force and base motion in phase)."""
        from .solvers.sdof.kernel import SdofCoulomb

        return SdofCoulomb(self.mass, self.stiffness, self.slip_force, self.equivalent_force_amplitude,
                           self.omega, self.damping)

    def initial_guess(self):
        """One-harmonic (describing-function) estimate ``(x, v)`` of the orbit at ``t = 0``."""
        p0 = self.equivalent_force_amplitude
        k_dyn = self.stiffness - self.mass * self.omega ** 2
        fr = 4 * self.slip_force / (math.pi * abs(p0)) if p0 != 0 else math.inf
        if fr < 1 and abs(k_dyn) < 1e-3 * self.stiffness and self.damping == 0:
            # near resonance the one-harmonic amplitude is poor (and Newton from rest meets the
            # stops of the start-up transient): Den Hartog's exact orbit where it applies
            from .analytic import den_hartog

            sol = den_hartog(self.frequency_ratio, self.slip_force / abs(p0))
            if sol.applicable:
                scale = p0 / self.stiffness  # x is odd in P0
                return (scale * float(sol.waveform(0.0)),
                        scale * self.natural_frequency * float(sol.waveform(0.0, derivative=1)))
        if fr >= 1 or abs(k_dyn) < 1e-3 * self.stiffness:
            return 0.0, 0.0
        amp = abs(p0) * math.sqrt(1 - fr ** 2) / abs(k_dyn)
        # x = X cos(wt - phi): in phase (or opposite) with P0, friction adds a lag
        phi = math.atan2(fr, math.sqrt(1 - fr ** 2) * math.copysign(1.0, k_dyn))
        if p0 < 0:
            phi += math.pi
        return amp * math.cos(phi), amp * self.omega * math.sin(phi)

    def steady_state(self, x0: float | None = None, v0: float | None = None, tol: float = 1e-12,
                     max_periods: int = 2000, n_samples: int = 0) -> PeriodicResponse:
        """Periodic steady state by shooting on the period map.

        Parameters
        ----------
        x0, v0 : float, optional
            Initial guess at ``t = 0`` [m, m/s]; the one-harmonic estimate if omitted.
        tol : float
            Tolerance on the scaled fixed-point residual.
        max_periods : int
            Periods marched at most when shooting fails.
        n_samples : int
            If > 0, also return that many samples of ``x`` over the period.

        Returns
        -------
        PeriodicResponse
            ``amplitude`` (``max |x|``) [m], ``phase`` (first-harmonic lag behind the force) [rad],
            ``stops_per_cycle``, ``converged`` and ``message`` (also on unbounded growth and
            non-unique orbits).

        Notes
        -----
        A forcing period far beyond the natural one (``omega/omega_n`` below about 1e-9 at
        ``f = 0.5``) is answered by the quasi-static limit, whose rigorous distance to the exact
        motion the message states (:func:`frictionjoint.solvers.sdof.steady.quasi_static_response`).
        Between that and an affordable march (undamped, ``omega/omega_n`` about 1e-9 .. 1e-5) the
        exact motion sticks and slips once per natural period, too often to march: status
        ``'not converged'``, the quasi-static limit and its bound in the message, in a few seconds.
        """
        max_periods = check_count("max_periods", max_periods, 0)
        n_samples = check_count("n_samples", n_samples, 0)
        gx, gv = self.initial_guess()
        x0 = gx if x0 is None else check_real("x0", x0)
        v0 = gv if v0 is None else check_real("v0", v0)
        if self.slip_force > 0:
            # the closed-form kernel with its exact Jacobian; the general marcher where it does not apply
            from .solvers.sdof.steady import sdof_periodic_response

            res = sdof_periodic_response(self._kernel(), x0, v0, tol=tol, max_newton=25, max_periods=max_periods,
                                         n_samples=n_samples)
            if res is not None:
                return res
        res = periodic_response(self.system, x0, v0, marcher=self._marcher, tol=tol,
                                max_periods=max_periods, n_samples=n_samples)
        if res.status == "failed":  # the march failed: a status, with the scalar fields of this API
            res.amplitude = res.phase = res.harmonic_amplitude = float("nan")
            return res
        res.amplitude = float(res.amplitude[0])
        res.phase = float(res.phase[0])
        res.harmonic_amplitude = float(res.harmonic_amplitude[0])
        if res.x is not None:
            res.x = res.x[0]
        return res  # its Floquet multipliers are exact (the general path's closed-form monodromy)

    def monodromy(self, t0: float, x0: float, v0: float):
        """Exact Jacobian ``d(x, v)(t0 + T) / d(x0, v0)`` of the period map from a slipping state
        (:meth:`frictionjoint.solvers.sdof.kernel.SdofCoulomb.monodromy`), or None where it has no
        derivative (a start at rest, or a grazing event on the way).

        Parameters
        ----------
        t0 : float
            Section time [s].
        x0, v0 : float
            State at ``t0`` [m, m/s].

        Returns
        -------
        (2, 2) ndarray or None
        """
        _, jac = self._kernel().monodromy(t0, x0, v0, t0 + self.period)
        return None if jac is None else np.array(jac)
