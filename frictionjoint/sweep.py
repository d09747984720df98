"""Forced-response sweeps: stepped sine, up and down, with the analytic answer beside it.

At each frequency the periodic steady state is found by shooting
(:meth:`frictionjoint.CoulombOscillator.steady_state`), started from the orbit of the previous
frequency (its state at ``t = 0``), so that a sweep follows one branch of the response as a
slowly stepped experiment would (DESIGN.md section 6). Where Den Hartog's closed form is the
motion (undamped, stop-free; DESIGN.md section 3) it is reported beside the simulated
answer with the relative error; elsewhere the regime word says why it does not apply.

:class:`FrequencyResponse` holds only arrays and words, so that other sweeps (e.g. through
FMUs) can return the same type; the analytic columns are then simply absent (all masked).
"""
from __future__ import annotations

import math
import sys
import warnings
import os
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike

from .threads import owns_blas_threads
from .analytic import den_hartog_curve
from .errors import ParameterError, check_nonnegative, check_oscillator, check_real
from .frequencies import check_omegas
from .regime import classify
from .results.frequency import _HARMONIC_KEYS, FrequencyResponse, OutputSweep, SystemSweep, _masked, _wrap
from .system_sweeps import peak_response, system_sweep

if TYPE_CHECKING:  # the drivers (and the FMU layer) are imported when a sweep runs
    from .drivers import Driver


__all__ = ["sweep", "FrequencyResponse", "SystemSweep", "oscillator_sweep", "system_sweep", "peak_response",
           "den_hartog_curve", "DIRECTIONS", "METHODS"]

#: Allowed values of ``direction``.
DIRECTIONS = ("up", "down", "both")

# --------------------------------------------------------------------------- the sweep


def _steady_state(osc, state):
    """``osc.steady_state`` from ``state`` (or the default guess).

    A failed march (a status of the result) is retried from the default guess (with a
    warning), and if that fails too the point is reported as not converged (with a warning), so
    that one bad point does not lose a whole sweep.
    """
    starts = [state, None] if state is not None else [None]
    errors = []
    res = None
    for start in starts:
        x0, v0 = (None, None) if start is None else start
        res = osc.steady_state(x0=x0, v0=v0)
        if res.status != "failed":  # the march ran (converged or not)
            if errors:
                warnings.warn(f"omega = {osc.omega!r}: steady-state solver failed ({errors[0]}); "
                              "succeeded from the default estimate", RuntimeWarning, stacklevel=3)
            return res
        errors.append(res.message + ("" if start is None else f" (from x0={start[0]!r}, v0={start[1]!r})"))
    res.message = "steady-state solver failed: " + "; ".join(errors)
    res.status = "not converged"  # the regime of the point
    warnings.warn(f"omega = {osc.omega!r}: {res.message}", RuntimeWarning, stacklevel=3)
    return res


