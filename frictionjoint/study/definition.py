"""A design study: one model, fixed parameters, varied ones (grids, lists, random samples), one
frequency sweep per point. Defined in Python (:class:`Study`) or in a TOML file
(:func:`load_study`); its points are fixed by the definition alone (random samples from the
seeded generator), so a point's inputs are the same bits on any worker and in any session.

TOML form::

    model = "ti64_compressor_blade"      # a models/ definition, a .toml path or a blade .fmu
    table = "damper_curve.csv"           # optional; .csv or .parquet, in the working directory

    [fixed]                              # parameters of every point
    tip_force_amplitude = 1.0

    [vary.centrifugal_force]             # a grid: start, stop, num (spacing "linear" or "log")
    start = 20.0
    stop = 2000.0
    num = 12
    spacing = "log"

    [vary.flank_angle]                   # a list
    values = [0.6, 0.7]

    [vary.friction_coefficient]          # random: a scipy.stats distribution and its parameters
    distribution = "uniform"
    loc = 0.2
    scale = 0.3

    [samples]                            # random parameters: n samples from this seed
    n = 100
    seed = 1

    [sweep]
    omega = "1950:2100:40"               # START:STOP:N [rad/s], or the list of frequencies
    direction = "up"
    method = "time"                      # or "hbm"
    harmonics = 7                        # of "hbm"
    refine_peak = true                   # a blade's peak refined between the sweep's points
    time_limit = 600.0                   # [s] per point (default 600): then a failed row

    [quantities]                         # optional: the root damping at a vibration level
    mode_damping = {mode = 0, amplitude = 1e-5, n_harmonics = 7, dof = "w0"}

The points are the Cartesian product of the grids and lists, times the ``n`` random samples
(drawn once, the same for every grid point).

A relative ``model`` path is taken from the study file's folder (an input beside it); the table
is an output, written where the study runs: a relative ``table`` (default the file's name with
``.csv``) is taken from the working directory, never from the file's folder (running an example
does not write into the source tree).

The frequencies follow the one convention of :mod:`frictionjoint.frequencies` (``"START:STOP:N"``
or the frequencies themselves; ``[1950.0, 2100.0, 40]`` could mean either and is refused). A
definition is checked whole when it is loaded, before any point runs: the model exists, every
fixed and varied parameter is one of the model's (a switch such as ``normal_load_variation`` takes
``true``/``false`` or 1/0), fixed values are finite, and the number of points, counted from the
grids' sizes before any is built, is at most :data:`MAX_POINTS`.

``[quantities] mode_damping`` (:class:`ModeDamping`) adds, to every point's row, its blade's
nonlinear mode at a first-harmonic amplitude: frequency and damping ratio
(:func:`~frictionjoint.study.point.mode_quantities`), so that a study maps the root's damping
over the root's parameters. The sweep's columns stay.
"""
from __future__ import annotations

import functools
import hashlib
import itertools
import json
import math
import os
import pickle
from dataclasses import dataclass, field
from numbers import Integral, Real
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ParameterError, check_bool
from ..frequencies import FORM, check_omegas

__all__ = ["Grid", "Values", "Random", "ModeDamping", "Study", "load_study", "MAX_POINTS", "DEFAULT_TIME_LIMIT",
           "model_parameters", "check_mode_declaration"]

SPACINGS = ("linear", "log")
METHODS = ("time", "hbm")
#: the most points of one study: counted from the grids' sizes before any point is built (a table
#: of more rows is a typing error or a study to split; its points alone would fill the memory)
MAX_POINTS = 100_000
#: a point's default time limit [s] (``[sweep] time_limit``): a point that has not finished by then
#: is a failed row saying so
DEFAULT_TIME_LIMIT = 600.0


def _count(name: str, value, low: int = 1) -> int:
    if isinstance(value, bool) or not isinstance(value, (Integral, np.integer)) or value < low:
        raise ParameterError(f"{name} must be an integer >= {low}, got {value!r}")
    return int(value)


