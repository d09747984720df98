"""Campbell diagrams of a blade on its friction root.

At each rotor speed ``Omega`` [rad/s] the blade model is assembled on its root as
:meth:`BladeAssembly.from_model <frictionjoint.structures.BladeAssembly.from_model>` builds it at
that speed: the blade's centrifugal stiffening (and spin softening) and the root's normal load,
the blade's centrifugal force, both follow the speed. Its undamped natural frequencies
``omega_k(Omega)`` are computed in the root's two linear limits
(:func:`~frictionjoint.linear_limits.limit_structures`): every slider stuck, every slider
slipping (free slip). Sorted eigenvalues are continuous in ``Omega``, and by Weyl's inequality
the free-slip ``omega_k`` is never above the stuck one (the sliders' springs only add
stiffness).

A crossing of mode ``k`` with engine order ``EO`` is a root of ``g(Omega) = omega_k(Omega) - EO
Omega``. Where ``g`` changes sign between two speed samples it is located by Brent's method on
``g`` itself, each evaluation a new assembly at that speed, to ``|dOmega| <= XTOL Omega``; the
crossing then lies on the mode's curve and on the line to the eigenvalues' rounding (on the Ti-64
blade, the mode recomputed at the crossing's speed: within 1.5e-12 of the line, stuck, 2.0e-12
free slip). An even number of crossings between two samples (a line grazing a
curve) is not seen: sample finely enough.

With ``amplitude``: at each speed the nonlinear mode that starts from each stuck mode
(:func:`~frictionjoint.solvers.frequency_domain.nonlinear_mode.nonlinear_mode`, EPMC with exact
hysteresis) at that first-harmonic amplitude of ``dof`` (default the root's tangential DOF): its
frequency lies between the two limits, near the stuck one at high speed (the root's load grows
like ``Omega^2``, the slip onset with it) and towards the free-slip one at low speed. Each speed's
mode is followed in amplitude from its stuck linear mode. ``H = 1`` by default, the describing
function's balance: smooth in speed and converged at every speed on the Ti-64 blade (50-1500
rad/s, 5e-5 m at ``w0``, 3 modes). With ``H = 3`` the band moves by up to 3e-3 (relative) above
500 rad/s for the two lowest modes, and more where a higher harmonic meets another mode (the third
harmonic of the second mode meets the third mode: up to 4e-2) or the root slips deeply at low
speed (up to 0.1); there the branch folds, 4 of 177 points did not converge and the curve jumps
between branches from one speed to the next. Its crossings are located the same way, to Newton's tolerance of the mode (on the Ti-64
blade within 5.7e-12 of the line).
"""
from __future__ import annotations

import math
import os
import re
import sys
from numbers import Real
from typing import TYPE_CHECKING

import numpy as np
import scipy.optimize
from numpy.typing import ArrayLike

from .errors import ParameterError, check_count, check_grid, check_positive
from .frequencies import check_omegas
from .linear_limits import limit_structures
from .results.campbell import CampbellDiagram, crossing_table
from .solvers.frequency_domain.nonlinear_mode import nonlinear_mode
from .threads import owns_blas_threads

if TYPE_CHECKING:  # structures/ is imported when a diagram is computed, not with the package
    from .structures.assembly import BladeAssembly
    from .structures.models import BladeModel

__all__ = ["campbell", "XTOL", "MAX_SPEEDS"]

#: relative tolerance of a crossing's speed (Brent's method)
XTOL = 1e-13
#: the most speeds of one diagram, counted before any assembly (as sweeps and studies count their
#: points: :data:`frictionjoint.frequencies.MAX_POINTS`, :data:`frictionjoint.study.definition.MAX_POINTS`).
#: Crossings are located by Brent's method between samples, so samples need only separate them; a
#: speed costs an assembly and two eigenproblems (50 ms on the Ti-64 beam blade, about a second on
#: the solid one, and a nonlinear mode per mode with ``amplitude``): 10^4 speeds are 8 minutes on the
#: beam, 10^6 would be 14 hours
MAX_SPEEDS = 10_000