def oscillator_sweep(mass: float, stiffness: float, slip_force: float, force_amplitude: float,
                     omegas: ArrayLike, damping: float = 0.0, base_amplitude: float = 0.0,
                     direction: str = "up", progress: bool = False) -> FrequencyResponse:
    """Stepped-sine forced response of the single-DOF Coulomb oscillator.

    ``m x'' + c x' + k (x - Y cos(omega t)) + T = P cos(omega t)`` (see
    :class:`frictionjoint.CoulombOscillator`). The ``'up'`` branch visits ``omegas`` in
    ascending, the ``'down'`` branch in descending order; ``'both'`` runs up, then down,
    carrying the state over. Each point starts from the orbit of the previous one
    (``PeriodicResponse.initial_state``), or from the one-harmonic estimate after a point
    that did not converge. Den Hartog's closed form is evaluated at every point; it applies
    only without viscous damping and where the motion is stop-free.

    Parameters
    ----------
    mass : float
        Mass m [kg], > 0.
    stiffness : float
        Spring k [N/m], > 0.
    slip_force : float
        Friction limit F [N], >= 0.
    force_amplitude : float
        Force amplitude P [N].
    omegas : str or (n,) array_like
        Excitation angular frequencies [rad/s], each > 0 (any order; duplicates allowed):
        ``"START:STOP:N"`` or the frequencies themselves (:mod:`frictionjoint.frequencies`; a list
        or tuple of three numbers whose last is whole, ``(0.5, 2.5, 60)``, is refused as ambiguous).
    damping : float
        Viscous damping c [N s/m], >= 0.
    base_amplitude : float
        Base motion amplitude Y [m]; ``P + k Y`` must not be 0.
    direction : {'up', 'down', 'both'}
        Sweep direction.
    progress : bool
        Show a progress bar (tqdm, on stderr).

    Returns
    -------
    FrequencyResponse
        ``2 n`` points for ``'both'``, else ``n``.

    Raises
    ------
    ParameterError
        If an argument is out of range (the message names it).

    See Also
    --------
    sweep : the one entry point (``sweep("CoulombOscillator", omegas, parameters)`` gives the same
        points, each checked over one more period through the stepping interface; FMUs, drivers
        and multi-DOF systems too). This function keeps the oscillator's parameters as arguments
        and solves each point with :meth:`frictionjoint.CoulombOscillator.steady_state`.
    """
    from .oscillator import CoulombOscillator

    params, c, ws = _check_sweep(mass, stiffness, slip_force, force_amplitude, damping, base_amplitude,
                                 omegas, direction, progress)

    def solve(w, state):
        osc = CoulombOscillator(omega=float(w), damping=c, **params)
        return _steady_state(osc, state)

    return _run_sweep(params, c, ws, direction, progress, solve)


def _check_sweep(mass, stiffness, slip_force, force_amplitude, damping, base_amplitude, omegas, direction,
                 progress):
    """Validate the arguments every oscillator sweep takes; return ``(params, damping, omegas)``."""
    m, k, fr, p, y, _ = check_oscillator(mass, stiffness, slip_force, force_amplitude, base_amplitude)
    c = check_nonnegative("damping", damping)
    ws = check_omegas("omegas", omegas)
    if direction not in DIRECTIONS:
        raise ParameterError(f"direction must be one of {DIRECTIONS}, got {direction!r}")
    if not isinstance(progress, (bool, np.bool_)):
        raise ParameterError(f"progress must be True or False, got {progress!r}")
    return dict(mass=m, stiffness=k, slip_force=fr, force_amplitude=p, base_amplitude=y), c, ws