@dataclass(frozen=True)
class Grid:
    """``num`` values from ``start`` to ``stop`` (both included), evenly spaced (``'linear'``) or
    evenly in the logarithm (``'log'``, positive ends)."""

    start: float
    stop: float
    num: int
    spacing: str = "linear"

    def size(self, name: str) -> int:
        """The number of values (checked, without building them)."""
        n = _count(f"vary.{name}.num", self.num)
        if n > MAX_POINTS:
            raise ParameterError(f"vary.{name}.num must be <= {MAX_POINTS} (the most points of a study), got {n}")
        try:
            a, b = float(self.start), float(self.stop)
        except (TypeError, ValueError):
            raise ParameterError(f"vary.{name}: start and stop must be numbers, got {self.start!r}, {self.stop!r}") from None
        if not (math.isfinite(a) and math.isfinite(b)):
            raise ParameterError(f"vary.{name}: start and stop must be finite, got {a!r}, {b!r}")
        if self.spacing not in SPACINGS:
            raise ParameterError(f"vary.{name}.spacing must be one of {SPACINGS}, got {self.spacing!r}")
        if self.spacing == "log" and (a <= 0 or b <= 0):
            raise ParameterError(f"vary.{name}: a log grid needs start and stop > 0, got {a!r}, {b!r}")
        return n

    def values(self, name: str) -> np.ndarray:
        n = self.size(name)
        a, b = float(self.start), float(self.stop)
        return np.geomspace(a, b, n) if self.spacing == "log" else np.linspace(a, b, n)


@dataclass(frozen=True)
class Values:
    """An explicit list of values."""

    values_: tuple

    def size(self, name: str) -> int:
        """The number of values (checked)."""
        return int(self.values(name).size)

    def values(self, name: str) -> np.ndarray:
        if len(self.values_) == 0:
            raise ParameterError(f"vary.{name}.values must not be empty")
        try:
            v = np.array(self.values_, dtype=float)
        except (TypeError, ValueError):
            raise ParameterError(f"vary.{name}.values must be numbers, got {list(self.values_)!r}") from None
        if v.ndim != 1 or not np.all(np.isfinite(v)):
            raise ParameterError(f"vary.{name}.values must be finite numbers, got {list(self.values_)!r}")
        if v.size > MAX_POINTS:
            raise ParameterError(f"vary.{name}.values: at most {MAX_POINTS} values, got {v.size}")
        return v


@dataclass(frozen=True)
class Random:
    """A random parameter: ``scipy.stats.<distribution>(**parameters)`` (e.g. ``'uniform'`` with
    ``loc``, ``scale``; ``'norm'`` with ``loc``, ``scale``; ``'lognorm'`` with ``s``, ``scale``;
    ``'truncnorm'`` with ``a``, ``b``, ``loc``, ``scale``)."""

    distribution: str
    parameters: tuple = ()

    def frozen(self, name: str):
        import scipy.stats

        dist = getattr(scipy.stats, str(self.distribution), None)
        if not isinstance(dist, scipy.stats.rv_continuous):
            raise ParameterError(f"vary.{name}.distribution must name a continuous scipy.stats distribution "
                                 f"(e.g. 'uniform', 'norm', 'lognorm', 'truncnorm'), got {self.distribution!r}")
        try:
            frozen = dist(**dict(self.parameters))
            median = float(frozen.median())  # NaN for parameters outside the distribution's range
        except (TypeError, ValueError) as exc:
            raise ParameterError(f"vary.{name}: bad parameters {dict(self.parameters)!r} for "
                                 f"{self.distribution!r}: {exc}") from None
        if not math.isfinite(median):
            raise ParameterError(f"vary.{name}: parameters {dict(self.parameters)!r} are outside the range of "
                                 f"{self.distribution!r} (e.g. scale must be > 0)")
        return frozen