class _Blade:
    """The model's assembly at any rotor speed, and its frequencies there."""

    def __init__(self, model: BladeModel, n_modes: int, reduction_modes: int, amplitude, dof, n_harmonics: int):
        self.model, self.n_modes, self.reduction_modes = model, n_modes, reduction_modes
        self.amplitude, self.dof, self.n_harmonics = amplitude, dof, n_harmonics
        self.reduction_given = False  # reduction_modes is 2 n_modes + 2
        self._last = (None, None)

    def assembly(self, speed: float) -> BladeAssembly:
        """The assembly at ``speed`` (the last one kept: the limits and the nonlinear modes at a
        speed share it; a solid blade's takes about a second)."""
        from .structures.assembly import BladeAssembly

        if self._last[0] != float(speed):
            try:
                asm = BladeAssembly.from_model(self.model, self.reduction_modes, rotor_speed=float(speed))
            except ParameterError as exc:
                # from_model's n_modes is our reduction_modes; keeping every interior mode leaves no room
                # for the tip's residual vector
                if not str(exc).startswith(("n_modes", "the residual vector")):
                    raise
                raise self._too_many_modes(exc) from None
            self._last = (float(speed), asm)
        return self._last[1]

    def _too_many_modes(self, exc: ParameterError) -> ParameterError:
        """The reduction's refusal of ``reduction_modes`` (its ``n_modes``) in the caller's words:
        the argument the caller gave and its range (from the interior DOFs the reduction names)."""
        found = re.search(r"\[0, (\d+)\]", str(exc))
        # the interior DOFs less the tip's residual vector
        most = None if found is None else int(found.group(1)) - 1
        detail = "" if found else f": {exc}"  # the reduction's words, where they give no range
        if self.reduction_given:
            allowed = " smaller" if most is None else f" in [0, {most}]"
            return ParameterError(f"reduction_modes must be{allowed} for {self.model.name} (the fixed-interface "
                                  f"modes of its blade, besides the tip's residual vector{detail}), got "
                                  f"{self.reduction_modes}")
        allowed = " smaller" if most is None else f" in [1, {(most - 2) // 2}]"
        return ParameterError(f"n_modes must be{allowed} for {self.model.name} (its blade is reduced to 2 n_modes + 2 "
                              f"fixed-interface modes besides the tip's residual vector{detail}; or give "
                              f"reduction_modes), got {self.n_modes}")

    def limits(self, speed: float) -> dict[str, np.ndarray]:
        """``{'stuck': omega, 'slipping': omega}``: the lowest ``n_modes`` undamped natural
        frequencies [rad/s] of both limits at ``speed``."""
        system = self.assembly(speed).system(1.0)
        out = {name: st.natural_frequencies()[:self.n_modes] for name, st in limit_structures(system).items()}
        if out["stuck"].size < self.n_modes:
            raise ParameterError(f"n_modes must be <= {out['stuck'].size}: the assembly of {self.model.name} has "
                                 f"{out['stuck'].size} DOFs with reduction_modes = {self.reduction_modes}")
        return out

    def nonlinear(self, speed: float, mode: int) -> tuple[float, float]:
        """``(omega, zeta)`` of the nonlinear mode ``mode`` at ``amplitude`` and ``speed`` (NaN
        where Newton did not converge)."""
        system = self.assembly(speed).system(1.0)
        nm = nonlinear_mode(system, mode=mode, amplitudes=[self.amplitude], n_harmonics=self.n_harmonics,
                            dof=self.dof)
        return float(nm.frequency[0]), float(nm.damping_ratio[0])

    def frequency(self, limit: str, mode: int, speed: float) -> float:
        """Mode ``mode``'s frequency on the curve ``limit`` at ``speed`` [rad/s]; :class:`_NoValue`
        where the nonlinear mode did not converge."""
        w = self.nonlinear(speed, mode)[0] if limit == "nonlinear" else float(self.limits(speed)[limit][mode])
        if not math.isfinite(w):
            raise _NoValue(speed)
        return w


class _NoValue(Exception):
    """A curve without a value at a trial speed (a nonlinear mode that did not converge)."""