def _run_sweep(params: dict, c: float, ws, direction: str, progress: bool, solve) -> FrequencyResponse:
    """The stepped-sine loop shared by every sweep: ``solve(omega, state)`` returns a
    :class:`~frictionjoint.results.PeriodicResponse` started from ``state`` (the previous orbit's
    ``(x0, v0)`` at ``t = 0``, or ``None``)."""
    m, k = params["mass"], params["stiffness"]
    up = np.sort(ws)
    plan = []
    if direction in ("up", "both"):
        plan += [("up", w) for w in up]
    if direction in ("down", "both"):
        plan += [("down", w) for w in up[::-1]]

    analytic = {}
    if c == 0.0:
        amp_ref, ph_ref, reg_ref = den_hartog_curve(up, **params)
        for i, w in enumerate(up):
            analytic[float(w)] = (None if amp_ref.mask[i] else float(amp_ref[i]),
                                  None if ph_ref.mask[i] else float(ph_ref[i]), str(reg_ref[i]))

    from tqdm import tqdm

    rows = []
    state = None
    wn = math.sqrt(k / m)
    with tqdm(total=len(plan), desc="sweep", unit="pt", file=sys.stderr, disable=not progress,
              leave=False) as bar:
        for branch, w in plan:
            ss = solve(float(w), state)
            ok = ss.converged and ss.initial_state is not None and np.all(np.isfinite(ss.initial_state[:2]))
            state = (float(ss.initial_state[0]), float(ss.initial_state[1])) if ok else None
            ref_amp, ref_ph, ref_reg = analytic.get(float(w), (None, None, "damped"))
            amp_err = ph_err = None
            if ref_amp is not None and ss.converged:
                amp_err = abs(ss.amplitude - ref_amp) / ref_amp
                ph_err = abs(float(_wrap(ss.phase - ref_ph))) / abs(ref_ph) if ref_ph != 0 else None
            rows.append((branch, float(w), ss, classify(ss), ref_amp, ref_ph,
                         ref_reg, amp_err, ph_err))
            bar.set_postfix_str(f"{branch} r={w / wn:.3f}", refresh=False)
            bar.update()

    def arr(fn, dtype=float):
        return np.array([fn(row) for row in rows], dtype=dtype)

    harmonics = {}
    for name in (rows[0][2].harmonics or {}) if rows else {}:
        harmonics[name] = {key: arr(lambda r, key=key: (r[2].harmonics or {}).get(name, {}).get(key, np.nan))
                           for key in _HARMONIC_KEYS}
    return FrequencyResponse(
        omega=arr(lambda r: r[1]),
        amplitude=arr(lambda r: r[2].amplitude),
        phase=arr(lambda r: r[2].phase),
        harmonic_amplitude=arr(lambda r: r[2].harmonic_amplitude),
        stops_per_cycle=arr(lambda r: r[2].stops_per_cycle, int),
        stuck=arr(lambda r: r[2].stuck, bool),
        converged=arr(lambda r: r[2].converged, bool),
        unique=arr(lambda r: r[2].unique, bool),
        regime=arr(lambda r: r[3], object).astype(str),
        branch=arr(lambda r: r[0], object).astype(str),
        periods=arr(lambda r: r[2].periods),
        messages=tuple(r[2].message for r in rows),
        analytic_amplitude=_masked([r[4] for r in rows]),
        analytic_phase=_masked([r[5] for r in rows]),
        analytic_regime=arr(lambda r: r[6], object).astype(str),
        amplitude_error=_masked([r[7] for r in rows]),
        phase_error=_masked([r[8] for r in rows]),
        natural_frequency=wn,
        analytic_name="Den Hartog",
        parameters=dict(params, damping=c),
        harmonics=harmonics,
    )


#: sweep methods: the steady state at each point found in the time domain (exact piecewise
#: solution, shooting), or the harmonic-balance branch ('hbm', blade model definitions)
METHODS = ("time", "hbm")