@dataclass(frozen=True)
class ModeDamping:
    """The nonlinear mode a study evaluates at every point (``[quantities] mode_damping``): the
    columns ``mode_frequency`` [rad/s] and ``mode_damping_ratio`` of the blade's mode ``mode`` at
    the first-harmonic amplitude ``amplitude`` [m] of ``dof``, with ``n_harmonics`` harmonics
    (:func:`~frictionjoint.study.point.mode_quantities`; the same as
    ``fj.nonlinear_mode(system, mode, amplitudes=mode_amplitudes(amplitude), n_harmonics, dof)``
    at its last amplitude).

    Parameters
    ----------
    amplitude : float
        [m], finite and > 0.
    mode : int
        The stuck blade's mode, from 0.
    n_harmonics : int
        ``H`` >= 1.
    dof : str, optional
        A DOF of the blade's (reduced) structure; default the root's tangential DOF (``'w0'`` on a
        :class:`~frictionjoint.elements.DovetailRoot`), the same at every point.
    """

    amplitude: float
    mode: int = 0
    n_harmonics: int = 7
    dof: Any = None

    #: the keys of ``[quantities] mode_damping``
    KEYS = ("amplitude", "mode", "n_harmonics", "dof")

    def __post_init__(self):
        where = "quantities.mode_damping"
        a = self.amplitude
        if isinstance(a, bool) or not isinstance(a, (Real, np.number)) or not (math.isfinite(a) and a > 0):
            raise ParameterError(f"{where}.amplitude must be a finite amplitude > 0 [m], got {a!r}")
        object.__setattr__(self, "amplitude", float(a))
        object.__setattr__(self, "mode", _count(f"{where}.mode", self.mode, 0))
        object.__setattr__(self, "n_harmonics", _count(f"{where}.n_harmonics", self.n_harmonics))
        if self.dof is not None and not isinstance(self.dof, str):
            raise ParameterError(f"{where}.dof must be the name of a DOF of the blade (e.g. 'w0'), got {self.dof!r}")

    @classmethod
    def from_table(cls, entry) -> "ModeDamping":
        """The declaration of a study file's ``mode_damping`` table (its keys :attr:`KEYS`)."""
        if isinstance(entry, ModeDamping):
            return entry
        if not isinstance(entry, dict):
            raise ParameterError(f"quantities.mode_damping must be a table {{amplitude = ..., mode = 0, n_harmonics "
                                 f"= 7, dof = 'w0'}}, got {entry!r}")
        unknown = set(entry) - set(cls.KEYS)
        if unknown or "amplitude" not in entry:
            what = f"unknown keys {sorted(unknown)}" if unknown else "amplitude is missing"
            raise ParameterError(f"quantities.mode_damping: {what} (its keys: {list(cls.KEYS)}, amplitude required)")
        return cls(**entry)

    def key(self) -> list:
        """The declaration in a study's fingerprint."""
        return [repr(self.amplitude), self.mode, self.n_harmonics, self.dof]


#: the kinds of a parameter's value: a real number, a whole number or a switch
KINDS = ("real", "int", "bool")


def _root_parameters() -> dict:
    """The parameters of a blade definition a study sets (:data:`frictionjoint.sweep.BLADE_SETTINGS`:
    the root's numbers and switch, the tip force), with their kinds (a switch from
    :class:`~frictionjoint.elements.DovetailRoot`'s signature)."""
    import inspect

    from ..elements import DovetailRoot
    from ..sweep import BLADE_SETTINGS

    sig = inspect.signature(DovetailRoot.__init__).parameters
    return {name: "bool" if name in sig and str(sig[name].annotation) in ("bool", "<class 'bool'>") else "real"
            for name in BLADE_SETTINGS}


#: why a study refuses a model that is not a blade (its quantities are a blade's: the tip's first
#: harmonic, the root's dissipation and slip state)
_NOT_A_BLADE = ("a study's model is a blade (its rows are the tip's first harmonic and the root's dissipation); "
                "sweep the Coulomb oscillator with frictionjoint.sweep or 'frictionjoint sweep'")


def _fmu_parameters(path: Path) -> dict:
    """The parameters of a blade FMU a study sets (its parameter variables but ``omega`` and
    ``start_on_orbit``, the sweep's)."""
    from fmpy import read_model_description

    from ..sweep import BLADE_FMU_VARIABLES

    try:
        variables = read_model_description(str(path)).modelVariables
    except Exception as exc:  # noqa: BLE001 - any unreadable FMU: the model is refused with the reason
        raise ParameterError(f"model: {str(path)!r} is not a readable FMU ({type(exc).__name__}: {exc})") from None
    if not set(BLADE_FMU_VARIABLES) <= {v.name for v in variables}:
        raise ParameterError(f"model: {path.name} is not a blade FMU (BladeDovetail.fmu): {_NOT_A_BLADE}")
    kinds = {"Real": "real", "Integer": "int", "Boolean": "bool"}
    return {v.name: kinds.get(v.type, "real") for v in variables
            if v.causality == "parameter" and v.name not in ("omega", "start_on_orbit")}


