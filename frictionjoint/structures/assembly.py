"""A blade assembly: a (reduced) blade structure, its root joints and its harmonic loads, as one
object that builds the :class:`~frictionjoint.system.FrictionSystem` at any ``omega`` and runs the
library's solvers on it.

Loads are given on the full model's DOFs (e.g. the tip ``w30``); on a Craig-Bampton structure
(:func:`~frictionjoint.structures.craig_bampton`, which keeps its ``transformation``) they are
projected, ``f_r = T^T f``, and the first harmonic of any full-model DOF is recovered from the
reduced orbit, ``X = T X_r`` (exact for the first harmonic, which is linear in the state).
"""
from __future__ import annotations

import math
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

# imported here, not in from_model: BladeDovetail.fmu builds its assembly there, and in an FMU a
# late import may resolve against another FMU's bundle (see frictionjoint.fmi.slaves)
from ..elements.dovetail import DovetailRoot
from ..errors import ParameterError, check_real
from ..excitation import HarmonicForce
from ..results import OutputSweep, PeriodicResponse, SystemSweep, TimeResponse
from ..structure import LinearStructure
from ..system import FrictionSystem
from ..system_sweeps import peak_response, system_sweep
from .reduction import craig_bampton
from .solid_root import solid_blade_on_patches

__all__ = ["BladeAssembly"]