def _check_args(model, speeds, engine_orders, n_modes, amplitude, n_harmonics, reduction_modes):
    from .structures.models import BladeModel, load_blade_model

    if isinstance(model, BladeModel):
        definition = model
    elif isinstance(model, (str, bytes)) or hasattr(model, "__fspath__"):
        definition = load_blade_model(model)
    else:
        raise ParameterError(f"model must be a blade model's name, a .toml path or a BladeModel, got "
                             f"{type(model).__name__}")
    try:
        speeds = check_omegas("speeds", speeds)
    except ParameterError as exc:
        if "> 0" not in str(exc):
            raise
        raise ParameterError(f"{exc} (the dovetail root carries no load at rest)") from None
    if speeds.size > MAX_SPEEDS:
        raise ParameterError(f"speeds must hold at most {MAX_SPEEDS} rotor speeds, got {speeds.size} (crossings are "
                             "located between samples: a coarser grid finds them to the same tolerance)")
    if speeds.size > 1 and not np.all(np.diff(speeds) > 0):
        raise ParameterError(f"speeds must increase strictly [rad/s], got {speeds.tolist()!r}")
    if isinstance(engine_orders, Real):
        engine_orders = [engine_orders]
    eos = check_grid("engine_orders", engine_orders)
    if np.unique(eos).size != eos.size:
        raise ParameterError(f"engine_orders must not repeat, got {eos.tolist()!r}")
    n_modes = check_count("n_modes", n_modes, 1)
    reduction = 2 * n_modes + 2 if reduction_modes is None else check_count("reduction_modes", reduction_modes, 0)
    if amplitude is not None:
        amplitude = check_positive("amplitude", amplitude)
    return definition, speeds, np.sort(eos), n_modes, reduction, check_count("n_harmonics", n_harmonics, 1)


@owns_blas_threads
def campbell(model: str | os.PathLike | BladeModel, speeds: str | ArrayLike, engine_orders: ArrayLike = (1, 2, 3, 4),
             n_modes: int = 3, amplitude: float | None = None, *,
             n_harmonics: int = 1, dof: str | None = None, reduction_modes: int | None = None,
             progress: bool = False) -> CampbellDiagram:
    """The Campbell diagram of a blade model on its friction root (module docstring): the modes'
    frequencies against rotor speed with the root stuck and slipping, the engine-order lines and
    their crossings; with ``amplitude``, the nonlinear modes at that amplitude between them.

    Parameters
    ----------
    model : str, os.PathLike or BladeModel
        A blade model definition: a name in ``models/`` (e.g. ``"ti64_compressor_blade"``), a
        ``.toml`` file (:func:`~frictionjoint.structures.load_blade_model`) or the definition.
    speeds : str or (n,) array_like
        Rotor speeds ``Omega`` [rad/s], > 0 (the root carries no load at rest), increasing:
        ``"START:STOP:N"`` or the speeds themselves (:mod:`frictionjoint.frequencies`).
    engine_orders : sequence of float
        ``EO`` > 0 of the lines ``omega = EO Omega`` (usually whole numbers), distinct.
    n_modes : int
        Modes per limit, the lowest, >= 1.
    amplitude : float, optional
        First-harmonic amplitude [m] at ``dof`` of the nonlinear modes drawn between the limits;
        none if omitted.
    n_harmonics : int
        ``H`` of the nonlinear modes, >= 1 (module docstring: the default, 1, is the describing
        function's balance).
    dof : str, optional
        The DOF of ``amplitude``, a DOF of the assembly's structure; default the root's
        tangential DOF (``w0`` on a beam blade's dovetail), or where the root has none (a solid
        blade's patches) the DOF with the largest component of each stuck mode.
    reduction_modes : int, optional
        Fixed-interface modes of the Craig-Bampton blade (``from_model``'s ``n_modes``); default
        ``2 n_modes + 2`` (on the Ti-64 blade at 1000 rad/s with n_modes = 3: the stuck
        frequencies within 3.2e-7 of the unreduced blade's, the free-slip ones within 4.9e-5).
    progress : bool
        Show a progress bar over the speeds (tqdm, on stderr).

    Returns
    -------
    CampbellDiagram
    """
    definition, speeds, eos, n_modes, reduction, hh = _check_args(model, speeds, engine_orders, n_modes, amplitude,
                                                                   n_harmonics, reduction_modes)
    blade = _Blade(definition, n_modes, reduction, amplitude, dof, hh)
    blade.reduction_given = reduction_modes is not None
    if amplitude is not None and dof is None:  # a beam blade's DovetailRoot; else nonlinear_mode's default
        tangential = getattr(blade.assembly(speeds[0]).joints[0], "tangential_dof", None)
        blade.dof = None if tangential is None else str(tangential)
    curves, zeta = _curves(blade, speeds, progress)
    rows, missed = [], 0
    for limit, omega in curves.items():
        found, lost = _crossings(blade, limit, speeds, omega, eos)
        rows, missed = rows + found, missed + lost
    n_found = {limit: sum(r[0] == limit for r in rows) for limit in curves}
    message = (f"{definition.name}: {speeds.size} speeds from {speeds[0]:g} to {speeds[-1]:g} rad/s, "
               f"{n_modes} modes, engine orders {', '.join(f'{e:g}' for e in eos)}; crossings "
               + ", ".join(f"{n} {limit}" for limit, n in n_found.items())
               + f", each located by Brent's method to |dOmega| <= {XTOL:g} Omega"
               + (f"; {missed} sign changes of the nonlinear curves not located (the mode did not converge at a "
                  "trial speed)" if missed else ""))
    nl = curves.get("nonlinear")
    if nl is not None:
        ok = np.isfinite(nl)
        where = blade.dof or "each stuck mode's largest DOF"
        message += f"; nonlinear modes at {amplitude:g} m ({where}, H = {hh}): {int(ok.sum())} of {ok.size} converged"
    return CampbellDiagram(
        model=definition.name, speed=speeds, engine_orders=eos, stuck_frequency=curves["stuck"],
        slipping_frequency=curves["slipping"], crossings=crossing_table(rows), amplitude=amplitude,
        dof=blade.dof if amplitude is not None else None, n_harmonics=hh if amplitude is not None else None,
        nonlinear_frequency=nl, nonlinear_damping_ratio=zeta,
        nonlinear_converged=None if nl is None else np.isfinite(nl),
        design_speed=_design_speed(definition), message=message)