def model_parameters(model) -> dict:
    """The parameters a study of ``model`` may fix or vary, ``{name: kind}`` (kind in
    :data:`KINDS`); checks that the model exists.

    Parameters
    ----------
    model : str, os.PathLike or BladeAssembly
        A blade definition (a name in ``models/`` or a ``.toml`` path), a blade FMU
        (``BladeDovetail.fmu``) or a :class:`~frictionjoint.structures.BladeAssembly`.

    Raises
    ------
    ParameterError
        The model names nothing (the message lists the models), or cannot be read.
    """
    from ..structures import BladeAssembly
    from ..structures.models import blade_model_names

    if isinstance(model, BladeAssembly):
        if len(model.joints) != 1 or not hasattr(model.joints[0], "replace"):
            raise ParameterError("model: a study varies the root of an assembly with one DovetailRoot joint")
        return _root_parameters()
    if not isinstance(model, (str, os.PathLike)):
        raise ParameterError(f"model must be a model name, a .toml or .fmu path or a BladeAssembly, got "
                             f"{type(model).__name__}")
    if str(model) == "CoulombOscillator":
        raise ParameterError(f"model 'CoulombOscillator': {_NOT_A_BLADE}")
    path = Path(model)
    if path.suffix == ".fmu":
        if not path.is_file():
            raise ParameterError(f"model: FMU {str(model)!r} not found")
        return _fmu_parameters(path)
    from ..sweep import _blade_definition

    try:
        definition = _blade_definition(model)
    except ParameterError as exc:
        raise ParameterError(f"model {str(model)!r}: {exc}") from None
    if definition is None:
        where = "file not found" if path.suffix == ".toml" else "not found"
        raise ParameterError(f"model {str(model)!r}: {where}; the models are {blade_model_names()} (or a blade "
                             "definition's .toml path, or an .fmu path)")
    return _root_parameters()


def _check_value(key: str, kind: str, value):
    """A fixed value of ``kind``: a switch as a bool, a whole number as an int, a real number as a
    finite float."""
    if kind == "bool":
        return check_bool(key, value)
    if isinstance(value, bool) or not isinstance(value, (Real, np.number)):
        raise ParameterError(f"{key} must be a {'whole ' if kind == 'int' else ''}number, got {value!r}")
    if not math.isfinite(value):
        raise ParameterError(f"{key} must be finite, got {value!r}")
    if kind == "int":
        if not float(value).is_integer():
            raise ParameterError(f"{key} must be a whole number, got {value!r}")
        return int(value)
    return float(value)