@owns_blas_threads
def sweep(model: str | os.PathLike | Driver | Callable, omegas: ArrayLike, parameters: dict | None = None,
          direction: str = "up", outputs: Sequence[str] = ("x",), n_samples: int = 256, progress: bool = False,
          method: str = "time", n_harmonics: int = 7,
          check: bool = False) -> FrequencyResponse | SystemSweep | OutputSweep:
    """Stepped-sine sweep: the one entry point for the library's models, FMUs and drivers.

    ``model`` says what is swept:

    - ``"CoulombOscillator"``: the library's single-DOF oscillator, stepped in the library
      (:class:`~frictionjoint.drivers.LibraryDriver`);
    - a ``.fmu`` file with the variables of ``CoulombOscillator.fmu``: through fmpy
      (:class:`~frictionjoint.fmi.driver.FMUDriver`);
    - any :class:`~frictionjoint.drivers.Driver` (a stepping oscillator of the user's);
    - a callable ``build(omega) -> FrictionSystem``: a multi-DOF system
      (:func:`system_sweep`; returns a :class:`~frictionjoint.results.SystemSweep`);
    - a blade model definition (a name in ``models/``, e.g. ``"ti64_compressor_blade"``, or a
      ``.toml`` path; :func:`~frictionjoint.structures.load_blade_model`): the Craig-Bampton blade
      on its dovetail root (:meth:`BladeAssembly.from_model
      <frictionjoint.structures.BladeAssembly.from_model>`), its tip (or ``outputs[0]``, a DOF of
      the full model) with the root's two linear limits (returns an
      :class:`~frictionjoint.results.OutputSweep`); ``parameters`` are the root's
      (:class:`~frictionjoint.elements.DovetailRoot` arguments, e.g. ``centrifugal_force``,
      ``friction_coefficient``) and ``tip_force_amplitude`` [N];
    - a :class:`~frictionjoint.structures.BladeAssembly`: as a blade model definition.

    The oscillator sweeps run one algorithm (:func:`frictionjoint.drivers.shoot`): the driver
    starts on the orbit where it can (the closed-form kernel's shooting with its exact Jacobian,
    checked over one communication step of a period), otherwise shooting on ``(x0, v0)`` through
    the driver; the state is carried from point to point; first harmonics of ``x`` and the
    friction force are integrated exactly (other outputs from ``n_samples`` points per period).

    Parameters
    ----------
    model : str, path, Driver or callable
        What is swept (see above).
    omegas : str or (n,) array_like
        Angular frequencies [rad/s], > 0: ``"START:STOP:N"`` (``N`` equally spaced from ``START`` to
        ``STOP``; :func:`~frictionjoint.frequencies.omega_range` builds the same array) or the
        frequencies themselves, as everywhere in the package (:mod:`frictionjoint.frequencies`). A
        list or tuple of three numbers whose last is whole, ``(0.5, 2.5, 60)``, could be either and
        is refused with a :class:`~frictionjoint.errors.ParameterError` that shows both forms.
    parameters : dict, optional
        Oscillator parameters (``mass``, ``stiffness``, ``damping``, ``slip_force``,
        ``force_amplitude``, ``base_amplitude``); ``omega``, ``x0``, ``v0`` are set by the sweep.
        Not for a ``build`` callable.
    direction : {'up', 'down', 'both'}
        ``'up'`` only for a ``build`` callable (its points in the given order).
    outputs : sequence of str
        Outputs whose first harmonic and peak are reported in ``FrequencyResponse.harmonics``.
    n_samples : int
        Samples per period for the first harmonics of outputs other than ``x`` and
        ``friction_force`` (those are integrated exactly, piece by piece), >= 16.
    progress : bool
        Show a progress bar (tqdm, on stderr).
    method : {'time', 'hbm'}
        How each steady state is found (:data:`METHODS`): ``'hbm'`` (blade model definitions) is the
        harmonic-balance branch from the first to the last of ``omegas`` by pseudo-arclength
        continuation (:meth:`BladeAssembly.frequency_response
        <frictionjoint.structures.BladeAssembly.frequency_response>`).
    n_harmonics : int
        Harmonics of ``'hbm'``, >= 1.
    check : bool
        ``'hbm'``: check every branch point against the exact orbit started from it, its truncation
        error and stability (the time-domain sweeps of blades and systems judge every orbit's
        stability anyway).

    Returns
    -------
    FrequencyResponse, SystemSweep or OutputSweep
    """
    from .drivers import Driver
    from .structures import BladeAssembly

    _check_method(model, method, check)
    if isinstance(model, type):
        raise ParameterError(f"model must be a Driver instance, not the class {model.__name__}")
    if isinstance(model, BladeAssembly):  # a blade assembly of the library: as a model definition
        return _blade_sweep(model, omegas, parameters, direction, outputs, progress, method, n_harmonics, check)
    if callable(model) and not isinstance(model, Driver):
        if parameters or direction != "up" or tuple(outputs) != ("x",):
            raise ParameterError("a build(omega) -> FrictionSystem sweep takes no parameters, outputs or "
                                 "direction (the system is built at each omega, in the given order)")
        return system_sweep(model, omegas, progress=progress)
    driver = model if isinstance(model, Driver) else None
    if driver is None and not isinstance(model, (str, os.PathLike)):
        raise ParameterError(f"model must be 'CoulombOscillator', a .fmu file, a blade model, a Driver or a "
                             f"build(omega) callable, got {model!r}")
    if driver is None and _is_blade_fmu(model):
        return _blade_fmu_sweep(model, omegas, parameters, direction, outputs, progress)
    if driver is None and str(model) != "CoulombOscillator" and not (Path(model).suffix == ".fmu"
                                                                     and Path(model).is_file()):
        blade = _blade_definition(model)
        if blade is None:
            raise model_not_found(model)
        return _blade_sweep(blade, omegas, parameters, direction, outputs, progress, method, n_harmonics, check)
    return _oscillator_driver_sweep(model, driver, omegas, parameters, direction, outputs, n_samples, progress)