class BladeAssembly:
    """Blade structure + root joints + harmonic loads.

    Parameters
    ----------
    structure : LinearStructure
        The blade (full, or reduced by :func:`~frictionjoint.structures.craig_bampton`, possibly
        :meth:`~frictionjoint.structure.LinearStructure.clamped` afterwards).
    joints : sequence
        Joint elements on its DOFs (e.g. a :class:`~frictionjoint.elements.DovetailRoot` on
        ``w0``/``u0``).
    loads : dict
        ``{dof: amplitude}``: forces ``amplitude cos(omega t)`` [N] on DOFs of the full model
        (projected onto a reduced structure) or of ``structure`` itself.
    """

    def __init__(self, structure: LinearStructure, joints: Sequence = (), loads: dict | None = None) -> None:
        if not isinstance(structure, LinearStructure):
            raise ParameterError(f"structure must be a LinearStructure, got {type(structure).__name__}")
        self.structure = structure
        self.joints = tuple(joints)
        self.loads = {str(k): check_real(f"loads[{k!r}]", v) for k, v in dict(loads or {}).items()}
        self._force = self._reduced_force()
        FrictionSystem(structure, self.joints)  # the joints' DOFs checked now

    @classmethod
    def from_model(cls, model, n_modes: int = 5, **blade_overrides) -> "BladeAssembly":
        """The assembly of a blade model definition (:func:`~frictionjoint.structures.load_blade_model`):
        its blade reduced by Craig-Bampton to the root DOFs, ``n_modes`` modes and the tip's
        residual vector, the root slope held by the slot unless the root rocks, a flat-flank
        :class:`~frictionjoint.elements.DovetailRoot` (``[root]``) under the blade's centrifugal
        force on ``w0``/``u0`` (and, with ``flank_half_width`` in ``[root]``, rocking on the root
        slope ``t0``), and ``[excitation] tip_force_amplitude`` at the tip.

        Parameters
        ----------
        model : BladeModel
            The definition (rotating: the dovetail needs a centrifugal force).
        n_modes : int
            Fixed-interface modes kept, >= 0.
        **blade_overrides
            BeamBlade arguments that replace the definition's (e.g. ``rotor_speed``).

        Returns
        -------
        BladeAssembly
        """
        blade = model.blade(**blade_overrides)
        amplitude = float(model.excitation.get("tip_force_amplitude", 1.0))
        if model.kind == "solid":
            reduced, root, tip = solid_blade_on_patches(blade, model.root, n_modes,
                                                        model.excitation.get("tip_point", "centre"))
            return cls(reduced, [root], {tip: amplitude})
        tip = f"w{blade.n_elements}"
        reduced = craig_bampton(blade.structure, ["u0", "w0", "t0"], n_modes, loaded_dofs=[tip])
        root_args = dict(model.root)
        if root_args.get("flank_half_width") is not None:
            root_args["rocking_dof"] = "t0"  # the root rocks on its flanks
        else:
            reduced = reduced.clamped(["t0"])
        if not blade.centrifugal_force > 0:
            raise ParameterError("the model's rotor_speed must be > 0 (the dovetail is loaded by the centrifugal force)")
        root = DovetailRoot(blade.centrifugal_force, tangential_dof="w0", radial_dof="u0", **root_args)
        return cls(reduced, [root], {tip: amplitude})

    # ------------------------------------------------------------------ DOFs
    def _reduced_force(self) -> np.ndarray:
        return sum((amp * self._row(dof, "loads") for dof, amp in self.loads.items()),
                   np.zeros(self.structure.n_dof))

    def _row(self, dof: str, what: str = "dof") -> np.ndarray:
        """Coefficients of a DOF, of the structure or of the full model that a reduced structure's
        ``transformation`` maps from, in the structure's DOFs (``what`` names it in the error)."""
        s = self.structure
        if dof in s.dof_names:
            row = np.zeros(s.n_dof)
            row[s.dof_index(dof)] = 1.0
            return row
        full = getattr(s, "full_dof_names", ())
        if dof not in full:
            raise ParameterError(f"{what}: {dof!r} is not a DOF of the blade")
        return s.transformation[list(full).index(dof)]

    # ------------------------------------------------------------------ solvers
    def system(self, omega: float) -> FrictionSystem:
        """The friction system at excitation frequency ``omega`` [rad/s].

        Parameters
        ----------
        omega : float
            Angular frequency [rad/s], > 0.

        Returns
        -------
        FrictionSystem
        """
        names = self.structure.dof_names
        exc = [HarmonicForce(names[k], float(a)) for k, a in enumerate(self._force) if a != 0.0]
        return FrictionSystem(self.structure, self.joints, omega=omega, excitation=exc)

    def steady_state(self, omega: float, **kwargs) -> PeriodicResponse:
        """Periodic steady state at ``omega`` (:func:`frictionjoint.solvers.marcher.steady.periodic_response`).

        Parameters
        ----------
        omega : float
            Angular frequency [rad/s], > 0.
        **kwargs
            Passed to ``periodic_response`` (start guess, tolerances).

        Returns
        -------
        PeriodicResponse
        """
        from ..solvers.steady_state import periodic_response

        return periodic_response(self.system(omega), **kwargs)

    def simulate(self, omega: float, t_end: float, **kwargs) -> TimeResponse:
        """Time response at ``omega`` from rest (:func:`frictionjoint.solvers.marcher.response.simulate`).

        Parameters
        ----------
        omega : float
            Angular frequency [rad/s], > 0.
        t_end : float
            End time [s].
        **kwargs
            Passed to ``simulate`` (initial state, output times, what to record).

        Returns
        -------
        TimeResponse
        """
        from ..solvers.marcher.response import simulate

        return simulate(self.system(omega), t_end, **kwargs)

    def sweep(self, omegas: ArrayLike, progress: bool = False) -> SystemSweep:
        """Stepped-sine sweep (:func:`~frictionjoint.system_sweeps.system_sweep` of this assembly's
        ``system``, as :func:`frictionjoint.sweep.sweep` runs it).

        Parameters
        ----------
        omegas : str or sequence of float
            Angular frequencies [rad/s], > 0, in the order swept: ``"START:STOP:N"`` or the
            frequencies themselves (:mod:`frictionjoint.frequencies`).
        progress : bool
            Show a progress bar.

        Returns
        -------
        SystemSweep
        """
        return system_sweep(self.system, omegas, progress=progress)

    @property
    def tip(self) -> str | None:
        """The first loaded DOF (e.g. ``'w30'``, where :meth:`from_model` puts its tip force)."""
        return next(iter(self.loads), None)

    def frequency_response(self, omegas: ArrayLike, dof: str | None = None, progress: bool = False,
                           method: str = "time", n_harmonics: int = 7, check: bool = False) -> OutputSweep:
        """Stepped-sine sweep (:meth:`sweep`) of one DOF's first harmonic, with that DOF's linear
        frequency response in the root's two limits (every slider stuck, every slider slipping:
        :func:`~frictionjoint.linear_limits.limit_structures`) at the same frequencies.

        Parameters
        ----------
        omegas : str or sequence of float
            Angular frequencies [rad/s], > 0, in the order swept: ``"START:STOP:N"`` or the
            frequencies themselves (:mod:`frictionjoint.frequencies`; ``(start, stop, n)`` is
            refused as ambiguous).
        dof : str, optional
            The output, a DOF of the full model or of the structure (default :attr:`tip`).
        progress : bool
            Show a progress bar.
        method : {'time', 'hbm'}
            ``'time'``: the exact steady state at each of ``omegas`` (shooting on the event-driven
            marcher); ``'hbm'``: the harmonic-balance branch from the first to the last of
            ``omegas`` (:func:`~frictionjoint.solvers.frequency_domain.continuation.hbm_sweep`, about ``len(omegas)``
            points; the points are the branch's, past a fold not monotonic in omega).
        n_harmonics : int
            Harmonics of ``'hbm'``.
        check : bool
            ``'hbm'``: check every branch point against the exact orbit started from it (one
            shooting per point): its truncation error and its stability from the exact Floquet
            multipliers. ``'time'`` judges the stability of every orbit anyway.

        Returns
        -------
        OutputSweep
        """
        from ..linear_limits import limit_structures

        dof = self.tip if dof is None else str(dof)
        if dof is None:
            raise ParameterError("dof: the assembly has no loads, name the output DOF")
        row = self._row(dof)
        if method == "hbm":
            from ..frequencies import check_omegas
            from ..solvers.frequency_domain.continuation import hbm_sweep

            ws = check_omegas("omegas", omegas)
            if ws.size < 2:
                raise ParameterError("omegas: the harmonic-balance branch needs a start and an end frequency")
            hb = hbm_sweep(self.system(float(ws[0])), (float(ws[0]), float(ws[-1])), n_harmonics=n_harmonics,
                           n_points=int(ws.size), progress=progress, check=bool(check))
            limits = {name: st.harmonic_response(hb.omega, self._force) @ row
                      for name, st in limit_structures(self.system(float(ws[0]))).items()}
            return OutputSweep(omega=hb.omega, output=dof, response=hb.harmonics[:, 1] @ row, limits=limits,
                               stuck=hb.stuck, converged=hb.converged,
                               dissipated_per_cycle=hb.dissipated_per_cycle,
                               messages=tuple(f"HBM H = {hb.n_harmonics}: {m}" for m in hb.messages),
                               stable=hb.stable, fold=hb.fold, truncation_error=hb.truncation_error)
        if method != "time":
            raise ParameterError(f"method must be 'time' or 'hbm', got {method!r}")
        # the first harmonics only: no displacement peaks located (half a point's time at the
        # damper optimum)
        sw = system_sweep(self.system, omegas, progress=progress, peaks=False)
        limits = {name: st.harmonic_response(sw.omega, self._force) @ row
                  for name, st in limit_structures(self.system(float(sw.omega[0]))).items()}
        return OutputSweep(omega=sw.omega, output=dof, response=sw.harmonics @ row, limits=limits, stuck=sw.stuck,
                           converged=sw.converged, dissipated_per_cycle=sw.dissipated_per_cycle,
                           messages=sw.messages, stable=sw.stable)

    def with_root(self, **changes) -> "BladeAssembly":
        """The assembly with its (single) root joint's parameters changed
        (:meth:`~frictionjoint.elements.DovetailRoot.replace`, e.g. ``centrifugal_force`` [N] or
        ``friction_coefficient``); structure and loads shared.

        Parameters
        ----------
        **changes
            The root's constructor arguments, by keyword.

        Returns
        -------
        BladeAssembly
        """
        if len(self.joints) != 1 or not hasattr(self.joints[0], "replace"):
            raise ParameterError("with_root needs an assembly with one root joint that has replace() (a DovetailRoot)")
        return BladeAssembly(self.structure, [self.joints[0].replace(**changes)], self.loads)

    def peak(self, omega_min: float, omega_max: float, dof: str, n_grid: int = 25,
             xtol: float = 1e-6) -> tuple[float, float]:
        """Resonance peak of the first-harmonic amplitude of ``dof`` (a DOF of the full model, e.g.
        the tip) over ``[omega_min, omega_max]`` (:func:`frictionjoint.system_sweeps.peak_response`).

        Parameters
        ----------
        omega_min, omega_max : float
            Frequency interval [rad/s].
        dof : str
            The DOF (of the full model or of the structure).
        n_grid : int
            Frequencies of the bracketing sweep, >= 3.
        xtol : float
            Tolerance of the peak frequency, relative.

        Returns
        -------
        (omega_peak, amplitude_peak) : (float, float)
            [rad/s], [m].
        """
        w, amp, _ = peak_response(self.system, omega_min, omega_max, n_grid=n_grid, xtol=xtol,
                                  output=self._row(dof), peaks=False)  # the sweep is not returned
        return w, amp

    def first_harmonic(self, response: PeriodicResponse, dof: str) -> complex:
        """First harmonic ``X`` of a DOF of the full model on a steady state, ``x = Re(X e^{i omega
        t})`` [m]: ``|X|`` its amplitude, ``-arg X`` its lag behind ``cos(omega t)``.

        Parameters
        ----------
        response : PeriodicResponse
            A steady state of this assembly.
        dof : str
            A DOF of the full model (e.g. the tip) or of the structure.

        Returns
        -------
        complex
        """
        amp = np.atleast_1d(np.asarray(response.harmonic_amplitude, dtype=float))
        phase = np.atleast_1d(np.asarray(response.phase, dtype=float))
        if amp.size != self.structure.n_dof:
            raise ParameterError(f"response must be a steady state of this assembly ({self.structure.n_dof} DOFs)")
        x = amp * np.exp(-1j * phase)
        out = complex(self._row(dof) @ x)
        if not (math.isfinite(out.real) and math.isfinite(out.imag)):
            raise ParameterError(f"response has no finite first harmonic ({response.status})")
        return out