@dataclass(eq=False)
class Study:
    """A design study (module docstring), checked whole when it is made: the model exists, every
    parameter is the model's, fixed values are finite, and its points number at most
    :data:`MAX_POINTS`.

    Parameters
    ----------
    model : str, os.PathLike or BladeAssembly
        A blade model definition (a name in ``models/`` or a ``.toml`` path), a blade ``.fmu``
        (``BladeDovetail.fmu``), or a :class:`~frictionjoint.structures.BladeAssembly`.
    omega : str or (n,) array_like
        The frequencies of every point's sweep [rad/s] (:mod:`frictionjoint.frequencies`):
        ``"START:STOP:N"`` or the frequencies themselves (a blade sweeps them in increasing order,
        or decreasing with ``direction='down'``; ``'hbm'``: the branch from the lowest to the
        highest, about ``n`` points). Kept as the array of frequencies.
    vary : dict
        ``{parameter: Grid | Values | Random}``; parameters of the model (a blade: its root's, e.g.
        ``centrifugal_force``, ``friction_coefficient``, ``normal_stiffness``, ``flank_angle``,
        and ``tip_force_amplitude``; :func:`model_parameters`).
    fixed : dict, optional
        Parameters of every point: finite numbers, or true/false (or 1/0) for a switch such as
        ``normal_load_variation``.
    n_samples : int
        Random samples (with any :class:`Random` parameter), >= 1.
    seed : int
        Seed of the random samples.
    direction : {'up', 'down'}
    method : {'time', 'hbm'}
    harmonics : int
        Harmonics of ``'hbm'``.
    refine_peak : bool
        Refine a blade's peak between the sweep's points (time domain: exact steady states and a
        bounded search; harmonic balance: the balance's amplitude), and take the dissipation and
        slip state there.
    table : str or os.PathLike, optional
        Where :func:`~frictionjoint.study.run_study` writes the table by default (a relative
        path from the working directory it runs in).
    time_limit : float
        A point's time limit [s], > 0 (default :data:`DEFAULT_TIME_LIMIT`): a point not finished by
        then is a failed row saying so (:mod:`frictionjoint.study.execution`). Not part of the
        study's fingerprint: a resumed study computes such points again.
    mode_damping : ModeDamping or dict, optional
        Evaluate every point's nonlinear mode at an amplitude (:class:`ModeDamping`, or its keys
        as a dict): the columns ``mode_frequency`` and ``mode_damping_ratio``. A blade definition
        or assembly only (not an FMU).
    """

    model: Any
    omega: Any
    vary: dict
    fixed: dict = field(default_factory=dict)
    n_samples: int = 1
    seed: int = 0
    direction: str = "up"
    method: str = "time"
    harmonics: int = 7
    refine_peak: bool = True
    table: Any = None
    time_limit: float = DEFAULT_TIME_LIMIT
    mode_damping: Any = None

    def __post_init__(self):
        if self.mode_damping is not None:
            self.mode_damping = ModeDamping.from_table(self.mode_damping)
            if isinstance(self.model, (str, os.PathLike)) and Path(self.model).suffix == ".fmu":
                raise ParameterError("quantities.mode_damping: the nonlinear mode needs the blade itself (a models/ "
                                     "definition, a .toml or a BladeAssembly), not an FMU")
        omega = check_omegas("omega", self.omega)
        if self.method == "hbm" and omega.min() == omega.max():
            raise ParameterError(f"omega: the harmonic-balance branch needs two frequencies at least, from the "
                                 f"lowest to the highest, e.g. {FORM}")
        omega.flags.writeable = False
        self.omega = omega
        if not isinstance(self.vary, dict) or not self.vary:
            raise ParameterError("vary must name at least one parameter: {name: Grid | Values | Random}")
        if not isinstance(self.fixed, dict):
            raise ParameterError(f"fixed must be a table of parameters and numbers, got {self.fixed!r}")
        from .quantities import QUANTITIES

        for name in self.vary:
            if name in ("point", "status", "error") or name in QUANTITIES:
                raise ParameterError(f"vary.{name}: {name!r} is a column of the study's table")
        for name, spec in self.vary.items():
            if not isinstance(spec, (Grid, Values, Random)):
                raise ParameterError(f"vary.{name} must be a Grid, Values or Random, got {spec!r}")
            if name in self.fixed:
                raise ParameterError(f"{name} is both fixed and varied")
        if self.direction not in ("up", "down"):
            raise ParameterError(f"direction must be 'up' or 'down', got {self.direction!r}")
        if self.method not in METHODS:
            raise ParameterError(f"method must be one of {METHODS}, got {self.method!r}")
        self.n_samples = _count("n_samples", self.n_samples)
        self.harmonics = _count("harmonics", self.harmonics)
        self.seed = _count("seed", self.seed, 0)
        if self.refine_peak not in (True, False):
            raise ParameterError(f"refine_peak must be true or false, got {self.refine_peak!r}")
        limit = self.time_limit
        if isinstance(limit, bool) or not isinstance(limit, (Real, np.number)) or not (math.isfinite(limit) and limit > 0):
            raise ParameterError(f"time_limit must be a finite number of seconds > 0, got {limit!r}")
        self.time_limit = float(limit)
        for name, value in self.fixed.items():  # the type before the model: fixed.NAME named either way
            if isinstance(value, str) or not isinstance(value, (Real, np.number, np.bool_)):
                raise ParameterError(f"fixed.{name} must be a number (or true/false), got {value!r}")
        count = self.n_points  # from the grids' sizes, before any point is built
        if count > MAX_POINTS:
            parts = " x ".join([f"{spec.size(k)} (vary.{k})" for k, spec in self.vary.items()
                                if not isinstance(spec, Random)] + ([f"{self.n_samples} (samples.n)"] if self.random else []))
            raise ParameterError(f"the study has {parts} = {count} points, more than {MAX_POINTS}: fewer values, "
                                 "or several studies")
        kinds = model_parameters(self.model)
        allowed = sorted(kinds)
        for key, names in (("fixed", self.fixed), ("vary", self.vary)):
            for name in names:
                if name not in kinds:
                    raise ParameterError(f"{key}.{name}: not a parameter of {self._model_name()}; its parameters are "
                                         f"{allowed}")
        self.fixed = {name: _check_value(f"fixed.{name}", kinds[name], v) for name, v in self.fixed.items()}
        for name, spec in self.vary.items():
            if isinstance(spec, Random):
                if kinds[name] != "real":
                    raise ParameterError(f"vary.{name}: a {'switch' if kinds[name] == 'bool' else 'whole number'} "
                                         "cannot be random; give its values")
                spec.frozen(name)
            else:
                for v in spec.values(name):
                    _check_value(f"vary.{name}", kinds[name], float(v))
        if self.mode_damping is not None:  # the mode and DOF against the blade's (built once, cached)
            check_mode_declaration(self.model, self.mode_damping)

    @property
    def n_points(self) -> int:
        """The number of points, from the grids' sizes and the samples (no point built)."""
        sizes = [spec.size(name) for name, spec in self.vary.items() if not isinstance(spec, Random)]
        return math.prod(sizes) * (int(self.n_samples) if self.random else 1)

    @property
    def kinds(self) -> dict:
        """``{parameter: kind}`` of the fixed and varied parameters (:func:`model_parameters`)."""
        kinds = model_parameters(self.model)
        return {name: kinds[name] for name in (*self.vary, *self.fixed)}

    def _model_name(self) -> str:
        return str(self.model) if isinstance(self.model, (str, os.PathLike)) else type(self.model).__name__

    @property
    def varied(self) -> list[str]:
        """The varied parameters, in definition order."""
        return list(self.vary)

    @property
    def random(self) -> bool:
        """Whether any parameter is random."""
        return any(isinstance(s, Random) for s in self.vary.values())

    def points(self) -> list[dict]:
        """Every point's varied parameters, in point order (grids and lists: the Cartesian
        product, the first parameter slowest; random ones: ``n_samples`` draws from
        ``default_rng(seed)``, parameter by parameter in definition order, repeated for every grid
        point)."""
        grid_names = [n for n, s in self.vary.items() if not isinstance(s, Random)]
        rand_names = [n for n, s in self.vary.items() if isinstance(s, Random)]
        axes = [self.vary[n].values(n) for n in grid_names]
        draws = {}
        if rand_names:
            rng = np.random.default_rng(int(self.seed))
            for n in rand_names:
                frozen = self.vary[n].frozen(n)
                try:
                    draws[n] = np.asarray(frozen.rvs(size=int(self.n_samples), random_state=rng), dtype=float)
                except (TypeError, ValueError) as exc:
                    raise ParameterError(f"vary.{n}: cannot draw from {self.vary[n].distribution!r} with "
                                         f"{dict(self.vary[n].parameters)!r}: {exc}") from None
                if draws[n].shape != (int(self.n_samples),) or not np.all(np.isfinite(draws[n])):
                    raise ParameterError(f"vary.{n}: the parameters {dict(self.vary[n].parameters)!r} must be "
                                         "numbers giving finite samples")
        n_rand = int(self.n_samples) if rand_names else 1
        out = []
        for combo in itertools.product(*axes):
            for k in range(n_rand):
                p = {n: float(v) for n, v in zip(grid_names, combo)}
                p.update({n: float(draws[n][k]) for n in rand_names})
                out.append({n: p[n] for n in self.vary})  # definition order
        return out

    def _omega_key(self) -> list:
        """The frequencies in the fingerprint: ``[start, stop, n]`` for an even grid (as tables
        written before the frequencies could be listed), else every frequency."""
        w = self.omega
        if w.size >= 2 and np.array_equal(w, np.linspace(w[0], w[-1], w.size)):
            return [float(w[0]), float(w[-1]), int(w.size)]
        return [repr(float(v)) for v in w]

    def fingerprint(self) -> str:
        """A hash of everything that decides the table's rows (model, sweep, fixed parameters and
        every point's varied ones): a table written for another study is not resumed."""
        model = self.model
        if not isinstance(model, (str, os.PathLike)):  # an assembly: its pickled bytes
            model = hashlib.sha256(pickle.dumps(model)).hexdigest()
        else:  # a file: its contents too (a model edited since is another study)
            from ..structures import MODELS_DIR

            path = Path(model)
            for candidate in (path, MODELS_DIR / f"{path.stem}.toml"):
                if candidate.is_file():
                    model = f"{model}:{hashlib.sha256(candidate.read_bytes()).hexdigest()}"
                    break
        fixed = sorted((k, float(v)) for k, v in self.fixed.items())
        desc = dict(model=str(model), omega=self._omega_key(), fixed=fixed,
                    direction=self.direction, method=self.method,
                    harmonics=int(self.harmonics) if self.method == "hbm" else None, refine=self.refine_peak,
                    points=[[repr(v) for v in p.values()] for p in self.points()], varied=self.varied)
        if self.mode_damping is not None:  # only then: the fingerprints of studies without it are unchanged
            desc["mode_damping"] = self.mode_damping.key()
        return hashlib.sha256(json.dumps(desc, sort_keys=True, default=str).encode()).hexdigest()[:16]