def _check_method(model, method, check) -> None:
    """Refuse a ``method`` or ``check`` of :func:`sweep` that ``model`` does not take."""
    from .drivers import Driver
    from .structures import BladeAssembly

    if method not in METHODS:
        raise ParameterError(f"method must be one of {METHODS}, got {method!r}")
    if method == "hbm" and not isinstance(model, BladeAssembly) and (
            isinstance(model, Driver) or callable(model) or _blade_definition(model) is None):
        raise ParameterError("method 'hbm' is for blade model definitions (the oscillator and FMU sweeps are "
                             "in the time domain; for a FrictionSystem use frictionjoint.hbm_sweep)")
    if check not in (True, False):
        raise ParameterError(f"check must be True or False, got {check!r}")
    if check and method != "hbm":
        raise ParameterError("check=True is for method 'hbm' (the time domain is exact and judges every orbit's "
                             "stability anyway)")


def _oscillator_driver_sweep(model, driver, omegas, parameters, direction, outputs, n_samples,
                             progress) -> FrequencyResponse:
    """:func:`sweep` of the Coulomb oscillator through a driver: ``driver``, or the library's
    (``model`` ``"CoulombOscillator"``) or an oscillator FMU's (``model`` its path) made and closed
    here; each point by :func:`~frictionjoint.drivers.shoot`."""
    from .drivers import FMUDriver, LibraryDriver, shoot
    from .stepping import OSCILLATOR_OUTPUTS, OSCILLATOR_PARAMETERS

    params = dict(parameters or {})
    allowed = set(OSCILLATOR_PARAMETERS) - {"omega", "x0", "v0", "harmonics"}
    unknown = set(params) - allowed
    if unknown:
        raise ParameterError(f"parameters must be among {sorted(allowed)}, got {sorted(unknown)}")
    full = {k: v[0] for k, v in OSCILLATOR_PARAMETERS.items() if k in allowed}
    full.update(params)
    base, c, ws = _check_sweep(full["mass"], full["stiffness"], full["slip_force"], full["force_amplitude"],
                               full["damping"], full["base_amplitude"], omegas, direction, progress)
    outputs = tuple(outputs)
    bad = [o for o in outputs if o not in OSCILLATOR_OUTPUTS]
    if bad:
        raise ParameterError(f"outputs must be among {sorted(OSCILLATOR_OUTPUTS)}, got {bad}")
    if isinstance(n_samples, bool) or not isinstance(n_samples, (int, np.integer)) or n_samples < 16:
        raise ParameterError(f"n_samples must be an integer >= 16, got {n_samples!r}")
    own = driver is None
    if own:
        driver = LibraryDriver() if str(model) == "CoulombOscillator" else FMUDriver(model)
    try:
        return _run_sweep(base, c, ws, direction, progress,
                          lambda w, st: shoot(driver, dict(base, damping=c, omega=w), st, outputs=outputs,
                                              n_samples=int(n_samples)))
    finally:
        if own:  # a driver given by the caller stays the caller's
            driver.close()


def _blade_definition(model):
    """The blade model definition ``model`` names (a ``.toml`` file, or a name in ``models/`` with or
    without ``.toml``), or None if it names none (a ``.fmu`` path never names one, found or not)."""
    from .structures import load_blade_model
    from .structures.models import blade_model_names

    if not isinstance(model, (str, os.PathLike)):
        return None
    path = Path(model)
    if path.suffix not in ("", ".toml"):
        return None
    if (path.suffix == ".toml" and path.is_file()) or path.stem in blade_model_names():
        return load_blade_model(model)
    return None


