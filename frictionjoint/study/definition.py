"""A design study: one model, fixed parameters, varied ones (grids, lists, random samples), one
frequency sweep per point. Defined in Python (:class:`Study`) or in a TOML file
(:func:`load_study`); its points are fixed by the definition alone (random samples from the
seeded generator), so a point's inputs are the same bits on any worker and in any session.

TOML form::

    model = "ti64_compressor_blade"      # a models/ definition, a .toml path or a blade .fmu
    table = "damper_curve.csv"           # optional; .csv or .parquet, relative to this file

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
    omega = [1950.0, 2100.0, 40]         # start, stop, number of frequencies [rad/s]
    direction = "up"
    method = "time"                      # or "hbm"
    harmonics = 7                        # of "hbm"
    refine_peak = true                   # a blade's peak refined between the sweep's points

The points are the Cartesian product of the grids and lists, times the ``n`` random samples
(drawn once, the same for every grid point).
"""
from __future__ import annotations

import hashlib
import itertools
import json
import math
import os
import pickle
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import ParameterError

__all__ = ["Grid", "Values", "Random", "Study", "load_study"]

SPACINGS = ("linear", "log")
METHODS = ("time", "hbm")


@dataclass(frozen=True)
class Grid:
    """``num`` values from ``start`` to ``stop`` (both included), evenly spaced (``'linear'``) or
    evenly in the logarithm (``'log'``, positive ends)."""

    start: float
    stop: float
    num: int
    spacing: str = "linear"

    def values(self, name: str) -> np.ndarray:
        if not (isinstance(self.num, (int, np.integer)) and not isinstance(self.num, bool) and self.num >= 1):
            raise ParameterError(f"vary.{name}.num must be an integer >= 1, got {self.num!r}")
        try:
            a, b = float(self.start), float(self.stop)
        except (TypeError, ValueError):
            raise ParameterError(f"vary.{name}: start and stop must be numbers, got {self.start!r}, {self.stop!r}") from None
        if not (math.isfinite(a) and math.isfinite(b)):
            raise ParameterError(f"vary.{name}: start and stop must be finite, got {a!r}, {b!r}")
        if self.spacing not in SPACINGS:
            raise ParameterError(f"vary.{name}.spacing must be one of {SPACINGS}, got {self.spacing!r}")
        if self.spacing == "log":
            if a <= 0 or b <= 0:
                raise ParameterError(f"vary.{name}: a log grid needs start and stop > 0, got {a!r}, {b!r}")
            return np.geomspace(a, b, int(self.num))
        return np.linspace(a, b, int(self.num))


@dataclass(frozen=True)
class Values:
    """An explicit list of values."""

    values_: tuple

    def values(self, name: str) -> np.ndarray:
        if len(self.values_) == 0:
            raise ParameterError(f"vary.{name}.values must not be empty")
        try:
            v = np.array(self.values_, dtype=float)
        except (TypeError, ValueError):
            raise ParameterError(f"vary.{name}.values must be numbers, got {list(self.values_)!r}") from None
        if not np.all(np.isfinite(v)):
            raise ParameterError(f"vary.{name}.values must be finite, got {list(self.values_)!r}")
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