@functools.lru_cache(maxsize=8)
def _blade(model: str, stamp: float):
    """The blade assembly of a model definition, or None if ``model`` names none; built once per
    process and definition file (``stamp``: its modification time): every point of a study shares
    the blade's structure and reduction, only the root's parameters change."""
    from ..structures import BladeAssembly
    from ..sweep import _blade_definition

    definition = _blade_definition(model)
    return None if definition is None else BladeAssembly.from_model(definition)


def _base_model(model):
    """A blade assembly for ``model`` (cached), or None for a model that is not a blade definition."""
    from ..structures import MODELS_DIR, BladeAssembly

    if isinstance(model, BladeAssembly):
        return model
    if not isinstance(model, (str, os.PathLike)):
        return None
    path = Path(model)
    for candidate in (path, MODELS_DIR / f"{path.stem}.toml"):
        if candidate.suffix == ".toml" and candidate.is_file():
            return _blade(str(model), candidate.stat().st_mtime)
    return None


def check_mode_declaration(model, declared) -> None:
    """Refuse, before any point runs, a nonlinear mode the blade of ``model`` cannot have: ``mode``
    beyond its stuck modes (one per DOF of its reduced structure, from 0), or a ``dof`` not its.
    The root's parameters a study varies change the joint, not the structure: what holds for the
    model holds at every point.

    Parameters
    ----------
    model : str, os.PathLike or BladeAssembly
        The study's model (a blade definition or assembly; nothing is checked for another).
    declared : ModeDamping

    Raises
    ------
    ParameterError
        Naming ``quantities.mode_damping.mode`` (with the number of modes) or ``.dof`` (with the
        blade's DOFs).
    """
    asm = _base_model(model)
    if asm is None:
        return
    s, where = asm.structure, "quantities.mode_damping"
    if declared.mode >= s.n_dof:
        raise ParameterError(f"{where}.mode must be < {s.n_dof} (the blade's {s.n_dof} DOFs: its stuck modes are 0 "
                             f"to {s.n_dof - 1}), got {declared.mode}")
    if declared.dof is not None and declared.dof not in s.dof_names:
        raise ParameterError(f"{where}.dof: {declared.dof!r} is not a DOF of the blade; its DOFs are {list(s.dof_names)}")