def model_not_found(model) -> ParameterError:
    """The error for a ``model`` that names nothing :func:`sweep` can run: says "not found" and
    lists what it takes, the blade models of ``models/`` by name."""
    from .structures.models import MODELS_DIR, blade_model_names

    path = Path(model)
    what = {".fmu": "FMU file ", ".toml": "blade model file "}.get(path.suffix, "")
    names = blade_model_names()
    other = MODELS_DIR / f"{path.stem}.toml"
    found = (f"{other.name} in {MODELS_DIR} is no blade model (no [blade] table)" if path.suffix in ("", ".toml")
             and other.is_file() else f"{what}{str(model)!r} not found")
    return ParameterError(
        f"model: {found}; a sweep takes 'CoulombOscillator', an existing .fmu file "
        f"(built by 'frictionjoint build-fmus', e.g. build/CoulombOscillator.fmu), a blade model of "
        f"{MODELS_DIR} ({', '.join(names) if names else 'none there'}) or a blade model .toml file (in Python "
        "also a Driver or a build(omega) callable)")


#: the parameters of a blade model definition that a sweep's ``parameters`` (and the CLI's ``--set``)
#: set by value: the root's numbers and switch (:class:`~frictionjoint.elements.DovetailRoot`; its DOF
#: names and contact law are the definition's) and the tip force
BLADE_SETTINGS = ("centrifugal_force", "friction_coefficient", "flank_angle", "normal_stiffness",
                  "tangential_stiffness", "flank_half_width", "normal_damping", "normal_load_variation",
                  "tip_force_amplitude")


def blade_assembly(model, parameters: dict | None = None):
    """The blade of a model definition (a name in ``models/``, a ``.toml`` path or a loaded
    :class:`~frictionjoint.structures.BladeModel`) or an assembly,
    with ``parameters``: its root's (:meth:`BladeAssembly.with_root
    <frictionjoint.structures.BladeAssembly.with_root>`) and ``tip_force_amplitude`` [N].

    Returns
    -------
    BladeAssembly
    """
    from .structures import BladeAssembly, load_blade_model

    params = dict(parameters or {})
    tip_force = params.pop("tip_force_amplitude", None)
    if isinstance(model, (str, os.PathLike)):
        model = load_blade_model(model)
    asm = model if isinstance(model, BladeAssembly) else BladeAssembly.from_model(model)
    if params:
        asm = asm.with_root(**params)
    if tip_force is not None:
        asm = BladeAssembly(asm.structure, asm.joints, {asm.tip: check_real("tip_force_amplitude", tip_force)})
    return asm


def _blade_sweep(definition, omegas, parameters, direction, outputs, progress, method="time",
                 n_harmonics=7, check=False) -> OutputSweep:
    """:func:`sweep` of a blade model definition (see there)."""
    if direction not in ("up", "down"):
        raise ParameterError(f"direction must be 'up' or 'down' for a blade model, got {direction!r}")
    outputs = tuple(outputs)
    if len(outputs) != 1:
        raise ParameterError(f"outputs: one output DOF for a blade model (default its tip), got {outputs!r}")
    asm = blade_assembly(definition, parameters)
    ws = check_omegas("omegas", omegas)
    ws = np.sort(ws) if direction == "up" else np.sort(ws)[::-1]
    return asm.frequency_response(ws, dof=None if outputs == ("x",) else outputs[0], progress=progress,
                                  method=method, n_harmonics=n_harmonics, check=check)


#: variables that make an FMU a blade FMU for :func:`sweep` (those of BladeDovetail.fmu)
BLADE_FMU_VARIABLES = ("omega", "start_on_orbit", "orbit_found", "tip_displacement", "tip_velocity",
                       "tip_cos_integral", "tip_sin_integral", "dissipated_energy")


def _is_blade_fmu(model) -> bool:
    if not isinstance(model, (str, os.PathLike)) or Path(model).suffix != ".fmu" or not Path(model).is_file():
        return False
    from fmpy import read_model_description

    try:
        names = {v.name for v in read_model_description(str(model)).modelVariables}
    except Exception:  # noqa: BLE001 -- not readable: the oscillator path reports it
        return False
    return set(BLADE_FMU_VARIABLES) <= names