def _design_speed(model: BladeModel) -> float | None:
    """The definition's ``[rotor] speed`` [rad/s], or None."""
    speed = model.blade_parameters.get("rotor_speed")
    return None if speed is None else float(speed)


def _curves(blade: _Blade, speeds: np.ndarray, progress: bool) -> tuple[dict[str, np.ndarray], np.ndarray | None]:
    """Every mode's frequency at every speed, ``{'stuck', 'slipping'[, 'nonlinear']}`` each
    ``(n_speeds, n_modes)``, and the nonlinear modes' damping ratios (None without amplitude)."""
    from tqdm import tqdm

    n, k = speeds.size, blade.n_modes
    out = {"stuck": np.empty((n, k)), "slipping": np.empty((n, k))}
    zeta = None
    if blade.amplitude is not None:
        out["nonlinear"], zeta = np.full((n, k), math.nan), np.full((n, k), math.nan)
    for i, s in enumerate(tqdm(speeds, desc="campbell", unit="speed", file=sys.stderr, disable=not progress)):
        for name, w in blade.limits(s).items():
            out[name][i] = w
        if zeta is not None:
            for mode in range(k):
                out["nonlinear"][i, mode], zeta[i, mode] = blade.nonlinear(s, mode)
    return out, zeta


def _crossings(blade: _Blade, limit: str, speeds: np.ndarray, omega: np.ndarray,
               eos: np.ndarray) -> tuple[list[tuple], int]:
    """The crossings of the curves ``omega`` (``(n_speeds, n_modes)``) of ``limit`` with the
    engine-order lines, ``(limit, EO, mode, speed, frequency)`` each, the speed by Brent's
    method between the samples where ``omega_k - EO Omega`` changes sign; and how many sign
    changes were not located (a curve without a value at a trial speed)."""
    rows, missed = [], 0
    for eo in eos:
        g = omega - eo * speeds[:, None]
        for mode in range(blade.n_modes):
            for i in range(speeds.size):
                a = g[i, mode]
                if a == 0.0:  # on the line at a sample
                    rows.append((limit, float(eo), mode, float(speeds[i]), float(omega[i, mode])))
                    continue
                if i + 1 == speeds.size or not a * g[i + 1, mode] < 0.0:  # NaN: no bracket
                    continue
                try:
                    s = scipy.optimize.brentq(lambda x: blade.frequency(limit, mode, x) - eo * x, speeds[i],
                                              speeds[i + 1], xtol=XTOL * speeds[i + 1], rtol=4 * np.finfo(float).eps)
                    rows.append((limit, float(eo), mode, float(s), blade.frequency(limit, mode, s)))
                except _NoValue:
                    missed += 1
    return rows, missed