def _spec(name: str, entry) -> Grid | Values | Random:
    if not isinstance(entry, dict):
        raise ParameterError(f"vary.{name} must be a table (start/stop/num, values, or distribution)")
    keys = set(entry)
    if "distribution" in keys:
        params = {k: v for k, v in entry.items() if k != "distribution"}
        return Random(str(entry["distribution"]), tuple(sorted(params.items())))
    if "values" in keys:
        if keys != {"values"}:
            raise ParameterError(f"vary.{name}: 'values' takes no other keys, got {sorted(keys)}")
        if not isinstance(entry["values"], list):
            raise ParameterError(f"vary.{name}.values must be a list of numbers, got {entry['values']!r}")
        return Values(tuple(entry["values"]))
    if {"start", "stop", "num"} <= keys:
        extra = keys - {"start", "stop", "num", "spacing"}
        if extra:
            raise ParameterError(f"vary.{name}: unknown keys {sorted(extra)} (start, stop, num, spacing)")
        return Grid(entry["start"], entry["stop"], entry["num"], entry.get("spacing", "linear"))
    raise ParameterError(f"vary.{name} needs start/stop/num, values, or distribution; got {sorted(keys)}")


def load_study(path: str | os.PathLike) -> Study:
    """Read a study definition (TOML, module docstring); a relative ``model`` path is taken from
    the file's folder, a relative ``table`` from the working directory (default: the file's name
    with ``.csv`` there).

    Parameters
    ----------
    path : str or os.PathLike

    Returns
    -------
    Study
    """
    try:
        import tomllib
    except ModuleNotFoundError:  # Python < 3.11
        import tomli as tomllib

    path = Path(path)
    if not path.is_file():
        raise ParameterError(f"study file {str(path)!r} does not exist")
    try:
        text = path.read_bytes().decode("utf-8-sig")  # a byte-order mark (a Windows editor's) is not the text
    except UnicodeDecodeError as exc:
        raise ParameterError(f"{path}: not UTF-8 text (byte {exc.object[exc.start]:#04x} at offset {exc.start}); "
                             "save the study file as UTF-8") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError(f"{path}: not valid TOML: {exc}") from None
    known = {"model", "table", "fixed", "vary", "samples", "sweep", "quantities"}
    for key in ("fixed", "vary", "samples", "sweep", "quantities"):
        if key in data and not isinstance(data[key], dict):
            raise ParameterError(f"{path}: [{key}] must be a table, got {data[key]!r}")
    if "table" in data and not isinstance(data["table"], str):
        raise ParameterError(f"{path}: table must be a file name (.csv or .parquet), got {data['table']!r}")
    unknown = set(data) - known
    if unknown:
        raise ParameterError(f"{path}: unknown keys {sorted(unknown)} (allowed: {sorted(known)})")
    if "model" not in data:
        raise ParameterError(f"{path}: 'model' is missing (a models/ name, a .toml or a blade .fmu)")
    model = str(data["model"])
    local = path.parent / model
    if Path(model).suffix in (".toml", ".fmu") and local.is_file():
        model = str(local)
    sweep = dict(data.get("sweep", {}))
    unknown = set(sweep) - {"omega", "direction", "method", "harmonics", "refine_peak", "time_limit"}
    if unknown:
        raise ParameterError(f"{path}: unknown keys in [sweep]: {sorted(unknown)}")
    if "omega" not in sweep:
        raise ParameterError(f"{path}: [sweep] omega is missing: {FORM}")
    samples = dict(data.get("samples", {}))
    unknown = set(samples) - {"n", "seed"}
    if unknown:
        raise ParameterError(f"{path}: unknown keys in [samples]: {sorted(unknown)} (n, seed)")
    vary = {name: _spec(name, entry) for name, entry in dict(data.get("vary", {})).items()}
    declared = dict(data.get("quantities", {}))
    unknown = set(declared) - {"mode_damping"}
    if unknown:
        raise ParameterError(f"{path}: unknown keys in [quantities]: {sorted(unknown)} (mode_damping)")
    table = data.get("table")
    table = Path(table) if table is not None else Path(path.with_suffix(".csv").name)  # an output: here, not there
    try:
        return Study(model=model, omega=sweep["omega"], vary=vary, fixed=dict(data.get("fixed", {})),
                     n_samples=samples.get("n", 1), seed=samples.get("seed", 0),
                     direction=sweep.get("direction", "up"), method=sweep.get("method", "time"),
                     harmonics=sweep.get("harmonics", 7), refine_peak=sweep.get("refine_peak", True), table=table,
                     time_limit=sweep.get("time_limit", DEFAULT_TIME_LIMIT), mode_damping=declared.get("mode_damping"))
    except ParameterError as exc:  # the file and the key
        raise ParameterError(f"{path}: {exc}") from None