def _blade_fmu_sweep(path, omegas, parameters, direction, outputs, progress) -> OutputSweep:
    """:func:`sweep` of ``BladeDovetail.fmu`` through fmpy: per frequency one (re)initialisation
    that starts on the periodic orbit (the FMU's shooting, from the previous point's orbit where the
    FMU has ``start_from_last_orbit``, as the library's sweep), then one communication step of a
    period, in which the FMU integrates the tip's first harmonic exactly; the orbit is accepted
    when the tip's displacement and velocity come back to their start values to 1e-8 of the
    harmonic (the FMU's own check of periodicity, through the FMI interface only)."""
    from tqdm import tqdm

    from .fmi.master import FMUInstance

    if direction not in ("up", "down"):
        raise ParameterError(f"direction must be 'up' or 'down' for a blade FMU, got {direction!r}")
    if tuple(outputs) != ("x",):
        raise ParameterError("outputs: a blade FMU sweep reports its tip (outputs takes no other)")
    ws = check_omegas("omegas", omegas)
    ws = np.sort(ws) if direction == "up" else np.sort(ws)[::-1]
    inst = FMUInstance(path)
    try:
        continued = "start_from_last_orbit" in inst.vr  # (an FMU built before it starts from rest)
        params = _fmu_parameters(inst, path, parameters,
                                 sweeps=("omega", "start_on_orbit") + (("start_from_last_orbit",) if continued else ()))
        if continued:
            params["start_from_last_orbit"] = True
        response, converged, diss, messages = [], [], [], []
        for w in tqdm(ws, desc="sweep", unit="pt", file=sys.stderr, disable=not progress, leave=False):
            inst.initialize(dict(params, omega=float(w), start_on_orbit=True))
            found, x0, v0 = inst.get(["orbit_found", "tip_displacement", "tip_velocity"])
            period = 2 * math.pi / w
            inst.step_to(period)
            xc, xs, e, x1, v1 = inst.get(["tip_cos_integral", "tip_sin_integral", "dissipated_energy",
                                          "tip_displacement", "tip_velocity"])
            x = (xc - 1j * xs) * (2 / period)
            closed = abs(x1 - x0) <= 1e-8 * abs(x) and abs(v1 - v0) <= 1e-8 * w * abs(x)
            ok = bool(found) and closed
            response.append(x)
            converged.append(ok)
            diss.append(e)
            messages.append("periodic orbit (FMU)" if ok else "no periodic orbit found by the FMU" if not found
                            else f"the FMU's orbit does not close over a period ({abs(x1 - x0):.3g} m)")
    finally:
        inst.close()
    diss = np.array(diss)
    return OutputSweep(omega=ws, output="tip", response=np.array(response), limits={}, stuck=diss == 0.0,
                       converged=np.array(converged), dissipated_per_cycle=diss, messages=tuple(messages))


def _fmu_parameters(inst, path, parameters, sweeps) -> dict:
    """``parameters`` checked against the FMU's parameters (but ``sweeps``, which the sweep sets)
    and converted to each variable's type: a Boolean from any way of writing a switch
    (:func:`~frictionjoint.errors.check_bool`: ``True``, ``1``, ``'true'``, ...), an Integer from a
    whole number, a Real from a real number -- never a silent ``bool(0.5)`` or ``int(5.5)``."""
    settable = sorted(v.name for v in inst.model.modelVariables  # read when the instance was made
                      if v.causality == "parameter" and v.name not in sweeps)
    params = dict(parameters or {})
    unknown = sorted(k for k in params if k not in settable)
    if unknown:
        raise ParameterError(f"parameters: {unknown} are not parameters of {Path(path).name} that a sweep sets; "
                             f"allowed: {settable} ({' and '.join(sweeps)} are the sweep's)")
    return {name: inst.convert(name, value) for name, value in params.items()}