@dataclass
class Study:
    """A design study (module docstring).

    Parameters
    ----------
    model : str, os.PathLike or BladeAssembly
        A blade model definition (a name in ``models/`` or a ``.toml`` path), a blade ``.fmu``
        (``BladeDovetail.fmu``), or a :class:`~frictionjoint.structures.BladeAssembly`.
    omega : (float, float, int)
        The sweep of every point: start, stop [rad/s] and number of frequencies.
    vary : dict
        ``{parameter: Grid | Values | Random}``; parameters of the model's root (e.g.
        ``centrifugal_force``, ``friction_coefficient``, ``normal_stiffness``, ``flank_angle``) or
        ``tip_force_amplitude``.
    fixed : dict, optional
        Parameters of every point.
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
        Where :func:`~frictionjoint.study.run_study` writes the table by default.
    """

    model: Any
    omega: tuple
    vary: dict
    fixed: dict = field(default_factory=dict)
    n_samples: int = 1
    seed: int = 0
    direction: str = "up"
    method: str = "time"
    harmonics: int = 7
    refine_peak: bool = True
    table: Any = None

    def __post_init__(self):
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
        try:
            w0, w1, n = self.omega
            if isinstance(n, bool) or float(n) != int(n):
                raise ValueError
            w0, w1, n = float(w0), float(w1), int(n)
        except (TypeError, ValueError):
            raise ParameterError(f"omega must be (start, stop, number) [rad/s], the number an integer, got "
                                 f"{self.omega!r}") from None
        if not (w0 > 0 and w1 > 0 and w0 != w1 and math.isfinite(w0) and math.isfinite(w1) and n >= 2):
            raise ParameterError(f"omega must be (start > 0, stop > 0, number >= 2), start != stop [rad/s], got "
                                 f"{self.omega!r}")
        self.omega = (w0, w1, n)
        if self.direction not in ("up", "down"):
            raise ParameterError(f"direction must be 'up' or 'down', got {self.direction!r}")
        if self.method not in METHODS:
            raise ParameterError(f"method must be one of {METHODS}, got {self.method!r}")
        for name, value, low in (("n_samples", self.n_samples, 1), ("harmonics", self.harmonics, 1),
                                 ("seed", self.seed, 0)):
            if not (isinstance(value, (int, np.integer)) and not isinstance(value, bool) and value >= low):
                raise ParameterError(f"{name} must be an integer >= {low}, got {value!r}")
        if self.refine_peak not in (True, False):
            raise ParameterError(f"refine_peak must be true or false, got {self.refine_peak!r}")
        for name, value in self.fixed.items():
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise ParameterError(f"fixed.{name} must be a number, got {value!r}")

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
        desc = dict(model=str(model), omega=list(self.omega), fixed=fixed,
                    direction=self.direction, method=self.method,
                    harmonics=int(self.harmonics) if self.method == "hbm" else None, refine=self.refine_peak,
                    points=[[repr(v) for v in p.values()] for p in self.points()], varied=self.varied)
        return hashlib.sha256(json.dumps(desc, sort_keys=True, default=str).encode()).hexdigest()[:16]


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
    """Read a study definition (TOML, module docstring); relative ``model`` and ``table`` paths are
    taken from the file's folder.

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
        data = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as exc:
        raise ParameterError(f"{path}: not valid TOML: {exc}") from None
    known = {"model", "table", "fixed", "vary", "samples", "sweep"}
    for key in ("fixed", "vary", "samples", "sweep"):
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
    unknown = set(sweep) - {"omega", "direction", "method", "harmonics", "refine_peak"}
    if unknown:
        raise ParameterError(f"{path}: unknown keys in [sweep]: {sorted(unknown)}")
    if not isinstance(sweep.get("omega"), list) or len(sweep["omega"]) != 3:
        raise ParameterError(f"{path}: [sweep] omega = [start, stop, number] is missing or not three numbers")
    samples = dict(data.get("samples", {}))
    unknown = set(samples) - {"n", "seed"}
    if unknown:
        raise ParameterError(f"{path}: unknown keys in [samples]: {sorted(unknown)} (n, seed)")
    vary = {name: _spec(name, entry) for name, entry in dict(data.get("vary", {})).items()}
    table = data.get("table")
    table = (path.parent / table) if table is not None else path.with_suffix(".csv")
    return Study(model=model, omega=tuple(sweep["omega"]), vary=vary, fixed=dict(data.get("fixed", {})),
                 n_samples=samples.get("n", 1), seed=samples.get("seed", 0),
                 direction=sweep.get("direction", "up"), method=sweep.get("method", "time"),
                 harmonics=sweep.get("harmonics", 7), refine_peak=sweep.get("refine_peak", True), table=table)
